//! Block Lanczos in the M-inner product with full reorthogonalisation and thick restart.
//!
//! Basis V (M-orthonormal) with MV = M V kept alongside, so M-inner products are plain dot
//! products with MV and the operator input M v is already at hand. The projected matrix
//! T = Vᵀ M Op V is kept explicitly (block tridiagonal, arrowhead after a restart).
//!
//! Each step: one block solve (the operator splits its columns over the threads, or works on
//! its own subdomains in parallel), two passes of block classical Gram–Schmidt against the
//! basis, and Cholesky QR (twice) of the new block in the M-inner product; a block that is
//! numerically rank deficient falls back to column-by-column Gram–Schmidt with random
//! replacement of vanishing columns. All n × b work blocks are allocated once.

use super::factor::Factor;
use super::spmm::sym_matmul;
use super::tall;
use crate::Real;
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};
use std::time::Instant;

/// What the caller wants: the lowest `n_modes`, and/or all with θ ≥ `theta_min`.
pub(crate) struct Want {
    pub n_modes: Option<usize>,
    pub theta_min: Option<Real>,
}

pub(crate) struct LanczosOut {
    /// Ritz vectors (n × count) of the selected pairs, θ descending.
    pub x: Mat<Real>,
    pub converged: usize,
    pub done: bool,
    pub iterations: usize,
    pub restarts: usize,
    pub solves: usize,
    pub m_products: usize,
    pub max_basis: usize,
    pub solve_s: Real,
    /// Seconds in Gram–Schmidt against the basis and the block QR (M products included).
    pub orth_s: Real,
    /// Seconds in the Rayleigh–Ritz eigen-solves and restarts.
    pub ritz_s: Real,
    /// Blocks that needed the column-by-column fall-back of the QR.
    pub qr_fallbacks: usize,
}

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> Real {
        // xorshift64*: uniform in [-1, 1).
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D);
        (v >> 11) as Real / (1u64 << 53) as Real * 2.0 - 1.0
    }
}

/// Dot product with 8 independent partial sums (vectorisable).
fn dot(a: &[Real], b: &[Real]) -> Real {
    let mut acc = [0.0; 8];
    let (ca, cb) = (a.chunks_exact(8), b.chunks_exact(8));
    let tail: Real = ca
        .remainder()
        .iter()
        .zip(cb.remainder())
        .map(|(x, y)| x * y)
        .sum();
    for (x, y) in ca.zip(cb) {
        for k in 0..8 {
            acc[k] += x[k] * y[k];
        }
    }
    acc.iter().sum::<Real>() + tail
}

struct Ctx<'a> {
    op: &'a Factor,
    m: SparseColMatRef<'a, usize, Real>,
    rng: Rng,
    solves: usize,
    m_products: usize,
    solve_s: Real,
    orth_s: Real,
    qr_fallbacks: usize,
    /// n × b scratch for the block QR.
    tmp: Mat<Real>,
}

