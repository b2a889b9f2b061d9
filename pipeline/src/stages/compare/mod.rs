//! `squeal compare A B`: regression of one reduced model or run against another.
//!
//! Inputs ([`Input::detect`]): a scene (`.toml`: its model built or read), stored matrices
//! (`.op4`/`.pch` with `dofmap.json` and, if present, `gaps.json` beside it, or a `squeal
//! reduce` folder holding them), or a run folder (`summary.json`, and `cea.json` for a CEA
//! run). Two models are compared by ([`compute`]):
//!
//! - their DOF maps (the same DOFs, in any order: B is taken in A's order; else an error names
//!   the first DOF one lacks), the relative Frobenius difference ‖A − B‖/‖A‖ of KR, MR, BR and
//!   PBRAKE ([`modal::matrix_diffs`]);
//! - the undamped modes paired by MAC, with the relative frequency difference of each pair
//!   ([`modal::pair_modes`]);
//! - the CEA roots paired by frequency (Δf, Δ Re p), when both are scenes, or stored models
//!   with `CompareOptions::scene` giving the analysis settings.
//!
//! Two run folders are compared by their `summary.json` values side by side and their CEA
//! roots (`cea.json`). Every tolerance the options set is a [`Check`]; [`CompareReport::passed`]
//! is false when one fails, and `squeal compare` then exits [`EXIT_BEYOND_TOLERANCE`].
//! [`write`] writes `compare.json` and `compare.md`.

pub mod modal;
mod report;

pub use report::{markdown, write};

use crate::error::PipelineError;
use crate::model;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::{ModelSource, Scene};
use crate::stages::cea;
use modal::{MatrixDiff, ModePair};
use serde::Serialize;
use std::path::{Path, PathBuf};

use squeal_solver::Real;

/// Exit status of `squeal compare` when a difference is beyond a tolerance the user set (1 is
/// an error, 3 `squeal sweep`'s failed values).
pub const EXIT_BEYOND_TOLERANCE: u8 = 4;

/// Tolerances and settings of a comparison (a tolerance left None is reported, not checked).
#[derive(Debug, Clone)]
pub struct CompareOptions {
    /// Largest |f_B − f_A|/f_A of a paired undamped mode.
    pub tol_freq: Option<Real>,
    /// Smallest MAC of each mode of A with its pair (an unpaired mode fails).
    pub tol_mac: Option<Real>,
    /// Largest ‖A − B‖_F/‖A‖_F of each matrix.
    pub tol_matrix: Option<Real>,
    /// Largest |Δf|/f and |Δ Re p|/|p| of each paired CEA root (an unpaired root fails).
    pub tol_root: Option<Real>,
    /// Largest relative difference of each numeric `summary.json` value of two run folders
    /// (timings — keys ending in `_s` — excluded), and equal text/boolean values (the
    /// verdict's state).
    pub tol_summary: Option<Real>,
    /// Undamped modes compared: the lowest this many of A (default: all).
    pub modes: Option<usize>,
    /// MAC below which two modes are not paired (default: 0.5, or `tol_mac` when that is
    /// lower: [`CompareOptions::pair_mac`]).
    pub pair_mac: Option<Real>,
    /// Analysis settings (friction, rotor, loads, `[cea]`) for stored models' CEA.
    pub scene: Option<PathBuf>,
    /// Run the CEA of model inputs (default: true).
    pub cea: bool,
    /// Model cache for scene inputs.
    pub cache: Option<model::ModelCache>,
}

