//! Components from the user's own gmsh `.geo` files (`geometry = { kind = "geo", path }`):
//! meshed at the component's element order, their physical groups checked against what the
//! scene names (errors name the file and the group), `set_numbers` passed to gmsh, and the
//! rigid rotation `rotate_deg` of a component's mesh.
//!
//! These tests need the gmsh program (the project's `.venv`, `bash scripts/setup.sh`); without
//! it they print why and return.

use squeal_pipeline::output::RunDir;
use squeal_pipeline::progress::Progress;
use squeal_pipeline::scene::Scene;
use squeal_pipeline::stages::model::cache::key::ModelKey;
use squeal_pipeline::stages::modes;
use std::path::{Path, PathBuf};

fn data() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/geo")
}

fn gmsh_missing() -> bool {
    match squeal_meshes::gmsh::find_gmsh() {
        Ok(_) => false,
        Err(e) => {
            eprintln!("skipped: this test needs gmsh: {e}");
            true
        }
    }
}

fn work(name: &str) -> RunDir {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("cad-geometry")
        .join(name);
    let _ = std::fs::remove_dir_all(&d);
    RunDir::create(&d).unwrap()
}

const STEEL: &str = "material = { young = 2.1e11, poisson = 0.3, density = 7850.0 }";

/// The beam of `beam.geo` (0.2 × 0.04 × 0.02 m, 10 × 2 × 2 hex20), clamped at x = 0.
fn beam_scene(geometry: &str, extra: &str) -> String {
    format!(
        r#"
[[components]]
name = "beam"
element = "hex20"
geometry = {geometry}
{STEEL}
fixed = [{{ set = "root" }}]
{extra}

[modes]
n_modes = 6
"#
    )
}

fn modes_of(scene: &Scene, name: &str) -> modes::ModesComputed {
    modes::compute(scene, Some("beam"), &work(name), &Progress::quiet()).unwrap()
}

