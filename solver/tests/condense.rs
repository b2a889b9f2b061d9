//! The band-limited model (`squeal_solver::condense`): its transfer function against a direct
//! solve of the full linear operator, its kept roots against the exact CEA, its statics, its
//! linearisation, and its transient against the full BSQL transient.
//!
//! References: the direct complex solve of the bordered operator [s²M + sC + K, Gᵀ − D; G, 0]
//! (an independent computation of the same transfer function), the exact CEA
//! (`cea::complex_eigen`), and the full BSQL system integrated by the same BDF.

mod common;

use common::hoffmann::{compliant_band, hoffmann, hoffmann_rk4, PointFriction};
use common::random::{RandomConstrained, Rng};
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions};
use squeal_solver::bsql::{
    steady_state, BsqlOptions, BsqlSystem, FrictionForces, LoadHistory, SteadyOptions,
};
use squeal_solver::cea::{complex_eigen, CeaMatrices, CeaOptions, Cplx};
use squeal_solver::condense::{
    BandContact, BandError, BandModel, BandOptions, BandReference, BandSystem, Inputs,
};
use squeal_solver::{Real, SolverError};

/// The dense real A_x of a band model (from `add_linear` on unit vectors).
fn a_matrix(m: &BandModel) -> Mat<Real> {
    let n = m.n_states;
    let mut a = Mat::zeros(n, n);
    for j in 0..n {
        let mut e = vec![0.0; n];
        e[j] = 1.0;
        let mut out = vec![0.0; n];
        m.add_linear(&e, &mut out);
        for i in 0..n {
            a[(i, j)] = out[i];
        }
    }
    a
}

fn to_c(a: &Mat<Real>) -> Mat<c64> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| c64::new(a[(i, j)], 0.0))
}

/// The band model's responses (u, v, N) to the inputs at s: C (sI − A)⁻¹ B + D.
fn band_response(m: &BandModel, s: c64) -> (Mat<c64>, Mat<c64>, Mat<c64>) {
    let n = m.n_states;
    let a = a_matrix(m);
    let si_a = Mat::from_fn(n, n, |i, j| {
        (if i == j { s } else { c64::new(0.0, 0.0) }) - c64::new(a[(i, j)], 0.0)
    });
    let mut x = to_c(&m.B_x);
    si_a.partial_piv_lu().solve_in_place(&mut x);
    (
        &to_c(&m.C_u) * &x + to_c(&m.D_u),
        &to_c(&m.C_v) * &x + to_c(&m.D_v),
        &to_c(&m.C_N) * &x + to_c(&m.D_N),
    )
}

/// The full model's response (u, N) to forces F at s: [s²M + sC + K, Gᵀ − D; G, 0]⁻¹ [F; 0].
fn direct_response(sys: &CeaMatrices, f: &Mat<Real>, s: c64) -> (Mat<c64>, Mat<c64>) {
    let n = sys.m.nrows();
    let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
    let c = match (&sys.b, &sys.c_f) {
        (Some(b), Some(cf)) => b - cf,
        (Some(b), None) => b.clone(),
        (None, Some(cf)) => -cf,
        (None, None) => Mat::zeros(n, n),
    };
    let q = Mat::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
        (true, true) => s * s * sys.m[(i, j)] + s * c[(i, j)] + sys.k[(i, j)],
        (true, false) => {
            let g = sys.g.as_ref().unwrap()[(j - n, i)];
            c64::new(g - sys.d.as_ref().map_or(0.0, |d| d[(i, j - n)]), 0.0)
        }
        (false, true) => c64::new(sys.g.as_ref().unwrap()[(i - n, j)], 0.0),
        _ => c64::new(0.0, 0.0),
    });
    let mut x = Mat::from_fn(n + ng, f.ncols(), |i, j| {
        c64::new(if i < n { f[(i, j)] } else { 0.0 }, 0.0)
    });
    q.partial_piv_lu().solve_in_place(&mut x);
    (
        Mat::from_fn(n, f.ncols(), |i, j| x[(i, j)]),
        Mat::from_fn(ng, f.ncols(), |i, j| x[(n + i, j)]),
    )
}

fn rel(a: &Mat<c64>, b: &Mat<c64>) -> Real {
    let mut num = 0.0;
    let mut den = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            num += (a[(i, j)] - b[(i, j)]).norm_sqr();
            den += b[(i, j)].norm_sqr();
        }
    }
    (num / den).sqrt()
}

