//! The hard-case suite (issue 7): numerically hard scenes, each with what "stable" means for
//! it, asserted. Fast cases run in CI; slow ones are `#[ignore]`d:
//! `cargo test --release -p squeal-pipeline --test hard_cases -- --ignored --nocapture`
//! (measured numbers in `examples/hard-cases/README.md`).
//!
//! The models are the stored-matrix models of `squeal_pipeline::stages::accuracy::models`
//! (belt, mass on a belt with analytic growth rate σ = (N·|dμ/dv| − c)/(2m); pad rows),
//! written into the test's temporary folder and read back as `[model] from = "op4"` scenes,
//! then integrated in process (no history writes) by `stages::accuracy::integrate`.

use faer::Mat;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::accuracy::{initial_state, integrate, models, Method, RunOutcome};
use squeal_pipeline::stages::transient::{roots, verdict};
use squeal_pipeline::stages::{model, transient::system};
use squeal_pipeline::{RunDir, Scene};
use std::f64::consts::PI;
use std::path::PathBuf;

/// A scene on a stored model; `extra` is TOML appended to the `[model]` table's scene.
struct Case {
    name: &'static str,
    model: models::StoredModel,
    friction: String,
    rpm: f64,
    loads: String,
    transient: String,
    model_extra: String,
}

struct Ran {
    run: RunOutcome,
    /// Energy balance residual and the largest energy term.
    energy_residual: f64,
    energy_scale: f64,
}

impl Case {
    fn belt(name: &'static str) -> Self {
        Case {
            name,
            model: models::belt(),
            friction: r#"law = { kind = "linear_speed", mu0 = 0.5, slope = -0.05 }"#.into(),
            rpm: models::RPM,
            loads: "pmax = 0.05\ntload = 0.05".into(),
            transient: "tfinal = 10.0\natol1 = 1e-10".into(),
            model_extra: String::new(),
        }
    }

    fn dir(&self) -> PathBuf {
        let d = PathBuf::from(env!("CARGO_TARGET_TMPDIR"))
            .join("hard-cases")
            .join(self.name);
        let _ = std::fs::remove_dir_all(&d);
        std::fs::create_dir_all(&d).unwrap();
        d
    }

    /// Runs with `method` (rtol scales ATOL1), sampling all DOFs at `samples` + 1 times.
    fn run(&self, method: Method, samples: usize) -> Ran {
        self.run_sampling(method, samples, None)
    }

    /// As [`Case::run`], sampling only `dofs` (all DOFs when None).
    fn run_sampling(&self, method: Method, samples: usize, dofs: Option<&[usize]>) -> Ran {
        let dir = self.dir();
        self.model.write(&dir, "m").unwrap();
        let text = format!(
            "[model]\nfrom = \"op4\"\nmatrices = \"m.op4\"\ndofmap = \"m.dofmap.json\"\n\
             gaps = \"m.gaps.csv\"\n{}\n\n[friction]\n{}\n\n[rotor]\nrpm = {}\n\n[loads]\n{}\n\n\
             [transient]\n{}\nnrstrt = 0\n\n[output]\nhistory = false\n",
            self.model_extra, self.friction, self.rpm, self.loads, self.transient
        );
        let path = dir.join("scene.toml");
        std::fs::write(&path, text).unwrap();
        let scene = Scene::load(&path, &[]).unwrap();
        let rd = RunDir::create(&dir.join("run")).unwrap();
        let m = model::build(&scene, &rd, &Progress::quiet()).unwrap();
        let problem = system::problem(&scene, &m).unwrap();
        let spec = scene.transient.clone().unwrap();
        let (y0, yp0) = initial_state(&problem, spec.tolint).unwrap();
        let grid: Vec<f64> = (0..=samples)
            .map(|k| spec.tfinal * k as f64 / samples as f64)
            .collect();
        let dofs: Vec<usize> = dofs.map_or_else(|| (0..m.n()).collect(), <[usize]>::to_vec);
        let run = integrate(&problem, &spec, method, &y0, &yp0, &grid, &dofs, true).unwrap();
        let e = run.energy.clone().unwrap();
        let scale = [
            e.kinetic,
            e.strain,
            e.friction_work,
            e.damping_dissipated,
            e.external_work,
            e.initial_energy,
        ]
        .iter()
        .fold(0.0f64, |a, b| a.max(b.abs()));
        Ran {
            energy_residual: e.residual(),
            energy_scale: scale,
            run,
        }
    }
}

