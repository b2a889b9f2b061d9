//! Error of a run against the reference on the common time grid, and the growth rate and
//! frequency of the response.

use super::drive::RunOutcome;
use crate::verdict;
use serde::Serialize;

use squeal_solver::Real;

/// Errors of one run relative to the reference.
#[derive(Debug, Clone, Default, Serialize)]
pub struct RunErrors {
    /// max_k max_j |v_kj − v_ref,kj| / max_k max_j |v_ref,kj| (None: the run did not reach TFINAL).
    pub error: Option<Real>,
    /// RMS over time and DOFs of (v − v_ref), over the RMS of v_ref.
    pub error_rms: Option<Real>,
    /// Growth rate σ of the response envelope (1/time).
    pub growth_rate: Option<Real>,
    /// |σ − σ_ref| / |σ_ref|.
    pub growth_rate_error: Option<Real>,
    /// Dominant frequency of the response (Hz).
    pub frequency_hz: Option<Real>,
    /// |f − f_ref| / f_ref.
    pub frequency_error: Option<Real>,
}

/// Column of the response: the DOF with the largest |v| after `t_after` in the reference.
pub fn response_column(reference: &RunOutcome, t_after: Real) -> usize {
    let nd = reference.v.first().map_or(0, Vec::len);
    (0..nd)
        .max_by(|&a, &b| {
            let peak = |j: usize| {
                reference
                    .t
                    .iter()
                    .zip(&reference.v)
                    .filter(|(t, _)| **t > t_after)
                    .fold(0.0f64, |m, (_, v)| m.max(v[j].abs()))
            };
            peak(a).total_cmp(&peak(b))
        })
        .unwrap_or(0)
}

/// σ and f of column `col` after `t_after`.
pub fn growth_and_frequency(
    run: &RunOutcome,
    col: usize,
    t_after: Real,
) -> (Option<Real>, Option<Real>) {
    let x: Vec<Real> = run.v.iter().map(|v| v[col]).collect();
    let vd = verdict::analyse(&run.t, &x, t_after);
    (vd.growth_rate_per_s, vd.dominant_frequency_hz)
}

/// Errors of `run` against `reference` (same grid).
pub fn compare(run: &RunOutcome, reference: &RunOutcome, col: usize, t_after: Real) -> RunErrors {
    let (g, f) = growth_and_frequency(run, col, t_after);
    let (g_ref, f_ref) = growth_and_frequency(reference, col, t_after);
    let rel = |a: Option<Real>, b: Option<Real>| match (a, b) {
        (Some(a), Some(b)) if b != 0.0 => Some((a - b).abs() / b.abs()),
        _ => None,
    };
    let mut out = RunErrors {
        growth_rate: g,
        growth_rate_error: rel(g, g_ref),
        frequency_hz: f,
        frequency_error: rel(f, f_ref),
        ..Default::default()
    };
    if !run.reached || run.non_finite || run.v.len() != reference.v.len() {
        return out;
    }
    let (mut dmax, mut rmax, mut d2, mut r2, mut cnt) = (0.0f64, 0.0f64, 0.0, 0.0, 0usize);
    for (a, b) in run.v.iter().zip(&reference.v) {
        for (x, y) in a.iter().zip(b) {
            dmax = dmax.max((x - y).abs());
            rmax = rmax.max(y.abs());
            d2 += (x - y) * (x - y);
            r2 += y * y;
            cnt += 1;
        }
    }
    if cnt > 0 && rmax > 0.0 {
        out.error = Some(dmax / rmax);
        out.error_rms = Some((d2 / r2).sqrt());
    }
    out
}
