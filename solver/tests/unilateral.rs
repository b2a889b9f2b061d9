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
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y0,
        &yp0,
        UnilateralOptions::default(),
    )
    .unwrap();
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
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y0,
        &yp0,
        UnilateralOptions::default(),
    )
    .unwrap();
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
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y0,
        &yp0,
        UnilateralOptions::default(),
    )
    .unwrap();
    let noop = |_: &mut BsqlSystem<BeltCoulomb>, _: Real, _: &[Real], _: &[Real]| Ok(true);
    assert!(uni
        .step_to(&mut bdf, &mut sys, t_mid, noop)
        .unwrap()
        .is_success());
    assert!(uni.state().open[0], "the gap must be open at t_mid");
    assert!(uni
        .step_to(&mut bdf, &mut sys, t_end, noop)
        .unwrap()
        .is_success());
    let y_ref = bdf.y().to_vec();
    // Restart at t_mid through JSON (as restart.json would hold it).
    let (bst, ust, ustats, _) = run_to(t_mid);
    let bst: BdfState = serde_json::from_str(&serde_json::to_string(&bst).unwrap()).unwrap();
    let ust: UnilateralState = serde_json::from_str(&serde_json::to_string(&ust).unwrap()).unwrap();
    let mut sys2 = bouncing_system();
    let mut bdf2 = Bdf::from_state(bdf_options(&sys2), bst).unwrap();
    let mut uni2 = Unilateral::from_state(&mut sys2, ust, UnilateralOptions::default()).unwrap();
    uni2.set_stats(ustats);
    assert!(uni2
        .step_to(&mut bdf2, &mut sys2, t_end, noop)
        .unwrap()
        .is_success());
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
    assert_eq!(
        (a.openings, a.closings, a.events),
        (b.openings, b.closings, b.events)
    );
    assert!((a.impact_dissipated - b.impact_dissipated).abs() < 1e-10 * a.impact_dissipated);
    assert_eq!(bdf.stats().steps, bdf2.stats().steps);
}

/// Coulomb friction with static μs and kinetic μk on a belt of speed V, for the stick–slip
/// oscillator: F = N μ(|s|) r(s) on DOF 0 with slip s = V − x', N = −λ'_0, a Stribeck
/// transition μ(s) = μk + (μs − μk) e^{−|s|/v_s} and the regularisation r(s) = (2/π) atan(s/ε).
struct StickSlip {
    mu_s: Real,
    mu_k: Real,
    v_belt: Real,
    v_s: Real,
    eps: Real,
}

impl StickSlip {
    /// (μ(s) r(s), d(μ r)/ds).
    fn law(&self, s: Real) -> (Real, Real) {
        let e = (-s.abs() / self.v_s).exp();
        let mu = self.mu_k + (self.mu_s - self.mu_k) * e;
        let dmu = -(self.mu_s - self.mu_k) * e / self.v_s * s.signum();
        let two_pi = 2.0 / std::f64::consts::PI;
        let r = two_pi * (s / self.eps).atan();
        let dr = two_pi / self.eps / (1.0 + (s / self.eps).powi(2));
        (mu * r, dmu * r + mu * dr)
    }
}

impl FrictionForces for StickSlip {
    fn add_forces(
        &mut self,
        _t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        f[0] += -lambda_dot[0] * self.law(self.v_belt - v[0]).0;
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
        let (f, df) = self.law(self.v_belt - v[0]);
        d_dlam[(0, 0)] += -f;
        if let Some(c) = d_dv {
            // ∂F/∂x' = −N d(μr)/ds with N = −λ'.
            c[(0, 0)] += lambda_dot[0] * df;
        }
        Ok(())
    }
    fn near_stick(&mut self, _t: Real, v: &[Real], _lambda_dot: &[Real]) -> bool {
        // Within 10× the width over which μ r varies fast (the larger of v_s and 10 ε).
        (self.v_belt - v[0]).abs() < 10.0 * self.v_s.max(10.0 * self.eps)
    }
}

const SS_M: Real = 1.0;
const SS_K: Real = 1.0;
const SS_N: Real = 10.0;
const SS_MU_S: Real = 0.4;
const SS_MU_K: Real = 0.25;
const SS_V: Real = 0.5;
const SS_VS: Real = 1e-3;
const SS_EPS: Real = 1e-6;

