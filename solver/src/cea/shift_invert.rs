//! Shift-invert Arnoldi on the full first-order operator of the constrained problem (no
//! constraint elimination, no projection): the exact check of the projected roots.

use super::operator::{complex_at, real_columns};
use super::{CeaError, CeaMatrices, Cplx};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};
use std::time::Instant;

/// `(F − σE)⁻¹E` for the first-order pencil of the constrained problem.
///
/// # Derivation
/// With `x = [u; v]`, `A = Gᵀ − D`, `C = B − C_f`, the linearised equations of the
/// [module docs](super) are the DAE `u̇ = v`, `M v̇ = −C v − K u − A N`, `G u = 0` (index 3:
/// `N` is fixed by the hidden constraint `G v̇ = 0`). Its finite eigenvalues are the
/// physical roots p; the rest are infinite. For a shift σ, `y = (F − σE)⁻¹E x` means
/// `y_v − σ y_u = a`, `−K y_u − C y_v − A y_N − σ M y_v = M b`, `G y_u = 0` for
/// `x = [a; b]`, i.e.
/// ```text
/// [σ²M + σC + K   A] [y_u]   [−M(b + σa) − C a]
/// [G              0] [y_N] = [0               ],      y_v = a + σ y_u
/// ```
/// — one complex LU of the bordered matrix `Q(σ)` (size n + ng) per shift. The operator has
/// the eigenvalues `θ = 1/(p − σ)` with eigenvectors `[u; p u]`, and 0 on the infinite
/// eigenvectors: the roots nearest σ dominate, and the spurious ones cannot appear.
pub(crate) struct ShiftInvert<'a> {
    m: &'a Mat<f64>,
    c: Option<&'a Mat<f64>>,
    sigma: Cplx,
    lu: PartialPivLu<c64>,
    n: usize,
    ng: usize,
}

impl<'a> ShiftInvert<'a> {
    /// Factorises `Q(σ)`; `c` is `B − C_f` (None: no damping).
    ///
    /// # Errors
    /// A singular (zero or non-finite pivot) `Q(σ)`: σ is a root to machine precision.
    pub(crate) fn new(
        sys: &'a CeaMatrices,
        c: Option<&'a Mat<f64>>,
        sigma: Cplx,
    ) -> Result<Self, CeaError> {
        let n = sys.m.nrows();
        let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
        let s2 = sigma * sigma;
        let (m, k) = (&sys.m, &sys.k);
        let g = sys.g.as_ref();
        let d = sys.d.as_ref();
        let q = Mat::<c64>::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
            (true, true) => {
                let cij = c.map_or(0.0, |c| c[(i, j)]);
                s2 * m[(i, j)] + sigma * cij + k[(i, j)]
            }
            (true, false) => {
                let gt = g.map_or(0.0, |g| g[(j - n, i)]);
                c64::new(gt - d.map_or(0.0, |d| d[(i, j - n)]), 0.0)
            }
            (false, true) => c64::new(g.map_or(0.0, |g| g[(i - n, j)]), 0.0),
            (false, false) => c64::new(0.0, 0.0),
        });
        let lu = q.partial_piv_lu();
        let u = lu.U();
        let (mut pmin, mut pmax) = (f64::INFINITY, 0.0f64);
        for i in 0..n + ng {
            let a = u[(i, i)].norm();
            pmin = pmin.min(a);
            pmax = pmax.max(a);
        }
        if !(pmin > 0.0 && pmax.is_finite()) {
            return Err(CeaError::SingularShift {
                re: sigma.re,
                im: sigma.im,
                ratio: pmin / pmax,
            });
        }
        Ok(ShiftInvert {
            m,
            c,
            sigma,
            lu,
            n,
            ng,
        })
    }

    /// The shift σ.
    pub(crate) fn sigma(&self) -> Cplx {
        self.sigma
    }

    /// `y = (F − σE)⁻¹E x` (x, y of length 2n) for several vectors at once: one product of M
    /// and of C with all of them (their real and imaginary parts as columns) and one
    /// multi-column LU solve, so each matrix and the factor are read once per block, not once
    /// per vector (the applications are bound by memory traffic: on the 2 043-DOF brake the
    /// factor alone is 107 MB).
    pub(crate) fn apply_block(&self, xs: &[&[Cplx]]) -> Vec<Vec<Cplx>> {
        let (n, s, nb) = (self.n, self.sigma, xs.len());
        let t = real_columns(n, nb, |j, i| xs[j][n + i] + s * xs[j][i]);
        let mt = self.m * &t;
        let ca = self.c.map(|c| c * real_columns(n, nb, |j, i| xs[j][i]));
        let mut rhs = Mat::<c64>::from_fn(n + self.ng, nb, |i, j| {
            if i < n {
                let mut r = -complex_at(&mt, i, j);
                if let Some(ca) = &ca {
                    r -= complex_at(ca, i, j);
                }
                r
            } else {
                c64::new(0.0, 0.0)
            }
        });
        self.lu.solve_in_place(&mut rhs);
        (0..nb)
            .map(|j| {
                let mut y = Vec::with_capacity(2 * n);
                y.extend((0..n).map(|i| rhs[(i, j)]));
                y.extend((0..n).map(|i| xs[j][i] + s * rhs[(i, j)]));
                y
            })
            .collect()
    }
}

