//! Friction sweep: CEA at a list of μ, mode tracking, critical μ.

use super::critical::{Bracket, CriticalExact, Point};
use super::eigen::exact;
use super::events::{coalescences, veering, EventTolerances, ModeEvent, PairStep};
use super::operator::check_inputs;
use super::refine::{RefineRun, RefineStats};
use super::shift_invert::SlaveSplit;
use super::track::{assign, mac_matrix};
use super::{
    compare_eigenvalues, CeaError, CeaMatrices, CeaMethod, CeaOptions, CeaResult, CeaStats,
    CheckKind, Cplx, EigenvalueComparison, EnrichPoint, ExactCheck, ModalBasis, Mode, SweepOptions,
};
use serde::Serialize;
use std::f64::consts::PI;
use std::fmt::Display;
use std::sync::Arc;
use std::time::Instant;

/// The modes at one μ of the sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SweepStep {
    /// Friction coefficient.
    pub mu: f64,
    /// Modes sorted by frequency (shapes empty unless `keep_shapes`).
    pub modes: Vec<Mode>,
    /// Statistics of the solve.
    pub stats: CeaStats,
}

/// Onset of instability of one tracked mode.
///
/// The onset is where the mode's Re p crosses the instability threshold `unstable_tol` × the
/// largest |p| of the solve (the `unstable` flag of [`Mode`]; 1.6e-3 /s on the hex20 brake).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Critical {
    /// Critical μ: `exact.mu` when the exact root's crossing was found (`exact.converged`),
    /// else `mu_located`.
    pub mu: f64,
    /// The crossing of the sweep's own roots (projected or exact dense) located between the
    /// bracketing steps by Illinois regula falsi when `bisection`, else (and above the check
    /// band of a projected sweep) `mu_interpolated`.
    pub mu_located: f64,
    /// μ where Re p crosses the threshold, linearly interpolated between the bracketing steps.
    pub mu_interpolated: f64,
    /// Index of the last step at which the mode was stable (the next one is unstable).
    pub step: usize,
    /// Frequency of the mode at the onset (exact, or located, or interpolated), Hz.
    pub frequency_hz: f64,
    /// Track id of the mode it merges with: the other mode whose frequency is nearest at the
    /// first unstable step (mode-coupling partner); `None` if it is alone.
    pub partner: Option<usize>,
    /// Frequency of this mode at the last stable step, Hz.
    pub frequency_before_hz: f64,
    /// Frequency of the partner at the last stable step, Hz (a coalescing pair: close).
    pub partner_frequency_before_hz: Option<f64>,
    /// Frequency of this mode at the first unstable step, Hz.
    pub frequency_after_hz: f64,
    /// Frequency of the partner at the first unstable step, Hz.
    pub partner_frequency_after_hz: Option<f64>,
    /// Number of eigenvalue solves spent locating the crossing (`mu_located`).
    pub locate_solves: usize,
    /// The crossing of the exact root (projected sweeps, in-band onsets, `refine_critical`).
    pub exact: Option<CriticalExact>,
}

/// A mode followed across the sweep by eigenvector correlation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Track {
    /// Track id (index in [`Sweep::tracks`]).
    pub id: usize,
    /// Index of the mode in `steps[s].modes` at each step s (`None` before the track starts
    /// or after it ends).
    pub modes: Vec<Option<usize>>,
    /// The mode was already unstable at its first step (no onset inside the sweep).
    pub unstable_at_start: bool,
    /// First onset of instability inside the sweep, if any.
    pub critical: Option<Critical>,
}

