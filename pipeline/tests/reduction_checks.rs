//! The Craig–Bampton checks through the model builder: a component held by fixed DOFs has no
//! rigid-body motion in its free DOFs, so its rigid-body mass is not compared (the tiny brake's
//! pad, held at its abutment `x0` in x and y, used to warn on every run: "rigid-body mass:
//! reduced vs full relative error 1.54e-1").

use squeal_pipeline::progress::Progress;
use squeal_pipeline::stages::model;
use squeal_pipeline::{RunDir, Scene};

#[test]
fn held_components_skip_the_rigid_body_mass_check() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .parent()
        .unwrap();
    let file = root.join("examples/transient/tiny-brake.toml");
    let dir = std::env::temp_dir().join(format!("squeal-rbcheck-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    let text = std::fs::read_to_string(&file).unwrap();
    let scene = Scene::from_toml_str(&text, file.parent().unwrap().to_path_buf(), &[]).unwrap();
    let run = RunDir::create(&dir.join("run")).unwrap();
    let m = model::build(&scene, &run, &Progress::quiet()).unwrap();
    assert_eq!(m.checks.len(), 2, "both components checked");
    for (name, c) in &m.checks {
        assert!(
            c.rigid.is_none(),
            "{name}: rigid-body mass compared on a held component"
        );
        // The other checks still ran: the reduced modes against the full component's.
        assert!(!c.frequencies.is_empty(), "{name}: no frequency comparison");
    }
    let rigid_warnings: Vec<_> = m
        .warnings
        .iter()
        .filter(|w| w.to_string().contains("rigid-body mass"))
        .collect();
    assert!(rigid_warnings.is_empty(), "{rigid_warnings:?}");
    let _ = std::fs::remove_dir_all(&dir);
}
