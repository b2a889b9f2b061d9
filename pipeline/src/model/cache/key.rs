//! The cache key of a reduced model: a 128-bit hash of exactly the scene values that
//! [`super::super::build_from_mesh`] turns into matrices, gap geometry, DOF map and loads.
//!
//! **In the key** (what the builder reads before any late parameter):
//! - every `[[components]]` table whole (name, geometry, element, hex8 formulation, material,
//!   per-volume materials, fixed sets, `rotate_deg`), for a `kind = "msh"` or `"geo"` geometry
//!   the hash of the file's bytes (not only its path; a `.geo` file's `Include`d files are not
//!   read), for a `kind = "bdf"` or `"inp"` geometry the hash of the bytes of the file and of
//!   every file it includes, and for a rotated component the `[rotor]` axis and origin it
//!   turns about;
//! - `model.merge_tolerance`;
//! - the Craig–Bampton options of `[reduction]` (`checks` excepted: it changes no matrix);
//! - every `[[ties]]` entry;
//! - each `[[contact]]` pair's pad, pad faces, rotor, rotor faces and matching tolerance, and
//!   with `pairing = "surface"` its `unmatched`, `extension` and `max_distance`;
//! - the load sets `loads.pressure` and `loads.force` (the unit brake load; PMAX scales it later);
//! - the element-damping factors GE_c/W4 per component (they scale each component's reduced
//!   stiffness into B at superelement assembly) and W4 itself when > 0 and a material may
//!   have a loss factor η (a scene `loss_factor` > 0, or a `bdf`/`inp` file, whose GE or
//!   *DAMPING is in the bytes hashed above): η adds (η/W4)·Tᵀ K_body T;
//! - a format number, the crate version and the build id (a hash of the model-building
//!   crates' sources and the build profile, `pipeline/build.rs`), so a squeal built from
//!   changed sources never reads an entry an older builder wrote.
//!
//! **Not in the key** (the operating point, [`crate::problem::OperatingPoint`], applied when the
//! problem is made, or read later by the stages): `[friction]` (law, VTOL), `[rotor]` (rpm, axis, origin → sliding velocities),
//! contact `p0`, `temperature`, `grid_temperatures`, `loads.pmax`/`tload`, `damping.g`/`w3`/
//! `modal_ratio`, `[transient]`, `[cea]`, `[output]`, `[modes]`, `title`.
//!
//! The key document is the canonical JSON of these typed structs (serde, fields in declaration
//! order, floats in shortest round-trip form), hashed with [`hash128`].

use crate::error::PipelineError;
use crate::scene::transient::{NodeForce, PressureLoad};
use crate::scene::{ComponentSpec, GeometrySpec, Scene};
use serde::Serialize;

use squeal_solver::Real;

/// Version of the cache entry layout and key document; bump it when either changes.
pub const CACHE_FORMAT: u32 = 1;

/// 128-bit FNV-1a-style hash over 64-bit little-endian words (the tail zero-padded), then the
/// byte length: stable across platforms and Rust versions, fast on megabytes of matrices.
/// A change detector, not a cryptographic hash.
pub fn hash128(bytes: &[u8]) -> u128 {
    const OFFSET: u128 = 0x6c62_272e_07bb_0142_62b8_2175_6295_c58d;
    const PRIME: u128 = 0x0000_0000_0100_0000_0000_0000_0000_013b;
    let mut h = OFFSET;
    let mut chunks = bytes.chunks_exact(8);
    for c in &mut chunks {
        let w = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]);
        h = (h ^ w as u128).wrapping_mul(PRIME);
    }
    let rest = chunks.remainder();
    if !rest.is_empty() {
        let mut w = [0u8; 8];
        w[..rest.len()].copy_from_slice(rest);
        h = (h ^ u64::from_le_bytes(w) as u128).wrapping_mul(PRIME);
    }
    (h ^ bytes.len() as u128).wrapping_mul(PRIME)
}

/// `hash128` as 32 hex digits.
pub fn hex128(bytes: &[u8]) -> String {
    format!("{:032x}", hash128(bytes))
}

/// A hash of the sources of the crates that build reduced models and of the build profile
/// (`pipeline/build.rs`): the `squeal` command, the tests and the Python module built from the
/// same sources share entries; a change to those sources starts a fresh cache.
fn build_id() -> &'static str {
    env!("SQUEAL_BUILD_ID")
}

#[derive(Serialize)]
struct ComponentKey<'a> {
    spec: &'a ComponentSpec,
    /// Hash of the `.msh` or `.geo` file's bytes (`kind = "msh"` or `"geo"` only; a `.geo`
    /// file's `Include`d files are not hashed).
    #[serde(skip_serializing_if = "Option::is_none")]
    msh_hash: Option<String>,
    /// The `[rotor]` axis and origin a rotated component (`rotate_deg` ≠ 0) turns about.
    #[serde(skip_serializing_if = "Option::is_none")]
    rotation_axis: Option<([Real; 3], [Real; 3])>,
}

#[derive(Serialize)]
struct PairKey<'a> {
    pad: &'a str,
    pad_faces: &'a str,
    rotor: &'a str,
    rotor_faces: &'a str,
    tolerance: Real,
    /// Surface pairing's options (absent for node pairing, so node-paired keys are unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    surface: Option<squeal_contact::TieOptions>,
    /// No pairing named (the default by the pad faces' kind; absent otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    auto: Option<bool>,
    /// Mortar pairing (absent otherwise, so other keys are unchanged).
    #[serde(skip_serializing_if = "Option::is_none")]
    mortar: Option<bool>,
}

#[derive(Serialize)]
struct ReductionKey {
    frequency_of_interest_hz: Option<Real>,
    cutoff_hz: Option<Real>,
    cutoff_factor: Real,
    n_modes: Option<usize>,
}

