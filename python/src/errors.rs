//! The pipeline's errors as Python exceptions, with the message the command line prints after
//! `squeal: error: `.
//!
//! | exception | pipeline errors |
//! |---|---|
//! | `SceneError` | scene parse, scene field, `--set`/`set` override, option |
//! | `InputError` | a file (I/O) or an input file's / array's content |
//! | `MeshError` | the mesh stage (gmsh, `.msh` reader) |
//! | `ModelError` | FE, reduction, contact, model assembly |
//! | `SolverError` | the transient integrator, the complex eigenvalue analysis |
//! | `OutputError` | writing an output |
//! | `Cancelled` | the progress callback raised, or asked to stop |
//!
//! All derive from `SquealError`. A run interrupted by Ctrl-C raises `KeyboardInterrupt`.
//!
//! Attributes: `SceneError.field` (the scene key or option the error names: `friction.mu_s`,
//! `compare.rtol`, the key of a `--set` assignment; None for a file that does not parse) and
//! `SceneError.path` (the scene file, when one does not parse); `InputError.path` (the file,
//! None for an in-memory array). A missing file raises `InputFileNotFound`, a subclass of both
//! `InputError` and the built-in `FileNotFoundError` (`errno` 2, `filename` the path).

use pyo3::create_exception;
use pyo3::exceptions::{PyException, PyFileNotFoundError};
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::{PyDict, PyTuple, PyType};
use squeal_pipeline::PipelineError;
use std::path::Path;

create_exception!(
    squeal,
    SquealError,
    PyException,
    "Base class of squeal's errors."
);
create_exception!(
    squeal,
    SceneError,
    SquealError,
    "A scene (file, text, dict, key or value) is invalid."
);
create_exception!(
    squeal,
    InputError,
    SquealError,
    "An input file or array is missing or invalid (the message names it)."
);
create_exception!(
    squeal,
    MeshError,
    SquealError,
    "The mesh stage failed (gmsh, .msh reader)."
);
create_exception!(
    squeal,
    ModelError,
    SquealError,
    "Building the reduced model failed (FE, reduction, contact)."
);
create_exception!(
    squeal,
    SolverError,
    SquealError,
    "The transient integrator or the complex eigenvalue analysis failed."
);
create_exception!(
    squeal,
    OutputError,
    SquealError,
    "Writing an output failed."
);
create_exception!(
    squeal,
    Cancelled,
    SquealError,
    "The run was cancelled by its progress callback."
);

/// `InputFileNotFound(InputError, FileNotFoundError)`, made once (a class with two bases is
/// made by calling `type`, which `create_exception!` does not do).
static INPUT_FILE_NOT_FOUND: PyOnceLock<Py<PyType>> = PyOnceLock::new();

