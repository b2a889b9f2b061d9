//! A component's material in the scene: isotropic (`young`, `poisson`, `density`, unchanged) or
//! anisotropic with material axes.
//!
//! ```toml
//! material = { young = 2.1e11, poisson = 0.3, density = 7850.0 }
//! # transversely isotropic lining, axis 3 = the pad's thickness direction (global z here)
//! materials = { lining = { density = 2500.0, transversely_isotropic = { e_plane = 8e9,
//!     e_axis = 2e9, nu_plane = 0.25, nu_plane_axis = 0.3, g_axis = 1e9 },
//!     axes = { kind = "rectangular", e1 = [1, 0, 0], e2 = [0, 1, 0] } } }
//! # orthotropic rotor with cylindrical axes (1 radial, 2 circumferential, 3 axial)
//! material = { density = 7200.0, orthotropic = { e1 = 1.1e11, e2 = 1.2e11, e3 = 1.0e11,
//!     nu12 = 0.26, nu13 = 0.26, nu23 = 0.26, g12 = 4.4e10, g13 = 4.2e10, g23 = 4.3e10 },
//!     axes = { kind = "cylindrical", origin = [0, 0, 0], axis = [0, 0, 1] } }
//! ```
//! `anisotropic = [[…6 numbers…] × 6]` gives a general D (Voigt order 11, 22, 33, 23, 13, 12
//! with engineering shears). Exactly one elasticity is required; every failing value is named.
//!
//! `loss_factor = η` (NASTRAN's MAT1 GE, Abaqus's `*DAMPING, STRUCTURAL`) is the material's
//! structural damping: its bodies add (η/W4)·K_body to the component's element damping
//! (`[damping] w4`, [`super::transient::DampingSpec`]); e.g. a shim
//! `materials = { shim = { young = 2e9, poisson = 0.45, density = 1200.0, loss_factor = 0.3 } }`.

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_fe::{Elasticity, MaterialAxes, Orthotropic, SolidMaterial, TransverselyIsotropic};

use squeal_solver::Real;

/// One material of a component (see the module documentation).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Isotropic Young's modulus (with `poisson`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub young: Option<Real>,
    /// Isotropic Poisson's ratio (with `young`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub poisson: Option<Real>,
    /// Mass density (required).
    pub density: Real,
    /// Orthotropic engineering constants in the material axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orthotropic: Option<Orthotropic>,
    /// Transversely isotropic constants (isotropic 1–2 plane, axis 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub transversely_isotropic: Option<TransverselyIsotropic>,
    /// A general 6×6 D in the material axes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub anisotropic: Option<[[Real; 6]; 6]>,
    /// Material axes (default: global).
    #[serde(default, skip_serializing_if = "is_global")]
    pub axes: MaterialAxes,
    /// Structural loss factor η (NASTRAN's GE), finite and >= 0: viscous (η/W4)·K of its
    /// bodies at `damping.w4` (default: 0).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub loss_factor: Real,
}

fn is_global(a: &MaterialAxes) -> bool {
    *a == MaterialAxes::Global
}

fn is_zero(x: &Real) -> bool {
    *x == 0.0
}

/// Checks a loss factor η (finite, >= 0); the error names `field` (the key) and the value.
pub fn check_loss_factor(field: &str, eta: Real) -> Result<(), PipelineError> {
    if eta.is_finite() && eta >= 0.0 {
        return Ok(());
    }
    Err(PipelineError::Scene {
        field: field.to_string(),
        message: format!(
            "loss factor {eta} must be finite and >= 0 (the structural damping η, NASTRAN's GE)"
        ),
    })
}

impl From<squeal_fe::Material> for MaterialSpec {
    fn from(m: squeal_fe::Material) -> Self {
        MaterialSpec {
            young: Some(m.young),
            poisson: Some(m.poisson),
            density: m.density,
            orthotropic: None,
            transversely_isotropic: None,
            anisotropic: None,
            axes: MaterialAxes::Global,
            loss_factor: 0.0,
        }
    }
}

