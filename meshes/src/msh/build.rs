//! From the file's raw nodes and elements to a [`Mesh`]: node renumbering, blocks per physical
//! volume, faces per physical surface, node sets per physical group, hex20 reordering and
//! orientation.

use super::element_types::{
    HEX20_FROM_GMSH, PYRAMID13_FROM_GMSH, TET10_FROM_GMSH, WEDGE15_FROM_GMSH,
};
use super::{RawElement, RawMesh};
use crate::collapse::recognise_collapsed_hex;
use crate::jacobian::{centroid_jacobian, mirror, node_jacobians};
use crate::{CellBlock, CellKind, Mesh, MeshError};
use std::collections::{BTreeMap, HashMap};

const UNUSED: usize = usize::MAX;

pub(crate) fn build(raw: RawMesh, file: &str) -> Result<Mesh, MeshError> {
    // Node tag → index in raw.nodes.
    let mut by_tag: HashMap<u64, usize> = HashMap::with_capacity(raw.nodes.len());
    for (i, n) in raw.nodes.iter().enumerate() {
        if let Some(&j) = by_tag.get(&n.tag) {
            return Err(MeshError::parse(
                file,
                n.line,
                format!(
                    "node tag {} defined twice (first on line {})",
                    n.tag, raw.nodes[j].line
                ),
            ));
        }
        by_tag.insert(n.tag, i);
    }
    // Element node tags → raw node indices (unknown tags are errors).
    let mut conn_raw = Vec::with_capacity(raw.conn.len());
    for e in &raw.elements {
        for &t in &raw.conn[e.start..e.start + e.ty.n_nodes()] {
            match by_tag.get(&t) {
                Some(&i) => conn_raw.push(i),
                None => {
                    return Err(MeshError::UnknownNode {
                        file: file.to_string(),
                        line: e.line,
                        element_tag: e.tag,
                        node_tag: t,
                    })
                }
            }
        }
    }
    let nodes_of = |e: &RawElement| &conn_raw[e.start..e.start + e.ty.n_nodes()];
    // The nodes the stored cell keeps (a complete second-order cell drops its face and body
    // nodes).
    let kept_of = |e: &RawElement| {
        let n = e.ty.cell().map_or(e.ty.n_nodes(), |k| k.n_nodes());
        &nodes_of(e)[..n]
    };
    let is_volume = |e: &RawElement| e.ty.cell().is_some_and(|k| k.is_volume());

    // Keep the nodes of volume cells, numbered in file order.
    let mut new_index = vec![UNUSED; raw.nodes.len()];
    for e in raw.elements.iter().filter(|e| is_volume(e)) {
        for &i in kept_of(e) {
            new_index[i] = 0;
        }
    }
    let mut mesh = Mesh::default();
    for (i, n) in raw.nodes.iter().enumerate() {
        if new_index[i] != UNUSED {
            new_index[i] = mesh.nodes.len();
            mesh.nodes.push(n.xyz);
            mesh.node_tags.push(n.tag);
        }
    }
    if mesh.nodes.is_empty() {
        return Err(MeshError::NoVolumeCells {
            file: file.to_string(),
        });
    }

    let name_of = |dim: i64, tag: i64| -> String {
        raw.names
            .get(&(dim, tag))
            .cloned()
            .unwrap_or_else(|| format!("physical_{tag}"))
    };

    // Volume blocks, keyed by (physical name, kind) in order of first appearance.
    let mut block_of: HashMap<(Option<String>, CellKind), usize> = HashMap::new();
    let mut sets: BTreeMap<String, Vec<usize>> = BTreeMap::new();
    let mut cell = Vec::with_capacity(20);
    for e in &raw.elements {
        let phys = &raw.phys_lists[e.phys];
        let dim = e.ty.dim();
        match e.ty.cell() {
            Some(kind) if kind.is_volume() => {
                cell.clear();
                let nodes = kept_of(e);
                let perm: &[usize] = match kind {
                    CellKind::Hex20 => &HEX20_FROM_GMSH,
                    CellKind::Tet10 => &TET10_FROM_GMSH,
                    CellKind::Wedge15 => &WEDGE15_FROM_GMSH,
                    CellKind::Pyramid13 => &PYRAMID13_FROM_GMSH,
                    _ => &[],
                };
                if perm.is_empty() {
                    cell.extend_from_slice(nodes);
                } else {
                    cell.extend(perm.iter().map(|&k| nodes[k]));
                }
                for c in cell.iter_mut() {
                    *c = new_index[*c];
                }
                // A hexahedron with repeated nodes: the wedge, pyramid or tet it collapses to.
                let mut kind = kind;
                if matches!(kind, CellKind::Hex8 | CellKind::Hex20) {
                    match recognise_collapsed_hex(&cell) {
                        Ok(None) => {}
                        Ok(Some((k, v))) => {
                            kind = k;
                            cell.clear();
                            cell.extend(v);
                        }
                        Err(c) => {
                            return Err(MeshError::CollapsedCell {
                                file: file.to_string(),
                                line: e.line,
                                element_tag: e.tag,
                                cell: kind.family(),
                                reason: c.reason,
                            })
                        }
                    }
                }
                orient(&mesh.nodes, kind, &mut cell, file, e)?;
                check_nodes(&mesh, kind, &cell, file, e)?;
                let name = phys.first().map(|&t| name_of(dim, t));
                let b = *block_of.entry((name.clone(), kind)).or_insert_with(|| {
                    mesh.volumes.push(CellBlock {
                        name,
                        kind,
                        conn: Vec::new(),
                        tags: Vec::new(),
                    });
                    mesh.volumes.len() - 1
                });
                mesh.volumes[b].conn.extend_from_slice(&cell);
                mesh.volumes[b].tags.push(e.tag);
            }
            Some(kind) => {
                let Some(&first) = phys.first() else {
                    continue;
                };
                let surface = name_of(dim, first);
                let mut conn = Vec::with_capacity(kind.n_nodes());
                for (&i, &t) in kept_of(e)
                    .iter()
                    .zip(&raw.conn[e.start..e.start + kind.n_nodes()])
                {
                    if new_index[i] == UNUSED {
                        return Err(MeshError::FaceNodeNotInVolume {
                            file: file.to_string(),
                            line: e.line,
                            element_tag: e.tag,
                            surface,
                            node_tag: t,
                        });
                    }
                    conn.push(new_index[i]);
                }
                for &t in phys {
                    let name = name_of(dim, t);
                    let set = mesh.faces.entry(name.clone()).or_default();
                    // One surface may hold quadrilaterals and triangles, but not linear and
                    // quadratic faces together.
                    if let Some(first) = set
                        .kinds()
                        .find(|k| k.is_quadratic() != kind.is_quadratic())
                    {
                        return Err(MeshError::MixedFaceKinds {
                            file: file.to_string(),
                            line: e.line,
                            surface: name,
                            first,
                            second: kind,
                            element_tag: e.tag,
                        });
                    }
                    let block = set.block_mut(kind, Some(&name));
                    block.conn.extend_from_slice(&conn);
                    block.tags.push(e.tag);
                }
            }
            None => {}
        }
        // Node sets of every physical group, restricted to kept nodes.
        for &t in phys {
            let set = sets.entry(name_of(dim, t)).or_default();
            set.extend(
                nodes_of(e)
                    .iter()
                    .map(|&i| new_index[i])
                    .filter(|&i| i != UNUSED),
            );
        }
    }
    for set in sets.values_mut() {
        set.sort_unstable();
        set.dedup();
    }
    mesh.node_sets = sets;
    Ok(mesh)
}

