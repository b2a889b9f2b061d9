//! The real modal basis of the constrained, friction-free problem (subspace projection).

use super::eigen::sandwich;
use super::lanczos::lowest_modes;
use super::operator::{check_inputs, cholesky, mass_solve, real_columns};
use super::{reduce, BasisSolver, CeaError, CeaMatrices, CeaOptions, Cplx};
use faer::{Mat, MatRef, Side};
use std::time::Instant;

/// A fixed real basis Ψ (n × nb) for the subspace projection of the complex eigenvalue
/// problem: the undamped real modes of the constrained problem at a reference state,
/// `G Ψ = 0` and `Ψᵀ M Ψ = I`.
///
/// Built once (one symmetric dense eigendecomposition of size n − ng), then
/// [`ModalBasis::solve`] projects the problem at any μ and solves an eigenproblem of size
/// 2 nb instead of 2(n − ng).
#[derive(Debug, Clone)]
pub struct ModalBasis {
    /// Ψ (n × nb).
    pub(crate) psi: Mat<f64>,
    /// Undamped frequencies of the basis modes, Hz, ascending.
    frequencies_hz: Vec<f64>,
    /// M of the reference state (a different M at solve time is projected afresh).
    pub(crate) m_ref: Mat<f64>,
    /// G of the reference state (the same G is required at solve time).
    pub(crate) g_ref: Option<Mat<f64>>,
    /// Gᵀ and Y = M⁻¹Gᵀ of the reference state (only with constraints).
    pub(crate) gt: Option<Mat<f64>>,
    pub(crate) y: Option<Mat<f64>>,
    /// K Ψ and B Ψ of the reference state, with K and B (a solve whose K and B equal them
    /// reuses the products: in a friction sweep only D and C_f change with μ).
    pub(crate) k_ref: Mat<f64>,
    pub(crate) kpsi: Mat<f64>,
    pub(crate) b_ref: Option<Mat<f64>>,
    pub(crate) bpsi: Option<Mat<f64>>,
    /// The μ-independent blocks of the Galerkin projection of a friction sweep
    /// ([`super::project`]; `None` without constraints).
    pub(crate) blocks: Option<Blocks>,
    /// Size of the reduced problem n − ng.
    pub(crate) n_reduced: usize,
    /// σ_min(G)/σ_max(G).
    pub(crate) rank_ratio: f64,
    /// Vectors added by [`ModalBasis::enrich`] (the last columns of Ψ).
    n_enriched: usize,
    time_s: f64,
}

impl ModalBasis {
    /// Computes the basis from the reference state `sys` and `opts.projection`.
    ///
    /// # Derivation
    /// The basis is the real modes of the friction-free, undamped constrained problem (D, B
    /// and C_f ignored; K symmetrised): `sym(K) φ = ω² M φ`, `G φ = 0`, `sym(X) = (X + Xᵀ)/2`.
    /// With `T` an orthonormal basis of null(G) ([`reduce`]) they solve
    /// `sym(K_r) φ = ω² M_r φ`, `M_r = TᵀMT`, `K_r = TᵀKT`. The modes with `ω/2π ≤` the cutoff
    /// are kept, at most `n_basis` of them (lowest first). (Until 2026-11 the basis took
    /// `K_r = TᵀPKT` with the friction tangent D in the contact projector P: `sym(PK)` is
    /// indefinite under friction — 9 negative eigenvalues on the hex20 brake — and each such
    /// mode gave the projection a spurious real root of up to 2e5 /s, which the refinement
    /// then had to disprove at the cost of one shift.)
    ///
    /// Two eigensolvers (`projection.basis_solver`):
    /// - `dense`: `M_r = L Lᵀ`, `L⁻¹ sym(K_r) L⁻ᵀ v = ω² v` (dense `self_adjoint_eigen` of size
    ///   n − ng), `φ = L⁻ᵀ v`, `Ψ = T Φ`; O(n³) with the null space and its products.
    /// - `auto` (default): when a cutoff is given and at most (n − ng)/4 modes lie below it,
    ///   shift-invert Lanczos on the bordered matrix `[sym(K) − σM, Gᵀ; G, 0]` with the count of
    ///   modes below the cutoff from the inertia of `[sym(K) − ω_c²M, Gᵀ; G, 0]`
    ///   (`lanczos.rs`): two factorisations of size n + ng and ~1.5 nb solves; else `dense`.
    ///   The Ritz pairs below half the cutoff (the band, for the default `cutoff_factor`) are
    ///   converged to 1e-8; those above span the rest of the subspace. `GΨ = 0` and
    ///   `ΨᵀMΨ = I` to round-off either way.
    ///
    /// # Errors
    /// As [`reduce`]; a reduced mass that is not positive definite; an empty basis (cutoff
    /// below the lowest mode), named with the lowest frequency.
    pub fn new(sys: &CeaMatrices, opts: &CeaOptions) -> Result<Self, CeaError> {
        opts.validate()?;
        let t0 = Instant::now();
        let (n, ng) = check_inputs(sys)?;
        let gt = sys.g.as_ref().map(|g| g.transpose().to_owned());
        let y = match (&gt, ng) {
            (Some(gt), ng) if ng > 0 => Some(mass_solve(&sys.m, gt)?),
            _ => None,
        };
        let pr = &opts.projection;
        let fast = match (pr.basis_solver, pr.cutoff_hz()) {
            (BasisSolver::Auto, Some(fc)) => lanczos_basis(sys, opts, gt.as_ref(), fc)?,
            _ => None,
        };
        let (psi, frequencies_hz, n_reduced, rank_ratio) = match fast {
            Some(x) => x,
            None => dense_basis(sys, opts)?,
        };
        debug_assert_eq!(psi.nrows(), n);
        let kpsi = &sys.k * &psi;
        let bpsi = sys.b.as_ref().map(|b| b * &psi);
        let blocks = Blocks::new(&psi, y.as_ref(), gt.as_ref(), &kpsi, bpsi.as_ref());
        Ok(ModalBasis {
            blocks,
            k_ref: sys.k.clone(),
            kpsi,
            b_ref: sys.b.clone(),
            bpsi,
            psi,
            frequencies_hz,
            m_ref: sys.m.clone(),
            g_ref: sys.g.clone(),
            gt,
            y,
            n_reduced,
            rank_ratio,
            n_enriched: 0,
            time_s: t0.elapsed().as_secs_f64(),
        })
    }

