//! The propensity study (`squeal propensity`) in three steps the Python package distributes:
//! the plan (inputs checked, design), the evaluation of chunks of design rows (threads or Dask
//! workers; the reduced model through a shared model cache), the estimates and files.

use crate::compute::run;
use crate::progress::Hook;
use crate::scene::PyScene;
use pyo3::prelude::*;
use squeal_pipeline::stages::model::ModelCache;
use squeal_pipeline::stages::propensity::{self as prop, Evaluator, Plan, PropensityArgs, Sample};
use squeal_pipeline::{PipelineError, RunDir};
use std::path::PathBuf;

fn json_err(what: &str, e: serde_json::Error) -> PipelineError {
    PipelineError::Option {
        option: what.into(),
        message: format!("not a propensity {what} (JSON): {e}"),
    }
}

fn to_json<T: serde::Serialize>(v: &T) -> Result<String, PipelineError> {
    serde_json::to_string(v).map_err(|e| json_err("result", e))
}

/// The plan of a study as JSON: `dists` ((key, distribution text) pairs), `corr` ((key a,
/// key b, ρ) triples), the evaluation budget, replicates (None: automatic), seed, rereduce.
#[pyfunction]
#[pyo3(signature = (scene, dists, corr, samples, replicates=None, seed=1, rereduce=false))]
pub fn propensity_plan(
    scene: &PyScene,
    dists: Vec<(String, String)>,
    corr: Vec<(String, String, f64)>,
    samples: usize,
    replicates: Option<usize>,
    seed: u32,
    rereduce: bool,
) -> PyResult<String> {
    let args = PropensityArgs {
        dists,
        corr,
        samples,
        replicates,
        seed,
        rereduce,
        ..Default::default()
    };
    prop::plan(&scene.inner, &args)
        .and_then(|p| to_json(&p))
        .map_err(|e| crate::errors::to_py(&e))
}

/// Evaluates the design rows `rows` of `plan` (JSON) on this process's threads: the model
/// through the cache in `cache_dir` (built by the first task, read by the others), scratch
/// files in `workdir`. Returns the samples as JSON; a failed row is recorded in its sample.
#[pyfunction]
#[pyo3(signature = (scene, plan, rows, workdir, cache_dir=None, progress=None, cancel=None))]
#[allow(clippy::too_many_arguments)]
pub fn propensity_evaluate(
    py: Python<'_>,
    scene: &PyScene,
    plan: &str,
    rows: Vec<usize>,
    workdir: PathBuf,
    cache_dir: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    cancel: Option<Py<PyAny>>,
) -> PyResult<String> {
    let plan: Plan =
        serde_json::from_str(plan).map_err(|e| crate::errors::to_py(&json_err("plan", e)))?;
    let hook = Hook::with_cancel(
        crate::args::callable("squeal.propensity", "progress", progress, py)?,
        crate::args::callable("squeal.propensity", "cancel", cancel, py)?,
    );
    let base = &scene.inner;
    run(py, &hook, |h| {
        if let Some(&r) = rows.iter().find(|&&r| r >= plan.design.rows.len()) {
            return Err(PipelineError::Option {
                option: "rows".into(),
                message: format!(
                    "row {r} is not in the design ({} rows)",
                    plan.design.rows.len()
                ),
            });
        }
        let dir = RunDir::create(&workdir)?;
        let cache = cache_dir.as_ref().map(ModelCache::new);
        let t0 = std::time::Instant::now();
        let ev = Evaluator::new(base, &plan, &dir, &h.progress.silenced(), cache.as_ref())?;
        let build_s = t0.elapsed().as_secs_f64();
        let t1 = std::time::Instant::now();
        let samples = prop::evaluate_rows(&ev, &plan, &rows, &h.progress)?;
        let v = serde_json::json!({
            "samples": samples,
            "build_s": build_s,
            "n_dofs": ev.info().n_dofs,
            "n_gaps": ev.info().n_gaps,
            "evaluate_s": t1.elapsed().as_secs_f64(),
        });
        Ok(v.to_string())
    })
}

/// The estimates of `plan` from every row's sample (JSON list, any order), written into
/// `out` (`propensity.json`, `samples.csv`, `summary.json`); returns `propensity.json`'s text.
#[pyfunction]
#[pyo3(signature = (scene, plan, samples, out, n_dofs=0, n_gaps=0, build_s=0.0, evaluate_s=0.0,
    wall_s=0.0, threads=1))]
#[allow(clippy::too_many_arguments)]
pub fn propensity_finish(
    scene: &PyScene,
    plan: &str,
    samples: &str,
    out: PathBuf,
    n_dofs: usize,
    n_gaps: usize,
    build_s: f64,
    evaluate_s: f64,
    wall_s: f64,
    threads: usize,
) -> PyResult<String> {
    let f = || -> Result<String, PipelineError> {
        let plan: Plan = serde_json::from_str(plan).map_err(|e| json_err("plan", e))?;
        let samples: Vec<Sample> =
            serde_json::from_str(samples).map_err(|e| json_err("samples", e))?;
        let dir = RunDir::create(&out)?;
        let info = prop::evaluate::info_of(&scene.inner, &plan, n_dofs, n_gaps);
        let mut o = prop::report::estimate(&scene.inner, &plan, &samples, &info)?;
        o.stats.build_s = build_s;
        o.stats.evaluate_s = evaluate_s;
        o.stats.wall_s = wall_s;
        o.stats.threads = threads;
        dir.write_bytes(
            "scene.resolved.toml",
            scene.inner.resolved_toml().as_bytes(),
        )?;
        prop::write(&dir, &plan, &samples, &mut o)?;
        to_json(&o)
    };
    f().map_err(|e| crate::errors::to_py(&e))
}
