//! Sensitivities of the CEA's roots to the design parameters ([`super::params`]):
//! `cea.json`'s `sensitivity` and `sensitivity.csv` (`[cea] sensitivity`, default on).
//!
//! For each root `p` (the unstable ones and the [`STABLE_ROOTS`] stable ones with the largest
//! Re p) the left and right eigenvectors of the bordered problem
//! (`squeal_solver::insight::eigen_triplet`), and for each parameter θ
//! ```text
//! ∂p/∂θ = −yᴴ (∂Q/∂θ) x / yᴴ (∂Q/∂p) x,   ∂Q/∂p x = [(2pM + C) φ; 0]
//! ```
//! (`squeal_solver::insight::eigenvalue_derivative`; docs/insight.md). The matrix derivative
//! `∂(M, C, K, G, D)/∂θ` is exact for the density scales and loss factors (the matrices are
//! linear in them, the state does not move); for the parameters that move the operating
//! point it is the central difference of the matrices over `θ ± h`, `h = STEP × scale`, with
//! the steady state solved again at each side (a semi-analytic derivative: no eigenproblem is
//! solved again and no root has to be tracked).
//!
//! **Ranking.** Per root the parameters are sorted by |scale · ∂Re p/∂θ| (the normalised
//! sensitivity: the change of Re p, 1/s, for a change of θ by its own size, or by its typical
//! size when θ = 0), with the first-order change `Δθ = −Re p / (∂Re p/∂θ)` that would bring
//! Re p to zero and whether θ + Δθ stays in the parameter's physical range.

use super::params::{matrices_at, parameters, Base, Parameter, StateTangent};
use crate::error::PipelineError;
use crate::output::RunDir;
use serde::Serialize;
use squeal_solver::cea::{CeaMatrices, Mode};
use squeal_solver::insight::{eigenvalue_derivative, MatrixDerivative, TripletSolver};
use std::time::Instant;

use squeal_solver::Real;

/// Relative step of the matrices' central difference (× the parameter's scale).
pub const STEP: Real = 1e-4;

/// Stable roots with the largest Re p that get sensitivities beside the unstable ones.
pub const STABLE_ROOTS: usize = 10;

/// Whether the first-order change brings Re p to zero within the parameter's range.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Reach {
    /// θ + Δθ is in [lower, upper] and |Δθ| ≤ scale.
    Reachable,
    /// θ + Δθ is in range but |Δθ| > scale (more than the parameter's own size, or its
    /// typical size at 0): far beyond where the first-order estimate can be trusted.
    BeyondFirstOrder,
    /// θ + Δθ is outside the physical range (e.g. a negative μ or modulus).
    OutsideRange,
    /// ∂Re p/∂θ is zero (or below 1e-12 |p| per unit scale): not reachable to first order.
    ZeroDerivative,
}

/// One parameter's effect on one root.
#[derive(Debug, Clone, Serialize)]
pub struct ParamSensitivity {
    pub name: String,
    pub value: Real,
    /// ∂Re p/∂θ (1/s per unit of θ).
    pub d_real_part: Real,
    /// ∂f/∂θ = ∂Im p/∂θ / 2π, Hz per unit of θ (sign of the root's Im p).
    pub d_frequency_hz: Real,
    /// scale × ∂Re p/∂θ (1/s): the ranking key.
    pub normalised: Real,
    /// Δθ = −Re p / (∂Re p/∂θ) (None: zero derivative).
    pub delta_to_neutral: Option<Real>,
    /// θ + Δθ.
    pub value_at_neutral: Option<Real>,
    pub status: Reach,
}

/// The sensitivities of one root.
#[derive(Debug, Clone, Serialize)]
pub struct RootSensitivity {
    /// Index into `modes`.
    pub mode: usize,
    pub frequency_hz: Real,
    pub real_part: Real,
    pub unstable: bool,
    /// The root refined by the two-sided Rayleigh functional (the derivatives are at it).
    pub refined_real_part: Real,
    /// Relative residuals of the right and left eigenvectors.
    pub residual: Real,
    pub left_residual: Real,
    /// `|yᴴ(2pM + C)x| / (‖ψ‖‖φ‖)`: near 0 at a double root (coalescence), where the first
    /// derivative loses its meaning.
    pub denominator: Real,
    /// Sorted by |normalised|, largest first.
    pub params: Vec<ParamSensitivity>,
}

