//! Writes the CEA matrices of a scene at its steady sliding state (M, K, B, G, D, C_f as raw
//! little-endian f64, row-major, plus `dump.json` with the sizes and the solver options) for
//! `squeal-solver`'s `cea_profile` example, which profiles the CEA without rebuilding the model.
//!
//! ```text
//! cargo run --release -p squeal-pipeline --example cea_dump -- [SCENE] DIR
//! ```

use squeal_pipeline::stages::cea::{banded, compute, tangents, CeaArgs};
use squeal_pipeline::stages::model;
use squeal_pipeline::{progress::Progress, RunDir, Scene};
use std::path::PathBuf;

fn write(dir: &std::path::Path, name: &str, a: &faer::Mat<f64>) -> std::io::Result<[usize; 2]> {
    let mut b = Vec::with_capacity(a.nrows() * a.ncols() * 8);
    for i in 0..a.nrows() {
        for j in 0..a.ncols() {
            b.extend_from_slice(&a[(i, j)].to_le_bytes());
        }
    }
    std::fs::write(dir.join(format!("{name}.f64")), b)?;
    Ok([a.nrows(), a.ncols()])
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let argv: Vec<String> = std::env::args().skip(1).collect();
    let (scene_path, out) = match argv.as_slice() {
        [d] => (
            PathBuf::from("examples/transient/sample-brake-case2.toml"),
            PathBuf::from(d),
        ),
        [s, d] => (PathBuf::from(s), PathBuf::from(d)),
        _ => return Err("usage: cea_dump [SCENE] DIR".into()),
    };
    std::fs::create_dir_all(&out)?;
    let tmp = std::env::temp_dir().join(format!("squeal-cea-dump-{}", std::process::id()));
    let dir = RunDir::create(&tmp)?;
    let sets = vec![
        "cea.friction_damping=true".to_string(),
        "cea.solver.method=\"exact\"".to_string(),
        "cea.solver.projection.refine.enabled=false".to_string(),
        "cea.solver.compute_shapes=false".to_string(),
    ];
    let scene = Scene::load(&scene_path, &sets)?;
    let m = model::build(&scene, &dir, &Progress::quiet())?;
    // A cheap projected run only to get the spec and the linearisation.
    let scene_p = Scene::load(
        &scene_path,
        &[
            "cea.friction_damping=true".to_string(),
            "cea.solver.method=\"projection\"".to_string(),
            "cea.solver.projection.refine.enabled=false".to_string(),
        ],
    )?;
    let c = compute(&scene_p, &m, &Progress::quiet(), &CeaArgs::default())?;
    let sys = tangents::cea_matrices(&c.problem, &c.lin, c.spec.friction_damping)?;
    let mut meta = serde_json::Map::new();
    meta.insert("m".into(), serde_json::to_value(write(&out, "m", &sys.m)?)?);
    meta.insert("k".into(), serde_json::to_value(write(&out, "k", &sys.k)?)?);
    for (name, a) in [
        ("b", &sys.b),
        ("g", &sys.g),
        ("d", &sys.d),
        ("c_f", &sys.c_f),
    ] {
        if let Some(a) = a {
            meta.insert(name.into(), serde_json::to_value(write(&out, name, a)?)?);
        }
    }
    let band = match (scene.band_hz(), c.spec.max_frequency_hz) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    let mut opts = banded(&c.spec.solver, band);
    opts.method = squeal_solver::cea::CeaMethod::Auto;
    opts.projection.refine.enabled = true;
    meta.insert("options".into(), serde_json::to_value(&opts)?);
    std::fs::write(
        out.join("dump.json"),
        serde_json::to_string_pretty(&serde_json::Value::Object(meta))?,
    )?;
    eprintln!("wrote {}", out.display());
    let _ = std::fs::remove_dir_all(&tmp);
    Ok(())
}
