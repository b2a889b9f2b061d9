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
//!   into K move with them. [`matrices_at`] solves the steady state again (a restart file's
//!   state stays as read: only the direct part is seen).
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
    at_steady_state, cea_matrices, tangents, Linearisation, StateSource,
};
use crate::scene::{CeaSpec, Scene};
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
/// YoungScale:   ∂K/∂s = T_cᵀ K_c T_c,   ∂B/∂s = (GE_c/W4 + G/W3) T_cᵀ K_c T_c
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
    let elem = model
        .components
        .iter()
        .find(|x| x.name == component)
        .map_or(0.0, |x| x.element_damping_factor);
    Ok(match property {
        ComponentProperty::YoungScale => {
            let f = elem + d.overall_factor();
            ReducedDerivative {
                m: None,
                k: Some(scatter(&c.k, 1.0)),
                b: (f != 0.0).then(|| scatter(&c.k, f)),
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

/// The CEA matrices with `param` at `value` (everything else as in `base`): the problem
/// changed, the steady state solved again when the parameter moves it (`base.lin` is a
/// steady state), the tangents evaluated there; and whether the state was solved only to the
/// scene's tolerance (the tight 1e-13 did not converge).
pub fn matrices_at(
    base: &Base,
    param: &Parameter,
    value: Real,
) -> Result<(CeaMatrices, bool), PipelineError> {
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
                ComponentProperty::YoungScale => {
                    let f = model
                        .components
                        .iter()
                        .find(|x| &x.name == component)
                        .map_or(0.0, |x| x.element_damping_factor);
                    d.k.as_ref()
                        .filter(|_| f != 0.0)
                        .map(|x| axpy(&Mat::zeros(x.nrows(), x.ncols()), f, x))
                }
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
    let steady = matches!(base.lin.source, StateSource::SteadyState { .. });
    let mut loosened = false;
    let lin = if param.moves_state && steady {
        let mut opts = base.spec.steady.clone();
        // The state's round-off enters the difference quotient divided by the step: solved
        // tighter than the scene asks, or, where the residual's round-off floor is above
        // 1e-13 (a light load: 4.6e-13 on the study brake at 1 psi), to the scene's tolerance.
        opts.tol = opts.tol.min(1e-13);
        opts.max_iters = opts.max_iters.max(100);
        match at_steady_state(&problem, &problem.gaps, &opts) {
            Ok(lin) => lin,
            Err(_) => {
                loosened = true;
                at_steady_state(&problem, &problem.gaps, &base.spec.steady)?
            }
        }
    } else {
        let (d, c_f) = tangents(
            &problem.gaps,
            problem.m.nrows(),
            &base.lin.v,
            &base.lin.lambda_dot,
        )?;
        Linearisation {
            d,
            c_f,
            ..base.lin.clone()
        }
    };
    Ok((
        cea_matrices(&problem, &lin, base.spec.friction_damping)?,
        loosened,
    ))
}
