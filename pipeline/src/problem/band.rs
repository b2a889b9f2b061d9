//! The band-limited model of a scene (`[transient] band_limited = true`, and `squeal
//! limit-cycle`): the reduced model linearised at the loaded steady sliding state (the CEA's
//! state, friction damping included), condensed to its roots below `band_cutoff` × the band
//! top plus the static correction that keeps the gap DOFs exact, closed by the exact contact
//! law ([`squeal_solver::condense`]).
//!
//! The contact I/O is each gap's relative coordinates: the remainder of the contact law acts
//! through two tangential patterns per gap (T₁ᵀ, T₂ᵀ of the pad-minus-rotor motion) and the
//! normal rows of the gaps that may open; the model reads the relative tangential velocities
//! and the rotor's normal velocity on the friction face of every gap. A unilateral gap must be
//! compliant (`normal_stiffness`): its force is min(q, P₀A), continuous, with no event.
//!
//! # Reference
//! Craig & Kurdila, *Fundamentals of Structural Dynamics* (2006) §10.4 and ch. 17 (the static
//! correction); Sinou & Besset, Mech. Syst. Signal Process. (2017) (double modal synthesis of a
//! brake with its contact kept nonlinear).

use super::system::{GapFriction, Problem};
use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::problem::tangents;
use crate::scene::Scene;
use faer::Mat;
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::bsql::SteadyOptions;
use squeal_solver::condense::{
    BandContact, BandError, BandOptions, BandReference, BandSystem, Condenser, Inputs,
};
use squeal_solver::Real;

/// What the condensation kept, removed and estimated, with the settings that decided it
/// (`summary.json`'s `band_limited`, `limit_cycle.json`'s `band_model`).
#[derive(Debug, Clone, Serialize)]
pub struct BandReport {
    /// `transient.band_cutoff`: the cut-off as a multiple of the band top.
    pub cutoff_factor: Real,
    /// `transient.band_tolerance`: the largest admissible error estimate.
    pub tolerance: Real,
    /// The contact's velocity rows (relative tangential velocities and the rotor's normal
    /// velocity at each gap) and the independent outputs the model reads them from (fewer
    /// when the rows are dependent, as on an interface-reduced rotor).
    pub velocity_rows: usize,
    pub velocity_outputs: usize,
    /// Kept, removed (count, the largest removed unstable root), the error estimate.
    #[serde(flatten)]
    pub stats: squeal_solver::condense::BandStats,
}

impl BandReport {
    /// One line for the run's log.
    pub fn line(&self) -> String {
        let s = &self.stats;
        let largest = s.largest_removed_unstable.map_or("none".to_string(), |r| {
            format!("Re p = {:+.1} /s at {:.1} Hz", r.real_part, r.frequency_hz)
        });
        format!(
            "band-limited model: cut-off {:.1} Hz ({} x band {:.1} Hz); kept {} roots ({} states), \
             removed {} ({} unstable, largest {largest}); error estimate {:.2e} at {:.1} Hz \
             (tolerance {:.0e}); {} velocity rows read through {} outputs",
            s.cutoff_hz,
            self.cutoff_factor,
            s.band_hz,
            s.kept,
            s.n_states,
            s.removed,
            s.removed_unstable,
            s.error_estimate,
            s.error_at_hz,
            self.tolerance,
            self.velocity_rows,
            self.velocity_outputs
        )
    }
}

/// The band-limited system of a scene, ready to integrate or to continue.
pub struct Band {
    pub system: BandSystem<GapFriction>,
    pub report: BandReport,
    /// Face rows (gaps × n_v): the rotor's normal velocity on the friction face of each gap over
    /// the model's velocity outputs.
    pub face: Mat<Real>,
    /// The time at which the load is complete (the state the model was linearised about).
    pub t_ref: Real,
    /// The largest sliding speed (the velocity scale of the harmonic balance).
    pub velocity_scale: Real,
}

