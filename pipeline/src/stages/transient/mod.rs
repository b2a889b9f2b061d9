//! `squeal transient`: the BSQL nonlinear transient of the reduced brake model.
//!
//! reduced model → BSQL system (M, B, K, G, P(t), gap friction) → steady sliding state before
//! the brake load (TOLINT) → consistent y'(0) → BDF (or generalized-α, `galpha_run`) to
//! TFINAL. Outputs: `history.npy` + `history_map.json` and `energy.csv` (both integrators,
//! written by [`records::Recorder`]), `restart.json` (BDF: every NRSTRT steps and at the
//! end), `summary.json` with every statistic and the squeal verdict.

pub mod export;
mod galpha_run;
mod records;
pub mod restart;
pub mod system;
pub mod verdict;

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{Scene, TransientSpec};
use crate::stages::model;
use indicatif::{ProgressBar, ProgressStyle};
use restart::RestartFile;
use serde::Serialize;
use squeal_solver::bdf::{
    consistent_initial_conditions, Bdf, BdfOptions, BdfStats, IcStats, InitialConditionOptions,
    Status,
};
use squeal_solver::bsql::{steady_state, BsqlStats, BsqlSystem, EnergyBalance, SteadyOptions};
use squeal_solver::SolverError;
use std::path::Path;
use std::time::Instant;
use verdict::Verdict;

/// Steps between progress updates, history flushes and chances to write the restart file.
const CHUNK: usize = 50;

/// `summary.json` of a transient run.
#[derive(Debug, Clone, Serialize)]
pub struct TransientReport {
    pub verb: &'static str,
    pub version: &'static str,
    /// How the integration ended.
    pub status: Status,
    /// Accepted steps (cumulative over restarts).
    pub steps: u64,
    /// Seconds inside the integrator (cumulative over restarts).
    pub cpu_s: f64,
    /// Whole run, wall seconds.
    pub wall_s: f64,
    pub squeal: bool,
    pub growth_rate_per_s: Option<f64>,
    pub dominant_frequency_hz: Option<f64>,
    /// History column of the verdict's response.
    pub response: String,
    pub verdict: Verdict,
    /// ‖G v‖∞ at the last step and its maximum.
    pub constraint_drift: f64,
    pub max_constraint_drift: f64,
    /// `bdf` or `generalized_alpha`.
    pub integrator: &'static str,
    /// BDF counters (zero for generalized-α runs).
    pub bdf_stats: BdfStats,
    /// Generalized-α counters (generalized-α runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub galpha_stats: Option<squeal_solver::galpha::GalphaStats>,
    pub bsql_stats: BsqlStats,
    pub steady_state: Option<SteadySummary>,
    pub initial_conditions: Option<IcStats>,
    pub energy: EnergyBalance,
    /// Energy balance residual ΔE − net work in.
    pub energy_residual: f64,
    pub t_start: f64,
    pub t_end: f64,
    pub n_dofs: usize,
    pub n_gaps: usize,
    pub history_rows: usize,
    /// The effects this run computed (only what the scene names).
    pub active_effects: Vec<String>,
    /// Scene values given but without effect, and why.
    pub ignored: Vec<String>,
    pub model_hash: String,
    pub restarted_from: Option<String>,
    /// Inputs accepted with a measured value to know about ([`crate::warning`]).
    pub warnings: Vec<crate::warning::Warning>,
}

/// Steady-state solve summary.
#[derive(Debug, Clone, Serialize)]
pub struct SteadySummary {
    pub iterations: usize,
    pub residual_norm: f64,
}

fn solver_err(what: &str) -> impl FnOnce(SolverError) -> PipelineError + '_ {
    move |source| PipelineError::Solver {
        what: what.to_string(),
        source,
    }
}

