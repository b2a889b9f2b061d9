//! One design row of a propensity study: the scene with the row's values → the reduced model
//! (the one built for the study with the row's late values applied, or rebuilt with
//! `--rereduce`) → a lean CEA (steady state, tangents, complex eigenvalues; no energy balance,
//! no shapes) → the largest Re λ and the unstable roots' one-third-octave bands.

use super::{value_text, ComponentInput, Plan};
use crate::error::PipelineError;
use crate::model::{self, ReducedModel};
use crate::output::RunDir;
use crate::problem::{linear, system};
use crate::progress::Progress;
use crate::scene::values;
use crate::scene::{CeaSpec, Scene};
use crate::stages::cea::params::{component_matrix_derivative, ComponentProperty};
use crate::stages::cea::volume::volume_matrix_derivative;
use crate::uq::{band_of, third_octave_bands, Band, Outcome};
use faer::Mat;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

use squeal_solver::Real;

/// The lowest one-third-octave mid-band frequency reported (Hz): squeal is audible, and a
/// mode below it (a real divergence root included) still counts in `p_unstable`.
pub const LOWEST_BAND_HZ: Real = 10.0;
/// The top of the bands when neither the model nor `[cea]` gives a validity band (Hz).
pub const DEFAULT_TOP_HZ: Real = 20_000.0;

/// What one design row gave.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Sample {
    /// Index into the design's rows.
    pub row: usize,
    /// The inputs' values, in the plan's key order.
    pub values: Vec<Real>,
    /// None: the row failed (`error`).
    pub outcome: Option<Outcome>,
    /// Frequency of the root with the largest Re λ (Hz).
    pub max_real_part_frequency_hz: Option<Real>,
    /// Unstable roots in the validity band.
    pub n_unstable: usize,
    pub error: Option<String>,
}

/// The model and settings every row shares.
#[derive(Debug, Clone, Serialize)]
pub struct EvalInfo {
    /// `reused`: one reduced model, late values per sample; `rereduced`: built per sample.
    pub model: &'static str,
    pub n_dofs: usize,
    pub n_gaps: usize,
    /// Roots above it are outside what the reduced model represents and never count.
    pub band_hz: Option<Real>,
    pub bands: Vec<Band>,
    /// Inputs that scale one volume on the reduced model, checked against re-reduction
    /// ([`Evaluator::check_basis`]; None: not checked, e.g. chunks evaluated from Python).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub basis_checks: Vec<BasisCheck>,
}

/// One volume input's basis error: the row with the input at `value` (the others at their
/// means, component scales at 1) on the one model through the derivative and on a model
/// re-reduced at `value`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BasisCheck {
    pub key: String,
    pub value: Real,
    /// Largest Re λ (1/s) and its frequency (Hz) through the derivative.
    pub derivative: (Real, Real),
    /// The same re-reduced.
    pub rereduced: (Real, Real),
    /// |ΔRe λ| (1/s) and |Δf|/f.
    pub real_part_change: Real,
    pub frequency_change: Real,
    /// The |ΔRe λ| allowed: `--basis-tolerance` × |Re λ| (re-reduced), at least 1 /s.
    pub allowed: Real,
    pub passed: bool,
}

/// Evaluates design rows of one study.
pub struct Evaluator {
    base: Scene,
    keys: Vec<String>,
    /// The study's reduced model (None: rebuilt per sample), without recovery data.
    model: Option<ReducedModel>,
    /// Where per-sample builds put their files (`--rereduce`).
    scratch: Option<PathBuf>,
    info: EvalInfo,
    /// Per input varied on the reduced model (a component property): its key's index, the
    /// value at scale 1, the derivative of K, M and the element damping.
    derivatives: Vec<(usize, Real, Derivative)>,
}

/// ∂K, ∂M and ∂B_element of a component property on the reduced model.
struct Derivative {
    k: Option<Mat<Real>>,
    m: Option<Mat<Real>>,
    b: Option<Mat<Real>>,
}

