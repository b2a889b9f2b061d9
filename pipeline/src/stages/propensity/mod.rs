//! `squeal propensity`: the probability of squeal under uncertain inputs (issue 24, item 4).
//!
//! `--dist KEY=uniform(a,b)` (normal, lognormal, truncnormal; `--corr A:B=ρ` a Gaussian
//! copula) over any scene key a sweep can vary → a randomised quasi-Monte Carlo design
//! (Saltelli's A, B, A_B^(i) on Owen-scrambled Sobol points, in independent replicates:
//! [`crate::uq::Design`]) → one lean CEA per design row ([`evaluate`]) → the estimates
//! ([`report`]): P(unstable) with its interval, the same per one-third-octave band, the
//! distribution of the largest Re λ, first-order and total Sobol indices → `propensity.json`,
//! `samples.csv`, `summary.json`.
//!
//! **The reduced model is built once** when no input changes it (the model cache's key,
//! [`crate::model::cache`], decides: μ and friction-law parameters, `loads.pmax`,
//! contact `p0`, `rotor.rpm`, contact normal stiffness, damping are late values applied per
//! sample to the one model). An input that changes the reduced model (a component's material
//! or geometry) is refused, naming the key, unless `--rereduce` asks to rebuild the model for
//! every sample (slow: a meshing, an assembly and a Craig–Bampton reduction per sample). A
//! component's Young's moduli or densities (`components.<name>.young_scale`, or
//! `components.<i>.material.young` of a one-material component) are varied on the one model
//! through the reduced-matrix derivative, the Craig–Bampton basis held fixed
//! ([`ComponentInput`]).
//!
//! Compute ([`plan`], [`Evaluator::evaluate`], [`report::estimate`]) and write ([`write`]) are
//! apart; the Python package evaluates chunks of rows on threads or Dask workers with the same
//! functions.

pub mod evaluate;
pub mod report;

use crate::error::PipelineError;
use crate::model::{self, cache::key::ModelKey};
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::values;
use crate::scene::Scene;
use crate::stages::cea::params::ComponentProperty;
use crate::uq::{Copula, Design, Distribution};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::time::Instant;

pub use evaluate::{Evaluator, Sample};
pub use report::PropensityOut;

use squeal_solver::Real;

/// The least |ΔRe λ| (1/s) the basis check refuses: a growth rate a transient of a few
/// hundred periods cannot tell from zero.
pub const BASIS_FLOOR: Real = 1.0;

/// What the command line gives.
#[derive(Debug, Clone)]
pub struct PropensityArgs {
    /// `--dist KEY=DIST`, in order: (key, distribution text).
    pub dists: Vec<(String, String)>,
    /// `--corr A:B=ρ`: correlations of the inputs' normal scores.
    pub corr: Vec<(String, String, Real)>,
    /// `--samples N`: the budget of CEA evaluations.
    pub samples: usize,
    /// `--replicates R` (None: the R in 4..=8 that uses the most of the budget).
    pub replicates: Option<usize>,
    /// `--seed`: selects the scrambling.
    pub seed: u32,
    /// `--rereduce`: rebuild the reduced model for every sample when an input changes it.
    pub rereduce: bool,
    /// `--basis-tolerance`: the change of the largest Re λ allowed, relative (at least 1 /s),
    /// between a volume's material on the reduced model and re-reduction.
    pub basis_tolerance: Real,
}

impl Default for PropensityArgs {
    fn default() -> Self {
        PropensityArgs {
            dists: Vec::new(),
            corr: Vec::new(),
            samples: 1000,
            replicates: None,
            seed: 1,
            rereduce: false,
            basis_tolerance: 0.05,
        }
    }
}

/// One input of the study.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Input {
    pub key: String,
    /// As given (`uniform(0.35, 0.55)`).
    pub text: String,
    pub distribution: Distribution,
    pub mean: Real,
    /// False: the key changes the reduced model (rebuilt per sample, `--rereduce`).
    pub reuses_model: bool,
    /// A component property varied through the reduced-matrix derivative (the
    /// Craig–Bampton basis held fixed) instead of a re-reduction.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub component: Option<ComponentInput>,
}

