//! Shift-invert Arnoldi on the full first-order operator of the constrained problem (no
//! projection): the exact check of the projected roots.

use super::operator::{complex_at, pivot_ratio, real_columns};
use super::{CeaError, CeaMatrices, Cplx};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};
use std::time::Instant;

/// Pivot ratio below which a slave block of [`Elimination`] is refused (the bordered LU runs
/// instead).
const SLAVE_PIVOT_RATIO: f64 = 1e-8;

/// The constraint `G u = 0` and the multipliers eliminated by slave DOFs, shared by every
/// shift of one refinement (G and D are the same for all of them).
///
/// # Derivation
/// Split the DOFs into ng slaves `s` and the others `m` (the first ng columns of a
/// column-pivoted QR of G, so that `G_s` is well conditioned). Then
/// `G y = 0 ⇔ y = T q`, `T = [−P; I]` (rows s; m), `P = G_s⁻¹ G_m`, and
/// `Zᵀ = [−R, I]` (columns s; m), `R = A_m A_s⁻¹`, annihilates `A = Gᵀ − D` (`Zᵀ A =
/// −A_m + A_m = 0`). The bordered system `X y + A y_N = f`, `G y = 0` of [`ShiftInvert`]
/// becomes `(Zᵀ X T) q = Zᵀ f = f_m − R f_s` of size n − ng, `y = T q` (y_N is not needed by
/// the operator). Both are exact; the reduced one is the smaller: on the cad brake's
/// 2 043-DOF model with 550 gaps, 1 493 unknowns instead of 2 593, a factor ~5× cheaper and
/// a third of the memory read per solve.
pub(crate) struct Elimination {
    split: std::sync::Arc<SlaveSplit>,
    /// `Rᵀ = A_s⁻ᵀ A_mᵀ` (ng × (n − ng)).
    rt: Mat<f64>,
    /// LU of `A_sᵀ`: the multipliers of a right eigenvector ([`Elimination::multipliers`]).
    ast_lu: PartialPivLu<f64>,
}

/// The part of an [`Elimination`] that depends on G only (the slaves, the others and
/// `P = G_s⁻¹ G_m`): the same for every μ of a friction sweep, where G does not change, so a
/// sweep makes it once (a column-pivoted QR of G and an LU of G_s: 0.2–0.3 s on the cad
/// brake's 550 × 2 043 G) and every refinement reuses it.
pub(crate) struct SlaveSplit {
    pub(crate) s: Vec<usize>,
    pub(crate) m: Vec<usize>,
    /// `P = G_s⁻¹ G_m` (ng × (n − ng)).
    pub(crate) p: Mat<f64>,
    /// LU of `G_s`: the adjoint multipliers of a left eigenvector
    /// ([`Elimination::multipliers`]).
    gs_lu: PartialPivLu<f64>,
}

impl SlaveSplit {
    /// The slaves of G (the first ng pivot columns of a column-pivoted QR) and `P`; `None`
    /// when there is no constraint or `G_s` is ill conditioned (pivot ratio < 1e-8).
    pub(crate) fn new(g: &Mat<f64>) -> Option<Self> {
        let (ng, n) = (g.nrows(), g.ncols());
        if ng == 0 || ng >= n {
            return None;
        }
        let qr = g.col_piv_qr();
        let fwd = qr.P().arrays().0;
        let s: Vec<usize> = fwd[..ng].to_vec();
        let mut is_slave = vec![false; n];
        s.iter().for_each(|&i| is_slave[i] = true);
        let m: Vec<usize> = (0..n).filter(|&i| !is_slave[i]).collect();
        let gs = Mat::<f64>::from_fn(ng, ng, |i, j| g[(i, s[j])]);
        let gm = Mat::<f64>::from_fn(ng, m.len(), |i, j| g[(i, m[j])]);
        let gs_lu = gs.partial_piv_lu();
        if pivot_ratio(gs_lu.U(), |x: &f64| x.abs()) < SLAVE_PIVOT_RATIO {
            return None;
        }
        let p = gs_lu.solve(&gm);
        p.norm_max()
            .is_finite()
            .then_some(SlaveSplit { s, m, p, gs_lu })
    }
}

