//! The run folder: every file a verb writes goes through here, atomically (temp file + rename),
//! so an interrupted run never leaves a half-written file in place of a good one.

use crate::error::PipelineError;
use serde::Serialize;
use std::path::{Path, PathBuf};

/// The `--out` folder of one run.
#[derive(Debug, Clone)]
pub struct RunDir {
    pub root: PathBuf,
}

impl RunDir {
    /// Creates the folder (and parents) if needed.
    pub fn create(root: &Path) -> Result<RunDir, PipelineError> {
        std::fs::create_dir_all(root).map_err(|source| PipelineError::Io {
            path: root.to_path_buf(),
            source,
        })?;
        Ok(RunDir {
            root: root.to_path_buf(),
        })
    }

    /// Path of a file inside the run folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.root.join(name)
    }

    /// A sub-folder, created if needed.
    pub fn subdir(&self, name: &str) -> Result<PathBuf, PipelineError> {
        let p = self.root.join(name);
        std::fs::create_dir_all(&p).map_err(|source| PipelineError::Io {
            path: p.clone(),
            source,
        })?;
        Ok(p)
    }

    /// Writes bytes atomically.
    pub fn write_bytes(&self, name: &str, bytes: &[u8]) -> Result<PathBuf, PipelineError> {
        let path = self.path(name);
        write_atomic(&path, bytes)?;
        Ok(path)
    }

    /// Writes pretty JSON atomically.
    pub fn write_json<T: Serialize>(
        &self,
        name: &str,
        value: &T,
    ) -> Result<PathBuf, PipelineError> {
        let text = serde_json::to_string_pretty(value).map_err(|e| PipelineError::Output {
            path: self.path(name),
            message: e.to_string(),
        })?;
        self.write_bytes(name, text.as_bytes())
    }
}

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PipelineError> {
    let tmp = path.with_extension(format!(
        "{}.tmp",
        path.extension().and_then(|e| e.to_str()).unwrap_or("")
    ));
    std::fs::write(&tmp, bytes).map_err(|source| PipelineError::Io {
        path: tmp.clone(),
        source,
    })?;
    std::fs::rename(&tmp, path).map_err(|source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    })
}
