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

use super::validity::{ContactValidity, GapEvent};
use crate::scene::Integrator;
use num_complex::Complex64;
use serde::Serialize;
use squeal_solver::bdf::Status;

type Real = f64;

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
                write!(f, ": {}", super::status_text(status))
            }
            Unresolved::NoResponse => f.write_str("no response after the load ramp"),
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

/// Decay rate of the undamped oscillation y' = iωy, ω = 2πf, under the integrator at step h:
/// σ = −ln|ξ|/h with ξ the principal root of its characteristic equation.
///
/// # Reference
/// BDF1: ξ = 1/(1 − iωh). BDF2 (fixed step): (3/2 − iωh) ξ² − 2ξ + 1/2 = 0, the root of
/// largest modulus. Generalized-α: the algorithmic damping ζ̄ of the principal root,
/// σ = ζ̄ |ln ξ|/h (`squeal_solver::galpha::spectral`). At 40 steps per period BDF2 gives
/// ζ = 9.1e-4, at 20 steps 6.2e-3, at 10 steps 3.1e-2.
pub fn numerical_decay(
    integrator: Integrator,
    max_order: usize,
    rho_inf: Real,
    h: Real,
    f: Real,
) -> Real {
    let th = 2.0 * std::f64::consts::PI * f * h;
    if !(th.is_finite() && th > 0.0 && h > 0.0) {
        return 0.0;
    }
    let ln_abs = match (integrator, max_order) {
        (Integrator::GeneralizedAlpha, _) => {
            let co = squeal_solver::galpha::GalphaCoeffs::from_rho_inf(rho_inf);
            let d = squeal_solver::galpha::spectral::algorithmic_damping(&co, th);
            let s_norm = th / (1.0 + d.period_error);
            -d.zeta * s_norm / (1.0 - d.zeta * d.zeta).max(1e-300).sqrt()
        }
        (Integrator::Bdf, 1) => -0.5 * (1.0 + th * th).ln(),
        (Integrator::Bdf, _) => {
            // (3/2 − iθ) ξ² − 2ξ + 1/2 = 0.
            let a = Complex64::new(1.5, -th);
            let disc = (Complex64::new(4.0, 0.0) - 2.0 * a).sqrt();
            let r1 = (Complex64::new(2.0, 0.0) + disc) / (2.0 * a);
            let r2 = (Complex64::new(2.0, 0.0) - disc) / (2.0 * a);
            r1.norm().max(r2.norm()).ln()
        }
    };
    -ln_abs / h
}

/// The BDF steps a run took after the load ramp, by order: what the window's numerical decay
/// is made of. The BDF lowers its order where its error estimates ask for it (the cad brake
/// with pad damping GE = 0.1: 5 596 of 14 001 steps at order 1), and BDF1 damps an oscillation
/// far more than BDF2 at the same step (at 5.4 kHz and h = 2.5 µs: 1 455 /s against 5 /s).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct StepsByOrder {
    /// Accepted steps at order k (index k) from `t0` to the end of the run.
    pub counts: Vec<u64>,
    /// Where the count starts: the last chunk end at or before the end of the ramp (at most
    /// one chunk of steps early: the count errs towards more steps), or the run's start.
    pub t0: Real,
    /// The end of the run.
    pub t1: Real,
}

impl StepsByOrder {
    /// The mean numerical decay rate of an undamped oscillation at `f` over these steps, each
    /// taken at step `h` (the largest step of the window: an upper bound per step):
    /// σ = Σ_k n_k (−ln|ξ_k(2πfh)|) / (t1 − t0). None without steps or span.
    pub fn decay(&self, h: Real, f: Real) -> Option<Real> {
        let span = self.t1 - self.t0;
        let total: u64 = self.counts.iter().sum();
        if !(span > 0.0 && total > 0 && h > 0.0) {
            return None;
        }
        let per_step: Real = self
            .counts
            .iter()
            .enumerate()
            .filter(|(_, &n)| n > 0)
            .map(|(k, &n)| n as Real * numerical_decay(Integrator::Bdf, k.max(1), 0.0, h, f) * h)
            .sum();
        Some(per_step / span)
    }
}

