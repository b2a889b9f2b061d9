//! Writing a [`Mesh`] with point and cell arrays as a VTK XML UnstructuredGrid (`.vtu`).
//!
//! Volume cells only (hex8 = VTK 12, hex20 = VTK 25; squeal's node order is VTK's), Float64
//! points, inline base64 `format="binary"` arrays with a UInt64 byte-count header, and a cell
//! array "block" holding each cell's block index in `mesh.volumes`. The file is written to a
//! temporary file beside the target and renamed, so readers never see half a file.

mod base64;

use crate::{Mesh, MeshError, Real};
use std::fmt::Write as _;
use std::io::Write as _;
use std::path::{Path, PathBuf};

/// Values at the nodes: `values[node * n_components + c]`.
#[derive(Debug, Clone, Copy)]
pub struct PointArray<'a> {
    pub name: &'a str,
    /// 1 (scalar) or 3 (vector); 1..=9 accepted.
    pub n_components: usize,
    pub values: &'a [Real],
}

/// Values per volume cell, cells counted block after block: `values[cell * n_components + c]`.
#[derive(Debug, Clone, Copy)]
pub struct CellArray<'a> {
    pub name: &'a str,
    /// 1 (scalar) or 3 (vector); 1..=9 accepted.
    pub n_components: usize,
    pub values: &'a [Real],
}

impl<'a> PointArray<'a> {
    /// A scalar per node.
    pub fn scalar(name: &'a str, values: &'a [Real]) -> Self {
        PointArray {
            name,
            n_components: 1,
            values,
        }
    }
    /// A 3-vector per node, flat `[x0, y0, z0, x1, ...]`.
    pub fn vector(name: &'a str, values: &'a [Real]) -> Self {
        PointArray {
            name,
            n_components: 3,
            values,
        }
    }
}

/// Writes `mesh` and the arrays to `path` (see the module documentation).
pub fn write_vtu(
    path: &Path,
    mesh: &Mesh,
    point_data: &[PointArray],
    cell_data: &[CellArray],
) -> Result<(), MeshError> {
    let n_points = mesh.nodes.len();
    let n_cells = mesh.n_volume_cells();
    for a in point_data {
        check_array(a.name, a.n_components, a.values, n_points, "points")?;
    }
    for a in cell_data {
        check_array(a.name, a.n_components, a.values, n_cells, "volume cells")?;
        if a.name == "block" {
            return Err(MeshError::VtuArray {
                name: a.name.into(),
                message: "the name is reserved for the block index the writer adds".into(),
            });
        }
    }
    for b in &mesh.volumes {
        if let Some(&i) = b.conn.iter().find(|&&i| i >= n_points) {
            return Err(MeshError::VtuArray {
                name: "connectivity".into(),
                message: format!("node index {i} but the mesh has {n_points} nodes"),
            });
        }
    }

    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n");
    s.push_str("<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n");
    s.push_str("  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{n_points}\" NumberOfCells=\"{n_cells}\">"
    );
    s.push_str("      <PointData>\n");
    for a in point_data {
        data_array(
            &mut s,
            "Float64",
            Some(a.name),
            a.n_components,
            &f64_bytes(a.values),
        );
    }
    s.push_str("      </PointData>\n      <CellData>\n");
    let block: Vec<u8> = mesh
        .volumes
        .iter()
        .enumerate()
        .flat_map(|(i, b)| std::iter::repeat_n(i as i32, b.len()))
        .flat_map(i32::to_le_bytes)
        .collect();
    data_array(&mut s, "Int32", Some("block"), 1, &block);
    for a in cell_data {
        data_array(
            &mut s,
            "Float64",
            Some(a.name),
            a.n_components,
            &f64_bytes(a.values),
        );
    }
    s.push_str("      </CellData>\n      <Points>\n");
    let points: Vec<Real> = mesh.nodes.iter().flatten().copied().collect();
    data_array(&mut s, "Float64", None, 3, &f64_bytes(&points));
    s.push_str("      </Points>\n      <Cells>\n");
    let conn: Vec<u8> = mesh
        .volumes
        .iter()
        .flat_map(|b| b.conn.iter())
        .flat_map(|&i| (i as i64).to_le_bytes())
        .collect();
    data_array(&mut s, "Int64", Some("connectivity"), 1, &conn);
    let mut offsets = Vec::with_capacity(8 * n_cells);
    let mut end = 0i64;
    for b in &mesh.volumes {
        for _ in 0..b.len() {
            end += b.kind.n_nodes() as i64;
            offsets.extend_from_slice(&end.to_le_bytes());
        }
    }
    data_array(&mut s, "Int64", Some("offsets"), 1, &offsets);
    let types: Vec<u8> = mesh
        .volumes
        .iter()
        .flat_map(|b| std::iter::repeat_n(b.kind.vtk_type(), b.len()))
        .collect();
    data_array(&mut s, "UInt8", Some("types"), 1, &types);
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    write_atomic(path, s.as_bytes())
}

fn check_array(
    name: &str,
    n_components: usize,
    values: &[Real],
    n: usize,
    what: &str,
) -> Result<(), MeshError> {
    let err = |message: String| MeshError::VtuArray {
        name: name.into(),
        message,
    };
    if name.is_empty() {
        return Err(err("empty name".into()));
    }
    if !(1..=9).contains(&n_components) {
        return Err(err(format!("{n_components} components (1..=9 allowed)")));
    }
    if values.len() != n * n_components {
        return Err(err(format!(
            "{} values, expected {n} {what} × {n_components} components = {}",
            values.len(),
            n * n_components
        )));
    }
    if let Some(i) = values.iter().position(|v| !v.is_finite()) {
        return Err(err(format!(
            "value {i} (entry {} component {}) is {}",
            i / n_components,
            i % n_components,
            values[i]
        )));
    }
    Ok(())
}

fn f64_bytes(v: &[Real]) -> Vec<u8> {
    v.iter().flat_map(|x| x.to_le_bytes()).collect()
}

/// One `<DataArray>`: base64 of (UInt64 byte count, then the little-endian data).
fn data_array(s: &mut String, ty: &str, name: Option<&str>, n_components: usize, data: &[u8]) {
    let _ = write!(s, "        <DataArray type=\"{ty}\"");
    if let Some(name) = name {
        let _ = write!(s, " Name=\"{}\"", xml_escape(name));
    }
    // Scalars without NumberOfComponents, as VTK writes them (readers then give 1-D arrays).
    if n_components != 1 {
        let _ = write!(s, " NumberOfComponents=\"{n_components}\"");
    }
    s.push_str(" format=\"binary\">\n          ");
    let mut payload = Vec::with_capacity(8 + data.len());
    payload.extend_from_slice(&(data.len() as u64).to_le_bytes());
    payload.extend_from_slice(data);
    base64::encode_into(&payload, s);
    s.push_str("\n        </DataArray>\n");
}

fn xml_escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// Writes `bytes` to `path.tmp` beside `path`, syncs it and renames it over `path`.
pub(crate) fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), MeshError> {
    let io = |p: &Path| {
        let p: PathBuf = p.to_path_buf();
        move |source| MeshError::Io { path: p, source }
    };
    let mut tmp = path.as_os_str().to_owned();
    tmp.push(".tmp");
    let tmp = PathBuf::from(tmp);
    let mut f = std::fs::File::create(&tmp).map_err(io(&tmp))?;
    f.write_all(bytes).map_err(io(&tmp))?;
    f.sync_all().map_err(io(&tmp))?;
    drop(f);
    std::fs::rename(&tmp, path).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        MeshError::Io {
            path: path.to_path_buf(),
            source: e,
        }
    })
}
