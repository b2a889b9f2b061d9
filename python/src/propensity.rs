//! The propensity study (`squeal propensity`) in three steps the Python package distributes:
//! the plan (inputs checked, design), the evaluation of chunks of design rows (threads or Dask
//! workers; the reduced model through a shared model cache), the estimates and files.

use crate::compute::run;
use crate::progress::Hook;
use crate::scene::PyScene;
use crate::values::{from_py, to_py};
use pyo3::prelude::*;
use serde::Serialize;
use squeal_pipeline::stages::model::ModelCache;
use squeal_pipeline::stages::propensity::{self as prop, Evaluator, Plan, PropensityArgs, Sample};
use squeal_pipeline::{PipelineError, RunDir};
use std::path::PathBuf;

/// `obj` (a dict or list as [`propensity_plan`] / [`propensity_evaluate`] return them) as the
/// study's `what` (`plan`, `samples`); a `SceneError` naming `what` otherwise.
fn typed<T: serde::de::DeserializeOwned>(obj: &Bound<'_, PyAny>, what: &str) -> PyResult<T> {
    from_py(obj).map_err(|e| {
        crate::errors::to_py(&PipelineError::Option {
            option: what.into(),
            message: format!("not a propensity {what}: {e}"),
        })
    })
}

/// What [`propensity_evaluate`] returns for its rows.
#[derive(Serialize)]
struct Evaluated {
    samples: Vec<Sample>,
    build_s: f64,
    n_dofs: usize,
    n_gaps: usize,
    evaluate_s: f64,
}

/// The plan of a study (a dict: inputs, correlation, design): `dists` ((key, distribution text) pairs), `corr` ((key a,
/// key b, ρ) triples), the evaluation budget, replicates (None: automatic), seed, rereduce.
#[pyfunction]
#[pyo3(signature = (scene, dists, corr, samples, replicates=None, seed=1, rereduce=false))]
pub fn propensity_plan<'py>(
    py: Python<'py>,
    scene: &PyScene,
    dists: Vec<(String, String)>,
    corr: Vec<(String, String, f64)>,
    samples: usize,
    replicates: Option<usize>,
    seed: u32,
    rereduce: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let args = PropensityArgs {
        dists,
        corr,
        samples,
        replicates,
        seed,
        rereduce,
        ..Default::default()
    };
    let plan = prop::plan(&scene.inner, &args).map_err(|e| crate::errors::to_py(&e))?;
    to_py(py, &plan)
}

/// Evaluates the design rows `rows` of `plan` (as [`propensity_plan`] returns it) on this
/// process's threads: the model through the cache in `cache_dir` (built by the first task,
/// read by the others), scratch files in `workdir`. Returns a dict: `samples` (one dict per
/// row; a failed row is recorded in its sample), `build_s`, `n_dofs`, `n_gaps`, `evaluate_s`.
#[pyfunction]
#[pyo3(signature = (scene, plan, rows, workdir, cache_dir=None, progress=None, cancel=None))]
#[allow(clippy::too_many_arguments)]
pub fn propensity_evaluate<'py>(
    py: Python<'py>,
    scene: &PyScene,
    plan: &Bound<'py, PyAny>,
    rows: Vec<usize>,
    workdir: PathBuf,
    cache_dir: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    cancel: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let plan: Plan = typed(plan, "plan")?;
    let hook = Hook::with_cancel(
        crate::args::callable("squeal.propensity", "progress", progress, py)?,
        crate::args::callable("squeal.propensity", "cancel", cancel, py)?,
    );
    let base = &scene.inner;
    let out = run(py, &hook, |h| {
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
        Ok(Evaluated {
            samples,
            build_s,
            n_dofs: ev.info().n_dofs,
            n_gaps: ev.info().n_gaps,
            evaluate_s: t1.elapsed().as_secs_f64(),
        })
    })?;
    to_py(py, &out)
}

/// The checks of the bases the rows hold fixed (`Evaluator::check_basis`, run once before
/// the rows are distributed: a volume's material against re-reduction, an input that changes
/// K or M against the CEA's own projection basis): a list of the checks' dicts for
/// [`propensity_finish`]; a change above `tolerance` × |Re λ| (at least 1 /s) raises the
/// error naming the key. An empty list when nothing needs a check (or with `rereduce`).
#[pyfunction]
#[pyo3(signature = (scene, plan, workdir, tolerance=0.05, cache_dir=None))]
pub fn propensity_check_basis<'py>(
    py: Python<'py>,
    scene: &PyScene,
    plan: &Bound<'py, PyAny>,
    workdir: PathBuf,
    tolerance: f64,
    cache_dir: Option<PathBuf>,
) -> PyResult<Bound<'py, PyAny>> {
    let plan: Plan = typed(plan, "plan")?;
    let hook = Hook::new(None);
    let base = &scene.inner;
    let checks = run(py, &hook, |h| {
        if plan.rereduce {
            return Ok(Vec::new());
        }
        let dir = RunDir::create(&workdir)?;
        let cache = cache_dir.as_ref().map(ModelCache::new);
        let quiet = h.progress.silenced();
        let mut ev = Evaluator::new(base, &plan, &dir, &quiet, cache.as_ref())?;
        ev.check_basis(&plan, &dir, (tolerance, prop::BASIS_FLOOR), &quiet)?;
        Ok(ev.info().basis_checks)
    })?;
    to_py(py, &checks)
}

/// The estimates of `plan` from every row's sample (a list of the sample dicts
/// [`propensity_evaluate`] returns, any order), written into `out` (`propensity.json`,
/// `samples.csv`, `summary.json`); returns `propensity.json`'s content as a dict.
#[pyfunction]
#[pyo3(signature = (scene, plan, samples, out, n_dofs=0, n_gaps=0, build_s=0.0, evaluate_s=0.0,
    wall_s=0.0, threads=1, basis_checks=None))]
#[allow(clippy::too_many_arguments)]
pub fn propensity_finish<'py>(
    py: Python<'py>,
    scene: &PyScene,
    plan: &Bound<'py, PyAny>,
    samples: &Bound<'py, PyAny>,
    out: PathBuf,
    n_dofs: usize,
    n_gaps: usize,
    build_s: f64,
    evaluate_s: f64,
    wall_s: f64,
    threads: usize,
    basis_checks: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let plan: Plan = typed(plan, "plan")?;
    let samples: Vec<Sample> = typed(samples, "samples")?;
    let checks: Vec<prop::evaluate::BasisCheck> = match basis_checks {
        Some(c) => typed(c, "basis_checks")?,
        None => Vec::new(),
    };
    let f = || -> Result<prop::report::PropensityOut, PipelineError> {
        let dir = RunDir::create(&out)?;
        let mut info = prop::evaluate::info_of(&scene.inner, &plan, n_dofs, n_gaps);
        info.basis_checks = checks;
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
        Ok(o)
    };
    let o = f().map_err(|e| crate::errors::to_py(&e))?;
    to_py(py, &o)
}
