//! The contact monitor: the normal pressure of every gap at every accepted step, as the
//! [`ContactValidity`] the verdict weighs (see [`crate::stages::transient::validity`]).

use super::super::sink::{Checkpoint, Saved, Sink, StepView};
use crate::error::PipelineError;
use crate::verdict::validity::{ContactValidity, GapEvent};
use serde::{Deserialize, Serialize};
use squeal_contact::GapSet;
use squeal_solver::Real;

/// The monitor's part of a checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactPart {
    /// What the contact did up to the restart point.
    pub contact: Option<ContactValidity>,
}

impl ContactPart {
    /// The part saved in a checkpoint.
    pub fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        s.part(None)
    }
}

/// Tracks p_n of every gap: a [`Sink`] of the transient driver that fills a
/// [`ContactValidity`], and carries it over restarts (checkpoint key `contact`).
pub struct ContactMonitor {
    area: Vec<Real>,
    p0: Vec<Real>,
    /// Offset of λ̇ in y' (= n).
    offset: usize,
    pub validity: ContactValidity,
}

impl ContactMonitor {
    /// The monitor of `gaps` in a model of `n` DOFs whose load ramp ends at `t_load`.
    pub fn new(gaps: &GapSet, n: usize, t_load: Real) -> Self {
        Self {
            area: gaps.gaps.iter().map(|g| g.area).collect(),
            p0: gaps.gaps.iter().map(|g| g.p0).collect(),
            offset: n,
            validity: ContactValidity {
                n_gaps: gaps.len(),
                judged_from: t_load,
                ..Default::default()
            },
        }
    }

    /// The monitor continuing a resumed run's record (`resumed`: its checkpoint part; a
    /// record written before `first_tensile_after_ramp` existed is upgraded).
    pub fn resumed(gaps: &GapSet, n: usize, t_load: Real, resumed: Option<&ContactPart>) -> Self {
        let mut m = Self::new(gaps, n, t_load);
        if let Some(v) = resumed.and_then(|p| p.contact.as_ref()) {
            m.validity = v.clone();
            m.validity.upgrade(t_load);
        }
        m
    }
}

/// Round-off band of the contact forces: a gap counts as tensile when p_n A < −band, with band
/// = 1e-12 × the step's force scale (the largest |λ'_g| and P0_g A_g, at least 1), the zero
/// band of the solver's separation events (`squeal_solver::bsql::unilateral`). An open gap's
/// row holds λ' = P0 A to round-off only (p_n ≈ −1e-20 with P0 = 0): it is not tensile, and a
/// gap that does not cross this band is not an event either.
pub(super) fn tensile_band(lam: &[Real], area: &[Real], p0: &[Real]) -> Real {
    let scale = lam
        .iter()
        .zip(area.iter().zip(p0))
        .fold(1.0, |m: Real, (l, (a, p))| {
            m.max(l.abs()).max((p * a).abs())
        });
    1e-12 * scale
}

impl Sink for ContactMonitor {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        let v = &mut self.validity;
        let first = v.steps == 0;
        // The state after an event (same t as the step before it) is no step: its pressures
        // are watched, the step counters are not advanced.
        if !s.repeat {
            v.steps += 1;
        }
        let lam = &s.yp[self.offset..self.offset + self.area.len()];
        let band = tensile_band(lam, &self.area, &self.p0);
        for (g, (&a, &p0)) in self.area.iter().zip(&self.p0).enumerate() {
            let p = -lam[g] / a + p0; // [Paper eq. (1)]
            if v.min_pressure.is_none_or(|m| p < m.pressure) {
                v.min_pressure = Some(GapEvent {
                    t: s.t,
                    gap: g,
                    pressure: p,
                });
            }
            if p < -band / a {
                v.tensile_gap_steps += u64::from(!s.repeat);
                if first {
                    v.tensile_at_start += 1;
                }
                let event = GapEvent {
                    t: s.t,
                    gap: g,
                    pressure: p,
                };
                if v.first_separation.is_none() {
                    v.first_separation = Some(event);
                }
                if v.first_tensile_after_ramp.is_none() && s.t >= v.judged_from {
                    v.first_tensile_after_ramp = Some(event);
                }
            }
        }
        Ok(())
    }
    fn save(&self, c: &mut Checkpoint) -> Result<(), PipelineError> {
        c.save(
            None,
            &ContactPart {
                contact: Some(self.validity.clone()),
            },
        )
    }
}
