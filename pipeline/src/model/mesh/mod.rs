//! A component's mesh: its geometry → gmsh → [`Mesh`], or the user's own `.msh`, Nastran
//! bulk data or Abaqus input.

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{ComponentSpec, GeometrySpec, Scene};
use serde::Serialize;
use squeal_meshes::{bdf, geo, gmsh, inp, msh, Mesh, ReadReport};

pub mod fixed;
pub mod groups;

pub use fixed::{check_not_all_fixed, fixed_dofs};

/// What meshing one component produced.
#[derive(Debug, Clone, Serialize)]
pub struct MeshReport {
    pub component: String,
    pub n_nodes: usize,
    pub n_cells: usize,
    pub msh_path: String,
    pub gmsh_s: Option<f64>,
    /// What a Nastran or Abaqus reader read, left out (unsupported cards, with counts) and
    /// changed (None for gmsh meshes).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reader: Option<ReadReport>,
}

impl MeshReport {
    /// The reader's unsupported cards as a warning, if any.
    pub fn warnings(&self) -> Vec<crate::warning::Warning> {
        let Some(r) = &self.reader else {
            return Vec::new();
        };
        r.unsupported_summary()
            .map(|message| crate::warning::Warning {
                input: format!("{} (component `{}`)", self.msh_path, self.component),
                message: format!("{message}: these cards are not in the model"),
                value: r.unsupported.iter().map(|u| u.count).sum::<usize>() as f64,
                tolerance: 0.0,
            })
            .into_iter()
            .collect()
    }
}

/// Meshes one component, writing `<out>/mesh/<name>.geo` and `.msh` when gmsh runs.
pub fn mesh_component(
    scene: &Scene,
    c: &ComponentSpec,
    dir: &RunDir,
    progress: &Progress,
) -> Result<(Mesh, MeshReport), PipelineError> {
    let err = |source| PipelineError::mesh(&c.name, source);
    let opts = gmsh::GmshOptions {
        order: c.element.gmsh_order(),
        interrupt: progress.interrupt(),
        ..Default::default()
    };
    if let Some((mesh, report)) = read_industrial(scene, c)? {
        return Ok((mesh, report));
    }
    // The user's file (for errors naming a missing physical group), the mesh read, gmsh's time.
    let (source, msh_path, gmsh_s) = match &c.geometry {
        GeometrySpec::Msh { path } => {
            let p = scene.resolve(path);
            (p.clone(), p, None)
        }
        GeometrySpec::Geo { path, set_numbers } => {
            let geo_path = scene.resolve(path);
            check_set_numbers(scene, c, &geo_path, set_numbers)?;
            let out = dir.subdir("mesh")?.join(format!("{}.msh", c.name));
            let step = progress.step(format!(
                "gmsh: meshing `{}` from {}",
                c.name,
                geo_path.display()
            ));
            let opts = gmsh::GmshOptions {
                set_numbers: set_numbers.clone(),
                ..opts
            };
            let run = gmsh::mesh_geo_file(&geo_path, &out, &opts).map_err(err)?;
            step.done(format!(
                "gmsh: meshed `{}` in {:.2} s",
                c.name, run.elapsed_s
            ));
            (geo_path, out, Some(run.elapsed_s))
        }
        g => {
            let text = match g {
                GeometrySpec::Rotor(r) => geo::rotor(r),
                GeometrySpec::Block(b) => geo::block(b),
                GeometrySpec::Pad { .. } => geo::pad(&scene.pad_geometry(&c.name)?),
                GeometrySpec::Caliper { .. } => geo::caliper(&scene.caliper_geometry(&c.name)?),
                GeometrySpec::Msh { .. }
                | GeometrySpec::Geo { .. }
                | GeometrySpec::Bdf { .. }
                | GeometrySpec::Inp { .. } => {
                    unreachable!("handled above")
                }
            };
            let mesh_dir = dir.subdir("mesh")?;
            let out = mesh_dir.join(format!("{}.msh", c.name));
            let step = progress.step(format!("gmsh: meshing `{}`", c.name));
            let run = gmsh::mesh_geo(&text, &out, &opts).map_err(err)?;
            step.done(format!(
                "gmsh: meshed `{}` in {:.2} s",
                c.name, run.elapsed_s
            ));
            (out.clone(), out, Some(run.elapsed_s))
        }
    };
    let mut mesh = msh::read_msh(&msh_path).map_err(err)?;
    if matches!(
        c.geometry,
        GeometrySpec::Msh { .. } | GeometrySpec::Geo { .. }
    ) {
        groups::check_groups(scene, c, &mesh, &source)?;
    }
    if c.rotate_deg != 0.0 {
        let axis = scene.rotor.clone().unwrap_or_default();
        groups::rotate_nodes(&mut mesh, c.rotate_deg, axis.axis, axis.origin);
    }
    let report = MeshReport {
        component: c.name.clone(),
        n_nodes: mesh.nodes.len(),
        n_cells: mesh.volumes.iter().map(|b| b.len()).sum(),
        msh_path: msh_path.display().to_string(),
        gmsh_s,
        reader: None,
    };
    Ok((mesh, report))
}

