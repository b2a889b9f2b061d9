//! `squeal reduce`: the reduced model written as OP4 + punch DMIG + DOF map + gap table, with
//! the Craig–Bampton checks (`checks.json`) and the lowest modes of the reduced (K, M).

use crate::error::PipelineError;
use crate::model::{self, ComponentReport, ReducedModel, StoredFiles};
use crate::output::RunDir;
use crate::problem::OperatingPoint;
use crate::progress::Progress;
use crate::scene::{ModelSource, Scene};
use serde::Serialize;
use squeal_contact::GapSet;
use std::time::Instant;

/// Number of reduced-model modes reported.
pub const N_REPORTED_MODES: usize = 10;

/// What `squeal reduce` produced (also `summary.json`'s `reduce` entry).
#[derive(Debug, Clone, Serialize)]
pub struct ReduceReport {
    pub source: ModelSource,
    pub n_reduced_dofs: usize,
    pub n_grid_dofs: usize,
    pub n_modal_dofs: usize,
    /// Interface coordinates of interface-reduced components (`[[components]] interface`).
    #[serde(skip_serializing_if = "is_zero")]
    pub n_interface_dofs: usize,
    pub n_gaps: usize,
    pub has_damping: bool,
    /// Lowest natural frequencies of the reduced (K, M), no contact constraint, Hz.
    pub frequencies_hz: Vec<f64>,
    pub components: Vec<ComponentReport>,
    pub files: StoredFiles,
    pub total_s: f64,
    /// Inputs accepted with a measured value to know about ([`crate::warning`]).
    pub warnings: Vec<crate::warning::Warning>,
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl ReduceReport {
    /// A short text summary.
    pub fn table(&self) -> String {
        let mut s = format!(
            "reduced model: {} DOFs ({} grid, {} modal), {} gaps\n  mode   frequency [Hz]\n",
            self.n_reduced_dofs, self.n_grid_dofs, self.n_modal_dofs, self.n_gaps
        );
        for (i, f) in self.frequencies_hz.iter().enumerate() {
            s.push_str(&format!("  {:>4}   {:>14.6}\n", i + 1, f));
        }
        s
    }
}

/// What `squeal reduce` computed, in memory: the reduced model and its gaps at the scene's
/// operating point (what the gap table carries: P0, temperature, sliding speed).
pub struct ReduceComputed {
    pub model: ReducedModel,
    pub gaps: GapSet,
}

/// Builds (or reads) the reduced model of `scene` (gmsh's files, when it meshes, go into
/// `work`).
pub fn compute(
    scene: &Scene,
    work: &RunDir,
    progress: &Progress,
) -> Result<ReduceComputed, PipelineError> {
    let model = model::build(scene, work, progress)?;
    let gaps = OperatingPoint::of(scene).gaps(&model)?;
    Ok(ReduceComputed { model, gaps })
}

/// `squeal reduce`: [`compute`], then [`write`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<ReduceReport, PipelineError> {
    let start = Instant::now();
    let c = compute(scene, dir, progress)?;
    write(scene, &c, dir, progress, start)
}

/// Writes the reduced model as stored files with its checks (`checks.json`, `grids.json`) and
/// `summary.json` (`start`: when the run began).
pub fn write(
    scene: &Scene,
    c: &ReduceComputed,
    dir: &RunDir,
    progress: &Progress,
    start: Instant,
) -> Result<ReduceReport, PipelineError> {
    let model = &c.model;
    let files = model::write_stored(model, &c.gaps, dir)?;
    let checks: serde_json::Map<String, serde_json::Value> = model
        .checks
        .iter()
        .map(|(name, c)| {
            progress.info(format!("{name}: {c}"));
            (
                name.clone(),
                serde_json::to_value(c).unwrap_or(serde_json::Value::Null),
            )
        })
        .collect();
    dir.write_json("checks.json", &checks)?;
    if !model.grids.is_empty() {
        dir.write_json("grids.json", &model.grids)?;
    }
    let n_modal = model
        .dofs
        .dofs
        .iter()
        .filter(|d| {
            matches!(
                d.kind,
                squeal_reduction::superelement::DofKind::Modal { .. }
            )
        })
        .count();
    let n_interface = model
        .dofs
        .dofs
        .iter()
        .filter(|d| {
            matches!(
                d.kind,
                squeal_reduction::superelement::DofKind::Interface { .. }
            )
        })
        .count();
    let report = ReduceReport {
        source: model.source,
        n_reduced_dofs: model.n(),
        n_grid_dofs: model.n() - n_modal - n_interface,
        n_modal_dofs: n_modal,
        n_interface_dofs: n_interface,
        n_gaps: model.gap_geometry.len(),
        has_damping: model.b.is_some(),
        frequencies_hz: model.frequencies_hz(N_REPORTED_MODES)?,
        components: model.components.clone(),
        files,
        total_s: start.elapsed().as_secs_f64(),
        warnings: model.warnings.clone(),
    };
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    dir.write_json(
        "summary.json",
        &serde_json::json!({ "verb": "reduce", "version": crate::VERSION, "reduce": &report, "checks": checks }),
    )?;
    Ok(report)
}
