//! `squeal cea`: complex eigenvalue analysis about a steady sliding state, and friction sweeps.
//! [Paper eqs. (19)–(24)]
//!
//! reduced model (shared builder) → BSQL problem (M, B, K, G, loads, gap friction) → state:
//! steady sliding equilibrium under preload + PMAX·brake load, or a restart file's state →
//! tangents D = ∂F_f/∂λ̇, C_f = ∂F_f/∂v ([`tangents`]) → `squeal_solver::cea::complex_eigen`
//! (constraint eliminated, no spurious roots) → `cea.json`, `stability_map.{png,svg}`,
//! `cea_modes.vtu` and `cea_modes_<component>.vtu` (unstable shapes), `summary.json`; with a sweep ([`sweep`]) also
//! `cea.sweep.json` and `root_locus*.{png,svg}`; with `--export-tangents`, `tangents.op4` and
//! `tangents.pch` ([`outputs`]).
//!
//! **Mode shapes.** `cea_modes.vtu` holds the shapes at the grid points of the reduced model
//! (every boundary/interface grid: contact nodes, joints). For a model built from meshes the
//! builder also keeps each component's mesh, DOF map and Craig–Bampton model, and
//! `cea_modes_<component>.vtu` holds the shapes expanded to the full mesh ([`shapes`]);
//! stored reduced matrices (OP4/punch) have no mesh, so only the grid-point file is written.

pub mod outputs;
pub mod shapes;
pub mod sweep;
pub mod tangents;

use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{CeaSpec, Scene};
use crate::stages::model;
use crate::stages::transient::system;
use serde::Serialize;
use squeal_solver::cea::{complex_eigen, CeaStats, Mode};
use std::time::Instant;
use tangents::{ContactSummary, StateSource};

type Real = f64;

/// What the command line adds to the scene.
#[derive(Debug, Clone, Default)]
pub struct CeaArgs {
    /// `--mu a:b:n`: a sweep over these values (overrides `[cea] sweep`'s values).
    pub mu: Option<(Real, Real, usize)>,
    /// `--export-tangents`: write `tangents.op4` and `tangents.pch`.
    pub export_tangents: bool,
    /// `--cache DIR`: read/store the reduced model in this cache ([`model::ModelCache`]).
    pub cache: Option<model::ModelCache>,
}

/// One mode in `cea.json`.
#[derive(Debug, Clone, Serialize)]
pub struct ModeOut {
    /// Index in the reported list (the VTU arrays are `mode{index}_re/_im`).
    pub index: usize,
    pub frequency_hz: Real,
    pub real_part: Real,
    /// ζ = −2 Re p/|Im p| (null for a real root).
    pub damping_ratio: Option<Real>,
    pub unstable: bool,
}

/// The state used, in `cea.json`.
#[derive(Debug, Clone, Serialize)]
pub struct StateOut {
    pub source: StateSource,
    pub contact: ContactSummary,
    /// Largest |u| and |v| of the state.
    pub max_abs_displacement: Real,
    pub max_abs_velocity: Real,
}

/// `cea.json`.
#[derive(Debug, Clone, Serialize)]
pub struct CeaOut {
    pub verb: &'static str,
    pub version: &'static str,
    pub friction_law: squeal_contact::FrictionLaw,
    pub friction_damping: bool,
    pub max_frequency_hz: Option<Real>,
    pub steady_state: StateOut,
    /// Modes sorted by frequency (up to `max_frequency_hz`).
    pub modes: Vec<ModeOut>,
    /// Indices (into `modes`) of the unstable modes, most unstable first.
    pub unstable: Vec<usize>,
    pub stats: CeaStats,
}

