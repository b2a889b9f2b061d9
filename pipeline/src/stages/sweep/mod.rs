//! `squeal sweep`: design iterations over one scene parameter.
//!
//! For every value v of `--param KEY`: the scene with `--set …` and `KEY=v` → the reduced model
//! through the model cache ([`crate::model::ModelCache`]: built only when the value
//! changes what meshing, FE and reduction see; μ, rpm, P0, PMAX, damping G/W3 and solver
//! options reuse the cached model) → CEA and/or the transient in `<out>/<NN>_<v>/{cea,transient}/`
//! → one row of `sweep.json` / `sweep.md` and a point of `sweep_indicators.{png,svg}` (the
//! largest CEA real part and the transient growth rate against the parameter) and
//! `sweep_frequencies.{png,svg}` (the unstable frequencies). A value whose build or analysis
//! fails (an error, or a transient that stops before TFINAL) is recorded with its error; the
//! others still run, every file is written, and the report counts the failed values
//! (`n_failed`, `failed`): `squeal sweep` then exits with [`EXIT_VALUES_FAILED`].

pub mod outputs;
pub use crate::scene::values;

use crate::error::PipelineError;
use crate::model::{self, ModelCache};
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use crate::stages::{cea, transient};
use serde::Serialize;
use std::path::{Path, PathBuf};
use std::time::Instant;

use squeal_solver::Real;

/// Exit status of `squeal sweep` when some values failed and the others' results are written
/// (0: every value ran; 1: an error stopped the sweep, or every value failed).
pub const EXIT_VALUES_FAILED: u8 = 3;

/// What each value runs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Analysis {
    /// Complex eigenvalues at the steady sliding state (cheap).
    #[default]
    Cea,
    /// The nonlinear transient.
    Transient,
    /// Both, on the same model.
    Both,
}

impl Analysis {
    /// `cea`, `transient` or `both`.
    pub fn parse(text: &str) -> Result<Analysis, PipelineError> {
        match text {
            "cea" => Ok(Analysis::Cea),
            "transient" => Ok(Analysis::Transient),
            "both" => Ok(Analysis::Both),
            _ => Err(PipelineError::Option {
                option: "--analysis".into(),
                message: format!("`{text}`: expected cea, transient or both"),
            }),
        }
    }
    fn cea(self) -> bool {
        self != Analysis::Transient
    }
}

/// What the command line gives.
#[derive(Debug, Clone, Default)]
pub struct SweepArgs {
    /// Dotted scene key, as `--set` writes it (`friction.law.mu`, `components.0.geometry.thickness`);
    /// several keys separated by commas are all set to each value.
    pub param: String,
    /// The values as TOML value texts ([`values::parse_values`]).
    pub values: Vec<String>,
    pub analysis: Analysis,
    /// Model cache folder (default: [`default_cache_dir`]).
    pub cache: Option<PathBuf>,
}

/// The default cache of a sweep writing into `out`: `.squeal-cache` beside it (`out/../`), so
/// sweeps into sibling folders share their models.
pub fn default_cache_dir(out: &Path) -> PathBuf {
    out.parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."))
        .join(".squeal-cache")
}

/// CEA results of one value (modes up to the scene's `cea.max_frequency_hz`).
#[derive(Debug, Clone, Serialize)]
pub struct CeaIndicators {
    pub max_frequency_hz: Option<Real>,
    pub n_unstable: usize,
    pub max_real_part: Option<Real>,
    pub max_real_part_frequency_hz: Option<Real>,
    pub min_damping_ratio: Option<Real>,
    /// From the scene's own `[cea] sweep`, if it has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lowest_critical_mu: Option<Real>,
    /// Most unstable first.
    pub unstable_modes: Vec<cea::ModeOut>,
}

/// Transient results of one value.
#[derive(Debug, Clone, Serialize)]
pub struct TransientIndicators {
    /// How the integration ended (`reached` or why it stopped).
    pub status: squeal_solver::bdf::Status,
    pub squeal: bool,
    /// `squeal`, `no_squeal`, or `unresolved` with its reasons.
    pub verdict: crate::verdict::guard::VerdictState,
    pub growth_rate_per_s: Option<Real>,
    pub dominant_frequency_hz: Option<Real>,
    pub steps: u64,
    pub cpu_s: Real,
    pub t_end: Real,
}

