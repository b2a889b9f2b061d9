//! The restart file and resuming a run from it.
//!
//! `restart.json` holds the integrator's complete state, the model hash and the time, and —
//! since records are resumed — the run's bookkeeping at that state ([`RunCheckpoint`]): the
//! rows of `history.npy`, `energy.csv` and `response.npy` written up to it, the energy
//! integrals, the BSQL counters, the contact monitor, the start time and steady state. It is
//! written atomically (and fsync'd, [`crate::output::write_atomic`]) every NRSTRT steps and at
//! the end of a run, after the record files were flushed, so its counts never exceed the rows
//! on disk.
//!
//! Reading checks every field against the model and the options before anything runs
//! ([`RestartFile::read`], [`RestartFile::bdf`]): the model (n, ng, hash), the state's own
//! consistency ([`BdfState::validate`]: lengths, order within MAXORD, a positive step, finite
//! numbers), `max_order` against `transient.maxord`, the checkpoint's times and counts. Errors
//! name the file and the field.
//!
//! A run resumed from it ([`Resume::load`]) is a true resume when the run's records lie beside
//! the restart file (its folder is the run folder that wrote it): the records are cut back to
//! the restart's counts (rows written after it, before a kill, are dropped) and continued,
//! into the same folder or a new one (which then gets the earlier rows too); the energy
//! integrals, counters and contact monitor continue; the verdict reads the whole response.
//! The result equals the uninterrupted run's bit for bit. Without those records (a restart
//! file copied elsewhere, or written by an older squeal) the run continues the state alone,
//! with a warning: its records and verdict start at the restart.

use super::driver::{ChunkView, EndView, Sink, StepView, Stepper};
use super::records::ENERGY_HEADER;
use super::validity::{ContactMonitor, ContactValidity};
use super::SteadySummary;
use crate::error::PipelineError;
use crate::history::npy::{read_header, read_npy};
use crate::history::HistoryMap;
use crate::output::write_atomic;
use crate::warning::Warning;
use serde::{Deserialize, Serialize};
use squeal_solver::bdf::{Bdf, BdfOptions, BdfState, IcStats};
use squeal_solver::bsql::{BsqlStats, EnergyRestart};
use squeal_solver::SolverError;
use std::io::BufRead;
use std::path::{Path, PathBuf};

type Real = f64;

/// The file of the response the verdict analyses (t, then the velocities, every accepted
/// step), written beside `restart.json` so that a resumed run's verdict covers the whole run.
pub const RESPONSE_FILE: &str = "response.npy";

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
    /// The run's bookkeeping at this state (None: a state alone, as older files hold).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub run: Option<RunCheckpoint>,
}

/// What a run carries over a restart besides the integrator's state (`restart.json`'s `run`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RunCheckpoint {
    /// Start time of the whole run (before any restart).
    pub t_start: Real,
    /// Accepted steps at this point.
    pub steps: u64,
    /// The steady state and initial conditions the run started from.
    pub steady_state: Option<SteadySummary>,
    pub initial_conditions: Option<IcStats>,
    /// The energy integrals with their last records.
    pub energy: Option<EnergyRestart>,
    /// The BSQL system's counters and drift monitor.
    pub bsql_stats: BsqlStats,
    /// The contact monitor.
    pub contact: Option<ContactValidity>,
    /// Seconds of bookkeeping so far.
    pub bookkeeping_s: Real,
    /// Rows of each record file written up to this state.
    pub records: RecordCounts,
    /// The BDF's order histogram at the last chunk end at or before the end of the load ramp,
    /// and its time, where the guard's count by order starts ([`super::guard::OrderTally`];
    /// None in older files).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orders_at_ramp: Option<(Real, Vec<u64>)>,
}

/// Rows of the record files at a restart point (None: the run does not write that file).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct RecordCounts {
    /// Rows of `history.npy`.
    pub history_rows: Option<usize>,
    /// Its columns.
    pub history_columns: Option<usize>,
    /// Time of its last row.
    pub history_last_t: Option<Real>,
    /// Data rows of `energy.csv` (after the header line).
    pub energy_rows: Option<usize>,
    /// Rows of `response.npy`.
    pub response_rows: Option<usize>,
    /// The reduced DOFs of its velocity columns.
    pub response_dofs: Vec<usize>,
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
        if let Some(c) = &r.run {
            c.validate(r.t, r.state.stats.steps, n)
                .map_err(|(field, m)| bad(&format!("run.{field}"), m))?;
        }
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