/// A component's Young's moduli or densities, scaled on the reduced model: K(s) = K + (s − 1)
/// ∂K/∂s with ∂K/∂s = T_cᵀ K_c T_c (`cea::params::component_matrix_derivative`; M and the
/// element damping alike). Exact for the fixed basis; the basis's own change is left out
/// (measured against re-reduction in docs/insight.md).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ComponentInput {
    pub component: String,
    /// One volume of the component (its `materials.<volume>`), None: every material of it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub volume: Option<String>,
    pub property: ComponentProperty,
    /// The key's value at scale 1 (1 for a `*_scale` key, E₀ or ρ₀ for a material key).
    pub base: Real,
}

/// The component property a key names, if it is one a propensity study varies on the reduced
/// model: `components.<name>.young_scale` / `density_scale` (every material of the component
/// scaled), `components.<i|name>.material.young` / `.density` of a component with that one
/// isotropic material (both exact on the fixed basis), or `components.<i|name>.materials.
/// <volume>.young` / `.density` of one isotropic volume (first order in the basis change,
/// checked against re-reduction: [`basis_check`]). None: another key. A component or
/// material that does not fit is an error naming the key.
pub fn component_input(scene: &Scene, key: &str) -> Result<Option<ComponentInput>, String> {
    let parts: Vec<&str> = key.split('.').collect();
    if parts.first() != Some(&"components") || parts.len() < 3 {
        return Ok(None);
    }
    let find = |id: &str| {
        id.parse::<usize>()
            .ok()
            .and_then(|i| scene.components.get(i))
            .or_else(|| scene.components.iter().find(|c| c.name == id))
            .ok_or_else(|| {
                let names: Vec<&str> = scene.components.iter().map(|c| c.name.as_str()).collect();
                format!("no component `{id}` (the scene has {names:?})")
            })
    };
    let (c, property, base) = match parts[2..] {
        ["materials", volume, prop @ ("young" | "density")] => {
            let c = find(parts[1])?;
            let m = c.materials.get(volume).ok_or_else(|| {
                let names: Vec<&String> = c.materials.keys().collect();
                format!(
                    "component `{}` has no `materials.{volume}` (it has {names:?})",
                    c.name
                )
            })?;
            let (property, base) = match prop {
                "young" => (
                    ComponentProperty::YoungScale,
                    m.young.ok_or_else(|| {
                        format!(
                            "`materials.{volume}` of `{}` is anisotropic (no `young`): vary it \
                             with --rereduce",
                            c.name
                        )
                    })?,
                ),
                _ => (ComponentProperty::DensityScale, m.density),
            };
            return Ok(Some(ComponentInput {
                component: c.name.clone(),
                volume: Some(volume.to_string()),
                property,
                base,
            }));
        }
        ["young_scale"] => (find(parts[1])?, ComponentProperty::YoungScale, 1.0),
        ["density_scale"] => (find(parts[1])?, ComponentProperty::DensityScale, 1.0),
        ["material", prop @ ("young" | "density")] => {
            let c = find(parts[1])?;
            let single = |what: &str| {
                format!(
                    "component `{}` {what}: vary `components.{}.{prop}_scale` (every material \
                     of it scaled on the reduced model), `components.{}.materials.<volume>.\
                     {prop}` (one volume, checked against re-reduction) or pass --rereduce",
                    c.name, c.name, c.name
                )
            };
            if !c.materials.is_empty() {
                let names: Vec<&String> = c.materials.keys().collect();
                return Err(single(&format!(
                    "has materials of its own volumes ({names:?})"
                )));
            }
            let m = c
                .material
                .as_ref()
                .ok_or_else(|| single("has no `material` table"))?;
            match prop {
                "young" => (
                    c,
                    ComponentProperty::YoungScale,
                    m.young
                        .ok_or_else(|| single("has an anisotropic material (no `young`)"))?,
                ),
                _ => (c, ComponentProperty::DensityScale, m.density),
            }
        }
        _ => return Ok(None),
    };
    Ok(Some(ComponentInput {
        component: c.name.clone(),
        volume: None,
        property,
        base,
    }))
}

