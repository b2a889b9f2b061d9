//! The `[cea]` table: complex eigenvalue analysis about a steady sliding state, and the
//! friction sweep. Its presence (or `squeal cea --mu a:b:n`) asks for `squeal cea`.
//!
//! ```toml
//! [cea]
//! at = "steady_state"            # or { restart = "run/restart.json" }
//! friction_damping = true        # C_f = ∂F_f/∂v in the eigenproblem (paper eq. 23)
//! max_frequency_hz = 10000.0     # modes above are not reported
//! sweep = { mu = [0.1, 0.9, 41] }   # or sweep = { mu_values = [0.2, 0.3, 0.5] }
//! solver = { method = "exact" }  # squeal_solver::cea::CeaOptions
//! ```

use crate::error::PipelineError;
use serde::{Deserialize, Serialize};
use squeal_solver::bsql::SteadyOptions;
use squeal_solver::cea::{CeaOptions, SweepOptions};
use std::path::PathBuf;

/// The most points a CEA friction sweep (`cea.sweep.mu`) may have.
pub const MAX_SWEEP_POINTS: usize = 100_000;

use squeal_solver::Real;

/// The state the problem is linearised about.
#[derive(Debug, Clone, PartialEq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum CeaState {
    /// The static sliding equilibrium under the preload P0 and the full brake load
    /// PMAX·P_brake (the end of the ramp), solved by Newton (`bsql::steady_state`).
    #[default]
    SteadyState,
    /// The state (u, v, λ̇) saved in a transient run's restart file (path relative to the
    /// scene), at that file's time.
    Restart(PathBuf),
}

/// How a sweep's μ values act on the scene's friction law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum SweepVary {
    /// Each value replaces the law by a constant μ (no speed or pressure dependence).
    #[default]
    Constant,
    /// Each value scales the scene's law (every μ value, slope and table entry × value).
    Scale,
}

/// Friction sweep: CEA at a list of μ with mode tracking and critical μ.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CeaSweepSpec {
    /// `[first, last, count]`: `count` evenly spaced values (default: none; give this or
    /// `mu_values`).
    pub mu: Option<(Real, Real, usize)>,
    /// Explicit strictly increasing values (default: empty).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub mu_values: Vec<Real>,
    /// What a value means: `constant` μ or `scale` of the scene's law (default: constant).
    pub vary: SweepVary,
    /// Smallest MAC for the same tracked mode at neighbouring μ (default: 0.1).
    pub mac_min: Real,
    /// Refine each critical μ by bisection (default: true).
    pub bisection: bool,
    /// Relative length of the bisection bracket at which it stops (default: 1e-7).
    pub bisection_tol: Real,
    /// With the projection method, exact checks at the ends of the sweep (default: true).
    pub exact_check: bool,
    /// Recompute the steady sliding state at every μ (default: true; false keeps the state of
    /// the scene's law and only changes the tangents).
    pub resolve_state: bool,
    /// With the projection method, move each in-band critical μ to the crossing of the exact
    /// root (shift-invert refinement of the tracked root; default: true).
    pub refine_critical: bool,
    /// With `refine_critical`: how many in-band onsets, lowest first, are moved to the exact
    /// crossing (default: 32; the others keep the projected crossing).
    pub max_exact_onsets: usize,
    /// With the projection method, enrich the basis with exact eigenvectors at the sweep's
    /// μ until its least stable in-band roots are within `enrich_tol` at a μ it was not
    /// enriched at (default: true; `stats.enrichment` and `stats.basis_error` in
    /// cea.sweep.json).
    pub enrich: bool,
    /// Relative root error the enrichment aims at (default: 1e-4).
    pub enrich_tol: Real,
}

impl Default for CeaSweepSpec {
    fn default() -> Self {
        let s = SweepOptions::default();
        Self {
            mu: None,
            mu_values: Vec::new(),
            vary: SweepVary::Constant,
            mac_min: s.mac_min,
            bisection: s.bisection,
            bisection_tol: s.bisection_tol,
            exact_check: s.exact_check,
            resolve_state: true,
            refine_critical: s.refine_critical,
            max_exact_onsets: s.max_exact_onsets,
            enrich: s.enrich,
            enrich_tol: s.enrich_tol,
        }
    }
}

/// Parses `a:b:n` (the `--mu` argument) into `(a, b, n)`.
pub fn parse_mu_range(text: &str) -> Result<(Real, Real, usize), PipelineError> {
    let bad = |why: &str| PipelineError::Scene {
        field: "--mu".into(),
        message: format!("`{text}`: {why}; write FIRST:LAST:COUNT, e.g. 0.1:0.9:41"),
    };
    let parts: Vec<&str> = text.split(':').map(str::trim).collect();
    if parts.len() != 3 {
        return Err(bad("expected three fields"));
    }
    let a: Real = parts[0].parse().map_err(|_| bad("FIRST is not a number"))?;
    let b: Real = parts[1].parse().map_err(|_| bad("LAST is not a number"))?;
    let n: usize = parts[2]
        .parse()
        .map_err(|_| bad("COUNT is not a whole number"))?;
    Ok((a, b, n))
}

