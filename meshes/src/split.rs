//! Conforming meshes of every element family from a hexahedral mesh: splitting hex8 cells into
//! wedges, tetrahedra and pyramids, and raising a linear mesh to its quadratic kinds.
//!
//! Used by the element verification (patch tests, FV52, convergence, mixed meshes); a mesh
//! made here is conforming by construction, so any difference from the hex mesh of the same
//! body is the elements'.

use crate::{CellBlock, CellKind, FaceSet, Mesh, Real};
use std::collections::{BTreeMap, HashMap};

/// What becomes of one hex8 cell.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HexSplit {
    /// Kept as a hexahedron.
    Keep,
    /// Two wedges, cut along the diagonal 0–2 of the bottom face (4–6 of the top).
    Wedges,
    /// Tetrahedra around a new centre node, with pyramids on the faces shared with kept hexes
    /// and with the wedges' quadrilateral sides (the hex–tet transition).
    Tets,
}

fn key(q: &[usize]) -> [usize; 4] {
    let mut k = [q[0], q[1], q[2], q[3]];
    k.sort_unstable();
    k
}

/// Splits the hex8 cells of `mesh` as `choose(block, cell)` says (other kinds are kept).
///
/// Faces cut into triangles (a tet-split cell's faces towards other tet-split cells or the
/// boundary, the wedges' bottom and top faces) share one diagonal on both sides: the wedge's
/// where a wedge owns the face, else the one through the face's lowest node index. Face sets
/// follow (a cut quad becomes two triangles of the same orientation); node sets are kept (the
/// centre nodes are interior). Blocks keep their names, one block per name and kind.
pub fn split_hexes(mesh: &Mesh, choose: impl Fn(usize, usize) -> HexSplit) -> Mesh {
    let mut out = Mesh {
        nodes: mesh.nodes.clone(),
        node_tags: mesh.node_tags.clone(),
        volumes: Vec::new(),
        faces: BTreeMap::new(),
        node_sets: mesh.node_sets.clone(),
        sections: mesh.sections.clone(),
        fixed: mesh.fixed.clone(),
    };
    let faces6 = CellKind::Hex8.faces();
    // Split decision per cell, and the cells on each face.
    let mut owner: HashMap<[usize; 4], Vec<HexSplit>> = HashMap::new();
    let mut diag: HashMap<[usize; 4], [usize; 2]> = HashMap::new();
    for (b, blk) in mesh.volumes.iter().enumerate() {
        if blk.kind != CellKind::Hex8 {
            continue;
        }
        for c in 0..blk.len() {
            let s = choose(b, c);
            let nd = blk.cell(c);
            for f in faces6 {
                let q: Vec<usize> = f.nodes.iter().map(|&a| nd[a]).collect();
                owner.entry(key(&q)).or_default().push(s);
            }
            if s == HexSplit::Wedges {
                diag.insert(key(&[nd[0], nd[1], nd[2], nd[3]]), [nd[0], nd[2]]);
                diag.insert(key(&[nd[4], nd[5], nd[6], nd[7]]), [nd[4], nd[6]]);
            }
        }
    }
    let diagonal = |q: &[usize]| -> [usize; 2] {
        if let Some(d) = diag.get(&key(q)) {
            return *d;
        }
        let i = (0..4).min_by_key(|&i| q[i]).unwrap_or(0);
        [q[i], q[(i + 2) % 4]]
    };
    // Triangles of quad q (outward cycle) cut along `d`, same orientation.
    let cut = |q: &[usize], d: [usize; 2]| -> [[usize; 3]; 2] {
        if d.contains(&q[0]) {
            [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]
        } else {
            [[q[0], q[1], q[3]], [q[1], q[2], q[3]]]
        }
    };
    let mut blocks: BTreeMap<(Option<String>, CellKind), CellBlock> = BTreeMap::new();
    let mut order: Vec<(Option<String>, CellKind)> = Vec::new();
    let mut push = |name: &Option<String>, kind: CellKind, cell: &[usize], tag: u64| {
        let k = (name.clone(), kind);
        let b = blocks.entry(k.clone()).or_insert_with(|| {
            order.push(k);
            CellBlock::new(name.clone(), kind)
        });
        b.conn.extend_from_slice(cell);
        b.tags.push(tag);
    };
    let mut next_tag = mesh
        .volumes
        .iter()
        .flat_map(|b| b.tags.iter().copied())
        .max()
        .unwrap_or(0)
        + 1;
    let mut next_node_tag = mesh.node_tags.iter().copied().max().unwrap_or(0) + 1;
    for (b, blk) in mesh.volumes.iter().enumerate() {
        for c in 0..blk.len() {
            let nd = blk.cell(c);
            let split = if blk.kind == CellKind::Hex8 {
                choose(b, c)
            } else {
                HexSplit::Keep
            };
            let mut tag = || {
                next_tag += 1;
                next_tag - 1
            };
            match split {
                HexSplit::Keep => push(&blk.name, blk.kind, nd, blk.tags[c]),
                HexSplit::Wedges => {
                    let t = tag();
                    push(
                        &blk.name,
                        CellKind::Wedge6,
                        &[nd[0], nd[1], nd[2], nd[4], nd[5], nd[6]],
                        t,
                    );
                    let t = tag();
                    push(
                        &blk.name,
                        CellKind::Wedge6,
                        &[nd[0], nd[2], nd[3], nd[4], nd[6], nd[7]],
                        t,
                    );
                }
                HexSplit::Tets => {
                    let centre: [Real; 3] = std::array::from_fn(|i| {
                        nd.iter().map(|&v| mesh.nodes[v][i]).sum::<Real>() / 8.0
                    });
                    let cn = out.nodes.len();
                    out.nodes.push(centre);
                    out.node_tags.push(next_node_tag);
                    next_node_tag += 1;
                    for f in faces6 {
                        let q: Vec<usize> = f.nodes.iter().map(|&a| nd[a]).collect();
                        let others = &owner[&key(&q)];
                        let towards_tets = others.len() == 1
                            || others.iter().all(|&s| s == HexSplit::Tets)
                            || diag.contains_key(&key(&q));
                        if towards_tets {
                            // Outward triangle (a, b, c) + centre: reversed base for a
                            // positive tet (0-1-2 counter-clockwise seen from 3).
                            for t in cut(&q, diagonal(&q)) {
                                let tg = tag();
                                push(&blk.name, CellKind::Tet4, &[t[0], t[2], t[1], cn], tg);
                            }
                        } else {
                            let tg = tag();
                            push(
                                &blk.name,
                                CellKind::Pyramid5,
                                &[q[0], q[3], q[2], q[1], cn],
                                tg,
                            );
                        }
                    }
                }
            }
        }
    }
    out.volumes = order
        .into_iter()
        .filter_map(|k| blocks.remove(&k))
        .collect();
    // Face sets: quads cut where their cell was.
    for (name, set) in &mesh.faces {
        let mut fs = FaceSet::default();
        for f in set.iter() {
            let q = f.nodes;
            let is_cut = f.kind == CellKind::Quad4
                && (diag.contains_key(&key(q))
                    || owner
                        .get(&key(q))
                        .is_some_and(|o| o.contains(&HexSplit::Tets)));
            if is_cut {
                for t in cut(q, diagonal(q)) {
                    fs.push(CellKind::Tri3, &t, f.tag);
                }
            } else {
                fs.push(f.kind, q, f.tag);
            }
        }
        for b in &mut fs.blocks {
            b.name = Some(name.clone());
        }
        out.faces.insert(name.clone(), fs);
    }
    out
}

