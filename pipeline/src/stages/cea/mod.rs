//! `squeal cea`: complex eigenvalue analysis about a steady sliding state, and friction sweeps.
//! [Paper eqs. (19)–(24)]
//!
//! reduced model (shared builder) → BSQL problem (M, B, K, G, loads, gap friction) → state:
//! steady sliding equilibrium under preload + PMAX·brake load, or a restart file's state →
//! tangents D = ∂F_f/∂λ̇, C_f = ∂F_f/∂v ([`tangents`]) → `squeal_solver::cea::complex_eigen`
//! (constraint eliminated, no spurious roots) → `cea.json`, `stability_map.{png,svg}`,
//! `cea_modes.vtu` and `cea_modes_<component>.vtu` (unstable shapes), `summary.json`; the
//! energy balance of every root in `cea.json` ([`energy`]) with `energy_mode<k>.{png,svg}`
//! and `cea_feed_in.vtu` for the unstable modes ([`insight_files`]); with a sweep ([`sweep`])
//! also `cea.sweep.json` (branches and their coalescence/veering events), `root_locus*` and
//! `mode_coupling*.{png,svg}`; with `--export-tangents`, `tangents.op4` and
//! `tangents.pch` ([`outputs`]).
//!
//! **Mode shapes.** `cea_modes.vtu` holds the shapes at the grid points of the reduced model
//! (every boundary/interface grid: contact nodes, joints). For a model built from meshes the
//! builder also keeps each component's mesh, DOF map and Craig–Bampton model, and
//! `cea_modes_<component>.vtu` holds the shapes expanded to the full mesh ([`shapes`]);
//! stored reduced matrices (OP4/punch) have no mesh, so only the grid-point file is written.

pub mod animation;
pub mod energy;
pub mod insight_files;
pub mod outputs;
pub mod params;
pub mod sensitivity;
pub mod shapes;
pub mod steady;
pub mod sweep;
pub mod volume;
pub use crate::problem::tangents;

use crate::error::PipelineError;
use crate::model;
use crate::output::RunDir;
use crate::problem::{linear, system};
use crate::progress::Progress;
use crate::scene::{CeaSpec, Scene};
use serde::Serialize;
use squeal_solver::cea::{CeaStats, Mode};
use std::time::Instant;
use tangents::{ContactSummary, StateSource};

use squeal_solver::Real;

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

/// Roots above the validity band (the band the model was reduced for, or
/// `cea.max_frequency_hz` if lower): outside what the reduced model represents — e.g. the
/// flutter of the interface modes of rigid contact at the mesh scale — so never squeal.
#[derive(Debug, Clone, Serialize)]
pub struct OutsideBand {
    /// The band's top (None: no band known, nothing is outside).
    pub band_hz: Option<Real>,
    /// Roots above it.
    pub count: usize,
    pub n_unstable: usize,
    /// Roots were computed up to about this frequency (the projection basis' highest
    /// undamped frequency); None: every root was computed (the exact method).
    pub computed_up_to_hz: Option<Real>,
    /// Highest frequency among them.
    pub max_frequency_hz: Option<Real>,
    /// Highest frequency among the unstable ones (the top of the interface flutter of rigid
    /// contact with friction, docs/interface-flutter.md).
    pub max_unstable_frequency_hz: Option<Real>,
    /// The most unstable of them (at most [`OutsideBand::LISTED`]).
    pub unstable: Vec<RootOut>,
}

/// A root above the band (not in the reported list, so without an index).
#[derive(Debug, Clone, Serialize)]
pub struct RootOut {
    pub frequency_hz: Real,
    pub real_part: Real,
    /// ζ = −2 Re p/|Im p| (null for a real root).
    pub damping_ratio: Option<Real>,
}

impl OutsideBand {
    /// Unstable roots listed.
    pub const LISTED: usize = 20;
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
    /// Roots above the validity band, apart.
    pub outside_band: OutsideBand,
    pub stats: CeaStats,
    /// Energy balance of each reported root ([`energy`]).
    pub energy: energy::EnergyOut,
    /// Sensitivities of the roots to the design parameters ([`sensitivity`]; None with
    /// `[cea] sensitivity = false`).
    pub sensitivity: Option<sensitivity::SensitivityOut>,
    /// Per interface-reduced component (`[components.interface]`): its degree and the error
    /// estimate of these roots (`model/degree.rs`); empty without interface reduction.
    pub interface_reduction: Vec<InterfaceOut>,
}

