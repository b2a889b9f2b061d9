//! The material of each volume block of a component's mesh: the scene's `materials.<name>`,
//! else the file's own section (Nastran PSOLID → MAT1/MAT9 with CORDM, Abaqus *SOLID SECTION →
//! *MATERIAL with *ORIENTATION), else the scene's `material`.

use super::ComponentSpec;
use crate::error::PipelineError;
use squeal_fe::{Elasticity, MaterialAxes, Orthotropic, SolidMaterial};
use squeal_meshes::{AxesKind, Elastic, Mesh, Section};

fn scene_err(field: String, message: impl ToString) -> PipelineError {
    PipelineError::Scene {
        field,
        message: message.to_string(),
    }
}

impl ComponentSpec {
    /// One material per volume block of `mesh` (in `mesh.volumes` order): the entry of
    /// `materials` named as the block, else the file's section of that name (its elasticity,
    /// density and material axes), else `material`. A `materials` name that no block has is an
    /// error (a typo would otherwise silently give another material); so is a block with none
    /// of the three. Every material is checked (positive definite, axes valid).
    pub fn block_materials(&self, mesh: &Mesh) -> Result<Vec<SolidMaterial>, PipelineError> {
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
                if let Some((n, m)) = name.and_then(|n| self.materials.get(n).map(|m| (n, m))) {
                    return m.solid(&format!("components[name = {}].materials.{n}", self.name));
                }
                if let Some((n, sec)) = name.and_then(|n| mesh.sections.get(n).map(|s| (n, s))) {
                    return self.section_material(n, sec);
                }
                match &self.material {
                    Some(m) => m.solid(&format!("components[name = {}].material", self.name)),
                    None => Err(scene_err(
                        format!("components[name = {}].material", self.name),
                        format!(
                            "volume `{}` has no material in the file: give `material` (or \
                             `materials.{}`)",
                            name.unwrap_or("(unnamed)"),
                            name.unwrap_or("<volume>")
                        ),
                    )),
                }
            })
            .collect()
    }

    /// fe's material for a file section (the errors name the volume, the file's material and
    /// where it is defined).
    fn section_material(&self, block: &str, sec: &Section) -> Result<SolidMaterial, PipelineError> {
        let field = format!("components[name = {}].materials.{block}", self.name);
        let m = &sec.material;
        let what = format!(
            "volume `{block}`: {} ({}, {})",
            m.name, m.source, sec.source
        );
        let elasticity = match m.elastic {
            Elastic::Isotropic { young, poisson } => Elasticity::Isotropic { young, poisson },
            Elastic::EngineeringConstants {
                young,
                poisson,
                shear,
            } => Elasticity::Orthotropic(Orthotropic {
                e1: young[0],
                e2: young[1],
                e3: young[2],
                nu12: poisson[0],
                nu13: poisson[1],
                nu23: poisson[2],
                g12: shear[0],
                g13: shear[1],
                g23: shear[2],
            }),
            // The same Voigt order (11, 22, 33, 23, 13, 12) in both crates.
            Elastic::Stiffness { c } => Elasticity::Anisotropic { stiffness: c },
        };
        let Some(density) = m.density else {
            return Err(scene_err(
                field,
                format!(
                    "{what} has no density: give it in the file (MAT1/MAT9 RHO, *DENSITY) or \
                     set `materials.{block}`"
                ),
            ));
        };
        let axes = match &sec.axes {
            None => MaterialAxes::Global,
            Some(a) => match a.kind {
                AxesKind::Rectangular => MaterialAxes::Rectangular {
                    e1: a.frame[0],
                    e2: a.frame[1],
                },
                AxesKind::Cylindrical => MaterialAxes::Cylindrical {
                    origin: a.origin,
                    axis: a.frame[2],
                },
                AxesKind::Spherical => {
                    return Err(scene_err(
                        field,
                        format!(
                            "{what}: spherical material axes are not supported (rectangular \
                             and cylindrical are); set `materials.{block}` with its axes"
                        ),
                    ))
                }
            },
        };
        let solid = SolidMaterial {
            elasticity,
            density,
            axes,
        };
        solid
            .validate(&field)
            .map_err(|e| scene_err(field.clone(), format!("{what}: {e}")))?;
        Ok(solid)
    }
}
