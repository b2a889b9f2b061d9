//! Shape functions and their parametric derivatives, squeal (= VTK) node order.

use crate::Real;

/// Parametric coordinates of the hex8 nodes (and hex20 corners).
pub const HEX8_NODES: [[Real; 3]; 8] = [
    [-1.0, -1.0, -1.0],
    [1.0, -1.0, -1.0],
    [1.0, 1.0, -1.0],
    [-1.0, 1.0, -1.0],
    [-1.0, -1.0, 1.0],
    [1.0, -1.0, 1.0],
    [1.0, 1.0, 1.0],
    [-1.0, 1.0, 1.0],
];

/// Parametric coordinates of the hex20 nodes (corners, then mid-edges, VTK order): the mesh
/// reader's table, which checks det J at these points, so elements and checks share one.
pub use squeal_meshes::jacobian::HEX_NODES as HEX20_NODES;

/// Parametric coordinates of the quad4 nodes (and quad8 corners).
pub const QUAD4_NODES: [[Real; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// Parametric coordinates of the quad8 nodes: corners, then mid-edges 4:(0,1) 5:(1,2) 6:(2,3) 7:(3,0).
pub const QUAD8_NODES: [[Real; 2]; 8] = [
    [-1.0, -1.0],
    [1.0, -1.0],
    [1.0, 1.0],
    [-1.0, 1.0],
    [0.0, -1.0],
    [1.0, 0.0],
    [0.0, 1.0],
    [-1.0, 0.0],
];

/// Trilinear hex8 shape functions N_a(ξ) and derivatives ∂N_a/∂ξ_j.
pub fn hex8(xi: [Real; 3]) -> ([Real; 8], [[Real; 3]; 8]) {
    let mut n = [0.0; 8];
    let mut d = [[0.0; 3]; 8];
    for (a, p) in HEX8_NODES.iter().enumerate() {
        let f = [1.0 + p[0] * xi[0], 1.0 + p[1] * xi[1], 1.0 + p[2] * xi[2]];
        n[a] = 0.125 * f[0] * f[1] * f[2];
        d[a] = [
            0.125 * p[0] * f[1] * f[2],
            0.125 * f[0] * p[1] * f[2],
            0.125 * f[0] * f[1] * p[2],
        ];
    }
    (n, d)
}

/// Serendipity hex20 shape functions N_a(ξ) and derivatives ∂N_a/∂ξ_j.
pub fn hex20(xi: [Real; 3]) -> ([Real; 20], [[Real; 3]; 20]) {
    let mut n = [0.0; 20];
    let mut d = [[0.0; 3]; 20];
    for (a, p) in HEX20_NODES.iter().enumerate() {
        if a < 8 {
            let f = [1.0 + p[0] * xi[0], 1.0 + p[1] * xi[1], 1.0 + p[2] * xi[2]];
            let s = p[0] * xi[0] + p[1] * xi[1] + p[2] * xi[2] - 2.0;
            n[a] = 0.125 * f[0] * f[1] * f[2] * s;
            for j in 0..3 {
                let (k, l) = ((j + 1) % 3, (j + 2) % 3);
                // ∂/∂ξ_j [f_j f_k f_l s] = p_j f_k f_l s + f_j f_k f_l p_j
                d[a][j] = 0.125 * p[j] * f[k] * f[l] * (s + f[j]);
            }
        } else {
            // Mid-edge node: the zero coordinate is the edge direction `e`.
            let e = (0..3).find(|&j| p[j] == 0.0).unwrap_or(0);
            let (k, l) = ((e + 1) % 3, (e + 2) % 3);
            let g = 1.0 - xi[e] * xi[e];
            let (fk, fl) = (1.0 + p[k] * xi[k], 1.0 + p[l] * xi[l]);
            n[a] = 0.25 * g * fk * fl;
            d[a][e] = -0.5 * xi[e] * fk * fl;
            d[a][k] = 0.25 * g * p[k] * fl;
            d[a][l] = 0.25 * g * fk * p[l];
        }
    }
    (n, d)
}

/// Bilinear quad4 shape functions and derivatives.
pub fn quad4(xi: [Real; 2]) -> ([Real; 4], [[Real; 2]; 4]) {
    let mut n = [0.0; 4];
    let mut d = [[0.0; 2]; 4];
    for (a, p) in QUAD4_NODES.iter().enumerate() {
        let f = [1.0 + p[0] * xi[0], 1.0 + p[1] * xi[1]];
        n[a] = 0.25 * f[0] * f[1];
        d[a] = [0.25 * p[0] * f[1], 0.25 * f[0] * p[1]];
    }
    (n, d)
}

/// Serendipity quad8 shape functions and derivatives.
pub fn quad8(xi: [Real; 2]) -> ([Real; 8], [[Real; 2]; 8]) {
    let mut n = [0.0; 8];
    let mut d = [[0.0; 2]; 8];
    for (a, p) in QUAD8_NODES.iter().enumerate() {
        if a < 4 {
            let f = [1.0 + p[0] * xi[0], 1.0 + p[1] * xi[1]];
            let s = p[0] * xi[0] + p[1] * xi[1] - 1.0;
            n[a] = 0.25 * f[0] * f[1] * s;
            d[a] = [
                0.25 * p[0] * f[1] * (s + f[0]),
                0.25 * p[1] * f[0] * (s + f[1]),
            ];
        } else {
            let e = if p[0] == 0.0 { 0 } else { 1 };
            let o = 1 - e;
            let g = 1.0 - xi[e] * xi[e];
            let fo = 1.0 + p[o] * xi[o];
            n[a] = 0.5 * g * fo;
            d[a][e] = -xi[e] * fo;
            d[a][o] = 0.5 * g * p[o];
        }
    }
    (n, d)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn kronecker_property_at_nodes() {
        for (b, p) in HEX20_NODES.iter().enumerate() {
            let (n, _) = hex20(*p);
            for a in 0..20 {
                assert!((n[a] - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        for (b, p) in QUAD8_NODES.iter().enumerate() {
            let (n, _) = quad8(*p);
            for a in 0..8 {
                assert!((n[a] - if a == b { 1.0 } else { 0.0 }).abs() < 1e-14);
            }
        }
        for (b, p) in HEX8_NODES.iter().enumerate() {
            let (n, _) = hex8(*p);
            assert!((n[b] - 1.0).abs() < 1e-15);
        }
    }

    #[test]
    fn derivatives_match_finite_differences() {
        let xi = [0.3, -0.41, 0.77];
        let h = 1e-6;
        let (_, d) = hex20(xi);
        for j in 0..3 {
            let (mut xp, mut xm) = (xi, xi);
            xp[j] += h;
            xm[j] -= h;
            let (np, nm) = (hex20(xp).0, hex20(xm).0);
            for a in 0..20 {
                assert!(
                    (d[a][j] - (np[a] - nm[a]) / (2.0 * h)).abs() < 1e-8,
                    "a {a} j {j}"
                );
            }
        }
        let x2 = [0.21, -0.63];
        let (_, d) = quad8(x2);
        for j in 0..2 {
            let (mut xp, mut xm) = (x2, x2);
            xp[j] += h;
            xm[j] -= h;
            let (np, nm) = (quad8(xp).0, quad8(xm).0);
            for a in 0..8 {
                assert!((d[a][j] - (np[a] - nm[a]) / (2.0 * h)).abs() < 1e-8);
            }
        }
    }
}
