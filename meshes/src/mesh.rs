//! The in-memory mesh that every later stage reads.
//!
//! Node ordering inside a cell is squeal's own convention, which equals VTK's (and, for the
//! hexahedra, tetrahedra and wedges, Abaqus's). Corners come first, then one node per edge in
//! the order listed; natural coordinates are given for the corners.
//! - hex8: bottom face 0-1-2-3 counter-clockwise seen from +ζ, top face 4-5-6-7 above them
//!   (ξ, η, ζ ∈ [−1, 1]).
//! - hex20: corners 0..8 as hex8, then mid-edge nodes
//!   8:(0,1) 9:(1,2) 10:(2,3) 11:(3,0) 12:(4,5) 13:(5,6) 14:(6,7) 15:(7,4)
//!   16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
//! - tet4: corners 0:(0,0,0) 1:(1,0,0) 2:(0,1,0) 3:(0,0,1) in (ξ, η, ζ); 0-1-2 counter-clockwise
//!   seen from 3.
//! - tet10: corners as tet4, then 4:(0,1) 5:(1,2) 6:(2,0) 7:(0,3) 8:(1,3) 9:(2,3).
//! - wedge6: bottom triangle 0:(0,0,−1) 1:(1,0,−1) 2:(0,1,−1) in (ξ, η, ζ), ζ ∈ [−1, 1], top
//!   triangle 3-4-5 above them; 0-1-2 counter-clockwise seen from the top. These are VTK's own
//!   parametric coordinates (`vtkWedge::GetParametricCoords`) and gmsh's and Abaqus's
//!   orientation; VTK's class documentation describes the opposite winding, which its
//!   parametric map does not follow.
//! - wedge15: corners as wedge6, then 6:(0,1) 7:(1,2) 8:(2,0) 9:(3,4) 10:(4,5) 11:(5,3)
//!   12:(0,3) 13:(1,4) 14:(2,5).
//! - pyramid5: base 0:(−1,−1,0) 1:(1,−1,0) 2:(1,1,0) 3:(−1,1,0) counter-clockwise seen from
//!   the apex 4:(0,0,1).
//! - pyramid13: corners as pyramid5, then 5:(0,1) 6:(1,2) 7:(2,3) 8:(3,0) 9:(0,4) 10:(1,4)
//!   11:(2,4) 12:(3,4).
//! - quad4: 0-1-2-3 around the face; quad8: corners then 4:(0,1) 5:(1,2) 6:(2,3) 7:(3,0).
//! - tri3: 0-1-2 around the face; tri6: corners then 3:(0,1) 4:(1,2) 5:(2,0).
//!
//! A cell is well oriented when det ∂x/∂ξ > 0 in these natural coordinates; readers reorder
//! cells that come in mirrored. Readers map file orderings (gmsh's hex20, tet10, wedge15 and
//! pyramid13 differ) to this one. The local faces of each volume kind are in
//! [`CellKind::faces`], the edges of each quadratic kind in [`CellKind::edges`].

use crate::topology::{self, LocalFace};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// The workspace's real scalar, the one definition: every other crate re-exports or uses
/// this (`squeal_solver::Real`, `squeal_contact::Real`, `squeal_reduction::Real` are it).
pub type Real = f64;

/// Kind of a cell. Volume kinds carry stiffness and mass; face kinds carry loads and contact areas.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CellKind {
    Hex8,
    Hex20,
    Quad4,
    Quad8,
    Tet4,
    Tet10,
    Wedge6,
    Wedge15,
    Pyramid5,
    Pyramid13,
    Tri3,
    Tri6,
}

impl CellKind {
    /// Every kind, volumes first.
    pub const ALL: [CellKind; 12] = [
        CellKind::Hex8,
        CellKind::Hex20,
        CellKind::Tet4,
        CellKind::Tet10,
        CellKind::Wedge6,
        CellKind::Wedge15,
        CellKind::Pyramid5,
        CellKind::Pyramid13,
        CellKind::Quad4,
        CellKind::Quad8,
        CellKind::Tri3,
        CellKind::Tri6,
    ];

    /// Nodes per cell.
    pub fn n_nodes(self) -> usize {
        match self {
            CellKind::Hex8 => 8,
            CellKind::Hex20 => 20,
            CellKind::Quad4 => 4,
            CellKind::Quad8 => 8,
            CellKind::Tet4 => 4,
            CellKind::Tet10 => 10,
            CellKind::Wedge6 => 6,
            CellKind::Wedge15 => 15,
            CellKind::Pyramid5 => 5,
            CellKind::Pyramid13 => 13,
            CellKind::Tri3 => 3,
            CellKind::Tri6 => 6,
        }
    }

    /// Corner (vertex) nodes per cell: the first `n_corners` nodes of the cell.
    pub fn n_corners(self) -> usize {
        self.linear().n_nodes()
    }

    /// True for the volume kinds (hexahedra, tetrahedra, wedges, pyramids).
    pub fn is_volume(self) -> bool {
        !matches!(
            self,
            CellKind::Quad4 | CellKind::Quad8 | CellKind::Tri3 | CellKind::Tri6
        )
    }

    /// True for the kinds with mid-edge nodes (hex20, tet10, wedge15, pyramid13, quad8, tri6).
    pub fn is_quadratic(self) -> bool {
        self.n_nodes() != self.n_corners()
    }

