//! Options of the complex eigenvalue analysis and of the friction sweep.

use super::{CeaError, RefineOptions};
use serde::{Deserialize, Serialize};

/// How the reduced quadratic problem is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum CeaMethod {
    /// `projection` when the basis is truncated (`n_basis`, `basis_cutoff_hz` or
    /// `frequency_max_hz` given) and the reduced problem has more than
    /// [`ProjectionOptions::auto_min_dofs`] DOFs in a sweep, more than
    /// [`ProjectionOptions::auto_single_min_dofs`] for a single CEA; else `exact`.
    #[default]
    Auto,
    /// Every root of the reduced problem from a dense `eigen()` of size 2(n − ng).
    Exact,
    /// Galerkin projection onto the real modes of the constrained, friction-free (symmetric)
    /// problem up to a cutoff, then a small dense `eigen()` (Abaqus-style subspace CEA); a
    /// single CEA then refines every in-band unstable root exactly (`projection.refine`).
    Projection,
}

/// How the projection basis' real modes are computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default)]
#[serde(rename_all = "snake_case")]
pub enum BasisSolver {
    /// `lanczos` when the basis has a frequency cutoff and holds at most a quarter of the
    /// n − ng modes, else `dense`.
    #[default]
    Auto,
    /// One dense symmetric eigendecomposition of size n − ng (constraint eliminated).
    Dense,
}

/// Subspace-projection options (used when the method resolves to `projection`).
///
/// The basis is the undamped real modes of `M_r q̈ + sym(K_r) q = 0` at the reference state,
/// sorted by frequency: all modes with frequency ≤ `basis_cutoff_hz`, at most `n_basis` of them.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ProjectionOptions {
    /// Highest frequency of interest, Hz (default: none). Sets the default cutoff
    /// (`cutoff_factor` × it) and the band of the sweep's exact checks.
    pub frequency_max_hz: Option<f64>,
    /// Basis cutoff frequency, Hz (default: none: `cutoff_factor × frequency_max_hz` if that is
    /// given, otherwise no frequency limit).
    pub basis_cutoff_hz: Option<f64>,
    /// Cutoff over frequency of interest when `basis_cutoff_hz` is not given (default: 2.5).
    pub cutoff_factor: f64,
    /// Largest number of basis modes (default: none: no count limit).
    pub n_basis: Option<usize>,
    /// Friction coefficient of the reference state whose real modes form a sweep's basis
    /// (default: none: the first μ of the sweep).
    pub basis_mu: Option<f64>,
    /// `auto` projects a sweep only above this many reduced DOFs n − ng (default: 200: below
    /// it a dense exact solve takes < ~0.1 s).
    pub auto_min_dofs: usize,
    /// `auto` projects a single CEA only above this many reduced DOFs n − ng (default: 1000:
    /// the exact dense solve of 2(n − ng) takes about 10 s there on 2 cores).
    pub auto_single_min_dofs: usize,
    /// Eigensolver of the basis (default: `auto`: shift-invert Lanczos on the bordered
    /// constrained problem with an inertia count, see [`super::ModalBasis::new`]).
    pub basis_solver: BasisSolver,
    /// Exact refinement of the in-band unstable projected roots of a single CEA (default:
    /// [`RefineOptions::default`]: on).
    pub refine: RefineOptions,
}

impl Default for ProjectionOptions {
    fn default() -> Self {
        ProjectionOptions {
            frequency_max_hz: None,
            basis_cutoff_hz: None,
            cutoff_factor: 2.5,
            n_basis: None,
            basis_mu: None,
            auto_min_dofs: 200,
            auto_single_min_dofs: 1000,
            basis_solver: BasisSolver::Auto,
            refine: RefineOptions::default(),
        }
    }
}

impl ProjectionOptions {
    /// The basis cutoff in Hz, if any: `basis_cutoff_hz`, else `cutoff_factor × frequency_max_hz`.
    pub fn cutoff_hz(&self) -> Option<f64> {
        self.basis_cutoff_hz
            .or(self.frequency_max_hz.map(|f| f * self.cutoff_factor))
    }

    /// True when the basis is truncated by a count or a frequency.
    pub fn is_truncated(&self) -> bool {
        self.n_basis.is_some() || self.cutoff_hz().is_some()
    }

    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        let pos = |field, v: Option<f64>| match v {
            Some(x) => check(field, x, x > 0.0, "must be > 0"),
            None => Ok(()),
        };
        pos("projection.frequency_max_hz", self.frequency_max_hz)?;
        pos("projection.basis_cutoff_hz", self.basis_cutoff_hz)?;
        if let Some(mu) = self.basis_mu {
            check("projection.basis_mu", mu, true, "must be finite")?;
        }
        check(
            "projection.cutoff_factor",
            self.cutoff_factor,
            self.cutoff_factor >= 1.0,
            "must be >= 1",
        )?;
        if self.n_basis == Some(0) {
            return Err(CeaError::InvalidOption {
                field: "projection.n_basis",
                value: "0".into(),
                reason: "must be >= 1".into(),
            });
        }
        self.refine.validate()
    }
}