impl Elimination {
    /// The slaves and the maps `P`, `R`; `None` when there is no constraint or a slave block
    /// is ill conditioned (pivot ratio < 1e-8: then the bordered LU is used).
    pub(crate) fn new(sys: &CeaMatrices) -> Option<Self> {
        let g = sys.g.as_ref().filter(|g| g.nrows() > 0)?;
        Self::with_split(sys, std::sync::Arc::new(SlaveSplit::new(g)?))
    }

    /// As [`Elimination::new`] with the slaves of G already chosen (`split` must be that of
    /// `sys.g`).
    pub(crate) fn with_split(sys: &CeaMatrices, split: std::sync::Arc<SlaveSplit>) -> Option<Self> {
        let g = sys.g.as_ref().filter(|g| g.nrows() > 0)?;
        let ng = g.nrows();
        let (s, m) = (&split.s, &split.m);
        // A = Gᵀ − D: A_sᵀ (ng × ng) and A_mᵀ (ng × (n − ng)).
        let a =
            |row: usize, col: usize| g[(col, row)] - sys.d.as_ref().map_or(0.0, |d| d[(row, col)]);
        let ast = Mat::<f64>::from_fn(ng, ng, |i, j| a(s[j], i));
        let amt = Mat::<f64>::from_fn(ng, m.len(), |i, j| a(m[j], i));
        let ast_lu = ast.partial_piv_lu();
        if pivot_ratio(ast_lu.U(), |x: &f64| x.abs()) < SLAVE_PIVOT_RATIO {
            return None;
        }
        let rt = ast_lu.solve(&amt);
        if !rt.norm_max().is_finite() {
            return None;
        }
        Some(Elimination { split, rt, ast_lu })
    }

    /// The slaves of G (shared by every μ of a sweep).
    pub(crate) fn split(&self) -> &std::sync::Arc<SlaveSplit> {
        &self.split
    }

    /// `Zᵀ f = f_m − R f_s` for complex vectors f given as [`real_columns`] (n × 2k); the
    /// result as `(n − ng) × k` complex.
    pub(crate) fn left(&self, f: &Mat<f64>) -> Mat<c64> {
        let (sl, ms) = (&self.split.s, &self.split.m);
        let k = f.ncols() / 2;
        let fm = Mat::<f64>::from_fn(ms.len(), 2 * k, |i, j| f[(ms[i], j)]);
        let fs = Mat::<f64>::from_fn(sl.len(), 2 * k, |i, j| f[(sl[i], j)]);
        let g = fm - self.rt.transpose() * fs;
        Mat::<c64>::from_fn(ms.len(), k, |i, j| complex_at(&g, i, j))
    }

    /// `u = T q` (n × k complex) for q ((n − ng) × k complex).
    pub(crate) fn right(&self, q: &Mat<c64>) -> Mat<c64> {
        let (sl, ms) = (&self.split.s, &self.split.m);
        let (k, n) = (q.ncols(), sl.len() + ms.len());
        let qr = real_columns(ms.len(), k, |j, i| q[(i, j)]);
        let ys = -(&self.split.p * &qr);
        let mut u = Mat::<c64>::zeros(n, k);
        for j in 0..k {
            for (i, &d) in ms.iter().enumerate() {
                u[(d, j)] = q[(i, j)];
            }
            for (i, &d) in sl.iter().enumerate() {
                u[(d, j)] = complex_at(&ys, i, j);
            }
        }
        u
    }

    /// Size of the reduced problem, n − ng.
    pub(crate) fn reduced_size(&self) -> usize {
        self.split.m.len()
    }

    /// `Zᵀ X T` of a real n × n matrix.
    pub(crate) fn reduce_matrix(&self, x: &Mat<f64>) -> Mat<f64> {
        self.reduce(x.nrows(), |i, j| x[(i, j)])
    }

    /// `T q` (length n): the displacements of reduced coordinates, `G T q = 0`.
    pub(crate) fn expand_right(&self, q: &[Cplx]) -> Vec<Cplx> {
        self.expand(q, &self.split.p)
    }

    /// `Z η` (length n): the left vectors' displacement part, `(Gᵀ − D)ᵀ Z η = 0`.
    pub(crate) fn expand_left(&self, eta: &[Cplx]) -> Vec<Cplx> {
        self.expand(eta, &self.rt)
    }

