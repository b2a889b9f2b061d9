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

impl PipelineError {
    /// A mesh-stage error of component `component`; the caller's interrupt (gmsh killed)
    /// becomes [`PipelineError::Cancelled`].
    pub fn mesh(component: &str, source: squeal_meshes::MeshError) -> PipelineError {
        match source {
            squeal_meshes::MeshError::Interrupted { command } => PipelineError::Cancelled {
                what: format!("gmsh on component `{component}` (killed: {command})"),
            },
            source => PipelineError::Mesh {
                component: component.to_string(),
                source,
            },
        }
    }

    /// An FE error of component `component`; the caller's interrupt becomes
    /// [`PipelineError::Cancelled`].
    pub fn fe(component: &str, source: squeal_fe::FeError) -> PipelineError {
        match source {
            squeal_fe::FeError::Interrupted { during } => PipelineError::Cancelled {
                what: format!("{during} (component `{component}`)"),
            },
            source => PipelineError::Fe {
                component: component.to_string(),
                source,
            },
        }
    }

    /// A reduction error while doing `what`; the caller's interrupt becomes
    /// [`PipelineError::Cancelled`], and a Lanczos that ran out of Krylov dimension names
    /// the scene key that raises it (`reduction.lanczos_max_dim`).
    pub fn reduction(what: String, source: squeal_reduction::ReductionError) -> PipelineError {
        use squeal_reduction::ReductionError as R;
        match source {
            R::Interrupted { during } => PipelineError::Cancelled {
                what: format!("{during} ({what})"),
            },
            e @ R::LanczosNotConverged { .. } => PipelineError::Scene {
                field: "reduction.lanczos_max_dim".into(),
                message: format!(
                    "{what}: {e}; raise `reduction.lanczos_max_dim`, or lower \
                     `reduction.cutoff_hz` / `reduction.frequency_of_interest_hz`"
                ),
            },
            source => PipelineError::Reduction { what, source },
        }
    }

    /// A CEA error while doing `what`; the caller's interrupt becomes
    /// [`PipelineError::Cancelled`].
    pub fn cea(what: String, source: squeal_solver::cea::CeaError) -> PipelineError {
        match source {
            squeal_solver::cea::CeaError::Interrupted { during } => PipelineError::Cancelled {
                what: format!("{during} ({what})"),
            },
            source => PipelineError::Cea { what, source },
        }
    }

    /// True for [`PipelineError::Cancelled`], also inside a resumed run's error.
    pub fn is_cancelled(&self) -> bool {
        match self {
            PipelineError::Cancelled { .. } => true,
            PipelineError::Resumed { source, .. } => source.is_cancelled(),
            _ => false,
        }
    }
}
