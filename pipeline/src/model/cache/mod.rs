//! A content-addressed cache of reduced models built from meshes (`--cache DIR`, `SQUEAL_CACHE`,
//! and always on in `squeal sweep`).
//!
//! Meshing, assembly and Craig–Bampton reduction depend only on part of the scene ([`key`]);
//! friction, rotor speed, preload, loads' scale (the operating point,
//! [`crate::problem::OperatingPoint`]), damping G/W3/ζ and the solver options are applied
//! when the problem is made. A scene whose key has an entry is therefore read from
//! disk (OP4 + JSON, bit-exact) instead of rebuilt: a sweep over μ builds once.
//!
//! Entries are written atomically (a temporary folder renamed into place); an entry that
//! fails its checks (a file missing, truncated or altered) is reported, removed and rebuilt.
//! Processes sharing the folder take an advisory lock per entry ([`lock`]): the first builds
//! and stores the model, the others wait and read it (where the file system cannot lock,
//! both build, the first rename wins and the other's copy is dropped). Nothing is ever
//! evicted: remove the folder to reclaim the space.

pub mod component;
mod entry;
pub mod key;
pub mod lock;

use super::{build_from_mesh_cached, ReducedModel};
use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::warning::Warning;
use key::ModelKey;
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// A cache folder of reduced models.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelCache {
    pub root: PathBuf,
}

/// How a model was obtained through the cache (in `summary.json` and `sweep.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CacheUse {
    /// The model's key (32 hex digits, the entry's folder name).
    pub key: String,
    /// True: read from the cache; false: built (and stored).
    pub hit: bool,
    /// The entry folder.
    pub entry: String,
    /// Seconds to read (hit) or build and store (miss) the model.
    pub seconds: f64,
    /// Warnings: an unusable entry that was rebuilt, an entry that could not be stored.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

fn stamp() -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!("{}-{nanos}", std::process::id())
}

/// A warning about the cache itself (an entry rebuilt, an entry not stored): `value` 1 (one
/// event), tolerance 0.
fn cache_warning(input: String, message: String) -> Warning {
    Warning {
        input,
        message,
        value: 1.0,
        tolerance: 0.0,
    }
}

/// Removes a folder by renaming it aside first, so no reader ever sees it half deleted.
fn discard(dir: &Path) {
    let aside = dir.with_file_name(format!(
        ".trash-{}-{}",
        dir.file_name().and_then(|n| n.to_str()).unwrap_or("entry"),
        stamp()
    ));
    if std::fs::rename(dir, &aside).is_ok() {
        let _ = std::fs::remove_dir_all(&aside);
    }
}

impl ModelCache {
    /// A cache in `root` (created when the first entry is stored).
    pub fn new(root: impl Into<PathBuf>) -> ModelCache {
        ModelCache { root: root.into() }
    }

    /// The folder of the entry with key `key`.
    pub fn entry_path(&self, key: &ModelKey) -> PathBuf {
        self.root.join(&key.hex)
    }

    /// The scene's reduced model from its entry, without building: `Ok(None)` when there is no
    /// entry; an unusable entry (a file missing, altered or failing the model checks) is an
    /// error naming the entry and the file, and is left in place.
    pub fn read(&self, scene: &Scene) -> Result<Option<ReducedModel>, PipelineError> {
        let key = ModelKey::of(scene)?;
        let path = self.entry_path(&key);
        if !path.exists() {
            return Ok(None);
        }
        let cached = entry::read_entry(&path, &key).map_err(|why| PipelineError::Input {
            path: path.clone(),
            message: format!("unusable cache entry: {why}"),
        })?;
        entry::finish(scene, cached)
            .map(Some)
            .map_err(|e| PipelineError::Input {
                path,
                message: format!("unusable cache entry: {e}"),
            })
    }