/// `cea.json`'s `sensitivity`.
#[derive(Debug, Clone, Serialize)]
pub struct SensitivityOut {
    /// The parameters varied (value, scale, range, whether they move the steady state).
    pub parameters: Vec<Parameter>,
    /// What was not varied and why.
    pub notes: Vec<String>,
    /// Relative step of the matrices' central difference.
    pub step: Real,
    /// The approximation of the component properties.
    pub component_basis: &'static str,
    /// Unstable roots (most unstable first), then the stable ones with the largest Re p.
    pub roots: Vec<RootSensitivity>,
    /// Parameters whose steady-state derivative was solved (one solve each with the one
    /// factorisation of the steady state's Newton matrix, [`StateTangent`]).
    pub n_state_solves: usize,
    /// The left and right eigenvectors' complex LU per root: `"null_space"` (size n − ng) or
    /// `"bordered"` (n + ng).
    pub triplet_factorisation: &'static str,
    /// Seconds: all, the eigenvector triplets, the parameters' matrix derivatives (steady
    /// states and matrices at θ ± h), and the products ψᴴ(∂Q/∂θ)φ.
    pub time_s: Real,
    pub time_triplets_s: Real,
    pub time_derivatives_s: Real,
    pub time_products_s: Real,
}

const COMPONENT_BASIS: &str = "Craig-Bampton basis held fixed (reduced blocks scaled); exact \
for a uniform scale of a component's materials while the modal cut-off keeps the same modes";

/// The roots to differentiate: the unstable ones of `unstable` (most unstable first), then the
/// [`STABLE_ROOTS`] stable ones with the largest Re p.
fn chosen(modes: &[Mode], unstable: &[usize]) -> Vec<usize> {
    let mut stable: Vec<usize> = (0..modes.len())
        .filter(|i| !unstable.contains(i) && !modes[*i].shape.is_empty())
        .collect();
    stable.sort_by(|&a, &b| modes[b].real_part.total_cmp(&modes[a].real_part));
    stable.truncate(STABLE_ROOTS);
    unstable
        .iter()
        .copied()
        .filter(|&i| !modes[i].shape.is_empty())
        .chain(stable)
        .collect()
}

/// The matrix derivative of `param` at `base` by central difference (one-sided over
/// `[θ, θ + 2h]` when `θ − h` is below the parameter's range), the state moved along its
/// derivative when the parameter moves it (`tangent`); and whether it did.
pub fn matrix_derivative(
    base: &Base,
    param: &Parameter,
    tangent: Option<&StateTangent>,
) -> Result<(MatrixDerivative, bool), PipelineError> {
    let h = STEP * param.scale;
    let (a, b) = if param.value - h < param.lower {
        (param.value + 2.0 * h, param.value)
    } else {
        (param.value + h, param.value - h)
    };
    let [plus, minus] = matrices_at(base, param, [a, b], tangent)?;
    let dq = MatrixDerivative::central_difference(&plus, &minus, h)
        .map_err(|source| PipelineError::cea(format!("derivative of {}", param.name), source))?;
    Ok((dq, param.moves_state && tangent.is_some()))
}

