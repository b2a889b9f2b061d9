//! The response's roots beside a CEA's.

use super::pencil::Root;
use serde::Serialize;
use squeal_solver::Real;

/// A transient root next to the CEA root nearest in frequency.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct RootPair {
    pub transient_growth_rate_per_s: Real,
    pub transient_frequency_hz: Real,
    pub transient_amplitude_end: Real,
    /// The transient root's σ over the fit and its refits ([`Root::growth_rate_range_per_s`]).
    pub transient_growth_rate_range_per_s: [Real; 2],
    /// Found again in every refit.
    pub transient_consistent: bool,
    pub cea_real_part: Real,
    pub cea_frequency_hz: Real,
    /// (σ_transient − Re p)/|Re p|.
    pub rel_diff_growth: Real,
    /// (f_transient − f_CEA)/f_CEA.
    pub rel_diff_frequency: Real,
}

/// Pairs each significant transient root with the CEA root (frequency Hz, Re p) nearest in
/// the complex plane, |Δσ + i2πΔf| (two CEA roots a few Hz apart, one stable and one not, are
/// told apart by σ); the transient's largest roots first.
pub fn pair_with_cea(roots: &[Root], cea: &[(Real, Real)]) -> Vec<RootPair> {
    let dist = |r: &Root, c: &(Real, Real)| {
        (r.growth_rate_per_s - c.1).hypot(2.0 * std::f64::consts::PI * (r.frequency_hz - c.0))
    };
    roots
        .iter()
        .filter(|r| r.significant)
        .filter_map(|r| {
            let &(f, re) = cea
                .iter()
                .min_by(|a, b| dist(r, a).total_cmp(&dist(r, b)))?;
            Some(RootPair {
                transient_growth_rate_per_s: r.growth_rate_per_s,
                transient_frequency_hz: r.frequency_hz,
                transient_amplitude_end: r.amplitude_end,
                transient_growth_rate_range_per_s: r.growth_rate_range_per_s,
                transient_consistent: r.consistent,
                cea_real_part: re,
                cea_frequency_hz: f,
                rel_diff_growth: (r.growth_rate_per_s - re) / re.abs(),
                rel_diff_frequency: (r.frequency_hz - f) / f,
            })
        })
        .collect()
}
