//! CEA of a brake-sized reduced model (issue 13 item 3): the hex20 sample brake
//! (`examples/transient/sample-brake-case2.toml`: 2153 reduced DOFs, 234 gaps) at its steady
//! sliding state, three ways, in one run:
//!
//! - `projected`: the default for this size (`auto`): the band-limited basis (real modes up to
//!   2.5 × the 10 kHz band), then every in-band unstable root refined exactly by shift-invert
//!   Arnoldi on the full first-order operator;
//! - `dense`: the exact dense CEA (`cea.solver.method = "exact"`; `--no-dense` skips it), the
//!   reference: each of its in-band unstable roots is compared with the refined one;
//! - `sweep`: the 50-point friction sweep μ = 0.1…0.9 (constant μ) on the same model, its
//!   in-band critical μ moved to the crossing of the exact root (`critical` in the JSON);
//! - `dense_at` (with `--dense-at MU,MU,…`): the exact dense CEA at those μ with the sweep's
//!   steady state, the reference for the critical μ (in-band roots with Re p > −1 /s).
//!
//! With `--npy DIR` it also writes what `python/bench/bench_cea_scipy.py` reads: the real
//! first-order matrix of the exact method (`first_order.npy`, size 2(n − ng); its eigenvalues
//! are the roots) and `squeal_roots.json` (the dense roots, the refined ones, the seconds).
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example bench_cea_brake
//! target/release/examples/bench_cea_brake [SCENE] [--out docs/bench/cea_brake.json]
//!     [--npy DIR] [--no-dense] [--sweep N] [--dense-at MU,MU,...]
//! ```
//! (gmsh is found as for `squeal`: `SQUEAL_GMSH`, `.venv/bin/gmsh`, or `PATH`.)

use serde_json::{json, Value};
use squeal_pipeline::history::npy::write_npy;
use squeal_pipeline::scene::CeaSweepSpec;
use squeal_pipeline::stages::cea::{compute, sweep, tangents, CeaArgs, CeaComputed};
use squeal_pipeline::stages::model;
use squeal_pipeline::{progress::Progress, RunDir, Scene};
use squeal_solver::cea::{complex_eigen, first_order_matrix, CeaMethod, CeaOptions, Mode};
use std::path::{Path, PathBuf};
use std::time::Instant;

fn roots(modes: &[Mode]) -> Vec<[f64; 2]> {
    modes
        .iter()
        .map(|m| [m.eigenvalue.re, m.eigenvalue.im])
        .collect()
}

fn in_band_unstable(c: &CeaComputed) -> Vec<Mode> {
    c.out.unstable.iter().map(|&i| c.modes[i].clone()).collect()
}

