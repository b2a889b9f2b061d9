//! Lumped outward area vectors S_p of the pad contact nodes.
//!
//! quad4 faces: the consistent ∫N_a n dA of [`squeal_fe::face_areas`] (all positive shares).
//! quad8 faces: the consistent corner values point *inward* (−A/12 on a flat face), which would
//! flip the gap normal at the corners; instead each face's area vector is shared by HRZ lumping
//! (weights ∝ ∫N_a² dA: corners 3/76, mid-sides 16/76 of the face), always outward and summing
//! to the face's area vector. tri3 faces: consistent (A/3 each). tri6 faces: the consistent
//! corner values vanish (∫N_corner dA = 0), so they are HRZ-lumped too (∫N_corner² = A/30,
//! ∫N_mid² = 8A/45: corners 1/19, mid-sides 16/57 of the face). A set may mix the kinds.

use squeal_fe::{face_areas, FeError};
use squeal_meshes::{CellKind, Mesh};
use std::collections::BTreeMap;

use squeal_solver::Real;

/// HRZ weights of a quad8 (corner, mid-side), from ∫N_a² over the reference square with a
/// 3×3 Gauss rule (exact for these degree-4 integrands).
fn hrz_quad8() -> (Real, Real) {
    let g = [-(0.6f64).sqrt(), 0.0, (0.6f64).sqrt()];
    let w = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let (mut c, mut m) = (0.0, 0.0);
    for (i, &x) in g.iter().enumerate() {
        for (j, &y) in g.iter().enumerate() {
            let nc = 0.25 * (1.0 + x) * (1.0 + y) * (x + y - 1.0);
            let nm = 0.5 * (1.0 - x * x) * (1.0 + y);
            c += w[i] * w[j] * nc * nc;
            m += w[i] * w[j] * nm * nm;
        }
    }
    let total = 4.0 * c + 4.0 * m;
    (c / total, m / total)
}

/// HRZ shares of a tri6 (corner, mid-side): ∫N_c² dA = A/30, ∫N_m² dA = 8A/45 over a flat
/// triangle, normalised so that three corners and three mid-sides sum to one.
fn hrz_tri6() -> (Real, Real) {
    let (c, m) = (1.0 / 30.0, 8.0 / 45.0);
    let total = 3.0 * c + 3.0 * m;
    (c / total, m / total)
}

/// (node, S_a) of the face set, sorted by node.
pub fn pad_areas(mesh: &Mesh, face_set: &str) -> Result<Vec<(usize, [Real; 3])>, FeError> {
    let consistent = face_areas(mesh, face_set)?;
    let block = &mesh.faces[face_set];
    if !block.kinds().any(|k| k.is_quadratic()) {
        return Ok(consistent);
    }
    let cons: BTreeMap<usize, [Real; 3]> = consistent.iter().copied().collect();
    // Linear faces keep their consistent shares, computed on their own.
    let mut acc: BTreeMap<usize, [Real; 3]> = BTreeMap::new();
    for face in block.iter() {
        let nodes = face.nodes;
        let x = |a: usize| mesh.nodes[nodes[a]];
        let sub = |p: [Real; 3], q: [Real; 3]| [p[0] - q[0], p[1] - q[1], p[2] - q[2]];
        let half_cross = |d1: [Real; 3], d2: [Real; 3]| {
            [
                0.5 * (d1[1] * d2[2] - d1[2] * d2[1]),
                0.5 * (d1[2] * d2[0] - d1[0] * d2[2]),
                0.5 * (d1[0] * d2[1] - d1[1] * d2[0]),
            ]
        };
        let (mut s, (wc, wm)) = match face.kind {
            CellKind::Quad8 | CellKind::Quad4 => (
                half_cross(sub(x(2), x(0)), sub(x(3), x(1))),
                if face.kind == CellKind::Quad8 {
                    hrz_quad8()
                } else {
                    (0.25, 0.0)
                },
            ),
            _ => (
                half_cross(sub(x(1), x(0)), sub(x(2), x(0))),
                if face.kind == CellKind::Tri6 {
                    hrz_tri6()
                } else {
                    (1.0 / 3.0, 0.0)
                },
            ),
        };
        // Outward: the consistent shares of the face's nodes point outward on the whole.
        let mut out = [0.0; 3];
        for &n in nodes {
            let v = cons[&n];
            (0..3).for_each(|i| out[i] += v[i]);
        }
        if face.kind.is_quadratic() {
            out = [0.0; 3];
            for &n in &nodes[face.kind.n_corners()..] {
                let v = cons[&n];
                (0..3).for_each(|i| out[i] += v[i]);
            }
        }
        if s[0] * out[0] + s[1] * out[1] + s[2] * out[2] < 0.0 {
            s = s.map(|v| -v);
        }
        for (a, &n) in nodes.iter().enumerate() {
            let w = if a < face.kind.n_corners() { wc } else { wm };
            let e = acc.entry(n).or_insert([0.0; 3]);
            (0..3).for_each(|i| e[i] += w * s[i]);
        }
    }
    Ok(acc.into_iter().collect())
}

#[cfg(test)]
mod tests {
    /// HRZ lumping of the 8-node serendipity quad on the reference square: ∫N_corner² = 2/15,
    /// ∫N_midside² = 32/45 (exact integrals of the shape functions), so the shares are
    /// (2/15)/(4·2/15 + 4·32/45) = 3/76 and (32/45)/(…) = 16/76.
    #[test]
    fn hrz_weights() {
        let (c, m) = super::hrz_quad8();
        assert!((4.0 * c + 4.0 * m - 1.0).abs() < 1e-14);
        assert!((c - 3.0 / 76.0).abs() < 1e-14, "{c}");
        assert!((m - 16.0 / 76.0).abs() < 1e-14, "{m}");
    }

    /// tri6 HRZ: ∫N_c² = A/30 and ∫N_m² = 8A/45 (exact integrals of the P2 functions) give
    /// corners 1/19 and mid-sides 16/57, summing to one.
    #[test]
    fn hrz_tri6_weights() {
        let (c, m) = super::hrz_tri6();
        assert!((3.0 * c + 3.0 * m - 1.0).abs() < 1e-15);
        assert!((c - 1.0 / 19.0).abs() < 1e-15 && (m - 16.0 / 57.0).abs() < 1e-15);
    }
}
