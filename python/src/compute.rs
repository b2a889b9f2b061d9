//! The compute functions: each takes a scene, runs one verb's computation of the library in
//! memory with the GIL released, and returns a dict of numpy arrays and plain values.

use crate::arrays::{dofmap_to_py, gaps_to_py, mat_to_py};
use crate::progress::Hook;
use crate::scene::PyScene;
use crate::values::{to_py, value_text};
use num_complex::Complex64;
use numpy::ndarray::{Array1, Array2, Array3};
use numpy::IntoPyArray;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use squeal_meshes::CellKind;
use squeal_pipeline::scene::ModelSource;
use squeal_pipeline::stages::model::{self, cache::key::ModelKey, ModelCache, ReducedModel};
use squeal_pipeline::stages::{cea as cea_stage, modes as modes_stage, sweep, transient as tr};
use squeal_pipeline::{PipelineError, RunDir, Scene};
use std::path::{Path, PathBuf};

/// Runs `f` without the GIL on a thread of its own while this thread polls for Ctrl-C and the
/// hook's `cancel()` ([`Hook::poll`]); maps its error through the hook (KeyboardInterrupt,
/// callback exceptions, pipeline errors).
pub(crate) fn run<T: Send>(
    py: Python<'_>,
    hook: &Hook,
    f: impl FnOnce(&Hook) -> Result<T, PipelineError> + Send,
) -> PyResult<T> {
    let r = py.detach(|| {
        std::thread::scope(|s| {
            let (done, finished) = std::sync::mpsc::channel::<()>();
            let worker = s.spawn(move || {
                let r = f(hook);
                let _ = done.send(());
                r
            });
            let mut polls = 0u32;
            while let Err(std::sync::mpsc::RecvTimeoutError::Timeout) =
                finished.recv_timeout(std::time::Duration::from_millis(20))
            {
                polls += 1;
                hook.poll(polls % 5 == 0);
            }
            worker.join()
        })
    });
    let r = match r {
        Ok(r) => r,
        Err(panic) => std::panic::resume_unwind(panic),
    };
    match r {
        Ok(v) => {
            hook.finish()?;
            Ok(v)
        }
        Err(e) => Err(hook.error(&e)),
    }
}

fn warn_list(ws: &[squeal_pipeline::Warning]) -> Vec<String> {
    ws.iter().map(|w| w.to_string()).collect()
}

/// The reduced model of `scene` (through `cache` when given), with gmsh's files in `workdir`.
fn build(
    scene: &Scene,
    workdir: &Path,
    cache: Option<&PathBuf>,
    hook: &Hook,
) -> Result<(ReducedModel, Option<model::CacheUse>), PipelineError> {
    let dir = RunDir::create(workdir)?;
    let cache = cache.map(ModelCache::new);
    model::build_cached(scene, &dir, &hook.progress, cache.as_ref())
}

fn cache_use<'py>(py: Python<'py>, u: &Option<model::CacheUse>) -> PyResult<Bound<'py, PyAny>> {
    Ok(match u {
        Some(u) => {
            let d = PyDict::new(py);
            d.set_item("hit", u.hit)?;
            d.set_item("key", &u.key)?;
            d.set_item("note", u.note.clone())?;
            d.into_any()
        }
        None => py.None().into_bound(py),
    })
}

/// Modal analysis of one component (`modes.json`'s report, nodal shapes, the mesh).
#[pyfunction]
#[pyo3(signature = (scene, workdir, component=None, progress=None))]
pub fn modes<'py>(
    py: Python<'py>,
    scene: &PyScene,
    workdir: PathBuf,
    component: Option<String>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let s = &scene.inner;
    let m = run(py, &hook, |h| {
        let dir = RunDir::create(&workdir)?;
        modes_stage::compute(s, component.as_deref(), &dir, &h.progress)
    })?;
    let (nn, nm) = (m.mesh.nodes.len(), m.shapes.len());
    let d = PyDict::new(py);
    d.set_item(
        "frequencies_hz",
        Array1::from(m.report.frequencies_hz.clone()).into_pyarray(py),
    )?;
    d.set_item(
        "shapes",
        Array3::from_shape_fn((nn, 3, nm), |(i, c, j)| m.shapes[j][i][c]).into_pyarray(py),
    )?;
    d.set_item(
        "nodes",
        Array2::from_shape_fn((nn, 3), |(i, c)| m.mesh.nodes[i][c]).into_pyarray(py),
    )?;
    d.set_item(
        "node_tags",
        Array1::from(m.mesh.node_tags.clone()).into_pyarray(py),
    )?;
    let cells = PyList::empty(py);
    for b in &m.mesh.volumes {
        let k = b.kind.n_nodes();
        let name = match b.kind {
            CellKind::Hex8 => "hexahedron",
            CellKind::Hex20 => "hexahedron20",
            CellKind::Quad4 => "quad",
            CellKind::Quad8 => "quad8",
            CellKind::Tet4 => "tetra",
            CellKind::Tet10 => "tetra10",
            CellKind::Wedge6 => "wedge",
            CellKind::Wedge15 => "wedge15",
            CellKind::Pyramid5 => "pyramid",
            CellKind::Pyramid13 => "pyramid13",
            CellKind::Tri3 => "triangle",
            CellKind::Tri6 => "triangle6",
        };
        let conn = Array2::from_shape_fn((b.len(), k), |(i, j)| b.conn[i * k + j] as i64);
        cells.append((name, conn.into_pyarray(py)))?;
    }
    d.set_item("cells", cells)?;
    d.set_item("report", to_py(py, &m.report)?)?;
    Ok(d)
}