/// `summary.json` of `squeal cea`.
#[derive(Debug, Clone, Serialize)]
pub struct CeaReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub wall_s: Real,
    pub n_dofs: usize,
    pub n_gaps: usize,
    pub n_modes_reported: usize,
    pub n_unstable: usize,
    /// Largest Re p among the reported modes.
    pub max_real_part: Option<Real>,
    /// Frequency of the mode with the largest Re p.
    pub max_real_part_frequency_hz: Option<Real>,
    /// Smallest damping ratio ζ among the reported modes (negative: unstable).
    pub min_damping_ratio: Option<Real>,
    /// The unstable modes, most unstable first.
    pub unstable_modes: Vec<ModeOut>,
    pub cea_stats: CeaStats,
    pub sweep_stats: Option<squeal_solver::cea::SweepStats>,
    pub lowest_critical_mu: Option<Real>,
    /// Points of `cea_modes.vtu` (0: not written).
    pub vtu_points: usize,
    /// Full-mesh mode-shape files `cea_modes_<component>.vtu` (empty: stored matrices).
    pub full_mesh_shapes: Vec<String>,
    pub mode_shapes_note: &'static str,
    pub files: Vec<String>,
    pub model_hash: String,
    /// How the reduced model came through the cache (`--cache` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_cache: Option<model::CacheUse>,
    /// Inputs accepted with a measured value to know about ([`crate::warning`]).
    pub warnings: Vec<crate::warning::Warning>,
}

fn cea_err(what: &str) -> impl FnOnce(squeal_solver::cea::CeaError) -> PipelineError + '_ {
    move |source| PipelineError::Cea {
        what: what.to_string(),
        source,
    }
}

const SHAPES_NOTE: &str = "cea_modes.vtu: mode shapes at the grid points of the reduced model \
(contact and interface grids); cea_modes_<component>.vtu: the shapes recovered with each \
component's Craig-Bampton transformation on its full mesh (models built from meshes only)";

/// Runs `squeal cea`: builds the reduced model (through `args.cache` when given) and
/// [`run_on_model`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    args: &CeaArgs,
) -> Result<CeaReport, PipelineError> {
    let wall = Instant::now();
    spec_of(scene, args)?;
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (model, cache_use) = model::build_cached(scene, dir, progress, args.cache.as_ref())?;
    run_on_model(scene, dir, progress, args, model, cache_use, wall)
}

/// The `[cea]` table with the command line's sweep applied, validated.
fn spec_of(scene: &Scene, args: &CeaArgs) -> Result<CeaSpec, PipelineError> {
    let mut spec: CeaSpec = match (&scene.cea, args.mu) {
        (Some(c), _) => c.clone(),
        (None, Some(_)) => CeaSpec::default(),
        (None, None) => {
            return Err(PipelineError::Scene {
                field: "cea".into(),
                message: "the scene asks for no complex eigenvalue analysis: add a `[cea]` \
                          table (e.g. `[cea]` alone for the defaults), or ask for a friction \
                          sweep with `squeal cea SCENE --mu FIRST:LAST:COUNT`"
                    .into(),
            })
        }
    };
    if let Some(mu) = args.mu {
        let mut sw = spec.sweep.clone().unwrap_or_default();
        sw.mu = Some(mu);
        sw.mu_values.clear();
        spec.sweep = Some(sw);
    }
    spec.validate()?;
    Ok(spec)
}

