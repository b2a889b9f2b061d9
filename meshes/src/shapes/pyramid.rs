//! Shape functions of the pyramids: pyramid5 and pyramid13 (rational, Bedrosian's family).
//!
//! The reference pyramid has its base corners at (±1, ±1, 0) and its apex at (0, 0, 1) in
//! (ξ, η, ζ). The functions are rational in (ξ, η, ζ) but polynomial in the collapsed
//! (Duffy) coordinates X = (x̂, ŷ, ζ) ∈ [−1, 1]² × [0, 1], ξ = x̂ (1 − ζ), η = ŷ (1 − ζ), so
//! they are evaluated there: `pyramid5(X)` and `pyramid13(X)` return N_a and the gradients
//! ∂N_a/∂(ξ, η, ζ) in the *pyramid* coordinates, written in forms without the 1/(1 − ζ) that
//! the chain rule introduces, so they stay finite at the apex (where their limit depends on
//! the direction (x̂, ŷ) of approach, as for any rational pyramid element). Integration over
//! the pyramid in these coordinates carries the factor dξ dη dζ = (1 − ζ)² dx̂ dŷ dζ, which
//! the pyramid quadrature rules include in their weights.
//!
//! # Reference
//! With s = 1 − ζ and P = (1 + ξ_a x̂)(1 + η_a ŷ) for base corner a = (ξ_a, η_a):
//! - pyramid5: corners N = ¼ s P, apex N = ζ (the collapsed trilinear hex; Bedrosian 1992).
//! - pyramid13: corners N = ¼ s P (s (ξ_a x̂ + η_a ŷ) − 1), i.e.
//!   $N = \tfrac14 (1+ξ_aξ−ζ)(1+η_aη−ζ)(ξ_aξ+η_aη−1)/(1−ζ)$; base mid-edge nodes
//!   N = ½ s² (1 − x̂²)(1 + η_m ŷ) (and with x̂, ŷ exchanged); slanted mid-edge nodes
//!   N = ζ s P; apex N = ζ (2ζ − 1). G. Bedrosian, "Shape functions and integration formulas
//!   for three-dimensional finite element analysis", IJNME 35 (1992) 95–108; the same 13-node
//!   functions as Nastran's CPYRAM and Code_Aster's PYRA13. On each triangular face they
//!   reduce to the tri6 functions and on the base to the quad8 ones, so the element is
//!   conforming with tet10, wedge15 and hex20 neighbours (tested).

use crate::Real;

/// Base corners (ξ_a, η_a) in squeal order.
pub const BASE: [[Real; 2]; 4] = [[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]];

/// ∂N/∂ζ at fixed (ξ, η) from the collapsed-coordinate derivative `dz` at fixed (x̂, ŷ)
/// and the pyramid gradients (`dxi`, `deta`): ∂/∂ζ|ξη = ∂/∂ζ|X + x̂ ∂/∂ξ + ŷ ∂/∂η.
fn dzeta(x: [Real; 3], dz: Real, dxi: Real, deta: Real) -> Real {
    dz + x[0] * dxi + x[1] * deta
}

/// Linear pyramid (5 nodes) at collapsed coordinates `x` = (x̂, ŷ, ζ).
pub fn pyramid5(x: [Real; 3]) -> ([Real; 5], [[Real; 3]; 5]) {
    let s = 1.0 - x[2];
    let mut n = [0.0; 5];
    let mut d = [[0.0; 3]; 5];
    for (a, &[p, q]) in BASE.iter().enumerate() {
        let (fx, fy) = (1.0 + p * x[0], 1.0 + q * x[1]);
        n[a] = 0.25 * s * fx * fy;
        let (dxi, deta) = (0.25 * p * fy, 0.25 * q * fx);
        d[a] = [dxi, deta, dzeta(x, -0.25 * fx * fy, dxi, deta)];
    }
    n[4] = x[2];
    d[4] = [0.0, 0.0, 1.0];
    (n, d)
}

/// Base mid-edge nodes 5..9: the corners they join.
const BASE_EDGES: [[usize; 2]; 4] = [[0, 1], [1, 2], [2, 3], [3, 0]];

/// Quadratic pyramid (13 nodes) at collapsed coordinates `x` = (x̂, ŷ, ζ).
pub fn pyramid13(x: [Real; 3]) -> ([Real; 13], [[Real; 3]; 13]) {
    let (u, v, z) = (x[0], x[1], x[2]);
    let s = 1.0 - z;
    let mut n = [0.0; 13];
    let mut d = [[0.0; 3]; 13];
    for (a, &[p, q]) in BASE.iter().enumerate() {
        let (fx, fy) = (1.0 + p * u, 1.0 + q * v);
        let r = p * u + q * v;
        let big_q = s * r - 1.0;
        let pp = fx * fy;
        // Corner: N = ¼ s P Q.
        n[a] = 0.25 * s * pp * big_q;
        let dxi = 0.25 * p * (fy * big_q + s * pp);
        let deta = 0.25 * q * (fx * big_q + s * pp);
        d[a] = [dxi, deta, dzeta(x, -0.25 * pp * (big_q + s * r), dxi, deta)];
        // Slanted mid-edge node (corner a, apex): N = ζ s P.
        let k = 9 + a;
        n[k] = z * s * pp;
        let (dxi, deta) = (z * p * fy, z * q * fx);
        d[k] = [dxi, deta, dzeta(x, (1.0 - 2.0 * z) * pp, dxi, deta)];
    }
    for (e, &[a, b]) in BASE_EDGES.iter().enumerate() {
        let k = 5 + e;
        let ([pa, qa], [pb, _]) = (BASE[a], BASE[b]);
        if pa != pb {
            // Edge along ξ at η = η_m: N = ½ s² (1 − x̂²)(1 + η_m ŷ).
            let fy = 1.0 + qa * v;
            let g = 1.0 - u * u;
            n[k] = 0.5 * s * s * g * fy;
            let (dxi, deta) = (-s * u * fy, 0.5 * s * g * qa);
            d[k] = [dxi, deta, dzeta(x, -s * g * fy, dxi, deta)];
        } else {
            // Edge along η at ξ = ξ_m.
            let fx = 1.0 + pa * u;
            let g = 1.0 - v * v;
            n[k] = 0.5 * s * s * g * fx;
            let (dxi, deta) = (0.5 * s * g * pa, -s * v * fx);
            d[k] = [dxi, deta, dzeta(x, -s * g * fx, dxi, deta)];
        }
    }
    n[4] = z * (2.0 * z - 1.0);
    d[4] = [0.0, 0.0, 4.0 * z - 1.0];
    (n, d)
}
