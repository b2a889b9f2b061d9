//! The one transient driver: either integrator, any number of sinks.
//!
//! `squeal transient`, the work–precision study, the hard-case suite, `reproduce` and the
//! Python package all integrate through [`drive`]. What a run does besides integrating is a
//! [`Sink`] on it: the history and energy files ([`super::records::Recorder`]), the in-memory
//! history ([`super::records::HistoryBuffer`]), the verdict's response
//! ([`super::records::Response`]), the restart writer ([`super::restart::RestartSink`]), the
//! accuracy study's grid sampler. The driver owns the loop: it steps in chunks of [`CHUNK`]
//! steps, keeps the energy balance when asked (the per-step bookkeeping, timed apart from the
//! integrator), stops at the times sinks ask for, caps the whole run's steps, reports progress
//! and honours cancellation between chunks. Sinks are flushed after every chunk, also a failed
//! one, so nothing already written is lost.

use super::restart::RunCheckpoint;
use super::system::{GapFriction, Problem};
use crate::error::PipelineError;
use crate::progress::Progress;
use crate::scene::{Integrator, TransientSpec};
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::bdf::{
    Bdf, BdfOptions, BdfState, BdfStats, Status, TolerancePartition, Tolerances,
};
use squeal_solver::bsql::{
    BsqlStats, BsqlSystem, EnergyBalance, EnergyRestart, PowerTerms, Unilateral, UnilateralOptions,
    UnilateralStats,
};
use squeal_solver::galpha::{Galpha, GalphaOptions, GalphaStats, GalphaSystem};
use squeal_solver::SolverError;
use std::time::Instant;

type Real = f64;

/// Steps between progress updates, sink flushes and chances to write a restart file.
pub const CHUNK: usize = 50;

/// Integrator and accuracy setting of one run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
#[serde(tag = "integrator", rename_all = "snake_case")]
pub enum Method {
    /// BDF with RTOL1 = `rtol` (ATOL1 scaled by rtol / scene RTOL1) and MAXORD.
    Bdf { rtol: Real, max_order: usize },
    /// Generalized-α: fixed step `h`, or adaptive with `rtol` when `h` is None.
    GeneralizedAlpha {
        h: Option<Real>,
        rtol: Real,
        rho_inf: Real,
    },
}

impl Method {
    /// The method the scene's `[transient]` table asks for.
    pub fn of_spec(spec: &TransientSpec) -> Self {
        match spec.integrator {
            Integrator::Bdf => Method::Bdf {
                rtol: spec.rtol1,
                max_order: spec.maxord,
            },
            Integrator::GeneralizedAlpha => Method::GeneralizedAlpha {
                h: spec.galpha_h,
                rtol: spec.rtol1,
                rho_inf: spec.rho_inf,
            },
        }
    }

    /// Which integrator.
    pub fn integrator(&self) -> Integrator {
        match self {
            Method::Bdf { .. } => Integrator::Bdf,
            Method::GeneralizedAlpha { .. } => Integrator::GeneralizedAlpha,
        }
    }
}

