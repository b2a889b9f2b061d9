//! The scene's `[transient]` table as the integrators' options: the step bound, the start's,
//! BDF's and generalized-α's — used by the run, the restart and the DAE export.

use super::system::GapFriction;
use crate::scene::TransientSpec;
use serde::Serialize;
use squeal_solver::bdf::{BdfOptions, InitialConditionOptions, TolerancePartition, Tolerances};
use squeal_solver::bsql::{BsqlSystem, SteadyOptions};
use squeal_solver::galpha::GalphaOptions;
use squeal_solver::Real;

/// The options of a run's start: the steady sliding state and the consistent y'(0), both to
/// TOLINT. The run and the DAE export take them from here.
pub fn start_options(tolint: Real) -> (SteadyOptions, InitialConditionOptions) {
    (
        SteadyOptions {
            tol: tolint,
            ..Default::default()
        },
        InitialConditionOptions {
            tol: tolint,
            ..Default::default()
        },
    )
}

/// BDF options of a run on `sys` with RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) and
/// MAXORD `max_order`; the tolerances per partition of y = {v, λ, u} come from the system.
pub fn bdf_options(
    spec: &TransientSpec,
    sys: &BsqlSystem<GapFriction>,
    rtol: Real,
    max_order: usize,
) -> BdfOptions {
    BdfOptions {
        max_order,
        tolerances: sys.tolerances(rtol, spec.atol1 * rtol / spec.rtol1, spec.rtol2, spec.atol2),
        h0: spec.h0,
        h_max: spec.h_max,
        max_steps: spec.max_steps,
        h_collapse: spec.h_collapse(),
        collapse_steps: spec.collapse_steps,
        ..BdfOptions::default()
    }
}

/// Generalized-α options of a run on n DOFs and ng gaps: fixed step `h`, or adaptive with
/// RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) from `h0` or TFINAL/1000 when `h` is
/// None.
///
/// The Newton matrix always includes the friction damping C_f = ∂F_f/∂v: the scene's
/// `friction_damping_in_jacobian` is the BDF's (the paper's) choice. Without C_f the Newton
/// iteration in (q̈, λ') converges only linearly, at a rate ≈ c_v‖M⁻¹C_f‖ (c_v = γh(1−α_f)/(1−α_m))
/// that reaches 1 where contact points approach the stick zone of [Paper eq. (5)].
pub fn galpha_options(
    spec: &TransientSpec,
    n: usize,
    ng: usize,
    h: Option<Real>,
    rtol: Real,
    rho_inf: Real,
    tf: Real,
) -> GalphaOptions {
    // Fixed steps: the tolerances only set Newton's test; make it tight.
    let rtol = if h.is_some() { 1e-10 } else { rtol };
    let p = |len, rtol, atol| TolerancePartition { len, rtol, atol };
    let atol = spec.atol1 * rtol / spec.rtol1;
    GalphaOptions {
        rho_inf,
        h: h.or(spec.h0).unwrap_or(tf / 1000.0),
        adaptive: h.is_none(),
        tolerances: Tolerances::Partitions {
            parts: vec![
                p(n, rtol, atol),
                p(ng, spec.rtol2, spec.atol2),
                p(n, rtol, atol),
            ],
        },
        h_max: spec.h_max,
        max_steps: spec.max_steps,
        include_friction_damping: true,
        ..GalphaOptions::default()
    }
}

/// The step bound a run used.
#[derive(Debug, Clone, Serialize)]
pub struct StepBound {
    /// The bound applied (None: unbounded).
    pub h_max: Option<Real>,
    /// The scene's own `h_max`.
    pub scene_h_max: Option<Real>,
    /// The model's band and the band bound 1/(N·f_band) (None: no band or bound off).
    pub band_hz: Option<Real>,
    pub band_h_max: Option<Real>,
    /// N, steps per period at the top of the band.
    pub band_samples_per_period: Real,
}

/// The step bound of `spec` on a model of band `band_hz`: the smaller of the scene's `h_max`
/// and 1/(N·f_band) (unless `band_step_bound = false`).
pub fn step_bound(spec: &TransientSpec, band_hz: Option<Real>) -> StepBound {
    let band_h_max = band_hz
        .filter(|_| spec.band_step_bound)
        .map(|f| 1.0 / (spec.band_samples_per_period * f));
    let h_max = match (spec.h_max, band_h_max) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    };
    StepBound {
        h_max,
        scene_h_max: spec.h_max,
        band_hz,
        band_h_max,
        band_samples_per_period: spec.band_samples_per_period,
    }
}
