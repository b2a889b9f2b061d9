//! Evaluation, dependency flags and validation of [`FrictionLaw`].

use super::{FrictionEval, FrictionLaw};
use crate::{ContactError, Real};

fn bad(field: &str, value: Real, reason: &str) -> ContactError {
    // 1e300 in full is 301 digits: large and tiny values in scientific notation.
    let big_or_tiny =
        value.is_finite() && (value.abs() >= 1e6 || (value != 0.0 && value.abs() < 1e-4));
    ContactError::InvalidOption {
        field: field.to_string(),
        value: if big_or_tiny {
            format!("{value:e}")
        } else {
            format!("{value}")
        },
        reason: reason.to_string(),
    }
}

/// Largest friction coefficient a law may give (at its reference point: `mu`, `mu0`, every
/// table value).
///
/// The largest coefficients measured between solids are a few units — clean metals in vacuum,
/// where the junctions grow by adhesion, reach μ ≈ 5–10 (Bowden & Tabor, *The Friction and
/// Lubrication of Solids*, 1950/1964), rubber on glass 2–4 — and brake pad/rotor pairs run at
/// 0.3–0.7. Above 10 the value is a unit or typing mistake (μ = 1e300 passed validation and
/// then failed as a singular steady-state Newton matrix), not a material.
pub const MU_MAX: Real = 10.0;

fn mu_value(field: &str, value: Real) -> Result<(), ContactError> {
    finite(field, value)?;
    if !(0.0..=MU_MAX).contains(&value) {
        return Err(bad(
            field,
            value,
            "must be in [0, 10] (MU_MAX: the largest friction coefficients measured between \
             solids, clean metals in vacuum, are below 10; brake pairs run at 0.3-0.7)",
        ));
    }
    Ok(())
}

fn finite(field: &str, value: Real) -> Result<(), ContactError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(bad(field, value, "must be finite"))
    }
}

impl FrictionLaw {
    /// μ and its partial derivatives at pressure `p`, sliding speed `speed` = |V_t| ≥ 0 and
    /// temperature `temperature`. Derivatives the law does not depend on are exactly 0.
    ///
    /// # Reference
    /// $$F_t = \mu(p_n, |V_t|, T)\, A\, p_n$$ [Paper eq. (4)] — this function is the μ( ) of it.
    pub fn evaluate(&self, p: Real, speed: Real, temperature: Real) -> FrictionEval {
        match self {
            FrictionLaw::Constant { mu } => FrictionEval {
                mu: *mu,
                ..FrictionEval::default()
            },
            FrictionLaw::LinearSpeed { mu0, slope } => FrictionEval {
                mu: mu0 + slope * speed,
                dmu_dv: *slope,
                ..FrictionEval::default()
            },
            FrictionLaw::Equation { mu0, a, b, c, t0 } => {
                let fp = 1.0 + a * p;
                let fv = 1.0 + b * speed;
                let ft = 1.0 + c * (temperature - t0);
                FrictionEval {
                    mu: mu0 * fp * fv * ft,
                    dmu_dp: mu0 * a * fv * ft,
                    dmu_dv: mu0 * fp * b * ft,
                    dmu_dt: mu0 * fp * fv * c,
                }
            }
            FrictionLaw::Table(t) => t.evaluate(p, speed, temperature),
        }
    }

    /// Whether μ depends on the contact pressure (∂μ/∂p may be non-zero).
    pub fn depends_on_pressure(&self) -> bool {
        match self {
            FrictionLaw::Constant { .. } | FrictionLaw::LinearSpeed { .. } => false,
            FrictionLaw::Equation { mu0, a, .. } => *mu0 != 0.0 && *a != 0.0,
            FrictionLaw::Table(t) => t.pressures.len() >= 2,
        }
    }

    /// Whether μ depends on the sliding speed |V_t| (∂μ/∂|V_t| may be non-zero).
    pub fn depends_on_speed(&self) -> bool {
        match self {
            FrictionLaw::Constant { .. } => false,
            FrictionLaw::LinearSpeed { slope, .. } => *slope != 0.0,
            FrictionLaw::Equation { mu0, b, .. } => *mu0 != 0.0 && *b != 0.0,
            FrictionLaw::Table(t) => t.speeds.len() >= 2,
        }
    }

    /// Whether μ depends on the temperature (only then are temperatures looked up).
    pub fn depends_on_temperature(&self) -> bool {
        match self {
            FrictionLaw::Constant { .. } | FrictionLaw::LinearSpeed { .. } => false,
            FrictionLaw::Equation { mu0, c, .. } => *mu0 != 0.0 && *c != 0.0,
            FrictionLaw::Table(t) => t.temperatures.len() >= 2,
        }
    }

    /// Checks the parameters; the error names the field (`friction.mu`, ...) and the value.
    pub fn validate(&self) -> Result<(), ContactError> {
        match self {
            FrictionLaw::Constant { mu } => mu_value("friction.mu", *mu)?,
            FrictionLaw::LinearSpeed { mu0, slope } => {
                mu_value("friction.mu0", *mu0)?;
                finite("friction.slope", *slope)?;
            }
            FrictionLaw::Equation { mu0, a, b, c, t0 } => {
                finite("friction.mu0", *mu0)?;
                finite("friction.a", *a)?;
                finite("friction.b", *b)?;
                finite("friction.c", *c)?;
                finite("friction.t0", *t0)?;
                mu_value("friction.mu0", *mu0)?;
            }
            FrictionLaw::Table(t) => t.validate()?,
        }
        Ok(())
    }
}
