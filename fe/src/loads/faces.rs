//! Outward area vectors of face sets, ∫ N_a n dA per node.

use crate::element::{quadrature::quad_rule, rules, shape, simplex};
use crate::{FeError, Mesh, Real};
use squeal_meshes::CellKind;
use std::collections::BTreeMap;

fn sub(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn centroid(mesh: &Mesh, nodes: &[usize]) -> [Real; 3] {
    let mut c = [0.0; 3];
    for &n in nodes {
        for i in 0..3 {
            c[i] += mesh.nodes[n][i];
        }
    }
    c.map(|v| v / nodes.len() as Real)
}

/// Parametric surface tangents' cross product x_ξ × x_η and the shape values at `xi`.
fn area_density(
    mesh: &Mesh,
    nodes: &[usize],
    kind: CellKind,
    xi: [Real; 2],
) -> (Vec<Real>, [Real; 3]) {
    let (n, d): (Vec<Real>, Vec<[Real; 2]>) = match kind {
        CellKind::Quad8 => {
            let (n, d) = shape::quad8(xi);
            (n.to_vec(), d.to_vec())
        }
        CellKind::Tri3 => {
            let (n, d) = simplex::tri3(xi);
            (n.to_vec(), d.to_vec())
        }
        CellKind::Tri6 => {
            let (n, d) = simplex::tri6(xi);
            (n.to_vec(), d.to_vec())
        }
        _ => {
            let (n, d) = shape::quad4(xi);
            (n.to_vec(), d.to_vec())
        }
    };
    let (mut tx, mut ty) = ([0.0; 3], [0.0; 3]);
    for (a, &node) in nodes.iter().enumerate() {
        let x = mesh.nodes[node];
        for i in 0..3 {
            tx[i] += x[i] * d[a][0];
            ty[i] += x[i] * d[a][1];
        }
    }
    (n, cross(tx, ty))
}

/// Lumped outward area vectors S_a = ∫ N_a n dA of the face set `face_set`, one entry per
/// node of the set, sorted by node (n is the outward normal of the adjacent volume cell).
///
/// Faces may be quad4, quad8, tri3 or tri6, mixed in one set. Rules: quad4 2×2 Gauss, quad8
/// 3×3, tri3 the degree-2 triangle rule, tri6 the degree-4 one: exact for N_a (x_ξ × x_η) on
/// flat and on curved (quadratic) faces. For quad8 faces the consistent corner values point
/// inward (∫ N_corner dA = −A/12 on a flat face) and tri6 corners carry nothing (∫ N_corner dA
/// = 0) — these are the exact consistent integrals; the sum over a face is its area vector.
pub fn face_areas(mesh: &Mesh, face_set: &str) -> Result<Vec<(usize, [Real; 3])>, FeError> {
    let block = mesh
        .faces
        .get(face_set)
        .ok_or_else(|| FeError::UnknownSet {
            what: "face set",
            name: face_set.to_string(),
            available: mesh.faces.keys().cloned().collect::<Vec<_>>().join(", "),
        })?;
    for k in block.kinds() {
        if k.is_volume() {
            return Err(FeError::WrongCellKind {
                block: face_set.to_string(),
                kind: format!("{k:?}"),
                expected: "quad4, quad8, tri3 or tri6",
            });
        }
    }
    for b in &block.blocks {
        let nn = b.kind.n_nodes();
        if b.conn.len() != nn * b.tags.len() {
            return Err(FeError::Dimension {
                what: "connectivity length of a face block",
                got: b.conn.len(),
                expected: nn * b.tags.len(),
            });
        }
    }
    if let Some(bad) = block.node_indices().find(|&v| v >= mesh.nodes.len()) {
        return Err(FeError::NodeOutOfRange {
            node: bad,
            n_nodes: mesh.nodes.len(),
            context: format!("face set '{face_set}'"),
        });
    }
    // Volume cells incident to the face nodes only.
    let mut wanted = vec![false; mesh.nodes.len()];
    block.node_indices().for_each(|v| wanted[v] = true);
    let mut incident: BTreeMap<usize, Vec<(usize, usize)>> = BTreeMap::new();
    for (bi, vb) in mesh.volumes.iter().enumerate() {
        for c in 0..vb.len() {
            for &v in vb.cell(c) {
                if v < wanted.len() && wanted[v] {
                    incident.entry(v).or_default().push((bi, c));
                }
            }
        }
    }
    let mut acc: BTreeMap<usize, [Real; 3]> = BTreeMap::new();
    for face in block.iter() {
        let (kind, nodes) = (face.kind, face.nodes);
        let rule: Vec<([Real; 2], Real)> = match kind {
            CellKind::Quad8 => quad_rule(3),
            CellKind::Tri3 => rules::triangle(2).to_vec(),
            CellKind::Tri6 => rules::triangle(4).to_vec(),
            _ => quad_rule(2),
        };
        let corners = &nodes[..kind.n_corners()];
        let cell = incident.get(&corners[0]).and_then(|cands| {
            cands.iter().find(|&&(bi, c)| {
                let cn = mesh.volumes[bi].cell(c);
                corners.iter().all(|v| cn.contains(v))
            })
        });
        let &(bi, c) = cell.ok_or_else(|| FeError::OrphanFace {
            set: face_set.to_string(),
            tag: face.tag,
        })?;
        let cc = centroid(mesh, mesh.volumes[bi].cell(c));
        let fc = centroid(mesh, nodes);
        let centre = if kind.n_corners() == 3 {
            [1.0 / 3.0, 1.0 / 3.0]
        } else {
            [0.0, 0.0]
        };
        let (_, n0) = area_density(mesh, nodes, kind, centre);
        let len0 = (n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2]).sqrt();
        if len0.is_nan() || len0 <= 0.0 {
            return Err(FeError::DegenerateFace {
                set: face_set.to_string(),
                tag: face.tag,
                det: len0,
            });
        }
        let out = sub(fc, cc);
        let sign = if n0[0] * out[0] + n0[1] * out[1] + n0[2] * out[2] >= 0.0 {
            1.0
        } else {
            -1.0
        };
        for (xi, w) in &rule {
            let (n, da) = area_density(mesh, nodes, kind, *xi);
            for (a, &node) in nodes.iter().enumerate() {
                let e = acc.entry(node).or_insert([0.0; 3]);
                for i in 0..3 {
                    e[i] += sign * w * n[a] * da[i];
                }
            }
        }
    }
    Ok(acc.into_iter().collect())
}
