//! A transient ready to run: the problem of the scene on the model, the step bound, and the
//! restart it continues, all checked before anything integrates.

use super::resume::Resume;
use crate::error::PipelineError;
use crate::model;
pub use crate::problem::options::{step_bound, StepBound};
use crate::problem::system::{self, Problem};
use crate::scene::{Integrator, Scene, TransientSpec};

/// A transient of `scene` on a reduced model, ready to run.
pub struct Prepared<'a> {
    pub scene: &'a Scene,
    pub model: &'a model::ReducedModel,
    pub spec: TransientSpec,
    pub problem: Problem,
    /// Hash of the model a restart file must match.
    pub model_hash: String,
    /// The step bound (`spec.h_max` holds it).
    pub bound: StepBound,
    /// The restart the run continues (`transient.restart`), read and checked.
    pub resume: Option<Resume>,
}

/// Assembles the problem of `scene`'s transient on `model`; checks what the integrator can do.
pub fn prepare<'a>(
    scene: &'a Scene,
    model: &'a model::ReducedModel,
) -> Result<Prepared<'a>, PipelineError> {
    let spec = scene.transient.clone().unwrap_or_default();
    if spec.integrator == Integrator::GeneralizedAlpha && spec.restart.is_some() {
        return Err(PipelineError::Scene {
            field: "transient.integrator".into(),
            message: "generalized_alpha has no restart; use bdf".into(),
        });
    }
    if spec.band_limited && spec.integrator == Integrator::GeneralizedAlpha {
        return Err(PipelineError::Scene {
            field: "transient.band_limited".into(),
            message:
                "the band-limited model runs on the BDF integrator (transient.integrator = \"bdf\")"
                    .into(),
        });
    }
    if spec.band_limited && spec.restart.is_some() {
        return Err(PipelineError::Scene {
            field: "transient.restart".into(),
            message: "a band-limited run writes no restart file and continues none; \
                      run it from its start"
                .into(),
        });
    }
    let problem = system::problem(scene, model)?;
    if spec.integrator == Integrator::GeneralizedAlpha && !problem.compliance.is_empty() {
        let i = scene
            .contact
            .iter()
            .position(|c| c.normal_stiffness.is_some())
            .unwrap_or(0);
        return Err(PipelineError::Scene {
            field: format!("contact[{i}].normal_stiffness"),
            message: "normal contact compliance needs the BDF integrator \
                      (transient.integrator = \"bdf\"); generalized_alpha carries the rigid \
                      constraint only"
                .into(),
        });
    }
    let model_hash = problem.model_hash();
    let bound = step_bound(&spec, scene.band_hz());
    let mut spec = spec;
    spec.h_max = bound.h_max;
    let resume = match &spec.restart {
        Some(p) => {
            let path = scene.resolve(p);
            let r = Resume::load(&path, &model_hash, model.n(), model.gap_geometry.len())?;
            // The restart's last step may end past TFINAL (the run then ends at TFINAL by
            // interpolation, as the uninterrupted run did); TFINAL before that step cannot be
            // reached.
            let (t, h_used) = (r.file.t, r.file.state.h_used);
            if spec.tfinal <= t - h_used || (spec.tfinal <= t && r.checkpoint().is_none()) {
                return Err(PipelineError::Scene {
                    field: "transient.tfinal".into(),
                    message: format!(
                        "{} is not after the restart's time {t} ({})",
                        spec.tfinal,
                        path.display()
                    ),
                });
            }
            Some(r)
        }
        None => None,
    };
    Ok(Prepared {
        scene,
        model,
        spec,
        problem,
        model_hash,
        bound,
        resume,
    })
}