/// Relative singular value below which a velocity row is a combination of the others.
const ROW_RANK_TOL: Real = 1e-10;

/// The velocity rows R (rows × contact DOFs) as the model reads them: R itself when its rows
/// are independent (None), else an orthonormal basis Qᵀ of their span (rank × contact DOFs,
/// from the SVD Rᵀ = U Σ Vᵀ, singular values above `ROW_RANK_TOL` × the largest) with the map
/// R Q = V Σ (rows × rank) from its outputs back to the rows. Every row of R is in the span,
/// so R v = (R Q)(Qᵀ v) exactly for every v.
fn independent_rows(rows: Mat<Real>) -> Result<(Mat<Real>, Option<Mat<Real>>), PipelineError> {
    let (nr, nc) = (rows.nrows(), rows.ncols());
    if nr == 0 {
        return Ok((rows, None));
    }
    let svd = rows
        .transpose()
        .thin_svd()
        .map_err(|e| PipelineError::Scene {
            field: "transient.band_limited".into(),
            message: format!("the SVD of the {nr} x {nc} contact velocity rows failed: {e:?}"),
        })?;
    let s = svd.S().column_vector();
    let smax = (0..s.nrows()).map(|i| s[i]).fold(0.0, Real::max);
    let keep: Vec<usize> = (0..s.nrows())
        .filter(|&i| s[i] > ROW_RANK_TOL * smax)
        .collect();
    if keep.len() == nr {
        return Ok((rows, None));
    }
    let (u, v) = (svd.U(), svd.V());
    let q_t = Mat::from_fn(keep.len(), nc, |r, a| u[(a, keep[r])]);
    let to_rows = Mat::from_fn(nr, keep.len(), |r, c| v[(r, keep[c])] * s[keep[c]]);
    Ok((q_t, Some(to_rows)))
}

/// Rows (ng × n) of the direction `dir(g)` of each gap's relative motion (rotor minus pad, or
/// the rotor's alone).
fn direction_rows(
    gaps: &GapSet,
    n: usize,
    dir: impl Fn(usize) -> [Real; 3],
    rotor_only: bool,
) -> Mat<Real> {
    let mut r = Mat::zeros(gaps.len(), n);
    for (ig, g) in gaps.gaps.iter().enumerate() {
        let d = dir(ig);
        for k in 0..3 {
            if d[k] == 0.0 {
                continue;
            }
            for (w, dofs) in g.rotor_terms() {
                if let Some(j) = dofs[k] {
                    r[(ig, j)] += w[k] * d[k];
                }
            }
            if !rotor_only {
                for (w, dofs) in g.pad_terms() {
                    if let Some(j) = dofs[k] {
                        r[(ig, j)] -= w[k] * d[k];
                    }
                }
            }
        }
    }
    r
}