/// The study before any evaluation: inputs, correlation and design (JSON: what the Python
/// package hands to each chunk's task).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Plan {
    pub inputs: Vec<Input>,
    /// The correlation matrix of the normal scores (None: independent inputs).
    pub correlation: Option<Vec<Vec<Real>>>,
    /// The model is rebuilt for every sample (an input changes it, `--rereduce`).
    pub rereduce: bool,
    pub seed: u32,
    /// The evaluation budget asked for.
    pub budget: usize,
    pub design: Design,
}

impl Plan {
    /// The input keys, in order.
    pub fn keys(&self) -> Vec<String> {
        self.inputs.iter().map(|i| i.key.clone()).collect()
    }
}

/// A number as a TOML value text that reads back to the same f64.
pub fn value_text(x: Real) -> String {
    let s = format!("{x:?}");
    if s.contains('.') || s.contains('e') || s.contains("inf") || s.contains("NaN") {
        s
    } else {
        format!("{s}.0")
    }
}

fn dist_err(key: &str, text: &str, message: String) -> PipelineError {
    PipelineError::Option {
        option: format!("--dist {key}={text}"),
        message,
    }
}

/// Parses `KEY=DIST` (the `--dist` flag's value).
pub fn parse_dist_flag(flag: &str) -> Result<(String, String), PipelineError> {
    match flag.split_once('=') {
        Some((k, d)) if !k.trim().is_empty() && !d.trim().is_empty() => {
            Ok((k.trim().to_string(), d.trim().to_string()))
        }
        _ => Err(PipelineError::Option {
            option: format!("--dist {flag}"),
            message: "expected KEY=DIST, e.g. friction.law.mu=uniform(0.35, 0.55)".into(),
        }),
    }
}

/// Parses `A:B=ρ` (the `--corr` flag's value).
pub fn parse_corr_flag(flag: &str) -> Result<(String, String, Real), PipelineError> {
    let err = |m: &str| PipelineError::Option {
        option: format!("--corr {flag}"),
        message: format!("{m}; write KEY_A:KEY_B=RHO, e.g. friction.law.mu:loads.pmax=0.5"),
    };
    let (pair, rho) = flag.split_once('=').ok_or_else(|| err("no `=`"))?;
    let (a, b) = pair
        .split_once(':')
        .ok_or_else(|| err("no `:` between the keys"))?;
    let rho: Real = rho
        .trim()
        .parse()
        .map_err(|_| err(&format!("`{}` is not a number", rho.trim())))?;
    Ok((a.trim().to_string(), b.trim().to_string(), rho))
}

/// The replicate count in 4..=8 whose design uses the most of `budget` evaluations.
fn auto_replicates(budget: usize, per_base: usize) -> usize {
    (4..=8usize)
        .max_by_key(|&r| {
            let per = budget / r / per_base;
            let n = if per == 0 {
                0
            } else {
                1usize << (usize::BITS - 1 - per.leading_zeros())
            };
            (r * n * per_base, std::cmp::Reverse(r))
        })
        .unwrap_or(4)
}

