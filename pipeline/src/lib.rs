//! squeal-pipeline: scenes, stage orchestration, outputs.
//!
//! Each verb of the `squeal` command is a function here taking a typed [`Scene`] and a
//! [`RunDir`]; the binary only parses arguments.

pub mod error;
pub mod figures;
pub mod history;
pub mod model;
pub mod output;
pub mod problem;
pub mod progress;
pub mod scene;
pub mod stages;
pub mod uq;
pub mod verdict;
pub mod warning;

pub use error::PipelineError;
pub use output::RunDir;
pub use scene::Scene;
pub use warning::Warning;

/// Version written into every run's summary.
pub const VERSION: &str = env!("CARGO_PKG_VERSION");
