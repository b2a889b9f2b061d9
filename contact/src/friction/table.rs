//! Multilinear friction table μ(p, |V_t|, T). [Paper eq. (4)]

use super::FrictionEval;
use crate::{ContactError, Real};
use serde::{Deserialize, Serialize};

/// Friction coefficient tabulated on a tensor grid of pressures × speeds × temperatures.
///
/// * An axis given with 0 or 1 knots is absent: μ does not depend on it (single-axis tables,
///   e.g. μ(|V_t|) only, give just `speeds`).
/// * `values` is flattened with temperature fastest:
///   `values[(ip·n_speeds + iv)·n_temperatures + it]`, where an absent axis counts as 1.
/// * Inside the grid, μ is multilinear (trilinear with all three axes). At an interior knot
///   the value is continuous and the derivative is the one of the cell on the right.
/// * **Extrapolation: clamped.** Outside `[first, last]` knot of an axis, the coordinate is
///   clamped to the nearest end knot: μ is constant beyond the table and its derivative along
///   that axis is 0 there.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct FrictionTable {
    /// Pressure knots, strictly increasing (default: empty = no pressure dependence).
    #[serde(default)]
    pub pressures: Vec<Real>,
    /// Sliding speed knots |V_t|, strictly increasing (default: empty = no speed dependence).
    #[serde(default)]
    pub speeds: Vec<Real>,
    /// Temperature knots, strictly increasing (default: empty = no temperature dependence).
    #[serde(default)]
    pub temperatures: Vec<Real>,
    /// μ at the knots, temperature fastest (required; length = product of the axis sizes).
    pub values: Vec<Real>,
}

/// Position on one axis: lower index, weight of the upper knot, d(weight)/dx.
#[derive(Clone, Copy)]
struct AxisPos {
    i0: usize,
    i1: usize,
    w1: Real,
    dw1: Real,
}

fn locate(knots: &[Real], x: Real) -> AxisPos {
    let n = knots.len();
    if n < 2 {
        return AxisPos {
            i0: 0,
            i1: 0,
            w1: 0.0,
            dw1: 0.0,
        };
    }
    if x <= knots[0] {
        // Clamped below (at the first knot exactly, the right-cell derivative applies).
        let h = knots[1] - knots[0];
        let dw1 = if x == knots[0] { 1.0 / h } else { 0.0 };
        return AxisPos {
            i0: 0,
            i1: 1,
            w1: 0.0,
            dw1,
        };
    }
    if x >= knots[n - 1] {
        // Clamped above.
        return AxisPos {
            i0: n - 2,
            i1: n - 1,
            w1: 1.0,
            dw1: 0.0,
        };
    }
    // Cell i with knots[i] <= x < knots[i+1].
    let i = knots.partition_point(|&k| k <= x) - 1;
    let h = knots[i + 1] - knots[i];
    AxisPos {
        i0: i,
        i1: i + 1,
        w1: (x - knots[i]) / h,
        dw1: 1.0 / h,
    }
}

impl FrictionTable {
    fn dims(&self) -> [usize; 3] {
        [
            self.pressures.len().max(1),
            self.speeds.len().max(1),
            self.temperatures.len().max(1),
        ]
    }

    /// μ and derivatives by multilinear interpolation, clamped outside the table.
    ///
    /// # Reference
    /// μ(p_n, |V_t|, T) of $$F_t = \mu(p_n,|V_t|,T)\,A\,p_n$$ "obtained with an interpolation
    /// scheme using tabular inputs" [Paper eq. (4)].
    pub fn evaluate(&self, p: Real, speed: Real, temperature: Real) -> FrictionEval {
        let [_, nv, nt] = self.dims();
        let axes = [
            locate(&self.pressures, p),
            locate(&self.speeds, speed),
            locate(&self.temperatures, temperature),
        ];
        let mut out = FrictionEval::default();
        for cp in 0..2 {
            for cv in 0..2 {
                for ct in 0..2 {
                    let corner = [cp, cv, ct];
                    // An absent axis (i0 = i1 = 0, w1 = 0) has only its corner 0.
                    if (0..3).any(|a| corner[a] == 1 && axes[a].i0 == axes[a].i1) {
                        continue;
                    }
                    let mut idx = [0usize; 3];
                    let mut w = [0.0; 3];
                    let mut dw = [0.0; 3];
                    for a in 0..3 {
                        let ax = axes[a];
                        if corner[a] == 0 {
                            idx[a] = ax.i0;
                            w[a] = 1.0 - ax.w1;
                            dw[a] = -ax.dw1;
                        } else {
                            idx[a] = ax.i1;
                            w[a] = ax.w1;
                            dw[a] = ax.dw1;
                        }
                    }
                    let v = self.values[(idx[0] * nv + idx[1]) * nt + idx[2]];
                    out.mu += v * w[0] * w[1] * w[2];
                    out.dmu_dp += v * dw[0] * w[1] * w[2];
                    out.dmu_dv += v * w[0] * dw[1] * w[2];
                    out.dmu_dt += v * w[0] * w[1] * dw[2];
                }
            }
        }
        out
    }

    /// Checks knots (finite, strictly increasing) and values (finite, ≥ 0, right count).
    pub fn validate(&self) -> Result<(), ContactError> {
        for (name, knots) in [
            ("friction.pressures", &self.pressures),
            ("friction.speeds", &self.speeds),
            ("friction.temperatures", &self.temperatures),
        ] {
            for (i, &k) in knots.iter().enumerate() {
                if !k.is_finite() {
                    return Err(ContactError::InvalidOption {
                        field: format!("{name}[{i}]"),
                        value: format!("{k}"),
                        reason: "must be finite".into(),
                    });
                }
                if i > 0 && k <= knots[i - 1] {
                    return Err(ContactError::InvalidOption {
                        field: format!("{name}[{i}]"),
                        value: format!("{k}"),
                        reason: format!("knots must increase strictly (previous {})", knots[i - 1]),
                    });
                }
            }
        }
        let [np, nv, nt] = self.dims();
        if self.values.len() != np * nv * nt {
            return Err(ContactError::InvalidOption {
                field: "friction.values".into(),
                value: format!("{} values", self.values.len()),
                reason: format!(
                    "expected {np} x {nv} x {nt} = {} (pressures x speeds x temperatures)",
                    np * nv * nt
                ),
            });
        }
        for (i, &v) in self.values.iter().enumerate() {
            if !(v.is_finite() && (0.0..=super::MU_MAX).contains(&v)) {
                return Err(ContactError::InvalidOption {
                    field: format!("friction.values[{i}]"),
                    value: format!("{v}"),
                    reason: format!(
                        "must be finite and in [0, {}] (friction::MU_MAX)",
                        super::MU_MAX
                    ),
                });
            }
        }
        Ok(())
    }
}
