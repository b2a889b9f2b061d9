//! Argument errors that name the argument: a wrong type is a `TypeError` saying which function
//! and argument, what it must be and what it got (pyo3's own conversion errors name neither).
//! The typed Python API (`squeal/_args.py`) checks the public functions' arguments the same
//! way before calling in.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use std::path::PathBuf;

/// `type repr` of a value, the repr cut to 60 characters.
pub fn describe(v: &Bound<'_, PyAny>) -> String {
    let ty = v
        .get_type()
        .name()
        .map(|n| n.to_string())
        .unwrap_or_else(|_| "?".into());
    let mut repr = v.repr().map(|r| r.to_string()).unwrap_or_default();
    if repr.chars().count() > 60 {
        repr = repr.chars().take(57).collect::<String>() + "...";
    }
    format!("{ty} {repr}")
}

/// `TypeError: {func}: argument `{arg}` must be {expected}, not {type} {repr}`.
pub fn type_error(func: &str, arg: &str, expected: &str, got: &Bound<'_, PyAny>) -> PyErr {
    PyTypeError::new_err(format!(
        "{func}: argument `{arg}` must be {expected}, not {}",
        describe(got)
    ))
}

/// A str argument.
pub fn string(func: &str, arg: &str, v: &Bound<'_, PyAny>, expected: &str) -> PyResult<String> {
    v.extract::<String>()
        .map_err(|_| type_error(func, arg, expected, v))
}

/// A path argument (str or os.PathLike).
pub fn path(func: &str, arg: &str, v: &Bound<'_, PyAny>) -> PyResult<PathBuf> {
    v.extract::<PathBuf>()
        .map_err(|_| type_error(func, arg, "a path (str or os.PathLike)", v))
}

/// A dict argument whose keys are str; `what` says what the keys are.
pub fn str_dict<'py>(
    func: &str,
    arg: &str,
    v: &Bound<'py, PyAny>,
    what: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let d = v
        .cast::<PyDict>()
        .map_err(|_| type_error(func, arg, &format!("a dict {{{what}: value}}"), v))?;
    for k in d.keys() {
        if k.extract::<String>().is_err() {
            return Err(PyTypeError::new_err(format!(
                "{func}: argument `{arg}`: key {} is not a str ({what})",
                describe(&k)
            )));
        }
    }
    Ok(d.clone())
}

/// A callable or None.
pub fn callable(
    func: &str,
    arg: &str,
    v: Option<Py<PyAny>>,
    py: Python<'_>,
) -> PyResult<Option<Py<PyAny>>> {
    match v {
        Some(c) if !c.bind(py).is_callable() => Err(type_error(
            func,
            arg,
            "a callable receiving one event dict, or None",
            c.bind(py),
        )),
        v => Ok(v),
    }
}
