//! Nastran and Abaqus components (`geometry = { kind = "bdf" | "inp", … }`, issue 23): the
//! same hex20 mesh through gmsh's `.msh`, pyNastran's `.bdf` and meshio's `.inp` (written by
//! `meshes/tests/data/industrial/make_industrial.py` from the `.msh`) gives the same modes;
//! the file's materials (isotropic and anisotropic on their axes) and constraints are used;
//! what the reader leaves out is a warning.

use squeal_fe::{Elasticity, Material, MaterialAxes, SolidMaterial};
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

/// A CAD-like part: the anchor arm (OpenCASCADE block + boss − bolt hole, `anchor.geo`)
/// meshed by gmsh in unstructured tet10 whose mid-edge nodes lie on the curved surfaces
/// (a mid-edge node up to 10 % of its edge's length off the chord, smallest dihedral angle
/// 11.6°, `anchor_tet10.json`), clamped at one end: gmsh's `.msh`, pyNastran's CTETRA deck
/// and meshio's C3D10 input give the same eight frequencies to 1e-10.
#[test]
fn curved_tet10_part_gives_the_same_modes_by_all_routes() {
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data().join("anchor_tet10.json")).unwrap())
            .unwrap();
    // The mesh is the distorted one the test is about.
    assert!(r["max_mid_edge_offset_over_length"].as_f64().unwrap() > 0.05);
    assert!(r["min_dihedral_deg"].as_f64().unwrap() < 20.0);
    let clamp = format!("{STEEL}\nfixed = [{{ set = \"clamp\" }}]");
    let msh = scene(r#"{ kind = "msh", path = "anchor_tet10.msh" }"#, &clamp);
    let bdf = scene(r#"{ kind = "bdf", path = "anchor_tet10.bdf" }"#, "");
    let inp = scene(r#"{ kind = "inp", path = "anchor_tet10.inp" }"#, &clamp);
    let q = Progress::quiet();
    let a = modes::compute(&msh, None, &work("anchor-msh"), &q).unwrap();
    let b = modes::compute(&bdf, None, &work("anchor-bdf"), &q).unwrap();
    let c = modes::compute(&inp, None, &work("anchor-inp"), &q).unwrap();
    let n = r["n_nodes"].as_u64().unwrap() as usize;
    let clamped = r["n_clamped_nodes"].as_u64().unwrap() as usize;
    for m in [&a, &b, &c] {
        assert_eq!(m.report.n_dofs, 3 * (n - clamped));
    }
    let fa = &a.report.frequencies_hz;
    let mut worst: f64 = 0.0;
    for f in [&b.report.frequencies_hz, &c.report.frequencies_hz] {
        for i in 0..8 {
            worst = worst.max(((f[i] - fa[i]) / fa[i]).abs());
        }
    }
    eprintln!(
        "anchor tet10: f1 = {:.6} Hz, f8 = {:.6} Hz, largest relative difference {worst:.2e}",
        fa[0], fa[7]
    );
    assert!(worst < 1e-10, "largest relative difference {worst:e}");
}

/// Cards the reader does not read are warnings with their counts (in `summary.json` through
/// the mesh report and the model's warnings); MAT1 and MAT9 (on the CORD1R axes of its
/// PSOLID's CORDM, pyNastran's) become fe's materials; the scene's `materials.<pid_N>`
/// overrides the file's.
#[test]
fn warnings_file_materials_and_overrides() {
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
    let steel = SolidMaterial::from(Material {
        young: 2.0e11,
        poisson: 0.29,
        density: 7800.0,
    });
    assert!(m.iter().all(|m| *m == steel), "{m:?}");

    let s = scene(r#"{ kind = "bdf", path = "mixed.bdf", pids = [2] }"#, "");
    let (mesh, _) = read(&s, "mixed-pid2");
    let m = s.components[0].block_materials(&mesh).unwrap();
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data().join("mixed.json")).unwrap()).unwrap();
    let axis =
        |k: usize| -> [f64; 3] { [0, 1, 2].map(|i| r["cordm4"]["axes"][k][i].as_f64().unwrap()) };
    for b in &m {
        assert!(matches!(b.elasticity, Elasticity::Anisotropic { .. }));
        assert_eq!(b.density, 1800.0);
        let MaterialAxes::Rectangular { e1, e2 } = b.axes else {
            panic!("{:?}", b.axes)
        };
        for k in 0..3 {
            assert!((e1[k] - axis(0)[k]).abs() < 1e-12 && (e2[k] - axis(1)[k]).abs() < 1e-12);
        }
    }
    let s = scene(
        r#"{ kind = "bdf", path = "mixed.bdf", pids = [2] }"#,
        "materials = { pid_2 = { young = 1e9, poisson = 0.3, density = 1800.0 } }",
    );
    let m = s.components[0].block_materials(&mesh).unwrap();
    assert!(m.iter().all(|m| m.elasticity
        == Elasticity::Isotropic {
            young: 1e9,
            poisson: 0.3
        }));
}

/// An orthotropic lining on axes turned 30° about z then 20° about the new axis 1, on the
/// bracket: the scene's `orthotropic` + `axes` on the gmsh mesh, the deck's MAT9 (numpy's
/// inverse of the compliance, Nastran's strain order) on a CORD2R, the input's ENGINEERING
/// CONSTANTS on an *ORIENTATION (with its *BOUNDARY): the same eight frequencies to 1e-10.
#[test]
fn anisotropic_material_axes_agree_across_routes() {
    let r: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(data().join("bracket_ortho.json")).unwrap())
            .unwrap();
    let o = &r["orthotropic"];
    let v = |k: &str| format!("{:?}", o[k].as_f64().unwrap());
    let vec3 = |k: &str| {
        format!(
            "[{}]",
            (0..3)
                .map(|i| format!("{:?}", r[k][i].as_f64().unwrap()))
                .collect::<Vec<_>>()
                .join(", ")
        )
    };
    let material = format!(
        "material = {{ density = 2500.0, orthotropic = {{ e1 = {}, e2 = {}, e3 = {}, nu12 = {}, \
         nu13 = {}, nu23 = {}, g12 = {}, g13 = {}, g23 = {} }}, axes = {{ kind = \
         \"rectangular\", e1 = {}, e2 = {} }} }}\nfixed = [{{ set = \"clamp\" }}]",
        v("e1"),
        v("e2"),
        v("e3"),
        v("nu12"),
        v("nu13"),
        v("nu23"),
        v("g12"),
        v("g13"),
        v("g23"),
        vec3("e1"),
        vec3("e2")
    );
    let msh = scene(r#"{ kind = "msh", path = "bracket_hex20.msh" }"#, &material);
    let bdf = scene(r#"{ kind = "bdf", path = "bracket_ortho.bdf" }"#, "");
    let inp = scene(r#"{ kind = "inp", path = "bracket_ortho.inp" }"#, "");
    let q = Progress::quiet();
    let a = modes::compute(&msh, None, &work("ortho-msh"), &q).unwrap();
    let b = modes::compute(&bdf, None, &work("ortho-bdf"), &q).unwrap();
    let c = modes::compute(&inp, None, &work("ortho-inp"), &q).unwrap();
    let fa = &a.report.frequencies_hz;
    let mut worst: f64 = 0.0;
    for f in [&b.report.frequencies_hz, &c.report.frequencies_hz] {
        for i in 0..8 {
            worst = worst.max(((f[i] - fa[i]) / fa[i]).abs());
        }
    }
    eprintln!(
        "orthotropic bracket: f1 = {:.6} Hz, largest relative difference {worst:.2e}",
        fa[0]
    );
    assert!(worst < 1e-10, "largest relative difference {worst:e}");
    // The lining is far softer than steel: not the isotropic steel bracket's modes.
    assert!(fa[0] < 1000.0, "{fa:?}");
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
