//! Hoffmann's mode-coupling model with one unilateral gap, on the solver alone (the pipeline's
//! `pipeline/tests/separation.rs` runs the same model through the contact crate's `GapSet`).
//!
//! Hoffmann, Fischer, Gaul & Wagner, Mech. Res. Commun. 29 (2002) 197–205: DOF 0 pad x,
//! DOF 1 pad z, DOF 2 a rotor point z of mass m_r on the normal spring k3 with a damper c_r
//! (m_r = 0.05 so that the free rotor point is integrable after separation); one gap
//! (normal +z, area 1, preload P0), the rotor sliding at 1 along x, constant μ with the
//! contact crate's arctangent regularisation (VTOL 1e-3). G = [0, −1, 1] (G u = u_r − u_p
//! grows as the gap opens); the pad is dragged along +x by μ p_n.
#![allow(dead_code)]

use faer::Mat;
use squeal_solver::bdf::consistent_initial_conditions;
use squeal_solver::bsql::{steady_state, BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
use squeal_solver::{Real, SolverError};

pub const K11: Real = 1.0;
pub const K12: Real = 0.3;
pub const K21: Real = 0.3;
pub const K22: Real = 1.2;
pub const K3: Real = 1.0;
pub const M_R: Real = 0.05;
pub const C_R: Real = 0.05;
pub const C_PAD: Real = 0.02;
pub const P0: Real = 0.2;
pub const MU: Real = 0.6;
pub const VTOL: Real = 1e-3;
/// atan(10): the regularisation's value at the end of its zone (squeal-contact).
const ATAN_10: Real = 1.471_127_674_303_734_7;

/// The pad's friction: F_x = μ A p_n r(|V_t|) sign(V_t), V_t = 1 − v_0, p_n = P0 − λ'.
pub struct HoffmannFriction {
    pub mu: Real,
}

impl HoffmannFriction {
    /// (r(s) sign w, d(r sign)/dw) at w = 1 − v_0 (r as squeal-contact's eq. (5)).
    fn dir(w: Real) -> (Real, Real) {
        let s = w.abs();
        if s >= 10.0 * VTOL {
            (w.signum(), 0.0)
        } else {
            let x = s / VTOL;
            (
                x.atan() / ATAN_10 * w.signum(),
                1.0 / (VTOL * ATAN_10 * (1.0 + x * x)),
            )
        }
    }
}

impl FrictionForces for HoffmannFriction {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        let p_n = P0 - lambda_dot[0];
        f[0] += self.mu * p_n * Self::dir(1.0 - v[0]).0;
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        let (r, dr) = Self::dir(1.0 - v[0]);
        d_dlam[(0, 0)] += -self.mu * r;
        if let Some(c) = d_dv {
            c[(0, 0)] += -self.mu * (P0 - lambda_dot[0]) * dr;
        }
        Ok(())
    }
    fn near_stick(&mut self, _t: Real, v: &[Real], _lambda_dot: &[Real]) -> bool {
        (1.0 - v[0]).abs() < 30.0 * VTOL
    }
}

/// The system; `normal_stiffness` Some(k_n) makes the gap compliant (c = 1/k_n, area 1).
#[allow(non_snake_case)]
pub fn hoffmann_system(normal_stiffness: Option<Real>) -> BsqlSystem<HoffmannFriction> {
    let k = [[K11, K12, 0.0], [K21, K22 - K3, 0.0], [0.0, 0.0, K3]];
    let M = Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, M_R][i] } else { 0.0 });
    let B = Mat::from_fn(
        3,
        3,
        |i, j| if i == j { [C_PAD, C_PAD, C_R][i] } else { 0.0 },
    );
    let K = Mat::from_fn(3, 3, |i, j| k[i][j]);
    let G = Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 1.0][j]);
    let mut sys = BsqlSystem::new(
        M,
        B,
        K,
        G,
        LoadHistory::default(),
        HoffmannFriction { mu: MU },
        BsqlOptions::default(),
    )
    .unwrap();
    if let Some(kn) = normal_stiffness {
        sys.set_compliance(vec![1.0 / kn]).unwrap();
    }
    sys
}

/// The steady sliding state with the pad's normal velocity and the rotor point's kicked by
/// 1e-3 (λ = 0), made consistent.
pub fn hoffmann_start(sys: &mut BsqlSystem<HoffmannFriction>) -> (Vec<Real>, Vec<Real>) {
    let st = steady_state(sys, 0.0, &Default::default()).unwrap();
    let mut y = sys.join(&[0.0, 1e-3, 1e-3], &[0.0], &st.u);
    let mut yp = vec![0.0; y.len()];
    consistent_initial_conditions(sys, 0.0, &mut y, &mut yp, None, &Default::default()).unwrap();
    (y, yp)
}
