//! Newton's method on the HB equations with a phase condition, and the pseudo-arclength
//! continuation of a limit-cycle branch from its Hopf point.
//!
//! # The equations
//! The unknowns u = [Z; ω; s] (the outputs' coefficients, the frequency, the friction scale)
//! satisfy the n_z(2H+1) HB equations ([`super::problem`]), a phase condition Z_s1[p] = 0
//! (an autonomous system's periodic solutions are defined up to a time shift: the first
//! harmonic of output p — the velocity output the Hopf eigenvector moves most — is made a
//! cosine) and one more:
//! - at the start, the amplitude Z_c1[p] = a (the branch leaves the trivial solution, where
//!   every ω solves the equations, so it is parametrised by its amplitude there);
//! - along the branch, the pseudo-arclength τ̂ᵀ(û − û_pred) = 0 (û the unknowns divided by
//!   their scales: the outputs' group scales, ω_H, 1), τ̂ the unit tangent (Keller; Krack &
//!   Gross 2019, §4.3), with the step adapted to the Newton iterations;
//! - at the end, s = the target.

#![allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.

use super::problem::Hb;
use super::{HbError, HbOptions};
use crate::bsql::FrictionForces;
use crate::Real;
use faer::linalg::solvers::Solve;
use faer::Mat;

/// The extra equation.
pub(crate) enum Extra<'a> {
    Amplitude(Real),
    Arclength {
        tangent: &'a [Real],
        pred: &'a [Real],
    },
    FixedS(Real),
}

/// Unknown scales and the phase output.
pub(crate) struct Frame {
    /// Scale of each unknown (Z entries: their output's group scale; ω: ω_H; s: 1).
    pub scale: Vec<Real>,
    /// Index in u of Z_c1[p] (Z_s1[p] is the next).
    pub p_c1: usize,
}

/// The residual of [R; phase; extra] at `u` (without the Jacobian): its scaled max-norm.
fn residual_norm<F: FrictionForces>(
    hb: &mut Hb<'_, F>,
    u: &[Real],
    extra: &Extra<'_>,
    frame: &Frame,
) -> Result<Real, HbError> {
    let n = u.len();
    let nzm = n - 2;
    let ev = hb.eval(u, false)?;
    let mut res = (0..nzm).fold(0.0f64, |m, i| m.max(ev.r[i].abs() / frame.scale[i]));
    res = res.max(u[frame.p_c1 + 1].abs() / frame.scale[frame.p_c1 + 1]);
    let e = match extra {
        Extra::Amplitude(a) => (u[frame.p_c1] - a) / frame.scale[frame.p_c1],
        Extra::Arclength { tangent, pred } => (0..n)
            .map(|j| tangent[j] * (u[j] - pred[j]) / frame.scale[j])
            .sum(),
        Extra::FixedS(s) => u[n - 1] - s,
    };
    Ok(res.max(e.abs()))
}

