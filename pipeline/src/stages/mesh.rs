//! `squeal mesh`: every component's mesh ([`crate::model::mesh`]) and its `.vtu`.

use crate::error::PipelineError;
pub use crate::model::mesh::{groups, mesh_component, MeshReport};
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use squeal_meshes::vtu;

/// `squeal mesh`: meshes every component and writes `<name>.vtu` beside each `.msh`.
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
) -> Result<Vec<MeshReport>, PipelineError> {
    let mut reports = Vec::new();
    for c in &scene.components {
        let (mesh, report) = mesh_component(scene, c, dir, progress)?;
        let mesh_dir = dir.subdir("mesh")?;
        vtu::write_vtu(&mesh_dir.join(format!("{}.vtu", c.name)), &mesh, &[], &[])
            .map_err(|source| PipelineError::mesh(&c.name, source))?;
        progress.info(format!(
            "{}: {} nodes, {} cells",
            report.component, report.n_nodes, report.n_cells
        ));
        reports.push(report);
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
