//! `squeal reproduce`: the paper's sample-brake study (section 3, its table of eight cases).
//!
//! study.toml (base scene + per-case RTOL1, TLOAD, μ, G, W3, P0, TF) → for every case
//! `squeal transient` (and `squeal cea` at the steady sliding state) in `caseN/` → `cases.json`,
//! `cases.md` (the table with our columns), figures analogous to the paper's Figs. 3–8 and a
//! spectrum of a squealing response ([`report`]), `report.md` that embeds them and states which
//! of the paper's findings reproduce.
//!
//! The report is made from the cases' typed results in memory: the transient's
//! [`TransientResult`](transient::TransientResult) with its sampled history
//! ([`TransientOptions::keep_history`](transient::TransientOptions)) and the CEA's
//! [`CeaComputed`](cea::CeaComputed) ([`report::CaseData`]); the case folders are written for
//! the user and never read back.
//!
//! Cases run `jobs` at a time (rayon). With a model cache (`--cache DIR` / `SQUEAL_CACHE`) the
//! reduced model is built once before the cases start (they vary only parameters outside its
//! key) and every case reads it from the cache.
//! With `[cea_sweep]` the study also sweeps constant μ over
//! the base scene's complex eigenvalues (`cea_sweep/`), so the report can say which mode pairs
//! couple at which μ.

pub mod report;
pub mod study;

use crate::error::PipelineError;
use crate::model::ModelCache;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::stages::{cea, transient};
use rayon::prelude::*;
use serde::Serialize;
use std::path::Path;
use std::time::Instant;
pub use study::{CaseSpec, FigureSpec, StudySpec};

use squeal_solver::Real;

/// What the command line adds.
#[derive(Debug, Clone, Default)]
pub struct ReproduceArgs {
    /// Run only these cases (default: all).
    pub cases: Option<Vec<u32>>,
    /// Overrides applied to the base scene of every case (before the case's own).
    pub set: Vec<String>,
    /// Cases run at the same time (default: the available cores).
    pub jobs: Option<usize>,
    /// Model cache folder (default: none, every case builds its model).
    pub cache: Option<std::path::PathBuf>,
}

/// An unstable complex mode of a case.
#[derive(Debug, Clone, Serialize)]
pub struct UnstableMode {
    pub frequency_hz: Real,
    pub real_part: Real,
}

/// One object of `cases.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CaseResult {
    pub case: u32,
    /// μ as the paper writes it.
    pub mu: String,
    pub rtol1: Real,
    pub tload: Real,
    pub g: Real,
    pub w3: Real,
    pub p0: Real,
    pub tf: Real,
    /// Accepted BDF steps (NS).
    pub steps: u64,
    /// Seconds in the integrator.
    pub cpu_s: Real,
    /// Seconds of the whole case (model build, transient, CEA).
    pub wall_s: Real,
    /// Time reached (= tf unless the run stopped early).
    pub t_end: Real,
    /// How the integration ended (`max_steps`: stopped at the study's step cap).
    pub status: squeal_solver::bdf::Status,
    pub squeal: bool,
    /// `squeal`, `no_squeal`, or `unresolved` with its reasons.
    pub verdict: crate::verdict::guard::VerdictState,
    pub growth_rate_per_s: Option<Real>,
    pub dominant_frequency_hz: Option<Real>,
    /// History column of the verdict's response.
    pub response: String,
    /// What the contact did (tensile gap-steps, first separation, smallest p_n).
    pub contact: crate::verdict::validity::ContactValidity,
    /// The step bound of the run.
    pub h_max: Option<Real>,
    /// Time the squealing root's fitted amplitude reaches the study's onset level.
    pub onset_s: Option<Real>,
    pub n_dofs: usize,
    pub n_gaps: usize,
    /// Unstable complex modes at the steady sliding state (None: CEA not run or failed).
    pub cea_unstable_modes: Option<Vec<UnstableMode>>,
    /// Why the CEA failed, if it did.
    pub cea_error: Option<String>,
    /// The response's largest roots (the verdict's estimator), at most 4.
    pub roots: Vec<crate::verdict::roots::Root>,
    /// The response's significant roots each beside the case's CEA root nearest to it, with
    /// the relative differences in σ and f (None: no CEA).
    pub transient_vs_cea: Option<Vec<crate::verdict::roots::RootPair>>,
}

/// Summary of a study run.
#[derive(Debug, Clone, Serialize)]
pub struct ReproduceReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub wall_s: Real,
    pub jobs: usize,
    pub cases: Vec<CaseResult>,
    pub findings: Vec<report::Finding>,
    pub files: Vec<String>,
}

