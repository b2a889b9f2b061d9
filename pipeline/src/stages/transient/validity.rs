//! Contact validity: the normal pressure of every gap at every accepted step.
//!
//! The BSQL contact is bilateral: p_n = −λ̇/A + P_0 [Paper eq. (1)] may go negative, and the
//! friction force μ A p_n then reverses — a state the paper's full-contact assumption does not
//! cover. [`ContactMonitor`] is a driver sink that records where and when that happens; the
//! verdict treats a run whose contact went tensile (with separation off) at or after the end of
//! the load ramp as unresolved from that time on, and `reproduce` reports it.
//!
//! The verdict judges the response after the ramp (TLOAD), about the loaded state. Before the
//! ramp ends the run is still being loaded: it starts from the sliding equilibrium under P0
//! alone, where the friction couple μ P0 A has no clamp force to lean on (the cad brake: 7 of
//! its 272 gaps tensile, p_n down to −0.107 MPa, while the loaded state has none). Tensile gaps
//! there are counted and reported (`tensile_at_start`, `first_separation`) but do not void the
//! window after the ramp: with every gap closed at the end of the ramp the loaded sliding
//! equilibrium is the same whichever gaps held in tension on the way (a linear solve with fixed
//! sliding directions), and the response after it vibrates about that state. A step load
//! (TLOAD = 0) has no ramp: its first instant, t = 0, is judged.

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
    /// The first time a gap's p_n went below 0, the load ramp included (None: never).
    pub first_separation: Option<GapEvent>,
    /// The end of the load ramp (TLOAD; 0 for a step load): the verdict judges the contact
    /// from here on.
    #[serde(default)]
    pub judged_from: Real,
    /// The first time a gap's p_n went below 0 at or after `judged_from` (None: never): the
    /// event that voids the verdict's window.
    #[serde(default)]
    pub first_tensile_after_ramp: Option<GapEvent>,
    /// The smallest p_n of any gap at any step.
    pub min_pressure: Option<GapEvent>,
    /// Points observed: the initial one and every accepted step (an event's state after the
    /// switch, at the same time, is not counted).
    pub steps: u64,
}

impl ContactValidity {
    /// True when some gap went tensile (the load ramp included).
    pub fn went_tensile(&self) -> bool {
        self.first_separation.is_some()
    }

    /// Fills `first_tensile_after_ramp` from `first_separation` for validity records written
    /// before the field existed (restart files): exact when that first event was after the
    /// ramp; an event during the ramp leaves it unknown (None).
    pub fn upgrade(&mut self, t_load: Real) {
        if self.first_tensile_after_ramp.is_none() && self.judged_from == 0.0 {
            self.judged_from = t_load;
            self.first_tensile_after_ramp = self.first_separation.filter(|e| e.t >= t_load);
        }
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
}
