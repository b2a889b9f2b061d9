//! The roots of the problem linearised about a state: the CEA's core, shared by `squeal cea`
//! (which adds energies, sensitivities, sweeps and files) and the transient's verdict (which
//! needs the roots only, [`verdict_roots`]). [Paper eqs. (19)–(24)]
//!
//! problem → state and tangents ([`super::tangents`]) → the solver's matrices →
//! `squeal_solver::cea::complex_eigen` on the validity band → the roots in the band and above
//! it, apart (roots above the band are outside what the reduced model represents).

use super::system::{self, Problem};
use super::tangents::{self, ContactSummary, Linearisation};
use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::progress::Progress;
use crate::scene::{CeaSpec, Scene};
use serde::Serialize;
use squeal_solver::cea::{
    complex_eigen, method_for, CeaError, CeaMatrices, CeaMethod, CeaOptions, CeaStats, ModalBasis,
    Mode,
};
use squeal_solver::Real;

/// The solver options with the validity band as the projection's band of interest
/// (`projection.frequency_max_hz`) when the scene gives neither it nor a basis cutoff: `auto`
/// then projects models above `projection.auto_single_min_dofs` reduced DOFs on the real modes
/// up to `cutoff_factor` × the band, and refines the in-band unstable roots exactly.
pub fn banded(solver: &CeaOptions, band_hz: Option<Real>) -> CeaOptions {
    let mut o = solver.clone();
    let pr = &mut o.projection;
    if pr.frequency_max_hz.is_none() && pr.basis_cutoff_hz.is_none() {
        pr.frequency_max_hz = band_hz;
    }
    o
}

/// The validity band: what the model was reduced for, or `max_frequency_hz` if lower.
pub fn band_of(scene: &Scene, spec: &CeaSpec) -> Option<Real> {
    match (scene.band_hz(), spec.max_frequency_hz) {
        (Some(a), Some(b)) => Some(a.min(b)),
        (a, b) => a.or(b),
    }
}

/// The problem linearised about the `[cea] at` state and its roots.
pub struct Roots {
    /// The state and tangents.
    pub lin: Linearisation,
    /// The contact state of the linearisation.
    pub contact: ContactSummary,
    /// The solver's matrices.
    pub sys: CeaMatrices,
    /// The validity band ([`band_of`]).
    pub band_hz: Option<Real>,
    /// The eigen-solver's options on that band ([`banded`]).
    pub solver: CeaOptions,
    /// Roots in the band, sorted by frequency (`shape`: the reduced eigenvector).
    pub kept: Vec<Mode>,
    /// Roots above it.
    pub above: Vec<Mode>,
    pub stats: CeaStats,
    /// Projected on a basis given to [`roots_on`]: `Some(true)` when that basis is the one
    /// this state would make (same K, M and G), `Some(false)` when it was made for other
    /// matrices (an approximation the caller must measure); None: solved afresh.
    pub reused_basis: Option<bool>,
}

/// Linearises `problem` about the state `spec.at` names and solves for its roots.
pub fn roots(
    scene: &Scene,
    spec: &CeaSpec,
    problem: &Problem,
    model: &ReducedModel,
    progress: &Progress,
) -> Result<Roots, PipelineError> {
    roots_on(scene, spec, problem, model, None, progress)
}

/// The projection basis the CEA of [`roots`] would make for `problem` (None: the CEA solves
/// exactly, as a small model does), for [`roots_on`] to reuse at other states.
pub fn projection_basis(
    scene: &Scene,
    spec: &CeaSpec,
    problem: &Problem,
    progress: &Progress,
) -> Result<Option<ModalBasis>, PipelineError> {
    let lin = tangents::linearise(scene, spec, problem)?;
    let sys = tangents::cea_matrices(problem, &lin, spec.friction_damping)?;
    let solver = banded(&spec.solver, band_of(scene, spec));
    let err = |source| PipelineError::cea("the projection basis".to_string(), source);
    progress.check("cea")?;
    match method_for(&sys, &solver).map_err(err)? {
        CeaMethod::Projection => Ok(Some(ModalBasis::new(&sys, &solver).map_err(err)?)),
        _ => Ok(None),
    }
}

