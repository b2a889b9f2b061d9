//! Benchmark of the band-limited transient (`[transient] band_limited = true`, issue 22 item
//! 2) against the full reduced model on the study cases of a `squeal reproduce` study (default
//! examples/sample-brake/study.toml, cases 1, 2, 3, 7), each case run as `squeal reproduce`
//! runs it (the study's step cap and growth-phase window), once on each model: steps, µs per
//! step, the verdict and its deciding root beside the CEA's most unstable in-band root; and
//! the cost of the two limit-cycle routes on Hoffmann's model with a separating contact (the
//! scene of pipeline/tests/limit_cycle.rs): harmonic balance (`squeal limit-cycle`) against
//! the transient into the cycle.
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example bench_band
//! nice target/release/examples/bench_band [STUDY] [--cases 1,2,3,7] [--note TEXT]
//!     [--out docs/bench/band_transient.json]
//! ```

use serde_json::{json, Value};
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::cea::{self, CeaArgs};
use squeal_pipeline::stages::limit_cycle;
use squeal_pipeline::stages::model;
use squeal_pipeline::stages::reproduce::study::StudySpec;
use squeal_pipeline::stages::transient::{self, TransientOptions, TransientResult};
use squeal_pipeline::{RunDir, Scene};
use std::path::PathBuf;
use std::time::Instant;