/// Runs the study's cases into `dir/caseN/` and writes the table, figures and report.
pub fn run(
    study_path: &Path,
    dir: &RunDir,
    progress: &Progress,
    args: &ReproduceArgs,
) -> Result<ReproduceReport, PipelineError> {
    let wall = Instant::now();
    let study = StudySpec::load(study_path)?;
    let base_path = study.base_path();
    let sets: Vec<String> = study.set.iter().chain(&args.set).cloned().collect();
    let base = Scene::load(&base_path, &sets)?;
    let n_contact = base.contact.len();
    let selected: Vec<&CaseSpec> = match &args.cases {
        Some(list) => {
            if let Some(c) = list
                .iter()
                .find(|c| !study.cases.iter().any(|s| s.case == **c))
            {
                return Err(PipelineError::Scene {
                    field: "--cases".into(),
                    message: format!("the study has no case {c}"),
                });
            }
            study
                .cases
                .iter()
                .filter(|s| list.contains(&s.case))
                .collect()
        }
        None => study.cases.iter().collect(),
    };
    // Each case's scene, checked before anything runs.
    let mut scenes = Vec::new();
    for c in &selected {
        let mut scene = base.clone();
        scene.set_all(&c.overrides(n_contact)?)?;
        // The run's step bound: the scene's h_max or the band bound.
        let h_max = scene
            .transient
            .as_ref()
            .and_then(|t| transient::step_bound(t, scene.band_hz()).h_max);
        let cap = match (h_max, scene.transient.as_ref()) {
            (Some(h), Some(t)) => Some((study.step_cap * t.tfinal / h).ceil() as usize + 100),
            _ => None,
        };
        scenes.push(((*c).clone(), scene, cap));
    }
    let jobs = args
        .jobs
        .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |n| n.get()))
        .clamp(1, scenes.len().max(1));
    progress.info(format!(
        "reproduce: {} cases of {}, {jobs} at a time",
        scenes.len(),
        study_path.display()
    ));
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(jobs)
        .build()
        .map_err(|e| PipelineError::Output {
            path: dir.path(""),
            message: format!("thread pool: {e}"),
        })?;
    let quiet = progress.silenced();
    let cache = args.cache.as_ref().map(ModelCache::new);
    if let (Some(c), Some((_, scene, _))) = (&cache, scenes.first()) {
        // Built once here, so the parallel cases all hit.
        c.get_or_build(scene, dir, progress)?;
    }
    let results: Vec<Result<(CaseResult, report::CaseData), PipelineError>> = pool.install(|| {
        scenes
            .par_iter()
            .map(|(c, scene, cap)| {
                let r = run_case(c, scene, *cap, &study, dir, &quiet, cache.as_ref());
                match &r {
                    Ok((r, _)) => progress.info(format!(
                        "case {}: {} steps, {:.1} s, t_end {:.4e}, squeal = {}, growth {:?} /s, f {:?} Hz",
                        r.case, r.steps, r.cpu_s, r.t_end, r.squeal, r.growth_rate_per_s, r.dominant_frequency_hz
                    )),
                    Err(e) => progress.info(format!("case {}: error: {e}", c.case)),
                }
                r
            })
            .collect()
    });
    let (cases, data): (Vec<CaseResult>, Vec<report::CaseData>) = results
        .into_iter()
        .collect::<Result<Vec<_>, _>>()?
        .into_iter()
        .unzip();
    let sweep = study
        .cea_sweep
        .map(|range| cea_sweep(&base, range, dir, &quiet, progress, cache.as_ref()));
    // A sweep stopped by Ctrl-C is recorded as failed; stop the study instead of reporting.
    progress.check("the study's CEA sweep")?;
    let (findings, files) = report::write(&study, &cases, &data, dir, &base, sweep.as_ref())?;
    let rep = ReproduceReport {
        verb: "reproduce",
        version: crate::VERSION,
        wall_s: wall.elapsed().as_secs_f64(),
        jobs,
        cases,
        findings,
        files,
    };
    dir.write_json("summary.json", &rep)?;
    Ok(rep)
}

/// Complex eigenvalues of the base scene over constant μ in `range` (`cea_sweep/`): the
/// couplings (critical μ of each mode pair) for the report. A failure is reported, not fatal.
fn cea_sweep(
    base: &Scene,
    range: study::MuRange,
    dir: &RunDir,
    quiet: &Progress,
    progress: &Progress,
    cache: Option<&ModelCache>,
) -> report::SweepSummary {
    let run = || -> Result<report::SweepSummary, PipelineError> {
        let mut scene = base.clone();
        if scene.cea.is_none() {
            scene.cea = Some(Default::default());
        }
        let mut friction = scene.friction.clone().unwrap_or_default();
        friction.law = squeal_contact::FrictionLaw::Constant { mu: range.first };
        scene.friction = Some(friction);
        let sdir = RunDir::create(&dir.path("cea_sweep"))?;
        let args = cea::CeaArgs {
            mu: Some((range.first, range.last, range.count)),
            cache: cache.cloned(),
            ..Default::default()
        };
        let rep = cea::run(&scene, &sdir, quiet, &args)?;
        rep.sweep
            .as_ref()
            .map(report::SweepSummary::of)
            .ok_or_else(|| PipelineError::Model("the CEA ran no friction sweep".into()))
    };
    let t0 = Instant::now();
    let out = run().unwrap_or_else(|e| report::SweepSummary::failed(e.to_string()));
    progress.info(format!(
        "CEA over mu = {}..{} ({} values): lowest critical mu {:?} ({:.1} s)",
        range.first,
        range.last,
        range.count,
        out.lowest_critical_mu,
        t0.elapsed().as_secs_f64()
    ));
    out
}