impl MaterialSpec {
    /// The material, checked (positive definite, axes valid); errors name `field`.
    pub fn solid(&self, field: &str) -> Result<SolidMaterial, PipelineError> {
        let err = |message: String| PipelineError::Scene {
            field: field.to_string(),
            message,
        };
        check_loss_factor(&format!("{field}.loss_factor"), self.loss_factor)?;
        let mut given = Vec::new();
        if self.young.is_some() || self.poisson.is_some() {
            given.push("young/poisson");
        }
        if self.orthotropic.is_some() {
            given.push("orthotropic");
        }
        if self.transversely_isotropic.is_some() {
            given.push("transversely_isotropic");
        }
        if self.anisotropic.is_some() {
            given.push("anisotropic");
        }
        if given.len() != 1 {
            return Err(err(format!(
                "give exactly one elasticity (young and poisson, orthotropic, \
                 transversely_isotropic or anisotropic); found: {}",
                if given.is_empty() {
                    "none".into()
                } else {
                    given.join(", ")
                }
            )));
        }
        let elasticity = match (self.young, self.poisson) {
            (Some(young), Some(poisson)) => Elasticity::Isotropic { young, poisson },
            (Some(_), None) => return Err(err("`young` needs `poisson`".into())),
            (None, Some(_)) => return Err(err("`poisson` needs `young`".into())),
            (None, None) => {
                if let Some(o) = self.orthotropic {
                    Elasticity::Orthotropic(o)
                } else if let Some(t) = self.transversely_isotropic {
                    Elasticity::TransverselyIsotropic(t)
                } else {
                    Elasticity::Anisotropic {
                        stiffness: self.anisotropic.unwrap_or_default(),
                    }
                }
            }
        };
        let m = SolidMaterial {
            elasticity,
            density: self.density,
            axes: self.axes.clone(),
        };
        m.validate(field).map_err(|e| err(e.to_string()))?;
        Ok(m)
    }

    /// Checks the material (see [`MaterialSpec::solid`]).
    pub fn validate(&self, field: &str) -> Result<(), PipelineError> {
        self.solid(field).map(|_| ())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isotropic_keys_and_anisotropic_tables() {
        let m: MaterialSpec =
            toml::from_str("young = 2.0e11\npoisson = 0.3\ndensity = 7800.0").unwrap();
        assert_eq!(
            m.solid("m").unwrap(),
            SolidMaterial::from(squeal_fe::Material {
                young: 2.0e11,
                poisson: 0.3,
                density: 7800.0
            })
        );
        let t: MaterialSpec = toml::from_str(
            "density = 2500.0\ntransversely_isotropic = { e_plane = 8e9, e_axis = 2e9, \
             nu_plane = 0.25, nu_plane_axis = 0.3, g_axis = 1e9 }\naxes = { kind = \
             \"cylindrical\", origin = [0.0, 0.0, 0.0], axis = [0.0, 0.0, 1.0] }",
        )
        .unwrap();
        assert!(t.solid("lining").is_ok());
        let bad = MaterialSpec {
            transversely_isotropic: Some(TransverselyIsotropic {
                nu_plane: 1.2,
                ..t.transversely_isotropic.unwrap()
            }),
            ..t.clone()
        };
        let e = bad
            .solid("components[1].materials.lining")
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("components[1].materials.lining") && e.contains("1.2"),
            "{e}"
        );
        let both = MaterialSpec {
            young: Some(1.0),
            poisson: Some(0.3),
            ..t
        };
        let e = both.solid("m").unwrap_err().to_string();
        assert!(e.contains("exactly one"), "{e}");
        assert!(
            toml::from_str::<MaterialSpec>("young = 1.0\npoison = 0.3\ndensity = 1.0").is_err()
        );
    }
}