    /// `Zᵀ f` (length n − ng).
    pub(crate) fn restrict_left(&self, f: &[Cplx]) -> Vec<Cplx> {
        self.restrict(f, &self.rt)
    }

    /// `Tᵀ f` (length n − ng).
    pub(crate) fn restrict_right(&self, f: &[Cplx]) -> Vec<Cplx> {
        self.restrict(f, &self.split.p)
    }

    /// `[−B q; q]` in (slave; other) rows, B = P or Rᵀ.
    fn expand(&self, q: &[Cplx], b: &Mat<f64>) -> Vec<Cplx> {
        let n = self.split.s.len() + self.split.m.len();
        let mut out = vec![Cplx::new(0.0, 0.0); n];
        for (k, &d) in self.split.m.iter().enumerate() {
            out[d] = q[k];
        }
        for (i, &d) in self.split.s.iter().enumerate() {
            out[d] = -(0..self.split.m.len())
                .map(|k| b[(i, k)] * q[k])
                .sum::<Cplx>();
        }
        out
    }

    /// `f_m − Bᵀ f_s`, B = P or Rᵀ.
    fn restrict(&self, f: &[Cplx], b: &Mat<f64>) -> Vec<Cplx> {
        let mut out: Vec<Cplx> = self.split.m.iter().map(|&d| f[d]).collect();
        for (i, &d) in self.split.s.iter().enumerate() {
            let fs = f[d];
            if fs == Cplx::new(0.0, 0.0) {
                continue;
            }
            for (k, o) in out.iter_mut().enumerate() {
                *o -= b[(i, k)] * fs;
            }
        }
        out
    }

    /// The multipliers of the bordered system from its first block row at the slaves:
    /// `ν = −A_s⁻¹ r_s` for a right vector (`r = X φ`, so that `X φ + A ν = 0` there), and
    /// `χ = −G_s⁻ᵀ r_s` for a left one (`r = Xᴴ ψ`, so that `Xᴴ ψ + Gᵀ χ = 0` there).
    pub(crate) fn multipliers(&self, r: &[Cplx], left: bool) -> Vec<Cplx> {
        let ng = self.split.s.len();
        // A_s = (A_sᵀ)ᵀ and G_sᵀ: transposed solves with the stored LUs.
        let mut rhs = Mat::<f64>::from_fn(ng, 2, |i, j| {
            let z = r[self.split.s[i]];
            -if j == 0 { z.re } else { z.im }
        });
        if left {
            self.split.gs_lu.solve_transpose_in_place(&mut rhs);
        } else {
            self.ast_lu.solve_transpose_in_place(&mut rhs);
        }
        (0..ng)
            .map(|i| Cplx::new(rhs[(i, 0)], rhs[(i, 1)]))
            .collect()
    }

    /// `Zᵀ X T` for the real matrix X given entry-wise by `x(i, j)`.
    fn reduce(&self, n: usize, x: impl Fn(usize, usize) -> f64) -> Mat<f64> {
        let (s, m) = (&self.split.s, &self.split.m);
        // X T = X_{:,m} − X_{:,s} P, then Zᵀ (X T) = (X T)_m − R (X T)_s.
        let xm = Mat::<f64>::from_fn(n, m.len(), |i, j| x(i, m[j]));
        let xs = Mat::<f64>::from_fn(n, s.len(), |i, j| x(i, s[j]));
        let xt = xm - xs * &self.split.p;
        let xtm = Mat::<f64>::from_fn(m.len(), m.len(), |i, j| xt[(m[i], j)]);
        let xts = Mat::<f64>::from_fn(s.len(), m.len(), |i, j| xt[(s[i], j)]);
        xtm - self.rt.transpose() * xts
    }
}

/// The factorisation behind [`ShiftInvert`].
enum Factor {
    /// `Q(σ)`, size n + ng.
    Bordered(PartialPivLu<c64>),
    /// `Zᵀ X(σ) T`, size n − ng ([`Elimination`]).
    Reduced(PartialPivLu<c64>),
}

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
/// — one complex LU per shift: of the bordered matrix `Q(σ)` (size n + ng), or, with an
/// [`Elimination`], of `Zᵀ(σ²M + σC + K)T` (size n − ng). The operator has the eigenvalues
/// `θ = 1/(p − σ)` with eigenvectors `[u; p u]`, and 0 on the infinite eigenvectors: the roots
/// nearest σ dominate, and the spurious ones cannot appear.
pub(crate) struct ShiftInvert<'a> {
    m: &'a Mat<f64>,
    c: Option<&'a Mat<f64>>,
    sigma: Cplx,
    factor: Factor,
    elim: Option<&'a Elimination>,
    n: usize,
    ng: usize,
}

