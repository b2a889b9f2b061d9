//! Shape functions of the wedges (triangular prisms): wedge6 and wedge15.
//!
//! Natural coordinates: (ξ, η) on the triangle (L0 = 1 − ξ − η, L1 = ξ, L2 = η) times
//! ζ ∈ [−1, 1]; corners 0-1-2 at ζ = −1, 3-4-5 at ζ = +1 (node order of `squeal_meshes::mesh`).
//!
//! # Reference
//! wedge6: N = L_i (1 + ζ_i ζ)/2. wedge15 (serendipity prism): corners
//! N = ½ L_i (1 + ζ_i ζ)(2 L_i + ζ_i ζ − 2), triangle-edge nodes N = 2 L_p L_q (1 + ζ_e ζ),
//! vertical-edge nodes N = L_i (1 − ζ²); Zienkiewicz & Taylor, *The Finite Element Method*,
//! vol. 1, §8.9 (the C3D15 / CPENTA15 family).

use crate::Real;

const DL: [[Real; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];

fn tri_l(xi: [Real; 3]) -> [Real; 3] {
    [1.0 - xi[0] - xi[1], xi[0], xi[1]]
}

/// Corner `a` → (triangle vertex, ζ_a).
fn corner(a: usize) -> (usize, Real) {
    (a % 3, if a < 3 { -1.0 } else { 1.0 })
}

/// Linear wedge (6 nodes).
pub fn wedge6(xi: [Real; 3]) -> ([Real; 6], [[Real; 3]; 6]) {
    let l = tri_l(xi);
    let z = xi[2];
    let mut n = [0.0; 6];
    let mut d = [[0.0; 3]; 6];
    for a in 0..6 {
        let (i, c) = corner(a);
        let h = 0.5 * (1.0 + c * z);
        n[a] = l[i] * h;
        d[a] = [DL[i][0] * h, DL[i][1] * h, 0.5 * c * l[i]];
    }
    (n, d)
}

/// Triangle edges of wedge15 nodes 6..12: (vertex p, vertex q, ζ level).
const TRI_EDGES: [(usize, usize, Real); 6] = [
    (0, 1, -1.0),
    (1, 2, -1.0),
    (2, 0, -1.0),
    (0, 1, 1.0),
    (1, 2, 1.0),
    (2, 0, 1.0),
];

/// Quadratic serendipity wedge (15 nodes).
pub fn wedge15(xi: [Real; 3]) -> ([Real; 15], [[Real; 3]; 15]) {
    let l = tri_l(xi);
    let z = xi[2];
    let mut n = [0.0; 15];
    let mut d = [[0.0; 3]; 15];
    for a in 0..6 {
        let (i, c) = corner(a);
        let h = 1.0 + c * z;
        let s = 2.0 * l[i] + c * z - 2.0;
        n[a] = 0.5 * l[i] * h * s;
        // ∂/∂ξ_j (j = 0, 1): ½ ∂L/∂ξ_j h (s + 2 L); ∂/∂ζ: ½ L c (s + h).
        let f = 0.5 * h * (s + 2.0 * l[i]);
        d[a] = [DL[i][0] * f, DL[i][1] * f, 0.5 * l[i] * c * (s + h)];
    }
    for (e, &(p, q, c)) in TRI_EDGES.iter().enumerate() {
        let h = 1.0 + c * z;
        n[6 + e] = 2.0 * l[p] * l[q] * h;
        d[6 + e] = [
            2.0 * h * (DL[p][0] * l[q] + l[p] * DL[q][0]),
            2.0 * h * (DL[p][1] * l[q] + l[p] * DL[q][1]),
            2.0 * c * l[p] * l[q],
        ];
    }
    for i in 0..3 {
        let g = 1.0 - z * z;
        n[12 + i] = l[i] * g;
        d[12 + i] = [DL[i][0] * g, DL[i][1] * g, -2.0 * z * l[i]];
    }
    (n, d)
}
