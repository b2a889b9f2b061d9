//! `response.npy`: the response the verdict analyses (t, then its velocities, then their
//! accelerations) at every accepted step, written beside `restart.json` so that a resumed
//! run's verdict covers the whole run ([`ResponseFile`]); its part of the checkpoint
//! ([`ResponsePart`]) and the rows read back ([`ResponsePart::read`]).

use super::super::collect::response::{same_response, Recorded};
use super::super::sink::{Checkpoint, ChunkView, EndView, Saved, Sink, StepView};
use crate::error::PipelineError;
use crate::history::npy::{read_npy, NpyAppender};
use crate::output::RunDir;
use serde::{Deserialize, Serialize};
use squeal_solver::Real;
use std::path::Path;

/// The file's name.
pub const RESPONSE_FILE: &str = "response.npy";

/// Rows of `response.npy` at a restart point and its DOFs; section `records` of the
/// checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ResponsePart {
    /// Rows of `response.npy`.
    pub response_rows: Option<usize>,
    /// The reduced DOFs of its velocity columns.
    #[serde(default)]
    pub response_dofs: Vec<usize>,
}

impl ResponsePart {
    /// The part saved in a checkpoint: DOFs of the model, at most one row per step and the
    /// start.
    pub fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        let r: ResponsePart = s.part(Some("records"))?;
        if let Some(&d) = r.response_dofs.iter().find(|&&d| d >= s.n) {
            return Err(s.bad(
                "records.response_dofs",
                format!("DOF {d} is out of range (the model has {} DOFs)", s.n),
            ));
        }
        if r.response_rows.is_some_and(|k| k as u64 > s.steps + 1) {
            return Err(s.bad(
                "records.response_rows",
                format!(
                    "{:?} rows after {} steps (at most one per step and the start)",
                    r.response_rows, s.steps
                ),
            ));
        }
        Ok(r)
    }

    /// The rows counted, read back from `response.npy` in `folder` (the run resumed; errors
    /// name the `restart` file and the count).
    pub fn read(&self, folder: &Path, restart: &Path) -> Result<Recorded, PipelineError> {
        let nd = self.response_dofs.len();
        let mut r = Recorded {
            restart: restart.to_path_buf(),
            dofs: self.response_dofs.clone(),
            t: Vec::new(),
            v: vec![Vec::new(); nd],
            a: vec![Vec::new(); nd],
        };
        let Some(rows) = self.response_rows else {
            return Ok(r);
        };
        let bad = |message: String| PipelineError::Input {
            path: restart.to_path_buf(),
            message: format!("field `run.records.response_rows`: {message}"),
        };
        let p = folder.join(RESPONSE_FILE);
        let (have, cols, data) =
            read_npy(&p).map_err(|e| bad(format!("{rows} rows are needed: {e}")))?;
        if cols != 2 * nd + 1 || have < rows {
            return Err(bad(format!(
                "{rows} rows of {} columns, but {} holds {have} rows of {cols} columns",
                2 * nd + 1,
                p.display()
            )));
        }
        for row in data.chunks_exact(cols).take(rows) {
            r.t.push(row[0]);
            for k in 0..nd {
                r.v[k].push(row[1 + k]);
                r.a[k].push(row[1 + nd + k]);
            }
        }
        Ok(r)
    }
}

/// The writer of `response.npy`.
pub struct ResponseFile {
    dofs: Vec<usize>,
    file: NpyAppender,
    row: Vec<Real>,
}

/// The response file a resumed run continues: the run folder, the restart file (named in
/// errors) and the checkpoint's counts.
#[derive(Debug, Clone, Copy)]
pub struct PriorResponse<'a> {
    pub folder: &'a Path,
    pub restart: &'a Path,
    pub part: &'a ResponsePart,
}

impl ResponseFile {
    /// Creates `response.npy` in `dir` for the velocities of `dofs`, or continues the rows of
    /// the run resumed (`prior`).
    pub fn open(
        dir: &RunDir,
        dofs: &[usize],
        prior: Option<PriorResponse<'_>>,
    ) -> Result<Self, PipelineError> {
        let path = dir.path(RESPONSE_FILE);
        let cols = 2 * dofs.len() + 1;
        let file = match prior.and_then(|p| p.part.response_rows.map(|k| (p, k))) {
            Some((p, rows)) => {
                same_response(p.restart, &p.part.response_dofs, dofs)?;
                NpyAppender::resume(&p.folder.join(RESPONSE_FILE), &path, cols, rows)?
            }
            None => NpyAppender::create(&path, cols)?,
        };
        Ok(Self {
            dofs: dofs.to_vec(),
            file,
            row: Vec::with_capacity(cols),
        })
    }
}

impl Sink for ResponseFile {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        self.row.clear();
        self.row.push(s.t);
        self.row.extend(self.dofs.iter().map(|&d| s.y[d]));
        self.row.extend(self.dofs.iter().map(|&d| s.yp[d]));
        self.file.push(&self.row)
    }
    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        match c.failed {
            true => {
                let _ = self.file.flush();
                Ok(())
            }
            false => self.file.flush(),
        }
    }
    fn end(&mut self, _: &EndView<'_>) -> Result<(), PipelineError> {
        self.file.flush()
    }
    fn save(&self, c: &mut Checkpoint) -> Result<(), PipelineError> {
        c.save(
            Some("records"),
            &ResponsePart {
                response_rows: Some(self.file.rows()),
                response_dofs: self.dofs.clone(),
            },
        )
    }
}