    /// The kind with the same corners and no mid-edge nodes (hex20 → hex8; linear kinds: self).
    pub fn linear(self) -> CellKind {
        match self {
            CellKind::Hex20 => CellKind::Hex8,
            CellKind::Quad8 => CellKind::Quad4,
            CellKind::Tet10 => CellKind::Tet4,
            CellKind::Wedge15 => CellKind::Wedge6,
            CellKind::Pyramid13 => CellKind::Pyramid5,
            CellKind::Tri6 => CellKind::Tri3,
            k => k,
        }
    }

    /// The kind with the same corners and a node on every edge (hex8 → hex20; quadratic
    /// kinds: self).
    pub fn quadratic(self) -> CellKind {
        match self {
            CellKind::Hex8 => CellKind::Hex20,
            CellKind::Quad4 => CellKind::Quad8,
            CellKind::Tet4 => CellKind::Tet10,
            CellKind::Wedge6 => CellKind::Wedge15,
            CellKind::Pyramid5 => CellKind::Pyramid13,
            CellKind::Tri3 => CellKind::Tri6,
            k => k,
        }
    }

    /// VTK cell type id (12 hexahedron, 25 quadratic hexahedron, 10 tetra, 24 quadratic tetra,
    /// 13 wedge, 26 quadratic wedge, 14 pyramid, 27 quadratic pyramid, 9 quad, 23 quadratic
    /// quad, 5 triangle, 22 quadratic triangle).
    pub fn vtk_type(self) -> u8 {
        match self {
            CellKind::Hex8 => 12,
            CellKind::Hex20 => 25,
            CellKind::Quad4 => 9,
            CellKind::Quad8 => 23,
            CellKind::Tet4 => 10,
            CellKind::Tet10 => 24,
            CellKind::Wedge6 => 13,
            CellKind::Wedge15 => 26,
            CellKind::Pyramid5 => 14,
            CellKind::Pyramid13 => 27,
            CellKind::Tri3 => 5,
            CellKind::Tri6 => 22,
        }
    }

    /// Readable name ("hex20", "tet10", "wedge15", …), as in the scene files and messages.
    pub fn name(self) -> &'static str {
        match self {
            CellKind::Hex8 => "hex8",
            CellKind::Hex20 => "hex20",
            CellKind::Quad4 => "quad4",
            CellKind::Quad8 => "quad8",
            CellKind::Tet4 => "tet4",
            CellKind::Tet10 => "tet10",
            CellKind::Wedge6 => "wedge6",
            CellKind::Wedge15 => "wedge15",
            CellKind::Pyramid5 => "pyramid5",
            CellKind::Pyramid13 => "pyramid13",
            CellKind::Tri3 => "tri3",
            CellKind::Tri6 => "tri6",
        }
    }

    /// The family's name ("hexahedron", "tetrahedron", "wedge", "pyramid", "quadrilateral",
    /// "triangle"), as error messages name a cell.
    pub fn family(self) -> &'static str {
        match self.linear() {
            CellKind::Hex8 => "hexahedron",
            CellKind::Tet4 => "tetrahedron",
            CellKind::Wedge6 => "wedge",
            CellKind::Pyramid5 => "pyramid",
            CellKind::Quad4 => "quadrilateral",
            _ => "triangle",
        }
    }

    /// The local faces of a volume kind, each with its face kind and its local node indices
    /// (corners first, counter-clockwise seen from outside the cell, then the mid-edge nodes in
    /// the face kind's order). Empty for face kinds.
    pub fn faces(self) -> &'static [LocalFace] {
        topology::faces(self)
    }

    /// The edges of a kind as corner pairs: for a quadratic kind, node `n_corners() + i` sits
    /// on edge `i`.
    pub fn edges(self) -> &'static [[usize; 2]] {
        topology::edges(self)
    }
}

impl std::fmt::Display for CellKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
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
    /// An empty block.
    pub fn new(name: Option<String>, kind: CellKind) -> Self {
        CellBlock {
            name,
            kind,
            conn: Vec::new(),
            tags: Vec::new(),
        }
    }
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

pub use crate::face_set::{Face, FaceSet};

/// A mesh: nodes, volume blocks, and named node and face sets (from gmsh physical groups).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Mesh {
    /// Node coordinates.
    pub nodes: Vec<[Real; 3]>,
    /// Node tags as given in the file (grid ids), same length as `nodes`.
    pub node_tags: Vec<u64>,
    /// Volume cells, one block per physical volume and kind.
    pub volumes: Vec<CellBlock>,
    /// Face cells (quad4/quad8/tri3/tri6, one block per kind) per physical surface name.
    pub faces: BTreeMap<String, FaceSet>,
    /// Node sets per physical group name (volume, surface, curve or point groups), sorted, unique.
    pub node_sets: BTreeMap<String, Vec<usize>>,
    /// Material and material axes of volume blocks, by block name, as the file gives them
    /// (Nastran PSOLID, Abaqus *SOLID SECTION; default: none, e.g. gmsh files).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub sections: BTreeMap<String, crate::section::Section>,
    /// DOFs the file holds at zero (Nastran SPC/SPC1/GRID PS, Abaqus *BOUNDARY): (node index,
    /// global component 0..3), sorted, unique (default: none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub fixed: Vec<(usize, usize)>,
}