/// [`roots`], projected on `basis` (made by [`projection_basis`] at another state of the
/// same model, e.g. another μ) when the CEA projects and the basis fits this problem's size
/// and constraint; else as [`roots`]. The in-band unstable roots are refined exactly either
/// way; the rest are the projection's. [`Roots::reused_basis`] says which ran.
pub fn roots_on(
    scene: &Scene,
    spec: &CeaSpec,
    problem: &Problem,
    model: &ReducedModel,
    basis: Option<&ModalBasis>,
    progress: &Progress,
) -> Result<Roots, PipelineError> {
    let gaps = &problem.gaps;
    let (n, ng) = (model.n(), gaps.len());
    let step = progress.step("linearising about the sliding state");
    let lin = tangents::linearise(scene, spec, problem)?;
    step.done("tangents at the state");
    let contact = tangents::contact_summary(gaps, &model.gap_pairs, &lin)?;
    let sys = tangents::cea_matrices(problem, &lin, spec.friction_damping)?;
    progress.check("cea")?;
    // Roots above the band are listed apart and never count as squeal.
    let band_hz = band_of(scene, spec);
    let solver = banded(&spec.solver, band_hz);
    let step = progress.step(format!("complex eigenvalues ({n} DOFs, {ng} constraints)"));
    let err = |source| PipelineError::cea("complex eigenvalues".to_string(), source);
    let reusable = match basis {
        Some(b) if method_for(&sys, &solver).map_err(err)? == CeaMethod::Projection => Some(b),
        _ => None,
    };
    let (res, reused_basis) = match reusable {
        Some(b) => match b.solve_refined(&sys, &solver) {
            Ok(r) => (r, Some(b.is_basis_of(&sys))),
            // Another size or constraint (G): the basis does not apply, solve afresh.
            Err(CeaError::Shape { .. } | CeaError::BasisMismatch { .. }) => {
                (complex_eigen(&sys, &solver).map_err(err)?, None)
            }
            Err(e) => return Err(err(e)),
        },
        None => (complex_eigen(&sys, &solver).map_err(err)?, None),
    };
    step.done(format!(
        "{} modes, {} unstable{}",
        res.stats.n_modes,
        res.stats.n_unstable,
        res.stats.refine.as_ref().map_or(String::new(), |r| format!(
            " ({} refined exactly, max |dp| {:.3e} /s)",
            r.n_refined, r.max_abs_change
        ))
    ));
    let fmax = band_hz.unwrap_or(Real::INFINITY);
    let (kept, above): (Vec<Mode>, Vec<Mode>) =
        res.modes.into_iter().partition(|m| m.frequency_hz <= fmax);
    Ok(Roots {
        lin,
        contact,
        sys,
        band_hz,
        solver,
        kept,
        above,
        stats: res.stats,
        reused_basis,
    })
}

/// The CEA the transient's verdict compares the response with: the roots at the steady state
/// under the full brake load (the state the response after the ramp vibrates about).
#[derive(Debug, Clone, Serialize)]
pub struct VerdictCeaResult {
    /// Unstable roots in the band, most unstable first: (frequency Hz, Re p 1/s).
    pub unstable_in_band: Vec<(Real, Real)>,
    /// Unstable roots above the band (never squeal: outside what the model was reduced for).
    pub unstable_outside_band: usize,
    /// Every root in the band (frequency Hz, Re p 1/s), for the transient/CEA table.
    #[serde(skip)]
    pub modes_in_band: Vec<(Real, Real)>,
    /// Why it failed, if it did (the verdict then goes without it).
    pub error: Option<String>,
}

/// The roots of `scene`'s `[cea]` table (its sweep left out) on `model`, for the verdict; a
/// failure is recorded, not returned.
pub fn verdict_roots(scene: &Scene, model: &ReducedModel, progress: &Progress) -> VerdictCeaResult {
    let found = (|| {
        let mut spec = scene.cea.clone().unwrap_or_default();
        spec.sweep = None;
        spec.validate()?;
        spec.solver.interrupt = progress.solver_interrupt();
        let problem = system::problem(scene, model)?;
        roots(scene, &spec, &problem, model, progress)
    })();
    match found {
        Ok(r) => {
            let mut unstable: Vec<(Real, Real)> = r
                .kept
                .iter()
                .filter(|m| m.unstable)
                .map(|m| (m.frequency_hz, m.real_part))
                .collect();
            // Most unstable first; equal real parts keep the frequency order (a stable sort).
            unstable.sort_by(|a, b| b.1.total_cmp(&a.1));
            VerdictCeaResult {
                unstable_in_band: unstable,
                unstable_outside_band: r.above.iter().filter(|m| m.unstable).count(),
                modes_in_band: r
                    .kept
                    .iter()
                    .map(|m| (m.frequency_hz, m.real_part))
                    .collect(),
                error: None,
            }
        }
        Err(e) => VerdictCeaResult {
            unstable_in_band: Vec::new(),
            unstable_outside_band: 0,
            modes_in_band: Vec::new(),
            error: Some(e.to_string()),
        },
    }
}
