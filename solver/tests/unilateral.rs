//! Unilateral contact (separation and re-contact with events) and the automatic friction
//! damping near sticking, against analytic solutions.

use faer::Mat;
use squeal_solver::bdf::{consistent_initial_conditions, Bdf, BdfOptions, BdfState};
use squeal_solver::bsql::{
    BsqlOptions, BsqlSystem, EnergyBalance, FrictionForces, LoadHistory, Unilateral,
    UnilateralOptions, UnilateralState, UnilateralStats,
};
use squeal_solver::{Real, SolverError};

/// Coulomb friction of a mass on a belt of speed `v_belt` in +x, on DOF 0, driven by the
/// compressive contact force N = −λ'_0 (the contact crate's F_z = −λ'): F = μ N (kinetic
/// slip, V_belt − x' > 0 throughout).
struct BeltCoulomb {
    mu: Real,
}

impl FrictionForces for BeltCoulomb {
    fn add_forces(
        &mut self,
        _t: Real,
        _v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        f[0] += -self.mu * lambda_dot[0];
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _t: Real,
        _v: &[Real],
        _lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        _d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        d_dlam[(0, 0)] += -self.mu;
        Ok(())
    }
}

/// The bouncing pair. DOFs (x, z1, z2): mass m1 slides in x on a rigid face at z1 = 0,
/// pressed on it by F0; a second mass m2 hangs on m1 through a spring k (unstretched at
/// z2 = z1) and starts at z2 = 0 moving away from the face at V0. Constraint g = z1 ≥ 0.
const M1: Real = 1.0;
const M2: Real = 1.0;
const K: Real = 100.0;
const F0: Real = 50.0;
const V0: Real = 10.0;
const MU: Real = 0.3;

fn bouncing_system() -> BsqlSystem<BeltCoulomb> {
    let mut m = Mat::zeros(3, 3);
    m[(0, 0)] = M1;
    m[(1, 1)] = M1;
    m[(2, 2)] = M2;
    let mut k = Mat::zeros(3, 3);
    k[(1, 1)] = K;
    k[(1, 2)] = -K;
    k[(2, 1)] = -K;
    k[(2, 2)] = K;
    let mut g = Mat::zeros(1, 3);
    g[(0, 1)] = 1.0;
    let load = LoadHistory {
        p_pre: vec![0.0, -F0, 0.0],
        ..Default::default()
    };
    BsqlSystem::new(
        m,
        Mat::zeros(3, 3),
        k,
        g,
        load,
        BeltCoulomb { mu: MU },
        BsqlOptions::default(),
    )
    .unwrap()
}

fn bdf_options(sys: &BsqlSystem<BeltCoulomb>) -> BdfOptions {
    BdfOptions {
        tolerances: sys.tolerances(1e-9, 1e-11, 1e-9, 1e-11),
        ..Default::default()
    }
}

fn start(sys: &mut BsqlSystem<BeltCoulomb>) -> (Vec<Real>, Vec<Real>) {
    // y = {x', z1', z2', λ, x, z1, z2}
    let mut y = vec![0.0, 0.0, V0, 0.0, 0.0, 0.0, 0.0];
    let mut yp = vec![0.0; 7];
    consistent_initial_conditions(sys, 0.0, &mut y, &mut yp, None, &Default::default()).unwrap();
    (y, yp)
}

/// Analytic events of the bouncing pair.
///
/// Contact phase: z1 = 0, z2 = (V0/ω2) sin ω2 t with ω2 = √(k/m2); the contact force is
/// N = F0 − k z2, zero first at t1 = asin(F0 ω2/(k V0))/ω2; the belt drives x' = (μ/m1)∫N dt.
/// Flight: the centre of mass Z = (m1 z1 + m2 z2)/(m1 + m2) falls with −F0/(m1 + m2); the
/// stretch r = z2 − z1 oscillates with ω_r = √(k (m1 + m2)/(m1 m2)) about r_e = F0 m2/(k (m1 + m2))
/// (r'' = −k r/m2 − (k r − F0)/m1). z1 = Z − m2 r/(m1 + m2); landing t2 at its first zero after
/// t1 (bisection on this closed form), where the plastic impact dissipates ½ m1 z1'(t2)².
struct Analytic {
    t1: Real,
    xdot_t1: Real,
    t2: Real,
    z1dot_t2: Real,
}