fn run(
    path: &Path,
    sets: &[&str],
    m: &model::ReducedModel,
    args: &CeaArgs,
) -> Result<(CeaComputed, f64), Box<dyn std::error::Error>> {
    let mut overrides: Vec<String> = vec!["cea.friction_damping=true".into()];
    overrides.extend(sets.iter().map(|s| s.to_string()));
    let scene = Scene::load(path, &overrides)?;
    let t = Instant::now();
    let c = compute(&scene, m, &Progress::quiet(), args)?;
    Ok((c, t.elapsed().as_secs_f64()))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut scene_path = PathBuf::from("examples/transient/sample-brake-case2.toml");
    let mut out = PathBuf::from("docs/bench/cea_brake.json");
    let (mut npy, mut dense, mut n_sweep) = (None::<PathBuf>, true, 50usize);
    let mut dense_at: Vec<f64> = Vec::new();
    let mut i = 0;
    while i < argv.len() {
        match argv[i].as_str() {
            "--out" => {
                out = argv[i + 1].clone().into();
                i += 1;
            }
            "--npy" => {
                npy = Some(argv[i + 1].clone().into());
                i += 1;
            }
            "--sweep" => {
                n_sweep = argv[i + 1].parse()?;
                i += 1;
            }
            "--no-dense" => dense = false,
            "--dense-at" => {
                dense_at = argv[i + 1]
                    .split(',')
                    .map(|x| x.trim().parse())
                    .collect::<Result<_, _>>()?;
                i += 1;
            }
            s => scene_path = s.into(),
        }
        i += 1;
    }
    let tmp = std::env::temp_dir().join(format!("squeal-bench-cea-{}", std::process::id()));
    let dir = RunDir::create(&tmp)?;
    let scene = Scene::load(&scene_path, &["cea.friction_damping=true".into()])?;
    let t = Instant::now();
    let m = model::build(&scene, &dir, &Progress::quiet())?;
    let build_s = t.elapsed().as_secs_f64();
    let (n, ng) = (m.n(), m.gap_geometry.len());
    eprintln!("model: {n} DOFs, {ng} gaps, built in {build_s:.1} s");
    let args = CeaArgs::default();

    let (p, projected_s) = run(&scene_path, &[], &m, &args)?;
    let st = &p.out.stats;
    eprintln!(
        "projected + refined: {projected_s:.2} s (basis {:.2} s, {} modes, {} unstable in band)",
        st.time_basis_s,
        st.n_basis,
        p.out.unstable.len()
    );
    let refined = in_band_unstable(&p);
    let mut doc = json!({
        "what": "CEA of the hex20 sample brake at its steady sliding state (case-2 scene)",
        "scene": scene_path.display().to_string(),
        "n_dofs": n, "n_gaps": ng, "n_reduced": n - ng,
        "threads": faer::get_global_parallelism().degree(),
        "model_build_s": build_s,
        "projected": {
            "wall_s": projected_s,
            "stats": serde_json::to_value(st)?,
            "in_band_unstable": roots(&refined),
        },
    });
    let mut dense_roots: Option<Vec<Mode>> = None;
    if dense {
        let (d, dense_s) = run(&scene_path, &["cea.solver.method=\"exact\""], &m, &args)?;
        let exact = in_band_unstable(&d);
        eprintln!(
            "dense exact: {dense_s:.1} s, {} unstable in band",
            exact.len()
        );
        // Each dense in-band unstable root against the nearest refined root.
        let mut worst: f64 = 0.0;
        let pairs: Vec<Value> = exact
            .iter()
            .map(|e| {
                let r = refined
                    .iter()
                    .min_by(|a, b| {
                        (a.eigenvalue - e.eigenvalue)
                            .norm()
                            .total_cmp(&(b.eigenvalue - e.eigenvalue).norm())
                    })
                    .map(|r| r.eigenvalue);
                let rel = r.map(|r| (r - e.eigenvalue).norm() / e.eigenvalue.norm());
                worst = worst.max(rel.unwrap_or(f64::INFINITY));
                json!({"dense": [e.eigenvalue.re, e.eigenvalue.im],
                       "refined": r.map(|r| [r.re, r.im]), "rel_diff": rel})
            })
            .collect();
        // Each refined in-band unstable root against the nearest dense root of any stability
        // (a root near neutral can be called unstable by one method and not the other: the
        // threshold is `unstable_tol` × the largest |p| each method computed).
        let reverse: Vec<Value> = refined
            .iter()
            .map(|r| {
                let e = d
                    .modes
                    .iter()
                    .min_by(|a, b| {
                        (a.eigenvalue - r.eigenvalue)
                            .norm()
                            .total_cmp(&(b.eigenvalue - r.eigenvalue).norm())
                    })
                    .map(|e| (e.eigenvalue, e.unstable));
                json!({"refined": [r.eigenvalue.re, r.eigenvalue.im],
                       "dense": e.map(|e| [e.0.re, e.0.im]),
                       "dense_unstable": e.map(|e| e.1),
                       "rel_diff": e.map(|e| (e.0 - r.eigenvalue).norm() / e.0.norm())})
            })
            .collect();
        doc["dense"] = json!({
            "unstable_threshold": d.out.stats.spectral_radius * d.spec.solver.unstable_tol,
            "projected_unstable_threshold": st.spectral_radius * p.spec.solver.unstable_tol,
            "refined_vs_nearest_dense": reverse,
            "wall_s": dense_s,
            "time_reduce_s": d.out.stats.time_reduce_s,
            "time_eigen_s": d.out.stats.time_eigen_s,
            "n_unstable_in_band": exact.len(),
            "n_unstable_in_band_refined": refined.len(),
            "max_rel_diff_refined_vs_dense": worst,
            "pairs": pairs,
        });
        dense_roots = Some(d.modes.clone());
    }
    if let Some(dir) = &npy {
        std::fs::create_dir_all(dir)?;
        let sys = tangents::cea_matrices(&p.problem, &p.lin, p.spec.friction_damping)?;
        let t = Instant::now();
        let a = first_order_matrix(&sys, &p.spec.solver)?;
        let form_s = t.elapsed().as_secs_f64();
        let k = a.nrows();
        let data: Vec<f64> = (0..k)
            .flat_map(|i| (0..k).map(move |j| (i, j)))
            .map(|(i, j)| a[(i, j)])
            .collect();
        write_npy(&dir.join("first_order.npy"), &data, k)?;
        let exact_all = dense_roots.as_deref().map(roots);
        std::fs::write(
            dir.join("squeal_roots.json"),
            serde_json::to_string_pretty(&json!({
                "n_dofs": n, "n_gaps": ng, "size": k,
                "band_hz": p.out.outside_band.band_hz,
                "first_order_form_s": form_s,
                "projected_s": projected_s,
                "dense_s": doc["dense"]["wall_s"],
                "refine": serde_json::to_value(&st.refine)?,
                "refined_in_band_unstable": roots(&refined),
                "dense_all": exact_all,
            }))?,
        )?;
        eprintln!(
            "wrote {} ({k} x {k})",
            dir.join("first_order.npy").display()
        );
    }
    if n_sweep > 0 {
        let set = format!("cea.sweep.mu=[0.1, 0.9, {n_sweep}]");
        let (s, sweep_s) = run(&scene_path, &[&set], &m, &args)?;
        let rep = s.sweep.as_ref().expect("a sweep ran");
        eprintln!(
            "sweep of {n_sweep} points: {sweep_s:.1} s (sweep {:.1} s; solves {}, checks {:.1} s), lowest critical mu {:?}",
            rep.stats.time_s, rep.stats.n_solves, rep.stats.time_check_s, rep.lowest_critical_mu
        );
        let band = p.out.outside_band.band_hz.unwrap_or(f64::INFINITY);
        let mut critical: Vec<Value> = rep
            .tracks
            .iter()
            .filter_map(|t| t.critical.as_ref().map(|c| (t.id, c)))
            .map(|(id, c)| {
                json!({"track": id, "in_band": c.frequency_hz <= band,
                       "critical": serde_json::to_value(c).unwrap_or(Value::Null)})
            })
            .collect();
        critical.sort_by(|a, b| {
            let m = |v: &Value| v["critical"]["mu"].as_f64().unwrap_or(f64::INFINITY);
            m(a).total_cmp(&m(b))
        });
        let lowest_in_band = critical
            .iter()
            .find(|c| c["in_band"] == json!(true))
            .map(|c| c["critical"]["mu"].clone());
        eprintln!("lowest in-band critical mu {lowest_in_band:?}");
        doc["sweep"] = json!({
            "points": n_sweep,
            "mu": [0.1, 0.9],
            "wall_s_with_single_cea": sweep_s,
            "sweep_s": rep.stats.time_s,
            "per_point_s": rep.stats.time_s / n_sweep as f64,
            "stats": serde_json::to_value(&rep.stats)?,
            "steady_states": serde_json::to_value(&rep.steady_states)?,
            "lowest_critical_mu": rep.lowest_critical_mu,
            "lowest_in_band_critical_mu": lowest_in_band,
            "band_hz": band,
            "n_couplings": rep.couplings.len(),
            "critical": critical,
        });
    }
    if !dense_at.is_empty() {
        // The exact dense CEA at each μ, with the sweep's steady state and tangents.
        let sw = CeaSweepSpec::default();
        let opts = CeaOptions {
            method: CeaMethod::Exact,
            ..p.spec.solver.clone()
        };
        let band = p.out.outside_band.band_hz.unwrap_or(f64::INFINITY);
        let mut out = Vec::new();
        for &mu in &dense_at {
            let t = Instant::now();
            let sys = sweep::matrices_at(&p.problem, &p.lin, &p.spec, &sw, mu, None)?;
            let r = complex_eigen(&sys, &opts)?;
            let wall_s = t.elapsed().as_secs_f64();
            let near: Vec<[f64; 2]> = r
                .modes
                .iter()
                .filter(|x| x.frequency_hz <= band && x.real_part > -1.0)
                .map(|x| [x.eigenvalue.re, x.eigenvalue.im])
                .collect();
            eprintln!("dense exact at mu = {mu}: {wall_s:.1} s, in-band Re p > -1: {near:?}");
            out.push(json!({
                "mu": mu, "wall_s": wall_s,
                "unstable_threshold": r.stats.spectral_radius * opts.unstable_tol,
                "in_band_re_above_minus_1": near,
            }));
        }
        doc["dense_at"] = Value::Array(out);
    }
    if let Some(parent) = out.parent() {
        std::fs::create_dir_all(parent)?;
    }
    std::fs::write(&out, serde_json::to_string_pretty(&doc)? + "\n")?;
    println!("{}", serde_json::to_string_pretty(&doc)?);
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}
