//! The reduced brake model shared by `squeal reduce` and `squeal transient`: built from the
//! scene's meshes (mesh → assemble → Craig–Bampton → superelement assembly → gaps → loads) or
//! read from stored reduced matrices (OP4 or punch DMIG + DOF map + gap table).

mod areas;
pub mod cache;
mod degree;
mod from_mesh;
pub mod gap_table;
pub mod grids;
pub mod inputs;
pub mod mesh;
mod stored;
pub mod ties;

pub use cache::{CacheUse, ModelCache};
pub use degree::{DegreeRow, InterfaceChoice};
pub use from_mesh::{build_from_mesh, build_from_mesh_cached};
pub use grids::GridInfo;
pub use stored::{load_arrays, load_stored, write_stored, StoredFiles};

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{ModelSource, Scene};
use faer::Mat;
use serde::Serialize;
use squeal_contact::{GapSet, RotorRow};
use squeal_fe::DofMap;
use squeal_meshes::Mesh;
use squeal_reduction::cb::CbCheck;
use squeal_reduction::superelement::{DofKey, DofKind, RecoveredDof, ReducedDofMap};
use squeal_reduction::CbModel;
use std::collections::HashMap;

use squeal_solver::Real;

/// What reducing one component gave.
#[derive(Debug, Clone, Serialize)]
pub struct ComponentReport {
    pub name: String,
    pub n_nodes: usize,
    pub n_free_dofs: usize,
    pub n_boundary_dofs: usize,
    pub n_modes: usize,
    pub fixed_interface_hz: Vec<Real>,
    /// Statistics of the reduction (absent when it was read from the component cache).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cb_stats: Option<squeal_reduction::cb::CbStats>,
    /// Viscous factor of this component's reduced stiffness in B (GE/W4).
    pub element_damping_factor: Real,
    /// The component cache's use, when the model was built through the model cache
    /// (`cache::component`): key, hit, seconds.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reduction_cache: Option<cache::component::ComponentCacheUse>,
    /// The interface reduction's degree and its error estimate (`[components.interface]`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub interface: Option<InterfaceChoice>,
}

/// What it takes to expand a reduced vector to one component's full mesh (meshed models only):
/// its mesh, free-DOF numbering and Craig–Bampton model, and where each of its reduced
/// coordinates (boundary DOFs, then modal coordinates) sits in the assembled reduced vector.
#[derive(Debug, Clone)]
pub struct ComponentRecovery {
    pub name: String,
    pub mesh: Mesh,
    /// Free-DOF numbering of the mesh (the rows of the Craig–Bampton model).
    pub dofs: DofMap,
    pub cb: CbModel,
    /// Merged grid id of each mesh node.
    pub grid_of: Vec<u64>,
    /// Component-reduced coordinate j as terms (assembled reduced index, weight) of the
    /// assembled vector (`cb.n_reduced()` entries): one term of weight 1, several for a grid
    /// DOF a tie eliminated, none when not in the assembled model.
    pub assembled: Vec<Vec<(usize, Real)>>,
    /// The bonded ties inside the component: its free DOFs are T × the reduction's
    /// (`model/ties.rs`); None without.
    pub mpc: Option<ties::Mpc>,
}

impl ComponentRecovery {
    /// Nodal 3-vectors of the assembled reduced vector `x` on this component's mesh:
    /// gather its reduced coordinates, recover the free DOFs with the Craig–Bampton
    /// transformation, expand to the nodes (zeros at fixed DOFs).
    pub fn expand(&self, x: &[Real]) -> Result<Vec<[Real; 3]>, PipelineError> {
        let xr: Vec<Real> = self
            .assembled
            .iter()
            .map(|t| {
                t.iter()
                    .map(|&(i, w)| w * x.get(i).copied().unwrap_or(0.0))
                    .sum()
            })
            .collect();
        let full = self
            .cb
            .recover(&xr)
            .map_err(|source| PipelineError::Reduction {
                what: format!("component `{}`: recovering a full vector", self.name),
                source,
            })?;
        let full = match &self.mpc {
            Some(t) => t.expand(&full),
            None => full,
        };
        Ok(self.dofs.expand(&full))
    }
}

