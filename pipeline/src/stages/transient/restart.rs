//! The restart writer: `restart.json` ([`RestartFile`]) at restart points.

use super::sink::{RestartPoint, Sink, StepView};
use crate::error::PipelineError;
pub use crate::problem::restart::RestartFile;

/// Writes `restart.json` every NRSTRT accepted steps (at the end of that chunk) and at the end
/// of a BDF run (generalized-α has no restart: nothing is written), with the checkpoint every
/// sink saved its part into ([`Sink::save`]).
pub struct RestartSink {
    pub path: std::path::PathBuf,
    pub model_hash: String,
    pub n: usize,
    pub ng: usize,
    pub max_order: usize,
    /// NRSTRT (0: only at the end).
    pub every: usize,
}

impl Sink for RestartSink {
    fn step(&mut self, _: &StepView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    fn wants_break(&self, step: usize) -> bool {
        self.every > 0 && step % self.every == 0
    }
    fn restart_point(&mut self, p: &RestartPoint<'_>) -> Result<(), PipelineError> {
        let Some(state) = p.state else {
            return Ok(());
        };
        RestartFile {
            version: crate::VERSION.into(),
            model_hash: self.model_hash.clone(),
            n: self.n,
            ng: self.ng,
            t: p.t,
            max_order: self.max_order,
            state: state.clone(),
            run: Some(p.checkpoint.clone()),
        }
        .write(&self.path)
    }
}
