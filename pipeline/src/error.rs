//! The pipeline's error: each stage's error wrapped with the stage name.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum PipelineError {
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("scene {path}: {message}")]
    SceneParse { path: PathBuf, message: String },
    #[error("scene field `{field}`: {message}")]
    Scene { field: String, message: String },
    #[error("{option}: {message}")]
    Option { option: String, message: String },
    #[error("--set {assignment}: {reason}")]
    Override { assignment: String, reason: String },
    #[error("mesh stage (component `{component}`): {source}")]
    Mesh {
        component: String,
        #[source]
        source: squeal_meshes::MeshError,
    },
    #[error("fe stage (component `{component}`): {source}")]
    Fe {
        component: String,
        #[source]
        source: squeal_fe::FeError,
    },
    #[error("writing {path}: {message}")]
    Output { path: PathBuf, message: String },
    #[error("reduction stage ({what}): {source}")]
    Reduction {
        what: String,
        #[source]
        source: squeal_reduction::ReductionError,
    },
    #[error("contact stage ({what}): {source}")]
    Contact {
        what: String,
        #[source]
        source: squeal_contact::ContactError,
    },
    #[error("transient stage ({what}): {source}")]
    Solver {
        what: String,
        #[source]
        source: squeal_solver::SolverError,
    },
    #[error("cea stage ({what}): {source}")]
    Cea {
        what: String,
        #[source]
        source: squeal_solver::cea::CeaError,
    },
    #[error("model: {0}")]
    Model(String),
    #[error("{path}: {message}")]
    Input { path: PathBuf, message: String },
    #[error("cancelled by the caller during {what}")]
    Cancelled { what: String },
    /// An error of a run resumed from a restart file (whose state it may come from).
    #[error("{source} (run resumed from {path})")]
    Resumed {
        path: PathBuf,
        #[source]
        source: Box<PipelineError>,
    },
}
