//! Brake components whose geometry depends on other components (a pad on its rotor's mesh, a
//! caliper over its two pads).

use super::{ComponentSpec, GeometrySpec, Scene};
use crate::error::PipelineError;
use squeal_meshes::geo::{CaliperGeometry, PadGeometry, RotorGeometry};

pub(crate) fn default_rotor_name() -> String {
    "rotor".into()
}
pub(crate) fn default_inboard_name() -> String {
    "inboard_pad".into()
}
pub(crate) fn default_outboard_name() -> String {
    "outboard_pad".into()
}

fn scene_err(field: String, message: impl ToString) -> PipelineError {
    PipelineError::Scene {
        field,
        message: message.to_string(),
    }
}

impl Scene {
    fn named(&self, name: &str, field: &str) -> Result<&ComponentSpec, PipelineError> {
        self.components
            .iter()
            .find(|c| c.name == name)
            .ok_or_else(|| {
                scene_err(
                    field.to_string(),
                    format!(
                        "no component named `{name}` (the scene has: {})",
                        self.components
                            .iter()
                            .map(|c| c.name.as_str())
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                )
            })
    }

    fn rotor_geometry(&self, name: &str, field: &str) -> Result<&RotorGeometry, PipelineError> {
        match &self.named(name, field)?.geometry {
            GeometrySpec::Rotor(r) => Ok(r),
            _ => Err(scene_err(
                field.to_string(),
                format!("component `{name}` is not a parametric rotor (kind = \"rotor\")"),
            )),
        }
    }

    /// The geometry of the pad component `name`, placed on its rotor's mesh.
    pub fn pad_geometry(&self, name: &str) -> Result<PadGeometry, PipelineError> {
        let field = format!("components[name = {name}].geometry");
        match &self.named(name, &field)?.geometry {
            GeometrySpec::Pad { rotor, placement } => {
                let r = self.rotor_geometry(rotor, &format!("{field}.rotor"))?;
                PadGeometry::on_rotor(r, placement).map_err(|e| scene_err(field, e))
            }
            _ => Err(scene_err(
                field,
                format!("component `{name}` is not a pad (kind = \"pad\")"),
            )),
        }
    }

    /// The geometry of the caliper component `name`, over its two pads.
    pub fn caliper_geometry(&self, name: &str) -> Result<CaliperGeometry, PipelineError> {
        let field = format!("components[name = {name}].geometry");
        match &self.named(name, &field)?.geometry {
            GeometrySpec::Caliper {
                inboard,
                outboard,
                dims,
            } => {
                let inb = self.pad_geometry(inboard)?;
                let outb = self.pad_geometry(outboard)?;
                let rotor = match &self.named(inboard, &field)?.geometry {
                    GeometrySpec::Pad { rotor, .. } => {
                        self.rotor_geometry(rotor, &format!("{field}.inboard"))?
                    }
                    _ => unreachable!("pad_geometry checked the kind"),
                };
                CaliperGeometry::over_pads(rotor, &inb, &outb, dims)
                    .map_err(|e| scene_err(field, e))
            }
            _ => Err(scene_err(
                field,
                format!("component `{name}` is not a caliper (kind = \"caliper\")"),
            )),
        }
    }

    /// Checks what [`Scene::validate`] cannot see from one component alone: pads and calipers
    /// resolve against the components they name, and the per-volume `materials` are valid.
    pub(crate) fn validate_brake_component(
        &self,
        i: usize,
        c: &ComponentSpec,
    ) -> Result<(), PipelineError> {
        match &c.geometry {
            GeometrySpec::Pad { .. } => {
                self.pad_geometry(&c.name)?;
            }
            GeometrySpec::Caliper { .. } => {
                self.caliper_geometry(&c.name)?;
            }
            _ => {}
        }
        for (volume, m) in &c.materials {
            m.validate(&format!("components[{i}].materials.{volume}"))?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use squeal_meshes::Mesh;

    const BRAKE: &str = r#"
[[components]]
name = "rotor"
geometry = { kind = "rotor", n_circ = 32, n_rad = 3, n_thick = 1 }
material = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }

[[components]]
name = "inboard_pad"
geometry = { kind = "pad", side = "top", start_element = -2, n_elements = 4, first_ring = 1, last_ring = 3 }
material = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }
materials = { lining = { young = 1.0e6, poisson = 0.25, density = 2.5e-4 } }

[[components]]
name = "outboard_pad"
geometry = { kind = "pad", side = "bottom", start_element = -2, n_elements = 4, first_ring = 1, last_ring = 3 }
material = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }

[[components]]
name = "caliper"
geometry = { kind = "caliper", clearance = 0.3 }
material = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }
"#;

    fn scene(text: &str) -> Result<Scene, PipelineError> {
        let s: Scene = toml::from_str(text).map_err(|e| PipelineError::Scene {
            field: "toml".into(),
            message: e.to_string(),
        })?;
        s.validate()?;
        Ok(s)
    }

    #[test]
    fn pads_and_caliper_resolve_against_the_rotor() {
        let s = scene(BRAKE).unwrap();
        let p = s.pad_geometry("inboard_pad").unwrap();
        // Rings 1..3 of a 2.0..5.5 rotor in 3 rings: r = 2 + 3.5/3 .. 5.5; 4 of 32 elements.
        assert!((p.r_in - (2.0 + 3.5 / 3.0)).abs() < 1e-12 && p.r_out == 5.5);
        assert_eq!((p.theta_start_deg, p.theta_span_deg), (-22.5, 45.0));
        let c = s.caliper_geometry("caliper").unwrap();
        assert!((c.r_bridge_in - 5.8).abs() < 1e-12);
        assert!((c.z_piston - 1.1).abs() < 1e-12 && (c.z_finger + 0.6).abs() < 1e-12);
    }

    #[test]
    fn typos_and_dangling_names_are_errors_naming_them() {
        let e = scene(&BRAKE.replace("first_ring = 1", "first_rign = 1"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("first_rign"), "{e}");
        let e = scene(&BRAKE.replace("clearance = 0.3", "clearence = 0.3"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("clearence"), "{e}");
        let e = scene(&BRAKE.replace("name = \"outboard_pad\"", "name = \"outer\""))
            .unwrap_err()
            .to_string();
        assert!(e.contains("outboard_pad"), "{e}");
        let e = scene(&BRAKE.replace("last_ring = 3 }\nmaterial = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }\nmaterials", "last_ring = 4 }\nmaterial = { young = 3.0e7, poisson = 0.29, density = 7.33e-4 }\nmaterials"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("last_ring"), "{e}");
        let e = scene(&BRAKE.replace("poisson = 0.25", "poisson = 0.6"))
            .unwrap_err()
            .to_string();
        assert!(e.contains("materials.lining"), "{e}");
    }

    #[test]
    fn block_materials_by_volume_name() {
        let s = scene(BRAKE).unwrap();
        let c = &s.components[1];
        let mut mesh = Mesh::default();
        for name in ["lining", "backplate"] {
            mesh.volumes.push(squeal_meshes::CellBlock {
                name: Some(name.into()),
                kind: squeal_meshes::CellKind::Hex8,
                conn: vec![],
                tags: vec![],
            });
        }
        let m = c.block_materials(&mesh).unwrap();
        let young = |m: &squeal_fe::SolidMaterial| match m.elasticity {
            squeal_fe::Elasticity::Isotropic { young, .. } => young,
            _ => f64::NAN,
        };
        assert_eq!(young(&m[0]), 1.0e6);
        assert_eq!(young(&m[1]), 3.0e7);
        mesh.volumes[0].name = Some("linning".into());
        let e = c.block_materials(&mesh).unwrap_err().to_string();
        assert!(e.contains("lining") && e.contains("linning"), "{e}");
    }
}