/// The reduced model: K, M, B, the unit brake load, the DOF map and gaps as records.
#[pyfunction]
#[pyo3(signature = (scene, workdir, cache=None, progress=None))]
pub fn reduce<'py>(
    py: Python<'py>,
    scene: &PyScene,
    workdir: PathBuf,
    cache: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let s = &scene.inner;
    let (m, u) = run(py, &hook, |h| build(s, &workdir, cache.as_ref(), h))?;
    // The gaps at the scene's operating point (sliding speeds, P0, temperatures, the law).
    let gaps = squeal_pipeline::problem::OperatingPoint::of(s)
        .gaps(&m)
        .map_err(|e| crate::errors::to_py(&e))?;
    let d = PyDict::new(py);
    d.set_item("K", mat_to_py(py, &m.k))?;
    d.set_item("M", mat_to_py(py, &m.m))?;
    d.set_item("B", m.b.as_ref().map(|b| mat_to_py(py, b)))?;
    d.set_item("p_brake", Array1::from(m.p_brake.clone()).into_pyarray(py))?;
    d.set_item("dofs", dofmap_to_py(py, &m.dofs)?)?;
    d.set_item("gaps", gaps_to_py(py, &gaps.gaps)?)?;
    d.set_item("gap_pairs", m.gap_pairs.clone())?;
    d.set_item("friction_law", to_py(py, &gaps.law)?)?;
    d.set_item("components", to_py(py, &m.components)?)?;
    d.set_item("warnings", warn_list(&m.warnings))?;
    d.set_item("cache", cache_use(py, &u)?)?;
    Ok(d)
}

/// The nonlinear transient: the sampled history (every NOUTPT-th step), its columns, the
/// energy rows, the summary (`summary.json`'s body) and the verdict.
#[pyfunction]
#[pyo3(signature = (scene, workdir, cache=None, progress=None))]
pub fn transient<'py>(
    py: Python<'py>,
    scene: &PyScene,
    workdir: PathBuf,
    cache: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let s = &scene.inner;
    let (r, u) = run(py, &hook, |h| {
        let (m, u) = build(s, &workdir, cache.as_ref(), h)?;
        let opts = tr::TransientOptions {
            keep_history: true,
            ..Default::default()
        };
        tr::compute(s, &m, &h.progress, &opts).map(|r| (r, u))
    })?;
    let d = PyDict::new(py);
    let h = r.history.as_ref();
    let cols = h.map_or(0, |h| h.columns.len());
    let rows = h.map_or(0, |h| h.rows());
    let values = h.map_or(Vec::new(), |h| h.values.clone());
    let hist = Array2::from_shape_vec((rows, cols), values)
        .map_err(|e| pyo3::exceptions::PyRuntimeError::new_err(e.to_string()))?;
    let time: Vec<f64> = (0..rows).map(|i| hist[[i, 0]]).collect();
    d.set_item("time", Array1::from(time).into_pyarray(py))?;
    d.set_item(
        "columns",
        h.map_or(Vec::new(), |h| {
            h.columns.iter().map(|c| c.name.clone()).collect()
        }),
    )?;
    d.set_item(
        "column_info",
        to_py(py, &h.map_or(Vec::new(), |h| h.columns.clone()))?,
    )?;
    d.set_item("history", hist.into_pyarray(py))?;
    let energy = h.map_or(Vec::new(), |h| h.energy.clone());
    d.set_item(
        "energy",
        Array2::from_shape_fn((energy.len(), 8), |(i, j)| energy[i][j]).into_pyarray(py),
    )?;
    d.set_item(
        "energy_columns",
        tr::ENERGY_HEADER
            .split(',')
            .map(|s| s.trim().to_string())
            .collect::<Vec<_>>(),
    )?;
    d.set_item("summary", to_py(py, &r)?)?;
    d.set_item("verdict", to_py(py, &r.verdict)?)?;
    d.set_item("success", r.status.is_success())?;
    d.set_item("warnings", warn_list(&r.warnings))?;
    d.set_item("cache", cache_use(py, &u)?)?;
    Ok(d)
}