impl Ctx<'_> {
    fn m_times(&mut self, x: MatRef<'_, Real>, mut out: MatMut<'_, Real>) {
        sym_matmul(self.m, x, out.as_mut());
        self.m_products += x.ncols();
    }

    fn solve(&mut self, x: MatMut<'_, Real>) {
        let ts = Instant::now();
        self.solves += x.ncols();
        self.op.solve_block(x);
        self.solve_s += ts.elapsed().as_secs_f64();
    }

    /// Two passes of block classical Gram–Schmidt of `w` against the basis (v, mv);
    /// returns h = (MV)ᵀ w_in.
    fn project_out(
        &self,
        v: MatRef<'_, Real>,
        mv: MatRef<'_, Real>,
        mut w: MatMut<'_, Real>,
    ) -> Mat<Real> {
        let mut h = Mat::<Real>::zeros(v.ncols(), w.ncols());
        if v.ncols() == 0 {
            return h;
        }
        for _ in 0..2 {
            let c = tall::tn(mv, w.as_ref());
            tall::nn(w.as_mut(), true, v, c.as_ref(), -1.0);
            h += &c;
        }
        h
    }

    /// M-orthonormalises the columns of `w` (already orthogonal to the basis), writing M w to
    /// `mw`; returns R with W_in = Q R. Cholesky QR twice; falls back to [`Ctx::orth_columns`]
    /// when a column vanished (relative to its norm `pre` before the projection) or the block's
    /// Gram matrix is too ill-conditioned for Cholesky QR.
    fn orth_block(
        &mut self,
        v: MatRef<'_, Real>,
        mv: MatRef<'_, Real>,
        w: &mut Mat<Real>,
        mw: &mut Mat<Real>,
        pre: &[Real],
    ) -> Mat<Real> {
        let b = w.ncols();
        self.m_times(w.as_ref(), mw.as_mut());
        let vanished = (0..b).any(|j| {
            let e = dot(w.col_as_slice(j), w.col_as_slice(j)).sqrt();
            e.is_nan() || e <= 1e-10 * pre[j]
        });
        if !vanished {
            let mut r = Mat::<Real>::identity(b, b);
            let mut ok = true;
            for _ in 0..2 {
                let g = tall::tn(w.as_ref(), mw.as_ref());
                let g = Mat::<Real>::from_fn(b, b, |i, j| 0.5 * (g[(i, j)] + g[(j, i)]));
                let Ok(llt) = g.llt(Side::Lower) else {
                    ok = false;
                    break;
                };
                let l = llt.L();
                // Cholesky QR is stable while cond(W) stays well below 1/sqrt(eps).
                let well = (0..b).all(|j| l[(j, j)] > 1e-6 * g[(j, j)].sqrt());
                if !well {
                    ok = false;
                    break;
                }
                let linv_t = l_inverse_transpose(l);
                tall::nn(self.tmp.as_mut(), false, w.as_ref(), linv_t.as_ref(), 1.0);
                w.copy_from(&self.tmp);
                tall::nn(self.tmp.as_mut(), false, mw.as_ref(), linv_t.as_ref(), 1.0);
                mw.copy_from(&self.tmp);
                r = l.transpose() * &r;
            }
            if ok {
                return r;
            }
            // Undo nothing: the columns still span the same space; redo column by column
            // from the current block (R composes with what was applied).
            self.qr_fallbacks += 1;
            self.m_times(w.as_ref(), mw.as_mut());
            let r2 = self.orth_columns(v, mv, w, mw, pre);
            return r2 * &r;
        }
        self.qr_fallbacks += 1;
        self.orth_columns(v, mv, w, mw, pre)
    }

    /// Column-by-column modified Gram–Schmidt (twice) in the M-inner product, `mw` = M w on
    /// entry; columns that vanish (relative to `pre` norms) are replaced by random vectors
    /// orthogonal to everything (R column zero there).
    fn orth_columns(
        &mut self,
        v: MatRef<'_, Real>,
        mv: MatRef<'_, Real>,
        w: &mut Mat<Real>,
        mw: &mut Mat<Real>,
        pre: &[Real],
    ) -> Mat<Real> {
        let b = w.ncols();
        let n = w.nrows();
        let mut r = Mat::<Real>::zeros(b, b);
        let (mut wj, mut mwj) = (vec![0.0; n], vec![0.0; n]);
        for j in 0..b {
            wj.copy_from_slice(w.col_as_slice(j));
            mwj.copy_from_slice(mw.col_as_slice(j));
            let mut replaced = false;
            loop {
                for _ in 0..2 {
                    for i in 0..j {
                        let (qi, mqi) = (w.col_as_slice(i), mw.col_as_slice(i));
                        let c = dot(mqi, &wj);
                        if !replaced {
                            r[(i, j)] += c;
                        }
                        wj.iter_mut().zip(qi).for_each(|(a, q)| *a -= c * q);
                        mwj.iter_mut().zip(mqi).for_each(|(a, q)| *a -= c * q);
                    }
                }
                let nrm2 = dot(&wj, &mwj);
                let e = dot(&wj, &wj).sqrt();
                if nrm2 > 0.0 && e > 1e-10 * pre[j] && nrm2.is_finite() {
                    let s = nrm2.sqrt();
                    if !replaced {
                        r[(j, j)] = s;
                    }
                    wj.iter_mut().for_each(|a| *a /= s);
                    mwj.iter_mut().for_each(|a| *a /= s);
                    break;
                }
                // Breakdown: a fresh random direction, orthogonal to the basis.
                replaced = true;
                let mut col = Mat::<Real>::from_fn(n, 1, |_, _| self.rng.next());
                let _ = self.project_out(v, mv, col.as_mut());
                let mut mcol = Mat::<Real>::zeros(n, 1);
                self.m_times(col.as_ref(), mcol.as_mut());
                wj.copy_from_slice(col.col_as_slice(0));
                mwj.copy_from_slice(mcol.col_as_slice(0));
            }
            w.col_as_slice_mut(j).copy_from_slice(&wj);
            mw.col_as_slice_mut(j).copy_from_slice(&mwj);
        }
        r
    }
}

