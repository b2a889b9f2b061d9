//! `squeal transient`: the BSQL nonlinear transient of the reduced brake model.
//!
//! reduced model → BSQL system (M, B, K, G, P(t), gap friction) ([`system`]) → steady sliding
//! state before the brake load (TOLINT) and consistent y'(0) ([`start_state`]), or a restart
//! file's state → BDF or generalized-α to TFINAL through the one [`driver`], whose sinks record
//! what the run keeps → the squeal verdict ([`verdict`]) on the response.
//!
//! - Compute: [`prepare`] the run (problem, model hash), then [`Prepared::run`] with any extra
//!   sinks; it returns a [`TransientResult`] in memory (status, statistics, verdict, energy,
//!   effects, and with [`TransientOptions::keep_history`] the sampled history arrays).
//! - Write: [`run_on_model`] (the CLI) attaches the file sinks — `history.npy` +
//!   `history_map.json` and `energy.csv` ([`records::Recorder`]), `restart.json` every NRSTRT
//!   steps and at the end (BDF, [`restart::RestartSink`]) with `response.npy`
//!   ([`records::ResponseFile`]) — and writes `summary.json` ([`TransientReport`]).
//! - Resume: with `transient.restart`, [`prepare`] reads the restart file and the records of
//!   the run that wrote it ([`restart::Resume`]); the run continues the state, the records,
//!   the energy integrals, counters and contact monitor, and its result covers the whole run
//!   — the uninterrupted run's, bit for bit.

pub mod driver;
pub mod effects;
pub mod export;
pub mod guard;
pub mod limit_cycle;
pub mod records;
pub mod restart;
pub mod roots;
pub mod system;
pub mod validity;
pub mod verdict;

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{Integrator, Scene, TransientSpec};
use crate::stages::model;
use driver::{
    drive_from, solver_err, Continued, DriveOptions, IntegratorStats, Method, Sink, Stepper,
};
use effects::{Effect, Ignored};
use records::{History, Recorder, Response, ResponseFile};
use restart::{MonitorSink, OriginSink, RestartSink, Resume};
use serde::{Deserialize, Serialize};
use squeal_contact::GapSet;
use squeal_solver::bdf::{
    consistent_initial_conditions, BdfStats, IcStats, InitialConditionOptions, Status,
};
use squeal_solver::bsql::{steady_state, BsqlStats, EnergyBalance, SteadyOptions};
use squeal_solver::galpha::GalphaStats;
use std::path::{Path, PathBuf};
use std::time::Instant;
use verdict::Verdict;

type Real = f64;

/// Steady-state solve summary.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct SteadySummary {
    pub iterations: usize,
    pub residual_norm: f64,
}

/// The start of a run without restart.
#[derive(Debug, Clone)]
pub struct StartState {
    pub y0: Vec<Real>,
    pub yp0: Vec<Real>,
    pub steady: SteadySummary,
    pub ic: IcStats,
}

/// The steady sliding state before the brake load (TOLINT) and consistent y'(0): the start of
/// every run that does not continue a restart (transient, accuracy study, hard cases).
pub fn start_state(
    problem: &system::Problem,
    gaps: &GapSet,
    tolint: Real,
) -> Result<StartState, PipelineError> {
    let mut sys = problem.system(gaps.clone())?;
    // t = −1 < 0: the ramp is 0, so the state is the sliding equilibrium under P0 alone.
    let steady_opts = SteadyOptions {
        tol: tolint,
        ..Default::default()
    };
    let ic_opts = InitialConditionOptions {
        tol: tolint,
        ..Default::default()
    };
    let ss = steady_state(&mut sys, -1.0, &steady_opts).map_err(solver_err("steady state"))?;
    let (mut y0, mut yp0) = ss.initial_values();
    let ic = consistent_initial_conditions(&mut sys, 0.0, &mut y0, &mut yp0, None, &ic_opts)
        .map_err(solver_err("consistent initial conditions"))?;
    Ok(StartState {
        y0,
        yp0,
        steady: SteadySummary {
            iterations: ss.iterations,
            residual_norm: ss.residual_norm,
        },
        ic,
    })
}

