//! Energy bookkeeping (BSQL's "energy.y" file): per-step energies and powers, integrated
//! with the trapezoidal rule over accepted steps.
//!
//! # Reference
//! From eq. (8) with Q = −Gᵀλ' [Paper eq. (12)] and u' = v [Paper eq. (10)], for symmetric M, K:
//! $$\frac{d}{dt}\Big(\tfrac12 v^T M v + \tfrac12 u^T K u\Big) = P·v + F_f·v − (G^Tλ')·v − v^T B v.$$
//! The balance residual is ΔE − ∫(P·v + F_f·v − (Gᵀλ')·v − vᵀBv) dt; it is zero up to the
//! integration and quadrature errors. With normal contact compliance the contact springs'
//! energy is part of the strain energy and their rows leave the constraint power
//! ([`super::compliance`]).

use serde::{Deserialize, Serialize};

use super::{BsqlSystem, FrictionForces};
use crate::{Real, SolverError};

/// Energies and powers at one instant.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
pub struct PowerTerms {
    /// Time.
    pub t: Real,
    /// Kinetic energy ½ vᵀ M v.
    pub kinetic: Real,
    /// Strain energy ½ uᵀ K u, plus the contact springs' energy with normal compliance
    /// (Σ ½ c_k λ'_k², see [`super::compliance`]).
    pub strain: Real,
    /// Damping power vᵀ B v (dissipated).
    pub damping: Real,
    /// Friction power F_f · v.
    pub friction: Real,
    /// External power P(t) · v.
    pub external: Real,
    /// Constraint power (Gᵀ λ') · v of the rigid rows (a compliant row's power is in the
    /// rate of `strain`).
    pub constraint: Real,
}

/// Integrated energy balance; feed it one [`PowerTerms`] per accepted step.
///
/// Its serialised form (`summary.json`) is the totals; [`EnergyBalance::restart_state`] adds
/// the last records the next step's quadrature needs, so that a restarted run continues the
/// integrals bit for bit ([`EnergyBalance::from_restart_state`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyBalance {
    /// Time of the first record.
    pub t0: Real,
    /// Time of the last record.
    pub t: Real,
    /// Kinetic + strain energy at the first record.
    pub initial_energy: Real,
    /// Kinetic energy at the last record.
    pub kinetic: Real,
    /// Strain energy at the last record.
    pub strain: Real,
    /// ∫ vᵀ B v dt.
    pub damping_dissipated: Real,
    /// ∫ F_f · v dt.
    pub friction_work: Real,
    /// ∫ P · v dt.
    pub external_work: Real,
    /// ∫ (Gᵀ λ') · v dt.
    pub constraint_work: Real,
    /// Kinetic energy lost in plastic impacts at re-contact events (set by the caller from
    /// [`super::UnilateralStats::impact_dissipated`]; 0 without separation).
    pub impact_dissipated: Real,
    /// Estimated error of the trapezoidal quadrature, Σ h³/12·|f''| over steps, with f'' of
    /// the net power from the second divided difference of the last three records.
    pub quadrature_error: Real,
    /// Records so far.
    pub records: u64,
    #[serde(skip)]
    last: Option<PowerTerms>,
    #[serde(skip)]
    prev: Option<(Real, Real)>,
}

/// An [`EnergyBalance`] with the records its next step integrates from (restart files).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct EnergyRestart {
    /// The totals.
    pub balance: EnergyBalance,
    /// The last record (None before the first).
    pub last: Option<PowerTerms>,
    /// (t, net power) of the record before it (quadrature-error estimate).
    pub prev: Option<(Real, Real)>,
}

/// Net power into the structure: P·v + F_f·v − (Gᵀλ')·v − vᵀBv.
fn net_power(p: &PowerTerms) -> Real {
    p.external + p.friction - p.constraint - p.damping
}

impl EnergyBalance {
    /// Empty balance.
    pub fn new() -> Self {
        Self::default()
    }

