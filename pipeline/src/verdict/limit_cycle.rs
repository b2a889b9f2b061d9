//! The limit cycle of a squealing run with separation: the stationary amplitude of the
//! rotor friction face's normal velocity, which the CEA (a linearisation about the steady
//! state) cannot give.
//!
//! The face monitor (a data-only sink of the driver) records, at every accepted step, the normal velocity of the rotor at each
//! gap, v_n,g = v_rotor,g · n_g (the friction face moving along the pad normal), as its
//! largest magnitude over the gaps and its mean square over the gaps ([`FaceSeries`]).
//! [`analyse`] cuts the
//! record after the load ramp into windows one period 1/f long (f: the verdict's dominant
//! frequency) and looks at the last [`CYCLES`] of them: the limit cycle is **reached** when the
//! peaks of those windows vary by less than [`TOLERANCE`] of their largest (a stationary
//! envelope) and the run had at least 2·[`CYCLES`] windows; the amplitude reported is the RMS
//! (time and gaps) and the peak over those last cycles.

use serde::Serialize;
use squeal_solver::Real;

/// Cycles over which the envelope must be stationary.
pub const CYCLES: usize = 10;
/// Largest relative variation of the per-cycle peaks of a stationary envelope.
pub const TOLERANCE: Real = 0.05;
/// The response saturates (leaves its linear growth) when its per-step peak first reaches
/// this fraction of the limit cycle's peak: the growth is fitted before it.
pub const SATURATION_LEVEL: Real = 0.5;

/// How a response reached its limit cycle: the time it saturated and the amplitude it grew
/// by. A reached limit cycle whose amplitude grew by the verdict's factor from the first
/// cycle after the ramp is a self-excited oscillation, i.e. squeal.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Saturation {
    /// End of the linear growth, where the roots are fitted to: the earlier of `t` and the
    /// first gap opening after the ramp (the contact set changes there; a gap that opened
    /// during the ramp is not counted).
    pub growth_end: Real,
    /// First time after the ramp the per-step peak reached `level`.
    pub t: Real,
    /// [`SATURATION_LEVEL`] × the limit cycle's peak.
    pub level: Real,
    /// Peak of the first cycle (1/f) after the ramp.
    pub first_cycle_peak: Real,
    /// The limit cycle's peak / `first_cycle_peak`.
    pub amplitude_growth: Real,
}

/// The limit cycle as `summary.json` reports it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LimitCycle {
    /// The envelope was stationary over the last cycles.
    pub reached: bool,
    /// Frequency the cycles were cut with (the verdict's dominant frequency).
    pub frequency_hz: Real,
    /// Cycles (windows of 1/f) after the ramp in the record.
    pub cycles_recorded: usize,
    /// Cycles analysed (the last ones, at most [`CYCLES`]).
    pub cycles_analysed: usize,
    /// RMS of the rotor friction face's normal velocity over those cycles (time and gaps).
    pub rms_normal_velocity: Real,
    /// Largest |normal velocity| of the rotor friction face over those cycles.
    pub peak_normal_velocity: Real,
    /// (max − min)/max of the per-cycle peaks over those cycles.
    pub envelope_variation: Real,
}

/// The per-step record of the rotor friction face's normal velocity.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct FaceSeries {
    pub t: Vec<Real>,
    /// max_g |v_n,g| per step.
    pub peak: Vec<Real>,
    /// mean_g v_n,g² per step.
    pub mean_square: Vec<Real>,
    /// Gaps open per step (p_n A within the round-off band of zero or below: the contact
    /// carries no force there). Empty when the run did not count them.
    pub open: Vec<u32>,
}

/// A response that grew while the load was still being applied, was held by the contact
/// opening before the ramp ended, and stayed at that amplitude after it: the growth is fitted
/// from the run's start to `first_opening`, the oscillation after the ramp is judged by its
/// per-cycle peaks ([`FaceSeries::after_ramp`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RampSaturation {
    /// The first gap opening after one whole cycle with every gap closed (the growth's end).
    pub first_opening: Real,
    /// The per-cycle peaks after the ramp ([`CycleTrend`]).
    #[serde(flatten)]
    pub after_ramp: CycleTrend,
}

/// The per-cycle peaks of the face's normal velocity after the ramp, cut into windows of one
/// period.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct CycleTrend {
    /// Whole cycles after the ramp.
    pub cycles: usize,
    /// Least-squares slope of ln(peak) over the cycles' mid-times, 1/s (≥ 0: not decaying).
    pub envelope_trend_per_s: Real,
    /// Largest and last per-cycle peak, m/s.
    pub max_peak: Real,
    pub last_peak: Real,
    /// Cycles in which some gap was open.
    pub cycles_with_open_gaps: usize,
}