/// Complex eigenvalues about the steady sliding state (`mu`: a friction sweep FIRST, LAST,
/// COUNT as `squeal cea --mu`).
#[pyfunction]
#[pyo3(signature = (scene, workdir, mu=None, cache=None, progress=None))]
pub fn cea<'py>(
    py: Python<'py>,
    scene: &PyScene,
    workdir: PathBuf,
    mu: Option<(f64, f64, usize)>,
    cache: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let s = &scene.inner;
    let (c, m, u) = run(py, &hook, |h| {
        let (m, u) = build(s, &workdir, cache.as_ref(), h)?;
        let args = cea_stage::CeaArgs {
            mu,
            ..Default::default()
        };
        cea_stage::compute(s, &m, &h.progress, &args).map(|c| (c, m, u))
    })?;
    let nm = c.modes.len();
    let n = m.n();
    let d = PyDict::new(py);
    d.set_item(
        "eigenvalues",
        Array1::from_iter(
            c.modes
                .iter()
                .map(|x| Complex64::new(x.eigenvalue.re, x.eigenvalue.im)),
        )
        .into_pyarray(py),
    )?;
    d.set_item(
        "frequencies_hz",
        Array1::from_iter(c.modes.iter().map(|x| x.frequency_hz)).into_pyarray(py),
    )?;
    d.set_item(
        "damping_ratios",
        Array1::from_iter(c.modes.iter().map(|x| x.damping_ratio.unwrap_or(f64::NAN)))
            .into_pyarray(py),
    )?;
    d.set_item(
        "unstable",
        Array1::from_iter(c.modes.iter().map(|x| x.unstable)).into_pyarray(py),
    )?;
    d.set_item(
        "shapes",
        Array2::from_shape_fn((n, nm), |(i, j)| {
            c.modes[j]
                .shape
                .get(i)
                .map_or(Complex64::new(f64::NAN, f64::NAN), |z| {
                    Complex64::new(z.re, z.im)
                })
        })
        .into_pyarray(py),
    )?;
    d.set_item("dofs", dofmap_to_py(py, &m.dofs)?)?;
    d.set_item("report", to_py(py, &c.out)?)?;
    d.set_item(
        "sweep",
        match &c.sweep {
            Some(sw) => to_py(py, sw)?,
            None => py.None().into_bound(py),
        },
    )?;
    d.set_item("warnings", warn_list(&m.warnings))?;
    d.set_item("cache", cache_use(py, &u)?)?;
    Ok(d)
}

/// One value of a design sweep: the scene with `assignments` ((key, value) pairs) set, the
/// model through the cache in `cache_dir`, the analyses with their files in `run_dir`; returns
/// the point (a `sweep.json` entry) as a dict. A failure is recorded in the point.
/// `cancel`: a callable polled every 100 ms; true stops the value (`Cancelled` is raised).
#[pyfunction]
#[pyo3(signature = (scene, assignments, label, index, analysis, cache_dir, run_dir, progress=None, cancel=None))]
pub fn sweep_value<'py>(
    py: Python<'py>,
    scene: &PyScene,
    assignments: Vec<(String, Bound<'py, PyAny>)>,
    label: String,
    index: usize,
    analysis: &str,
    cache_dir: PathBuf,
    run_dir: PathBuf,
    progress: Option<Py<PyAny>>,
    cancel: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let analysis = sweep::Analysis::parse(analysis).map_err(|e| crate::errors::to_py(&e))?;
    let mut texts = Vec::new();
    for (k, v) in &assignments {
        texts.push((k.clone(), value_text(v, k)?));
    }
    let hook = Hook::with_cancel(
        crate::args::callable("squeal.sweep_value", "progress", progress, py)?,
        crate::args::callable("squeal.sweep_value", "cancel", cancel, py)?,
    );
    let base = &scene.inner;
    let p = run(py, &hook, |h| {
        let mut s = sweep::values::scene_for_all(base, &texts)?;
        if analysis != sweep::Analysis::Transient && s.cea.is_none() {
            s.cea = Some(Default::default());
        }
        h.progress.check("sweep value")?;
        let vdir = RunDir::create(&run_dir)?;
        let cache = ModelCache::new(&cache_dir);
        let mut p = sweep::run_value(index, &label, &s, &vdir, &cache, analysis, &h.progress)?;
        if texts.len() > 1 {
            p.value = serde_json::Value::Array(
                texts
                    .iter()
                    .map(|(_, v)| sweep::values::value_json(v))
                    .collect(),
            );
        }
        Ok(p)
    })?;
    let d = to_py(py, &p)?;
    // SweepPoint::failed: an error, or a transient stopped before TFINAL.
    d.set_item("failed", p.failed())?;
    Ok(d)
}