/// L⁻ᵀ of a small lower-triangular L (forward substitution on the identity).
fn l_inverse_transpose(l: MatRef<'_, Real>) -> Mat<Real> {
    let b = l.nrows();
    let mut inv = Mat::<Real>::zeros(b, b);
    for c in 0..b {
        for i in c..b {
            let mut s = if i == c { 1.0 } else { 0.0 };
            for k in c..i {
                s -= l[(i, k)] * inv[(k, c)];
            }
            inv[(i, c)] = s / l[(i, i)];
        }
    }
    inv.transpose().to_owned()
}

/// Runs the block Lanczos iteration on Op = (K − σM)⁻¹M.
#[allow(clippy::too_many_arguments)]
pub(crate) fn lanczos(
    op: &Factor,
    m: SparseColMatRef<'_, usize, Real>,
    want: &Want,
    block_size: usize,
    max_basis: usize,
    tol: Real,
    max_restarts: usize,
    seed: u64,
    interrupt: &crate::Interrupt,
) -> Result<LanczosOut, crate::FeError> {
    let n = m.nrows();
    let b = block_size;
    let mut mmax = max_basis;
    let mut ctx = Ctx {
        op,
        m,
        rng: Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1),
        solves: 0,
        m_products: 0,
        solve_s: 0.0,
        orth_s: 0.0,
        qr_fallbacks: 0,
        tmp: Mat::zeros(n, b),
    };
    let mut ritz_s = 0.0;
    let mut v = Mat::<Real>::zeros(n, mmax + b);
    let mut mv = Mat::<Real>::zeros(n, mmax + b);
    let mut t = Mat::<Real>::zeros(mmax + b, mmax + b);
    let mut w = Mat::<Real>::zeros(n, b);
    let mut mw = Mat::<Real>::zeros(n, b);

    // Starting block: Op applied to a random block (filters the high modes).
    w.copy_from(Mat::<Real>::from_fn(n, b, |_, _| ctx.rng.next()));
    ctx.m_times(w.as_ref(), mw.as_mut());
    ctx.solve(mw.as_mut());
    w.copy_from(&mw);
    let pre: Vec<Real> = (0..b)
        .map(|j| dot(w.col_as_slice(j), w.col_as_slice(j)).sqrt())
        .collect();
    ctx.orth_block(
        v.as_ref().subcols(0, 0),
        mv.as_ref().subcols(0, 0),
        &mut w,
        &mut mw,
        &pre,
    );
    v.as_mut().subcols_mut(0, b).copy_from(&w);
    mv.as_mut().subcols_mut(0, b).copy_from(&mw);

    let (mut cur, mut tot) = (0usize, b);
    let (mut iterations, mut restarts) = (0usize, 0usize);
    let mut used_basis = 0;
    loop {
        if interrupt.is_set() {
            return Err(crate::FeError::Interrupted {
                during: "Lanczos iterations",
            });
        }
        // Apply Op to the block cur..tot and extend the basis.
        w.copy_from(mv.as_ref().subcols(cur, b));
        ctx.solve(w.as_mut());
        iterations += 1;
        let to = Instant::now();
        let pre: Vec<Real> = (0..b)
            .map(|j| dot(w.col_as_slice(j), w.col_as_slice(j)).sqrt())
            .collect();
        let h = ctx.project_out(
            v.as_ref().subcols(0, tot),
            mv.as_ref().subcols(0, tot),
            w.as_mut(),
        );
        for r in 0..tot {
            for c in 0..b {
                t[(r, cur + c)] = h[(r, c)];
                if r < cur {
                    t[(cur + c, r)] = h[(r, c)];
                }
            }
        }
        for r in 0..b {
            for c in 0..r {
                let s = 0.5 * (t[(cur + r, cur + c)] + t[(cur + c, cur + r)]);
                t[(cur + r, cur + c)] = s;
                t[(cur + c, cur + r)] = s;
            }
        }
        let rr = ctx.orth_block(
            v.as_ref().subcols(0, tot),
            mv.as_ref().subcols(0, tot),
            &mut w,
            &mut mw,
            &pre,
        );
        v.as_mut().subcols_mut(tot, b).copy_from(&w);
        mv.as_mut().subcols_mut(tot, b).copy_from(&mw);
        for r in 0..b {
            for c in 0..b {
                t[(tot + r, cur + c)] = rr[(r, c)];
                t[(cur + c, tot + r)] = rr[(r, c)];
            }
        }
        cur = tot;
        tot += b;
        used_basis = used_basis.max(tot);
        ctx.orth_s += to.elapsed().as_secs_f64();

        // Rayleigh–Ritz on the applied part.
        let tr = Instant::now();
        let (theta, y, res) = ritz(&t, cur, b);
        ritz_s += tr.elapsed().as_secs_f64();
        let nev_target = match (want.n_modes, want.theta_min) {
            (Some(k), _) => k,
            (None, Some(tm)) => theta.iter().filter(|&&th| th >= tm).count() + 1,
            (None, None) => b,
        };
        let mut converged = 0;
        let mut done = false;
        let cap = want.n_modes.unwrap_or(usize::MAX);
        loop {
            let i = converged;
            if i == cap {
                done = true;
                break;
            }
            if i >= theta.len() {
                break;
            }
            let ok = res[i] <= tol * theta[i].abs();
            if let Some(tm) = want.theta_min {
                if theta[i] < tm {
                    // First pair beyond the cut-off: it must be converged to trust the boundary.
                    done = ok && i + b < cur;
                    break;
                }
            }
            if !ok {
                break;
            }
            converged += 1;
        }
        let finish = |x_count: usize, done: bool, converged: usize, ctx: &Ctx<'_>| {
            let mut x = Mat::<Real>::zeros(n, x_count);
            tall::nn(
                x.as_mut(),
                false,
                v.as_ref().subcols(0, cur),
                y.as_ref().subcols(0, x_count),
                1.0,
            );
            LanczosOut {
                x,
                converged: converged.min(x_count),
                done,
                iterations,
                restarts,
                solves: ctx.solves,
                m_products: ctx.m_products,
                max_basis: used_basis,
                solve_s: ctx.solve_s,
                orth_s: ctx.orth_s,
                ritz_s,
                qr_fallbacks: ctx.qr_fallbacks,
            }
        };
        if done || cur >= n.saturating_sub(b) {
            let count = match want.n_modes {
                Some(k) => k.min(theta.len()),
                None => converged,
            };
            let count = match want.theta_min {
                Some(tm) => theta[..count].iter().filter(|&&th| th >= tm).count(),
                None => count,
            };
            return Ok(finish(count, done, converged, &ctx));
        }
        if tot + b <= mmax + b && tot <= mmax {
            continue;
        }
        // Thick restart: keep the best Ritz vectors plus the residual block.
        if restarts >= max_restarts {
            let count = want.n_modes.unwrap_or(converged).min(theta.len());
            return Ok(finish(count, false, converged, &ctx));
        }
        let tr = Instant::now();
        restarts += 1;
        if nev_target + 2 * b > mmax {
            // Cut-off mode found more modes than the basis can hold: grow it.
            let new_max = (2 * nev_target + 2 * b).min(n.saturating_sub(b));
            if new_max > mmax {
                mmax = new_max;
                v.resize_with(n, mmax + b, |_, _| 0.0);
                mv.resize_with(n, mmax + b, |_, _| 0.0);
                t.resize_with(mmax + b, mmax + b, |_, _| 0.0);
            }
        }
        let keep = (nev_target + (cur.saturating_sub(nev_target)) / 2)
            .max(nev_target)
            .min(cur.saturating_sub(b))
            .max(1);
        let yk = y.as_ref().subcols(0, keep);
        let mut x = Mat::<Real>::zeros(n, keep);
        let mut mx = Mat::<Real>::zeros(n, keep);
        tall::nn(x.as_mut(), false, v.as_ref().subcols(0, cur), yk, 1.0);
        tall::nn(mx.as_mut(), false, mv.as_ref().subcols(0, cur), yk, 1.0);
        let resid_v = v.as_ref().subcols(cur, b).to_owned();
        let resid_mv = mv.as_ref().subcols(cur, b).to_owned();
        let mut coupling = Mat::<Real>::zeros(b, keep);
        matmul(
            coupling.as_mut(),
            Accum::Replace,
            t.as_ref().submatrix(cur, 0, b, cur),
            yk,
            1.0,
            Par::Seq,
        );
        v.as_mut().subcols_mut(0, keep).copy_from(&x);
        mv.as_mut().subcols_mut(0, keep).copy_from(&mx);
        v.as_mut().subcols_mut(keep, b).copy_from(&resid_v);
        mv.as_mut().subcols_mut(keep, b).copy_from(&resid_mv);
        t.fill(0.0);
        for i in 0..keep {
            t[(i, i)] = theta[i];
            for r in 0..b {
                t[(keep + r, i)] = coupling[(r, i)];
                t[(i, keep + r)] = coupling[(r, i)];
            }
        }
        cur = keep;
        tot = keep + b;
        ritz_s += tr.elapsed().as_secs_f64();
    }
}

