//! Cost per step of each friction effect on the same model (issue 7, effects on demand).
//!
//! Model: `models::pad_row(PADS)` — PADS belt-like pads in a row (n = 3·PADS DOFs, PADS gaps),
//! the same matrices, loads and tolerances for every law:
//! - `constant`: μ = 0.45 (no ∂μ/∂p, ∂μ/∂v, no temperature lookup);
//! - `linear_speed`: μ = 0.5 − 0.05|V_t| (∂μ/∂v only);
//! - `table_pvT`: a 3 × 3 × 2 table in (p, |V_t|, T) at T = 50 (trilinear lookups, all
//!   derivatives).
//!
//! For each: the BDF transient (RTOL1 = 1e-6, TFINAL = 2, no history writes) and, separately,
//! the friction callbacks alone (`GapSet::add_forces` and `add_tangents` at the initial
//! state), so the per-step cost can be split into friction evaluation and the rest.
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example bench_effects
//! target/release/examples/bench_effects [PADS] [out.json]   # default 60, target/bench/bench_effects.json
//! ```

use faer::Mat;
use serde::Serialize;
use squeal_pipeline::stages::accuracy::{initial_state, integrate, models, Method};
use squeal_pipeline::stages::{model, transient::system};
use squeal_pipeline::{progress::Progress, RunDir, Scene};
use std::path::PathBuf;
use std::time::Instant;

#[derive(Serialize)]
struct Row {
    law: &'static str,
    active_dependencies: Vec<&'static str>,
    n_dofs: usize,
    n_gaps: usize,
    steps: u64,
    newton_iterations: u64,
    factorisations: u64,
    cpu_s: f64,
    cpu_per_step_us: f64,
    newton_per_step: f64,
    /// One `add_forces` call over all gaps, microseconds.
    forces_call_us: f64,
    /// One `add_tangents` call (∂F/∂λ' only, as the transient's iteration matrix), microseconds.
    tangents_call_us: f64,
    /// One `add_tangents` call with C_f = ∂F/∂v too, microseconds.
    tangents_with_cf_us: f64,
    growth_rate_check: Option<f64>,
}

fn per_call_us(mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    let mut reps = 0u64;
    while start.elapsed().as_secs_f64() < 0.2 {
        for _ in 0..100 {
            f();
        }
        reps += 100;
    }
    1e6 * start.elapsed().as_secs_f64() / reps as f64
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let pads: usize = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(60);
    let out = std::env::args()
        .nth(2)
        .unwrap_or_else(|| "target/bench/bench_effects.json".into());
    let dir = std::env::temp_dir().join(format!("squeal-bench-effects-{}", std::process::id()));
    models::pad_row(pads).write(&dir, "row")?;
    let laws: [(&str, &str, Vec<&str>); 3] = [
        ("constant", r#"{ kind = "constant", mu = 0.45 }"#, vec![]),
        (
            "linear_speed",
            r#"{ kind = "linear_speed", mu0 = 0.5, slope = -0.05 }"#,
            vec!["speed"],
        ),
        (
            "table_pvT",
            r#"{ kind = "table", pressures = [0.0, 10.0, 20.0], speeds = [0.0, 1.0, 2.0], temperatures = [0.0, 100.0], values = [0.5, 0.48, 0.45, 0.43, 0.40, 0.38, 0.5, 0.48, 0.44, 0.42, 0.38, 0.36, 0.5, 0.48, 0.43, 0.41, 0.36, 0.34] }"#,
            vec!["pressure", "speed", "temperature"],
        ),
    ];
    let mut rows = Vec::new();
    for (name, law, deps) in laws {
        let text = format!(
            "[model]\nfrom = \"op4\"\nmatrices = \"row.op4\"\ndofmap = \"row.dofmap.json\"\n\
             gaps = \"row.gaps.csv\"\ntemperature = 50.0\n\n[friction]\nlaw = {law}\n\n\
             [rotor]\nrpm = {}\n\n[loads]\npmax = 0.05\ntload = 0.05\n\n\
             [transient]\ntfinal = 2.0\nrtol1 = 1e-6\natol1 = 1e-10\nnrstrt = 0\n\n\
             [output]\nhistory = false\n",
            models::RPM
        );
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text)?;
        let scene = Scene::load(&path, &[])?;
        let run_dir = RunDir::create(&dir.join(format!("run-{name}")))?;
        let model = model::build(&scene, &run_dir, &Progress::quiet())?;
        let problem = system::problem(&scene, &model)?;
        let spec = scene.transient.clone().unwrap_or_default();
        let (y0, yp0) = initial_state(&problem, spec.tolint)?;
        let n = model.n();
        let ng = model.gap_geometry.len();
        let grid: Vec<f64> = (0..=200).map(|k| spec.tfinal * k as f64 / 200.0).collect();
        let r = integrate(
            &problem,
            &spec,
            Method::Bdf {
                rtol: spec.rtol1,
                max_order: 2,
            },
            &y0,
            &yp0,
            &grid,
            &[0],
            false,
        )?;
        let (v, lam) = (&y0[..n], &yp0[n..n + ng]);
        let gaps = &problem.gaps;
        let mut f = vec![0.0; n];
        let forces_us = per_call_us(|| {
            f.fill(0.0);
            gaps.add_forces(v, lam, &mut f).unwrap();
        });
        let mut dl = Mat::<f64>::zeros(n, ng);
        let tangents_us = per_call_us(|| {
            gaps.add_tangents(v, lam, &mut dl, None).unwrap();
        });
        let mut dv = Mat::<f64>::zeros(n, n);
        let tangents_cf_us = per_call_us(|| {
            gaps.add_tangents(v, lam, &mut dl, Some(&mut dv)).unwrap();
        });
        let x: Vec<f64> = r.v.iter().map(|v| v[0]).collect();
        let vd = squeal_pipeline::verdict::analyse(&r.t, &x, 0.05);
        let row = Row {
            law: name,
            active_dependencies: deps,
            n_dofs: n,
            n_gaps: ng,
            steps: r.steps,
            newton_iterations: r.newton_iterations,
            factorisations: r.factorisations,
            cpu_s: r.cpu_s,
            cpu_per_step_us: 1e6 * r.cpu_s / r.steps.max(1) as f64,
            newton_per_step: r.newton_iterations as f64 / r.steps.max(1) as f64,
            forces_call_us: forces_us,
            tangents_call_us: tangents_us,
            tangents_with_cf_us: tangents_cf_us,
            growth_rate_check: vd.growth_rate_per_s,
        };
        println!(
            "{:<13} n = {n}, ng = {ng}: {} steps, {:.1} us/step, {:.2} Newton/step, {} facts; \
             add_forces {:.2} us, add_tangents {:.2} us (with C_f {:.2} us)",
            row.law,
            row.steps,
            row.cpu_per_step_us,
            row.newton_per_step,
            row.factorisations,
            row.forces_call_us,
            row.tangents_call_us,
            row.tangents_with_cf_us
        );
        rows.push(row);
    }
    let _ = std::fs::remove_dir_all(&dir);
    let out = PathBuf::from(out);
    if let Some(p) = out.parent() {
        std::fs::create_dir_all(p)?;
    }
    std::fs::write(&out, serde_json::to_string_pretty(&rows)?)?;
    println!("wrote {}", out.display());
    Ok(())
}
