//! Friction sweep: the CEA at each μ of the sweep, tracked by the solver's MAC tracking.

use super::steady::SweepSteady;
use crate::error::PipelineError;
use crate::problem::system::Problem;
use crate::problem::tangents::{at_steady_state, cea_matrices_of, tangents, Linearisation};
use crate::scene::{CeaSpec, CeaSweepSpec, SweepVary};
use serde::{Deserialize, Serialize};
use squeal_contact::FrictionLaw;
use squeal_solver::cea::{sweep, CeaMatrices, CeaMethod, ModeEvent, Sweep, SweepStats};

use squeal_solver::Real;

/// The friction law of one sweep value.
pub fn law_at(base: &FrictionLaw, vary: SweepVary, value: Real) -> FrictionLaw {
    match vary {
        SweepVary::Constant => FrictionLaw::Constant { mu: value },
        SweepVary::Scale => match base {
            FrictionLaw::Constant { mu } => FrictionLaw::Constant { mu: mu * value },
            FrictionLaw::LinearSpeed { mu0, slope } => FrictionLaw::LinearSpeed {
                mu0: mu0 * value,
                slope: slope * value,
            },
            FrictionLaw::Equation { mu0, a, b, c, t0 } => FrictionLaw::Equation {
                mu0: mu0 * value,
                a: *a,
                b: *b,
                c: *c,
                t0: *t0,
            },
            FrictionLaw::Table(t) => {
                let mut t = t.clone();
                t.values.iter_mut().for_each(|v| *v *= value);
                FrictionLaw::Table(t)
            }
        },
    }
}

/// The matrices at one sweep value: the law replaced or scaled, the steady state solved again
/// (if `resolve_state` and the base state is a steady state: by `steady` when given, K
/// factorised once for the sweep, else by the dense Newton), the tangents evaluated there.
pub fn matrices_at(
    problem: &Problem,
    base: &Linearisation,
    spec: &CeaSpec,
    sw: &CeaSweepSpec,
    value: Real,
    steady_cache: Option<&mut SweepSteady>,
) -> Result<CeaMatrices, PipelineError> {
    // The operating point's law varied: the problem's gaps with the law at `value`.
    let gaps = &problem.gaps;
    let law = law_at(&gaps.law, sw.vary, value);
    let g = gaps
        .clone()
        .with_friction(law, gaps.vtol)
        .map_err(|source| PipelineError::Contact {
            what: format!("friction law at sweep value {value}"),
            source,
        })?;
    let steady = matches!(
        base.source,
        crate::problem::tangents::StateSource::SteadyState { .. }
    );
    let lin = if sw.resolve_state && steady {
        match steady_cache {
            Some(c) => c.solve(problem, &g, &spec.steady)?,
            None => at_steady_state(problem, &g, &spec.steady)?,
        }
    } else {
        let (d, c_f) = tangents(&g, problem.m.nrows(), &base.v, &base.lambda_dot)?;
        Linearisation {
            d,
            c_f,
            ..base.clone()
        }
    };
    cea_matrices_of(problem, lin.d, lin.c_f, spec.friction_damping)
}

/// One point of a tracked mode.
#[derive(Debug, Clone, Serialize)]
pub struct TrackPoint {
    pub mu: Real,
    pub frequency_hz: Real,
    pub real_part: Real,
    pub damping_ratio: Option<Real>,
}

/// A tracked mode in `cea.sweep.json`.
#[derive(Debug, Clone, Serialize)]
pub struct TrackOut {
    pub id: usize,
    pub unstable_at_start: bool,
    /// Onset of instability inside the sweep (critical μ, merging partner).
    pub critical: Option<squeal_solver::cea::Critical>,
    /// Indices into [`SweepReport::events`] of the coalescences and veerings of this branch.
    pub events: Vec<usize>,
    pub points: Vec<TrackPoint>,
}

/// A critical μ with the pair of modes that merge.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct CouplingOut {
    pub track: usize,
    pub mu_critical: Real,
    pub frequency_hz: Real,
    /// The partner track (the other mode of the merging pair).
    pub partner: Option<usize>,
    /// Frequencies of the pair at the last stable step.
    pub pair_frequencies_before_hz: [Option<Real>; 2],
    /// Frequencies of the pair at the first unstable step.
    pub pair_frequencies_after_hz: [Option<Real>; 2],
}