fn analytic() -> Analytic {
    let w2 = (K / M2).sqrt();
    let a = V0 / w2;
    let t1 = (F0 / (K * a)).asin() / w2;
    let n_impulse = F0 * t1 - K * a * (1.0 - (w2 * t1).cos()) / w2;
    let xdot_t1 = MU * n_impulse / M1;
    let (z2, z2d) = (a * (w2 * t1).sin(), V0 * (w2 * t1).cos());
    let mt = M1 + M2;
    let wr = (K * mt / (M1 * M2)).sqrt();
    let re = F0 * M2 / (K * mt);
    let (z0, zd0) = (M2 * z2 / mt, M2 * z2d / mt);
    let (r0, rd0) = (z2, z2d);
    let z1 = |tau: Real| {
        let zc = z0 + zd0 * tau - 0.5 * F0 / mt * tau * tau;
        let r = re + (r0 - re) * (wr * tau).cos() + rd0 / wr * (wr * tau).sin();
        zc - M2 * r / mt
    };
    let z1d = |tau: Real| {
        let zcd = zd0 - F0 / mt * tau;
        let rd = -(r0 - re) * wr * (wr * tau).sin() + rd0 * (wr * tau).cos();
        zcd - M2 * rd / mt
    };
    // First sign change of z1 on a fine grid, then bisection.
    let dtau = 1e-4;
    let mut tau = dtau;
    while z1(tau) > 0.0 {
        tau += dtau;
        assert!(tau < 10.0, "no landing found");
    }
    let (mut lo, mut hi) = (tau - dtau, tau);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if z1(mid) > 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Analytic {
        t1,
        xdot_t1,
        t2: t1 + hi,
        z1dot_t2: z1d(hi),
    }
}

#[test]
fn bouncing_mass_with_friction_matches_analytic_events_and_energy() {
    let an = analytic();
    let mut sys = bouncing_system();
    let (y0, yp0) = start(&mut sys);
    let mut bdf = Bdf::new(bdf_options(&sys), 0.0, &y0, &yp0).unwrap();
    let mut uni =
        Unilateral::new(&mut sys, vec![0.0], &y0, &yp0, UnilateralOptions::default()).unwrap();
    let mut bal = EnergyBalance::new();
    bal.push(&sys.observe(0.0, &y0, &yp0).unwrap());
    // Record (t, x', z1') at every callback (events appear twice: before and after).
    let mut rec: Vec<(Real, Real, Real)> = Vec::new();
    let t_end = an.t2 + 0.01;
    let status = uni
        .step_to(&mut bdf, &mut sys, t_end, |s, t, y, yp| {
            bal.push(&s.observe(t, y, yp)?);
            rec.push((t, y[0], y[1]));
            Ok(true)
        })
        .unwrap();
    assert!(status.is_success(), "{status:?}");
    let st = uni.stats().clone();
    println!("analytic t1 {:.12} t2 {:.12}, stats {st:?}", an.t1, an.t2);
    assert!(st.openings >= 1 && st.closings >= 1, "{st:?}");
    let t1 = st.first_separation_t.unwrap();
    assert!((t1 - an.t1).abs() < 1e-6 * an.t1, "t1 {t1} vs {}", an.t1);
    // The closing event: the first callback time after t1 at which z1' jumps.
    let jumps: Vec<&(Real, Real, Real)> = rec
        .windows(2)
        .filter(|w| w[0].0 == w[1].0 && w[0].0 > t1 + 1e-9)
        .map(|w| &w[0])
        .collect();
    assert!(!jumps.is_empty(), "no closing event recorded");
    let (t2, xdot, z1dot) = *jumps[0];
    println!(
        "t1 {t1:.12} (analytic {:.12}), t2 {t2:.12} (analytic {:.12}), x' {xdot:.9} ({:.9}), \
         z1'(t2-) {z1dot:.9} ({:.9})",
        an.t1, an.t2, an.xdot_t1, an.z1dot_t2
    );
    assert!((t2 - an.t2).abs() < 1e-6 * an.t2, "t2 {t2} vs {}", an.t2);
    assert!((xdot - an.xdot_t1).abs() < 1e-6 * an.xdot_t1);
    assert!((z1dot - an.z1dot_t2).abs() < 1e-5 * an.z1dot_t2.abs());
    // Impact dissipation ½ m1 z1'(t2)² (analytic), and the energy balance closes with it.
    let loss = 0.5 * M1 * an.z1dot_t2 * an.z1dot_t2;
    let first_loss = st.impact_dissipated;
    assert!(
        (first_loss - loss).abs() < 1e-5 * loss,
        "impact loss {first_loss} vs {loss}"
    );
    bal.impact_dissipated = st.impact_dissipated;
    let res = bal.residual();
    println!(
        "energy: residual {res:e} of scale {:e}, friction work {:e}, impact {:e}",
        bal.scale(),
        bal.friction_work,
        bal.impact_dissipated
    );
    assert!(res.abs() < 1e-5 * bal.scale(), "energy residual {res:e}");
    // Only friction acts along x and x starts at rest (the impact is normal): the belt's work
    // μ∫N x' dt is the tangential kinetic energy ½ m1 x'².
    let xdot_end = rec.last().unwrap().1;
    let tangential = 0.5 * M1 * xdot_end * xdot_end;
    assert!(
        (bal.friction_work - tangential).abs() < 1e-6 * tangential,
        "friction work {} vs {tangential}",
        bal.friction_work
    );
}