impl CompareOptions {
    /// Checks the tolerances and `pair_mac` (finite and >= 0; a MAC, `tol_mac` and
    /// `pair_mac`, at most 1; `pair_mac` <= `tol_mac`, else a mode whose MAC lies between them
    /// is left unpaired and fails `tol_mac` although its MAC passes it) and `modes` (>= 1 when
    /// a mode tolerance is given: 0 modes would check nothing and pass); the error names the
    /// option and the value. `compute` calls it, so the CLI and the Python package get the
    /// same check.
    pub fn validate(&self) -> Result<(), PipelineError> {
        let bad = |name: &str, message: String| PipelineError::Option {
            option: format!("compare.{name}"),
            message,
        };
        for (name, v) in [
            ("tol_freq", self.tol_freq),
            ("tol_mac", self.tol_mac),
            ("tol_matrix", self.tol_matrix),
            ("tol_root", self.tol_root),
            ("tol_summary", self.tol_summary),
            ("pair_mac", self.pair_mac),
        ] {
            if let Some(v) = v.filter(|v| !(v.is_finite() && *v >= 0.0)) {
                return Err(PipelineError::Option {
                    option: format!("compare.{name}"),
                    message: format!("{v}: must be a finite number >= 0"),
                });
            }
        }
        for (name, v) in [("tol_mac", self.tol_mac), ("pair_mac", self.pair_mac)] {
            if let Some(v) = v.filter(|&v| v > 1.0) {
                return Err(bad(name, format!("{v}: a MAC is in [0, 1]")));
            }
        }
        if let (Some(t), Some(p)) = (
            self.tol_mac,
            self.pair_mac.filter(|&p| Some(p) > self.tol_mac),
        ) {
            return Err(bad(
                "pair_mac",
                format!(
                    "{} is above compare.tol_mac = {t}: a mode whose MAC lies between them \
                     would be left unpaired and fail tol_mac although its MAC passes it; give \
                     pair_mac <= tol_mac",
                    p
                ),
            ));
        }
        if self.modes == Some(0) {
            if let Some((name, v)) = [("tol_freq", self.tol_freq), ("tol_mac", self.tol_mac)]
                .into_iter()
                .find_map(|(n, v)| v.map(|v| (n, v)))
            {
                return Err(bad(
                    "modes",
                    format!(
                        "0 compares no undamped mode, so compare.{name} = {v} would check \
                         nothing and pass; give modes >= 1 (or leave it out: all modes)"
                    ),
                ));
            }
        }
        Ok(())
    }
}

impl CompareOptions {
    /// The pairing threshold used: `pair_mac`, else 0.5, or `tol_mac` when that is lower (a
    /// mode with a MAC that passes `tol_mac` is then always paired).
    pub fn pair_mac(&self) -> Real {
        self.pair_mac
            .unwrap_or_else(|| self.tol_mac.map_or(0.5, |t| t.min(0.5)))
    }
}

impl Default for CompareOptions {
    fn default() -> Self {
        Self {
            tol_freq: None,
            tol_mac: None,
            tol_matrix: None,
            tol_root: None,
            tol_summary: None,
            modes: None,
            pair_mac: None,
            scene: None,
            cea: true,
            cache: None,
        }
    }
}

/// What an input path is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind")]
pub enum Input {
    /// A scene file.
    Scene { path: PathBuf },
    /// Stored matrices with their DOF map (and gap table).
    Stored {
        matrices: PathBuf,
        dofmap: PathBuf,
        gaps: Option<PathBuf>,
    },
    /// A run folder (`summary.json`, maybe `cea.json`).
    Run { path: PathBuf },
}

impl Input {
    /// Classifies a path; errors name it.
    pub fn detect(p: &Path) -> Result<Self, PipelineError> {
        let bad = |m: &str| PipelineError::Input {
            path: p.to_path_buf(),
            message: m.to_string(),
        };
        let stored = |matrices: PathBuf, dir: &Path| -> Result<Input, PipelineError> {
            let dofmap = dir.join("dofmap.json");
            if !dofmap.is_file() {
                return Err(PipelineError::Input {
                    path: matrices,
                    message: format!(
                        "stored matrices need their DOF map {} beside them",
                        dofmap.display()
                    ),
                });
            }
            let gaps = Some(dir.join("gaps.json")).filter(|g| g.is_file());
            Ok(Input::Stored {
                matrices,
                dofmap,
                gaps,
            })
        };
        if p.is_dir() {
            for name in ["reduced.op4", "reduced.pch"] {
                if p.join(name).is_file() && p.join("dofmap.json").is_file() {
                    return stored(p.join(name), p);
                }
            }
            if p.join("summary.json").is_file() {
                return Ok(Input::Run {
                    path: p.to_path_buf(),
                });
            }
            return Err(bad(
                "neither a reduce folder (reduced.op4 + dofmap.json) nor a run folder (summary.json)",
            ));
        }
        let ext = p
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match ext.as_deref() {
            Some("toml") => Ok(Input::Scene {
                path: p.to_path_buf(),
            }),
            Some("op4") | Some("pch") | Some("punch") => {
                let dir = p.parent().unwrap_or(Path::new("."));
                stored(p.to_path_buf(), dir)
            }
            _ if !p.exists() => Err(bad("no such file or folder")),
            _ => Err(bad(
                "not a scene (.toml), stored matrices (.op4, .pch), a reduce folder or a run folder",
            )),
        }
    }