/// `cea.sweep.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepReport {
    pub vary: SweepVary,
    pub base_law: FrictionLaw,
    pub mu: Vec<Real>,
    pub max_frequency_hz: Option<Real>,
    /// Critical μ per coupling, lowest first.
    pub couplings: Vec<CouplingOut>,
    pub lowest_critical_mu: Option<Real>,
    /// The validity band of the CEA, Hz (the model's band or `max_frequency_hz`).
    pub band_hz: Option<Real>,
    /// The lowest critical μ of a coupling whose onset frequency is in the band (above it the
    /// roots are not squeal, and a projected sweep does not resolve them).
    pub lowest_critical_mu_in_band: Option<Real>,
    /// How `lowest_critical_mu_in_band` was found (None: no in-band onset).
    pub lowest_critical_mu_in_band_status: Option<CriticalStatus>,
    /// The branches: each mode followed across the sweep (MAC of the shapes with eigenvalue
    /// continuity), with its points and events.
    pub tracks: Vec<TrackOut>,
    /// Coalescences (`kind = "coalescence"`: two branches lock in frequency while their real
    /// parts split, the lock-in of mode coupling) and veerings (`kind = "veering"`: two
    /// branches approach and part, exchanging shapes) between the branches listed, in the
    /// validity band, by μ.
    pub events: Vec<ModeEvent>,
    /// Events between listed branches above the validity band (not listed).
    pub events_above_band: usize,
    pub stats: SweepStats,
    /// How the steady states were solved (`None` without `resolve_state`).
    pub steady_states: Option<SteadyStatesOut>,
}

/// How a critical μ was found.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CriticalStatus {
    /// The sweep solved every μ exactly (dense): the crossing of the exact roots.
    ExactSweep,
    /// A projected sweep's onset moved to the crossing of the exact root (`critical.exact`
    /// converged).
    ExactCrossing,
    /// A projected sweep's onset that the exact refinement did not confirm: the exact root
    /// does not cross within one sweep step of it (`critical.exact` not converged). The
    /// value is the projection's; the exact onset is elsewhere or absent.
    ProjectedNotConfirmed,
    /// A projected sweep's onset not refined (`refine_critical` off, or beyond
    /// `max_exact_onsets`).
    Projected,
}

/// How a sweep's steady states were solved.
#[derive(Debug, Clone, Serialize)]
pub struct SteadyStatesOut {
    /// By Newton with K factorised once for the sweep (block elimination).
    pub block_elimination: usize,
    /// By the dense Newton (K singular, or the block Newton did not converge).
    pub dense: usize,
    /// Newton iterations of the block elimination, in total.
    pub newton_iterations: usize,
    /// Wall time of the LU of K and W = K⁻ᵀGᵀ, seconds.
    pub time_setup_s: Real,
}

/// The two branches of an event.
pub fn event_tracks(e: &ModeEvent) -> [usize; 2] {
    match e {
        ModeEvent::Coalescence { tracks, .. } | ModeEvent::Veering { tracks, .. } => *tracks,
    }
}

/// The frequency of an event, Hz.
pub fn event_frequency(e: &ModeEvent) -> Real {
    match e {
        ModeEvent::Coalescence { frequency_hz, .. } | ModeEvent::Veering { frequency_hz, .. } => {
            *frequency_hz
        }
    }
}

