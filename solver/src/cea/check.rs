//! Error control of the projected method: comparison with exact eigenvalues.

use super::Mode;
use serde::Serialize;

/// Projected versus exact eigenvalues in a frequency band.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct EigenvalueComparison {
    /// Upper end of the band compared, Hz (modes with frequency ≤ it; real roots included).
    pub band_hz: f64,
    /// Exact modes in the band (each compared with its nearest projected eigenvalue).
    pub n_exact_in_band: usize,
    /// Projected modes in the band (≠ `n_exact_in_band`: a root missed or spurious).
    pub n_projected_in_band: usize,
    /// max over the exact modes in the band of |p_proj − p_exact| / |p_exact|
    /// (absolute difference where p_exact = 0).
    pub max_rel_error: f64,
    /// max |Re p_proj − Re p_exact| over the same pairs (absolute, 1/s).
    pub max_real_part_error: f64,
    /// Frequency of the exact mode with the largest relative error, Hz.
    pub worst_frequency_hz: f64,
}

/// Compares projected with exact modes: each exact mode with frequency ≤ `band_hz` is
/// paired with the projected eigenvalue nearest to it in the complex plane.
pub fn compare_eigenvalues(
    projected: &[Mode],
    exact: &[Mode],
    band_hz: f64,
) -> EigenvalueComparison {
    let mut c = EigenvalueComparison {
        band_hz,
        n_projected_in_band: projected
            .iter()
            .filter(|m| m.frequency_hz <= band_hz)
            .count(),
        ..EigenvalueComparison::default()
    };
    for e in exact.iter().filter(|m| m.frequency_hz <= band_hz) {
        c.n_exact_in_band += 1;
        let Some(p) = projected.iter().min_by(|a, b| {
            (a.eigenvalue - e.eigenvalue)
                .norm()
                .total_cmp(&(b.eigenvalue - e.eigenvalue).norm())
        }) else {
            c.max_rel_error = f64::INFINITY;
            continue;
        };
        let d = (p.eigenvalue - e.eigenvalue).norm();
        let scale = e.eigenvalue.norm();
        let rel = if scale > 0.0 { d / scale } else { d };
        if rel > c.max_rel_error {
            c.max_rel_error = rel;
            c.worst_frequency_hz = e.frequency_hz;
        }
        c.max_real_part_error = c.max_real_part_error.max((p.real_part - e.real_part).abs());
    }
    c
}

/// How an exact check of a projected sweep ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum CheckKind {
    /// The dense exact CEA: every root of the band compared.
    #[default]
    Dense,
    /// The shift-invert refinement of the in-band unstable projected roots (above
    /// `projection.auto_single_min_dofs` reduced DOFs, where the dense CEA takes minutes):
    /// those roots (and the projected roots near the shifts) compared with their exact values.
    Refine,
}

/// One exact check of a projected sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ExactCheck {
    /// Step index.
    pub step: usize,
    /// Friction coefficient.
    pub mu: f64,
    /// How the exact values were computed.
    pub kind: CheckKind,
    /// The comparison (with `refine`: `n_exact_in_band` = exact roots found, refined targets
    /// plus missed ones; `n_projected_in_band` = targets; the errors over the refined roots).
    pub comparison: EigenvalueComparison,
    /// Wall time of the exact solve (eigenvalues only), seconds.
    pub time_s: f64,
}
