//! Which effects a transient run computes (only what the scene names), and which scene values
//! had no effect, as enums: `summary.json` lists them by name, the CLI prints their text.

use crate::model::ReducedModel;
use crate::problem::system::Problem;
use crate::scene::{Integrator, Scene};
use serde::Serialize;
use squeal_contact::FrictionLaw;
use squeal_solver::Real;

/// An effect a run computes.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "effect", rename_all = "snake_case")]
pub enum Effect {
    /// Pad/rotor gaps with their constraint rows.
    Contact { gaps: usize },
    /// The friction law of the gaps.
    FrictionLaw { law: FrictionLaw },
    /// ∂μ/∂v is evaluated.
    FrictionSpeedDependence,
    /// ∂μ/∂p is evaluated.
    FrictionPressureDependence,
    /// Constant μ: no derivative of μ is evaluated.
    ConstantMu,
    /// μ is looked up at the gap temperatures.
    TemperatureLookups,
    /// The preload P0 of eq. (1).
    Preload,
    /// The rotor's sliding velocity ω × r.
    RotorSliding,
    /// The brake load as a step at t = 0.
    BrakeLoadStep,
    /// The brake load ramped over TLOAD.
    BrakeLoadRamp { t_load: Real },
    /// Structural damping G/W3.
    StructuralDamping,
    /// Element damping GE/W4.
    ElementDamping,
    /// Modal damping ratio.
    ModalDamping,
    /// C_f = ∂F_f/∂v in the BDF iteration matrix.
    FrictionDampingInJacobian,
    /// Unilateral contact: `gaps` gaps may separate and close (events, plastic impact), and
    /// the limit cycle is analysed.
    Separation { gaps: usize },
    /// The integrator and its setting.
    Integrator {
        integrator: Integrator,
        max_order: Option<usize>,
        rho_inf: Option<Real>,
        fixed_step: Option<Real>,
    },
    /// The history database and energy file, every `noutpt` steps.
    History { noutpt: usize },
    /// No history writes (`output.history = false`).
    NoHistory,
}

/// A scene value given but without effect.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "ignored", rename_all = "snake_case")]
pub enum Ignored {
    /// Gap temperatures, with a law that does not depend on temperature.
    GapTemperatures,
    /// A `[friction]` table on a model without gaps.
    FrictionWithoutGaps,
    /// `damping.g` with W3 = 0.
    StructuralDampingOff,
    /// A `[cea]` table, which `squeal transient` does not run.
    CeaNotRun,
}

impl std::fmt::Display for Effect {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Effect::Contact { gaps } => write!(f, "contact ({gaps} gaps)"),
            Effect::FrictionLaw { law } => write!(
                f,
                "friction law {}",
                serde_json::to_string(law).unwrap_or_default()
            ),
            Effect::FrictionSpeedDependence => f.write_str("friction: speed dependence dmu/dv"),
            Effect::FrictionPressureDependence => {
                f.write_str("friction: pressure dependence dmu/dp")
            }
            Effect::ConstantMu => {
                f.write_str("friction: constant mu, no derivatives of mu evaluated")
            }
            Effect::TemperatureLookups => f.write_str("friction: temperature lookups"),
            Effect::Preload => f.write_str("preload P0"),
            Effect::RotorSliding => f.write_str("rotor sliding velocity"),
            Effect::BrakeLoadStep => f.write_str("brake load (step)"),
            Effect::BrakeLoadRamp { t_load } => write!(f, "brake load (ramp over {t_load})"),
            Effect::StructuralDamping => f.write_str("damping G/W3"),
            Effect::ElementDamping => f.write_str("element damping GE/W4"),
            Effect::ModalDamping => f.write_str("modal damping"),
            Effect::FrictionDampingInJacobian => {
                f.write_str("friction damping C_f in the iteration matrix")
            }
            Effect::Separation { gaps } => write!(
                f,
                "separation: {gaps} gaps may open and close (events, or a compliant pair's \
                 smooth law), limit cycle"
            ),
            Effect::Integrator {
                integrator: Integrator::Bdf,
                max_order,
                ..
            } => write!(f, "integrator: BDF, MAXORD {}", max_order.unwrap_or(0)),
            Effect::Integrator {
                rho_inf,
                fixed_step,
                ..
            } => write!(
                f,
                "integrator: generalized-alpha, rho_inf {}, {}",
                rho_inf.unwrap_or(0.0),
                fixed_step.map_or("adaptive step".to_string(), |h| format!("fixed step {h}"))
            ),
            Effect::History { noutpt } => {
                write!(f, "history database + energy.csv (every {noutpt} steps)")
            }
            Effect::NoHistory => f.write_str("no history writes (output.history = false)"),
        }
    }
}

