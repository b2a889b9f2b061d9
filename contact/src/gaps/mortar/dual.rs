//! Dual (biorthogonal) Lagrange multiplier bases of the pad faces.
//!
//! On a linear face (quad4, tri3) the dual functions ψ_j = Σ_k A_jk N_k are biorthogonal to
//! the standard shape functions: ∫ψ_j N_k dΓ = δ_jk D_j, D_j = ∫N_j dΓ > 0 (Wohlmuth 2000).
//! On a quadratic face (quad8, tri6) that is impossible with positive D_j: the corner
//! integrals ∫N_corner dΓ are −A/12 (quad8) and 0 (tri6). The basis is first transformed,
//! N̂ = T N (Lamichhane & Wohlmuth 2004; Popp, Wohlmuth, Gee & Wall 2012):
//!
//! N̂_v = N_v + α Σ_{edges e ∋ v} N_e (corners), N̂_e = (1 − 2α) N_e (mid-sides), α = 1/5,
//!
//! which keeps the partition of unity and, on straight edges (mid-side nodes at the
//! midpoints), reproduces linear fields with the same nodal values, and makes every integral
//! positive: on a parallelogram ∫N̂_v = A/20 (quad8), 2A/15 (tri6), ∫N̂_e = A/5. The duals are
//! biorthogonal to N̂, and the pad side of gap j is the transformed nodal value
//! û = T^{-T} u: û_v = u_v, û_e = (u_e − α(u_v1 + u_v2))/(1 − 2α).
//!
//! α = 1/5 for both quad8 and tri6: a smaller α would do on tri6 alone (any α > 0) and on
//! quad8 alone (α > 1/8), but one α for both keeps the transformed basis continuous across an
//! edge shared by a tri6 and a quad8 face (a hex20/wedge15 pad), as Popp et al. choose.

use super::quadrature::face_rule;
use crate::gaps::face::RotorFace;
use crate::gaps::vec3::{cross, norm};
use crate::gaps::FaceKind;
use crate::Real;

/// The basis transformation parameter α of quadratic faces (see the module docs).
pub(crate) const ALPHA: Real = 0.2;

/// The dual basis of one pad face.
#[derive(Debug, Clone)]
pub(crate) struct DualFace {
    pub kind: FaceKind,
    /// ψ_j = Σ_k a[j][k] N̂_k.
    pub a: [[Real; 8]; 8],
    /// D̂_j = ∫_face N̂_j dΓ.
    pub d: [Real; 8],
    /// Ŝ_j = ∫_face N̂_j n dΓ (n the face's unit normal from its node order).
    pub s: [[Real; 3]; 8],
    /// ∫_face ψ_j N_k dΓ (standard N_k): the mortar row of a coincident rotor face.
    pub psi_n: [[Real; 8]; 8],
}

/// N̂ = T N at ξ (values only; T is the identity on linear faces).
pub(crate) fn transformed(kind: FaceKind, n: &[Real; 8]) -> [Real; 8] {
    let mut h = *n;
    for &(m, v1, v2) in kind.edges() {
        h[v1] += ALPHA * n[m];
        h[v2] += ALPHA * n[m];
        h[m] = (1.0 - 2.0 * ALPHA) * n[m];
    }
    h
}

/// The pad side of gap j as (local node, weight) terms of T^{-T}: a corner is itself; a
/// mid-side node e of edge (v1, v2) is (u_e − α(u_v1 + u_v2))/(1 − 2α).
pub(crate) fn pad_side(kind: FaceKind, local: usize) -> Vec<(usize, Real)> {
    match kind.edges().iter().find(|e| e.0 == local) {
        Some(&(m, v1, v2)) => {
            let c = 1.0 / (1.0 - 2.0 * ALPHA);
            vec![(m, c), (v1, -ALPHA * c), (v2, -ALPHA * c)]
        }
        None => vec![(local, 1.0)],
    }
}

/// Inverse of the leading n×n block by Gauss–Jordan with partial pivoting (None when
/// singular relative to the largest entry).
fn invert(m: &[[Real; 8]; 8], n: usize) -> Option<[[Real; 8]; 8]> {
    let mut a = *m;
    let mut inv = [[0.0; 8]; 8];
    for (i, row) in inv.iter_mut().enumerate().take(n) {
        row[i] = 1.0;
    }
    let scale = (0..n)
        .flat_map(|i| (0..n).map(move |j| (i, j)))
        .fold(0.0f64, |s, (i, j)| s.max(m[i][j].abs()));
    for c in 0..n {
        let p = (c..n).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c].is_nan() || a[p][c].abs() <= 1e-13 * scale {
            return None;
        }
        a.swap(c, p);
        inv.swap(c, p);
        let piv = a[c][c];
        for k in 0..n {
            a[c][k] /= piv;
            inv[c][k] /= piv;
        }
        for r in 0..n {
            if r != c {
                let f = a[r][c];
                if f != 0.0 {
                    for k in 0..n {
                        a[r][k] -= f * a[c][k];
                        inv[r][k] -= f * inv[c][k];
                    }
                }
            }
        }
    }
    Some(inv)
}

