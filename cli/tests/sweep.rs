//! System tests of `squeal sweep` and the reduced-model cache on the tiny brake
//! (examples/transient/tiny-brake.toml with a `[cea]` table): a mesh parameter builds a model
//! per value, μ builds once; a model read from the cache equals a fresh build bit for bit (so
//! CEA results are identical); a damaged entry is rebuilt; a bad `--param` names the key.

mod common;
use common::{json, root, run, squeal, tmp};

use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::model::{self, ModelCache};
use squeal_pipeline::stages::{cea, sweep};
use squeal_pipeline::{RunDir, Scene};
use std::path::{Path, PathBuf};

fn quiet() -> Progress {
    Progress::quiet()
}

/// The tiny brake with a `[cea]` table, written into `dir`.
fn tiny_scene(dir: &Path) -> PathBuf {
    let text = std::fs::read_to_string(root().join("examples/transient/tiny-brake.toml")).unwrap();
    let p = dir.join("tiny.toml");
    std::fs::write(&p, format!("{text}\n[cea]\nmax_frequency_hz = 2000.0\n")).unwrap();
    p
}

fn hits(v: &serde_json::Value) -> Vec<bool> {
    v["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["cache_hit"].as_bool().expect("cache_hit"))
        .collect()
}

#[test]
fn mesh_parameter_builds_a_model_per_value_and_a_rerun_reads_them_all() {
    let dir = tmp("sweep_mesh_param");
    let scene = tiny_scene(&dir);
    let out = dir.join("out/lz");
    let sweep_cmd = || {
        let mut c = squeal();
        c.args(["-q", "sweep"])
            .arg(&scene)
            .args(["--param", "components.1.geometry.lz", "--values", "0.2,0.3"])
            .arg("--out")
            .arg(&out);
        c
    };
    let (ok, _, err) = run(&mut sweep_cmd());
    assert!(ok, "{err}");
    let rep = json(&out.join("sweep.json"));
    assert_eq!(hits(&rep), [false, false]);
    let keys: Vec<&str> = rep["points"]
        .as_array()
        .unwrap()
        .iter()
        .map(|p| p["cache_key"].as_str().unwrap())
        .collect();
    assert_ne!(keys[0], keys[1], "the pad thickness is in the model's key");
    // Default cache: beside the output folder.
    for k in &keys {
        assert!(dir
            .join("out/.squeal-cache")
            .join(k)
            .join("entry.json")
            .is_file());
    }
    for f in [
        "sweep.md",
        "summary.json",
        "sweep_indicators.png",
        "sweep_indicators.svg",
        "sweep_frequencies.png",
        "00_0.2/cea/cea.json",
        "01_0.3/cea/cea.json",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    for p in rep["points"].as_array().unwrap() {
        assert!(p["error"].is_null(), "{p}");
        let c = &p["cea"];
        assert!(c["n_unstable"].as_u64().unwrap() > 0, "{p}");
        assert!(c["max_real_part"].as_f64().unwrap() > 0.0, "{p}");
        assert!(c["min_damping_ratio"].as_f64().unwrap() < 0.0, "{p}");
    }
    let md = std::fs::read_to_string(out.join("sweep.md")).unwrap();
    assert!(md.contains("| `0.3` | miss |"), "{md}");
    // Same sweep again: every model comes from the cache, results unchanged.
    let (ok, _, err) = run(&mut sweep_cmd());
    assert!(ok, "{err}");
    let again = json(&out.join("sweep.json"));
    assert_eq!(hits(&again), [true, true]);
    for (a, b) in rep["points"]
        .as_array()
        .unwrap()
        .iter()
        .zip(again["points"].as_array().unwrap())
    {
        assert_eq!(a["cea"], b["cea"]);
    }
}

#[test]
fn mu_sweep_builds_once_and_cached_models_equal_fresh_builds() {
    let dir = tmp("sweep_mu");
    let scene_path = tiny_scene(&dir);
    let out = RunDir::create(&dir.join("out")).unwrap();
    let cache_dir = dir.join("cache");
    let args = sweep::SweepArgs {
        param: "friction.law.mu0".into(),
        values: vec!["0.3".into(), "0.6".into(), "0.9".into()],
        cache: Some(cache_dir.clone()),
        ..Default::default()
    };
    let base = Scene::load(&scene_path, &[]).unwrap();
    let rep = sweep::run(&base, "tiny", &out, &quiet(), &args).unwrap();
    let flags: Vec<Option<bool>> = rep.points.iter().map(|p| p.cache_hit).collect();
    assert_eq!(flags, [Some(false), Some(true), Some(true)]);
    assert_eq!((rep.n_built, rep.n_cached), (1, 2));
    assert!(rep
        .points
        .iter()
        .all(|p| p.cache_key == rep.points[0].cache_key));
    // Re p grows with μ on this brake.
    let re: Vec<f64> = rep
        .points
        .iter()
        .map(|p| p.cea.as_ref().unwrap().max_real_part.unwrap())
        .collect();
    assert!(re[0] < re[1] && re[1] < re[2], "{re:?}");

    // CEA at μ0 = 0.9 on a fresh build (no cache) = the sweep's, read from the cache.
    let scene = Scene::load(&scene_path, &["friction.law.mu0=0.9".into()]).unwrap();
    let fresh_dir = RunDir::create(&dir.join("fresh")).unwrap();
    cea::run(&scene, &fresh_dir, &quiet(), &cea::CeaArgs::default()).unwrap();
    let fresh = json(&fresh_dir.path("cea.json"));
    let cached = json(&out.path("02_0.9/cea/cea.json"));
    assert_eq!(fresh["modes"], cached["modes"]);
    assert_eq!(fresh["steady_state"], cached["steady_state"]);

    // The late parameters (rpm, P0, temperature, μ) are the operating point's: a cached model
    // and a built one have the same gap geometry, and the same gaps at the point.
    let sets: Vec<String> = [
        "friction.law.mu0=0.45",
        "rotor.rpm=17.5",
        "contact.0.p0=2.5",
        "contact.0.temperature=80.0",
        "loads.pmax=3.0",
        "damping.modal_ratio=0.02",
    ]
    .map(String::from)
    .to_vec();
    let scene = Scene::load(&scene_path, &sets).unwrap();
    let d = RunDir::create(&dir.join("late")).unwrap();
    let (from_cache, used) = ModelCache::new(&cache_dir)
        .get_or_build(&scene, &d, &quiet())
        .unwrap();
    assert!(used.hit, "{used:?}");
    let built = model::build(&scene, &d, &quiet()).unwrap();
    assert!(from_cache.k == built.k && from_cache.m == built.m);
    assert_eq!(from_cache.b.is_some(), built.b.is_some());
    assert_eq!(from_cache.p_brake, built.p_brake);
    assert_eq!(from_cache.gap_geometry, built.gap_geometry);
    let op = squeal_pipeline::problem::OperatingPoint::of(&scene);
    assert_eq!(op.gaps(&from_cache).unwrap(), op.gaps(&built).unwrap());
    assert_eq!(from_cache.gap_pairs, built.gap_pairs);
    assert_eq!(from_cache.dofs, built.dofs);
    assert_eq!(from_cache.grids, built.grids);
}

#[test]
fn damaged_cache_entries_are_rebuilt() {
    let dir = tmp("sweep_corrupt");
    let scene = Scene::load(&tiny_scene(&dir), &[]).unwrap();
    let run_dir = RunDir::create(&dir.join("run")).unwrap();
    let cache = ModelCache::new(dir.join("cache"));
    let (first, u) = cache.get_or_build(&scene, &run_dir, &quiet()).unwrap();
    assert!(!u.hit && u.note.is_none());
    let entry = PathBuf::from(&u.entry);
    // One flipped byte in the matrices.
    let op4 = entry.join("reduced.op4");
    let mut bytes = std::fs::read(&op4).unwrap();
    let mid = bytes.len() / 2;
    bytes[mid] ^= 0x40;
    std::fs::write(&op4, bytes).unwrap();
    let (m, u) = cache.get_or_build(&scene, &run_dir, &quiet()).unwrap();
    assert!(!u.hit, "{u:?}");
    assert!(u.note.as_deref().unwrap().contains("reduced.op4"), "{u:?}");
    assert!(m.k == first.k);
    // A truncated gap table.
    let gaps = entry.join("gaps.json");
    let text = std::fs::read(&gaps).unwrap();
    std::fs::write(&gaps, &text[..text.len() / 3]).unwrap();
    let (_, u) = cache.get_or_build(&scene, &run_dir, &quiet()).unwrap();
    assert!(
        !u.hit && u.note.as_deref().unwrap().contains("gaps.json"),
        "{u:?}"
    );
    // A missing description (e.g. a copy interrupted by hand).
    std::fs::remove_file(entry.join("entry.json")).unwrap();
    let (_, u) = cache.get_or_build(&scene, &run_dir, &quiet()).unwrap();
    assert!(!u.hit && u.note.is_some(), "{u:?}");
    // Rebuilt entries are good again.
    let (m, u) = cache.get_or_build(&scene, &run_dir, &quiet()).unwrap();
    assert!(u.hit && u.note.is_none(), "{u:?}");
    assert!(m.k == first.k && m.gap_geometry == first.gap_geometry);
    // No temporary or discarded folders are left behind (beside the entry, the component
    // reductions' folder `components/`, whose entries are complete ones only).
    let list = |d: PathBuf| -> Vec<String> {
        let mut v: Vec<String> = std::fs::read_dir(d)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        v.sort();
        v
    };
    // The advisory lock files `.lock-<key>` (README: a cache shared by many processes) stay
    // beside their entries by design: they are plain empty files, never folders.
    let is_lock = |d: &PathBuf, n: &String| n.starts_with(".lock-") && d.join(n).is_file();
    let cache_dir = dir.join("cache");
    let names: Vec<String> = list(cache_dir.clone())
        .into_iter()
        .filter(|n| !is_lock(&cache_dir, n))
        .collect();
    let mut want = vec![u.key, "components".to_string()];
    want.sort();
    assert_eq!(names, want, "{names:?}");
    let comps_dir = dir.join("cache").join("components");
    let comps: Vec<String> = list(comps_dir.clone())
        .into_iter()
        .filter(|n| !is_lock(&comps_dir, n))
        .collect();
    assert!(
        !comps.is_empty() && comps.iter().all(|n| !n.starts_with('.')),
        "{comps:?}"
    );
}

#[test]
fn a_bad_param_is_an_error_naming_the_key() {
    let dir = tmp("sweep_bad_param");
    let scene = tiny_scene(&dir);
    for (param, why) in [
        ("friction.law.muu", "unknown field `muu`"),
        ("components.5.geometry.lz", "out of range"),
        ("rotor.rpm.x", "is a value, not a table"),
    ] {
        let (ok, _, err) = run(squeal()
            .args(["-q", "sweep"])
            .arg(&scene)
            .args(["--param", param, "--values", "0.5,0.6"])
            .arg("--out")
            .arg(dir.join("out")));
        assert!(!ok, "{param}");
        assert!(err.contains(&format!("--param {param}")), "{err}");
        assert!(err.contains(why), "{err}");
    }
    assert!(
        !dir.join("out/sweep.json").exists(),
        "nothing runs on a bad key"
    );
    let (ok, _, err) = run(squeal().args(["-q", "sweep"]).arg(&scene).args([
        "--param",
        "rotor.rpm",
        "--values-range",
        "1:2",
    ]));
    assert!(!ok && err.contains("--values-range"), "{err}");
}