/// The assembled reduced model with its contact and loads.
#[derive(Debug, Clone)]
pub struct ReducedModel {
    /// Reduced stiffness (symmetrised).
    pub k: Mat<Real>,
    /// Reduced mass (symmetrised).
    pub m: Mat<Real>,
    /// Element damping Σ_c (GE_c/W4)·K_c, reduced (None when no component has GE).
    pub b: Option<Mat<Real>>,
    /// Brake load before PMAX (Σ load sets projected on the reduced DOFs).
    pub p_brake: Vec<Real>,
    /// Row/column i of the matrices is `dofs.dofs[i]`.
    pub dofs: ReducedDofMap,
    /// The gap elements' geometry with DOF indices into the reduced vector: points, normals,
    /// areas, pairings (and a stored gap table's own P0 and temperature). No operating value:
    /// sliding velocities are zero and the law is the default; the scene's operating point
    /// makes the gaps a problem runs with ([`crate::problem::OperatingPoint::gaps`]).
    pub gap_geometry: GapSet,
    /// Number of gaps of each `[[contact]]` pair, in scene order (the gaps of pair i follow
    /// those of pair i − 1); a stored model's gap table is one pair (`[n_gaps]`, read with
    /// the scene's only `[[contact]]` table, if any).
    pub gap_pairs: Vec<usize>,
    /// Grid table (meshed models only).
    pub grids: Vec<GridInfo>,
    /// Craig–Bampton checks per component (meshed models with `reduction.checks`).
    pub checks: Vec<(String, CbCheck)>,
    pub components: Vec<ComponentReport>,
    /// Per-component recovery data (meshed models only; empty for stored matrices).
    pub recovery: Vec<ComponentRecovery>,
    pub source: ModelSource,
    /// Inputs accepted with a measured value the user may want to know (e.g. a slightly
    /// non-symmetric stored matrix that was symmetrised); see [`crate::warning`].
    pub warnings: Vec<crate::warning::Warning>,
}

/// The `[[contact]]` pair of each of `n_gaps` gaps from the gap count of each pair (the
/// gaps of pair i follow those of pair i − 1); None when the counts do not add up to the gaps
/// (a gap table read with other pairs).
pub fn gap_pair_index(gap_pairs: &[usize], n_gaps: usize) -> Option<Vec<usize>> {
    (gap_pairs.iter().sum::<usize>() == n_gaps).then(|| {
        gap_pairs
            .iter()
            .enumerate()
            .flat_map(|(p, &c)| std::iter::repeat_n(p, c))
            .collect()
    })
}

impl ReducedModel {
    /// Number of reduced DOFs.
    pub fn n(&self) -> usize {
        self.k.nrows()
    }

    /// The `[[contact]]` pair of each gap ([`gap_pair_index`] of `gap_pairs`).
    pub fn gap_pair_index(&self) -> Option<Vec<usize>> {
        gap_pair_index(&self.gap_pairs, self.gap_geometry.len())
    }

    /// Index of a grid DOF (comp 1..6) in the reduced vector.
    pub fn grid_index(&self) -> HashMap<DofKey, usize> {
        self.dofs
            .dofs
            .iter()
            .enumerate()
            .filter_map(|(i, d)| match d.kind {
                DofKind::Grid { grid, comp } => Some((DofKey { grid, comp }, i)),
                DofKind::Modal { .. } | DofKind::Interface { .. } => None,
            })
            .collect()
    }

    /// Sets every gap's pad and rotor DOFs from the DOF map; a gap node absent from the map is
    /// an error naming it.
    pub fn assign_gap_dofs(&mut self) -> Result<(), PipelineError> {
        let index = self.grid_index();
        let recovered: HashMap<DofKey, &RecoveredDof> = self
            .dofs
            .recovered
            .iter()
            .map(|r| {
                (
                    DofKey {
                        grid: r.grid,
                        comp: r.comp,
                    },
                    r,
                )
            })
            .collect();
        let mut missing = Vec::new();
        for g in &self.gap_geometry.gaps {
            // A pad node must have grid DOFs; a rotor node may be recovered instead.
            let pad = g.pad_nodes().into_iter().map(|n| (n, false));
            for (node, may_recover) in pad.chain(g.rotor_nodes().into_iter().map(|n| (n, true))) {
                if (1..=3).all(|c| {
                    let key = DofKey {
                        grid: node,
                        comp: c,
                    };
                    !(index.contains_key(&key) || may_recover && recovered.contains_key(&key))
                }) {
                    missing.push(node);
                }
            }
        }
        if !missing.is_empty() {
            missing.sort_unstable();
            missing.dedup();
            return Err(PipelineError::Model(format!(
                "gap grids with no DOF in the reduced model: {missing:?}"
            )));
        }
        self.gap_geometry
            .assign_dofs(|grid| [1u8, 2, 3].map(|comp| index.get(&DofKey { grid, comp }).copied()));
        if !recovered.is_empty() {
            for g in &mut self.gap_geometry.gaps {
                g.rotor_rows = recovery_rows(g, &index, &recovered);
            }
        }
        self.check_gap_rows()
    }

