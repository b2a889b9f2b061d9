//! The squeal verdict of a run from what it recorded: a pure function of series and settings.
//!
//! 1. The roots of the response after the load ramp ([`fit`]), up to a step collapse
//!    (`stall_h`).
//! 2. With separation, the limit cycle of the rotor face's normal velocity; when it was
//!    reached, the roots are refitted on the growth before the response saturated.
//!    When it grew while the load was applied and the contact's opening held it before the
//!    ramp ended, the roots are fitted from the run's start to that opening
//!    ([`RampSaturation`]).
//! 3. With a tensile gap after the ramp (separation off), the growth is judged on the part
//!    before it, and the roots, window and growth reported are that part's.
//! 4. The guard ([`judge`]): a clear growth is `squeal`; a negative only when the run could
//!    have seen squeal (frequencies resolved — the dominant one, a CEA's highest in-band
//!    unstable root or else the band's top —, a long enough window, a valid contact, TFINAL
//!    reached); else `unresolved` with the reasons.
//! 5. The roots decide only when they explain the response: with a fit residual above the
//!    pencil's `max_relative_residual` neither a growth nor a decay is claimed (`poor_fit`).
//! 6. With a CEA of the same state, the response's roots beside the CEA's.

use super::fit::{fit, Series};
use super::guard::{
    judge, Evidence, FrequencySource, LimitCycleEvidence, StepsByOrder, Unresolved, VerdictState,
};
use super::limit_cycle::{FaceSeries, LimitCycle, RampSaturation};
use super::outcome::{SquealEvidence, Verdict};
use super::roots::{pair_with_cea, PencilOptions, RootPair};
use super::validity::ContactValidity;
use crate::verdict::Integrator;
use squeal_solver::bdf::Status;
use squeal_solver::Real;

/// What a run recorded, as the verdict reads it.
pub struct Record<'a> {
    /// The response: velocities of the analysed DOFs at every accepted step.
    pub response: &'a Series,
    /// The rotor face's normal velocity at every step (with separation).
    pub face: Option<&'a FaceSeries>,
    /// What the contact did.
    pub contact: &'a ContactValidity,
    /// The BDF's steps after the ramp by order (None: generalized-α).
    pub steps_by_order: Option<&'a StepsByOrder>,
    /// How the integration ended.
    pub status: &'a Status,
    /// Step size at the end of the run.
    pub h_end: Option<Real>,
    /// The first gap opening (separation on).
    pub first_opening: Option<Real>,
}

/// How the verdict judges (the scene's `[output]` thresholds and the run's integrator).
#[derive(Debug, Clone, PartialEq)]
pub struct Settings {
    /// End of the load ramp (or the run's start, if later): the window starts here.
    pub t_after: Real,
    /// Judge only the growth phase: up to the first step shorter than this after the ramp.
    pub stall_h: Option<Real>,
    /// The model's band (bounds the roots and the sampling; the top is resolved without CEA).
    pub band_hz: Option<Real>,
    pub pencil: PencilOptions,
    /// Gaps may separate (a tensile gap opens instead of voiding the window).
    pub separation: bool,
    pub integrator: Integrator,
    pub max_order: usize,
    pub rho_inf: Real,
    /// `output.squeal_growth_threshold`: σ above which a root grows clearly, 1/s.
    pub growth_threshold_per_s: Real,
    /// `output.squeal_min_growth_factor`: the growth over the window a squeal needs.
    pub min_growth_factor: Real,
    /// `output.min_growth_rate_per_s`: the smallest growth that matters.
    pub min_growth_rate_per_s: Real,
}

/// The roots of a CEA at the run's steady state: (frequency Hz, Re p 1/s).
#[derive(Debug, Clone, Copy)]
pub struct CeaRoots<'a> {
    /// Unstable roots in the band.
    pub unstable_in_band: &'a [(Real, Real)],
    /// Every root in the band.
    pub modes_in_band: &'a [(Real, Real)],
}

