//! The one transient driver: either integrator, any number of sinks.
//!
//! `squeal transient`, the work–precision study, the hard-case suite, `reproduce` and the
//! Python package all integrate through [`drive`]. What a run does besides integrating is a
//! [`Sink`] on it (the history and energy files, the verdict's response, the restart writer,
//! the accuracy study's grid sampler). The driver owns the loop: it steps in chunks of
//! [`CHUNK`] steps, keeps the energy balance when asked (the per-step bookkeeping, timed apart
//! from the integrator), stops at the times sinks ask for, caps the whole run's steps, reports
//! progress and honours cancellation between chunks. Sinks are flushed after every chunk, also
//! a failed one, so nothing already written is lost. At a restart point (after a chunk that
//! ended where a sink wanted a break, and after the end) every sink saves its part of the
//! [`Checkpoint`], the driver its own ([`DriverPart`]), and every sink sees the point.

use super::sink::{Checkpoint, ChunkView, EndView, RestartPoint, Saved, Sink, StepView};
use super::stepper::{IntegratorStats, Stepper};
use crate::error::PipelineError;
use crate::problem::system::solver_err;
use crate::progress::Progress;
use serde::{Deserialize, Serialize};
use squeal_solver::bdf::Status;
use squeal_solver::bsql::{BsqlStats, EnergyBalance, EnergyRestart};
use squeal_solver::Real;
use squeal_solver::SolverError;
use std::time::Instant;

/// Steps between progress updates, sink flushes and chances to write a restart file.
pub const CHUNK: usize = 50;

/// The bookkeeping a resumed run continues (from a restart file's checkpoint).
#[derive(Debug, Clone, Default)]
pub struct Continued {
    /// The energy integrals with their last records (None: a fresh balance).
    pub energy: Option<EnergyRestart>,
    /// Seconds of bookkeeping before the restart.
    pub bookkeeping_s: Real,
}

/// The driver's part of a checkpoint (top-level keys of `restart.json`'s `run`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DriverPart {
    /// Accepted steps at this point.
    pub steps: u64,
    /// The energy integrals with their last records.
    pub energy: Option<EnergyRestart>,
    /// The BSQL system's counters and drift monitor.
    pub bsql_stats: BsqlStats,
    /// Seconds of bookkeeping so far.
    pub bookkeeping_s: Real,
}

impl DriverPart {
    /// The part saved in a checkpoint, checked against the state it belongs to: the same
    /// steps, a duration, energy integrals that end at the state's time.
    pub fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        let p: DriverPart = s.part(None)?;
        if p.steps != s.steps {
            return Err(s.bad(
                "steps",
                format!("{} differs from the state's {} steps", p.steps, s.steps),
            ));
        }
        if !(p.bookkeeping_s.is_finite() && p.bookkeeping_s >= 0.0) {
            return Err(s.bad(
                "bookkeeping_s",
                format!("{} is not a duration", p.bookkeeping_s),
            ));
        }
        let t = s.t;
        if let Some(e) = &p.energy {
            if e.balance.t != t || e.last.is_none_or(|p| p.t != t) {
                return Err(s.bad(
                    "energy.balance.t",
                    format!(
                        "the integrals end at t = {} (last record {:?}), not at the state's t = {t}",
                        e.balance.t,
                        e.last.map(|p| p.t)
                    ),
                ));
            }
        }
        Ok(p)
    }

    /// The bookkeeping a resumed run continues.
    pub fn continued(&self) -> Continued {
        Continued {
            energy: self.energy.clone(),
            bookkeeping_s: self.bookkeeping_s,
        }
    }
}

/// The checkpoint at a restart point — the driver's part, then every sink's — and the restart
/// point itself, which every sink sees.
fn restart_point(
    stepper: &Stepper,
    sinks: &mut [&mut dyn Sink],
    balance: &EnergyBalance,
    energy: bool,
    bookkeeping_s: Real,
) -> Result<(), PipelineError> {
    let stats = stepper.stats();
    let mut c = Checkpoint::default();
    c.save(
        None,
        &DriverPart {
            steps: stats.steps(),
            energy: energy.then(|| balance.restart_state()),
            bsql_stats: match stats {
                IntegratorStats::Bdf { bsql, .. } => bsql,
                IntegratorStats::GeneralizedAlpha { .. } => BsqlStats::default(),
            },
            bookkeeping_s,
        },
    )?;
    for s in sinks.iter() {
        s.save(&mut c)?;
    }
    let point = RestartPoint {
        t: stepper.t(),
        state: stepper.bdf_state(),
        checkpoint: &c,
    };
    for s in sinks.iter_mut() {
        s.restart_point(&point)?;
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
            t: stepper.t(),
            steps: done,
            failed: st.is_err(),
            order_histogram: stepper.order_histogram(),
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
        t: stepper.t(),
        y: stepper.y(),
        yp: stepper.yp(),
        tfinal: opts.tfinal,
        order_histogram: stepper.order_histogram(),
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