/// Two unit tangents of a unit normal.
fn tangents_of(nv: [Real; 3]) -> ([Real; 3], [Real; 3]) {
    let a = if nv[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let dot = a[0] * nv[0] + a[1] * nv[1] + a[2] * nv[2];
    let mut t1 = [a[0] - dot * nv[0], a[1] - dot * nv[1], a[2] - dot * nv[2]];
    let l = (t1[0] * t1[0] + t1[1] * t1[1] + t1[2] * t1[2]).sqrt();
    for x in &mut t1 {
        *x /= l;
    }
    let t2 = [
        nv[1] * t1[2] - nv[2] * t1[1],
        nv[2] * t1[0] - nv[0] * t1[2],
        nv[0] * t1[1] - nv[1] * t1[0],
    ];
    (t1, t2)
}

fn band_err(e: BandError) -> PipelineError {
    match e {
        BandError::EstimateAboveTolerance { .. } => PipelineError::Scene {
            field: "transient.band_tolerance".into(),
            message: format!("the band-limited model is refused: {e}"),
        },
        BandError::Option { field, .. } => PipelineError::Scene {
            field: format!("transient.band ({field})"),
            message: e.to_string(),
        },
        e => PipelineError::Model(format!("band-limited model: {e}")),
    }
}

/// The band-limited model of `scene` on `model` (`problem`: the scene's BSQL problem), with
/// the cut-off and tolerance of `scene`'s `[transient]` table.
///
/// # Errors
/// No band (`reduction.frequency_of_interest_hz` / `model.band_hz`); a unilateral gap without
/// normal stiffness, or with `separation_smoothing`; the steady state, the decomposition or the
/// static solve failing; an error estimate above `transient.band_tolerance` (a refusal that
/// names the estimate and the lowest removed root).
pub fn build(
    scene: &Scene,
    model: &ReducedModel,
    problem: &Problem,
) -> Result<Band, PipelineError> {
    let spec = scene.transient.clone().unwrap_or_default();
    let band = scene.band_hz().ok_or_else(|| PipelineError::Scene {
        field: "transient.band_limited".into(),
        message: "the band-limited model needs the model's band \
                  (reduction.frequency_of_interest_hz, or model.band_hz for stored matrices)"
            .into(),
    })?;
    let (n, ng) = (model.n(), model.gap_geometry.len());
    let sep = super::system::separation_mask(scene, model);
    for (i, c) in scene.contact.iter().enumerate() {
        if c.separation && c.separation_smoothing.is_some() {
            return Err(PipelineError::Scene {
                field: format!("contact[{i}].separation_smoothing"),
                message: "the band-limited model opens a compliant gap with its own law \
                          (force min(q, P0 A)); leave separation_smoothing out"
                    .into(),
            });
        }
    }
    let compliance: Vec<Real> = if problem.compliance.is_empty() {
        vec![0.0; ng]
    } else {
        problem.compliance.clone()
    };
    if let Some(k) = (0..ng).find(|&k| sep[k] && compliance[k] == 0.0) {
        return Err(PipelineError::Scene {
            field: "contact[].normal_stiffness".into(),
            message: format!(
                "gap {k} may separate but is rigid: the band-limited model opens compliant \
                 gaps only (give the pair a normal_stiffness)"
            ),
        });
    }
    let steady = SteadyOptions {
        tol: spec.tolint,
        ..Default::default()
    };
    let lin = tangents::at_steady_state(problem, &problem.gaps, &steady)?;
    let sys = tangents::cea_matrices(problem, &lin, true)?;
    let t_ref = tangents::full_load_time(problem);
    let gaps = &problem.gaps;
    let t1 = direction_rows(gaps, n, |g| tangents_of(gaps.gaps[g].normal).0, false);
    let t2 = direction_rows(gaps, n, |g| tangents_of(gaps.gaps[g].normal).1, false);
    let nrot = direction_rows(gaps, n, |g| gaps.gaps[g].normal, true);
    let dofs: Vec<usize> = (0..n)
        .filter(|&j| {
            (0..ng).any(|k| problem.g[(k, j)] != 0.0 || t1[(k, j)] != 0.0 || t2[(k, j)] != 0.0)
        })
        .collect();
    let nc = dofs.len();
    let uni: Vec<usize> = (0..ng).filter(|&k| sep[k]).collect();
    let np = 2 * ng + uni.len();
    // A direction with no DOF at a gap (a stored model's pad without an x DOF) gives a zero
    // pattern and a zero row: left out, so that both have full rank.
    let nonzero = |m: &Mat<Real>, k: usize| dofs.iter().any(|&d| m[(k, d)] != 0.0);
    let mut pattern_cols: Vec<Vec<Real>> = Vec::with_capacity(np);
    for m in [&t1, &t2] {
        for k in (0..ng).filter(|&k| nonzero(m, k)) {
            pattern_cols.push(dofs.iter().map(|&d| m[(k, d)]).collect());
        }
    }
    for &k in &uni {
        pattern_cols.push(dofs.iter().map(|&d| problem.g[(k, d)]).collect());
    }
    let patterns = Mat::from_fn(nc, pattern_cols.len(), |a, j| pattern_cols[j][a]);
    let mut row_list: Vec<Vec<Real>> = Vec::with_capacity(3 * ng);
    for m in [&t1, &t2] {
        for k in (0..ng).filter(|&k| nonzero(m, k)) {
            row_list.push(dofs.iter().map(|&d| m[(k, d)]).collect());
        }
    }
    let first_face = row_list.len();
    let mut face_of = vec![None; ng];
    for (k, f) in face_of.iter_mut().enumerate() {
        if nonzero(&nrot, k) {
            *f = Some(row_list.len());
            row_list.push(dofs.iter().map(|&d| nrot[(k, d)]).collect());
        }
    }
    let n_rows = row_list.len();
    let rows = Mat::from_fn(n_rows, nc, |r, a| row_list[r][a]);
    // The rows read the model's velocities through its reduced coordinates: on an
    // interface-reduced rotor the rotor's normal velocity at every gap is a combination of the
    // interface's few coordinates, so the rows are dependent. The model then reads an
    // orthonormal basis of their span (`outputs`), from which every row is exact.
    let (rows, to_rows) = independent_rows(rows)?;
    let velocity_outputs = rows.nrows();
    let compliant: Vec<usize> = (0..ng).filter(|&k| compliance[k] > 0.0).collect();
    let inputs = Inputs {
        load: problem.load.p_brake.clone(),
        contact_dofs: dofs,
        patterns: Some(patterns),
        velocity_rows: Some(rows),
        compliant_rows: Mat::from_fn(compliant.len(), n, |r, j| {
            problem.g[(compliant[r], j)] / compliance[compliant[r]]
        }),
    };
    let opts = BandOptions {
        cutoff_hz: spec.band_cutoff * band,
        band_hz: Some(band),
        tolerance: spec.band_tolerance,
        ..Default::default()
    };
    let condenser = Condenser::new(&sys).map_err(band_err)?;
    let bm = condenser.model(inputs, &opts).map_err(band_err)?;
    let report = BandReport {
        cutoff_factor: spec.band_cutoff,
        tolerance: spec.band_tolerance,
        velocity_rows: n_rows,
        velocity_outputs,
        stats: bm.stats.clone(),
    };
    let open_force: Vec<Option<Real>> = (0..ng)
        .map(|k| sep[k].then(|| gaps.gaps[k].p0 * gaps.gaps[k].area))
        .collect();
    let system = BandSystem::new(
        bm,
        GapFriction { set: gaps.clone() },
        problem.load.clone(),
        BandReference {
            u: lin.u.clone(),
            lambda_dot: lin.lambda_dot.clone(),
            ramp: problem.load.ramp(t_ref),
        },
        BandContact {
            g: problem.g.clone(),
            compliance,
            open_force,
        },
    )
    .map_err(|e| PipelineError::Solver {
        what: "band-limited system".into(),
        source: e,
    })?;
    let faces: Vec<usize> = face_of.iter().flatten().copied().collect();
    debug_assert!(faces.iter().all(|&r| r >= first_face));
    let face_rows = Mat::from_fn(
        faces.len(),
        n_rows,
        |g, r| if r == faces[g] { 1.0 } else { 0.0 },
    );
    let face = match &to_rows {
        Some(t) => &face_rows * t,
        None => face_rows,
    };
    let velocity_scale = gaps
        .gaps
        .iter()
        .map(|g| (g.v_slide[0].powi(2) + g.v_slide[1].powi(2) + g.v_slide[2].powi(2)).sqrt())
        .fold(0.0, Real::max);
    Ok(Band {
        system,
        report,
        face,
        t_ref,
        velocity_scale,
    })
}