/// One value of the sweep (an object of `sweep.json`).
#[derive(Debug, Clone, Serialize)]
pub struct SweepPoint {
    pub index: usize,
    /// The value (number, string, …).
    pub value: serde_json::Value,
    /// The value as given.
    pub label: String,
    pub run_dir: String,
    /// True: model read from the cache; false: built; null: the build failed.
    pub cache_hit: Option<bool>,
    pub cache_key: Option<String>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cache_note: Option<String>,
    /// Seconds to build or read the reduced model.
    pub build_s: Real,
    /// Seconds of the analyses (CEA + transient).
    pub analysis_s: Real,
    pub cea: Option<CeaIndicators>,
    pub transient: Option<TransientIndicators>,
    /// Why this value has no (or partial) results.
    pub error: Option<String>,
    /// The warnings of its model and analyses (also in their `summary.json`).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub warnings: Vec<crate::warning::Warning>,
}

/// `sweep.json` and `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct SweepReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub scene: String,
    pub param: String,
    pub analysis: Analysis,
    pub cache_dir: String,
    /// Values whose model was built / read from the cache.
    pub n_built: usize,
    pub n_cached: usize,
    pub wall_s: Real,
    /// Values that failed ([`SweepPoint::failed`]), and their labels.
    pub n_failed: usize,
    pub failed: Vec<String>,
    pub points: Vec<SweepPoint>,
    pub files: Vec<String>,
}

impl SweepPoint {
    /// The value has an error, or its transient stopped before TFINAL.
    pub fn failed(&self) -> bool {
        self.error.is_some()
            || self
                .transient
                .as_ref()
                .is_some_and(|t| !t.status.is_success())
    }
}

impl SweepReport {
    /// The command's exit status: 0, or [`EXIT_VALUES_FAILED`] when a value failed.
    pub fn exit_code(&self) -> u8 {
        if self.n_failed > 0 {
            EXIT_VALUES_FAILED
        } else {
            0
        }
    }
}

/// A folder name for value `label`: `NN_<label>` with only `[A-Za-z0-9._-]`.
fn value_dir(index: usize, label: &str) -> String {
    let clean: String = label
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || matches!(c, '.' | '-' | '_') {
                c
            } else {
                '_'
            }
        })
        .take(40)
        .collect();
    format!("{index:02}_{clean}")
}

/// Runs the sweep into `dir`.
pub fn run(
    base: &Scene,
    scene_name: &str,
    dir: &RunDir,
    progress: &Progress,
    args: &SweepArgs,
) -> Result<SweepReport, PipelineError> {
    let wall = Instant::now();
    // Every value's scene, checked before anything runs.
    let mut scenes = Vec::with_capacity(args.values.len());
    for v in &args.values {
        // `--param a,b`: keys set together to each value (e.g. both pads' `rotate_deg`).
        let keys: Vec<(String, String)> = args
            .param
            .split(',')
            .map(|k| (k.trim().to_string(), v.clone()))
            .collect();
        let mut s = values::scene_for_all(base, &keys)?;
        if args.analysis.cea() && s.cea.is_none() {
            s.cea = Some(Default::default());
        }
        scenes.push(s);
    }
    if scenes.is_empty() {
        return Err(PipelineError::Option {
            option: "--values".into(),
            message: "no values to sweep".into(),
        });
    }
    let cache = ModelCache::new(
        args.cache
            .clone()
            .unwrap_or_else(|| default_cache_dir(&dir.root)),
    );
    dir.write_bytes("scene.resolved.toml", base.resolved_toml().as_bytes())?;
    progress.info(format!(
        "sweep: {} = {} ({} values, {:?}), cache {}",
        args.param,
        args.values.join(", "),
        args.values.len(),
        args.analysis,
        cache.root.display()
    ));
    let quiet = progress.silenced();
    let mut points = Vec::with_capacity(scenes.len());
    for (i, (label, scene)) in args.values.iter().zip(&scenes).enumerate() {
        progress.check("sweep")?;
        let vdir = RunDir::create(&dir.path(&value_dir(i, label)))?;
        let p = run_value(i, label, scene, &vdir, &cache, args.analysis, &quiet)?;
        progress.info(outputs::progress_line(&args.param, &p));
        points.push(p);
    }
    let n_built = points.iter().filter(|p| p.cache_hit == Some(false)).count();
    let n_cached = points.iter().filter(|p| p.cache_hit == Some(true)).count();
    let failed: Vec<String> = points
        .iter()
        .filter(|p| p.failed())
        .map(|p| p.label.clone())
        .collect();
    let mut report = SweepReport {
        verb: "sweep",
        version: crate::VERSION,
        scene: scene_name.to_string(),
        param: args.param.clone(),
        analysis: args.analysis,
        cache_dir: cache.root.display().to_string(),
        n_built,
        n_cached,
        wall_s: 0.0,
        n_failed: failed.len(),
        failed,
        points,
        files: Vec::new(),
    };
    report.files = outputs::write(dir, &report)?;
    report.wall_s = wall.elapsed().as_secs_f64();
    dir.write_json("sweep.json", &report)?;
    dir.write_json("summary.json", &report)?;
    if report.points.iter().all(|p| p.error.is_some()) {
        return Err(PipelineError::Model(format!(
            "every value of the sweep failed; first error: {}",
            report.points[0].error.as_deref().unwrap_or("")
        )));
    }
    Ok(report)
}