/// Saved BDF state and active set, as a restart file would hold them.
fn run_to(t: Real) -> (BdfState, UnilateralState, UnilateralStats, Vec<Real>) {
    let mut sys = bouncing_system();
    let (y0, yp0) = start(&mut sys);
    let mut bdf = Bdf::new(bdf_options(&sys), 0.0, &y0, &yp0).unwrap();
    let mut uni =
        Unilateral::new(&mut sys, vec![0.0], &y0, &yp0, UnilateralOptions::default()).unwrap();
    assert!(uni
        .step_to(&mut bdf, &mut sys, t, |_, _, _, _| Ok(true))
        .unwrap()
        .is_success());
    (
        bdf.state().clone(),
        uni.state().clone(),
        uni.stats().clone(),
        bdf.y().to_vec(),
    )
}

#[test]
fn restart_across_an_open_gap_equals_uninterrupted_run() {
    let an = analytic();
    let t_mid = 0.5 * (an.t1 + an.t2);
    let t_end = an.t2 + 0.2;
    // Uninterrupted (stopping at t_mid as the restarted run's first leg does).
    let mut sys = bouncing_system();
    let (y0, yp0) = start(&mut sys);
    let mut bdf = Bdf::new(bdf_options(&sys), 0.0, &y0, &yp0).unwrap();
    let mut uni =
        Unilateral::new(&mut sys, vec![0.0], &y0, &yp0, UnilateralOptions::default()).unwrap();
    let noop = |_: &mut BsqlSystem<BeltCoulomb>, _: Real, _: &[Real], _: &[Real]| Ok(true);
    assert!(uni.step_to(&mut bdf, &mut sys, t_mid, noop).unwrap().is_success());
    assert!(uni.state().open[0], "the gap must be open at t_mid");
    assert!(uni.step_to(&mut bdf, &mut sys, t_end, noop).unwrap().is_success());
    let y_ref = bdf.y().to_vec();
    // Restart at t_mid through JSON (as restart.json would hold it).
    let (bst, ust, ustats, _) = run_to(t_mid);
    let bst: BdfState = serde_json::from_str(&serde_json::to_string(&bst).unwrap()).unwrap();
    let ust: UnilateralState =
        serde_json::from_str(&serde_json::to_string(&ust).unwrap()).unwrap();
    let mut sys2 = bouncing_system();
    let mut bdf2 = Bdf::from_state(bdf_options(&sys2), bst).unwrap();
    let mut uni2 = Unilateral::from_state(&mut sys2, ust, UnilateralOptions::default()).unwrap();
    uni2.set_stats(ustats);
    assert!(uni2.step_to(&mut bdf2, &mut sys2, t_end, noop).unwrap().is_success());
    let diff = y_ref
        .iter()
        .zip(bdf2.y())
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
    println!(
        "restart across the open gap: max |Δy| = {diff:e}; events {} vs {}",
        uni.stats().events,
        uni2.stats().events
    );
    assert!(diff <= 1e-10, "restart differs by {diff}");
    let (a, b) = (uni.stats(), uni2.stats());
    assert_eq!((a.openings, a.closings, a.events), (b.openings, b.closings, b.events));
    assert!((a.impact_dissipated - b.impact_dissipated).abs() < 1e-10 * a.impact_dissipated);
    assert_eq!(bdf.stats().steps, bdf2.stats().steps);
}
