//! Test surfaces as CAD meshes them: quad4/quad8/tri3/tri6 faces over a parameter square,
//! interior nodes moved by up to a fraction of the cell size (boundary nodes along the
//! boundary), mapped on a plane in any orientation or on a cylinder.

#![allow(dead_code)]

use squeal_contact::{ContactNode, FaceKind, RotorFace};
use std::collections::HashMap;

/// A deterministic generator (xorshift64*), uniform in [−1, 1].
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    pub fn uniform(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        let v = self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11;
        2.0 * (v as f64 / (1u64 << 53) as f64) - 1.0
    }
}

/// A meshed surface: faces and every node with its coordinates.
pub struct Surface {
    pub faces: Vec<RotorFace>,
    pub nodes: Vec<(u64, [f64; 3])>,
}

impl Surface {
    pub fn xyz(&self) -> HashMap<u64, [f64; 3]> {
        self.nodes.iter().copied().collect()
    }
}

/// The map of the parameter square onto 3D space.
pub type Map<'a> = &'a dyn Fn([f64; 2]) -> [f64; 3];

/// A plane through `o` spanned by two orthonormal vectors tilted out of every axis
/// (side length `l`).
pub fn tilted_plane(o: [f64; 3], l: f64) -> impl Fn([f64; 2]) -> [f64; 3] {
    let (a, b) = (0.4f64, 0.7f64);
    let e1 = [a.cos() * b.cos(), a.sin() * b.cos(), b.sin()];
    let e2raw = [-a.sin(), a.cos(), 0.3];
    let d: f64 = (0..3).map(|k| e1[k] * e2raw[k]).sum();
    let e2u = [0, 1, 2].map(|k| e2raw[k] - d * e1[k]);
    let n2 = e2u.iter().map(|v| v * v).sum::<f64>().sqrt();
    let e2 = e2u.map(|v| v / n2);
    move |p| [0, 1, 2].map(|k| o[k] + l * (p[0] * e1[k] + p[1] * e2[k]))
}

/// A cylinder of radius `r` about the y axis, the parameter s along the arc (angle s·`arc`
/// from −arc/2), t along y (length `ly`): the outer surface points away from the axis.
pub fn cylinder(r: f64, arc: f64, ly: f64) -> impl Fn([f64; 2]) -> [f64; 3] {
    move |p| {
        let th = arc * (p[0] - 0.5);
        [r * th.sin(), ly * p[1], r * th.cos()]
    }
}

/// `nx × ny` cells of `kind` over the parameter square (triangles: each cell split along
/// alternating diagonals), corner lattice points moved by up to `distortion` × the cell
/// size (interior points in any direction, boundary points along the boundary, the four
/// corners fixed), mid-side nodes at the parameter midpoints of the edges, everything
/// mapped by `map`. Faces counterclockwise about the map's normal when `up`, else reversed.
/// Node ids from `base` (mid-side nodes from base + 100 000).
pub fn surface(
    kind: FaceKind,
    nx: usize,
    ny: usize,
    distortion: f64,
    seed: u64,
    base: u64,
    up: bool,
    map: Map,
) -> Surface {
    let mut rng = Rng::new(seed);
    let h = (1.0 / nx as f64).min(1.0 / ny as f64);
    let mut st = vec![[0.0; 2]; (nx + 1) * (ny + 1)];
    for j in 0..=ny {
        for i in 0..=nx {
            let mut p = [i as f64 / nx as f64, j as f64 / ny as f64];
            let (bx, by) = (i == 0 || i == nx, j == 0 || j == ny);
            // A random direction and radius ≤ distortion·h (each component, scaled).
            let (mut dx, mut dy) = (rng.uniform(), rng.uniform());
            let len = (dx * dx + dy * dy).sqrt().max(1.0);
            dx *= distortion * h / len;
            dy *= distortion * h / len;
            if !bx {
                p[0] += dx;
            }
            if !by {
                p[1] += dy;
            }
            st[j * (nx + 1) + i] = p;
        }
    }
    let corner = |i: usize, j: usize| j * (nx + 1) + i;
    let mut nodes: Vec<(u64, [f64; 3])> = st
        .iter()
        .enumerate()
        .map(|(k, &p)| (base + k as u64, map(p)))
        .collect();
    let mut mids: HashMap<(usize, usize), u64> = HashMap::new();
    let mut faces = Vec::new();
    let mut push =
        |cs: Vec<usize>, faces: &mut Vec<RotorFace>, nodes: &mut Vec<(u64, [f64; 3])>| {
            let mut cs = cs;
            if !up {
                cs.reverse();
            }
            let mut ids: Vec<u64> = cs.iter().map(|&c| base + c as u64).collect();
            let mut xs: Vec<[f64; 3]> = cs.iter().map(|&c| map(st[c])).collect();
            if kind.n_nodes() > cs.len() {
                for a in 0..cs.len() {
                    let (p, q) = (cs[a], cs[(a + 1) % cs.len()]);
                    let key = (p.min(q), p.max(q));
                    let mid = [0.5 * (st[p][0] + st[q][0]), 0.5 * (st[p][1] + st[q][1])];
                    let next = base + 100_000 + mids.len() as u64;
                    let id = *mids.entry(key).or_insert_with(|| {
                        nodes.push((next, map(mid)));
                        next
                    });
                    ids.push(id);
                    xs.push(map(mid));
                }
            }
            faces.push(RotorFace {
                id: faces.len() as u64,
                kind,
                nodes: ids,
                coords: xs,
            });
        };
    for j in 0..ny {
        for i in 0..nx {
            let (a, b, c, d) = (
                corner(i, j),
                corner(i + 1, j),
                corner(i + 1, j + 1),
                corner(i, j + 1),
            );
            if kind.n_corners() == 4 {
                push(vec![a, b, c, d], &mut faces, &mut nodes);
            } else if (i + j) % 2 == 0 {
                push(vec![a, b, c], &mut faces, &mut nodes);
                push(vec![a, c, d], &mut faces, &mut nodes);
            } else {
                push(vec![a, b, d], &mut faces, &mut nodes);
                push(vec![b, c, d], &mut faces, &mut nodes);
            }
        }
    }
    Surface { faces, nodes }
}

