//! Fixtures shared by the pipeline's integration tests.

#![allow(dead_code)]

/// Hoffmann-type 2-DOF mode-coupling model as stored reduced matrices (as in
/// `cli/tests/cea.rs`; the insight and propensity tests use it): a pad point (grid 1: x, z)
/// with springs k11, k22 − k3 and coupling k12, pressed on a nearly massless rotor point
/// (grid 2: z) held by k3; friction along x makes the constrained stiffness
/// [[k11, k12 − μk3], [k12, k22]]. Damping c on both pad DOFs (× √S). Stiffnesses scaled by
/// S = 1e4. The scene has friction μ and ends with `cea` (a `[cea]` table, or nothing).
pub fn hoffmann(dir: &std::path::Path, c: f64, mu: f64, cea: &str) -> std::path::PathBuf {
    use squeal_reduction::matrix::{MatrixForm, NamedMatrix};
    use squeal_reduction::op4::{self, Op4WriteOptions};
    let s: f64 = 1.0e4;
    let (k11, k12, k22, k3) = (1.0, 0.3, 1.2, 1.0);
    let k = faer::Mat::from_fn(3, 3, |i, j| {
        s * [[k11, k12, 0.0], [k12, k22 - k3, 0.0], [0.0, 0.0, k3]][i][j]
    });
    let eps = 1e-6;
    let m = faer::Mat::from_fn(3, 3, |i, j| {
        if i == j {
            [1.0, 1.0 - eps, eps][i]
        } else {
            0.0
        }
    });
    let b = faer::Mat::from_fn(
        3,
        3,
        |i, j| if i == j && i < 2 { s.sqrt() * c } else { 0.0 },
    );
    let p = faer::Mat::from_fn(3, 1, |_, _| 0.0);
    let mats = [
        NamedMatrix::real("KR", k),
        NamedMatrix::real("MR", m),
        NamedMatrix::real("BR", b),
        NamedMatrix::real("PBRAKE", p).with_form(MatrixForm::Rectangular),
    ];
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    std::fs::write(
        dir.join("hoffmann.op4"),
        op4::write_bytes(&refs, &Op4WriteOptions::default()).unwrap(),
    )
    .unwrap();
    std::fs::write(
        dir.join("dofmap.json"),
        r#"{"dofs": [
            {"component": "pad", "kind": "grid", "grid": 1, "comp": 1},
            {"component": "pad", "kind": "grid", "grid": 1, "comp": 3},
            {"component": "rotor", "kind": "grid", "grid": 2, "comp": 3}]}"#,
    )
    .unwrap();
    std::fs::write(
        dir.join("gaps.csv"),
        "pad_grid,rotor_grid,x,y,z,nx,ny,nz,area,p0,temperature\n1,2,0,-1,0,0,0,1,1,1,0\n",
    )
    .unwrap();
    let p = dir.join("hoffmann.toml");
    std::fs::write(
        &p,
        format!(
            r#"
[model]
from = "op4"
matrices = "hoffmann.op4"
dofmap = "dofmap.json"
gaps = "gaps.csv"

[friction]
law = {{ kind = "constant", mu = {mu} }}
vtol = 1e-6

[rotor]
rpm = 9549.296585513720
axis = [0.0, 0.0, 1.0]

[loads]
pmax = 1.0
tload = 0.0

{cea}
"#
        ),
    )
    .unwrap();
    p
}

