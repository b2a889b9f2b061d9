//! The state of the linearisation and the friction tangents there:
//! D = ∂F_f/∂λ̇ and C_f = ∂F_f/∂v. [Paper eq. (18)]

use crate::error::PipelineError;
use crate::problem::restart::RestartFile;
use crate::problem::system::{GapFriction, Problem};
use crate::scene::{CeaSpec, CeaState, Scene};
use faer::Mat;
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_solver::bsql::{compliant_cea, steady_state_of, Statics, SteadyOptions};
use squeal_solver::cea::CeaMatrices;

use squeal_solver::Real;

/// A state (u, v, λ̇) of the brake and the friction tangents there.
#[derive(Debug, Clone)]
pub struct Linearisation {
    /// Where the state comes from.
    pub source: StateSource,
    /// Displacements u (length n).
    pub u: Vec<Real>,
    /// Velocities v (length n; zero at a steady state).
    pub v: Vec<Real>,
    /// Contact multipliers λ̇ (length ng; tensile normal force, F_z = −λ̇).
    pub lambda_dot: Vec<Real>,
    /// D = ∂F_f/∂λ̇ (n × ng).
    pub d: Mat<Real>,
    /// C_f = ∂F_f/∂v (n × n).
    pub c_f: Mat<Real>,
}

/// Where a linearisation state comes from (written to `cea.json`).
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StateSource {
    /// Static sliding equilibrium at load time `t` (load factor = ramp(t), 1 at full load).
    SteadyState {
        t: Real,
        load_factor: Real,
        newton_iterations: usize,
        residual_norm: Real,
    },
    /// A transient's restart file at its time `t`.
    Restart { path: String, t: Real },
}

fn contact_err(what: &str) -> impl FnOnce(squeal_contact::ContactError) -> PipelineError + '_ {
    move |source| PipelineError::Contact {
        what: what.to_string(),
        source,
    }
}

/// `(D, C_f)` of the gap set at (v, λ̇).
///
/// # Reference
/// The partitions ∂F_f/∂λ and C_f = ∂F_f/∂v of [Paper eq. (18)] (here derivatives of +F_f;
/// see `squeal_contact::GapSet::add_tangents` and `squeal_solver::cea` for the signs).
pub fn tangents(
    gaps: &GapSet,
    n: usize,
    v: &[Real],
    lambda_dot: &[Real],
) -> Result<(Mat<Real>, Mat<Real>), PipelineError> {
    let mut d = Mat::zeros(n, gaps.len());
    let mut c_f = Mat::zeros(n, n);
    gaps.add_tangents(v, lambda_dot, &mut d, Some(&mut c_f))
        .map_err(contact_err("friction tangents"))?; // [Paper eq. (18)]
    Ok((d, c_f))
}

/// Load time at which the brake load is complete (end of the ramp).
pub fn full_load_time(problem: &Problem) -> Real {
    if problem.load.step {
        0.0
    } else {
        problem.load.t_load.max(0.0)
    }
}

/// Steady sliding state under the preload and the full brake load, and its tangents.
pub fn at_steady_state(
    problem: &Problem,
    gaps: &GapSet,
    opts: &SteadyOptions,
) -> Result<Linearisation, PipelineError> {
    let n = problem.m.nrows();
    let mut friction = GapFriction { set: gaps.clone() };
    let statics = Statics {
        k: &problem.k,
        g: &problem.g,
        load: &problem.load,
        friction: &mut friction,
        compliance: &problem.compliance,
    };
    let t = full_load_time(problem);
    let ss = steady_state_of(statics, t, opts).map_err(|source| PipelineError::Solver {
        what: format!("steady sliding state at full brake load (t = {t})"),
        source,
    })?;
    let v = vec![0.0; n];
    let (d, c_f) = tangents(gaps, n, &v, &ss.lambda_dot)?;
    Ok(Linearisation {
        source: StateSource::SteadyState {
            t,
            load_factor: problem.load.ramp(t),
            newton_iterations: ss.iterations,
            residual_norm: ss.residual_norm,
        },
        u: ss.u,
        v,
        lambda_dot: ss.lambda_dot,
        d,
        c_f,
    })
}