/// One interface-reduced component in `cea.json`.
#[derive(Debug, Clone, Serialize)]
pub struct InterfaceOut {
    pub component: String,
    #[serde(flatten)]
    pub choice: crate::model::InterfaceChoice,
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
    /// Gaps in tension (p_n < 0) at the linearisation's state: held closed by the bilateral
    /// contact, so the roots are those of a contact the brake would not keep (a warning too).
    pub n_tensile_gaps: usize,
    /// Their smallest p_n, Pa (None: no gap).
    pub min_contact_pressure: Option<Real>,
    /// Largest Re p among the reported modes.
    pub max_real_part: Option<Real>,
    /// Frequency of the mode with the largest Re p.
    pub max_real_part_frequency_hz: Option<Real>,
    /// Smallest damping ratio ζ among the reported modes (negative: unstable).
    pub min_damping_ratio: Option<Real>,
    /// The unstable modes in the band, most unstable first.
    pub unstable_modes: Vec<ModeOut>,
    /// Roots above the validity band (never squeal).
    pub outside_band: OutsideBand,
    pub cea_stats: CeaStats,
    pub sweep_stats: Option<squeal_solver::cea::SweepStats>,
    pub lowest_critical_mu: Option<Real>,
    /// The lowest critical μ of a mode in the validity band (with a sweep and a band).
    pub lowest_critical_mu_in_band: Option<Real>,
    /// How it was found (`exact_sweep`, `exact_crossing`, `projected_not_confirmed`,
    /// `projected`).
    pub lowest_critical_mu_in_band_status: Option<sweep::CriticalStatus>,
    /// Points of `cea_modes.vtu` (0: not written).
    pub vtu_points: usize,
    /// Full-mesh mode-shape files `cea_modes_<component>.vtu` (empty: stored matrices).
    pub full_mesh_shapes: Vec<String>,
    /// `cea_modes.pvd`: the unstable shapes of every component animated over the phase
    /// (`cea.phase_frames` frames in `cea_modes_phase/`; None: no shapes or no mesh).
    pub mode_animation: Option<String>,
    /// `mode_shape_rotor.png`: the most unstable mode on the rotor's friction face (None: no
    /// shape, no mesh, or built without the `figures` feature).
    pub rotor_face_figure: Option<String>,
    pub mode_shapes_note: &'static str,
    pub files: Vec<String>,
    pub model_hash: String,
    /// How the reduced model came through the cache (`--cache` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub model_cache: Option<model::CacheUse>,
    /// The friction sweep, in memory (written to `cea.sweep.json`).
    #[serde(skip)]
    pub sweep: Option<sweep::SweepReport>,
    /// Inputs accepted with a measured value to know about ([`crate::warning`]).
    pub warnings: Vec<crate::warning::Warning>,
}

const SHAPES_NOTE: &str = "cea_modes.vtu: mode shapes at the grid points of the reduced model \
(contact and interface grids); cea_modes_<component>.vtu: the shapes recovered with each \
component's Craig-Bampton transformation on its full mesh (models built from meshes only); \
cea_modes.pvd: those shapes animated over the phase, Re(u e^(i theta)) for theta in [0, 2 pi) \
(ParaView: open the .pvd, Warp By Vector on a mode array, play); mode_shape_rotor.png: the \
most unstable mode's out-of-plane displacement on the rotor friction face";

pub use crate::problem::linear::banded;

/// Runs `squeal cea`: builds the reduced model (through `args.cache` when given) and
/// [`run_on_model`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
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

/// What the CEA of a scene found, in memory: the state, the modes (eigenvalues and shapes on
/// the reduced DOFs) up to `max_frequency_hz`, and the friction sweep's tracks.
pub struct CeaComputed {
    /// The `[cea]` table as run (command-line sweep applied).
    pub spec: CeaSpec,
    /// The problem linearised (M, B, K, G, loads).
    pub problem: system::Problem,
    /// The state and tangents.
    pub lin: tangents::Linearisation,
    /// Modes up to `max_frequency_hz`, sorted by frequency; `shape` holds the reduced
    /// eigenvector (length n).
    pub modes: Vec<Mode>,
    /// `cea.json`'s content.
    pub out: CeaOut,
    /// The friction sweep (when asked for).
    pub sweep: Option<sweep::SweepReport>,
    /// (component, face set) of the first contact pair's rotor friction face: where
    /// `mode_shape_rotor.png` draws the most unstable mode.
    pub rotor_face: Option<(String, String)>,
}

