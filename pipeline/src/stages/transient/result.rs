//! What a transient run gives: [`TransientResult`] in memory, [`TransientReport`] as
//! `summary.json`, and what a caller asks of a run besides the scene ([`TransientOptions`]).

use super::effects::{Effect, Ignored};
use super::files::history::History;
use super::prepare::StepBound;
use super::start::SteadySummary;
use crate::scene::Integrator;
use crate::verdict::guard::StepsByOrder;
use crate::verdict::limit_cycle::LimitCycle;
use crate::verdict::roots::RootPair;
use crate::verdict::validity::ContactValidity;
use crate::verdict::Verdict;
use serde::Serialize;
use squeal_solver::bdf::{BdfStats, IcStats, Status};
use squeal_solver::bsql::{BsqlStats, EnergyBalance};
use squeal_solver::galpha::GalphaStats;
use squeal_solver::Real;
use std::path::PathBuf;

pub use crate::problem::linear::VerdictCeaResult;

/// What a caller asks of a run besides the scene.
#[derive(Debug, Clone, Default)]
pub struct TransientOptions {
    /// Keep the sampled history (every NOUTPT-th step, as `history.npy`) in memory.
    pub keep_history: bool,
    /// Cap on the accepted steps (default: the scene's `max_steps`).
    pub step_cap: Option<usize>,
    /// Judge only the growth phase: the response up to the first step shorter than this after
    /// the load ramp (a study case's stick–slip onset, where the step collapses).
    pub stall_h: Option<Real>,
}

/// What a transient run found, in memory. Serialised (without the history arrays) it is the
/// body of `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct TransientResult {
    /// How the integration ended.
    pub status: Status,
    /// Accepted steps (cumulative over restarts).
    pub steps: u64,
    /// Seconds inside the integrator (cumulative over restarts).
    pub cpu_s: Real,
    /// Seconds of per-step bookkeeping outside the integrator (energy terms, records).
    pub bookkeeping_s: Real,
    pub squeal: bool,
    pub growth_rate_per_s: Option<Real>,
    pub dominant_frequency_hz: Option<Real>,
    /// History column of the verdict's response.
    pub response: String,
    pub verdict: Verdict,
    /// ‖G v‖∞ at the last step and its maximum.
    pub constraint_drift: Real,
    pub max_constraint_drift: Real,
    pub integrator: Integrator,
    /// BDF counters (zero for generalized-α runs).
    pub bdf_stats: BdfStats,
    /// Generalized-α counters (generalized-α runs only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub galpha_stats: Option<GalphaStats>,
    pub bsql_stats: BsqlStats,
    pub steady_state: Option<SteadySummary>,
    pub initial_conditions: Option<IcStats>,
    pub energy: EnergyBalance,
    /// Energy balance residual ΔE − net work in.
    pub energy_residual: Real,
    pub t_start: Real,
    pub t_end: Real,
    pub n_dofs: usize,
    pub n_gaps: usize,
    /// Rows of the recorded history (`history.npy`, or the in-memory history).
    pub history_rows: usize,
    /// The effects this run computed (only what the scene names).
    pub active_effects: Vec<Effect>,
    /// Scene values given but without effect.
    pub ignored: Vec<Ignored>,
    pub model_hash: String,
    pub restarted_from: Option<PathBuf>,
    /// The step bound used (the scene's `h_max` and the band bound).
    pub step_bound: StepBound,
    /// The BDF's steps after the load ramp by order, whose mean numerical decay the guard
    /// weighs (None for generalized-α).
    pub steps_by_order_after_ramp: Option<StepsByOrder>,
    /// The band-limited model the run integrated (`transient.band_limited`): the cut-off, what
    /// was kept and removed (count, the largest removed unstable root), the error estimate.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band_limited: Option<crate::problem::band::BandReport>,
    /// What the contact did: tensile gap-steps, the first separation, the smallest p_n.
    pub contact: ContactValidity,
    /// Separation events (`[[contact]] separation = true`): openings, closings, impact
    /// dissipation, first separation (absent when separation is off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<squeal_solver::bsql::UnilateralStats>,
    /// The limit cycle of the rotor friction face's normal velocity (with separation, when
    /// the verdict found a dominant frequency; see [`super::limit_cycle`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit_cycle: Option<LimitCycle>,
    /// The CEA at the run's steady state, when the verdict ran one (`output.verdict_cea`).
    pub verdict_cea: Option<VerdictCeaResult>,
    /// The response's significant roots each beside the CEA root nearest in frequency, with
    /// the relative differences in σ and f (when the verdict ran a CEA).
    pub transient_vs_cea: Option<Vec<RootPair>>,
    /// Inputs accepted with a measured value to know about ([`crate::warning`]).
    pub warnings: Vec<crate::warning::Warning>,
    /// The sampled history (with [`TransientOptions::keep_history`]).
    #[serde(skip)]
    pub history: Option<History>,
}

/// `summary.json` of a transient run.
#[derive(Debug, Clone, Serialize)]
pub struct TransientReport {
    pub verb: &'static str,
    pub version: &'static str,
    /// Whole run, wall seconds.
    pub wall_s: Real,
    #[serde(flatten)]
    pub result: TransientResult,
}