/// A Ritz pair of the Arnoldi factorisation.
pub(crate) struct Ritz {
    /// Root p = σ + 1/θ.
    pub(crate) p: Cplx,
    /// Residual estimate of θ relative to |θ|: ‖S x − θ x‖/(|θ| ‖x‖).
    pub(crate) rel_residual: f64,
    /// Coefficients of the Ritz vector in the Arnoldi basis (unit norm).
    coeffs: Vec<Cplx>,
}

/// Band (block) Arnoldi factorisation `S V_k = V_{k+b} H_k` with full (twice-repeated
/// Gram–Schmidt) orthogonalisation, grown on demand, `b` the block size.
///
/// # Reference
/// Ruhe (1979), "Implementation aspects of band Lanczos algorithms for computation of
/// eigenvalues of large sparse symmetric matrices", Math. Comp. 33: the vectors are
/// orthogonalised one at a time, `S v_j = Σ_{i ≤ j+b} h_ij v_i`, so H is banded upper
/// Hessenberg (b subdiagonals) and b = 1 is the plain Arnoldi process. The b images
/// `S v_j … S v_{j+b−1}` exist before any of them is orthogonalised, so they are computed by
/// one block application ([`ShiftInvert::apply_block`]). The Ritz residual of `(θ, V_k y)`
/// is `‖H_{k:k+b, :} y‖`, the rows of H below the square part.
pub(crate) struct Arnoldi {
    v: Vec<Vec<Cplx>>,
    /// Hessenberg entries, column j has j + b + 1 of them.
    h: Vec<Vec<Cplx>>,
    /// An invariant subspace was found (the last `h` entry is 0).
    pub(crate) exhausted: bool,
    /// Operator applications.
    pub(crate) applications: usize,
    /// Seconds in operator applications and in the orthogonalisation.
    pub(crate) time_apply_s: f64,
    pub(crate) time_orth_s: f64,
}

fn dot(a: &[Cplx], b: &[Cplx]) -> Cplx {
    a.iter().zip(b).map(|(x, y)| x.conj() * y).sum()
}

fn norm(a: &[Cplx]) -> f64 {
    a.iter().map(|z| z.norm_sqr()).sum::<f64>().sqrt()
}

/// Removes from `w` its components along the orthonormal `v` (classical Gram–Schmidt, twice);
/// returns the coefficients removed, one per vector of `v`.
fn orthogonalise(v: &[Vec<Cplx>], w: &mut [Cplx]) -> Vec<Cplx> {
    let mut h = vec![Cplx::new(0.0, 0.0); v.len()];
    for _ in 0..2 {
        for (hi, vi) in h.iter_mut().zip(v) {
            let c = dot(vi, w);
            *hi += c;
            w.iter_mut().zip(vi).for_each(|(x, y)| *x -= c * y);
        }
    }
    h
}

