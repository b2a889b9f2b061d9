//! Friction sweep: the CEA at each μ of the sweep, tracked by the solver's MAC tracking.

use super::tangents::{at_steady_state, cea_matrices, tangents, Linearisation};
use crate::error::PipelineError;
use crate::scene::{CeaSpec, CeaSweepSpec, SweepVary};
use crate::stages::transient::system::Problem;
use serde::{Deserialize, Serialize};
use squeal_contact::{FrictionLaw, GapSet};
use squeal_solver::cea::{sweep, CeaMatrices, Sweep, SweepStats};

type Real = f64;

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
/// (if `resolve_state` and the base state is a steady state), the tangents evaluated there.
pub fn matrices_at(
    problem: &Problem,
    gaps: &GapSet,
    base: &Linearisation,
    spec: &CeaSpec,
    sw: &CeaSweepSpec,
    value: Real,
) -> Result<CeaMatrices, PipelineError> {
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
        super::tangents::StateSource::SteadyState { .. }
    );
    let lin = if sw.resolve_state && steady {
        at_steady_state(problem, &g, &spec.steady)?
    } else {
        let (d, c_f) = tangents(&g, problem.m.nrows(), &base.v, &base.lambda_dot)?;
        Linearisation {
            d,
            c_f,
            ..base.clone()
        }
    };
    cea_matrices(problem, &lin, spec.friction_damping)
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
    pub tracks: Vec<TrackOut>,
    pub stats: SweepStats,
}

/// Runs the sweep over `values`.
pub fn run_sweep(
    problem: &Problem,
    gaps: &GapSet,
    base: &Linearisation,
    spec: &CeaSpec,
    sw: &CeaSweepSpec,
    values: &[Real],
) -> Result<(Sweep, SweepReport), PipelineError> {
    let opts = sw.sweep_options(&spec.solver);
    let s = sweep(
        |mu| matrices_at(problem, gaps, base, spec, sw, mu),
        values,
        &opts,
    )
    .map_err(|source| PipelineError::Cea {
        what: "friction sweep".into(),
        source,
    })?;
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
            points,
        });
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
    let report = SweepReport {
        vary: sw.vary,
        base_law: gaps.law.clone(),
        mu: values.to_vec(),
        max_frequency_hz: spec.max_frequency_hz,
        lowest_critical_mu: couplings.first().map(|c| c.mu_critical),
        couplings,
        tracks,
        stats: s.stats.clone(),
    };
    Ok((s, report))
}
