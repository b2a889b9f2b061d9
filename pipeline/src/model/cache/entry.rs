//! One cache entry on disk, `<cache>/<key>/`:
//!
//! - `reduced.op4`: KR, MR (BR), PBRAKE, binary double precision, exactly as `squeal reduce`
//!   writes them (bit-exact round trip);
//! - `dofmap.json`, `gaps.json` (the gap geometry: nodes, coordinates, normal, area), `grids.json`;
//! - `entry.json`, written last: format, version, the key and its document, sizes, the number of
//!   gaps per contact pair, and the length and [`hash128`] of every file above.
//!
//! An entry is written into a temporary folder beside it and renamed into place, so a reader
//! sees a whole entry or none; [`read_entry`] checks every file against `entry.json` before
//! use. [`finish`] reassigns the gap DOFs of what was read (the scene's late parameters —
//! sliding velocities, P0, temperatures, friction law and VTOL — are the operating point's).

use super::key::{hash128, ModelKey, CACHE_FORMAT};
use crate::error::PipelineError;
use crate::model::grids::GridInfo;
use crate::model::stored::stored_matrices;
use crate::model::ReducedModel;
use crate::model::{gap_table, inputs};
use crate::scene::{ModelSource, Scene};
use faer::Mat;
use serde::{Deserialize, Serialize};
use squeal_contact::{FrictionLaw, Gap, GapSet};
use squeal_reduction::matrix::NamedMatrix;
use squeal_reduction::op4::{self, Op4WriteOptions};
use squeal_reduction::superelement::ReducedDofMap;
use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use squeal_solver::Real;

const OP4: &str = "reduced.op4";
const DOFMAP: &str = "dofmap.json";
const GAPS: &str = "gaps.json";
const GRIDS: &str = "grids.json";
/// Written last; its presence and checksums make the entry valid.
pub(super) const META: &str = "entry.json";

/// Length and hash of one file of the entry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct FileSum {
    bytes: u64,
    hash: String,
}

/// `entry.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
struct EntryMeta {
    format: u32,
    squeal_version: String,
    key: String,
    /// The key document (what was hashed), for inspection.
    key_document: serde_json::Value,
    n_dofs: usize,
    n_gaps: usize,
    gaps_per_pair: Vec<usize>,
    /// Seconds the build took.
    build_s: Real,
    files: BTreeMap<String, FileSum>,
    /// The build's warnings (e.g. pad nodes a surface pairing excluded), repeated on reuse.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    warnings: Vec<crate::warning::Warning>,
}

/// What an entry holds before the late parameters are applied.
pub(super) struct Cached {
    k: Mat<Real>,
    m: Mat<Real>,
    b: Option<Mat<Real>>,
    p_brake: Vec<Real>,
    dofs: ReducedDofMap,
    gaps: Vec<Gap>,
    gaps_per_pair: Vec<usize>,
    grids: Vec<GridInfo>,
    warnings: Vec<crate::warning::Warning>,
}

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> PipelineError + '_ {
    move |source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    }
}

fn json_bytes<T: Serialize>(value: &T, name: &str) -> Result<Vec<u8>, PipelineError> {
    serde_json::to_vec(value).map_err(|e| PipelineError::Output {
        path: name.into(),
        message: e.to_string(),
    })
}

