//! The history's part of a restart checkpoint: the rows of `history.npy` and `energy.csv`
//! written up to the restart point, checked against the files a resumed run continues.

use super::super::sink::Saved;
use super::columns::ENERGY_HEADER;
use crate::error::PipelineError;
use crate::history::npy::read_header;
use crate::history::{Column, HistoryMap};
use crate::output::write_atomic;
use serde::{Deserialize, Serialize};
use squeal_solver::Real;
use std::io::BufRead;
use std::path::Path;

/// Rows of the history files at a restart point (None: the run does not write that file);
/// section `records` of the checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct HistoryPart {
    /// Rows of `history.npy`.
    pub history_rows: Option<usize>,
    /// Its columns.
    pub history_columns: Option<usize>,
    /// Time of its last row.
    pub history_last_t: Option<Real>,
    /// Data rows of `energy.csv` (after the header line).
    pub energy_rows: Option<usize>,
}

/// An error naming the restart file and the field of the counts.
fn bad(restart: &Path, field: &str, message: String) -> PipelineError {
    PipelineError::Input {
        path: restart.to_path_buf(),
        message: format!("field `run.records.{field}`: {message}"),
    }
}

impl HistoryPart {
    /// The part saved in a checkpoint: rows, columns and last time go together, the last time
    /// between the run's start `t_start` and the state's time.
    pub fn restore(s: &Saved<'_>, t_start: Real) -> Result<Self, PipelineError> {
        let r: HistoryPart = s.part(Some("records"))?;
        let t = s.t;
        if r.history_rows.is_some() != r.history_columns.is_some()
            || r.history_rows.is_some_and(|k| k > 0) != r.history_last_t.is_some()
        {
            return Err(s.bad(
                "records.history_rows",
                "history_rows, history_columns and history_last_t go together".into(),
            ));
        }
        if r.history_last_t.is_some_and(|h| !(h <= t && h >= t_start)) {
            return Err(s.bad(
                "records.history_last_t",
                format!(
                    "{:?} is not between the start {t_start} and the state's t = {t}",
                    r.history_last_t
                ),
            ));
        }
        Ok(r)
    }

    /// Checks the files in `folder` (the run resumed) against the counts: every file counted
    /// must hold at least that many rows, `history.npy` the same columns and the row time.
    pub fn check_files(&self, folder: &Path, restart: &Path) -> Result<(), PipelineError> {
        if let (Some(rows), Some(cols)) = (self.history_rows, self.history_columns) {
            let p = folder.join("history.npy");
            let h = read_header(&p).map_err(|e| {
                bad(
                    restart,
                    "history_rows",
                    format!("{rows} rows of {} are needed: {e}", p.display()),
                )
            })?;
            if h.cols != cols || h.rows.min(h.data_rows) < rows {
                return Err(bad(
                    restart,
                    "history_rows",
                    format!(
                        "{rows} rows of {cols} columns, but {} holds {} rows of {} columns",
                        p.display(),
                        h.rows.min(h.data_rows),
                        h.cols
                    ),
                ));
            }
            if let Some(t) = self.history_last_t {
                let last = read_value(&p, h.data_offset + (rows - 1) * cols * 8)?;
                if last != t {
                    return Err(bad(
                        restart,
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
        if let Some(rows) = self.energy_rows {
            let p = folder.join("energy.csv");
            let have = count_lines(&p, rows + 1).map_err(|e| {
                bad(
                    restart,
                    "energy_rows",
                    format!("{rows} rows of {} are needed: {e}", p.display()),
                )
            })?;
            if have < rows + 1 {
                return Err(bad(
                    restart,
                    "energy_rows",
                    format!(
                        "{rows} rows, but {} holds {} complete lines after its header",
                        p.display(),
                        have.saturating_sub(1)
                    ),
                ));
            }
        }
        Ok(())
    }

    /// Checks that the history in `folder` continues with `columns` history columns (the
    /// scene's `[output]`), naming the scene field when they changed.
    pub fn check_columns(&self, folder: &Path, columns: &[Column]) -> Result<(), PipelineError> {
        let Some(cols) = self.history_columns else {
            return Ok(());
        };
        let map = HistoryMap::read(&folder.join("history_map.json")).ok();
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
                    folder.join("history.npy").display(),
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