/// What the verdict found.
#[derive(Debug, Clone)]
pub struct Decision {
    /// Name of the channel of the envelope cross-check.
    pub response: String,
    pub verdict: Verdict,
    /// The limit cycle (separation on, with a dominant frequency).
    pub limit_cycle: Option<LimitCycle>,
    /// The response's significant roots beside the CEA's (with a CEA).
    pub transient_vs_cea: Option<Vec<RootPair>>,
}

/// The verdict on a run's record (see the module documentation).
pub fn decide(r: &Record<'_>, s: &Settings, cea: Option<CeaRoots<'_>>) -> Decision {
    let t_after = s.t_after;
    let t_stop = r
        .contact
        .first_tensile_after_ramp
        .filter(|_| !s.separation)
        .map(|e| e.t);
    let fit_to = |t_stop| fit(r.response, t_after, s.stall_h, t_stop, s.band_hz, &s.pencil);
    let (response, mut verdict) = fit_to(None);
    // With separation the response may saturate into a limit cycle; the fit over the whole
    // window then sees little growth. The growth that matters is the one before the response
    // saturated: the roots are fitted there.
    let face = r.face.filter(|_| s.separation);
    let limit_cycle = face.and_then(|f| f.analyse(t_after, verdict.dominant_frequency_hz));
    let saturation = match (face, limit_cycle.as_ref().filter(|l| l.reached)) {
        (Some(f), Some(l)) => f.saturation(t_after, l, r.first_opening),
        _ => None,
    };
    if let Some(sat) = saturation {
        let (_, before) = fit_to(Some(sat.growth_end));
        if before.estimator.is_some() {
            verdict = before;
        }
        verdict.saturation = Some(sat);
    }
    // With separation the response may also have grown while the load was being applied and
    // been held by the contact's opening before the ramp ended: after the ramp it oscillates
    // at the separation amplitude, which no sum of roots explains. Its growth is then fitted
    // from the run's start to that opening.
    if saturation.is_none() && !verdict.is_squeal(s.growth_threshold_per_s, s.min_growth_factor) {
        if let Some((rs, growth)) = face.and_then(|f| growth_during_ramp(r, f, s, &verdict)) {
            verdict = growth;
            verdict.ramp_saturation = Some(rs);
        }
    }
    // The growth and frequency are judged on the window up to the first tensile gap when
    // there is one: a clear growth counts as squeal only within the part where the contact
    // was valid.
    let growth_while_valid = match t_stop {
        Some(_) => fit_to(t_stop).1,
        None => verdict.clone(),
    };
    // The state is judged on the valid part, so the roots, growth and window reported are
    // those of that part too (a run once said `squeal` beside a whole-window σ of −1.4 /s:
    // the hex20 brake's case 7, tensile from 10.5 ms).
    if t_stop.is_some() && growth_while_valid.estimator.is_some() {
        let saturation = verdict.saturation.take();
        verdict = growth_while_valid.clone();
        verdict.saturation = saturation;
    }
    verdict.valid_until = t_stop;
    let mut frequencies = Vec::new();
    if let Some(f) = verdict.dominant_frequency_hz {
        frequencies.push((FrequencySource::Dominant, f));
    }
    match (cea, s.band_hz) {
        (Some(c), _) => {
            if let Some(f) = c.unstable_in_band.iter().map(|r| r.0).reduce(Real::max) {
                frequencies.push((FrequencySource::CeaUnstable, f));
            }
        }
        (None, Some(band)) => frequencies.push((FrequencySource::BandTop, band)),
        _ => {}
    }
    // The roots judge the run only when they explain its response.
    let poor_fit = growth_while_valid
        .estimator
        .as_ref()
        .map(|e| e.relative_residual)
        .filter(|&r| r > s.pencil.max_relative_residual);
    let clear_growth = poor_fit.is_none()
        && growth_while_valid.is_squeal(s.growth_threshold_per_s, s.min_growth_factor);
    let (state, resolution, detectable) = judge(&Evidence {
        clear_growth,
        window: verdict.window,
        h_max_window: verdict.h_max_window,
        steps_by_order: r.steps_by_order,
        frequencies,
        contact: r.contact,
        separation: s.separation,
        status: r.status,
        h_end: r.h_end,
        integrator: s.integrator,
        max_order: s.max_order,
        rho_inf: s.rho_inf,
        min_growth_rate_per_s: s.min_growth_rate_per_s,
        min_growth_factor: s.min_growth_factor,
        limit_cycle: limit_cycle
            .as_ref()
            .filter(|l| l.reached)
            .map(|l| LimitCycleEvidence {
                peak_normal_velocity: l.peak_normal_velocity,
                amplitude_growth: saturation.map(|s| s.amplitude_growth),
            }),
    });
    let state = match (state, poor_fit) {
        (VerdictState::NoSqueal, Some(r)) => VerdictState::Unresolved {
            reasons: vec![poor_fit_reason(r, &s.pencil)],
        },
        (VerdictState::Unresolved { mut reasons }, Some(r)) => {
            reasons.push(poor_fit_reason(r, &s.pencil));
            VerdictState::Unresolved { reasons }
        }
        (state, _) => state,
    };
    verdict.evidence = state
        .is_squeal()
        .then_some(match (clear_growth, verdict.ramp_saturation) {
            (true, None) => SquealEvidence::Growth,
            (true, Some(_)) => SquealEvidence::GrowthDuringRamp,
            (false, _) => SquealEvidence::LimitCycle,
        });
    verdict.state = state;
    verdict.resolution = resolution;
    verdict.detectable_growth_per_s = detectable;
    let transient_vs_cea = cea.map(|c| pair_with_cea(&verdict.roots, c.modes_in_band));
    Decision {
        response,
        verdict,
        limit_cycle,
        transient_vs_cea,
    }
}