/// Complex eigenvalue analysis options. [Paper eqs. (19)–(24)]
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CeaOptions {
    /// A mode is unstable when Re p > `unstable_tol` × (largest |p| of the problem)
    /// (default: 1e-8; round-off on Re p is ~1e-16 |p|, and ~1e-8 |p| at a coalescence).
    pub unstable_tol: f64,
    /// G is rank deficient when σ_min(G)/σ_max(G) ≤ `rank_tol` (default: 1e-10).
    pub rank_tol: f64,
    /// Compute the mode shapes u = T q (default: true; false returns empty shapes).
    pub compute_shapes: bool,
    /// Solution method (default: `auto`: exact for a single CEA, see [`CeaMethod::Auto`]).
    pub method: CeaMethod,
    /// Subspace-projection options (default: [`ProjectionOptions::default`]).
    pub projection: ProjectionOptions,
    /// Asked at every sweep point and regula-falsi trial, every Lanczos vector of the
    /// projection basis and every refinement shift; when set the analysis returns
    /// [`CeaError::Interrupted`] (default: never; not serialised).
    #[serde(skip)]
    pub interrupt: crate::Interrupt,
}

impl Default for CeaOptions {
    fn default() -> Self {
        CeaOptions {
            unstable_tol: 1e-8,
            rank_tol: 1e-10,
            compute_shapes: true,
            method: CeaMethod::Auto,
            projection: ProjectionOptions::default(),
            interrupt: crate::Interrupt::never(),
        }
    }
}

/// `Err(CeaError::Interrupted)` when `interrupt` is set.
pub(crate) fn check_interrupt(
    interrupt: &crate::Interrupt,
    during: &'static str,
) -> Result<(), CeaError> {
    if interrupt.is_set() {
        Err(CeaError::Interrupted { during })
    } else {
        Ok(())
    }
}

fn check(field: &'static str, v: f64, ok: bool, reason: &str) -> Result<(), CeaError> {
    if ok && v.is_finite() {
        Ok(())
    } else {
        Err(CeaError::InvalidOption {
            field,
            value: format!("{v}"),
            reason: reason.to_string(),
        })
    }
}

impl CeaOptions {
    /// `Err(CeaError::Interrupted)` when the caller asked to stop.
    pub(crate) fn check_interrupt(&self, during: &'static str) -> Result<(), CeaError> {
        check_interrupt(&self.interrupt, during)
    }

    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        check(
            "cea.unstable_tol",
            self.unstable_tol,
            self.unstable_tol >= 0.0,
            "must be >= 0",
        )?;
        check(
            "cea.rank_tol",
            self.rank_tol,
            self.rank_tol >= 0.0 && self.rank_tol < 1.0,
            "must be in [0, 1)",
        )?;
        self.projection.validate()
    }
}