/// One case in process: its transient (capped at `cap` steps, judged on the growth phase
/// before a step collapse when the scene bounds the step) and its CEA, files in `caseN/`;
/// returns its `cases.json` row and what the report uses of it in memory.
fn run_case(
    c: &CaseSpec,
    scene: &Scene,
    cap: Option<usize>,
    study: &StudySpec,
    dir: &RunDir,
    quiet: &Progress,
    cache: Option<&ModelCache>,
) -> Result<(CaseResult, report::CaseData), PipelineError> {
    let wall = Instant::now();
    let cdir = RunDir::create(&dir.path(&format!("case{}", c.case)))?;
    cdir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, _) = crate::model::build_cached(scene, &cdir, quiet, cache)?;
    let h_max = scene
        .transient
        .as_ref()
        .and_then(|t| transient::step_bound(t, scene.band_hz()).h_max);
    let opts = transient::TransientOptions {
        // The report's figures and findings read the sampled history from memory.
        keep_history: true,
        step_cap: cap,
        // The growth phase only: up to the first step below h_max/100 after the ramp (the
        // start of stick-slip, where the step collapses).
        stall_h: cap.and(h_max).map(|h| 1e-2 * h),
    };
    let mut r = transient::run_on_model(scene, &cdir, quiet, None, &model, wall, &opts)?.result;
    let history = r.history.take();
    let mut transient_vs_cea = r.transient_vs_cea.clone();
    let mut cea_mu_range = None;
    let (cea_unstable_modes, cea_error) = if study.cea {
        let mut cs = scene.clone();
        if cs.cea.is_none() {
            cs.cea = Some(Default::default());
        }
        let cea_dir = RunDir::create(&cdir.path("cea"))?;
        let args = cea::CeaArgs::default();
        let t0 = Instant::now();
        // `squeal cea` into caseN/cea/ (its files as `cea::run_on_model` writes them), keeping
        // the computed result: the report reads nothing back.
        let run_cea = || -> Result<(cea::CeaComputed, cea::CeaReport), PipelineError> {
            cea_dir.write_bytes("scene.resolved.toml", cs.resolved_toml().as_bytes())?;
            let c = cea::compute(&cs, &model, quiet, &args)?;
            let rep = cea::write(&c, &model, &cea_dir, &args, None, t0)?;
            Ok((c, rep))
        };
        match run_cea() {
            Ok((c, rep)) => {
                // Every in-band root of the case's CEA, paired with the response's; a
                // non-finite root or μ (`null` in cea.json) leaves them out, as before.
                let finite = |a: Real, b: Real| (a.is_finite() && b.is_finite()).then_some((a, b));
                let modes: Option<Vec<(Real, Real)>> = c
                    .out
                    .modes
                    .iter()
                    .map(|m| finite(m.frequency_hz, m.real_part))
                    .collect();
                if let Some(m) = modes {
                    transient_vs_cea =
                        Some(crate::verdict::roots::pair_with_cea(&r.verdict.roots, &m));
                }
                let k = &c.out.steady_state.contact;
                cea_mu_range = finite(k.mu_min, k.mu_max);
                (
                    Some(
                        rep.unstable_modes
                            .iter()
                            .map(|m| UnstableMode {
                                frequency_hz: m.frequency_hz,
                                real_part: m.real_part,
                            })
                            .collect(),
                    ),
                    None,
                )
            }
            Err(e) if e.is_cancelled() => return Err(e),
            Err(e) => (None, Some(e.to_string())),
        }
    } else {
        (None, None)
    };
    let tr = scene.transient.clone().unwrap_or_default();
    let loads = scene.loads.clone().unwrap_or_default();
    let damping = scene.damping.clone().unwrap_or_default();
    let law = scene.friction.clone().unwrap_or_default().law;
    let onset_s = report::onset_time(&r.verdict, study.onset_level);
    let result = CaseResult {
        case: c.case,
        mu: study::mu_label(&law),
        rtol1: tr.rtol1,
        tload: loads.tload,
        g: damping.g,
        w3: damping.w3,
        p0: scene.contact.first().map_or(0.0, |p| p.p0),
        tf: tr.tfinal,
        steps: r.steps,
        cpu_s: r.cpu_s,
        wall_s: wall.elapsed().as_secs_f64(),
        t_end: r.t_end,
        status: r.status,
        squeal: r.squeal,
        verdict: r.verdict.state.clone(),
        growth_rate_per_s: r.growth_rate_per_s,
        dominant_frequency_hz: r.dominant_frequency_hz,
        response: r.response,
        contact: r.contact.clone(),
        h_max: r.step_bound.h_max,
        onset_s,
        n_dofs: r.n_dofs,
        n_gaps: r.n_gaps,
        cea_unstable_modes,
        cea_error,
        roots: r.verdict.roots.iter().take(4).copied().collect(),
        transient_vs_cea,
    };
    let data = report::CaseData {
        case: c.case,
        history,
        cea_mu_range,
    };
    Ok((result, data))
}