impl CycleTrend {
    /// The oscillation is sustained and held by the contact: at least 2·[`CYCLES`] cycles,
    /// no decay faster than `min_rate` (1/s, the smallest growth that matters: a decay at that
    /// rate shows as −`min_rate`), and a gap open in at least half the cycles.
    pub fn sustained_by_separation(&self, min_rate: Real) -> bool {
        self.cycles >= 2 * CYCLES
            && self.envelope_trend_per_s >= -min_rate
            && 2 * self.cycles_with_open_gaps >= self.cycles
    }
}

impl FaceSeries {
    /// The limit cycle of the record after `t_from` at `frequency_hz`.
    pub fn analyse(&self, t_from: Real, frequency_hz: Option<Real>) -> Option<LimitCycle> {
        analyse(
            &self.t,
            &self.peak,
            &self.mean_square,
            t_from,
            frequency_hz?,
        )
    }

    /// Where the record after `t_from` saturated into `lc` (see [`saturation`]).
    pub fn saturation(
        &self,
        t_from: Real,
        lc: &LimitCycle,
        first_opening: Option<Real>,
    ) -> Option<Saturation> {
        saturation(&self.t, &self.peak, t_from, lc, first_opening)
    }

    /// The first step with an open gap after one whole period 1/`frequency_hz` in which every
    /// gap was closed (a loaded contact that then opens; the gaps that carry no load at the
    /// very start of a ramp are not an opening). None without open counts or without such a
    /// step.
    pub fn first_opening_after_closure(&self, frequency_hz: Real) -> Option<Real> {
        if self.open.len() != self.t.len() || frequency_hz.is_nan() || frequency_hz <= 0.0 {
            return None;
        }
        let period = 1.0 / frequency_hz;
        let mut closed_since: Option<Real> = None;
        for (&t, &o) in self.t.iter().zip(&self.open) {
            match (o, closed_since) {
                (0, None) => closed_since = Some(t),
                (0, Some(_)) => {}
                (_, Some(t0)) if t - t0 >= period => return Some(t),
                (_, _) => closed_since = None,
            }
        }
        None
    }

    /// The per-cycle peaks after `t_from` in windows of 1/`frequency_hz` (None without open
    /// counts, a positive frequency, or two whole cycles).
    pub fn after_ramp(&self, t_from: Real, frequency_hz: Real) -> Option<CycleTrend> {
        if self.open.len() != self.t.len() || !(frequency_hz > 0.0 && frequency_hz.is_finite()) {
            return None;
        }
        let period = 1.0 / frequency_hz;
        let t0 = t_from.max(*self.t.first()?);
        let cycles = ((*self.t.last()? - t0) / period).floor() as usize;
        if cycles < 2 {
            return None;
        }
        let mut peaks = vec![0.0 as Real; cycles];
        let mut open = vec![false; cycles];
        for i in 0..self.t.len() {
            let x = (self.t[i] - t0) / period;
            if x < 0.0 || x >= cycles as Real {
                continue;
            }
            let w = x as usize;
            peaks[w] = peaks[w].max(self.peak[i]);
            open[w] |= self.open[i] > 0;
        }
        // ln(peak) against the cycle's mid-time, least squares; a zero peak has no logarithm
        // and makes the trend −∞ (a response that died out).
        let mid = |k: usize| (k as Real + 0.5) * period;
        let n = cycles as Real;
        let (tm, lm) = peaks
            .iter()
            .enumerate()
            .fold((0.0, 0.0), |(a, b), (k, &p)| {
                (a + mid(k) / n, b + p.ln() / n)
            });
        let (mut sxy, mut sxx) = (0.0, 0.0);
        for (k, &p) in peaks.iter().enumerate() {
            let dx = mid(k) - tm;
            sxy += dx * (p.ln() - lm);
            sxx += dx * dx;
        }
        let trend = if peaks.iter().any(|&p| p.is_nan() || p <= 0.0) {
            Real::NEG_INFINITY
        } else {
            sxy / sxx
        };
        Some(CycleTrend {
            cycles,
            envelope_trend_per_s: trend,
            max_peak: peaks.iter().cloned().fold(0.0, Real::max),
            last_peak: peaks[cycles - 1],
            cycles_with_open_gaps: open.iter().filter(|&&o| o).count(),
        })
    }
}

