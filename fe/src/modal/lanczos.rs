//! Block Lanczos in the M-inner product with full reorthogonalisation and thick restart.
//!
//! Basis V (M-orthonormal) with MV = M V kept alongside, so M-inner products are plain dot
//! products with MV and the operator input M v is already at hand. The projected matrix
//! T = Vᵀ M Op V is kept explicitly (block tridiagonal, arrowhead after a restart).

use super::factor::Factor;
use super::spmm::sym_matmul;
use super::tall;
use crate::Real;
use faer::linalg::matmul::matmul;
use faer::sparse::SparseColMatRef;
use faer::{Accum, Mat, MatMut, MatRef, Par, Side};

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
    /// Parallelism of the small dense products (the tall-skinny ones go through
    /// [`tall`], which splits rows over the threads itself).
    par: Par,
    rng: Rng,
    solves: usize,
    m_products: usize,
    solve_s: Real,
}

impl Ctx<'_> {
    fn m_times(&mut self, x: MatRef<'_, Real>, mut out: MatMut<'_, Real>) {
        sym_matmul(self.m, x, out.as_mut());
        self.m_products += x.ncols();
    }

    /// Two passes of classical Gram–Schmidt of `w` against the basis (v, mv); returns h.
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
    /// `mw`; returns R with W_in = Q R. Columns that vanish (relative to `pre` norms) are
    /// replaced by random vectors orthogonal to everything (R column zero there).
    fn orth_block(
        &mut self,
        v: MatRef<'_, Real>,
        mv: MatRef<'_, Real>,
        w: &mut Mat<Real>,
        mw: &mut Mat<Real>,
        pre: &[Real],
    ) -> Mat<Real> {
        let b = w.ncols();
        let n = w.nrows();
        self.m_times(w.as_ref(), mw.as_mut());
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

/// Runs the block Lanczos iteration on Op = (K − σM)⁻¹M.
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
        par: Par::Seq,
        rng: Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1),
        solves: 0,
        m_products: 0,
        solve_s: 0.0,
    };
    let mut v = Mat::<Real>::zeros(n, mmax + b);
    let mut mv = Mat::<Real>::zeros(n, mmax + b);
    let mut t = Mat::<Real>::zeros(mmax + b, mmax + b);

    // Starting block: Op applied to a random block (filters the high modes).
    let mut w = Mat::<Real>::from_fn(n, b, |_, _| ctx.rng.next());
    let mut mw = Mat::<Real>::zeros(n, b);
    ctx.m_times(w.as_ref(), mw.as_mut());
    ctx.op.solve_in_place(mw.as_mut());
    ctx.solves += b;
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
        let mut w = mv.as_ref().subcols(cur, b).to_owned();
        let ts = std::time::Instant::now();
        ctx.op.solve_in_place(w.as_mut());
        ctx.solve_s += ts.elapsed().as_secs_f64();
        ctx.solves += b;
        iterations += 1;
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
        let mut mw = Mat::<Real>::zeros(n, b);
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

        // Rayleigh–Ritz on the applied part.
        let (theta, y, res) = ritz(&t, cur, b);
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
        if done || cur >= n.saturating_sub(b) {
            let count = match want.n_modes {
                Some(k) => k.min(theta.len()),
                None => converged,
            };
            let count = match want.theta_min {
                Some(tm) => theta[..count].iter().filter(|&&th| th >= tm).count(),
                None => count,
            };
            let mut x = Mat::<Real>::zeros(n, count);
            tall::nn(
                x.as_mut(),
                false,
                v.as_ref().subcols(0, cur),
                y.as_ref().subcols(0, count),
                1.0,
            );
            return Ok(LanczosOut {
                x,
                converged: converged.min(count),
                done,
                iterations,
                restarts,
                solves: ctx.solves,
                m_products: ctx.m_products,
                max_basis: used_basis,
                solve_s: ctx.solve_s,
            });
        }
        if tot + b <= mmax + b && tot <= mmax {
            continue;
        }
        // Thick restart: keep the best Ritz vectors plus the residual block.
        if restarts >= max_restarts {
            let count = want.n_modes.unwrap_or(converged).min(theta.len());
            let mut x = Mat::<Real>::zeros(n, count);
            tall::nn(
                x.as_mut(),
                false,
                v.as_ref().subcols(0, cur),
                y.as_ref().subcols(0, count),
                1.0,
            );
            return Ok(LanczosOut {
                x,
                converged: converged.min(count),
                done: false,
                iterations,
                restarts,
                solves: ctx.solves,
                m_products: ctx.m_products,
                max_basis: used_basis,
                solve_s: ctx.solve_s,
            });
        }
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
            ctx.par,
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
    for (i, ri) in res.iter_mut().enumerate() {
        let mut s = 0.0;
        for r in 0..b {
            let mut acc = 0.0;
            for k in 0..cur {
                acc += t[(cur + r, k)] * y[(k, i)];
            }
            s += acc * acc;
        }
        *ri = s.sqrt();
    }
    (theta, y, res)
}