/// After [`orient`]: det J at every node of the cell (a linear kind's corners, a quadratic
/// kind's corners and mid-edge nodes, a pyramid's apex from each base corner's direction) must
/// be positive (above 1e-12 × the cell's size cubed), else the cell is folded near that node.
fn check_nodes(
    mesh: &Mesh,
    kind: CellKind,
    cell: &[usize],
    file: &str,
    e: &RawElement,
) -> Result<(), MeshError> {
    let x: Vec<[f64; 3]> = cell.iter().map(|&i| mesh.nodes[i]).collect();
    let centroid_det = centroid_jacobian(kind, &x);
    let tol = 1e-12 * cell_size(&x[..kind.n_corners()]).powi(3);
    match node_jacobians(kind, &x).first() {
        Some(&(a, det)) if det.is_nan() || det <= tol => Err(MeshError::InvertedAtNode {
            file: file.to_string(),
            line: e.line,
            element_tag: e.tag,
            kind: if a < kind.n_corners() {
                "corner"
            } else {
                "mid-edge"
            },
            node_tag: mesh.node_tags[cell[a]],
            det,
            centroid_det,
            cell: kind.family(),
        }),
        _ => Ok(()),
    }
}

/// The largest corner-to-corner extent of a cell (max norm).
fn cell_size(corners: &[[f64; 3]]) -> f64 {
    let mut size: f64 = 0.0;
    for a in corners {
        for b in corners {
            let d = (0..3).map(|k| (a[k] - b[k]).abs()).fold(0.0, f64::max);
            size = size.max(d);
        }
    }
    size
}

/// Mirrors a cell with a negative centroid Jacobian; a (near) zero one is an error.
fn orient(
    nodes: &[[f64; 3]],
    kind: CellKind,
    cell: &mut [usize],
    file: &str,
    e: &RawElement,
) -> Result<(), MeshError> {
    let x: Vec<[f64; 3]> = cell.iter().map(|&i| nodes[i]).collect();
    let det = centroid_jacobian(kind, &x);
    // Scale: the cube of the largest corner-to-corner extent of the cell.
    let size = cell_size(&x[..kind.n_corners()]);
    if !det.is_finite() || det.abs() <= 1e-12 * size.powi(3) {
        return Err(MeshError::DegenerateCell {
            file: file.to_string(),
            line: e.line,
            element_tag: e.tag,
            det,
            cell: kind.family(),
        });
    }
    if det < 0.0 {
        let old: Vec<usize> = cell.to_vec();
        for (k, &f) in mirror(kind).iter().enumerate() {
            cell[k] = old[f];
        }
    }
    Ok(())
}
