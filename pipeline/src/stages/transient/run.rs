//! Running a prepared transient: start → drive → decide → result.
//!
//! - start: the restart's state, or the steady sliding state before the brake load and
//!   consistent y'(0) ([`super::start::start_state`]); separation switched on;
//! - drive: the one driver with the run's own sinks ([`Own`]: the collectors, the run's
//!   origin, the in-memory history) and the caller's;
//! - decide: the verdict on what the collectors hold ([`crate::verdict::decide`]), with the
//!   roots of a CEA at the steady state when the scene asks for one;
//! - result: the [`TransientResult`].

use super::collect::contact::ContactMonitor;
use super::collect::face::FaceMonitor;
use super::collect::orders::OrderTally;
use super::collect::response::Response;
use super::driver::{drive_from, DriveOptions, DriveOutcome};
use super::effects;
use super::files::history::Recorder;
use super::prepare::Prepared;
use super::result::{TransientOptions, TransientResult, VerdictCeaResult};
use super::sink::Sink;
use super::start::{start_state, Origin, SteadySummary};
use super::stepper::{IntegratorStats, Method, Stepper};
use crate::error::PipelineError;
use crate::problem::band::{self, BandReport};
use crate::problem::linear::verdict_roots;
use crate::problem::system::{event_mask, separation_mask};
use crate::progress::Progress;
use crate::verdict::roots::PencilOptions;
use crate::verdict::{decide, CeaRoots, Decision, Record, Settings};
use squeal_solver::bdf::BdfStats;
use squeal_solver::bsql::BsqlStats;
use squeal_solver::Real;

/// The sinks every run carries: what the verdict reads, the run's origin (its checkpoint
/// part) and the in-memory history.
struct Own {
    response: Response,
    contact: ContactMonitor,
    origin: Origin,
    orders: OrderTally,
    face: FaceMonitor,
    memory: Recorder,
    separation: bool,
    keep_history: bool,
}

