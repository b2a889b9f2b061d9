//! The history of a run — `history.npy` + `history_map.json` and `energy.csv`, or the same rows
//! in memory ([`History`]) — written by the [`Recorder`]; a resumed run continues the rows its
//! checkpoint counts ([`HistoryPart`]).

use super::super::sink::{Checkpoint, ChunkView, EndView, Sink, StepView};
use super::columns::{columns, fill_row, ENERGY_HEADER};
use super::history_part::{continue_lines, HistoryPart};
use crate::error::PipelineError;
use crate::history::npy::NpyAppender;
use crate::history::{Column, HistoryMap};
use crate::model::ReducedModel;
use crate::output::RunDir;
use crate::scene::Scene;
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::Real;
use std::io::Write;
use std::path::{Path, PathBuf};

/// The records a resumed run continues: the run folder that wrote them, the restart file
/// (named in errors) and the checkpoint's counts.
#[derive(Debug, Clone, Copy)]
pub struct Prior<'a> {
    pub folder: &'a Path,
    pub restart: &'a Path,
    pub part: &'a HistoryPart,
}

/// The recorded history of a run, in memory: the rows `history.npy` holds, and the rows of
/// `energy.csv`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct History {
    /// What each column is (column 0 is t).
    pub columns: Vec<Column>,
    /// Row-major values, `columns.len()` per row.
    pub values: Vec<Real>,
    /// One row per recorded step after the initial point: the columns of [`ENERGY_HEADER`].
    pub energy: Vec<[Real; 8]>,
}

impl History {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.values.len() / self.columns.len().max(1)
    }

    /// Column `name` as a vector (None: no such column).
    pub fn column(&self, name: &str) -> Option<Vec<Real>> {
        let c = self.columns.iter().position(|c| c.name == name)?;
        let w = self.columns.len();
        Some(self.values.iter().skip(c).step_by(w).copied().collect())
    }
}

/// The history of a run — initial point, every NOUTPT-th accepted step, the final time — and
/// its energy rows, written to `history.npy` + `history_map.json` and `energy.csv` when given a
/// folder and `output.history` is on, and kept in memory when asked ([`History`]). With
/// `output.history = false` nothing is opened, written or kept (effects on demand); the
/// columns are still known (for the verdict's response).
pub struct Recorder {
    cols: Vec<Column>,
    gaps: GapSet,
    n: usize,
    noutpt: usize,
    row: Vec<Real>,
    history: Option<NpyAppender>,
    energy: Option<std::io::BufWriter<std::fs::File>>,
    memory: Option<History>,
    history_path: PathBuf,
    energy_path: PathBuf,
    /// Time of the last history row.
    last_t: Option<Real>,
    rows: usize,
    /// Rows of the energy file.
    energy_rows: usize,
    /// The initial point was recorded (or the run resumed records that hold it).
    started: bool,
}

impl Recorder {
    /// The recorder of `scene`'s `[output]` on `model` with its `gaps` (at the operating point): files in `dir` (when given; writes
    /// `history_map.json` and opens `history.npy` and `energy.csv`), rows in memory when
    /// `keep`. Errors name the grids or gaps the scene asks for that do not exist.
    pub fn open(
        scene: &Scene,
        model: &ReducedModel,
        gaps: &GapSet,
        dir: Option<&RunDir>,
        keep: bool,
    ) -> Result<Self, PipelineError> {
        Self::open_resumed(scene, model, gaps, dir, keep, None)
    }

