//! Mortar pairing: each pad node tied to the rotor surface by a segment-to-segment (mortar)
//! integral with dual Lagrange multipliers on the pad's quad4 faces.

use super::face::RotorFace;
use super::tie::{check_faces, distance_limit, Unmatched};
use super::{ContactNode, FaceKind, FaceTie, Gap, GapSet, MatchOptions, TieOptions, TieOutcome};
use crate::{ContactError, FrictionLaw, NodeReport, Real};
use std::collections::HashMap;

/// Statistics of one mortar pairing (besides [`super::TieStats`]).
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct MortarStats {
    /// Pad faces integrated.
    pub n_pad_faces: usize,
    /// Mortar segments (non-empty pad face ∩ rotor face polygons).
    pub n_segments: usize,
    /// Smallest coverage Σ_a M_ja / D_j of a tied pad node (1: its dual basis function's
    /// whole support lies on rotor faces).
    pub min_coverage: Real,
}

/// Weights within this distance of 0 or 1 are set to it (coincident meshes give node pairing).
const WEIGHT_SNAP: Real = 1e-12;
/// A pad node whose coverage differs from 1 by more than this projects partly on no face.
/// The coverage is a ratio of two quadratures of the node's dual function (over the mortar
/// segments and over its own pad faces). On pad quads that are not parallelograms (the
/// annular-sector faces of a real pad) that function is not polynomial in the plane, and the
/// two quadratures differ by the rule's error: up to 9.3e-9 on the cad brake's pads and
/// 3.2e-7 on trapezoids tapered by 60 % (`contact/tests/mortar.rs`), in +/− pairs on
/// neighbouring nodes. Below 1e-4 of its support off the rotor, a node is tied with its
/// weights normalised to sum 1 (the rows still vanish on rigid motions); beyond it, it is
/// reported as unmatched.
const COVERAGE_TOL: Real = 1e-4;

/// Degree-5 seven-point rule on the reference triangle (Dunavant 1985, rule 5):
/// (barycentric a, b, weight); the weights sum to 1 (times the triangle's area).
fn triangle_rule() -> [([Real; 3], Real); 7] {
    let s15 = 15.0f64.sqrt();
    let (a1, w1) = ((6.0 - s15) / 21.0, (155.0 - s15) / 1200.0);
    let (a2, w2) = ((6.0 + s15) / 21.0, (155.0 + s15) / 1200.0);
    let (b1, b2) = (1.0 - 2.0 * a1, 1.0 - 2.0 * a2);
    [
        ([1.0 / 3.0, 1.0 / 3.0, 1.0 / 3.0], 9.0 / 40.0),
        ([a1, a1, b1], w1),
        ([a1, b1, a1], w1),
        ([b1, a1, a1], w1),
        ([a2, a2, b2], w2),
        ([a2, b2, a2], w2),
        ([b2, a2, a2], w2),
    ]
}

