//! gmsh element types squeal reads, and the gmsh → squeal node permutations.

use crate::CellKind;

/// An element type squeal keeps or knowingly skips.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum GmshType {
    /// Type 15: 1-node point (kept for node sets only).
    Point,
    /// Type 1: 2-node line (kept for node sets only).
    Line2,
    /// Type 8: 3-node line (kept for node sets only).
    Line3,
    /// A cell squeal stores.
    Cell(CellKind),
    /// A complete second-order gmsh cell (type 10, 9-node quadrangle; type 12, 27-node
    /// hexahedron; type 13, 18-node prism; type 14, 14-node pyramid) stored as the serendipity
    /// cell `CellKind` (quad8, hex20, wedge15, pyramid13): gmsh lists the
    /// serendipity nodes first, in the same order, then the face and body nodes, which are
    /// dropped. gmsh writes these when `Mesh.SecondOrderIncomplete` does not take effect.
    Complete(CellKind),
}

impl GmshType {
    /// The type for a gmsh type number, or None when squeal does not support it.
    pub fn from_number(t: i64) -> Option<GmshType> {
        Some(match t {
            15 => GmshType::Point,
            1 => GmshType::Line2,
            8 => GmshType::Line3,
            2 => GmshType::Cell(CellKind::Tri3),
            9 => GmshType::Cell(CellKind::Tri6),
            4 => GmshType::Cell(CellKind::Tet4),
            11 => GmshType::Cell(CellKind::Tet10),
            6 => GmshType::Cell(CellKind::Wedge6),
            18 => GmshType::Cell(CellKind::Wedge15),
            13 => GmshType::Complete(CellKind::Wedge15),
            7 => GmshType::Cell(CellKind::Pyramid5),
            19 => GmshType::Cell(CellKind::Pyramid13),
            14 => GmshType::Complete(CellKind::Pyramid13),
            3 => GmshType::Cell(CellKind::Quad4),
            16 => GmshType::Cell(CellKind::Quad8),
            5 => GmshType::Cell(CellKind::Hex8),
            17 => GmshType::Cell(CellKind::Hex20),
            10 => GmshType::Complete(CellKind::Quad8),
            12 => GmshType::Complete(CellKind::Hex20),
            _ => return None,
        })
    }

    pub fn n_nodes(self) -> usize {
        match self {
            GmshType::Point => 1,
            GmshType::Line2 => 2,
            GmshType::Line3 => 3,
            GmshType::Cell(k) => k.n_nodes(),
            GmshType::Complete(CellKind::Quad8) => 9,
            GmshType::Complete(CellKind::Hex20) => 27,
            GmshType::Complete(CellKind::Wedge15) => 18,
            GmshType::Complete(CellKind::Pyramid13) => 14,
            GmshType::Complete(k) => k.n_nodes(),
        }
    }

    /// The cell squeal stores for this type (None: points and lines).
    pub fn cell(self) -> Option<CellKind> {
        match self {
            GmshType::Cell(k) | GmshType::Complete(k) => Some(k),
            _ => None,
        }
    }

    /// Topological dimension (matches the dimension of the physical group it belongs to).
    pub fn dim(self) -> i64 {
        match self {
            GmshType::Point => 0,
            GmshType::Line2 | GmshType::Line3 => 1,
            GmshType::Cell(k) | GmshType::Complete(k) if k.is_volume() => 3,
            GmshType::Cell(_) | GmshType::Complete(_) => 2,
        }
    }
}

/// A readable name for a gmsh element type number (for error messages).
pub(crate) fn type_name(t: i64) -> String {
    match t {
        1 => "2-node line",
        2 => "3-node triangle",
        3 => "4-node quadrangle",
        4 => "4-node tetrahedron",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        8 => "3-node line",
        9 => "6-node triangle",
        10 => "9-node quadrangle",
        11 => "10-node tetrahedron",
        12 => "27-node hexahedron",
        13 => "18-node prism",
        14 => "14-node pyramid",
        15 => "1-node point",
        16 => "8-node quadrangle",
        17 => "20-node hexahedron",
        18 => "15-node prism",
        19 => "13-node pyramid",
        _ => "unknown or unsupported type",
    }
    .to_string()
}

/// `squeal[k] = gmsh[HEX20_FROM_GMSH[k]]`.
///
/// gmsh hex20 edge nodes: 8:(0,1) 9:(0,3) 10:(0,4) 11:(1,2) 12:(1,5) 13:(2,3) 14:(2,6)
/// 15:(3,7) 16:(4,5) 17:(4,7) 18:(5,6) 19:(6,7); squeal (= VTK): 8:(0,1) 9:(1,2) 10:(2,3)
/// 11:(3,0) 12:(4,5) 13:(5,6) 14:(6,7) 15:(7,4) 16:(0,4) 17:(1,5) 18:(2,6) 19:(3,7).
/// Corners (0..8) are the same in both. quad4, quad8 and hex8 orders are the same too.
pub(crate) const HEX20_FROM_GMSH: [usize; 20] = [
    0, 1, 2, 3, 4, 5, 6, 7, 8, 11, 13, 9, 16, 18, 19, 17, 10, 12, 14, 15,
];

