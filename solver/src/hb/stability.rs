//! The stability of a periodic solution: Floquet multipliers from the monodromy matrix.
//!
//! # Why the monodromy and not Hill's method
//! Hill's method takes the eigenvalues of the HB Jacobian and keeps the 2n_x "physical" ones
//! among (2H+1)·n_x by a sorting criterion; it is cheap, but for a contact that opens and
//! closes (a kink in the force) its eigenvalues converge slowly in H and the sorting can pick
//! spurious ones (Krack & Gross 2019, §3.6). The band-limited model has few states (n_x, the
//! kept roots), so the monodromy is cheap and exact for the HB orbit: integrate the
//! variational equation δẋ = A_lin(t) δx over one period along the orbit (A_lin of
//! [`super::hopf`] at the orbit's outputs z(t), a continuous, piecewise-smooth vector field: no
//! saltation matrix is needed for a kink), Φ' = A_lin Φ, Φ(0) = I, by classical RK4; the
//! multipliers are the eigenvalues of Φ(T). One of them is 1 (the phase shift along the
//! orbit): its distance from 1 measures the orbit's and the integration's accuracy. The orbit
//! is stable when every other multiplier lies inside the unit circle.

use super::fourier;
use super::problem::Hb;
use crate::bsql::FrictionForces;
use crate::{Real, SolverError};
use faer::linalg::solvers::Solve;
use faer::Mat;
use serde::{Deserialize, Serialize};

/// Floquet multipliers of a periodic solution.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Floquet {
    /// Largest |ρ| among the multipliers other than the trivial one.
    pub max_multiplier: Real,
    /// |ρ − 1| of the trivial multiplier (the one nearest 1): the accuracy check.
    pub trivial_error: Real,
    /// Every other multiplier |ρ| < 1 + `trivial_error` (the check's size).
    pub stable: bool,
    /// RK4 steps over the period.
    pub steps: usize,
}

/// A_lin at the outputs z.
fn a_lin<F: FrictionForces>(
    hb: &mut Hb<'_, F>,
    z: &[Real],
    a0: &Mat<Real>,
    b_r: &Mat<Real>,
    d_r: &Mat<Real>,
    c_z: &Mat<Real>,
) -> Result<Mat<Real>, SolverError> {
    let t = hb.t;
    let (_, jr) = hb.sys.evaluate(t, z, true)?;
    let jr = jr.expect("asked for the Jacobian");
    let n_z = z.len();
    let mut s = -(d_r * &jr);
    for i in 0..n_z {
        s[(i, i)] += 1.0;
    }
    let mut dzdx = c_z.clone();
    s.partial_piv_lu().solve_in_place(&mut dzdx);
    Ok(a0 + b_r * (&jr * &dzdx))
}

/// The Floquet multipliers of the HB solution `u` = [Z; ω; s] by RK4 with `steps` steps.
pub(crate) fn floquet<F: FrictionForces>(
    hb: &mut Hb<'_, F>,
    u: &[Real],
    steps: usize,
) -> Result<Floquet, SolverError> {
    let m = hb.m();
    let n_z = hb.n_z;
    let nzm = n_z * m;
    let (zc, w, s) = (&u[..nzm], u[nzm], u[nzm + 1]);
    hb.sys.set_friction_scale(s);
    let n_x = hb.sys.n_states();
    let n_p = hb.n_p;
    let o = hb.o;
    let (c_z, d_z) = hb.sys.output_maps();
    let (c_z, d_r) = (c_z.clone(), d_z.subcols(o, n_p).to_owned());
    let b_r = hb.sys.model().B_x.subcols(o, n_p).to_owned();
    let mut a0 = Mat::zeros(n_x, n_x);
    for j in 0..n_x {
        let mut e = vec![0.0; n_x];
        e[j] = 1.0;
        let mut out = vec![0.0; n_x];
        hb.sys.model().add_linear(&e, &mut out);
        for i in 0..n_x {
            a0[(i, j)] = out[i];
        }
    }
    let period = 2.0 * std::f64::consts::PI / w;
    let h = period / steps as Real;
    let z_at = |tau: Real| -> Vec<Real> {
        (0..n_z)
            .map(|a| fourier::evaluate(&zc[a * m..(a + 1) * m], w * tau))
            .collect()
    };
    let mut phi = Mat::<Real>::identity(n_x, n_x);
    let mut a_start = a_lin(hb, &z_at(0.0), &a0, &b_r, &d_r, &c_z)?;
    for k in 0..steps {
        let t0 = k as Real * h;
        let a_mid = a_lin(hb, &z_at(t0 + 0.5 * h), &a0, &b_r, &d_r, &c_z)?;
        let a_end = a_lin(hb, &z_at(t0 + h), &a0, &b_r, &d_r, &c_z)?;
        let k1 = &a_start * &phi;
        let k2 = &a_mid * (&phi + &k1 * faer::Scale(0.5 * h));
        let k3 = &a_mid * (&phi + &k2 * faer::Scale(0.5 * h));
        let k4 = &a_end * (&phi + &k3 * faer::Scale(h));
        phi += (k1 + k2 * faer::Scale(2.0) + k3 * faer::Scale(2.0) + k4) * faer::Scale(h / 6.0);
        a_start = a_end;
    }
    let ev = phi.eigenvalues().map_err(|_| SolverError::Callback {
        t: Real::NAN,
        message: "eigenvalues of the monodromy matrix".into(),
    })?;
    let triv = (0..ev.len())
        .min_by(|&a, &b| {
            let da = (ev[a] - faer::c64::new(1.0, 0.0)).norm();
            let db = (ev[b] - faer::c64::new(1.0, 0.0)).norm();
            da.total_cmp(&db)
        })
        .unwrap_or(0);
    let trivial_error = ev
        .get(triv)
        .map_or(Real::NAN, |r| (r - faer::c64::new(1.0, 0.0)).norm());
    let max_multiplier = ev
        .iter()
        .enumerate()
        .filter(|(i, _)| *i != triv)
        .map(|(_, r)| r.norm())
        .fold(0.0, Real::max);
    Ok(Floquet {
        max_multiplier,
        trivial_error,
        stable: max_multiplier < 1.0 + trivial_error.max(1e-9),
        steps,
    })
}