/// `squeal cea` on a reduced model already built for `scene` (`wall`: when the run started;
/// `cache_use`: reported in `summary.json`).
pub fn run_on_model(
    scene: &Scene,
    dir: &RunDir,
    progress: Progress,
    args: &CeaArgs,
    model: model::ReducedModel,
    cache_use: Option<model::CacheUse>,
    wall: Instant,
) -> Result<CeaReport, PipelineError> {
    let spec = spec_of(scene, args)?;
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let problem = system::problem(scene, &model)?;
    let gaps = &model.gaps;
    let (n, ng) = (model.n(), gaps.len());
    let mut files = Vec::new();

    let step = progress.step("linearising about the sliding state");
    let lin = tangents::linearise(scene, &spec, &problem, gaps)?;
    step.done("tangents at the state");
    let contact = tangents::contact_summary(gaps, &lin)?;
    let sys = tangents::cea_matrices(&problem, &lin, spec.friction_damping);
    let step = progress.step(format!("complex eigenvalues ({n} DOFs, {ng} constraints)"));
    let res = complex_eigen(&sys, &spec.solver).map_err(cea_err("complex eigenvalues"))?;
    step.done(format!(
        "{} modes, {} unstable",
        res.stats.n_modes, res.stats.n_unstable
    ));
    let fmax = spec.max_frequency_hz.unwrap_or(Real::INFINITY);
    let kept: Vec<&Mode> = res
        .modes
        .iter()
        .filter(|m| m.frequency_hz <= fmax)
        .collect();
    let modes: Vec<ModeOut> = kept
        .iter()
        .enumerate()
        .map(|(i, m)| ModeOut {
            index: i,
            frequency_hz: m.frequency_hz,
            real_part: m.real_part,
            damping_ratio: m.damping_ratio,
            unstable: m.unstable,
        })
        .collect();
    let mut unstable: Vec<usize> = modes
        .iter()
        .filter(|m| m.unstable)
        .map(|m| m.index)
        .collect();
    unstable.sort_by(|&a, &b| modes[b].real_part.total_cmp(&modes[a].real_part));
    let amax = |x: &[Real]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let out = CeaOut {
        verb: "cea",
        version: crate::VERSION,
        friction_law: gaps.law.clone(),
        friction_damping: spec.friction_damping,
        max_frequency_hz: spec.max_frequency_hz,
        steady_state: StateOut {
            source: lin.source.clone(),
            contact,
            max_abs_displacement: amax(&lin.u),
            max_abs_velocity: amax(&lin.v),
        },
        modes: modes.clone(),
        unstable: unstable.clone(),
        stats: res.stats.clone(),
    };
    files.push(dir.write_json("cea.json", &out)?.display().to_string());
    if let Some(stem) = outputs::write_stability_map(
        dir,
        &kept,
        &format!("Stability map ({} unstable)", unstable.len()),
    )? {
        files.push(format!("{stem}.png"));
        files.push(format!("{stem}.svg"));
    }
    let shown: Vec<(usize, &Mode)> = unstable
        .iter()
        .take(spec.max_shapes)
        .map(|&i| (i, kept[i]))
        .collect();
    let vtu_points = outputs::write_mode_shapes(dir, &model, &shown)?;
    if vtu_points > 0 {
        files.push(dir.path("cea_modes.vtu").display().to_string());
    }
    let full_mesh_shapes = shapes::write_full_mode_shapes(dir, &model, &shown)?;
    files.extend(full_mesh_shapes.iter().cloned());
    if args.export_tangents {
        files.extend(outputs::export_tangents(dir, &model, &problem, &lin)?);
    }

    let mut sweep_stats = None;
    let mut lowest_critical_mu = None;
    if let Some(sw) = &spec.sweep {
        let values = sw.values()?;
        let step = progress.step(format!("friction sweep over {} values", values.len()));
        let (_, rep) = sweep::run_sweep(&problem, gaps, &lin, &spec, sw, &values)?;
        step.done(format!(
            "{} tracks, lowest critical mu {:?}",
            rep.tracks.len(),
            rep.lowest_critical_mu
        ));
        files.push(
            dir.write_json("cea.sweep.json", &rep)?
                .display()
                .to_string(),
        );
        for stem in outputs::write_root_locus(dir, &rep)? {
            files.push(format!("{stem}.png"));
            files.push(format!("{stem}.svg"));
        }
        lowest_critical_mu = rep.lowest_critical_mu;
        sweep_stats = Some(rep.stats.clone());
    }

    let report = CeaReport {
        verb: "cea",
        version: crate::VERSION,
        wall_s: wall.elapsed().as_secs_f64(),
        n_dofs: n,
        n_gaps: ng,
        n_modes_reported: modes.len(),
        n_unstable: unstable.len(),
        max_real_part: modes.iter().map(|m| m.real_part).reduce(f64::max),
        max_real_part_frequency_hz: modes
            .iter()
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part))
            .map(|m| m.frequency_hz),
        min_damping_ratio: modes
            .iter()
            .filter_map(|m| m.damping_ratio)
            .reduce(f64::min),
        unstable_modes: unstable.iter().map(|&i| modes[i].clone()).collect(),
        cea_stats: res.stats,
        sweep_stats,
        lowest_critical_mu,
        vtu_points,
        full_mesh_shapes,
        mode_shapes_note: SHAPES_NOTE,
        files,
        model_hash: problem.model_hash(),
        model_cache: cache_use,
        warnings: model.warnings.clone(),
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}