/// The saturation of a record (t, per-step peak) after `t_from` into the limit cycle `lc`:
/// the first time the peak reaches [`SATURATION_LEVEL`] × `lc.peak_normal_velocity`, and the
/// growth of the amplitude from the first cycle after `t_from` to the limit cycle; the growth
/// ends there or at `first_opening` (the run's first gap opening) when that is after
/// `t_from`. None without a positive peak in the first cycle or without a crossing of the
/// level.
pub fn saturation(
    t: &[Real],
    peak: &[Real],
    t_from: Real,
    lc: &LimitCycle,
    first_opening: Option<Real>,
) -> Option<Saturation> {
    if !(lc.frequency_hz > 0.0 && lc.peak_normal_velocity > 0.0) {
        return None;
    }
    let t0 = t_from.max(*t.first()?);
    let first_end = t0 + 1.0 / lc.frequency_hz;
    let first_cycle_peak = t
        .iter()
        .zip(peak)
        .filter(|(&ti, _)| ti >= t0 && ti < first_end)
        .fold(0.0 as Real, |m, (_, &p)| m.max(p));
    if first_cycle_peak.is_nan() || first_cycle_peak <= 0.0 {
        return None;
    }
    let level = SATURATION_LEVEL * lc.peak_normal_velocity;
    let i = (0..t.len()).find(|&i| t[i] >= t0 && peak[i] >= level)?;
    let growth_end = first_opening
        .filter(|&o| o > t0)
        .map_or(t[i], |o| o.min(t[i]));
    Some(Saturation {
        growth_end,
        t: t[i],
        level,
        first_cycle_peak,
        amplitude_growth: lc.peak_normal_velocity / first_cycle_peak,
    })
}

