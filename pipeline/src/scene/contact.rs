//! `[[contact]]` pad/rotor pairs, `[friction]` and `[rotor]`.

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_contact::{FrictionLaw, TieOptions, Unmatched};

use squeal_solver::Real;

/// How the pad nodes of a `[[contact]]` pair find their rotor points (docs/pairing.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Pairing {
    /// PREBSQL's rule: each pad node coincides (within `tolerance`) with one rotor node of
    /// the rotor face set (the default on linear pad faces).
    #[default]
    Nodes,
    /// Node-to-surface tie: each pad node is projected on the rotor face set's faces (quad4,
    /// quad8, tri3, tri6) and tied to that point (its face nodes carry the shape-function
    /// weights); meshes need not match.
    Surface,
    /// Mortar tie (segment-to-segment, dual Lagrange multipliers on the pad's faces,
    /// `squeal_contact::mortar_gaps`): each pad node's rotor side is the mortar average of
    /// the rotor surface under its dual basis function; passes the flat patch test for any
    /// pair of meshes and face kinds (the default on quadratic pad faces: quad8, tri6);
    /// `unmatched`, `extension`, `max_distance` as `surface`.
    Mortar,
}

impl Pairing {
    /// The pairing of a pair that does not name one: `mortar` on quadratic pad faces (their
    /// consistent corner areas are 0 or negative, so node-based gaps there are zero or
    /// tensile: docs/pairing.md), `nodes` otherwise.
    pub fn default_for(quadratic_pad_faces: bool) -> Pairing {
        if quadratic_pad_faces {
            Pairing::Mortar
        } else {
            Pairing::Nodes
        }
    }
}

/// One pad/rotor contact surface (PREBSQL's input): one gap element per pad node of the pad
/// face set, paired with the rotor face set by `pairing`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ContactPair {
    /// Pad component name (required).
    pub pad: String,
    /// Face set (physical surface) of the pad in contact (required).
    pub pad_faces: String,
    /// Rotor component name (required).
    pub rotor: String,
    /// Face set of the rotor in contact (its nodes are the candidates) (required).
    pub rotor_faces: String,
    /// Distance within which a pad node and a rotor node coincide (default: 1e-6, model
    /// units; `pairing = "nodes"` only).
    #[serde(default = "default_tolerance")]
    pub tolerance: Real,
    /// `"nodes"` (coincident pad and rotor nodes, PREBSQL), `"surface"` (each pad node
    /// projected on the rotor faces; non-matching meshes) or `"mortar"` (segment-to-segment)
    /// (default: "mortar" when the pad faces are quadratic, quad8 or tri6, else "nodes";
    /// [`Pairing::default_for`]).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pairing: Option<Pairing>,
    /// Surface pairing: pad nodes projecting on no rotor face are an `"error"` naming them,
    /// or are left out (`"exclude"`) with a warning listing them (default: "error").
    #[serde(default)]
    pub unmatched: Unmatched,
    /// Surface pairing: face extension ε, a projection with |ξ|, |η| ≤ 1 + ε is on the face
    /// (default: 0.01).
    #[serde(default = "default_extension")]
    pub extension: Real,
    /// Surface pairing: largest distance from a pad node to its projection (default: 0.05 ×
    /// the mean edge length of the rotor faces).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_distance: Option<Real>,
    /// Preload pressure P_0 of every gap of this pair, finite and >= 0 (default: 0). [Paper eq. (1)]
    #[serde(default)]
    pub p0: Real,
    /// Temperature of every gap of this pair (default: 0; read only when the friction law
    /// depends on temperature).
    #[serde(default)]
    pub temperature: Real,
    /// Grid temperatures `[[grid, T], ...]` overriding `temperature` for the gaps whose pad grid
    /// is listed (default: none).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub grid_temperatures: Vec<(u64, Real)>,
    /// Unilateral contact: a gap of this pair opens when its pressure p_n would turn tensile
    /// and closes when its gap closes (events, plastic impact; BDF only) (default: false, the
    /// paper's bilateral contact, tensile gaps only reported).
    #[serde(default)]
    pub separation: bool,
    /// Normal contact compliance: the stiffness k_n per unit area of a penalty spring between
    /// pad and rotor at every gap of this pair (force / area / length, e.g. psi/in), finite
    /// and > 0; the gap's contact force is then k_n A (G u) and its pressure
    /// p_n = P_0 − k_n G u (BDF transient, steady state and CEA; generalized-α refuses it)
    /// (default: absent, the paper's rigid constraint). See `squeal_solver::bsql::compliance`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub normal_stiffness: Option<Real>,
    /// With `separation` and `normal_stiffness`: the gaps of this pair separate through a
    /// smooth unilateral law instead of events. The pressure is k_n s(x) with x the
    /// penetration beyond the opening level and s a C² ramp that equals x above p_ε/k_n and 0
    /// below −p_ε/k_n, p_ε = this value (a pressure, finite and > 0; the law equals the linear
    /// spring wherever that carries at least p_ε). See `squeal_solver::bsql::smooth` and
    /// docs/separation-integration.md (default: absent, events).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub separation_smoothing: Option<Real>,
    /// This pair's own friction law μ(p, |V_t|, T), e.g. pad ears on the bracket's abutments
    /// (default: absent, the scene's `[friction]` law; VTOL stays the scene's).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub friction: Option<FrictionLaw>,
    /// How the `rotor` side of the pair moves past the `pad` side in the steady state:
    /// `"rotor"` at the `[rotor]` speed, ω × (x − origin) (a friction face on the rotor), or
    /// `"none"` (two bodies that do not rotate: pad ears on abutments, a piston or caliper
    /// fingers on a backplate: friction acts on the vibration's slip only) (default: "rotor").
    #[serde(default, skip_serializing_if = "Sliding::is_rotor")]
    pub sliding: Sliding,
}