/// Statistics of a sweep.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct SweepStats {
    /// Number of μ steps.
    pub n_steps: usize,
    /// Number of eigenvalue solves of the sweep's method (steps + locating the crossings).
    pub n_solves: usize,
    /// Of those, the solves spent locating the crossings (Illinois regula falsi).
    pub n_locate_solves: usize,
    /// Number of tracks.
    pub n_tracks: usize,
    /// Number of tracks with an onset of instability.
    pub n_critical: usize,
    /// Wall time, seconds.
    pub time_s: f64,
    /// Wall time spent in the eigenvalue solves (building the matrices, projecting and
    /// solving; not the exact checks), seconds.
    pub time_eigen_s: f64,
    /// Of all the wall time, the part spent building the matrices (`build(μ)`: steady state
    /// and tangents), seconds.
    pub time_build_s: f64,
    /// Method that ran (`exact` or `projection`).
    pub method: CeaMethod,
    /// Number of basis modes with `projection` (0 with `exact`).
    pub n_basis: usize,
    /// Size of the reduced problem n − ng (the full basis size).
    pub n_reduced: usize,
    /// Highest undamped frequency in the basis, Hz (`projection` only).
    pub basis_max_frequency_hz: Option<f64>,
    /// Friction coefficient of the basis' reference state (`projection` only).
    pub basis_mu: Option<f64>,
    /// Wall time of the basis computation, seconds.
    pub time_basis_s: f64,
    /// The basis enrichment's tests, in order ([`SweepOptions::enrich`]; empty without it).
    pub enrichment: Vec<EnrichPoint>,
    /// Basis columns added by the enrichment (part of `n_basis`).
    pub n_basis_enriched: usize,
    /// The basis' measured error: the largest relative root error of the last enrichment
    /// test, at a μ the basis was not enriched at (`None` without enrichment).
    pub basis_error: Option<f64>,
    /// That error is within `enrich_tol` (`None` without enrichment).
    pub basis_converged: Option<bool>,
    /// Wall time of the enrichment, seconds.
    pub time_enrich_s: f64,
    /// Band of the exact checks, Hz: `projection.frequency_max_hz`, else the highest basis
    /// frequency / `cutoff_factor` (`projection` only).
    pub check_band_hz: Option<f64>,
    /// The exact checks of a projected sweep (first and last μ, and every
    /// `exact_check_every`-th step): dense, or by refinement above
    /// `projection.auto_single_min_dofs` reduced DOFs ([`CheckKind`]).
    pub exact_checks: Vec<ExactCheck>,
    /// Largest relative eigenvalue difference projected vs exact over the checks and the
    /// modes in `check_band_hz` (`None` without checks).
    pub max_rel_eigenvalue_error: Option<f64>,
    /// Wall time of the exact checks, seconds.
    pub time_check_s: f64,
    /// Onsets whose critical μ was moved to the crossing of the exact root (`Critical::exact`
    /// converged): in-band onsets of a projected sweep with `refine_critical`.
    pub n_critical_exact: usize,
    /// In-band onsets whose exact crossing was not found (kept at the projected crossing).
    pub n_critical_exact_failed: usize,
    /// In-band onsets not refined because `max_exact_onsets` lower ones were (kept at the
    /// projected crossing).
    pub n_critical_exact_skipped: usize,
    /// Exact evaluations spent on the critical μ (each a shift-invert refinement of the
    /// tracked root: at least one complex LU of size n + ng).
    pub n_critical_exact_solves: usize,
    /// Of those, evaluations that followed the exact root from the previous trial with its
    /// LU (residual inverse iteration; no factorisation, no projected solve).
    pub n_critical_exact_followed: usize,
    /// Largest |μ_exact − μ_projected| over the onsets refined exactly.
    pub max_critical_mu_change: Option<f64>,
    /// Largest |p_exact − p_projected| / |p_exact| of the tracked roots at those evaluations.
    pub max_rel_critical_root_error: Option<f64>,
    /// Wall time of the exact critical μ, seconds.
    pub time_critical_exact_s: f64,
}

/// Result of [`sweep`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sweep {
    /// One entry per μ.
    pub steps: Vec<SweepStep>,
    /// Tracked modes.
    pub tracks: Vec<Track>,
    /// Coalescences (lock-in) and veerings between tracked branches, by μ.
    pub events: Vec<ModeEvent>,
    /// Statistics.
    pub stats: SweepStats,
}

impl Sweep {
    /// The smallest critical μ over all tracks, with its track id.
    pub fn lowest_critical(&self) -> Option<(usize, &Critical)> {
        self.tracks
            .iter()
            .filter_map(|t| t.critical.as_ref().map(|c| (t.id, c)))
            .min_by(|a, b| a.1.mu.total_cmp(&b.1.mu))
    }

    /// The eigenvalue of track `id` at each step (`None` where the track is absent).
    pub fn track_eigenvalues(&self, id: usize) -> Vec<Option<Cplx>> {
        self.tracks[id]
            .modes
            .iter()
            .enumerate()
            .map(|(s, m)| m.map(|i| self.steps[s].modes[i].eigenvalue))
            .collect()
    }
}