impl Arnoldi {
    /// Starts from `block` fixed pseudo-random vectors, each applied twice to the operator so
    /// that it has no component on the infinite eigenvectors (the index-3 Jordan chains map
    /// to 0), then orthonormalised.
    pub(crate) fn new(op: &ShiftInvert<'_>, block: usize) -> Self {
        let (dim, block) = (2 * op.n, block.max(1));
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let mut rnd = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64 - 0.5
        };
        let t = Instant::now();
        let mut xs: Vec<Vec<Cplx>> = (0..block)
            .map(|_| (0..dim).map(|_| Cplx::new(rnd(), rnd())).collect())
            .collect();
        for _ in 0..2 {
            let refs: Vec<&[Cplx]> = xs.iter().map(|x| x.as_slice()).collect();
            xs = op.apply_block(&refs);
            for x in xs.iter_mut() {
                let nx = norm(x);
                x.iter_mut().for_each(|z| *z /= nx);
            }
        }
        let time_apply_s = t.elapsed().as_secs_f64();
        let mut v: Vec<Vec<Cplx>> = Vec::with_capacity(block);
        for mut x in xs {
            let nx0 = norm(&x);
            orthogonalise(&v, &mut x);
            let nx = norm(&x);
            // A start vector in the span of the others adds nothing: the block shrinks.
            if nx > 1e-10 * nx0 {
                x.iter_mut().for_each(|z| *z /= nx);
                v.push(x);
            }
        }
        Arnoldi {
            v,
            h: Vec::new(),
            exhausted: false,
            applications: 2 * block,
            time_apply_s,
            time_orth_s: 0.0,
        }
    }

    /// Current dimension k (number of columns of H).
    pub(crate) fn dim(&self) -> usize {
        self.h.len()
    }

    /// Grows the factorisation to dimension `k` or more (by whole blocks; or until an
    /// invariant subspace).
    pub(crate) fn grow(&mut self, op: &ShiftInvert<'_>, k: usize) {
        while self.h.len() < k && !self.exhausted {
            let j = self.h.len();
            let t = Instant::now();
            let images = {
                let refs: Vec<&[Cplx]> = self.v[j..].iter().map(|x| x.as_slice()).collect();
                op.apply_block(&refs)
            };
            if images.is_empty() {
                // No vector left to apply (every start vector was dependent).
                self.exhausted = true;
                break;
            }
            self.applications += images.len();
            let t1 = Instant::now();
            self.time_apply_s += (t1 - t).as_secs_f64();
            for mut w in images {
                let len = self.v.len();
                let mut hj = orthogonalise(&self.v, &mut w);
                let beta = norm(&w);
                hj.push(Cplx::new(beta, 0.0));
                let scale = hj.iter().take(len).map(|z| z.norm()).fold(beta, f64::max);
                self.h.push(hj);
                if beta <= 1e-14 * scale {
                    self.exhausted = true;
                    break;
                }
                w.iter_mut().for_each(|z| *z /= beta);
                self.v.push(w);
            }
            self.time_orth_s += t1.elapsed().as_secs_f64();
        }
    }

    /// Ritz pairs of the current factorisation (σ = the operator's shift).
    ///
    /// # Errors
    /// Non-convergence of the small dense eigensolver.
    pub(crate) fn ritz(&self, sigma: Cplx) -> Result<Vec<Ritz>, CeaError> {
        let k = self.h.len();
        let h = Mat::<c64>::from_fn(k, k, |i, j| {
            if i < self.h[j].len() {
                self.h[j][i]
            } else {
                c64::new(0.0, 0.0)
            }
        });
        let evd = h.eigen().map_err(|_| CeaError::NoConvergence {
            what: "Arnoldi Hessenberg eigendecomposition",
            n: k,
        })?;
        let (s, u) = (evd.S().column_vector(), evd.U());
        // Rows of H below the square part (b of them; after an invariant subspace the last
        // column's is ~0): the Ritz residual is ‖H_{k:, :} y‖.
        let rows = self.h.iter().map(|c| c.len()).max().unwrap_or(k);
        let mut out = Vec::with_capacity(k);
        for i in 0..k {
            let theta = s[i];
            let nu = (0..k).map(|r| u[(r, i)].norm_sqr()).sum::<f64>().sqrt();
            let coeffs: Vec<Cplx> = (0..k).map(|r| u[(r, i)] / nu).collect();
            if theta.norm() == 0.0 || !theta.norm().is_finite() {
                continue;
            }
            let residual = (k..rows)
                .map(|r| {
                    (0..k)
                        .filter(|&c| r < self.h[c].len())
                        .map(|c| self.h[c][r] * coeffs[c])
                        .sum::<Cplx>()
                        .norm_sqr()
                })
                .sum::<f64>()
                .sqrt();
            out.push(Ritz {
                p: sigma + theta.inv(),
                rel_residual: residual / theta.norm(),
                coeffs,
            });
        }
        Ok(out)
    }

    /// The Ritz vector `V_k s` (length 2n).
    pub(crate) fn vector(&self, r: &Ritz) -> Vec<Cplx> {
        let dim = self.v[0].len();
        let mut x = vec![Cplx::new(0.0, 0.0); dim];
        for (c, v) in r.coeffs.iter().zip(&self.v) {
            x.iter_mut().zip(v).for_each(|(a, b)| *a += c * b);
        }
        x
    }
}
