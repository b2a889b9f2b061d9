//! `squeal._squeal`: the extension module of the Python package `squeal`.
//!
//! A thin layer over the `squeal-pipeline` library: scenes ([`scene::PyScene`]), the compute
//! functions of each verb (modes, reduce, transient, cea, one sweep value) returning dicts of
//! numpy arrays and JSON-like values, the pipeline's errors as Python exceptions
//! ([`errors`]), and progress/cancellation through a Python callback ([`progress`]). Every
//! computation runs with the GIL released. The typed Python API (`squeal/__init__.py`) wraps
//! these functions.

mod args;
mod arrays;
mod compute;
mod errors;
mod progress;
mod propensity;
mod scene;
mod values;

use pyo3::prelude::*;

#[pymodule]
fn _squeal(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", squeal_pipeline::VERSION)?;
    m.add_class::<scene::PyScene>()?;
    errors::register(m)?;
    m.add_function(wrap_pyfunction!(compute::modes, m)?)?;
    m.add_function(wrap_pyfunction!(compute::reduce, m)?)?;
    m.add_function(wrap_pyfunction!(compute::transient, m)?)?;
    m.add_function(wrap_pyfunction!(compute::cea, m)?)?;
    m.add_function(wrap_pyfunction!(compute::limit_cycle, m)?)?;
    m.add_function(wrap_pyfunction!(compute::sweep_value, m)?)?;
    m.add_function(wrap_pyfunction!(compute::model_key, m)?)?;
    m.add_function(wrap_pyfunction!(compute::compare, m)?)?;
    m.add_function(wrap_pyfunction!(propensity::propensity_plan, m)?)?;
    m.add_function(wrap_pyfunction!(propensity::propensity_evaluate, m)?)?;
    m.add_function(wrap_pyfunction!(propensity::propensity_finish, m)?)?;
    m.add_function(wrap_pyfunction!(propensity::propensity_check_basis, m)?)?;
    m.add_function(wrap_pyfunction!(scene::scene_from_state, m)?)?;
    Ok(())
}
