//! The linearisation of the band-limited model at its equilibrium for a friction scale s, and
//! the Hopf point of an unstable root: where, lowering s from the operating point, the root
//! crosses the imaginary axis.
//!
//! # Derivation
//! At the equilibrium (x*, z*) of friction scale s, perturbations obey δẋ = A δx + B_r J_r δz
//! and δz = C δx + D_r J_r δz (J_r = ∂r/∂z at z*, B_r, D_r the contact inputs' columns), so
//! ```text
//! δẋ = A_lin(s) δx,   A_lin(s) = A + B_r J_r (I − D_r J_r)⁻¹ C,   δz = (I − D_r J_r)⁻¹ C δx.
//! ```
//! At s = 1 and the reference state J_r = 0 and A_lin = A: the kept roots. A root followed
//! from s = 1 downwards (nearest eigenvalue of the next A_lin) that crosses Re λ = 0 at s_H is
//! a Hopf point, located by bisection; its eigenvector gives the first harmonic of a small
//! limit cycle (the start of the branch).

use crate::bsql::FrictionForces;
use crate::cea::Cplx;
use crate::condense::BandSystem;
use crate::{Real, SolverError};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};

/// The linearisation at one friction scale.
pub(crate) struct Linearised {
    /// A_lin (n_x × n_x).
    pub a: Mat<Real>,
    /// The equilibrium's outputs z*.
    pub z: Vec<Real>,
    /// δz/δx = (I − D_r J_r)⁻¹ C (n_z × n_x).
    pub dzdx: Mat<Real>,
}

/// A located Hopf point.
#[derive(Debug, Clone)]
pub(crate) struct HopfPoint {
    /// Friction scale s_H.
    pub s: Real,
    /// The crossing root (Re ≈ 0, Im > 0).
    pub root: Cplx,
    /// The first harmonic of the outputs, Ẑ_1 = (δz/δx) φ (unscaled, n_z).
    pub z1: Vec<c64>,
    /// The equilibrium's outputs there.
    pub z: Vec<Real>,
}

/// The linearisation at friction scale `s`, evaluated at time `t` (after the load ramp).
pub(crate) fn linearise<F: FrictionForces>(
    sys: &mut BandSystem<F>,
    t: Real,
    s: Real,
) -> Result<Linearised, SolverError> {
    sys.set_friction_scale(s);
    let (y, _) = sys.initial_values(t, t)?;
    let n_x = sys.n_states();
    let z = y[n_x..].to_vec();
    let n_z = z.len();
    let n_p = sys.n_patterns();
    let o = sys.model().inputs.first_contact();
    let (c_z, d_z) = sys.output_maps();
    let (c_z, d_z) = (c_z.clone(), d_z.clone());
    let b_r = sys.model().B_x.subcols(o, n_p).to_owned();
    let (_, jr) = sys.evaluate(t, &z, true)?;
    let jr = jr.expect("asked for the Jacobian");
    let d_r = d_z.subcols(o, n_p).to_owned();
    let mut s_mat = -(&d_r * &jr);
    for i in 0..n_z {
        s_mat[(i, i)] += 1.0;
    }
    let mut dzdx = c_z.clone();
    s_mat.partial_piv_lu().solve_in_place(&mut dzdx);
    let mut a = Mat::zeros(n_x, n_x);
    for j in 0..n_x {
        let mut e = vec![0.0; n_x];
        e[j] = 1.0;
        let mut out = vec![0.0; n_x];
        sys.model().add_linear(&e, &mut out);
        for i in 0..n_x {
            a[(i, j)] = out[i];
        }
    }
    a += &b_r * (&jr * &dzdx);
    Ok(Linearised { a, z, dzdx })
}

fn eig(a: &Mat<Real>) -> Result<(Vec<Cplx>, Mat<c64>), SolverError> {
    let e = a.eigen().map_err(|_| SolverError::Callback {
        t: Real::NAN,
        message: format!(
            "eigendecomposition of the {}x{} linearised model",
            a.nrows(),
            a.nrows()
        ),
    })?;
    let s = e.S();
    let vals = (0..a.nrows())
        .map(|i| Cplx::new(s.column_vector()[i].re, s.column_vector()[i].im))
        .collect();
    Ok((vals, e.U().to_owned()))
}