/// How a run ended, in words: `reached` or the status with its numbers (tables and logs; the
/// results themselves carry the [`Status`] enum).
pub fn status_text(s: &Status) -> String {
    match s {
        Status::Reached { .. } => "reached".into(),
        Status::MaxSteps { t, steps } => {
            format!("stopped at the step cap ({steps} steps) at t = {t:.4e}")
        }
        other => format!("{other:?}"),
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

/// The CEA a transient ran at its steady state for its verdict.
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
    pub steps_by_order_after_ramp: Option<guard::StepsByOrder>,
    /// What the contact did: tensile gap-steps, the first separation, the smallest p_n.
    pub contact: validity::ContactValidity,
    /// Separation events (`[[contact]] separation = true`): openings, closings, impact
    /// dissipation, first separation (absent when separation is off).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub separation: Option<squeal_solver::bsql::UnilateralStats>,
    /// The limit cycle of the rotor friction face's normal velocity (with separation, when
    /// the verdict found a dominant frequency; see [`limit_cycle`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub limit_cycle: Option<limit_cycle::LimitCycle>,
    /// The CEA at the run's steady state, when the verdict ran one (`output.verdict_cea`).
    pub verdict_cea: Option<VerdictCeaResult>,
    /// The response's significant roots each beside the CEA root nearest in frequency, with
    /// the relative differences in σ and f (when the verdict ran a CEA).
    pub transient_vs_cea: Option<Vec<roots::RootPair>>,
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

/// A transient of `scene` on a reduced model, ready to run.
pub struct Prepared<'a> {
    pub scene: &'a Scene,
    pub model: &'a model::ReducedModel,
    pub spec: TransientSpec,
    pub problem: system::Problem,
    /// Hash of the model a restart file must match.
    pub model_hash: String,
    /// The step bound (`spec.h_max` holds it).
    pub bound: StepBound,
    /// The restart the run continues (`transient.restart`), read and checked.
    pub resume: Option<Resume>,
}

/// Per gap: may it separate (`separation = true` on its `[[contact]]` pair)? A stored model's
/// gap table is one pair, read with the scene's `[[contact]]` table.
pub fn separation_mask(scene: &Scene, model: &model::ReducedModel) -> Vec<bool> {
    let mut mask = Vec::with_capacity(model.gaps.len());
    for (pair, &count) in model.gap_pairs.iter().enumerate() {
        let on = scene.contact.get(pair).is_some_and(|c| c.separation);
        mask.extend(std::iter::repeat_n(on, count));
    }
    mask.resize(model.gaps.len(), false);
    mask
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
            let r = Resume::load(&path, &model_hash, model.n(), model.gaps.len())?;
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

impl Prepared<'_> {
    /// Runs the transient, feeding `sinks` besides its own (the verdict's response, and the
    /// in-memory history when asked).
    pub fn run(
        &self,
        progress: &Progress,
        opts: &TransientOptions,
        sinks: &mut [&mut dyn Sink],
    ) -> Result<TransientResult, PipelineError> {
        let (scene, model, spec) = (self.scene, self.model, &self.spec);
        let (n, ng) = (model.n(), model.gaps.len());
        // Initial state: restart file, or steady sliding before the brake load + y'(0).
        let (mut stepper, steady, ic, restarted_from) = match &self.resume {
            Some(r) => {
                let st = Stepper::from_restart(
                    &self.problem,
                    &model.gaps,
                    spec,
                    r.file.clone(),
                    &r.path,
                )?;
                let (steady, ic) = r.checkpoint().map_or((None, None), |c| {
                    (c.steady_state.clone(), c.initial_conditions.clone())
                });
                (st, steady, ic, Some(r.path.clone()))
            }
            None => {
                let s = start_state(&self.problem, &model.gaps, spec.tolint)?;
                let st = Stepper::new(
                    &self.problem,
                    &model.gaps,
                    spec,
                    Method::of_spec(spec),
                    0.0,
                    &s.y0,
                    &s.yp0,
                    spec.tfinal,
                )?;
                (st, Some(s.steady), Some(s.ic), None)
            }
        };
        let can_open = separation_mask(scene, model);
        let separation = can_open.iter().any(|&c| c);
        if separation {
            if restarted_from.is_some() {
                return Err(PipelineError::Scene {
                    field: "transient.restart".into(),
                    message: "a restart file does not carry the open gaps yet: run a scene \
                              with `[[contact]] separation = true` from its start"
                        .into(),
                });
            }
            stepper.enable_separation(&model.gaps, can_open)?;
        }
        // A true resume continues the run's records and bookkeeping; its result covers the
        // whole run from the original start.
        let checkpoint = self.resume.as_ref().and_then(Resume::checkpoint);
        let records = self.resume.as_ref().and_then(|r| r.records.as_ref());
        let t_start = checkpoint.map_or(stepper.t(), |c| c.t_start);
        if spec.tfinal <= t_start {
            return Err(PipelineError::Scene {
                field: "transient.tfinal".into(),
                message: format!("{} is not after the start time {t_start}", spec.tfinal),
            });
        }
        let mut memory = Recorder::open_resumed(scene, model, None, opts.keep_history, records)?;
        let mut resp = Response::new(scene, model, memory.columns())?;
        let mut contact = validity::ContactMonitor::new(&model.gaps, n, self.problem.load.t_load);
        if let (Some(r), Some(c)) = (records, checkpoint) {
            resp.resume(r)?;
            if let Some(v) = &c.contact {
                contact.validity = v.clone();
                contact.validity.upgrade(self.problem.load.t_load);
            }
        }
        let mut origin = OriginSink {
            t_start,
            steady_state: steady.clone(),
            initial_conditions: ic.clone(),
        };
        let mut face = limit_cycle::FaceMonitor::new(&model.gaps);
        let mut orders = guard::OrderTally::new(
            t_start,
            self.problem.load.t_load.max(t_start),
            checkpoint.and_then(|c| c.orders_at_ramp.clone()),
        );
        let outcome = {
            let mut monitor = MonitorSink(&mut contact);
            let mut all: Vec<&mut dyn Sink> = vec![
                &mut resp as &mut dyn Sink,
                &mut monitor as &mut dyn Sink,
                &mut origin as &mut dyn Sink,
                &mut orders as &mut dyn Sink,
            ];
            if separation {
                all.push(&mut face as &mut dyn Sink);
            }
            if opts.keep_history {
                all.push(&mut memory as &mut dyn Sink);
            }
            all.extend(sinks.iter_mut().map(|s| &mut **s as &mut dyn Sink));
            drive_from(
                &mut stepper,
                &mut all,
                &DriveOptions {
                    tfinal: spec.tfinal,
                    max_steps: opts.step_cap.unwrap_or(spec.max_steps),
                    energy: true,
                    label: "transient".into(),
                },
                progress,
                checkpoint.map(|c| Continued {
                    energy: c.energy.clone(),
                    bookkeeping_s: c.bookkeeping_s,
                }),
            )?
        };
        if !outcome.status.is_success() {
            progress.info(format!("integration stopped: {:?}", outcome.status));
        }
        // Verdict on the response after the ramp, before any tensile contact after the ramp
        // (tensile gaps while the load is applied are reported, not judged: see `validity`).
        let contact = contact.validity;
        let t_after = self.problem.load.t_load.max(t_start);
        let t_stop = contact
            .first_tensile_after_ramp
            .filter(|_| !separation)
            .map(|e| e.t);
        // The growth and frequency are fitted on the window after the ramp, up to the first
        // tensile gap when there is one (below): a clear growth counts as squeal only within
        // the part where the contact was valid.
        let band = scene.band_hz();
        let po = roots::PencilOptions::default();
        let (response, mut verdict) =
            resp.verdict(t_after, opts.stall_h, None, memory.columns(), band, &po);
        // With separation the response may saturate into a limit cycle; the fit over the
        // whole window then sees little growth. The growth that matters is the one before
        // the response saturated: the roots are fitted there.
        let limit_cycle = separation
            .then(|| face.analyse(t_after, verdict.dominant_frequency_hz))
            .flatten();
        let saturation = limit_cycle.as_ref().filter(|l| l.reached).and_then(|l| {
            let first_opening = match stepper.stats() {
                IntegratorStats::Bdf {
                    separation: Some(s),
                    ..
                } => s.first_separation_t,
                _ => None,
            };
            face.saturation(t_after, l, first_opening)
        });
        if let Some(sat) = saturation {
            let (_, before) = resp.verdict(
                t_after,
                opts.stall_h,
                Some(sat.growth_end),
                memory.columns(),
                band,
                &po,
            );
            if before.estimator.is_some() {
                verdict = before;
            }
            verdict.saturation = Some(sat);
        }
        let growth_while_valid = match t_stop {
            Some(_) => {
                resp.verdict(t_after, opts.stall_h, t_stop, memory.columns(), band, &po)
                    .1
            }
            None => verdict.clone(),
        };
        // The state is judged on the valid part, so the roots, growth and window reported are
        // those of that part too (a run once said `squeal` beside a whole-window σ of −1.4 /s:
        // the hex20 brake's case 7, tensile from 10.5 ms).
        if t_stop.is_some() && growth_while_valid.estimator.is_some() {
            let saturation = verdict.saturation.take();
            verdict = growth_while_valid.clone();
            verdict.saturation = saturation;
        }
        verdict.valid_until = t_stop;
        let verdict_cea = scene
            .output
            .verdict_cea
            .runs(n)
            .then(|| self.verdict_cea(progress));
        let mut frequencies = Vec::new();
        if let Some(f) = verdict.dominant_frequency_hz {
            frequencies.push((guard::FrequencySource::Dominant, f));
        }
        match (&verdict_cea, scene.band_hz()) {
            (Some(c), _) if c.error.is_none() => {
                if let Some(f) = c.unstable_in_band.iter().map(|r| r.0).reduce(Real::max) {
                    frequencies.push((guard::FrequencySource::CeaUnstable, f));
                }
            }
            (_, Some(band)) => frequencies.push((guard::FrequencySource::BandTop, band)),
            _ => {}
        }
        let clear_growth = growth_while_valid.is_squeal(
            scene.output.squeal_growth_threshold,
            scene.output.squeal_min_growth_factor,
        );
        let (state, resolution, detectable) = guard::judge(&guard::Evidence {
            clear_growth,
            window: verdict.window,
            h_max_window: verdict.h_max_window,
            steps_by_order: orders.result.as_ref(),
            frequencies,
            contact: &contact,
            separation,
            status: &outcome.status,
            h_end: Some(stepper.h_order().0),
            integrator: stepper.integrator(),
            max_order: spec.maxord,
            rho_inf: spec.rho_inf,
            min_growth_rate_per_s: scene.output.min_growth_rate_per_s,
            min_growth_factor: scene.output.squeal_min_growth_factor,
            limit_cycle: limit_cycle.as_ref().filter(|l| l.reached).map(|l| {
                guard::LimitCycleEvidence {
                    peak_normal_velocity: l.peak_normal_velocity,
                    amplitude_growth: saturation.map(|s| s.amplitude_growth),
                }
            }),
        });
        verdict.evidence = state.is_squeal().then_some(match clear_growth {
            true => verdict::SquealEvidence::Growth,
            false => verdict::SquealEvidence::LimitCycle,
        });
        verdict.state = state;
        verdict.resolution = resolution;
        verdict.detectable_growth_per_s = detectable;
        let transient_vs_cea = verdict_cea
            .as_ref()
            .filter(|c| c.error.is_none())
            .map(|c| roots::pair_with_cea(&verdict.roots, &c.modes_in_band));
        let (active_effects, ignored) = effects::effects(scene, model, &self.problem);
        let stats = stepper.stats();
        let (drift, max_drift) = stats.constraint_drift();
        let (bdf_stats, galpha_stats, bsql_stats) = match stats.clone() {
            IntegratorStats::Bdf { bdf, bsql, .. } => (bdf, None, bsql),
            IntegratorStats::GeneralizedAlpha { galpha } => {
                (BdfStats::default(), Some(galpha), BsqlStats::default())
            }
        };
        let separation_stats = match &stats {
            IntegratorStats::Bdf { separation, .. } => separation.clone(),
            IntegratorStats::GeneralizedAlpha { .. } => None,
        };
        let energy = outcome.energy.unwrap_or_default();
        let history = memory.take_history();
        Ok(TransientResult {
            status: outcome.status,
            steps: stats.steps(),
            cpu_s: stats.cpu_s(),
            bookkeeping_s: outcome.bookkeeping_s,
            squeal: verdict.state.is_squeal(),
            growth_rate_per_s: verdict.growth_rate_per_s,
            dominant_frequency_hz: verdict.dominant_frequency_hz,
            response,
            verdict,
            constraint_drift: drift,
            max_constraint_drift: max_drift,
            integrator: stepper.integrator(),
            bdf_stats,
            galpha_stats,
            bsql_stats,
            steady_state: steady,
            initial_conditions: ic,
            energy_residual: energy.residual(),
            energy,
            t_start,
            t_end: outcome.t_end,
            n_dofs: n,
            n_gaps: ng,
            history_rows: history.as_ref().map_or(0, |h| h.rows()),
            active_effects,
            ignored,
            model_hash: self.model_hash.clone(),
            restarted_from,
            step_bound: self.bound.clone(),
            steps_by_order_after_ramp: orders.result.clone(),
            contact,
            separation: separation_stats,
            limit_cycle,
            verdict_cea,
            transient_vs_cea,
            warnings: model
                .warnings
                .iter()
                .cloned()
                .chain(self.resume.as_ref().and_then(|r| r.warning.clone()))
                .collect(),
            history,
        })
    }

    /// The CEA at the steady state under the full brake load (the state the response after
    /// the ramp vibrates about), for the verdict; a failure is recorded, not fatal.
    fn verdict_cea(&self, progress: &Progress) -> VerdictCeaResult {
        let mut cs = self.scene.clone();
        let mut spec = cs.cea.clone().unwrap_or_default();
        spec.sweep = None;
        cs.cea = Some(spec);
        match crate::stages::cea::compute(
            &cs,
            self.model,
            &progress.silenced(),
            &Default::default(),
        ) {
            // The CEA's modes are those in its validity band; the rest it counts apart.
            Ok(c) => VerdictCeaResult {
                unstable_in_band: c
                    .unstable()
                    .iter()
                    .map(|(_, m)| (m.frequency_hz, m.real_part))
                    .collect(),
                unstable_outside_band: c.out.outside_band.n_unstable,
                modes_in_band: c
                    .out
                    .modes
                    .iter()
                    .map(|m| (m.frequency_hz, m.real_part))
                    .collect(),
                error: None,
            },
            Err(e) => VerdictCeaResult {
                unstable_in_band: Vec::new(),
                unstable_outside_band: 0,
                modes_in_band: Vec::new(),
                error: Some(e.to_string()),
            },
        }
    }
}

/// The transient of `scene` on `model`, in memory (no file is written): the library's and the
/// Python package's entry point.
pub fn compute(
    scene: &Scene,
    model: &model::ReducedModel,
    progress: &Progress,
    opts: &TransientOptions,
) -> Result<TransientResult, PipelineError> {
    prepare(scene, model)?.run(progress, opts, &mut [])
}

/// Runs the transient (model built or read through `cache`) and writes its outputs into `dir`;
/// `export_dae` also writes the problem as data into that folder.
pub fn run_cached(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
    cache: Option<&model::ModelCache>,
) -> Result<TransientReport, PipelineError> {
    let wall = Instant::now();
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, _) = model::build_cached(scene, dir, progress, cache)?;
    run_on_model(
        scene,
        dir,
        progress,
        export_dae,
        &model,
        wall,
        &Default::default(),
    )
}