pub(super) struct Solver<'a, F> {
    build: F,
    pub(super) cea: CeaOptions,
    /// The projection basis (`None`: exact).
    pub(super) basis: Option<ModalBasis>,
    /// A system already built (to choose the method or the basis), used by the next solve.
    cached: Option<(f64, CeaMatrices)>,
    /// The slaves of G for the refinements' constraint elimination, made once (G is the
    /// basis' at every μ of a projected sweep; `Some(None)`: none exists).
    split: Option<Option<Arc<SlaveSplit>>>,
    pub(super) stats: &'a mut SweepStats,
}

impl<F, E> Solver<'_, F>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    /// Builds the system at μ into the cache (if it is not there) and returns it.
    fn peek(&mut self, mu: f64) -> Result<&CeaMatrices, CeaError> {
        if self.cached.as_ref().is_none_or(|c| c.0 != mu) {
            let t = Instant::now();
            let sys = (self.build)(mu).map_err(|e| CeaError::Build {
                mu,
                message: e.to_string(),
            })?;
            self.stats.time_build_s += t.elapsed().as_secs_f64();
            self.cached = Some((mu, sys));
        }
        Ok(&self.cached.as_ref().expect("just filled").1)
    }

    /// The slaves of G of a projected sweep (made at the first call; G is checked against the
    /// basis' by every projected solve, and by [`Solver::same_g`]), `None` without a basis.
    pub(super) fn slave_split(&mut self, sys: &CeaMatrices) -> Option<Arc<SlaveSplit>> {
        self.basis.as_ref()?;
        if self.split.is_none() {
            let g = sys.g.as_ref().filter(|g| g.nrows() > 0);
            self.split = Some(g.and_then(|g| SlaveSplit::new(g).map(Arc::new)));
        }
        self.split.clone().flatten()
    }

    /// Returns a system built at μ to the cache (the next [`Solver::system`] at μ takes it).
    pub(super) fn put_back(&mut self, mu: f64, sys: CeaMatrices) {
        self.cached = Some((mu, sys));
    }

    pub(super) fn system(&mut self, mu: f64) -> Result<CeaMatrices, CeaError> {
        self.peek(mu)?;
        Ok(self.cached.take().expect("just filled").1)
    }

    pub(super) fn solve(&mut self, mu: f64) -> Result<CeaResult, CeaError> {
        self.solve_checked(mu, None)
    }

    /// Solves at μ; with `check = Some(step)` and a basis, also solves exactly (eigenvalues
    /// only) and records the comparison.
    fn solve_checked(&mut self, mu: f64, check: Option<usize>) -> Result<CeaResult, CeaError> {
        self.cea.check_interrupt("the friction sweep")?;
        let t = Instant::now();
        let sys = self.system(mu)?;
        let r = match &self.basis {
            Some(b) => b.solve(&sys, &self.cea)?,
            None => exact(&sys, &self.cea)?,
        };
        self.stats.n_solves += 1;
        self.stats.time_eigen_s += t.elapsed().as_secs_f64();
        if let (Some(step), Some(band)) = (check, self.stats.check_band_hz) {
            let t = Instant::now();
            let pr = &self.cea.projection;
            let (kind, comparison) =
                if pr.refine.enabled && self.stats.n_reduced > pr.auto_single_min_dofs {
                    let mut modes = r.modes.clone();
                    let tol = self.cea.unstable_tol * r.stats.spectral_radius;
                    let targets: Vec<usize> = (0..modes.len())
                        .filter(|&i| modes[i].unstable && modes[i].frequency_hz <= band)
                        .collect();
                    let split = self.slave_split(&sys);
                    let pr = &self.cea.projection;
                    let run = RefineRun {
                        band_hz: band,
                        unstable_tol_abs: tol,
                        opts: &pr.refine,
                        interrupt: &self.cea.interrupt,
                        split: split.as_ref(),
                        keep: false,
                    };
                    let st = run.targets(&sys, &mut modes, targets)?.0;
                    (CheckKind::Refine, refine_comparison(&st))
                } else {
                    let opts = CeaOptions {
                        compute_shapes: false,
                        ..self.cea.clone()
                    };
                    let e = exact(&sys, &opts)?;
                    (
                        CheckKind::Dense,
                        compare_eigenvalues(&r.modes, &e.modes, band),
                    )
                };
            let worst = self.stats.max_rel_eigenvalue_error.unwrap_or(0.0);
            self.stats.max_rel_eigenvalue_error = Some(worst.max(comparison.max_rel_error));
            let time_s = t.elapsed().as_secs_f64();
            self.stats.time_check_s += time_s;
            self.stats.exact_checks.push(ExactCheck {
                step,
                mu,
                kind,
                comparison,
                time_s,
            });
        }
        Ok(r)
    }
}

