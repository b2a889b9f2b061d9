//! Friction sweep: CEA at a list of μ, mode tracking, critical μ.

use super::eigen::exact;
use super::operator::check_inputs;
use super::refine::{refine, RefineStats};
use super::track::{assign, mac_matrix};
use super::{
    compare_eigenvalues, CeaError, CeaMatrices, CeaMethod, CeaOptions, CeaResult, CeaStats,
    CheckKind, Cplx, EigenvalueComparison, ExactCheck, ModalBasis, Mode, SweepOptions,
};
use serde::Serialize;
use std::fmt::Display;
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
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Critical {
    /// Critical μ: bisection-refined if `bisection`, else `mu_interpolated`.
    pub mu: f64,
    /// μ where Re p crosses 0, linearly interpolated between the bracketing steps.
    pub mu_interpolated: f64,
    /// Index of the last step at which the mode was stable (the next one is unstable).
    pub step: usize,
    /// Frequency of the mode at the onset (from the last bisection solve, or interpolated), Hz.
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
    /// Number of eigenvalue solves spent in the bisection.
    pub bisection_solves: usize,
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
    /// Number of eigenvalue solves (steps + bisection).
    pub n_solves: usize,
    /// Number of tracks.
    pub n_tracks: usize,
    /// Number of tracks with an onset of instability.
    pub n_critical: usize,
    /// Wall time, seconds.
    pub time_s: f64,
    /// Wall time spent in the eigenvalue solves (building the matrices, projecting and
    /// solving; not the exact checks), seconds.
    pub time_eigen_s: f64,
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
}

/// Result of [`sweep`].
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Sweep {
    /// One entry per μ.
    pub steps: Vec<SweepStep>,
    /// Tracked modes.
    pub tracks: Vec<Track>,
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

struct Solver<'a, F> {
    build: F,
    cea: CeaOptions,
    /// The projection basis (`None`: exact).
    basis: Option<ModalBasis>,
    /// A system already built (to choose the method or the basis), used by the next solve.
    cached: Option<(f64, CeaMatrices)>,
    stats: &'a mut SweepStats,
}

impl<F, E> Solver<'_, F>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    /// Builds the system at μ into the cache (if it is not there) and returns it.
    fn peek(&mut self, mu: f64) -> Result<&CeaMatrices, CeaError> {
        if self.cached.as_ref().is_none_or(|c| c.0 != mu) {
            let sys = (self.build)(mu).map_err(|e| CeaError::Build {
                mu,
                message: e.to_string(),
            })?;
            self.cached = Some((mu, sys));
        }
        Ok(&self.cached.as_ref().expect("just filled").1)
    }

    fn system(&mut self, mu: f64) -> Result<CeaMatrices, CeaError> {
        self.peek(mu)?;
        Ok(self.cached.take().expect("just filled").1)
    }

    fn solve(&mut self, mu: f64) -> Result<CeaResult, CeaError> {
        self.solve_checked(mu, None)
    }

    /// Solves at μ; with `check = Some(step)` and a basis, also solves exactly (eigenvalues
    /// only) and records the comparison.
    fn solve_checked(&mut self, mu: f64, check: Option<usize>) -> Result<CeaResult, CeaError> {
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
                    let st = refine(&sys, &mut modes, band, tol, &pr.refine)?;
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

    /// Bisection on "a mode resembling `reference` is unstable" in (lo, hi].
    /// Candidates at a trial μ are the modes whose MAC with the reference is at least half the
    /// best MAC (near a coalescence both partners qualify, and the unstable one counts).
    fn bisect(
        &mut self,
        mut lo: f64,
        mut hi: f64,
        mut reference: Vec<Cplx>,
        opts: &SweepOptions,
        mut freq: f64,
    ) -> Result<(f64, f64, usize), CeaError> {
        let mut count = 0;
        while hi - lo > opts.bisection_tol * hi.abs().max(1.0) && count < opts.max_bisection {
            let mid = 0.5 * (lo + hi);
            let r = self.solve(mid)?;
            count += 1;
            let macs: Vec<f64> = r
                .modes
                .iter()
                .map(|m| super::mac(&reference, &m.shape))
                .collect();
            let best = macs.iter().cloned().fold(0.0, f64::max);
            let unstable = r
                .modes
                .iter()
                .zip(&macs)
                .filter(|(m, &x)| x >= 0.5 * best && m.unstable)
                .max_by(|a, b| a.1.total_cmp(b.1));
            if let Some((m, _)) = unstable {
                hi = mid;
                freq = m.frequency_hz;
            } else {
                lo = mid;
                if let Some(i) = (0..macs.len()).max_by(|&a, &b| macs[a].total_cmp(&macs[b])) {
                    reference = r.modes[i].shape.clone();
                }
            }
        }
        Ok((0.5 * (lo + hi), freq, count))
    }
}

/// Runs the CEA at each friction coefficient of `mus` (strictly increasing), tracks the
/// modes from step to step by complex MAC (greedy assignment, ties by eigenvalue distance)
/// and finds, per tracked mode, the first μ where Re p crosses 0.
///
/// The critical μ is linearly interpolated in Re p between the bracketing steps and, when
/// `opts.bisection`, refined by bisection (each trial μ is a new `build` + solve). The
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
        stats: &mut stats,
    };
    choose_method(&mut solver, mus, opts)?;
    let mut steps: Vec<SweepStep> = Vec::with_capacity(mus.len());
    let mut tracks: Vec<Track> = Vec::new();
    // (track id, mode index) of the tracks alive at the previous step, and its modes.
    let mut alive: Vec<(usize, usize)> = Vec::new();
    let mut prev: Option<CeaResult> = None;
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
            let pb: Vec<Cplx> = res.modes.iter().map(|m| m.eigenvalue).collect();
            let map = assign(&mac_matrix(&a, &b), &pa, &pb, opts.mac_min);
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
                let (mu_c, f_c, nb) = if opts.bisection {
                    solver.bisect(mu0, mu1, m0.shape.clone(), opts, m1.frequency_hz)?
                } else {
                    (mu_lin, f_lin, 0)
                };
                tracks[tid].critical = Some(Critical {
                    mu: mu_c,
                    mu_interpolated: mu_lin,
                    step: s - 1,
                    frequency_hz: f_c,
                    partner,
                    frequency_before_hz: m0.frequency_hz,
                    partner_frequency_before_hz: partner_before,
                    frequency_after_hz: m1.frequency_hz,
                    partner_frequency_after_hz: partner_after,
                    bisection_solves: nb,
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
        prev = Some(res);
    }
    drop(solver);
    stats.n_tracks = tracks.len();
    stats.n_critical = tracks.iter().filter(|t| t.critical.is_some()).count();
    stats.time_s = start.elapsed().as_secs_f64();
    Ok(Sweep {
        steps,
        tracks,
        stats,
    })
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
    solver.stats.check_band_hz = Some(pr.frequency_max_hz.unwrap_or(f_max / pr.cutoff_factor));
    solver.stats.time_basis_s = t.elapsed().as_secs_f64();
    solver.basis = Some(basis);
    Ok(())
}

/// The comparison of an exact check by refinement: the targets' projected roots against their
/// exact values.
fn refine_comparison(st: &RefineStats) -> EigenvalueComparison {
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
