//! Work–precision of the BDF and generalized-α integrators on the belt model (issue 7).
//!
//! Model: the 2-DOF mass on a belt with falling friction μ = μ0 − a·v_rel (DOF 0 tangential,
//! DOF 1 normal held by G = [0, 1]); m = 1, k = (2π)², c = 0.3, N = 10, a = 0.05: the
//! linearised growth rate is σ = −(c − N a)/(2m) = +0.1 /s at ω_d ≈ 2π. Each run starts
//! from the steady sliding state with a velocity kick 0.05, integrates 12 s, samples the
//! solution every 1/200 s, and measures σ and ω_d from w = v − s̄ (x − x_eq) (least-squares
//! slopes of ln|w| and of the unwrapped arg w over t ≥ 1 s; s the exact root).
//!
//! Runs: BDF (rtol 1e-3 … 1e-8, max_order 1 and 2), generalized-α with fixed steps
//! (ωh = 0.8 … 0.0125, ρ∞ = 0.9) and adaptive generalized-α (rtol 1e-3 … 1e-8).
//! CPU seconds are the mean over repeats of one run (repeated until ≥ 0.2 s in total).
//!
//! ```text
//! cargo build --release -p squeal-solver --example galpha_vs_bdf
//! target/release/examples/galpha_vs_bdf [out.json]   # default target/bench/galpha_vs_bdf.json
//! ```

use faer::Mat;
use num_complex::Complex64;
use serde::Serialize;
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, InitialConditionOptions, Tolerances,
};
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
use squeal_solver::galpha::{Galpha, GalphaOptions, GalphaSystem};
use squeal_solver::{Real, SolverError};
use std::f64::consts::PI;
use std::time::Instant;

const M: Real = 1.0;
const C: Real = 0.3;
const N_LOAD: Real = 10.0;
const MU0: Real = 0.5;
const A: Real = 0.05;
const V_BELT: Real = 1.0;
const T_END: Real = 12.0;
const SAMPLES_PER_S: usize = 200;

fn k() -> Real {
    (2.0 * PI).powi(2)
}
fn sigma() -> Real {
    -(C - N_LOAD * A) / (2.0 * M)
}
fn omega_d() -> Real {
    (k() / M - sigma() * sigma()).sqrt()
}
fn x_eq() -> Real {
    N_LOAD * (MU0 - A * V_BELT) / k()
}

/// μ = μ0 − a·(V − v0) times the contact force λ'_0 on DOF 0.
struct Belt;

impl FrictionForces for Belt {
    fn add_forces(
        &mut self,
        _: Real,
        v: &[Real],
        lam: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        f[0] += (MU0 - A * (V_BELT - v[0])) * lam[0];
        Ok(())
    }
    fn add_tangents(
        &mut self,
        _: Real,
        v: &[Real],
        lam: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        d_dlam[(0, 0)] += MU0 - A * (V_BELT - v[0]);
        if let Some(d) = d_dv {
            d[(0, 0)] += A * lam[0];
        }
        Ok(())
    }
}

#[allow(clippy::type_complexity)]
fn matrices() -> (Mat<Real>, Mat<Real>, Mat<Real>, Mat<Real>, LoadHistory) {
    let mm = Mat::from_fn(2, 2, |i, j| [[M, 0.0], [0.0, 2.0]][i][j]);
    let bb = Mat::from_fn(2, 2, |i, j| if i + j == 0 { C } else { 0.0 });
    let kk = Mat::from_fn(2, 2, |i, j| [[k(), 0.0], [0.0, 50.0]][i][j]);
    let g = Mat::from_fn(1, 2, |_, j| j as Real);
    let load = LoadHistory {
        p_pre: vec![0.0, N_LOAD],
        ..Default::default()
    };
    (mm, bb, kk, g, load)
}

fn initial() -> (Vec<Real>, Vec<Real>) {
    (
        vec![0.05, 0.0, 0.0, x_eq(), 0.0],
        vec![0.0, 0.0, N_LOAD, 0.05, 0.0],
    )
}

