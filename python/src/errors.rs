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

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;
use squeal_pipeline::PipelineError;

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

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
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

/// The exception of a pipeline error, carrying its message (as the CLI prints it).
pub fn to_py(e: &PipelineError) -> PyErr {
    let msg = e.to_string();
    let mut kind = e;
    while let PipelineError::Resumed { source, .. } = kind {
        kind = source;
    }
    match kind {
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
    }
}
