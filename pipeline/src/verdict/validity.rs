//! Contact validity: the normal pressure of every gap at every accepted step.
//!
//! The BSQL contact is bilateral: p_n = −λ̇/A + P_0 [Paper eq. (1)] may go negative, and the
//! friction force μ A p_n then reverses — a state the paper's full-contact assumption does not
//! cover. The contact monitor (a data-only sink of the driver) records where and when that happens; the
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

use serde::{Deserialize, Serialize};
use squeal_solver::Real;

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
    /// (gap, accepted step) pairs with p_n < 0 (beyond round-off: p_n A < −1e-12 × the force
    /// scale, see `collect::contact`), the initial point included.
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