/// The limit cycle of a record (t, per-step peak, per-step mean square) after `t_from`, cut
/// into windows of 1/`frequency_hz` (see the module docs). None without a positive frequency
/// or without a whole cycle after `t_from`.
pub fn analyse(
    t: &[Real],
    peak: &[Real],
    mean_square: &[Real],
    t_from: Real,
    frequency_hz: Real,
) -> Option<LimitCycle> {
    if !(frequency_hz > 0.0 && frequency_hz.is_finite()) || t.is_empty() {
        return None;
    }
    let period = 1.0 / frequency_hz;
    let t_end = *t.last()?;
    let t0 = t_from.max(t[0]);
    let recorded = ((t_end - t0) / period).floor() as usize;
    if recorded == 0 {
        return None;
    }
    let analysed = recorded.min(CYCLES);
    let start = t_end - analysed as Real * period;
    let mut peaks = vec![0.0 as Real; analysed];
    let (mut integral, mut span) = (0.0, 0.0);
    for i in 0..t.len() {
        if t[i] < start {
            continue;
        }
        let w = (((t[i] - start) / period) as usize).min(analysed - 1);
        peaks[w] = peaks[w].max(peak[i]);
        if i > 0 && t[i - 1] >= start {
            let h = t[i] - t[i - 1];
            integral += 0.5 * h * (mean_square[i] + mean_square[i - 1]);
            span += h;
        }
    }
    let hi = peaks.iter().cloned().fold(0.0, Real::max);
    let lo = peaks.iter().cloned().fold(Real::INFINITY, Real::min);
    let variation = if hi > 0.0 { (hi - lo) / hi } else { 0.0 };
    Some(LimitCycle {
        reached: recorded >= 2 * CYCLES && hi > 0.0 && variation < TOLERANCE,
        frequency_hz,
        cycles_recorded: recorded,
        cycles_analysed: analysed,
        rms_normal_velocity: if span > 0.0 {
            (integral / span).sqrt()
        } else {
            0.0
        },
        peak_normal_velocity: hi,
        envelope_variation: variation,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sine of amplitude a·min(1, t/τ): reached once the envelope stops growing; RMS a/√2.
    fn record(a: Real, tau: Real, t_end: Real) -> (Vec<Real>, Vec<Real>, Vec<Real>) {
        let w = 2.0 * std::f64::consts::PI * 10.0;
        let (mut t, mut p, mut m) = (Vec::new(), Vec::new(), Vec::new());
        let n = (t_end * 2000.0) as usize;
        for i in 0..=n {
            let ti = i as Real / 2000.0;
            let v = a * (ti / tau).min(1.0) * (w * ti).sin();
            t.push(ti);
            p.push(v.abs());
            m.push(v * v);
        }
        (t, p, m)
    }

    #[test]
    fn stationary_sine_is_reached_with_its_rms_and_peak() {
        let (t, p, m) = record(2.0, 0.5, 4.0);
        let lc = analyse(&t, &p, &m, 0.0, 10.0).unwrap();
        assert!(lc.reached, "{lc:?}");
        assert!((lc.rms_normal_velocity - 2.0 / 2f64.sqrt()).abs() < 1e-3);
        assert!((lc.peak_normal_velocity - 2.0).abs() < 1e-3);
    }

    /// The ramped sine a·min(1, t/τ)·sin(ωt): half the limit cycle's peak is first reached
    /// near t = τ/2 (at a crest, within a period), and the amplitude grew from the first
    /// cycle's peak a·(1/f)/τ (to one period's resolution) to a.
    #[test]
    fn saturation_is_where_the_envelope_reaches_half_the_limit_cycle() {
        let (a, tau, f) = (2.0, 0.5, 10.0);
        let (t, p, m) = record(a, tau, 4.0);
        let lc = analyse(&t, &p, &m, 0.0, f).unwrap();
        let s = saturation(&t, &p, 0.0, &lc, None).unwrap();
        assert!((s.t - 0.5 * tau).abs() <= 1.0 / f, "{s:?}");
        assert_eq!(s.growth_end, s.t);
        // A gap that opened before the level was reached ends the growth there; one that
        // opened before `t_from` (during the ramp) does not.
        let early = saturation(&t, &p, 0.0, &lc, Some(0.1)).unwrap();
        assert_eq!((early.growth_end, early.t), (0.1, s.t));
        let ramp = saturation(&t, &p, 0.05, &lc, Some(0.01)).unwrap();
        assert_eq!(ramp.growth_end, ramp.t);
        assert!((s.level - 0.5 * a).abs() < 1e-3, "{s:?}");
        // First cycle: the largest of a·(t/τ)|sin ωt| over t < 1/f = 0.1 is at the second
        // crest, t ≈ 0.075: 2·0.15 = 0.30; below the ramp's value at 1/f, 0.4.
        let first = s.first_cycle_peak;
        assert!(first > 0.2 && first < a * (1.0 / f) / tau, "{s:?}");
        assert!((s.amplitude_growth - lc.peak_normal_velocity / first).abs() < 1e-12);
        assert!(s.amplitude_growth > 5.0, "{s:?}");
    }

    /// e^{σt} sin(ωt) at 10 Hz from t = 0, with a gap open at the start (t < 0.05) and
    /// wherever the peak is above 1.5: the first opening after a closed cycle is the first
    /// crest above 1.5, and the per-cycle peaks after 1 s grow at σ.
    #[test]
    fn first_opening_after_closure_and_the_trend_of_the_cycle_peaks() {
        let (sigma, f) = (0.3, 10.0);
        let w = 2.0 * std::f64::consts::PI * f;
        let mut s = FaceSeries::default();
        for i in 0..=8000 {
            let t = i as Real / 2000.0;
            let v = (sigma * t).exp() * (w * t).sin();
            s.t.push(t);
            s.peak.push(v.abs());
            s.mean_square.push(v * v);
            s.open.push(u32::from(t < 0.05 || v.abs() > 1.5));
        }
        let t_open = s.first_opening_after_closure(f).unwrap();
        let crest = (1.5f64).ln() / sigma;
        assert!(
            t_open >= crest && t_open < crest + 1.0 / f,
            "{t_open} (crest {crest})"
        );
        let c = s.after_ramp(1.0, f).unwrap();
        assert_eq!(c.cycles, 30);
        // Per-cycle peaks e^{σ t_crest}: ln is linear in the cycle with slope σ (the crest's
        // offset in the cycle is the same in each).
        assert!((c.envelope_trend_per_s - sigma).abs() < 1e-3, "{c:?}");
        assert!(c.sustained_by_separation(100.0), "{c:?}");
        // No open counts: no answer.
        let none = FaceSeries {
            open: Vec::new(),
            ..s.clone()
        };
        assert!(none.first_opening_after_closure(f).is_none());
        assert!(none.after_ramp(1.0, f).is_none());
        // Closed throughout after the start: no opening, and not held by separation.
        let closed = FaceSeries {
            open: s.t.iter().map(|&t| u32::from(t < 0.05)).collect(),
            ..s
        };
        assert!(closed.first_opening_after_closure(f).is_none());
        assert!(!closed
            .after_ramp(1.0, f)
            .unwrap()
            .sustained_by_separation(100.0));
    }

    #[test]
    fn growing_envelope_is_not_reached() {
        let (t, p, m) = record(2.0, 10.0, 4.0);
        let lc = analyse(&t, &p, &m, 0.0, 10.0).unwrap();
        assert!(!lc.reached, "{lc:?}");
        assert!(lc.envelope_variation > TOLERANCE);
    }
}