pub(crate) fn solver_err(what: &str) -> impl FnOnce(SolverError) -> PipelineError + '_ {
    move |source| PipelineError::Solver {
        what: what.to_string(),
        source,
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

/// The integrator of a run with its system. The BDF's BSQL system also observes the energy
/// terms; generalized-α integrates its own system and a BSQL system observes.
#[allow(clippy::large_enum_variant)] // one per run, never moved in a loop
pub enum Stepper {
    Bdf {
        bdf: Bdf,
        sys: BsqlSystem<GapFriction>,
        /// Separation events (`[[contact]] separation = true`), None when off.
        uni: Option<Unilateral>,
    },
    GeneralizedAlpha {
        ga: Galpha,
        sys: GalphaSystem<GapFriction>,
        obs: BsqlSystem<GapFriction>,
    },
}

/// The integrator's counters, whichever it is.
// Counters, built once per run and serialised: the BDF variant's size does not matter.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, Serialize)]
#[serde(tag = "integrator", rename_all = "snake_case")]
pub enum IntegratorStats {
    Bdf {
        bdf: BdfStats,
        bsql: BsqlStats,
        /// Separation events (None when separation is off).
        #[serde(skip_serializing_if = "Option::is_none")]
        separation: Option<UnilateralStats>,
    },
    GeneralizedAlpha {
        galpha: GalphaStats,
    },
}

impl IntegratorStats {
    /// Accepted steps (cumulative over restarts).
    pub fn steps(&self) -> u64 {
        match self {
            IntegratorStats::Bdf { bdf, .. } => bdf.steps,
            IntegratorStats::GeneralizedAlpha { galpha } => galpha.steps,
        }
    }

    /// Seconds inside the integrator.
    pub fn cpu_s(&self) -> Real {
        match self {
            IntegratorStats::Bdf { bdf, .. } => bdf.cpu_s,
            IntegratorStats::GeneralizedAlpha { galpha } => galpha.cpu_s,
        }
    }

    /// (last, largest) ‖G v‖∞ the integrator's system saw.
    pub fn constraint_drift(&self) -> (Real, Real) {
        match self {
            IntegratorStats::Bdf { bsql, .. } => (bsql.constraint_drift, bsql.max_constraint_drift),
            IntegratorStats::GeneralizedAlpha { galpha } => {
                (galpha.constraint_drift, galpha.max_constraint_drift)
            }
        }
    }
}

impl Stepper {
    /// A new integrator at (t0, y0, y0') for `method`.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        problem: &Problem,
        gaps: &GapSet,
        spec: &TransientSpec,
        method: Method,
        t0: Real,
        y0: &[Real],
        yp0: &[Real],
        tfinal: Real,
    ) -> Result<Self, PipelineError> {
        let n = problem.m.nrows();
        let ng = problem.g.nrows();
        match method {
            Method::Bdf { rtol, max_order } => {
                let sys = problem.system(gaps.clone())?;
                let bdf = Bdf::new(bdf_options(spec, &sys, rtol, max_order), t0, y0, yp0)
                    .map_err(solver_err("integrator"))?;
                Ok(Stepper::Bdf {
                    bdf,
                    sys,
                    uni: None,
                })
            }
            Method::GeneralizedAlpha { h, rtol, rho_inf } => {
                let obs = problem.system(gaps.clone())?;
                let mut sys = GalphaSystem::new(
                    problem.m.clone(),
                    problem.b.clone(),
                    problem.k.clone(),
                    problem.g.clone(),
                    problem.load.clone(),
                    GapFriction { set: gaps.clone() },
                )
                .map_err(solver_err("building the generalized-alpha system"))?;
                let opts = galpha_options(spec, n, ng, h, rtol, rho_inf, tfinal);
                let ga = Galpha::new(opts, &mut sys, t0, y0, yp0)
                    .map_err(solver_err("generalized-alpha start"))?;
                Ok(Stepper::GeneralizedAlpha { ga, sys, obs })
            }
        }
    }

    /// A BDF integrator continuing a restart file's state (`path`: the file, named in errors).
    pub fn from_restart(
        problem: &Problem,
        gaps: &GapSet,
        spec: &TransientSpec,
        restart: super::restart::RestartFile,
        path: &std::path::Path,
    ) -> Result<Self, PipelineError> {
        let mut sys = problem.system(gaps.clone())?;
        let stats = restart.run.as_ref().map(|r| r.bsql_stats.clone());
        let mut bdf = restart.bdf(path, bdf_options(spec, &sys, spec.rtol1, spec.maxord))?;
        if let Some(stats) = stats {
            // The matrix the run last formed, re-formed now, then the run's counters: the
            // resumed run counts as the uninterrupted one does.
            bdf.restore_iteration_matrix(&mut sys)
                .map_err(|e| PipelineError::Input {
                    path: path.to_path_buf(),
                    message: format!("field `state.jacobian_point`: {e}"),
                })?;
            sys.restore_stats(stats);
        }
        Ok(Stepper::Bdf {
            bdf,
            sys,
            uni: None,
        })
    }

    /// Let the gaps with `can_open[k]` separate and close again (events, plastic impact,
    /// restart at order 1; see [`squeal_solver::bsql::unilateral`]). An open gap carries
    /// λ' = P_0 A (p_n = 0). BDF only: generalized-α gets an error naming the option.
    pub fn enable_separation(
        &mut self,
        gaps: &GapSet,
        can_open: Vec<bool>,
    ) -> Result<(), PipelineError> {
        match self {
            Stepper::Bdf { bdf, sys, uni } => {
                let open_force = gaps.gaps.iter().map(|g| g.p0 * g.area).collect();
                let (y, yp) = (bdf.y().to_vec(), bdf.yp().to_vec());
                *uni = Some(
                    Unilateral::new(
                        sys,
                        open_force,
                        Some(can_open),
                        &y,
                        &yp,
                        UnilateralOptions::default(),
                    )
                    .map_err(solver_err("separation"))?,
                );
                Ok(())
            }
            Stepper::GeneralizedAlpha { .. } => Err(PipelineError::Scene {
                field: "contact[].separation".into(),
                message: "separation events need the BDF integrator \
                          (transient.integrator = \"bdf\")"
                    .into(),
            }),
        }
    }

    /// Kinetic energy lost in the plastic impacts so far (0 without separation).
    pub fn impact_dissipated(&self) -> Real {
        match self {
            Stepper::Bdf { uni: Some(u), .. } => u.stats().impact_dissipated,
            _ => 0.0,
        }
    }

    /// Which integrator.
    pub fn integrator(&self) -> Integrator {
        match self {
            Stepper::Bdf { .. } => Integrator::Bdf,
            Stepper::GeneralizedAlpha { .. } => Integrator::GeneralizedAlpha,
        }
    }

    /// Time of the solution in `y()`.
    pub fn t(&self) -> Real {
        match self {
            Stepper::Bdf { bdf, .. } => bdf.t(),
            Stepper::GeneralizedAlpha { ga, .. } => ga.t(),
        }
    }

    /// y = {v, λ, u} at the last step or output time.
    pub fn y(&self) -> &[Real] {
        match self {
            Stepper::Bdf { bdf, .. } => bdf.y(),
            Stepper::GeneralizedAlpha { ga, .. } => ga.y(),
        }
    }

    /// y' at the last step or output time.
    pub fn yp(&self) -> &[Real] {
        match self {
            Stepper::Bdf { bdf, .. } => bdf.yp(),
            Stepper::GeneralizedAlpha { ga, .. } => ga.yp(),
        }
    }

    /// Step size of the next step, and the BDF order (2 for generalized-α).
    pub fn h_order(&self) -> (Real, usize) {
        match self {
            Stepper::Bdf { bdf, .. } => (bdf.state().h, bdf.state().order),
            Stepper::GeneralizedAlpha { ga, .. } => (ga.h(), 2),
        }
    }

    /// The BDF's complete state (None for generalized-α: no restart).
    pub fn bdf_state(&self) -> Option<&BdfState> {
        match self {
            Stepper::Bdf { bdf, .. } => Some(bdf.state()),
            Stepper::GeneralizedAlpha { .. } => None,
        }
    }

    /// Counters so far.
    pub fn stats(&self) -> IntegratorStats {
        match self {
            Stepper::Bdf { bdf, sys, uni } => IntegratorStats::Bdf {
                bdf: bdf.stats().clone(),
                bsql: sys.stats().clone(),
                separation: uni.as_ref().map(|u| u.stats().clone()),
            },
            Stepper::GeneralizedAlpha { ga, .. } => IntegratorStats::GeneralizedAlpha {
                galpha: ga.stats().clone(),
            },
        }
    }

    /// The BSQL system that observes energies.
    fn observer(&mut self) -> &mut BsqlSystem<GapFriction> {
        match self {
            Stepper::Bdf { sys, .. } => sys,
            Stepper::GeneralizedAlpha { obs, .. } => obs,
        }
    }

    /// Integrates to `tout`, calling `on_step(observer, t, y, y')` after every accepted step.
    fn step_to<F>(&mut self, tout: Real, mut on_step: F) -> Result<Status, SolverError>
    where
        F: FnMut(&mut BsqlSystem<GapFriction>, Real, &[Real], &[Real]) -> Result<bool, SolverError>,
    {
        match self {
            Stepper::Bdf {
                bdf,
                sys,
                uni: Some(u),
            } => u.step_to(bdf, sys, tout, on_step),
            Stepper::Bdf {
                bdf,
                sys,
                uni: None,
            } => bdf.step_to(sys, tout, on_step),
            Stepper::GeneralizedAlpha { ga, sys, obs } => {
                ga.step_to(sys, tout, |_, t, y, yp| on_step(obs, t, y, yp))
            }
        }
    }
}