    /// [`Recorder::open`] continuing the records of a resumed run: the files get the rows
    /// `prior` counts (cut back to them in the same folder, copied into a new one) and are
    /// appended to; in memory, those rows are read back.
    pub fn open_resumed(
        scene: &Scene,
        model: &ReducedModel,
        gaps: &GapSet,
        dir: Option<&RunDir>,
        keep: bool,
        resumed: Option<Prior<'_>>,
    ) -> Result<Self, PipelineError> {
        let cols = columns(scene, model)?;
        let noutpt = scene.transient.as_ref().map_or(1, |t| t.noutpt).max(1);
        let (history_path, energy_path) = match dir {
            Some(d) => (d.path("history.npy"), d.path("energy.csv")),
            None => (PathBuf::from("history.npy"), PathBuf::from("energy.csv")),
        };
        let on = scene.output.history;
        // What the resumed run recorded (its records, history rows, energy rows).
        let prior = match resumed.filter(|_| on) {
            Some(r) => {
                r.part.check_columns(r.folder, &cols)?;
                match (r.part.history_rows, r.part.energy_rows) {
                    (Some(h), Some(e)) => Some((r, h, e)),
                    _ => {
                        return Err(PipelineError::Scene {
                            field: "output.history".into(),
                            message: format!(
                                "the run resumed ({}) wrote no history (output.history = false): \
                                 resume it with output.history = false too",
                                r.restart.display()
                            ),
                        })
                    }
                }
            }
            None => None,
        };
        let (mut history, mut energy) = (None, None);
        if let (Some(dir), true) = (dir, on) {
            dir.write_json(
                "history_map.json",
                &HistoryMap {
                    n_columns: cols.len(),
                    noutpt,
                    columns: cols.clone(),
                },
            )?;
            let eio = |source| PipelineError::Io {
                path: energy_path.clone(),
                source,
            };
            match prior {
                Some((r, h, e)) => {
                    history = Some(NpyAppender::resume(
                        &r.folder.join("history.npy"),
                        &history_path,
                        cols.len(),
                        h,
                    )?);
                    continue_lines(&r.folder.join("energy.csv"), &energy_path, e)?;
                    let f = std::fs::OpenOptions::new()
                        .append(true)
                        .open(&energy_path)
                        .map_err(eio)?;
                    energy = Some(std::io::BufWriter::new(f));
                }
                None => {
                    history = Some(NpyAppender::create(&history_path, cols.len())?);
                    let mut e =
                        std::io::BufWriter::new(std::fs::File::create(&energy_path).map_err(eio)?);
                    writeln!(e, "{ENERGY_HEADER}").map_err(eio)?;
                    energy = Some(e);
                }
            }
        }
        let mut memory = (keep && on).then(|| History {
            columns: cols.clone(),
            ..Default::default()
        });
        if let (Some(m), Some((r, h, e))) = (memory.as_mut(), prior) {
            read_back(r, h, e, m)?;
        }
        let (rows, energy_rows, last_t) = match prior {
            Some((r, h, e)) => (h, e, r.part.history_last_t),
            None => (0, 0, None),
        };
        Ok(Self {
            row: Vec::with_capacity(cols.len()),
            memory,
            cols,
            gaps: gaps.clone(),
            n: model.n(),
            noutpt,
            history,
            energy,
            history_path,
            energy_path,
            last_t,
            rows,
            energy_rows,
            started: resumed.is_some(),
        })
    }

    /// The columns of the history.
    pub fn columns(&self) -> &[Column] {
        &self.cols
    }

    /// Rows recorded so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The history kept in memory (None unless asked for), leaving none behind.
    pub fn take_history(&mut self) -> Option<History> {
        self.memory.take()
    }

    fn recording(&self) -> bool {
        self.history.is_some() || self.memory.is_some()
    }

    /// A history row at (t, y, y') (no energy line).
    pub fn point(&mut self, t: Real, y: &[Real], yp: &[Real]) -> Result<(), PipelineError> {
        if !self.recording() {
            return Ok(());
        }
        fill_row(&self.cols, &self.gaps, self.n, t, y, yp, &mut self.row)
            .map_err(PipelineError::Model)?;
        if let Some(h) = self.history.as_mut() {
            h.push(&self.row)?;
        }
        if let Some(m) = self.memory.as_mut() {
            m.values.extend_from_slice(&self.row);
        }
        self.last_t = Some(t);
        self.rows += 1;
        Ok(())
    }