/// The state of a restart file (y = {v, λ, u} at t_n, λ̇ from y'), and its tangents.
pub fn at_restart(
    scene: &Scene,
    path: &std::path::Path,
    problem: &Problem,
) -> Result<Linearisation, PipelineError> {
    let gaps = &problem.gaps;
    let (n, ng) = (problem.m.nrows(), gaps.len());
    let path = scene.resolve(path);
    let r = RestartFile::read(&path, &problem.model_hash(), n, ng)?;
    let y = r.state.phi.first().ok_or_else(|| PipelineError::Input {
        path: path.clone(),
        message: "the BDF state has no difference arrays".into(),
    })?;
    let yp = &r.state.yp;
    if y.len() != 2 * n + ng || yp.len() != 2 * n + ng {
        return Err(PipelineError::Input {
            path: path.clone(),
            message: format!(
                "state vectors have lengths {} and {}, expected 2n + ng = {}",
                y.len(),
                yp.len(),
                2 * n + ng
            ),
        });
    }
    let v = y[..n].to_vec();
    let u = y[n + ng..].to_vec();
    let lambda_dot = yp[n..n + ng].to_vec();
    let (d, c_f) = tangents(gaps, n, &v, &lambda_dot)?;
    Ok(Linearisation {
        source: StateSource::Restart {
            path: path.display().to_string(),
            t: r.state.t,
        },
        u,
        v,
        lambda_dot,
        d,
        c_f,
    })
}

/// The state the scene's `[cea] at` names.
pub fn linearise(
    scene: &Scene,
    spec: &CeaSpec,
    problem: &Problem,
) -> Result<Linearisation, PipelineError> {
    match &spec.at {
        CeaState::SteadyState => at_steady_state(problem, &problem.gaps, &spec.steady),
        CeaState::Restart(p) => at_restart(scene, p, problem),
    }
}

/// The solver's matrices `M ü + (B − C_f) u̇ + K u + (Gᵀ − D) N = 0, G u = 0`
/// (C_f left out when `friction_damping` is false).
///
/// # Reference
/// [Paper eqs. (19)–(24)] with `Hᵀ = Gᵀ − D`, `B + C_f` of the paper = `B − C_f` here (the
/// paper's derivatives are those of the residual, which carries −F_f). With normal contact
/// compliance the compliant rows are folded into the stiffness,
/// `K_c = K + Σ_k (Gᵀ − D)_{:,k} G_{k,:}/c_k`, and G, D keep the rigid rows
/// (`squeal_solver::bsql::compliant_cea`).
pub fn cea_matrices(
    problem: &Problem,
    lin: &Linearisation,
    friction_damping: bool,
) -> Result<CeaMatrices, PipelineError> {
    cea_matrices_of(problem, lin.d.clone(), lin.c_f.clone(), friction_damping)
}

/// [`cea_matrices`] taking the tangents `d` and `c_f` of the linearisation by value (a
/// friction sweep builds them afresh at every μ: no copy of n × n and n × ng matrices).
pub fn cea_matrices_of(
    problem: &Problem,
    d: Mat<Real>,
    c_f: Mat<Real>,
    friction_damping: bool,
) -> Result<CeaMatrices, PipelineError> {
    let has_g = problem.g.nrows() > 0;
    let rigid = CeaMatrices {
        m: problem.m.clone(),
        k: problem.k.clone(),
        b: Some(problem.b.clone()),
        g: has_g.then(|| problem.g.clone()),
        d: has_g.then_some(d),                // [Paper eq. (22)]
        c_f: friction_damping.then_some(c_f), // [Paper eq. (23)]
    };
    if problem.compliance.is_empty() {
        return Ok(rigid);
    }
    // Normal compliance: the compliant rows fold into K (squeal_solver::bsql::compliance).
    compliant_cea(&rigid, &problem.compliance).map_err(|source| PipelineError::Solver {
        what: "CEA with normal contact compliance".into(),
        source,
    })
}