impl Derivative {
    /// The derivative of `c` on `model` (which still has its recovery data); errors name the
    /// input's key.
    fn of(
        scene: &Scene,
        model: &ReducedModel,
        key: &str,
        c: &ComponentInput,
    ) -> Result<Self, PipelineError> {
        let d = match &c.volume {
            None => component_matrix_derivative(scene, model, &c.component, c.property),
            Some(v) => volume_matrix_derivative(scene, model, &c.component, v, c.property),
        }
        .map_err(|e| PipelineError::Option {
            option: format!("--dist {key}"),
            message: format!("the reduced-matrix derivative: {e}"),
        })?;
        // B's element part only: the overall G/W3 K and the modal part follow K and M when
        // the problem's damping matrix is made.
        let elem = model
            .components
            .iter()
            .find(|x| x.name == c.component)
            .map_or(0.0, |x| x.element_damping_factor);
        let b = match (&d.k, elem != 0.0) {
            (Some(k), true) => Some(Mat::from_fn(k.nrows(), k.ncols(), |i, j| elem * k[(i, j)])),
            _ => None,
        };
        Ok(Derivative { k: d.k, m: d.m, b })
    }
}

/// The scene key of a volume input (`components.<index>.materials.<volume>.young`): what a
/// re-reduction sets.
fn scene_key(scene: &Scene, input: &super::Input) -> Result<String, PipelineError> {
    let c = input.component.as_ref();
    let (Some(c), Some(v)) = (c, c.and_then(|c| c.volume.as_ref())) else {
        return Err(PipelineError::Model(format!(
            "`{}` is no volume input",
            input.key
        )));
    };
    let i = scene
        .components
        .iter()
        .position(|x| x.name == c.component)
        .ok_or_else(|| PipelineError::Model(format!("no component `{}`", c.component)))?;
    let prop = match c.property {
        ComponentProperty::DensityScale => "density",
        _ => "young",
    };
    Ok(format!("components.{i}.materials.{v}.{prop}"))
}

/// The reduced model of `scene` built afresh in the scratch folder `path` (removed after).
fn rebuilt(
    scene: &Scene,
    path: &std::path::Path,
    progress: &Progress,
) -> Result<ReducedModel, PipelineError> {
    let dir = RunDir::create(path)?;
    let m = model::build(scene, &dir, &progress.silenced());
    let _ = std::fs::remove_dir_all(path);
    m
}

/// `a + f x`, in place.
fn add_scaled(a: &mut Mat<Real>, f: Real, x: &Mat<Real>) {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            a[(i, j)] += f * x[(i, j)];
        }
    }
}

/// The scene as every row starts from: a `[cea]` table (the defaults when it has none),
/// without its friction sweep.
fn base_scene(scene: &Scene) -> Scene {
    let mut base = scene.clone();
    if base.cea.is_none() {
        base.cea = Some(CeaSpec::default());
    }
    if let Some(c) = base.cea.as_mut() {
        c.sweep = None;
    }
    base
}

/// The settings every row of `plan` shares on `scene` (band, one-third-octave bands), with the
/// model's size (0 when rebuilt per sample).
pub fn info_of(scene: &Scene, plan: &Plan, n_dofs: usize, n_gaps: usize) -> EvalInfo {
    let base = base_scene(scene);
    let band_hz = linear::band_of(&base, base.cea.as_ref().unwrap_or(&CeaSpec::default()));
    EvalInfo {
        model: if plan.rereduce { "rereduced" } else { "reused" },
        n_dofs,
        n_gaps,
        band_hz,
        bands: third_octave_bands(LOWEST_BAND_HZ, band_hz.unwrap_or(DEFAULT_TOP_HZ)),
        basis_checks: Vec::new(),
    }
}

