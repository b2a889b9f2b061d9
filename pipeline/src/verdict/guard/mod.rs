//! The verdict's guard: a run says "no squeal" only when it could have seen squeal.
//!
//! A transient that finds no clear growth is a negative only if
//! - its steps resolve the frequencies it must: the response's dominant frequency and the
//!   highest in-band unstable frequency of a CEA of the same state (or, without a CEA, the top
//!   of the model's band). At a frequency f and the largest step h of the analysed window, the
//!   integrator's own numerical decay σ_num(h, f) (BDF1/BDF2: from the principal root of the
//!   method's characteristic equation on y' = iωy, averaged over the orders the BDF used after
//!   the ramp, [`StepsByOrder`]; generalized-α: its algorithmic damping) must
//!   stay below the smallest growth that matters, `output.min_growth_rate_per_s` — otherwise a
//!   root growing that fast would be damped away numerically;
//! - its window is long enough to see that growth: the detectable rate ln(G)/T of a window of
//!   length T, with G = `output.squeal_min_growth_factor` (the growth the verdict requires),
//!   must not exceed `min_growth_rate_per_s`;
//! - its contact stayed valid (no gap went tensile after the load ramp while separation is
//!   off; tensile gaps while the load is still being applied are reported, see `validity`);
//! - it reached TFINAL (no step-size collapse or convergence failure, no step cap).
//!
//! A clear growth before any of these failures is a positive (`squeal`): the A-stable
//! integrators used here do not create growth, and the contact was valid while it grew.
//! So is a limit cycle that was reached (separation on) with an amplitude grown by the
//! required factor from the first cycle after the ramp: a self-excited oscillation that
//! saturated. A reached limit cycle is never `no_squeal`. Anything else is `unresolved`, with
//! every reason and its numbers.

pub mod decay;
pub mod state;

pub use decay::{numerical_decay, StepsByOrder};
pub use state::{status_text, FrequencySource, Resolution, Unresolved, VerdictState};

use super::validity::ContactValidity;
use crate::verdict::Integrator;
use squeal_solver::bdf::Status;
use squeal_solver::Real;

/// Everything the guard weighs.
pub struct Evidence<'a> {
    /// A clear growth in the valid part of the window (the fit's verdict).
    pub clear_growth: bool,
    /// Analysed window [t0, t1] (after the ramp, before any invalidity).
    pub window: [Real; 2],
    /// Largest accepted step in the window (None: no steps there).
    pub h_max_window: Option<Real>,
    /// The BDF's steps after the ramp by order (None: not counted, e.g. generalized-α): the
    /// numerical decay is then their mean, not that of `max_order` alone.
    pub steps_by_order: Option<&'a StepsByOrder>,
    /// Frequencies to resolve.
    pub frequencies: Vec<(FrequencySource, Real)>,
    pub contact: &'a ContactValidity,
    /// Separation on: tensile gaps open instead of holding.
    pub separation: bool,
    pub status: &'a Status,
    /// Step size at the end of the run.
    pub h_end: Option<Real>,
    pub integrator: Integrator,
    pub max_order: usize,
    pub rho_inf: Real,
    pub min_growth_rate_per_s: Real,
    pub min_growth_factor: Real,
    /// The limit cycle the run reached (separation on, `limit_cycle.reached`): its peak and
    /// the growth of the amplitude to it (None: not reached).
    pub limit_cycle: Option<LimitCycleEvidence>,
}

/// A reached limit cycle as the guard weighs it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LimitCycleEvidence {
    pub peak_normal_velocity: Real,
    /// The limit cycle's peak over the first cycle's after the ramp.
    pub amplitude_growth: Option<Real>,
}

impl LimitCycleEvidence {
    /// The amplitude grew by at least `min_factor` (≥ 2) to the limit cycle.
    pub fn self_excited(&self, min_factor: Real) -> bool {
        self.amplitude_growth
            .is_some_and(|g| g >= min_factor.max(2.0))
    }
}

/// The resolution of each frequency, the window's detectable growth, and the state.
pub fn judge(e: &Evidence<'_>) -> (VerdictState, Vec<Resolution>, Option<Real>) {
    let resolutions: Vec<Resolution> = match e.h_max_window {
        Some(h) => e
            .frequencies
            .iter()
            .filter(|(_, f)| f.is_finite() && *f > 0.0)
            .map(|&(source, f)| {
                let decay = match (e.integrator, e.steps_by_order) {
                    (Integrator::Bdf, Some(c)) => c.decay(h, f),
                    _ => None,
                }
                .unwrap_or_else(|| numerical_decay(e.integrator, e.max_order, e.rho_inf, h, f));
                Resolution {
                    source,
                    frequency_hz: f,
                    samples_per_period: 1.0 / (h * f),
                    h_times_f: h * f,
                    numerical_decay_per_s: decay,
                    resolved: decay <= e.min_growth_rate_per_s,
                }
            })
            .collect(),
        None => Vec::new(),
    };
    let span = e.window[1] - e.window[0];
    let detectable = (span > 0.0).then(|| e.min_growth_factor.max(2.0).ln() / span);
    if e.clear_growth {
        return (VerdictState::Squeal, resolutions, detectable);
    }
    let mut reasons = Vec::new();
    if let Some(lc) = &e.limit_cycle {
        if lc.self_excited(e.min_growth_factor) {
            return (VerdictState::Squeal, resolutions, detectable);
        }
        // Never `no_squeal`: the run oscillates at a stationary amplitude.
        reasons.push(Unresolved::LimitCycleWithoutGrowth {
            peak_normal_velocity: lc.peak_normal_velocity,
            amplitude_growth: lc.amplitude_growth,
            min_growth_factor: e.min_growth_factor.max(2.0),
        });
    }
    if e.h_max_window.is_none() {
        reasons.push(Unresolved::NoResponse);
    }
    reasons.extend(
        resolutions
            .iter()
            .filter(|r| !r.resolved)
            .map(|r| Unresolved::StepsTooCoarse(*r)),
    );
    if let Some(d) = detectable {
        if d > e.min_growth_rate_per_s {
            reasons.push(Unresolved::WindowTooShort {
                window_s: span,
                detectable_growth_per_s: d,
                min_growth_rate_per_s: e.min_growth_rate_per_s,
            });
        }
    }
    if let (false, Some(ev)) = (e.separation, e.contact.first_tensile_after_ramp) {
        reasons.push(Unresolved::ContactTensile(ev));
    }
    if !e.status.is_success() {
        let t = match e.status {
            Status::StepSizeTooSmall { t, .. }
            | Status::ErrorTestFailures { t, .. }
            | Status::ConvergenceFailures { t, .. }
            | Status::MaxSteps { t, .. }
            | Status::StepCollapse { t, .. }
            | Status::Interrupted { t }
            | Status::Reached { t } => *t,
        };
        let h = match e.status {
            Status::StepSizeTooSmall { h, .. }
            | Status::ErrorTestFailures { h, .. }
            | Status::ConvergenceFailures { h, .. }
            | Status::StepCollapse { h, .. } => Some(*h),
            _ => e.h_end,
        };
        reasons.push(Unresolved::Stopped {
            t,
            h,
            status: e.status.clone(),
        });
    }
    let state = match reasons.is_empty() {
        true => VerdictState::NoSqueal,
        false => VerdictState::Unresolved { reasons },
    };
    (state, resolutions, detectable)
}

#[cfg(test)]
mod tests;
