//! `[reduction]` (Craig–Bampton per component) and `[model]` (where the reduced model comes from).

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_reduction::cb::SubstructureOptions;
use squeal_reduction::CbOptions;
use std::path::PathBuf;

use squeal_solver::Real;

/// `[reduction]`: Craig–Bampton reduction of every meshed component.
///
/// Boundary of a component = its contact-face nodes + the nodes it shares with other
/// components. Kept fixed-interface modes: those below `cutoff_hz`, else below
/// `cutoff_factor × frequency_of_interest_hz`, capped at (or, alone, exactly) `n_modes`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ReductionSpec {
    /// Highest frequency the reduced model must reproduce, Hz (default: 10000, the squeal band's top).
    pub frequency_of_interest_hz: Option<Real>,
    /// Cutoff of the fixed-interface modes, Hz (default: none = `cutoff_factor × frequency_of_interest_hz`).
    pub cutoff_hz: Option<Real>,
    /// Cutoff over frequency of interest (default: 2.0, DESIGN.md).
    pub cutoff_factor: Real,
    /// Number of fixed-interface modes per component: alone, exactly this many; with a cutoff, at
    /// most this many (default: none).
    pub n_modes: Option<usize>,
    /// Run the Craig–Bampton checks (symmetry, M_qq = I, K_bq = 0, rigid-body mass, frequencies
    /// against the full component) and write `checks.json` (default: true).
    pub checks: bool,
    /// Largest Krylov dimension of the block Lanczos computing a large component's
    /// fixed-interface modes (interiors above 1500 DOFs) before it gives up (default: 600);
    /// raise it when the error says the modes below the cutoff did not converge.
    pub lanczos_max_dim: usize,
    /// Substructured reduction of large components: `[reduction.substructures]` with
    /// `above_dofs` (default: off), `max_dofs`, `cutoff_factor`, `degree`, `max_degree`, `tol`,
    /// `max_rounds` (squeal_reduction::cb::SubstructureOptions; docs/multilevel.md).
    pub substructures: SubstructureOptions,
}

impl Default for ReductionSpec {
    fn default() -> Self {
        Self {
            frequency_of_interest_hz: Some(10_000.0),
            cutoff_hz: None,
            cutoff_factor: 2.0,
            n_modes: None,
            checks: true,
            lanczos_max_dim: CbOptions::default().lanczos_max_dim,
            substructures: SubstructureOptions::default(),
        }
    }
}

impl ReductionSpec {
    /// The reduction crate's options.
    pub fn cb_options(&self) -> CbOptions {
        CbOptions {
            frequency_of_interest_hz: self.frequency_of_interest_hz,
            cutoff_hz: self.cutoff_hz,
            cutoff_factor: self.cutoff_factor,
            n_modes: self.n_modes,
            lanczos_max_dim: self.lanczos_max_dim,
            substructures: self.substructures.clone(),
            ..CbOptions::default()
        }
    }

    /// Checks every field through [`CbOptions::validate`].
    pub fn validate(&self) -> Result<(), PipelineError> {
        self.cb_options()
            .validate()
            .map_err(|e| PipelineError::Scene {
                field: "reduction".into(),
                message: e.to_string(),
            })
    }
}

/// Where the reduced model comes from.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ModelSource {
    /// Mesh, assemble and reduce the scene's `[[components]]`.
    #[default]
    Mesh,
    /// NASTRAN OP4 file holding `KR`, `MR` (and `BR`, `PBRAKE` when present), as `squeal reduce` writes.
    Op4,
    /// Punch file with DMIG `KR`, `MR` (and `BR`, `PBRAKE`), rows/columns = grid/component of the map.
    Punch,
    /// Matrices, DOF map and gaps given in memory by a library caller
    /// (`Scene::with_arrays`, the Python package's `Scene.from_arrays`); a scene file alone
    /// cannot name this source.
    Arrays,
}