fn bdf(rtol: f64) -> Method {
    Method::Bdf { rtol, max_order: 2 }
}

/// Growth rate and frequency of DOF `j`'s velocity after `t_after`.
fn sigma_f(r: &RunOutcome, j: usize, t_after: f64) -> (f64, f64) {
    let x: Vec<f64> = r.v.iter().map(|v| v[j]).collect();
    let vd = verdict::analyse(&r.t, &x, t_after);
    (
        vd.growth_rate_per_s.expect("a growth rate (>= 3 peaks)"),
        vd.dominant_frequency_hz.expect("a frequency"),
    )
}

/// The root estimator (matrix pencil, `transient::roots`) on DOF `j`'s velocity after
/// `t_after` (the run's uniform sample grid): the largest root at the window's end, checked
/// against the analytic σ0 (absolute tolerance `ds`) and, when given, f0 (relative `df`), the
/// references the envelope fit of the same test is held to.
fn check_roots(
    name: &str,
    r: &RunOutcome,
    j: usize,
    t_after: f64,
    s0: f64,
    ds: f64,
    f0: Option<(f64, f64)>,
) {
    let first = r.t.iter().position(|&t| t > t_after).unwrap();
    let x: Vec<f64> = r.v[first..].iter().map(|v| v[j]).collect();
    let dt = r.t[first + 1] - r.t[first];
    let fit = roots::matrix_pencil(&[x], dt, r.t[first], None, &Default::default()).expect("a fit");
    let top = fit.roots[0];
    eprintln!(
        "{name}: pencil sigma = {} ({s0}), f = {} (order {}, residual {:.1e})",
        top.growth_rate_per_s, top.frequency_hz, fit.order, fit.relative_residual
    );
    assert!((top.growth_rate_per_s - s0).abs() < ds, "{name}: {fit:?}");
    if let Some((f0, df)) = f0 {
        assert!((top.frequency_hz - f0).abs() < df * f0, "{name}: {fit:?}");
    }
}

/// max_k |a_k − b_k| / max_k |b_k| over all sampled DOFs.
fn rel_diff(a: &RunOutcome, b: &RunOutcome) -> f64 {
    let (mut d, mut s) = (0.0f64, 0.0f64);
    for (x, y) in a.v.iter().zip(&b.v) {
        for (p, q) in x.iter().zip(y) {
            d = d.max((p - q).abs());
            s = s.max(q.abs());
        }
    }
    d / s
}

/// Stable = reached TFINAL, every sample finite, energy balance closed to `energy_tol` of the
/// largest energy term.
fn assert_stable(name: &str, r: &Ran, energy_tol: f64) {
    assert!(r.run.reached, "{name}: {:?}", r.run.status);
    assert!(!r.run.non_finite, "{name}: non-finite samples");
    assert!(
        r.energy_residual.abs() <= energy_tol * r.energy_scale,
        "{name}: energy residual {:e} vs scale {:e}",
        r.energy_residual,
        r.energy_scale
    );
    eprintln!(
        "{name}: {} steps, {} Newton, {} factorisations, energy residual {:.2e} of {:.2e}, \
         max drift {:.1e}",
        r.run.steps,
        r.run.newton_iterations,
        r.run.factorisations,
        r.energy_residual,
        r.energy_scale,
        r.run.max_constraint_drift
    );
}

