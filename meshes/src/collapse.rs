//! Collapsed (degenerate) hexahedra: a wedge, pyramid or tetrahedron written as a hex8/hex20
//! with repeated nodes (Ansys SOLID185/186 degenerate forms, Abaqus or Nastran decks that
//! repeat grids) is recognised and converted to the cell it is; any other repetition is refused.
//!
//! Every orientation-preserving renumbering of the hexahedron (its 24 rotations) is tried
//! against the three canonical collapses (squeal order): wedge — corners 2 = 3 and 6 = 7;
//! pyramid — 4 = 5 = 6 = 7; tetrahedron — 2 = 3 and 4 = 5 = 6 = 7. For a hex20 the mid-edge
//! nodes of the collapsed edges must be the collapsed corner itself, and two merged edges must
//! share their mid-edge node.

use crate::CellKind;

const HEX_EDGES: [[usize; 2]; 12] = [
    [0, 1],
    [1, 2],
    [2, 3],
    [3, 0],
    [4, 5],
    [5, 6],
    [6, 7],
    [7, 4],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// The 24 rotations of the cube as corner maps (new corner k is old corner `g[k]`).
fn rotations() -> Vec<[usize; 8]> {
    // 90° about z and about x, as images of each corner.
    let rz = [1, 2, 3, 0, 5, 6, 7, 4];
    let rx = [3, 2, 6, 7, 0, 1, 5, 4];
    let mut out: Vec<[usize; 8]> = vec![[0, 1, 2, 3, 4, 5, 6, 7]];
    let mut i = 0;
    while i < out.len() {
        let g = out[i];
        for r in [rz, rx] {
            let h: [usize; 8] = std::array::from_fn(|k| g[r[k]]);
            if !out.contains(&h) {
                out.push(h);
            }
        }
        i += 1;
    }
    out
}

/// Why a repeated-node hexahedron could not be converted.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct CollapseError {
    /// Readable reason, naming the local nodes.
    pub reason: String,
}

