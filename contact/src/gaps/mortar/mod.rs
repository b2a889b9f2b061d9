//! Mortar pairing: each pad node tied to the rotor surface by a segment-to-segment (mortar)
//! integral with dual Lagrange multipliers on the pad's faces (quad4, quad8, tri3, tri6;
//! the quadratic ones through the transformed basis of [`dual`]).
//!
//! Files: `dual.rs` (dual bases), `clip.rs` (plane, shadows, clipping), `quadrature.rs`
//! (rules, adaptive integration), `segments.rs` (one pad face's integrals).

mod clip;
mod dual;
mod quadrature;
mod segments;

use super::face::RotorFace;
use super::grid::Grid;
use super::tie::{check_faces, distance_limit, Unmatched};
use super::vec3::dot;
use super::{ContactNode, FaceTie, Gap, GapSet, MatchOptions, PadSide, TieOptions, TieOutcome};
use crate::{ContactError, FrictionLaw, NodeReport, Real};
use quadrature::{triangle_rule, Adaptive};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::collections::HashMap;

/// Options of the mortar integration (besides [`TieOptions`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MortarOptions {
    /// Accepted quadrature error per unit area on a mortar triangle whose faces are not
    /// affine (non-parallelogram quads): a triangle is split in four until the children's
    /// sum differs from the parent's value by at most this times its area, for every
    /// integrand ψ_j Ñ_a (values of order 1) (default: 1e-13).
    pub quadrature_tolerance: Real,
    /// Deepest subdivision of a mortar triangle (4^depth pieces); a triangle that has not
    /// met the tolerance there is an error naming the pad face (default: 8).
    pub max_depth: usize,
    /// A pad node whose coverage Σ_a M_ja / ∫ψ_j (the share of its dual function's support
    /// on rotor faces) differs from 1 by more than this is not tied (reported as unmatched);
    /// within it, its weights are normalised to sum 1 (default: 1e-6).
    pub coverage_tolerance: Real,
}

impl Default for MortarOptions {
    fn default() -> Self {
        MortarOptions {
            quadrature_tolerance: 1e-13,
            max_depth: 8,
            coverage_tolerance: 1e-6,
        }
    }
}

impl MortarOptions {
    /// Checks the options; the error names the field and the value.
    pub fn validate(&self) -> Result<(), ContactError> {
        let bad = |field: &str, value: String, reason: &str| ContactError::InvalidOption {
            field: format!("mortar.{field}"),
            value,
            reason: reason.into(),
        };
        let t = self.quadrature_tolerance;
        if !(t.is_finite() && t > 0.0) {
            return Err(bad(
                "quadrature_tolerance",
                format!("{t}"),
                "must be finite and > 0",
            ));
        }
        if !(1..=12).contains(&self.max_depth) {
            return Err(bad(
                "max_depth",
                format!("{}", self.max_depth),
                "must be in 1..=12",
            ));
        }
        let c = self.coverage_tolerance;
        if !(c.is_finite() && c > 0.0 && c < 1.0) {
            return Err(bad(
                "coverage_tolerance",
                format!("{c}"),
                "must be in (0, 1)",
            ));
        }
        Ok(())
    }
}

/// Statistics of one mortar pairing (besides [`super::TieStats`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default)]
pub struct MortarStats {
    /// Pad faces integrated.
    pub n_pad_faces: usize,
    /// Mortar segments (pad face × rotor face pairs with a non-empty overlap).
    pub n_segments: usize,
    /// Segments integrated exactly by the fixed rule (both faces affine: parallelograms,
    /// triangles, straight-edged quadratic faces).
    pub n_exact_segments: usize,
    /// Pad faces coinciding with a rotor face (integrated in the shared parametrisation).
    pub n_coincident_faces: usize,
    /// Triangles the rule was applied to (adaptive subdivisions included).
    pub n_triangles: usize,
    /// Largest quadrature error estimate of a tied pad node relative to ∫ψ_j (the sum of
    /// its faces' adaptive estimates; 0 where every segment was exact).
    pub quadrature_error: Real,
    /// Smallest coverage Σ_a M_ja / ∫ψ_j of a tied pad node (1: its dual basis function's
    /// whole support lies on rotor faces).
    pub min_coverage: Real,
    /// Pad nodes on quadratic faces whose gap uses the transformed basis (area D̂_j, pad side
    /// û_j).
    pub n_transformed: usize,
}

