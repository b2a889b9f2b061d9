//! What the guard decides: the verdict's state, the reasons a run is unresolved, and how well
//! its steps resolve each frequency.

use super::super::validity::GapEvent;
use serde::Serialize;
use squeal_solver::bdf::Status;
use squeal_solver::Real;

/// How a run ended, in words: `reached` or the status with its numbers (tables and logs; the
/// results themselves carry the [`Status`] enum).
pub fn status_text(s: &Status) -> String {
    match s {
        Status::Reached { .. } => "reached".into(),
        Status::MaxSteps { t, steps } => {
            format!("stopped at the step cap ({steps} steps) at t = {t:.4e}")
        }
        Status::StepCollapse {
            t,
            h,
            order,
            h_collapse,
            steps,
        } => format!(
            "stopped at t = {t:.4e}: the step collapsed ({steps} consecutive steps below \
             {h_collapse:.3e} s = h_max / transient.collapse_factor; the last h = {h:.3e} s at \
             order {order}), far below what the band needs"
        ),
        other => format!("{other:?}"),
    }
}

/// Where a frequency the run must resolve comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FrequencySource {
    /// The dominant frequency of the response.
    Dominant,
    /// The highest unstable root in the band of a CEA at the run's steady state.
    CeaUnstable,
    /// The top of the model's band (no CEA to say where an unstable root could be).
    BandTop,
}

/// How well the run's steps resolve one frequency.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Resolution {
    pub source: FrequencySource,
    pub frequency_hz: Real,
    /// 1/(h f) with h the largest step of the analysed window.
    pub samples_per_period: Real,
    pub h_times_f: Real,
    /// The integrator's numerical decay rate of an undamped oscillation at f with step h, 1/s.
    pub numerical_decay_per_s: Real,
    /// `numerical_decay_per_s` ≤ the smallest growth that matters.
    pub resolved: bool,
}

/// Why a run could not decide.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "reason", rename_all = "snake_case")]
pub enum Unresolved {
    /// The steps are too coarse for a frequency the run must resolve.
    StepsTooCoarse(Resolution),
    /// The analysed window is too short to see the smallest growth that matters.
    WindowTooShort {
        window_s: Real,
        detectable_growth_per_s: Real,
        min_growth_rate_per_s: Real,
    },
    /// A gap went tensile (p_n < 0) with separation off: the bilateral contact holds in
    /// tension and the friction force reverses from then on.
    ContactTensile(GapEvent),
    /// The integration stopped before TFINAL.
    Stopped {
        t: Real,
        h: Option<Real>,
        status: Status,
    },
    /// No response after the load ramp to analyse.
    NoResponse,
    /// The fitted roots do not explain the response (a chirp, a drifting frequency): the
    /// fit's relative residual is above the pencil's `max_relative_residual`.
    PoorFit {
        relative_residual: Real,
        max_relative_residual: Real,
    },
    /// A limit cycle was reached but neither a clear growth before saturation nor an
    /// amplitude grown by the required factor shows that it is self-excited.
    LimitCycleWithoutGrowth {
        peak_normal_velocity: Real,
        /// The limit cycle's peak over the first cycle's after the ramp (None: not measured).
        amplitude_growth: Option<Real>,
        min_growth_factor: Real,
    },
}

/// The verdict's state.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "state", rename_all = "snake_case")]
pub enum VerdictState {
    /// A clear growth while the run was valid.
    Squeal,
    /// No growth, and the run could have seen growth at `min_growth_rate_per_s`.
    NoSqueal,
    /// Neither can be claimed.
    Unresolved { reasons: Vec<Unresolved> },
}

impl VerdictState {
    pub fn is_squeal(&self) -> bool {
        matches!(self, VerdictState::Squeal)
    }
    /// A short word for tables.
    pub fn label(&self) -> &'static str {
        match self {
            VerdictState::Squeal => "squeal",
            VerdictState::NoSqueal => "no squeal",
            VerdictState::Unresolved { .. } => "unresolved",
        }
    }
}

impl std::fmt::Display for Unresolved {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Unresolved::StepsTooCoarse(r) => write!(
                f,
                "steps too coarse for {:.0} Hz ({:?}): {:.1} steps per period (h·f = {:.3}), \
                 numerical decay {:.0} /s",
                r.frequency_hz, r.source, r.samples_per_period, r.h_times_f, r.numerical_decay_per_s
            ),
            Unresolved::WindowTooShort {
                window_s,
                detectable_growth_per_s,
                min_growth_rate_per_s,
            } => write!(
                f,
                "window {window_s:.4e} s too short: detects growth above {detectable_growth_per_s:.0} /s, \
                 not {min_growth_rate_per_s:.0} /s"
            ),
            Unresolved::ContactTensile(e) => write!(
                f,
                "contact tensile from t = {:.4e} (gap {}, p_n = {:.3e}) with separation off",
                e.t, e.gap, e.pressure
            ),
            Unresolved::Stopped { t, h, status } => {
                write!(f, "stopped at t = {t:.4e}")?;
                if let Some(h) = h {
                    write!(f, ", h = {h:.3e}")?;
                }
                write!(f, ": {}", status_text(status))
            }
            Unresolved::NoResponse => f.write_str("no response after the load ramp"),
            Unresolved::PoorFit {
                relative_residual,
                max_relative_residual,
            } => write!(
                f,
                "the fitted roots do not explain the response (relative residual \
                 {relative_residual:.3} above {max_relative_residual}): no sum of damped \
                 exponentials, e.g. a drifting frequency"
            ),
            Unresolved::LimitCycleWithoutGrowth {
                peak_normal_velocity,
                amplitude_growth,
                min_growth_factor,
            } => {
                write!(
                    f,
                    "limit cycle (peak normal velocity {peak_normal_velocity:.3e}) without a \
                     clear growth to it"
                )?;
                match amplitude_growth {
                    Some(g) => write!(f, ": amplitude ×{g:.2} from the first cycle"),
                    None => f.write_str(": no amplitude of the first cycle"),
                }?;
                write!(f, ", not ×{min_growth_factor:.2}")
            }
        }
    }
}
