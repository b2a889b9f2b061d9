//! The material of each volume block of a component's mesh: the scene's `materials.<name>`,
//! else the file's own section (Nastran PSOLID → MAT1, Abaqus *SOLID SECTION → *MATERIAL),
//! else the scene's `material`.

use super::ComponentSpec;
use crate::error::PipelineError;
use squeal_fe::Material;
use squeal_meshes::{Elastic, Mesh, Section};

fn scene_err(field: String, message: impl ToString) -> PipelineError {
    PipelineError::Scene {
        field,
        message: message.to_string(),
    }
}

impl ComponentSpec {
    /// One material per volume block of `mesh` (in `mesh.volumes` order): the entry of
    /// `materials` named as the block, else the file's section of that name (isotropic with a
    /// density; anisotropic sections are not yet supported and say so), else `material`. A
    /// `materials` name that no block has is an error (a typo would otherwise silently give
    /// another material); so is a block with none of the three.
    pub fn block_materials(&self, mesh: &Mesh) -> Result<Vec<Material>, PipelineError> {
        let names: Vec<&str> = mesh
            .volumes
            .iter()
            .filter_map(|b| b.name.as_deref())
            .collect();
        if let Some(unknown) = self.materials.keys().find(|k| !names.contains(&k.as_str())) {
            return Err(scene_err(
                format!("components[name = {}].materials.{unknown}", self.name),
                format!(
                    "the mesh has no volume `{unknown}` (it has: {})",
                    names.join(", ")
                ),
            ));
        }
        mesh.volumes
            .iter()
            .map(|b| {
                let name = b.name.as_deref();
                if let Some(m) = name.and_then(|n| self.materials.get(n)) {
                    return Ok(*m);
                }
                if let Some(sec) = name.and_then(|n| mesh.sections.get(n)) {
                    return self.section_material(name.unwrap_or(""), sec);
                }
                self.material.ok_or_else(|| {
                    scene_err(
                        format!("components[name = {}].material", self.name),
                        format!(
                            "volume `{}` has no material in the file: give `material` (or \
                             `materials.{}`)",
                            name.unwrap_or("(unnamed)"),
                            name.unwrap_or("<volume>")
                        ),
                    )
                })
            })
            .collect()
    }

    /// fe's material for a file section: isotropic only until fe has anisotropic elasticity.
    fn section_material(&self, block: &str, sec: &Section) -> Result<Material, PipelineError> {
        let field = format!("components[name = {}].materials.{block}", self.name);
        let m = &sec.material;
        let Elastic::Isotropic { young, poisson } = m.elastic else {
            return Err(scene_err(
                field,
                format!(
                    "volume `{block}`: {} ({}, {}) is anisotropic ({}); anisotropic materials \
                     are not yet supported: set `materials.{block}` to an isotropic material \
                     to run without it",
                    m.name,
                    m.source,
                    sec.source,
                    match m.elastic {
                        Elastic::EngineeringConstants { .. } => "engineering constants",
                        _ => "a 6×6 stiffness",
                    }
                ),
            ));
        };
        let Some(density) = m.density else {
            return Err(scene_err(
                field,
                format!(
                    "volume `{block}`: {} ({}) has no density: give it in the file (MAT1 RHO, \
                     *DENSITY) or set `materials.{block}`",
                    m.name, m.source
                ),
            ));
        };
        let mat = Material {
            young,
            poisson,
            density,
        };
        mat.validate().map_err(|e| {
            scene_err(
                field.clone(),
                format!("volume `{block}`: {} ({}): {e}", m.name, m.source),
            )
        })?;
        Ok(mat)
    }
}