    /// Every gap's constraint row G_g (eq. 9 over the DOFs its grids have) must be nonzero:
    /// a normal with no component along those DOFs (a pad with x, z DOFs and a normal along y)
    /// leaves the gap's force undetermined, and the first factorisation failed as a bare
    /// "singular Newton". ‖G_g‖ < 1e-6 |n| is an error naming the gap and its normal.
    fn check_gap_rows(&self) -> Result<(), PipelineError> {
        let n = self.n();
        let trip =
            self.gap_geometry
                .constraint_triplets(n)
                .map_err(|source| PipelineError::Contact {
                    what: "gap constraint rows".into(),
                    source,
                })?;
        let mut rows: HashMap<(usize, usize), Real> = HashMap::new();
        for (i, j, x) in trip {
            *rows.entry((i, j)).or_default() += x;
        }
        let mut norm2 = vec![0.0; self.gap_geometry.len()];
        for ((i, _), x) in rows {
            norm2[i] += x * x;
        }
        for (i, g) in self.gap_geometry.gaps.iter().enumerate() {
            let nn = g.normal.iter().map(|x| x * x).sum::<Real>().sqrt();
            if norm2[i].sqrt() < 1e-6 * nn || nn == 0.0 {
                let has = |dofs: [Option<usize>; 3]| -> String {
                    let s: String = (0..3)
                        .filter(|&k| dofs[k].is_some())
                        .map(|k| ['x', 'y', 'z'][k])
                        .collect();
                    if s.is_empty() {
                        "none".into()
                    } else {
                        s
                    }
                };
                return Err(PipelineError::Model(format!(
                    "gap {i} (pad grid {}, rotor grid {} at {:?}): its normal {:?} has no \
                     component along the DOFs of its grids (pad: {}; rotor: {}), so its \
                     constraint row is zero (norm {:.3e}) and its contact force undetermined; \
                     give the outward normal of the pad's contact face",
                    g.pad_node,
                    g.rotor_node,
                    g.coords,
                    g.normal,
                    has(g.pad_dofs),
                    has(g.rotor_dofs),
                    norm2[i].sqrt()
                )));
            }
        }
        Ok(())
    }

    /// Lowest `count` natural frequencies (Hz) of the reduced (K, M), without contact.
    pub fn frequencies_hz(&self, count: usize) -> Result<Vec<Real>, PipelineError> {
        let (vals, _) =
            squeal_reduction::cb::dense_generalized_eigen(self.k.as_ref(), self.m.as_ref())
                .map_err(|source| PipelineError::Reduction {
                    what: "modes of the reduced model".into(),
                    source,
                })?;
        Ok(vals
            .iter()
            .take(count)
            .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
            .collect())
    }
}

/// The rotor point of gap `g` as rows over the reduced vector when any of its rotor nodes is
/// recovered (an interface-reduced rotor), else none: u_k = Σ_a w_a u_{a,k} with u_{a,k} the
/// grid DOF itself or its recovery row, summed per reduced DOF.
fn recovery_rows(
    g: &squeal_contact::Gap,
    index: &HashMap<DofKey, usize>,
    recovered: &HashMap<DofKey, &RecoveredDof>,
) -> Vec<RotorRow> {
    let nodes: Vec<(u64, Real)> = match &g.tie {
        None => vec![(g.rotor_node, 1.0)],
        Some(t) => t
            .nodes
            .iter()
            .copied()
            .zip(t.weights.iter().copied())
            .filter(|&(_, w)| w != 0.0)
            .collect(),
    };
    let key = |grid, k: usize| DofKey {
        grid,
        comp: k as u8 + 1,
    };
    if !nodes
        .iter()
        .any(|&(n, _)| (0..3).any(|k| recovered.contains_key(&key(n, k))))
    {
        return Vec::new();
    }
    let mut rows: std::collections::BTreeMap<usize, [Real; 3]> = Default::default();
    for (n, w) in nodes {
        for k in 0..3 {
            if let Some(&i) = index.get(&key(n, k)) {
                rows.entry(i).or_default()[k] += w;
            } else if let Some(r) = recovered.get(&key(n, k)) {
                for (&i, &c) in r.dofs.iter().zip(&r.coefs) {
                    rows.entry(i).or_default()[k] += w * c;
                }
            }
        }
    }
    rows.into_iter()
        .map(|(dof, weights)| RotorRow { dof, weights })
        .collect()
}

/// Symmetric part (A + Aᵀ)/2.
pub(crate) fn symmetrise(a: &Mat<Real>) -> Mat<Real> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| 0.5 * (a[(i, j)] + a[(j, i)]))
}

/// Builds or reads the reduced model the scene describes.
pub fn build(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<ReducedModel, PipelineError> {
    match scene.model.from {
        ModelSource::Mesh => build_from_mesh(scene, dir, progress),
        ModelSource::Op4 | ModelSource::Punch => load_stored(scene),
        ModelSource::Arrays => load_arrays(scene),
    }
}

/// [`build`] through a model cache: a meshed model is read from `cache` when an entry for its
/// key exists (else built and stored, [`ModelCache::get_or_build`]); stored matrices are read
/// as by [`build`] (no cache use reported).
pub fn build_cached(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    cache: Option<&ModelCache>,
) -> Result<(ReducedModel, Option<CacheUse>), PipelineError> {
    match (cache, scene.model.from) {
        (Some(c), ModelSource::Mesh) => c
            .get_or_build(scene, dir, progress)
            .map(|(m, u)| (m, Some(u))),
        _ => build(scene, dir, progress).map(|m| (m, None)),
    }
}