    /// Adds the real and imaginary parts of the complex vectors `vectors` (exact eigenvectors
    /// of the problem at another state: a friction sweep's multi-point basis) to Ψ; returns how
    /// many columns were added.
    ///
    /// # Derivation
    /// Each part w is first put in null(G) by the M-orthogonal projection
    /// `w ← w − Y (G Y)⁻¹ G w`, `Y = M⁻¹Gᵀ` (an exact eigenvector has `G u = 0` to round-off;
    /// the projection keeps `G Ψ = 0` exact), then made M-orthogonal to Ψ by two passes of
    /// Gram–Schmidt `w ← w − Ψ Ψᵀ M w` (M the reference mass) and normalised, so that
    /// `ΨᵀMΨ = I` still holds and [`ModalBasis::solve`] is unchanged. A part whose M-norm
    /// falls below `drop_tol` × its norm before the orthogonalisation lies in span Ψ already
    /// and is dropped. K Ψ and B Ψ are extended by the new columns. The Galerkin projection
    /// onto the enlarged space reproduces the added eigenpairs exactly at their own state
    /// (their residual is zero) and, the friction terms being smooth in μ, improves the roots
    /// between the states.
    pub(crate) fn enrich(
        &mut self,
        vectors: &[Vec<Cplx>],
        drop_tol: f64,
    ) -> Result<usize, CeaError> {
        let n = self.psi.nrows();
        let vectors: Vec<&Vec<Cplx>> = vectors.iter().filter(|v| v.len() == n).collect();
        if vectors.is_empty() {
            return Ok(0);
        }
        let mut w = real_columns(n, vectors.len(), |j, i| vectors[j][i]);
        if let (Some(g), Some(y)) = (&self.g_ref, &self.y) {
            let gy = g * y;
            let llt = cholesky("G M^-1 G^T", &gy)?;
            let mut c = g * &w;
            faer::linalg::solvers::Solve::solve_in_place(&llt, &mut c);
            w -= y * &c;
        }
        let m = &self.m_ref;
        let mut new_cols: Vec<Vec<f64>> = Vec::new();
        for j in 0..w.ncols() {
            let mut v: Vec<f64> = (0..n).map(|i| w[(i, j)]).collect();
            let m_norm = |v: &[f64]| -> f64 {
                let x = faer::ColRef::from_slice(v);
                let mx = m * x;
                (0..n).map(|i| v[i] * mx[i]).sum::<f64>().max(0.0).sqrt()
            };
            let norm0 = m_norm(&v);
            if !norm0.is_finite() || norm0 <= 0.0 {
                continue;
            }
            for _ in 0..2 {
                let mv = m * faer::ColRef::from_slice(&v);
                let coef = self.psi.transpose() * &mv;
                let proj = &self.psi * &coef;
                for i in 0..n {
                    v[i] -= proj[i];
                }
                for q in &new_cols {
                    let c: f64 = (0..n).map(|i| q[i] * mv[i]).sum();
                    for i in 0..n {
                        v[i] -= c * q[i];
                    }
                }
            }
            let norm = m_norm(&v);
            if norm <= drop_tol * norm0 {
                continue;
            }
            v.iter_mut().for_each(|x| *x /= norm);
            new_cols.push(v);
        }
        let added = new_cols.len();
        if added == 0 {
            return Ok(0);
        }
        let nb = self.psi.ncols();
        let wn = Mat::from_fn(n, added, |i, j| new_cols[j][i]);
        let ext = |a: &Mat<f64>, b: Mat<f64>| {
            Mat::from_fn(n, nb + added, |i, j| {
                if j < nb {
                    a[(i, j)]
                } else {
                    b[(i, j - nb)]
                }
            })
        };
        self.kpsi = ext(&self.kpsi, &self.k_ref * &wn);
        if let (Some(b), Some(bp)) = (&self.b_ref, &self.bpsi) {
            self.bpsi = Some(ext(bp, b * &wn));
        }
        self.psi = ext(&self.psi, wn);
        self.blocks = Blocks::new(
            &self.psi,
            self.y.as_ref(),
            self.gt.as_ref(),
            &self.kpsi,
            self.bpsi.as_ref(),
        );
        self.n_enriched += added;
        Ok(added)
    }