impl Evaluator {
    /// Builds the study's model once (through `cache` when given), unless the plan rebuilds
    /// it per sample.
    pub fn new(
        scene: &Scene,
        plan: &Plan,
        dir: &RunDir,
        progress: &Progress,
        cache: Option<&model::ModelCache>,
    ) -> Result<Evaluator, PipelineError> {
        let base = base_scene(scene);
        let mut derivatives = Vec::new();
        let (model, scratch, n_dofs, n_gaps) = if plan.rereduce {
            (None, Some(dir.path("rereduce")), 0, 0)
        } else {
            // The component inputs' derivatives need each component's blocks: a cache hit has
            // none, so the model is built when there is one.
            let needs_blocks = plan.inputs.iter().any(|i| i.component.is_some());
            let mut m = match needs_blocks {
                true => model::build(&base, dir, progress)?,
                false => model::build_cached(&base, dir, progress, cache)?.0,
            };
            for (i, input) in plan.inputs.iter().enumerate() {
                if let Some(c) = &input.component {
                    derivatives.push((i, c.base, Derivative::of(&base, &m, &input.key, c)?));
                }
            }
            m.recovery.clear();
            let (n, g) = (m.n(), m.gap_geometry.len());
            (Some(m), None, n, g)
        };
        Ok(Evaluator {
            keys: plan.keys(),
            model,
            scratch,
            info: info_of(scene, plan, n_dofs, n_gaps),
            base,
            derivatives,
        })
    }

    /// The shared settings (for the report).
    pub fn info(&self) -> EvalInfo {
        self.info.clone()
    }

    /// For each input that scales one volume on the reduced model (first order in the
    /// basis's change): the row with it at its 0.5 % and 99.5 % quantiles (the other inputs at
    /// their means, component scales at 1), evaluated on the one model and on a model
    /// re-reduced there (in `dir`); kept in [`EvalInfo::basis_checks`]. A change of the
    /// largest Re λ above `tolerance` × |Re λ|, and above `floor` (1/s), is an error naming
    /// the key.
    pub fn check_basis(
        &mut self,
        plan: &Plan,
        dir: &RunDir,
        (tolerance, floor): (Real, Real),
        progress: &Progress,
    ) -> Result<(), PipelineError> {
        let mut checks = Vec::new();
        for (i, input) in plan.inputs.iter().enumerate() {
            if input.component.as_ref().is_none_or(|c| c.volume.is_none()) {
                continue;
            }
            for q in [0.005, 0.995] {
                let value = input.distribution.quantile(q);
                let mut values: Vec<Real> = plan.inputs.iter().map(|x| x.mean).collect();
                for (j, x) in plan.inputs.iter().enumerate() {
                    if let Some(c) = &x.component {
                        values[j] = c.base;
                    }
                }
                values[i] = value;
                let (o, f, _) = self.try_evaluate(0, &values, progress)?;
                // Re-reduced: the scene's keys (the volume's too) on a fresh build.
                let mut sets: Vec<(String, String)> = plan
                    .inputs
                    .iter()
                    .zip(&values)
                    .filter(|(x, _)| x.component.is_none())
                    .map(|(x, v)| (x.key.clone(), value_text(*v)))
                    .collect();
                sets.push((scene_key(&self.base, input)?, value_text(value)));
                let scene = values::scene_for_all(&self.base, &sets)?;
                let path = dir.path(&format!("basis-check-{i}-{q}"));
                let m = rebuilt(&scene, &path, progress)?;
                let (or, fr, _) = self.cea(&scene, &m, progress)?;
                let (fd, fr) = (f.unwrap_or(0.0), fr.unwrap_or(0.0));
                let change = (o.max_real_part - or.max_real_part).abs();
                let allowed = (tolerance * or.max_real_part.abs()).max(floor);
                checks.push(BasisCheck {
                    key: input.key.clone(),
                    value,
                    derivative: (o.max_real_part, fd),
                    rereduced: (or.max_real_part, fr),
                    real_part_change: change,
                    frequency_change: (fd - fr).abs() / fr.abs().max(Real::MIN_POSITIVE),
                    allowed,
                    passed: change <= allowed,
                });
            }
        }
        let failed = checks.iter().find(|c| !c.passed).cloned();
        self.info.basis_checks = checks;
        match failed {
            Some(c) => Err(PipelineError::Option {
                option: format!("--dist {}", c.key),
                message: format!(
                    "one volume's material on the reduced model (Craig-Bampton basis held \
                     fixed) moves the largest Re λ by {:.3e} /s at {} = {} ({:.4e} /s \
                     re-reduced, {:.4e} /s on the one model), above the {:.3e} /s allowed \
                     (--basis-tolerance {tolerance}): pass --rereduce, or narrow the \
                     distribution",
                    c.real_part_change, c.key, c.value, c.rereduced.0, c.derivative.0, c.allowed
                ),
            }),
            None => Ok(()),
        }
    }

