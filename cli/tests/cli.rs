//! System tests: the `squeal` command end to end on tiny scenes.

mod common;
use common::{root, run, squeal, tmp};

#[test]
fn check_prints_the_resolved_scene_with_defaults() {
    let scene = root().join("examples/verification/cantilever-hex20.toml");
    let (ok, stdout, stderr) = run(squeal().arg("check").arg(&scene));
    assert!(ok, "{stderr}");
    // Defaults the file does not write appear resolved.
    assert!(stdout.contains("hex8 = \"incompatible\""), "{stdout}");
    assert!(stdout.contains("max_restarts = 50"), "{stdout}");
    assert!(stdout.contains("nx = 40"), "{stdout}");
}

#[test]
fn unknown_scene_key_is_an_error_naming_the_key() {
    let d = tmp("unknown-key");
    let scene = d.join("bad.toml");
    std::fs::write(&scene, "[modes]\nn_modes = 3\nn_modez = 4\n").unwrap();
    let (ok, _, stderr) = run(squeal().arg("check").arg(&scene));
    assert!(!ok);
    assert!(stderr.contains("n_modez"), "{stderr}");
    assert!(stderr.contains("bad.toml"), "{stderr}");
}

#[test]
fn set_override_changes_the_scene_and_bad_values_are_named() {
    let scene = root().join("examples/verification/cantilever-hex20.toml");
    let (ok, stdout, stderr) = run(squeal().arg("check").arg(&scene).args([
        "--set",
        "components.0.geometry.nx=8",
        "--set",
        "modes.n_modes=5",
    ]));
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("nx = 8") && stdout.contains("n_modes = 5"),
        "{stdout}"
    );

    let (ok, _, stderr) = run(squeal()
        .arg("check")
        .arg(&scene)
        .args(["--set", "components.0.material.poisson=0.7"]));
    assert!(!ok);
    assert!(
        stderr.contains("poisson") && stderr.contains("0.7"),
        "{stderr}"
    );
}

#[test]
fn modes_on_a_tiny_block_writes_json_and_vtu() {
    let d = tmp("tiny-modes");
    let scene = d.join("tiny.toml");
    std::fs::write(
        &scene,
        r#"
[[components]]
name = "block"
element = "hex8"
geometry = { kind = "block", lx = 1.0, ly = 0.5, lz = 0.2, nx = 4, ny = 2, nz = 1 }
material = { young = 1.0e3, poisson = 0.25, density = 1.0 }
fixed = [{ set = "x0" }]
[modes]
n_modes = 4
"#,
    )
    .unwrap();
    let out = d.join("out");
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "modes"])
        .arg(&scene)
        .arg("--out")
        .arg(&out));
    assert!(ok, "{stderr}");
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("modes.json")).unwrap()).unwrap();
    let f = json["frequencies_hz"].as_array().unwrap();
    assert_eq!(f.len(), 4);
    assert!(f.windows(2).all(|w| w[0].as_f64() <= w[1].as_f64()));
    assert!(json["n_dofs"].as_u64().unwrap() > 0);
    let vtu = std::fs::read_to_string(out.join("modes.vtu")).unwrap();
    assert!(vtu.contains("mode_01_"), "mode arrays named in the VTU");
}

#[test]
fn missing_fixed_set_lists_the_sets_the_mesh_has() {
    let d = tmp("missing-set");
    let scene = d.join("s.toml");
    std::fs::write(
        &scene,
        r#"
[[components]]
name = "block"
element = "hex8"
geometry = { kind = "block", nx = 1, ny = 1, nz = 1 }
material = { young = 1.0, poisson = 0.3, density = 1.0 }
fixed = [{ set = "clamp" }]
"#,
    )
    .unwrap();
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "modes"])
        .arg(&scene)
        .arg("--out")
        .arg(d.join("o")));
    assert!(!ok);
    assert!(
        stderr.contains("clamp") && stderr.contains("z0_edges"),
        "{stderr}"
    );
}

#[test]
fn malformed_user_mesh_names_file_and_line() {
    let d = tmp("bad-msh");
    std::fs::write(
        d.join("bad.msh"),
        "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 2 1 2\n3 1 0 2\n1\n2\n0 0 zero\n",
    )
    .unwrap();
    let scene = d.join("s.toml");
    std::fs::write(
        &scene,
        r#"
[[components]]
name = "pad"
geometry = { kind = "msh", path = "bad.msh" }
material = { young = 1.0, poisson = 0.3, density = 1.0 }
"#,
    )
    .unwrap();
    let (ok, _, stderr) = run(squeal()
        .args(["-q", "modes"])
        .arg(&scene)
        .arg("--out")
        .arg(d.join("o")));
    assert!(!ok);
    assert!(stderr.contains("bad.msh"), "{stderr}");
    // file:line: of the bad coordinate, and the value.
    assert!(
        stderr.contains("bad.msh:9:") && stderr.contains("zero"),
        "{stderr}"
    );
}

#[test]
fn inspect_lists_op4_matrices_as_table_and_json() {
    // A file written by pyyeti (reduction/scripts/make_interop_data.py); its ground truth is
    // reduction/tests/data/truth.json: KSYM 7×7 symmetric, RECT 6×4, CPLX 5×5 complex.
    let file = root().join("reduction/tests/data/op4/yeti_ascii_dense.op4");
    let (ok, stdout, stderr) = run(squeal().arg("inspect").arg(&file));
    assert!(ok, "{stderr}");
    assert!(
        stdout.contains("KSYM") && stdout.contains("RECT") && stdout.contains("CPLX"),
        "{stdout}"
    );
    let (ok, stdout, stderr) = run(squeal().arg("inspect").arg(&file).arg("--json"));
    assert!(ok, "{stderr}");
    let json: serde_json::Value = serde_json::from_str(&stdout).unwrap();
    let ksym = json
        .as_array()
        .unwrap()
        .iter()
        .find(|m| m["name"] == "KSYM")
        .unwrap();
    assert_eq!(ksym["nrows"], 7);
    assert_eq!(ksym["symmetric"], true);

    let (ok, _, stderr) = run(squeal().arg("inspect").arg(root().join("Cargo.toml")));
    assert!(!ok);
    assert!(stderr.contains("Cargo.toml"), "{stderr}");
}
