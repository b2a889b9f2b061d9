//! From a reader's cells (in squeal node order, possibly mirrored) to a [`Mesh`]: orientation,
//! validity, the nodes the cells use numbered in input order, one block per (name, kind),
//! node and face sets.

use super::faces;
use crate::collapse::recognise_collapsed_hex;
use crate::jacobian::mirror;
use crate::section::Section;
use crate::{CellBlock, CellKind, FaceSet, Mesh, MeshError};
use std::collections::{BTreeMap, HashMap};

/// One volume cell as read: node indices into [`Builder::nodes`], squeal order.
#[derive(Debug, Clone)]
pub(crate) struct RawCell {
    pub kind: CellKind,
    pub nodes: Vec<usize>,
    pub tag: u64,
    /// Block (and material) name; None for cells without one.
    pub block: Option<String>,
    /// Where it is defined, for errors.
    pub file: String,
    pub line: usize,
    /// Its name in errors, e.g. `CHEXA 12` or `element 12 (C3D20R)`.
    pub what: String,
}

/// Every input node and the cells selected.
#[derive(Debug, Default)]
pub(crate) struct Builder {
    pub nodes: Vec<[f64; 3]>,
    pub tags: Vec<u64>,
    pub cells: Vec<RawCell>,
}

impl Builder {
    /// Orients every cell (a hexahedron with repeated nodes becomes the wedge, pyramid or
    /// tetrahedron it is; a mirrored cell is reordered) and checks it; errors name the cell.
    pub fn orient(&mut self) -> Result<(), MeshError> {
        for c in &mut self.cells {
            if matches!(c.kind, CellKind::Hex8 | CellKind::Hex20) {
                match recognise_collapsed_hex(&c.nodes) {
                    Ok(None) => {}
                    Ok(Some((kind, nodes))) => {
                        c.kind = kind;
                        c.nodes = nodes;
                    }
                    Err(e) => {
                        return Err(MeshError::Parse {
                            file: c.file.clone(),
                            line: c.line,
                            message: format!(
                                "{} ({}) repeats nodes but is no wedge, pyramid or tetrahedron: \
                                 {}",
                                c.what, c.kind, e.reason
                            ),
                        })
                    }
                }
            }
            let x: Vec<[f64; 3]> = c.nodes.iter().map(|&i| self.nodes[i]).collect();
            match faces::orientation(c.kind, &x) {
                faces::Orientation::Positive => {}
                faces::Orientation::Mirrored => {
                    let old = c.nodes.clone();
                    for (k, &f) in mirror(c.kind).iter().enumerate() {
                        c.nodes[k] = old[f];
                    }
                }
                faces::Orientation::Degenerate(det) => {
                    return Err(MeshError::Parse {
                        file: c.file.clone(),
                        line: c.line,
                        message: format!(
                            "{} ({}) is degenerate: Jacobian determinant {det:e} at its centroid",
                            c.what, c.kind
                        ),
                    })
                }
            }
            let x: Vec<[f64; 3]> = c.nodes.iter().map(|&i| self.nodes[i]).collect();
            if let Some((a, det)) = faces::folded_node(c.kind, &x) {
                return Err(MeshError::Parse {
                    file: c.file.clone(),
                    line: c.line,
                    message: format!(
                        "{} ({}) is inverted at its node {} (Jacobian determinant {det:.4e} \
                         there): move the node back inside the cell",
                        c.what, c.kind, self.tags[c.nodes[a]]
                    ),
                });
            }
        }
        Ok(())
    }

    /// The local face of cell `cell` whose corners are the input nodes `corners` (any order):
    /// its kind and its nodes (outward, squeal face order).
    pub fn face_with_corners(
        &self,
        cell: usize,
        corners: &[usize],
    ) -> Option<(CellKind, Vec<usize>)> {
        let c = &self.cells[cell];
        let mut want: Vec<usize> = corners.to_vec();
        want.sort_unstable();
        for f in c.kind.faces() {
            let nc = f.kind.n_corners();
            let mut have: Vec<usize> = f.nodes[..nc].iter().map(|&k| c.nodes[k]).collect();
            have.sort_unstable();
            if have == want {
                return Some((f.kind, f.nodes.iter().map(|&k| c.nodes[k]).collect()));
            }
        }
        None
    }

