//! Shared models for the solver verification tests.
#![allow(dead_code)]

pub mod hoffmann;
pub mod hoffmann_gap;
pub mod random;

use faer::Mat;
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, DaeSystem, InitialConditionOptions,
};
use squeal_solver::bsql::{
    steady_state, BsqlOptions, BsqlSystem, FrictionForces, LoadHistory, SteadyOptions,
};
use squeal_solver::{Real, SolverError};

/// Undamped oscillator x' = v, v' = −ω² x as F(t, y, y') = [x' − v, v' + ω² x].
pub struct Oscillator {
    pub omega: Real,
    lu: [[Real; 2]; 2],
}

impl Oscillator {
    pub fn new(omega: Real) -> Self {
        Self {
            omega,
            lu: [[0.0; 2]; 2],
        }
    }
}

impl DaeSystem for Oscillator {
    fn len(&self) -> usize {
        2
    }
    fn residual(
        &mut self,
        _t: Real,
        y: &[Real],
        yp: &[Real],
        res: &mut [Real],
    ) -> Result<(), SolverError> {
        res[0] = yp[0] - y[1];
        res[1] = yp[1] + self.omega * self.omega * y[0];
        Ok(())
    }
    fn setup_jacobian(
        &mut self,
        _t: Real,
        _y: &[Real],
        _yp: &[Real],
        cj: Real,
    ) -> Result<(), SolverError> {
        // J = [[cj, −1], [ω², cj]]
        self.lu = [[cj, -1.0], [self.omega * self.omega, cj]];
        Ok(())
    }
    fn solve_jacobian(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        let [[a, bb], [c, d]] = self.lu;
        let det = a * d - bb * c;
        let x0 = (d * b[0] - bb * b[1]) / det;
        let x1 = (a * b[1] - c * b[0]) / det;
        b[0] = x0;
        b[1] = x1;
        Ok(())
    }
}

/// Falling friction law of the belt test: on DOF 0, F = (μ0 − a·v_rel)·λ'_0 with
/// v_rel = V_belt − v_0 (the belt drags the mass in +x while v_rel > 0).
pub struct BeltFriction {
    pub mu0: Real,
    pub a: Real,
    pub v_belt: Real,
}

impl FrictionForces for BeltFriction {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        let v_rel = self.v_belt - v[0];
        f[0] += (self.mu0 - self.a * v_rel) * lambda_dot[0];
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
        let v_rel = self.v_belt - v[0];
        d_dlam[(0, 0)] += self.mu0 - self.a * v_rel;
        if let Some(d) = d_dv {
            d[(0, 0)] += self.a * lambda_dot[0];
        }
        Ok(())
    }
}

/// Parameters of the 2-DOF belt model: DOF 0 tangential (m, c, k), DOF 1 normal (m_z, k_z),
/// pressed on the belt by N; one constraint G = [0, 1] keeps the normal DOF on the belt.
pub struct Belt {
    pub m: Real,
    pub k: Real,
    pub c: Real,
    pub n_load: Real,
    pub mu0: Real,
    pub a: Real,
    pub v_belt: Real,
}

impl Belt {
    /// Linearised growth rate σ = −(c − N·a)/(2m) of m x'' + (c − N a) x' + k x = const.
    pub fn sigma(&self) -> Real {
        -(self.c - self.n_load * self.a) / (2.0 * self.m)
    }

    pub fn system(&self, opts: BsqlOptions) -> BsqlSystem<BeltFriction> {
        let (m_z, k_z) = (2.0, 50.0);
        let mut mm = Mat::zeros(2, 2);
        mm[(0, 0)] = self.m;
        mm[(1, 1)] = m_z;
        let mut bb = Mat::zeros(2, 2);
        bb[(0, 0)] = self.c;
        let mut kk = Mat::zeros(2, 2);
        kk[(0, 0)] = self.k;
        kk[(1, 1)] = k_z;
        let mut g = Mat::zeros(1, 2);
        g[(0, 1)] = 1.0;
        let load = LoadHistory {
            p_pre: vec![0.0, self.n_load],
            ..Default::default()
        };
        let fr = BeltFriction {
            mu0: self.mu0,
            a: self.a,
            v_belt: self.v_belt,
        };
        BsqlSystem::new(mm, bb, kk, g, load, fr, opts).expect("valid belt system")
    }
}

/// Least-squares slope of ys against xs.
pub fn slope(xs: &[Real], ys: &[Real]) -> Real {
    let n = xs.len() as Real;
    let mx = xs.iter().sum::<Real>() / n;
    let my = ys.iter().sum::<Real>() / n;
    let sxy: Real = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: Real = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

/// Local maxima of a uniformly sampled signal, refined by a parabola through 3 samples:
/// returns (time, value) pairs.
pub fn peaks(t: &[Real], x: &[Real]) -> Vec<(Real, Real)> {
    let mut out = Vec::new();
    for i in 1..x.len() - 1 {
        if x[i] > x[i - 1] && x[i] >= x[i + 1] && x[i] > 0.0 {
            let (a, b, c) = (x[i - 1], x[i], x[i + 1]);
            let den = a - 2.0 * b + c;
            let d = if den != 0.0 { 0.5 * (a - c) / den } else { 0.0 };
            let dt = t[i + 1] - t[i];
            out.push((t[i] + d * dt, b - 0.25 * (a - c) * d));
        }
    }
    out
}

/// Steady state, a kick of 0.05 on DOF 0's velocity, consistent y'; then BDF (RTOL/ATOL
/// 1e-7/1e-9 on both parts) to `tf`. Returns (final y, steps, Newton iterations): the run the
/// factorisation-path tests (modal elimination, component blocks) compare.
pub fn kicked_run<F: FrictionForces>(sys: &mut BsqlSystem<F>, tf: Real) -> (Vec<Real>, u64, u64) {
    let ss = steady_state(sys, 0.0, &SteadyOptions::default()).unwrap();
    let (mut y0, mut yp0) = ss.initial_values();
    y0[0] = 0.05;
    consistent_initial_conditions(
        sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let opts = BdfOptions {
        tolerances: sys.tolerances(1e-7, 1e-9, 1e-7, 1e-9),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    assert!(bdf.integrate_to(sys, tf).unwrap().is_success());
    let st = bdf.stats();
    (bdf.y().to_vec(), st.steps, st.newton_iterations)
}

/// max |a − b| / max |b|.
pub fn max_rel_diff(a: &[Real], b: &[Real]) -> Real {
    let scale = b.iter().fold(0.0 as Real, |m, x| m.max(x.abs()));
    a.iter()
        .zip(b)
        .fold(0.0 as Real, |m, (x, y)| m.max((x - y).abs()))
        / scale
}
