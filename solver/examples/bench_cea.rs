//! Benchmark of the complex eigenvalue analysis on a random ~500-DOF reduced model with 20
//! contact constraints: one exact CEA, a 50-point friction sweep with the projected
//! (subspace) method, the exact sweep (run on a few of the same μ and extrapolated, unless
//! `--exact-points` equals `--steps`), and the projection error against the exact
//! eigenvalues. Writes JSON (default `target/bench/cea.json`) and prints it.
//!
//! ```text
//! cargo build --release -p squeal-solver --example bench_cea
//! target/release/examples/bench_cea [OUT.json] [--n 500] [--ng 20] [--steps 50]
//!     [--exact-points 4] [--f-max-hz 0.6] [--cutoff-factor 2.5] [--n-basis 100 | --n-basis 0]
//! ```
//! (`--n-basis 0`: no count limit, the cutoff alone decides.)

use faer::Mat;
use serde_json::{json, Value};
use squeal_solver::cea::{
    compare_eigenvalues, complex_eigen, sweep, CeaError, CeaMatrices, CeaMethod, CeaOptions,
    ProjectionOptions, Sweep, SweepOptions,
};
use std::time::Instant;

struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d);
        (x >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// A random model: M = I + small SPD, K = SPD with spread eigenvalues, B = 1e-4 K,
/// G: ng rows u_q − u_p on disjoint DOF pairs (p, q), a tangential DOF t per pair coupled
/// to it, friction −μ K1 (t row) and D = μ D1 (friction ∝ contact force on t).
struct Model {
    m: Mat<f64>,
    k0: Mat<f64>,
    k1: Mat<f64>,
    b: Mat<f64>,
    g: Mat<f64>,
    d1: Mat<f64>,
}

fn model(n: usize, ng: usize) -> Model {
    let mut rng = Rng(0x1234_5678_9abc_def1);
    let a = Mat::from_fn(n, n, |_, _| rng.next() / (n as f64).sqrt());
    let mut m = &a * a.transpose() * 0.1;
    let c = Mat::from_fn(n, n, |_, _| rng.next() / (n as f64).sqrt());
    let mut k0 = &c * c.transpose();
    for i in 0..n {
        m[(i, i)] += 1.0;
        k0[(i, i)] += 1.0 + 100.0 * i as f64 / n as f64;
    }
    let mut g = Mat::zeros(ng, n);
    let mut d1 = Mat::zeros(n, ng);
    let mut k1 = Mat::zeros(n, n);
    for r in 0..ng {
        let (p, q) = (2 * r, 2 * r + 1);
        g[(r, q)] = 1.0;
        g[(r, p)] = -1.0;
        // Friction on a tangential DOF of the pad driven by the normal force.
        let t = 2 * ng + r;
        // Bring the tangential DOF near the frequency of the constrained pair and couple
        // them symmetrically, so that friction can merge the two modes (Hoffmann-like).
        k0[(t, t)] = 0.5 * (k0[(p, p)] + k0[(q, q)]) + 0.5;
        for x in [p, q] {
            k0[(t, x)] += 0.5;
            k0[(x, t)] += 0.5;
        }
        d1[(t, r)] = -1.0;
        k1[(t, p)] = 5.0 * rng.next();
        k1[(t, q)] = 5.0 * rng.next();
    }
    let b = &k0 * 1e-4;
    Model {
        m,
        k0,
        k1,
        b,
        g,
        d1,
    }
}

fn build(md: &Model, mu: f64) -> CeaMatrices {
    let mut s = CeaMatrices::new(md.m.clone(), &md.k0 - &md.k1 * mu);
    s.b = Some(md.b.clone());
    s.g = Some(md.g.clone());
    s.d = Some(&md.d1 * mu);
    s
}

struct Args {
    out: String,
    n: usize,
    ng: usize,
    steps: usize,
    exact_points: usize,
    f_max_hz: f64,
    cutoff_factor: f64,
    n_basis: Option<usize>,
}

fn args() -> Args {
    let mut a = Args {
        out: "target/bench/cea.json".into(),
        n: 500,
        ng: 20,
        steps: 50,
        exact_points: 4,
        // The friction-coupled DOFs (0..3 ng) have diagonal stiffness ≲ 1 + 100·3ng/n + 1.5
        // ≈ 14.5 with unit mass: ω ≲ 3.8 rad/s, f ≲ 0.6 Hz; the whole model reaches ~1.6 Hz.
        f_max_hz: 0.6,
        cutoff_factor: 2.5,
        // This model's undamped spectrum is uniform in ω² and ends at ~1.6 Hz, so a 2.5×
        // cutoff keeps 432 of the 480 modes (no speed-up: ~0.9 s per step). 100 modes reach
        // ~0.78 Hz (1.3× the band); the error this costs is measured and written below.
        n_basis: Some(100),
    };
    let v: Vec<String> = std::env::args().skip(1).collect();
    let mut i = 0;
    while i < v.len() {
        let val = |i: usize| -> &str { v.get(i + 1).map(|s| s.as_str()).unwrap_or("") };
        let num = |i: usize| -> f64 {
            val(i)
                .parse()
                .unwrap_or_else(|_| panic!("{} needs a number, got `{}`", v[i], val(i)))
        };
        match v[i].as_str() {
            "--n" => a.n = num(i) as usize,
            "--ng" => a.ng = num(i) as usize,
            "--steps" => a.steps = num(i) as usize,
            "--exact-points" => a.exact_points = num(i) as usize,
            "--f-max-hz" => a.f_max_hz = num(i),
            "--cutoff-factor" => a.cutoff_factor = num(i),
            "--n-basis" => a.n_basis = Some(num(i) as usize).filter(|&k| k > 0),
            s if !s.starts_with("--") => {
                a.out = s.to_string();
                i += 1;
                continue;
            }
            s => panic!("unknown argument {s}"),
        }
        i += 2;
    }
    a
}

fn lowest(s: &Sweep) -> Value {
    match s.lowest_critical() {
        Some((id, c)) => json!({"track": id, "mu": c.mu, "frequency_hz": c.frequency_hz}),
        None => Value::Null,
    }
}

fn main() {
    let a = args();
    let md = model(a.n, a.ng);
    let mu_max = 2.0;
    let mus: Vec<f64> = (0..a.steps)
        .map(|i| mu_max * i as f64 / (a.steps - 1).max(1) as f64)
        .collect();

    // 1. One exact CEA at μ = 0.5, with and without shapes.
    let sys = build(&md, 0.5);
    let t = Instant::now();
    let exact = complex_eigen(&sys, &CeaOptions::default()).expect("exact CEA");
    let t_exact = t.elapsed().as_secs_f64();
    let values_only = CeaOptions {
        compute_shapes: false,
        ..CeaOptions::default()
    };
    let t = Instant::now();
    let exact_values = complex_eigen(&sys, &values_only).expect("exact CEA");
    let t_exact_values = t.elapsed().as_secs_f64();
    assert_eq!(exact.modes.len(), exact_values.modes.len());

    // 2. A single projected CEA with the full basis: equal to the exact one to round-off.
    let full = CeaOptions {
        method: CeaMethod::Projection,
        compute_shapes: false,
        ..CeaOptions::default()
    };
    let t = Instant::now();
    let proj_full = complex_eigen(&sys, &full).expect("projected CEA");
    let t_proj_full = t.elapsed().as_secs_f64();
    let cmp_full = compare_eigenvalues(&proj_full.modes, &exact_values.modes, f64::INFINITY);

    // 3. The projected sweep (the default `auto` method picks projection: n − ng > 200 and
    // a frequency of interest is given); exact checks at the first and last μ.
    let projection = ProjectionOptions {
        frequency_max_hz: Some(a.f_max_hz),
        cutoff_factor: a.cutoff_factor,
        n_basis: a.n_basis,
        ..ProjectionOptions::default()
    };
    let sopts = SweepOptions {
        bisection: false,
        cea: CeaOptions {
            projection,
            ..CeaOptions::default()
        },
        ..SweepOptions::default()
    };
    let t = Instant::now();
    let ps = sweep(|mu| Ok::<_, CeaError>(build(&md, mu)), &mus, &sopts).expect("sweep");
    let t_ps = t.elapsed().as_secs_f64();
    let st = &ps.stats;

    // 4. The exact sweep on `exact_points` of the same μ (evenly spread, ends included).
    let k = a.exact_points.clamp(1, a.steps);
    let idx: Vec<usize> = if k == 1 {
        vec![0]
    } else {
        (0..k).map(|i| i * (a.steps - 1) / (k - 1)).collect()
    };
    let emus: Vec<f64> = idx.iter().map(|&i| mus[i]).collect();
    let eopts = SweepOptions {
        bisection: false,
        cea: CeaOptions {
            method: CeaMethod::Exact,
            ..CeaOptions::default()
        },
        ..SweepOptions::default()
    };
    let t = Instant::now();
    let es = sweep(|mu| Ok::<_, CeaError>(build(&md, mu)), &emus, &eopts).expect("sweep");
    let t_es = t.elapsed().as_secs_f64();
    let full_run = k == a.steps;

    // 5. Projection error at each exact point.
    let band = st.check_band_hz.unwrap_or(f64::INFINITY);
    let errors: Vec<Value> = idx
        .iter()
        .zip(&es.steps)
        .map(|(&i, e)| {
            let c = compare_eigenvalues(&ps.steps[i].modes, &e.modes, band);
            json!({"mu": mus[i], "comparison": c})
        })
        .collect();
    let max_err = errors
        .iter()
        .map(|e| {
            e["comparison"]["max_rel_error"]
                .as_f64()
                .unwrap_or(f64::NAN)
        })
        .fold(0.0, f64::max);
    let max_re_err = errors
        .iter()
        .map(|e| {
            e["comparison"]["max_real_part_error"]
                .as_f64()
                .unwrap_or(f64::NAN)
        })
        .fold(0.0, f64::max);
    let max_unstable_hz = es
        .steps
        .iter()
        .flat_map(|s| {
            s.modes
                .iter()
                .filter(|m| m.unstable)
                .map(|m| m.frequency_hz)
        })
        .fold(0.0, f64::max);

    let out = json!({
        "machine_cores": std::thread::available_parallelism().map(|x| x.get()).unwrap_or(1),
        "model": {
            "n": a.n, "n_constraints": a.ng, "n_reduced": exact.stats.n_reduced,
            "first_order_size": 2 * exact.stats.n_reduced,
            "highest_undamped_hz": proj_full.modes.last().map(|m| m.frequency_hz),
            "highest_unstable_hz_exact": max_unstable_hz,
            "mu_range": [0.0, mu_max],
        },
        "exact_cea": {
            "mu": 0.5,
            "with_shapes_s": t_exact,
            "reduce_s": exact.stats.time_reduce_s,
            "eigen_s": exact.stats.time_eigen_s,
            "eigenvalues_only_s": t_exact_values,
            "n_modes": exact.stats.n_modes,
            "n_unstable": exact.stats.n_unstable,
        },
        "projected_cea_full_basis": {
            "time_s": t_proj_full,
            "n_basis": proj_full.stats.n_basis,
            "max_rel_error_all_modes": cmp_full.max_rel_error,
        },
        "projected_sweep": {
            "steps": st.n_steps,
            "bisection": false,
            "time_s": t_ps,
            "time_without_exact_checks_s": t_ps - st.time_check_s,
            "time_basis_s": st.time_basis_s,
            "time_exact_checks_s": st.time_check_s,
            "time_per_step_s": (t_ps - st.time_check_s - st.time_basis_s) / st.n_solves as f64,
            "method": st.method,
            "n_basis": st.n_basis,
            "basis_max_frequency_hz": st.basis_max_frequency_hz,
            "frequency_max_hz": a.f_max_hz,
            "check_band_hz": st.check_band_hz,
            "max_rel_eigenvalue_error_at_checks": st.max_rel_eigenvalue_error,
            "exact_checks": st.exact_checks,
            "n_tracks": st.n_tracks,
            "n_critical": st.n_critical,
            "lowest_critical": lowest(&ps),
            "target_s": 2.0,
            "meets_target": t_ps < 2.0,
        },
        "exact_sweep": {
            "points_run": k,
            "time_s": t_es,
            "time_per_step_s": t_es / k as f64,
            "time_for_all_steps_s": t_es / k as f64 * a.steps as f64,
            "time_for_all_steps_is": if full_run { "measured" } else { "extrapolated from points_run" },
            "lowest_critical": if full_run { lowest(&es) } else { Value::Null },
        },
        "projection_error_vs_exact": {
            "band_hz": band,
            "max_rel_eigenvalue_error": max_err,
            "max_real_part_error": max_re_err,
            "points": errors,
        },
    });
    let text = serde_json::to_string_pretty(&out).expect("json");
    if let Some(dir) = std::path::Path::new(&a.out).parent() {
        if !dir.as_os_str().is_empty() {
            std::fs::create_dir_all(dir).expect("create output directory");
        }
    }
    std::fs::write(&a.out, &text).expect("write JSON");
    println!("{text}");
    eprintln!("written to {}", a.out);
}
