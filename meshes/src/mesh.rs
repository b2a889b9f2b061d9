//! The in-memory mesh that every later stage reads.
//!
//! Node ordering inside a cell is squeal's own convention, which equals VTK's (and Abaqus's):
//! - hex8: bottom face 0-1-2-3 counter-clockwise seen from +ζ, top face 4-5-6-7 above them.
//! - hex20: corners 0..8 as hex8, then mid-edge nodes
//!   8:(0,1) 9:(1,2) 10:(2,3) 11:(3,0) 12:(4,5) 13:(5,6) 14:(6,7) 15:(7,4)
//!   16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
//! - quad4: 0-1-2-3 around the face; quad8: corners then 4:(0,1) 5:(1,2) 6:(2,3) 7:(3,0).
//!
//! Readers map file orderings (gmsh's hex20 differs) to this one.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Scalar type of the whole project.
pub type Real = f64;

/// Kind of a cell. Volume kinds carry stiffness and mass; face kinds carry loads and contact areas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CellKind {
    Hex8,
    Hex20,
    Quad4,
    Quad8,
}

impl CellKind {
    /// Nodes per cell.
    pub fn n_nodes(self) -> usize {
        match self {
            CellKind::Hex8 => 8,
            CellKind::Hex20 => 20,
            CellKind::Quad4 => 4,
            CellKind::Quad8 => 8,
        }
    }
    /// True for the volume kinds (hex8, hex20).
    pub fn is_volume(self) -> bool {
        matches!(self, CellKind::Hex8 | CellKind::Hex20)
    }
    /// VTK cell type id (12 hexahedron, 25 quadratic hexahedron, 9 quad, 23 quadratic quad).
    pub fn vtk_type(self) -> u8 {
        match self {
            CellKind::Hex8 => 12,
            CellKind::Hex20 => 25,
            CellKind::Quad4 => 9,
            CellKind::Quad8 => 23,
        }
    }
}

/// Cells of one kind, e.g. one physical volume of a gmsh file.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct CellBlock {
    /// Physical-group name, or `None` for cells outside any named group.
    pub name: Option<String>,
    pub kind: CellKind,
    /// Flat connectivity, `kind.n_nodes()` 0-based node indices per cell, squeal ordering.
    pub conn: Vec<usize>,
    /// Element tags as given in the file (for error messages and outputs).
    pub tags: Vec<u64>,
}

impl CellBlock {
    /// Number of cells.
    pub fn len(&self) -> usize {
        self.tags.len()
    }
    pub fn is_empty(&self) -> bool {
        self.tags.is_empty()
    }
    /// Node indices of cell `i`.
    pub fn cell(&self, i: usize) -> &[usize] {
        let n = self.kind.n_nodes();
        &self.conn[i * n..(i + 1) * n]
    }
}

/// A mesh: nodes, volume blocks, and named node and face sets (from gmsh physical groups).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<[Real; 3]>,
    /// Node tags as given in the file (grid ids), same length as `nodes`.
    pub node_tags: Vec<u64>,
    /// Volume cells (hex8/hex20), one block per physical volume.
    pub volumes: Vec<CellBlock>,
    /// Face cells (quad4/quad8) per physical surface name.
    pub faces: BTreeMap<String, CellBlock>,
    /// Node sets per physical group name (volume, surface, curve or point groups), sorted, unique.
    pub node_sets: BTreeMap<String, Vec<usize>>,
}
