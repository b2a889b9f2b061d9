//! Resuming a run from its restart file.
//!
//! [`Resume::load`] reads the file ([`RestartFile::read`]: the model, the state) and has every
//! part of its checkpoint checked by the sink that owns it — the driver's counters and energy
//! integrals, the run's origin, the contact monitor, the count by order, the history's rows,
//! the response's rows — before anything runs. Errors name the file and the field.
//!
//! The run is a true resume when its records lie beside the restart file (its folder is the
//! run folder that wrote it): the history files are checked against the counts and the
//! response is read back; the records are then cut back to the counts (rows written after it,
//! before a kill, are dropped) and continued, into the same folder or a new one (which then
//! gets the earlier rows too); the energy integrals, counters and contact monitor continue;
//! the verdict reads the whole response. The result equals the uninterrupted run's bit for
//! bit. Without those records (a restart file copied elsewhere, or written by an older
//! squeal) the run continues the state alone, with a warning: its records and verdict start
//! at the restart.

use super::collect::contact::ContactPart;
use super::collect::orders::OrdersPart;
use super::collect::response::Recorded;
use super::driver::DriverPart;
use super::files::history::Prior;
use super::files::history_part::HistoryPart;
use super::files::response::{PriorResponse, ResponsePart, RESPONSE_FILE};
use super::restart::RestartFile;
use super::sink::Saved;
use super::start::Origin;
use crate::error::PipelineError;
use crate::warning::Warning;
use std::path::{Path, PathBuf};

/// The parts of a restart file's checkpoint, each read and checked by its owner.
#[derive(Debug, Clone)]
pub struct Parts {
    pub driver: DriverPart,
    pub origin: Origin,
    pub contact: ContactPart,
    pub orders: OrdersPart,
    pub history: HistoryPart,
    pub response: ResponsePart,
}

impl Parts {
    /// Every part of `s`, checked.
    fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        let origin = Origin::restore(s)?;
        let driver = DriverPart::restore(s)?;
        Ok(Self {
            contact: ContactPart::restore(s)?,
            orders: OrdersPart::restore(s)?,
            history: HistoryPart::restore(s, origin.t_start)?,
            response: ResponsePart::restore(s)?,
            driver,
            origin,
        })
    }
}

/// How a run continues a restart file.
#[derive(Debug, Clone)]
pub struct Resume {
    /// The restart file.
    pub path: PathBuf,
    pub file: RestartFile,
    /// Its checkpoint's parts (None: the file holds none).
    pub parts: Option<Parts>,
    /// The run folder whose records the run continues, and the response read back from it
    /// (None: the state alone).
    pub records: Option<(PathBuf, Recorded)>,
    /// Why the run continues the state alone.
    pub warning: Option<Warning>,
}

impl Resume {
    /// Reads the restart file `path` (checked against the model, [`RestartFile::read`]) and
    /// its checkpoint; when the run's records lie beside it, checks them and reads the
    /// response.
    pub fn load(path: &Path, model_hash: &str, n: usize, ng: usize) -> Result<Self, PipelineError> {
        let file = RestartFile::read(path, model_hash, n, ng)?;
        let parts = match &file.run {
            Some(c) => Some(Parts::restore(&Saved {
                checkpoint: c,
                path,
                t: file.t,
                steps: file.state.stats.steps,
                n,
            })?),
            None => None,
        };
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
        let (records, warning) = match &parts {
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
            Some(p) => {
                p.history.check_files(&folder, path)?;
                let response = p.response.read(&folder, path)?;
                (Some((folder, response)), None)
            }
        };
        Ok(Resume {
            path: path.to_path_buf(),
            file,
            parts,
            records,
            warning,
        })
    }

    /// The checkpoint's parts, when the run continues its records (a true resume).
    pub fn checkpoint(&self) -> Option<&Parts> {
        self.records.as_ref().and(self.parts.as_ref())
    }

    /// The history files the run continues (a true resume).
    pub fn history(&self) -> Option<Prior<'_>> {
        let (folder, _) = self.records.as_ref()?;
        Some(Prior {
            folder,
            restart: &self.path,
            part: &self.parts.as_ref()?.history,
        })
    }

    /// The response file the run continues (a true resume).
    pub fn response_file(&self) -> Option<PriorResponse<'_>> {
        let (folder, _) = self.records.as_ref()?;
        Some(PriorResponse {
            folder,
            restart: &self.path,
            part: &self.parts.as_ref()?.response,
        })
    }

    /// The response recorded up to the restart (a true resume).
    pub fn response(&self) -> Option<&Recorded> {
        self.records.as_ref().map(|(_, r)| r)
    }
}