/// Stick region: belt speed V = 5e-3 inside 10·VTOL = 1e-2. The pad's velocity amplitude
/// (~8e-3 from the kick) exceeds V, so the slip speed crosses zero (stick–slip through the
/// arctangent of eq. (5)). Stable: reached, finite, energy balance within 1e-3, and the
/// RTOL1 = 1e-6 run within 1e-2 (max relative) of the 1e-8 run.
#[test]
fn stick_region_slow_rotor() {
    let mut c = Case::belt("stick_region");
    c.rpm = models::RPM * 5e-3;
    c.transient = "tfinal = 4.0\natol1 = 1e-10".into();
    let a = c.run(bdf(1e-6), 800);
    let b = c.run(bdf(1e-8), 800);
    assert_stable("stick_region rtol 1e-6", &a, 1e-3);
    assert_stable("stick_region rtol 1e-8", &b, 1e-3);
    let d = rel_diff(&a.run, &b.run);
    eprintln!("stick_region: 1e-6 vs 1e-8: {d:.2e}");
    assert!(d < 1e-2, "{d}");
}

/// VTOL 100× smaller (1e-5) in the same stick–slip case: the regularised friction's slope
/// at zero slip is 100× steeper (a stiff, nearly non-smooth problem). Stable as above.
#[test]
fn vtol_hundred_times_smaller() {
    let mut c = Case::belt("vtol_small");
    c.rpm = models::RPM * 5e-3;
    c.friction = r#"law = { kind = "linear_speed", mu0 = 0.5, slope = -0.05 }
vtol = 1e-5"#
        .into();
    c.transient = "tfinal = 4.0\natol1 = 1e-10".into();
    let a = c.run(bdf(1e-6), 800);
    let b = c.run(bdf(1e-8), 800);
    assert_stable("vtol_small rtol 1e-6", &a, 1e-3);
    assert_stable("vtol_small rtol 1e-8", &b, 1e-3);
    let d = rel_diff(&a.run, &b.run);
    // Slip speed |V − v_pad| must enter the (now 1e-4 wide) regularisation zone: stick–slip.
    let min_slip = b
        .run
        .v
        .iter()
        .fold(f64::INFINITY, |m, v| m.min((5e-3 - v[0]).abs()));
    eprintln!("vtol_small: 1e-6 vs 1e-8: {d:.2e}, min slip speed {min_slip:.2e}");
    assert!(min_slip < 1e-4, "no stick phase: min slip {min_slip}");
    assert!(d < 1e-2, "{d}");
}

/// μ = 1.5 (constant): friction adds no damping, so the belt's oscillation decays at
/// σ = −c/(2m) = −0.15 /s exactly (linear analysis). Stable: σ within 1 % of −0.15.
#[test]
fn mu_one_and_a_half() {
    let mut c = Case::belt("mu_1_5");
    c.friction = r#"law = { kind = "constant", mu = 1.5 }"#.into();
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("mu_1_5", &r, 1e-4);
    let (s, f) = sigma_f(&r.run, 0, 0.05);
    eprintln!("mu_1_5: sigma = {s}, f = {f}");
    assert!((s + 0.15).abs() < 0.01 * 0.15, "sigma = {s}");
    check_roots("mu_1_5", &r.run, 0, 0.05, -0.15, 0.01 * 0.15, None);
}

/// Contact (normal) stiffness 1e4× the structure's: the pad and rotor normal DOFs get
/// k = 1e4·(2π)² (the contact constraint ties them), the tangential mode is unchanged: σ
/// = +0.1 /s, f = √((2π)² − σ²)/2π (analytic, [`models::belt_reference`]). Stable: σ and f
/// within 1 %.
#[test]
fn stiff_contact() {
    let mut c = Case::belt("stiff_contact");
    let k = 1e4 * (2.0 * PI).powi(2);
    c.model.k[(1, 1)] = k;
    c.model.k[(2, 2)] = k;
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("stiff_contact", &r, 1e-4);
    let (s, f) = sigma_f(&r.run, 0, 0.05);
    let (s0, f0) = models::belt_reference();
    eprintln!("stiff_contact: sigma = {s} ({s0}), f = {f} ({f0})");
    assert!((s - s0).abs() < 0.01 * s0 && (f - f0).abs() < 0.01 * f0);
    check_roots(
        "stiff_contact",
        &r.run,
        0,
        0.05,
        s0,
        0.01 * s0,
        Some((f0, 0.01)),
    );
}