impl CeaComputed {
    /// The unstable modes, most unstable first, as (index into `modes`, mode).
    pub fn unstable(&self) -> Vec<(usize, &Mode)> {
        self.out
            .unstable
            .iter()
            .map(|&i| (i, &self.modes[i]))
            .collect()
    }

    /// Each component's full-mesh shape of the modes `which` (indices into `modes`): meshed
    /// models only (stored matrices have no mesh: empty).
    pub fn recover_shapes(
        &self,
        model: &model::ReducedModel,
        which: &[usize],
    ) -> Result<Vec<shapes::ComponentShapes>, PipelineError> {
        let modes: Vec<(usize, &Mode)> = which.iter().map(|&i| (i, &self.modes[i])).collect();
        shapes::recover(model, &modes)
    }
}

/// The complex eigenvalue analysis of `scene` on `model` (and its friction sweep), in memory.
pub fn compute(
    scene: &Scene,
    model: &model::ReducedModel,
    progress: &Progress,
    args: &CeaArgs,
) -> Result<CeaComputed, PipelineError> {
    let mut spec = spec_of(scene, args)?;
    // Ctrl-C reaches inside the eigen-solves, the sweep's points and refinements.
    spec.solver.interrupt = progress.solver_interrupt();
    let problem = system::problem(scene, model)?;
    let gaps = &problem.gaps;
    let (n, ng) = (model.n(), gaps.len());
    let linear::Roots {
        lin,
        contact,
        sys,
        band_hz,
        solver,
        kept,
        above,
        stats,
        ..
    } = linear::roots(scene, &spec, &problem, model, progress)?;
    let mut above_unstable: Vec<RootOut> = above
        .iter()
        .filter(|m| m.unstable)
        .map(|m| RootOut {
            frequency_hz: m.frequency_hz,
            real_part: m.real_part,
            damping_ratio: m.damping_ratio,
        })
        .collect();
    above_unstable.sort_by(|a, b| b.real_part.total_cmp(&a.real_part));
    let outside_band = OutsideBand {
        band_hz,
        computed_up_to_hz: stats.basis_max_frequency_hz,
        count: above.len(),
        n_unstable: above_unstable.len(),
        max_frequency_hz: above.iter().map(|m| m.frequency_hz).reduce(Real::max),
        max_unstable_frequency_hz: above_unstable
            .iter()
            .map(|m| m.frequency_hz)
            .reduce(Real::max),
        unstable: above_unstable
            .into_iter()
            .take(OutsideBand::LISTED)
            .collect(),
    };
    let modes_out: Vec<ModeOut> = kept
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
    let mut unstable: Vec<usize> = modes_out
        .iter()
        .filter(|m| m.unstable)
        .map(|m| m.index)
        .collect();
    unstable.sort_by(|&a, &b| modes_out[b].real_part.total_cmp(&modes_out[a].real_part));
    let amax = |x: &[Real]| x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    let step = progress.step(format!("energy balance of {} roots", kept.len()));
    let energy = energy::energies(
        scene,
        model,
        &problem,
        &lin,
        &sys,
        spec.friction_damping,
        &kept,
    )?;
    step.done(format!(
        "identity closes to {:.1e} (eigen-equation residual {:.1e})",
        energy.max_identity_residual, energy.max_eigen_residual
    ));
    let sens = if spec.sensitivity {
        progress.check("cea sensitivities")?;
        let step = progress.step("sensitivities of the roots to the design parameters");
        let base = params::Base {
            scene,
            model,
            problem: &problem,
            lin: &lin,
            spec: &spec,
        };
        let s = sensitivity::sensitivities(&base, &sys, &kept, &unstable)?;
        step.done(format!(
            "{} roots x {} parameters ({} steady states, {:.2} s: eigenvectors {:.2} s, \
             matrix derivatives {:.2} s, products {:.2} s)",
            s.roots.len(),
            s.parameters.len(),
            s.n_state_solves,
            s.time_s,
            s.time_triplets_s,
            s.time_derivatives_s,
            s.time_products_s
        ));
        Some(s)
    } else {
        None
    };
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
        modes: modes_out,
        unstable,
        outside_band,
        stats,
        energy,
        sensitivity: sens,
        interface_reduction: model
            .components
            .iter()
            .filter_map(|c| {
                c.interface.clone().map(|choice| InterfaceOut {
                    component: c.name.clone(),
                    choice,
                })
            })
            .collect(),
    };
    let mut sweep_rep = None;
    if let Some(sw) = &spec.sweep {
        progress.check("cea sweep")?;
        let values = sw.values()?;
        let step = progress.step(format!("friction sweep over {} values", values.len()));
        // Large models sweep on the band-limited basis (small ones stay exact, as before).
        let big = n.saturating_sub(ng) > spec.solver.projection.auto_single_min_dofs;
        let swept = CeaSpec {
            solver: if big {
                solver.clone()
            } else {
                spec.solver.clone()
            },
            ..spec.clone()
        };
        let (_, rep) = sweep::run_sweep(&problem, &lin, &swept, sw, &values, band_hz)?;
        step.done(format!(
            "{} tracks, lowest critical mu {:?}",
            rep.tracks.len(),
            rep.lowest_critical_mu
        ));
        sweep_rep = Some(rep);
    }
    Ok(CeaComputed {
        spec,
        problem,
        lin,
        modes: kept,
        out,
        sweep: sweep_rep,
        rotor_face: scene
            .contact
            .first()
            .map(|p| (p.rotor.clone(), p.rotor_faces.clone())),
    })
}