/// Newton on [R; phase; extra] = 0 from `u`, with backtracking (the step halved, up to four
/// times, while the scaled residual grows: a contact that opens makes the equations piecewise
/// smooth, and a full Newton step can then cycle about a kink); returns the iterations on
/// success.
pub(crate) fn newton<F: FrictionForces>(
    hb: &mut Hb<'_, F>,
    u: &mut [Real],
    extra: &Extra<'_>,
    frame: &Frame,
    opts: &HbOptions,
) -> Result<Option<usize>, HbError> {
    let n = u.len();
    let nzm = n - 2;
    for it in 0..=opts.max_newton {
        let ev = hb.eval(u, true)?;
        let jr = ev.jac.expect("asked for the Jacobian");
        let mut rhs = vec![0.0; n];
        rhs[..nzm].copy_from_slice(&ev.r);
        rhs[nzm] = u[frame.p_c1 + 1];
        let mut a = Mat::zeros(n, n);
        for j in 0..n {
            for i in 0..nzm {
                a[(i, j)] = jr[(i, j)];
            }
        }
        a[(nzm, frame.p_c1 + 1)] = 1.0;
        let extra_res = match extra {
            Extra::Amplitude(amp) => {
                a[(n - 1, frame.p_c1)] = 1.0;
                u[frame.p_c1] - amp
            }
            Extra::Arclength { tangent, pred } => {
                let mut g = 0.0;
                for j in 0..n {
                    let sc = frame.scale[j];
                    g += tangent[j] * (u[j] - pred[j]) / sc;
                    a[(n - 1, j)] = tangent[j] / sc;
                }
                g
            }
            Extra::FixedS(s) => {
                a[(n - 1, n - 1)] = 1.0;
                u[n - 1] - s
            }
        };
        rhs[n - 1] = extra_res;
        let res = (0..nzm)
            .fold(0.0f64, |m, i| m.max(ev.r[i].abs() / frame.scale[i]))
            .max(rhs[nzm].abs() / frame.scale[frame.p_c1 + 1]);
        let lu = a.partial_piv_lu();
        let mut dx = Mat::from_fn(n, 1, |i, _| rhs[i]);
        lu.solve_in_place(&mut dx);
        let mut step = 0.0f64;
        for j in 0..n {
            let d = dx[(j, 0)];
            if !d.is_finite() {
                return Ok(None);
            }
            step = step.max(d.abs() / frame.scale[j]);
        }
        if std::env::var_os("SQUEAL_HB_DEBUG").is_some() {
            eprintln!(
                "  newton it {it}: res {res:.3e} step {step:.3e} s {:.6} w {:.6}",
                u[n - 1],
                u[n - 2]
            );
        }
        if res <= opts.tol && step <= opts.tol.sqrt() {
            return Ok(Some(it));
        }
        if it == opts.max_newton {
            return Ok(None);
        }
        let res0 = res.max(extra_res.abs());
        let mut lambda = 1.0;
        let mut trial = u.to_vec();
        for _ in 0..5 {
            for j in 0..n {
                trial[j] = u[j] - lambda * dx[(j, 0)];
            }
            if !(trial[n - 2] > 0.0) {
                lambda *= 0.5;
                continue;
            }
            let r1 = residual_norm(hb, &trial, extra, frame)?;
            if r1 < res0 || lambda < 0.1 {
                break;
            }
            lambda *= 0.5;
        }
        if !(trial[n - 2] > 0.0) {
            return Ok(None);
        }
        u.copy_from_slice(&trial);
    }
    Ok(None)
}

/// The unit tangent (in scaled unknowns, returned unscaled·1/scale convention: τ̂) of the
/// branch at `u`, oriented along `prev`.
pub(crate) fn tangent<F: FrictionForces>(
    hb: &mut Hb<'_, F>,
    u: &[Real],
    prev: &[Real],
    frame: &Frame,
) -> Result<Vec<Real>, HbError> {
    let n = u.len();
    let nzm = n - 2;
    let ev = hb.eval(u, true)?;
    let jr = ev.jac.expect("asked for the Jacobian");
    let mut a = Mat::zeros(n, n);
    for j in 0..n {
        for i in 0..nzm {
            // Columns in scaled unknowns: ∂R/∂û_j = ∂R/∂u_j · scale_j.
            a[(i, j)] = jr[(i, j)] * frame.scale[j];
        }
        a[(n - 1, j)] = prev[j];
    }
    a[(nzm, frame.p_c1 + 1)] = frame.scale[frame.p_c1 + 1];
    let mut t = Mat::zeros(n, 1);
    t[(n - 1, 0)] = 1.0;
    a.partial_piv_lu().solve_in_place(&mut t);
    let norm = (0..n).map(|i| t[(i, 0)] * t[(i, 0)]).sum::<Real>().sqrt();
    let dot: Real = (0..n).map(|i| t[(i, 0)] * prev[i]).sum();
    let sign = if dot < 0.0 { -1.0 } else { 1.0 };
    Ok((0..n).map(|i| sign * t[(i, 0)] / norm).collect())
}