    /// Row `row` with input values `values`; a failure (bad scene, steady state, eigen-solve)
    /// is recorded in the sample, only a cancellation is an error.
    pub fn evaluate(
        &self,
        row: usize,
        values: &[Real],
        progress: &Progress,
    ) -> Result<Sample, PipelineError> {
        let mut s = Sample {
            row,
            values: values.to_vec(),
            outcome: None,
            max_real_part_frequency_hz: None,
            n_unstable: 0,
            error: None,
        };
        match self.try_evaluate(row, values, progress) {
            Ok((o, f, n)) => {
                s.outcome = Some(o);
                s.max_real_part_frequency_hz = f;
                s.n_unstable = n;
            }
            Err(e) if e.is_cancelled() => return Err(e),
            Err(e) => s.error = Some(e.to_string()),
        }
        Ok(s)
    }

    fn try_evaluate(
        &self,
        row: usize,
        values: &[Real],
        progress: &Progress,
    ) -> Result<(Outcome, Option<Real>, usize), PipelineError> {
        // The scene's keys set on the scene; a component property on the reduced model.
        let on_model = |i: usize| self.derivatives.iter().any(|d| d.0 == i);
        let assignments: Vec<(String, String)> = self
            .keys
            .iter()
            .zip(values)
            .enumerate()
            .filter(|(i, _)| !on_model(*i))
            .map(|(_, (k, v))| (k.clone(), value_text(*v)))
            .collect();
        let scene = values::scene_for_all(&self.base, &assignments)?;
        match (&self.model, &self.scratch) {
            (Some(m), _) if !self.derivatives.is_empty() => {
                let mut m = m.clone();
                for (i, base, d) in &self.derivatives {
                    let delta = values[*i] / base - 1.0;
                    if let Some(x) = &d.k {
                        add_scaled(&mut m.k, delta, x);
                    }
                    if let Some(x) = &d.m {
                        add_scaled(&mut m.m, delta, x);
                    }
                    if let Some(x) = &d.b {
                        let b = m.b.get_or_insert_with(|| Mat::zeros(x.nrows(), x.ncols()));
                        add_scaled(b, delta, x);
                    }
                }
                self.cea(&scene, &m, progress)
            }
            // The sample's operating point is the scene's: applied when its problem is made.
            (Some(m), _) => self.cea(&scene, m, progress),
            (None, Some(scratch)) => {
                let m = rebuilt(&scene, &scratch.join(format!("{row:06}")), progress)?;
                self.cea(&scene, &m, progress)
            }
            (None, None) => Err(PipelineError::Model("propensity: no model".into())),
        }
    }

    /// The lean CEA: largest Re λ in the band, its frequency, the unstable roots' bands.
    fn cea(
        &self,
        scene: &Scene,
        m: &ReducedModel,
        progress: &Progress,
    ) -> Result<(Outcome, Option<Real>, usize), PipelineError> {
        let mut spec = scene.cea.clone().unwrap_or_default();
        spec.sweep = None;
        spec.validate()?;
        spec.solver.interrupt = progress.solver_interrupt();
        spec.solver.compute_shapes = false;
        let problem = system::problem(scene, m)?;
        let r = linear::roots(scene, &spec, &problem, m, &progress.silenced())?;
        let (kept, fmax) = (&r.kept, r.band_hz.unwrap_or(Real::INFINITY));
        let top = kept
            .iter()
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part))
            .ok_or_else(|| {
                PipelineError::Model(format!(
                    "the CEA found no root up to {fmax} Hz (the validity band)"
                ))
            })?;
        let mut unstable_bands: Vec<usize> = kept
            .iter()
            .filter(|m| m.unstable)
            .filter_map(|m| band_of(&self.info.bands, m.frequency_hz))
            .collect();
        unstable_bands.sort_unstable();
        unstable_bands.dedup();
        let n_unstable = kept.iter().filter(|m| m.unstable).count();
        Ok((
            Outcome {
                max_real_part: top.real_part,
                unstable_bands,
                unstable: n_unstable > 0,
            },
            Some(top.frequency_hz),
            n_unstable,
        ))
    }
}