    fn is_run(&self) -> bool {
        matches!(self, Input::Run { .. })
    }

    /// The path named in messages.
    pub fn path(&self) -> &Path {
        match self {
            Input::Scene { path } | Input::Run { path } => path,
            Input::Stored { matrices, .. } => matrices,
        }
    }
}

/// A paired CEA root.
#[derive(Debug, Clone, Serialize)]
pub struct RootPair {
    pub frequency_a_hz: Real,
    pub real_part_a: Real,
    pub frequency_b_hz: Option<Real>,
    pub real_part_b: Option<Real>,
    /// (f_B − f_A)/f_A.
    pub relative_frequency_difference: Option<Real>,
    /// Re p_B − Re p_A (1/s).
    pub real_part_difference: Option<Real>,
    /// |Re p_B − Re p_A| / |p_A| (|p| = √(Re p² + (2πf)²)).
    pub relative_real_part_difference: Option<Real>,
}

/// One `summary.json` value of two runs.
#[derive(Debug, Clone, Serialize)]
pub struct SummaryRow {
    /// Dotted key.
    pub key: String,
    pub a: serde_json::Value,
    pub b: serde_json::Value,
    /// (b − a)/|a| for numbers.
    pub relative: Option<Real>,
    /// A timing (not checked).
    pub timing: bool,
}

/// One tolerance check.
#[derive(Debug, Clone, Serialize)]
pub struct Check {
    /// `tol_freq`, `tol_mac`, `tol_matrix`, `tol_root`, `tol_summary`.
    pub tolerance_name: String,
    pub tolerance: Real,
    /// The worst value found and where.
    pub worst: Real,
    pub at: String,
    pub passed: bool,
}

/// What `squeal compare` found (`compare.json`).
#[derive(Debug, Clone, Serialize)]
pub struct CompareReport {
    pub verb: &'static str,
    pub version: &'static str,
    pub a: Input,
    pub b: Input,
    /// Reduced DOFs of each model (models only).
    pub n_dofs: Option<(usize, usize)>,
    pub matrices: Vec<MatrixDiff>,
    pub modes: Vec<ModePair>,
    /// Modes of B paired with none of A.
    pub unpaired_modes_b: Vec<usize>,
    /// CEA roots of A paired with B's by frequency (None: not compared, see `cea_note`).
    pub roots: Option<Vec<RootPair>>,
    pub cea_note: Option<String>,
    /// `summary.json` values side by side (run folders).
    pub summaries: Vec<SummaryRow>,
    pub checks: Vec<Check>,
    /// Every check passed.
    pub passed: bool,
}

/// Compares `a` with `b` (see the module documentation).
pub fn compute(
    a: &Path,
    b: &Path,
    opts: &CompareOptions,
    dir: &RunDir,
    progress: &Progress,
) -> Result<CompareReport, PipelineError> {
    opts.validate()?;
    let (ia, ib) = (Input::detect(a)?, Input::detect(b)?);
    if ia.is_run() != ib.is_run() {
        return Err(PipelineError::Input {
            path: b.to_path_buf(),
            message: format!(
                "compared with {}: two models or two run folders are compared, not one of each",
                a.display()
            ),
        });
    }
    let mut report = CompareReport {
        verb: "compare",
        version: crate::VERSION,
        a: ia.clone(),
        b: ib.clone(),
        n_dofs: None,
        matrices: Vec::new(),
        modes: Vec::new(),
        unpaired_modes_b: Vec::new(),
        roots: None,
        cea_note: None,
        summaries: Vec::new(),
        checks: Vec::new(),
        passed: true,
    };
    if ia.is_run() {
        compare_runs(&ia, &ib, &mut report)?;
    } else {
        compare_models(&ia, &ib, opts, dir, progress, &mut report)?;
    }
    report.checks = checks(&report, opts);
    report.passed = report.checks.iter().all(|c| c.passed);
    Ok(report)
}