    /// On every NOUTPT-th accepted step: a history row and an energy row (the energies at `p`,
    /// the integrals of `balance`).
    fn record_step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        if s.step % self.noutpt != 0 || !self.recording() {
            return Ok(());
        }
        self.point(s.t, s.y, s.yp)?;
        let (kinetic, strain) = s.power.map_or((0.0, 0.0), |p| (p.kinetic, p.strain));
        let b = s.balance;
        let e = [
            s.t,
            kinetic,
            strain,
            b.damping_dissipated,
            b.friction_work,
            b.external_work,
            b.constraint_work,
            b.residual(),
        ];
        if let Some(m) = self.memory.as_mut() {
            m.energy.push(e);
        }
        if let Some(w) = self.energy.as_mut() {
            self.energy_rows += 1;
            writeln!(
                w,
                "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7]
            )
            .map_err(|source| PipelineError::Io {
                path: self.energy_path.clone(),
                source,
            })?;
        }
        Ok(())
    }

    /// Makes both files complete and valid up to the last record.
    pub fn flush(&mut self) -> Result<(), PipelineError> {
        if let Some(h) = self.history.as_mut() {
            h.flush()?;
        }
        if let Some(e) = self.energy.as_mut() {
            e.flush().map_err(|source| PipelineError::Io {
                path: self.energy_path.clone(),
                source,
            })?;
        }
        Ok(())
    }

    /// Where the history goes (for error messages).
    pub fn history_path(&self) -> &std::path::Path {
        &self.history_path
    }
}

impl Sink for Recorder {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        if self.started {
            return self.record_step(s);
        }
        self.started = true;
        self.point(s.t, s.y, s.yp)
    }

    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        match c.failed {
            // Keep what was recorded; the chunk's own error is the one reported.
            true => {
                let _ = self.flush();
                Ok(())
            }
            false => self.flush(),
        }
    }

    /// The row at the final time TFINAL (unless the last recorded step ended exactly there, as
    /// fixed steps do), and a flush.
    fn end(&mut self, e: &EndView<'_>) -> Result<(), PipelineError> {
        if e.status.is_success() && self.last_t != Some(e.tfinal) {
            self.point(e.tfinal, e.y, e.yp)?;
        }
        self.flush()
    }

    /// The rows of the files (a recorder in memory writes none and saves nothing).
    fn save(&self, c: &mut Checkpoint) -> Result<(), PipelineError> {
        let mut part = HistoryPart::default();
        if self.history.is_some() {
            part.history_rows = Some(self.rows);
            part.history_columns = Some(self.cols.len());
            part.history_last_t = self.last_t;
        }
        if self.energy.is_some() {
            part.energy_rows = Some(self.energy_rows);
        }
        match part == HistoryPart::default() {
            true => Ok(()),
            false => c.save(Some("records"), &part),
        }
    }
}

/// The first `rows` rows of the history and `energy_rows` rows of the energy of the run `r`
/// resumes, into `m`.
fn read_back(
    r: Prior<'_>,
    rows: usize,
    energy_rows: usize,
    m: &mut History,
) -> Result<(), PipelineError> {
    let (_, cols, data) = crate::history::npy::read_npy(&r.folder.join("history.npy"))?;
    m.values
        .extend_from_slice(&data[..(rows * cols).min(data.len())]);
    let p = r.folder.join("energy.csv");
    let text = std::fs::read_to_string(&p).map_err(|source| PipelineError::Io {
        path: p.clone(),
        source,
    })?;
    for (i, line) in text.lines().skip(1).take(energy_rows).enumerate() {
        let values: Option<Vec<Real>> = line.split(',').map(|x| x.parse().ok()).collect();
        let e: [Real; 8] =
            values
                .and_then(|v| v.try_into().ok())
                .ok_or_else(|| PipelineError::Input {
                    path: p.clone(),
                    message: format!("line {}: not 8 numbers: `{line}`", i + 2),
                })?;
        m.energy.push(e);
    }
    Ok(())
}
