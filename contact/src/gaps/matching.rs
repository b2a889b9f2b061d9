//! PREBSQL gap matching: coincident pad/rotor nodes → gap elements.

use super::grid::Grid;
use super::{ContactNode, Gap, GapSet, MatchOptions};
use crate::{ContactError, FrictionLaw, NodeReport, Real};

/// Matches every pad node to the rotor node that coincides with it within
/// `opts.tolerance`, and builds one gap per pad node.
///
/// * normal `n = S_p/|S_p|` (out of the pad, toward the rotor);
/// * sliding velocity `v_slide = ω × (x − origin)`, ω = 2π·rpm/60 about `rotor_axis`;
/// * `p0`, `temperature` from the options; DOF indices are left `None` (set them with
///   [`GapSet::assign_dofs`]); the friction law is `Constant { mu: 0 }` and VTOL = 1e-3
///   until set with [`GapSet::with_friction`].
///
/// The search buckets the rotor nodes in a grid of cell size `tolerance` (linear time).
/// Call once per contact surface and [`GapSet::append`] the results for several surfaces.
///
/// # Errors
/// [`ContactError::Matching`] listing **every** offending node with id and coordinates:
/// pad nodes with no rotor node within tolerance, pad nodes with several (ambiguous), rotor
/// nodes matched by several pad nodes, pad nodes with a zero or non-finite area vector, and
/// nodes with non-finite coordinates.
///
/// # Reference
/// The rotor velocity at the point is the paper's $\{0, V_y, 0\}$ of
/// $$\{\Delta v\} = \{v_r\} - \{v_p\} + \{0, V_y, 0\}$$ [Paper eq. (2)], kept as a general 3D
/// vector ω × r.
pub fn match_gaps(
    pad: &[ContactNode],
    rotor: &[ContactNode],
    opts: &MatchOptions,
) -> Result<GapSet, ContactError> {
    opts.validate()?;
    let tol = opts.tolerance;
    let mut bad: Vec<NodeReport> = Vec::new();
    let report = |n: &ContactNode, reason: String| NodeReport {
        id: n.id,
        coords: n.coords,
        reason,
    };
    for (side, nodes) in [("pad", pad), ("rotor", rotor)] {
        for n in nodes {
            if n.coords.iter().any(|x| !x.is_finite()) {
                bad.push(report(n, format!("{side} node has non-finite coordinates")));
            }
        }
    }
    if !bad.is_empty() {
        return Err(ContactError::Matching {
            tolerance: tol,
            nodes: bad,
        });
    }
    let rotor_pts: Vec<[Real; 3]> = rotor.iter().map(|n| n.coords).collect();
    let grid = Grid::new(&rotor_pts, tol);
    let mut used_by: Vec<Vec<usize>> = vec![Vec::new(); rotor.len()];
    let mut gaps = Vec::with_capacity(pad.len());
    for (ip, pn) in pad.iter().enumerate() {
        let a = match pn.pad_area() {
            Ok(a) => a,
            Err(reason) => {
                bad.push(report(pn, reason));
                continue;
            }
        };
        let cand = grid.within(&rotor_pts, &pn.coords, tol);
        match cand.len() {
            0 => bad.push(report(
                pn,
                "pad node has no rotor node within tolerance".into(),
            )),
            1 => {
                let ir = cand[0];
                used_by[ir].push(ip);
                gaps.push(Gap::at_pad_node(pn, a, rotor[ir].id, opts, None));
            }
            _ => {
                let ids: Vec<String> = cand
                    .iter()
                    .map(|&i| {
                        let d = ((rotor[i].coords[0] - pn.coords[0]).powi(2)
                            + (rotor[i].coords[1] - pn.coords[1]).powi(2)
                            + (rotor[i].coords[2] - pn.coords[2]).powi(2))
                        .sqrt();
                        format!("{} (distance {d:.3e})", rotor[i].id)
                    })
                    .collect();
                bad.push(report(
                    pn,
                    format!(
                        "ambiguous: rotor nodes {} are all within tolerance",
                        ids.join(", ")
                    ),
                ));
            }
        }
    }
    for (ir, users) in used_by.iter().enumerate() {
        if users.len() > 1 {
            let ids: Vec<String> = users.iter().map(|&i| pad[i].id.to_string()).collect();
            bad.push(report(
                &rotor[ir],
                format!(
                    "rotor node matched by {} pad nodes: {}",
                    users.len(),
                    ids.join(", ")
                ),
            ));
        }
    }
    if !bad.is_empty() {
        return Err(ContactError::Matching {
            tolerance: tol,
            nodes: bad,
        });
    }
    Ok(GapSet {
        gaps,
        law: FrictionLaw::default(),
        vtol: GapSet::DEFAULT_VTOL,
    })
}