fn sub(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: [Real; 3], b: [Real; 3]) -> Real {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
fn unit(a: [Real; 3]) -> [Real; 3] {
    let l = dot(a, a).sqrt();
    [a[0] / l, a[1] / l, a[2] / l]
}

/// Signed area of a 2D polygon.
fn area2(p: &[[Real; 2]]) -> Real {
    let n = p.len();
    (0..n)
        .map(|i| {
            let (a, b) = (p[i], p[(i + 1) % n]);
            a[0] * b[1] - a[1] * b[0]
        })
        .sum::<Real>()
        * 0.5
}

/// Sutherland–Hodgman: `subject` clipped by the convex counterclockwise polygon `clip`.
fn clip_polygon(subject: &[[Real; 2]], clip: &[[Real; 2]]) -> Vec<[Real; 2]> {
    let mut out = subject.to_vec();
    let n = clip.len();
    for i in 0..n {
        if out.is_empty() {
            break;
        }
        let (a, b) = (clip[i], clip[(i + 1) % n]);
        let side = |p: [Real; 2]| (b[0] - a[0]) * (p[1] - a[1]) - (b[1] - a[1]) * (p[0] - a[0]);
        let input = std::mem::take(&mut out);
        let m = input.len();
        for j in 0..m {
            let (p, q) = (input[j], input[(j + 1) % m]);
            let (sp, sq) = (side(p), side(q));
            if sp >= 0.0 {
                out.push(p);
            }
            if (sp >= 0.0) != (sq >= 0.0) {
                let t = sp / (sp - sq);
                out.push([p[0] + t * (q[0] - p[0]), p[1] + t * (q[1] - p[1])]);
            }
        }
    }
    out
}

/// The plane of a pad face: centroid, unit normal, tangents.
struct Plane {
    c: [Real; 3],
    n: [Real; 3],
    t1: [Real; 3],
    t2: [Real; 3],
}

impl Plane {
    fn of(f: &RotorFace) -> Option<Plane> {
        let x = &f.coords;
        let c = [0, 1, 2].map(|k| 0.25 * (x[0][k] + x[1][k] + x[2][k] + x[3][k]));
        let nv = cross(sub(x[2], x[0]), sub(x[3], x[1]));
        let l = dot(nv, nv).sqrt();
        if !(l.is_finite() && l > 0.0) {
            return None;
        }
        let n = [nv[0] / l, nv[1] / l, nv[2] / l];
        let t1 = unit(sub(x[1], x[0]));
        let t2 = cross(n, t1);
        Some(Plane { c, n, t1, t2 })
    }
    fn to2(&self, x: [Real; 3]) -> [Real; 2] {
        let d = sub(x, self.c);
        [dot(d, self.t1), dot(d, self.t2)]
    }
    fn to3(&self, p: [Real; 2]) -> [Real; 3] {
        [0, 1, 2].map(|k| self.c[k] + p[0] * self.t1[k] + p[1] * self.t2[k])
    }
    /// The corners of a face in the plane, counterclockwise.
    fn polygon(&self, f: &RotorFace) -> Vec<[Real; 2]> {
        let mut p: Vec<[Real; 2]> = f.coords[..4].iter().map(|&x| self.to2(x)).collect();
        if area2(&p) < 0.0 {
            p.reverse();
        }
        p
    }
}

/// Dual basis coefficients of a bilinear pad face: ψ_j = Σ_k A_jk N_k with A = D M⁻¹, where
/// D = diag(∫N_k dΓ) and M = (∫N_j N_k dΓ) (3×3 Gauss: exact for these integrands on a
/// parallelogram, and the rule's own consistent values on a general quad). Also returns D.
fn dual_basis(f: &RotorFace) -> Option<([[Real; 4]; 4], [Real; 4])> {
    let g = [-(0.6f64).sqrt(), 0.0, (0.6f64).sqrt()];
    let w = [5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0];
    let mut m = [[0.0; 4]; 4];
    let mut d = [0.0; 4];
    for (i, &x) in g.iter().enumerate() {
        for (j, &y) in g.iter().enumerate() {
            let (_, t) = f.point([x, y]);
            let ja = dot(cross(t[0], t[1]), cross(t[0], t[1])).sqrt();
            let (n, _) = FaceKind::Quad4.shape([x, y]);
            let wt = w[i] * w[j] * ja;
            for a in 0..4 {
                d[a] += wt * n[a];
                for b in 0..4 {
                    m[a][b] += wt * n[a] * n[b];
                }
            }
        }
    }
    let inv = invert4(m)?;
    let mut a = [[0.0; 4]; 4];
    for j in 0..4 {
        for k in 0..4 {
            a[j][k] = d[j] * inv[j][k];
        }
    }
    Some((a, d))
}

/// Inverse of a 4×4 matrix by Gauss–Jordan with partial pivoting (None when singular).
fn invert4(m: [[Real; 4]; 4]) -> Option<[[Real; 4]; 4]> {
    let mut a = m;
    let mut inv = [[0.0; 4]; 4];
    for (i, row) in inv.iter_mut().enumerate() {
        row[i] = 1.0;
    }
    let scale = m.iter().flatten().fold(0.0f64, |s, v| s.max(v.abs()));
    for c in 0..4 {
        let p = (c..4).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        let big = a[p][c].abs() > 1e-14 * scale;
        if !big {
            return None;
        }
        a.swap(c, p);
        inv.swap(c, p);
        let piv = a[c][c];
        for k in 0..4 {
            a[c][k] /= piv;
            inv[c][k] /= piv;
        }
        for r in 0..4 {
            if r != c {
                let f = a[r][c];
                for k in 0..4 {
                    a[r][k] -= f * a[c][k];
                    inv[r][k] -= f * inv[c][k];
                }
            }
        }
    }
    Some(inv)
}

/// Ties every pad node to the rotor surface by a mortar integral with dual Lagrange
/// multipliers (segment-to-segment, Wohlmuth 2000; Popp et al. 2010 for 3D): the gap of pad
/// node j has the rotor side Σ_a W_ja u_a with W_ja = M_ja / D_j, M_ja = ∫ ψ_j Ñ_a dΓ over
/// the pad surface, D_j = ∫ N_j dΓ (its consistent area), ψ_j the dual basis of the pad's
/// bilinear faces (biorthogonal: ∫ψ_j N_k = δ_jk D_j) and Ñ_a the rotor faces' shape
/// functions. `pad_faces` are the pad's quad4 friction faces (ids of `pad`'s nodes);
/// `faces` the rotor's quad4/quad8 faces.
///
/// The gap keeps the pad node's position, normal, area |S_p| (for quad4 faces = D_j), P0,
/// temperature and sliding velocity as [`crate::tie_gaps`]; its [`FaceTie`] has `mortar =
/// true`, the rotor nodes of non-zero weight and their weights W_ja (they sum to 1; dual
/// weights may be negative), and, for reports, the face, (ξ, η) and distance of the pad
/// node's closest projection. Coincident meshes give weights 1 and 0 (node pairing).
///
/// *Integration.* For each pad face, each rotor face whose bounding box (grown by the
/// distance limit) meets the pad face's is projected with it on the pad face's plane; the
/// rotor face's corner polygon is clipped by the pad face's (Sutherland–Hodgman), the
/// intersection fanned into triangles and integrated with a 7-point degree-5 rule, each point
/// mapped back to both faces by projection. On flat interfaces with straight-edged faces this
/// is exact for bilinear × bilinear integrands, so a uniform pressure passes exactly (patch
/// test) whatever the two meshes.
///
/// # Reference
/// The constraint row is $n\cdot(\sum_a W_{ja} u_a - u_j) = 0$, the mortar form of
/// $(\vec u_d - \vec u_p)\cdot\vec n = 0$ [Paper eq. (9)] divided by $D_j$; friction forces
/// on the rotor, eq. (7), go to the rotor nodes with the same weights
/// ([`GapSet::add_forces`]). Derivation of exactness: a linear field x satisfies
/// $\sum_a W_{ja} x_a = D_j^{-1}\int\psi_j x\,d\Gamma = x_j$ (biorthogonality), and the rotor
/// nodal forces of multipliers $\lambda_j = -pD_j$ are $-p\int\tilde N_a\,d\Gamma$ (the dual
/// functions sum to 1).
///
/// # Errors
/// As [`crate::tie_gaps`], and [`ContactError::InvalidOption`] for a pad face that is not a
/// quad4 (quad8 pad faces have negative corner integrals ∫N_j, so no usable dual basis),
/// is degenerate, or names a node not in `pad`.
pub fn mortar_gaps(
    pad: &[ContactNode],
    pad_faces: &[RotorFace],
    faces: &[RotorFace],
    opts: &MatchOptions,
    tie: &TieOptions,
) -> Result<(TieOutcome, MortarStats), ContactError> {
    opts.validate()?;
    tie.validate()?;
    check_faces(faces, "faces")?;
    check_faces(pad_faces, "pad_faces")?;
    let index: HashMap<u64, usize> = pad.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let mut local: Vec<[usize; 4]> = Vec::with_capacity(pad_faces.len());
    let mut duals = Vec::with_capacity(pad_faces.len());
    for (i, f) in pad_faces.iter().enumerate() {
        let bad = |reason: String| ContactError::InvalidOption {
            field: format!("pad_faces[{i}]"),
            value: format!("face {} ({:?}, nodes {:?})", f.id, f.kind, f.nodes),
            reason,
        };
        if f.kind != FaceKind::Quad4 {
            return Err(bad(
                "mortar pairing needs quad4 (hex8) pad faces: a quad8 face's corner integrals \
                 are negative, so it has no usable dual basis"
                    .into(),
            ));
        }
        let mut ids = [0; 4];
        for (a, n) in f.nodes.iter().enumerate() {
            ids[a] = *index
                .get(n)
                .ok_or_else(|| bad(format!("node {n} is not one of the pad nodes")))?;
        }
        local.push(ids);
        let dual = dual_basis(f).ok_or_else(|| bad("degenerate face".into()))?;
        duals.push(dual);
    }
    let (tol, _) = distance_limit(faces, opts, tie);
    let boxes: Vec<([Real; 3], [Real; 3])> = faces
        .iter()
        .chain(pad_faces)
        .map(|f| {
            let mut lo = [Real::INFINITY; 3];
            let mut hi = [Real::NEG_INFINITY; 3];
            for c in &f.coords {
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k] - tol);
                    hi[k] = hi[k].max(c[k] + tol);
                }
            }
            (lo, hi)
        })
        .collect();
    let (rotor_boxes, pad_boxes) = boxes.split_at(faces.len());
    let rule = triangle_rule();
    let mut stats = MortarStats {
        n_pad_faces: pad_faces.len(),
        min_coverage: Real::INFINITY,
        ..MortarStats::default()
    };
    // Per pad node: D_j and the mortar row M_j· as (rotor node id → (value, x/y/z of node)).
    let mut d_full = vec![0.0; pad.len()];
    let mut rows: Vec<HashMap<u64, Real>> = vec![HashMap::new(); pad.len()];
    // Per pad node: per rotor face, ∫ψ_j over its segment (to name the main face).
    let mut share: Vec<HashMap<usize, Real>> = vec![HashMap::new(); pad.len()];
    for (e, pf) in pad_faces.iter().enumerate() {
        let (a_dual, d) = duals[e];
        for (k, &j) in local[e].iter().enumerate() {
            d_full[j] += d[k];
        }
        let plane = Plane::of(pf).ok_or_else(|| ContactError::InvalidOption {
            field: format!("pad_faces[{e}]"),
            value: format!("face {}", pf.id),
            reason: "degenerate face".into(),
        })?;
        let clip = plane.polygon(pf);
        let (plo, phi) = pad_boxes[e];
        for (r, rf) in faces.iter().enumerate() {
            let (lo, hi) = rotor_boxes[r];
            if (0..3).any(|k| lo[k] > phi[k] || hi[k] < plo[k]) {
                continue;
            }
            let Some(rp) = Plane::of(rf) else { continue };
            if dot(rp.n, plane.n).abs() < 0.5 || dot(sub(rp.c, plane.c), plane.n).abs() > tol {
                continue;
            }
            let poly = clip_polygon(&plane.polygon(rf), &clip);
            if poly.len() < 3 || area2(&poly) <= 1e-14 * area2(&clip) {
                continue;
            }
            stats.n_segments += 1;
            let nr = rf.kind.n_nodes();
            for t in 1..poly.len() - 1 {
                let (p0, p1, p2) = (poly[0], poly[t], poly[t + 1]);
                let at = area2(&[p0, p1, p2]);
                for (bary, w) in rule {
                    let q = [
                        bary[0] * p0[0] + bary[1] * p1[0] + bary[2] * p2[0],
                        bary[0] * p0[1] + bary[1] * p1[1] + bary[2] * p2[1],
                    ];
                    let x = plane.to3(q);
                    let (Some(xp), Some(xr)) = (pf.project(x), rf.project(x)) else {
                        return Err(ContactError::InvalidOption {
                            field: format!("pad_faces[{e}]"),
                            value: format!("face {} against rotor face {}", pf.id, rf.id),
                            reason: format!(
                                "a mortar integration point {x:?} does not project on both faces"
                            ),
                        });
                    };
                    let (np, _) = FaceKind::Quad4.shape(xp.xi);
                    let (nrot, _) = rf.kind.shape(xr.xi);
                    for (k, &j) in local[e].iter().enumerate() {
                        let psi: Real = (0..4).map(|l| a_dual[k][l] * np[l]).sum();
                        let wp = w * at * psi;
                        *share[j].entry(r).or_insert(0.0) += wp;
                        for a in 0..nr {
                            *rows[j].entry(rf.nodes[a]).or_insert(0.0) += wp * nrot[a];
                        }
                    }
                }
            }
        }
    }
    let node_xyz: HashMap<u64, [Real; 3]> = faces
        .iter()
        .flat_map(|f| f.nodes.iter().copied().zip(f.coords.iter().copied()))
        .collect();
    let mut bad: Vec<NodeReport> = Vec::new();
    let mut unmatched = Vec::new();
    let mut gaps = Vec::with_capacity(pad.len());
    let mut tstats = super::TieStats {
        n_pad: pad.len(),
        max_distance: tol,
        ..Default::default()
    };
    for (j, pn) in pad.iter().enumerate() {
        let report = |reason: String| NodeReport {
            id: pn.id,
            coords: pn.coords,
            reason,
        };
        let a = match pn.pad_area() {
            Ok(a) => a,
            Err(reason) => {
                bad.push(report(reason));
                continue;
            }
        };
        if d_full[j] <= 0.0 {
            bad.push(report(
                "on no pad face (mortar pairing integrates over pad faces)".into(),
            ));
            continue;
        }
        let sum: Real = rows[j].values().sum();
        let coverage = sum / d_full[j];
        if !(coverage.is_finite() && (coverage - 1.0).abs() <= COVERAGE_TOL) {
            unmatched.push(report(format!(
                "the rotor faces cover {:.6} of its dual basis function's support (1 {:+.3e}; \
                 mortar pairing needs the pad face around it on the rotor surface)",
                coverage,
                coverage - 1.0
            )));
            continue;
        }
        stats.min_coverage = stats.min_coverage.min(coverage);
        // Main face: the largest share; the projection there, for reports.
        let Some((&main, _)) = share[j]
            .iter()
            .max_by(|x, y| x.1.total_cmp(y.1).then(y.0.cmp(x.0)))
        else {
            unmatched.push(report("no mortar segment".into()));
            continue;
        };
        let f = &faces[main];
        let (xi, distance) = match f.project(pn.coords) {
            Some(p) => (p.xi, p.distance),
            None => ([Real::NAN; 2], Real::NAN),
        };
        if distance.is_nan() || distance > tol {
            unmatched.push(report(format!(
                "farther than {tol:e} from its main rotor face {} (distance {distance:.3e})",
                f.id
            )));
            continue;
        }
        let mut nodes: Vec<(u64, Real)> = rows[j]
            .iter()
            .map(|(&n, &m)| {
                let mut w = m / sum;
                if w.abs() <= WEIGHT_SNAP {
                    w = 0.0;
                } else if (w - 1.0).abs() <= WEIGHT_SNAP {
                    w = 1.0;
                }
                (n, w)
            })
            .filter(|&(_, w)| w != 0.0)
            .collect();
        nodes.sort_by_key(|&(n, _)| n);
        let main_node = nodes
            .iter()
            .fold(None, |m: Option<(u64, Real)>, &(n, w)| match m {
                Some((_, mw)) if mw >= w => m,
                _ => Some((n, w)),
            })
            .map_or(f.nodes[0], |(n, _)| n);
        if nodes.len() == 1 {
            tstats.n_on_node += 1;
        }
        tstats.largest_distance = tstats.largest_distance.max(distance);
        let coords = nodes
            .iter()
            .map(|(n, _)| node_xyz.get(n).copied().unwrap_or([Real::NAN; 3]))
            .collect();
        let t = FaceTie {
            face: f.id,
            kind: f.kind,
            xi,
            nodes: nodes.iter().map(|&(n, _)| n).collect(),
            weights: nodes.iter().map(|&(_, w)| w).collect(),
            distance,
            dofs: Vec::new(),
            mortar: true,
            coords,
        };
        gaps.push(Gap::at_pad_node(pn, a, main_node, opts, Some(t)));
    }
    if !unmatched.is_empty() && tie.unmatched == Unmatched::Error {
        bad.extend(unmatched.iter().cloned());
    }
    if !bad.is_empty() {
        return Err(ContactError::Matching {
            tolerance: tol,
            nodes: bad,
        });
    }
    if gaps.is_empty() {
        stats.min_coverage = 0.0;
    }
    tstats.n_tied = gaps.len();
    tstats.n_excluded = unmatched.len();
    Ok((
        TieOutcome {
            gaps: GapSet {
                gaps,
                law: FrictionLaw::default(),
                vtol: GapSet::DEFAULT_VTOL,
            },
            unmatched,
            stats: tstats,
        },
        stats,
    ))
}