/// Builds (or reads through `cache`) the model of one value's `scene` (as
/// [`values::scene_for`] makes it) and runs the analyses with their files in `vdir`; failures
/// are recorded in the point, and only a cancellation (Ctrl-C) is returned as an error. The
/// Python package runs a sweep's values as separate tasks (threads or Dask workers) through
/// this.
pub fn run_value(
    index: usize,
    label: &str,
    scene: &Scene,
    vdir: &RunDir,
    cache: &ModelCache,
    analysis: Analysis,
    quiet: &Progress,
) -> Result<SweepPoint, PipelineError> {
    let mut p = SweepPoint {
        index,
        value: values::value_json(label),
        label: label.to_string(),
        run_dir: vdir.root.display().to_string(),
        cache_hit: None,
        cache_key: None,
        cache_note: None,
        build_s: 0.0,
        analysis_s: 0.0,
        cea: None,
        transient: None,
        error: None,
        warnings: Vec::new(),
    };
    let t0 = Instant::now();
    let built = model::build_cached(scene, vdir, quiet, Some(cache));
    p.build_s = t0.elapsed().as_secs_f64();
    let model = match built {
        Ok((m, u)) => {
            if let Some(u) = u {
                p.cache_hit = Some(u.hit);
                p.cache_key = Some(u.key);
                p.cache_note = u.note;
            }
            m
        }
        Err(e) if e.is_cancelled() => return Err(e),
        Err(e) => {
            p.error = Some(format!("model: {e}"));
            return Ok(p);
        }
    };
    let (for_cea, for_transient) = match analysis {
        Analysis::Cea => (Some(model), None),
        Analysis::Transient => (None, Some(model)),
        Analysis::Both => (Some(model.clone()), Some(model)),
    };
    let mut errors = Vec::new();
    let t1 = Instant::now();
    if let Some(m) = for_cea {
        let args = cea::CeaArgs::default();
        let r = RunDir::create(&vdir.path("cea"))
            .and_then(|d| cea::run_on_model(scene, &d, quiet, &args, m, None, Instant::now()));
        match r {
            Ok(r) => {
                p.warnings.extend(r.warnings.iter().cloned());
                p.cea = Some(CeaIndicators {
                    max_frequency_hz: scene.cea.as_ref().and_then(|c| c.max_frequency_hz),
                    n_unstable: r.n_unstable,
                    max_real_part: r.max_real_part,
                    max_real_part_frequency_hz: r.max_real_part_frequency_hz,
                    min_damping_ratio: r.min_damping_ratio,
                    lowest_critical_mu: r.lowest_critical_mu,
                    unstable_modes: r.unstable_modes,
                })
            }
            Err(e) if e.is_cancelled() => return Err(e),
            Err(e) => errors.push(format!("cea: {e}")),
        }
    }
    if let Some(m) = for_transient {
        let r = RunDir::create(&vdir.path("transient")).and_then(|d| {
            transient::run_on_model(
                scene,
                &d,
                quiet,
                None,
                &m,
                Instant::now(),
                &Default::default(),
            )
        });
        match r {
            Ok(r) => {
                let r = r.result;
                for w in &r.warnings {
                    if !p.warnings.contains(w) {
                        p.warnings.push(w.clone());
                    }
                }
                p.transient = Some(TransientIndicators {
                    status: r.status,
                    squeal: r.squeal,
                    verdict: r.verdict.state.clone(),
                    growth_rate_per_s: r.growth_rate_per_s,
                    dominant_frequency_hz: r.dominant_frequency_hz,
                    steps: r.steps,
                    cpu_s: r.cpu_s,
                    t_end: r.t_end,
                })
            }
            Err(e) if e.is_cancelled() => return Err(e),
            Err(e) => errors.push(format!("transient: {e}")),
        }
    }
    p.analysis_s = t1.elapsed().as_secs_f64();
    if !errors.is_empty() {
        p.error = Some(errors.join("; "));
    }
    Ok(p)
}