/// Run the stick–slip oscillator from the start of a stick phase for `t_end`; returns the
/// samples (t, x) every accepted step and the Newton convergence failures.
fn stick_slip_run(near_stick: bool, t_end: Real) -> (Vec<(Real, Real)>, u64, u64) {
    let mut m = Mat::zeros(2, 2);
    m[(0, 0)] = SS_M;
    m[(1, 1)] = 1.0;
    let mut k = Mat::zeros(2, 2);
    k[(0, 0)] = SS_K;
    k[(1, 1)] = 50.0;
    let mut g = Mat::zeros(1, 2);
    g[(0, 1)] = 1.0;
    let load = LoadHistory {
        p_pre: vec![0.0, -SS_N],
        ..Default::default()
    };
    let fr = StickSlip {
        mu_s: SS_MU_S,
        mu_k: SS_MU_K,
        v_belt: SS_V,
        v_s: SS_VS,
        eps: SS_EPS,
    };
    let opts = BsqlOptions {
        include_friction_damping: false,
        friction_damping_near_stick: near_stick,
    };
    let mut sys = BsqlSystem::new(m, Mat::zeros(2, 2), k, g, load, fr, opts).unwrap();
    // Start of a stick phase: x = x_k − d, x' = V (d = (μs − μk) N/k, x_k = μk N/k).
    let (xk, d) = (SS_MU_K * SS_N / SS_K, (SS_MU_S - SS_MU_K) * SS_N / SS_K);
    let mut y = vec![SS_V, 0.0, 0.0, xk - d, 0.0];
    let mut yp = vec![0.0; 5];
    consistent_initial_conditions(&mut sys, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    let bopts = BdfOptions {
        tolerances: sys.tolerances(1e-8, 1e-10, 1e-8, 1e20),
        max_steps: 200_000,
        ..Default::default()
    };
    let mut bdf = Bdf::new(bopts, 0.0, &y, &yp).unwrap();
    let mut rec = Vec::new();
    let status = bdf
        .step_to(&mut sys, t_end, |_, t, y, _| {
            rec.push((t, y[3]));
            Ok(true)
        })
        .unwrap();
    if near_stick {
        assert!(status.is_success(), "{status:?}");
    }
    println!("{status:?}: {} steps", bdf.stats().steps);
    (
        rec,
        bdf.stats().convergence_failures,
        sys.stats().near_stick_factorisations,
    )
}

/// The classical stick–slip limit cycle of m x'' + k x = F on a belt of speed V with static
/// μs and kinetic μk under N: stick (x' = V) from x_k − d to x_k + d, d = (μs − μk)N/k,
/// x_k = μk N/k; slip is a harmonic arc about x_k with amplitude A = √(d² + (V/ω)²), of
/// duration (π + 2 atan(V/(ω d)))/ω. Period T = 2d/V + (π + 2 atan(V/(ωd)))/ω, extremes x_k ± A.
///
/// The regularised law breaks away at the largest force it can hold, max_s μ(s) r(s) =: μs_eff
/// (= 0.388 here for μs = 0.4: the atan costs O(√(ε/v_s)) of μs); the analytic cycle is taken
/// with μs_eff, found by a fine search of the law itself.
#[test]
fn stick_slip_belt_follows_the_analytic_limit_cycle() {
    let law = StickSlip {
        mu_s: SS_MU_S,
        mu_k: SS_MU_K,
        v_belt: SS_V,
        v_s: SS_VS,
        eps: SS_EPS,
    };
    let mut mu_eff: Real = 0.0;
    for i in 0..=20_000 {
        let s = 10f64.powf(-9.0 + 9.0 * i as Real / 20_000.0);
        mu_eff = mu_eff.max(law.law(s).0);
    }
    let w = (SS_K / SS_M).sqrt();
    let (xk, d) = (SS_MU_K * SS_N / SS_K, (mu_eff - SS_MU_K) * SS_N / SS_K);
    let a = (d * d + (SS_V / w).powi(2)).sqrt();
    let period = 2.0 * d / SS_V + (std::f64::consts::PI + 2.0 * (SS_V / (w * d)).atan()) / w;
    let (rec, ncf, stick_setups) = stick_slip_run(true, 4.0 * period);
    // Extremes after the first cycle and the times of the maxima.
    let mut maxima = Vec::new();
    let mut x_min = Real::INFINITY;
    for i in 1..rec.len() - 1 {
        let (t, x) = rec[i];
        if x > rec[i - 1].1 && x >= rec[i + 1].1 {
            maxima.push((t, x));
        }
        if t > period {
            x_min = x_min.min(x);
        }
    }
    println!(
        "stick–slip: μs_eff {mu_eff:.6}; analytic max {:.6} min {:.6} period {:.6}; maxima \
         {maxima:?}, min {x_min:.6}; Newton failures {ncf}, C_f factorisations {stick_setups}",
        xk + a,
        xk - a,
        period
    );
    assert!(maxima.len() >= 3, "{maxima:?}");
    // The Stribeck width v_s delays re-stick by O(v_s/V) = 2e-3 of the cycle: tolerance 5 v_s/V.
    let tol = 5.0 * SS_VS / SS_V;
    for &(_, x) in &maxima {
        assert!((x - (xk + a)).abs() < tol * a, "max {x} vs {}", xk + a);
    }
    assert!(
        (x_min - (xk - a)).abs() < tol * a,
        "min {x_min} vs {}",
        xk - a
    );
    for p in maxima.windows(2) {
        let tp = p[1].0 - p[0].0;
        assert!(
            (tp - period).abs() < tol * period,
            "period {tp} vs {period}"
        );
    }
    assert_eq!(ncf, 0, "Newton convergence failures with C_f near sticking");
}

/// C_f near sticking: without it the same stick–slip run fails Newton at every step of the
/// first stick phase and stalls (the step cap ends it); with it (the default) there are none.
#[test]
fn friction_damping_near_stick_removes_newton_failures() {
    let (_, with, setups) = stick_slip_run(true, 25.0);
    let (_, without, none) = stick_slip_run(false, 25.0);
    println!("Newton convergence failures: {with} with C_f near stick ({setups} factorisations with C_f), {without} without");
    assert_eq!(none, 0);
    assert!(setups > 0);
    assert_eq!(with, 0);
    assert!(without > 1000, "without C_f: {without} failures");
}

/// A gap at zero pressure that a load pulls off (issue: with P_0 = 0 no gap ever opened, the
/// run held it in tension). A mass m on a face (DOFs x, z; constraint g = z ≥ 0), no
/// preload, pulled off by a ramp F r(t), r = t/T_L: at t = 0 the contact force is exactly 0,
/// and any t > 0 needs tension, so the gap must open at t = 0. Open, the mass is free:
/// z(t) = F t³/(6 m T_L) (exact), and the contact carries nothing.
#[test]
fn a_gap_at_zero_pressure_opens_when_the_load_pulls_it_off() {
    const M: Real = 2.0;
    const F: Real = 3.0;
    const T_L: Real = 0.5;
    let mut m = Mat::zeros(2, 2);
    m[(0, 0)] = M;
    m[(1, 1)] = M;
    let mut g = Mat::zeros(1, 2);
    g[(0, 1)] = 1.0;
    let load = LoadHistory {
        p_brake: vec![0.0, F],
        t_load: T_L,
        ..Default::default()
    };
    let mut sys = BsqlSystem::new(
        m,
        Mat::zeros(2, 2),
        Mat::zeros(2, 2),
        g,
        load,
        BeltCoulomb { mu: MU },
        BsqlOptions::default(),
    )
    .unwrap();
    let mut y = vec![0.0; 5];
    let mut yp = vec![0.0; 5];
    consistent_initial_conditions(&mut sys, 0.0, &mut y, &mut yp, None, &Default::default())
        .unwrap();
    assert_eq!(yp[2], 0.0, "zero contact force at t = 0");
    let opts = BdfOptions {
        tolerances: sys.tolerances(1e-9, 1e-12, 1e-9, 1e-12),
        ..Default::default()
    };
    let mut bdf = Bdf::new(opts, 0.0, &y, &yp).unwrap();
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y,
        &yp,
        UnilateralOptions::default(),
    )
    .unwrap();
    let mut max_tension: Real = 0.0;
    let t_end = 0.4;
    let status = uni
        .step_to(&mut bdf, &mut sys, t_end, |_, t, _, yp| {
            // The contact force λ' (> 0: tension) the gap carried after t = 0: the bug held
            // it closed with λ' = r(t) F. (The view before the event at t = 0 is interpolated
            // on the step that crossed.)
            if t > 0.0 {
                max_tension = max_tension.max(yp[2]);
            }
            Ok(true)
        })
        .unwrap();
    assert!(status.is_success(), "{status:?}");
    let st = uni.stats();
    println!("{st:?}, largest tension carried {max_tension:e}");
    assert_eq!((st.openings, st.closings), (1, 0), "{st:?}");
    assert_eq!(st.first_separation_t, Some(0.0));
    assert!(max_tension <= 0.0, "tension {max_tension} carried");
    let z = bdf.y()[4];
    let exact = F * t_end.powi(3) / (6.0 * M * T_L);
    assert!((z - exact).abs() < 1e-6 * exact, "z {z} vs {exact}");
    // Nothing is carried through the open gap: no friction, x stays at rest.
    assert_eq!(bdf.y()[0], 0.0);
}