/// A driver sink that counts the BDF's steps by order after the load ramp ([`StepsByOrder`]).
///
/// The order histogram is read at chunk ends (every [`super::driver::CHUNK`] steps and at
/// restart points); the count starts at the last chunk end at or before the end of the ramp,
/// so it may include up to one chunk of ramp steps (more steps: more decay, the conservative
/// side). It does not stop the integrator there (a stop at a given time changes the BDF's
/// steps). A restart carries the start point over: chunks restart at restart points in the
/// uninterrupted run too, so a resumed run counts from the same step.
pub struct OrderTally {
    t_after: Real,
    /// (time, cumulative order histogram) at the last chunk end at or before `t_after`.
    before: (Real, Vec<u64>),
    pub result: Option<StepsByOrder>,
}

impl OrderTally {
    /// Counts from `t_after` (the end of the ramp) in a run that started at `t_start`,
    /// continuing `resumed` (a restart checkpoint's `orders_at_ramp`).
    pub fn new(t_start: Real, t_after: Real, resumed: Option<(Real, Vec<u64>)>) -> Self {
        Self {
            t_after,
            before: resumed.unwrap_or((t_start, Vec::new())),
            result: None,
        }
    }

    fn histogram(stepper: &super::driver::Stepper) -> Option<Vec<u64>> {
        match stepper.stats() {
            super::driver::IntegratorStats::Bdf { bdf, .. } => Some(bdf.order_histogram),
            _ => None,
        }
    }
}

impl super::driver::Sink for OrderTally {
    fn step(&mut self, _s: &super::driver::StepView<'_>) -> Result<(), crate::PipelineError> {
        Ok(())
    }
    fn chunk_end(&mut self, c: &super::driver::ChunkView<'_>) -> Result<(), crate::PipelineError> {
        let t = c.stepper.t();
        if t <= self.t_after {
            if let Some(h) = Self::histogram(c.stepper) {
                self.before = (t, h);
            }
        }
        Ok(())
    }
    fn end(&mut self, e: &super::driver::EndView<'_>) -> Result<(), crate::PipelineError> {
        let (t0, before) = &self.before;
        self.result = Self::histogram(e.stepper).map(|end| StepsByOrder {
            counts: end
                .iter()
                .enumerate()
                .map(|(k, &n)| n.saturating_sub(before.get(k).copied().unwrap_or(0)))
                .collect(),
            t0: *t0,
            t1: e.stepper.t(),
        });
        Ok(())
    }
    fn checkpoint(&self, c: &mut super::restart::RunCheckpoint) {
        c.orders_at_ramp = Some(self.before.clone());
    }
}

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
mod tests {
    use super::*;

    /// BDF2's numerical damping ratio at N steps per period against the values computed from
    /// the characteristic root independently (numpy.roots on the same polynomial): 40 → 9.128e-4,
    /// 20 → 6.227e-3, 10 → 3.124e-2; BDF1 against ln(1 + θ²)/(2θ).
    #[test]
    fn numerical_decay_of_bdf1_and_bdf2() {
        let f = 1000.0;
        for (n, zeta) in [(40.0, 9.128e-4), (20.0, 6.227e-3), (10.0, 3.124e-2)] {
            let h = 1.0 / (n * f);
            let s = numerical_decay(Integrator::Bdf, 2, 0.9, h, f);
            let z = s / (2.0 * std::f64::consts::PI * f);
            assert!((z / zeta - 1.0).abs() < 1e-3, "N = {n}: {z} vs {zeta}");
        }
        let h = 1e-4;
        let th = 2.0 * std::f64::consts::PI * f * h;
        let s1 = numerical_decay(Integrator::Bdf, 1, 0.9, h, f);
        assert!((s1 - (1.0 + th * th).ln() / (2.0 * h)).abs() < 1e-9 * s1);
        // Generalized-α with ρ∞ = 1 is energy conserving: no decay.
        let s = numerical_decay(Integrator::GeneralizedAlpha, 2, 1.0, h, f);
        assert!(s.abs() < 1e-6, "{s}");
        assert!(numerical_decay(Integrator::GeneralizedAlpha, 2, 0.5, h, f) > 0.0);
    }

