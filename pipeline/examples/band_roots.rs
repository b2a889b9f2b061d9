//! Issue 22 item 2's acceptance on a brake too big for a test: the band-limited model's own
//! in-band roots against the full reduced model's CEA.
//!
//! The reference is the pipeline's CEA of the full reduced model at the loaded steady sliding
//! state, friction damping on (the condensed model's linear part), solved exactly
//! (`cea.solver.method = "exact"`: the dense first-order eigenproblem, no projection whose
//! own error would blur the comparison). The condensed model is linearised at its own
//! equilibrium (`squeal_solver::hb::hopf::linearised_roots`: Newton on its outputs), as
//! `pipeline/tests/band.rs` does on the coarse study brake. Each in-band CEA root is paired
//! with the condensed root nearest in frequency; the worst relative differences in f and in
//! Re p are the acceptance figures (≤ 0.05 % and ≤ 0.5 %).
//!
//! ```text
//! cargo build --release -p squeal-pipeline --example band_roots
//! target/release/examples/band_roots SCENE.toml [--set key=value ...] [--name NAME]
//!     [--out docs/bench/band_roots_NAME.json]
//! ```

use serde_json::json;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::cea::{self, CeaArgs};
use squeal_pipeline::stages::model;
use squeal_pipeline::stages::transient::{band, system};
use squeal_pipeline::{RunDir, Scene};
use squeal_solver::hb::hopf::linearised_roots;
use std::path::PathBuf;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let mut scene_path: Option<PathBuf> = None;
    let mut sets: Vec<String> = Vec::new();
    let mut name = "brake".to_string();
    let mut out: Option<PathBuf> = None;
    while let Some(a) = args.next() {
        match a.as_str() {
            "--set" => sets.push(args.next().ok_or("--set needs key=value")?),
            "--name" => name = args.next().ok_or("--name needs a name")?,
            "--out" => out = Some(args.next().ok_or("--out needs a file")?.into()),
            s => scene_path = Some(s.into()),
        }
    }
    let scene_path = scene_path.ok_or("usage: band_roots SCENE.toml [--set key=value ...]")?;
    let out = out.unwrap_or_else(|| PathBuf::from(format!("docs/bench/band_roots_{name}.json")));
    let mut all = sets.clone();
    all.extend([
        "transient.band_limited=true".to_string(),
        "cea.friction_damping=true".to_string(),
        "cea.solver.method=\"exact\"".to_string(),
    ]);
    let scene = Scene::load(&scene_path, &all)?;
    let band_hz = scene.band_hz().ok_or("the scene has no band")?;
    let tmp = std::env::temp_dir().join(format!("band_roots_{}", std::process::id()));
    let quiet = Progress::quiet();
    let t = Instant::now();
    let m = model::build(&scene, &RunDir::create(&tmp)?, &quiet)?;
    let build_s = t.elapsed().as_secs_f64();
    eprintln!(
        "model: {} DOFs, {} gaps, {build_s:.1} s",
        m.n(),
        m.gap_geometry.len()
    );
    let t = Instant::now();
    let c = cea::compute(&scene, &m, &quiet, &CeaArgs::default())?;
    let cea_s = t.elapsed().as_secs_f64();
    let t = Instant::now();
    let problem = system::problem(&scene, &m)?;
    let mut b = band::build(&scene, &m, &problem)?;
    let band_s = t.elapsed().as_secs_f64();
    eprintln!("{}", b.report.line());
    let t = Instant::now();
    let roots = linearised_roots(&mut b.system, b.t_ref, 1.0)?;
    let roots_s = t.elapsed().as_secs_f64();
    let two_pi = 2.0 * std::f64::consts::PI;
    let (mut worst_f, mut worst_re, mut worst_re_abs) = (0.0f64, 0.0f64, 0.0f64);
    let mut pairs = Vec::new();
    for mode in c
        .out
        .modes
        .iter()
        .filter(|m| m.frequency_hz > 0.0 && m.frequency_hz <= band_hz)
    {
        let p = roots
            .iter()
            .filter(|p| p.im > 0.0)
            .min_by(|a, b| {
                let d = |p: &&squeal_solver::cea::Cplx| (p.im / two_pi - mode.frequency_hz).abs();
                d(a).total_cmp(&d(b))
            })
            .ok_or("the condensed model has no oscillating root")?;
        let f = p.im / two_pi;
        let df = (f - mode.frequency_hz).abs() / mode.frequency_hz;
        let dre = (p.re - mode.real_part).abs() / mode.real_part.abs();
        worst_f = worst_f.max(df);
        worst_re = worst_re.max(dre);
        worst_re_abs = worst_re_abs.max((p.re - mode.real_part).abs());
        eprintln!(
            "{:10.2} Hz {:+10.3} /s | condensed {:10.2} Hz {:+10.3} /s | df {df:.1e} dRe {dre:.1e}",
            mode.frequency_hz, mode.real_part, f, p.re
        );
        pairs.push(json!({
            "cea": {"frequency_hz": mode.frequency_hz, "real_part": mode.real_part},
            "condensed": {"frequency_hz": f, "real_part": p.re},
            "rel_diff_frequency": df,
            "rel_diff_real_part": dre,
        }));
    }
    eprintln!(
        "{} in-band roots; worst: f {worst_f:.2e} (limit 5e-4), Re p {worst_re:.2e} (limit 5e-3), |dRe p| {worst_re_abs:.3e} /s",
        pairs.len()
    );
    let doc = json!({
        "what": "issue 22 item 2: the band-limited model's in-band roots (linearised at its own equilibrium) against the exact CEA of the full reduced model at the loaded steady sliding state, friction damping on",
        "scene": scene_path,
        "overrides": sets,
        "n_dofs": m.n(),
        "n_gaps": m.gap_geometry.len(),
        "band_hz": band_hz,
        "band_model": b.report,
        "n_in_band": pairs.len(),
        "worst_rel_diff_frequency": worst_f,
        "worst_rel_diff_real_part": worst_re,
        "worst_abs_diff_real_part_per_s": worst_re_abs,
        "acceptance": {"frequency": 5e-4, "real_part": 5e-3,
            "met": worst_f <= 5e-4 && worst_re <= 5e-3},
        "time_s": {"model": build_s, "cea_exact": cea_s, "band_model": band_s, "linearised_roots": roots_s},
        "roots": pairs,
    });
    std::fs::write(&out, serde_json::to_string_pretty(&doc)? + "\n")?;
    eprintln!("wrote {}", out.display());
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}
