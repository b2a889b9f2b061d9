//! `squeal mesh`: every component's mesh ([`crate::model::mesh`]) and its `.vtu`.

use crate::error::PipelineError;
pub use crate::model::mesh::{groups, mesh_component, MeshReport};
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use squeal_meshes::{vtu, Mesh};

/// Every component's mesh and its report (gmsh's files, when it meshes, go into `work`).
pub fn compute(
    scene: &Scene,
    work: &RunDir,
    progress: &Progress,
) -> Result<Vec<(Mesh, MeshReport)>, PipelineError> {
    scene
        .components
        .iter()
        .map(|c| mesh_component(scene, c, work, progress))
        .collect()
}

/// `squeal mesh`: [`compute`], then [`write`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<Vec<MeshReport>, PipelineError> {
    let meshes = compute(scene, dir, progress)?;
    write(scene, &meshes, dir, progress)
}

/// Writes `<name>.vtu` beside each component's `.msh` and `summary.json`.
pub fn write(
    scene: &Scene,
    meshes: &[(Mesh, MeshReport)],
    dir: &RunDir,
    progress: &Progress,
) -> Result<Vec<MeshReport>, PipelineError> {
    let mut reports = Vec::new();
    for (mesh, report) in meshes {
        let mesh_dir = dir.subdir("mesh")?;
        vtu::write_vtu(
            &mesh_dir.join(format!("{}.vtu", report.component)),
            mesh,
            &[],
            &[],
        )
        .map_err(|source| PipelineError::mesh(&report.component, source))?;
        progress.info(format!(
            "{}: {} nodes, {} cells",
            report.component, report.n_nodes, report.n_cells
        ));
        reports.push(report.clone());
    }
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    dir.write_json(
        "summary.json",
        &serde_json::json!({
            "verb": "mesh",
            "version": crate::VERSION,
            "components": reports,
            "warnings": reports.iter().flat_map(|r| r.warnings()).collect::<Vec<_>>(),
        }),
    )?;
    Ok(reports)
}
