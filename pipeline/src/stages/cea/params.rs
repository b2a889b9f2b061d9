//! The design parameters of the CEA's sensitivities (`cea.json`'s `sensitivity`) and the
//! CEA matrices at a changed parameter value.
//!
//! A parameter enters the CEA matrices `(M, C = B − C_f, K, G, D)` in one of two ways:
//! - **directly**: a component's density scale and loss factor change M and B only; the
//!   steady state (a static equilibrium) and so the friction tangents stay;
//! - **through the operating point**: μ and the law's parameters, the brake pressure (PMAX),
//!   the rotor speed, a contact pair's normal stiffness and a component's Young's modulus
//!   change the steady sliding state (u, λ̇), so the tangents D = ∂F_f/∂λ̇ and C_f = ∂F_f/∂v
//!   (law derivatives at the new pressure and slip speed) and the compliant fold of the gaps
//!   into K move with them. [`matrices_at`] moves the state along its derivative by the
//!   implicit function theorem ([`StateTangent`]: one factorisation of the steady state's
//!   Newton matrix for every parameter; a restart file's state stays as read: only the direct
//!   part is seen).
//!
//! **Component properties** use the reduced matrices with the Craig–Bampton basis held fixed
//! ([`component_matrix_derivative`]): the component's block `T_cᵀ K_c T_c` scaled. For a
//! uniform scale of every material of a component (what these parameters are) the fixed-
//! interface modes and constraint modes are unchanged (an eigenvector of (sK, M) or (K, sM)
//! is one of (K, M); `K_ii⁻¹K_ib` does not see s), so the basis is exact for small changes
//! unless the modal cut-off selects other modes; docs/insight.md measures it.

use super::energy::{from_reductions, scatter_check};
use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::problem::system::{damping_matrix, Problem};
use crate::problem::tangents::{
    cea_matrices, full_load_time, tangents, Linearisation, StateSource,
};
use crate::scene::{CeaSpec, Scene};
use faer::linalg::solvers::Solve;
use faer::Mat;
use serde::Serialize;
use squeal_contact::{FrictionLaw, GapSet};
use squeal_solver::cea::CeaMatrices;

use squeal_solver::Real;

/// What a parameter is.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ParamKind {
    /// A coefficient of the scene's friction law (`friction.law.<field>`; a table law: the
    /// scale of all its μ values, value 1).
    FrictionLaw { field: String },
    /// `loads.pmax`, the scale of the brake load (the brake pressure's factor).
    BrakePressure,
    /// `rotor.rpm` (every gap's sliding velocity ω × r scales with it).
    RotorSpeed,
    /// `contact[pair].normal_stiffness` (a compliant pair only).
    NormalStiffness { pair: usize },
    /// Scale of the Young's moduli of every material of a component (value 1).
    YoungScale { component: String },
    /// Scale of the densities of every material of a component (value 1).
    DensityScale { component: String },
    /// Element damping (loss factor) GE of a component, viscous at `damping.w4`.
    LossFactor { component: String },
}

/// Which [`ComponentProperty`] a reduced-matrix derivative is of.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ComponentProperty {
    /// θ = scale s of every Young's modulus of the component (E = s E₀).
    YoungScale,
    /// θ = scale s of every density of the component (ρ = s ρ₀).
    DensityScale,
    /// θ = GE of the component (`damping.ge.<component>`, viscous GE/W4).
    LossFactor,
}

/// A parameter and its value in the scene.
#[derive(Debug, Clone, Serialize)]
pub struct Parameter {
    /// Scene key (or a descriptive key for the scales): `friction.law.mu0`, `loads.pmax`,
    /// `rotor.rpm`, `contact[0].normal_stiffness`, `components.rotor.young_scale`, ….
    pub name: String,
    #[serde(flatten)]
    pub kind: ParamKind,
    /// Its value.
    pub value: Real,
    /// The scale of a change: |value|, or a typical size when the value is 0 (its step is
    /// `step × scale`, its normalised sensitivity `scale × ∂Re p/∂θ`).
    pub scale: Real,
    /// Physically admissible range [lower, upper] (a zero change to stability outside it is
    /// reported `outside_range`).
    pub lower: Real,
    pub upper: Real,
    /// Whether it changes the steady state (then the state is solved again at θ ± h).
    pub moves_state: bool,
}

