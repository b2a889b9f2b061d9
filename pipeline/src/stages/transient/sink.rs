//! What a run does besides integrating: the [`Sink`] trait, the views sinks receive, and the
//! [`Checkpoint`] each sink saves its own state into at a restart point.
//!
//! The bottom of the transient wing: it imports nothing from its siblings. The views are plain
//! data (times, states, counters), not the stepper: a sink cannot reach into the integrator.
//! A checkpoint is a JSON object (`restart.json`'s `run`) in which every sink owns its keys —
//! a part at the top level or in a section (`records`) shared with others, each key written
//! once; a sink reads its part back with [`Saved::part`], ignoring the keys of others.

use crate::error::PipelineError;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use squeal_solver::bdf::{BdfState, Status};
use squeal_solver::bsql::{EnergyBalance, PowerTerms};
use squeal_solver::Real;
use std::path::Path;

/// One accepted step (or the initial point, `step` = the steps before the run) as sinks see it.
///
/// At a separation event the sinks see two views at the same time t: the state before the
/// switch (it ends the integrator's accepted step that crossed the event, cut back to the
/// event) and the state after it (switched rows, impact, consistent y'), which has
/// `repeat = true` and is no step: counters of steps skip it.
pub struct StepView<'a> {
    /// Accepted integrator steps so far, counted from the start of the integration (a
    /// restarted run continues its count); the state after an event does not add one.
    pub step: usize,
    /// This view is at the same time as the previous one: the state after an event, not an
    /// accepted step.
    pub repeat: bool,
    pub t: Real,
    /// y = {v, λ, u}.
    pub y: &'a [Real],
    /// y' = {v', λ', u'}.
    pub yp: &'a [Real],
    /// Energies at this point (when the run keeps the energy balance).
    pub power: Option<&'a PowerTerms>,
    /// The balance integrated so far (empty when not kept).
    pub balance: &'a EnergyBalance,
}

/// The end of a chunk of steps.
pub struct ChunkView<'a> {
    /// Time of the integrator's solution.
    pub t: Real,
    /// Accepted steps so far.
    pub steps: usize,
    /// The chunk ended in an error (sinks flush and write nothing new).
    pub failed: bool,
    /// The BDF's accepted steps by order so far (None for generalized-α).
    pub order_histogram: Option<&'a [u64]>,
}

/// The end of a run.
pub struct EndView<'a> {
    pub status: &'a Status,
    /// The solution where the integrator stopped (at TFINAL when it reached it).
    pub t: Real,
    pub y: &'a [Real],
    pub yp: &'a [Real],
    pub tfinal: Real,
    /// The BDF's accepted steps by order (None for generalized-α).
    pub order_histogram: Option<&'a [u64]>,
}

/// A restart point: the integrator's state and the checkpoint every sink saved into.
pub struct RestartPoint<'a> {
    /// Time of the state.
    pub t: Real,
    /// The BDF's complete state (None for generalized-α: no restart).
    pub state: Option<&'a BdfState>,
    pub checkpoint: &'a Checkpoint,
}