/// A model input as a scene (for stored matrices: `opts.scene`'s settings, or none).
fn scene_of(input: &Input, opts: &CompareOptions) -> Result<Scene, PipelineError> {
    match input {
        Input::Scene { path } => Scene::load(path, &[]),
        Input::Stored {
            matrices,
            dofmap,
            gaps,
        } => {
            let mut scene = match &opts.scene {
                Some(p) => Scene::load(p, &[])?,
                None => Scene::from_toml_str("", ".", &[])?,
            };
            let abs = |p: &Path| std::path::absolute(p).unwrap_or_else(|_| p.to_path_buf());
            let is_punch = matrices
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("pch") || e.eq_ignore_ascii_case("punch"));
            scene.model.from = if is_punch {
                ModelSource::Punch
            } else {
                ModelSource::Op4
            };
            scene.model.matrices = Some(abs(matrices));
            scene.model.dofmap = Some(abs(dofmap));
            scene.model.gaps = gaps.as_deref().map(abs);
            Ok(scene)
        }
        Input::Run { path } => Err(PipelineError::Input {
            path: path.clone(),
            message: "a run folder holds no model".into(),
        }),
    }
}

fn compare_models(
    ia: &Input,
    ib: &Input,
    opts: &CompareOptions,
    dir: &RunDir,
    progress: &Progress,
    report: &mut CompareReport,
) -> Result<(), PipelineError> {
    let (sa, sb) = (scene_of(ia, opts)?, scene_of(ib, opts)?);
    let load = |s: &Scene, name: &str| -> Result<model::ReducedModel, PipelineError> {
        let sub = RunDir::create(&dir.path(name))?;
        model::build_cached(s, &sub, progress, opts.cache.as_ref()).map(|(m, _)| m)
    };
    let (ma, mb) = (load(&sa, "model-a")?, load(&sb, "model-b")?);
    report.n_dofs = Some((ma.n(), mb.n()));
    let perm = modal::align(&ma, &mb).map_err(|m| PipelineError::Input {
        path: ib.path().to_path_buf(),
        message: format!("DOF map differs from {}'s: {m}", ia.path().display()),
    })?;
    report.matrices = modal::matrix_diffs(&ma, &mb, &perm);
    let (moa, mob) = (modal::modes(&ma, "A")?, modal::modes(&mb, "B")?);
    let count = opts.modes.unwrap_or(ma.n()).min(ma.n());
    report.modes = modal::pair_modes(&ma, &moa, &mob, &perm, count, opts.pair_mac());
    let used: Vec<usize> = report.modes.iter().filter_map(|p| p.mode_b).collect();
    report.unpaired_modes_b = (0..count.min(mob.0.len()))
        .filter(|j| !used.contains(j))
        .collect();
    // CEA: scenes carry their analysis; stored matrices need `opts.scene`.
    let analysable = |i: &Input| matches!(i, Input::Scene { .. }) || opts.scene.is_some();
    if !opts.cea {
        report.cea_note = Some("not run (--no-cea)".into());
    } else if !(analysable(ia) && analysable(ib)) {
        report.cea_note = Some(
            "not run: stored matrices carry no friction, rotor or load settings (give --scene)"
                .into(),
        );
    } else if ma.gap_geometry.is_empty() || mb.gap_geometry.is_empty() {
        report.cea_note = Some("not run: a model without gaps".into());
    } else {
        let roots =
            |s: &Scene, m: &model::ReducedModel| -> Result<Vec<(Real, Real)>, PipelineError> {
                // A scene without `[cea]` gets its defaults (the steady state under full load).
                let mut s = s.clone();
                s.cea.get_or_insert_with(Default::default).sensitivity = false;
                let c = cea::compute(&s, m, &progress.silenced(), &Default::default())?;
                Ok(c.out
                    .modes
                    .iter()
                    .map(|m| (m.frequency_hz, m.real_part))
                    .collect())
            };
        report.roots = Some(pair_roots(&roots(&sa, &ma)?, &roots(&sb, &mb)?));
    }
    Ok(())
}

