//! Surface pairing: each pad node tied to the point of a rotor face it projects on
//! (node-to-surface, small sliding, in the style of Abaqus' small-sliding contact or
//! Code_Aster's LIAISON_MAIL).

use super::face::RotorFace;
use super::grid::Grid;
use super::{ContactNode, FaceTie, Gap, GapSet, MatchOptions};
use crate::{ContactError, FrictionLaw, NodeReport, Real};
use serde::{Deserialize, Serialize};

/// What to do with pad nodes that project on no rotor face.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Unmatched {
    /// Stop with an error listing every such node (the default).
    #[default]
    Error,
    /// Leave them out (no gap) and list them in [`TieOutcome::unmatched`].
    Exclude,
}

/// Options of the surface pairing (besides the rotor motion, P0 and temperature of
/// [`MatchOptions`], whose `tolerance` is not used here).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct TieOptions {
    /// Face extension ε: a projection with |ξ|, |η| ≤ 1 + ε is on the face (default: 0.01,
    /// i.e. half a percent of the face's width beyond its edges).
    pub extension: Real,
    /// Largest distance from a pad node to its projection (default: None = 0.05 × the mean
    /// edge length of the rotor faces).
    pub max_distance: Option<Real>,
    /// Pad nodes projecting on no face: error or exclude (default: error).
    pub unmatched: Unmatched,
}

impl Default for TieOptions {
    fn default() -> Self {
        TieOptions {
            extension: 0.01,
            max_distance: None,
            unmatched: Unmatched::Error,
        }
    }
}

impl TieOptions {
    /// Checks the options; the error names the field and the value.
    pub fn validate(&self) -> Result<(), ContactError> {
        let bad = |field: &str, value: Real, reason: &str| ContactError::InvalidOption {
            field: format!("tie.{field}"),
            value: format!("{value}"),
            reason: reason.into(),
        };
        if !(self.extension.is_finite() && (0.0..=1.0).contains(&self.extension)) {
            return Err(bad("extension", self.extension, "must be in [0, 1]"));
        }
        if let Some(d) = self.max_distance {
            if !(d.is_finite() && d > 0.0) {
                return Err(bad("max_distance", d, "must be finite and > 0"));
            }
        }
        Ok(())
    }
}

/// Statistics of one surface pairing.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct TieStats {
    /// Pad nodes given.
    pub n_pad: usize,
    /// Gaps made.
    pub n_tied: usize,
    /// Gaps whose projection is a rotor node (one weight 1, the others 0).
    pub n_on_node: usize,
    /// Pad nodes left out (`unmatched = exclude`).
    pub n_excluded: usize,
    /// Distance limit used.
    pub max_distance: Real,
    /// Largest distance of a tied pad node to its projection.
    pub largest_distance: Real,
    /// Largest max(|ξ|, |η|) − 1 of a tied node (> 0: in the face extension).
    pub largest_outside: Real,
    /// Most Newton iterations of a chosen projection.
    pub max_iterations: usize,
}

/// What [`tie_gaps`] returns.
#[derive(Debug, Clone)]
pub struct TieOutcome {
    /// One gap per tied pad node, DOFs unassigned; friction law and VTOL as in
    /// [`crate::match_gaps`] until set.
    pub gaps: GapSet,
    /// Pad nodes projecting on no face (only with [`Unmatched::Exclude`]; else an error).
    pub unmatched: Vec<NodeReport>,
    /// Counters and extremes.
    pub stats: TieStats,
}

