//! A cache of single components' Craig–Bampton reductions, inside the model cache
//! (`<cache>/components/<key>/`).
//!
//! A component's reduced K and M and its projected brake load depend only on what
//! `reduce_component` reads: its mesh (nodes and cells, after any `rotate_deg`), its
//! materials and hex8 formulation, its fixed DOFs, its boundary DOFs (with their grid ids),
//! the Craig–Bampton options and its unit load vector. The key hashes exactly those values
//! (and the build id), so it is content-addressed: a sweep over a pad's `rotate_deg` changes
//! the pads' keys but not the rotor's when the rotor's boundary does not depend on the pads
//! (`boundary = "contact_faces"`), and the rotor's reduction is read back instead of
//! recomputed. The entry holds the reduced matrices, not Ψ and Φ: a model built from a hit has
//! no per-component recovery data (as every model read through the cache).
//!
//! Entries are written atomically (a temporary folder renamed into place); an entry whose
//! data does not match its recorded size and hash is reported and rebuilt.

use super::key::hex128;
use crate::error::PipelineError;
use faer::Mat;
use serde::{Deserialize, Serialize};
use squeal_fe::SolidMaterial;
use squeal_meshes::Mesh;
use squeal_reduction::cb::CbOptions;
use squeal_reduction::superelement::DofKey;
use std::path::{Path, PathBuf};

use squeal_solver::Real;

/// Version of the component entry layout and key bytes; bump it when either changes.
pub const COMPONENT_CACHE_FORMAT: u32 = 1;

const META: &str = "component.json";
const DATA: &str = "reduction.bin";

/// The cache folder of component reductions.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ComponentCache {
    pub root: PathBuf,
}

/// How one component's reduction was obtained (in the component's report).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ComponentCacheUse {
    /// The component key (32 hex digits, the entry's folder name).
    pub key: String,
    /// True: read from the cache; false: reduced (and stored).
    pub hit: bool,
    /// Seconds to read (hit) or reduce and store (miss).
    pub seconds: Real,
    /// An unusable entry that was rebuilt, or an entry that could not be stored.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub note: Option<String>,
}

/// A component reduction as stored: [u_b, q] ordering, as `CbModel`.
#[derive(Debug, Clone)]
pub struct StoredReduction {
    pub k: Mat<Real>,
    pub m: Mat<Real>,
    /// Projected unit brake load f_r = Tᵀ f.
    pub load: Vec<Real>,
    pub n_boundary: usize,
    pub n_modes: usize,
    /// Free DOFs of the full component.
    pub n_dofs: usize,
    pub fixed_frequencies_hz: Vec<Real>,
}

#[derive(Serialize, Deserialize)]
struct Meta {
    format: u32,
    key: String,
    component: String,
    n_boundary: usize,
    n_modes: usize,
    n_dofs: usize,
    fixed_frequencies_hz: Vec<Real>,
    /// Bytes and hash of `reduction.bin` (K, M row by row, then the load; f64 little-endian).
    data_bytes: usize,
    data_hash: String,
    build_s: Real,
}

/// What the key of a component reduction is made of.
pub struct ComponentInputs<'a> {
    pub name: &'a str,
    pub mesh: &'a Mesh,
    pub materials: &'a [SolidMaterial],
    pub hex8: &'a squeal_fe::Hex8Formulation,
    /// Fixed (node, component) pairs.
    pub fixed: &'a [(usize, usize)],
    /// Boundary free-DOF indices, in reduced order, and their grid keys.
    pub boundary: &'a [usize],
    pub keys: &'a [DofKey],
    pub cb: &'a CbOptions,
    /// The unit brake load on the free DOFs.
    pub load: &'a [Real],
}

fn push_f64s(buf: &mut Vec<u8>, xs: impl IntoIterator<Item = Real>) {
    for x in xs {
        buf.extend_from_slice(&x.to_bits().to_le_bytes());
    }
}

fn push_u64s(buf: &mut Vec<u8>, xs: impl IntoIterator<Item = u64>) {
    for x in xs {
        buf.extend_from_slice(&x.to_le_bytes());
    }
}

fn push_text(buf: &mut Vec<u8>, tag: &str, text: &str) {
    push_u64s(buf, [text.len() as u64]);
    buf.extend_from_slice(tag.as_bytes());
    buf.extend_from_slice(text.as_bytes());
}

impl ComponentInputs<'_> {
    /// The key: 32 hex digits of [`hex128`] over every input, each length-prefixed.
    pub fn key(&self) -> Result<String, PipelineError> {
        let name = self.name;
        fn json<T: Serialize + ?Sized>(
            name: &str,
            what: &str,
            v: &T,
        ) -> Result<String, PipelineError> {
            serde_json::to_string(v).map_err(|e| {
                PipelineError::Model(format!("component `{name}` cache key, {what}: {e}"))
            })
        }
        let mut b = Vec::new();
        push_text(&mut b, "format", &COMPONENT_CACHE_FORMAT.to_string());
        push_text(&mut b, "version", crate::VERSION);
        push_text(&mut b, "build", env!("SQUEAL_BUILD_ID"));
        push_text(&mut b, "name", self.name);
        push_text(
            &mut b,
            "materials",
            &json(name, "materials", self.materials)?,
        );
        push_text(&mut b, "hex8", &json(name, "hex8", self.hex8)?);
        push_text(&mut b, "cb", &json(name, "Craig–Bampton options", self.cb)?);
        push_u64s(&mut b, [self.mesh.nodes.len() as u64]);
        push_f64s(&mut b, self.mesh.nodes.iter().flatten().copied());
        for v in &self.mesh.volumes {
            push_u64s(&mut b, [u64::from(v.kind.vtk_type()), v.conn.len() as u64]);
            push_u64s(&mut b, v.conn.iter().map(|&n| n as u64));
        }
        push_u64s(&mut b, [self.fixed.len() as u64]);
        push_u64s(
            &mut b,
            self.fixed.iter().flat_map(|&(n, k)| [n as u64, k as u64]),
        );
        push_u64s(&mut b, [self.boundary.len() as u64]);
        push_u64s(&mut b, self.boundary.iter().map(|&i| i as u64));
        push_u64s(
            &mut b,
            self.keys.iter().flat_map(|k| [k.grid, u64::from(k.comp)]),
        );
        push_u64s(&mut b, [self.load.len() as u64]);
        push_f64s(&mut b, self.load.iter().copied());
        Ok(hex128(&b))
    }
}

