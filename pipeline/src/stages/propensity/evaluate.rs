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
use squeal_solver::cea::ModalBasis;
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
    /// The CEA's projection basis, made once at the design's centre and reused by every row
    /// (None: the CEA solves exactly, or the model is rebuilt per sample).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub projection_basis: Option<ProjectionBasis>,
}

/// The projection basis the rows share ([`linear::projection_basis`]).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ProjectionBasis {
    /// Real modes in it, and the highest one's frequency (Hz).
    pub n_modes: usize,
    pub max_frequency_hz: Real,
    /// Seconds to make it (once, instead of once per row).
    pub time_s: Real,
}

/// What a [`BasisCheck`] measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BasisKind {
    /// One volume's material through the reduced-matrix derivative (the Craig–Bampton basis
    /// and the projection basis held) against a model re-reduced there.
    CraigBampton,
    /// The CEA's projection basis of the design's centre against one made for the row.
    Projection,
}

/// One input's basis error: the row with the input at `value` (the others at their means,
/// component scales at 1) as every row runs (the one model, the shared projection basis) and
/// afresh: on a model re-reduced at `value` (`craig_bampton`: a volume's material), or with
/// the projection basis made for the row (`projection`: any input that changes K or M; an
/// input that changes neither leaves the basis exact and is not checked).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BasisCheck {
    pub kind: BasisKind,
    pub key: String,
    pub value: Real,
    /// Largest Re λ (1/s) and its frequency (Hz) as the rows run.
    pub derivative: (Real, Real),
    /// The same afresh (re-reduced, or with the row's own projection basis).
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
    /// The CEA's projection basis at the design's centre, reused by every row.
    basis: Option<ModalBasis>,
    /// Seconds per phase, summed over the rows ([`Evaluator::phases`]).
    phases: std::sync::Mutex<Phases>,
}

