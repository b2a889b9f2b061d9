//! The mortar integrals of one pad face: M_ja = ∫ ψ_j Ñ_a dΓ over its segments with the
//! rotor faces (clipped shadows on the pad face's plane, fanned into triangles, integrated
//! exactly or adaptively), and ∫ ψ_j dΓ over the face's own shadow (the coverage reference).

use super::clip::{area2, clip_polygon, Plane};
use super::dual::DualFace;
use super::quadrature::{Adaptive, AdaptiveInfo};
use crate::gaps::face::RotorFace;
use crate::gaps::vec3::{cross, dot, norm, sub};
use crate::Real;

/// What one pad face contributes.
#[derive(Debug, Clone, Default)]
pub(super) struct FaceIntegrals {
    /// (local pad node k, rotor node id, ∫ψ_k Ñ_a dΓ over the face's segments).
    pub m: Vec<(usize, u64, Real)>,
    /// ∫ψ_k ρ dA over the face's own shadow (per local node).
    pub own: [Real; 8],
    /// (local pad node k, rotor face index, ∫ψ_k dΓ over the segment): the main face.
    pub share: Vec<(usize, usize, Real)>,
    /// Sum of the adaptive rule's error estimates over the face (max over the entries).
    pub error: Real,
    /// Mortar segments (non-empty clipped polygons).
    pub n_segments: usize,
    /// Rule applications (sub-triangles integrated).
    pub n_triangles: usize,
    /// Sub-triangles accepted at the deepest subdivision above the tolerance.
    pub n_unconverged: usize,
    /// Segments integrated exactly by the fixed rule (both faces affine).
    pub n_exact: usize,
    /// The face coincides with one rotor face (integrated in the shared parametrisation).
    pub coincident: bool,
}

/// x(ξ) of face `f` is affine in ξ (to 1e-12 of its edges): a parallelogram quad, any
/// triangle, with the mid-side nodes of quadratic faces at their edges' midpoints. Then its
/// shape functions are polynomials of the plane coordinates, of the face's degree.
pub(super) fn is_affine(f: &RotorFace) -> bool {
    let x = &f.coords;
    let tol = 1e-12 * f.edge_length();
    let close = |a: [Real; 3], b: [Real; 3]| norm(sub(a, b)) <= tol;
    if f.kind.n_corners() == 4 {
        let d = [0, 1, 2].map(|k| x[0][k] - x[1][k] + x[2][k] - x[3][k]);
        if norm(d) > tol {
            return false;
        }
    }
    f.kind
        .edges()
        .iter()
        .all(|&(m, a, b)| close(x[m], [0, 1, 2].map(|k| 0.5 * (x[a][k] + x[b][k]))))
}

/// The node permutation of a rotor face coinciding with pad face `pf` (same kind, every node
/// within 1e-10 of the edge length of one node of the other): rotor local node of each pad
/// local node. None when they do not coincide.
fn coincident(pf: &RotorFace, rf: &RotorFace) -> Option<[usize; 8]> {
    if pf.kind != rf.kind {
        return None;
    }
    let tol = 1e-10 * pf.edge_length();
    let mut perm = [usize::MAX; 8];
    for (k, xk) in pf.coords.iter().enumerate() {
        perm[k] = rf.coords.iter().position(|xa| norm(sub(*xa, *xk)) <= tol)?;
    }
    Some(perm)
}

/// The fan triangles of a polygon from its first vertex (reversed for a piece of sign −1),
/// after dropping repeated and
/// collinear vertices (the mid-side nodes of straight edges, clipping's duplicates): every
/// triangle has an area (a zero-area one could never meet a tolerance per unit area). On a
/// non-convex polygon some triangles have negative areas: the rules integrate with signed
/// areas, so the sum is the polygon's integral (of integrands defined around it).
fn fan(p: &[[Real; 2]], sign: Real) -> Vec<[[Real; 2]; 3]> {
    let area = area2(p).abs();
    let mut q: Vec<[Real; 2]> = p.to_vec();
    loop {
        let n = q.len();
        if n < 3 {
            return Vec::new();
        }
        let drop = (0..n).find(|&i| {
            let (a, b, c) = (q[(i + n - 1) % n], q[i], q[(i + 1) % n]);
            let z = (b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1]);
            z.abs() <= 1e-13 * area
        });
        match drop {
            Some(i) => {
                q.remove(i);
            }
            None => break,
        }
    }
    // A negative piece: its triangles reversed (clockwise), so that their areas subtract.
    (1..q.len() - 1)
        .map(|t| {
            if sign < 0.0 {
                [q[0], q[t + 1], q[t]]
            } else {
                [q[0], q[t], q[t + 1]]
            }
        })
        .collect()
}

/// The range of a face's node heights above `plane`.
fn heights(f: &RotorFace, plane: &Plane) -> (Real, Real) {
    f.coords
        .iter()
        .map(|&x| plane.height(x))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(a, b), v| {
            (a.min(v), b.max(v))
        })
}

/// Area of the pad face per unit area of its plane at ξ: |t_ξ × t_η| / |n·(t_ξ × t_η)|
/// (1 on a flat face).
fn density(pf: &RotorFace, plane: &Plane, xi: [Real; 2]) -> Real {
    let (_, t) = pf.point(xi);
    let c = cross(t[0], t[1]);
    norm(c) / dot(plane.n, c).abs()
}