impl<'a> ShiftInvert<'a> {
    /// Factorises `Q(σ)` (or its reduction by `elim`); `c` is `B − C_f` (None: no damping).
    ///
    /// # Errors
    /// A singular (zero or non-finite pivot) `Q(σ)`: σ is a root to machine precision.
    pub(crate) fn new(
        sys: &'a CeaMatrices,
        c: Option<&'a Mat<f64>>,
        sigma: Cplx,
        elim: Option<&'a Elimination>,
    ) -> Result<Self, CeaError> {
        let n = sys.m.nrows();
        let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
        let s2 = sigma * sigma;
        let (m, k) = (&sys.m, &sys.k);
        let cij = |i: usize, j: usize| c.map_or(0.0, |c| c[(i, j)]);
        let (factor, elim) = match elim {
            Some(e) => {
                // X(σ) = σ²M + σC + K in real and imaginary parts, both reduced in real
                // arithmetic.
                let re = e.reduce(n, |i, j| {
                    s2.re * m[(i, j)] + sigma.re * cij(i, j) + k[(i, j)]
                });
                let im = e.reduce(n, |i, j| s2.im * m[(i, j)] + sigma.im * cij(i, j));
                let q = Mat::<c64>::from_fn(re.nrows(), re.ncols(), |i, j| {
                    c64::new(re[(i, j)], im[(i, j)])
                });
                (Factor::Reduced(q.partial_piv_lu()), Some(e))
            }
            None => {
                let g = sys.g.as_ref();
                let d = sys.d.as_ref();
                let q = Mat::<c64>::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
                    (true, true) => s2 * m[(i, j)] + sigma * cij(i, j) + k[(i, j)],
                    (true, false) => {
                        let gt = g.map_or(0.0, |g| g[(j - n, i)]);
                        c64::new(gt - d.map_or(0.0, |d| d[(i, j - n)]), 0.0)
                    }
                    (false, true) => c64::new(g.map_or(0.0, |g| g[(i - n, j)]), 0.0),
                    (false, false) => c64::new(0.0, 0.0),
                });
                (Factor::Bordered(q.partial_piv_lu()), None)
            }
        };
        let u = match &factor {
            Factor::Bordered(lu) | Factor::Reduced(lu) => lu.U(),
        };
        let ratio = pivot_ratio(u, |z: &c64| z.norm());
        if !(ratio > 0.0) {
            return Err(CeaError::SingularShift {
                re: sigma.re,
                im: sigma.im,
                ratio,
            });
        }
        Ok(ShiftInvert {
            m,
            c,
            sigma,
            factor,
            elim,
            n,
            ng,
        })
    }

    /// The LU of `Zᵀ X(σ) T` when the factorisation is the reduced one (kept by a friction
    /// sweep's critical-μ search for the next trials, [`super::onset`]).
    pub(crate) fn into_reduced_lu(self) -> Option<PartialPivLu<c64>> {
        match self.factor {
            Factor::Reduced(lu) => Some(lu),
            Factor::Bordered(_) => None,
        }
    }

    /// The shift σ.
    pub(crate) fn sigma(&self) -> Cplx {
        self.sigma
    }

    /// Size of the complex LU.
    pub(crate) fn factor_size(&self) -> usize {
        match &self.factor {
            Factor::Bordered(lu) | Factor::Reduced(lu) => lu.U().nrows(),
        }
    }

    /// `"null_space"` (the reduced LU of size n − ng) or `"bordered"` (size n + ng).
    pub(crate) fn kind(&self) -> &'static str {
        match &self.factor {
            Factor::Bordered(_) => "bordered",
            Factor::Reduced(_) => "null_space",
        }
    }

    /// `y = (F − σE)⁻¹E x` (x, y of length 2n) for several vectors at once: one product of M
    /// and of C with all of them (their real and imaginary parts as columns) and one
    /// multi-column LU solve, so each matrix and the factor are read once per block, not once
    /// per vector (the applications are bound by memory traffic: on the 2 043-DOF brake the
    /// bordered factor alone is 107 MB, the reduced one 36 MB).
    pub(crate) fn apply_block(&self, xs: &[&[Cplx]]) -> Vec<Vec<Cplx>> {
        let (n, s, nb) = (self.n, self.sigma, xs.len());
        let t = real_columns(n, nb, |j, i| xs[j][n + i] + s * xs[j][i]);
        // f = −M(b + σa) − C a as real columns.
        let mut f = -(self.m * &t);
        if let Some(c) = self.c {
            f -= c * real_columns(n, nb, |j, i| xs[j][i]);
        }
        let yu: Mat<c64> = match (&self.factor, self.elim) {
            (Factor::Reduced(lu), Some(e)) => {
                let mut rhs = e.left(&f);
                lu.solve_in_place(&mut rhs);
                e.right(&rhs)
            }
            (Factor::Bordered(lu), _) | (Factor::Reduced(lu), None) => {
                let mut rhs = Mat::<c64>::from_fn(n + self.ng, nb, |i, j| {
                    if i < n {
                        complex_at(&f, i, j)
                    } else {
                        c64::new(0.0, 0.0)
                    }
                });
                lu.solve_in_place(&mut rhs);
                rhs
            }
        };
        (0..nb)
            .map(|j| {
                let mut y = Vec::with_capacity(2 * n);
                y.extend((0..n).map(|i| yu[(i, j)]));
                y.extend((0..n).map(|i| xs[j][i] + s * yu[(i, j)]));
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

#[cfg(test)]
mod tests {
    use super::*;

    /// 3 DOFs, one constraint on DOF 0. With D = 0 the slave is DOF 0 and the elimination
    /// exists; with D's row 0 equal to Gᵀ's, A = Gᵀ − D vanishes on the slave (A_s = 0, no
    /// left null-space basis of that form), so the elimination is refused and the bordered LU
    /// runs, with the same operator as the reduced one where both exist.
    #[test]
    fn the_elimination_is_refused_on_a_singular_slave_block_and_both_factors_agree() {
        let m = Mat::<f64>::from_fn(3, 3, |i, j| if i == j { 1.0 + i as f64 } else { 0.1 });
        let k = Mat::<f64>::from_fn(
            3,
            3,
            |i, j| if i == j { 10.0 * (1 + i) as f64 } else { -1.0 },
        );
        let mut sys = CeaMatrices::new(m, k);
        sys.g = Some(Mat::from_fn(1, 3, |_, j| if j == 0 { 2.0 } else { 0.0 }));
        sys.d = Some(Mat::from_fn(3, 1, |i, _| [0.0, 0.5, -0.25][i]));
        let c = Mat::<f64>::from_fn(3, 3, |i, j| {
            if i == j {
                0.3
            } else {
                0.05 * (i as f64 - j as f64)
            }
        });
        let e = Elimination::new(&sys).expect("a regular slave block");
        assert_eq!(e.split.s, vec![0]);
        let sigma = Cplx::new(0.2, 1.7);
        let red = ShiftInvert::new(&sys, Some(&c), sigma, Some(&e)).unwrap();
        let bor = ShiftInvert::new(&sys, Some(&c), sigma, None).unwrap();
        assert_eq!((red.kind(), red.factor_size()), ("null_space", 2));
        assert_eq!((bor.kind(), bor.factor_size()), ("bordered", 4));
        let x: Vec<Cplx> = (0..6)
            .map(|i| Cplx::new(1.0 + i as f64, 0.5 - i as f64))
            .collect();
        let (yr, yb) = (red.apply_block(&[&x]), bor.apply_block(&[&x]));
        let scale = yb[0].iter().map(|z| z.norm()).fold(0.0, f64::max);
        for (a, b) in yr[0].iter().zip(&yb[0]) {
            assert!((a - b).norm() <= 1e-13 * scale, "{a} vs {b}");
        }
        // G y_u = 0 on both.
        assert!(yr[0][0].norm() <= 1e-14 * scale);
        sys.d = Some(Mat::from_fn(3, 1, |i, _| [2.0, 0.5, -0.25][i]));
        assert!(Elimination::new(&sys).is_none());
    }
}