/// The parameters of `scene`/`model`: the friction law's coefficients, PMAX, the rotor speed
/// (when it turns), each compliant pair's k_n, and per component (meshed models with their
/// Craig–Bampton blocks) the Young's and density scales and, with `damping.w4 > 0`, GE.
/// Gaps with a friction law of their own (a pair's `friction`) are not varied: `notes` says.
pub fn parameters(
    scene: &Scene,
    model: &ReducedModel,
    gaps: &GapSet,
) -> (Vec<Parameter>, Vec<String>) {
    let mut out = Vec::new();
    let mut notes = Vec::new();
    let p =
        |name: String, kind, value: Real, typical: Real, lo: Real, hi: Real, mv: bool| Parameter {
            name,
            kind,
            value,
            scale: if value != 0.0 { value.abs() } else { typical },
            lower: lo,
            upper: hi,
            moves_state: mv,
        };
    let mu_max = squeal_contact::friction::MU_MAX;
    let inf = Real::INFINITY;
    for (field, value, typical, lo, hi) in law_fields(&gaps.law, gaps) {
        out.push(p(
            format!("friction.law.{field}"),
            ParamKind::FrictionLaw {
                field: field.to_string(),
            },
            value,
            typical,
            lo.unwrap_or(-inf),
            hi.unwrap_or(inf)
                .min(if lo.is_some() { mu_max } else { inf }),
            true,
        ));
    }
    if gaps.gaps.iter().any(|g| g.friction.is_some()) {
        notes.push(
            "gaps with a friction law of their own (a pair's `friction`) keep it: only the \
             scene's `[friction]` law is varied"
                .into(),
        );
    }
    let loads = scene.loads.clone().unwrap_or_default();
    if model.p_brake.iter().any(|&x| x != 0.0) {
        out.push(p(
            "loads.pmax".into(),
            ParamKind::BrakePressure,
            loads.pmax,
            1.0,
            0.0,
            inf,
            true,
        ));
    }
    let rpm = scene.rotor.clone().unwrap_or_default().rpm;
    if rpm != 0.0 {
        out.push(p(
            "rotor.rpm".into(),
            ParamKind::RotorSpeed,
            rpm,
            1.0,
            0.0,
            inf,
            true,
        ));
    }
    if model.gap_pairs.iter().sum::<usize>() == gaps.len() {
        for (i, c) in scene.contact.iter().enumerate() {
            if let Some(kn) = c.normal_stiffness {
                out.push(p(
                    format!("contact[{i}].normal_stiffness"),
                    ParamKind::NormalStiffness { pair: i },
                    kn,
                    kn,
                    0.0,
                    inf,
                    true,
                ));
            }
        }
    }
    let damping = scene.damping.clone().unwrap_or_default();
    match from_reductions(model, 0.0) {
        Some(parts) if scatter_check(&parts, &model.m, &model.k) <= 1e-10 => {
            for c in &parts {
                let n = &c.name;
                out.push(p(
                    format!("components.{n}.young_scale"),
                    ParamKind::YoungScale {
                        component: n.clone(),
                    },
                    1.0,
                    1.0,
                    0.0,
                    inf,
                    true,
                ));
                out.push(p(
                    format!("components.{n}.density_scale"),
                    ParamKind::DensityScale {
                        component: n.clone(),
                    },
                    1.0,
                    1.0,
                    0.0,
                    inf,
                    false,
                ));
                if damping.w4 > 0.0 {
                    out.push(p(
                        format!("damping.ge.{n}"),
                        ParamKind::LossFactor {
                            component: n.clone(),
                        },
                        damping.ge.get(n).copied().unwrap_or(0.0),
                        0.1,
                        0.0,
                        inf,
                        false,
                    ));
                }
            }
            if damping.w4 <= 0.0 {
                notes.push(
                    "damping.w4 = 0: element damping GE has no effect, so no loss-factor \
                     parameters"
                        .into(),
                );
            }
        }
        Some(_) => notes.push(
            "the components' Craig-Bampton blocks do not reassemble the model's M and K \
             (to 1e-10): no component-property parameters"
                .into(),
        ),
        None => notes.push(
            "stored reduced matrices have no component blocks: no component-property \
             parameters"
                .into(),
        ),
    }
    (out, notes)
}