/// What a run does besides integrating. Every method but `step` has a default that does
/// nothing.
pub trait Sink {
    /// The initial point and every accepted step, in order.
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError>;
    /// True when the chunk should end after accepted step `step` (a restart is due).
    fn wants_break(&self, _step: usize) -> bool {
        false
    }
    /// The next time at which the sink wants the solution exactly (interpolated), if any.
    fn next_stop(&self) -> Option<Real> {
        None
    }
    /// The solution at a time `next_stop` asked for.
    fn stop(&mut self, _t: Real, _y: &[Real], _yp: &[Real]) -> Result<(), PipelineError> {
        Ok(())
    }
    /// After every chunk, also a failed one: flush.
    fn chunk_end(&mut self, _c: &ChunkView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// The run ended (any status).
    fn end(&mut self, _e: &EndView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// At a restart point (after the chunk ends where a sink wanted a break, and after the
    /// end), what this sink must carry over a restart: its own keys of the checkpoint.
    fn save(&self, _c: &mut Checkpoint) -> Result<(), PipelineError> {
        Ok(())
    }
    /// A restart point, after every sink saved its part (the restart writer writes it).
    fn restart_point(&mut self, _p: &RestartPoint<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
}

/// What a run carries over a restart besides the integrator's state: the parts of its sinks,
/// each under its own keys (`restart.json`'s `run`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(transparent)]
pub struct Checkpoint(Map<String, Value>);

impl Checkpoint {
    /// Saves the fields of `part` (a struct) at the top level (`section` None) or in the
    /// object `section`. A key another sink saved is an error (two owners of one key).
    pub fn save<T: Serialize>(
        &mut self,
        section: Option<&str>,
        part: &T,
    ) -> Result<(), PipelineError> {
        let err = |message: String| PipelineError::Model(format!("restart checkpoint: {message}"));
        let Value::Object(fields) = serde_json::to_value(part).map_err(|e| err(e.to_string()))?
        else {
            return Err(err("a part must be an object".into()));
        };
        let target = match section {
            None => &mut self.0,
            Some(s) => match self.0.entry(s).or_insert_with(|| Value::Object(Map::new())) {
                Value::Object(m) => m,
                _ => return Err(err(format!("`{s}` is not a section"))),
            },
        };
        for (k, v) in fields {
            if target.contains_key(&k) {
                return Err(err(format!("`{k}` is saved twice")));
            }
            target.insert(k, v);
        }
        Ok(())
    }

    /// The keys saved (at the top level).
    pub fn keys(&self) -> impl Iterator<Item = &String> {
        self.0.keys()
    }
}

/// A checkpoint read back from a restart file, with what its parts are checked against.
pub struct Saved<'a> {
    pub checkpoint: &'a Checkpoint,
    /// The restart file (named in errors).
    pub path: &'a Path,
    /// Time of the integrator's state.
    pub t: Real,
    /// Accepted steps of the state.
    pub steps: u64,
    /// Reduced DOFs n.
    pub n: usize,
}

impl Saved<'_> {
    /// A sink's part: the fields of `T` at the top level (`section` None) or in `section`
    /// (the keys of other sinks ignored). A missing section reads as an empty one.
    pub fn part<T: DeserializeOwned>(&self, section: Option<&str>) -> Result<T, PipelineError> {
        let empty = Value::Object(Map::new());
        let value = match section {
            None => Value::Object(self.checkpoint.0.clone()),
            Some(s) => self.checkpoint.0.get(s).unwrap_or(&empty).clone(),
        };
        let field = section.map_or("run".to_string(), |s| format!("run.{s}"));
        serde_json::from_value(value).map_err(|e| PipelineError::Input {
            path: self.path.to_path_buf(),
            message: format!("field `{field}`: {e}"),
        })
    }

    /// An error naming the restart file and the checkpoint's `field` (`run.<field>`).
    pub fn bad(&self, field: &str, message: String) -> PipelineError {
        PipelineError::Input {
            path: self.path.to_path_buf(),
            message: format!("field `run.{field}`: {message}"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct A {
        a: u32,
    }
    #[derive(Debug, PartialEq, Serialize, Deserialize)]
    struct B {
        b: Option<f64>,
    }

    /// Two parts share a section; each reads back its own; a key saved twice is refused.
    #[test]
    fn parts_share_sections_and_keys_have_one_owner() {
        let mut c = Checkpoint::default();
        c.save(None, &A { a: 3 }).unwrap();
        c.save(Some("records"), &A { a: 4 }).unwrap();
        c.save(Some("records"), &B { b: Some(0.1) }).unwrap();
        assert!(c.save(Some("records"), &A { a: 5 }).is_err());
        assert!(c.save(None, &A { a: 5 }).is_err());
        let text = serde_json::to_string(&c).unwrap();
        assert_eq!(text, r#"{"a":3,"records":{"a":4,"b":0.1}}"#);
        let back: Checkpoint = serde_json::from_str(&text).unwrap();
        let s = Saved {
            checkpoint: &back,
            path: Path::new("r.json"),
            t: 0.0,
            steps: 0,
            n: 1,
        };
        assert_eq!(s.part::<A>(None).unwrap(), A { a: 3 });
        assert_eq!(s.part::<A>(Some("records")).unwrap(), A { a: 4 });
        assert_eq!(s.part::<B>(Some("records")).unwrap(), B { b: Some(0.1) });
        assert_eq!(s.part::<B>(Some("other")).unwrap(), B { b: None });
        let e = s.part::<A>(Some("other")).unwrap_err().to_string();
        assert!(
            e.contains("r.json") && e.contains("field `run.other`"),
            "{e}"
        );
    }
}
