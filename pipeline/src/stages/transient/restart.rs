//! The restart file: the integrator's complete state, the model it belongs to, and the run's
//! checkpoint (each sink's part, [`Checkpoint`]).
//!
//! `restart.json` is written atomically (and fsync'd, [`crate::output::write_atomic`]) every
//! NRSTRT steps and at the end of a BDF run by [`RestartSink`], after the record files were
//! flushed, so the counts it holds never exceed the rows on disk.
//!
//! Reading checks the file against the model and the options before anything runs
//! ([`RestartFile::read`], [`RestartFile::bdf`]): the model (n, ng, hash), the state's own
//! consistency ([`BdfState::validate`]: lengths, order within MAXORD, a positive step, finite
//! numbers), `max_order` against `transient.maxord`. Errors name the file and the field. The
//! checkpoint's parts are checked by the sinks that own them (see `resume`).

use super::sink::{Checkpoint, RestartPoint, Sink, StepView};
use crate::error::PipelineError;
use crate::output::write_atomic;
use serde::{Deserialize, Serialize};
use squeal_solver::bdf::{Bdf, BdfOptions, BdfState};
use squeal_solver::SolverError;
use std::path::Path;

/// `restart.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RestartFile {
    /// squeal version that wrote it.
    pub version: String,
    /// Hash of n, ng, M, K, G: a restart continues only the same model (see `Problem::model_hash`).
    pub model_hash: String,
    /// Reduced DOFs n.
    pub n: usize,
    /// Gaps ng.
    pub ng: usize,
    /// Time of the state (the last accepted step).
    pub t: f64,
    /// MAXORD of the run (the state holds MAXORD + 2 difference arrays).
    pub max_order: usize,
    /// The BDF state.
    pub state: BdfState,
    /// The run's bookkeeping at this state, each sink's part (None: a state alone, as older
    /// files hold).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<Checkpoint>,
}

impl RestartFile {
    /// Writes it atomically.
    pub fn write(&self, path: &Path) -> Result<(), PipelineError> {
        let text = serde_json::to_string(self).map_err(|e| PipelineError::Output {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        write_atomic(path, text.as_bytes())
    }

    /// Reads one and checks it belongs to this model.
    pub fn read(path: &Path, model_hash: &str, n: usize, ng: usize) -> Result<Self, PipelineError> {
        let text = std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
            path: path.to_path_buf(),
            source,
        })?;
        let r: RestartFile = serde_json::from_str(&text).map_err(|e| PipelineError::Input {
            path: path.to_path_buf(),
            message: format!("not a squeal restart file: {e}"),
        })?;
        let bad = |field: &str, message: String| PipelineError::Input {
            path: path.to_path_buf(),
            message: format!("field `{field}`: {message}"),
        };
        if r.n != n || r.ng != ng || r.model_hash != model_hash {
            return Err(PipelineError::Input {
                path: path.to_path_buf(),
                message: format!(
                    "written for another model (n = {}, ng = {}, hash {}); this scene's model has n = {n}, ng = {ng}, hash {model_hash}",
                    r.n, r.ng, r.model_hash
                ),
            });
        }
        // y = {v, λ, u}: the BSQL system has 2n + ng unknowns.
        let len = 2 * n + ng;
        if r.state.n != len {
            return Err(bad(
                "state.n",
                format!(
                    "{} differs from 2n + ng = {len} (the BSQL unknowns v, lambda, u)",
                    r.state.n
                ),
            ));
        }
        if !r.t.is_finite() || r.t != r.state.t {
            return Err(bad(
                "t",
                format!("{} differs from the state's time {}", r.t, r.state.t),
            ));
        }
        if !(1..=5).contains(&r.max_order) {
            return Err(bad(
                "max_order",
                format!("{} is not a BDF order 1..=5", r.max_order),
            ));
        }
        // The state's own consistency, at the MAXORD it was written with (its arrays' length).
        r.state
            .validate(r.max_order)
            .map_err(|e| state_err(path, e))?;
        Ok(r)
    }

    /// The integrator continuing from this state with `opts`; its MAXORD must be the one the
    /// state was written with. Errors name the file and the field.
    pub fn bdf(self, path: &Path, opts: BdfOptions) -> Result<Bdf, PipelineError> {
        if self.max_order != opts.max_order {
            return Err(PipelineError::Input {
                path: path.to_path_buf(),
                message: format!(
                    "field `max_order`: {} (the run that wrote it); this scene's \
                     transient.maxord is {}: resume with the same MAXORD",
                    self.max_order, opts.max_order
                ),
            });
        }
        Bdf::from_state(opts, self.state).map_err(|e| state_err(path, e))
    }
}

/// A solver error about a restored state, as an error naming the restart file (and the field).
fn state_err(path: &Path, e: SolverError) -> PipelineError {
    let message = match e {
        SolverError::InvalidState { field, message } => format!("field `state.{field}`: {message}"),
        other => other.to_string(),
    };
    PipelineError::Input {
        path: path.to_path_buf(),
        message,
    }
}

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