/// `squeal[k] = gmsh[TET10_FROM_GMSH[k]]`: gmsh's tet10 has 8:(2,3) 9:(1,3), squeal
/// 8:(1,3) 9:(2,3).
pub(crate) const TET10_FROM_GMSH: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];
/// `squeal[k] = gmsh[WEDGE15_FROM_GMSH[k]]`: gmsh's prism15 (and the first 15 nodes of its
/// prism18) has edges 6:(0,1) 7:(0,2) 8:(0,3) 9:(1,2) 10:(1,4) 11:(2,5) 12:(3,4) 13:(3,5)
/// 14:(4,5).
pub(crate) const WEDGE15_FROM_GMSH: [usize; 15] =
    [0, 1, 2, 3, 4, 5, 6, 9, 7, 12, 14, 13, 8, 10, 11];
/// `squeal[k] = gmsh[PYRAMID13_FROM_GMSH[k]]`: gmsh's pyramid13 (and the first 13 nodes of
/// its pyramid14) has edges 5:(0,1) 6:(0,3) 7:(0,4) 8:(1,2) 9:(1,4) 10:(2,3) 11:(2,4)
/// 12:(3,4).
pub(crate) const PYRAMID13_FROM_GMSH: [usize; 13] = [0, 1, 2, 3, 4, 5, 8, 10, 6, 7, 9, 11, 12];

#[cfg(test)]
mod tests {
    use super::*;

    /// The permutation is a bijection of 0..20 and keeps the corners.
    #[test]
    fn hex20_permutation_is_a_bijection() {
        let mut seen = [false; 20];
        for (k, &g) in HEX20_FROM_GMSH.iter().enumerate() {
            assert!(!seen[g]);
            seen[g] = true;
            if k < 8 {
                assert_eq!(g, k);
            }
        }
        let mut seen = [false; 20];
        for &g in crate::jacobian::mirror(CellKind::Hex20) {
            assert!(!seen[g]);
            seen[g] = true;
        }
    }

    /// Edge endpoints of each scheme (from the gmsh manual's node ordering figure and the
    /// VTK_QUADRATIC_HEXAHEDRON documentation) agree through the permutation.
    #[test]
    fn hex20_permutation_maps_edges() {
        let gmsh: [(usize, usize); 12] = [
            (0, 1),
            (0, 3),
            (0, 4),
            (1, 2),
            (1, 5),
            (2, 3),
            (2, 6),
            (3, 7),
            (4, 5),
            (4, 7),
            (5, 6),
            (6, 7),
        ];
        let squeal: [(usize, usize); 12] = [
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
        let norm = |(a, b): (usize, usize)| (a.min(b), a.max(b));
        for k in 8..20 {
            let g = HEX20_FROM_GMSH[k];
            assert_eq!(norm(squeal[k - 8]), norm(gmsh[g - 8]), "squeal node {k}");
        }
        // Flipping maps each squeal edge to the edge between the flipped corners.
        for k in 8..20 {
            let (a, b) = squeal[k - 8];
            let flip = crate::jacobian::mirror(CellKind::Hex20);
            let (fa, fb) = (flip[a], flip[b]);
            let (oa, ob) = squeal[flip[k] - 8];
            assert_eq!(norm((fa, fb)), norm((oa, ob)), "flipped node {k}");
        }
    }

    /// The permutations put gmsh's nodes where squeal's natural coordinates are: the gmsh
    /// local coordinates below are gmsh 4.15's `getElementProperties` for types 11, 18 and 19
    /// (tet10, prism15, pyramid13).
    #[test]
    fn tet_wedge_pyramid_permutations_match_gmsh_coordinates() {
        let tet10: [[f64; 3]; 10] = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.0, 0.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.0],
            [0.0, 0.0, 0.5],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ];
        let prism15: [[f64; 3]; 15] = [
            [0.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, 1.0, -1.0],
            [0.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
            [0.5, 0.0, -1.0],
            [0.0, 0.5, -1.0],
            [0.0, 0.0, 0.0],
            [0.5, 0.5, -1.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.5, 0.0, 1.0],
            [0.0, 0.5, 1.0],
            [0.5, 0.5, 1.0],
        ];
        let pyramid13: [[f64; 3]; 13] = [
            [-1.0, -1.0, 0.0],
            [1.0, -1.0, 0.0],
            [1.0, 1.0, 0.0],
            [-1.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
            [-1.0, 0.0, 0.0],
            [-0.5, -0.5, 0.5],
            [1.0, 0.0, 0.0],
            [0.5, -0.5, 0.5],
            [0.0, 1.0, 0.0],
            [0.5, 0.5, 0.5],
            [-0.5, 0.5, 0.5],
        ];
        let check = |kind: CellKind, gmsh: &[[f64; 3]], perm: &[usize]| {
            for (k, &g) in perm.iter().enumerate() {
                assert_eq!(
                    crate::topology::node_coords(kind, k),
                    gmsh[g],
                    "{kind} node {k}"
                );
            }
        };
        check(CellKind::Tet10, &tet10, &TET10_FROM_GMSH);
        check(CellKind::Wedge15, &prism15, &WEDGE15_FROM_GMSH);
        check(CellKind::Pyramid13, &pyramid13, &PYRAMID13_FROM_GMSH);
    }
}
