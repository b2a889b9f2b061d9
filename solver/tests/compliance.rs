//! Normal contact compliance (`squeal_solver::bsql::compliance`): a mass on a compliant
//! contact against its analytic frequency in the CEA and in the BDF transient, the energy
//! balance with the contact springs' energy stored, the rigid limit of the CEA (error ~ 1/k),
//! and bad compliance values.

mod common;

use common::Belt;
use faer::Mat;
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions, InitialConditionOptions};
use squeal_solver::bsql::{
    compliant_cea, steady_state, BsqlOptions, BsqlSystem, EnergyBalance, LoadHistory, NoFriction,
    SteadyOptions, Unilateral, UnilateralOptions,
};
use squeal_solver::cea::{complex_eigen, CeaMatrices, CeaOptions};
use squeal_solver::Real;

const TWO_PI: Real = 2.0 * std::f64::consts::PI;

/// One DOF: a pad of mass m on a normal contact spring k_n (per unit area) of area A; the
/// constraint row g = (u_rotor − u_pad)·n with the pad's DOF only, G = [−1].
struct OneDof {
    m: Real,
    kn: Real,
    area: Real,
}

impl OneDof {
    /// Analytic angular frequency √(k_n A / m).
    fn omega(&self) -> Real {
        (self.kn * self.area / self.m).sqrt()
    }
    fn compliance(&self) -> Real {
        1.0 / (self.kn * self.area)
    }
    fn system(&self) -> BsqlSystem<NoFriction> {
        let mut sys = BsqlSystem::new(
            Mat::from_fn(1, 1, |_, _| self.m),
            Mat::zeros(1, 1),
            Mat::zeros(1, 1),
            Mat::from_fn(1, 1, |_, _| -1.0),
            LoadHistory::default(),
            NoFriction,
            BsqlOptions::default(),
        )
        .unwrap();
        sys.set_compliance(vec![self.compliance()]).unwrap();
        sys
    }
}

const PAD: OneDof = OneDof {
    m: 2.0,
    kn: 1.0e4,
    area: 0.5,
};

#[test]
fn one_dof_on_a_compliant_contact_has_the_analytic_frequency_in_the_cea() {
    let p = &PAD;
    let rigid = CeaMatrices {
        g: Some(Mat::from_fn(1, 1, |_, _| -1.0)),
        ..CeaMatrices::new(Mat::from_fn(1, 1, |_, _| p.m), Mat::zeros(1, 1))
    };
    let sys = compliant_cea(&rigid, &[p.compliance()]).unwrap();
    assert!(sys.g.is_none() && sys.d.is_none());
    let r = complex_eigen(&sys, &CeaOptions::default()).unwrap();
    assert_eq!(r.modes.len(), 1, "{:?}", r.modes);
    let f = r.modes[0].frequency_hz;
    let f_ref = p.omega() / TWO_PI; // √(k A / m)/2π = 50/2π Hz
    println!("CEA: f = {f} Hz, analytic {f_ref} Hz");
    assert!((f - f_ref).abs() < 1e-12 * f_ref, "{f} vs {f_ref}");
    assert!(r.modes[0].real_part.abs() < 1e-12 * f_ref);
}