#[derive(Serialize)]
struct KeyDoc<'a> {
    format: u32,
    squeal_version: &'a str,
    build: &'a str,
    components: Vec<ComponentKey<'a>>,
    merge_tolerance: Real,
    reduction: ReductionKey,
    contact: Vec<PairKey<'a>>,
    /// `[[ties]]` as written (absent when none, so other keys are unchanged).
    #[serde(skip_serializing_if = "<[_]>::is_empty")]
    ties: &'a [crate::scene::TieSpec],
    pressure_loads: &'a [PressureLoad],
    force_loads: &'a [NodeForce],
    element_damping: Vec<Real>,
    /// W4 when > 0 and a material may have a loss factor (the loss factors' (η/W4)·K_body;
    /// absent otherwise, so a scene without one keeps its key whatever W4).
    #[serde(skip_serializing_if = "Option::is_none")]
    w4: Option<Real>,
}

/// True when a material of `c` may have a loss factor: a scene `loss_factor` > 0, or a
/// Nastran or Abaqus file (MAT1/MAT9 GE, *DAMPING, STRUCTURAL), whose materials the key does
/// not read.
fn may_have_loss_factor(c: &ComponentSpec) -> bool {
    matches!(
        c.geometry,
        GeometrySpec::Bdf { .. } | GeometrySpec::Inp { .. }
    ) || c.material.iter().any(|m| m.loss_factor > 0.0)
        || c.materials.values().any(|m| m.loss_factor > 0.0)
}

/// A reduced model's cache key: the hash and the document it hashes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ModelKey {
    /// 32 hex digits, the entry's folder name.
    pub hex: String,
    /// The canonical JSON that was hashed (stored in the entry for inspection).
    pub document: String,
}

impl ModelKey {
    /// The key of the model the scene's meshed components give.
    pub fn of(scene: &Scene) -> Result<ModelKey, PipelineError> {
        let mut components = Vec::with_capacity(scene.components.len());
        for c in &scene.components {
            let msh_hash = match &c.geometry {
                GeometrySpec::Msh { path } | GeometrySpec::Geo { path, .. } => {
                    let p = scene.resolve(path);
                    let bytes = std::fs::read(&p)
                        .map_err(|source| PipelineError::Io { path: p, source })?;
                    Some(hex128(&bytes))
                }
                GeometrySpec::Bdf { path, .. } | GeometrySpec::Inp { path, .. } => {
                    // The file and every file it includes.
                    let p = scene.resolve(path);
                    let files = match &c.geometry {
                        GeometrySpec::Bdf { .. } => squeal_meshes::bdf::deck_files(&p),
                        _ => squeal_meshes::inp::input_files(&p),
                    }
                    .map_err(|source| PipelineError::Mesh {
                        component: c.name.clone(),
                        source,
                    })?;
                    let mut bytes = Vec::new();
                    for f in files {
                        let f = std::path::PathBuf::from(f);
                        bytes.extend(
                            std::fs::read(&f)
                                .map_err(|source| PipelineError::Io { path: f, source })?,
                        );
                    }
                    Some(hex128(&bytes))
                }
                _ => None,
            };
            let rotation_axis = (c.rotate_deg != 0.0).then(|| {
                let r = scene.rotor.clone().unwrap_or_default();
                (r.axis, r.origin)
            });
            components.push(ComponentKey {
                spec: c,
                msh_hash,
                rotation_axis,
            });
        }
        let red = scene.reduction.clone().unwrap_or_default();
        let damping = scene.damping.clone().unwrap_or_default();
        let loads = scene.loads.as_ref();
        let doc = KeyDoc {
            format: CACHE_FORMAT,
            squeal_version: crate::VERSION,
            build: build_id(),
            components,
            merge_tolerance: scene.model.merge_tolerance,
            reduction: ReductionKey {
                frequency_of_interest_hz: red.frequency_of_interest_hz,
                cutoff_hz: red.cutoff_hz,
                cutoff_factor: red.cutoff_factor,
                n_modes: red.n_modes,
            },
            contact: scene
                .contact
                .iter()
                .map(|p| PairKey {
                    pad: &p.pad,
                    pad_faces: &p.pad_faces,
                    rotor: &p.rotor,
                    rotor_faces: &p.rotor_faces,
                    tolerance: p.tolerance,
                    surface: (p.pairing != Some(crate::scene::Pairing::Nodes))
                        .then(|| p.tie_options()),
                    mortar: (p.pairing == Some(crate::scene::Pairing::Mortar)).then_some(true),
                    // No pairing named: the pad faces' kind decides (the mesh is in the key).
                    auto: p.pairing.is_none().then_some(true),
                })
                .collect(),
            ties: &scene.ties,
            pressure_loads: loads.map_or(&[], |l| &l.pressure),
            force_loads: loads.map_or(&[], |l| &l.force),
            element_damping: scene
                .components
                .iter()
                .map(|c| damping.element_factor(&c.name))
                .collect(),
            w4: (damping.w4 > 0.0 && scene.components.iter().any(may_have_loss_factor))
                .then_some(damping.w4),
        };
        let document = serde_json::to_string(&doc)
            .map_err(|e| PipelineError::Model(format!("cache key of the scene: {e}")))?;
        Ok(ModelKey {
            hex: hex128(document.as_bytes()),
            document,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn hash_depends_on_every_byte_and_the_length() {
        let a = hash128(b"abcdefghij");
        assert_ne!(a, hash128(b"abcdefghik"));
        assert_ne!(a, hash128(b"abcdefghij\0"));
        assert_ne!(hash128(b""), hash128(b"\0"));
        assert_eq!(a, hash128(b"abcdefghij"));
        assert_eq!(hex128(b"").len(), 32);
    }
}