/// Checks the inputs against the scene and builds the design. Every key must be a value the
/// scene accepts (set to the distribution's mean and to its quartiles); a key that changes
/// the reduced model (its cache key) is refused unless `args.rereduce`.
pub fn plan(scene: &Scene, args: &PropensityArgs) -> Result<Plan, PipelineError> {
    if args.dists.is_empty() {
        return Err(PipelineError::Option {
            option: "--dist".into(),
            message: "a propensity study needs at least one --dist KEY=DIST".into(),
        });
    }
    let base_key = ModelKey::of(scene)?.hex;
    let mut inputs = Vec::with_capacity(args.dists.len());
    for (key, text) in &args.dists {
        if inputs.iter().any(|i: &Input| &i.key == key) {
            return Err(dist_err(
                key,
                text,
                "this key has a distribution already".into(),
            ));
        }
        let d = Distribution::parse(key, text)?;
        let component = if args.rereduce && !key.ends_with("_scale") {
            None
        } else {
            component_input(scene, key).map_err(|m| dist_err(key, text, m))?
        };
        if let Some(c) = &component {
            let q = d.quantile(0.001) / c.base;
            if q.is_nan() || q <= 0.0 {
                return Err(dist_err(
                    key,
                    text,
                    format!(
                        "a scale of component `{}` must stay positive (its 0.1 % quantile is \
                         {})",
                        c.component,
                        d.quantile(0.001)
                    ),
                ));
            }
            inputs.push(Input {
                key: key.clone(),
                text: text.clone(),
                mean: d.mean(),
                distribution: d,
                reuses_model: true,
                component,
            });
            continue;
        }
        let mut reuses = true;
        for u in [0.25, 0.5, 0.75] {
            let v = value_text(d.quantile(u));
            let s = values::scene_for_all(scene, &[(key.clone(), v.clone())]).map_err(|e| {
                let m = match e {
                    PipelineError::Option { message, .. } => message,
                    other => other.to_string(),
                };
                dist_err(key, text, format!("at {key} = {v}: {m}"))
            })?;
            if ModelKey::of(&s)?.hex != base_key {
                reuses = false;
            }
        }
        if !reuses && !args.rereduce {
            return Err(dist_err(
                key,
                text,
                format!(
                    "`{key}` changes the reduced model (what meshing, FE and the Craig-Bampton \
                     reduction see), which a propensity study builds once: vary a value applied \
                     to the reduced model (friction.law.*, loads.pmax, contact.N.p0, rotor.rpm, \
                     contact.N.normal_stiffness, damping.*, components.<name>.young_scale or \
                     density_scale on the reduced model), or pass --rereduce to rebuild the \
                     model for every sample (slow: one reduction per sample)"
                ),
            ));
        }
        inputs.push(Input {
            key: key.clone(),
            text: text.clone(),
            mean: d.mean(),
            distribution: d,
            reuses_model: reuses,
            component: None,
        });
    }
    if let (Some(c), true) = (
        inputs.iter().find(|i| i.component.is_some()),
        inputs.iter().any(|i| !i.reuses_model),
    ) {
        return Err(dist_err(
            &c.key,
            &c.text,
            "varies the one reduced model, which an input that changes the model (rebuilt per \
             sample, --rereduce) replaces: give the component's `material` key instead"
                .into(),
        ));
    }
    let d = inputs.len();
    let correlation = if args.corr.is_empty() {
        None
    } else {
        let mut r = vec![vec![0.0; d]; d];
        (0..d).for_each(|i| r[i][i] = 1.0);
        for (a, b, rho) in &args.corr {
            let pos = |k: &str| {
                inputs
                    .iter()
                    .position(|i| i.key == k)
                    .ok_or_else(|| PipelineError::Option {
                        option: format!("--corr {a}:{b}={rho}"),
                        message: format!("`{k}` has no --dist"),
                    })
            };
            let (i, j) = (pos(a)?, pos(b)?);
            if i == j {
                return Err(PipelineError::Option {
                    option: format!("--corr {a}:{b}={rho}"),
                    message: "a key's correlation with itself is 1".into(),
                });
            }
            r[i][j] = *rho;
            r[j][i] = *rho;
        }
        Some(r)
    };
    let copula = correlation.as_deref().map(Copula::new).transpose()?;
    let dists: Vec<Distribution> = inputs.iter().map(|i| i.distribution.clone()).collect();
    let per_base = if copula.is_none() && d > 1 { d + 2 } else { 2 };
    let replicates = args
        .replicates
        .unwrap_or_else(|| auto_replicates(args.samples, per_base));
    let design = Design::new(&dists, copula.as_ref(), args.samples, replicates, args.seed)?;
    Ok(Plan {
        rereduce: inputs.iter().any(|i| !i.reuses_model),
        inputs,
        correlation,
        seed: args.seed,
        budget: args.samples,
        design,
    })
}