/// The reduced-model cache key of a meshed scene (32 hex digits), None for stored models.
#[pyfunction]
pub fn model_key(scene: &PyScene) -> PyResult<Option<String>> {
    if scene.inner.model.from != ModelSource::Mesh {
        return Ok(None);
    }
    ModelKey::of(&scene.inner)
        .map(|k| Some(k.hex))
        .map_err(|e| crate::errors::to_py(&e))
}

/// Compares two reduced models (scenes, stored matrices, reduce folders) or two run folders
/// (`squeal compare A B`): `compare.json`'s report as a dict, also written (with
/// `compare.md`) into `workdir`.
#[pyfunction]
#[pyo3(signature = (a, b, workdir, tol_freq=None, tol_mac=None, tol_matrix=None, tol_root=None,
    tol_summary=None, modes=None, pair_mac=None, scene=None, cea=true, cache=None, progress=None))]
pub fn compare<'py>(
    py: Python<'py>,
    a: PathBuf,
    b: PathBuf,
    workdir: PathBuf,
    tol_freq: Option<f64>,
    tol_mac: Option<f64>,
    tol_matrix: Option<f64>,
    tol_root: Option<f64>,
    tol_summary: Option<f64>,
    modes: Option<usize>,
    pair_mac: Option<f64>,
    scene: Option<PathBuf>,
    cea: bool,
    cache: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    use squeal_pipeline::stages::compare as cmp;
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let opts = cmp::CompareOptions {
        tol_freq,
        tol_mac,
        tol_matrix,
        tol_root,
        tol_summary,
        modes,
        pair_mac,
        scene,
        cea,
        cache: cache.map(ModelCache::new),
    };
    let report = run(py, &hook, |h| {
        let dir = RunDir::create(&workdir)?;
        let r = cmp::compute(&a, &b, &opts, &dir, &h.progress)?;
        cmp::write(&r, &dir)?;
        Ok(r)
    })?;
    to_py(py, &report)
}

/// The limit cycles of the band-limited model (`squeal limit-cycle`): `report` is
/// `limit_cycle.json`'s body (band model, per unstable mode the cycle).
#[pyfunction]
#[pyo3(signature = (scene, workdir, cache=None, progress=None))]
pub fn limit_cycle<'py>(
    py: Python<'py>,
    scene: &PyScene,
    workdir: PathBuf,
    cache: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let hook = Hook::new(crate::args::callable("squeal", "progress", progress, py)?);
    let s = &scene.inner;
    let (c, m) = run(py, &hook, |h| {
        let (m, _) = build(s, &workdir, cache.as_ref(), h)?;
        squeal_pipeline::stages::limit_cycle::compute(s, &m, &h.progress).map(|c| (c, m))
    })?;
    let d = PyDict::new(py);
    d.set_item(
        "frequencies_hz",
        Array1::from_iter(c.modes.iter().map(|x| x.frequency_hz)).into_pyarray(py),
    )?;
    d.set_item(
        "peak_normal_velocity",
        Array1::from_iter(c.modes.iter().map(|x| x.peak_normal_velocity)).into_pyarray(py),
    )?;
    d.set_item(
        "rms_normal_velocity",
        Array1::from_iter(c.modes.iter().map(|x| x.rms_normal_velocity)).into_pyarray(py),
    )?;
    d.set_item(
        "reached",
        Array1::from_iter(c.modes.iter().map(|x| x.reached)).into_pyarray(py),
    )?;
    d.set_item("report", to_py(py, &c)?)?;
    d.set_item("warnings", warn_list(&m.warnings))?;
    Ok(d)
}