impl CeaSweepSpec {
    /// The μ values of the sweep.
    pub fn values(&self) -> Result<Vec<Real>, PipelineError> {
        let err = |field: &str, message: String| PipelineError::Scene {
            field: format!("cea.sweep.{field}"),
            message,
        };
        let v = match (&self.mu, self.mu_values.is_empty()) {
            (Some(_), false) => {
                return Err(err(
                    "mu",
                    "give either `mu = [first, last, count]` or `mu_values`, not both".into(),
                ))
            }
            (None, true) => {
                return Err(err(
                    "mu",
                    "no values: give `mu = [first, last, count]` or `mu_values = [...]`".into(),
                ))
            }
            (Some((a, b, n)), true) => {
                if *n < 1 || !(a.is_finite() && b.is_finite()) || (*n > 1 && b <= a) {
                    return Err(err(
                        "mu",
                        format!("[{a}, {b}, {n}]: need finite first < last and count >= 1"),
                    ));
                }
                // One CEA per point: a count beyond this is a typo, and allocating it aborted
                // the process (found by fuzzing: the count 1e18 from a scene).
                if *n > MAX_SWEEP_POINTS {
                    return Err(err(
                        "mu",
                        format!("[{a}, {b}, {n}]: count above {MAX_SWEEP_POINTS} points"),
                    ));
                }
                if *n == 1 {
                    vec![*a]
                } else {
                    (0..*n)
                        .map(|i| a + (b - a) * i as Real / (*n - 1) as Real)
                        .collect()
                }
            }
            (None, false) => self.mu_values.clone(),
        };
        for (i, w) in v.windows(2).enumerate() {
            if w[1].partial_cmp(&w[0]) != Some(std::cmp::Ordering::Greater) {
                return Err(err(
                    "mu_values",
                    format!(
                        "values must be strictly increasing: [{i}] = {}, [{}] = {}",
                        w[0],
                        i + 1,
                        w[1]
                    ),
                ));
            }
        }
        if let Some(x) = v.iter().find(|x| !x.is_finite()) {
            return Err(err("mu_values", format!("{x} is not finite")));
        }
        let field = if self.mu.is_some() { "mu" } else { "mu_values" };
        let max = squeal_contact::friction::MU_MAX;
        if let Some(x) = v.iter().find(|x| !(0.0..=max).contains(*x)) {
            return Err(err(
                field,
                format!(
                    "{x} is not in [0, {max}] (the largest friction coefficients measured \
                     between solids are below {max}: squeal_contact::friction::MU_MAX)"
                ),
            ));
        }
        Ok(v)
    }

    /// The solver's sweep options with these tracking settings and `cea` solve options.
    pub fn sweep_options(&self, cea: &CeaOptions) -> SweepOptions {
        SweepOptions {
            cea: cea.clone(),
            mac_min: self.mac_min,
            bisection: self.bisection,
            bisection_tol: self.bisection_tol,
            exact_check: self.exact_check,
            refine_critical: self.refine_critical,
            max_exact_onsets: self.max_exact_onsets,
            enrich: self.enrich,
            enrich_tol: self.enrich_tol,
            ..SweepOptions::default()
        }
    }
}

/// Complex eigenvalue analysis options of a scene. [Paper eqs. (19)–(24)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CeaSpec {
    /// State of the linearisation (default: `"steady_state"`, at full brake load).
    pub at: CeaState,
    /// Include the friction damping C_f = ∂F_f/∂v (default: true). The paper's CEA has it
    /// (eq. 23, "B + C_f"), and the transient's residual always carries the velocity
    /// dependence of friction (only its Newton matrix may leave it out), so growth rates
    /// agree with the transient only with C_f; false gives the classical "stiffness-only"
    /// mode-coupling analysis.
    pub friction_damping: bool,
    /// Modes above this frequency are not reported, plotted or swept (default: none = all).
    pub max_frequency_hz: Option<Real>,
    /// Friction sweep (default: none; `squeal cea --mu a:b:n` also asks for one).
    pub sweep: Option<CeaSweepSpec>,
    /// Eigen-solution options: `method` (`auto`/`exact`/`projection`), `projection`,
    /// `unstable_tol`, `rank_tol` (default: the solver's [`CeaOptions::default`]).
    pub solver: CeaOptions,
    /// Steady-state Newton options (default: tol 1e-10, 50 iterations).
    pub steady: SteadyOptions,
    /// Most unstable modes written as VTU shapes (default: 20).
    pub max_shapes: usize,
    /// Frames of the phase animation `cea_modes.pvd` over θ ∈ [0, 2π) (default: 24; 0: none).
    pub phase_frames: usize,
    /// Sensitivities of the roots to the design parameters (`cea.json`'s `sensitivity`,
    /// `sensitivity.csv`; docs/insight.md) (default: true).
    pub sensitivity: bool,
}

impl Default for CeaSpec {
    fn default() -> Self {
        Self {
            at: CeaState::SteadyState,
            friction_damping: true,
            max_frequency_hz: None,
            sweep: None,
            solver: CeaOptions::default(),
            steady: SteadyOptions::default(),
            max_shapes: 20,
            phase_frames: 24,
            sensitivity: true,
        }
    }
}

impl CeaSpec {
    /// Checks the table; errors name the field.
    pub fn validate(&self) -> Result<(), PipelineError> {
        if let Some(f) = self.max_frequency_hz {
            if !(f > 0.0 && f.is_finite()) {
                return Err(PipelineError::Scene {
                    field: "cea.max_frequency_hz".into(),
                    message: format!("{f} must be > 0"),
                });
            }
        }
        self.solver.validate().map_err(|e| PipelineError::Scene {
            field: "cea.solver".into(),
            message: e.to_string(),
        })?;
        self.steady.validate().map_err(|e| PipelineError::Scene {
            field: "cea.steady".into(),
            message: e.to_string(),
        })?;
        if let Some(s) = &self.sweep {
            s.values()?;
            s.sweep_options(&self.solver)
                .validate()
                .map_err(|e| PipelineError::Scene {
                    field: "cea.sweep".into(),
                    message: e.to_string(),
                })?;
        }
        Ok(())
    }
}