/// `(field, value, typical scale when 0, lower bound, upper bound)` of a law's coefficients;
/// a lower bound `Some(0)` marks a friction coefficient (upper bound MU_MAX).
type LawField = (&'static str, Real, Real, Option<Real>, Option<Real>);

fn law_fields(law: &FrictionLaw, gaps: &GapSet) -> Vec<LawField> {
    // Typical pressure and slip speed for the zero-valued sensitivities' scales.
    let v_typ = gaps
        .gaps
        .iter()
        .map(|g| g.v_slide.iter().map(|x| x * x).sum::<Real>().sqrt())
        .fold(0.0, Real::max)
        .max(1.0);
    let p_typ = gaps
        .gaps
        .iter()
        .map(|g| g.p0.abs())
        .fold(0.0, Real::max)
        .max(1.0);
    match law {
        FrictionLaw::Constant { mu } => vec![("mu", *mu, 0.1, Some(0.0), None)],
        FrictionLaw::LinearSpeed { mu0, slope } => vec![
            ("mu0", *mu0, 0.1, Some(0.0), None),
            ("slope", *slope, 0.1 / v_typ, None, None),
        ],
        FrictionLaw::Equation { mu0, a, b, c, .. } => vec![
            ("mu0", *mu0, 0.1, Some(0.0), None),
            ("a", *a, 0.1 / p_typ, None, None),
            ("b", *b, 0.1 / v_typ, None, None),
            ("c", *c, 1e-3, None, None),
        ],
        FrictionLaw::Table(_) => vec![("values_scale", 1.0, 1.0, Some(0.0), None)],
    }
}

/// The law with `field` set to `value`.
fn law_with(law: &FrictionLaw, field: &str, value: Real) -> FrictionLaw {
    let mut l = law.clone();
    match &mut l {
        FrictionLaw::Constant { mu } => *mu = value,
        FrictionLaw::LinearSpeed { mu0, slope } => match field {
            "mu0" => *mu0 = value,
            _ => *slope = value,
        },
        FrictionLaw::Equation { mu0, a, b, c, .. } => match field {
            "mu0" => *mu0 = value,
            "a" => *a = value,
            "b" => *b = value,
            _ => *c = value,
        },
        FrictionLaw::Table(t) => t.values.iter_mut().for_each(|v| *v *= value),
    }
    l
}

/// ∂M/∂θ, ∂K/∂θ and ∂B/∂θ of one component property on the assembled reduced DOFs with the
/// Craig–Bampton basis held fixed (`None`: that matrix does not change).
#[derive(Debug, Clone)]
pub struct ReducedDerivative {
    pub m: Option<Mat<Real>>,
    pub k: Option<Mat<Real>>,
    /// ∂B/∂θ: the element damping (GE_c/W4)·K_c and the overall (G/W3)·K parts (exact);
    /// modal damping (`damping.modal_ratio`) is not linear in K and M, and is left out here
    /// (the CEA's sensitivities take it by central difference of the damping matrix).
    pub b: Option<Mat<Real>>,
}

/// The reduced-matrix derivative of `component`'s `property`, the Craig–Bampton basis held
/// fixed: with `S_c` the scatter of the component's reduced coordinates to the assembled ones
/// (`T_c` of `ComponentRecovery::assembled`),
/// ```text
/// YoungScale:   ∂K/∂s = T_cᵀ K_c T_c,   ∂B/∂s = (GE_c/W4 + G/W3) T_cᵀ K_c T_c + T_cᵀ B_η,c T_c
/// DensityScale: ∂M/∂s = T_cᵀ M_c T_c
/// LossFactor:   ∂B/∂GE = T_cᵀ K_c T_c / W4
/// ```
/// All three are exact derivatives of the fixed-basis matrices, which are linear in θ:
/// `A(θ) = A(θ₀) + (θ − θ₀) ∂A/∂θ` for any change (what a propensity study may reuse without
/// re-reducing). Stored matrices (no component blocks), a component not in the model, or
/// blocks that do not reassemble the model's K and M are an error naming the component.
pub fn component_matrix_derivative(
    scene: &Scene,
    model: &ReducedModel,
    component: &str,
    property: ComponentProperty,
) -> Result<ReducedDerivative, PipelineError> {
    let err = |message: String| PipelineError::Scene {
        field: format!("components.{component}"),
        message,
    };
    let parts = from_reductions(model, 0.0).ok_or_else(|| {
        err("the model has no Craig-Bampton blocks (stored reduced matrices)".into())
    })?;
    let check = scatter_check(&parts, &model.m, &model.k);
    if check > 1e-10 {
        return Err(err(format!(
            "the components' blocks do not reassemble the model's K and M (relative \
             difference {check:.2e} > 1e-10)"
        )));
    }
    let c = parts.iter().find(|c| c.name == component).ok_or_else(|| {
        err(format!(
            "no component `{component}` among {:?}",
            parts.iter().map(|c| c.name.as_str()).collect::<Vec<_>>()
        ))
    })?;
    let n = model.n();
    let scatter = |a: &Mat<Real>, f: Real| {
        let mut out = Mat::<Real>::zeros(n, n);
        for (x, &i) in c.dofs.iter().enumerate() {
            for (y, &j) in c.dofs.iter().enumerate() {
                out[(i, j)] = f * a[(x, y)];
            }
        }
        out
    };
    let d = scene.damping.clone().unwrap_or_default();
    Ok(match property {
        ComponentProperty::YoungScale => {
            // c.b = (GE_c/W4)·K_c + the bodies' T_cᵀ B_η T_c: every term scales with the moduli.
            let o = d.overall_factor();
            let b = match &c.b {
                Some(b) => Some(Mat::from_fn(b.nrows(), b.ncols(), |i, j| {
                    b[(i, j)] + o * c.k[(i, j)]
                })),
                None => (o != 0.0)
                    .then(|| Mat::from_fn(c.k.nrows(), c.k.ncols(), |i, j| o * c.k[(i, j)])),
            };
            ReducedDerivative {
                m: None,
                k: Some(scatter(&c.k, 1.0)),
                b: b.map(|b| scatter(&b, 1.0)),
            }
        }
        ComponentProperty::DensityScale => ReducedDerivative {
            m: Some(scatter(&c.m, 1.0)),
            k: None,
            b: None,
        },
        ComponentProperty::LossFactor => {
            if d.w4 <= 0.0 {
                return Err(err("damping.w4 = 0: GE has no effect".into()));
            }
            ReducedDerivative {
                m: None,
                k: None,
                b: Some(scatter(&c.k, 1.0 / d.w4)),
            }
        }
    })
}

/// What the CEA of the base point used: the scene, model, problem, state and `[cea]` table.
pub struct Base<'a> {
    pub scene: &'a Scene,
    pub model: &'a ReducedModel,
    pub problem: &'a Problem,
    pub lin: &'a Linearisation,
    pub spec: &'a CeaSpec,
}