fn run_json(r: &TransientResult, wall: f64) -> Value {
    json!({
        "verdict": r.verdict.state,
        "status": r.status,
        "steps": r.steps,
        "integrator_cpu_s": r.cpu_s,
        "bookkeeping_s": r.bookkeeping_s,
        "wall_s": wall,
        "us_per_step": 1e6 * r.cpu_s / r.steps.max(1) as f64,
        "growth_rate_per_s": r.verdict.growth_rate_per_s,
        "dominant_frequency_hz": r.verdict.dominant_frequency_hz,
        "h_max_window": r.verdict.h_max_window,
        "band_limited": r.band_limited,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let mut study_path = PathBuf::from("examples/sample-brake/study.toml");
    let mut cases: Vec<u32> = vec![1, 2, 3, 7];
    let mut out = PathBuf::from("docs/bench/band_transient.json");
    let mut note = "machine: 2 cores shared with other helpers' builds and tests".to_string();
    let mut brake_hb = false;
    let mut i = 0;
    while i < argv.len() {
        let next = argv.get(i + 1).cloned().unwrap_or_default();
        match argv[i].as_str() {
            "--cases" => {
                cases = next
                    .split(',')
                    .map(|s| s.trim().parse())
                    .collect::<Result<_, _>>()?
            }
            "--out" => out = next.into(),
            "--note" => note = next,
            "--brake-hb" => {
                brake_hb = true;
                i += 1;
                continue;
            }
            s => {
                study_path = s.into();
                i += 1;
                continue;
            }
        }
        i += 2;
    }
    let study = StudySpec::load(&study_path)?;
    let overrides = study.set.clone();
    let mut base = Scene::load(&study.base_path(), &overrides)?;
    base.set_all(&["cea.friction_damping=true".to_string()])?;
    let tmp = std::env::temp_dir().join(format!("bench_band_{}", std::process::id()));
    let quiet = Progress::quiet();
    let mut rows = Vec::new();
    for c in study.cases.iter().filter(|c| cases.contains(&c.case)) {
        let mut scene = base.clone();
        scene.set_all(&c.overrides(scene.contact.len())?)?;
        let spec = scene.transient.clone().unwrap_or_default();
        let h_max = transient::step_bound(&spec, scene.band_hz()).h_max;
        let cap = h_max.map(|h| (study.step_cap * spec.tfinal / h).ceil() as usize + 100);
        let opts = TransientOptions {
            step_cap: cap,
            stall_h: cap.and(h_max).map(|h| 1e-2 * h),
            ..Default::default()
        };
        let dir = RunDir::create(&tmp.join(format!("case{}", c.case)))?;
        let m = model::build(&scene, &dir, &quiet)?;
        let cea_c = cea::compute(&scene, &m, &quiet, &CeaArgs::default())?;
        let reference = cea_c
            .unstable()
            .into_iter()
            .max_by(|a, b| a.1.real_part.total_cmp(&b.1.real_part))
            .map(|(_, m)| json!({"frequency_hz": m.frequency_hz, "real_part": m.real_part}));
        let t0 = Instant::now();
        let full = transient::compute(&scene, &m, &quiet, &opts)?;
        let w_full = t0.elapsed().as_secs_f64();
        let mut banded = scene.clone();
        banded.set_all(&["transient.band_limited=true".to_string()])?;
        let t1 = Instant::now();
        let band = transient::compute(&banded, &m, &quiet, &opts)?;
        let w_band = t1.elapsed().as_secs_f64();
        eprintln!(
            "case {}: full {:?} {} steps {:.2} s; band {:?} {} steps {:.2} s",
            c.case,
            full.verdict.state,
            full.steps,
            full.cpu_s,
            band.verdict.state,
            band.steps,
            band.cpu_s
        );
        rows.push(json!({
            "case": c.case,
            "rtol1": spec.rtol1,
            "tfinal": spec.tfinal,
            "step_cap": cap,
            "cea_most_unstable": reference,
            "full": run_json(&full, w_full),
            "band": run_json(&band, w_band),
        }));
    }
    // The two limit-cycle routes on Hoffmann's model with separation.
    let hs = Scene::load(
        std::path::Path::new("examples/limit-cycle/hoffmann.toml"),
        &[],
    )?;
    let dir = RunDir::create(&tmp.join("hoffmann"))?;
    let hm = model::build(&hs, &dir, &quiet)?;
    let t0 = Instant::now();
    let lc = limit_cycle::compute(&hs, &hm, &quiet)?;
    let w_hb = t0.elapsed().as_secs_f64();
    let mut routes = vec![json!({
        "route": "harmonic_balance",
        "wall_s": w_hb,
        "frequency_hz": lc.modes.first().map(|m| m.frequency_hz),
        "peak_normal_velocity": lc.modes.first().map(|m| m.peak_normal_velocity),
        "harmonics": lc.modes.first().map(|m| m.detail.harmonics),
        "newton_iterations": lc.modes.first().map(|m| m.detail.newton_iterations),
        "branch_points": lc.modes.first().map(|m| m.detail.branch.len()),
    })];
    for (name, sets) in [
        ("transient_full", vec![]),
        (
            "transient_band",
            vec!["transient.band_limited=true".to_string()],
        ),
    ] {
        let mut s = hs.clone();
        s.set_all(&sets)?;
        let t = Instant::now();
        let r = transient::compute(&s, &hm, &quiet, &TransientOptions::default())?;
        let w = t.elapsed().as_secs_f64();
        routes.push(json!({
            "route": name,
            "wall_s": w,
            "steps": r.steps,
            "frequency_hz": r.limit_cycle.as_ref().map(|c| c.frequency_hz),
            "peak_normal_velocity": r.limit_cycle.as_ref().map(|c| c.peak_normal_velocity),
        }));
    }
    // The study brake's limit cycle (case 3, both pairs unilateral): HB against the
    // band-limited transient run into its cycle (--brake-hb).
    let mut brake = Value::Null;
    if brake_hb {
        if let Some(c) = study.cases.iter().find(|c| c.case == 3) {
            let mut scene = base.clone();
            scene.set_all(&c.overrides(scene.contact.len())?)?;
            let mut sets: Vec<String> = (0..scene.contact.len())
                .map(|i| format!("contact.{i}.separation=true"))
                .collect();
            sets.push("transient.band_limited=true".into());
            sets.push("transient.tfinal=0.02".into());
            scene.set_all(&sets)?;
            let dir = RunDir::create(&tmp.join("brake_hb"))?;
            let m = model::build(&scene, &dir, &quiet)?;
            let t = Instant::now();
            let r = transient::compute(&scene, &m, &quiet, &TransientOptions::default())?;
            let w_tr = t.elapsed().as_secs_f64();
            eprintln!(
                "brake transient: {:?}, {} steps, {w_tr:.1} s, cycle {:?}",
                r.verdict.state, r.steps, r.limit_cycle
            );
            let t = Instant::now();
            let lc = limit_cycle::compute(&scene, &m, &Progress::quiet())?;
            let w_hb = t.elapsed().as_secs_f64();
            let first = lc.modes.first();
            eprintln!(
                "brake HB: {w_hb:.1} s, {:?}",
                first.map(|m| (
                    m.reached,
                    m.frequency_hz,
                    m.peak_normal_velocity,
                    m.rms_normal_velocity,
                    &m.detail.status
                ))
            );
            brake = json!({
                "scene": "study case 3, contact.*.separation = true, band_limited, tfinal 0.02",
                "transient": {
                    "verdict": r.verdict.state, "steps": r.steps, "wall_s": w_tr,
                    "limit_cycle": r.limit_cycle,
                },
                "harmonic_balance": {
                    "wall_s": w_hb,
                    "modes": lc.modes.iter().map(|m| json!({
                        "root_frequency_hz": m.root_frequency_hz,
                        "root_real_part": m.root_real_part,
                        "reached": m.reached,
                        "status": m.detail.status,
                        "frequency_hz": m.frequency_hz,
                        "peak_normal_velocity": m.peak_normal_velocity,
                        "rms_normal_velocity": m.rms_normal_velocity,
                        "stable": m.stable,
                        "harmonics": m.detail.harmonics,
                        "time_s": m.detail.time_s,
                    })).collect::<Vec<_>>(),
                },
            });
        }
    }
    let doc = json!({
        "study_brake_limit_cycle": brake,
        "what": "band-limited transient (transient.band_limited, cut-off 2 x band) against the full reduced model on the study cases, as squeal reproduce runs them; and the cost of the limit-cycle routes on Hoffmann's model with a separating compliant contact",
        "study": study_path,
        "note": note,
        "profile": if cfg!(debug_assertions) { "dev" } else { "release" },
        "cases": rows,
        "limit_cycle_routes": routes,
    });
    if let Some(p) = out.parent() {
        std::fs::create_dir_all(p)?;
    }
    std::fs::write(&out, serde_json::to_string_pretty(&doc)? + "\n")?;
    let _ = std::fs::remove_dir_all(&tmp);
    eprintln!("wrote {}", out.display());
    Ok(())
}
