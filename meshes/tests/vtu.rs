//! VTU writing, checked by reading the file back with meshio (the project's Python peer).

use squeal_meshes::vtu::{write_vtu, CellArray, PointArray};
use squeal_meshes::{CellBlock, CellKind, Mesh, MeshError};
use std::path::PathBuf;
use std::process::Command;

/// Two blocks: two hex8 sharing a face (12 nodes) and one separate hex20 (20 nodes).
fn two_block_mesh() -> Mesh {
    let mut nodes = Vec::new();
    for k in 0..2 {
        for j in 0..2 {
            for i in 0..3 {
                nodes.push([i as f64, j as f64, k as f64 * 0.5]);
            }
        }
    }
    let id = |i: usize, j: usize, k: usize| i + 3 * j + 6 * k;
    let hex = |i: usize| {
        [
            id(i, 0, 0),
            id(i + 1, 0, 0),
            id(i + 1, 1, 0),
            id(i, 1, 0),
            id(i, 0, 1),
            id(i + 1, 0, 1),
            id(i + 1, 1, 1),
            id(i, 1, 1),
        ]
    };
    let hex8 = CellBlock {
        name: Some("left".into()),
        kind: CellKind::Hex8,
        conn: [hex(0), hex(1)].concat(),
        tags: vec![1, 2],
    };
    // hex20 on [5,6]×[0,1]×[0,1], squeal order: corners then the mesh.rs edge list.
    let c = [
        [5.0, 0.0, 0.0],
        [6.0, 0.0, 0.0],
        [6.0, 1.0, 0.0],
        [5.0, 1.0, 0.0],
        [5.0, 0.0, 1.0],
        [6.0, 0.0, 1.0],
        [6.0, 1.0, 1.0],
        [5.0, 1.0, 1.0],
    ];
    let edges = [
        (0, 1),
        (1, 2),
        (2, 3),
        (3, 0),
        (4, 5),
        (5, 6),
        (6, 7),
        (7, 4),
        (0, 4),
        (1, 5),
        (2, 6),
        (3, 7),
    ];
    let first = nodes.len();
    nodes.extend_from_slice(&c);
    for (a, b) in edges {
        let (p, q): ([f64; 3], [f64; 3]) = (c[a], c[b]);
        nodes.push([
            (p[0] + q[0]) / 2.0,
            (p[1] + q[1]) / 2.0,
            (p[2] + q[2]) / 2.0,
        ]);
    }
    let hex20 = CellBlock {
        name: Some("right".into()),
        kind: CellKind::Hex20,
        conn: (first..first + 20).collect(),
        tags: vec![3],
    };
    let n = nodes.len();
    Mesh {
        nodes,
        node_tags: (1..=n as u64).collect(),
        volumes: vec![hex8, hex20],
        ..Default::default()
    }
}

/// Reads `path` with meshio and prints points, cells, point and cell data as JSON; real
/// arrays as the hex of their little-endian float64 bytes (exact), with their shapes.
const READ_BACK: &str = r#"
import json, sys, meshio, numpy as np
m = meshio.read(sys.argv[1])
def real(a):
    a = np.asarray(a)
    return {"shape": list(a.shape), "hex": a.astype("<f8").tobytes().hex()}
print(json.dumps({
    "points": real(m.points),
    "cells": [[b.type, b.data.tolist()] for b in m.cells],
    "point_data": {k: real(v) for k, v in m.point_data.items()},
    "cell_data": {k: real(np.concatenate(v)) for k, v in m.cell_data.items()},
}))
"#;