/// Each root of A with the nearest unpaired root of B in frequency (roots of A in order of
/// frequency).
pub fn pair_roots(a: &[(Real, Real)], b: &[(Real, Real)]) -> Vec<RootPair> {
    let mut used = vec![false; b.len()];
    let mut order: Vec<usize> = (0..a.len()).collect();
    order.sort_by(|&i, &j| a[i].0.total_cmp(&a[j].0));
    order
        .into_iter()
        .map(|i| {
            let (fa, ra) = a[i];
            let j = (0..b.len())
                .filter(|&j| !used[j])
                .min_by(|&x, &y| (b[x].0 - fa).abs().total_cmp(&(b[y].0 - fa).abs()));
            let modulus = (ra * ra + (2.0 * std::f64::consts::PI * fa).powi(2)).sqrt();
            match j {
                Some(j) => {
                    used[j] = true;
                    let (fb, rb) = b[j];
                    RootPair {
                        frequency_a_hz: fa,
                        real_part_a: ra,
                        frequency_b_hz: Some(fb),
                        real_part_b: Some(rb),
                        relative_frequency_difference: Some(modal::relative(fa, fb)),
                        real_part_difference: Some(rb - ra),
                        relative_real_part_difference: Some(if modulus > 0.0 {
                            (rb - ra).abs() / modulus
                        } else {
                            (rb - ra).abs()
                        }),
                    }
                }
                None => RootPair {
                    frequency_a_hz: fa,
                    real_part_a: ra,
                    frequency_b_hz: None,
                    real_part_b: None,
                    relative_frequency_difference: None,
                    real_part_difference: None,
                    relative_real_part_difference: None,
                },
            }
        })
        .collect()
}

fn read_json(p: &Path) -> Result<serde_json::Value, PipelineError> {
    let text = std::fs::read_to_string(p).map_err(|source| PipelineError::Io {
        path: p.to_path_buf(),
        source,
    })?;
    serde_json::from_str(&text).map_err(|e| PipelineError::Input {
        path: p.to_path_buf(),
        message: format!("not JSON: {e}"),
    })
}

/// The roots (frequency, Re p) of a `cea.json`; errors name the file and the entry.
fn cea_roots(p: &Path) -> Result<Vec<(Real, Real)>, PipelineError> {
    let v = read_json(p)?;
    let modes = v["modes"].as_array().ok_or_else(|| PipelineError::Input {
        path: p.to_path_buf(),
        message: "no `modes` array".into(),
    })?;
    modes
        .iter()
        .enumerate()
        .map(
            |(i, m)| match (m["frequency_hz"].as_f64(), m["real_part"].as_f64()) {
                (Some(f), Some(r)) if f.is_finite() && r.is_finite() => Ok((f, r)),
                _ => Err(PipelineError::Input {
                    path: p.to_path_buf(),
                    message: format!("modes[{i}]: no finite `frequency_hz` and `real_part`"),
                }),
            },
        )
        .collect()
}

/// Scalars of a JSON document by dotted key (arrays are skipped).
fn flatten(prefix: &str, v: &serde_json::Value, out: &mut Vec<(String, serde_json::Value)>) {
    match v {
        serde_json::Value::Object(o) => {
            for (k, x) in o {
                let key = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&key, x, out);
            }
        }
        serde_json::Value::Array(_) => {}
        x => out.push((prefix.to_string(), x.clone())),
    }
}

/// Timings (seconds: keys ending in `_s`, rates `_per_s` aside) and the version differ
/// between identical runs: reported, never checked.
fn is_timing(key: &str) -> bool {
    (key.ends_with("_s") && !key.ends_with("_per_s")) || key == "version"
}