fn effects(
    scene: &Scene,
    model: &model::ReducedModel,
    p: &system::Problem,
) -> (Vec<String>, Vec<String>) {
    let mut on = Vec::new();
    let mut ignored = Vec::new();
    let law = &model.gaps.law;
    if !model.gaps.is_empty() {
        on.push(format!("contact ({} gaps)", model.gaps.len()));
        on.push(format!(
            "friction law {}",
            serde_json::to_string(law).unwrap_or_default()
        ));
        if law.depends_on_speed() {
            on.push("friction: speed dependence dmu/dv".into());
        }
        if law.depends_on_pressure() {
            on.push("friction: pressure dependence dmu/dp".into());
        }
        if !law.depends_on_speed() && !law.depends_on_pressure() {
            on.push("friction: constant mu, no derivatives of mu evaluated".into());
        }
        if law.depends_on_temperature() {
            on.push("friction: temperature lookups".into());
        } else if model.gaps.gaps.iter().any(|g| g.temperature != 0.0) {
            ignored
                .push("gap temperatures: the friction law does not depend on temperature".into());
        }
        if model.gaps.gaps.iter().any(|g| g.p0 != 0.0) {
            on.push("preload P0".into());
        }
        if model
            .gaps
            .gaps
            .iter()
            .any(|g| g.v_slide.iter().any(|&v| v != 0.0))
        {
            on.push("rotor sliding velocity".into());
        }
    } else if scene.friction.is_some() {
        ignored.push("[friction]: the model has no gaps".into());
    }
    if p.load.p_brake.iter().any(|&x| x != 0.0) {
        on.push(if p.load.step {
            "brake load (step)".into()
        } else {
            format!("brake load (ramp over {})", p.load.t_load)
        });
    }
    if let Some(d) = &scene.damping {
        if d.overall_factor() != 0.0 {
            on.push("damping G/W3".into());
        } else if d.g != 0.0 {
            ignored.push("damping.g: W3 = 0 turns it off".into());
        }
        if model.b.is_some() {
            on.push("element damping GE/W4".into());
        }
        if d.modal_ratio > 0.0 {
            on.push("modal damping".into());
        }
    }
    if p.bsql.include_friction_damping {
        on.push("friction damping C_f in the iteration matrix".into());
    }
    let spec = scene.transient.clone().unwrap_or_default();
    on.push(match spec.integrator {
        crate::scene::Integrator::Bdf => format!("integrator: BDF, MAXORD {}", spec.maxord),
        crate::scene::Integrator::GeneralizedAlpha => format!(
            "integrator: generalized-alpha, rho_inf {}, {}",
            spec.rho_inf,
            spec.galpha_h
                .map_or("adaptive step".to_string(), |h| format!("fixed step {h}"))
        ),
    });
    if scene.output.history {
        on.push(format!(
            "history database + energy.csv (every {} steps)",
            spec.noutpt
        ));
    } else {
        on.push("no history writes (output.history = false)".into());
    }
    if scene.cea.is_some() {
        ignored.push("[cea]: not run by `squeal transient` (use `squeal cea`)".into());
    }
    (on, ignored)
}

/// The start of a run without restart: the steady sliding state before the brake load
/// (TOLINT) and consistent y'(0), as (y0, y0', steady-state summary, initial-condition stats).
pub(crate) fn start_state(
    sys: &mut BsqlSystem<system::GapFriction>,
    spec: &TransientSpec,
) -> Result<(Vec<f64>, Vec<f64>, SteadySummary, IcStats), PipelineError> {
    // t = −1 < 0: the ramp is 0, so the state is the sliding equilibrium under P0 alone.
    let steady_opts = SteadyOptions {
        tol: spec.tolint,
        ..Default::default()
    };
    let ic_opts = InitialConditionOptions {
        tol: spec.tolint,
        ..Default::default()
    };
    let ss = steady_state(sys, -1.0, &steady_opts).map_err(solver_err("steady state"))?;
    let (mut y0, mut yp0) = ss.initial_values();
    let ic = consistent_initial_conditions(sys, 0.0, &mut y0, &mut yp0, None, &ic_opts)
        .map_err(solver_err("consistent initial conditions"))?;
    let steady = SteadySummary {
        iterations: ss.iterations,
        residual_norm: ss.residual_norm,
    };
    Ok((y0, yp0, steady, ic))
}

/// The run's progress bar (none when quiet).
fn progress_bar(progress: Progress) -> Option<ProgressBar> {
    (!progress.quiet).then(|| {
        let b = ProgressBar::new(1000);
        b.set_style(
            ProgressStyle::with_template("{bar:40} {msg} [{elapsed}]")
                .unwrap_or_else(|_| ProgressStyle::default_bar()),
        );
        b
    })
}