/// The drift monitor counts the closed rigid rows only (issue: with separation it counted an
/// open gap's separation speed, 0.48 on a Hoffmann-type model whose closed rows held to
/// 1e-17). The bouncing pair flies off its face at z1' of order 1 (analytic: `analytic()`),
/// while its closed row holds G v = 0 to the Newton tolerance.
#[test]
fn constraint_drift_counts_closed_rows_only() {
    let an = analytic();
    let mut sys = bouncing_system();
    let (y0, yp0) = start(&mut sys);
    let mut bdf = Bdf::new(bdf_options(&sys), 0.0, &y0, &yp0).unwrap();
    let mut uni = Unilateral::new(
        &mut sys,
        vec![0.0],
        None,
        &y0,
        &yp0,
        UnilateralOptions::default(),
    )
    .unwrap();
    let mut fastest: Real = 0.0;
    let status = uni
        .step_to(&mut bdf, &mut sys, an.t2 + 0.2, |s, t, y, yp| {
            s.observe(t, y, yp)?;
            fastest = fastest.max(y[1].abs());
            Ok(true)
        })
        .unwrap();
    assert!(status.is_success(), "{status:?}");
    assert!(uni.stats().closings >= 1);
    let drift = sys.stats().max_constraint_drift;
    println!("largest |z1'| {fastest:.4}, largest drift of the closed row {drift:e}");
    assert!(fastest > 0.5 * an.z1dot_t2.abs(), "{fastest}");
    assert!(drift < 1e-8, "drift {drift}");
}