/// Ties every pad node to the rotor surface: projects it on the faces near it, keeps the
/// closest valid projection (|ξ|, |η| ≤ 1 + ε and distance ≤ the limit), and makes one gap
/// whose rotor side is the face's nodes with weights N_a(ξ*).
///
/// The gap keeps the pad node's position, normal n = S_p/|S_p|, area, P0, temperature and
/// sliding velocity ω × r, as [`crate::match_gaps`] does; `rotor_node` is the face node of
/// largest weight (for reports), and [`Gap::tie`] carries the face, (ξ, η), the nodes and the
/// weights. A pad node coincident with a rotor node gets weight 1 on it and 0 on the others
/// (face coordinates within [`crate::gaps::FACE_SNAP`] of −1, 0, 1 are set to it), so the gap acts
/// exactly as the coincident pair of [`crate::match_gaps`].
///
/// *Candidates.* Each face's bounding box, grown by the distance limit and the extension, is
/// bucketed in a uniform grid (cell: the mean face diagonal); a pad node is projected on the
/// faces of its cell. *Choice.* Among valid projections, the one least outside its face,
/// then the closest, then the lowest face index.
///
/// # Reference
/// The constraint row of the gap is $n\cdot(\sum_a N_a(\xi^*) u_a - u_{pad}) = 0$, the
/// paper's $(\vec u_d - \vec u_p)\cdot\vec n = 0$ [Paper eq. (9)] with the rotor point
/// interpolated on its face; the friction forces on the rotor, eq. (7), go to the face nodes
/// with the same weights ([`GapSet::add_forces`]).
///
/// # Errors
/// [`ContactError::InvalidOption`] for bad options or faces (wrong node count, non-finite
/// coordinates); [`ContactError::Matching`] for pad nodes with a zero area vector or
/// non-finite coordinates, and, with [`Unmatched::Error`], listing every pad node that
/// projects on no face (with the nearest face tried, its (ξ, η) and the distance).
pub fn tie_gaps(
    pad: &[ContactNode],
    faces: &[RotorFace],
    opts: &MatchOptions,
    tie: &TieOptions,
) -> Result<TieOutcome, ContactError> {
    opts.validate()?;
    tie.validate()?;
    check_faces(faces, "faces")?;
    let (tol, mean_edge) = distance_limit(faces, opts, tie);
    let mut bad: Vec<NodeReport> = Vec::new();
    let report = |n: &ContactNode, reason: String| NodeReport {
        id: n.id,
        coords: n.coords,
        reason,
    };
    for n in pad {
        if n.coords.iter().any(|x| !x.is_finite()) {
            bad.push(report(n, "pad node has non-finite coordinates".into()));
        }
    }
    if !bad.is_empty() {
        return Err(ContactError::Matching {
            tolerance: tol,
            nodes: bad,
        });
    }
    // Faces bucketed by their grown bounding boxes.
    let cell = (2.0f64.sqrt() * mean_edge).max(tol).max(Real::MIN_POSITIVE);
    let boxes: Vec<([Real; 3], [Real; 3])> = faces
        .iter()
        .map(|f| {
            let grow = tol + tie.extension * f.edge_length();
            let mut lo = [Real::INFINITY; 3];
            let mut hi = [Real::NEG_INFINITY; 3];
            for c in &f.coords {
                for k in 0..3 {
                    lo[k] = lo[k].min(c[k] - grow);
                    hi[k] = hi[k].max(c[k] + grow);
                }
            }
            (lo, hi)
        })
        .collect();
    let grid = Grid::from_boxes(&boxes, cell);
    let mut stats = TieStats {
        n_pad: pad.len(),
        max_distance: tol,
        ..TieStats::default()
    };
    let mut gaps = Vec::with_capacity(pad.len());
    let mut unmatched = Vec::new();
    // A pad node whose consistent area is round-off next to the others' (a tri6 face's
    // corner: ∫N_corner dΓ = 0) has no normal: its gap would point anywhere.
    let mean_area =
        pad.iter().filter_map(|n| n.pad_area().ok()).sum::<Real>() / pad.len().max(1) as Real;
    for pn in pad {
        let a = match pn.pad_area() {
            Ok(a) if a <= 1e-9 * mean_area => {
                bad.push(report(
                    pn,
                    format!(
                        "its area vector {:?} is round-off ({a:.3e} against a mean of \
                         {mean_area:.3e}: a corner of a quadratic triangle, whose consistent \
                         area ∫N dΓ is 0); node-to-surface pairing needs a positive area at \
                         every pad node: use the mortar pairing",
                        pn.area
                    ),
                ));
                continue;
            }
            Ok(a) => a,
            Err(reason) if pn.area == [0.0; 3] => {
                bad.push(report(
                    pn,
                    format!(
                        "{reason} (a corner of a quadratic triangle has ∫N dΓ = 0: use the \
                         mortar pairing)"
                    ),
                ));
                continue;
            }
            Err(reason) => {
                bad.push(report(pn, reason));
                continue;
            }
        };
        let mut best: Option<(usize, super::face::Projection)> = None;
        let mut nearest: Option<(usize, super::face::Projection)> = None;
        for fi in grid.boxes_at(&pn.coords) {
            let Some(pr) = faces[fi].project(pn.coords) else {
                continue;
            };
            if nearest.is_none_or(|(_, q)| (pr.outside, pr.distance) < (q.outside, q.distance)) {
                nearest = Some((fi, pr));
            }
            if pr.outside > tie.extension || pr.distance > tol {
                continue;
            }
            let key = |q: &super::face::Projection| (q.outside, q.distance);
            if best.is_none_or(|(bi, q)| key(&pr) < key(&q) || (key(&pr) == key(&q) && fi < bi)) {
                best = Some((fi, pr));
            }
        }
        let Some((fi, pr)) = best else {
            let reason = match nearest {
                Some((fi, q)) => format!(
                    "projects on no rotor face within |xi|,|eta| <= 1 + {} and distance {tol:e}; \
                     nearest: face {} at (xi, eta) = ({:.4}, {:.4}), distance {:.3e}",
                    tie.extension, faces[fi].id, q.xi[0], q.xi[1], q.distance
                ),
                None => format!("no rotor face within distance {tol:e}"),
            };
            unmatched.push(report(pn, reason));
            continue;
        };
        let f = &faces[fi];
        let nn = f.kind.n_nodes();
        let (w, _) = f.kind.shape(pr.xi);
        let weights = w[..nn].to_vec();
        let main = (0..nn).fold(0, |m, i| if weights[i] > weights[m] { i } else { m });
        if weights[main] == 1.0 {
            stats.n_on_node += 1;
        }
        stats.largest_distance = stats.largest_distance.max(pr.distance);
        stats.largest_outside = stats.largest_outside.max(pr.outside);
        stats.max_iterations = stats.max_iterations.max(pr.iterations);
        let tie = FaceTie {
            face: f.id,
            kind: f.kind,
            xi: pr.xi,
            nodes: f.nodes.clone(),
            weights,
            distance: pr.distance,
            dofs: Vec::new(),
            mortar: false,
            coords: f.coords.clone(),
        };
        gaps.push(Gap::at_pad_node(pn, a, f.nodes[main], opts, Some(tie)));
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
    stats.n_tied = gaps.len();
    stats.n_excluded = unmatched.len();
    Ok(TieOutcome {
        gaps: GapSet {
            gaps,
            law: FrictionLaw::default(),
            vtol: GapSet::DEFAULT_VTOL,
        },
        unmatched,
        stats,
    })
}

/// Checks each face's node count and coordinates; errors name `field[i]`.
pub(super) fn check_faces(faces: &[RotorFace], field: &str) -> Result<(), ContactError> {
    for (i, f) in faces.iter().enumerate() {
        let n = f.kind.n_nodes();
        if f.nodes.len() != n || f.coords.len() != n {
            return Err(ContactError::InvalidOption {
                field: format!("{field}[{i}]"),
                value: format!(
                    "face {} with {} ids, {} points",
                    f.id,
                    f.nodes.len(),
                    f.coords.len()
                ),
                reason: format!("a {:?} face has {n} nodes", f.kind),
            });
        }
        if f.coords.iter().flatten().any(|x| !x.is_finite()) {
            return Err(ContactError::InvalidOption {
                field: format!("{field}[{i}]"),
                value: format!("face {}: {:?}", f.id, f.coords),
                reason: "non-finite node coordinates".into(),
            });
        }
    }
    Ok(())
}

/// The distance limit (`max_distance`, default 0.05 × the faces' mean edge length, or the
/// matching tolerance when that is 0) and the mean edge length.
pub(super) fn distance_limit(
    faces: &[RotorFace],
    opts: &MatchOptions,
    tie: &TieOptions,
) -> (Real, Real) {
    let mean_edge = if faces.is_empty() {
        0.0
    } else {
        faces.iter().map(RotorFace::edge_length).sum::<Real>() / faces.len() as Real
    };
    let max_distance = tie.max_distance.unwrap_or(0.05 * mean_edge);
    let tol = if max_distance > 0.0 {
        max_distance
    } else {
        opts.tolerance
    };
    (tol, mean_edge)
}