fn random_inputs(n: usize, seed: u64) -> Inputs {
    let mut rng = Rng(seed);
    Inputs::at_dofs(
        (0..n).map(|_| rng.next()).collect(),
        (0..n).collect(),
        Mat::zeros(0, n),
    )
}

/// With every root kept, the band-limited model is the full linear model: its transfer
/// functions from the load and the contact forces to the displacements, velocities and
/// multipliers equal a direct solve of the bordered operator at complex frequencies.
#[test]
fn every_root_kept_reproduces_the_transfer_function() {
    let n = 10;
    let mut sys = RandomConstrained::new(n, 2, 11).at(0.4);
    let mut rng = Rng(5);
    sys.c_f = Some(Mat::from_fn(n, n, |_, _| 0.02 * rng.next()));
    let inputs = random_inputs(n, 3);
    let f = inputs.matrix(n);
    let model = BandModel::build(&sys, inputs, &BandOptions::default()).unwrap();
    assert_eq!(model.stats.removed, 0);
    assert_eq!(model.n_states, 2 * (n - 2));
    println!("static check {:e}", model.stats.static_check);
    assert!(model.stats.static_check < 1e-10);
    for s in [
        c64::new(0.3, 2.1),
        c64::new(-1.0, 7.5),
        c64::new(0.0, 0.0),
        c64::new(2.0, -20.0),
    ] {
        let (u, v, nn) = band_response(&model, s);
        let (u_ref, n_ref) = direct_response(&sys, &f, s);
        let v_ref = Mat::from_fn(u_ref.nrows(), u_ref.ncols(), |i, j| u_ref[(i, j)] * s);
        let (eu, ev, en) = (rel(&u, &u_ref), rel(&v, &v_ref), rel(&nn, &n_ref));
        println!("s = {s}: u {eu:e}, v {ev:e}, N {en:e}");
        assert!(eu < 1e-9 && en < 1e-9, "s = {s}: u {eu:e}, N {en:e}");
        if s.norm() > 0.0 {
            assert!(ev < 1e-9, "s = {s}: v {ev:e}");
        }
    }
}

/// A cut-off keeps exactly the CEA's roots below it (the same numbers, not approximations),
/// keeps every static response exact, and removes the rest; the estimate bounds what the
/// removed roots do in the band, and a tolerance below it is refused.
#[test]
fn a_cut_off_keeps_the_cea_roots_and_the_statics() {
    let n = 16;
    let sys = RandomConstrained::new(n, 3, 21).at(0.5);
    let inputs = random_inputs(n, 4);
    let f = inputs.matrix(n);
    let cea = complex_eigen(&sys, &CeaOptions::default()).unwrap();
    let mut freqs: Vec<Real> = cea.modes.iter().map(|m| m.frequency_hz).collect();
    freqs.sort_by(Real::total_cmp);
    let cutoff = 0.5 * (freqs[6] + freqs[7]);
    let opts = BandOptions {
        cutoff_hz: cutoff,
        band_hz: Some(freqs[3]),
        tolerance: 1.0,
        ..Default::default()
    };
    let model = BandModel::build(&sys, inputs.clone(), &opts).unwrap();
    println!("{:#?}", model.stats);
    assert_eq!(model.stats.kept + model.stats.removed, cea.modes.len());
    for p in &model.roots {
        let best = cea
            .modes
            .iter()
            .map(|m| (m.eigenvalue - *p).norm() / p.norm())
            .fold(Real::INFINITY, Real::min);
        assert!(best < 1e-9, "kept root {p} not a CEA root ({best:e})");
        assert!(p.im / (2.0 * std::f64::consts::PI) <= cutoff);
    }
    // The removed unstable roots are the CEA's above the cut-off.
    let above = cea
        .modes
        .iter()
        .filter(|m| m.frequency_hz > cutoff && m.unstable)
        .count();
    assert_eq!(model.stats.removed_unstable, above);
    // Statics exact.
    let (u, _, nn) = band_response(&model, c64::new(0.0, 0.0));
    let (u_ref, n_ref) = direct_response(&sys, &f, c64::new(0.0, 0.0));
    assert!(rel(&u, &u_ref) < 1e-9 && rel(&nn, &n_ref) < 1e-9);
    // In the band the error is of the estimate's order; above the cut-off much larger.
    let w = 2.0 * std::f64::consts::PI * freqs[2];
    let (u_band, _, _) = band_response(&model, c64::new(0.0, w));
    let (u_full, _) = direct_response(&sys, &f, c64::new(0.0, w));
    let e_band = rel(&u_band, &u_full);
    println!(
        "error at {:.3} Hz: {e_band:e}; estimate {:e}",
        freqs[2], model.stats.error_estimate
    );
    assert!(model.stats.error_estimate > 0.0 && model.stats.error_estimate < 0.5);
    // A tolerance below the estimate is refused, with the numbers.
    let strict = BandOptions {
        tolerance: 0.5 * model.stats.error_estimate,
        ..opts
    };
    match BandModel::build(&sys, inputs, &strict) {
        Err(BandError::EstimateAboveTolerance { estimate, .. }) => {
            assert!((estimate - model.stats.error_estimate).abs() < 1e-12 * estimate)
        }
        other => panic!("expected the tolerance refusal, got {other:?}"),
    }
}

