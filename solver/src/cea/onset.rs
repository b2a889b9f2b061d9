//! An exact root followed from one friction coefficient to a nearby one without a new
//! factorisation: residual inverse iteration with the LU of the refinement that found it
//! (a friction sweep's critical-μ search evaluates the same root at several μ a few 1e-5
//! apart).

use super::operator::{complex_norm, real_columns};
use super::refine::KeptFactor;
use super::shift_invert::Elimination;
use super::{CeaError, CeaMatrices, Cplx};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};

/// A root followed by [`follow`].
#[derive(Debug, Clone)]
pub(crate) struct Followed {
    /// The exact root p at the new state.
    pub(crate) p: Cplx,
    /// Its u (length n, unit 2-norm, not phase-normalised).
    pub(crate) u: Vec<Cplx>,
    /// Iterations (one solve with the kept LU for three right-hand sides each).
    pub(crate) iterations: usize,
    /// Backward error of the final pair in the reduced equations:
    /// ‖Zᵀ(p²M + pC + K)Tq‖ / ((|p|²‖M‖ + |p|‖C‖ + ‖K‖)‖Tq‖) (Frobenius norms).
    pub(crate) residual: f64,
}

/// Follows the exact root `p0` with eigenvector `u0` (at a neighbouring state) to the state
/// `sys` by residual inverse iteration preconditioned with `kept` (the reduced LU of
/// `Z₀ᵀ X(σ) T` made at that neighbouring state, σ near p0). `c` is `B − C_f` of `sys`.
/// Returns `None` when it did not converge to `tol` in `max_iter` iterations or the
/// elimination of `sys` does not exist (the caller then refines afresh).
///
/// # Reference
/// Neumaier (1985), "Residual inverse iteration for the nonlinear eigenvalue problem", SIAM
/// J. Numer. Anal. 22: for `R(p) q = 0`, `q_{k+1} = q_k − R(σ)⁻¹ R(p_{k+1}) q_k` with
/// p_{k+1} the root of `wᴴ R(σ)⁻¹ R(p) q_k = 0` (wᴴq_k = 1) nearest p_k; it converges
/// linearly, at a rate of order |σ − p*| over the distance to the other roots, with one
/// factorisation for all iterations.
///
/// # Derivation
/// With the slaves of G ([`Elimination`]), `u = T q` satisfies `G u = 0` and `Zᵀ(μ)` (which
/// annihilates `A(μ) = Gᵀ − D(μ)`) removes the multipliers: the constrained problem at μ is
/// exactly `R(p) q = Zᵀ(μ)(p²M + pC(μ) + K)T q = 0` (as in [`super::shift_invert`]). R is
/// quadratic in p, so with `v_X = R₀⁻¹ Zᵀ(μ) X T q_k` for X = M, C, K the functional is
/// `a p² + b p + c = 0`, `a = wᴴv_M`, `b = wᴴv_C`, `c = wᴴv_K`, and the update is
/// `q_{k+1} = q_k − (p² v_M + p v_C + v_K)`: one LU solve with three right-hand sides per
/// iteration. `R₀ = Z₀ᵀX(σ)T` is the neighbouring state's: it differs from R(σ) at μ by
/// O(Δμ), which slows the convergence a little but does not move its fixed point, the exact
/// root at μ.
pub(crate) fn follow(
    kept: &KeptFactor,
    sys: &CeaMatrices,
    c: Option<&Mat<f64>>,
    p0: Cplx,
    u0: &[Cplx],
    tol: f64,
    max_iter: usize,
) -> Result<Option<Followed>, CeaError> {
    let n = sys.m.nrows();
    if u0.len() != n {
        return Ok(None);
    }
    let Some(elim) = Elimination::with_split(sys, kept.elim.split().clone()) else {
        return Ok(None);
    };
    let ms = &elim.split().m;
    let mut q = Mat::<c64>::from_fn(ms.len(), 1, |i, _| u0[ms[i]]);
    let norms = [
        sys.m.norm_l2(),
        c.map_or(0.0, |c| c.norm_l2()),
        sys.k.norm_l2(),
    ];
    let mut p = p0;
    for it in 1..=max_iter {
        let (_, z) = products(&elim, sys, c, &q);
        let mut v = z;
        kept.lu.solve_in_place(&mut v);
        // w = q / (qᴴq): wᴴq = 1.
        let qq: f64 = (0..q.nrows()).map(|i| q[(i, 0)].norm_sqr()).sum();
        let wdot = |j: usize| -> Cplx {
            let s: c64 = (0..q.nrows()).map(|i| q[(i, 0)].conj() * v[(i, j)]).sum();
            Cplx::new(s.re, s.im) / qq
        };
        let (a, b, cc) = (wdot(0), wdot(1), wdot(2));
        let disc = (b * b - 4.0 * a * cc).sqrt();
        let roots = [(-b + disc) / (2.0 * a), (-b - disc) / (2.0 * a)];
        let pn = if (roots[0] - p).norm() <= (roots[1] - p).norm() {
            roots[0]
        } else {
            roots[1]
        };
        if !(pn.re.is_finite() && pn.im.is_finite()) {
            return Ok(None);
        }
        let pc = c64::new(pn.re, pn.im);
        let step = Mat::<c64>::from_fn(q.nrows(), 1, |i, _| {
            pc * pc * v[(i, 0)] + pc * v[(i, 1)] + v[(i, 2)]
        });
        let snorm = (0..step.nrows())
            .map(|i| step[(i, 0)].norm_sqr())
            .sum::<f64>()
            .sqrt();
        q -= &step;
        let dp = (pn - p).norm();
        p = pn;
        let qn = (0..q.nrows())
            .map(|i| q[(i, 0)].norm_sqr())
            .sum::<f64>()
            .sqrt();
        if !qn.is_finite() || qn == 0.0 {
            return Ok(None);
        }
        let scale_q = c64::new(1.0 / qn, 0.0);
        for i in 0..q.nrows() {
            q[(i, 0)] *= scale_q;
        }
        if dp <= tol * p.norm() && snorm <= tol * qn {
            // The backward error of the final pair.
            let (u, z) = products(&elim, sys, c, &q);
            let pc = c64::new(p.re, p.im);
            let rnorm = (0..z.nrows())
                .map(|i| (pc * pc * z[(i, 0)] + pc * z[(i, 1)] + z[(i, 2)]).norm_sqr())
                .sum::<f64>()
                .sqrt();
            let un = complex_norm(&u, 0);
            let pa = p.norm();
            let scale = (pa * pa * norms[0] + pa * norms[1] + norms[2]) * un;
            return Ok(Some(Followed {
                p,
                u: (0..n)
                    .map(|i| Cplx::new(u[(i, 0)], u[(i, 1)]) / un)
                    .collect(),
                iterations: it,
                residual: if scale > 0.0 { rnorm / scale } else { rnorm },
            }));
        }
    }
    Ok(None)
}