/// (σ, ω_d) from samples (t, v, x).
fn measure(samples: &[(Real, Real, Real)]) -> (Real, Real) {
    let s_conj = Complex64::new(sigma(), -omega_d());
    let (mut ts, mut ls, mut ph) = (Vec::new(), Vec::new(), Vec::new());
    let mut last: Option<Complex64> = None;
    let mut phase = 0.0;
    for &(t, v, x) in samples.iter().filter(|s| s.0 >= 1.0) {
        let w = Complex64::from(v) - s_conj * (x - x_eq());
        if let Some(l) = last {
            phase += (w / l).arg();
        }
        last = Some(w);
        ts.push(t);
        ls.push(w.norm().ln());
        ph.push(phase);
    }
    (slope(&ts, &ls), slope(&ts, &ph))
}

fn slope(xs: &[Real], ys: &[Real]) -> Real {
    let n = xs.len() as Real;
    let mx = xs.iter().sum::<Real>() / n;
    let my = ys.iter().sum::<Real>() / n;
    let sxy: Real = xs.iter().zip(ys).map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: Real = xs.iter().map(|x| (x - mx) * (x - mx)).sum();
    sxy / sxx
}

#[derive(Debug, Clone, Serialize)]
struct Run {
    integrator: &'static str,
    rtol: Option<Real>,
    max_order: Option<usize>,
    h: Option<Real>,
    omega_h: Option<Real>,
    rho_inf: Option<Real>,
    sigma: Real,
    /// Relative error of the growth rate, (σ_measured − σ)/σ.
    error: Real,
    /// Relative error of the damped frequency.
    freq_error: Real,
    steps: u64,
    newton_iterations: u64,
    factorisations: u64,
    rejected_steps: u64,
    cpu_s: Real,
}

/// Run `f` repeatedly until ≥ 0.2 s; return its last result and the mean seconds per run.
fn timed<T>(mut f: impl FnMut() -> T) -> (T, Real) {
    let start = Instant::now();
    let mut reps = 0;
    loop {
        let out = f();
        reps += 1;
        let el = start.elapsed().as_secs_f64();
        if el >= 0.2 || reps >= 50 {
            return (out, el / reps as Real);
        }
    }
}

fn bdf_run(rtol: Real, max_order: usize) -> Run {
    let ((samples, stats), cpu) = timed(|| {
        let (mm, bb, kk, g, load) = matrices();
        let mut sys = BsqlSystem::new(
            mm,
            bb,
            kk,
            g,
            load,
            Belt,
            BsqlOptions {
                include_friction_damping: true,
                ..Default::default()
            },
        )
        .unwrap();
        let (mut y, mut yp) = initial();
        consistent_initial_conditions(
            &mut sys,
            0.0,
            &mut y,
            &mut yp,
            None,
            &InitialConditionOptions::default(),
        )
        .unwrap();
        let opts = BdfOptions {
            max_order,
            tolerances: sys.tolerances(rtol, 1e-2 * rtol, rtol, 1e-2 * rtol),
            ..Default::default()
        };
        let mut bdf = Bdf::new(opts, 0.0, &y, &yp).unwrap();
        let mut samples = vec![(0.0, y[0], y[3])];
        for i in 1..=(T_END as usize * SAMPLES_PER_S) {
            let t = i as Real / SAMPLES_PER_S as Real;
            assert!(bdf.integrate_to(&mut sys, t).unwrap().is_success());
            samples.push((t, bdf.y()[0], bdf.y()[3]));
        }
        (samples, bdf.stats().clone())
    });
    let (s, w) = measure(&samples);
    Run {
        integrator: "bdf",
        rtol: Some(rtol),
        max_order: Some(max_order),
        h: None,
        omega_h: None,
        rho_inf: None,
        sigma: s,
        error: (s - sigma()) / sigma(),
        freq_error: (w - omega_d()) / omega_d(),
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        factorisations: stats.jacobian_setups,
        rejected_steps: stats.error_test_failures,
        cpu_s: cpu,
    }
}