// ---------------------------------------------------------------------------------------
// Hoffmann's model through the band-limited transient.

/// The band system of Hoffmann's model about its steady state under P0 (no brake load in the
/// reference: ramp_ref = 0), every root kept unless `cutoff_hz`.
#[allow(non_snake_case)]
fn hoffmann_band(load: LoadHistory, cutoff_hz: Real) -> BandSystem<PointFriction> {
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
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let mut fr0 = fr.clone();
    let mut d = Mat::zeros(3, 1);
    let mut cf = Mat::zeros(3, 3);
    fr0.add_tangents(-1.0, &[0.0; 3], &ss.lambda_dot, &mut d, Some(&mut cf))
        .unwrap();
    let mut sys = CeaMatrices::new(M, K);
    sys.b = Some(B);
    sys.g = Some(G.clone());
    sys.d = Some(d);
    sys.c_f = Some(cf);
    let inputs = Inputs::at_dofs(load.p_brake.clone(), vec![0, 1, 2], Mat::zeros(0, 3));
    let opts = BandOptions {
        cutoff_hz,
        ..Default::default()
    };
    let model = BandModel::build(&sys, inputs, &opts).unwrap();
    BandSystem::new(
        model,
        fr,
        load,
        BandReference {
            u: ss.u,
            lambda_dot: ss.lambda_dot,
            ramp: 0.0,
        },
        BandContact {
            g: G,
            compliance: vec![0.0],
            open_force: vec![None],
        },
    )
    .unwrap()
}

/// The linearisation of the band-limited DAE at its reference (finite differences of its
/// residual, the algebraic outputs eliminated) has exactly the CEA's roots.
#[test]
fn the_band_system_linearised_has_the_cea_roots() {
    let mut band = hoffmann_band(LoadHistory::default(), Real::INFINITY);
    let roots = band.model().roots.clone();
    let (y0, yp0) = band.initial_values(-1.0, -1.0).unwrap();
    let n = y0.len();
    let nx = band.n_states();
    use squeal_solver::bdf::DaeSystem;
    let mut r0 = vec![0.0; n];
    band.residual(-1.0, &y0, &yp0, &mut r0).unwrap();
    assert!(r0.iter().all(|r| r.abs() < 1e-12), "{r0:?}");
    // ∂F/∂y by central differences.
    let mut jac = Mat::zeros(n, n);
    for j in 0..n {
        let h = 1e-6 * (1.0 + y0[j].abs());
        let (mut yp, mut ym) = (y0.clone(), y0.clone());
        yp[j] += h;
        ym[j] -= h;
        let (mut rp, mut rm) = (vec![0.0; n], vec![0.0; n]);
        band.residual(-1.0, &yp, &yp0, &mut rp).unwrap();
        band.residual(-1.0, &ym, &yp0, &mut rm).unwrap();
        for i in 0..n {
            jac[(i, j)] = (rp[i] - rm[i]) / (2.0 * h);
        }
    }
    // x' = −(J_xx − J_xz J_zz⁻¹ J_zx) x.
    let jxx = jac.submatrix(0, 0, nx, nx).to_owned();
    let jxz = jac.submatrix(0, nx, nx, n - nx).to_owned();
    let jzx = jac.submatrix(nx, 0, n - nx, nx).to_owned();
    let jzz = jac.submatrix(nx, nx, n - nx, n - nx).to_owned();
    let mut t = jzx.clone();
    jzz.partial_piv_lu().solve_in_place(&mut t);
    let a = -(&jxx - &jxz * &t);
    let ev = a.eigenvalues().unwrap();
    for p in &roots {
        let best = ev
            .iter()
            .map(|e| (Cplx::new(e.re, e.im) - *p).norm())
            .fold(Real::INFINITY, Real::min);
        println!("root {p}: linearised {best:e}");
        assert!(best < 1e-6 * p.norm(), "root {p}: {best:e}");
    }
    assert!(
        roots.iter().any(|p| p.re > 0.0),
        "Hoffmann at μ = 0.6 is unstable"
    );
}