/// The hand-written `.geo` (explicit points, lines, surfaces and a transfinite volume) and
/// squeal's parametric block (an extruded rectangle) mesh the same beam: same nodes and cells
/// and the same frequencies to round-off. The first bending mode (about the thin side) is
/// within 2 % of Euler–Bernoulli's f₁ = (1.8751²/2π)·√(EI/ρAL⁴) = 411.0 Hz (E = 210 GPa,
/// ρ = 7850, I = W H³/12); for L/H = 10 shear and rotary inertia lower it by about 1 %.
#[test]
fn geo_file_gives_the_parametric_blocks_mesh_and_frequencies() {
    if gmsh_missing() {
        return;
    }
    let geo = Scene::from_toml_str(
        &beam_scene(r#"{ kind = "geo", path = "beam.geo" }"#, ""),
        data(),
        &[],
    )
    .unwrap();
    let block = Scene::from_toml_str(
        &beam_scene(
            r#"{ kind = "block", lx = 0.2, ly = 0.04, lz = 0.02, nx = 10, ny = 2, nz = 2 }"#,
            "",
        )
        .replace("set = \"root\"", "set = \"x0\""),
        data(),
        &[],
    )
    .unwrap();
    let a = modes_of(&geo, "geo");
    let b = modes_of(&block, "block");
    // hex20: corners 11·3·3 = 99 + edges 10·3·3 + 11·2·3 + 11·3·2 = 90 + 66 + 66.
    assert_eq!(a.mesh.nodes.len(), 321);
    assert_eq!(a.mesh.nodes.len(), b.mesh.nodes.len());
    assert_eq!(a.report.n_dofs, b.report.n_dofs);
    for (fa, fb) in a.report.frequencies_hz.iter().zip(&b.report.frequencies_hz) {
        assert!((fa - fb).abs() <= 1e-8 * fb, "geo {fa} Hz, block {fb} Hz");
    }
    let (e, rho, w, h, l): (f64, f64, f64, f64, f64) = (2.1e11, 7850.0, 0.04, 0.02, 0.2);
    let ei = e * w * h * h * h / 12.0;
    let f1 =
        1.8751_f64.powi(2) / (2.0 * std::f64::consts::PI) * (ei / (rho * w * h * l.powi(4))).sqrt();
    let got = a.report.frequencies_hz[0];
    eprintln!("beam.geo f1 = {got:.2} Hz, Euler–Bernoulli {f1:.2} Hz");
    assert!(((got - f1) / f1).abs() < 0.02, "{got} vs {f1}");
}

/// `element = "hex8"` meshes the same file at order 1, and `set_numbers` reaches the file's
/// `DefineConstant`s: nl = 20 doubles the cells along the beam.
#[test]
fn element_order_and_set_numbers_reach_gmsh() {
    if gmsh_missing() {
        return;
    }
    let text = beam_scene(
        r#"{ kind = "geo", path = "beam.geo", set_numbers = { nl = 20 } }"#,
        "",
    )
    .replace("element = \"hex20\"", "element = \"hex8\"");
    let s = Scene::from_toml_str(&text, data(), &[]).unwrap();
    let m = modes_of(&s, "hex8");
    assert_eq!(m.report.mesh.n_cells, 80);
    assert_eq!(m.mesh.nodes.len(), 21 * 3 * 3);
    assert!(m
        .mesh
        .volumes
        .iter()
        .all(|b| b.kind == squeal_meshes::CellKind::Hex8));
    // A bad parameter name is a scene error naming it, before gmsh runs.
    let e = Scene::from_toml_str(&text.replace("nl = 20", "\"n l\" = 20"), data(), &[])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("components[0].geometry") && e.contains("n l"),
        "{e}"
    );
    // A misspelt name (issue 26): gmsh ignored it and meshed the defaults; now an error naming
    // the key and the constants the file defines, before gmsh runs.
    let s = Scene::from_toml_str(&text.replace("nl = 20", "nL = 20"), data(), &[]).unwrap();
    let e = modes::compute(&s, Some("beam"), &work("misspelt"), &Progress::quiet())
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("components[0].geometry.set_numbers.nL")
            && e.contains("beam.geo")
            && e.contains("H, L, W, nh, nl, nw"),
        "{e}"
    );
}

/// Every physical group the scene names for a `.geo` component must be in the file; the error
/// names the file, the group, the scene key asking for it and the groups the file has.
#[test]
fn missing_physical_groups_are_errors_naming_the_file_and_group() {
    if gmsh_missing() {
        return;
    }
    let geo = r#"{ kind = "geo", path = "beam.geo" }"#;
    let err = |text: String, name: &str| {
        let s = Scene::from_toml_str(&text, data(), &[]).unwrap();
        let e = modes::compute(&s, Some("beam"), &work(name), &Progress::quiet())
            .map(|_| ())
            .unwrap_err()
            .to_string();
        assert!(e.contains("beam.geo"), "{e}");
        e
    };
    let e = err(
        beam_scene(geo, "").replace("set = \"root\"", "set = \"clamp\""),
        "fixed",
    );
    assert!(
        e.contains("`clamp`") && e.contains("fixed[0].set") && e.contains("root_edges"),
        "{e}"
    );
    let other = r#"
[[components]]
name = "disc"
geometry = { kind = "block" }
material = { young = 2.1e11, poisson = 0.3, density = 7850.0 }
"#;
    let contact = r#"
[[contact]]
pad = "beam"
pad_faces = "lining"
rotor = "disc"
rotor_faces = "z1"
"#;
    let e = err(
        format!("{}{other}{contact}", beam_scene(geo, "")),
        "contact",
    );
    assert!(
        e.contains("`lining`") && e.contains("contact[0].pad_faces") && e.contains("top"),
        "{e}"
    );
    // A curve group is not a friction face: it has no quad faces.
    let e = err(
        format!(
            "{}{other}{}",
            beam_scene(geo, ""),
            contact.replace("\"lining\"", "\"root_edges\"")
        ),
        "curve",
    );
    assert!(
        e.contains("`root_edges`") && e.contains("no quad4/quad8 faces"),
        "{e}"
    );
    let loads = r#"
[loads]
pressure = [{ component = "beam", faces = "botom" }]
"#;
    let e = err(format!("{}{loads}", beam_scene(geo, "")), "pressure");
    assert!(
        e.contains("`botom`") && e.contains("loads.pressure[0].faces") && e.contains("bottom"),
        "{e}"
    );
    let loads = r#"
[loads]
force = [{ component = "beam", nodes = "tipp", force = [0.0, 0.0, 1.0] }]
"#;
    let e = err(format!("{}{loads}", beam_scene(geo, "")), "force");
    assert!(
        e.contains("`tipp`") && e.contains("loads.force[0].nodes"),
        "{e}"
    );
}

