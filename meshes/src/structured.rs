//! Pure-Rust structured hexahedral meshes for tests and benchmarks (no gmsh).
//!
//! Both generators map a structured parametric grid `(ξ, η, ζ) ∈ [0,1]³` to space, node by node,
//! so hex20 mid-edge nodes lie on the exact (curved) geometry. Cells are numbered with ξ fastest;
//! the ξ, η, ζ directions are chosen so that every Jacobian is positive. Node ordering inside
//! cells is squeal's (= VTK's), see [`crate::mesh`].

use crate::mesh::{CellBlock, CellKind, FaceSet, Mesh, Real};
use std::collections::BTreeMap;

/// Corner offsets (in units of the cell size) of the hex8 / hex20 corners, VTK order.
const CORNERS: [[usize; 3]; 8] = [
    [0, 0, 0],
    [1, 0, 0],
    [1, 1, 0],
    [0, 1, 0],
    [0, 0, 1],
    [1, 0, 1],
    [1, 1, 1],
    [0, 1, 1],
];
/// Corner pairs of the hex20 mid-edge nodes 8..20, VTK order.
const EDGES: [[usize; 2]; 12] = [
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
/// Corner cycles of the six hex faces with outward normals: ξ=0, ξ=1, η=0, η=1, ζ=0, ζ=1.
const FACES: [[usize; 4]; 6] = [
    [0, 4, 7, 3],
    [1, 2, 6, 5],
    [0, 1, 5, 4],
    [3, 7, 6, 2],
    [0, 3, 2, 1],
    [4, 5, 6, 7],
];

/// A structured grid of `n[0] × n[1] × n[2]` cells, optionally periodic in η.
struct Grid {
    n: [usize; 3],
    /// Points per cell edge in the refined index space: 1 for hex8, 2 for hex20.
    sub: usize,
    periodic_eta: bool,
    kind: CellKind,
    /// Refined index (i, j, k) → node index, or `usize::MAX` for points that are not nodes.
    index: Vec<usize>,
    dims: [usize; 3],
}

impl Grid {
    fn new(n: [usize; 3], periodic_eta: bool, kind: CellKind) -> Self {
        let sub = if kind == CellKind::Hex20 { 2 } else { 1 };
        let mut dims = [n[0] * sub + 1, n[1] * sub + 1, n[2] * sub + 1];
        if periodic_eta {
            dims[1] = n[1] * sub;
        }
        Grid {
            n,
            sub,
            periodic_eta,
            kind,
            index: vec![usize::MAX; dims[0] * dims[1] * dims[2]],
            dims,
        }
    }

    fn flat(&self, i: usize, j: usize, k: usize) -> usize {
        let j = if self.periodic_eta {
            j % self.dims[1]
        } else {
            j
        };
        (k * self.dims[1] + j) * self.dims[0] + i
    }

    /// True if the refined point is a node: hex8 all points; hex20 points with at most one odd index.
    fn is_node(&self, i: usize, j: usize, k: usize) -> bool {
        self.sub == 1 || (i % 2) + (j % 2) + (k % 2) <= 1
    }

    /// Numbers the nodes and evaluates `map` at their parametric coordinates.
    fn nodes(&mut self, map: &dyn Fn(Real, Real, Real) -> [Real; 3]) -> Vec<[Real; 3]> {
        let mut nodes = Vec::new();
        let scale = [
            (self.n[0] * self.sub) as Real,
            (self.n[1] * self.sub) as Real,
            (self.n[2] * self.sub) as Real,
        ];
        for k in 0..self.dims[2] {
            for j in 0..self.dims[1] {
                for i in 0..self.dims[0] {
                    if self.is_node(i, j, k) {
                        let f = self.flat(i, j, k);
                        self.index[f] = nodes.len();
                        nodes.push(map(
                            i as Real / scale[0],
                            j as Real / scale[1],
                            k as Real / scale[2],
                        ));
                    }
                }
            }
        }
        nodes
    }

    /// Refined index of local node `a` of cell (ci, cj, ck).
    fn local(&self, cell: [usize; 3], a: usize) -> [usize; 3] {
        let s = self.sub;
        let base = [cell[0] * s, cell[1] * s, cell[2] * s];
        let off = if a < 8 {
            let c = CORNERS[a];
            [c[0] * s, c[1] * s, c[2] * s]
        } else {
            let [p, q] = EDGES[a - 8];
            let (c, d) = (CORNERS[p], CORNERS[q]);
            [c[0] + d[0], c[1] + d[1], c[2] + d[2]]
        };
        [base[0] + off[0], base[1] + off[1], base[2] + off[2]]
    }

    fn node(&self, r: [usize; 3]) -> usize {
        self.index[self.flat(r[0], r[1], r[2])]
    }

    /// Volume connectivity, ξ fastest.
    fn cells(&self) -> Vec<usize> {
        let nn = self.kind.n_nodes();
        let mut conn = Vec::with_capacity(self.n[0] * self.n[1] * self.n[2] * nn);
        for ck in 0..self.n[2] {
            for cj in 0..self.n[1] {
                for ci in 0..self.n[0] {
                    for a in 0..nn {
                        conn.push(self.node(self.local([ci, cj, ck], a)));
                    }
                }
            }
        }
        conn
    }

    /// Boundary face block on side `face` (index into [`FACES`]), outward node order.
    fn face_block(&self, name: &str, face: usize) -> CellBlock {
        let axis = face / 2;
        let high = face % 2 == 1;
        let (kind, nn) = match self.kind {
            CellKind::Hex20 => (CellKind::Quad8, 8),
            _ => (CellKind::Quad4, 4),
        };
        let corners = FACES[face];
        let mut conn = Vec::new();
        for ck in 0..self.n[2] {
            for cj in 0..self.n[1] {
                for ci in 0..self.n[0] {
                    let cell = [ci, cj, ck];
                    if cell[axis] != if high { self.n[axis] - 1 } else { 0 } {
                        continue;
                    }
                    for m in 0..nn {
                        let r = if m < 4 {
                            self.local(cell, corners[m])
                        } else {
                            let (p, q) = (corners[m - 4], corners[(m - 3) % 4]);
                            let e = EDGES
                                .iter()
                                .position(|e| (e[0] == p && e[1] == q) || (e[0] == q && e[1] == p))
                                .expect("face edges are hex edges");
                            self.local(cell, 8 + e)
                        };
                        conn.push(self.node(r));
                    }
                }
            }
        }
        let tags = (1..=(conn.len() / nn) as u64).collect();
        CellBlock {
            name: Some(name.to_string()),
            kind,
            conn,
            tags,
        }
    }

    /// Sorted unique nodes of the refined points satisfying `pred(i, j, k)`.
    fn node_set(&self, pred: &dyn Fn(usize, usize, usize) -> bool) -> Vec<usize> {
        let mut set = Vec::new();
        for k in 0..self.dims[2] {
            for j in 0..self.dims[1] {
                for i in 0..self.dims[0] {
                    if self.is_node(i, j, k) && pred(i, j, k) {
                        set.push(self.index[self.flat(i, j, k)]);
                    }
                }
            }
        }
        set.sort_unstable();
        set.dedup();
        set
    }
}

fn check_kind(kind: CellKind) -> CellKind {
    // Structured grids are hexahedral: any other kind selects the hexahedron of its order.
    if kind.is_quadratic() {
        CellKind::Hex20
    } else {
        CellKind::Hex8
    }
}

fn finish(nodes: Vec<[Real; 3]>, grid: &Grid, volume: &str) -> Mesh {
    let conn = grid.cells();
    let ncell = conn.len() / grid.kind.n_nodes();
    Mesh {
        node_tags: (1..=nodes.len() as u64).collect(),
        nodes,
        volumes: vec![CellBlock {
            name: Some(volume.to_string()),
            kind: grid.kind,
            conn,
            tags: (1..=ncell as u64).collect(),
        }],
        faces: BTreeMap::new(),
        node_sets: BTreeMap::new(),
        ..Default::default()
    }
}

/// Box `[0,lx]×[0,ly]×[0,lz]` of `nx×ny×nz` hex8 or hex20 cells (another kind selects the
/// hexahedron of its order; zero counts are raised to 1).
///
/// Volume block `"block"`; node sets and quad4/quad8 face blocks `"x0","x1","y0","y1","z0","z1"`;
/// node set `"z0_edges"`: nodes on the four edges of the face z = 0.
pub fn box_mesh(
    lx: Real,
    ly: Real,
    lz: Real,
    nx: usize,
    ny: usize,
    nz: usize,
    kind: CellKind,
) -> Mesh {
    let kind = check_kind(kind);
    let n = [nx.max(1), ny.max(1), nz.max(1)];
    let mut grid = Grid::new(n, false, kind);
    let nodes = grid.nodes(&|u, v, w| [lx * u, ly * v, lz * w]);
    let mut mesh = finish(nodes, &grid, "block");
    let d = grid.dims;
    let names = ["x0", "x1", "y0", "y1", "z0", "z1"];
    for (f, name) in names.iter().enumerate() {
        let axis = f / 2;
        let val = if f % 2 == 1 { d[axis] - 1 } else { 0 };
        let set = grid.node_set(&|i, j, k| [i, j, k][axis] == val);
        mesh.node_sets.insert(name.to_string(), set);
        mesh.faces.insert(
            name.to_string(),
            FaceSet::from_block(grid.face_block(name, f)),
        );
    }
    let edges =
        grid.node_set(&|i, j, k| k == 0 && (i == 0 || i == d[0] - 1 || j == 0 || j == d[1] - 1));
    mesh.node_sets.insert("z0_edges".to_string(), edges);
    mesh
}

/// Annulus `r_in ≤ r ≤ r_out`, `0 ≤ z ≤ thickness` of `n_circ × n_rad × n_thick` hex8 or hex20
/// cells (counts below 3 / 1 / 1 are raised to them).
///
/// ξ runs along the radius, η around the circumference, ζ along z (positive Jacobian).
/// Volume block `"rotor"`; node sets and quad face blocks `"hub"` (r = r_in), `"outer"`
/// (r = r_out), `"friction_bottom"` (z = 0), `"friction_top"` (z = thickness).
pub fn annulus_mesh(
    r_in: Real,
    r_out: Real,
    thickness: Real,
    n_circ: usize,
    n_rad: usize,
    n_thick: usize,
    kind: CellKind,
) -> Mesh {
    let kind = check_kind(kind);
    let n = [n_rad.max(1), n_circ.max(3), n_thick.max(1)];
    let mut grid = Grid::new(n, true, kind);
    let nodes = grid.nodes(&|u, v, w| {
        let r = r_in + (r_out - r_in) * u;
        let t = 2.0 * std::f64::consts::PI * v;
        [r * t.cos(), r * t.sin(), thickness * w]
    });
    let mut mesh = finish(nodes, &grid, "rotor");
    let d = grid.dims;
    for (name, f) in [
        ("hub", 0),
        ("outer", 1),
        ("friction_bottom", 4),
        ("friction_top", 5),
    ] {
        let axis = f / 2;
        let val = if f % 2 == 1 { d[axis] - 1 } else { 0 };
        let set = grid.node_set(&|i, j, k| [i, j, k][axis] == val);
        mesh.node_sets.insert(name.to_string(), set);
        mesh.faces.insert(
            name.to_string(),
            FaceSet::from_block(grid.face_block(name, f)),
        );
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;

    fn jac_sign_ok(mesh: &Mesh) -> bool {
        // Signed volume of each cell's corner hex via the triple product at corner 0.
        let b = &mesh.volumes[0];
        (0..b.len()).all(|c| {
            let n = b.cell(c);
            let p = |a: usize| mesh.nodes[n[a]];
            let d = |a: usize| {
                let (x, y) = (p(a), p(0));
                [x[0] - y[0], x[1] - y[1], x[2] - y[2]]
            };
            let (e1, e2, e3) = (d(1), d(3), d(4));
            let det = e1[0] * (e2[1] * e3[2] - e2[2] * e3[1])
                - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0])
                + e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]);
            det > 0.0
        })
    }

    #[test]
    fn box_counts_hex8_and_hex20() {
        let m = box_mesh(1.0, 2.0, 3.0, 2, 3, 4, CellKind::Hex8);
        assert_eq!(m.nodes.len(), 3 * 4 * 5);
        assert_eq!(m.volumes[0].len(), 24);
        assert_eq!(m.node_sets["x0"].len(), 4 * 5);
        assert_eq!(m.faces["z1"].len(), 6);
        assert_eq!(m.node_sets["z0_edges"].len(), 2 * 3 + 2 * 4 - 4); // perimeter of the 3 × 4 node grid of z = 0
        assert!(jac_sign_ok(&m));
        let m = box_mesh(1.0, 1.0, 1.0, 1, 1, 1, CellKind::Hex20);
        assert_eq!(m.nodes.len(), 20);
        assert_eq!(m.faces["x0"].kind(), Some(CellKind::Quad8));
        assert_eq!(m.node_sets["z0_edges"].len(), 8);
        assert!(jac_sign_ok(&m));
        // Every node is used by some cell.
        let m = box_mesh(1.0, 1.0, 1.0, 2, 2, 2, CellKind::Hex20);
        let mut used = vec![false; m.nodes.len()];
        m.volumes[0].conn.iter().for_each(|&n| used[n] = true);
        assert!(used.iter().all(|&u| u));
    }

    #[test]
    fn annulus_is_periodic_and_positive() {
        let m = annulus_mesh(0.1, 0.2, 0.01, 8, 2, 1, CellKind::Hex20);
        // corners 8*3*2, radial mid 8*2*2, circumferential mid 8*3*2, thickness mid 8*3
        assert_eq!(m.nodes.len(), 48 + 32 + 48 + 24);
        assert!(jac_sign_ok(&m));
        for &n in &m.node_sets["hub"] {
            let p = m.nodes[n];
            assert!(((p[0] * p[0] + p[1] * p[1]).sqrt() - 0.1).abs() < 1e-12);
        }
        assert_eq!(m.faces["friction_top"].len(), 16);
    }
}