/// [`run_cached`] without a cache.
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
) -> Result<TransientReport, PipelineError> {
    run_cached(scene, dir, progress, export_dae, None)
}

/// The transient on a reduced model already built for `scene`, with its files in `dir`
/// (`wall`: when the run started). The errors of a resumed run name the restart file.
pub fn run_on_model(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
    model: &model::ReducedModel,
    wall: Instant,
    opts: &TransientOptions,
) -> Result<TransientReport, PipelineError> {
    let restart = scene.transient.as_ref().and_then(|t| t.restart.as_ref());
    run_model(scene, dir, progress, export_dae, model, wall, opts).map_err(|e| match restart {
        Some(p)
            if !e
                .to_string()
                .contains(&scene.resolve(p).display().to_string()) =>
        {
            PipelineError::Resumed {
                path: scene.resolve(p),
                source: Box::new(e),
            }
        }
        _ => e,
    })
}

fn run_model(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    export_dae: Option<&Path>,
    model: &model::ReducedModel,
    wall: Instant,
    opts: &TransientOptions,
) -> Result<TransientReport, PipelineError> {
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let prepared = prepare(scene, model)?;
    let spec = &prepared.spec;
    if let Some(d) = export_dae {
        if spec.integrator == Integrator::GeneralizedAlpha {
            return Err(PipelineError::Scene {
                field: "transient.integrator".into(),
                message: "generalized_alpha has no DAE export; use bdf".into(),
            });
        }
        let sys = prepared.problem.system(model.gaps.clone())?;
        let bdf_opts = squeal_solver::bdf::BdfOptions {
            max_order: spec.maxord,
            tolerances: sys.tolerances(spec.rtol1, spec.atol1, spec.rtol2, spec.atol2),
            h0: spec.h0,
            h_max: spec.h_max,
            max_steps: spec.max_steps,
            ..Default::default()
        };
        let edir = RunDir::create(d)?;
        export::export(
            &edir,
            &prepared.problem,
            &model.gaps,
            &bdf_opts,
            &InitialConditionOptions {
                tol: spec.tolint,
                ..Default::default()
            },
            &SteadyOptions {
                tol: spec.tolint,
                ..Default::default()
            },
            spec.tfinal,
        )?;
        progress.info(format!("exported the DAE to {}", d.display()));
    }
    let records = prepared.resume.as_ref().and_then(|r| r.records.as_ref());
    let mut files = Recorder::open_resumed(scene, model, Some(dir), false, records)?;
    let mut restart = RestartSink {
        path: dir.path("restart.json"),
        model_hash: prepared.model_hash.clone(),
        n: model.n(),
        ng: model.gaps.len(),
        max_order: spec.maxord,
        every: spec.nrstrt,
    };
    let mut result = match spec.integrator {
        // The response beside the restart file, for a resumed run's verdict.
        Integrator::Bdf => {
            let dofs = Response::new(scene, model, files.columns())?
                .dofs()
                .to_vec();
            let mut response = ResponseFile::open(dir, &dofs, records)?;
            prepared.run(
                progress,
                opts,
                &mut [&mut files, &mut response, &mut restart],
            )?
        }
        Integrator::GeneralizedAlpha => {
            prepared.run(progress, opts, &mut [&mut files, &mut restart])?
        }
    };
    result.history_rows = files.rows();
    let report = TransientReport {
        verb: "transient",
        version: crate::VERSION,
        wall_s: wall.elapsed().as_secs_f64(),
        result,
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