fn input_file_not_found(py: Python<'_>) -> PyResult<&Py<PyType>> {
    INPUT_FILE_NOT_FOUND.get_or_try_init(py, || {
        let bases = PyTuple::new(
            py,
            [
                py.get_type::<InputError>().into_any(),
                py.get_type::<PyFileNotFoundError>().into_any(),
            ],
        )?;
        let ns = PyDict::new(py);
        ns.set_item("__module__", "squeal")?;
        ns.set_item(
            "__doc__",
            "An input file does not exist (an InputError and a FileNotFoundError).",
        )?;
        let ty = py
            .import("builtins")?
            .getattr("type")?
            .call1(("InputFileNotFound", bases, ns))?;
        Ok(ty.cast_into::<PyType>()?.unbind())
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // Class-level defaults: an error raised without them still has both attributes.
    for ty in [py.get_type::<SceneError>(), py.get_type::<InputError>()] {
        ty.setattr("field", py.None())?;
        ty.setattr("path", py.None())?;
    }
    m.add("InputFileNotFound", input_file_not_found(py)?.bind(py))?;
    m.add("SquealError", py.get_type::<SquealError>())?;
    m.add("SceneError", py.get_type::<SceneError>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("MeshError", py.get_type::<MeshError>())?;
    m.add("ModelError", py.get_type::<ModelError>())?;
    m.add("SolverError", py.get_type::<SolverError>())?;
    m.add("OutputError", py.get_type::<OutputError>())?;
    m.add("Cancelled", py.get_type::<Cancelled>())?;
    Ok(())
}

/// The exception of a pipeline error, carrying its message (as the CLI prints it) and the
/// attributes of the module documentation.
pub fn to_py(e: &PipelineError) -> PyErr {
    let msg = e.to_string();
    let mut kind = e;
    while let PipelineError::Resumed { source, .. } = kind {
        kind = source;
    }
    let err = match kind {
        PipelineError::SceneParse { .. }
        | PipelineError::Scene { .. }
        | PipelineError::Override { .. }
        | PipelineError::Option { .. } => SceneError::new_err(msg),
        PipelineError::Io { .. } | PipelineError::Input { .. } => InputError::new_err(msg),
        PipelineError::Mesh { .. } => MeshError::new_err(msg),
        PipelineError::Fe { .. }
        | PipelineError::Reduction { .. }
        | PipelineError::Contact { .. }
        | PipelineError::Model(_) => ModelError::new_err(msg),
        PipelineError::Solver { .. } | PipelineError::Cea { .. } => SolverError::new_err(msg),
        PipelineError::Output { .. } => OutputError::new_err(msg),
        PipelineError::Cancelled { .. } => Cancelled::new_err(msg),
        PipelineError::Resumed { .. } => SquealError::new_err(msg),
    };
    Python::attach(|py| with_attributes(py, kind, err, e))
}

/// `err` (of `e`, whose innermost error is `kind`) with its attributes set (an attribute that cannot be set leaves the error as it is:
/// the message still names the key or file).
fn with_attributes(py: Python<'_>, kind: &PipelineError, err: PyErr, e: &PipelineError) -> PyErr {
    let path = |p: &Path| p.display().to_string();
    let set = |err: PyErr, attrs: &[(&str, Option<String>)]| -> PyErr {
        for (name, value) in attrs {
            let _ = err.value(py).setattr(*name, value.clone());
        }
        err
    };
    match kind {
        PipelineError::Io { path: p, source } if source.kind() == std::io::ErrorKind::NotFound => {
            match input_file_not_found(py) {
                Ok(ty) => {
                    let nf = PyErr::from_type(ty.bind(py).clone(), (e.to_string(),));
                    let _ = nf.value(py).setattr("errno", 2);
                    let _ = nf.value(py).setattr("strerror", source.to_string());
                    let _ = nf.value(py).setattr("filename", path(p));
                    set(nf, &[("path", Some(path(p)))])
                }
                Err(_) => set(err, &[("path", Some(path(p)))]),
            }
        }
        PipelineError::Io { path: p, .. } | PipelineError::Input { path: p, .. } => {
            let p = path(p);
            set(err, &[("path", (!p.starts_with('<')).then_some(p))])
        }
        PipelineError::Scene { field, .. } => {
            set(err, &[("field", Some(field.clone())), ("path", None)])
        }
        PipelineError::Option { option, .. } => {
            set(err, &[("field", Some(option.clone())), ("path", None)])
        }
        PipelineError::Override { assignment, .. } => {
            let key = assignment
                .split('=')
                .next()
                .unwrap_or("")
                .trim()
                .to_string();
            set(err, &[("field", Some(key)), ("path", None)])
        }
        PipelineError::SceneParse { path: p, message } => {
            let p = path(p);
            let file = (!p.starts_with('<')).then_some(p);
            set(err, &[("field", parse_error_key(message)), ("path", file)])
        }
        _ => err,
    }
}

/// The key a scene's typing error names: the toml crate ends the message with "in `table`"
/// and serde names an unknown field as "unknown field `x`" (`friction.law.mu0x`); None for
/// a syntax error, which names a line instead.
fn parse_error_key(message: &str) -> Option<String> {
    let quoted = |after: &str| -> Option<String> {
        let i = message.rfind(after)? + after.len();
        let rest = &message[i..];
        let end = rest.find('`')?;
        Some(rest[..end].to_string())
    };
    let table = quoted("\nin `");
    let field = quoted("unknown field `");
    match (table, field) {
        (Some(t), Some(f)) => Some(format!("{t}.{f}")),
        (None, Some(f)) => Some(f),
        (Some(t), None) => Some(t),
        (None, None) => None,
    }
}
