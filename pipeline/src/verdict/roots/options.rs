//! The estimator's options.
use squeal_solver::Real;

/// Options of the estimator.
#[derive(Debug, Clone, PartialEq)]
pub struct PencilOptions {
    /// Largest model order M, i.e. complex roots (default: 40 = 20 oscillating pairs).
    pub max_order: usize,
    /// Singular values below `sv_floor`·s₁ are noise (default: 1e-7).
    pub sv_floor: Real,
    /// A ratio s_k/s_{k+1} at least this large is a signal/noise gap (default: 100).
    pub gap_ratio: Real,
    /// Most uniform samples per channel (default: 1500; Δt grows to keep within it).
    pub max_samples: usize,
    /// Largest pencil parameter L (default: 300; L = N/3 below it).
    pub max_pencil: usize,
    /// Samples per period of the dominant frequency (default: 20).
    pub samples_per_period: Real,
    /// Samples per period at the top of the band (default: 4: Nyquist at twice the band).
    pub band_samples_per_period: Real,
    /// A root counts (for the verdict) when its amplitude at the window's end is at least
    /// this fraction of the largest (default: 0.01).
    pub significance: Real,
    /// Refits on the later parts of the window (default: 2: [t0 + kT/6, t1], k = 1, 2; 0:
    /// none, every root counts as consistent).
    pub refits: usize,
    /// A root is found again in a refit when the refit has a root within this fraction of
    /// its frequency (default: 0.01) …
    pub refit_frequency_tol: Real,
    /// … or within this fraction of the refit window's resolution 1/T_r, whichever is
    /// larger (default: 0.25).
    pub refit_resolution_fraction: Real,
    /// The fitted roots explain the response when the fit's relative residual
    /// ‖v − Σ a e^{st}‖/‖v‖ is at most this (default: 0.2; the sample study's fits are
    /// 4e-6–0.055). Above it the response is no sum of damped exponentials (a chirp, a
    /// drifting frequency) and neither a growth nor a decay is claimed.
    pub max_relative_residual: Real,
}

impl Default for PencilOptions {
    fn default() -> Self {
        Self {
            max_order: 40,
            sv_floor: 1e-7,
            gap_ratio: 100.0,
            max_samples: 1500,
            max_pencil: 300,
            samples_per_period: 20.0,
            band_samples_per_period: 4.0,
            significance: 0.01,
            refits: 2,
            refit_frequency_tol: 0.01,
            refit_resolution_fraction: 0.25,
            max_relative_residual: 0.2,
        }
    }
}