/// The integrals of pad face `pf` (dual basis `dual`, plane `plane`) against the rotor
/// faces `candidates` (indices into `faces`, already near it). `tol` is the distance within
/// which a rotor face is in contact: its nodes' height range about the plane must come
/// within `tol` of the pad face's own. Err: a message naming the faces.
pub(super) fn integrate_face(
    pf: &RotorFace,
    dual: &DualFace,
    plane: &Plane,
    faces: &[RotorFace],
    candidates: &[usize],
    tol: Real,
    adaptive: &Adaptive<'_>,
) -> Result<FaceIntegrals, String> {
    let mut out = FaceIntegrals::default();
    let np = pf.kind.n_nodes();
    // A coincident rotor face: the segment is the whole face, and in the shared
    // parametrisation ∫ψ_j Ñ_a = ∫ψ_j N_k (a the rotor node on pad node k) is a polynomial
    // integral, computed with the dual basis ([`DualFace::psi_n`]).
    for &r in candidates {
        if let Some(perm) = coincident(pf, &faces[r]) {
            out.coincident = true;
            out.n_segments = 1;
            for j in 0..np {
                out.own[j] = dual.d[j];
                out.share.push((j, r, dual.d[j]));
                for k in 0..np {
                    out.m.push((j, faces[r].nodes[perm[k]], dual.psi_n[j][k]));
                }
            }
            return Ok(out);
        }
    }
    let pad_affine = is_affine(pf);
    // The pad face's own height range about its plane (a warped or curved face's sagitta).
    let (pad_lo, pad_hi) = heights(pf, plane);
    let pad_pieces = plane.pieces(pf);
    let pad_area: Real = pad_pieces.iter().map(|(p, sign)| sign * area2(p)).sum();
    // An absolute error per sub-triangle negligible for the face (a millionth of its share
    // of the tolerance): slivers left by clipping nearly coincident edges meet it.
    let floor = 1e-6 * adaptive.tolerance * pad_area;
    let mut xi_p = pf.kind.center_ref();
    let no_map = |what: &str, x: [Real; 3]| {
        format!("the mortar integration point {x:?} does not map on {what} along the pad plane's normal")
    };
    // ∫ψ_j over the face's own shadow (the coverage reference).
    let mut failed = None;
    {
        let mut info = AdaptiveInfo::default();
        let mut eval = |q: [Real; 2], v: &mut [Real]| {
            let x = plane.to3(q);
            let Some((xi, _)) = pf.along(x, plane.n, xi_p) else {
                failed = Some(no_map("the pad face", x));
                return false;
            };
            xi_p = xi;
            let (psi, rho) = (dual.psi(xi), density(pf, plane, xi));
            for j in 0..np {
                v[j] = rho * psi[j];
            }
            true
        };
        let mut own = vec![0.0; np];
        for (piece, sign) in &pad_pieces {
            for t in fan(piece, *sign) {
                if !adaptive.integrate(t, pad_affine, floor, &mut eval, &mut own, &mut info) {
                    return Err(failed.unwrap_or_default());
                }
            }
        }
        out.own[..np].copy_from_slice(&own);
        out.error += info.error;
        out.n_triangles += info.n_triangles;
        out.n_unconverged += info.n_unconverged;
    }
    for &r in candidates {
        let rf = &faces[r];
        let Some(rp) = Plane::of(rf) else { continue };
        if dot(rp.n, plane.n).abs() < 0.5 {
            continue;
        }
        let (lo, hi) = heights(rf, plane);
        if lo > pad_hi + tol || hi < pad_lo - tol {
            continue;
        }
        let nr = rf.kind.n_nodes();
        let exact = pad_affine && is_affine(rf);
        let mut sums = vec![0.0; np * nr];
        let mut info = AdaptiveInfo::default();
        let mut xi_r = rf.kind.center_ref();
        let mut any = false;
        let rshadow = plane.shadow(rf);
        for (ppiece, sign) in &pad_pieces {
            let seg = clip_polygon(&rshadow, ppiece);
            if seg.len() < 3 || area2(&seg) <= 1e-12 * pad_area {
                continue;
            }
            any = true;
            let mut eval = |q: [Real; 2], v: &mut [Real]| {
                let x = plane.to3(q);
                let Some((xe, _)) = pf.along(x, plane.n, xi_p) else {
                    failed = Some(no_map("the pad face", x));
                    return false;
                };
                let Some((xr, _)) = rf.along(x, plane.n, xi_r) else {
                    failed = Some(no_map(&format!("rotor face {}", rf.id), x));
                    return false;
                };
                xi_p = xe;
                xi_r = xr;
                let (psi, rho) = (dual.psi(xe), density(pf, plane, xe));
                let (nrot, _) = rf.kind.shape(xr);
                for j in 0..np {
                    for a in 0..nr {
                        v[j * nr + a] = rho * psi[j] * nrot[a];
                    }
                }
                true
            };
            for t in fan(&seg, *sign) {
                if !adaptive.integrate(t, exact, floor, &mut eval, &mut sums, &mut info) {
                    return Err(failed.unwrap_or_default());
                }
            }
        }
        if !any {
            continue;
        }
        out.n_segments += 1;
        out.n_exact += exact as usize;
        out.error += info.error;
        out.n_triangles += info.n_triangles;
        out.n_unconverged += info.n_unconverged;
        for j in 0..np {
            let row = &sums[j * nr..(j + 1) * nr];
            out.share.push((j, r, row.iter().sum()));
            for a in 0..nr {
                out.m.push((j, rf.nodes[a], row[a]));
            }
        }
    }
    Ok(out)
}