/// Friction sweep options (mode tracking, critical μ, projection error control).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SweepOptions {
    /// Options of each eigenvalue solve, including the method (default:
    /// [`CeaOptions::default`]: `auto`; shapes are always computed during a sweep since
    /// tracking needs them).
    pub cea: CeaOptions,
    /// Smallest MAC for two modes at neighbouring μ to be the same tracked mode; below it a
    /// track ends and a new one starts (default: 0.1).
    pub mac_min: f64,
    /// Locate each critical μ between the two steps that bracket it by Illinois regula falsi
    /// on the tracked root's Re p (default: true; false: linear interpolation between the
    /// steps). A projected sweep on a truncated basis interpolates the onsets above its check
    /// band in any case (the projection does not resolve them). (The name is historical: it was a bisection
    /// until 2026-11.)
    pub bisection: bool,
    /// Locating a crossing stops when its bracket is shorter than `bisection_tol`·max(1, |μ|)
    /// (default: 1e-7); so does the exact crossing of `refine_critical`.
    pub bisection_tol: f64,
    /// Largest number of solves locating one critical μ (default: 60).
    pub max_bisection: usize,
    /// With projection (and `cea.projection.refine.enabled`), move each in-band critical μ to
    /// the crossing of the exact root: bracket search and regula falsi on the Re p of the
    /// tracked root refined by shift-invert Arnoldi (default: true).
    pub refine_critical: bool,
    /// Largest number of exact evaluations per critical μ with `refine_critical` (default: 12).
    pub max_exact_critical: usize,
    /// Largest number of onsets moved to the exact crossing with `refine_critical`, the
    /// lowest in-band onsets first (default: 32, every in-band onset of the brakes here). Each
    /// costs up to `max_exact_critical` exact evaluations: the first a steady state, a
    /// projected solve and a complex LU (about 2 s on the cad brake's 2 043-DOF model), the
    /// next ones usually the root followed with that LU (a steady state and a few LU solves);
    /// the onsets beyond it keep their projected crossing and are counted in
    /// [`super::SweepStats::n_critical_exact_skipped`].
    pub max_exact_onsets: usize,
    /// The exact crossing stops when its bracket is shorter than
    /// `exact_critical_tol`·max(1, |μ|) (default: 1e-5; each evaluation costs a complex LU of
    /// size n + ng).
    pub exact_critical_tol: f64,
    /// Keep the mode shapes of every step in the result (default: false: memory n × modes × steps).
    pub keep_shapes: bool,
    /// With projection, also solve exactly (eigenvalues only) at the first and last μ and
    /// report the largest relative eigenvalue difference in the checked band (default: true).
    pub exact_check: bool,
    /// With projection, also check every k-th step (k ≥ 1; default: 0: the ends only).
    pub exact_check_every: usize,
    /// With projection (and `cea.projection.refine.enabled`), enrich the basis before the
    /// sweep (default: true): at the sweep's μ in the order last, midpoints (breadth first),
    /// first, the `enrich_roots` in-band projected roots with the largest Re p are refined
    /// exactly; when their largest relative error exceeds `enrich_tol` their exact
    /// eigenvectors (real and imaginary parts) join the basis, at most `max_enrich_points`
    /// times; the test that passes (or the one after the last enrichment) is at a μ the basis
    /// was not enriched at, so its error is the basis' measured error
    /// ([`super::SweepStats::basis_error`]). The friction-free modes alone were 5 % off at
    /// μ = 0.9 on the cad brake's 2 043-DOF model.
    pub enrich: bool,
    /// Relative root error |p_exact − p_projected| / |p_exact| the enrichment aims at
    /// (default: 1e-4: about 3 /s in Re p at 5 kHz).
    pub enrich_tol: f64,
    /// Most μ at which the basis is enriched (default: 3).
    pub max_enrich_points: usize,
    /// In-band roots refined per enrichment test, the largest Re p first (default: 8).
    pub enrich_roots: usize,
    /// Weight of eigenvalue continuity in the tracking: a candidate's score is its MAC less
    /// this weight × its distance from the track's linearly predicted eigenvalue relative to
    /// |p| (default: 1; 0: MAC alone).
    pub continuity_weight: f64,
    /// Two tracked branches whose frequencies differ by at most this fraction are locked: the
    /// start of a lock is reported as a coalescence (default: 5e-3).
    pub lock_tol: f64,
    /// A local minimum of two branches' relative frequency gap below this fraction (and
    /// above `lock_tol`) across which their shapes are exchanged is reported as a veering
    /// (default: 0.05).
    pub veer_tol: f64,
    /// Smallest MAC between one branch's shape before a veering and the other's after it
    /// (default: 0.5).
    pub exchange_mac: f64,
}

impl Default for SweepOptions {
    fn default() -> Self {
        SweepOptions {
            cea: CeaOptions::default(),
            mac_min: 0.1,
            bisection: true,
            bisection_tol: 1e-7,
            max_bisection: 60,
            refine_critical: true,
            max_exact_critical: 12,
            max_exact_onsets: 32,
            exact_critical_tol: 1e-5,
            keep_shapes: false,
            exact_check: true,
            exact_check_every: 0,
            enrich: true,
            enrich_tol: 1e-4,
            max_enrich_points: 3,
            enrich_roots: 8,
            continuity_weight: 1.0,
            lock_tol: 5e-3,
            veer_tol: 0.05,
            exchange_mac: 0.5,
        }
    }
}

impl SweepOptions {
    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        self.cea.validate()?;
        check(
            "sweep.mac_min",
            self.mac_min,
            (0.0..=1.0).contains(&self.mac_min),
            "must be in [0, 1]",
        )?;
        check(
            "sweep.bisection_tol",
            self.bisection_tol,
            self.bisection_tol > 0.0,
            "must be > 0",
        )?;
        check(
            "sweep.exact_critical_tol",
            self.exact_critical_tol,
            self.exact_critical_tol > 0.0,
            "must be > 0",
        )?;
        check(
            "sweep.enrich_tol",
            self.enrich_tol,
            self.enrich_tol > 0.0 && self.enrich_tol.is_finite(),
            "must be finite and > 0",
        )?;
        if self.enrich && self.enrich_roots == 0 {
            return Err(CeaError::InvalidOption {
                field: "sweep.enrich_roots",
                value: "0".into(),
                reason: "must be >= 1 when enrich is on".into(),
            });
        }
        check(
            "sweep.continuity_weight",
            self.continuity_weight,
            self.continuity_weight >= 0.0 && self.continuity_weight.is_finite(),
            "must be finite and >= 0",
        )?;
        check(
            "sweep.lock_tol",
            self.lock_tol,
            self.lock_tol >= 0.0 && self.lock_tol < 1.0,
            "must be in [0, 1)",
        )?;
        check(
            "sweep.veer_tol",
            self.veer_tol,
            self.veer_tol >= self.lock_tol && self.veer_tol < 1.0,
            "must be in [lock_tol, 1)",
        )?;
        check(
            "sweep.exchange_mac",
            self.exchange_mac,
            (0.0..=1.0).contains(&self.exchange_mac),
            "must be in [0, 1]",
        )
    }
}