    /// The scene's reduced model: read from the entry of its key when there is a valid one,
    /// else built with [`super::build_from_mesh`] (without the Craig–Bampton checks, which change no
    /// matrix) and stored. Either way the model has no per-component recovery data, so results
    /// do not depend on whether the cache hit.
    pub fn get_or_build(
        &self,
        scene: &Scene,
        dir: &RunDir,
        progress: &Progress,
    ) -> Result<(ReducedModel, CacheUse), PipelineError> {
        let start = Instant::now();
        let key = ModelKey::of(scene)?;
        let path = self.entry_path(&key);
        // Held until the entry is read, or built and stored (dropped on return).
        let held = lock::lock_entry(
            &self.root,
            &key.hex,
            &format!("model {}", key.hex),
            progress,
        )?;
        let mut note = match &held {
            lock::EntryLock::Held(_) => None,
            lock::EntryLock::Unsupported(why) => Some(why.clone()),
        };
        if path.exists() {
            match entry::read_entry(&path, &key) {
                Ok(cached) => {
                    let model = entry::finish(scene, cached)?;
                    let seconds = start.elapsed().as_secs_f64();
                    progress.info(format!(
                        "model: cache hit {} ({} DOFs, {} gaps, read in {seconds:.2} s)",
                        key.hex,
                        model.n(),
                        model.gap_geometry.len()
                    ));
                    return Ok((
                        model,
                        CacheUse {
                            key: key.hex,
                            hit: true,
                            entry: path.display().to_string(),
                            seconds,
                            note,
                        },
                    ));
                }
                Err(why) => {
                    let msg = format!(
                        "cache entry {} is unusable ({why}); rebuilding it",
                        path.display()
                    );
                    discard(&path);
                    note = Some(msg);
                }
            }
        }
        let mut plain = scene.clone();
        plain.reduction.get_or_insert_with(Default::default).checks = false;
        let components = component::ComponentCache::in_model_cache(&self.root);
        let mut model = build_from_mesh_cached(&plain, dir, progress, Some(&components))?;
        model.recovery.clear();
        let build_s = start.elapsed().as_secs_f64();
        if let Err(e) = self.store(&key, &model, build_s) {
            let msg = format!("could not store the model in {}: {e}", self.root.display());
            note = Some(match note {
                Some(n) => format!("{n}; {msg}"),
                None => msg,
            });
        }
        // What happened to the cache on this build (not stored in the entry: a reuse does
        // not repeat it) reaches the caller as warnings: summary.json, stderr.
        let component_notes = model.components.iter().filter_map(|c| {
            let note = c.reduction_cache.as_ref()?.note.clone()?;
            Some(cache_warning(
                format!("component cache (`{}`)", c.name),
                note,
            ))
        });
        let notes: Vec<Warning> = note
            .iter()
            .map(|n| cache_warning(format!("model cache {}", self.root.display()), n.clone()))
            .chain(component_notes)
            .collect();
        model.warnings.extend(notes);
        let seconds = start.elapsed().as_secs_f64();
        progress.info(format!(
            "model: cache miss {}, built and stored in {seconds:.2} s",
            key.hex
        ));
        Ok((
            model,
            CacheUse {
                key: key.hex,
                hit: false,
                entry: path.display().to_string(),
                seconds,
                note,
            },
        ))
    }

    /// Writes the entry of `key` into a temporary folder and renames it into place.
    fn store(
        &self,
        key: &ModelKey,
        model: &ReducedModel,
        build_s: f64,
    ) -> Result<(), PipelineError> {
        std::fs::create_dir_all(&self.root).map_err(|source| PipelineError::Io {
            path: self.root.clone(),
            source,
        })?;
        let tmp = self.root.join(format!(".tmp-{}-{}", key.hex, stamp()));
        std::fs::create_dir(&tmp).map_err(|source| PipelineError::Io {
            path: tmp.clone(),
            source,
        })?;
        let path = self.entry_path(key);
        let done = entry::write_entry(&tmp, key, model, build_s).and_then(|()| {
            std::fs::rename(&tmp, &path)
                .and_then(|()| crate::output::sync_dir(&self.root))
                .or_else(|source| {
                    // Another process stored the same key first: keep its entry.
                    if path.join(entry::META).is_file() {
                        Ok(())
                    } else {
                        Err(PipelineError::Io {
                            path: path.clone(),
                            source,
                        })
                    }
                })
        });
        if tmp.exists() {
            let _ = std::fs::remove_dir_all(&tmp);
        }
        done
    }
}
