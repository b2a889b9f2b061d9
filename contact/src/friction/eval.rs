//! Evaluation, dependency flags and validation of [`FrictionLaw`].

use super::{FrictionEval, FrictionLaw};
use crate::{ContactError, Real};

fn bad(field: &str, value: Real, reason: &str) -> ContactError {
    ContactError::InvalidOption {
        field: field.to_string(),
        value: format!("{value}"),
        reason: reason.to_string(),
    }
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
            FrictionLaw::Constant { mu } => {
                finite("friction.mu", *mu)?;
                if *mu < 0.0 {
                    return Err(bad("friction.mu", *mu, "must be >= 0"));
                }
            }
            FrictionLaw::LinearSpeed { mu0, slope } => {
                finite("friction.mu0", *mu0)?;
                finite("friction.slope", *slope)?;
                if *mu0 < 0.0 {
                    return Err(bad("friction.mu0", *mu0, "must be >= 0"));
                }
            }
            FrictionLaw::Equation { mu0, a, b, c, t0 } => {
                finite("friction.mu0", *mu0)?;
                finite("friction.a", *a)?;
                finite("friction.b", *b)?;
                finite("friction.c", *c)?;
                finite("friction.t0", *t0)?;
                if *mu0 < 0.0 {
                    return Err(bad("friction.mu0", *mu0, "must be >= 0"));
                }
            }
            FrictionLaw::Table(t) => t.validate()?,
        }
        Ok(())
    }
}