fn axpy(a: &Mat<Real>, f: Real, d: &Mat<Real>) -> Mat<Real> {
    Mat::from_fn(a.nrows(), a.ncols(), |i, j| a[(i, j)] + f * d[(i, j)])
}

/// The problem with `param` at `value` (everything else as in `base`).
pub fn problem_at_value(
    base: &Base,
    param: &Parameter,
    value: Real,
) -> Result<Problem, PipelineError> {
    let (scene, model, pb) = (base.scene, base.model, base.problem);
    let delta = value - param.value;
    // An operating value varies the operating point; the gaps and the load are made anew.
    let mut op = pb.op.clone();
    match &param.kind {
        ParamKind::FrictionLaw { field } => {
            op.friction.law = law_with(&op.friction.law, field, value)
        }
        ParamKind::BrakePressure => op.pmax = value,
        ParamKind::RotorSpeed => op.rotor.rpm = value,
        _ => {}
    }
    let mut problem = pb.at(model, op).map_err(|e| match e {
        PipelineError::Contact { source, .. } => PipelineError::Contact {
            what: format!("friction law with {} = {value}", param.name),
            source,
        },
        e => e,
    })?;
    match &param.kind {
        ParamKind::FrictionLaw { .. } | ParamKind::BrakePressure | ParamKind::RotorSpeed => {}
        ParamKind::NormalStiffness { pair } => {
            let start: usize = model.gap_pairs[..*pair].iter().sum();
            let f = param.value / value; // c = 1/(k_n A)
            for g in start..start + model.gap_pairs[*pair] {
                problem.compliance[g] *= f;
                if let Some(w) = problem.smooth_width.get_mut(g) {
                    *w *= f;
                }
            }
        }
        ParamKind::YoungScale { component }
        | ParamKind::DensityScale { component }
        | ParamKind::LossFactor { component } => {
            let prop = match &param.kind {
                ParamKind::YoungScale { .. } => ComponentProperty::YoungScale,
                ParamKind::DensityScale { .. } => ComponentProperty::DensityScale,
                _ => ComponentProperty::LossFactor,
            };
            let d = component_matrix_derivative(scene, model, component, prop)?;
            let m =
                d.m.as_ref()
                    .map_or_else(|| model.m.clone(), |x| axpy(&model.m, delta, x));
            let k =
                d.k.as_ref()
                    .map_or_else(|| model.k.clone(), |x| axpy(&model.k, delta, x));
            // The model's own B is the element damping; the overall and modal parts come
            // from `damping_matrix` on the changed K and M.
            let elem = match prop {
                ComponentProperty::LossFactor => d.b.clone(),
                // ∂B/∂s less its overall part (G/W3)·∂K, which `damping_matrix` adds from the
                // changed K: GE_c/W4 and the bodies' loss factors.
                ComponentProperty::YoungScale => match (&d.b, &d.k) {
                    (Some(b), Some(k)) => {
                        let o = scene.damping.clone().unwrap_or_default().overall_factor();
                        Some(axpy(b, -o, k))
                    }
                    _ => None,
                },
                ComponentProperty::DensityScale => None,
            };
            let b_el = match (&model.b, &elem) {
                (Some(b), Some(e)) => Some(axpy(b, delta, e)),
                (None, Some(e)) => Some(axpy(&Mat::zeros(e.nrows(), e.ncols()), delta, e)),
                (b, None) => b.clone(),
            };
            let light = ReducedModel {
                k,
                m,
                b: b_el,
                p_brake: Vec::new(),
                dofs: model.dofs.clone(),
                gap_geometry: GapSet {
                    gaps: Vec::new(),
                    law: FrictionLaw::default(),
                    vtol: GapSet::DEFAULT_VTOL,
                },
                gap_pairs: Vec::new(),
                grids: Vec::new(),
                checks: Vec::new(),
                components: Vec::new(),
                recovery: Vec::new(),
                source: model.source,
                warnings: Vec::new(),
            };
            problem.b = damping_matrix(scene, &light)?;
            problem.m = light.m;
            problem.k = light.k;
        }
    }
    Ok(problem)
}