/// The growth of a response that the contact's opening held before the load ramp ended
/// ([`RampSaturation`]): the first opening after a whole closed cycle (at the post-ramp fit's
/// dominant frequency) is before the ramp's end; the oscillation after the ramp is sustained
/// and held by open gaps ([`super::limit_cycle::CycleTrend::sustained_by_separation`]); and the roots fitted from
/// the run's start to that opening explain the response and grow clearly. A forced response
/// to the ramp does not grow exponentially at a fixed frequency, and a decaying one is not
/// sustained: the three together are a self-excited oscillation. None otherwise.
fn growth_during_ramp(
    r: &Record<'_>,
    face: &FaceSeries,
    s: &Settings,
    after: &Verdict,
) -> Option<(RampSaturation, Verdict)> {
    let f = after.dominant_frequency_hz?;
    let first_opening = face
        .first_opening_after_closure(f)
        .filter(|&t| t < s.t_after)?;
    let after_ramp = face
        .after_ramp(s.t_after, f)
        .filter(|c| c.sustained_by_separation(s.min_growth_rate_per_s))?;
    let t0 = *r.response.t.first()?;
    let (_, growth) = fit(
        r.response,
        t0,
        s.stall_h,
        Some(first_opening),
        s.band_hz,
        &s.pencil,
    );
    let explains = growth
        .estimator
        .as_ref()
        .is_some_and(|e| e.relative_residual <= s.pencil.max_relative_residual);
    (explains && growth.is_squeal(s.growth_threshold_per_s, s.min_growth_factor)).then_some((
        RampSaturation {
            first_opening,
            after_ramp,
        },
        growth,
    ))
}

fn poor_fit_reason(relative_residual: Real, p: &PencilOptions) -> Unresolved {
    Unresolved::PoorFit {
        relative_residual,
        max_relative_residual: p.max_relative_residual,
    }
}