fn nearest(vals: &[Cplx], p: Cplx) -> usize {
    (0..vals.len())
        .min_by(|&a, &b| (vals[a] - p).norm().total_cmp(&(vals[b] - p).norm()))
        .unwrap_or(0)
}

/// Follows the kept root `root` (Im > 0, unstable at s = `s_from`) down in s in steps `ds`
/// to `s_min`; returns the Hopf point, or None when it stays unstable down to `s_min`.
pub(crate) fn find_hopf<F: FrictionForces>(
    sys: &mut BandSystem<F>,
    t: Real,
    root: Cplx,
    s_from: Real,
    s_min: Real,
    ds: Real,
) -> Result<Option<HopfPoint>, SolverError> {
    let track = |sys: &mut BandSystem<F>,
                 s: Real,
                 prev: Cplx|
     -> Result<(Cplx, Linearised, Mat<c64>, usize), SolverError> {
        let lin = linearise(sys, t, s)?;
        let (vals, vecs) = eig(&lin.a)?;
        // The member of the pair with Im > 0.
        let target = Cplx::new(prev.re, prev.im.abs());
        let j = nearest(&vals, target);
        Ok((vals[j], lin, vecs, j))
    };
    let (mut p_hi, _, _, _) = track(sys, s_from, root)?;
    let mut s_hi = s_from;
    if p_hi.re <= 0.0 {
        return Ok(None);
    }
    let mut s = s_from;
    let (s_lo, mut p_lo) = loop {
        s = (s - ds).max(s_min);
        let (p, _, _, _) = track(sys, s, p_hi)?;
        if p.re <= 0.0 {
            break (s, p);
        }
        p_hi = p;
        s_hi = s;
        if s <= s_min {
            return Ok(None);
        }
    };
    let mut s_lo = s_lo;
    for _ in 0..60 {
        let mid = 0.5 * (s_lo + s_hi);
        let (p, _, _, _) = track(sys, mid, 0.5 * (p_lo + p_hi))?;
        if p.re > 0.0 {
            s_hi = mid;
            p_hi = p;
        } else {
            s_lo = mid;
            p_lo = p;
        }
        if s_hi - s_lo <= 1e-12 * s_hi.abs().max(1.0) {
            break;
        }
    }
    let s_h = 0.5 * (s_lo + s_hi);
    let (p, lin, vecs, j) = track(sys, s_h, 0.5 * (p_lo + p_hi))?;
    let p = if p.im < 0.0 { p.conj() } else { p };
    let phi: Vec<c64> = (0..vecs.nrows())
        .map(|i| {
            let v = vecs[(i, j)];
            if vecs.nrows() > 0 && p.im >= 0.0 {
                v
            } else {
                v.conj()
            }
        })
        .collect();
    let z1: Vec<c64> = (0..lin.dzdx.nrows())
        .map(|i| {
            (0..lin.dzdx.ncols())
                .map(|k| phi[k] * lin.dzdx[(i, k)])
                .sum()
        })
        .collect();
    Ok(Some(HopfPoint {
        s: s_h,
        root: p,
        z1,
        z: lin.z,
    }))
}

/// The roots of the band-limited model linearised at its own equilibrium at time `t` (after
/// the load ramp) with the friction scaled by `s`: A_lin(s)'s eigenvalues, both of each pair
/// (see the module's derivation). At s = 1 these are the model's CEA roots, found through its
/// equilibrium and outputs rather than read from the condensation; the friction scale is
/// restored on return.
///
/// # Errors
/// The equilibrium's Newton or a callback failing; the eigendecomposition failing.
pub fn linearised_roots<F: FrictionForces>(
    sys: &mut BandSystem<F>,
    t: Real,
    s: Real,
) -> Result<Vec<Cplx>, SolverError> {
    let before = sys.friction_scale();
    let l = linearise(sys, t, s);
    sys.set_friction_scale(before);
    Ok(eig(&l?.a)?.0)
}
