//! The material of each volume block of a component's mesh: the scene's `materials.<name>`,
//! else the file's own section (Nastran PSOLID → MAT1/MAT9 with CORDM, Abaqus *SOLID SECTION →
//! *MATERIAL with *ORIENTATION), else the scene's `material`.

use super::material::{check_loss_factor, MaterialSpec};
use super::ComponentSpec;
use crate::error::PipelineError;
use squeal_fe::{Elasticity, MaterialAxes, Orthotropic, SolidMaterial};
use squeal_meshes::{AxesKind, Elastic, Mesh, Section};

use squeal_solver::Real;

/// The structural loss factor of one volume block.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockLoss {
    /// The volume's name (`(unnamed)` when it has none).
    pub volume: String,
    /// Where η is given: the scene key, or the volume and the file's material and place.
    pub input: String,
    /// η (NASTRAN's GE), finite and >= 0.
    pub eta: Real,
}

/// Where a block's material comes from.
enum Source<'a> {
    /// The scene's `materials.<name>` or `material` (its field).
    Scene(String, &'a MaterialSpec),
    /// The file's section of that name.
    Section(&'a str, &'a Section),
}

/// `m` with its elasticity scaled by `f` (every modulus; Poisson's ratios kept): the element
/// stiffness is linear in the elasticity tensor, so its K is f·K. Density and axes unchanged.
pub fn scaled_stiffness(m: &SolidMaterial, f: Real) -> SolidMaterial {
    let mut m = m.clone();
    m.elasticity = match m.elasticity {
        Elasticity::Isotropic { young, poisson } => Elasticity::Isotropic {
            young: f * young,
            poisson,
        },
        Elasticity::Orthotropic(mut o) => {
            for x in [
                &mut o.e1, &mut o.e2, &mut o.e3, &mut o.g12, &mut o.g13, &mut o.g23,
            ] {
                *x *= f;
            }
            Elasticity::Orthotropic(o)
        }
        Elasticity::TransverselyIsotropic(mut t) => {
            for x in [&mut t.e_plane, &mut t.e_axis, &mut t.g_axis] {
                *x *= f;
            }
            Elasticity::TransverselyIsotropic(t)
        }
        Elasticity::Anisotropic { stiffness } => Elasticity::Anisotropic {
            stiffness: stiffness.map(|row| row.map(|x| f * x)),
        },
    };
    m
}

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
        self.check_material_names(mesh)?;
        mesh.volumes
            .iter()
            .map(|b| match self.block_source(mesh, b.name.as_deref())? {
                Source::Scene(field, m) => m.solid(&field),
                Source::Section(n, sec) => self.section_material(n, sec),
            })
            .collect()
    }

    /// The structural loss factor η of each volume block of `mesh` (in `mesh.volumes` order),
    /// from the same material as [`ComponentSpec::block_materials`] takes: the scene's
    /// `loss_factor` key, or the file's GE (MAT1/MAT9) or `*DAMPING, STRUCTURAL`. Errors name
    /// the key or the file's material and the value (η must be finite and >= 0).
    pub fn block_loss_factors(&self, mesh: &Mesh) -> Result<Vec<BlockLoss>, PipelineError> {
        self.check_material_names(mesh)?;
        mesh.volumes
            .iter()
            .map(|b| {
                let volume = b.name.clone().unwrap_or_else(|| "(unnamed)".into());
                let (input, eta) = match self.block_source(mesh, b.name.as_deref())? {
                    Source::Scene(field, m) => (format!("{field}.loss_factor"), m.loss_factor),
                    Source::Section(n, sec) => (
                        format!(
                            "components[name = {}].materials.{n} ({}, {})",
                            self.name, sec.material.name, sec.material.source
                        ),
                        sec.material.structural_damping.unwrap_or(0.0),
                    ),
                };
                check_loss_factor(&input, eta)?;
                Ok(BlockLoss { volume, input, eta })
            })
            .collect()
    }

    /// A `materials` name that no block has is an error (a typo would otherwise silently
    /// give another material).
    fn check_material_names(&self, mesh: &Mesh) -> Result<(), PipelineError> {
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
        Ok(())
    }

    /// Where the material of the block named `name` comes from (see
    /// [`ComponentSpec::block_materials`]).
    fn block_source<'a>(
        &'a self,
        mesh: &'a Mesh,
        name: Option<&'a str>,
    ) -> Result<Source<'a>, PipelineError> {
        if let Some((n, m)) = name.and_then(|n| self.materials.get(n).map(|m| (n, m))) {
            return Ok(Source::Scene(
                format!("components[name = {}].materials.{n}", self.name),
                m,
            ));
        }
        if let Some((n, sec)) = name.and_then(|n| mesh.sections.get(n).map(|s| (n, s))) {
            return Ok(Source::Section(n, sec));
        }
        match &self.material {
            Some(m) => Ok(Source::Scene(
                format!("components[name = {}].material", self.name),
                m,
            )),
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