/// Writes the entry's files into the (new, empty) folder `dir`, `entry.json` last.
pub(super) fn write_entry(
    dir: &Path,
    key: &ModelKey,
    model: &ReducedModel,
    build_s: Real,
) -> Result<(), PipelineError> {
    let mats = stored_matrices(model);
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    let op4_bytes = op4::write_bytes(&refs, &Op4WriteOptions::default()).map_err(|source| {
        PipelineError::Reduction {
            what: "writing the cached reduced.op4".into(),
            source,
        }
    })?;
    let files: [(&str, Vec<u8>); 4] = [
        (OP4, op4_bytes),
        (DOFMAP, json_bytes(&model.dofs, DOFMAP)?),
        (GAPS, json_bytes(&model.gap_geometry.gaps, GAPS)?),
        (GRIDS, json_bytes(&model.grids, GRIDS)?),
    ];
    let mut sums = BTreeMap::new();
    for (name, bytes) in &files {
        let p = dir.join(name);
        crate::output::write_synced(&p, bytes).map_err(io_err(&p))?;
        sums.insert(
            name.to_string(),
            FileSum {
                bytes: bytes.len() as u64,
                hash: format!("{:032x}", hash128(bytes)),
            },
        );
    }
    let meta = EntryMeta {
        format: CACHE_FORMAT,
        squeal_version: crate::VERSION.into(),
        key: key.hex.clone(),
        key_document: serde_json::from_str(&key.document).unwrap_or_default(),
        n_dofs: model.n(),
        n_gaps: model.gap_geometry.len(),
        gaps_per_pair: model.gap_pairs.clone(),
        build_s,
        files: sums,
        warnings: model.warnings.clone(),
    };
    let text = serde_json::to_string_pretty(&meta).map_err(|e| PipelineError::Output {
        path: dir.join(META),
        message: e.to_string(),
    })?;
    let p = dir.join(META);
    crate::output::write_synced(&p, text.as_bytes()).map_err(io_err(&p))?;
    crate::output::sync_dir(dir).map_err(io_err(dir))
}

/// Reads and checks an entry; `Err` says why it cannot be used (missing or altered file,
/// another key or format, inconsistent sizes).
pub(super) fn read_entry(dir: &Path, key: &ModelKey) -> Result<Cached, String> {
    let read = |name: &str| std::fs::read(dir.join(name)).map_err(|e| format!("{name}: {e}"));
    let meta: EntryMeta = serde_json::from_slice(&read(META)?)
        .map_err(|e| format!("{META}: not an entry description ({e})"))?;
    if meta.format != CACHE_FORMAT || meta.key != key.hex {
        return Err(format!(
            "{META}: format {} key {}, expected format {CACHE_FORMAT} key {}",
            meta.format, meta.key, key.hex
        ));
    }
    let doc: serde_json::Value = serde_json::from_str(&key.document).unwrap_or_default();
    if meta.key_document != doc {
        return Err(format!(
            "{META}: the key document differs (hash collision?)"
        ));
    }
    let checked = |name: &str| -> Result<Vec<u8>, String> {
        let bytes = read(name)?;
        let sum = meta
            .files
            .get(name)
            .ok_or_else(|| format!("{META} lists no {name}"))?;
        let hash = format!("{:032x}", hash128(&bytes));
        if sum.bytes != bytes.len() as u64 || sum.hash != hash {
            return Err(format!(
                "{name}: {} bytes with hash {hash}, the entry recorded {} bytes with hash {}",
                bytes.len(),
                sum.bytes,
                sum.hash
            ));
        }
        Ok(bytes)
    };
    let op4_bytes = checked(OP4)?;
    let dofs: ReducedDofMap =
        serde_json::from_slice(&checked(DOFMAP)?).map_err(|e| format!("{DOFMAP}: {e}"))?;
    let gaps: Vec<Gap> =
        serde_json::from_slice(&checked(GAPS)?).map_err(|e| format!("{GAPS}: {e}"))?;
    let grids: Vec<GridInfo> =
        serde_json::from_slice(&checked(GRIDS)?).map_err(|e| format!("{GRIDS}: {e}"))?;
    let n = dofs.len();
    let mut named: HashMap<String, Mat<Real>> = HashMap::new();
    for m in op4::read_bytes(&op4_bytes).map_err(|e| format!("{OP4}: {e}"))? {
        let a = m
            .as_real()
            .cloned()
            .ok_or_else(|| format!("{OP4}: matrix {} is complex", m.name))?;
        named.insert(m.name.to_ascii_uppercase(), a);
    }
    let mut take = |name: &str, cols: usize| -> Result<Option<Mat<Real>>, String> {
        match named.remove(name) {
            Some(a) if a.nrows() == n && a.ncols() == cols => Ok(Some(a)),
            Some(a) => Err(format!(
                "{OP4}: {name} is {}x{}, the DOF map has {n} DOFs",
                a.nrows(),
                a.ncols()
            )),
            None => Ok(None),
        }
    };
    let k = take("KR", n)?.ok_or_else(|| format!("{OP4}: no KR"))?;
    let m = take("MR", n)?.ok_or_else(|| format!("{OP4}: no MR"))?;
    let b = take("BR", n)?;
    let p = take("PBRAKE", 1)?.ok_or_else(|| format!("{OP4}: no PBRAKE"))?;
    // The same checks as a stored model's inputs (an entry failing them is rebuilt).
    let at = Path::new(OP4);
    let mut warnings = Vec::new();
    let checks = inputs::check_dofmap(&dofs, Path::new(DOFMAP))
        .and_then(|()| inputs::symmetric("KR", &k, at, &mut warnings))
        .and_then(|_| inputs::symmetric("MR", &m, at, &mut warnings))
        .and_then(|_| inputs::check_mass("MR", &m, at))
        .and_then(|()| {
            b.as_ref()
                .map_or(Ok(()), |b| inputs::check_finite("BR", b, at))
        })
        .and_then(|()| inputs::check_finite("PBRAKE", &p, at));
    checks.map_err(|e| e.to_string())?;
    if !warnings.is_empty() {
        return Err(format!("{OP4}: KR or MR is not symmetric"));
    }
    let places: Vec<String> = (0..gaps.len()).map(|i| format!("gap {i}")).collect();
    gap_table::check_gaps(&gaps, &places, true, false).map_err(|e| format!("{GAPS}: {e}"))?;
    if meta.n_dofs != n
        || meta.n_gaps != gaps.len()
        || meta.gaps_per_pair.iter().sum::<usize>() != gaps.len()
    {
        return Err(format!(
            "{META}: {} DOFs and {} gaps ({:?} per pair), the files hold {n} DOFs and {} gaps",
            meta.n_dofs,
            meta.n_gaps,
            meta.gaps_per_pair,
            gaps.len()
        ));
    }
    Ok(Cached {
        k,
        m,
        b,
        p_brake: (0..n).map(|i| p[(i, 0)]).collect(),
        dofs,
        gaps,
        gaps_per_pair: meta.gaps_per_pair,
        grids,
        warnings: meta.warnings,
    })
}

