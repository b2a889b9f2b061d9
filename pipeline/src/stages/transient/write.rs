//! `squeal transient`'s files: the run with its file sinks — `history.npy` +
//! `history_map.json` and `energy.csv` ([`Recorder`]), `restart.json` every NRSTRT steps and
//! at the end (BDF, [`RestartSink`]) with `response.npy` ([`ResponseFile`]) — then
//! `summary.json` ([`TransientReport`]); with `--export-dae`, the problem as data.

use super::collect::response::response_dofs;
use super::export;
use super::files::history::Recorder;
use super::files::response::ResponseFile;
use super::prepare::prepare;
use super::restart::RestartSink;
use super::result::{TransientOptions, TransientReport};
use crate::error::PipelineError;
use crate::model;
use crate::output::RunDir;
use crate::problem::options::{bdf_options, start_options};
use crate::progress::Progress;
use crate::scene::{Integrator, Scene};
use std::path::Path;
use std::time::Instant;

/// Runs the transient (model built or read through `cache`) and writes its outputs into `dir`;
/// `export_dae` also writes the problem as data into that folder.
pub fn run_cached(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
    cache: Option<&model::ModelCache>,
) -> Result<TransientReport, PipelineError> {
    let wall = Instant::now();
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, _) = model::build_cached(scene, dir, progress, cache)?;
    run_on_model(
        scene,
        dir,
        progress,
        export_dae,
        &model,
        wall,
        &Default::default(),
    )
}

/// [`run_cached`] without a cache.
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
) -> Result<TransientReport, PipelineError> {
    run_cached(scene, dir, progress, export_dae, None)
}

/// The transient on a reduced model already built for `scene`, with its files in `dir`
/// (`wall`: when the run started). The errors of a resumed run name the restart file.
pub fn run_on_model(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
    model: &model::ReducedModel,
    wall: Instant,
    opts: &TransientOptions,
) -> Result<TransientReport, PipelineError> {
    let restart = scene.transient.as_ref().and_then(|t| t.restart.as_ref());
    run_model(scene, dir, progress, export_dae, model, wall, opts).map_err(|e| match restart {
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
    progress: &Progress,
    export_dae: Option<&Path>,
    model: &model::ReducedModel,
    wall: Instant,
    opts: &TransientOptions,
) -> Result<TransientReport, PipelineError> {
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let prepared = prepare(scene, model)?;
    let spec = &prepared.spec;
    if let Some(d) = export_dae {
        if spec.integrator == Integrator::GeneralizedAlpha {
            return Err(PipelineError::Scene {
                field: "transient.integrator".into(),
                message: "generalized_alpha has no DAE export; use bdf".into(),
            });
        }
        let sys = prepared.problem.system(prepared.problem.gaps.clone())?;
        let bdf_opts = bdf_options(spec, &sys, spec.rtol1, spec.maxord);
        let edir = RunDir::create(d)?;
        let (steady, ic) = start_options(spec.tolint);
        let p = &prepared.problem;
        export::export(&edir, p, &bdf_opts, &ic, &steady, spec.tfinal)?;
        progress.info(format!("exported the DAE to {}", d.display()));
    }
    let resume = prepared.resume.as_ref();
    let prior = resume.and_then(|r| r.history());
    let mut files = Recorder::open_resumed(
        scene,
        model,
        &prepared.problem.gaps,
        Some(dir),
        false,
        prior,
    )?;
    let mut restart = RestartSink {
        path: dir.path("restart.json"),
        model_hash: prepared.model_hash.clone(),
        n: model.n(),
        ng: model.gap_geometry.len(),
        max_order: spec.maxord,
        every: spec.nrstrt,
    };
    let mut result = match spec.integrator {
        // The response beside the restart file, for a resumed run's verdict.
        Integrator::Bdf => {
            let dofs = response_dofs(scene, model, files.columns())?;
            let prior = resume.and_then(|r| r.response_file());
            let mut response = ResponseFile::open(dir, &dofs, prior)?;
            prepared.run(
                progress,
                opts,
                &mut [&mut files, &mut response, &mut restart],
            )?
        }
        Integrator::GeneralizedAlpha => {
            prepared.run(progress, opts, &mut [&mut files, &mut restart])?
        }
    };
    result.history_rows = files.rows();
    let report = TransientReport {
        verb: "transient",
        version: crate::VERSION,
        wall_s: wall.elapsed().as_secs_f64(),
        result,
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