/// `squeal cea` on a reduced model already built for `scene`: [`compute`], then the files
/// (`wall`: when the run started; `cache_use`: reported in `summary.json`).
pub fn run_on_model(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    args: &CeaArgs,
    model: model::ReducedModel,
    cache_use: Option<model::CacheUse>,
    wall: Instant,
) -> Result<CeaReport, PipelineError> {
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let c = compute(scene, &model, progress, args)?;
    write(&c, &model, dir, args, cache_use, wall)
}

/// Writes what [`compute`] found into `dir`: `cea.json`, `stability_map.{png,svg}`,
/// `cea_modes.vtu`, `cea_modes_<component>.vtu`, optionally `tangents.{op4,pch}`, and with a
/// sweep `cea.sweep.json` and `root_locus*.{png,svg}`; then `summary.json`.
pub fn write(
    c: &CeaComputed,
    model: &model::ReducedModel,
    dir: &RunDir,
    args: &CeaArgs,
    cache_use: Option<model::CacheUse>,
    wall: Instant,
) -> Result<CeaReport, PipelineError> {
    let (n, ng) = (model.n(), model.gap_geometry.len());
    let (modes, unstable) = (&c.out.modes, &c.out.unstable);
    let mut files = Vec::new();
    files.push(dir.write_json("cea.json", &c.out)?.display().to_string());
    let kept: Vec<&Mode> = c.modes.iter().collect();
    if let Some(stem) = outputs::write_stability_map(
        dir,
        &kept,
        c.out.outside_band.band_hz,
        &format!("Stability map ({} unstable)", unstable.len()),
    )? {
        files.push(format!("{stem}.png"));
        files.push(format!("{stem}.svg"));
    }
    let shown: Vec<(usize, &Mode)> = unstable
        .iter()
        .take(c.spec.max_shapes)
        .map(|&i| (i, kept[i]))
        .collect();
    let vtu_points = outputs::write_mode_shapes(dir, model, &shown)?;
    if vtu_points > 0 {
        files.push(dir.path("cea_modes.vtu").display().to_string());
    }
    let comp_shapes = shapes::recover(model, &shown)?;
    let full_mesh_shapes = shapes::write_full_mode_shapes(dir, model, &comp_shapes)?;
    files.extend(full_mesh_shapes.iter().cloned());
    let mode_animation =
        animation::write_phase_animation(dir, model, &comp_shapes, c.spec.phase_frames)?;
    files.extend(mode_animation.iter().cloned());
    let rotor_face_figure = match shown.first() {
        Some((k, m)) => animation::write_face_figure(
            dir,
            model,
            &comp_shapes,
            c.rotor_face.as_ref().map(|(a, b)| (a.as_str(), b.as_str())),
            &format!(
                "Most unstable mode {k}: {:.1} Hz, Re p = {:+.1} /s (rotor face {})",
                m.frequency_hz,
                m.real_part,
                c.rotor_face.as_ref().map_or("", |f| f.1.as_str())
            ),
        )?,
        None => None,
    };
    if let Some(stem) = &rotor_face_figure {
        files.push(format!("{stem}.png"));
        files.push(format!("{stem}.svg"));
    }
    // The energy balance of the unstable modes shown: component shares, feed-in map.
    let shown_idx: Vec<usize> = shown.iter().map(|(k, _)| *k).collect();
    for stem in insight_files::write_energy_bars(dir, &c.out.energy, &shown_idx)? {
        files.push(format!("{stem}.png"));
        files.push(format!("{stem}.svg"));
    }
    files.extend(insight_files::write_feed_in_vtu(
        dir,
        model,
        &c.out.energy,
        &shown_idx,
    )?);
    if let Some(s) = &c.out.sensitivity {
        files.extend(sensitivity::write_table(dir, s)?);
    }
    if args.export_tangents {
        files.extend(outputs::export_tangents(dir, model, &c.problem, &c.lin)?);
    }
    if let Some(rep) = &c.sweep {
        files.push(dir.write_json("cea.sweep.json", rep)?.display().to_string());
        for stem in outputs::write_root_locus(dir, rep)?
            .into_iter()
            .chain(insight_files::write_mode_coupling(dir, rep)?)
        {
            files.push(format!("{stem}.png"));
            files.push(format!("{stem}.svg"));
        }
    }
    let contact = &c.out.steady_state.contact;
    let min_contact_pressure = (contact.n_gaps > 0).then_some(contact.min_pressure);
    let mut warnings = model.warnings.clone();
    if contact.n_tensile > 0 {
        warnings.push(crate::warning::Warning {
            input: "contact".into(),
            message: format!(
                "the CEA's state has {} of {} gaps in tension (smallest p_n {:.4e} Pa{}): the \
                 bilateral contact holds them closed, so the roots are those of a contact the \
                 brake would not keep (a transient with `separation = true` on the pairs shows \
                 what happens)",
                contact.n_tensile,
                contact.n_gaps,
                contact.min_pressure,
                match contact.tensile_pairs() {
                    v if v.is_empty() => String::new(),
                    v => format!("; {}", v.join(", ")),
                }
            ) + &non_sliding_note(&c.problem.op, contact),
            value: contact.min_pressure,
            tolerance: 0.0,
        });
    }
    let report = CeaReport {
        verb: "cea",
        version: crate::VERSION,
        wall_s: wall.elapsed().as_secs_f64(),
        n_dofs: n,
        n_gaps: ng,
        n_modes_reported: modes.len(),
        n_unstable: unstable.len(),
        n_tensile_gaps: contact.n_tensile,
        min_contact_pressure,
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
        outside_band: c.out.outside_band.clone(),
        cea_stats: c.out.stats.clone(),
        sweep_stats: c.sweep.as_ref().map(|r| r.stats.clone()),
        lowest_critical_mu: c.sweep.as_ref().and_then(|r| r.lowest_critical_mu),
        lowest_critical_mu_in_band: c.sweep.as_ref().and_then(|r| r.lowest_critical_mu_in_band),
        lowest_critical_mu_in_band_status: c
            .sweep
            .as_ref()
            .and_then(|r| r.lowest_critical_mu_in_band_status),
        vtu_points,
        full_mesh_shapes,
        // File names relative to the run folder (`files` has the paths): two runs of the same
        // scene in two folders have equal summaries (`squeal compare`).
        mode_animation: mode_animation.as_deref().map(run_relative),
        rotor_face_figure: rotor_face_figure.map(|s| run_relative(&format!("{s}.png"))),
        mode_shapes_note: SHAPES_NOTE,
        files,
        model_hash: c.problem.model_hash(),
        model_cache: cache_use,
        sweep: c.sweep.clone(),
        warnings,
    };
    dir.write_json("summary.json", &report)?;
    Ok(report)
}

