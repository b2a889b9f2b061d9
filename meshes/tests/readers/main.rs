//! The Nastran and Abaqus readers (issue 23) on files written by other tools (pyNastran,
//! meshio, and the generator `tests/data/industrial/make_industrial.py`) and on bad input.
//! References: pyNastran's own reading of the deck (grid positions in basic, MAT9, the CORD1R
//! axes), numpy's placement of Abaqus instances (Rodrigues), and geometry (a quadratic cell's
//! mid-edge nodes at its edges' midpoints, a positive volume through its outward faces).

mod bdf;
mod inp;

use squeal_meshes::{CellKind, Mesh};
use std::path::{Path, PathBuf};

pub fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/industrial")
        .join(name)
}

pub fn json(name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(data(name)).unwrap()).unwrap()
}

/// Signed volume of a cell through its outward faces (corner triangle fans, divergence
/// theorem): positive when the cell is oriented as squeal's node order requires.
pub fn volume(kind: CellKind, x: &[[f64; 3]]) -> f64 {
    let mut v = 0.0;
    for f in kind.faces() {
        let c: Vec<[f64; 3]> = f.nodes[..f.kind.n_corners()]
            .iter()
            .map(|&k| x[k])
            .collect();
        for t in 1..c.len() - 1 {
            let (a, b, d) = (c[0], c[t], c[t + 1]);
            v += (a[0] * (b[1] * d[2] - b[2] * d[1]) - a[1] * (b[0] * d[2] - b[2] * d[0])
                + a[2] * (b[0] * d[1] - b[1] * d[0]))
                / 6.0;
        }
    }
    v
}

/// Every cell of the mesh: positive volume and, for quadratic kinds, mid-edge nodes at the
/// midpoints of their edges (the file's straight edges) within `tol`; returns the number of
/// cells checked.
pub fn check_cells(mesh: &Mesh, tol: f64) -> usize {
    let mut n = 0;
    for b in &mesh.volumes {
        for i in 0..b.len() {
            let c = b.cell(i);
            let x: Vec<[f64; 3]> = c.iter().map(|&k| mesh.nodes[k]).collect();
            assert!(
                volume(b.kind, &x) > 0.0,
                "cell {} ({}) inverted",
                b.tags[i],
                b.kind
            );
            if b.kind.is_quadratic() {
                for (e, [p, q]) in b.kind.edges().iter().enumerate() {
                    let m = x[b.kind.n_corners() + e];
                    for k in 0..3 {
                        let mid = (x[*p][k] + x[*q][k]) / 2.0;
                        assert!(
                            (m[k] - mid).abs() < tol,
                            "cell {} ({}): mid-edge node {} is not on edge ({p}, {q})",
                            b.tags[i],
                            b.kind,
                            b.kind.n_corners() + e
                        );
                    }
                }
            }
            n += 1;
        }
    }
    n
}

/// Index of the node with tag `t`.
pub fn node(mesh: &Mesh, t: u64) -> usize {
    mesh.node_tags
        .iter()
        .position(|&x| x == t)
        .unwrap_or_else(|| panic!("no node {t}"))
}

/// Writes `text` into a fresh folder under the test's target dir and returns its path.
pub fn write(dir: &str, name: &str, text: &str) -> PathBuf {
    let d = Path::new(env!("CARGO_TARGET_TMPDIR"))
        .join("readers")
        .join(dir);
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join(name);
    std::fs::write(&p, text).unwrap();
    p
}
