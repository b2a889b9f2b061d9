//! The BSQL system from the reduced model: M, B, K, G, P(t), friction adapter.

use super::operating::OperatingPoint;
use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::scene::{ContactPair, Scene};
use faer::Mat;
use squeal_contact::GapSet;
use squeal_solver::bsql::{BsqlOptions, BsqlSystem, FrictionForces, LoadHistory};
use squeal_solver::{Real, SolverError};

/// A solver error as the pipeline's, saying what was being done.
pub(crate) fn solver_err(what: &str) -> impl FnOnce(SolverError) -> PipelineError + '_ {
    move |source| PipelineError::Solver {
        what: what.to_string(),
        source,
    }
}

/// Per gap: may it separate (`separation = true` on its `[[contact]]` pair)? A stored model's
/// gap table is one pair, read with the scene's `[[contact]]` table.
pub fn separation_mask(scene: &Scene, model: &ReducedModel) -> Vec<bool> {
    pair_mask(scene, model, |c| c.separation)
}

/// Per gap: does it separate through events (`separation = true` without
/// `separation_smoothing`)? The smooth law's gaps open and close with no event.
pub fn event_mask(scene: &Scene, model: &ReducedModel) -> Vec<bool> {
    pair_mask(scene, model, |c| {
        c.separation && c.separation_smoothing.is_none()
    })
}

fn pair_mask(scene: &Scene, model: &ReducedModel, on: impl Fn(&ContactPair) -> bool) -> Vec<bool> {
    let mut mask = Vec::with_capacity(model.gap_geometry.len());
    for (pair, &count) in model.gap_pairs.iter().enumerate() {
        let on = scene.contact.get(pair).is_some_and(&on);
        mask.extend(std::iter::repeat_n(on, count));
    }
    mask.resize(model.gap_geometry.len(), false);
    mask
}

/// The contact crate's gap elements as the solver's friction callback.
pub struct GapFriction {
    pub set: GapSet,
}

impl FrictionForces for GapFriction {
    fn add_forces(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        f: &mut [Real],
    ) -> Result<(), SolverError> {
        self.set
            .add_forces(v, lambda_dot, f)
            .map_err(|e| SolverError::Callback {
                t,
                message: e.to_string(),
            })
    }
    fn add_tangents(
        &mut self,
        t: Real,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), SolverError> {
        self.set
            .add_tangents(v, lambda_dot, d_dlam, d_dv)
            .map_err(|e| SolverError::Callback {
                t,
                message: e.to_string(),
            })
    }
    fn near_stick(&mut self, _t: Real, v: &[Real], lambda_dot: &[Real]) -> bool {
        self.set.near_stick(v, lambda_dot)
    }
}

/// The matrices, loads and gaps the solver integrates.
pub struct Problem {
    pub m: Mat<Real>,
    pub b: Mat<Real>,
    pub k: Mat<Real>,
    pub g: Mat<Real>,
    pub load: LoadHistory,
    pub bsql: BsqlOptions,
    /// Normal contact compliance c_g = 1/(k_n A_g) per gap (`[[contact]] normal_stiffness`);
    /// empty when every gap is rigid (the paper's constraint).
    pub compliance: Vec<Real>,
    /// Width ε_g = p_ε/k_n of the smooth unilateral law per gap (`[[contact]]
    /// separation_smoothing`; 0: none), empty when no pair has one; the law's opening force
    /// per gap is P_0 A.
    pub smooth_width: Vec<Real>,
    /// The gaps at the operating point (the model's gap geometry with `op` applied).
    pub gaps: GapSet,
    /// The operating point the problem was made at.
    pub op: OperatingPoint,
}

