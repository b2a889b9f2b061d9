//! Hoffmann's mode-coupling model (Hoffmann, Fischer, Allgaier & Gaul, Mech. Res. Commun. 29 (2002)
//! 197–205) with a point friction law, and an independent explicit integration of it on a
//! compliant unilateral contact.

use faer::Mat;
use squeal_solver::bsql::{FrictionForces, LoadHistory};
use squeal_solver::{Real, SolverError};

/// Friction on a point contact: DOF 0 the pad's tangential DOF, the rotor sliding at V;
/// F_0 = μ (P0 A − λ'_0) w/√(w² + ε²), w = V − v_0 (squeal's convention: λ' tensile, p_n =
/// P0 − λ'/A), a smooth saturation of the sliding direction like the arctangent of eq. (5).
#[derive(Clone)]
pub struct PointFriction {
    pub mu: Real,
    pub p0a: Real,
    pub v: Real,
    pub eps: Real,
}

impl PointFriction {
    pub fn reg(&self, w: Real) -> (Real, Real) {
        let d = (w * w + self.eps * self.eps).sqrt();
        (w / d, self.eps * self.eps / (d * d * d))
    }
}

impl FrictionForces for PointFriction {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lam: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        let (r, _) = self.reg(self.v - v[0]);
        f[0] += self.mu * (self.p0a - lam[0]) * r;
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _t: Real,
        v: &[Real],
        lam: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        let (r, dr) = self.reg(self.v - v[0]);
        d_dlam[(0, 0)] += -self.mu * r;
        if let Some(d) = d_dv {
            d[(0, 0)] += -self.mu * (self.p0a - lam[0]) * dr;
        }
        Ok(())
    }
}

/// Hoffmann et al.'s model (Mech. Res. Commun. 29, 2002) as `pipeline/tests/separation.rs`
/// builds it: DOF 0 pad x, DOF 1 pad z, DOF 2 a rotor point z (mass 0.05, spring 1, damper
/// 0.05); one gap G = u_2 − u_1; μ = 0.6 above the critical μ.
#[allow(non_snake_case)]
pub fn hoffmann() -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>, PointFriction) {
    let k = [[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]];
    let M = Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, 0.05][i] } else { 0.0 });
    let B = Mat::from_fn(
        3,
        3,
        |i, j| if i == j { [0.02, 0.02, 0.05][i] } else { 0.0 },
    );
    let K = Mat::from_fn(3, 3, |i, j| k[i][j]);
    let G = Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 1.0][j]);
    let fr = PointFriction {
        mu: 0.6,
        p0a: 0.2,
        v: 1.0,
        eps: 0.3,
    };
    (M, B, K, G, fr)
}

/// Hoffmann's model on a compliant, unilateral contact, integrated independently: the explicit
/// ODE M ü + B u̇ + K u = F_f − Gᵀ λ', λ' = min(G u/c, P0 A), by classical RK4 with a fixed
/// step. Returns the peak and the RMS of |v_rotor,z| and the frequency of the pad's x
/// velocity over [0.75 T, T].
#[allow(non_snake_case)]
pub fn hoffmann_rk4(
    c: Real,
    u0: &[Real],
    load: &LoadHistory,
    t_end: Real,
    h: Real,
) -> (Real, Real, Real) {
    let (M, B, K, G, mut fr) = hoffmann();
    let rhs = |t: Real, y: &[Real; 6], fr: &mut PointFriction| -> [Real; 6] {
        let (u, v) = (&y[..3], &y[3..]);
        let q: Real = (0..3).map(|j| G[(0, j)] * u[j]).sum::<Real>() / c;
        let lam = q.min(fr.p0a);
        let mut f = [0.0; 3];
        fr.add_forces(t, v, &[lam], &mut f).unwrap();
        load.add_to(t, 1.0, &mut f);
        let mut out = [0.0; 6];
        for i in 0..3 {
            let mut fi = f[i] - G[(0, i)] * lam;
            for j in 0..3 {
                fi -= B[(i, j)] * v[j] + K[(i, j)] * u[j];
            }
            out[i] = v[i];
            out[3 + i] = fi / M[(i, i)];
        }
        out
    };
    let mut y = [u0[0], u0[1], u0[2], 0.0, 0.0, 0.0];
    let steps = (t_end / h).round() as usize;
    let (mut peak, mut ups, mut prev) = (0.0f64, Vec::new(), 0.0);
    let (mut sq, mut count) = (0.0, 0usize);
    let add = |y: &[Real; 6], k: &[Real; 6], a: Real| -> [Real; 6] {
        std::array::from_fn(|i| y[i] + a * k[i])
    };
    for s in 0..steps {
        let t = s as Real * h;
        let k1 = rhs(t, &y, &mut fr);
        let k2 = rhs(t + 0.5 * h, &add(&y, &k1, 0.5 * h), &mut fr);
        let k3 = rhs(t + 0.5 * h, &add(&y, &k2, 0.5 * h), &mut fr);
        let k4 = rhs(t + h, &add(&y, &k3, h), &mut fr);
        for i in 0..6 {
            y[i] += h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]);
        }
        let tn = t + h;
        if tn > 0.75 * t_end {
            peak = peak.max(y[5].abs());
            sq += y[5] * y[5];
            count += 1;
            if prev < 0.0 && y[3] >= 0.0 {
                ups.push(tn - h * y[3] / (y[3] - prev));
            }
        }
        prev = y[3];
    }
    (
        peak,
        (sq / count as Real).sqrt(),
        (ups.len() - 1) as Real / (ups[ups.len() - 1] - ups[0]),
    )
}

