//! The restart file: the integrator's complete state, the model it belongs to, and the run's
//! checkpoint (each sink's part, [`Checkpoint`]): what a transient run carries over a restart,
//! and the state a CEA may linearise about.
//!
//! `restart.json` is written atomically (and fsync'd, [`crate::output::write_atomic`]) every
//! NRSTRT steps and at the end of a BDF run by the transient's `RestartSink`, after the record files were
//! flushed, so the counts it holds never exceed the rows on disk.
//!
//! Reading checks the file against the model and the options before anything runs
//! ([`RestartFile::read`], [`RestartFile::bdf`]): the model (n, ng, hash), the state's own
//! consistency ([`BdfState::validate`]: lengths, order within MAXORD, a positive step, finite
//! numbers), `max_order` against `transient.maxord`. Errors name the file and the field. The
//! checkpoint's parts are checked by the sinks that own them (see `resume`).

use crate::error::PipelineError;
use crate::output::write_atomic;
use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};
use squeal_solver::bdf::{Bdf, BdfOptions, BdfState};
use squeal_solver::{Real, SolverError};
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