/// B = B_element (stored/reduced) + (G/W3)·K + M Φ diag(2ζω) Φᵀ M.
///
/// # Reference
/// NASTRAN's transient damping: structural damping G converted with W3, element damping GE
/// with W4 (both viscous equivalents at one frequency); the modal term gives every mode of
/// the reduced (K, M) the ratio ζ.
pub fn damping_matrix(scene: &Scene, model: &ReducedModel) -> Result<Mat<Real>, PipelineError> {
    let n = model.n();
    let d = scene.damping.clone().unwrap_or_default();
    let mut b = model.b.clone().unwrap_or_else(|| Mat::zeros(n, n));
    let a = d.overall_factor();
    if a != 0.0 {
        for j in 0..n {
            for i in 0..n {
                b[(i, j)] += a * model.k[(i, j)];
            }
        }
    }
    if d.modal_ratio > 0.0 {
        let (vals, phi) =
            squeal_reduction::cb::dense_generalized_eigen(model.k.as_ref(), model.m.as_ref())
                .map_err(|source| PipelineError::Reduction {
                    what: "modal damping: modes of the reduced model".into(),
                    source,
                })?;
        let lmax = vals.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mphi = &model.m * &phi;
        for (q, &l) in vals.iter().enumerate() {
            if l <= 1e-10 * lmax {
                continue; // rigid modes get no damping
            }
            let c = 2.0 * d.modal_ratio * l.sqrt();
            for j in 0..n {
                let x = c * mphi[(j, q)];
                for i in 0..n {
                    b[(i, j)] += mphi[(i, q)] * x;
                }
            }
        }
    }
    Ok(b)
}

/// Assembles the problem from the model at the scene's operating point, with its damping and
/// options.
pub fn problem(scene: &Scene, model: &ReducedModel) -> Result<Problem, PipelineError> {
    problem_at(scene, model, OperatingPoint::of(scene))
}

/// The problem of `scene` on `model` at the operating point `op` (the scene's own, or one a
/// sweep varies): the gaps at `op`, the brake load scaled by its PMAX over its ramp.
pub fn problem_at(
    scene: &Scene,
    model: &ReducedModel,
    op: OperatingPoint,
) -> Result<Problem, PipelineError> {
    let n = model.n();
    let gaps = op.gaps(model)?;
    let g = gaps
        .constraint_matrix(n)
        .map_err(|source| PipelineError::Contact {
            what: "constraint matrix G".into(),
            source,
        })?;
    let t = scene.transient.clone().unwrap_or_default();
    let load = LoadHistory {
        p_pre: Vec::new(),
        p_brake: model.p_brake.iter().map(|p| op.pmax * p).collect(),
        t_load: op.tload,
        step: op.tload == 0.0,
    };
    let compliance = compliance(scene, model)?;
    let smooth_width = smooth_widths(scene, model, &compliance);
    Ok(Problem {
        m: model.m.clone(),
        b: damping_matrix(scene, model)?,
        k: model.k.clone(),
        g,
        load,
        bsql: BsqlOptions {
            include_friction_damping: t.friction_damping_in_jacobian,
            friction_damping_near_stick: t.friction_damping_near_stick,
        },
        compliance,
        smooth_width,
        gaps,
        op,
    })
}

/// Per gap, ε = p_ε/k_n of its pair's `separation_smoothing` (0 without); empty when no pair
/// has one. The scene's checks make such a pair compliant, so `compliance` has its gaps.
fn smooth_widths(scene: &Scene, model: &ReducedModel, compliance: &[Real]) -> Vec<Real> {
    if compliance.is_empty()
        || scene
            .contact
            .iter()
            .all(|c| c.separation_smoothing.is_none())
    {
        return Vec::new();
    }
    let mut w = Vec::with_capacity(model.gap_geometry.len());
    for (pair, &count) in model.gap_pairs.iter().enumerate() {
        let p = scene.contact.get(pair).and_then(|c| c.separation_smoothing);
        for k in w.len()..w.len() + count {
            // ε = p_ε/k_n = p_ε c A.
            let area = model.gap_geometry.gaps[k].area;
            w.push(p.map_or(0.0, |p| p * compliance[k] * area));
        }
    }
    w.resize(model.gap_geometry.len(), 0.0);
    w
}