/// Hoffmann's model above its critical μ, excited by a load pulse, grows into the nonlinear
/// range of the friction law (the sliding direction saturating): the band-limited transient
/// with every root kept follows the full BSQL transient (the same BDF and tolerances).
#[test]
#[allow(non_snake_case)]
fn band_transient_follows_the_full_bsql_transient_into_the_nonlinear_range() {
    let load = LoadHistory {
        p_brake: vec![0.0, 0.05, 0.0],
        t_load: 1.0,
        ..Default::default()
    };
    let (M, B, K, G, fr) = hoffmann();
    let mut full = BsqlSystem::new(M, B, K, G, load.clone(), fr, BsqlOptions::default()).unwrap();
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let (mut y, mut yp) = ss.initial_values();
    consistent_initial_conditions(&mut full, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    let tol = (1e-9, 1e-11);
    let mut bdf_full = Bdf::new(
        BdfOptions {
            tolerances: full.tolerances(tol.0, tol.1, tol.0, 1e20),
            max_steps: 1_000_000,
            ..Default::default()
        },
        0.0,
        &y,
        &yp,
    )
    .unwrap();
    let mut band = hoffmann_band(load, Real::INFINITY);
    let (yb, ypb) = band.initial_values(-1.0, 0.0).unwrap();
    let mut bdf_band = Bdf::new(
        BdfOptions {
            tolerances: band.tolerances(tol.0, tol.1, tol.0, 1e20),
            max_steps: 1_000_000,
            ..Default::default()
        },
        0.0,
        &yb,
        &ypb,
    )
    .unwrap();
    let (mut u, mut v, mut l) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 1]);
    let mut worst: Real = 0.0;
    let mut vmax: Real = 0.0;
    let mut t = 0.0;
    while t < 60.0 {
        t += 0.5;
        assert!(bdf_full.integrate_to(&mut full, t).unwrap().is_success());
        assert!(bdf_band.integrate_to(&mut band, t).unwrap().is_success());
        let yf = bdf_full.y().to_vec();
        let (ypb, yb) = (bdf_band.yp().to_vec(), bdf_band.y().to_vec());
        band.physical(t, &yb, &ypb, &mut u, &mut v, &mut l, None)
            .unwrap();
        let (vf, uf) = (&yf[0..3], &yf[4..7]);
        vmax = vmax.max(vf[0].abs());
        for i in 0..3 {
            worst = worst.max((v[i] - vf[i]).abs()).max((u[i] - uf[i]).abs());
        }
    }
    println!(
        "largest |v_0| {vmax:.4}, largest difference {worst:e}; band {:?}, full steps {}",
        band.stats(),
        bdf_full.stats().steps
    );
    assert!(
        vmax > 0.4,
        "the response should reach the nonlinear range ({vmax})"
    );
    assert!(worst < 1e-5 * vmax, "band vs full: {worst:e}");
}

