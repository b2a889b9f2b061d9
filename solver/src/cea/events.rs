//! Mode-coupling events along a sweep: coalescence (lock-in) and veering of tracked branches.

use super::track::mac;
use super::Mode;
use serde::Serialize;

/// What happens between two branches of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ModeEvent {
    /// Two branches' frequencies merge and their real parts split (a mode-coupling or
    /// "lock-in" instability: the eigenvalues meet at an exceptional point).
    Coalescence {
        /// The two track ids (lower frequency first at the last step before the lock).
        tracks: [usize; 2],
        /// μ of the coalescence: the zero of the squared frequency gap, linearly
        /// interpolated between the last two steps before the lock (the gap of a pair near an
        /// exceptional point goes as sqrt(μc − μ)).
        mu: f64,
        /// Frequency at the coalescence (mean of the pair at the first locked step), Hz.
        frequency_hz: f64,
        /// First step of the lock.
        step: usize,
        /// Last step of the lock (the pair stays locked through the rest of the sweep when it
        /// equals the last step).
        last_step: usize,
    },
    /// Two branches approach in frequency and part again without merging, exchanging their
    /// shapes (curve veering).
    Veering {
        /// The two track ids (lower frequency first).
        tracks: [usize; 2],
        /// μ of the closest approach (the step with the smallest gap).
        mu: f64,
        /// Smallest frequency gap, Hz.
        min_gap_hz: f64,
        /// Mean frequency there, Hz.
        frequency_hz: f64,
        /// Step of the closest approach.
        step: usize,
        /// MAC of the lower branch before the veering with the upper one after it (≈ 1 when
        /// the shapes are exchanged).
        mac_exchange: f64,
    },
}

/// Thresholds of the event detection.
#[derive(Debug, Clone, Copy)]
pub(crate) struct EventTolerances {
    /// Relative frequency gap below which two branches are locked.
    pub lock: f64,
    /// Relative frequency gap below which a closest approach counts as a veering candidate.
    pub veer: f64,
    /// Smallest exchange MAC (shape of one branch before ≈ shape of the other after).
    pub exchange_mac: f64,
}

/// One step of a branch pair: μ, the two modes.
pub(crate) struct PairStep<'a> {
    pub mu: f64,
    pub a: &'a Mode,
    pub b: &'a Mode,
}

fn rel_gap(a: &Mode, b: &Mode) -> f64 {
    let f = 0.5 * (a.frequency_hz + b.frequency_hz);
    if f > 0.0 {
        (a.frequency_hz - b.frequency_hz).abs() / f
    } else {
        f64::INFINITY
    }
}

/// The coalescences of one pair of branches over the steps they share (consecutive).
pub(crate) fn coalescences(
    ids: [usize; 2],
    first_step: usize,
    steps: &[PairStep<'_>],
    tol: &EventTolerances,
) -> Vec<ModeEvent> {
    let mut out = Vec::new();
    let locked = |s: &PairStep<'_>| {
        // Locked: equal frequencies, and the roots split in real part (one grows relative to
        // the other) — a pair of real roots (f = 0) is not a mode coupling.
        s.a.frequency_hz > 0.0 && rel_gap(s.a, s.b) <= tol.lock
    };
    let mut k = 1;
    while k < steps.len() {
        if locked(&steps[k]) && !locked(&steps[k - 1]) {
            let start = k;
            while k + 1 < steps.len() && locked(&steps[k + 1]) {
                k += 1;
            }
            // Zero of gap² (in Hz²) between the last unlocked step and the first locked one,
            // extrapolated from the two unlocked steps before it when there are two.
            let g2 = |s: &PairStep<'_>| (s.a.frequency_hz - s.b.frequency_hz).powi(2);
            let (s0, s1) = if start >= 2 {
                (&steps[start - 2], &steps[start - 1])
            } else {
                (&steps[start - 1], &steps[start])
            };
            let (y0, y1) = (g2(s0), g2(s1));
            let mu = if y1 < y0 {
                let mu = s1.mu + y1 * (s1.mu - s0.mu) / (y0 - y1);
                mu.clamp(steps[start - 1].mu, steps[start].mu)
            } else {
                0.5 * (steps[start - 1].mu + steps[start].mu)
            };
            let s = &steps[start];
            let low_first = steps[start - 1].a.frequency_hz <= steps[start - 1].b.frequency_hz;
            out.push(ModeEvent::Coalescence {
                tracks: if low_first { ids } else { [ids[1], ids[0]] },
                mu,
                frequency_hz: 0.5 * (s.a.frequency_hz + s.b.frequency_hz),
                step: first_step + start,
                last_step: first_step + k,
            });
        }
        k += 1;
    }
    out
}

/// A veering of the pair (a, b) at the middle of three consecutive steps: an interior local
/// minimum of the relative frequency gap, above the lock tolerance and below the veering one,
/// with the branches keeping their frequency order (a crossing of uncoupled modes swaps it:
/// the tracker follows the shapes) while their shapes are exchanged (the MAC of a before with
/// b after, and of b before with a after, exceeds each branch's MAC with itself). Needs the
/// shapes at the outer steps.
pub(crate) fn veering(
    ids: [usize; 2],
    step: usize,
    w: [PairStep<'_>; 3],
    tol: &EventTolerances,
) -> Option<ModeEvent> {
    let [before, mid, after] = w;
    let (g_prev, g, g_next) = (
        rel_gap(before.a, before.b),
        rel_gap(mid.a, mid.b),
        rel_gap(after.a, after.b),
    );
    if !(g < g_prev && g <= g_next && g > tol.lock && g <= tol.veer) {
        return None;
    }
    let order = |s: &PairStep<'_>| (s.a.frequency_hz - s.b.frequency_hz).signum();
    if order(&before) != order(&mid) || order(&mid) != order(&after) {
        return None;
    }
    let shape = |m: &Mode| (!m.shape.is_empty()).then_some(());
    shape(before.a)?;
    shape(before.b)?;
    shape(after.a)?;
    shape(after.b)?;
    let exchange = mac(&before.a.shape, &after.b.shape).min(mac(&before.b.shape, &after.a.shape));
    let keep = mac(&before.a.shape, &after.a.shape).max(mac(&before.b.shape, &after.b.shape));
    if exchange < tol.exchange_mac || exchange <= keep {
        return None;
    }
    let low_first = mid.a.frequency_hz <= mid.b.frequency_hz;
    Some(ModeEvent::Veering {
        tracks: if low_first { ids } else { [ids[1], ids[0]] },
        mu: mid.mu,
        min_gap_hz: (mid.a.frequency_hz - mid.b.frequency_hz).abs(),
        frequency_hz: 0.5 * (mid.a.frequency_hz + mid.b.frequency_hz),
        step,
        mac_exchange: exchange,
    })
}