    fn base<'a>(c: &'a ContactValidity, st: &'a Status) -> Evidence<'a> {
        Evidence {
            clear_growth: false,
            window: [0.0, 0.02],
            h_max_window: Some(2.5e-6),
            steps_by_order: None,
            frequencies: vec![(FrequencySource::Dominant, 2000.0)],
            contact: c,
            separation: false,
            status: st,
            h_end: Some(2.5e-6),
            integrator: Integrator::Bdf,
            max_order: 2,
            rho_inf: 0.9,
            min_growth_rate_per_s: 100.0,
            min_growth_factor: 2.0,
            limit_cycle: None,
        }
    }

    /// BDF1 steps after the ramp count in the window's numerical decay (it once said
    /// `no_squeal` with the CEA's 5.4 kHz root at +298 /s: the cad brake with pad damping
    /// GE = 0.1 took 5 596 of its 14 001 steps at order 1, and the guard weighed BDF2's decay
    /// alone, 5 /s at h = 2.5 µs). Reference: BDF1 damps y' = iωy by ½ ln(1 + θ²) a step,
    /// θ = ωh (its amplification 1/(1 − iθ)).
    #[test]
    fn bdf1_steps_after_the_ramp_count_in_the_numerical_decay() {
        let (h, f) = (2.5e-6, 5437.0);
        let th = 2.0 * std::f64::consts::PI * f * h;
        let bdf1 = 0.5 * (1.0 + th * th).ln() / h;
        assert!((bdf1 - 1453.6).abs() < 0.5, "{bdf1}");
        let bdf2 = numerical_decay(Integrator::Bdf, 2, 0.9, h, f);
        assert!(bdf2 > 4.0 && bdf2 < 6.0, "{bdf2}");
        // Only order 2: the mean is BDF2's.
        let only2 = StepsByOrder {
            counts: vec![0, 0, 6000],
            t0: 0.02,
            t1: 0.02 + 6000.0 * h,
        };
        assert!((only2.decay(h, f).unwrap() - bdf2).abs() < 1e-9 * bdf2);
        // 5 596 BDF1 steps among 6 001: the mean is theirs, weighted.
        let mixed = StepsByOrder {
            counts: vec![0, 5596, 405],
            t0: 0.02,
            t1: 0.02 + 6001.0 * h,
        };
        let want = (5596.0 * bdf1 + 405.0 * bdf2) / 6001.0;
        let got = mixed.decay(h, f).unwrap();
        assert!((got - want).abs() < 1e-9 * want, "{got} {want}");
        let c = ContactValidity::default();
        let ok = Status::Reached { t: 0.035 };
        let mut e = base(&c, &ok);
        e.window = [0.02, 0.035];
        e.frequencies = vec![(FrequencySource::CeaUnstable, f)];
        assert_eq!(judge(&e).0, VerdictState::NoSqueal);
        e.steps_by_order = Some(&only2);
        assert_eq!(judge(&e).0, VerdictState::NoSqueal);
        e.steps_by_order = Some(&mixed);
        let (s, r, _) = judge(&e);
        assert!(
            matches!(&s, VerdictState::Unresolved { reasons } if matches!(reasons[0], Unresolved::StepsTooCoarse(_))),
            "{s:?}"
        );
        assert!(
            !r[0].resolved && r[0].numerical_decay_per_s > 1000.0,
            "{r:?}"
        );
        // Generalized-α runs have no order count: the scheme's own decay.
        e.integrator = Integrator::GeneralizedAlpha;
        assert!(judge(&e).1[0].numerical_decay_per_s < 1.0);
    }

