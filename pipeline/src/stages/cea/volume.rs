//! The reduced-matrix derivative of one volume's material in a component (a pad's lining
//! without its backplate), the component's Craig–Bampton basis held fixed.
//!
//! ```text
//! ∂K/∂s_V = T_cᵀ Φ_cᵀ K_V Φ_c T_c,   ∂M/∂s_V = T_cᵀ Φ_cᵀ M_V Φ_c T_c
//! ```
//! with Φ_c the component's basis on its free DOFs (each reduced coordinate recovered,
//! through the component's internal ties when it has them), T_c its reduced coordinates'
//! place in the assembled model, and K_V, M_V the matrices of the volume's cells alone:
//! assembled with the volume's moduli (or density) doubled, less the component's own —
//! element matrices are linear in D and ρ, so the difference is exact.
//!
//! Unlike a whole component's scale ([`super::params::component_matrix_derivative`], exact
//! because s K_c keeps the basis), one volume's scale changes the fixed-interface modes: the
//! derivative is first order in the basis change, and a propensity study measures its error
//! against re-reduction (docs/insight.md).

use super::energy::scatter_of;
use super::params::{ComponentProperty, ReducedDerivative};
use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::scene::scaled_stiffness;
use crate::scene::Scene;
use faer::Mat;
use squeal_fe::{assemble, AssemblyOptions, SolidMaterial};
use squeal_solver::Real;

/// The material with its moduli (`YoungScale`) or density (`DensityScale`) times `f`.
fn scaled(m: &SolidMaterial, property: ComponentProperty, f: Real) -> SolidMaterial {
    match property {
        ComponentProperty::DensityScale => {
            let mut m = m.clone();
            m.density *= f;
            m
        }
        _ => scaled_stiffness(m, f),
    }
}

/// ∂K (`YoungScale`) or ∂M (`DensityScale`) of the moduli or density of volume `volume` of
/// `component` on `model` (a model built from meshes, with its recovery data). Errors name
/// `components.<component>.materials.<volume>`.
pub fn volume_matrix_derivative(
    scene: &Scene,
    model: &ReducedModel,
    component: &str,
    volume: &str,
    property: ComponentProperty,
) -> Result<ReducedDerivative, PipelineError> {
    let err = |message: String| PipelineError::Scene {
        field: format!("components.{component}.materials.{volume}"),
        message,
    };
    if property == ComponentProperty::LossFactor {
        return Err(err("a volume's loss factor has no derivative here".into()));
    }
    let r =
        model
            .recovery
            .iter()
            .find(|r| r.name == component)
            .ok_or_else(|| {
                err("the model has no Craig-Bampton basis of this component (stored matrices, or a \
                 cached model)"
                .into())
            })?;
    let spec = scene
        .components
        .iter()
        .find(|c| c.name == component)
        .ok_or_else(|| err("no such component in the scene".into()))?;
    let base = spec.block_materials(&r.mesh)?;
    let blocks: Vec<usize> = (0..r.mesh.volumes.len())
        .filter(|&b| r.mesh.volumes[b].name.as_deref() == Some(volume))
        .collect();
    if blocks.is_empty() {
        let names: Vec<&str> = r
            .mesh
            .volumes
            .iter()
            .filter_map(|b| b.name.as_deref())
            .collect();
        return Err(err(format!(
            "the mesh has no volume `{volume}` (it has {names:?})"
        )));
    }
    let mut doubled = base.clone();
    for &b in &blocks {
        doubled[b] = scaled(&base[b], property, 2.0);
    }
    let opts = AssemblyOptions {
        hex8: spec.hex8,
        ..Default::default()
    };
    let fe = |e| PipelineError::fe(component, e);
    let a0 = assemble(&r.mesh, &base, &r.dofs, &opts).map_err(fe)?;
    let a1 = assemble(&r.mesh, &doubled, &r.dofs, &opts).map_err(fe)?;
    let (s0, s1) = match property {
        ComponentProperty::DensityScale => (&a0.m, &a1.m),
        _ => (&a0.k, &a1.k),
    };
    // The basis on the free DOFs: each reduced coordinate recovered (ties expanded).
    let nr = r.cb.n_reduced();
    let nf = r.dofs.n_free();
    let mut phi = Mat::<Real>::zeros(nf, nr);
    let mut e = vec![0.0; nr];
    for j in 0..nr {
        e[j] = 1.0;
        let x =
            r.cb.recover(&e)
                .map_err(|source| PipelineError::Reduction {
                    what: format!("component `{component}`: its basis"),
                    source,
                })?;
        let x = match &r.mpc {
            Some(t) => t.expand(&x),
            None => x,
        };
        for (i, v) in x.iter().enumerate().take(nf) {
            phi[(i, j)] = *v;
        }
        e[j] = 0.0;
    }
    // Φᵀ (K₁ − K₀) Φ, scattered to the assembled reduced coordinates (T_cᵀ · T_c).
    let dc = phi.transpose() * (s1 * &phi - s0 * &phi);
    let (dofs, t) = scatter_of(r);
    let local = t.transpose() * &dc * &t;
    let n = model.n();
    let mut out = Mat::<Real>::zeros(n, n);
    for (x, &i) in dofs.iter().enumerate() {
        for (y, &j) in dofs.iter().enumerate() {
            out[(i, j)] = local[(x, y)];
        }
    }
    // Symmetric up to round-off: symmetrised as the model's matrices are.
    let out = Mat::from_fn(n, n, |i, j| 0.5 * (out[(i, j)] + out[(j, i)]));
    Ok(match property {
        ComponentProperty::DensityScale => ReducedDerivative {
            m: Some(out),
            k: None,
            b: None,
        },
        _ => {
            // ∂B/∂s_V: the component's GE_c/W4, the volume's own loss factor η_V/W4 and the
            // overall G/W3, each times ∂K/∂s_V.
            let d = scene.damping.clone().unwrap_or_default();
            let eta = spec.block_loss_factors(&r.mesh)?[blocks[0]].eta;
            let f = d.element_factor(component)
                + d.overall_factor()
                + if d.w4 > 0.0 { eta / d.w4 } else { 0.0 };
            ReducedDerivative {
                m: None,
                b: (f != 0.0).then(|| Mat::from_fn(n, n, |i, j| f * out[(i, j)])),
                k: Some(out),
            }
        }
    })
}