/// The file name of an output path (the run folder's files are named in `files`).
fn run_relative(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map_or_else(|| path.to_string(), |f| f.to_string_lossy().into_owned())
}

/// The note on tensile gaps of pairs that do not slide (`sliding = "none"`): their friction
/// acts on the vibration's slip through the regularised law (eq. 5), about 0.68 μ p A / VTOL per unit slip
/// speed, which turns negative where p_n < 0: a friction that feeds energy in, whose real
/// roots with Re p > 0 (if any) are the bilateral constraint's, not the brake's.
fn non_sliding_note(op: &crate::problem::OperatingPoint, contact: &ContactSummary) -> String {
    let pairs: Vec<String> = contact
        .per_pair
        .iter()
        .enumerate()
        .filter(|(i, p)| {
            p.n_tensile > 0
                && op
                    .pairs
                    .get(*i)
                    .is_some_and(|c| c.sliding == crate::scene::Sliding::None)
        })
        .map(|(i, _)| format!("contact[{i}]"))
        .collect();
    if pairs.is_empty() {
        return String::new();
    }
    format!(
        "; on {} (sliding = \"none\") the friction's damping (about 0.68 μ p A / VTOL, paper eq. 5) is negative where \
         p_n < 0: real roots with Re p > 0 may come from it, not from the brake",
        pairs.join(", ")
    )
}