/// Free vibration of the one-DOF pad from an initial spring compression; returns the up-
/// crossings of u (linear interpolation between output points) and the energy balance.
fn free_vibration(p: &OneDof, periods: Real, rtol: Real) -> (Vec<Real>, EnergyBalance, Real) {
    let mut sys = p.system();
    let u0 = 1e-3;
    // y = {v, λ, u}; y' made consistent: λ' = G u/c = −u0 k A.
    let (mut y0, mut yp0) = (vec![0.0, 0.0, u0], vec![0.0; 3]);
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let lam_ref = -u0 * p.kn * p.area;
    assert!((yp0[1] - lam_ref).abs() < 1e-10 * lam_ref.abs(), "{yp0:?}");
    // m v' = −Gᵀλ' = λ'... F_v = m v' + Gᵀλ' = m v' − λ' = 0 → v' = λ'/m = −k A u0 / m.
    assert!((yp0[0] - lam_ref / p.m).abs() < 1e-10 * (lam_ref / p.m).abs());
    let opts = BdfOptions {
        tolerances: sys.tolerances(rtol, rtol * u0, rtol, 1e20),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut bal = EnergyBalance::new();
    let e0 = sys.observe(0.0, &y0, &yp0).unwrap();
    // The initial energy is the contact spring's ½ k A u0² (K = 0): it is stored energy.
    let spring = 0.5 * p.kn * p.area * u0 * u0;
    assert!((e0.strain - spring).abs() < 1e-12 * spring, "{e0:?}");
    assert_eq!(e0.constraint, 0.0);
    bal.push(&e0);
    let t_end = periods * TWO_PI / p.omega();
    let (mut last, mut ups) = ((0.0, u0), Vec::new());
    let st = bdf
        .step_to(&mut sys, t_end, |s, t, y, yp| {
            bal.push(&s.observe(t, y, yp)?);
            let u = y[2];
            if last.1 < 0.0 && u >= 0.0 {
                // Cubic accuracy is not needed: the steps are small against the period and
                // u is nearly linear at its zero.
                ups.push(last.0 + (t - last.0) * (-last.1) / (u - last.1));
            }
            last = (t, u);
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    println!("transient stats {:?}", bdf.stats());
    (ups, bal, spring)
}

#[test]
fn one_dof_on_a_compliant_contact_has_the_analytic_frequency_in_the_transient() {
    let p = &PAD;
    let (ups, bal, spring) = free_vibration(p, 20.0, 1e-9);
    assert!(ups.len() >= 19, "{} up-crossings", ups.len());
    let period = (ups[ups.len() - 1] - ups[0]) / (ups.len() - 1) as Real;
    let omega = TWO_PI / period;
    println!(
        "transient: ω = {omega}, analytic {}; energy residual {:e} of {spring:e}",
        p.omega(),
        bal.residual()
    );
    // BDF2 at rtol 1e-9: a relative phase error of order (ωh)² ≈ 1e-7 per period.
    assert!(
        (omega - p.omega()).abs() < 1e-5 * p.omega(),
        "ω = {omega} vs {}",
        p.omega()
    );
    // Nothing does work: the stored energy (kinetic + contact spring) is conserved up to
    // BDF2's numerical dissipation (ζ ~ (ωh)³) and the quadrature.
    assert!(
        bal.residual().abs() < 1e-5 * spring,
        "energy residual {:e} vs {spring:e}",
        bal.residual()
    );
    assert!(bal.kinetic + bal.strain > 0.99 * spring);
}

#[test]
fn steady_state_compresses_the_contact_spring() {
    // The one-DOF pad pressed by a load P: k A (−u) = P, λ' = −P (F_z = P compressive);
    // with a structural spring k0 in parallel the spring takes P·kA/(kA + k0).
    let p = &PAD;
    let k0 = 3000.0;
    let load = 7.0;
    let mut sys = BsqlSystem::new(
        Mat::from_fn(1, 1, |_, _| p.m),
        Mat::zeros(1, 1),
        Mat::from_fn(1, 1, |_, _| k0),
        Mat::from_fn(1, 1, |_, _| -1.0),
        LoadHistory {
            p_pre: vec![load],
            ..Default::default()
        },
        NoFriction,
        BsqlOptions::default(),
    )
    .unwrap();
    sys.set_compliance(vec![p.compliance()]).unwrap();
    let ss = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap();
    let ka = p.kn * p.area;
    let u = load / (ka + k0);
    assert!((ss.u[0] - u).abs() < 1e-12 * u, "{ss:?}");
    assert!((ss.lambda_dot[0] + ka * u).abs() < 1e-10 * ka * u, "{ss:?}");
}

#[test]
fn energy_balance_closes_with_compliance_and_friction() {
    // The belt of bsql_verification.rs (falling friction driven by the normal force λ') with a
    // compliant normal contact: the normal DOF now vibrates on the contact spring, the
    // friction force follows the varying λ', and the balance must close with the springs'
    // energy counted as stored energy (and not as constraint work).
    let b = Belt {
        m: 1.0,
        k: TWO_PI * TWO_PI,
        c: 0.7,
        n_load: 10.0,
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    };
    let mut sys = b.system(BsqlOptions::default());
    let kn = 400.0; // the normal DOF (m_z = 2, k_z = 50) then vibrates at √(450/2) = 15 rad/s
    sys.set_compliance(vec![1.0 / kn]).unwrap();
    let ss = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap();
    // Normal DOF: k_z u + λ' = N, u − λ'/k_n = 0 (G = [0, 1]) → λ' = N k_n/(k_n + k_z).
    let lam = b.n_load * kn / (kn + 50.0);
    assert!((ss.lambda_dot[0] - lam).abs() < 1e-10 * lam, "{ss:?}");
    let (mut y0, mut yp0) = ss.initial_values();
    y0[0] = 0.05;
    y0[1] = 0.02; // a normal velocity: the contact spring works
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let opts = BdfOptions {
        tolerances: sys.tolerances(1e-7, 1e-9, 1e-7, 1e20),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut bal = EnergyBalance::new();
    bal.push(&sys.observe(0.0, &y0, &yp0).unwrap());
    let (mut lam_min, mut lam_max) = (Real::INFINITY, Real::NEG_INFINITY);
    let st = bdf
        .step_to(&mut sys, 20.0, |s, t, y, yp| {
            lam_min = lam_min.min(yp[2]);
            lam_max = lam_max.max(yp[2]);
            bal.push(&s.observe(t, y, yp)?);
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    println!(
        "belt with compliance: λ' in [{lam_min}, {lam_max}], balance {bal:?}, residual {:e}",
        bal.residual()
    );
    // The contact force did vary (the friction force with it).
    assert!(lam_max - lam_min > 0.1, "λ' in [{lam_min}, {lam_max}]");
    // Only the rigid rows' power is constraint work: none here.
    assert_eq!(bal.constraint_work, 0.0);
    assert!(bal.friction_work.abs() > 0.0 && bal.damping_dissipated > 0.0);
    let work = bal.friction_work.abs() + bal.damping_dissipated;
    assert!(
        bal.residual().abs() <= bal.quadrature_error.max(1e-6 * work),
        "residual {:e} > quadrature estimate {:e}",
        bal.residual(),
        bal.quadrature_error
    );
    assert!(
        bal.residual().abs() < 1e-4 * work,
        "residual {:e} vs work {work:e}",
        bal.residual()
    );
}

/// The 3-DOF model with one constraint and a friction tangent D of tests/cea.rs
/// (`friction_tangent_d_is_projected_exactly`), with light damping.
fn constrained_with_friction(mu: Real) -> CeaMatrices {
    let m_r = 0.5;
    let mut s = CeaMatrices::new(
        Mat::from_fn(3, 3, |i, j| if i == j { [1.0, 1.0, m_r][i] } else { 0.0 }),
        Mat::from_fn(3, 3, |i, j| {
            [[1.0, 0.3, 0.0], [0.3, 0.2, 0.0], [0.0, 0.0, 1.0]][i][j]
        }),
    );
    s.g = Some(Mat::from_fn(1, 3, |_, j| [0.0, -1.0, 1.0][j]));
    s.d = Some(Mat::from_fn(3, 1, |i, _| [-mu, 0.0, 0.0][i]));
    s.b = Some(Mat::from_fn(3, 3, |i, j| if i == j { 0.01 } else { 0.0 }));
    s
}

#[test]
fn cea_roots_converge_to_the_rigid_ones_like_one_over_k() {
    let rigid = constrained_with_friction(0.5);
    let r0 = complex_eigen(&rigid, &CeaOptions::default()).unwrap();
    assert_eq!(r0.modes.len(), 2);
    let mut errs = Vec::new();
    for kn in [1e3, 1e4, 1e5, 1e6] {
        let sys = compliant_cea(&rigid, &[1.0 / kn]).unwrap();
        let r = complex_eigen(&sys, &CeaOptions::default()).unwrap();
        // The rigid roots and one more pair, the contact mode near √(k_n (1/m_1 + 1/m_r)).
        assert_eq!(r.modes.len(), 3, "k_n = {kn}: {:?}", r.modes);
        let top = r.modes.last().unwrap().eigenvalue.im;
        let contact = (kn * (1.0 + 1.0 / 0.5)).sqrt();
        assert!((top - contact).abs() < 0.05 * contact, "{top} vs {contact}");
        let err = r0
            .modes
            .iter()
            .map(|m0| {
                r.modes
                    .iter()
                    .map(|m| (m.eigenvalue - m0.eigenvalue).norm() / m0.eigenvalue.norm())
                    .fold(Real::INFINITY, Real::min)
            })
            .fold(0.0, Real::max);
        println!("k_n = {kn:e}: max relative root error {err:e}");
        errs.push(err);
    }
    // The error falls like c = 1/k_n: by 10 (within 15 %) per decade of k_n.
    for w in errs.windows(2) {
        let ratio = w[0] / w[1];
        assert!((ratio - 10.0).abs() < 1.5, "error ratio {ratio} ({errs:?})");
    }
    assert!(errs[3] < 1e-4, "{errs:?}");
}

#[test]
fn mixed_rows_keep_the_rigid_ones_as_constraints() {
    // Two rows: the first rigid stays in G (and its column in D), the second folds into K.
    let mut s = constrained_with_friction(0.3);
    s.g = Some(Mat::from_fn(2, 3, |i, j| {
        [[0.0, -1.0, 1.0], [1.0, 0.0, 0.0]][i][j]
    }));
    s.d = Some(Mat::from_fn(3, 2, |i, k| {
        [[-0.3, 0.1], [0.0, 0.0], [0.0, 0.2]][i][k]
    }));
    let kn = 50.0;
    let c = compliant_cea(&s, &[0.0, 1.0 / kn]).unwrap();
    let g = c.g.as_ref().unwrap();
    assert_eq!((g.nrows(), g.ncols()), (1, 3));
    assert_eq!(g[(0, 1)], -1.0);
    let d = c.d.as_ref().unwrap();
    assert_eq!((d.nrows(), d.ncols()), (3, 1));
    assert_eq!(d[(0, 0)], -0.3);
    // K_c = K + (Gᵀ − D)_{:,1} k_n G_1: column 0 gets k_n (G_1 − D_{:,1}) = 50·[1 − 0.1, 0, −0.2].
    let expect = [1.0 + 50.0 * 0.9, 0.3, -10.0];
    for (i, e) in expect.iter().enumerate() {
        assert!(
            (c.k[(i, 0)] - e).abs() < 1e-12,
            "K_c[{i},0] = {}",
            c.k[(i, 0)]
        );
    }
    // The eigenvalues are those of the constrained problem with the spring in K.
    let r = complex_eigen(&c, &CeaOptions::default()).unwrap();
    assert_eq!(r.modes.len(), 2);
    assert!(r.modes.iter().all(|m| m.eigenvalue.norm() > 0.0));
}

#[test]
fn bad_compliance_values_are_errors() {
    let mut sys = PAD.system();
    for bad in [-1.0, Real::NAN, Real::INFINITY] {
        let e = sys.set_compliance(vec![bad]).unwrap_err().to_string();
        assert!(e.contains("compliance") && e.contains("row 0"), "{e}");
    }
    let e = sys.set_compliance(vec![1.0, 2.0]).unwrap_err().to_string();
    assert!(e.contains("contact compliance"), "{e}");
    let rigid = constrained_with_friction(0.5);
    let e = compliant_cea(&rigid, &[Real::NAN]).unwrap_err().to_string();
    assert!(e.contains("NaN (row 0)"), "{e}");
    // Zero compliance is the rigid row: the system is unchanged.
    let same = compliant_cea(&rigid, &[0.0]).unwrap();
    assert_eq!(same.k, rigid.k);
}

#[test]
fn iteration_matrix_with_compliance_inverts_finite_difference_jacobian() {
    use squeal_solver::bdf::DaeSystem;
    // The compliant rows of J = ∂F/∂y + cj ∂F/∂y' (see bsql::compliance): check J·x by
    // central differences of the residual, then solve back to x (belt with friction and a
    // compliant normal contact).
    let b = Belt {
        m: 1.0,
        k: TWO_PI * TWO_PI,
        c: 0.3,
        n_load: 10.0,
        mu0: 0.5,
        a: 0.05,
        v_belt: 1.0,
    };
    let mut sys = b.system(BsqlOptions {
        include_friction_damping: true,
        ..Default::default()
    });
    sys.set_compliance(vec![1.0 / 400.0]).unwrap();
    let ss = steady_state(&mut sys, 0.0, &SteadyOptions::default()).unwrap();
    let (y0, yp0) = ss.initial_values();
    // cj up to 1e15: the first steps; the compliant rows are scaled to keep the LU's pivots
    // meaningful there.
    for cj in [250.0, 1e6, 1e15] {
        let x: Vec<Real> = (0..5).map(|i| 0.1 + 0.37 * i as Real).collect();
        let eps = 1e-6;
        let mut rp = vec![0.0; 5];
        let mut rm = vec![0.0; 5];
        let shift = |s: Real| -> (Vec<Real>, Vec<Real>) {
            (
                y0.iter().zip(&x).map(|(a, d)| a + s * d).collect(),
                yp0.iter().zip(&x).map(|(a, d)| a + s * cj * d).collect(),
            )
        };
        let (yp_, ypp) = shift(eps);
        sys.residual(0.0, &yp_, &ypp, &mut rp).unwrap();
        let (ym, ypm) = shift(-eps);
        sys.residual(0.0, &ym, &ypm, &mut rm).unwrap();
        let mut jx: Vec<Real> = rp
            .iter()
            .zip(&rm)
            .map(|(a, b)| (a - b) / (2.0 * eps))
            .collect();
        sys.setup_jacobian(0.0, &y0, &yp0, cj).unwrap();
        sys.solve_jacobian(&mut jx).unwrap();
        for (a, b) in jx.iter().zip(&x) {
            assert!(
                (a - b).abs() < 1e-6 * b.abs().max(1.0),
                "cj = {cj}: {jx:?} vs {x:?}"
            );
        }
    }
}

#[test]
fn compliant_contact_separates_and_closes_without_impact() {
    // The one-DOF pad pushed onto the rotor by a constant force F (P0 = 0), started pressed
    // three times its static compression u_s = F/(kA) deeper, at rest: it springs back on the
    // contact spring, u(t) = u_s + 2 u_s cos ωt, until the spring force vanishes at u = 0
    // (p_n = 0: cos ωt = −1/2, t1 = 2π/(3ω)) with speed √3 u_s ω; it flies off and F brings
    // it back to u = 0 after 2·√3 u_s ω m/F = 2√3/ω (t2 = t1 + 2√3/ω), where the gap closes
    // with a continuous force: no impact, no energy lost, an elastic bounce.
    let p = &PAD;
    let ka = p.kn * p.area;
    let f = 5.0;
    let u_s = f / ka;
    let mut sys = BsqlSystem::new(
        Mat::from_fn(1, 1, |_, _| p.m),
        Mat::zeros(1, 1),
        Mat::zeros(1, 1),
        Mat::from_fn(1, 1, |_, _| -1.0),
        LoadHistory {
            p_pre: vec![f],
            ..Default::default()
        },
        NoFriction,
        BsqlOptions::default(),
    )
    .unwrap();
    sys.set_compliance(vec![p.compliance()]).unwrap();
    let (mut y0, mut yp0) = (vec![0.0, 0.0, 3.0 * u_s], vec![0.0; 3]);
    consistent_initial_conditions(
        &mut sys,
        0.0,
        &mut y0,
        &mut yp0,
        None,
        &InitialConditionOptions::default(),
    )
    .unwrap();
    let rtol = 1e-9;
    let opts = BdfOptions {
        tolerances: sys.tolerances(rtol, rtol * u_s, rtol, 1e20),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y0, &yp0).unwrap();
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y0,
        &yp0,
        UnilateralOptions::default(),
    )
    .unwrap();
    let w = p.omega();
    let t1 = 2.0 * std::f64::consts::PI / (3.0 * w);
    let t2 = t1 + 2.0 * 3f64.sqrt() / w;
    let mut bal = EnergyBalance::new();
    bal.push(&sys.observe(0.0, &y0, &yp0).unwrap());
    let mut events = Vec::new();
    let mut last_t = -1.0;
    let st = uni
        .step_to(&mut bdf, &mut sys, t2 + 0.5 * t1, |s, t, y, yp| {
            if t == last_t {
                events.push((t, y[0]));
            }
            last_t = t;
            bal.push(&s.observe(t, y, yp)?);
            Ok(true)
        })
        .unwrap();
    assert!(st.is_success(), "{st:?}");
    let stats = uni.stats().clone();
    println!("analytic t1 {t1:.10}, t2 {t2:.10}; events {events:?}; {stats:?}");
    assert_eq!((stats.openings, stats.closings), (1, 1), "{stats:?}");
    assert_eq!(events.len(), 2, "{events:?}");
    assert!((events[0].0 - t1).abs() < 1e-6 * t1, "{events:?}");
    assert!((events[1].0 - t2).abs() < 1e-6 * t2, "{events:?}");
    // Speeds at opening and closing: √3 u_s ω away, then towards the rotor.
    let v1 = 3f64.sqrt() * u_s * w;
    assert!((events[0].1 + v1).abs() < 1e-5 * v1, "{events:?} vs {v1}");
    assert!((events[1].1 - v1).abs() < 1e-5 * v1, "{events:?} vs {v1}");
    assert_eq!(stats.impact_dissipated, 0.0);
    // The spring's energy (closed) and the open gap's potential join at the events: the
    // balance (kinetic + spring = F's work) closes.
    let scale = bal.scale();
    println!("energy residual {:e} of {scale:e}", bal.residual());
    assert!(bal.residual().abs() < 1e-6 * scale, "{bal:?}");
}