/// Where the rows' CEAs spent their time, seconds summed over the rows (each on its thread).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Phases {
    /// Rows timed.
    pub rows: usize,
    /// The problem, the steady sliding state, its tangents and the CEA matrices.
    pub state_s: Real,
    /// The eigen-solve: projection and exact refinement.
    pub eigen_s: Real,
    /// Of that, the refinement of the in-band unstable roots.
    pub refine_s: Real,
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
        // B's element part only (GE_c/W4 and the bodies' loss factors): the overall G/W3 K
        // and the modal part follow K and M when the problem's damping matrix is made.
        let overall = scene.damping.clone().unwrap_or_default().overall_factor();
        let b = match (&d.b, &d.k) {
            (Some(b), Some(k)) => Some(Mat::from_fn(k.nrows(), k.ncols(), |i, j| {
                b[(i, j)] - overall * k[(i, j)]
            })),
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
        projection_basis: None,
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
        let mut ev = Evaluator {
            keys: plan.keys(),
            model,
            scratch,
            info: info_of(scene, plan, n_dofs, n_gaps),
            base,
            derivatives,
            basis: None,
            phases: Default::default(),
        };
        // One projection basis for every row, made at the design's centre (a basis does not
        // depend on μ; an input that changes K or M is checked by `check_basis`).
        if ev.model.is_some() {
            let t = std::time::Instant::now();
            let (scene, m) = ev.row_model(&centre(plan))?;
            let problem = system::problem(&scene, &m)?;
            let spec = lean_spec(&scene, progress)?;
            ev.basis = linear::projection_basis(&scene, &spec, &problem, &progress.silenced())?;
            ev.info.projection_basis = ev.basis.as_ref().map(|b| ProjectionBasis {
                n_modes: b.len(),
                max_frequency_hz: b.frequencies_hz().last().copied().unwrap_or(0.0),
                time_s: t.elapsed().as_secs_f64(),
            });
        }
        Ok(ev)
    }

    /// Makes every later row build its own projection basis, as a single CEA does (for
    /// comparisons: the rows are exact but slower).
    pub fn forget_projection_basis(&mut self) {
        self.basis = None;
        self.info.projection_basis = None;
    }

    /// Where the rows evaluated so far spent their time.
    pub fn phases(&self) -> Phases {
        self.phases.lock().map(|p| p.clone()).unwrap_or_default()
    }

    /// The shared settings (for the report).
    pub fn info(&self) -> EvalInfo {
        self.info.clone()
    }

    /// The bases the rows hold fixed, checked per input at its 0.5 % and 99.5 % quantiles
    /// (the other inputs at their means, component scales at 1), the row as every row runs
    /// against the same afresh; kept in [`EvalInfo::basis_checks`]:
    /// - an input that scales one volume on the reduced model (first order in the Craig–
    ///   Bampton basis's change): against a model re-reduced there (in `dir`), with its own
    ///   projection basis;
    /// - any other input whose row changes K or M (a whole component's modulus or density, a
    ///   contact stiffness): against the CEA with the row's own projection basis. An input that
    ///   leaves K, M and G as at the centre (μ, a friction-law coefficient) leaves the basis
    ///   exact and is not checked.
    ///
    /// A change of the largest Re λ above `tolerance` × |Re λ|, and above `floor` (1/s), is
    /// an error naming the key.
    pub fn check_basis(
        &mut self,
        plan: &Plan,
        dir: &RunDir,
        (tolerance, floor): (Real, Real),
        progress: &Progress,
    ) -> Result<(), PipelineError> {
        let mut checks = Vec::new();
        for (i, input) in plan.inputs.iter().enumerate() {
            let volume = input.component.as_ref().is_some_and(|c| c.volume.is_some());
            // Without a shared projection basis (an exact CEA, or a model rebuilt per row)
            // only a volume's material holds a basis fixed.
            if !volume && self.basis.is_none() {
                continue;
            }
            for q in [0.005, 0.995] {
                let value = input.distribution.quantile(q);
                let mut values = centre(plan);
                values[i] = value;
                if !volume {
                    // The projection basis: exact when the row has the centre's K, M and G.
                    let (scene, m) = self.row_model(&values)?;
                    let (o, f, _, exact_basis) =
                        self.cea(&scene, &m, self.basis.as_ref(), progress)?;
                    if exact_basis != Some(false) {
                        continue;
                    }
                    let (or, fr, _, _) = self.cea(&scene, &m, None, progress)?;
                    checks.push(BasisCheck::new(
                        BasisKind::Projection,
                        &input.key,
                        value,
                        (o.max_real_part, f),
                        (or.max_real_part, fr),
                        (tolerance, floor),
                    ));
                    continue;
                }
                let (o, f, _, _) = self.try_evaluate(0, &values, progress)?;
                // Re-reduced: the scene's keys (the volume's too) on a fresh build.
                let mut sets: Vec<(String, String)> = plan
                    .inputs
                    .iter()
                    .zip(&values)
                    .filter(|(x, _)| x.component.is_none())
                    .map(|(x, v)| (x.key.clone(), value_text(*v)))
                    .collect();
                sets.push((scene_key(&self.base, input)?, value_text(value)));
                // The reference model needs no reduction checks: they verify a reduction,
                // they do not change it (the study's own model was checked when built).
                sets.push(("reduction.checks".into(), "false".into()));
                let scene = values::scene_for_all(&self.base, &sets)?;
                let path = dir.path(&format!("basis-check-{i}-{q}"));
                let m = rebuilt(&scene, &path, progress)?;
                let (or, fr, _, _) = self.cea(&scene, &m, None, progress)?;
                checks.push(BasisCheck::new(
                    BasisKind::CraigBampton,
                    &input.key,
                    value,
                    (o.max_real_part, f),
                    (or.max_real_part, fr),
                    (tolerance, floor),
                ));
            }
        }
        let failed = checks.iter().find(|c| !c.passed).cloned();
        self.info.basis_checks = checks;
        match failed {
            Some(c) if c.kind == BasisKind::Projection => Err(PipelineError::Option {
                option: format!("--dist {}", c.key),
                message: format!(
                    "the CEA's projection basis made at the design's centre moves the largest \
                     Re λ by {:.3e} /s at {} = {} ({:.4e} /s with the row's own basis, {:.4e} \
                     /s with the centre's), above the {:.3e} /s allowed (--basis-tolerance \
                     {tolerance}): narrow the distribution, or widen [cea.solver.projection] \
                     cutoff_factor",
                    c.real_part_change, c.key, c.value, c.rereduced.0, c.derivative.0, c.allowed
                ),
            }),
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
            Ok((o, f, n, _)) => {
                s.outcome = Some(o);
                s.max_real_part_frequency_hz = f;
                s.n_unstable = n;
            }
            Err(e) if e.is_cancelled() => return Err(e),
            Err(e) => s.error = Some(e.to_string()),
        }
        Ok(s)
    }

    /// The row's CEA: on the one model and the shared projection basis, or (`--rereduce`)
    /// on a model built for it. The last value is [`linear::Roots::reused_basis`].
    fn try_evaluate(
        &self,
        row: usize,
        values: &[Real],
        progress: &Progress,
    ) -> Result<Lean, PipelineError> {
        match (&self.model, &self.scratch) {
            (Some(_), _) => {
                let (scene, m) = self.row_model(values)?;
                self.cea(&scene, &m, self.basis.as_ref(), progress)
            }
            (None, Some(scratch)) => {
                let scene = self.row_scene(values)?;
                let m = rebuilt(&scene, &scratch.join(format!("{row:06}")), progress)?;
                self.cea(&scene, &m, None, progress)
            }
            (None, None) => Err(PipelineError::Model("propensity: no model".into())),
        }
    }

    /// The row's scene: the inputs that are scene keys set on the base scene.
    fn row_scene(&self, values: &[Real]) -> Result<Scene, PipelineError> {
        let on_model = |i: usize| self.derivatives.iter().any(|d| d.0 == i);
        let assignments: Vec<(String, String)> = self
            .keys
            .iter()
            .zip(values)
            .enumerate()
            .filter(|(i, _)| !on_model(*i))
            .map(|(_, (k, v))| (k.clone(), value_text(*v)))
            .collect();
        values::scene_for_all(&self.base, &assignments)
    }

    /// The row's scene and the one model with the row's component properties applied.
    fn row_model(
        &self,
        values: &[Real],
    ) -> Result<(Scene, std::borrow::Cow<'_, ReducedModel>), PipelineError> {
        use std::borrow::Cow;
        let scene = self.row_scene(values)?;
        let Some(m) = &self.model else {
            return Err(PipelineError::Model("propensity: no model".into()));
        };
        match self.derivatives.is_empty() {
            false => {
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
                Ok((scene, Cow::Owned(m)))
            }
            // The sample's operating point is the scene's: applied when its problem is made.
            true => Ok((scene, Cow::Borrowed(m))),
        }
    }

    /// The lean CEA: largest Re λ in the band, its frequency, the unstable roots' bands.
    fn cea(
        &self,
        scene: &Scene,
        m: &ReducedModel,
        basis: Option<&ModalBasis>,
        progress: &Progress,
    ) -> Result<Lean, PipelineError> {
        let t = std::time::Instant::now();
        let spec = lean_spec(scene, progress)?;
        let problem = system::problem(scene, m)?;
        let r = linear::roots_on(scene, &spec, &problem, m, basis, &progress.silenced())?;
        if let Ok(mut p) = self.phases.lock() {
            let eigen = r.stats.time_eigen_s + r.stats.time_reduce_s;
            p.rows += 1;
            p.state_s += t.elapsed().as_secs_f64() - eigen;
            p.eigen_s += eigen;
            p.refine_s += r.stats.refine.as_ref().map_or(0.0, |x| x.time_s);
        }
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
            r.reused_basis,
        ))
    }
}