impl RunCheckpoint {
    /// Checks the checkpoint of a state at time `t` after `steps` steps on n DOFs:
    /// Err((field, message)).
    fn validate(&self, t: Real, steps: u64, n: usize) -> Result<(), (String, String)> {
        let err = |f: &str, m: String| Err((f.to_string(), m));
        if !self.t_start.is_finite() || self.t_start > t {
            return err(
                "t_start",
                format!("{} is not a start time at or before t = {t}", self.t_start),
            );
        }
        if self.steps != steps {
            return err(
                "steps",
                format!("{} differs from the state's {steps} steps", self.steps),
            );
        }
        if !(self.bookkeeping_s.is_finite() && self.bookkeeping_s >= 0.0) {
            return err(
                "bookkeeping_s",
                format!("{} is not a duration", self.bookkeeping_s),
            );
        }
        if let Some(e) = &self.energy {
            if e.balance.t != t || e.last.is_none_or(|p| p.t != t) {
                return err(
                    "energy.balance.t",
                    format!(
                        "the integrals end at t = {} (last record {:?}), not at the state's t = {t}",
                        e.balance.t,
                        e.last.map(|p| p.t)
                    ),
                );
            }
        }
        let r = &self.records;
        if r.history_rows.is_some() != r.history_columns.is_some()
            || r.history_rows.is_some_and(|k| k > 0) != r.history_last_t.is_some()
        {
            return err(
                "records.history_rows",
                "history_rows, history_columns and history_last_t go together".into(),
            );
        }
        if r.history_last_t
            .is_some_and(|h| !(h <= t && h >= self.t_start))
        {
            return err(
                "records.history_last_t",
                format!(
                    "{:?} is not between the start {} and the state's t = {t}",
                    r.history_last_t, self.t_start
                ),
            );
        }
        if let Some(&d) = r.response_dofs.iter().find(|&&d| d >= n) {
            return err(
                "records.response_dofs",
                format!("DOF {d} is out of range (the model has {n} DOFs)"),
            );
        }
        if r.response_rows.is_some_and(|k| k as u64 > steps + 1) {
            return err(
                "records.response_rows",
                format!(
                    "{:?} rows after {steps} steps (at most one per step and the start)",
                    r.response_rows
                ),
            );
        }
        Ok(())
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

/// The records of the run a restart file belongs to, where a resumed run continues them.
#[derive(Debug, Clone)]
pub struct Records {
    /// The restart file (named in errors).
    pub restart: PathBuf,
    /// Its folder: the run folder that wrote it.
    pub folder: PathBuf,
    pub counts: RecordCounts,
    /// The response rows up to the restart: times and, per DOF of `counts.response_dofs`,
    /// velocities and accelerations (the root estimator's Hermite resampling reads both).
    pub response_t: Vec<Real>,
    pub response_v: Vec<Vec<Real>>,
    pub response_a: Vec<Vec<Real>>,
}

impl Records {
    /// `history.npy` of the run resumed.
    pub fn history(&self) -> PathBuf {
        self.folder.join("history.npy")
    }

    /// `energy.csv` of the run resumed.
    pub fn energy(&self) -> PathBuf {
        self.folder.join("energy.csv")
    }

    /// `response.npy` of the run resumed.
    pub fn response(&self) -> PathBuf {
        self.folder.join(RESPONSE_FILE)
    }

    /// An error naming the restart file and the field of its counts.
    fn bad(&self, field: &str, message: String) -> PipelineError {
        PipelineError::Input {
            path: self.restart.clone(),
            message: format!("field `run.records.{field}`: {message}"),
        }
    }

    /// Checks the run's files against the counts and reads the response: every file counted
    /// must hold at least that many rows, `history.npy` the same columns and the row time.
    fn read(restart: &Path, folder: &Path, counts: RecordCounts) -> Result<Self, PipelineError> {
        let mut r = Records {
            restart: restart.to_path_buf(),
            folder: folder.to_path_buf(),
            counts,
            response_t: Vec::new(),
            response_v: Vec::new(),
            response_a: Vec::new(),
        };
        let c = r.counts.clone();
        if let (Some(rows), Some(cols)) = (c.history_rows, c.history_columns) {
            let p = r.history();
            let h = read_header(&p).map_err(|e| {
                r.bad(
                    "history_rows",
                    format!("{rows} rows of {} are needed: {e}", p.display()),
                )
            })?;
            if h.cols != cols || h.rows.min(h.data_rows) < rows {
                return Err(r.bad(
                    "history_rows",
                    format!(
                        "{rows} rows of {cols} columns, but {} holds {} rows of {} columns",
                        p.display(),
                        h.rows.min(h.data_rows),
                        h.cols
                    ),
                ));
            }
            if let Some(t) = c.history_last_t {
                let last = read_value(&p, h.data_offset + (rows - 1) * cols * 8)?;
                if last != t {
                    return Err(r.bad(
                        "history_last_t",
                        format!(
                            "{t}, but row {} of {} is at t = {last} (not this run's history)",
                            rows - 1,
                            p.display()
                        ),
                    ));
                }
            }
        }
        if let Some(rows) = c.energy_rows {
            let p = r.energy();
            let have = count_lines(&p, rows + 1).map_err(|e| {
                r.bad(
                    "energy_rows",
                    format!("{rows} rows of {} are needed: {e}", p.display()),
                )
            })?;
            if have < rows + 1 {
                return Err(r.bad(
                    "energy_rows",
                    format!(
                        "{rows} rows, but {} holds {} complete lines after its header",
                        p.display(),
                        have.saturating_sub(1)
                    ),
                ));
            }
        }
        if let Some(rows) = c.response_rows {
            let p = r.response();
            let (have, cols, data) = read_npy(&p)
                .map_err(|e| r.bad("response_rows", format!("{rows} rows are needed: {e}")))?;
            let nd = c.response_dofs.len();
            if cols != 2 * nd + 1 || have < rows {
                return Err(r.bad(
                    "response_rows",
                    format!(
                        "{rows} rows of {} columns, but {} holds {have} rows of {cols} columns",
                        2 * nd + 1,
                        p.display()
                    ),
                ));
            }
            r.response_v = vec![Vec::with_capacity(rows); nd];
            r.response_a = vec![Vec::with_capacity(rows); nd];
            for row in data.chunks_exact(cols).take(rows) {
                r.response_t.push(row[0]);
                for k in 0..nd {
                    r.response_v[k].push(row[1 + k]);
                    r.response_a[k].push(row[1 + nd + k]);
                }
            }
        }
        Ok(r)
    }

    /// Checks that the records continue with `columns` history columns (the scene's
    /// `[output]`), naming the scene field when they changed.
    pub fn check_columns(&self, columns: &[crate::history::Column]) -> Result<(), PipelineError> {
        let Some(cols) = self.counts.history_columns else {
            return Ok(());
        };
        let map = HistoryMap::read(&self.folder.join("history_map.json")).ok();
        let same = cols == columns.len()
            && map.is_none_or(|m| {
                m.columns.len() == columns.len()
                    && m.columns.iter().zip(columns).all(|(a, b)| a.name == b.name)
            });
        match same {
            true => Ok(()),
            false => Err(PipelineError::Scene {
                field: "output.grids".into(),
                message: format!(
                    "the history of the run resumed ({}) has {cols} other columns than this \
                     scene's [output] ({}): resume with the same output.grids and output.gaps",
                    self.history().display(),
                    columns.len()
                ),
            }),
        }
    }
}

/// The f64 at byte `offset` of a file.
fn read_value(path: &Path, offset: usize) -> Result<Real, PipelineError> {
    use std::io::{Read, Seek, SeekFrom};
    let io = |source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    };
    let mut f = std::fs::File::open(path).map_err(io)?;
    f.seek(SeekFrom::Start(offset as u64)).map_err(io)?;
    let mut b = [0u8; 8];
    f.read_exact(&mut b).map_err(io)?;
    Ok(Real::from_le_bytes(b))
}

/// Complete lines (ending in a newline) of a text file, counting up to `max`.
fn count_lines(path: &Path, max: usize) -> std::io::Result<usize> {
    let mut f = std::io::BufReader::new(std::fs::File::open(path)?);
    let mut line = Vec::new();
    let mut n = 0;
    while n < max {
        line.clear();
        if f.read_until(b'\n', &mut line)? == 0 || line.last() != Some(&b'\n') {
            break;
        }
        if n == 0 && line.strip_suffix(b"\n") != Some(ENERGY_HEADER.as_bytes()) {
            return Err(std::io::Error::other(format!(
                "its first line is not the header `{ENERGY_HEADER}`"
            )));
        }
        n += 1;
    }
    Ok(n)
}

/// Copies the header line and the first `rows` data lines of `src` (an `energy.csv`) into
/// `dst` atomically (`src` may be `dst`).
pub fn continue_lines(src: &Path, dst: &Path, rows: usize) -> Result<(), PipelineError> {
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| PipelineError::Io { path: p, source }
    };
    let mut f = std::io::BufReader::new(std::fs::File::open(src).map_err(io(src))?);
    let mut out = Vec::new();
    for _ in 0..=rows {
        if f.read_until(b'\n', &mut out).map_err(io(src))? == 0 {
            break;
        }
    }
    write_atomic(dst, &out)
}