/// Moves the bar to `fraction` of the run and shows `message()` (nothing when quiet).
fn show_progress(bar: &Option<ProgressBar>, fraction: f64, message: impl FnOnce() -> String) {
    if let Some(b) = bar {
        b.set_position((1000.0 * fraction).clamp(0.0, 1000.0) as u64);
        b.set_message(message());
    }
}

/// Runs the transient; `export_dae` also writes the problem as data into that folder.
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    export_dae: Option<&Path>,
) -> Result<TransientReport, PipelineError> {
    run_cached(scene, dir, progress, export_dae, None)
}

/// [`run`] with the reduced model read from / stored in `cache` ([`model::ModelCache`]).
pub fn run_cached(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    export_dae: Option<&Path>,
    cache: Option<&model::ModelCache>,
) -> Result<TransientReport, PipelineError> {
    let wall = Instant::now();
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, _) = model::build_cached(scene, dir, progress, cache)?;
    run_on_model(scene, dir, progress, export_dae, model, wall)
}

/// The transient on a reduced model already built for `scene` (`wall`: when the run started).
/// The errors of a resumed run name the restart file.
pub fn run_on_model(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    export_dae: Option<&Path>,
    model: model::ReducedModel,
    wall: Instant,
) -> Result<TransientReport, PipelineError> {
    let restart = scene.transient.as_ref().and_then(|t| t.restart.as_ref());
    run_model(scene, dir, progress, export_dae, model, wall).map_err(|e| match restart {
        Some(p)
            if !e
                .to_string()
                .contains(&scene.resolve(p).display().to_string()) =>
        {
            PipelineError::Resumed {
                path: scene.resolve(p),
                source: Box::new(e),
            }
        }
        _ => e,
    })
}

