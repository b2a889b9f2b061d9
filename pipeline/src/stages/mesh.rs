//! Mesh stage: a component's geometry → gmsh → [`Mesh`], or the user's own `.msh`.

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{ComponentSpec, GeometrySpec, Scene};
use serde::Serialize;
use squeal_meshes::{geo, gmsh, msh, vtu, Mesh};

/// What meshing one component produced.
#[derive(Debug, Clone, Serialize)]
pub struct MeshReport {
    pub component: String,
    pub n_nodes: usize,
    pub n_cells: usize,
    pub msh_path: String,
    pub gmsh_s: Option<f64>,
}

/// Meshes one component, writing `<out>/mesh/<name>.geo` and `.msh` when gmsh runs.
pub fn mesh_component(
    scene: &Scene,
    c: &ComponentSpec,
    dir: &RunDir,
    progress: &Progress,
) -> Result<(Mesh, MeshReport), PipelineError> {
    let err = |source| PipelineError::Mesh {
        component: c.name.clone(),
        source,
    };
    let (msh_path, gmsh_s) = match &c.geometry {
        GeometrySpec::Msh { path } => (scene.resolve(path), None),
        g => {
            let text = match g {
                GeometrySpec::Rotor(r) => geo::rotor(r),
                GeometrySpec::Block(b) => geo::block(b),
                GeometrySpec::Pad { .. } => geo::pad(&scene.pad_geometry(&c.name)?),
                GeometrySpec::Caliper { .. } => geo::caliper(&scene.caliper_geometry(&c.name)?),
                GeometrySpec::Msh { .. } => unreachable!("handled above"),
            };
            let mesh_dir = dir.subdir("mesh")?;
            let out = mesh_dir.join(format!("{}.msh", c.name));
            let step = progress.step(format!("gmsh: meshing `{}`", c.name));
            let opts = gmsh::GmshOptions {
                order: c.element.gmsh_order(),
                ..Default::default()
            };
            let run = gmsh::mesh_geo(&text, &out, &opts).map_err(err)?;
            step.done(format!(
                "gmsh: meshed `{}` in {:.2} s",
                c.name, run.elapsed_s
            ));
            (out, Some(run.elapsed_s))
        }
    };
    let mesh = msh::read_msh(&msh_path).map_err(err)?;
    let report = MeshReport {
        component: c.name.clone(),
        n_nodes: mesh.nodes.len(),
        n_cells: mesh.volumes.iter().map(|b| b.len()).sum(),
        msh_path: msh_path.display().to_string(),
        gmsh_s,
    };
    Ok((mesh, report))
}

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
        vtu::write_vtu(&mesh_dir.join(format!("{}.vtu", c.name)), &mesh, &[], &[]).map_err(
            |source| PipelineError::Mesh {
                component: c.name.clone(),
                source,
            },
        )?;
        progress.info(format!(
            "{}: {} nodes, {} cells",
            report.component, report.n_nodes, report.n_cells
        ));
        reports.push(report);
    }
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    dir.write_json(
        "summary.json",
        &serde_json::json!({ "verb": "mesh", "version": crate::VERSION, "components": reports }),
    )?;
    Ok(reports)
}