fn galpha_run(h: Option<Real>, rtol: Option<Real>) -> Run {
    let rho_inf = GalphaOptions::default().rho_inf;
    let ((samples, stats), cpu) = timed(|| {
        let (mm, bb, kk, g, load) = matrices();
        let mut sys = GalphaSystem::new(mm, bb, kk, g, load, Belt).unwrap();
        let (y, yp) = initial();
        let opts = match (h, rtol) {
            (Some(h), _) => GalphaOptions {
                h,
                tolerances: Tolerances::Scalar {
                    rtol: 1e-10,
                    atol: 1e-12,
                },
                ..Default::default()
            },
            (None, Some(r)) => GalphaOptions {
                h: 1e-3,
                adaptive: true,
                tolerances: Tolerances::Scalar {
                    rtol: r,
                    atol: 1e-2 * r,
                },
                ..Default::default()
            },
            _ => unreachable!(),
        };
        let mut ga = Galpha::new(opts, &mut sys, 0.0, &y, &yp).unwrap();
        let mut samples = vec![(0.0, y[0], y[3])];
        for i in 1..=(T_END as usize * SAMPLES_PER_S) {
            let t = i as Real / SAMPLES_PER_S as Real;
            let st = ga.integrate_to(&mut sys, t).unwrap();
            assert!(st.is_success(), "{st:?}");
            samples.push((t, ga.y()[0], ga.y()[3]));
        }
        (samples, ga.stats().clone())
    });
    let (s, w) = measure(&samples);
    Run {
        integrator: if h.is_some() {
            "galpha"
        } else {
            "galpha_adaptive"
        },
        rtol,
        max_order: None,
        h,
        omega_h: h.map(|h| h * (k() / M).sqrt()),
        rho_inf: Some(rho_inf),
        sigma: s,
        error: (s - sigma()) / sigma(),
        freq_error: (w - omega_d()) / omega_d(),
        steps: stats.steps,
        newton_iterations: stats.newton_iterations,
        factorisations: stats.factorisations,
        rejected_steps: stats.rejected_steps,
        cpu_s: cpu,
    }
}

fn main() -> anyhow_free::Result {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/bench/galpha_vs_bdf.json".into());
    let rtols = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8];
    let omega = (k() / M).sqrt();
    let mut runs = Vec::new();
    for max_order in [1, 2] {
        for &r in &rtols {
            runs.push(bdf_run(r, max_order));
        }
    }
    for wh in [0.8, 0.4, 0.2, 0.1, 0.05, 0.025, 0.0125] {
        runs.push(galpha_run(Some(wh / omega), None));
    }
    for &r in &rtols {
        runs.push(galpha_run(None, Some(r)));
    }
    println!(
        "{:<16} {:>8} {:>5} {:>9} {:>12} {:>11} {:>11} {:>7} {:>7} {:>6} {:>10}",
        "integrator",
        "rtol",
        "order",
        "ωh",
        "σ",
        "σ rel.err",
        "ω rel.err",
        "steps",
        "newton",
        "facts",
        "cpu_s"
    );
    let opt = |x: Option<Real>| x.map_or("-".to_string(), |v| format!("{v:.0e}"));
    for r in &runs {
        println!(
            "{:<16} {:>8} {:>5} {:>9} {:>12.8} {:>11.3e} {:>11.3e} {:>7} {:>7} {:>6} {:>10.3e}",
            r.integrator,
            opt(r.rtol),
            r.max_order.map_or("-".into(), |o| o.to_string()),
            r.omega_h.map_or("-".into(), |w| format!("{w:.4}")),
            r.sigma,
            r.error,
            r.freq_error,
            r.steps,
            r.newton_iterations,
            r.factorisations,
            r.cpu_s
        );
    }
    if let Some(dir) = std::path::Path::new(&path).parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let json = serde_json::to_string_pretty(&runs).map_err(|e| e.to_string())?;
    std::fs::write(&path, json).map_err(|e| format!("{path}: {e}"))?;
    println!("wrote {path}");
    Ok(())
}

/// `main`'s error type without an extra dependency.
mod anyhow_free {
    pub type Result = std::result::Result<(), String>;
}