/// Runs the CEA at each friction coefficient of `mus` (strictly increasing), tracks the
/// modes from step to step by complex MAC (greedy assignment, ties by eigenvalue distance)
/// and finds, per tracked mode, the first μ where Re p crosses 0.
///
/// The critical μ is linearly interpolated in Re p between the bracketing steps and, when
/// `opts.bisection`, located by Illinois regula falsi on the tracked root's Re p (each trial
/// μ is a new `build` + solve; candidates at a trial are the modes whose MAC with the
/// reference is at least half the best, the most unstable counting: near a coalescence both
/// partners qualify). A projected sweep then moves each in-band onset (frequency ≤ the check
/// band) to the crossing of the exact root when `opts.refine_critical`: a bracket search and
/// regula falsi on the Re p of the tracked root refined exactly by shift-invert Arnoldi
/// (exact evaluations only), as the single projected CEA
/// refines its unstable roots ([`Critical::exact`], [`SweepStats::n_critical_exact`]). The
/// merging partner is the tracked mode with the nearest frequency at the first unstable
/// step (for a mode-coupling instability the two frequencies coalesce there).
///
/// `build(μ)` returns the linearised matrices at μ (e.g. friction tangents from the
/// contact crate); its error is wrapped in [`CeaError::Build`].
pub fn sweep<F, E>(build: F, mus: &[f64], opts: &SweepOptions) -> Result<Sweep, CeaError>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    opts.validate()?;
    if mus.is_empty() {
        return Err(CeaError::InvalidOption {
            field: "sweep.mus",
            value: "[]".into(),
            reason: "needs at least one value".into(),
        });
    }
    if let Some(i) = mus.iter().position(|x| !x.is_finite()) {
        return Err(CeaError::InvalidOption {
            field: "sweep.mus",
            value: format!("mus[{i}] = {}", mus[i]),
            reason: "must be finite".into(),
        });
    }
    for (i, w) in mus.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(CeaError::InvalidOption {
                field: "sweep.mus",
                value: format!("mus[{}] = {}, mus[{}] = {}", i, w[0], i + 1, w[1]),
                reason: "must be strictly increasing".into(),
            });
        }
    }
    let start = Instant::now();
    let mut stats = SweepStats {
        n_steps: mus.len(),
        ..SweepStats::default()
    };
    let mut cea = opts.cea.clone();
    cea.compute_shapes = true;
    let mut solver = Solver {
        build,
        cea,
        basis: None,
        cached: None,
        split: None,
        stats: &mut stats,
    };
    choose_method(&mut solver, mus, opts)?;
    let mut steps: Vec<SweepStep> = Vec::with_capacity(mus.len());
    let mut tracks: Vec<Track> = Vec::new();
    // (track id, mode index) of the tracks alive at the previous step, and its modes.
    let mut alive: Vec<(usize, usize)> = Vec::new();
    let mut prev: Option<CeaResult> = None;
    let mut prev2: Option<CeaResult> = None;
    let mut events: Vec<ModeEvent> = Vec::new();
    let tol = EventTolerances {
        lock: opts.lock_tol,
        veer: opts.veer_tol,
        exchange_mac: opts.exchange_mac,
    };
    let last = mus.len() - 1;
    for (s, &mu) in mus.iter().enumerate() {
        let check = (opts.exact_check && (s == 0 || s == last))
            || (opts.exact_check_every > 0 && s % opts.exact_check_every == 0);
        let res = solver.solve_checked(mu, check.then_some(s))?;
        let mut next_alive = Vec::with_capacity(res.modes.len());
        let mut taken = vec![false; res.modes.len()];
        if let Some(pr) = &prev {
            let a: Vec<&[Cplx]> = alive
                .iter()
                .map(|&(_, i)| pr.modes[i].shape.as_slice())
                .collect();
            let b: Vec<&[Cplx]> = res.modes.iter().map(|m| m.shape.as_slice()).collect();
            let pa: Vec<Cplx> = alive.iter().map(|&(_, i)| pr.modes[i].eigenvalue).collect();
            // Each alive track's eigenvalue predicted at μ by linear extrapolation from its
            // last two steps (its last one when it is new).
            let pred: Vec<Cplx> = alive
                .iter()
                .map(|&(tid, i)| {
                    let p1 = pr.modes[i].eigenvalue;
                    match (s >= 2).then(|| tracks[tid].modes[s - 2]).flatten() {
                        Some(k) => {
                            let p0 = steps[s - 2].modes[k].eigenvalue;
                            p1 + (p1 - p0) * ((mu - mus[s - 1]) / (mus[s - 1] - mus[s - 2]))
                        }
                        None => p1,
                    }
                })
                .collect();
            let pb: Vec<Cplx> = res.modes.iter().map(|m| m.eigenvalue).collect();
            let map = assign(
                &mac_matrix(&a, &b),
                &pa,
                &pred,
                &pb,
                opts.mac_min,
                opts.continuity_weight,
            );
            for (k, &(tid, _)) in alive.iter().enumerate() {
                if let Some(j) = map[k] {
                    tracks[tid].modes.push(Some(j));
                    taken[j] = true;
                    next_alive.push((tid, j));
                } else {
                    tracks[tid].modes.push(None);
                }
            }
            // Tracks that ended earlier stay None.
            for t in tracks.iter_mut() {
                if t.modes.len() < s + 1 {
                    t.modes.push(None);
                }
            }
        }
        for (j, m) in res.modes.iter().enumerate() {
            if !taken[j] {
                let id = tracks.len();
                let mut modes = vec![None; s];
                modes.push(Some(j));
                tracks.push(Track {
                    id,
                    modes,
                    unstable_at_start: m.unstable,
                    critical: None,
                });
                next_alive.push((id, j));
            }
        }
        // Veerings with their closest approach at step s − 1 (shapes of s − 2 and s).
        if let (Some(p1), Some(p2)) = (&prev, &prev2) {
            find_veerings(&tracks, s, [p2, p1, &res], mus, &tol, &mut events);
        }
        // Onsets between step s−1 and s.
        if let Some(pr) = &prev {
            let freq_now: Vec<(usize, f64)> = next_alive
                .iter()
                .map(|&(t, j)| (t, res.modes[j].frequency_hz))
                .collect();
            for &(tid, j) in &next_alive {
                let (Some(i), true) = (tracks[tid].modes[s - 1], tracks[tid].critical.is_none())
                else {
                    continue;
                };
                let (m0, m1) = (&pr.modes[i], &res.modes[j]);
                if m0.unstable || !m1.unstable {
                    continue;
                }
                let (mu0, mu1) = (mus[s - 1], mu);
                let (r0, r1) = (m0.real_part, m1.real_part);
                let frac = if r1 > r0 {
                    (-r0 / (r1 - r0)).clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let mu_lin = mu0 + frac * (mu1 - mu0);
                let f_lin = m0.frequency_hz + frac * (m1.frequency_hz - m0.frequency_hz);
                let partner = freq_now
                    .iter()
                    .filter(|&&(t, _)| t != tid)
                    .min_by(|a, b| {
                        (a.1 - m1.frequency_hz)
                            .abs()
                            .total_cmp(&(b.1 - m1.frequency_hz).abs())
                    })
                    .map(|&(t, _)| t);
                let pf = |step_modes: &Vec<Mode>, st: usize| {
                    partner.and_then(|p| tracks[p].modes[st].map(|k| step_modes[k].frequency_hz))
                };
                let partner_before = pf(&pr.modes, s - 1);
                let partner_after = pf(&res.modes, s);
                // Onsets above the check band of a projected sweep on a truncated basis are
                // interpolated only: the projection does not resolve them (nor do the checks).
                let truncated = solver.stats.n_basis < solver.stats.n_reduced;
                let in_band = solver.basis.is_none()
                    || !truncated
                    || solver.stats.check_band_hz.is_none_or(|b| f_lin <= b);
                let (mu_loc, f_loc, nb, located) = if opts.bisection && in_band {
                    let thr = |r: &CeaResult| solver.cea.unstable_tol * r.stats.spectral_radius;
                    let br = Bracket {
                        lo: Point {
                            mu: mu0,
                            f: m0.real_part - thr(pr),
                            p: m0.eigenvalue,
                        },
                        hi: Point {
                            mu: mu1,
                            f: m1.real_part - thr(&res),
                            p: m1.eigenvalue,
                        },
                    };
                    let (br, nb) = solver.locate(br, m0.shape.clone(), opts)?;
                    let (mu_c, p_c) = br.crossing();
                    (mu_c, p_c.im.abs() / (2.0 * PI), nb, Some(br))
                } else {
                    (mu_lin, f_lin, 0, None)
                };
                solver.stats.n_locate_solves += nb;
                let band = solver.stats.check_band_hz;
                let refinable = opts.refine_critical
                    && solver.basis.is_some()
                    && solver.cea.projection.refine.enabled
                    && located.is_some()
                    && band.is_some_and(|b| f_loc <= b);
                let attempted =
                    solver.stats.n_critical_exact + solver.stats.n_critical_exact_failed;
                if refinable && attempted >= opts.max_exact_onsets {
                    solver.stats.n_critical_exact_skipped += 1;
                }
                let exact = match (&located, band) {
                    (Some(br), Some(band)) if refinable && attempted < opts.max_exact_onsets => {
                        Some(solver.refine_critical(
                            br,
                            m0.shape.clone(),
                            (mu0, mu1),
                            band,
                            opts,
                        )?)
                    }
                    _ => None,
                };
                if let Some(x) = &exact {
                    let st = &mut *solver.stats;
                    st.n_critical_exact_solves += x.n_solves;
                    st.n_critical_exact_followed += x.n_followed;
                    st.time_critical_exact_s += x.time_s;
                    if x.converged {
                        st.n_critical_exact += 1;
                        let d = x.mu_change.abs();
                        st.max_critical_mu_change =
                            Some(st.max_critical_mu_change.unwrap_or(0.0).max(d));
                    } else {
                        st.n_critical_exact_failed += 1;
                    }
                    st.max_rel_critical_root_error = Some(
                        st.max_rel_critical_root_error
                            .unwrap_or(0.0)
                            .max(x.max_rel_root_error),
                    );
                }
                let (mu_c, f_c) = match &exact {
                    Some(x) if x.converged => (x.mu, x.frequency_hz),
                    _ => (mu_loc, f_loc),
                };
                tracks[tid].critical = Some(Critical {
                    mu: mu_c,
                    mu_located: mu_loc,
                    mu_interpolated: mu_lin,
                    step: s - 1,
                    frequency_hz: f_c,
                    partner,
                    frequency_before_hz: m0.frequency_hz,
                    partner_frequency_before_hz: partner_before,
                    frequency_after_hz: m1.frequency_hz,
                    partner_frequency_after_hz: partner_after,
                    locate_solves: nb,
                    exact,
                });
            }
        }
        let mut modes_out = res.modes.clone();
        if !opts.keep_shapes {
            for m in &mut modes_out {
                m.shape = Vec::new();
            }
        }
        steps.push(SweepStep {
            mu,
            modes: modes_out,
            stats: res.stats.clone(),
        });
        alive = next_alive;
        prev2 = prev.take();
        prev = Some(res);
    }
    drop(solver);
    for a in 0..tracks.len() {
        for b in a + 1..tracks.len() {
            let shared: Vec<usize> = (0..mus.len())
                .filter(|&s| tracks[a].modes[s].is_some() && tracks[b].modes[s].is_some())
                .collect();
            // Runs of consecutive shared steps.
            for run in shared.chunk_by(|x, y| y == &(x + 1)) {
                let pair: Vec<PairStep<'_>> = run
                    .iter()
                    .map(|&s| PairStep {
                        mu: mus[s],
                        a: &steps[s].modes[tracks[a].modes[s].expect("shared")],
                        b: &steps[s].modes[tracks[b].modes[s].expect("shared")],
                    })
                    .collect();
                events.extend(coalescences([a, b], run[0], &pair, &tol));
            }
        }
    }
    events.sort_by(|x, y| event_mu(x).total_cmp(&event_mu(y)));
    stats.n_tracks = tracks.len();
    stats.n_critical = tracks.iter().filter(|t| t.critical.is_some()).count();
    stats.time_s = start.elapsed().as_secs_f64();
    Ok(Sweep {
        steps,
        tracks,
        events,
        stats,
    })
}