/// n × n Gauss–Legendre on [−1, 1] (n ≤ 4), or the collapsed rule on the unit triangle.
pub fn face_rule(kind: FaceKind) -> Vec<([f64; 2], f64)> {
    let s = (3.0f64 / 7.0 - 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let l = (3.0f64 / 7.0 + 2.0 / 7.0 * (6.0f64 / 5.0).sqrt()).sqrt();
    let ws = (18.0 + 30f64.sqrt()) / 36.0;
    let wl = (18.0 - 30f64.sqrt()) / 36.0;
    let g = [(-l, wl), (-s, ws), (s, ws), (l, wl)];
    let mut out = Vec::new();
    for &(a, wa) in &g {
        for &(b, wb) in &g {
            if kind.n_corners() == 4 {
                out.push(([a, b], wa * wb));
            } else {
                let (u, v) = (0.5 * (a + 1.0), 0.5 * (b + 1.0));
                out.push(([u, (1.0 - u) * v], 0.25 * wa * wb * (1.0 - u)));
            }
        }
    }
    out
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Consistent nodal area vectors ∫N_a n dA (n from the face's node order) of every node.
pub fn area_vectors(s: &Surface) -> HashMap<u64, [f64; 3]> {
    let mut out: HashMap<u64, [f64; 3]> = HashMap::new();
    for f in &s.faces {
        for (xi, w) in face_rule(f.kind) {
            let (n, d) = f.kind.shape(xi);
            let (mut tx, mut ty) = ([0.0; 3], [0.0; 3]);
            for (a, x) in f.coords.iter().enumerate() {
                for k in 0..3 {
                    tx[k] += d[a][0] * x[k];
                    ty[k] += d[a][1] * x[k];
                }
            }
            let c = cross(tx, ty);
            for (a, id) in f.nodes.iter().enumerate() {
                let e = out.entry(*id).or_insert([0.0; 3]);
                for k in 0..3 {
                    e[k] += w * n[a] * c[k];
                }
            }
        }
    }
    out
}

/// Pad contact nodes of a surface with their consistent area vectors.
pub fn contact_nodes(s: &Surface) -> Vec<ContactNode> {
    let areas = area_vectors(s);
    s.nodes
        .iter()
        .map(|&(id, x)| ContactNode {
            id,
            coords: x,
            area: areas[&id],
        })
        .collect()
}

/// Every node id → 3 consecutive DOFs, in the order given.
pub fn dof_map(ids: &[u64]) -> impl Fn(u64) -> [Option<usize>; 3] + '_ {
    let pos: HashMap<u64, usize> = ids.iter().enumerate().map(|(i, &x)| (x, i)).collect();
    move |id| {
        let i = pos[&id];
        [Some(3 * i), Some(3 * i + 1), Some(3 * i + 2)]
    }
}

/// Smallest interior corner angle (degrees) of the faces' corner polygons.
pub fn min_angle_deg(s: &Surface) -> f64 {
    let mut best = 180.0f64;
    for f in &s.faces {
        let nc = f.kind.n_corners();
        for a in 0..nc {
            let (p, q, r) = (
                f.coords[(a + nc - 1) % nc],
                f.coords[a],
                f.coords[(a + 1) % nc],
            );
            let u = [0, 1, 2].map(|k| p[k] - q[k]);
            let v = [0, 1, 2].map(|k| r[k] - q[k]);
            let d: f64 = (0..3).map(|k| u[k] * v[k]).sum();
            let nu = u.iter().map(|x| x * x).sum::<f64>().sqrt();
            let nv = v.iter().map(|x| x * x).sum::<f64>().sqrt();
            best = best.min((d / (nu * nv)).clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    best
}