fn stamp() -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map_or(0, |d| d.as_nanos());
    format!("{}-{nanos}", std::process::id())
}

fn data_bytes(r: &StoredReduction) -> Vec<u8> {
    let n = r.k.nrows();
    let mut b = Vec::with_capacity(8 * (2 * n * n + n));
    for mat in [&r.k, &r.m] {
        for i in 0..n {
            push_f64s(&mut b, (0..n).map(|j| mat[(i, j)]));
        }
    }
    push_f64s(&mut b, r.load.iter().copied());
    b
}

impl ComponentCache {
    /// The component cache of a model cache folder: `<root>/components`.
    pub fn in_model_cache(root: &Path) -> ComponentCache {
        ComponentCache {
            root: root.join("components"),
        }
    }

    /// The entry of `key`, or why it cannot be used (`Ok(None)`: no entry).
    pub fn read(&self, key: &str) -> Result<Option<StoredReduction>, String> {
        let dir = self.root.join(key);
        if !dir.exists() {
            return Ok(None);
        }
        let meta: Meta = std::fs::read_to_string(dir.join(META))
            .map_err(|e| format!("{META}: {e}"))
            .and_then(|t| serde_json::from_str(&t).map_err(|e| format!("{META}: {e}")))?;
        if meta.format != COMPONENT_CACHE_FORMAT || meta.key != key {
            return Err(format!(
                "{META}: format {} key {} (expected {COMPONENT_CACHE_FORMAT}, {key})",
                meta.format, meta.key
            ));
        }
        let bytes = std::fs::read(dir.join(DATA)).map_err(|e| format!("{DATA}: {e}"))?;
        let n = meta.n_boundary + meta.n_modes;
        if bytes.len() != meta.data_bytes || bytes.len() != 8 * (2 * n * n + n) {
            return Err(format!(
                "{DATA}: {} bytes, expected {} for {n} reduced DOFs",
                bytes.len(),
                8 * (2 * n * n + n)
            ));
        }
        if hex128(&bytes) != meta.data_hash {
            return Err(format!("{DATA}: content does not match its recorded hash"));
        }
        let x: Vec<Real> = bytes
            .chunks_exact(8)
            .map(|c| Real::from_bits(u64::from_le_bytes(c.try_into().unwrap_or([0; 8]))))
            .collect();
        let (k, rest) = x.split_at(n * n);
        let (m, load) = rest.split_at(n * n);
        Ok(Some(StoredReduction {
            k: Mat::from_fn(n, n, |i, j| k[i * n + j]),
            m: Mat::from_fn(n, n, |i, j| m[i * n + j]),
            load: load.to_vec(),
            n_boundary: meta.n_boundary,
            n_modes: meta.n_modes,
            n_dofs: meta.n_dofs,
            fixed_frequencies_hz: meta.fixed_frequencies_hz,
        }))
    }

    /// Removes an unusable entry (renamed aside first, so no reader sees it half deleted).
    pub fn discard(&self, key: &str) {
        let dir = self.root.join(key);
        let aside = self.root.join(format!(".trash-{key}-{}", stamp()));
        if std::fs::rename(&dir, &aside).is_ok() {
            let _ = std::fs::remove_dir_all(&aside);
        }
    }

    /// Stores `r` under `key` (a temporary folder renamed into place; when another process
    /// stored the same key first, its entry is kept).
    pub fn store(
        &self,
        key: &str,
        component: &str,
        r: &StoredReduction,
        build_s: Real,
    ) -> Result<(), String> {
        std::fs::create_dir_all(&self.root).map_err(|e| format!("{}: {e}", self.root.display()))?;
        let tmp = self.root.join(format!(".tmp-{key}-{}", stamp()));
        let io = |p: &Path, e: std::io::Error| format!("{}: {e}", p.display());
        std::fs::create_dir(&tmp).map_err(|e| io(&tmp, e))?;
        let bytes = data_bytes(r);
        let meta = Meta {
            format: COMPONENT_CACHE_FORMAT,
            key: key.to_string(),
            component: component.to_string(),
            n_boundary: r.n_boundary,
            n_modes: r.n_modes,
            n_dofs: r.n_dofs,
            fixed_frequencies_hz: r.fixed_frequencies_hz.clone(),
            data_bytes: bytes.len(),
            data_hash: hex128(&bytes),
            build_s,
        };
        let text = serde_json::to_string_pretty(&meta).map_err(|e| e.to_string())?;
        let done = std::fs::write(tmp.join(DATA), &bytes)
            .and_then(|()| std::fs::write(tmp.join(META), text))
            .map_err(|e| io(&tmp, e))
            .and_then(|()| {
                let path = self.root.join(key);
                match std::fs::rename(&tmp, &path) {
                    Ok(()) => Ok(()),
                    Err(_) if path.join(META).is_file() => Ok(()),
                    Err(e) => Err(io(&path, e)),
                }
            });
        if tmp.exists() {
            let _ = std::fs::remove_dir_all(&tmp);
        }
        done
    }
}
