//! The run folder: every file a verb writes goes through here, atomically (temp file, fsync,
//! rename, fsync of the folder), so an interrupted run — or a crash of the machine — never
//! leaves a half-written file in place of a good one.

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

/// Writes `bytes` to `path` through a temporary file in the same folder and a rename: the
/// temporary file is flushed to disk (fsync) before the rename and, on Unix, the folder after
/// it, so that after a crash or power loss `path` holds either the old contents or the new
/// ones, never a renamed but empty or partial file.
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), PipelineError> {
    let tmp = path.with_extension(format!(
        "{}.tmp",
        path.extension().and_then(|e| e.to_str()).unwrap_or("")
    ));
    let io = |p: &Path| {
        let p = p.to_path_buf();
        move |source| PipelineError::Io { path: p, source }
    };
    write_synced(&tmp, bytes).map_err(io(&tmp))?;
    std::fs::rename(&tmp, path).map_err(io(path))?;
    sync_parent(path).map_err(io(path))
}

/// Writes a file and flushes it to disk (fsync) before returning.
pub fn write_synced(path: &Path, bytes: &[u8]) -> std::io::Result<()> {
    use std::io::Write;
    let mut f = std::fs::File::create(path)?;
    f.write_all(bytes)?;
    f.sync_all()
}

/// Flushes the folder holding `path` (its directory entries: a rename into it) to disk. A
/// no-op where folders cannot be opened as files (Windows).
pub fn sync_parent(path: &Path) -> std::io::Result<()> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    sync_dir(dir)
}

/// Flushes a folder's directory entries to disk (Unix; a no-op elsewhere).
pub fn sync_dir(dir: &Path) -> std::io::Result<()> {
    #[cfg(unix)]
    {
        std::fs::File::open(dir)?.sync_all()
    }
    #[cfg(not(unix))]
    {
        let _ = dir;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_the_file_and_leaves_no_temporary() {
        let dir = std::env::temp_dir().join(format!("squeal-atomic-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join("restart.json");
        write_atomic(&p, b"old").unwrap();
        write_atomic(&p, b"new contents").unwrap();
        assert_eq!(std::fs::read(&p).unwrap(), b"new contents");
        let names: Vec<_> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name())
            .collect();
        assert_eq!(names, vec![std::ffi::OsString::from("restart.json")]);
        std::fs::remove_dir_all(&dir).ok();
    }
}