fn run_model(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    export_dae: Option<&Path>,
    model: model::ReducedModel,
    wall: Instant,
) -> Result<TransientReport, PipelineError> {
    let spec = scene.transient.clone().unwrap_or_default();
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let problem = system::problem(scene, &model)?;
    if spec.integrator == crate::scene::Integrator::GeneralizedAlpha {
        if export_dae.is_some() || spec.restart.is_some() {
            return Err(PipelineError::Scene {
                field: "transient.integrator".into(),
                message: "generalized_alpha has no DAE export or restart; use bdf".into(),
            });
        }
        let (on, ignored) = effects(scene, &model, &problem);
        return galpha_run::run(scene, dir, progress, &model, &problem, wall, on, ignored);
    }
    let mut sys = problem.system(model.gaps.clone())?;
    let (n, ng) = (model.n(), model.gaps.len());
    let model_hash = problem.model_hash();
    let bdf_opts = BdfOptions {
        max_order: spec.maxord,
        tolerances: sys.tolerances(spec.rtol1, spec.atol1, spec.rtol2, spec.atol2),
        h0: spec.h0,
        h_max: spec.h_max,
        max_steps: spec.max_steps,
        ..BdfOptions::default()
    };
    let ic_opts = InitialConditionOptions {
        tol: spec.tolint,
        ..Default::default()
    };
    let steady_opts = SteadyOptions {
        tol: spec.tolint,
        ..Default::default()
    };
    if let Some(d) = export_dae {
        let edir = RunDir::create(d)?;
        export::export(
            &edir,
            &problem,
            &model.gaps,
            &bdf_opts,
            &ic_opts,
            &steady_opts,
            spec.tfinal,
        )?;
        progress.info(format!("exported the DAE to {}", d.display()));
    }

    // Initial state: restart file, or steady sliding before the brake load + consistent y'(0).
    let (mut bdf, steady, ic, restarted_from) = match &spec.restart {
        Some(p) => {
            let path = scene.resolve(p);
            let bdf = RestartFile::read(&path, &model_hash, n, ng)?.bdf(&path, bdf_opts.clone())?;
            (bdf, None, None, Some(path.display().to_string()))
        }
        None => {
            let (y0, yp0, steady, ic) = start_state(&mut sys, &spec)?;
            let bdf =
                Bdf::new(bdf_opts.clone(), 0.0, &y0, &yp0).map_err(solver_err("integrator"))?;
            (bdf, Some(steady), Some(ic), None)
        }
    };
    let t_start = bdf.t();
    if spec.tfinal <= t_start {
        return Err(PipelineError::Scene {
            field: "transient.tfinal".into(),
            message: format!("{} is not after the start time {t_start}", spec.tfinal),
        });
    }

    // Outputs (effects on demand: `output.history = false` opens no history or energy file).
    let mut rec = records::Recorder::open(scene, &model, dir, spec.noutpt)?;
    let mut resp = records::Response::new(scene, &model, rec.columns())?;

    let mut balance = EnergyBalance::new();
    let mut out_err: Option<String> = None;
    let mut steps_done = bdf.stats().steps as usize;
    // The initial point.
    {
        let (y, yp) = (bdf.y().to_vec(), bdf.yp().to_vec());
        let p = sys
            .observe(t_start, &y, &yp)
            .map_err(solver_err("energy"))?;
        balance.push(&p);
        rec.point(t_start, &y, &yp)?;
        resp.push(t_start, &y);
    }
    let bar = progress_bar(progress);
    let restart_path = dir.path("restart.json");
    let write_restart = |bdf: &Bdf| -> Result<(), PipelineError> {
        RestartFile {
            version: crate::VERSION.into(),
            model_hash: model_hash.clone(),
            n,
            ng,
            t: bdf.t(),
            max_order: spec.maxord,
            state: bdf.state().clone(),
        }
        .write(&restart_path)
    };
    let status = loop {
        let mut in_chunk = 0usize;
        let nrstrt = spec.nrstrt;
        let st = bdf.step_to(&mut sys, spec.tfinal, |s, t, y, yp| {
            steps_done += 1;
            in_chunk += 1;
            let p = s.observe(t, y, yp)?;
            balance.push(&p);
            resp.push(t, y);
            if let Err(e) = rec.step(steps_done, t, y, yp, &p, &balance) {
                out_err = Some(e.to_string());
                return Err(SolverError::Callback {
                    t,
                    message: e.to_string(),
                });
            }
            let restart_due = nrstrt > 0 && steps_done % nrstrt == 0;
            Ok(in_chunk < CHUNK && !restart_due)
        });
        let st = rec.end_chunk(st, &mut out_err, "integration")?;
        show_progress(&bar, (bdf.t() - t_start) / (spec.tfinal - t_start), || {
            format!(
                "t = {:.4e}, h = {:.2e}, order {}, steps {}",
                bdf.t(),
                bdf.state().h,
                bdf.state().order,
                steps_done
            )
        });
        match st {
            Status::Interrupted { .. } => {
                if spec.nrstrt > 0 && steps_done % spec.nrstrt == 0 {
                    write_restart(&bdf)?;
                }
                // The integrator counts max_steps per call; the run's cap counts every step.
                if steps_done >= spec.max_steps {
                    break Status::MaxSteps {
                        t: bdf.t(),
                        steps: steps_done,
                    };
                }
            }
            other => break other,
        }
    };
    if let Some(b) = &bar {
        b.finish();
    }
    write_restart(&bdf)?;
    if status.is_success() {
        rec.finish(spec.tfinal, bdf.y(), bdf.yp())?;
    } else {
        progress.info(format!("integration stopped: {status:?}"));
    }

    // Verdict on the response after the ramp.
    let t_after = problem.load.t_load.max(t_start);
    let (response, verdict) = resp.verdict(t_after, rec.columns());
    let (active_effects, ignored) = effects(scene, &model, &problem);
    let bs = sys.stats().clone();
    let stats = bdf.stats().clone();
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
        constraint_drift: bs.constraint_drift,
        max_constraint_drift: bs.max_constraint_drift,
        integrator: "bdf",
        bdf_stats: stats,
        galpha_stats: None,
        bsql_stats: bs,
        steady_state: steady,
        initial_conditions: ic,
        energy_residual: balance.residual(),
        energy: balance,
        t_start,
        t_end: bdf.t(),
        n_dofs: n,
        n_gaps: ng,
        history_rows: rec.rows(),
        active_effects,
        ignored,
        model_hash,
        restarted_from,
        warnings: model.warnings.clone(),
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