/// Hoffmann's model on a compliant, unilateral contact (k_n = 10 per unit area: p_n = P0 −
/// λ'/A with λ' = G u/c, and the gap open where p_n would turn tensile): above the critical μ
/// the flutter grows until the gap opens once per cycle and settles into a limit cycle (the
/// rotor point ringing while it is free). The band-limited transient (every root kept; the
/// contact law λ' = min(G u/c, P0 A) as a continuous nonlinearity, no event) reaches the
/// cycle of an independent explicit RK4 integration of the same equations (h = 2e-3, which
/// agrees with scipy's LSODA at rtol 1e-10 to 1e-8 on both numbers).
#[test]
#[allow(non_snake_case)]
fn compliant_unilateral_limit_cycle_matches_an_independent_integration() {
    let (M, B, K, G, fr) = hoffmann();
    let c = 0.1; // 1/(k_n A)
    let p0a = fr.p0a;
    // A small, slow load on the pad's x excites the flutter.
    let load = LoadHistory {
        p_brake: vec![0.02, 0.0, 0.0],
        t_load: 2.0,
        ..Default::default()
    };
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
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let mut d = Mat::zeros(3, 1);
    let mut cf = Mat::zeros(3, 3);
    fr.clone()
        .add_tangents(-1.0, &[0.0; 3], &ss.lambda_dot, &mut d, Some(&mut cf))
        .unwrap();
    let mut lin = CeaMatrices::new(M.clone(), K.clone());
    lin.b = Some(B.clone());
    lin.g = Some(G.clone());
    lin.d = Some(d);
    lin.c_f = Some(cf);
    let folded = squeal_solver::bsql::compliant_cea(&lin, &[c]).unwrap();
    let cea = complex_eigen(&folded, &CeaOptions::default()).unwrap();
    let grow = cea
        .modes
        .iter()
        .map(|m| m.real_part)
        .fold(Real::MIN, Real::max);
    assert!(grow > 0.0, "unstable steady state ({grow})");
    let inputs = Inputs::at_dofs(
        load.p_brake.clone(),
        vec![0, 1, 2],
        Mat::from_fn(1, 3, |_, j| G[(0, j)] / c),
    );
    let model = BandModel::build(&folded, inputs, &BandOptions::default()).unwrap();
    let mut band = BandSystem::new(
        model,
        fr.clone(),
        load.clone(),
        BandReference {
            u: ss.u.clone(),
            lambda_dot: ss.lambda_dot.clone(),
            ramp: 0.0,
        },
        BandContact {
            g: G.clone(),
            compliance: vec![c],
            open_force: vec![Some(p0a)],
        },
    )
    .unwrap();
    let (yb, ypb) = band.initial_values(-1.0, 0.0).unwrap();
    let mut bdf = Bdf::new(
        BdfOptions {
            tolerances: band.tolerances(1e-7, 1e-9, 1e-7, 1e20),
            max_steps: 10_000_000,
            ..Default::default()
        },
        0.0,
        &yb,
        &ypb,
    )
    .unwrap();
    let t_end = 300.0;
    let (mut peak, mut ups, mut prev) = (0.0f64, Vec::new(), (0.0, 0.0));
    let (mut u, mut v, mut l) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 1]);
    let (mut opened, mut was_open) = (0usize, false);
    let st = bdf
        .step_to(&mut band, t_end, |s, t, y, yp| {
            s.physical(t, y, yp, &mut u, &mut v, &mut l, None)?;
            let open = l[0] >= p0a;
            opened += usize::from(open && !was_open);
            was_open = open;
            if t > 0.75 * t_end {
                peak = peak.max(v[2].abs());
                if prev.1 < 0.0 && v[0] >= 0.0 {
                    ups.push(prev.0 + (t - prev.0) * (-prev.1) / (v[0] - prev.1));
                }
            }
            prev = (t, v[0]);
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    let fb = (ups.len() - 1) as Real / (ups[ups.len() - 1] - ups[0]);
    let (pr, _, fr_ref) = hoffmann_rk4(c, &ss.u, &load, t_end, 2e-3);
    println!(
        "openings {opened}; band: peak {peak:.6}, f {fb:.8} ({} steps, {:?}); RK4: peak {pr:.6}, f \
         {fr_ref:.8}",
        bdf.stats().steps,
        bdf.stats()
    );
    assert!(opened > 20, "the gap must open every cycle ({opened})");
    // Each opening and closing changes the row's branch (χ of J_r) within a Newton attempt:
    // the matrix is formed again there (semi-smooth Newton, `DaeSystem::matrix_stale`), and
    // no attempt fails. With the matrix of the attempt's start the run had a convergence
    // failure and 3 retries with a fresh matrix (written 2026-11-28).
    let stats = bdf.stats();
    assert!(stats.setups_branch > 0, "{stats:?}");
    assert_eq!(stats.convergence_failures, 0, "{stats:?}");
    assert!((peak - pr).abs() < 1e-3 * pr, "peak {peak} vs {pr}");
    assert!((fb - fr_ref).abs() < 1e-4 * fr_ref, "f {fb} vs {fr_ref}");
}

/// Friction at several point contacts: gap k drags DOF `dof[k]` with μ (P0A_k − λ'_k) w/√(w² +
/// ε²), w = V − v (as [`PointFriction`]).
#[derive(Clone)]
struct Points {
    dof: Vec<usize>,
    p0a: Vec<Real>,
    mu: Real,
    eps: Real,
}

impl FrictionForces for Points {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lam: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        for (k, &d) in self.dof.iter().enumerate() {
            let w = 1.0 - v[d];
            f[d] += self.mu * (self.p0a[k] - lam[k]) * w / (w * w + self.eps * self.eps).sqrt();
        }
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
        let e2 = self.eps * self.eps;
        let mut cf = d_dv;
        for (k, &d) in self.dof.iter().enumerate() {
            let w = 1.0 - v[d];
            let den = (w * w + e2).sqrt();
            d_dlam[(d, k)] += -self.mu * w / den;
            if let Some(c) = cf.as_deref_mut() {
                c[(d, d)] += -self.mu * (self.p0a[k] - lam[k]) * e2 / (den * den * den);
            }
        }
        Ok(())
    }
}