/// The shape and the values of an array printed by [`READ_BACK`].
fn reals(v: &serde_json::Value) -> (Vec<usize>, Vec<f64>) {
    let shape = v["shape"]
        .as_array()
        .unwrap()
        .iter()
        .map(|x| x.as_u64().unwrap() as usize)
        .collect();
    let hex = v["hex"].as_str().unwrap().as_bytes();
    let bytes: Vec<u8> = hex
        .chunks(2)
        .map(|h| u8::from_str_radix(std::str::from_utf8(h).unwrap(), 16).unwrap())
        .collect();
    let values = bytes
        .chunks(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    (shape, values)
}

fn python() -> PathBuf {
    let root = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("..");
    let py = root.join(".venv").join("bin").join("python");
    assert!(
        py.is_file(),
        "{} is missing: run `bash scripts/test.sh` (the README's test command), which creates the \
         project .venv with meshio before running the tests",
        py.display()
    );
    py
}

#[test]
fn vtu_round_trips_through_meshio() {
    let m = two_block_mesh();
    let n = m.nodes.len();
    // u = (x, 2y, -z + 0.1 i), T = x + y + z + 1/3 (a value that needs all 64 bits).
    let u: Vec<f64> = m
        .nodes
        .iter()
        .enumerate()
        .flat_map(|(i, p)| [p[0], 2.0 * p[1], -p[2] + 0.1 * i as f64])
        .collect();
    let t: Vec<f64> = m
        .nodes
        .iter()
        .map(|p| p[0] + p[1] + p[2] + 1.0 / 3.0)
        .collect();
    let s = [1.5, -2.25, 1e-300];
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("squeal-meshes-tests");
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("two_blocks.vtu");
    write_vtu(
        &path,
        &m,
        &[PointArray::vector("u", &u), PointArray::scalar("T", &t)],
        &[CellArray {
            name: "stress <xx>",
            n_components: 1,
            values: &s,
        }],
    )
    .unwrap();
    let out = Command::new(python())
        .arg("-c")
        .arg(READ_BACK)
        .arg(&path)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "meshio failed: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();

    let want_points: Vec<f64> = m.nodes.iter().flatten().copied().collect();
    assert_eq!(reals(&v["points"]), (vec![n, 3], want_points));
    let cells = v["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 2);
    for (c, (want_type, block)) in cells.iter().zip([("hexahedron", 0), ("hexahedron20", 1)]) {
        assert_eq!(c[0].as_str().unwrap(), want_type);
        let conn: Vec<usize> = c[1]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|cell| cell.as_array().unwrap().iter())
            .map(|x| x.as_u64().unwrap() as usize)
            .collect();
        assert_eq!(conn, m.volumes[block].conn);
    }
    assert_eq!(reals(&v["point_data"]["u"]), (vec![n, 3], u));
    assert_eq!(reals(&v["point_data"]["T"]), (vec![n], t));
    assert_eq!(reals(&v["cell_data"]["stress <xx>"]), (vec![3], s.to_vec()));
    assert_eq!(
        reals(&v["cell_data"]["block"]),
        (vec![3], vec![0.0, 0.0, 1.0])
    );
    assert!(!dir.join("two_blocks.vtu.tmp").exists());
}

#[test]
fn vtu_rejects_arrays_that_do_not_fit() {
    let m = two_block_mesh();
    let path = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("never_written.vtu");
    let short = vec![0.0; 3 * m.nodes.len() - 1];
    let e = write_vtu(&path, &m, &[PointArray::vector("u", &short)], &[]).unwrap_err();
    assert!(matches!(e, MeshError::VtuArray { .. }));
    assert!(
        e.to_string().contains("`u`") && e.to_string().contains(&format!("{}", 3 * m.nodes.len())),
        "{e}"
    );
    let mut nan = vec![0.0; m.nodes.len()];
    nan[4] = f64::NAN;
    let e = write_vtu(&path, &m, &[PointArray::scalar("T", &nan)], &[]).unwrap_err();
    assert!(e.to_string().contains("value 4"), "{e}");
    let e = write_vtu(
        &path,
        &m,
        &[],
        &[CellArray {
            name: "block",
            n_components: 1,
            values: &[0.0; 3],
        }],
    )
    .unwrap_err();
    assert!(e.to_string().contains("reserved"), "{e}");
    assert!(!path.exists());
}