/// Preload P0 = 0: no normal force, so no friction; the belt decays at σ = −c/(2m) = −0.15.
#[test]
fn zero_preload() {
    let mut c = Case::belt("p0_zero");
    c.model_extra = "p0 = 0.0".into();
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("p0_zero", &r, 1e-4);
    let (s, _) = sigma_f(&r.run, 0, 0.05);
    eprintln!("p0_zero: sigma = {s}");
    assert!((s + 0.15).abs() < 0.01 * 0.15, "sigma = {s}");
    check_roots("p0_zero", &r.run, 0, 0.05, -0.15, 0.01 * 0.15, None);
}

/// Step load (TLOAD = 0): the load jumps at t = 0 (an inconsistent start the initial
/// conditions must absorb). Stable: σ within 1 % of the analytic +0.1, and RTOL1 = 1e-6
/// within 1e-2 of 1e-8.
#[test]
fn step_load() {
    let mut c = Case::belt("step_load");
    c.loads = "pmax = 0.05\ntload = 0.0".into();
    let a = c.run(bdf(1e-6), 2000);
    let b = c.run(bdf(1e-8), 2000);
    assert_stable("step_load rtol 1e-6", &a, 1e-3);
    assert_stable("step_load rtol 1e-8", &b, 1e-4);
    let (s, _) = sigma_f(&b.run, 0, 0.0);
    let d = rel_diff(&a.run, &b.run);
    eprintln!("step_load: sigma = {s}, 1e-6 vs 1e-8: {d:.2e}");
    assert!((s - 0.1).abs() < 0.01 * 0.1, "sigma = {s}");
    assert!(d < 1e-2, "{d}");
}

/// Long run, TF = 0.1 s on a 1 kHz belt (100 periods, the sample brake's time scale):
/// k = (2π·1000)², c = 300, N = A·P0 = 1000, dμ/dv = −0.305: σ = (1000·0.305 − 300)/2
/// = +2.5 /s. Stable: σ within 2 % (only 0.25 e-foldings in the window) and f within 0.1 %.
#[test]
fn long_run_tf_0_1() {
    let mut c = Case::belt("long_run");
    let w = 2.0 * PI * 1000.0;
    c.model.k[(0, 0)] = w * w;
    c.model.b = Some(Mat::from_fn(
        3,
        3,
        |i, j| if i + j == 0 { 300.0 } else { 0.0 },
    ));
    c.model.gaps[0].4 = 1000.0;
    c.friction = r#"law = { kind = "linear_speed", mu0 = 0.5, slope = -0.305 }"#.into();
    c.loads = "pmax = 500.0\ntload = 1e-4".into();
    c.transient = "tfinal = 0.1\natol1 = 1e-12".into();
    let r = c.run(bdf(1e-8), 20000);
    assert_stable("long_run", &r, 1e-4);
    let (s, f) = sigma_f(&r.run, 0, 1e-4);
    let f0 = (w * w - 2.5f64 * 2.5).sqrt() / (2.0 * PI);
    eprintln!("long_run: sigma = {s} (2.5), f = {f} ({f0})");
    assert!((s - 2.5).abs() < 0.02 * 2.5, "sigma = {s}");
    assert!((f - f0).abs() < 1e-3 * f0, "f = {f}");
    check_roots(
        "long_run",
        &r.run,
        0,
        1e-4,
        2.5,
        0.02 * 2.5,
        Some((f0, 1e-3)),
    );
}