/// Two Hoffmann oscillators: the in-band one (DOFs 0–2, gap 0) and a copy 30 times faster
/// (K × 900, B × 30 × `damp`, P0A × 900; DOFs 3–5, gap 1) standing for the stiff interface
/// modes far above the band, coupled by a spring 0.05 between the pads' z (DOFs 1, 4).
#[allow(non_snake_case)]
fn two_speed(damp: Real) -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>, Points) {
    let (m, b, k, _, fr) = hoffmann();
    let s = 30.0;
    let mut M = Mat::zeros(6, 6);
    let mut B = Mat::zeros(6, 6);
    let mut K = Mat::zeros(6, 6);
    for i in 0..3 {
        for j in 0..3 {
            M[(i, j)] = m[(i, j)];
            B[(i, j)] = b[(i, j)];
            K[(i, j)] = k[(i, j)];
            M[(3 + i, 3 + j)] = m[(i, j)];
            B[(3 + i, 3 + j)] = s * damp * b[(i, j)];
            K[(3 + i, 3 + j)] = s * s * k[(i, j)];
        }
    }
    let kc = 0.05;
    K[(1, 1)] += kc;
    K[(4, 4)] += kc;
    K[(1, 4)] -= kc;
    K[(4, 1)] -= kc;
    let G = Mat::from_fn(2, 6, |r, j| match (r, j) {
        (0, 1) | (1, 4) => -1.0,
        (0, 2) | (1, 5) => 1.0,
        _ => 0.0,
    });
    let pts = Points {
        dof: vec![0, 3],
        p0a: vec![fr.p0a, s * s * fr.p0a],
        mu: fr.mu,
        eps: fr.eps,
    };
    (M, B, K, G, pts)
}

/// The two-speed model's band system with the given cut-off, about its steady state under
/// P0 (a load `kick` on both pads' x, ramped over `t_load` or a step), and its full BSQL
/// system.
#[allow(non_snake_case)]
fn two_speed_systems(
    damp: Real,
    cutoff_hz: Real,
    kick: Real,
    t_load: Real,
) -> (
    BandSystem<Points>,
    BsqlSystem<Points>,
    Vec<squeal_solver::cea::Mode>,
) {
    let (M, B, K, G, pts) = two_speed(damp);
    let load = LoadHistory {
        p_brake: vec![kick, 0.0, 0.0, kick, 0.0, 0.0],
        t_load,
        ..Default::default()
    };
    let mut full = BsqlSystem::new(
        M.clone(),
        B.clone(),
        K.clone(),
        G.clone(),
        load.clone(),
        pts.clone(),
        BsqlOptions::default(),
    )
    .unwrap();
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let mut d = Mat::zeros(6, 2);
    let mut cf = Mat::zeros(6, 6);
    pts.clone()
        .add_tangents(-1.0, &[0.0; 6], &ss.lambda_dot, &mut d, Some(&mut cf))
        .unwrap();
    let mut lin = CeaMatrices::new(M, K);
    lin.b = Some(B);
    lin.g = Some(G.clone());
    lin.d = Some(d);
    lin.c_f = Some(cf);
    let cea = complex_eigen(&lin, &CeaOptions::default()).unwrap();
    let inputs = Inputs::at_dofs(load.p_brake.clone(), (0..6).collect(), Mat::zeros(0, 6));
    let opts = BandOptions {
        cutoff_hz,
        band_hz: Some(0.25),
        tolerance: 0.05,
        ..Default::default()
    };
    let model = BandModel::build(&lin, inputs, &opts).unwrap();
    let band = BandSystem::new(
        model,
        pts,
        load,
        BandReference {
            u: ss.u,
            lambda_dot: ss.lambda_dot,
            ramp: 0.0,
        },
        BandContact {
            g: G,
            compliance: vec![0.0; 2],
            open_force: vec![None; 2],
        },
    )
    .unwrap();
    (band, full, cea.modes)
}