fn compare_runs(ia: &Input, ib: &Input, report: &mut CompareReport) -> Result<(), PipelineError> {
    let (pa, pb) = (ia.path(), ib.path());
    let (sa, sb) = (
        read_json(&pa.join("summary.json"))?,
        read_json(&pb.join("summary.json"))?,
    );
    let (mut fa, mut fb) = (Vec::new(), Vec::new());
    flatten("", &sa, &mut fa);
    flatten("", &sb, &mut fb);
    let b_of: std::collections::HashMap<String, serde_json::Value> = fb.into_iter().collect();
    for (key, a) in fa {
        let b = b_of.get(&key).cloned().unwrap_or(serde_json::Value::Null);
        let relative = match (a.as_f64(), b.as_f64()) {
            (Some(x), Some(y)) => Some(modal::relative(x, y)),
            _ => None,
        };
        report.summaries.push(SummaryRow {
            timing: is_timing(&key),
            key,
            a,
            b,
            relative,
        });
    }
    let (ca, cb) = (pa.join("cea.json"), pb.join("cea.json"));
    match (ca.is_file(), cb.is_file()) {
        (true, true) => report.roots = Some(pair_roots(&cea_roots(&ca)?, &cea_roots(&cb)?)),
        _ => report.cea_note = Some("not compared: cea.json is not in both run folders".into()),
    }
    Ok(())
}

/// The checks of the tolerances `opts` sets.
fn checks(r: &CompareReport, opts: &CompareOptions) -> Vec<Check> {
    let mut out = Vec::new();
    let mut check = |name: &str, tol: Option<Real>, items: Vec<(Real, String)>, above: bool| {
        let Some(tol) = tol else { return };
        // `above`: the value must be at most tol (differences); else at least tol (MAC).
        let worst = items
            .into_iter()
            .fold(None, |w: Option<(Real, String)>, (v, at)| {
                let v = if v.is_nan() { Real::INFINITY } else { v };
                match &w {
                    Some((x, _)) if (above && *x >= v) || (!above && *x <= v) => w,
                    _ => Some((v, at)),
                }
            });
        let (worst, at) =
            worst.unwrap_or((if above { 0.0 } else { 1.0 }, "nothing compared".into()));
        out.push(Check {
            tolerance_name: name.into(),
            tolerance: tol,
            worst,
            at,
            passed: if above { worst <= tol } else { worst >= tol },
        });
    };
    check(
        "tol_matrix",
        opts.tol_matrix,
        r.matrices
            .iter()
            .map(|m| (m.relative, m.name.clone()))
            .collect(),
        true,
    );
    check(
        "tol_freq",
        opts.tol_freq,
        r.modes
            .iter()
            .filter_map(|p| {
                p.relative_frequency_difference.map(|d| {
                    (
                        d.abs(),
                        format!("mode {} ({:.6} Hz)", p.mode_a, p.frequency_a_hz),
                    )
                })
            })
            .collect(),
        true,
    );
    check(
        "tol_mac",
        opts.tol_mac,
        r.modes
            .iter()
            .map(|p| {
                let mac = if p.mode_b.is_some() { p.mac } else { 0.0 };
                (
                    mac,
                    format!("mode {} ({:.6} Hz)", p.mode_a, p.frequency_a_hz),
                )
            })
            .collect(),
        false,
    );
    check(
        "tol_root",
        opts.tol_root,
        r.roots
            .iter()
            .flatten()
            .map(|p| {
                let at = format!(
                    "root {:.6} Hz, Re p {:.6e}",
                    p.frequency_a_hz, p.real_part_a
                );
                match (
                    p.relative_frequency_difference,
                    p.relative_real_part_difference,
                ) {
                    (Some(df), Some(dr)) => (df.abs().max(dr), at),
                    _ => (Real::INFINITY, format!("{at}: unpaired")),
                }
            })
            .collect(),
        true,
    );
    check(
        "tol_summary",
        opts.tol_summary,
        r.summaries
            .iter()
            .filter(|s| !s.timing && s.key != "restarted_from")
            .map(|s| {
                let v = match s.relative {
                    Some(d) => d.abs(),
                    None if s.a == s.b => 0.0,
                    None => Real::INFINITY,
                };
                (v, s.key.clone())
            })
            .collect(),
        true,
    );
    out
}