/// Eigenpairs of the symmetric T[0..cur, 0..cur], θ descending, and the Lanczos residual
/// bounds ‖T[cur..cur+b, 0..cur] y‖.
fn ritz(t: &Mat<Real>, cur: usize, b: usize) -> (Vec<Real>, Mat<Real>, Vec<Real>) {
    let ts = Mat::<Real>::from_fn(cur, cur, |i, j| 0.5 * (t[(i, j)] + t[(j, i)]));
    let (theta, y) = match ts.self_adjoint_eigen(Side::Lower) {
        Ok(e) => {
            let s = e.S();
            let u = e.U();
            let th: Vec<Real> = (0..cur).rev().map(|i| s[i]).collect();
            let y = Mat::<Real>::from_fn(cur, cur, |r, c| u[(r, cur - 1 - c)]);
            (th, y)
        }
        Err(_) => (vec![Real::NAN; cur], Mat::<Real>::zeros(cur, cur)),
    };
    let mut res = vec![0.0; cur];
    let mut coupling = Mat::<Real>::zeros(b, cur);
    matmul(
        coupling.as_mut(),
        Accum::Replace,
        t.as_ref().submatrix(cur, 0, b, cur),
        y.as_ref(),
        1.0,
        Par::Seq,
    );
    for (i, ri) in res.iter_mut().enumerate() {
        *ri = (0..b)
            .map(|r| coupling[(r, i)].powi(2))
            .sum::<Real>()
            .sqrt();
    }
    (theta, y, res)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_transpose_of_a_triangle() {
        let l = Mat::<Real>::from_fn(4, 4, |i, j| {
            if j > i {
                0.0
            } else {
                1.0 + (i * 3 + j) as Real * 0.25
            }
        });
        let it = l_inverse_transpose(l.as_ref());
        let prod = l.transpose() * &it;
        for i in 0..4 {
            for j in 0..4 {
                let e = if i == j { 1.0 } else { 0.0 };
                assert!((prod[(i, j)] - e).abs() < 1e-13, "{i} {j} {}", prod[(i, j)]);
            }
        }
    }
}
