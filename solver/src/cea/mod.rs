//! Complex eigenvalue analysis (CEA) about a steady sliding state, without spurious roots.
//! [Paper eqs. (19)–(24)]
//!
//! # The linearised problem
//! The equilibrium (eq. 8) with the contact forces `Q = −Gᵀλ̇` (eq. 12) and friction
//! `F_f(λ̇, v)`, perturbed about a steady sliding state by `u`, `v = u̇` and `N = δλ̇`, with
//! `F_f ≈ F_f⁰ + D N + C_f u̇`, reads
//! ```text
//! M ü + (B − C_f) u̇ + K u + (Gᵀ − D) N = 0,      G u = 0,
//! D = ∂F_f/∂λ̇ (n×ng),   C_f = ∂F_f/∂v (n×n).
//! ```
//! **Signs versus the paper.** Eqs. (18) and (22)–(23) write `Hᵀ = Gᵀ + ∂F_f/∂λ` and
//! `B + C_f`; those derivatives are the ones of the residual of eq. (16), which carries `−F_f`.
//! Here `D` and `C_f` are derivatives of `+F_f` (what `squeal_contact::GapSet::add_tangents`
//! returns), so the paper's `Hᵀ` is our `Gᵀ − D` and its `B + C_f` is our `B − C_f`. In
//! eq. (22) the multiplier unknown is `λ` with `p²λ = N` (λ is a double integral of the
//! force), which is why `Hᵀ` appears in the paper's *mass* matrix; the problems are the same.
//!
//! # Why there are no spurious roots
//! The paper's pencil (eqs. 22–24) has `ng` zero roots from the λ block (its Lanczos found
//! them all). We eliminate the constraint exactly instead (see [`reduce`] for the
//! derivation): `u = T q` with `T` an orthonormal basis of null(G), and `N` solved from
//! `G ü = 0`, giving `M_r q̈ + C_r q̇ + K_r q = 0` of size `n − ng` and a standard eigenproblem
//! of size `2(n − ng)` — exactly the physical roots.
//!
//! # Exact or projected
//! The exact method ([`CeaMethod::Exact`], the default of a single [`complex_eigen`]) solves
//! that standard eigenproblem densely: O((2(n − ng))³), ~1 s at n − ng = 480 here. The
//! projected method ([`CeaMethod::Projection`], [`ModalBasis`]) does what Abaqus's complex
//! eigenvalue extraction does: it projects the constrained problem on the real modes of the
//! friction-free, undamped problem up to a cutoff (computed once per sweep) and solves an
//! eigenproblem of size 2 nb per μ. A sweep picks it automatically for large truncated
//! problems ([`CeaMethod::Auto`]) and measures its error against exact solves at the ends
//! of the sweep ([`SweepOptions::exact_check`], [`SweepStats::max_rel_eigenvalue_error`]).

mod basis;
mod check;
mod critical;
pub(crate) mod eigen;
mod enrich;
mod error;
mod events;
pub(crate) mod first_order;
mod lanczos;
mod onset;
pub(crate) mod operator;
mod options;
mod project;
mod reduce;
mod refine;
pub(crate) mod shift_invert;
mod sweep;
mod track;

/// Random test models shared by the unit tests of the sweep's modules.
#[cfg(test)]
pub(crate) mod test_random {
    use faer::Mat;

    /// Uniform in [−1, 1) (xorshift64*).
    pub(crate) struct Rng(pub(crate) u64);
    impl Rng {
        pub(crate) fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
            (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
    }