fn bdf_options(
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
        ..BdfOptions::default()
    }
}

/// One accepted step (or the initial point, `step` = the steps before the run) as sinks see it.
///
/// At a separation event the sinks see two views at the same time t: the state before the
/// switch (it ends the integrator's accepted step that crossed the event, cut back to the
/// event) and the state after it (switched rows, impact, consistent y'), which has
/// `repeat = true` and is no step: counters of steps skip it.
pub struct StepView<'a> {
    /// Accepted integrator steps so far, counted from the start of the integration (a
    /// restarted run continues its count); the state after an event does not add one.
    pub step: usize,
    /// This view is at the same time as the previous one: the state after an event, not an
    /// accepted step.
    pub repeat: bool,
    pub t: Real,
    /// y = {v, λ, u}.
    pub y: &'a [Real],
    /// y' = {v', λ', u'}.
    pub yp: &'a [Real],
    /// Energies at this point (when the run keeps the energy balance).
    pub power: Option<&'a PowerTerms>,
    /// The balance integrated so far (empty when not kept).
    pub balance: &'a EnergyBalance,
}

/// The end of a chunk of steps.
pub struct ChunkView<'a> {
    pub stepper: &'a Stepper,
    /// Accepted steps so far.
    pub steps: usize,
    /// The chunk ended in an error (sinks flush and write nothing new).
    pub failed: bool,
}