/// How a run continues a restart file.
#[derive(Debug, Clone)]
pub struct Resume {
    /// The restart file.
    pub path: PathBuf,
    pub file: RestartFile,
    /// The run's records to continue (None: the state alone).
    pub records: Option<Records>,
    /// Why the run continues the state alone.
    pub warning: Option<Warning>,
}

impl Resume {
    /// Reads the restart file `path` (checked against the model, [`RestartFile::read`]) and,
    /// when its checkpoint's records lie beside it, checks them and reads the response.
    pub fn load(path: &Path, model_hash: &str, n: usize, ng: usize) -> Result<Self, PipelineError> {
        let file = RestartFile::read(path, model_hash, n, ng)?;
        let folder = path
            .parent()
            .filter(|p| !p.as_os_str().is_empty())
            .unwrap_or(Path::new("."))
            .to_path_buf();
        let alone = |why: String| Warning {
            input: path.display().to_string(),
            message: format!(
                "{why}: the run continues the state alone, its history, energy integrals and \
                 verdict start at the restart time t = {}",
                file.t
            ),
            value: file.t,
            tolerance: 0.0,
        };
        let (records, warning) = match &file.run {
            None => (
                None,
                Some(alone(
                    "the file holds no run checkpoint (written by an older squeal)".into(),
                )),
            ),
            Some(_) if !folder.join(RESPONSE_FILE).is_file() => (
                None,
                Some(alone(format!(
                    "the run's records ({RESPONSE_FILE}, history.npy, energy.csv) are not beside it"
                ))),
            ),
            Some(c) => (Some(Records::read(path, &folder, c.records.clone())?), None),
        };
        Ok(Resume {
            path: path.to_path_buf(),
            file,
            records,
            warning,
        })
    }