/// The derivative of the steady sliding state with respect to a parameter, by the implicit
/// function theorem: R(x, θ) = 0 at x = (u, λ̇) gives ∂x/∂θ = −J⁻¹ ∂R/∂θ, with J the steady
/// state's Newton matrix at the base state,
/// ```text
/// J = [ K   Gᵀ − D ]      R = [ K u + Gᵀ λ̇ − P(t) − F_f(λ̇, 0) ]
///     [ G   −C     ]          [ G u − C λ̇                      ]
/// ```
/// (D = ∂F_f/∂λ̇, C the compliance) factorised once for every parameter, and ∂R/∂θ the
/// central difference of the residual at the base state. A state at θ ± h is then
/// x₀ ± h ∂x/∂θ: the matrices' central difference is the chain rule's ∂A/∂x ∂x/∂θ + ∂A/∂θ to
/// O(h²), as with states solved again, without a Newton solve per value.
///
/// # Reference
/// [Paper eqs. (8), (9), (12)] at v = v' = 0 (`squeal_solver::bsql::steady_state`).
pub struct StateTangent {
    lu: faer::linalg::solvers::PartialPivLu<Real>,
}

/// R(u, λ̇) of the steady state of `problem` at its full-load time.
fn steady_residual(
    problem: &Problem,
    u: &[Real],
    lamp: &[Real],
) -> Result<Vec<Real>, PipelineError> {
    let (n, ng) = (problem.k.nrows(), problem.g.nrows());
    let t = full_load_time(problem);
    let mut r = vec![0.0; n + ng];
    let mut f = vec![0.0; n];
    problem
        .gaps
        .add_forces(&vec![0.0; n], lamp, &mut f)
        .map_err(|source| PipelineError::Contact {
            what: "friction forces at the steady state".into(),
            source,
        })?;
    let mut p = vec![0.0; n];
    problem.load.add_to(t, 1.0, &mut p);
    for i in 0..n {
        let mut x = -p[i] - f[i];
        for j in 0..n {
            x += problem.k[(i, j)] * u[j];
        }
        for k in 0..ng {
            x += problem.g[(k, i)] * lamp[k];
        }
        r[i] = x;
    }
    for k in 0..ng {
        let mut x = -problem.compliance.get(k).copied().unwrap_or(0.0) * lamp[k];
        for j in 0..n {
            x += problem.g[(k, j)] * u[j];
        }
        r[n + k] = x;
    }
    Ok(r)
}