    /// Add a record (trapezoidal rule from the previous one).
    pub fn push(&mut self, p: &PowerTerms) {
        match self.last {
            None => {
                self.t0 = p.t;
                self.initial_energy = p.kinetic + p.strain;
            }
            Some(q) => {
                let h = p.t - q.t;
                let f1 = net_power(&q);
                let f2 = net_power(p);
                if let Some((t0, f0)) = self.prev {
                    let h0 = q.t - t0;
                    if h0 > 0.0 && h > 0.0 {
                        let dd2 = ((f2 - f1) / h - (f1 - f0) / h0) / (h + h0);
                        self.quadrature_error += h * h * h / 12.0 * (2.0 * dd2).abs();
                    }
                }
                self.prev = Some((q.t, f1));
                let dt = 0.5 * h;
                self.damping_dissipated += dt * (p.damping + q.damping);
                self.friction_work += dt * (p.friction + q.friction);
                self.external_work += dt * (p.external + q.external);
                self.constraint_work += dt * (p.constraint + q.constraint);
            }
        }
        self.t = p.t;
        self.kinetic = p.kinetic;
        self.strain = p.strain;
        self.records += 1;
        self.last = Some(*p);
    }

    /// The complete balance for a restart file: the totals and the last records.
    pub fn restart_state(&self) -> EnergyRestart {
        EnergyRestart {
            balance: self.clone(),
            last: self.last,
            prev: self.prev,
        }
    }

    /// The balance of a restart file ([`EnergyBalance::restart_state`]).
    pub fn from_restart_state(r: EnergyRestart) -> Self {
        Self {
            last: r.last,
            prev: r.prev,
            ..r.balance
        }
    }

    /// Energy change minus net work in: zero for an exact solution.
    pub fn residual(&self) -> Real {
        let de = self.kinetic + self.strain - self.initial_energy;
        de - (self.external_work + self.friction_work
            - self.constraint_work
            - self.damping_dissipated
            - self.impact_dissipated)
    }

    /// Scale for a relative balance error: the largest of the energy terms.
    pub fn scale(&self) -> Real {
        [
            self.initial_energy,
            self.kinetic + self.strain,
            self.damping_dissipated,
            self.friction_work,
            self.external_work,
            self.constraint_work,
            self.impact_dissipated,
        ]
        .iter()
        .fold(0.0, |m: Real, x| m.max(x.abs()))
    }
}

#[allow(non_snake_case)]
impl<F: FrictionForces> BsqlSystem<F> {
    /// Energies and powers at an accepted step (t, y, y'), and update the constraint-drift
    /// monitor ‖G v‖∞ (closed rigid rows). Call it from the integrator's per-step callback.
    pub fn observe(&mut self, t: Real, y: &[Real], yp: &[Real]) -> Result<PowerTerms, SolverError> {
        let (n, ng) = (self.n, self.ng);
        if y.len() != 2 * n + ng || yp.len() != y.len() {
            return Err(SolverError::DimensionMismatch {
                what: "observed state",
                expected: 2 * n + ng,
                got: y.len().min(yp.len()),
            });
        }
        let v = &y[..n];
        let u = &y[n + ng..];
        let lamp = &yp[n..n + ng];
        let dot = |a: &[Real], b: &[Real]| a.iter().zip(b).map(|(x, y)| x * y).sum::<Real>();
        let mut p = PowerTerms {
            t,
            ..Default::default()
        };
        // vᵀMv, vᵀBv, uᵀKu in one pass over the union pattern of M, B, K.
        let [qm, qb, qk] = self.mbk.quadratic_forms3(v, u);
        p.kinetic = 0.5 * qm;
        // The contact springs' energy is stored energy (see [`super::compliance`]).
        p.strain = 0.5 * qk + self.contact_spring_energy(u, lamp);
        p.damping = qb;
        // (Gᵀλ')·v = λ'·(G v); G v is also the drift monitor's.
        self.g_rows.apply(0, v, &mut self.gv, false, 1.0);
        p.constraint = if self.compliance.is_empty() {
            dot(lamp, &self.gv)
        } else {
            // The rigid rows only: a compliant row's power λ'_k G_k v is the rate of its
            // spring energy, counted in `strain`.
            (0..ng)
                .filter(|&k| self.compliance[k] == 0.0)
                .map(|k| lamp[k] * self.gv[k])
                .sum()
        };
        self.f_n.fill(0.0);
        self.friction.add_forces(t, v, lamp, &mut self.f_n)?;
        p.friction = dot(v, &self.f_n);
        p.external = self.load.dot(t, v);
        // Constraint drift ‖G v‖∞ over the closed rigid rows: a compliant row has G v ≠ 0 by
        // design, and an open (separated) row's G v is its separation speed, not a drift.
        let drift = (0..ng)
            .filter(|&k| self.compliance_of(k) <= 0.0 && !self.open[k])
            .fold(0.0, |m: Real, k| m.max(self.gv[k].abs()));
        self.stats.constraint_drift = drift;
        self.stats.max_constraint_drift = self.stats.max_constraint_drift.max(drift);
        Ok(p)
    }
}