/// A model whose fast copy flutters far above the band: the cut-off removes that root by
/// construction (reported: count and the root itself, the CEA's), keeps the in-band unstable
/// root exactly, and the band-limited transient grows at the in-band rate only.
#[test]
fn a_flutter_far_above_the_band_is_removed_and_reported() {
    let (mut band, mut full, modes) = two_speed_systems(1.0, 1.0, 1e-6, 0.0);
    let unstable: Vec<_> = modes.iter().filter(|m| m.unstable).collect();
    println!(
        "CEA unstable: {:?}",
        unstable
            .iter()
            .map(|m| (m.frequency_hz, m.real_part))
            .collect::<Vec<_>>()
    );
    assert_eq!(unstable.len(), 2, "one slow, one fast flutter");
    let fast = unstable
        .iter()
        .max_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz))
        .unwrap();
    let slow = unstable
        .iter()
        .min_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz))
        .unwrap();
    let st = band.model().stats.clone();
    println!("{st:#?}");
    assert_eq!(st.removed_unstable, 1);
    let r = st.largest_removed_unstable.unwrap();
    assert!((r.frequency_hz - fast.frequency_hz).abs() < 1e-9 * fast.frequency_hz);
    assert!((r.real_part - fast.real_part).abs() < 1e-9 * fast.real_part);
    assert_eq!(st.kept_unstable.len(), 1);
    assert!((st.kept_unstable[0].real_part - slow.real_part).abs() < 1e-9 * slow.real_part);
    // The transient grows like the slow root: the peaks of v_0 from t = 30 to 100.
    let (y, yp) = band.initial_values(-1.0, 0.0).unwrap();
    let opts = |tolerances| BdfOptions {
        tolerances,
        max_steps: 1_000_000,
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts(band.tolerances(1e-7, 1e-9, 1e-7, 1e20)), 0.0, &y, &yp).unwrap();
    let (mut u, mut v, mut l) = (vec![0.0; 6], vec![0.0; 6], vec![0.0; 2]);
    let (mut env, mut vmax) = ([0.0f64; 2], 0.0f64);
    let (w0, w1) = ((60.0, 66.0), (94.0, 100.0));
    let mut pk: Vec<(Real, Real)> = Vec::new();
    let mut hist = [(0.0, 0.0); 2];
    bdf.step_to(&mut band, 100.0, |s, t, y, yp| {
        s.physical(t, y, yp, &mut u, &mut v, &mut l, None)?;
        if hist[1].1 > hist[0].1 && hist[1].1 >= v[0] && t > 30.0 {
            pk.push(hist[1]);
        }
        hist = [hist[1], (t, v[0])];
        vmax = vmax.max(v[0].abs());
        if (w0.0..w0.1).contains(&t) {
            env[0] = env[0].max(v[0].abs());
        }
        if (w1.0..w1.1).contains(&t) {
            env[1] = env[1].max(v[0].abs());
        }
        Ok(true)
    })
    .unwrap();
    let _ = env;
    // Least-squares slope of ln(peak) against the peak times.
    let (ts, ls): (Vec<Real>, Vec<Real>) = pk.iter().map(|&(t, p)| (t, p.ln())).unzip();
    let sigma = common::slope(&ts, &ls);
    let steps_band = bdf.stats().steps;
    println!(
        "peak growth {sigma:.4} vs slow root {:.4} (fast {:.3}); largest |v_0| {vmax:.3e}; {} steps to t = 100",
        slow.real_part, fast.real_part, steps_band
    );
    assert!(vmax < 0.05, "linear range");
    assert!(
        (sigma - slow.real_part).abs() < 0.03 * slow.real_part,
        "σ {sigma}"
    );
    // The full model follows the fast flutter (the step load excites it): its steps shrink
    // to its period, and within 40 it has grown into slip reversal.
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let (mut y, mut yp) = ss.initial_values();
    consistent_initial_conditions(&mut full, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    let mut bf = Bdf::new(opts(full.tolerances(1e-7, 1e-9, 1e-7, 1e20)), 0.0, &y, &yp).unwrap();
    let mut fast_max = 0.0f64;
    let stf = bf
        .step_to(&mut full, 40.0, |_, _, y, _| {
            fast_max = fast_max.max(y[3].abs());
            Ok(true)
        })
        .unwrap();
    assert!(stf.is_success(), "{stf:?}");
    let steps_full = bf.stats().steps;
    println!("full to t = 40: {steps_full} steps, largest |v_3| (the fast pad) {fast_max:.3}");
    assert!(
        fast_max > 1.0,
        "the fast flutter grows into slip reversal in the full model"
    );
    assert!(steps_full > 5 * steps_band, "{steps_full} vs {steps_band}");
}