/// The steady sliding of a contact pair (`[[contact]] sliding`).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Sliding {
    /// The rotor side moves at the rotor's speed. [Paper eq. (2)]
    #[default]
    Rotor,
    /// No steady sliding: the gaps' sliding velocity is zero.
    None,
}

impl Sliding {
    fn is_rotor(&self) -> bool {
        *self == Sliding::Rotor
    }
}

fn default_tolerance() -> Real {
    1e-6
}

fn default_extension() -> Real {
    TieOptions::default().extension
}

impl ContactPair {
    /// The surface pairing's options.
    pub fn tie_options(&self) -> TieOptions {
        TieOptions {
            extension: self.extension,
            max_distance: self.max_distance,
            unmatched: self.unmatched,
        }
    }

    /// Checks tolerance and values; errors name `contact[i].field`.
    pub fn validate(&self, i: usize) -> Result<(), PipelineError> {
        let bad = |field: &str, message: String| PipelineError::Scene {
            field: format!("contact[{i}].{field}"),
            message,
        };
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(bad(
                "tolerance",
                format!("{} must be finite and > 0", self.tolerance),
            ));
        }
        if !(self.p0.is_finite() && self.p0 >= 0.0) {
            return Err(bad(
                "p0",
                format!(
                    "{} must be finite and >= 0 (a compressive preload pressure)",
                    self.p0
                ),
            ));
        }
        if !self.temperature.is_finite() {
            return Err(bad(
                "temperature",
                format!("{} must be finite", self.temperature),
            ));
        }
        if let Some((g, t)) = self.grid_temperatures.iter().find(|(_, t)| !t.is_finite()) {
            return Err(bad(
                "grid_temperatures",
                format!("grid {g}: {t} must be finite"),
            ));
        }
        if !(self.extension.is_finite() && (0.0..=1.0).contains(&self.extension)) {
            return Err(bad(
                "extension",
                format!("{} must be in [0, 1]", self.extension),
            ));
        }
        if let Some(d) = self.max_distance {
            if !(d.is_finite() && d > 0.0) {
                return Err(bad("max_distance", format!("{d} must be finite and > 0")));
            }
        }
        if self.pairing == Some(Pairing::Nodes) {
            let set = [
                ("unmatched", self.unmatched != Unmatched::default()),
                ("extension", self.extension != default_extension()),
                ("max_distance", self.max_distance.is_some()),
            ];
            if let Some((key, _)) = set.iter().find(|(_, on)| *on) {
                return Err(bad(
                    key,
                    "is read only with pairing = \"surface\" or \"mortar\" (this pair matches \
                     coincident nodes)"
                        .into(),
                ));
            }
        }
        if let Some(k) = self.normal_stiffness {
            if !(k.is_finite() && k > 0.0) {
                return Err(bad(
                    "normal_stiffness",
                    format!(
                        "{k} must be finite and > 0 (a normal contact stiffness per unit \
                         area; leave the key out for rigid contact)"
                    ),
                ));
            }
        }
        if let Some(p) = self.separation_smoothing {
            if !(p.is_finite() && p > 0.0) {
                return Err(bad(
                    "separation_smoothing",
                    format!("{p} must be finite and > 0 (a pressure width)"),
                ));
            }
            if !self.separation || self.normal_stiffness.is_none() {
                return Err(bad(
                    "separation_smoothing",
                    format!(
                        "{p} is read only with separation = true and a normal_stiffness (the \
                         smooth law is a compliant gap's; this pair has separation = {}, \
                         normal_stiffness {})",
                        self.separation,
                        if self.normal_stiffness.is_some() {
                            "set"
                        } else {
                            "absent"
                        }
                    ),
                ));
            }
        }
        if self.pad == self.rotor {
            return Err(bad("rotor", format!("`{}` is also the pad", self.rotor)));
        }
        if let Some(law) = &self.friction {
            law.validate()
                .map_err(|e| bad("friction", format!("{law:?}: {e}")))?;
        }
        Ok(())
    }
}