    /// A reached limit cycle (separation on) with the fitted window showing no growth: its
    /// amplitude grew ×8 from the first cycle, so `squeal`; ×1.2 is not evidence of
    /// self-excitation but never `no_squeal` either.
    #[test]
    fn a_reached_limit_cycle_is_squeal_never_no_squeal() {
        let c = ContactValidity::default();
        let ok = Status::Reached { t: 0.02 };
        let mut e = base(&c, &ok);
        e.separation = true;
        assert_eq!(judge(&e).0, VerdictState::NoSqueal);
        e.limit_cycle = Some(LimitCycleEvidence {
            peak_normal_velocity: 3.0,
            amplitude_growth: Some(8.0),
        });
        assert_eq!(judge(&e).0, VerdictState::Squeal);
        for growth in [Some(1.2), None] {
            e.limit_cycle = Some(LimitCycleEvidence {
                peak_normal_velocity: 3.0,
                amplitude_growth: growth,
            });
            let s = judge(&e).0;
            assert!(
                matches!(&s, VerdictState::Unresolved { reasons }
                    if matches!(reasons[0], Unresolved::LimitCycleWithoutGrowth { .. })),
                "{s:?}"
            );
        }
    }

    /// Each guard turns a negative into `unresolved` with its reason; a clear growth stays
    /// `squeal` whatever else happened.
    #[test]
    fn guards_decide_the_state() {
        let c = ContactValidity::default();
        let ok = Status::Reached { t: 0.02 };
        assert_eq!(judge(&base(&c, &ok)).0, VerdictState::NoSqueal);
        // 0.02 s window: ln 2 / 0.02 = 34.7 /s ≤ 100.
        assert!((judge(&base(&c, &ok)).2.unwrap() - 2f64.ln() / 0.02).abs() < 1e-12);
        let mut e = base(&c, &ok);
        e.h_max_window = Some(2.1e-3); // the hex20 example's last step: 1 step per period
        let (s, r, _) = judge(&e);
        assert!(
            matches!(&s, VerdictState::Unresolved { reasons } if matches!(reasons[0], Unresolved::StepsTooCoarse(_))),
            "{s:?}"
        );
        assert!(!r[0].resolved && r[0].samples_per_period < 1.0);
        let mut e = base(&c, &ok);
        e.window = [0.0025, 0.006];
        assert!(matches!(judge(&e).0, VerdictState::Unresolved { .. }));
        let event = GapEvent {
            t: 0.0171,
            gap: 0,
            pressure: -3.0,
        };
        let tensile = ContactValidity {
            first_separation: Some(event),
            first_tensile_after_ramp: Some(event),
            ..Default::default()
        };
        let s = judge(&base(&tensile, &ok)).0;
        assert!(format!("{s:?}").contains("ContactTensile"), "{s:?}");
        // Tensile only while the load was applied (the start state under P0 alone): reported,
        // not judged.
        let during_ramp = ContactValidity {
            tensile_at_start: 7,
            first_separation: Some(GapEvent { t: 0.0, ..event }),
            judged_from: 5e-4,
            ..Default::default()
        };
        assert_eq!(judge(&base(&during_ramp, &ok)).0, VerdictState::NoSqueal);
        let mut e = base(&tensile, &ok);
        e.separation = true;
        assert_eq!(judge(&e).0, VerdictState::NoSqueal);
        let collapsed = Status::StepSizeTooSmall {
            t: 0.019,
            h: 1e-14,
            order: 1,
            residual_norm: 1.0,
        };
        let s = judge(&base(&c, &collapsed)).0;
        assert!(matches!(s, VerdictState::Unresolved { .. }), "{s:?}");
        let mut e = base(&tensile, &collapsed);
        e.clear_growth = true;
        assert_eq!(judge(&e).0, VerdictState::Squeal);
    }
}