fn event_mu(e: &ModeEvent) -> f64 {
    match e {
        ModeEvent::Coalescence { mu, .. } | ModeEvent::Veering { mu, .. } => *mu,
    }
}

/// Veerings whose closest approach is at step `s − 1`, between tracks alive at s − 2, s − 1
/// and s whose frequencies are neighbours at s − 1 (`w` holds the three steps' results, with
/// shapes).
fn find_veerings(
    tracks: &[Track],
    s: usize,
    w: [&CeaResult; 3],
    mus: &[f64],
    tol: &EventTolerances,
    events: &mut Vec<ModeEvent>,
) {
    let idx = |t: &Track, k: usize| t.modes.get(k).copied().flatten();
    let mut alive: Vec<(usize, [usize; 3])> = tracks
        .iter()
        .filter_map(|t| Some((t.id, [idx(t, s - 2)?, idx(t, s - 1)?, idx(t, s)?])))
        .collect();
    alive.sort_by(|x, y| {
        w[1].modes[x.1[1]]
            .frequency_hz
            .total_cmp(&w[1].modes[y.1[1]].frequency_hz)
    });
    for pair in alive.windows(2) {
        let ((ta, ia), (tb, ib)) = (pair[0], pair[1]);
        let step = |k: usize| PairStep {
            mu: mus[s - 2 + k],
            a: &w[k].modes[ia[k]],
            b: &w[k].modes[ib[k]],
        };
        if let Some(e) = veering([ta, tb], s - 1, [step(0), step(1), step(2)], tol) {
            events.push(e);
        }
    }
}

