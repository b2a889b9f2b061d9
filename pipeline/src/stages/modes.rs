//! `squeal modes`: mesh → assemble → shift-invert Lanczos → modes.json + modes.vtu.

use crate::error::PipelineError;
use crate::model::mesh::{check_not_all_fixed, fixed_dofs, mesh_component, MeshReport};
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use serde::Serialize;
use squeal_fe::modal::{solve_modes_with, ModalStats, ModalStatus};
use squeal_fe::{assemble, AssemblyOptions, AssemblyStats, DofMap};
use squeal_meshes::{vtu, Mesh};
use std::time::Instant;

/// What `squeal modes` found; also the content of `modes.json`.
#[derive(Debug, Clone, Serialize)]
pub struct ModesReport {
    pub component: String,
    pub n_nodes: usize,
    pub n_dofs: usize,
    pub frequencies_hz: Vec<f64>,
    pub status: ModalStatus,
    pub modal_stats: ModalStats,
    pub assembly_stats: AssemblyStats,
    pub mesh: MeshReport,
    pub total_s: f64,
}

impl ModesReport {
    /// A short text table of the frequencies.
    pub fn table(&self) -> String {
        let mut s = format!(
            "{}: {} nodes, {} free DOFs, {} modes ({:?})\n  mode   frequency [Hz]\n",
            self.component,
            self.n_nodes,
            self.n_dofs,
            self.frequencies_hz.len(),
            self.status
        );
        for (i, f) in self.frequencies_hz.iter().enumerate() {
            s.push_str(&format!("  {:>4}   {:>14.3}\n", i + 1, f));
        }
        s
    }
}

/// What the modal analysis of one component found, in memory.
#[derive(Debug, Clone)]
pub struct ModesComputed {
    pub report: ModesReport,
    /// The component's mesh (nodes and cells, for meshio or pyvista).
    pub mesh: Mesh,
    /// Mode shapes as nodal 3-vectors: `shapes[mode][node]` (zeros at fixed DOFs), mass
    /// normalised as the Lanczos solver returns them.
    pub shapes: Vec<Vec<[f64; 3]>>,
}

/// The modal analysis of one component (`component`: its name, or None for the scene's only
/// one). gmsh writes its `.geo`/`.msh` into `work` (the mesh stage needs a folder).
pub fn compute(
    scene: &Scene,
    component: Option<&str>,
    work: &RunDir,
    progress: &Progress,
) -> Result<ModesComputed, PipelineError> {
    let start = Instant::now();
    let c = scene.component(component)?;
    let mut opts = scene.modes.clone().unwrap_or_default();
    opts.interrupt = progress.interrupt();
    let fe_err = |source| PipelineError::fe(&c.name, source);
    let (mesh, mesh_report) = mesh_component(scene, c, work, progress)?;
    let fixed = fixed_dofs(c, &mesh)?;
    check_not_all_fixed(scene, c, &mesh, &fixed, &mesh_report.msh_path)?;
    let dofs = DofMap::new(mesh.nodes.len(), &fixed).map_err(fe_err)?;
    let materials = c.block_materials(&mesh)?;
    progress.check("modes")?;
    let step = progress.step(format!("assembling K, M ({} DOFs)", dofs.n_free()));
    let asm_opts = AssemblyOptions {
        hex8: c.hex8,
        interrupt: progress.interrupt(),
    };
    let assembled = assemble(&mesh, &materials, &dofs, &asm_opts).map_err(fe_err)?;
    step.done(format!("assembled K, M ({} DOFs)", dofs.n_free()));
    progress.check("modes")?;
    let step = progress.step("shift-invert Lanczos");
    // Node coordinates let the factorisation use nested dissection on large meshes.
    let coords = squeal_fe::dof_coordinates(&mesh, &dofs);
    let modes =
        solve_modes_with(&assembled.k, &assembled.m, &opts, Some(&coords)).map_err(fe_err)?;
    step.done(format!(
        "{} modes in {:.2} s",
        modes.frequencies_hz.len(),
        modes.stats.factor_s + modes.stats.lanczos_s
    ));
    let shapes = (0..modes.frequencies_hz.len())
        .map(|j| {
            let col: Vec<f64> = (0..modes.shapes.nrows())
                .map(|i| modes.shapes[(i, j)])
                .collect();
            dofs.expand(&col)
        })
        .collect();
    let report = ModesReport {
        component: c.name.clone(),
        n_nodes: mesh.nodes.len(),
        n_dofs: dofs.n_free(),
        frequencies_hz: modes.frequencies_hz.clone(),
        status: modes.status,
        modal_stats: modes.stats.clone(),
        assembly_stats: assembled.stats.clone(),
        mesh: mesh_report,
        total_s: start.elapsed().as_secs_f64(),
    };
    Ok(ModesComputed {
        report,
        mesh,
        shapes,
    })
}

/// Writes what [`compute`] found: `modes.vtu` (one point array `mode_NN_<f>Hz` per mode),
/// `modes.json`, `scene.resolved.toml`, `summary.json`.
pub fn write(scene: &Scene, m: &ModesComputed, dir: &RunDir) -> Result<(), PipelineError> {
    let fields: Vec<Vec<f64>> = m
        .shapes
        .iter()
        .map(|s| s.iter().flat_map(|v| v.iter().copied()).collect())
        .collect();
    let names: Vec<String> = m
        .report
        .frequencies_hz
        .iter()
        .enumerate()
        .map(|(j, f)| format!("mode_{:02}_{:.1}Hz", j + 1, f))
        .collect();
    let arrays: Vec<vtu::PointArray> = names
        .iter()
        .zip(&fields)
        .map(|(n, v)| vtu::PointArray::vector(n, v))
        .collect();
    vtu::write_vtu(&dir.path("modes.vtu"), &m.mesh, &arrays, &[]).map_err(|source| {
        PipelineError::Mesh {
            component: m.report.component.clone(),
            source,
        }
    })?;
    dir.write_json("modes.json", &m.report)?;
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    dir.write_json(
        "summary.json",
        &serde_json::json!({
            "verb": "modes",
            "version": crate::VERSION,
            "modes": &m.report,
            "warnings": m.report.mesh.warnings(),
        }),
    )?;
    Ok(())
}

/// Runs the modal analysis of one component and writes its outputs ([`compute`] + [`write`]).
pub fn run(
    scene: &Scene,
    component: Option<&str>,
    dir: &RunDir,
    progress: &Progress,
) -> Result<ModesReport, PipelineError> {
    let m = compute(scene, component, dir, progress)?;
    write(scene, &m, dir)?;
    Ok(m.report)
}