/// Evaluates the design rows `rows` (indices into `plan.design.rows`) on rayon's threads.
pub fn evaluate_rows(
    ev: &Evaluator,
    plan: &Plan,
    rows: &[usize],
    progress: &Progress,
) -> Result<Vec<Sample>, PipelineError> {
    let done = std::sync::atomic::AtomicUsize::new(0);
    let bar = progress.bar(format!("{} CEAs", rows.len()));
    let quiet = progress.silenced();
    let out: Vec<Result<Sample, PipelineError>> = rows
        .par_iter()
        .map(|&r| {
            progress.check("propensity")?;
            let s = ev.evaluate(r, &plan.design.rows[r].values, &quiet);
            let k = done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
            bar.set(k as f64 / rows.len().max(1) as f64, || {
                format!("{k}/{}", rows.len())
            });
            s
        })
        .collect();
    bar.finish(format!("{} CEAs", rows.len()));
    out.into_iter().collect()
}

/// The whole study in memory on a model built once for `scene` (or per sample with
/// `--rereduce`): plan, evaluations, estimates.
pub fn compute(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    args: &PropensityArgs,
    cache: Option<&model::ModelCache>,
) -> Result<(Plan, Vec<Sample>, PropensityOut), PipelineError> {
    let wall = Instant::now();
    let plan = plan(scene, args)?;
    progress.info(format!(
        "propensity: {} inputs, {} evaluations ({} replicates × {} base points{}), {}",
        plan.inputs.len(),
        plan.design.rows.len(),
        plan.design.replicates,
        plan.design.n_base,
        if plan.design.indices {
            " with the Sobol-index rows"
        } else {
            ""
        },
        if plan.rereduce {
            "the model rebuilt per sample"
        } else {
            "one reduced model"
        }
    ));
    let t0 = Instant::now();
    let mut ev = Evaluator::new(scene, &plan, dir, progress, cache)?;
    ev.check_basis(&plan, dir, (args.basis_tolerance, BASIS_FLOOR), progress)?;
    let build_s = t0.elapsed().as_secs_f64();
    let rows: Vec<usize> = (0..plan.design.rows.len()).collect();
    let t1 = Instant::now();
    let samples = evaluate_rows(&ev, &plan, &rows, progress)?;
    let eval_s = t1.elapsed().as_secs_f64();
    let mut out = report::estimate(scene, &plan, &samples, &ev.info())?;
    out.stats.build_s = build_s;
    out.stats.evaluate_s = eval_s;
    out.stats.wall_s = wall.elapsed().as_secs_f64();
    out.stats.threads = rayon::current_num_threads();
    out.stats.phases = Some(ev.phases());
    Ok((plan, samples, out))
}

/// `propensity.json`, `samples.csv`, `summary.json` (the same as `propensity.json`).
pub fn write(
    dir: &RunDir,
    plan: &Plan,
    samples: &[Sample],
    out: &mut PropensityOut,
) -> Result<Vec<String>, PipelineError> {
    let csv = report::samples_csv(plan, samples);
    let mut files = vec![dir
        .write_bytes("samples.csv", csv.as_bytes())?
        .display()
        .to_string()];
    files.push(dir.path("propensity.json").display().to_string());
    out.files = files.clone();
    dir.write_json("propensity.json", out)?;
    dir.write_json("summary.json", out)?;
    Ok(files)
}

/// Runs `squeal propensity`: [`compute`] then [`write`].
pub fn run(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    args: &PropensityArgs,
    cache: Option<&model::ModelCache>,
) -> Result<PropensityOut, PipelineError> {
    dir.write_bytes("scene.resolved.toml", scene.resolved_toml().as_bytes())?;
    let (plan, samples, mut out) = compute(scene, dir, progress, args, cache)?;
    write(dir, &plan, &samples, &mut out)?;
    Ok(out)
}

#[cfg(test)]
mod tests;