/// Very light damping: constant μ = 0.45, c = 1e-4 (ζ = 8e-6): σ = −c/(2m) = −5e-5 /s.
/// BDF2's own damping ζ_num ≈ (ωh)³/4 per radian must not swamp it at RTOL1 = 1e-8.
/// Stable: |σ + 5e-5| < 5e-6 /s (numerical damping below 10 % of the physical one) and the
/// energy balance closes within 1e-4.
#[test]
fn very_light_damping() {
    let mut c = Case::belt("light_damping");
    c.model.b = Some(Mat::from_fn(
        3,
        3,
        |i, j| if i + j == 0 { 1e-4 } else { 0.0 },
    ));
    c.friction = r#"law = { kind = "constant", mu = 0.45 }"#.into();
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("light_damping", &r, 1e-4);
    let (s, _) = sigma_f(&r.run, 0, 0.05);
    eprintln!("light_damping: sigma = {s:e} (exact -5e-5)");
    assert!((s + 5e-5).abs() < 5e-6, "sigma = {s}");
    check_roots("light_damping", &r.run, 0, 0.05, -5e-5, 5e-6, None);
}

/// Heavy damping: c = 10·m·ω (ζ = 5, overdamped): no oscillation, the kick decays with the
/// slow root −ω(ζ − √(ζ² − 1)) = −0.63 /s, i.e. to e^{−0.63·9.95} = 1.9e-3 of its peak by
/// TFINAL. Stable: finite, energy balance within 1e-4, |v(TFINAL)| < 1e-2 of the peak.
#[test]
fn heavy_damping() {
    let mut c = Case::belt("heavy_damping");
    let cc = 10.0 * 2.0 * PI;
    c.model.b = Some(Mat::from_fn(3, 3, |i, j| if i + j == 0 { cc } else { 0.0 }));
    c.friction = r#"law = { kind = "constant", mu = 0.45 }"#.into();
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("heavy_damping", &r, 1e-4);
    let peak = r.run.v.iter().fold(0.0f64, |m, v| m.max(v[0].abs()));
    let last = r.run.v.last().unwrap()[0].abs();
    eprintln!("heavy_damping: peak {peak:e}, last {last:e}");
    assert!(last < 1e-2 * peak, "{last} vs {peak}");
}

/// Nearly redundant constraints: a second gap on the same pad/rotor grids with its normal
/// tilted by 1e-6 rad (cond(G) ~ 1e6). Both hold pad x, so the y motion is the belt's: σ and
/// f within 1 % of the analytic root. Stable also = the constraint drift stays < 1e-8.
#[test]
fn nearly_redundant_constraints() {
    let mut c = Case::belt("redundant");
    c.model = models::belt_redundant(1e-6);
    let r = c.run(bdf(1e-8), 2000);
    assert_stable("redundant", &r, 1e-4);
    let (s, f) = sigma_f(&r.run, 1, 0.05);
    let (s0, f0) = models::belt_reference();
    eprintln!(
        "redundant: sigma = {s} ({s0}), f = {f} ({f0}), drift {:e}",
        r.run.max_constraint_drift
    );
    assert!((s - s0).abs() < 0.01 * s0 && (f - f0).abs() < 0.01 * f0);
    assert!(r.run.max_constraint_drift < 1e-8);
    check_roots(
        "redundant",
        &r.run,
        1,
        0.05,
        s0,
        0.01 * s0,
        Some((f0, 0.01)),
    );
}

/// Generalized-α on the belt as a cross-check of the BDF growth rate (fixed ωh = 0.05):
/// σ within 1 % of the analytic +0.1 (its numerical damping at ωh = 0.05, ρ∞ = 0.9 is
/// ~1e-8 per radian).
#[test]
fn generalized_alpha_cross_check() {
    let c = Case::belt("galpha");
    let h = 0.05 / (2.0 * PI);
    let r = c.run(
        Method::GeneralizedAlpha {
            h: Some(h),
            rtol: 1e-6,
            rho_inf: 0.9,
        },
        2000,
    );
    assert_stable("galpha", &r, 1e-4);
    let (s, _) = sigma_f(&r.run, 0, 0.05);
    eprintln!("galpha: sigma = {s}");
    assert!((s - 0.1).abs() < 0.01 * 0.1, "sigma = {s}");
}

