//! Options, statistics and result of the modal solve.

use crate::ordering::{FillOrdering, NestedDissectionOptions, NestedDissectionStats};
use crate::{FeError, Real};
use faer::Mat;
use serde::{Deserialize, Serialize};

/// Modal solve options.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModalOptions {
    /// Number of lowest modes wanted (default: 20). `None` with `max_frequency_hz` set asks for
    /// every mode below that frequency; with both set, the lowest `n_modes` below it.
    pub n_modes: Option<usize>,
    /// Highest frequency of interest in Hz (default: none).
    pub max_frequency_hz: Option<Real>,
    /// Shift as a frequency in Hz, σ = −(2π·shift_hz)² (default: none = automatic,
    /// σ = −1e-8·median(K_ii/M_ii), far below the first elastic mode yet keeping K − σM
    /// well-conditioned for free-free models).
    pub shift_hz: Option<Real>,
    /// Convergence tolerance on the Lanczos residual bound ‖(K−σM)⁻¹Mx − θx‖_M ≤ tol·θ
    /// (default: 1e-6; eigenvalue errors are of order tol², and the bound stagnates near
    /// 1e-8 on ill-conditioned 100k-DOF free-free models).
    pub tol: Real,
    /// Block size of the block Lanczos (default: 8; ≥ the largest eigenvalue multiplicity
    /// wanted converges fastest).
    pub block_size: usize,
    /// Largest Krylov basis before a thick restart (default: 0 = automatic,
    /// max(2·n_modes, n_modes + 4·block_size)).
    pub max_basis: usize,
    /// Thick restarts allowed before returning `MaxIterations` (default: 50).
    pub max_restarts: usize,
    /// Problems with at most this many DOFs are solved densely (default: 400).
    pub dense_below: usize,
    /// Seed of the random starting block (default: 7).
    pub seed: u64,
    /// Fill-reducing ordering of the Cholesky factorisation (default: `auto` = nested
    /// dissection when DOF coordinates are given to
    /// [`solve_modes_with`](super::solve_modes_with) and n ≥ 20 000, AMD otherwise).
    pub ordering: FillOrdering,
    /// Nested-dissection parameters (default: [`NestedDissectionOptions::default`]).
    pub nested_dissection: NestedDissectionOptions,
    /// Asked before the factorisation and at every Lanczos block step; when set the solve
    /// returns `FeError::Interrupted` (default: never).
    #[serde(skip)]
    pub interrupt: crate::Interrupt,
    /// With nested dissection, factorise the two halves of its top level in parallel and
    /// solve with them in parallel ([`SplitCholesky`](crate::cholesky::SplitCholesky))
    /// (default: true; the same factor to round-off).
    pub split_factor: bool,
}

impl Default for ModalOptions {
    fn default() -> Self {
        ModalOptions {
            n_modes: Some(20),
            max_frequency_hz: None,
            shift_hz: None,
            tol: 1e-6,
            block_size: 8,
            max_basis: 0,
            max_restarts: 50,
            dense_below: 400,
            seed: 7,
            ordering: FillOrdering::Auto,
            nested_dissection: NestedDissectionOptions::default(),
            interrupt: crate::Interrupt::never(),
            split_factor: true,
        }
    }
}

impl ModalOptions {
    /// Checks the option values; errors name the field.
    pub fn validate(&self) -> Result<(), FeError> {
        let bad = |field: &str, value: Real, reason| {
            Err(FeError::InvalidValue {
                field: format!("modal.{field}"),
                value,
                reason,
            })
        };
        if self.n_modes.is_none() && self.max_frequency_hz.is_none() {
            return bad("n_modes", 0.0, "give n_modes, max_frequency_hz, or both");
        }
        if self.n_modes == Some(0) {
            return bad("n_modes", 0.0, "must be at least 1");
        }
        if let Some(f) = self.max_frequency_hz {
            if !(f > 0.0 && f.is_finite()) {
                return bad("max_frequency_hz", f, "must be finite and > 0");
            }
        }
        if let Some(f) = self.shift_hz {
            if !(f > 0.0 && f.is_finite()) {
                return bad(
                    "shift_hz",
                    f,
                    "must be finite and > 0 (sigma = -(2 pi f)^2)",
                );
            }
        }
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return bad("tol", self.tol, "must be in (0, 1)");
        }
        if self.block_size == 0 {
            return bad("block_size", 0.0, "must be at least 1");
        }
        self.nested_dissection.validate()
    }
}