/// The same mesh with a node on every edge: hex8 → hex20, tet4 → tet10, wedge6 → wedge15,
/// pyramid5 → pyramid13, quad4 → quad8, tri3 → tri6 (quadratic kinds are kept). The new
/// nodes sit at the edge midpoints, numbered after the existing ones; a node set gains an
/// edge's node when it holds both of the edge's ends (exact for sets of whole faces).
pub fn to_quadratic(mesh: &Mesh) -> Mesh {
    let mut out = mesh.clone();
    let mut mid: HashMap<(usize, usize), usize> = HashMap::new();
    let mut next_tag = mesh.node_tags.iter().copied().max().unwrap_or(0) + 1;
    let mut raise =
        |kind: CellKind, cell: &[usize], out_nodes: &mut Vec<[Real; 3]>, tags: &mut Vec<u64>| {
            let mut v = cell[..kind.n_corners()].to_vec();
            if kind.is_quadratic() {
                return cell.to_vec();
            }
            for &[p, q] in kind.edges() {
                let (a, b) = (cell[p], cell[q]);
                let k = (a.min(b), a.max(b));
                let idx = *mid.entry(k).or_insert_with(|| {
                    let x: [Real; 3] =
                        std::array::from_fn(|i| 0.5 * (out_nodes[a][i] + out_nodes[b][i]));
                    out_nodes.push(x);
                    tags.push(next_tag);
                    next_tag += 1;
                    out_nodes.len() - 1
                });
                v.push(idx);
            }
            v
        };
    let mut nodes = mesh.nodes.clone();
    let mut tags = mesh.node_tags.clone();
    for blk in &mut out.volumes {
        let kind = blk.kind;
        let mut conn = Vec::new();
        for c in 0..blk.len() {
            conn.extend(raise(kind, blk.cell(c), &mut nodes, &mut tags));
        }
        blk.kind = kind.quadratic();
        blk.conn = conn;
    }
    for set in out.faces.values_mut() {
        for blk in &mut set.blocks {
            let kind = blk.kind;
            let mut conn = Vec::new();
            for c in 0..blk.len() {
                conn.extend(raise(kind, blk.cell(c), &mut nodes, &mut tags));
            }
            blk.kind = kind.quadratic();
            blk.conn = conn;
        }
    }
    for set in out.node_sets.values_mut() {
        let mut inside = vec![false; nodes.len()];
        set.iter().for_each(|&v| inside[v] = true);
        for (&(a, b), &m) in &mid {
            if inside[a] && inside[b] {
                set.push(m);
            }
        }
        set.sort_unstable();
        set.dedup();
    }
    out.nodes = nodes;
    out.node_tags = tags;
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structured::box_mesh;

    /// Signed volume of a linear cell by the divergence theorem over its local faces.
    fn volume(kind: CellKind, x: &[[Real; 3]]) -> Real {
        let mut v = 0.0;
        for f in kind.linear().faces() {
            let p = |a: usize| x[f.nodes[a]];
            // Each face fanned from its first corner; a non-planar quad's two triangles.
            for a in 1..f.kind.n_corners() - 1 {
                let (o, b, c) = (p(0), p(a), p(a + 1));
                v += (o[0] * (b[1] * c[2] - b[2] * c[1]) - o[1] * (b[0] * c[2] - b[2] * c[0])
                    + o[2] * (b[0] * c[1] - b[1] * c[0]))
                    / 6.0;
            }
        }
        v
    }

    /// Every split keeps the body's volume, every cell positive, and the mesh conforming:
    /// each interior face is shared by exactly two cells.
    #[test]
    fn splits_are_conforming_and_fill_the_box() {
        let m = box_mesh(2.0, 1.0, 1.0, 4, 2, 2, CellKind::Hex8);
        let s = split_hexes(&m, |_, c| match c % 4 {
            0 => HexSplit::Keep,
            1 => HexSplit::Wedges,
            _ => HexSplit::Tets,
        });
        let mut total = 0.0;
        let mut faces: HashMap<Vec<usize>, usize> = HashMap::new();
        for b in &s.volumes {
            for c in 0..b.len() {
                let nd = b.cell(c);
                let x: Vec<[Real; 3]> = nd.iter().map(|&v| s.nodes[v]).collect();
                let v = volume(b.kind, &x);
                assert!(v > 0.0, "{} cell {c}: {v}", b.kind);
                total += v;
                for f in b.kind.faces() {
                    let mut k: Vec<usize> = f.nodes.iter().map(|&a| nd[a]).collect();
                    k.sort_unstable();
                    *faces.entry(k).or_default() += 1;
                }
            }
        }
        assert!((total - 2.0).abs() < 1e-12, "{total}");
        let kinds: Vec<CellKind> = s.volumes.iter().map(|b| b.kind).collect();
        for k in [
            CellKind::Hex8,
            CellKind::Wedge6,
            CellKind::Tet4,
            CellKind::Pyramid5,
        ] {
            assert!(kinds.contains(&k), "{k}");
        }
        // Boundary faces: 2·(2·1 + 2·1 + 1·1)·… counted by area below; interior ones twice.
        assert!(faces.values().all(|&n| n <= 2));
        let area: Real = s
            .faces
            .values()
            .flat_map(|f| f.iter())
            .map(|f| {
                let p = |a: usize| s.nodes[f.nodes[a]];
                let mut a = [0.0; 3];
                for k in 1..f.kind.n_corners() - 1 {
                    let (u, v) = (
                        [p(k)[0] - p(0)[0], p(k)[1] - p(0)[1], p(k)[2] - p(0)[2]],
                        [
                            p(k + 1)[0] - p(0)[0],
                            p(k + 1)[1] - p(0)[1],
                            p(k + 1)[2] - p(0)[2],
                        ],
                    );
                    a[0] += 0.5 * (u[1] * v[2] - u[2] * v[1]);
                    a[1] += 0.5 * (u[2] * v[0] - u[0] * v[2]);
                    a[2] += 0.5 * (u[0] * v[1] - u[1] * v[0]);
                }
                (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
            })
            .sum();
        assert!((area - 10.0).abs() < 1e-12, "{area}");
        let q = to_quadratic(&s);
        for b in &q.volumes {
            assert!(b.kind.is_quadratic());
            for c in 0..b.len() {
                let nd = b.cell(c);
                for (e, &[p, r]) in b.kind.edges().iter().enumerate() {
                    let m = q.nodes[nd[b.kind.n_corners() + e]];
                    for i in 0..3 {
                        assert!(
                            (m[i] - 0.5 * (q.nodes[nd[p]][i] + q.nodes[nd[r]][i])).abs() < 1e-15
                        );
                    }
                }
            }
        }
        assert!(q
            .faces
            .values()
            .all(|f| f.kinds().all(|k| k.is_quadratic())));
    }
}