/// The sensitivities of the roots `modes` (the CEA's reported roots, on `sys`).
pub fn sensitivities(
    base: &Base,
    sys: &CeaMatrices,
    modes: &[Mode],
    unstable: &[usize],
) -> Result<SensitivityOut, PipelineError> {
    let t0 = Instant::now();
    let (mut params, mut notes) = parameters(base.scene, base.model, &base.problem.gaps);
    let which = chosen(modes, unstable);
    let solver = TripletSolver::new(sys)
        .map_err(|source| PipelineError::cea("left and right eigenvectors".into(), source))?;
    let mut triplets = Vec::with_capacity(which.len());
    for &i in &which {
        let t = solver.triplet(modes[i].eigenvalue).map_err(|source| {
            PipelineError::cea(format!("left and right eigenvectors of mode {i}"), source)
        })?;
        triplets.push(t);
    }
    let time_triplets_s = t0.elapsed().as_secs_f64();
    let (mut time_derivatives_s, mut time_products_s) = (0.0, 0.0);
    let mut per_root: Vec<Vec<ParamSensitivity>> = vec![Vec::new(); which.len()];
    let mut n_state_solves = 0;
    // One factorisation of the steady state's Newton matrix for every parameter.
    let tangent = StateTangent::of(base);
    // A parameter whose difference cannot be formed is left out and named in `notes`: the
    // roots and the other parameters stand.
    let mut computed = Vec::with_capacity(params.len());
    for param in params.drain(..) {
        let td = Instant::now();
        let derivative = matrix_derivative(base, &param, tangent.as_ref());
        time_derivatives_s += td.elapsed().as_secs_f64();
        let (dq, solves) = match derivative {
            Ok((dq, moved)) => (dq, usize::from(moved)),
            Err(e) => {
                notes.push(format!("{}: not computed: {e}", param.name));
                continue;
            }
        };
        n_state_solves += solves;
        let tp = Instant::now();
        for (r, t) in triplets.iter().enumerate() {
            let s = eigenvalue_derivative(sys, t, &dq);
            per_root[r].push(entry(&param, t.p, s.dp));
        }
        time_products_s += tp.elapsed().as_secs_f64();
        computed.push(param);
    }
    let params = computed;
    let roots = which
        .iter()
        .zip(triplets)
        .zip(per_root)
        .map(|((&i, t), mut ps)| {
            ps.sort_by(|a, b| b.normalised.abs().total_cmp(&a.normalised.abs()));
            let den = eigenvalue_derivative(sys, &t, &MatrixDerivative::default()).denominator;
            RootSensitivity {
                mode: i,
                frequency_hz: modes[i].frequency_hz,
                real_part: modes[i].real_part,
                unstable: unstable.contains(&i),
                refined_real_part: t.p.re,
                residual: t.residual,
                left_residual: t.left_residual,
                denominator: den,
                params: ps,
            }
        })
        .collect();
    Ok(SensitivityOut {
        parameters: params,
        notes,
        step: STEP,
        component_basis: COMPONENT_BASIS,
        roots,
        n_state_solves,
        triplet_factorisation: solver.factorisation(),
        time_s: t0.elapsed().as_secs_f64(),
        time_triplets_s,
        time_derivatives_s,
        time_products_s,
    })
}

/// One ranked entry from ∂p/∂θ.
fn entry(
    param: &Parameter,
    p: squeal_solver::cea::Cplx,
    dp: squeal_solver::cea::Cplx,
) -> ParamSensitivity {
    let d_re = dp.re;
    let normalised = param.scale * d_re;
    let sign = if p.im < 0.0 { -1.0 } else { 1.0 };
    let zero = !d_re.is_finite() || normalised.abs() <= 1e-12 * p.norm().max(1.0);
    let delta = (!zero).then(|| -p.re / d_re);
    let at = delta.map(|d| param.value + d);
    let status = match at {
        None => Reach::ZeroDerivative,
        Some(v) if v < param.lower || v > param.upper => Reach::OutsideRange,
        Some(v) if (v - param.value).abs() > param.scale => Reach::BeyondFirstOrder,
        Some(_) => Reach::Reachable,
    };
    ParamSensitivity {
        name: param.name.clone(),
        value: param.value,
        d_real_part: d_re,
        d_frequency_hz: sign * dp.im / (2.0 * std::f64::consts::PI),
        normalised,
        delta_to_neutral: delta,
        value_at_neutral: at,
        status,
    }
}

/// `sensitivity.csv`: the ranked table of every unstable root (one row per root and
/// parameter, rank 1 = largest |normalised|). Returns its path (None: no table asked for).
pub fn write_table(dir: &RunDir, s: &SensitivityOut) -> Result<Option<String>, PipelineError> {
    let mut text = String::from(
        "mode,frequency_hz,real_part,rank,parameter,value,d_real_part,d_frequency_hz,\
         normalised,delta_to_neutral,value_at_neutral,status\n",
    );
    let opt = |x: Option<Real>| x.map_or(String::new(), |v| format!("{v:.9e}"));
    for r in s.roots.iter().filter(|r| r.unstable) {
        for (k, p) in r.params.iter().enumerate() {
            text.push_str(&format!(
                "{},{:.6},{:.6},{},{},{:.9e},{:.9e},{:.9e},{:.9e},{},{},{}\n",
                r.mode,
                r.frequency_hz,
                r.real_part,
                k + 1,
                p.name,
                p.value,
                p.d_real_part,
                p.d_frequency_hz,
                p.normalised,
                opt(p.delta_to_neutral),
                opt(p.value_at_neutral),
                match p.status {
                    Reach::Reachable => "reachable",
                    Reach::OutsideRange => "outside_range",
                    Reach::BeyondFirstOrder => "beyond_first_order",
                    Reach::ZeroDerivative => "zero_derivative",
                }
            ));
        }
    }
    Ok(Some(
        dir.write_bytes("sensitivity.csv", text.as_bytes())?
            .display()
            .to_string(),
    ))
}
