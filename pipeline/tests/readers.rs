//! Nastran and Abaqus components (`geometry = { kind = "bdf" | "inp", … }`, issue 23): the
//! same hex20 mesh through gmsh's `.msh`, pyNastran's `.bdf` and meshio's `.inp` (written by
//! `meshes/tests/data/industrial/make_industrial.py` from the `.msh`) gives the same modes;
//! the file's material and constraints are used; what the reader leaves out is a warning; an
//! anisotropic section is refused with a clear "not yet supported".

use squeal_pipeline::output::RunDir;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::scene::Scene;
use squeal_pipeline::stages::mesh::mesh_component;
use squeal_pipeline::stages::model::cache::key::ModelKey;
use squeal_pipeline::stages::modes;
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../meshes/tests/data/industrial")
}

fn work(name: &str) -> RunDir {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("readers")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    RunDir::create(&d).unwrap()
}

fn scene(geometry: &str, extra: &str) -> Scene {
    let text = format!(
        r#"
[[components]]
name = "bracket"
geometry = {geometry}
{extra}

[modes]
n_modes = 8
"#
    );
    Scene::from_toml_str(&text, data(), &[]).unwrap()
}

const STEEL: &str = "material = { young = 210e9, poisson = 0.3, density = 7850.0 }";

/// The bracket (twisted, tapered, graded hex20; 6 × 3 × 2 cells), clamped on one end: gmsh's
/// `.msh` with the scene's steel and `fixed` set, the `.bdf` with its own MAT1 and SPC1, the
/// `.inp` (meshio's C3D20RH) with the scene's steel and its `*NSET` — the same eight
/// frequencies to 1e-10 relative (the `.bdf` holds 11–12 digit coordinates, the others 16–17).
#[test]
fn gmsh_nastran_and_abaqus_routes_give_the_same_modes() {
    let msh = scene(
        r#"{ kind = "msh", path = "bracket_hex20.msh" }"#,
        &format!("{STEEL}\nfixed = [{{ set = \"clamp\" }}]"),
    );
    let bdf = scene(r#"{ kind = "bdf", path = "bracket_hex20.bdf" }"#, "");
    let inp = scene(
        r#"{ kind = "inp", path = "bracket_hex20.inp" }"#,
        &format!("{STEEL}\nfixed = [{{ set = \"clamp\" }}]"),
    );
    let q = Progress::quiet();
    let a = modes::compute(&msh, None, &work("msh"), &q).unwrap();
    let b = modes::compute(&bdf, None, &work("bdf"), &q).unwrap();
    let c = modes::compute(&inp, None, &work("inp"), &q).unwrap();
    assert_eq!(a.report.n_dofs, b.report.n_dofs);
    assert_eq!(a.report.n_dofs, c.report.n_dofs);
    let fa = &a.report.frequencies_hz;
    let mut worst: f64 = 0.0;
    for (fb, fc) in [(&b.report.frequencies_hz, &c.report.frequencies_hz)] {
        assert_eq!(fa.len(), 8);
        for i in 0..8 {
            worst = worst.max(((fb[i] - fa[i]) / fa[i]).abs());
            worst = worst.max(((fc[i] - fa[i]) / fa[i]).abs());
        }
    }
    eprintln!(
        "bracket: f1 = {:.6} Hz, largest relative difference {worst:.2e}",
        fa[0]
    );
    assert!(worst < 1e-10, "largest relative difference {worst:e}");
    // The deck's SPC set was applied (the only one), and said so.
    let reader = b.report.mesh.reader.as_ref().unwrap();
    assert!(reader.notes.iter().any(|n| n.contains("SPC set 1 applied")));
    let reader = c.report.mesh.reader.as_ref().unwrap();
    assert!(reader.notes.iter().any(|n| n.contains("C3D20RH")));
}

/// Cards the reader does not read are warnings with their counts (in `summary.json` through
/// the mesh report and the model's warnings); the scene's `materials.<pid_N>` overrides the
/// file's; an anisotropic section is refused, naming the material, the file and what to do.
#[test]
fn warnings_material_overrides_and_anisotropic_sections() {
    let read = |s: &Scene, name: &str| {
        mesh_component(s, &s.components[0], &work(name), &Progress::quiet()).unwrap()
    };
    let s = scene(r#"{ kind = "bdf", path = "mixed.bdf", pids = [1] }"#, "");
    let (mesh, report) = read(&s, "mixed-pid1");
    let w = report.warnings();
    assert_eq!(w.len(), 1);
    assert!(w[0].message.contains("CONM2 ×1"), "{}", w[0].message);
    let json = serde_json::to_string(&report).unwrap();
    assert!(
        json.contains("\"unsupported\"") && json.contains("EIGRL"),
        "{json}"
    );
    let m = s.components[0].block_materials(&mesh).unwrap();
    assert!(m
        .iter()
        .all(|m| m.young == 2.0e11 && m.poisson == 0.29 && m.density == 7800.0));

    let s = scene(r#"{ kind = "bdf", path = "mixed.bdf", pids = [2] }"#, "");
    let (mesh, _) = read(&s, "mixed-pid2");
    let e = s.components[0]
        .block_materials(&mesh)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("pid_2")
            && e.contains("MAT9 9")
            && e.contains("mixed.bdf")
            && e.contains("not yet supported"),
        "{e}"
    );
    let s = scene(
        r#"{ kind = "bdf", path = "mixed.bdf", pids = [2] }"#,
        "materials = { pid_2 = { young = 1e9, poisson = 0.3, density = 1800.0 } }",
    );
    let m = s.components[0].block_materials(&mesh).unwrap();
    assert!(m.iter().all(|m| m.young == 1e9));
}

/// A component without `material` is accepted for a Nastran or Abaqus file only; the model
/// cache key follows the file and its includes.
#[test]
fn material_required_unless_the_file_brings_it_and_cache_key_covers_includes() {
    let text = r#"
[[components]]
name = "b"
geometry = { kind = "msh", path = "bracket_hex20.msh" }
"#;
    let e = Scene::from_toml_str(text, data(), &[])
        .unwrap_err()
        .to_string();
    assert!(e.contains("components[0].material"), "{e}");
    // The key of a deck changes with an included file.
    let d = Path::new(env!("CARGO_TARGET_TMPDIR")).join("readers/key");
    std::fs::create_dir_all(&d).unwrap();
    for f in ["mixed.bdf", "mixed_grids.bdf", "mixed_free.bdf"] {
        std::fs::copy(data().join(f), d.join(f)).unwrap();
    }
    let text = r#"
[[components]]
name = "b"
geometry = { kind = "bdf", path = "mixed.bdf", pids = [1] }
"#;
    let s = Scene::from_toml_str(text, &d, &[]).unwrap();
    let k1 = ModelKey::of(&s).unwrap();
    let free = std::fs::read_to_string(d.join("mixed_free.bdf")).unwrap();
    std::fs::write(
        d.join("mixed_free.bdf"),
        free.replace("GRID*,9001,,1.5", "GRID*,9001,,1.6"),
    )
    .unwrap();
    let k2 = ModelKey::of(&s).unwrap();
    assert_ne!(k1.hex, k2.hex);
}