/// With the fast copy stable (damped 20×), the band-limited transient with it condensed out
/// follows the full BSQL transient into the nonlinear range within the estimate's order (in
/// about as many steps: stable fast modes never limited BDF's step).
#[test]
fn condensing_a_stable_fast_part_follows_the_full_transient() {
    let (mut band, mut full, _) = two_speed_systems(20.0, 1.0, 0.02, 2.0);
    let est = band.model().stats.error_estimate;
    let ss = steady_state(&mut full, -1.0, &SteadyOptions::default()).unwrap();
    let (mut y, mut yp) = ss.initial_values();
    consistent_initial_conditions(&mut full, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    let tol = (1e-6, 1e-8);
    let mut bf = Bdf::new(
        BdfOptions {
            tolerances: full.tolerances(tol.0, tol.1, tol.0, 1e20),
            max_steps: 1_000_000,
            ..Default::default()
        },
        0.0,
        &y,
        &yp,
    )
    .unwrap();
    let (yb, ypb) = band.initial_values(-1.0, 0.0).unwrap();
    let mut bb = Bdf::new(
        BdfOptions {
            tolerances: band.tolerances(tol.0, tol.1, tol.0, 1e20),
            max_steps: 1_000_000,
            ..Default::default()
        },
        0.0,
        &yb,
        &ypb,
    )
    .unwrap();
    let (mut u, mut v, mut l) = (vec![0.0; 6], vec![0.0; 6], vec![0.0; 2]);
    let (mut worst, mut vmax) = (0.0f64, 0.0f64);
    let mut t = 0.0;
    while t < 50.0 {
        t += 0.25;
        assert!(bf.integrate_to(&mut full, t).unwrap().is_success());
        assert!(bb.integrate_to(&mut band, t).unwrap().is_success());
        let (yb, ypb) = (bb.y().to_vec(), bb.yp().to_vec());
        band.physical(t, &yb, &ypb, &mut u, &mut v, &mut l, None)
            .unwrap();
        let yf = bf.y();
        for i in 0..3 {
            vmax = vmax.max(yf[i].abs());
            worst = worst.max((v[i] - yf[i]).abs());
        }
    }
    let (sf, sb) = (bf.stats().steps, bb.stats().steps);
    println!("in-band DOFs: largest |v| {vmax:.4}, difference {worst:.3e} (estimate {est:.3e}); steps full {sf}, band {sb}");
    assert!(vmax > 0.3, "nonlinear range ({vmax})");
    assert!(worst < 10.0 * est * vmax, "{worst:e} vs estimate {est:e}");
}

/// The gap's relative coordinates as the contact's inputs and outputs (force patterns [e_0,
/// Gᵀ], velocity rows [−e_0ᵀ, e_2ᵀ]: 3 outputs instead of 4) give the same transient as a
/// unit force and the velocity at each contact DOF (two integrations at RTOL 1e-9 whose error
/// tests see different outputs: they agree to ~1e-6 of the response, the integration's
/// global error).
#[test]
fn relative_contact_coordinates_give_the_same_transient() {
    let load = LoadHistory {
        p_brake: vec![0.02, 0.0, 0.0],
        t_load: 2.0,
        ..Default::default()
    };
    let run = |relative: bool| -> (Vec<Real>, usize) {
        let (mut band, _) = compliant_band(0.1, true, relative, &load);
        let (y, yp) = band.initial_values(-1.0, 0.0).unwrap();
        let mut bdf = Bdf::new(
            BdfOptions {
                tolerances: band.tolerances(1e-9, 1e-11, 1e-9, 1e20),
                max_steps: 1_000_000,
                ..Default::default()
            },
            0.0,
            &y,
            &yp,
        )
        .unwrap();
        assert!(bdf.integrate_to(&mut band, 30.0).unwrap().is_success());
        let (y, yp) = (bdf.y().to_vec(), bdf.yp().to_vec());
        let (mut u, mut v, mut l) = (vec![0.0; 3], vec![0.0; 3], vec![0.0; 1]);
        band.physical(30.0, &y, &yp, &mut u, &mut v, &mut l, None)
            .unwrap();
        (v.into_iter().chain(u).collect(), y.len())
    };
    let (a, na) = run(false);
    let (b, nb) = run(true);
    println!("unknowns {na} vs {nb}; {a:?} vs {b:?}");
    assert_eq!(na, nb + 1);
    let scale = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    for (x, y) in a.iter().zip(&b) {
        assert!((x - y).abs() < 1e-5 * scale, "{a:?} vs {b:?}");
    }
}
