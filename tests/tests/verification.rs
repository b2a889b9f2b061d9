//! Verification scenes (`examples/verification/*.toml`) run through the whole front end
//! (scene → gmsh → .msh reader → elements → shift-invert Lanczos), against published or analytic
//! frequencies in `tests/data/verification.json`, each with its source.

use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::modes;
use squeal_pipeline::{RunDir, Scene};
use squeal_tests::{distinct, fresh_out_dir, workspace_root};

fn check_scene(name: &str) {
    let root = workspace_root();
    let refs: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(root.join("tests/data/verification.json")).unwrap(),
    )
    .unwrap();
    let r = &refs[name];
    let expected: Vec<f64> = serde_json::from_value(r["frequencies_hz"].clone()).unwrap();
    let skip = r["skip_rigid"].as_u64().unwrap() as usize;
    let tol = r["rel_tol"].as_f64().unwrap();

    let scene = Scene::load(
        &root.join(format!("examples/verification/{name}.toml")),
        &[],
    )
    .unwrap_or_else(|e| panic!("{name}: {e}"));
    let out = fresh_out_dir(env!("CARGO_TARGET_TMPDIR"), name);
    let dir = RunDir::create(&out).unwrap();
    let report = modes::run(&scene, None, &dir, &Progress::quiet())
        .unwrap_or_else(|e| panic!("{name}: {e}"));

    let f = &report.frequencies_hz;
    // Rigid-body modes: tiny next to the first elastic frequency.
    for (i, &fr) in f.iter().take(skip).enumerate() {
        assert!(
            fr.abs() < 1e-3 * f[skip],
            "{name}: mode {} should be rigid, got {fr} Hz",
            i + 1
        );
    }
    let elastic = &f[skip..];
    let got = if r["distinct"].as_bool() == Some(true) {
        distinct(elastic, 1e-6)
    } else {
        elastic.to_vec()
    };
    assert!(
        got.len() >= expected.len(),
        "{name}: {} modes, want {}",
        got.len(),
        expected.len()
    );
    for (i, (&g, &e)) in got.iter().zip(&expected).enumerate() {
        let rel = (g - e) / e;
        eprintln!(
            "{name}: mode {:>2}: {g:10.3} Hz vs {e:10.3} Hz ({:+.3} %)",
            i + 1,
            100.0 * rel
        );
        assert!(
            rel.abs() <= tol,
            "{name}: mode {} is {g} Hz, reference {e} Hz (tolerance {tol})",
            i + 1
        );
    }
    // Every output the verb promises is there.
    for file in [
        "modes.json",
        "modes.vtu",
        "summary.json",
        "scene.resolved.toml",
    ] {
        assert!(out.join(file).is_file(), "{name}: {file} missing");
    }
}

#[test]
fn nafems_fv52_hex20_4x4x1() {
    check_scene("fv52-hex20");
}

#[test]
fn nafems_fv52_hex8_incompatible_8x8x3() {
    check_scene("fv52-hex8i");
}

#[test]
fn cantilever_hex20_first_bending() {
    check_scene("cantilever-hex20");
}

#[test]
fn clamped_annular_plate_hex20() {
    check_scene("annular-plate-hex20");
}