/// A Nastran or Abaqus component: read, its sets checked against the scene, turned by
/// `rotate_deg` (None for the other kinds).
fn read_industrial(
    scene: &Scene,
    c: &ComponentSpec,
) -> Result<Option<(Mesh, MeshReport)>, PipelineError> {
    let err = |source| PipelineError::mesh(&c.name, source);
    let (path, (mut mesh, reader)) = match &c.geometry {
        GeometrySpec::Bdf { path, pids, spc } => {
            let p = scene.resolve(path);
            let opts = bdf::BdfOptions {
                pids: pids.clone(),
                spc: *spc,
            };
            (p.clone(), bdf::read_bdf(&p, &opts).map_err(err)?)
        }
        GeometrySpec::Inp {
            path,
            instances,
            part,
            elsets,
        } => {
            let p = scene.resolve(path);
            let opts = inp::InpOptions {
                instances: instances.clone(),
                part: part.clone(),
                elsets: elsets.clone(),
            };
            (p.clone(), inp::read_inp(&p, &opts).map_err(err)?)
        }
        _ => return Ok(None),
    };
    groups::check_groups(scene, c, &mesh, &path)?;
    if c.rotate_deg != 0.0 {
        let axis = scene.rotor.clone().unwrap_or_default();
        groups::rotate_nodes(&mut mesh, c.rotate_deg, axis.axis, axis.origin);
    }
    let report = MeshReport {
        component: c.name.clone(),
        n_nodes: mesh.nodes.len(),
        n_cells: mesh.volumes.iter().map(|b| b.len()).sum(),
        msh_path: path.display().to_string(),
        gmsh_s: None,
        reader: Some(reader),
    };
    Ok(Some((mesh, report)))
}

/// Every `set_numbers` key of a `.geo` component must be a `DefineConstant` of the file (or
/// of a file it includes): gmsh ignores any other name, and the mesh would silently have the
/// file's defaults. The error names the key and the constants the file defines.
fn check_set_numbers(
    scene: &Scene,
    c: &ComponentSpec,
    geo_path: &std::path::Path,
    set_numbers: &std::collections::BTreeMap<String, f64>,
) -> Result<(), PipelineError> {
    if set_numbers.is_empty() {
        return Ok(());
    }
    let defined = squeal_meshes::geo_file::defined_constants(geo_path)
        .map_err(|e| PipelineError::mesh(&c.name, e))?;
    if let Some(name) = set_numbers.keys().find(|k| !defined.contains(*k)) {
        let i = scene
            .components
            .iter()
            .position(|x| x.name == c.name)
            .unwrap_or(0);
        let list = if defined.is_empty() {
            "none".to_string()
        } else {
            defined.iter().cloned().collect::<Vec<_>>().join(", ")
        };
        return Err(PipelineError::Scene {
            field: format!("components[{i}].geometry.set_numbers.{name}"),
            message: format!(
                "{} has no `DefineConstant` named `{name}` (gmsh would ignore it and mesh the \
                 file's defaults); the constants it defines: {list}",
                geo_path.display()
            ),
        });
    }
    Ok(())
}
