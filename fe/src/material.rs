//! Isotropic linear-elastic material.

use crate::{FeError, Real};
use serde::{Deserialize, Serialize};

/// Isotropic linear-elastic material, consistent units (like NASTRAN's MAT1).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Material {
    /// Young's modulus E (> 0).
    pub young: Real,
    /// Poisson's ratio ν (−1 < ν < 0.5).
    pub poisson: Real,
    /// Mass density ρ (> 0).
    pub density: Real,
}

impl Material {
    /// Steel as used by the verification tests: E = 200 GPa, ν = 0.3, ρ = 8000 kg/m³ (SI).
    pub fn steel_si() -> Self {
        Material {
            young: 200e9,
            poisson: 0.3,
            density: 8000.0,
        }
    }

    /// Checks E > 0, −1 < ν < 0.5, ρ > 0; the error names the field and value.
    pub fn validate(&self) -> Result<(), FeError> {
        let bad = |field: &str, value: Real, reason| {
            Err(FeError::InvalidValue {
                field: field.to_string(),
                value,
                reason,
            })
        };
        if !(self.young > 0.0 && self.young.is_finite()) {
            return bad("material.young", self.young, "must be finite and > 0");
        }
        if !(self.poisson > -1.0 && self.poisson < 0.5) {
            return bad(
                "material.poisson",
                self.poisson,
                "must satisfy -1 < nu < 0.5",
            );
        }
        if !(self.density > 0.0 && self.density.is_finite()) {
            return bad("material.density", self.density, "must be finite and > 0");
        }
        Ok(())
    }

    /// Lamé constants (λ, μ).
    pub fn lame(&self) -> (Real, Real) {
        let (e, nu) = (self.young, self.poisson);
        let mu = e / (2.0 * (1.0 + nu));
        let lambda = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
        (lambda, mu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validate_names_the_value() {
        assert!(Material::steel_si().validate().is_ok());
        let m = Material {
            poisson: 0.5,
            ..Material::steel_si()
        };
        let msg = m.validate().unwrap_err().to_string();
        assert!(msg.contains("poisson") && msg.contains("0.5"), "{msg}");
        let m = Material {
            young: -1.0,
            ..Material::steel_si()
        };
        assert!(m.validate().unwrap_err().to_string().contains("young"));
        let m = Material {
            density: 0.0,
            ..Material::steel_si()
        };
        assert!(m.validate().unwrap_err().to_string().contains("density"));
    }

    #[test]
    fn lame_constants_of_steel() {
        // λ = Eν/((1+ν)(1−2ν)) = 115.38 GPa, μ = E/(2(1+ν)) = 76.92 GPa for E = 200 GPa, ν = 0.3.
        let (l, m) = Material::steel_si().lame();
        assert!((l - 200e9 * 0.3 / (1.3 * 0.4)).abs() < 1.0);
        assert!((m - 200e9 / 2.6).abs() < 1.0);
    }
}