impl StateTangent {
    /// The Newton matrix of `base`'s steady state, factorised (None: the base state is a
    /// restart file's, which a parameter does not move).
    pub fn of(base: &Base) -> Option<Self> {
        if !matches!(base.lin.source, StateSource::SteadyState { .. }) {
            return None;
        }
        let (p, lin) = (base.problem, base.lin);
        let (n, ng) = (p.k.nrows(), p.g.nrows());
        let j = Mat::<Real>::from_fn(n + ng, n + ng, |r, c| match (r < n, c < n) {
            (true, true) => p.k[(r, c)],
            (true, false) => p.g[(c - n, r)] - lin.d[(r, c - n)],
            (false, true) => p.g[(r - n, c)],
            (false, false) if r == c => -p.compliance.get(r - n).copied().unwrap_or(0.0),
            (false, false) => 0.0,
        });
        Some(StateTangent {
            lu: j.partial_piv_lu(),
        })
    }
}

/// The CEA matrices at `values` of `param` (everything else as in `base`): the problem changed
/// and, when the parameter moves the steady state (`tangent`: the base state is a steady
/// state), the state moved along ∂x/∂θ ([`StateTangent`]), the tangents evaluated there.
pub fn matrices_at(
    base: &Base,
    param: &Parameter,
    values: [Real; 2],
    tangent: Option<&StateTangent>,
) -> Result<[CeaMatrices; 2], PipelineError> {
    let problems = [
        problem_at_value(base, param, values[0])?,
        problem_at_value(base, param, values[1])?,
    ];
    let n = base.problem.m.nrows();
    let (u0, l0) = (&base.lin.u, &base.lin.lambda_dot);
    // ∂x/∂θ (None: the state stays).
    let dx = match (tangent, param.moves_state) {
        (Some(t), true) => {
            let ra = steady_residual(&problems[0], u0, l0)?;
            let rb = steady_residual(&problems[1], u0, l0)?;
            let w = values[0] - values[1];
            let rhs = Mat::<Real>::from_fn(ra.len(), 1, |i, _| -(ra[i] - rb[i]) / w);
            let x = t.lu.solve(&rhs);
            Some((0..ra.len()).map(|i| x[(i, 0)]).collect::<Vec<Real>>())
        }
        _ => None,
    };
    let at = |k: usize| -> Result<CeaMatrices, PipelineError> {
        let problem = &problems[k];
        let lin = match &dx {
            Some(dx) => {
                let d = values[k] - param.value;
                // x = (u, λ̇): u in dx[..n], λ̇ in dx[n..].
                let u: Vec<Real> = (0..n).map(|i| u0[i] + d * dx[i]).collect();
                let lamp: Vec<Real> = (0..l0.len()).map(|g| l0[g] + d * dx[n + g]).collect();
                let (dd, c_f) = tangents(&problem.gaps, n, &base.lin.v, &lamp)?;
                Linearisation {
                    u,
                    lambda_dot: lamp,
                    d: dd,
                    c_f,
                    ..base.lin.clone()
                }
            }
            None => {
                let (d, c_f) = tangents(&problem.gaps, n, &base.lin.v, l0)?;
                Linearisation {
                    d,
                    c_f,
                    ..base.lin.clone()
                }
            }
        };
        cea_matrices(problem, &lin, base.spec.friction_damping)
    };
    Ok([at(0)?, at(1)?])
}