    /// Columns added by [`ModalBasis::enrich`].
    pub fn n_enriched(&self) -> usize {
        self.n_enriched
    }

    /// Number of basis modes nb.
    pub fn len(&self) -> usize {
        self.psi.ncols()
    }

    /// True when the basis is empty (never, for a basis built by [`ModalBasis::new`]).
    pub fn is_empty(&self) -> bool {
        self.psi.ncols() == 0
    }

    /// Undamped frequencies of the basis modes, Hz, ascending.
    pub fn frequencies_hz(&self) -> &[f64] {
        &self.frequencies_hz
    }

    /// The basis vectors Ψ (n × nb; `G Ψ = 0`, `Ψᵀ M Ψ = I` for the reference M).
    pub fn vectors(&self) -> MatRef<'_, f64> {
        self.psi.as_ref()
    }

    /// Wall time of the basis computation, seconds.
    pub fn time_s(&self) -> f64 {
        self.time_s
    }
}

/// The products of the Galerkin projection that do not change with the friction (K, B, M and
/// G of the reference state), made once per basis: with `W = [Ψ, Y]` (n × (nb + ng)),
/// `Y = M⁻¹Gᵀ`, the blocks `WᵀKΨ`, `WᵀBΨ` and `WᵀGᵀ` (see [`ModalBasis::solve`]).
#[derive(Debug, Clone)]
pub(crate) struct Blocks {
    /// `W = [Ψ, Y]`.
    pub(crate) w: Mat<f64>,
    /// `WᵀKΨ` ((nb + ng) × nb).
    pub(crate) wk: Mat<f64>,
    /// `WᵀBΨ` ((nb + ng) × nb; `None` without B).
    pub(crate) wb: Option<Mat<f64>>,
    /// `WᵀGᵀ` ((nb + ng) × ng): `(GΨ)ᵀ` (zero to round-off) over `YᵀGᵀ = GM⁻¹Gᵀ`.
    pub(crate) wg: Mat<f64>,
}

impl Blocks {
    fn new(
        psi: &Mat<f64>,
        y: Option<&Mat<f64>>,
        gt: Option<&Mat<f64>>,
        kpsi: &Mat<f64>,
        bpsi: Option<&Mat<f64>>,
    ) -> Option<Self> {
        let (y, gt) = (y?, gt?);
        let (n, nb, ng) = (psi.nrows(), psi.ncols(), y.ncols());
        let w = Mat::from_fn(n, nb + ng, |i, j| {
            if j < nb {
                psi[(i, j)]
            } else {
                y[(i, j - nb)]
            }
        });
        let wt = w.transpose();
        Some(Blocks {
            wk: wt * kpsi,
            wb: bpsi.map(|b| wt * b),
            wg: wt * gt,
            w,
        })
    }
}

