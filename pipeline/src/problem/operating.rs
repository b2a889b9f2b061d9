//! The operating point: what a scene sets on a reduced model besides its structure — the
//! friction law and VTOL, the rotor's speed (the sliding velocity of every gap), each contact
//! pair's preload P0 and temperatures, and the brake load's PMAX and ramp.
//!
//! A pair may have a law of its own and no steady sliding (`[[contact]] friction`,
//! `sliding = "none"`: pad ears on abutments, a piston on a backplate).
//!
//! A [`ReducedModel`] holds what its cache key hashes (K, M, B, the DOF map, the gap geometry);
//! the operating point is applied once, when the problem is made ([`super::system::problem`]).
//! Every variation of an operating value (a friction sweep, a sensitivity's difference, a
//! propensity sample) varies an `OperatingPoint` and makes the gaps anew ([`OperatingPoint::gaps`]),
//! never the model.

use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::scene::{FrictionSpec, LoadsSpec, ModelSource, RotorSpec, Scene, Sliding};
use squeal_contact::{FrictionLaw, Gap, GapSet};
use squeal_solver::Real;
use std::collections::HashMap;

/// One `[[contact]]` pair's operating values.
#[derive(Debug, Clone, PartialEq)]
pub struct PairPoint {
    /// Preload pressure P_0 of its gaps. [Paper eq. (1)]
    pub p0: Real,
    /// Temperature of its gaps, unless `grid_temperatures` names the pad grid.
    pub temperature: Real,
    /// Temperature per pad grid id.
    pub grid_temperatures: Vec<(u64, Real)>,
    /// The pair's own friction law (None: the scene's).
    pub friction: Option<FrictionLaw>,
    /// Whether its rotor side slides at the rotor's speed.
    pub sliding: Sliding,
}

impl PairPoint {
    /// Sets this pair's values on its gaps (`stored`: a stored gap table, whose P0 and
    /// temperature are the table's unless the scene's `model.p0` / `temperature` override).
    fn apply(&self, gaps: &mut [Gap], stored: Option<(Option<Real>, Option<Real>)>) {
        let temps: HashMap<u64, Real> = self.grid_temperatures.iter().copied().collect();
        for g in gaps {
            match stored {
                None => {
                    g.p0 = self.p0;
                    g.temperature = temps.get(&g.pad_node).copied().unwrap_or(self.temperature);
                }
                Some((p0, t)) => {
                    g.p0 = p0.unwrap_or(g.p0);
                    g.temperature = t.unwrap_or(g.temperature);
                }
            }
            if self.sliding == Sliding::None {
                g.v_slide = [0.0; 3];
            }
            if self.friction.is_some() {
                // A stored table's own per-gap law stays unless the pair names one.
                g.friction = self.friction.clone();
            }
        }
    }
}

/// The operating values of a scene (see the module's documentation).
#[derive(Debug, Clone, PartialEq)]
pub struct OperatingPoint {
    /// `[friction]`: μ(p, |V_t|, T) and VTOL. [Paper eqs. (4)–(5)]
    pub friction: FrictionSpec,
    /// `[rotor]`: speed, axis and a point on it.
    pub rotor: RotorSpec,
    /// Per `[[contact]]` pair, in scene order (models built from meshes).
    pub pairs: Vec<PairPoint>,
    /// `model.p0` / `model.temperature`: a stored gap table's P0 and temperature overridden
    /// (None: the table's own).
    pub stored_p0: Option<Real>,
    pub stored_temperature: Option<Real>,
    /// `loads.pmax`, the scale of the brake load at the end of the ramp.
    pub pmax: Real,
    /// `loads.tload`, the ramp time (0: a step at t = 0).
    pub tload: Real,
}

impl Default for OperatingPoint {
    /// The defaults of the scene's tables: no friction, a rotor at rest, no pair, PMAX 1.
    fn default() -> Self {
        let loads = LoadsSpec::default();
        OperatingPoint {
            friction: FrictionSpec::default(),
            rotor: RotorSpec::default(),
            pairs: Vec::new(),
            stored_p0: None,
            stored_temperature: None,
            pmax: loads.pmax,
            tload: loads.tload,
        }
    }
}

impl OperatingPoint {
    /// The scene's operating values.
    pub fn of(scene: &Scene) -> Self {
        let loads = scene.loads.clone().unwrap_or_default();
        OperatingPoint {
            friction: scene.friction.clone().unwrap_or_default(),
            rotor: scene.rotor.clone().unwrap_or_default(),
            pairs: scene
                .contact
                .iter()
                .map(|c| PairPoint {
                    p0: c.p0,
                    temperature: c.temperature,
                    grid_temperatures: c.grid_temperatures.clone(),
                    friction: c.friction.clone(),
                    sliding: c.sliding,
                })
                .collect(),
            stored_p0: scene.model.p0,
            stored_temperature: scene.model.temperature,
            pmax: loads.pmax,
            tload: loads.tload,
        }
    }

    /// ω (rad/s) along the rotor axis: rpm · 2π/60 · axis.
    pub fn omega(&self) -> [Real; 3] {
        let w = self.rotor.rpm * 2.0 * std::f64::consts::PI / 60.0;
        self.rotor.axis.map(|a| w * a)
    }

    /// The model's gaps at this point: its gap geometry with every gap's sliding velocity
    /// ω × (x − origin) [Paper eq. (2)], P0 and temperature (its pair's, or for a stored
    /// gap table the table's unless overridden), and the friction law and VTOL (validated).
    pub fn gaps(&self, model: &ReducedModel) -> Result<GapSet, PipelineError> {
        let mut gaps = model.gap_geometry.gaps.clone();
        let (omega, o) = (self.omega(), self.rotor.origin);
        for g in &mut gaps {
            let r = [0, 1, 2].map(|i| g.coords[i] - o[i]);
            g.v_slide = [
                omega[1] * r[2] - omega[2] * r[1],
                omega[2] * r[0] - omega[0] * r[2],
                omega[0] * r[1] - omega[1] * r[0],
            ];
        }
        let stored = (self.stored_p0, self.stored_temperature);
        match model.source {
            ModelSource::Mesh => {
                if self.pairs.len() != model.gap_pairs.len() {
                    return Err(PipelineError::Model(format!(
                        "the model has {} contact pairs, the scene {}",
                        model.gap_pairs.len(),
                        self.pairs.len()
                    )));
                }
                let mut start = 0;
                for (pair, &count) in self.pairs.iter().zip(&model.gap_pairs) {
                    pair.apply(&mut gaps[start..start + count], None);
                    start += count;
                }
            }
            // A stored gap table is one pair: the scene's only `[[contact]]` table, if any.
            ModelSource::Op4 | ModelSource::Punch | ModelSource::Arrays => match &self.pairs[..] {
                [pair] => pair.apply(&mut gaps, Some(stored)),
                _ => {
                    for g in &mut gaps {
                        g.p0 = stored.0.unwrap_or(g.p0);
                        g.temperature = stored.1.unwrap_or(g.temperature);
                    }
                }
            },
        }
        GapSet::new(gaps, self.friction.law.clone(), self.friction.vtol).map_err(|source| {
            PipelineError::Contact {
                what: "friction".into(),
                source,
            }
        })
    }
}