impl std::fmt::Display for Ignored {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Ignored::GapTemperatures => {
                "gap temperatures: the friction law does not depend on temperature"
            }
            Ignored::FrictionWithoutGaps => "[friction]: the model has no gaps",
            Ignored::StructuralDampingOff => "damping.g: W3 = 0 turns it off",
            Ignored::CeaNotRun => "[cea]: not run by `squeal transient` (use `squeal cea`)",
        })
    }
}

/// The effects a run of `scene` on `model` computes, and the values it ignores.
pub fn effects(scene: &Scene, model: &ReducedModel, p: &Problem) -> (Vec<Effect>, Vec<Ignored>) {
    let mut on = Vec::new();
    let mut ignored = Vec::new();
    let gaps = &p.gaps;
    let law = &gaps.law;
    if !gaps.is_empty() {
        on.push(Effect::Contact { gaps: gaps.len() });
        on.push(Effect::FrictionLaw { law: law.clone() });
        if law.depends_on_speed() {
            on.push(Effect::FrictionSpeedDependence);
        }
        if law.depends_on_pressure() {
            on.push(Effect::FrictionPressureDependence);
        }
        if !law.depends_on_speed() && !law.depends_on_pressure() {
            on.push(Effect::ConstantMu);
        }
        if law.depends_on_temperature() {
            on.push(Effect::TemperatureLookups);
        } else if gaps.gaps.iter().any(|g| g.temperature != 0.0) {
            ignored.push(Ignored::GapTemperatures);
        }
        if gaps.gaps.iter().any(|g| g.p0 != 0.0) {
            on.push(Effect::Preload);
        }
        if gaps
            .gaps
            .iter()
            .any(|g| g.v_slide.iter().any(|&v| v != 0.0))
        {
            on.push(Effect::RotorSliding);
        }
    } else if scene.friction.is_some() {
        ignored.push(Ignored::FrictionWithoutGaps);
    }
    if p.load.p_brake.iter().any(|&x| x != 0.0) {
        on.push(match p.load.step {
            true => Effect::BrakeLoadStep,
            false => Effect::BrakeLoadRamp {
                t_load: p.load.t_load,
            },
        });
    }
    if let Some(d) = &scene.damping {
        if d.overall_factor() != 0.0 {
            on.push(Effect::StructuralDamping);
        } else if d.g != 0.0 {
            ignored.push(Ignored::StructuralDampingOff);
        }
        if model.b.is_some() {
            on.push(Effect::ElementDamping);
        }
        if d.modal_ratio > 0.0 {
            on.push(Effect::ModalDamping);
        }
    }
    if p.bsql.include_friction_damping {
        on.push(Effect::FrictionDampingInJacobian);
    }
    let can_open = crate::problem::system::separation_mask(scene, model);
    let separating = can_open.iter().filter(|&&c| c).count();
    if separating > 0 {
        on.push(Effect::Separation { gaps: separating });
    }
    let spec = scene.transient.clone().unwrap_or_default();
    on.push(match spec.integrator {
        Integrator::Bdf => Effect::Integrator {
            integrator: Integrator::Bdf,
            max_order: Some(spec.maxord),
            rho_inf: None,
            fixed_step: None,
        },
        Integrator::GeneralizedAlpha => Effect::Integrator {
            integrator: Integrator::GeneralizedAlpha,
            max_order: None,
            rho_inf: Some(spec.rho_inf),
            fixed_step: spec.galpha_h,
        },
    });
    on.push(match scene.output.history {
        true => Effect::History {
            noutpt: spec.noutpt,
        },
        false => Effect::NoHistory,
    });
    if scene.cea.is_some() {
        ignored.push(Ignored::CeaNotRun);
    }
    (on, ignored)
}
