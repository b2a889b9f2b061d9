//! Exact elimination of the contact constraint and multipliers (null space of G).

use super::operator::{check_inputs, damping, mass_solve, ContactProjector};
use super::{CeaError, CeaMatrices, CeaOptions};
use faer::Mat;

/// The reduced second-order problem `M_r q̈ + C_r q̇ + K_r q = 0`, `u = T q`.
#[derive(Debug, Clone)]
pub struct Reduced {
    /// Orthonormal basis T of null(G) (n×(n−ng)); `None` when there is no constraint (T = I).
    pub t: Option<Mat<f64>>,
    /// M_r = TᵀMT (symmetric positive definite).
    pub m_r: Mat<f64>,
    /// C_r = TᵀP(B − C_f)T; `None` when B and C_f are both absent.
    pub c_r: Option<Mat<f64>>,
    /// K_r = TᵀPKT.
    pub k_r: Mat<f64>,
    /// σ_min(G)/σ_max(G) (1 without constraint).
    pub rank_ratio: f64,
}

/// Eliminates `G u = 0` and the multiplier perturbations `N` exactly.
///
/// # Reference
/// Replaces the pencil of [Paper eqs. (19)–(24)]
/// $$\left(p^2\begin{bmatrix}M & H^T\\ G & 0\end{bmatrix} + p\begin{bmatrix}B+C_f & 0\\0&0\end{bmatrix} + \begin{bmatrix}K&0\\0&0\end{bmatrix}\right)\begin{Bmatrix}u\\ \lambda\end{Bmatrix} = 0$$
/// whose λ block gives `ng` spurious zero roots, by an equivalent problem without them. In
/// our signs (see the [module docs](super)) `Hᵀ = Gᵀ − D` and `B + C_f` ↦ `B − C_f`.
///
/// # Derivation
/// Write `A = Gᵀ − D` (n×ng) and `C = B − C_f`. The linearised equations are
/// `M ü + C u̇ + K u + A N = 0` and `G u = 0` at all times, hence `G ü = 0`.
///
/// 1. *Multipliers.* `ü = −M⁻¹(C u̇ + K u + A N)` and `G ü = 0` give `S N = −G M⁻¹(C u̇ + K u)`
///    with `S = G M⁻¹ A` (ng×ng; SPD when D = 0 and G has full row rank). So
///    `N = −S⁻¹ G M⁻¹ (C u̇ + K u)`, and substituting,
///    `M ü + P C u̇ + P K u = 0` with `P = I − A S⁻¹ G M⁻¹`.
///    P is an oblique projector: `P² = P`, `P A = 0`, `G M⁻¹ P = 0`.
/// 2. *Displacements.* `u = T q`, `T` an orthonormal basis of null(G) (the last n − ng left
///    singular vectors of Gᵀ), satisfies `G u = 0` identically. The residual
///    `r = M T q̈ + P C T q̇ + P K T q` obeys `G M⁻¹ r = G T q̈ = 0` for every q, i.e. r lies in
///    `range(M T)`. `Tᵀ` is injective on `range(M T)` (TᵀMT is SPD), so `r = 0 ⟺ Tᵀ r = 0`:
///    ```text
///    M_r = TᵀMT,   C_r = TᵀPCT,   K_r = TᵀPKT      (size n − ng)
///    ```
///    has exactly the eigenvalues of the constrained problem — none lost, none spurious.
/// 3. When `D = 0`, `TᵀA = TᵀGᵀ = 0`, so `TᵀP = Tᵀ` and the reduction is the plain congruence
///    `TᵀCT`, `TᵀKT`; P (and the Cholesky factor of M) is only built when D is given.
///
/// Cost: an SVD of Gᵀ (n×ng, full U), one Cholesky of M, products with T: O(n³).
///
/// # Errors
/// Shape mismatches, non-finite entries, rank-deficient G, M not positive definite (when D
/// is given), singular `S`, non-convergence of the SVD.
#[allow(non_snake_case)]
pub fn reduce(sys: &CeaMatrices, opts: &CeaOptions) -> Result<Reduced, CeaError> {
    let (n, ng) = check_inputs(sys)?;
    let C = damping(sys);
    if ng == 0 {
        return Ok(Reduced {
            t: None,
            m_r: sys.m.clone(),
            c_r: C,
            k_r: sys.k.clone(),
            rank_ratio: 1.0,
        });
    }
    let G = sys.g.as_ref().expect("ng > 0 implies G");
    let Gt = G.transpose().to_owned();
    let svd = Gt.svd().map_err(|_| CeaError::NoConvergence {
        what: "SVD of G^T",
        n,
    })?;
    let sv = svd.S().column_vector();
    let (mut smin, mut smax) = (f64::INFINITY, 0.0f64);
    for i in 0..ng {
        smin = smin.min(sv[i].abs());
        smax = smax.max(sv[i].abs());
    }
    let ratio = if smax > 0.0 { smin / smax } else { 0.0 };
    if ratio <= opts.rank_tol {
        return Err(CeaError::RankDeficientConstraints {
            ng,
            n,
            ratio,
            tol: opts.rank_tol,
        });
    }
    let T = svd.U().subcols(ng, n - ng).to_owned();
    let M = &sys.m;
    let m_r = T.transpose() * (M * &T);

    // P is only needed when D is present.
    let project = match &sys.d {
        None => None,
        Some(D) => Some(ContactProjector::new(mass_solve(M, &Gt)?, &Gt, D)?),
    };
    let apply = |X: &Mat<f64>| -> Mat<f64> {
        let XT = X * &T;
        let PXT = match &project {
            Some(p) => p.apply(XT),
            None => XT,
        };
        T.transpose() * PXT
    };
    let k_r = apply(&sys.k);
    let c_r = C.as_ref().map(&apply);
    Ok(Reduced {
        t: Some(T),
        m_r,
        c_r,
        k_r,
        rank_ratio: ratio,
    })
}