/// Resolves `auto`, and builds the basis for `projection` (see [`CeaMethod::Auto`]).
fn choose_method<F, E>(
    solver: &mut Solver<'_, F>,
    mus: &[f64],
    opts: &SweepOptions,
) -> Result<(), CeaError>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    let pr = &opts.cea.projection;
    let n_reduced = {
        let (n, ng) = check_inputs(solver.peek(mus[0])?)?;
        n - ng
    };
    solver.stats.n_reduced = n_reduced;
    let method = match opts.cea.method {
        CeaMethod::Exact => CeaMethod::Exact,
        CeaMethod::Projection => CeaMethod::Projection,
        CeaMethod::Auto => {
            if pr.is_truncated() && n_reduced > pr.auto_min_dofs {
                CeaMethod::Projection
            } else {
                CeaMethod::Exact
            }
        }
    };
    solver.stats.method = method;
    if method == CeaMethod::Exact {
        return Ok(());
    }
    let t = Instant::now();
    let basis_mu = pr.basis_mu.unwrap_or(mus[0]);
    let cea = solver.cea.clone();
    let basis = ModalBasis::new(solver.peek(basis_mu)?, &cea)?;
    let f_max = basis.frequencies_hz().last().copied().unwrap_or(0.0);
    solver.stats.n_basis = basis.len();
    solver.stats.basis_max_frequency_hz = Some(f_max);
    solver.stats.basis_mu = Some(basis_mu);
    let band = pr.frequency_max_hz.unwrap_or(f_max / pr.cutoff_factor);
    solver.stats.check_band_hz = Some(band);
    solver.stats.time_basis_s = t.elapsed().as_secs_f64();
    solver.basis = Some(basis);
    let truncated = solver.stats.n_basis < n_reduced;
    if opts.enrich && pr.refine.enabled && truncated {
        let t = Instant::now();
        let skip = mus.iter().position(|&m| m == basis_mu);
        let (points, pass) = solver.enrich(mus, skip, band, opts)?;
        let basis = solver.basis.as_ref().expect("kept");
        solver.stats.n_basis = basis.len();
        solver.stats.n_basis_enriched = basis.n_enriched();
        solver.stats.basis_error = points.last().map(|p| p.max_rel_error);
        solver.stats.basis_converged = Some(pass);
        solver.stats.enrichment = points;
        solver.stats.time_enrich_s = t.elapsed().as_secs_f64();
    }
    Ok(())
}

/// The comparison of an exact check by refinement: the targets' projected roots against their
/// exact values.
pub(super) fn refine_comparison(st: &RefineStats) -> EigenvalueComparison {
    let mut c = EigenvalueComparison {
        band_hz: st.band_hz,
        n_exact_in_band: st.n_targets_refined + st.n_missed,
        n_projected_in_band: st.n_targets,
        ..EigenvalueComparison::default()
    };
    for r in st.roots.iter().filter(|r| r.target) {
        if r.rel_change > c.max_rel_error {
            c.max_rel_error = r.rel_change;
            c.worst_frequency_hz = r.exact.im.abs() / (2.0 * std::f64::consts::PI);
        }
        c.max_real_part_error = c
            .max_real_part_error
            .max((r.exact.re - r.projected.re).abs());
    }
    c
}
