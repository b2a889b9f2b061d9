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
