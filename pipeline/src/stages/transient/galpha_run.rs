//! `squeal transient` with `integrator = "generalized_alpha"`: the same problem and initial
//! state as the BDF path, integrated by the generalized-α method (fixed `galpha_h`, or
//! adaptive with RTOL1), sampled every NOUTPT·(TFINAL/1000) on a uniform grid for the
//! verdict. Writes `summary.json` (statistics, verdict, energy balance).
//!
//! Not written on this path (yet): `history.npy`, `energy.csv`, `restart.json`.

use super::system::Problem;
use super::verdict;
use super::{SteadySummary, TransientReport};
use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::stages::accuracy::drive::{initial_state, integrate, Method};
use crate::stages::model::ReducedModel;
use squeal_solver::bdf::BdfStats;
use squeal_solver::galpha::GalphaStats;

type Real = f64;

/// Runs the generalized-α transient and writes `summary.json`.
#[allow(clippy::too_many_arguments)]
pub(super) fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    model: &ReducedModel,
    problem: &Problem,
    wall: std::time::Instant,
    active_effects: Vec<String>,
    ignored: Vec<String>,
) -> Result<TransientReport, PipelineError> {
    let spec = scene.transient.clone().unwrap_or_default();
    let n = model.n();
    let (y0, yp0) = initial_state(problem, &model.gaps, spec.tolint)?;
    let samples = 2000usize;
    let grid: Vec<Real> = (0..=samples)
        .map(|k| spec.tfinal * k as Real / samples as Real)
        .collect();
    let dofs: Vec<usize> = (0..n).collect();
    let method = Method::GeneralizedAlpha {
        h: spec.galpha_h,
        rtol: spec.rtol1,
        rho_inf: spec.rho_inf,
    };
    let r = integrate(
        problem,
        &model.gaps,
        &spec,
        method,
        &y0,
        &yp0,
        &grid,
        &dofs,
        true,
    )?;
    if !r.status.is_success() {
        progress.info(format!("integration stopped: {:?}", r.status));
    }
    let t_after = problem.load.t_load;
    let (col, vd) = (0..n)
        .map(|j| {
            let x: Vec<Real> = r.v.iter().map(|v| v[j]).collect();
            let peak =
                r.t.iter()
                    .zip(&x)
                    .filter(|(t, _)| **t > t_after)
                    .fold(0.0f64, |m, (_, v)| m.max(v.abs()));
            (j, peak, x)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(j, _, x)| (j, verdict::analyse(&r.t, &x, t_after)))
        .unwrap_or((0, verdict::analyse(&[], &[], 0.0)));
    let energy = r.energy.clone().unwrap_or_default();
    let report = TransientReport {
        verb: "transient",
        version: crate::VERSION,
        status: r.status.clone(),
        steps: r.steps,
        cpu_s: r.cpu_s,
        wall_s: wall.elapsed().as_secs_f64(),
        squeal: vd
            .growth_rate_per_s
            .is_some_and(|g| g > scene.output.squeal_growth_threshold),
        growth_rate_per_s: vd.growth_rate_per_s,
        dominant_frequency_hz: vd.dominant_frequency_hz,
        response: format!("v_dof{col}"),
        verdict: vd,
        constraint_drift: r.max_constraint_drift,
        max_constraint_drift: r.max_constraint_drift,
        integrator: "generalized_alpha",
        bdf_stats: BdfStats::default(),
        galpha_stats: Some(GalphaStats {
            steps: r.steps,
            newton_iterations: r.newton_iterations,
            residual_evals: r.residual_evals,
            factorisations: r.factorisations,
            rejected_steps: r.rejected_steps,
            cpu_s: r.cpu_s,
            max_constraint_drift: r.max_constraint_drift,
            ..GalphaStats::default()
        }),
        bsql_stats: Default::default(),
        steady_state: None::<SteadySummary>,
        initial_conditions: None,
        energy_residual: energy.residual(),
        energy,
        t_start: 0.0,
        t_end: r.t.last().copied().unwrap_or(0.0),
        n_dofs: n,
        n_gaps: model.gaps.len(),
        history_rows: 0,
        active_effects,
        ignored,
        model_hash: problem.model_hash(),
        restarted_from: None,
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