/// Contact state of the linearisation (for `cea.json`).
#[derive(Debug, Clone, Serialize)]
pub struct ContactSummary {
    pub n_gaps: usize,
    /// Pressure p_n = −λ̇/A + P0 over the gaps. [Paper eq. (1)]
    pub max_pressure: Real,
    pub min_pressure: Real,
    /// Total compressive normal force Σ −λ̇.
    pub total_normal_force: Real,
    /// Slip speed |V_t| over the gaps. [Paper eq. (3)]
    pub max_slip_speed: Real,
    pub min_slip_speed: Real,
    /// μ over the gaps. [Paper eq. (4)]
    pub mu_min: Real,
    pub mu_max: Real,
    /// Gaps with p_n < 0 (tension: the bilateral constraint holds them closed).
    pub n_tensile: usize,
    /// The same per `[[contact]]` pair, in the scene's order (empty when the model's gaps
    /// are not grouped by pair, e.g. a gap table).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub per_pair: Vec<PairContact>,
}

/// The contact state of one `[[contact]]` pair's gaps.
#[derive(Debug, Clone, Serialize)]
pub struct PairContact {
    pub n_gaps: usize,
    pub n_tensile: usize,
    pub min_pressure: Real,
    pub max_pressure: Real,
    /// Σ −λ̇ over the pair's gaps.
    pub normal_force: Real,
}

impl ContactSummary {
    /// "contact[i]: n of m tensile, smallest p_n x" for each pair with tensile gaps.
    pub fn tensile_pairs(&self) -> Vec<String> {
        self.per_pair
            .iter()
            .enumerate()
            .filter(|(_, p)| p.n_tensile > 0)
            .map(|(i, p)| {
                format!(
                    "contact[{i}]: {} of {} (smallest p_n {:.4e} Pa)",
                    p.n_tensile, p.n_gaps, p.min_pressure
                )
            })
            .collect()
    }
}

/// Pressure, slip and μ ranges at the state, over all gaps and per pair (`gap_pairs`: the
/// gap count of each `[[contact]]` pair in order, the model's `gap_pairs`; per pair only when
/// they add up to the gaps).
pub fn contact_summary(
    gaps: &GapSet,
    gap_pairs: &[usize],
    lin: &Linearisation,
) -> Result<ContactSummary, PipelineError> {
    let mut s = ContactSummary {
        n_gaps: gaps.len(),
        max_pressure: Real::NEG_INFINITY,
        min_pressure: Real::INFINITY,
        total_normal_force: 0.0,
        max_slip_speed: Real::NEG_INFINITY,
        min_slip_speed: Real::INFINITY,
        mu_min: Real::INFINITY,
        mu_max: Real::NEG_INFINITY,
        n_tensile: 0,
        per_pair: Vec::new(),
    };
    let pair_of = crate::model::gap_pair_index(gap_pairs, gaps.len());
    if pair_of.is_some() {
        s.per_pair = gap_pairs
            .iter()
            .map(|&n_gaps| PairContact {
                n_gaps,
                n_tensile: 0,
                min_pressure: if n_gaps > 0 { Real::INFINITY } else { 0.0 },
                max_pressure: if n_gaps > 0 { Real::NEG_INFINITY } else { 0.0 },
                normal_force: 0.0,
            })
            .collect();
    }
    for g in 0..gaps.len() {
        let o = gaps
            .gap_output(g, &lin.v, &lin.lambda_dot)
            .map_err(contact_err("gap state"))?;
        s.max_pressure = s.max_pressure.max(o.pressure);
        s.min_pressure = s.min_pressure.min(o.pressure);
        s.total_normal_force -= lin.lambda_dot[g];
        s.max_slip_speed = s.max_slip_speed.max(o.slip_speed);
        s.min_slip_speed = s.min_slip_speed.min(o.slip_speed);
        s.mu_min = s.mu_min.min(o.friction.mu);
        s.mu_max = s.mu_max.max(o.friction.mu);
        if o.pressure < 0.0 {
            s.n_tensile += 1;
        }
        if let Some(pair_of) = &pair_of {
            let p = &mut s.per_pair[pair_of[g]];
            p.min_pressure = p.min_pressure.min(o.pressure);
            p.max_pressure = p.max_pressure.max(o.pressure);
            p.normal_force -= lin.lambda_dot[g];
            if o.pressure < 0.0 {
                p.n_tensile += 1;
            }
        }
    }
    if gaps.is_empty() {
        for x in [
            &mut s.max_pressure,
            &mut s.min_pressure,
            &mut s.max_slip_speed,
            &mut s.min_slip_speed,
            &mut s.mu_min,
            &mut s.mu_max,
        ] {
            *x = 0.0;
        }
    }
    Ok(s)
}
