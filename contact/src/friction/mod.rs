//! Friction laws μ(p_n, |V_t|, T) and their derivatives. [Paper eq. (4)]
//!
//! Four forms, chosen in the scene file by `kind` (serde, snake_case tags):
//!
//! | kind | μ | dependencies |
//! |---|---|---|
//! | `constant` | `mu` | none |
//! | `linear_speed` | `mu0 + slope·|V_t|` (paper's `0.7 − 0.0005 V`: `mu0 = 0.7, slope = −0.0005`) | speed |
//! | `equation` | `mu0·(1 + a·p)·(1 + b·|V_t|)·(1 + c·(T − t0))` | those whose coefficient ≠ 0 |
//! | `table` | multilinear interpolation in (p, |V_t|, T), clamped outside the knots | axes with ≥ 2 knots |
//!
//! No law is clamped at μ ≥ 0: a `linear_speed` law with a negative slope gives a negative μ
//! above `mu0/|slope|` (the paper's law at 1400 in/s); keep speeds inside the law's range.

mod eval;
mod table;

use crate::Real;
use serde::{Deserialize, Serialize};

pub use eval::MU_MAX;
pub use table::FrictionTable;

/// Value of a friction law and its partial derivatives at one (p, |V_t|, T).
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize)]
pub struct FrictionEval {
    /// Friction coefficient μ.
    pub mu: Real,
    /// ∂μ/∂p (0 when the law does not depend on pressure).
    pub dmu_dp: Real,
    /// ∂μ/∂|V_t| (0 when the law does not depend on speed).
    pub dmu_dv: Real,
    /// ∂μ/∂T (0 when the law does not depend on temperature).
    pub dmu_dt: Real,
}

fn zero() -> Real {
    0.0
}

/// A friction law μ(p, |V_t|, T). [Paper eq. (4)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum FrictionLaw {
    /// Constant μ (no derivatives are ever evaluated).
    Constant {
        /// Friction coefficient (required).
        mu: Real,
    },
    /// μ = mu0 + slope·|V_t| (the paper's cases 1–3: `0.7 − 0.0005 V`).
    LinearSpeed {
        /// μ at zero sliding speed (required).
        mu0: Real,
        /// dμ/d|V_t|, per unit of speed (required; negative = falling μ(v)).
        slope: Real,
    },
    /// μ = mu0·(1 + a·p)·(1 + b·|V_t|)·(1 + c·(T − t0)): a separable closed form.
    Equation {
        /// μ at p = 0, |V_t| = 0, T = t0 (required).
        mu0: Real,
        /// Relative pressure sensitivity, per unit of pressure (default: 0).
        #[serde(default = "zero")]
        a: Real,
        /// Relative speed sensitivity, per unit of speed (default: 0).
        #[serde(default = "zero")]
        b: Real,
        /// Relative temperature sensitivity, per degree (default: 0).
        #[serde(default = "zero")]
        c: Real,
        /// Reference temperature t0 (default: 0).
        #[serde(default = "zero")]
        t0: Real,
    },
    /// Multilinear table in (p, |V_t|, T); see [`FrictionTable`].
    Table(FrictionTable),
}

impl Default for FrictionLaw {
    /// `Constant { mu: 0.0 }`: no friction.
    fn default() -> Self {
        FrictionLaw::Constant { mu: 0.0 }
    }
}