/// `u = T q` (as real columns, n × 2) and `Zᵀ X u` for X = M, C, K (three complex columns).
fn products(
    elim: &Elimination,
    sys: &CeaMatrices,
    c: Option<&Mat<f64>>,
    q: &Mat<c64>,
) -> (Mat<f64>, Mat<c64>) {
    let n = sys.m.nrows();
    let u = elim.right(q);
    let ur = real_columns(n, 1, |_, i| u[(i, 0)]);
    let mu = &sys.m * &ur;
    let ku = &sys.k * &ur;
    let cu = match c {
        Some(c) => c * &ur,
        None => Mat::zeros(n, 2),
    };
    let f = Mat::<f64>::from_fn(n, 6, |i, j| match j / 2 {
        0 => mu[(i, j % 2)],
        1 => cu[(i, j % 2)],
        _ => ku[(i, j % 2)],
    });
    (ur, elim.left(&f))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cea::eigen::exact;
    use crate::cea::operator::damping;
    use crate::cea::refine::{RefineOptions, RefineRun};
    use crate::cea::test_random::{random_spd, Rng};
    use crate::cea::{mac, CeaMethod, CeaOptions};

    /// 24 DOFs, 5 constraints; μ enters the stiffness (μ K1), the friction tangent (μ D1) and
    /// a friction damping C_f = μ C1, as a friction sweep's tangents do.
    fn model(mu: f64) -> CeaMatrices {
        let (n, ng) = (24, 5);
        let mut rng = Rng(11);
        let mut spd = |shift: f64| random_spd(n, &mut rng, shift);
        let m = spd(n as f64);
        let mut k0 = spd(0.0);
        for i in 0..n {
            k0[(i, i)] += n as f64 * (1.0 + 100.0 * (i as f64 / n as f64).powi(2));
        }
        let mut rng = Rng(5);
        let k1 = Mat::from_fn(n, n, |_, _| 0.5 * rng.next() * (n as f64).sqrt());
        let g = Mat::from_fn(ng, n, |_, _| rng.next());
        let d1 = Mat::from_fn(n, ng, |_, _| 0.3 * rng.next());
        let c1 = Mat::from_fn(n, n, |_, _| 0.05 * rng.next());
        let mut s = CeaMatrices::new(m.clone(), &k0 + &k1 * mu);
        s.b = Some(&k0 * 1e-4 + &m * 1e-3);
        s.g = Some(g);
        s.d = Some(&d1 * mu);
        s.c_f = Some(&c1 * mu);
        s
    }

    /// The nearest dense exact root (and its shape) to p.
    fn dense_nearest(sys: &CeaMatrices, p: Cplx) -> (Cplx, Vec<Cplx>) {
        let opts = CeaOptions {
            method: CeaMethod::Exact,
            ..CeaOptions::default()
        };
        let r = exact(sys, &opts).unwrap();
        let m = r
            .modes
            .iter()
            .min_by(|a, b| {
                (a.eigenvalue - p)
                    .norm()
                    .total_cmp(&(b.eigenvalue - p).norm())
            })
            .unwrap();
        (m.eigenvalue, m.shape.clone())
    }

    /// A root refined at μ0 (from a projected value 1e-4 off, as a sweep's shift is), then
    /// followed with that refinement's LU to μ0 + Δμ for Δμ up to 3e-4 (a critical-μ search's
    /// trials): every followed root equals the dense exact root at its μ to 1e-10 (relative),
    /// its shape the dense shape (MAC 1 − 1e-10), with no new factorisation; the roots moved by
    /// far more than that. Far away (Δμ = 0.05) the iteration either fails (the search then
    /// refines afresh) or still converges to the exact root.
    #[test]
    fn followed_roots_equal_the_dense_exact_roots_at_the_new_mu() {
        let mu0 = 0.45;
        let sys0 = model(mu0);
        let opts = CeaOptions {
            method: CeaMethod::Exact,
            ..CeaOptions::default()
        };
        let r0 = exact(&sys0, &opts).unwrap();
        for target in [3usize, 10] {
            let mut modes = r0.modes.clone();
            let p_exact0 = modes[target].eigenvalue;
            modes[target].eigenvalue = p_exact0 * Cplx::new(1.0 + 1e-4, 5e-5);
            let ro = RefineOptions::default();
            let interrupt = crate::Interrupt::default();
            let run = RefineRun {
                band_hz: f64::INFINITY,
                unstable_tol_abs: 0.0,
                opts: &ro,
                interrupt: &interrupt,
                split: None,
                keep: true,
            };
            let (st, kept) = run.targets(&sys0, &mut modes, vec![target]).unwrap();
            let kept = kept.expect("the reduced factorisation");
            assert_eq!(st.n_shifts, 1);
            let refined = modes
                .iter()
                .find(|m| (m.eigenvalue - p_exact0).norm() <= 1e-9 * p_exact0.norm())
                .expect("the refined root");
            let (mut p, mut u) = (refined.eigenvalue, refined.shape.clone());
            for dmu in [3e-5, 1e-4, 3e-4, 5e-2] {
                let sys = model(mu0 + dmu);
                let c = damping(&sys);
                let x = follow(&kept, &sys, c.as_ref(), p, &u, 1e-12, 30).unwrap();
                let Some(x) = x else {
                    assert_eq!(dmu, 5e-2, "converged at dmu {dmu}");
                    eprintln!("target {target} dmu {dmu:e}: not converged");
                    continue;
                };
                let (pd, ud) = dense_nearest(&sys, x.p);
                let err = (x.p - pd).norm() / pd.norm();
                let moved = (pd - p_exact0).norm() / pd.norm();
                eprintln!(
                    "target {target} dmu {dmu:e}: p {:.10} dense {:.10}: error {err:.1e}, moved \
                     {moved:.1e}, {} iterations, residual {:.1e}",
                    x.p, pd, x.iterations, x.residual
                );
                assert!(err <= 1e-10, "error {err:e}");
                assert!(moved >= 1e3 * err.max(1e-14), "moved {moved:e}");
                assert!(mac(&x.u, &ud) >= 1.0 - 1e-10);
                assert!(x.residual <= 1e-12, "residual {:e}", x.residual);
                (p, u) = (x.p, x.u);
            }
        }
    }
}