/// The reduced model of `scene` from a cached entry: its gap geometry with the DOFs
/// reassigned (the scene's operating point is applied when the problem is made,
/// [`crate::problem::OperatingPoint`]). No Craig–Bampton checks and no per-component recovery
/// data (cached models have neither).
pub(super) fn finish(scene: &Scene, c: Cached) -> Result<ReducedModel, PipelineError> {
    if c.gaps_per_pair.len() != scene.contact.len() {
        return Err(PipelineError::Model(format!(
            "cached model has {} contact pairs, the scene {}",
            c.gaps_per_pair.len(),
            scene.contact.len()
        )));
    }
    let mut gaps = c.gaps;
    for g in &mut gaps {
        g.pad_dofs = [None; 3];
        g.rotor_dofs = [None; 3];
    }
    let gap_geometry = GapSet {
        gaps,
        law: FrictionLaw::default(),
        vtol: GapSet::DEFAULT_VTOL,
    };
    let mut model = ReducedModel {
        k: c.k,
        m: c.m,
        b: c.b,
        p_brake: c.p_brake,
        dofs: c.dofs,
        gap_geometry,
        gap_pairs: c.gaps_per_pair,
        grids: c.grids,
        checks: Vec::new(),
        components: Vec::new(),
        recovery: Vec::new(),
        source: ModelSource::Mesh,
        warnings: c.warnings,
    };
    model.assign_gap_dofs()?;
    Ok(model)
}