/// The end of a run.
pub struct EndView<'a> {
    pub status: &'a Status,
    pub stepper: &'a Stepper,
    pub tfinal: Real,
}

/// What a run does besides integrating. Every method but `step` has a default that does
/// nothing.
pub trait Sink {
    /// The initial point and every accepted step, in order.
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError>;
    /// True when the chunk should end after accepted step `step` (a restart is due).
    fn wants_break(&self, _step: usize) -> bool {
        false
    }
    /// The next time at which the sink wants the solution exactly (interpolated), if any.
    fn next_stop(&self) -> Option<Real> {
        None
    }
    /// The solution at a time `next_stop` asked for.
    fn stop(&mut self, _t: Real, _y: &[Real], _yp: &[Real]) -> Result<(), PipelineError> {
        Ok(())
    }
    /// After every chunk, also a failed one: flush.
    fn chunk_end(&mut self, _c: &ChunkView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// The run ended (any status).
    fn end(&mut self, _e: &EndView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    /// At a restart point (after the chunk ends where a sink wanted a break, and after the
    /// end), what this sink must carry over a restart: its part of the checkpoint.
    fn checkpoint(&self, _c: &mut RunCheckpoint) {}
    /// A restart point: the checkpoint every sink contributed to (the restart writer saves it).
    fn restart_point(
        &mut self,
        _stepper: &Stepper,
        _c: &RunCheckpoint,
    ) -> Result<(), PipelineError> {
        Ok(())
    }
}

/// The bookkeeping a resumed run continues (from a restart file's checkpoint).
#[derive(Debug, Clone, Default)]
pub struct Continued {
    /// The energy integrals with their last records (None: a fresh balance).
    pub energy: Option<EnergyRestart>,
    /// Seconds of bookkeeping before the restart.
    pub bookkeeping_s: Real,
}

/// The checkpoint of every sink at a restart point, and the restart point itself.
fn restart_point(
    stepper: &Stepper,
    sinks: &mut [&mut dyn Sink],
    balance: &EnergyBalance,
    energy: bool,
    bookkeeping_s: Real,
) -> Result<(), PipelineError> {
    let stats = stepper.stats();
    let mut c = RunCheckpoint {
        steps: stats.steps(),
        energy: energy.then(|| balance.restart_state()),
        bsql_stats: match stats {
            IntegratorStats::Bdf { bsql, .. } => bsql,
            IntegratorStats::GeneralizedAlpha { .. } => BsqlStats::default(),
        },
        bookkeeping_s,
        ..Default::default()
    };
    for s in sinks.iter() {
        s.checkpoint(&mut c);
    }
    for s in sinks.iter_mut() {
        s.restart_point(stepper, &c)?;
    }
    Ok(())
}

/// How to drive a run.
#[derive(Debug, Clone)]
pub struct DriveOptions {
    /// End time.
    pub tfinal: Real,
    /// Cap on the accepted steps of the whole run (not per call).
    pub max_steps: usize,
    /// Keep the energy balance (the per-step bookkeeping).
    pub energy: bool,
    /// Progress bar label.
    pub label: String,
}

/// What a run gave, besides what its sinks kept.
#[derive(Debug, Clone)]
pub struct DriveOutcome {
    pub status: Status,
    pub t_start: Real,
    pub t_end: Real,
    /// Accepted steps in this run (a restarted run counts from its restart).
    pub steps: usize,
    /// Energy balance (None when not kept).
    pub energy: Option<EnergyBalance>,
    /// Seconds of per-step bookkeeping (energy terms and sinks), outside the integrator.
    pub bookkeeping_s: Real,
}

/// Integrates from the stepper's state to `opts.tfinal`, feeding every sink. See the module
/// documentation.
pub fn drive(
    stepper: &mut Stepper,
    sinks: &mut [&mut dyn Sink],
    opts: &DriveOptions,
    progress: &Progress,
) -> Result<DriveOutcome, PipelineError> {
    drive_from(stepper, sinks, opts, progress, None)
}

/// [`drive`], continuing a resumed run's bookkeeping when `continued` is given: the energy
/// integrals go on from the checkpoint's, and the starting point (the restart's last step,
/// which the run resumed has already recorded) is not passed to the sinks again.
pub fn drive_from(
    stepper: &mut Stepper,
    sinks: &mut [&mut dyn Sink],
    opts: &DriveOptions,
    progress: &Progress,
    continued: Option<Continued>,
) -> Result<DriveOutcome, PipelineError> {
    let t_start = stepper.t();
    let first = stepper.stats().steps() as usize;
    let resumed = continued.is_some();
    let (mut balance, mut book) = match continued {
        Some(c) => (
            c.energy
                .map(EnergyBalance::from_restart_state)
                .unwrap_or_default(),
            c.bookkeeping_s,
        ),
        None => (EnergyBalance::new(), 0.0),
    };
    if !resumed {
        let clock = Instant::now();
        let (y, yp) = (stepper.y().to_vec(), stepper.yp().to_vec());
        let p = match opts.energy {
            true => Some(
                stepper
                    .observer()
                    .observe(t_start, &y, &yp)
                    .map_err(solver_err("energy"))?,
            ),
            false => None,
        };
        if let Some(p) = &p {
            balance.push(p);
        }
        let view = StepView {
            step: first,
            repeat: false,
            t: t_start,
            y: &y,
            yp: &yp,
            power: p.as_ref(),
            balance: &balance,
        };
        for s in sinks.iter_mut() {
            s.step(&view)?;
        }
        book += clock.elapsed().as_secs_f64();
    }
    let bar = progress.bar(&opts.label);
    let span = (opts.tfinal - t_start).max(Real::MIN_POSITIVE);
    let mut done = first;
    // Time of the last view the sinks saw: a view at the same time is an event's second
    // state (after the switch), not an accepted step.
    let mut last_t = t_start;
    let status = loop {
        progress.check(&opts.label)?;
        let tout = sinks
            .iter()
            .filter_map(|s| s.next_stop())
            .fold(opts.tfinal, Real::min);
        let mut in_chunk = 0usize;
        let mut stash: Option<PipelineError> = None;
        let st = stepper.step_to(tout, |obs, t, y, yp| {
            let clock = Instant::now();
            let repeat = t <= last_t;
            last_t = t;
            if !repeat {
                done += 1;
                in_chunk += 1;
            }
            let p = match opts.energy {
                true => {
                    let p = obs.observe(t, y, yp)?;
                    balance.push(&p);
                    Some(p)
                }
                false => None,
            };
            let view = StepView {
                step: done,
                repeat,
                t,
                y,
                yp,
                power: p.as_ref(),
                balance: &balance,
            };
            for s in sinks.iter_mut() {
                if let Err(e) = s.step(&view) {
                    let message = e.to_string();
                    stash = Some(e);
                    return Err(SolverError::Callback { t, message });
                }
            }
            let brk = sinks.iter().any(|s| s.wants_break(done));
            book += clock.elapsed().as_secs_f64();
            Ok(in_chunk < CHUNK && !brk && done - first < opts.max_steps)
        });
        balance.impact_dissipated = stepper.impact_dissipated();
        let view = ChunkView {
            stepper,
            steps: done,
            failed: st.is_err(),
        };
        let mut flushed = Ok(());
        for s in sinks.iter_mut() {
            let r = s.chunk_end(&view);
            if flushed.is_ok() {
                flushed = r;
            }
        }
        let st = match st {
            Ok(st) => st,
            Err(source) => {
                return Err(stash.unwrap_or(PipelineError::Solver {
                    what: "integration".into(),
                    source,
                }))
            }
        };
        flushed?;
        if sinks.iter().any(|s| s.wants_break(done)) {
            restart_point(stepper, sinks, &balance, opts.energy, book)?;
        }
        let (h, order) = stepper.h_order();
        bar.set((stepper.t() - t_start) / span, || {
            format!(
                "t = {:.4e}, h = {h:.2e}, order {order}, steps {done}",
                stepper.t()
            )
        });
        match st {
            Status::Reached { t } => {
                let (y, yp) = (stepper.y().to_vec(), stepper.yp().to_vec());
                for s in sinks.iter_mut() {
                    if s.next_stop().is_some_and(|ts| ts <= t) {
                        s.stop(t, &y, &yp)?;
                    }
                }
                if t >= opts.tfinal {
                    break st;
                }
            }
            Status::Interrupted { .. } if done - first >= opts.max_steps => {
                break Status::MaxSteps {
                    t: stepper.t(),
                    steps: done - first,
                }
            }
            Status::Interrupted { .. } => {}
            other => break other,
        }
    };
    bar.finish(format!("{done} steps, t = {:.4e}", stepper.t()));
    let end = EndView {
        status: &status,
        stepper,
        tfinal: opts.tfinal,
    };
    for s in sinks.iter_mut() {
        s.end(&end)?;
    }
    restart_point(stepper, sinks, &balance, opts.energy, book)?;
    Ok(DriveOutcome {
        t_start,
        t_end: stepper.t(),
        steps: done - first,
        status,
        energy: opts.energy.then_some(balance),
        bookkeeping_s: book,
    })
}
