//! `squeal transient` with `integrator = "generalized_alpha"`: the same problem, initial state
//! and outputs as the BDF path, integrated by the generalized-α method (fixed `galpha_h`, or
//! adaptive with RTOL1; the options of `accuracy::drive::galpha_options`, which the
//! work–precision study uses too).
//!
//! Outputs: `history.npy` + `history_map.json` and `energy.csv` (the BDF path's writers,
//! [`Recorder`]: the initial point, every NOUTPT-th accepted step, the final time),
//! `summary.json` (statistics, the verdict on the same response as the BDF's, energy
//! balance). Not written: `restart.json` (a restart continues a BDF state).

use super::records::{Recorder, Response};
use super::system::{GapFriction, Problem};
use super::{progress_bar, show_progress, solver_err, start_state, TransientReport, CHUNK};
use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::stages::accuracy::drive::galpha_options;
use crate::stages::model::ReducedModel;
use squeal_solver::bdf::{BdfStats, Status};
use squeal_solver::bsql::EnergyBalance;
use squeal_solver::galpha::{Galpha, GalphaSystem};
use squeal_solver::SolverError;

/// Runs the generalized-α transient and writes its outputs and `summary.json`.
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
    let (n, ng) = (model.n(), model.gaps.len());
    // The BSQL system gives the start (as the BDF path's) and the energy terms per step.
    let mut obs = problem.system(model.gaps.clone())?;
    let (y0, yp0, steady, ic) = start_state(&mut obs, &spec)?;
    let mut sys = GalphaSystem::new(
        problem.m.clone(),
        problem.b.clone(),
        problem.k.clone(),
        problem.g.clone(),
        problem.load.clone(),
        GapFriction {
            set: model.gaps.clone(),
        },
    )
    .map_err(solver_err("building the generalized-alpha system"))?;
    let opts = galpha_options(
        &spec,
        n,
        ng,
        spec.galpha_h,
        spec.rtol1,
        spec.rho_inf,
        spec.tfinal,
    );
    let mut ga = Galpha::new(opts, &mut sys, 0.0, &y0, &yp0)
        .map_err(solver_err("generalized-alpha start"))?;
    let t_start = ga.t();

    let mut rec = Recorder::open(scene, model, dir, spec.noutpt)?;
    let mut resp = Response::new(scene, model, rec.columns())?;
    let mut balance = EnergyBalance::new();
    {
        let (y, yp) = (ga.y().to_vec(), ga.yp().to_vec());
        balance.push(
            &obs.observe(t_start, &y, &yp)
                .map_err(solver_err("energy"))?,
        );
        rec.point(t_start, &y, &yp)?;
        resp.push(t_start, &y);
    }
    let bar = progress_bar(progress);
    let mut out_err: Option<String> = None;
    let mut steps_done = 0usize;
    let status = loop {
        let mut in_chunk = 0usize;
        let st = ga.step_to(&mut sys, spec.tfinal, |_, t, y, yp| {
            steps_done += 1;
            in_chunk += 1;
            let p = obs.observe(t, y, yp)?;
            balance.push(&p);
            resp.push(t, y);
            if let Err(e) = rec.step(steps_done, t, y, yp, &p, &balance) {
                out_err = Some(e.to_string());
                return Err(SolverError::Callback {
                    t,
                    message: e.to_string(),
                });
            }
            Ok(in_chunk < CHUNK)
        });
        let st = rec.end_chunk(st, &mut out_err, "integration (generalized-alpha)")?;
        show_progress(&bar, (ga.t() - t_start) / (spec.tfinal - t_start), || {
            format!(
                "t = {:.4e}, h = {:.2e}, generalized-alpha, steps {steps_done}",
                ga.t(),
                ga.h()
            )
        });
        match st {
            // The integrator counts max_steps per call; the run's cap counts every step.
            Status::Interrupted { .. } if steps_done >= spec.max_steps => {
                break Status::MaxSteps {
                    t: ga.t(),
                    steps: steps_done,
                }
            }
            Status::Interrupted { .. } => {}
            other => break other,
        }
    };
    if let Some(b) = &bar {
        b.finish();
    }
    if status.is_success() {
        rec.finish(spec.tfinal, ga.y(), ga.yp())?;
    } else {
        progress.info(format!("integration stopped: {status:?}"));
    }

    let t_after = problem.load.t_load.max(t_start);
    let (response, verdict) = resp.verdict(t_after, rec.columns());
    let stats = ga.stats().clone();
    let report = TransientReport {
        verb: "transient",
        version: crate::VERSION,
        status,
        steps: stats.steps,
        cpu_s: stats.cpu_s,
        wall_s: wall.elapsed().as_secs_f64(),
        squeal: verdict.is_squeal(
            scene.output.squeal_growth_threshold,
            scene.output.squeal_min_growth_factor,
        ),
        growth_rate_per_s: verdict.growth_rate_per_s,
        dominant_frequency_hz: verdict.dominant_frequency_hz,
        response,
        verdict,
        constraint_drift: stats.constraint_drift,
        max_constraint_drift: stats.max_constraint_drift,
        integrator: "generalized_alpha",
        bdf_stats: BdfStats::default(),
        galpha_stats: Some(stats),
        bsql_stats: Default::default(),
        steady_state: Some(steady),
        initial_conditions: Some(ic),
        energy_residual: balance.residual(),
        energy: balance,
        t_start,
        t_end: ga.t(),
        n_dofs: n,
        n_gaps: ng,
        history_rows: rec.rows(),
        active_effects,
        ignored,
        model_hash: problem.model_hash(),
        restarted_from: None,
        warnings: model.warnings.clone(),
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
