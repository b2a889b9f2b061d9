//! The verdict on one response: the deciding root, the roots, the envelope cross-check, and the
//! state the guard gave it.

use super::envelope::Envelope;
use super::guard::{Resolution, Unresolved, VerdictState};
use super::limit_cycle::{RampSaturation, Saturation};
use super::roots::{PencilFit, Root};
use serde::Serialize;
use squeal_solver::Real;

/// Verdict on one response history (after the load ramp).
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// σ of the root that decides: the fastest-growing significant root of the estimator
    /// (None: no fit).
    pub growth_rate_per_s: Option<Real>,
    /// Frequency of the estimator's largest root at the window's end.
    pub dominant_frequency_hz: Option<Real>,
    /// e^{σT} of the deciding root over the fitted window T.
    pub growth_factor: Option<Real>,
    /// The deciding root's smallest σ over the fit and its refits on the later parts of the
    /// window: a clear growth needs it above the threshold too.
    pub growth_rate_min_per_s: Option<Real>,
    /// The response's oscillating roots, largest at the window's end first (at most 12).
    pub roots: Vec<Root>,
    /// How the roots were estimated (window, channels, samples, order, residual).
    pub estimator: Option<PencilFit>,
    /// The envelope cross-check (one DOF, the later half of the window).
    pub envelope: Envelope,
    /// Window [t_start, t_end] the roots were fitted on (after the ramp, before any
    /// invalidity or step collapse).
    pub window: [Real; 2],
    /// `squeal`, `no_squeal`, or `unresolved` with its reasons (the guard: `guard.rs`).
    #[serde(flatten)]
    pub state: VerdictState,
    /// How the run's steps resolve the frequencies it must (dominant, CEA, band top).
    pub resolution: Vec<Resolution>,
    /// Smallest growth rate the window can show, ln(G)/T (G: the required growth factor).
    pub detectable_growth_per_s: Option<Real>,
    /// Largest accepted step in the window.
    pub h_max_window: Option<Real>,
    /// The contact went tensile here (separation off): a growth counts as squeal only when
    /// it is clear before this time (None: the contact stayed valid).
    pub valid_until: Option<Real>,
    /// A reached limit cycle (separation on): where the response saturated; the roots and
    /// the window are then those of the growth before it (None: no limit cycle reached).
    pub saturation: Option<Saturation>,
    /// The response grew during the load ramp and the contact's opening held it before the
    /// ramp ended (separation on): the roots and the window are then those of the growth from
    /// the run's start to the first opening (None: not this case).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ramp_saturation: Option<RampSaturation>,
    /// What a `squeal` rests on: a clear growth of the deciding root, or a reached limit
    /// cycle whose amplitude grew by the required factor (None: not squeal).
    pub evidence: Option<SquealEvidence>,
}

/// What a `squeal` verdict rests on.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SquealEvidence {
    /// The deciding root grows clearly in the fitted window.
    Growth,
    /// The run reached a limit cycle with an amplitude grown by the required factor (the
    /// fitted growth alone was not clear).
    LimitCycle,
    /// The deciding root grew clearly while the load was applied, the contact's opening held
    /// the amplitude before the ramp ended, and the oscillation was sustained after it
    /// ([`RampSaturation`]).
    GrowthDuringRamp,
}

impl Verdict {
    /// The estimator's roots with the envelope as cross-check: the state is judged later by
    /// the guard.
    pub fn new(
        fit: Option<PencilFit>,
        envelope: Envelope,
        window: [Real; 2],
        h_max: Option<Real>,
    ) -> Self {
        let deciding = fit.as_ref().and_then(|f| f.deciding().copied());
        let span = fit.as_ref().map_or(0.0, |f| f.window[1] - f.window[0]);
        let mut roots = fit.as_ref().map_or_else(Vec::new, |f| f.roots.clone());
        roots.truncate(12);
        Verdict {
            growth_rate_per_s: deciding.map(|r| r.growth_rate_per_s),
            dominant_frequency_hz: roots.first().map(|r| r.frequency_hz),
            growth_factor: deciding.map(|r| (r.growth_rate_per_s * span).exp()),
            growth_rate_min_per_s: deciding.map(|r| r.growth_rate_range_per_s[0]),
            roots,
            estimator: fit,
            envelope,
            window,
            state: VerdictState::Unresolved {
                reasons: vec![Unresolved::NoResponse],
            },
            resolution: Vec::new(),
            detectable_growth_per_s: None,
            h_max_window: h_max,
            valid_until: None,
            saturation: None,
            ramp_saturation: None,
            evidence: None,
        }
    }

    /// A clear growth: the deciding root grows faster than `rate` (per unit time) and by at
    /// least `min_factor` over the fitted window, and faster than `rate` in every refit on
    /// the window's later parts. (The verdict's `state` also weighs whether a run without it
    /// could have seen squeal.)
    pub fn is_squeal(&self, rate: Real, min_factor: Real) -> bool {
        match (self.growth_rate_per_s, self.growth_factor) {
            (Some(g), Some(f)) => {
                g > rate && f >= min_factor && self.growth_rate_min_per_s.is_none_or(|m| m > rate)
            }
            _ => false,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::envelope::analyse;
    use super::*;

    /// A clear growth needs the deciding root to grow in every refit: σ = +108 /s over a
    /// window of 8.5 ms (×2.5) with a refit at −24 /s is no clear growth (the hex20 brake's
    /// case 7 had such a root at 9.2 kHz), with the refits at +60 and +130 /s it is.
    #[test]
    fn a_clear_growth_grows_in_every_refit() {
        let verdict = |range: [Real; 2]| {
            let fit = PencilFit {
                roots: vec![Root {
                    growth_rate_per_s: 108.0,
                    frequency_hz: 9187.0,
                    amplitude: 1.0,
                    amplitude_end: 2.5,
                    significant: true,
                    consistent: true,
                    growth_rate_range_per_s: range,
                }],
                window: [2e-3, 10.5e-3],
                channels: 9,
                samples: 1500,
                dt: 5.7e-6,
                pencil: 300,
                order: 40,
                singular_values: vec![],
                relative_residual: 0.02,
            };
            Verdict::new(
                Some(fit),
                analyse(&[], &[], 0.0),
                [2e-3, 10.5e-3],
                Some(2.5e-6),
            )
        };
        let v = verdict([-24.0, 110.0]);
        assert!((v.growth_factor.unwrap() - (108.0f64 * 8.5e-3).exp()).abs() < 1e-12);
        assert!(!v.is_squeal(0.0, 2.0), "{v:?}");
        assert!(verdict([60.0, 130.0]).is_squeal(0.0, 2.0));
    }
}
