//! `squeal limit-cycle`: the periodic solutions of the band-limited model by harmonic balance
//! (issue 22 item 4; docs/limit-cycle.md).
//!
//! reduced model → band-limited model at the loaded steady sliding state
//! ([`crate::problem::band`], `[transient] band_cutoff` / `band_tolerance`) → for
//! every unstable kept root in the band: its Hopf point in the friction scale, harmonic balance
//! with alternating frequency–time evaluation of the friction and unilateral contact forces,
//! arclength continuation up to the operating point, the harmonics doubled until converged,
//! Floquet stability ([`squeal_solver::hb`]) → per unstable mode the limit cycle's frequency
//! and the amplitude (peak and RMS over the gaps and the period) of the rotor's normal velocity
//! on the friction face, "how loud".
//!
//! - Compute: [`compute`] → [`LimitCycleComputed`] (in memory).
//! - Write: [`write`] → `limit_cycle.json` ([`LimitCycleReport`]); [`run`] builds the model
//!   (cached) and writes.

use crate::error::PipelineError;
use crate::model::{self, ModelCache, ReducedModel};
use crate::output::RunDir;
use crate::problem::band::{self, BandReport};
use crate::problem::system;
use crate::progress::Progress;
use crate::scene::Scene;
use serde::Serialize;
use squeal_solver::hb::{limit_cycle, HbError, HbOptions, LimitCycle, LimitCycleStatus};
use squeal_solver::Real;
use std::time::Instant;

/// The limit cycle of one unstable mode.
#[derive(Debug, Clone, Serialize)]
pub struct ModeCycle {
    /// The unstable root at the operating point: frequency (Hz) and Re p (1/s).
    pub root_frequency_hz: Real,
    pub root_real_part: Real,
    /// The cycle reached the operating point with its harmonics converged.
    pub reached: bool,
    /// Its frequency, Hz (the operating point's when reached).
    pub frequency_hz: Real,
    /// Peak over the gaps and the period of the rotor's normal velocity on the friction face.
    pub peak_normal_velocity: Real,
    /// Its RMS over the gaps and the period.
    pub rms_normal_velocity: Real,
    /// Stable (all Floquet multipliers but the trivial one inside the unit circle); None when
    /// not computed or not reached.
    pub stable: Option<bool>,
    /// The solver's whole result: Hopf point, branch, harmonics and their convergence, status.
    pub detail: LimitCycle,
}

/// What `squeal limit-cycle` found, in memory (`limit_cycle.json`'s body).
#[derive(Debug, Clone, Serialize)]
pub struct LimitCycleComputed {
    /// The band-limited model the cycles are of.
    pub band_model: BandReport,
    /// Unstable in-band roots at the operating point, most unstable first, each with its cycle.
    pub modes: Vec<ModeCycle>,
    /// The options of the harmonic balance.
    pub options: HbOptions,
    /// Seconds: the condensation, and the cycles.
    pub time_band_s: Real,
    pub time_cycles_s: Real,
}

/// `limit_cycle.json`.
#[derive(Debug, Clone, Serialize)]
pub struct LimitCycleReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub wall_s: Real,
    #[serde(flatten)]
    pub result: LimitCycleComputed,
}

/// The limit cycles of `scene` on `model`. A mode whose branch fails is reported with its
/// status (not an error).
///
/// # Errors
/// The band-limited model's (no band, a rigid unilateral gap, an estimate above
/// `transient.band_tolerance`, ...); bad `[limit_cycle]` options; a callback failure;
/// cancellation between modes.
pub fn compute(
    scene: &Scene,
    model: &ReducedModel,
    progress: &Progress,
) -> Result<LimitCycleComputed, PipelineError> {
    let clock = Instant::now();
    let problem = system::problem(scene, model)?;
    let mut b = band::build(scene, model, &problem)?;
    progress.info(b.report.line());
    let time_band_s = clock.elapsed().as_secs_f64();
    let band_hz = b.report.stats.band_hz;
    let mut opts = scene.limit_cycle.clone().unwrap_or_default();
    if opts.velocity_scale == HbOptions::default().velocity_scale && b.velocity_scale > 0.0 {
        opts.velocity_scale = b.velocity_scale;
    }
    opts.validate().map_err(hb_err)?;
    let two_pi = 2.0 * std::f64::consts::PI;
    let unstable_tol = 1e-8;
    let pmax = b
        .system
        .model()
        .roots
        .iter()
        .fold(0.0f64, |m, p| m.max(p.norm()));
    let mut roots: Vec<_> = b
        .system
        .model()
        .roots
        .iter()
        .copied()
        .filter(|p| p.im > 0.0 && p.re > unstable_tol * pmax && p.im / two_pi <= band_hz)
        .collect();
    roots.sort_by(|a, c| c.re.total_cmp(&a.re));
    let clock = Instant::now();
    let mut modes = Vec::with_capacity(roots.len());
    // Any time after the load ramp: the contact law there is the operating point's.
    let t = b.t_ref + 1.0;
    for (i, p) in roots.iter().enumerate() {
        progress.check("limit-cycle")?;
        progress.info(format!(
            "mode {}/{}: root {:.1} Hz, Re p {:+.2} /s",
            i + 1,
            roots.len(),
            p.im / two_pi,
            p.re
        ));
        let lc = limit_cycle(&mut b.system, t, *p, &b.face, &opts).map_err(hb_err)?;
        let reached = lc.status == LimitCycleStatus::Reached;
        progress.info(format!(
            "  {:?}: {:.2} Hz, face normal velocity peak {:.4e}, rms {:.4e} (H = {}, {:.1} s)",
            lc.status,
            lc.frequency_hz,
            lc.peak_face_velocity,
            lc.rms_face_velocity,
            lc.harmonics,
            lc.time_s
        ));
        modes.push(ModeCycle {
            root_frequency_hz: p.im / two_pi,
            root_real_part: p.re,
            reached,
            frequency_hz: lc.frequency_hz,
            peak_normal_velocity: lc.peak_face_velocity,
            rms_normal_velocity: lc.rms_face_velocity,
            stable: lc.floquet.as_ref().filter(|_| reached).map(|f| f.stable),
            detail: lc,
        });
    }
    Ok(LimitCycleComputed {
        band_model: b.report,
        modes,
        options: opts,
        time_band_s,
        time_cycles_s: clock.elapsed().as_secs_f64(),
    })
}

fn hb_err(e: HbError) -> PipelineError {
    match e {
        HbError::Option { field, .. } => PipelineError::Scene {
            field: format!("limit_cycle.{field}"),
            message: e.to_string(),
        },
        HbError::Solver(source) => PipelineError::Solver {
            what: "limit cycle".into(),
            source,
        },
    }
}

/// Writes `limit_cycle.json` of a computed result.
pub fn write(
    dir: &RunDir,
    result: LimitCycleComputed,
    wall_s: Real,
) -> Result<LimitCycleReport, PipelineError> {
    let report = LimitCycleReport {
        verb: "limit-cycle",
        version: crate::VERSION,
        wall_s,
        result,
    };
    dir.write_json("limit_cycle.json", &report)?;
    Ok(report)
}

/// `squeal limit-cycle`: the model (from the cache when given), the cycles, `limit_cycle.json`.
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    cache: Option<&ModelCache>,
) -> Result<LimitCycleReport, PipelineError> {
    let wall = Instant::now();
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, _) = model::build_cached(scene, dir, progress, cache)?;
    let result = compute(scene, &model, progress)?;
    write(dir, result, wall.elapsed().as_secs_f64())
}