    /// The checkpoint, when the run continues its records (a true resume).
    pub fn checkpoint(&self) -> Option<&RunCheckpoint> {
        self.records.as_ref().and(self.file.run.as_ref())
    }
}

/// Writes `restart.json` every NRSTRT accepted steps (at the end of that chunk) and at the end
/// of a BDF run (generalized-α has no restart: nothing is written), with the checkpoint every
/// sink contributed to ([`Sink::checkpoint`]).
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
    fn restart_point(
        &mut self,
        stepper: &Stepper,
        checkpoint: &RunCheckpoint,
    ) -> Result<(), PipelineError> {
        let Some(state) = stepper.bdf_state() else {
            return Ok(());
        };
        RestartFile {
            version: crate::VERSION.into(),
            model_hash: self.model_hash.clone(),
            n: self.n,
            ng: self.ng,
            t: stepper.t(),
            max_order: self.max_order,
            state: state.clone(),
            run: Some(checkpoint.clone()),
        }
        .write(&self.path)
    }
}

/// The contact monitor as a sink that also checkpoints (and was restored from) its state.
pub struct MonitorSink<'a>(pub &'a mut ContactMonitor);

impl Sink for MonitorSink<'_> {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        self.0.step(s)
    }
    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        self.0.chunk_end(c)
    }
    fn end(&mut self, e: &EndView<'_>) -> Result<(), PipelineError> {
        self.0.end(e)
    }
    fn checkpoint(&self, c: &mut RunCheckpoint) {
        c.contact = Some(self.0.validity.clone());
    }
}

/// Where the run started: its start time, steady state and initial conditions, for the
/// checkpoint.
pub struct OriginSink {
    pub t_start: Real,
    pub steady_state: Option<SteadySummary>,
    pub initial_conditions: Option<IcStats>,
}

impl Sink for OriginSink {
    fn step(&mut self, _: &StepView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    fn checkpoint(&self, c: &mut RunCheckpoint) {
        c.t_start = self.t_start;
        c.steady_state = self.steady_state.clone();
        c.initial_conditions = self.initial_conditions.clone();
    }
}