    /// The faces of `cells` that no other cell of the builder shares: (kind, nodes, cell tag).
    pub fn free_faces(&self, cells: &[usize]) -> Vec<(CellKind, Vec<usize>, u64)> {
        let mut count: HashMap<Vec<usize>, usize> = HashMap::new();
        for c in &self.cells {
            for f in c.kind.faces() {
                let mut key: Vec<usize> = f.nodes[..f.kind.n_corners()]
                    .iter()
                    .map(|&k| c.nodes[k])
                    .collect();
                key.sort_unstable();
                *count.entry(key).or_insert(0) += 1;
            }
        }
        let mut out = Vec::new();
        for &ci in cells {
            let c = &self.cells[ci];
            for f in c.kind.faces() {
                let mut key: Vec<usize> = f.nodes[..f.kind.n_corners()]
                    .iter()
                    .map(|&k| c.nodes[k])
                    .collect();
                key.sort_unstable();
                if count.get(&key) == Some(&1) {
                    out.push((f.kind, f.nodes.iter().map(|&k| c.nodes[k]).collect(), c.tag));
                }
            }
        }
        out
    }

    /// The mesh: the nodes the cells use (input order), blocks per (name, kind) in order of
    /// first appearance, node sets and face sets mapped to the kept nodes (nodes outside every
    /// cell dropped from node sets; faces must use kept nodes), sections and fixed DOFs.
    pub fn finish(
        self,
        node_sets: BTreeMap<String, Vec<usize>>,
        face_sets: BTreeMap<String, Vec<(CellKind, Vec<usize>, u64)>>,
        sections: BTreeMap<String, Section>,
        fixed: Vec<(usize, usize)>,
    ) -> Mesh {
        const UNUSED: usize = usize::MAX;
        let mut new = vec![UNUSED; self.nodes.len()];
        for c in &self.cells {
            for &i in &c.nodes {
                new[i] = 0;
            }
        }
        let mut mesh = Mesh::default();
        for (i, x) in self.nodes.iter().enumerate() {
            if new[i] != UNUSED {
                new[i] = mesh.nodes.len();
                mesh.nodes.push(*x);
                mesh.node_tags.push(self.tags[i]);
            }
        }
        let mut block_of: HashMap<(Option<String>, CellKind), usize> = HashMap::new();
        for c in &self.cells {
            let b = *block_of
                .entry((c.block.clone(), c.kind))
                .or_insert_with(|| {
                    mesh.volumes.push(CellBlock::new(c.block.clone(), c.kind));
                    mesh.volumes.len() - 1
                });
            mesh.volumes[b].conn.extend(c.nodes.iter().map(|&i| new[i]));
            mesh.volumes[b].tags.push(c.tag);
        }
        for (name, nodes) in node_sets {
            let mut v: Vec<usize> = nodes
                .into_iter()
                .filter_map(|i| new.get(i).copied().filter(|&j| j != UNUSED))
                .collect();
            v.sort_unstable();
            v.dedup();
            mesh.node_sets.insert(name, v);
        }
        for (name, faces) in face_sets {
            let mut set = FaceSet::default();
            let mut nodes = Vec::new();
            for (kind, f, tag) in faces {
                let conn: Vec<usize> = f.iter().map(|&i| new[i]).collect();
                debug_assert!(conn.iter().all(|&j| j != UNUSED));
                nodes.extend_from_slice(&conn);
                set.block_mut(kind, Some(&name))
                    .conn
                    .extend_from_slice(&conn);
                set.block_mut(kind, Some(&name)).tags.push(tag);
            }
            // A face set is also a node set of its nodes (as a gmsh physical surface is).
            nodes.sort_unstable();
            nodes.dedup();
            mesh.node_sets.entry(name.clone()).or_insert(nodes);
            mesh.faces.insert(name, set);
        }
        mesh.sections = sections;
        let mut fx: Vec<(usize, usize)> = fixed
            .into_iter()
            .filter_map(|(i, k)| new.get(i).copied().filter(|&j| j != UNUSED).map(|j| (j, k)))
            .collect();
        fx.sort_unstable();
        fx.dedup();
        mesh.fixed = fx;
        mesh
    }
}