/// Weights within this distance of 0 or 1 are set to it (coincident meshes give node pairing).
const WEIGHT_SNAP: Real = 1e-13;

/// Ties every pad node to the rotor surface by a mortar integral with dual Lagrange
/// multipliers (segment-to-segment, Wohlmuth 2000; Puso & Laursen 2004 and Popp, Gee & Wall
/// 2009/2010 in 3D; the quadratic faces as Popp, Wohlmuth, Gee & Wall 2012): the gap of pad
/// node j has the rotor side Σ_a W_ja u_a with W_ja = M_ja / Σ_b M_jb, M_ja = ∫ ψ_j Ñ_a dΓ,
/// ψ_j the dual basis of the pad's faces (biorthogonal: ∫ψ_j N̂_k = δ_jk D̂_j) and Ñ_a the
/// rotor faces' shape functions. `pad_faces` are the pad's friction faces (ids of `pad`'s
/// nodes), `faces` the rotor's; both of any kind (quad4, quad8, tri3, tri6).
///
/// The gap keeps the pad node's position, P0, temperature and sliding velocity as
/// [`crate::tie_gaps`]. On linear pad faces its normal and area are the caller's S_p (for
/// quad4 and tri3 faces = D_j); on quadratic faces they are Ŝ_j = ∫N̂_j n dΓ (positive
/// where ∫N_j n dΓ is not), oriented as the caller's area vectors of the face's nodes, and
/// the gap of a mid-side node has the pad side û_e = (u_e − α(u_v1 + u_v2))/(1 − 2α)
/// ([`Gap::pad_side`]). Its [`FaceTie`] has `mortar = true`, the rotor nodes of non-zero
/// weight and their weights W_ja (they sum to 1; dual weights may be negative), and, for
/// reports, the face, (ξ, η) and distance of the pad node's closest projection.
///
/// *Integration (segment-based).* Each pad face's plane carries the shadows (orthogonal
/// projections) of the pad face and of each rotor face near it, as convex polygons
/// ([`clip::Plane::pieces`]); every rotor shadow is clipped by the pad's (Sutherland–Hodgman),
/// the overlap fanned into triangles, and a point of the plane is mapped to both faces along
/// the plane's normal. When both faces are affine (parallelograms, triangles, straight-edged
/// quadratic faces) the integrands are polynomials of the plane coordinates of degree ≤ 6,
/// and the collapsed 4×4 Gauss rule (total degree 6) integrates them exactly; otherwise (a
/// quad that is no parallelogram: its shape functions are not polynomials of the plane
/// coordinates, but analytic on the face) the collapsed 8×8 rule (degree 14) is applied on
/// each triangle, its difference from the 6×6 rule (degree 10) is the error estimate, and
/// triangles are split adaptively until it meets `quadrature_tolerance`; the estimate is
/// reported. A pad face coinciding with a rotor face is integrated in their
/// shared parametrisation, so coincident meshes give exactly nodal weights.
///
/// # Reference
/// The constraint row is $n\cdot(\sum_a W_{ja} u_a - \hat u_j) = 0$, the mortar form of
/// $(\vec u_d - \vec u_p)\cdot\vec n = 0$ [Paper eq. (9)] divided by $\int\psi_j$; friction
/// forces on the rotor, eq. (7), go to the rotor nodes with the same weights
/// ([`GapSet::add_forces`]). Why this passes the patch test: a linear field x satisfies
/// $\sum_a W_{ja} x_a = \int\psi_j x\,/\int\psi_j = \hat x_j$ (the rotor interpolation
/// reproduces x, then biorthogonality), and the rotor nodal forces of multipliers
/// $\lambda_j = -p\hat D_j$ are $-p\int\tilde N_a\,d\Gamma$ (the dual functions sum to 1).
///
/// # Errors
/// As [`crate::tie_gaps`], and [`ContactError::InvalidOption`] for bad options, a pad face
/// that is degenerate, names a node not in `pad`, cannot be oriented (its nodes' area vectors
/// are all zero), or whose integration did not reach the tolerance; [`ContactError::Matching`]
/// also for a pad node whose D̂_j ≤ 0 (a quadratic face too distorted for its dual basis).
pub fn mortar_gaps(
    pad: &[ContactNode],
    pad_faces: &[RotorFace],
    faces: &[RotorFace],
    opts: &MatchOptions,
    tie: &TieOptions,
    mortar: &MortarOptions,
) -> Result<(TieOutcome, MortarStats), ContactError> {
    opts.validate()?;
    tie.validate()?;
    mortar.validate()?;
    check_faces(faces, "faces")?;
    check_faces(pad_faces, "pad_faces")?;
    let index: HashMap<u64, usize> = pad.iter().enumerate().map(|(i, n)| (n.id, i)).collect();
    let (tol, mean_edge) = distance_limit(faces, opts, tie);
    let nn = pad.len();
    // Per pad node: D̂_j, Ŝ_j, the pad side (quadratic faces), whether transformed.
    let mut d_hat = vec![0.0; nn];
    let mut s_hat = vec![[0.0; 3]; nn];
    let mut side: Vec<Option<Vec<(u64, Real)>>> = vec![None; nn];
    let mut setup = Vec::with_capacity(pad_faces.len());
    for (i, f) in pad_faces.iter().enumerate() {
        let bad = |reason: String| ContactError::InvalidOption {
            field: format!("pad_faces[{i}]"),
            value: format!("face {} ({:?}, nodes {:?})", f.id, f.kind, f.nodes),
            reason,
        };
        let mut ids = [0usize; 8];
        for (a, n) in f.nodes.iter().enumerate() {
            ids[a] = *index
                .get(n)
                .ok_or_else(|| bad(format!("node {n} is not one of the pad nodes")))?;
        }
        let dualf = dual::DualFace::new(f).ok_or_else(|| bad("degenerate face".into()))?;
        let plane = clip::Plane::of(f).ok_or_else(|| bad("degenerate face".into()))?;
        let np = f.kind.n_nodes();
        let s: Real = ids[..np].iter().map(|&j| dot(pad[j].area, plane.n)).sum();
        if !(s.is_finite() && s != 0.0) {
            return Err(bad(
                "its nodes' area vectors are zero (or not finite): the face cannot be oriented"
                    .into(),
            ));
        }
        let sign = s.signum();
        if f.kind.is_quadratic() {
            for k in 0..np {
                let j = ids[k];
                d_hat[j] += dualf.d[k];
                for c in 0..3 {
                    s_hat[j][c] += sign * dualf.s[k][c];
                }
                side[j].get_or_insert_with(|| {
                    dual::pad_side(f.kind, k)
                        .into_iter()
                        .map(|(l, w)| (f.nodes[l], w))
                        .collect()
                });
            }
        }
        setup.push((ids, dualf, plane));
    }
    // Candidate rotor faces by bounding boxes grown by the distance limit.
    let bbox = |f: &RotorFace| {
        let mut lo = [Real::INFINITY; 3];
        let mut hi = [Real::NEG_INFINITY; 3];
        for c in &f.coords {
            for k in 0..3 {
                lo[k] = lo[k].min(c[k] - tol);
                hi[k] = hi[k].max(c[k] + tol);
            }
        }
        (lo, hi)
    };
    let rotor_boxes: Vec<([Real; 3], [Real; 3])> = faces.iter().map(bbox).collect();
    let cell = (2.0f64.sqrt() * mean_edge).max(tol).max(Real::MIN_POSITIVE);
    let grid = Grid::from_boxes(&rotor_boxes, cell);
    let (exact_rule, rule, check_rule) = (triangle_rule(4), triangle_rule(8), triangle_rule(6));
    let adaptive = Adaptive {
        exact_rule: &exact_rule,
        rule: &rule,
        check_rule: &check_rule,
        tolerance: mortar.quadrature_tolerance,
        max_depth: mortar.max_depth,
    };
    let mut stats = MortarStats {
        n_pad_faces: pad_faces.len(),
        min_coverage: Real::INFINITY,
        ..MortarStats::default()
    };
    let mut rows: Vec<HashMap<u64, Real>> = vec![HashMap::new(); nn];
    let mut own = vec![0.0; nn];
    let mut err = vec![0.0; nn];
    let mut share: Vec<HashMap<usize, Real>> = vec![HashMap::new(); nn];
    // Each pad face's integrals (in parallel; merged below in face order, so the sums are
    // the same whatever the thread count).
    let integrals: Vec<Result<segments::FaceIntegrals, ContactError>> = pad_faces
        .par_iter()
        .enumerate()
        .map(|(e, pf)| {
            let (_, dualf, plane) = &setup[e];
            let (plo, phi) = bbox(pf);
            let candidates: Vec<usize> = grid
                .boxes_near(&plo, &phi)
                .into_iter()
                .filter(|&r| {
                    let (lo, hi) = rotor_boxes[r];
                    (0..3).all(|k| lo[k] <= phi[k] && hi[k] >= plo[k])
                })
                .collect();
            segments::integrate_face(pf, dualf, plane, faces, &candidates, tol, &adaptive).map_err(
                |reason| ContactError::InvalidOption {
                    field: format!("pad_faces[{e}]"),
                    value: format!("face {}", pf.id),
                    reason,
                },
            )
        })
        .collect();
    for (e, (pf, fi)) in pad_faces.iter().zip(integrals).enumerate() {
        let fi = fi?;
        let ids = &setup[e].0;
        if fi.n_unconverged > 0 {
            return Err(ContactError::InvalidOption {
                field: format!("pad_faces[{e}]"),
                value: format!("face {} ({:?})", pf.id, pf.kind),
                reason: format!(
                    "the mortar quadrature did not reach {:e} per unit area on {} triangle(s) \
                     after {} subdivisions (error estimate {:.3e}): a degenerate face?",
                    mortar.quadrature_tolerance, fi.n_unconverged, mortar.max_depth, fi.error
                ),
            });
        }
        stats.n_segments += fi.n_segments;
        stats.n_exact_segments += fi.n_exact;
        stats.n_coincident_faces += fi.coincident as usize;
        stats.n_triangles += fi.n_triangles;
        let np = pf.kind.n_nodes();
        for k in 0..np {
            own[ids[k]] += fi.own[k];
            err[ids[k]] += fi.error;
        }
        for (k, id, v) in fi.m {
            *rows[ids[k]].entry(id).or_insert(0.0) += v;
        }
        for (k, r, v) in fi.share {
            *share[ids[k]].entry(r).or_insert(0.0) += v;
        }
    }
    let node_xyz: HashMap<u64, [Real; 3]> = faces
        .iter()
        .flat_map(|f| f.nodes.iter().copied().zip(f.coords.iter().copied()))
        .collect();
    let mut bad: Vec<NodeReport> = Vec::new();
    let mut unmatched = Vec::new();
    let mut gaps = Vec::with_capacity(nn);
    let mut tstats = super::TieStats {
        n_pad: nn,
        max_distance: tol,
        ..Default::default()
    };
    for (j, pn) in pad.iter().enumerate() {
        let report = |reason: String| NodeReport {
            id: pn.id,
            coords: pn.coords,
            reason,
        };
        let transformed = side[j].is_some();
        // The gap's area vector: the caller's S_p, or Ŝ_j on quadratic faces.
        let node = if transformed {
            if d_hat[j].is_nan() || d_hat[j] <= 0.0 {
                bad.push(report(format!(
                    "its transformed dual integral D̂ = {:e} is not positive (a quadratic pad \
                     face too distorted for the dual basis)",
                    d_hat[j]
                )));
                continue;
            }
            ContactNode {
                area: s_hat[j],
                ..*pn
            }
        } else {
            *pn
        };
        let a = match node.pad_area() {
            Ok(a) => a,
            Err(reason) => {
                bad.push(report(reason));
                continue;
            }
        };
        if own[j].is_nan() || own[j] <= 0.0 {
            bad.push(report(
                "on no pad face (mortar pairing integrates over pad faces)".into(),
            ));
            continue;
        }
        let sum: Real = rows[j].values().sum();
        let coverage = sum / own[j];
        if !(coverage.is_finite() && (coverage - 1.0).abs() <= mortar.coverage_tolerance) {
            unmatched.push(report(format!(
                "the rotor faces cover {:.9} of its dual basis function's support (1 {:+.3e}; \
                 mortar pairing needs the pad face around it on the rotor surface)",
                coverage,
                coverage - 1.0
            )));
            continue;
        }
        stats.min_coverage = stats.min_coverage.min(coverage);
        stats.quadrature_error = stats.quadrature_error.max(err[j] / own[j]);
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
        let mut gap = Gap::at_pad_node(&node, a, main_node, opts, Some(t));
        if let Some(terms) = side[j].as_ref().filter(|t| t.len() > 1) {
            gap.pad_side = Some(PadSide {
                nodes: terms.iter().map(|&(n, _)| n).collect(),
                weights: terms.iter().map(|&(_, w)| w).collect(),
                dofs: Vec::new(),
            });
        }
        stats.n_transformed += transformed as usize;
        gaps.push(gap);
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