/// The y chain of [`models::pad_row`] with its friction linearised, and no contact: the
/// exact equivalent of the pad row as long as nothing loads the normal DOFs (see
/// [`large_reduced_model`]). DOFs: the pad y of each pad (grids 1..=count, comp 2).
fn pad_row_y_chain(row: &models::StoredModel, count: usize) -> models::StoredModel {
    let y = |p: usize| 3 * p;
    // Friction on a pad: A·P0·(μ0 + slope·(V − v_y)) = 10·(0.45 + 0.05 v_y): a negative
    // damper N·|slope| = 0.5 (the constant 4.5 only shifts the steady state).
    let b = row.b.as_ref().expect("pad_row has damping");
    models::StoredModel {
        k: Mat::from_fn(count, count, |i, j| row.k[(y(i), y(j))]),
        m: Mat::from_fn(count, count, |i, j| row.m[(y(i), y(j))]),
        b: Some(Mat::from_fn(count, count, |i, j| {
            b[(y(i), y(j))] - if i == j { 0.5 } else { 0.0 }
        })),
        p_brake: (0..count).map(|i| row.p_brake[y(i)]).collect(),
        dofs: (0..count).map(|p| (1 + p as u64, 2)).collect(),
        gaps: Vec::new(),
    }
}

/// A large reduced model: 1700 pads in a row ([`models::pad_row`]: n = 5100 DOFs, 1700 gaps,
/// a dense 6800 × 6800 saddle system factorised at every change of BDF step or order), run
/// at RTOL1 = 1e-6 over the brake-load ramp and two periods of the ~1 Hz pad modes (TF = 2 s).
/// (At the paper's RTOL1 = 1e-4 the velocities are 5 % off the reference after two periods:
/// the error test weighs the displacements against their preload offset, ~100× the motion.)
///
/// Reference: nothing loads the normal DOFs, so the contact forces stay λ' = 0 (P_n = P0)
/// and each pad's friction is exactly 10·(0.45 + 0.05 v_y) (|V_t| = 1 − v_y > 10·VTOL): the
/// pads' y motion is that of the 1700-DOF chain M ÿ + (B − 0.5 I) ẏ + K y = P(t) without
/// constraints ([`pad_row_y_chain`]), integrated at RTOL1 = 1e-8.
///
/// Stable: reached TF, every sample finite, energy balance within 1e-6 of the largest energy
/// term (the preload's strain energy; 1e-4 for the reference, whose largest term is the
/// motion's), and the pad y velocities within 1e-2 (max over pads and samples, relative to
/// the largest) of the reference.
#[test]
#[ignore = "slow (minutes): dense factorisations of a 6800 x 6800 saddle system"]
fn large_reduced_model() {
    const PADS: usize = 1700;
    let mut c = Case::belt("large");
    c.model = models::pad_row(PADS);
    c.transient = "tfinal = 2.0\natol1 = 1e-8".into();
    let ydofs: Vec<usize> = (0..PADS).map(|p| 3 * p).collect();
    let started = std::time::Instant::now();
    let r = c.run_sampling(bdf(1e-6), 100, Some(&ydofs));
    let wall = started.elapsed().as_secs_f64();
    let mut chain = Case::belt("large_y_chain");
    chain.model = pad_row_y_chain(&c.model, PADS);
    chain.transient = c.transient.clone();
    let reference = chain.run(bdf(1e-8), 100);
    let d = rel_diff(&r.run, &reference.run);
    let vmax = reference
        .run
        .v
        .iter()
        .flatten()
        .fold(0.0f64, |m, x| m.max(x.abs()));
    eprintln!(
        "large: n = {}, gaps = {PADS}, {:?}, {} steps, {} Newton, {} factorisations, \
         cpu_s {:.1}, wall {wall:.1} s (model build + initial state + run); vs the y chain at \
         RTOL1 1e-8 ({} steps, cpu_s {:.2}): {d:.2e} of max |v| {vmax:.2e}",
        3 * PADS,
        r.run.status,
        r.run.steps,
        r.run.newton_iterations,
        r.run.factorisations,
        r.run.cpu_s,
        reference.run.steps,
        reference.run.cpu_s
    );
    assert_stable("large", &r, 1e-6);
    assert_stable("large y chain (reference)", &reference, 1e-4);
    assert!(d < 1e-2, "{d}");
}