/// A small brake (`tests/interface.rs`, `tests/interface_tolerance.rs`): a plate rotor
/// 3 × 3 × 0.3 (9 × 9 × 2 hex8) clamped at x = 0 and x = 3, and a pad 1 × 1 × 0.2 (4 × 4 × 1
/// hex8: non-matching) with its lower corner at `pad_xy` on the rotor's top face, tied by
/// surface pairing. `rotor` is added to the rotor's table (an `interface` table, a
/// `boundary`), `cea` to the `[cea]` table.
pub fn plate_brake(rotor: &str, pad_xy: [f64; 2], cea: &str) -> String {
    let [x, y] = pad_xy;
    format!(
        r#"title = "plate brake"
units = "consistent"

[[components]]
name = "rotor"
element = "hex8"
geometry = {{ kind = "block", origin = [0.0, 0.0, -0.3], lx = 3.0, ly = 3.0, lz = 0.3, nx = 9, ny = 9, nz = 2 }}
material = {{ young = 1.0e4, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x0" }}, {{ set = "x1" }}]
{rotor}

[[components]]
name = "pad"
element = "hex8"
geometry = {{ kind = "block", origin = [{x:?}, {y:?}, 0.0], lx = 1.0, ly = 1.0, lz = 0.2, nx = 4, ny = 4, nz = 1 }}
material = {{ young = 5.0e3, poisson = 0.3, density = 1.0 }}
fixed = [{{ set = "x0", dofs = "xy" }}]

[reduction]
n_modes = 12

[[contact]]
pad = "pad"
pad_faces = "z0"
rotor = "rotor"
rotor_faces = "z1"
pairing = "surface"
p0 = 1.0

[friction]
law = {{ kind = "linear_speed", mu0 = 0.6, slope = -0.05 }}
vtol = 1e-3

[rotor]
rpm = 10.0

[loads]
pmax = 2.0
tload = 0.01
pressure = [{{ component = "pad", faces = "z1", pressure = 1.0 }}]

[damping]
modal_ratio = 0.01

[cea]
at = "steady_state"
friction_damping = true
{cea}
"#
    )
}

/// The scene of `text` (files relative to `dir`) and its reduced model, built in a run folder
/// under `dir` named by the text's length.
pub fn build_model(
    text: &str,
    dir: &std::path::Path,
) -> (
    squeal_pipeline::Scene,
    squeal_pipeline::stages::model::ReducedModel,
) {
    use squeal_pipeline::progress::Progress;
    let s = squeal_pipeline::Scene::from_toml_str(text, dir.to_path_buf(), &[]).unwrap();
    let run = squeal_pipeline::RunDir::create(&dir.join(format!("run{}", text.len()))).unwrap();
    let m = squeal_pipeline::stages::model::build(&s, &run, &Progress::quiet()).unwrap();
    (s, m)
}

/// A corner example's meshes (`examples/<name>/corner.toml` with `sets`, every component
/// meshed by gmsh into a fresh run folder), after checking that the scene has `n_ties` ties
/// and that every slave node of each is tied (the meshes are independent, so none merges).
/// Returns the scene, the run folder and the meshes.
pub fn corner_meshes(
    name: &str,
    sets: &[String],
    n_ties: usize,
) -> (
    squeal_pipeline::scene::Scene,
    squeal_pipeline::output::RunDir,
    Vec<squeal_meshes::Mesh>,
) {
    use squeal_pipeline::stages::mesh;
    use squeal_pipeline::stages::model::{grids, ties};
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    let path = root.join(format!("../examples/{name}/corner.toml"));
    let scene = squeal_pipeline::scene::Scene::load(&path, sets).unwrap_or_else(|e| panic!("{e}"));
    let d = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join(name);
    let _ = std::fs::remove_dir_all(&d);
    let dir = squeal_pipeline::output::RunDir::create(&d).unwrap();
    let progress = squeal_pipeline::progress::Progress::quiet();
    let meshes: Vec<_> = scene
        .components
        .iter()
        .map(|c| mesh::mesh_component(&scene, c, &dir, &progress).unwrap().0)
        .collect();
    let g = grids::merge(&scene, &meshes, scene.model.merge_tolerance);
    let rows = ties::pair_ties(&scene, &meshes, &g).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(rows.len(), n_ties);
    for (t, r) in scene.ties.iter().zip(&rows) {
        let c = component_index(&scene, &t.a.component);
        let slaves = meshes[c].faces[&t.a.faces].nodes().len();
        eprintln!(
            "tie {} {} on {} {}: {} slave nodes",
            t.a.component,
            t.a.faces,
            t.b.component,
            t.b.faces,
            r.rows.len()
        );
        assert_eq!(r.rows.len(), slaves, "{} {}", t.a.component, t.a.faces);
    }
    (scene, dir, meshes)
}

/// The index of component `name` of `scene`.
pub fn component_index(scene: &squeal_pipeline::scene::Scene, name: &str) -> usize {
    scene
        .components
        .iter()
        .position(|x| x.name == name)
        .unwrap_or_else(|| panic!("no component {name}"))
}

/// |z resultant| of the consistent load of pressure `p` on the face set `set` of `mesh`.
pub fn pressure_resultant_z(mesh: &squeal_meshes::Mesh, set: &str, p: f64) -> f64 {
    let dofs = squeal_fe::DofMap::new(mesh.nodes.len(), &[]).unwrap();
    let f = squeal_fe::pressure_load(mesh, set, p, &dofs).unwrap();
    (0..mesh.nodes.len())
        .map(|n| f[3 * n + 2])
        .sum::<f64>()
        .abs()
}