/// `[model]`: the reduced model's source and the node merging of meshed components.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelSpec {
    /// `mesh`, `op4` or `punch` (default: mesh).
    pub from: ModelSource,
    /// Matrix file (`reduced.op4` or `reduced.pch`), relative to the scene (default: none; required
    /// unless `from = "mesh"`).
    pub matrices: Option<PathBuf>,
    /// DOF map JSON (`dofmap.json` of `squeal reduce`) (default: none; required unless `from = "mesh"`).
    pub dofmap: Option<PathBuf>,
    /// Gap table, JSON (`gaps.json` of `squeal reduce`) or CSV whose first line names the
    /// columns `pad_grid,rotor_grid,x,y,z,nx,ny,nz,area,p0,temperature` in any order (default:
    /// none = no contact). Checks: `crate::model::gap_table`.
    pub gaps: Option<PathBuf>,
    /// Overrides the preload P0 stored in the gap table, for stored models; finite and >= 0
    /// (default: none = as stored).
    pub p0: Option<Real>,
    /// Overrides the gap temperature stored in the gap table, for stored models (default: none).
    pub temperature: Option<Real>,
    /// Distance below which nodes of different components are merged into one grid (shared,
    /// superelement-connected), except contact-face nodes of a pad/rotor pair (default: 1e-6).
    pub merge_tolerance: Real,
    /// The band stored matrices were reduced for, Hz (default: none = unknown; meshed models
    /// use `reduction.frequency_of_interest_hz`). Bounds the transient's step and separates
    /// the CEA's roots outside the band.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_hz: Option<Real>,
    /// The model's arrays with `from = "arrays"` (in memory only, never read from or written
    /// to TOML).
    #[serde(skip)]
    pub arrays: Option<super::ArraysRef>,
}

impl Default for ModelSpec {
    fn default() -> Self {
        Self {
            from: ModelSource::Mesh,
            matrices: None,
            dofmap: None,
            gaps: None,
            p0: None,
            temperature: None,
            merge_tolerance: 1e-6,
            band_hz: None,
            arrays: None,
        }
    }
}

impl ModelSpec {
    /// Checks that the stored-model paths are present when needed, and the numbers.
    pub fn validate(&self) -> Result<(), PipelineError> {
        let bad = |field: &str, message: String| PipelineError::Scene {
            field: format!("model.{field}"),
            message,
        };
        if !(self.merge_tolerance.is_finite() && self.merge_tolerance > 0.0) {
            return Err(bad(
                "merge_tolerance",
                format!("{} must be finite and > 0", self.merge_tolerance),
            ));
        }
        if let Some(b) = self.band_hz {
            if !(b.is_finite() && b > 0.0) {
                return Err(bad("band_hz", format!("{b} must be finite and > 0")));
            }
        }
        if let Some(p0) = self.p0 {
            if !(p0.is_finite() && p0 >= 0.0) {
                return Err(bad(
                    "p0",
                    format!("{p0} must be finite and >= 0 (a compressive preload pressure)"),
                ));
            }
        }
        if let Some(t) = self.temperature.filter(|t| !t.is_finite()) {
            return Err(bad("temperature", format!("{t} must be finite")));
        }
        if self.from == ModelSource::Arrays {
            if self.arrays.is_none() {
                return Err(bad(
                    "from",
                    "`arrays` names a model given in memory (Scene::with_arrays, Python \
                     squeal.Scene.from_arrays); a scene file cannot hold one"
                        .into(),
                ));
            }
            for (field, set) in [
                ("matrices", self.matrices.is_some()),
                ("dofmap", self.dofmap.is_some()),
                ("gaps", self.gaps.is_some()),
            ] {
                if set {
                    return Err(bad(
                        field,
                        "not used with from = \"arrays\" (the arrays hold the model); remove it"
                            .into(),
                    ));
                }
            }
        } else if self.from != ModelSource::Mesh {
            if self.matrices.is_none() {
                return Err(bad(
                    "matrices",
                    format!("required with from = {:?}", self.from),
                ));
            }
            if self.dofmap.is_none() {
                return Err(bad(
                    "dofmap",
                    format!("required with from = {:?}", self.from),
                ));
            }
        }
        Ok(())
    }
}