/// Converts a hex8 (8 nodes) or hex20 (20 nodes, squeal order) with repeated nodes into the
/// wedge, pyramid or tetrahedron it is: `Ok(None)` when no node repeats, `Ok(Some((kind,
/// nodes)))` for a recognised collapse, `Err` for any other repetition.
pub fn recognise_collapsed_hex(
    cell: &[usize],
) -> Result<Option<(CellKind, Vec<usize>)>, CollapseError> {
    let quadratic = match cell.len() {
        8 => false,
        20 => true,
        n => {
            return Err(CollapseError {
                reason: format!("a hexahedron has 8 or 20 nodes, not {n}"),
            })
        }
    };
    let c = &cell[..8];
    let distinct = |v: &[usize]| (0..v.len()).all(|i| (i + 1..v.len()).all(|j| v[i] != v[j]));
    if distinct(c) {
        if quadratic && !distinct(cell) {
            return Err(CollapseError {
                reason: "its corners are distinct but mid-edge nodes repeat".into(),
            });
        }
        return Ok(None);
    }
    for g in rotations() {
        let n = |k: usize| c[g[k]];
        // Mid-edge node of the rotated edge (p, q).
        let m = |p: usize, q: usize| -> usize {
            let (a, b) = (g[p], g[q]);
            let e = HEX_EDGES
                .iter()
                .position(|&[x, y]| (x, y) == (a, b) || (x, y) == (b, a))
                .unwrap_or(0);
            cell[8 + e]
        };
        let wedge = n(2) == n(3) && n(6) == n(7) && distinct(&[n(0), n(1), n(2), n(4), n(5), n(6)]);
        let pyramid = n(4) == n(5)
            && n(5) == n(6)
            && n(6) == n(7)
            && distinct(&[n(0), n(1), n(2), n(3), n(4)]);
        let tet = n(2) == n(3)
            && n(4) == n(5)
            && n(5) == n(6)
            && n(6) == n(7)
            && distinct(&[n(0), n(1), n(2), n(4)]);
        let bad_mid = |what: &str| CollapseError {
            reason: format!(
                "collapsed to a {what}, but the mid-edge nodes of its collapsed edges are not \
                 the collapsed corners (or its merged edges have different mid-edge nodes)"
            ),
        };
        if wedge {
            let corners = vec![n(0), n(1), n(2), n(4), n(5), n(6)];
            if !quadratic {
                return Ok(Some((CellKind::Wedge6, corners)));
            }
            if m(2, 3) != n(2) || m(6, 7) != n(6) || m(2, 6) != m(3, 7) {
                return Err(bad_mid("wedge"));
            }
            let mut v = corners;
            v.extend([
                m(0, 1),
                m(1, 2),
                m(3, 0),
                m(4, 5),
                m(5, 6),
                m(7, 4),
                m(0, 4),
                m(1, 5),
                m(2, 6),
            ]);
            return Ok(Some((CellKind::Wedge15, v)));
        }
        if pyramid {
            let corners = vec![n(0), n(1), n(2), n(3), n(4)];
            if !quadratic {
                return Ok(Some((CellKind::Pyramid5, corners)));
            }
            if [m(4, 5), m(5, 6), m(6, 7), m(7, 4)]
                .iter()
                .any(|&v| v != n(4))
            {
                return Err(bad_mid("pyramid"));
            }
            let mut v = corners;
            v.extend([
                m(0, 1),
                m(1, 2),
                m(2, 3),
                m(3, 0),
                m(0, 4),
                m(1, 5),
                m(2, 6),
                m(3, 7),
            ]);
            return Ok(Some((CellKind::Pyramid13, v)));
        }
        if tet {
            let corners = vec![n(0), n(1), n(2), n(4)];
            if !quadratic {
                return Ok(Some((CellKind::Tet4, corners)));
            }
            if m(2, 3) != n(2)
                || [m(4, 5), m(5, 6), m(6, 7), m(7, 4)]
                    .iter()
                    .any(|&v| v != n(4))
                || m(2, 6) != m(3, 7)
            {
                return Err(bad_mid("tetrahedron"));
            }
            let mut v = corners;
            v.extend([m(0, 1), m(1, 2), m(3, 0), m(0, 4), m(1, 5), m(2, 6)]);
            return Ok(Some((CellKind::Tet10, v)));
        }
    }
    let mut pairs = Vec::new();
    for i in 0..8 {
        for j in i + 1..8 {
            if c[i] == c[j] {
                pairs.push(format!("{i}={j}"));
            }
        }
    }
    Err(CollapseError {
        reason: format!(
            "its corners repeat as {} (local corners), which is no wedge (2=3, 6=7), pyramid \
             (4=5=6=7) or tetrahedron (2=3, 4=5=6=7) in any numbering",
            pairs.join(", ")
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn there_are_24_rotations_preserving_faces() {
        let r = rotations();
        assert_eq!(r.len(), 24);
        // A rotation maps the hex's faces onto faces (as corner sets).
        let faces: Vec<Vec<usize>> = CellKind::Hex8
            .faces()
            .iter()
            .map(|f| {
                let mut v = f.nodes.to_vec();
                v.sort_unstable();
                v
            })
            .collect();
        for g in &r {
            for f in &faces {
                let mut img: Vec<usize> = f.iter().map(|&k| g[k]).collect();
                img.sort_unstable();
                assert!(faces.contains(&img));
            }
        }
    }

    #[test]
    fn collapses_are_recognised_in_any_numbering() {
        // Ansys-style prism: I J K K M N O O.
        let (k, v) = recognise_collapsed_hex(&[10, 11, 12, 12, 13, 14, 15, 15])
            .unwrap()
            .unwrap();
        assert_eq!((k, v), (CellKind::Wedge6, vec![10, 11, 12, 13, 14, 15]));
        // The same prism collapsed on another pair of faces: corners 1 = 2, 5 = 6.
        let (k, v) = recognise_collapsed_hex(&[10, 11, 11, 12, 13, 14, 14, 15])
            .unwrap()
            .unwrap();
        assert_eq!(k, CellKind::Wedge6);
        let mut s = v.clone();
        s.sort_unstable();
        assert_eq!(s, [10, 11, 12, 13, 14, 15]);
        let (k, _) = recognise_collapsed_hex(&[1, 2, 3, 4, 5, 5, 5, 5])
            .unwrap()
            .unwrap();
        assert_eq!(k, CellKind::Pyramid5);
        let (k, v) = recognise_collapsed_hex(&[1, 2, 3, 3, 5, 5, 5, 5])
            .unwrap()
            .unwrap();
        assert_eq!((k, v), (CellKind::Tet4, vec![1, 2, 3, 5]));
        assert_eq!(
            recognise_collapsed_hex(&[0, 1, 2, 3, 4, 5, 6, 7]).unwrap(),
            None
        );
        let e = recognise_collapsed_hex(&[0, 0, 2, 3, 4, 5, 6, 7]).unwrap_err();
        assert!(e.reason.contains("0=1"), "{}", e.reason);
        // hex20 prism: the collapsed edges' mid nodes are the corners, merged edges share one.
        let mut h = vec![10, 11, 12, 12, 13, 14, 15, 15];
        h.extend([20, 21, 12, 22, 23, 24, 15, 25, 26, 27, 28, 28]);
        let (k, v) = recognise_collapsed_hex(&h).unwrap().unwrap();
        assert_eq!(k, CellKind::Wedge15);
        assert_eq!(
            v,
            [10, 11, 12, 13, 14, 15, 20, 21, 22, 23, 24, 25, 26, 27, 28]
        );
        h[10] = 99;
        assert!(recognise_collapsed_hex(&h).is_err());
    }
}