/// Per gap, the compliance c_g = 1/(k_n A_g) of its pair's `normal_stiffness` (0 for a rigid
/// gap); empty when no pair has one. A stored model's gap table is one pair (its
/// `[[contact]]` table's `normal_stiffness` applies to every gap).
pub fn compliance(scene: &Scene, model: &ReducedModel) -> Result<Vec<Real>, PipelineError> {
    let Some(first) = scene
        .contact
        .iter()
        .position(|c| c.normal_stiffness.is_some())
    else {
        return Ok(Vec::new());
    };
    if model.gap_pairs.iter().sum::<usize>() != model.gap_geometry.len() {
        return Err(PipelineError::Scene {
            field: format!("contact[{first}].normal_stiffness"),
            message: format!(
                "the model's {} gaps are not grouped by `[[contact]]` pair (a stored model's \
                 gap table): normal compliance needs a model built from meshes",
                model.gap_geometry.len()
            ),
        });
    }
    let mut c = Vec::with_capacity(model.gap_geometry.len());
    for (pair, &count) in model.gap_pairs.iter().enumerate() {
        let kn = scene.contact.get(pair).and_then(|p| p.normal_stiffness);
        for g in &model.gap_geometry.gaps[c.len()..c.len() + count] {
            c.push(match kn {
                Some(kn) if g.area > 0.0 => 1.0 / (kn * g.area),
                Some(kn) => {
                    return Err(PipelineError::Scene {
                        field: format!("contact[{pair}].normal_stiffness"),
                        message: format!(
                            "{kn}: gap of pad grid {} has area {} (a compliant gap needs \
                             a positive area)",
                            g.pad_node, g.area
                        ),
                    })
                }
                None => 0.0,
            });
        }
    }
    Ok(c)
}

impl Problem {
    /// The same problem at another operating point: the matrices kept, the gaps and the brake
    /// load made anew at `op`.
    pub fn at(&self, model: &ReducedModel, op: OperatingPoint) -> Result<Problem, PipelineError> {
        Ok(Problem {
            m: self.m.clone(),
            b: self.b.clone(),
            k: self.k.clone(),
            g: self.g.clone(),
            load: LoadHistory {
                p_pre: self.load.p_pre.clone(),
                p_brake: model.p_brake.iter().map(|p| op.pmax * p).collect(),
                t_load: op.tload,
                step: op.tload == 0.0,
            },
            bsql: self.bsql.clone(),
            compliance: self.compliance.clone(),
            smooth_width: self.smooth_width.clone(),
            gaps: op.gaps(model)?,
            op,
        })
    }

    /// The solver's system (matrices copied).
    pub fn system(&self, gaps: GapSet) -> Result<BsqlSystem<GapFriction>, PipelineError> {
        // The force an open gap carries: its preload's, P_0 A (p_n = 0).
        let open_force: Vec<Real> = gaps.gaps.iter().map(|g| g.p0 * g.area).collect();
        let mut sys = BsqlSystem::new(
            self.m.clone(),
            self.b.clone(),
            self.k.clone(),
            self.g.clone(),
            self.load.clone(),
            GapFriction { set: gaps },
            self.bsql.clone(),
        )
        .map_err(|source| PipelineError::Solver {
            what: "building the BSQL system".into(),
            source,
        })?;
        if !self.compliance.is_empty() {
            sys.set_compliance(self.compliance.clone())
                .map_err(|source| PipelineError::Solver {
                    what: "normal contact compliance".into(),
                    source,
                })?;
        }
        if !self.smooth_width.is_empty() {
            sys.set_smooth_unilateral(open_force, self.smooth_width.clone())
                .map_err(|source| PipelineError::Solver {
                    what: "smooth unilateral contact".into(),
                    source,
                })?;
        }
        Ok(sys)
    }

    /// FNV-1a hash of n, ng and M, K, G (values rounded to 12 significant digits): a restart
    /// file only continues the model it was written for.
    pub fn model_hash(&self) -> String {
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let mut eat = |bytes: &[u8]| {
            for &b in bytes {
                h ^= b as u64;
                h = h.wrapping_mul(0x0100_0000_01b3);
            }
        };
        eat(&(self.m.nrows() as u64).to_le_bytes());
        eat(&(self.g.nrows() as u64).to_le_bytes());
        for a in [&self.m, &self.k, &self.g] {
            for j in 0..a.ncols() {
                for i in 0..a.nrows() {
                    let v = a[(i, j)];
                    if v != 0.0 {
                        eat(format!("{i},{j}:{v:.11e};").as_bytes());
                    }
                }
            }
        }
        // Compliance changes the model (only hashed when present: rigid hashes are unchanged).
        for (k, c) in self.compliance.iter().enumerate() {
            if *c != 0.0 {
                eat(format!("c{k}:{c:.11e};").as_bytes());
            }
        }
        for (k, w) in self.smooth_width.iter().enumerate() {
            if *w != 0.0 {
                eat(format!("s{k}:{w:.11e};").as_bytes());
            }
        }
        format!("{h:016x}")
    }
}
