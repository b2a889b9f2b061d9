//! Contact validity: the normal pressure of every gap at every accepted step.
//!
//! The BSQL contact is bilateral: p_n = −λ̇/A + P_0 [Paper eq. (1)] may go negative, and the
//! friction force μ A p_n then reverses — a state the paper's full-contact assumption does not
//! cover. [`ContactMonitor`] is a driver sink that records where and when that happens; the
//! verdict treats a run whose contact went tensile (with separation off) as unresolved from
//! that time on, and `reproduce` reports it.

use super::driver::{Sink, StepView};
use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_contact::GapSet;

type Real = f64;

/// One gap at one time.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct GapEvent {
    pub t: Real,
    /// Gap index (gap-table order).
    pub gap: usize,
    /// Normal pressure p_n there.
    pub pressure: Real,
}

/// What the run's contact did (`summary.json`'s `contact`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ContactValidity {
    pub n_gaps: usize,
    /// Gaps with p_n < 0 at the start (after the steady state and consistent initial
    /// conditions).
    pub tensile_at_start: usize,
    /// (gap, accepted step) pairs with p_n < 0, the initial point included.
    pub tensile_gap_steps: u64,
    /// The first time a gap's p_n went below 0 (None: never).
    pub first_separation: Option<GapEvent>,
    /// The smallest p_n of any gap at any step.
    pub min_pressure: Option<GapEvent>,
    /// Points observed: the initial one and every accepted step (an event's state after the
    /// switch, at the same time, is not counted).
    pub steps: u64,
}

impl ContactValidity {
    /// True when some gap went tensile.
    pub fn went_tensile(&self) -> bool {
        self.first_separation.is_some()
    }
}

/// Tracks p_n of every gap: a [`Sink`] of the transient driver.
pub struct ContactMonitor {
    area: Vec<Real>,
    p0: Vec<Real>,
    /// Offset of λ̇ in y' (= n).
    offset: usize,
    pub validity: ContactValidity,
}

impl ContactMonitor {
    /// The monitor of `gaps` in a model of `n` DOFs.
    pub fn new(gaps: &GapSet, n: usize) -> Self {
        Self {
            area: gaps.gaps.iter().map(|g| g.area).collect(),
            p0: gaps.gaps.iter().map(|g| g.p0).collect(),
            offset: n,
            validity: ContactValidity {
                n_gaps: gaps.len(),
                ..Default::default()
            },
        }
    }
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
        for (g, (&a, &p0)) in self.area.iter().zip(&self.p0).enumerate() {
            let p = -s.yp[self.offset + g] / a + p0; // [Paper eq. (1)]
            if v.min_pressure.is_none_or(|m| p < m.pressure) {
                v.min_pressure = Some(GapEvent {
                    t: s.t,
                    gap: g,
                    pressure: p,
                });
            }
            if p < 0.0 {
                v.tensile_gap_steps += u64::from(!s.repeat);
                if first {
                    v.tensile_at_start += 1;
                }
                if v.first_separation.is_none() {
                    v.first_separation = Some(GapEvent {
                        t: s.t,
                        gap: g,
                        pressure: p,
                    });
                }
            }
        }
        Ok(())
    }
}