    /// A Aᵀ + shift I with A uniform in [−1, 1) (n × n), drawn from `rng`.
    pub(crate) fn random_spd(n: usize, rng: &mut Rng, shift: f64) -> Mat<f64> {
        let a = Mat::from_fn(n, n, |_, _| rng.next());
        let mut s = &a * a.transpose();
        for i in 0..n {
            s[(i, i)] += shift;
        }
        s
    }
}

pub use basis::ModalBasis;
pub use check::{compare_eigenvalues, CheckKind, EigenvalueComparison, ExactCheck};
pub use critical::CriticalExact;
pub use eigen::{complex_eigen, first_order_matrix, method_for};
pub use enrich::EnrichPoint;
pub use error::CeaError;
pub use events::ModeEvent;
pub use options::{BasisSolver, CeaMethod, CeaOptions, ProjectionOptions, SweepOptions};
pub use reduce::{reduce, Reduced};
pub use refine::{RefineOptions, RefineStats, RefinedRoot, ShiftStats};
pub use sweep::{sweep, Critical, Sweep, SweepStats, SweepStep, Track};
pub use track::mac;

use faer::Mat;
use serde::{Serialize, Serializer};

/// Complex scalar.
pub type Cplx = num_complex::Complex<f64>;

/// The matrices of the linearised problem (all dense, reduced-model sized).
///
/// `M ü + (B − C_f) u̇ + K u + (Gᵀ − D) N = 0, G u = 0`. Only `m` and `k` are required; a
/// `None` is a zero matrix (no constraint when `g` is `None` or has 0 rows).
#[derive(Debug, Clone)]
#[allow(non_snake_case)]
pub struct CeaMatrices {
    /// Mass M (n×n, symmetric positive definite).
    pub m: Mat<f64>,
    /// Stiffness K (n×n; may be unsymmetric, may carry friction stiffness terms).
    pub k: Mat<f64>,
    /// Viscous damping B (n×n).
    pub b: Option<Mat<f64>>,
    /// Contact constraint G (ng×n, full row rank), `G u = 0`. [Paper eq. (11)]
    pub g: Option<Mat<f64>>,
    /// Friction tangent D = ∂F_f/∂λ̇ (n×ng). [Paper eq. (18), ∂F_f/∂λ]
    pub d: Option<Mat<f64>>,
    /// Friction damping C_f = ∂F_f/∂v (n×n). [Paper eq. (18)]
    pub c_f: Option<Mat<f64>>,
}

impl CeaMatrices {
    /// Mass and stiffness only (no damping, no constraint, no friction).
    pub fn new(m: Mat<f64>, k: Mat<f64>) -> Self {
        CeaMatrices {
            m,
            k,
            b: None,
            g: None,
            d: None,
            c_f: None,
        }
    }
}

fn ser_cplx<S: Serializer>(p: &Cplx, s: S) -> Result<S::Ok, S::Error> {
    [p.re, p.im].serialize(s)
}

fn ser_shape<S: Serializer>(u: &[Cplx], s: S) -> Result<S::Ok, S::Error> {
    let v: Vec<[f64; 2]> = u.iter().map(|z| [z.re, z.im]).collect();
    v.serialize(s)
}

/// One complex mode (one of each conjugate pair: Im p ≥ 0).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Mode {
    /// Eigenvalue p (serialised as `[re, im]`); the motion is `Re(u e^{pt})`.
    #[serde(serialize_with = "ser_cplx")]
    pub eigenvalue: Cplx,
    /// |Im p|/2π.
    pub frequency_hz: f64,
    /// Re p (> 0: growing).
    pub real_part: f64,
    /// ζ = −2 Re p/|Im p| (DESIGN.md's definition, NASTRAN's "damping"); `None` for a real
    /// root (Im p = 0), whose growth or decay is given by `real_part` alone.
    pub damping_ratio: Option<f64>,
    /// Re p > `unstable_tol` × max|p|.
    pub unstable: bool,
    /// Mode shape u = T q (length n, unit 2-norm, largest entry real positive; serialised
    /// as `[[re, im], ...]`); empty when shapes were not computed.
    #[serde(serialize_with = "ser_shape")]
    pub shape: Vec<Cplx>,
}

/// Statistics of one eigenvalue solve.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct CeaStats {
    /// Number of DOFs n.
    pub n: usize,
    /// Number of constraints ng.
    pub n_constraints: usize,
    /// Size of the reduced second-order problem n − ng.
    pub n_reduced: usize,
    /// Method that ran (`exact` or `projection`).
    pub method: CeaMethod,
    /// Number of basis modes nb with `projection` (0 with `exact`).
    pub n_basis: usize,
    /// Highest undamped frequency of the basis, Hz (`projection` only): roots well above it
    /// are not computed.
    pub basis_max_frequency_hz: Option<f64>,
    /// Number of modes returned (complex pairs counted once, real roots each).
    pub n_modes: usize,
    /// Number of real roots (Im p = 0).
    pub n_real_roots: usize,
    /// Number of unstable modes.
    pub n_unstable: usize,
    /// Largest Re p.
    pub max_real_part: f64,
    /// Largest |p| (the scale of `unstable_tol`).
    pub spectral_radius: f64,
    /// σ_min(G)/σ_max(G) (1 when there is no constraint).
    pub constraint_rank_ratio: f64,
    /// Wall time of the constraint elimination (exact) or of the projection on the basis
    /// (projection), seconds.
    pub time_reduce_s: f64,
    /// Wall time of the basis computation when a single projected CEA built its own, seconds.
    pub time_basis_s: f64,
    /// Wall time of the eigenvalue solve and shape recovery, seconds.
    pub time_eigen_s: f64,
    /// The exact refinement of the in-band unstable projected roots (`projection` with
    /// `projection.refine.enabled` only).
    pub refine: Option<RefineStats>,
}

/// Result of [`complex_eigen`]: the modes sorted by frequency, and statistics.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CeaResult {
    /// Modes, sorted by frequency (real roots, frequency 0, first), then by real part.
    pub modes: Vec<Mode>,
    /// Statistics.
    pub stats: CeaStats,
}

pub(crate) fn check_finite(
    what: &'static str,
    a: faer::MatRef<'_, f64>,
) -> Result<(), error::CeaError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let x = a[(i, j)];
            if !x.is_finite() {
                return Err(CeaError::NonFinite {
                    what,
                    row: i,
                    col: j,
                    value: x,
                });
            }
        }
    }
    Ok(())
}