/// A `.geo` file that does not exist, and one gmsh rejects, are errors naming the file.
#[test]
fn missing_or_broken_geo_files_are_errors_naming_them() {
    if gmsh_missing() {
        return;
    }
    let s = Scene::from_toml_str(
        &beam_scene(r#"{ kind = "geo", path = "nowhere.geo" }"#, ""),
        data(),
        &[],
    )
    .unwrap();
    let e = modes::compute(&s, None, &work("nowhere"), &Progress::quiet())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("nowhere.geo") && e.contains("beam"), "{e}");

    let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("cad-geometry");
    std::fs::create_dir_all(&dir).unwrap();
    let broken = std::fs::read_to_string(data().join("beam.geo"))
        .unwrap()
        .replace("Volume(1) = {1};", "Volume(1) = {1;");
    std::fs::write(dir.join("broken.geo"), broken).unwrap();
    let s = Scene::from_toml_str(
        &beam_scene(r#"{ kind = "geo", path = "broken.geo" }"#, ""),
        &dir,
        &[],
    )
    .unwrap();
    let e = modes::compute(&s, None, &work("broken"), &Progress::quiet())
        .map(|_| ())
        .unwrap_err()
        .to_string();
    assert!(e.contains("broken.geo") && e.contains("Error"), "{e}");
}

/// `rotate_deg` turns the component's mesh rigidly about the `[rotor]` axis: every node moves
/// to its rotated place (checked against the rotation written out by hand), the fixed set
/// turns with it, the frequencies are unchanged to round-off, and the angle is in the
/// reduced-model cache key (any angle: a continuous parameter).
#[test]
fn rotate_deg_turns_the_mesh_rigidly_about_the_rotor_axis() {
    if gmsh_missing() {
        return;
    }
    let geo = r#"{ kind = "geo", path = "beam.geo" }"#;
    let base = beam_scene(geo, "");
    let s0 = Scene::from_toml_str(&base, data(), &[]).unwrap();
    let deg = 37.3_f64;
    // About the z axis through (0.05, -0.1, 0): the [rotor] origin.
    let rotor = "\n[rotor]\norigin = [0.05, -0.1, 0.0]\n";
    let s1 = Scene::from_toml_str(
        &format!("{base}{rotor}"),
        data(),
        &[format!("components.0.rotate_deg={deg}")],
    )
    .unwrap();
    let a = modes_of(&s0, "rot0");
    let b = modes_of(&s1, "rot1");
    let (s, c) = deg.to_radians().sin_cos();
    for (p, q) in a.mesh.nodes.iter().zip(&b.mesh.nodes) {
        let (dx, dy) = (p[0] - 0.05, p[1] + 0.1);
        let want = [0.05 + c * dx - s * dy, -0.1 + s * dx + c * dy, p[2]];
        for k in 0..3 {
            assert!((q[k] - want[k]).abs() < 1e-14, "{q:?} vs {want:?}");
        }
    }
    for (fa, fb) in a.report.frequencies_hz.iter().zip(&b.report.frequencies_hz) {
        assert!((fa - fb).abs() <= 1e-8 * fa, "{fa} vs {fb} Hz");
    }
    let k0 = ModelKey::of(&s0).unwrap().hex;
    let k1 = ModelKey::of(&s1).unwrap().hex;
    let mut s2 = s1.clone();
    s2.set("components.0.rotate_deg", "37.30001").unwrap();
    let k2 = ModelKey::of(&s2).unwrap().hex;
    assert!(k0 != k1 && k1 != k2 && k0 != k2);
    // A non-finite angle names the key.
    let e = Scene::from_toml_str(&base, data(), &["components.0.rotate_deg=nan".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("rotate_deg"), "{e}");
}

/// `examples/cad-brake/brake.toml` (its rotor coarsened through `set_numbers` to keep the test
/// fast): every part meshes from its `.geo` with positive Jacobians at every node (the
/// reader's check) and the scene's groups; each pad's friction face lies on its rotor face
/// (z = 0 below the ring, z = t_ring = 26 mm above it) inside the ring, and no pad
/// friction-face node coincides with a rotor friction-face node (the meshes are independent).
#[test]
fn cad_brake_example_parts_mesh_independently() {
    if gmsh_missing() {
        return;
    }
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../examples/cad-brake/brake.toml");
    let coarse: Vec<String> = ["n_quarter=9", "n_ring=5", "n_hat=2", "n_flange=3"]
        .iter()
        .map(|s| format!("components.0.geometry.set_numbers.{s}"))
        .collect();
    let scene = Scene::load(&path, &coarse).unwrap();
    let dir = work("cad-brake");
    let mesh = |name: &str| {
        let c = scene.component(Some(name)).unwrap();
        squeal_pipeline::stages::mesh::mesh_component(&scene, c, &dir, &Progress::quiet())
            .unwrap()
            .0
    };
    let rotor = mesh("rotor");
    let face_nodes = |m: &squeal_meshes::Mesh, set: &str| -> Vec<[f64; 3]> {
        let v = m.faces[set].nodes();
        v.iter().map(|&n| m.nodes[n]).collect()
    };
    for (pad, rotor_face, z) in [
        ("inboard_pad", "friction_in", 0.0),
        ("outboard_pad", "friction_out", 0.026),
    ] {
        let m = mesh(pad);
        assert_eq!(m.volumes.len(), 2, "{pad}: lining and backplate");
        let cells: usize = m.volumes.iter().map(|b| b.len()).sum();
        // brake.toml's pad mesh: 24 elements along the lining, 3 + 4 + 3 across.
        assert_eq!(cells, 2352, "{pad}");
        let pf = face_nodes(&m, "friction");
        let rf = face_nodes(&rotor, rotor_face);
        // The pads are hex8 (brake.toml: quad8 corner nodes of hex20 pads carry tensile
        // nodal forces under a uniform pressure): a 24 × 10 face has 25·11 nodes.
        assert_eq!(pf.len(), 275, "{pad}: 25·11 hex8 face nodes");
        let mut min_d = f64::INFINITY;
        for p in &pf {
            assert!(
                (p[2] - z).abs() < 1e-12,
                "{pad}: friction node {p:?} off z = {z}"
            );
            let r = p[0].hypot(p[1]);
            assert!((0.094..=0.160).contains(&r), "{pad}: r = {r} off the ring");
            for q in &rf {
                min_d = min_d.min(((p[0] - q[0]).powi(2) + (p[1] - q[1]).powi(2)).sqrt());
            }
        }
        eprintln!(
            "{pad}: closest rotor friction node {:.3} mm away",
            1e3 * min_d
        );
        assert!(
            min_d > 1e-5,
            "{pad}: a friction node coincides with the rotor's"
        );
    }
}