/// Hoffmann's model on a compliant (c = 1/(k_n A)), optionally unilateral contact, loaded by
/// `load`: its band system with every root kept, about the steady state under P0 (t = −1),
/// and that state's displacements. With `relative`, the gap's relative coordinates are the
/// contact's inputs and outputs: force patterns [e_0, Gᵀ] (the friction on the pad's x, the
/// normal pair) and velocity rows [−e_0ᵀ, e_2ᵀ] (the relative tangential velocity, the rotor
/// point's normal velocity); else a unit force and the velocity at each DOF.
#[allow(non_snake_case)]
pub fn compliant_band(
    c: Real,
    unilateral: bool,
    relative: bool,
    load: &LoadHistory,
) -> (
    squeal_solver::condense::BandSystem<PointFriction>,
    Vec<Real>,
) {
    use squeal_solver::bsql::{compliant_cea, steady_state, BsqlOptions, BsqlSystem};
    use squeal_solver::cea::CeaMatrices;
    use squeal_solver::condense::{
        BandContact, BandModel, BandOptions, BandReference, BandSystem, Inputs,
    };
    let (M, B, K, G, fr) = hoffmann();
    let mut full = BsqlSystem::new(
        M.clone(),
        B.clone(),
        K.clone(),
        G.clone(),
        load.clone(),
        fr.clone(),
        BsqlOptions::default(),
    )
    .unwrap();
    full.set_compliance(vec![c]).unwrap();
    let ss = steady_state(&mut full, -1.0, &Default::default()).unwrap();
    let mut d = Mat::zeros(3, 1);
    let mut cf = Mat::zeros(3, 3);
    fr.clone()
        .add_tangents(-1.0, &[0.0; 3], &ss.lambda_dot, &mut d, Some(&mut cf))
        .unwrap();
    let mut lin = CeaMatrices::new(M, K);
    lin.b = Some(B);
    lin.g = Some(G.clone());
    lin.d = Some(d);
    lin.c_f = Some(cf);
    let folded = compliant_cea(&lin, &[c]).unwrap();
    let mut inputs = Inputs::at_dofs(
        load.p_brake.clone(),
        vec![0, 1, 2],
        Mat::from_fn(1, 3, |_, j| G[(0, j)] / c),
    );
    if relative {
        inputs.patterns = Some(Mat::from_fn(3, 2, |i, j| match (i, j) {
            (0, 0) => 1.0,
            (_, 1) => G[(0, i)],
            _ => 0.0,
        }));
        inputs.velocity_rows = Some(Mat::from_fn(2, 3, |r, j| match (r, j) {
            (0, 0) => -1.0,
            (1, 2) => 1.0,
            _ => 0.0,
        }));
    }
    let model = BandModel::build(&folded, inputs, &BandOptions::default()).unwrap();
    let p0a = fr.p0a;
    let band = BandSystem::new(
        model,
        fr,
        load.clone(),
        BandReference {
            u: ss.u.clone(),
            lambda_dot: ss.lambda_dot.clone(),
            ramp: 0.0,
        },
        BandContact {
            g: G,
            compliance: vec![c],
            open_force: vec![unilateral.then_some(p0a)],
        },
    )
    .unwrap();
    (band, ss.u)
}