fn hz(x: f64) -> f64 {
    x.max(0.0).sqrt() / (2.0 * std::f64::consts::PI)
}

/// (Ψ, frequencies, n − ng, σ_min(G)/σ_max(G)).
type BasisParts = (Mat<f64>, Vec<f64>, usize, f64);

/// The dense path: constraint eliminated (null space T of G), one symmetric
/// eigendecomposition of size n − ng (see [`ModalBasis::new`]).
fn dense_basis(sys: &CeaMatrices, opts: &CeaOptions) -> Result<BasisParts, CeaError> {
    let undamped = CeaMatrices {
        m: sys.m.clone(),
        k: sys.k.clone(),
        b: None,
        g: sys.g.clone(),
        d: None,
        c_f: None,
    };
    let red = reduce(&undamped, opts)?;
    let m = red.m_r.nrows();
    let llt = cholesky("T^T M T", &red.m_r)?;
    let l = llt.L();
    let ksym = Mat::from_fn(m, m, |i, j| 0.5 * (red.k_r[(i, j)] + red.k_r[(j, i)]));
    let khat = sandwich(l, &ksym);
    let evd = khat
        .self_adjoint_eigen(Side::Lower)
        .map_err(|_| CeaError::NoConvergence {
            what: "symmetric eigendecomposition (projection basis)",
            n: m,
        })?;
    let lam = evd.S().column_vector();
    let pr = &opts.projection;
    let mut nb = match pr.cutoff_hz() {
        Some(fc) => (0..m).take_while(|&i| hz(lam[i]) <= fc).count(),
        None => m,
    };
    if let Some(cap) = pr.n_basis {
        nb = nb.min(cap);
    }
    if nb == 0 {
        return Err(CeaError::InvalidOption {
            field: "projection.basis_cutoff_hz",
            value: format!("{:?}", pr.cutoff_hz()),
            reason: format!(
                "no real mode below the cutoff (lowest: {} Hz)",
                if m > 0 { hz(lam[0]) } else { f64::NAN }
            ),
        });
    }
    let mut phi = evd.U().subcols(0, nb).to_owned();
    l.transpose().solve_upper_triangular_in_place(&mut phi);
    let psi = match &red.t {
        Some(t) => t * &phi,
        None => phi,
    };
    Ok((
        psi,
        (0..nb).map(|i| hz(lam[i])).collect(),
        m,
        red.rank_ratio,
    ))
}

/// The Lanczos path ([`super::lanczos::lowest_modes`]) on `sym(K)`: `Tᵀ sym(K) T = sym(K_r)`
/// of the friction-free problem, so the modes are those of the dense path.
/// `None` when it does not apply (the dense path then runs).
#[allow(non_snake_case)]
fn lanczos_basis(
    sys: &CeaMatrices,
    opts: &CeaOptions,
    gt: Option<&Mat<f64>>,
    cutoff_hz: f64,
) -> Result<Option<BasisParts>, CeaError> {
    let n = sys.m.nrows();
    let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
    let rank_ratio = match gt {
        Some(gt) if ng > 0 => {
            let sv = gt.singular_values().map_err(|_| CeaError::NoConvergence {
                what: "singular values of G^T",
                n,
            })?;
            let smax = sv.iter().fold(0.0f64, |a, &b| a.max(b.abs()));
            let smin = sv.iter().fold(f64::INFINITY, |a, &b| a.min(b.abs()));
            let ratio = if smax > 0.0 { smin / smax } else { 0.0 };
            if ratio <= opts.rank_tol {
                return Err(CeaError::RankDeficientConstraints {
                    ng,
                    n,
                    ratio,
                    tol: opts.rank_tol,
                });
            }
            ratio
        }
        _ => 1.0,
    };
    let m_red = n - ng;
    let max_modes = opts.projection.n_basis.unwrap_or(usize::MAX).min(m_red / 4);
    if max_modes == 0 {
        return Ok(None);
    }
    let pk = &sys.k;
    let ks = Mat::from_fn(n, n, |i, j| 0.5 * (pk[(i, j)] + pk[(j, i)]));
    let w_c = 2.0 * std::f64::consts::PI * cutoff_hz;
    let low = lowest_modes(
        &ks,
        &sys.m,
        sys.g.as_ref(),
        w_c * w_c,
        max_modes,
        1e-8,
        &opts.interrupt,
    )?;
    Ok(low.map(|l| {
        let f = l.lambda.iter().map(|&x| hz(x)).collect();
        (l.phi, f, m_red, rank_ratio)
    }))
}