/// `[friction]`: the friction law of every gap and the regularisation speed.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct FrictionSpec {
    /// μ(p, |V_t|, T), e.g. `{ kind = "linear_speed", mu0 = 0.7, slope = -0.0005 }` (default:
    /// `{ kind = "constant", mu = 0.0 }`, no friction). [Paper eq. (4)]
    pub law: FrictionLaw,
    /// VTOL: below 10·VTOL the friction force is regularised by an arctangent (default: 1e-3,
    /// the paper's sample brake). [Paper eq. (5)]
    pub vtol: Real,
}

impl Default for FrictionSpec {
    fn default() -> Self {
        Self {
            law: FrictionLaw::default(),
            vtol: 1e-3,
        }
    }
}

impl FrictionSpec {
    /// Validates the law and VTOL.
    pub fn validate(&self) -> Result<(), PipelineError> {
        self.law.validate().map_err(|e| PipelineError::Scene {
            field: "friction.law".into(),
            message: e.to_string(),
        })?;
        if !(self.vtol.is_finite() && self.vtol > 0.0) {
            return Err(PipelineError::Scene {
                field: "friction.vtol".into(),
                message: format!("{} must be finite and > 0", self.vtol),
            });
        }
        Ok(())
    }
}

/// `[rotor]`: the rotor's steady rotation (sliding velocity ω × r at each gap).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RotorSpec {
    /// Speed in revolutions per unit time × 60, i.e. RPM when time is in seconds (default: 0;
    /// the paper's sample brake: 143.239 = 15 rad/s).
    pub rpm: Real,
    /// Unit vector of the rotor axis, positive rotation by the right hand (default: [0, 0, 1]).
    pub axis: [Real; 3],
    /// A point on the axis (default: [0, 0, 0]).
    pub origin: [Real; 3],
}

impl Default for RotorSpec {
    fn default() -> Self {
        Self {
            rpm: 0.0,
            axis: [0.0, 0.0, 1.0],
            origin: [0.0; 3],
        }
    }
}

impl RotorSpec {
    /// Checks rpm and origin (finite) and that the axis is a unit vector.
    pub fn validate(&self) -> Result<(), PipelineError> {
        let n = self.axis.iter().map(|a| a * a).sum::<Real>().sqrt();
        if !self.rpm.is_finite() {
            return Err(PipelineError::Scene {
                field: "rotor.rpm".into(),
                message: format!("{} must be finite", self.rpm),
            });
        }
        if self.origin.iter().any(|x| !x.is_finite()) {
            return Err(PipelineError::Scene {
                field: "rotor.origin".into(),
                message: format!("{:?} must be finite", self.origin),
            });
        }
        if !(n.is_finite() && (n - 1.0).abs() < 1e-6) {
            return Err(PipelineError::Scene {
                field: "rotor.axis".into(),
                message: format!("{:?} must be a unit vector (norm {n})", self.axis),
            });
        }
        Ok(())
    }
}