impl DualFace {
    /// The dual basis of face `f`, its integrals from a 5-point-per-direction rule in the
    /// face's reference coordinates (exact for the products N̂_j N̂_k times the surface
    /// Jacobian on straight-edged faces of every kind: degree ≤ 5 per variable on quads, ≤ 5
    /// in total on triangles). None when the face is degenerate (zero Jacobian or a singular
    /// mass matrix).
    pub fn new(f: &RotorFace) -> Option<DualFace> {
        let kind = f.kind;
        let nn = kind.n_nodes();
        let mut mm = [[0.0; 8]; 8];
        let mut b = [[0.0; 8]; 8];
        let mut d = [0.0; 8];
        let mut s = [[0.0; 3]; 8];
        for (xi, w) in face_rule(kind, 5) {
            let (n, _) = kind.shape(xi);
            let (_, t) = f.point(xi);
            let nv = cross(t[0], t[1]);
            let ja = norm(nv);
            if !(ja.is_finite() && ja > 0.0) {
                return None;
            }
            let h = transformed(kind, &n);
            let wt = w * ja;
            for j in 0..nn {
                d[j] += wt * h[j];
                for k in 0..3 {
                    s[j][k] += w * h[j] * nv[k];
                }
                for k in 0..nn {
                    mm[j][k] += wt * h[j] * h[k];
                    b[j][k] += wt * h[j] * n[k];
                }
            }
        }
        let inv = invert(&mm, nn)?;
        let mut a = [[0.0; 8]; 8];
        for j in 0..nn {
            for k in 0..nn {
                a[j][k] = d[j] * inv[j][k];
            }
        }
        let mut psi_n = [[0.0; 8]; 8];
        for j in 0..nn {
            for k in 0..nn {
                psi_n[j][k] = (0..nn).map(|l| a[j][l] * b[l][k]).sum();
            }
        }
        Some(DualFace {
            kind,
            a,
            d,
            s,
            psi_n,
        })
    }

    /// ψ_j(ξ) for every node j of the face (first `n_nodes`).
    pub fn psi(&self, xi: [Real; 2]) -> [Real; 8] {
        let nn = self.kind.n_nodes();
        let (n, _) = self.kind.shape(xi);
        let h = transformed(self.kind, &n);
        let mut out = [0.0; 8];
        for j in 0..nn {
            out[j] = (0..nn).map(|k| self.a[j][k] * h[k]).sum();
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face(kind: FaceKind, f: impl Fn([Real; 2]) -> [Real; 3]) -> RotorFace {
        RotorFace {
            id: 0,
            kind,
            nodes: (0..kind.n_nodes() as u64).collect(),
            coords: kind.nodes_ref().iter().map(|&r| f(r)).collect(),
        }
    }

    /// On parallelograms the transformed corner and mid-side integrals are the closed forms
    /// above (quad8 A/20 and A/5, tri6 2A/15 and A/5, Popp et al. 2012); on a distorted face
    /// the duals are biorthogonal to N̂ (∫ψ_j N̂_k = δ_jk D̂_j), sum to 1 and the transformed
    /// basis reproduces linear fields.
    #[test]
    fn transformed_integrals_and_biorthogonality() {
        let para = |r: [Real; 2]| [2.0 * r[0] + 0.5 * r[1], 1.5 * r[1], 0.0];
        for (kind, area, corner, mid) in [
            (FaceKind::Quad8, 12.0, 12.0 / 20.0, 12.0 / 5.0),
            (FaceKind::Tri6, 1.5, 2.0 * 1.5 / 15.0, 1.5 / 5.0),
            (FaceKind::Quad4, 12.0, 3.0, 0.0),
            (FaceKind::Tri3, 1.5, 0.5, 0.0),
        ] {
            let df = DualFace::new(&face(kind, para)).unwrap();
            let nc = kind.n_corners();
            for j in 0..kind.n_nodes() {
                let want = if j < nc { corner } else { mid };
                assert!((df.d[j] - want).abs() < 1e-13, "{kind:?} {j}: {}", df.d[j]);
                assert!((df.s[j][2] - want).abs() < 1e-13);
            }
            let sum: Real = df.d.iter().sum();
            assert!((sum - area).abs() < 1e-12);
        }
        // A distorted, straight-edged quad8 and tri6 (mid-sides at the midpoints).
        for kind in [
            FaceKind::Quad8,
            FaceKind::Tri6,
            FaceKind::Quad4,
            FaceKind::Tri3,
        ] {
            let mut f = face(kind, |r| [r[0] + 0.2 * r[0] * r[1], r[1] - 0.1 * r[0], 0.0]);
            for &(m, v1, v2) in kind.edges() {
                let (a, b) = (f.coords[v1], f.coords[v2]);
                f.coords[m] = [0, 1, 2].map(|k| 0.5 * (a[k] + b[k]));
            }
            let df = DualFace::new(&f).unwrap();
            let nn = kind.n_nodes();
            let mut bi = [[0.0; 8]; 8];
            for (xi, w) in face_rule(kind, 6) {
                let (n, _) = kind.shape(xi);
                let (_, t) = f.point(xi);
                let ja = norm(cross(t[0], t[1]));
                let h = transformed(kind, &n);
                let psi = df.psi(xi);
                assert!((psi[..nn].iter().sum::<Real>() - 1.0).abs() < 1e-12);
                let lin: Real = (0..nn).map(|k| h[k] * f.coords[k][0]).sum();
                let (x, _) = f.point(xi);
                assert!((lin - x[0]).abs() < 1e-14, "{kind:?} linear field");
                for j in 0..nn {
                    for k in 0..nn {
                        bi[j][k] += w * ja * psi[j] * h[k];
                    }
                }
            }
            for j in 0..nn {
                assert!(df.d[j] > 0.0, "{kind:?} D̂_{j} = {}", df.d[j]);
                for k in 0..nn {
                    let want = if j == k { df.d[j] } else { 0.0 };
                    assert!((bi[j][k] - want).abs() < 1e-13, "{kind:?} {j} {k}");
                }
            }
        }
    }
}