impl Own {
    /// As sinks, in the order the driver feeds them.
    fn sinks(&mut self) -> Vec<&mut dyn Sink> {
        let mut all: Vec<&mut dyn Sink> = vec![
            &mut self.response,
            &mut self.contact,
            &mut self.origin,
            &mut self.orders,
        ];
        if self.separation {
            all.push(&mut self.face);
        }
        if self.keep_history {
            all.push(&mut self.memory);
        }
        all
    }
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
        let (mut stepper, origin, band) = self.start(progress)?;
        let mut own = self.own(origin, opts)?;
        let continued = self
            .resume
            .as_ref()
            .and_then(|r| r.checkpoint())
            .map(|c| c.driver.continued());
        let outcome = {
            let mut all = own.sinks();
            all.extend(sinks.iter_mut().map(|s| &mut **s as &mut dyn Sink));
            let drive = DriveOptions {
                tfinal: self.spec.tfinal,
                max_steps: opts.step_cap.unwrap_or(self.spec.max_steps),
                energy: true,
                label: "transient".into(),
            };
            drive_from(&mut stepper, &mut all, &drive, progress, continued)?
        };
        if !outcome.status.is_success() {
            progress.info(format!("integration stopped: {:?}", outcome.status));
        }
        let cea = self
            .scene
            .output
            .verdict_cea
            .runs(self.model.n())
            .then(|| verdict_roots(self.scene, self.model, &progress.silenced()));
        let roots = cea
            .as_ref()
            .filter(|c| c.error.is_none())
            .map(|c| CeaRoots {
                unstable_in_band: &c.unstable_in_band,
                modes_in_band: &c.modes_in_band,
            });
        let record = Record {
            response: &own.response.series,
            face: Some(&own.face.series),
            contact: &own.contact.validity,
            steps_by_order: own.orders.result.as_ref(),
            status: &outcome.status,
            h_end: Some(stepper.h_order().0),
            first_opening: match stepper.stats() {
                IntegratorStats::Bdf {
                    separation: Some(s),
                    ..
                } => s.first_separation_t,
                _ => None,
            },
        };
        let decision = decide(
            &record,
            &self.settings(own.origin.t_start, opts, &own),
            roots,
        );
        let mut result = self.result(&stepper, own, outcome, decision, cea);
        result.band_limited = band;
        Ok(result)
    }

    /// The stepper at the start (the restart's state, or the steady sliding state and
    /// consistent y'(0)), with separation on when the scene asks, and the run's origin; on
    /// the band-limited model (`transient.band_limited`) its own steady state and initial
    /// values, and what the condensation removed (also in the run's log).
    fn start(
        &self,
        progress: &Progress,
    ) -> Result<(Stepper, Origin, Option<BandReport>), PipelineError> {
        let (spec, model) = (&self.spec, self.model);
        if spec.band_limited {
            let b = band::build(self.scene, model, &self.problem)?;
            progress.info(b.report.line());
            let (st, residual) = Stepper::band(&self.problem, spec, b.system)?;
            let origin = Origin {
                t_start: st.t(),
                steady_state: Some(SteadySummary {
                    iterations: st_band_iterations(&st),
                    residual_norm: residual,
                }),
                initial_conditions: None,
            };
            if spec.tfinal <= origin.t_start {
                return Err(PipelineError::Scene {
                    field: "transient.tfinal".into(),
                    message: format!(
                        "{} is not after the start time {}",
                        spec.tfinal, origin.t_start
                    ),
                });
            }
            return Ok((st, origin, Some(b.report)));
        }
        let resumed = self.resume.as_ref().and_then(|r| r.checkpoint());
        let (mut stepper, origin) = match &self.resume {
            Some(r) => {
                let stats = r.parts.as_ref().map(|p| p.driver.bsql_stats.clone());
                let st =
                    Stepper::from_restart(&self.problem, spec, r.file.clone(), stats, &r.path)?;
                let origin = Origin {
                    t_start: resumed.map_or(st.t(), |c| c.origin.t_start),
                    steady_state: resumed.and_then(|c| c.origin.steady_state.clone()),
                    initial_conditions: resumed.and_then(|c| c.origin.initial_conditions.clone()),
                };
                (st, origin)
            }
            None => {
                let s = start_state(&self.problem, spec.tolint)?;
                let method = Method::of_spec(spec);
                let st =
                    Stepper::new(&self.problem, spec, method, 0.0, &s.y0, &s.yp0, spec.tfinal)?;
                let origin = Origin {
                    t_start: st.t(),
                    steady_state: Some(s.steady),
                    initial_conditions: Some(s.ic),
                };
                (st, origin)
            }
        };
        // The smooth law's gaps (`separation_smoothing`) open through the system itself.
        let can_open = event_mask(self.scene, model);
        if can_open.iter().any(|&c| c) {
            if self.resume.is_some() {
                return Err(PipelineError::Scene {
                    field: "transient.restart".into(),
                    message: "a restart file does not carry the open gaps yet: run a scene \
                              with `[[contact]] separation = true` from its start"
                        .into(),
                });
            }
            stepper.enable_separation(&self.problem.gaps, can_open, spec.event_restart)?;
        }
        if spec.tfinal <= origin.t_start {
            return Err(PipelineError::Scene {
                field: "transient.tfinal".into(),
                message: format!(
                    "{} is not after the start time {}",
                    spec.tfinal, origin.t_start
                ),
            });
        }
        Ok((stepper, origin, None))
    }

    /// The run's own sinks, continuing a resumed run's records.
    fn own(&self, origin: Origin, opts: &TransientOptions) -> Result<Own, PipelineError> {
        let (scene, model) = (self.scene, self.model);
        let resume = self.resume.as_ref();
        let resumed = resume.and_then(|r| r.checkpoint());
        let prior = resume.and_then(|r| r.history());
        let memory = Recorder::open_resumed(
            scene,
            model,
            &self.problem.gaps,
            None,
            opts.keep_history,
            prior,
        )?;
        let mut response = Response::new(scene, model, memory.columns())?;
        if let Some(r) = resume.and_then(|r| r.response()) {
            response.resume(r)?;
        }
        let t_load = self.problem.load.t_load;
        let contact = ContactMonitor::resumed(
            &self.problem.gaps,
            model.n(),
            t_load,
            resumed.map(|c| &c.contact),
        );
        let t_start = origin.t_start;
        let orders = OrderTally::new(t_start, t_load.max(t_start), resumed.map(|c| &c.orders));
        Ok(Own {
            response,
            contact,
            origin,
            orders,
            face: FaceMonitor::new(&self.problem.gaps, model.n()),
            memory,
            separation: separation_mask(scene, model).iter().any(|&c| c),
            keep_history: opts.keep_history,
        })
    }

    /// How the verdict judges this run.
    fn settings(&self, t_start: Real, opts: &TransientOptions, own: &Own) -> Settings {
        let out = &self.scene.output;
        Settings {
            t_after: self.problem.load.t_load.max(t_start),
            stall_h: opts.stall_h,
            band_hz: self.scene.band_hz(),
            pencil: PencilOptions::default(),
            separation: own.separation,
            integrator: self.spec.integrator,
            max_order: self.spec.maxord,
            rho_inf: self.spec.rho_inf,
            growth_threshold_per_s: out.squeal_growth_threshold,
            min_growth_factor: out.squeal_min_growth_factor,
            min_growth_rate_per_s: out.min_growth_rate_per_s,
        }
    }

    /// The result of the run.
    fn result(
        &self,
        stepper: &Stepper,
        mut own: Own,
        outcome: DriveOutcome,
        d: Decision,
        verdict_cea: Option<VerdictCeaResult>,
    ) -> TransientResult {
        let (scene, model) = (self.scene, self.model);
        let (active_effects, ignored) = effects::effects(scene, model, &self.problem);
        let stats = stepper.stats();
        let (drift, max_drift) = stats.constraint_drift();
        let (bdf_stats, galpha_stats, bsql_stats, separation) = match stats.clone() {
            IntegratorStats::Bdf {
                bdf,
                bsql,
                separation,
            } => (bdf, None, bsql, separation),
            IntegratorStats::GeneralizedAlpha { galpha } => (
                BdfStats::default(),
                Some(galpha),
                BsqlStats::default(),
                None,
            ),
        };
        let energy = outcome.energy.unwrap_or_default();
        let history = own.memory.take_history();
        TransientResult {
            status: outcome.status,
            steps: stats.steps(),
            cpu_s: stats.cpu_s(),
            bookkeeping_s: outcome.bookkeeping_s,
            squeal: d.verdict.state.is_squeal(),
            growth_rate_per_s: d.verdict.growth_rate_per_s,
            dominant_frequency_hz: d.verdict.dominant_frequency_hz,
            response: d.response,
            verdict: d.verdict,
            constraint_drift: drift,
            max_constraint_drift: max_drift,
            integrator: stepper.integrator(),
            bdf_stats,
            galpha_stats,
            bsql_stats,
            steady_state: own.origin.steady_state,
            initial_conditions: own.origin.initial_conditions,
            energy_residual: energy.residual(),
            energy,
            t_start: own.origin.t_start,
            t_end: outcome.t_end,
            n_dofs: model.n(),
            n_gaps: model.gap_geometry.len(),
            history_rows: history.as_ref().map_or(0, |h| h.rows()),
            active_effects,
            ignored,
            model_hash: self.model_hash.clone(),
            restarted_from: self.resume.as_ref().map(|r| r.path.clone()),
            step_bound: self.bound.clone(),
            steps_by_order_after_ramp: own.orders.result,
            band_limited: None,
            contact: own.contact.validity,
            separation,
            limit_cycle: d.limit_cycle,
            verdict_cea,
            transient_vs_cea: d.transient_vs_cea,
            warnings: model
                .warnings
                .iter()
                .cloned()
                .chain(self.resume.as_ref().and_then(|r| r.warning.clone()))
                .collect(),
            history,
        }
    }
}

/// Newton iterations of the band-limited model's steady state and initial values.
fn st_band_iterations(st: &Stepper) -> usize {
    match st {
        Stepper::Band { sys, .. } => sys.stats().algebraic_iterations as usize,
        _ => 0,
    }
}
