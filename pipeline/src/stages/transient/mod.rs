//! `squeal transient`: the BSQL nonlinear transient of the reduced brake model.
//!
//! reduced model → the problem at the scene's operating point (M, B, K, G, P(t), the gaps;
//! [`crate::problem`]) → steady sliding state before the brake load (TOLINT) and consistent
//! y'(0) (`problem::start`), or a restart file's state ([`resume`]) → BDF or generalized-α
//! ([`stepper`]) to TFINAL through the one [`driver`], whose sinks record what the run keeps →
//! the squeal verdict on what they recorded ([`verdict`], pure), with the roots of the
//! linearised problem as its CEA input (`problem::linear::verdict_roots`).
//!
//! The folder is layered, each layer importing only those below it and the problem layer
//! (checked by `pipeline/tests/layers.rs`):
//!
//! 1. [`sink`]: the `Sink` trait, its views (the checkpoint each sink saves its part into is
//!    `problem::restart`'s); [`verdict`]: the analysis, pure (no sink, scene or file);
//! 2. [`restart`] (the restart file's writer), [`stepper`], [`driver`], [`start`] (the run's
//!    origin as a checkpoint part);
//! 3. [`collect`]: data-only sinks (response, contact validity, face velocity, steps by
//!    order); [`files`]: the history, energy and response writers;
//! 4. [`prepare`], [`resume`], [`run`] (start → drive → decide → result), [`result`],
//!    [`effects`], [`export`], [`write`] (the verb's files).
//!
//! - Compute: [`prepare`] the run (problem, model hash), then [`Prepared::run`] with any extra
//!   sinks; it returns a [`TransientResult`] in memory (status, statistics, verdict, energy,
//!   effects, and with [`TransientOptions::keep_history`] the sampled history arrays).
//! - Write: [`run_on_model`] (the CLI) attaches the file sinks and writes `summary.json`
//!   ([`TransientReport`]).
//! - Resume: with `transient.restart`, [`prepare`] reads the restart file and the records of
//!   the run that wrote it ([`Resume`]); the run continues the state, the records, the energy
//!   integrals, counters and contact monitor, and its result covers the whole run — the
//!   uninterrupted run's, bit for bit.

pub mod collect;
pub mod driver;
pub mod effects;
pub mod export;
pub mod files;
pub mod prepare;
pub mod restart;
pub mod result;
pub mod resume;
pub mod run;
pub mod sink;
pub mod start;
pub mod stepper;

pub mod write;

/// The problem layer's modules under their former paths (the library's API).
pub use crate::problem::{band, options, recover, system};

pub use crate::verdict::guard::status_text;
pub use crate::verdict::{self, guard, limit_cycle, roots, validity};
pub use files::columns::ENERGY_HEADER;
pub use files::history::History;
pub use prepare::{prepare, step_bound, Prepared, StepBound};
pub use result::{TransientOptions, TransientReport, TransientResult, VerdictCeaResult};
pub use resume::Resume;
pub use start::{start_state, StartState, SteadySummary};
pub use system::separation_mask;
pub use write::{run, run_cached, run_on_model};

use crate::error::PipelineError;
use crate::model;
use crate::progress::Progress;
use crate::scene::Scene;

/// The transient of `scene` on `model`, in memory (no file is written): the library's and the
/// Python package's entry point.
pub fn compute(
    scene: &Scene,
    model: &model::ReducedModel,
    progress: &Progress,
    opts: &TransientOptions,
) -> Result<TransientResult, PipelineError> {
    prepare(scene, model)?.run(progress, opts, &mut [])
}