/// A lean CEA's outcome, the frequency of its largest Re λ, its count of unstable roots in
/// the band, and whether it reused a projection basis ([`linear::Roots::reused_basis`]).
type Lean = (Outcome, Option<Real>, usize, Option<bool>);

/// The `[cea]` table of a row: its sweep left out, no shapes.
fn lean_spec(scene: &Scene, progress: &Progress) -> Result<CeaSpec, PipelineError> {
    let mut spec = scene.cea.clone().unwrap_or_default();
    spec.sweep = None;
    spec.validate()?;
    spec.solver.interrupt = progress.solver_interrupt();
    spec.solver.compute_shapes = false;
    Ok(spec)
}

/// The design's centre: every input at its mean, a component property at its value in the
/// model as built.
fn centre(plan: &Plan) -> Vec<Real> {
    plan.inputs
        .iter()
        .map(|x| x.component.as_ref().map_or(x.mean, |c| c.base))
        .collect()
}

impl BasisCheck {
    /// `rows` (largest Re λ, its frequency) as the rows run, `fresh` afresh; allowed:
    /// `tolerance` × |Re λ afresh|, at least `floor`.
    fn new(
        kind: BasisKind,
        key: &str,
        value: Real,
        rows: (Real, Option<Real>),
        fresh: (Real, Option<Real>),
        (tolerance, floor): (Real, Real),
    ) -> BasisCheck {
        let (fd, fr) = (rows.1.unwrap_or(0.0), fresh.1.unwrap_or(0.0));
        let change = (rows.0 - fresh.0).abs();
        let allowed = (tolerance * fresh.0.abs()).max(floor);
        BasisCheck {
            kind,
            key: key.to_string(),
            value,
            derivative: (rows.0, fd),
            rereduced: (fresh.0, fr),
            real_part_change: change,
            frequency_change: (fd - fr).abs() / fr.abs().max(Real::MIN_POSITIVE),
            allowed,
            passed: change <= allowed,
        }
    }
}