/// Which factorisation of K − σM was used.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FactorKind {
    /// Sparse Cholesky LLᵀ (the normal case).
    Llt,
    /// Sparse LDLᵀ on the Cholesky structure (Cholesky failed: K − σM not positive definite).
    Ldlt,
    /// Sparse LU (both symmetric factorisations failed).
    Lu,
    /// Small problem solved densely (no sparse factorisation).
    Dense,
}

/// Modal solve statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModalStats {
    /// Problem size (free DOFs).
    pub n: usize,
    /// Shift σ used (ω² units).
    pub shift: Real,
    /// Factorisation used.
    pub factor_kind: FactorKind,
    /// Why a fall-back factorisation was used, if one was.
    pub fallback_reason: Option<String>,
    /// Fill-reducing ordering used (`None` for LU and dense).
    pub ordering: Option<FillOrdering>,
    /// Nested-dissection statistics, when it was used.
    pub nested_dissection: Option<NestedDissectionStats>,
    /// Stored entries of the factor L, including the explicit zeros of supernodes
    /// (0 for LU and dense).
    pub factor_nnz: usize,
    /// Whether the Cholesky factor is supernodal (else simplicial).
    pub supernodal: bool,
    /// Multiply–adds of the numeric factorisation, Σ_j n_j² over the columns of L
    /// (supernodal factors only, else 0).
    pub factor_flops: Real,
    /// Block Lanczos steps (one block solve each).
    pub iterations: usize,
    /// Thick restarts.
    pub restarts: usize,
    /// Numeric factorisations performed.
    pub factorisations: usize,
    /// Operator applications (K − σM)⁻¹M v, counted per vector.
    pub matvecs: usize,
    /// Products with M, counted per vector.
    pub m_products: usize,
    /// Block size used.
    pub block_size: usize,
    /// Largest Krylov basis used.
    pub max_basis: usize,
    /// Seconds in the symbolic and numeric factorisation (ordering included).
    pub factor_s: Real,
    /// Seconds computing the fill-reducing ordering (part of `factor_s`; AMD's time is inside
    /// faer's symbolic factorisation and not separated).
    pub ordering_s: Real,
    /// Seconds in the Lanczos iteration (solves, orthogonalisation, Rayleigh–Ritz).
    pub lanczos_s: Real,
    /// Seconds in the triangular solves (part of `lanczos_s`).
    pub solve_s: Real,
    /// The split factor's sizes and timings, when it was used.
    pub split: Option<crate::cholesky::SplitStats>,
    /// Seconds in Gram–Schmidt against the basis and the block QR, M products included
    /// (part of `lanczos_s`).
    pub orth_s: Real,
    /// Seconds in the Rayleigh–Ritz eigen-solves and thick restarts (part of `lanczos_s`).
    pub ritz_s: Real,
    /// Lanczos blocks whose Cholesky QR fell back to column-by-column Gram–Schmidt.
    pub qr_fallbacks: usize,
    /// Seconds forming the Rayleigh quotients, M-normalising and computing the residuals.
    pub post_s: Real,
    /// Total seconds.
    pub total_s: Real,
    /// Largest relative residual ‖Kφ − ω²Mφ‖ / max(‖Kφ‖, |σ|‖Mφ‖) of the returned modes.
    pub max_residual: Real,
}

/// Outcome of the iteration.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ModalStatus {
    /// All wanted Ritz pairs converged.
    Converged,
    /// Restarts exhausted; the first `converged` returned modes are converged.
    MaxIterations { converged: usize },
}

/// Result of [`solve_modes`](super::solve_modes), modes sorted by ascending ω².
#[derive(Debug, Clone)]
pub struct Modes {
    /// sign(ω²)·sqrt(|ω²|)/2π in Hz (rigid modes: ≈ 0, possibly slightly negative).
    pub frequencies_hz: Vec<Real>,
    /// ω² (Rayleigh quotients φᵀKφ of the M-normalised shapes).
    pub eigenvalues: Vec<Real>,
    /// Shapes over the free DOFs, n_free × n_modes, M-orthonormal.
    pub shapes: Mat<Real>,
    /// Statistics.
    pub stats: ModalStats,
    /// Convergence status.
    pub status: ModalStatus,
}