/// Runs the sweep over `values` (`band_hz`: the CEA's validity band, for
/// `lowest_critical_mu_in_band`).
pub fn run_sweep(
    problem: &Problem,
    base: &Linearisation,
    spec: &CeaSpec,
    sw: &CeaSweepSpec,
    values: &[Real],
    band_hz: Option<Real>,
) -> Result<(Sweep, SweepReport), PipelineError> {
    let opts = sw.sweep_options(&spec.solver);
    let steady = matches!(
        base.source,
        crate::problem::tangents::StateSource::SteadyState { .. }
    );
    let t = std::time::Instant::now();
    let mut cache = (sw.resolve_state && steady).then(|| SweepSteady::new(problem));
    let time_setup_s = t.elapsed().as_secs_f64();
    let s = sweep(
        |mu| matrices_at(problem, base, spec, sw, mu, cache.as_mut()),
        values,
        &opts,
    )
    .map_err(|source| PipelineError::cea("friction sweep".into(), source))?;
    let fmax = spec.max_frequency_hz.unwrap_or(Real::INFINITY);
    let mut tracks = Vec::new();
    for t in &s.tracks {
        let points: Vec<TrackPoint> = t
            .modes
            .iter()
            .enumerate()
            .filter_map(|(k, m)| {
                m.map(|i| {
                    let md = &s.steps[k].modes[i];
                    TrackPoint {
                        mu: s.steps[k].mu,
                        frequency_hz: md.frequency_hz,
                        real_part: md.real_part,
                        damping_ratio: md.damping_ratio,
                    }
                })
            })
            .collect();
        if points.iter().all(|p| p.frequency_hz > fmax) {
            continue;
        }
        tracks.push(TrackOut {
            id: t.id,
            unstable_at_start: t.unstable_at_start,
            critical: t.critical.clone(),
            events: Vec::new(),
            points,
        });
    }
    // Events between branches that are both listed, at a frequency in the validity band
    // (above it the roots are not squeal, and a dense spectrum gives brief frequency locks).
    let listed = |id: usize| tracks.iter().any(|t| t.id == id);
    let (events, above): (Vec<ModeEvent>, Vec<ModeEvent>) = s
        .events
        .iter()
        .filter(|e| event_tracks(e).iter().all(|&id| listed(id)))
        .cloned()
        .partition(|e| band_hz.is_none_or(|b| event_frequency(e) <= b));
    let events_above_band = above.len();
    for (k, e) in events.iter().enumerate() {
        for id in event_tracks(e) {
            if let Some(t) = tracks.iter_mut().find(|t| t.id == id) {
                t.events.push(k);
            }
        }
    }
    let mut couplings: Vec<CouplingOut> = tracks
        .iter()
        .filter_map(|t| {
            t.critical.as_ref().map(|c| CouplingOut {
                track: t.id,
                mu_critical: c.mu,
                frequency_hz: c.frequency_hz,
                partner: c.partner,
                pair_frequencies_before_hz: [
                    Some(c.frequency_before_hz),
                    c.partner_frequency_before_hz,
                ],
                pair_frequencies_after_hz: [
                    Some(c.frequency_after_hz),
                    c.partner_frequency_after_hz,
                ],
            })
        })
        .collect();
    couplings.sort_by(|a, b| a.mu_critical.total_cmp(&b.mu_critical));
    // The lowest in-band onset and how it was found (exact crossing or not).
    let (lowest_mu_in_band, lowest_in_band_status) = couplings
        .iter()
        .find(|c| band_hz.is_none_or(|b| c.frequency_hz <= b))
        .map(|c| {
            let exact = tracks
                .iter()
                .find(|t| t.id == c.track)
                .and_then(|t| t.critical.as_ref())
                .and_then(|k| k.exact.as_ref());
            let status = match exact {
                Some(x) if x.converged => CriticalStatus::ExactCrossing,
                Some(_) => CriticalStatus::ProjectedNotConfirmed,
                None if s.stats.method == CeaMethod::Exact => CriticalStatus::ExactSweep,
                None => CriticalStatus::Projected,
            };
            (c.mu_critical, status)
        })
        .unzip();
    let report = SweepReport {
        vary: sw.vary,
        base_law: problem.gaps.law.clone(),
        mu: values.to_vec(),
        max_frequency_hz: spec.max_frequency_hz,
        lowest_critical_mu: couplings.first().map(|c| c.mu_critical),
        band_hz,
        lowest_critical_mu_in_band: lowest_mu_in_band,
        lowest_critical_mu_in_band_status: lowest_in_band_status,
        couplings,
        tracks,
        events,
        events_above_band,
        stats: s.stats.clone(),
        steady_states: cache.map(|c| SteadyStatesOut {
            block_elimination: c.n_fast,
            dense: c.n_dense,
            newton_iterations: c.newton_iterations,
            time_setup_s,
        }),
    };
    Ok((s, report))
}
