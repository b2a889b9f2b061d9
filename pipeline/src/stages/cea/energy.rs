//! Energy balance of every reported root (`cea.json`'s `energy`): the work per cycle each gap's
//! friction feeds into the mode (and its sum per contact pair), the work each component's
//! damping takes out, the kinetic and strain share of each component, and the closure of
//! `2σ E = net power` (`squeal_solver::insight::mode_energy`; derivation in `docs/insight.md`).
//!
//! **Components.** A model built from meshes keeps each component's Craig–Bampton matrices
//! and where its coordinates sit in the assembled vector ([`ReducedModel::recovery`]): the
//! component's part of M and K is its reduced block mapped to the assembled DOFs,
//! `T_cᵀ M_c T_c` (a shared boundary DOF gets the blocks of every component on it, as the
//! superelement assembly adds them; a DOF a tie eliminated is its combination), and its part
//! of B is its element damping (GE_c/W4) plus the overall damping (G/W3) times its K block.
//! Damping that belongs to no component (modal damping, `damping.modal_ratio`) is reported
//! apart as the whole model's. The split is used only when the scattered blocks sum to the
//! assembled M and K (to 1e-10 relative); otherwise — and for stored reduced matrices, which
//! have no component blocks — each matrix is split by DOF ownership (the DOF map's
//! `component`, the first component of a shared DOF): `A_c = ½(P_c A + A P_c)`, P_c the
//! selector of c's DOFs, so `φᴴA_cφ = Re(φ_cᴴ A φ)` and Σ_c A_c = A. `split` says which.
//!
//! **Scale.** The eigenvector is scaled to unit mode energy E = 1, so each number is a
//! fraction of the mode's energy: per cycle of a complex root (period T = 2π/ω) the works sum
//! to the relative energy growth per cycle 2σT; for a real root (no cycle) they are powers per
//! unit energy (1/s), summing to 2σ.
//!
//! **Multipliers.** The CEA gives φ; the contact-force perturbation ν of the rigid gaps is the
//! least-squares solution of `(Gᵀ − D) ν = −(p²M + pC + K) φ` (one QR for all roots), and the
//! remaining residual is reported (`eigen_residual`) beside the identity's closure.

use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::problem::system::Problem;
use crate::problem::tangents::Linearisation;
use crate::scene::Scene;
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;
use serde::Serialize;
use squeal_solver::cea::{CeaMatrices, Cplx, Mode};
use squeal_solver::insight::{mode_energy, ComponentPart, EnergyParts, GapPart, Triplet};
use std::time::Instant;

use squeal_solver::Real;

/// How the model's M, K, B were split among the components.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Split {
    /// Each component's reduced (Craig–Bampton) matrices, scattered to its assembled DOFs.
    ComponentReductions,
    /// `A_c = ½(P_c A + A P_c)` by DOF ownership (stored matrices, or component blocks that
    /// do not sum to the assembled model).
    DofOwnership,
}

/// What a root's numbers are: work per cycle (complex root) or power (real root), both per
/// unit mode energy.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Basis {
    WorkPerCycle,
    Power,
}

/// A contact pair of the energy table.
#[derive(Debug, Clone, Serialize)]
pub struct PairLabel {
    /// `pad:pad_faces -> rotor:rotor_faces` (a stored model: `gap table`).
    pub name: String,
    /// Number of gaps of the pair (the gaps of pair i follow those of pair i − 1).
    pub n_gaps: usize,
}

/// The energy balance of one reported root, per unit mode energy.
#[derive(Debug, Clone, Serialize)]
pub struct RootEnergy {
    /// Index into `modes`.
    pub mode: usize,
    pub frequency_hz: Real,
    pub real_part: Real,
    pub basis: Basis,
    /// Work per cycle (or power) fed into the mode by each gap's friction (positive: the
    /// gap feeds the mode), in the gap table's order.
    pub feed_in_per_gap: Vec<Real>,
    /// The same summed per contact pair.
    pub feed_in_per_pair: Vec<Real>,
    pub feed_in_total: Real,
    /// Work per cycle (or power) of each component's damping (≤ 0: dissipated).
    pub damping_per_component: Vec<Real>,
    /// Of damping that belongs to no component (modal damping).
    pub damping_whole_model: Real,
    /// Cycle-average kinetic energy of each component, as a share of the mode's energy.
    pub kinetic_share: Vec<Real>,
    /// Cycle-average strain energy of each component, as a share.
    pub strain_share: Vec<Real>,
    /// Strain energy of the compliant contact springs, as a share (0: rigid contact).
    pub contact_strain_share: Real,
    /// Σ feed-in + Σ damping.
    pub net: Real,
    /// 2σT (work per cycle) or 2σ (power): what `net` must equal.
    pub growth: Real,
    /// `|2σE − net power| / (|p|E + Σ|powers|)` (`ModeEnergy::identity_residual`).
    pub identity_residual: Real,
    /// `‖(p²M + pC + K)φ + (Gᵀ − D)ν‖ / (|p|²‖Mφ‖ + |p|‖Cφ‖ + ‖Kφ‖)` with the least-squares ν:
    /// how well the CEA's (p, φ) satisfy the eigen-equation.
    pub eigen_residual: Real,
}

/// `cea.json`'s `energy`.
#[derive(Debug, Clone, Serialize)]
pub struct EnergyOut {
    pub split: Split,
    /// Largest |Σ_c M_c − M|, |Σ_c K_c − K| relative to max|M|, max|K| of the split used.
    pub split_check: Real,
    pub components: Vec<String>,
    pub pairs: Vec<PairLabel>,
    /// One entry per reported mode (same order as `modes`).
    pub roots: Vec<RootEnergy>,
    /// Largest `identity_residual` over the roots.
    pub max_identity_residual: Real,
    /// Largest `eigen_residual` over the roots.
    pub max_eigen_residual: Real,
    pub time_s: Real,
}

fn max_abs(a: &Mat<Real>) -> Real {
    a.norm_max()
}

/// Scatters `parts` (M and K) and returns the largest relative difference to the model's.
pub(crate) fn scatter_check(parts: &[ComponentPart], m: &Mat<Real>, k: &Mat<Real>) -> Real {
    let mut dm = m.clone();
    let mut dk = k.clone();
    for c in parts {
        for (a, &i) in c.dofs.iter().enumerate() {
            for (b, &j) in c.dofs.iter().enumerate() {
                dm[(i, j)] -= c.m[(a, b)];
                dk[(i, j)] -= c.k[(a, b)];
            }
        }
    }
    let rel = |d: &Mat<Real>, a: &Mat<Real>| {
        let s = max_abs(a);
        if s > 0.0 {
            max_abs(d) / s
        } else {
            max_abs(d)
        }
    };
    rel(&dm, m).max(rel(&dk, k))
}

/// The components' blocks from their reductions (meshed models): the component's reduced
/// coordinates are `x_c = T_c x` (`ComponentRecovery::assembled`: one term of weight 1, or
/// several for a grid DOF a tie eliminated), so its part of M is `T_cᵀ M_c T_c` on the
/// assembled DOFs its terms touch; its B is `(GE_c/W4 + overall)·K_c` plus its bodies' loss
/// factors' `T_cᵀ B_η,c T_c` (the reduction's `b`). None when the model has no recovery data.
pub(crate) fn from_reductions(model: &ReducedModel, overall: Real) -> Option<Vec<ComponentPart>> {
    if model.recovery.is_empty() {
        return None;
    }
    let mut parts = Vec::with_capacity(model.recovery.len());
    for r in &model.recovery {
        let (dofs, t) = scatter_of(r);
        let factor = model
            .components
            .iter()
            .find(|c| c.name == r.name)
            .map_or(0.0, |c| c.element_damping_factor)
            + overall;
        let tt = t.transpose();
        let k = tt * &r.cb.k * &t;
        let m = tt * &r.cb.m * &t;
        // The bodies' loss factors: the reduction's material damping Tᵀ B_η T.
        let material = r.cb.b.as_ref().map(|b| tt * b * &t);
        let b = match material {
            Some(bm) => Some(Mat::from_fn(k.nrows(), k.ncols(), |i, j| {
                factor * k[(i, j)] + bm[(i, j)]
            })),
            None => (factor != 0.0)
                .then(|| Mat::from_fn(k.nrows(), k.ncols(), |i, j| factor * k[(i, j)])),
        };
        parts.push(ComponentPart {
            name: r.name.clone(),
            dofs,
            m,
            k,
            b,
        });
    }
    Some(parts)
}

/// The assembled DOFs a component's reduced coordinates touch (sorted) and `T_c` on them:
/// `x_c = T_c x` (`ComponentRecovery::assembled`), so a component matrix `A_c` is
/// `T_cᵀ A_c T_c` on those DOFs.
pub(crate) fn scatter_of(r: &crate::model::ComponentRecovery) -> (Vec<usize>, Mat<Real>) {
    let mut dofs: Vec<usize> = r.assembled.iter().flatten().map(|t| t.0).collect();
    dofs.sort_unstable();
    dofs.dedup();
    let mut t = Mat::<Real>::zeros(r.assembled.len(), dofs.len());
    for (j, terms) in r.assembled.iter().enumerate() {
        for &(i, w) in terms {
            // `dofs` holds every i of the terms.
            let a = dofs.binary_search(&i).unwrap_or_else(|a| a);
            t[(j, a)] += w;
        }
    }
    (dofs, t)
}

/// `A_c = ½(P_c A + A P_c)` on the DOFs of c and those coupled to them.
fn by_ownership(model: &ReducedModel, b: &Mat<Real>) -> Vec<ComponentPart> {
    let n = model.n();
    let mut names: Vec<String> = Vec::new();
    let owner: Vec<usize> = model
        .dofs
        .dofs
        .iter()
        .map(|d| match names.iter().position(|x| *x == d.component) {
            Some(i) => i,
            None => {
                names.push(d.component.clone());
                names.len() - 1
            }
        })
        .collect();
    let (m, k) = (&model.m, &model.k);
    let has_b = b.norm_max() > 0.0;
    names
        .iter()
        .enumerate()
        .map(|(c, name)| {
            let mut support = vec![false; n];
            for i in (0..n).filter(|&i| owner[i] == c) {
                support[i] = true;
                for j in 0..n {
                    if m[(i, j)] != 0.0 || k[(i, j)] != 0.0 || b[(i, j)] != 0.0 {
                        support[j] = true;
                    }
                }
            }
            let dofs: Vec<usize> = (0..n).filter(|&i| support[i]).collect();
            let w = |i: usize, j: usize| {
                0.5 * (Real::from(u8::from(owner[i] == c)) + Real::from(u8::from(owner[j] == c)))
            };
            let block = |a: &Mat<Real>| {
                Mat::from_fn(dofs.len(), dofs.len(), |x, y| {
                    let (i, j) = (dofs[x], dofs[y]);
                    w(i, j) * a[(i, j)]
                })
            };
            ComponentPart {
                name: name.clone(),
                m: block(m),
                k: block(k),
                b: has_b.then(|| block(b)),
                dofs,
            }
        })
        .collect()
}

/// The model split into components and gaps (with the whole model's damping that no
/// component carries as a last part named `whole model damping`), the split used and its
/// check.
fn parts(
    scene: &Scene,
    model: &ReducedModel,
    problem: &Problem,
    lin: &Linearisation,
    friction_damping: bool,
) -> Result<(EnergyParts, Split, Real, bool), PipelineError> {
    let overall = scene.damping.clone().unwrap_or_default().overall_factor();
    let mut whole = false;
    let (components, split, check) = match from_reductions(model, overall) {
        Some(p) => {
            let check = scatter_check(&p, &model.m, &model.k);
            if check <= 1e-10 {
                (p, Split::ComponentReductions, check)
            } else {
                let p = by_ownership(model, &problem.b);
                let check = scatter_check(&p, &model.m, &model.k);
                (p, Split::DofOwnership, check)
            }
        }
        None => {
            let p = by_ownership(model, &problem.b);
            let check = scatter_check(&p, &model.m, &model.k);
            (p, Split::DofOwnership, check)
        }
    };
    let mut components = components;
    if split == Split::ComponentReductions {
        // Damping no component carries (modal damping): one part over every DOF.
        let n = model.n();
        let mut rest = problem.b.clone();
        for c in &components {
            if let Some(cb) = &c.b {
                for (a, &i) in c.dofs.iter().enumerate() {
                    for (bb, &j) in c.dofs.iter().enumerate() {
                        rest[(i, j)] -= cb[(a, bb)];
                    }
                }
            }
        }
        if rest.norm_max() > 1e-12 * problem.b.norm_max() {
            whole = true;
            components.push(ComponentPart {
                name: "whole model damping".into(),
                dofs: (0..n).collect(),
                m: Mat::zeros(n, n),
                k: Mat::zeros(n, n),
                b: Some(rest),
            });
        }
    }
    let blocks = problem
        .gaps
        .gap_blocks(&lin.v, &lin.lambda_dot)
        .map_err(|source| PipelineError::Contact {
            what: "per-gap friction tangents for the energy balance".into(),
            source,
        })?;
    let pair_of = pair_index(model);
    let gaps = blocks
        .into_iter()
        .enumerate()
        .map(|(g, b)| {
            let r = b.dofs.len();
            GapPart {
                pair: pair_of[g],
                dofs: b.dofs,
                g: b.g,
                d: b.d,
                c_f: if friction_damping {
                    b.c_f
                } else {
                    Mat::zeros(r, r)
                },
                compliance: problem.compliance.get(g).copied().unwrap_or(0.0),
            }
        })
        .collect();
    Ok((EnergyParts { components, gaps }, split, check, whole))
}

/// The contact pair of each gap (one pair when the gap counts do not add up: a stored
/// model's gap table).
fn pair_index(model: &ReducedModel) -> Vec<usize> {
    model
        .gap_pair_index()
        .unwrap_or_else(|| vec![0; model.gap_geometry.len()])
}

fn pair_labels(scene: &Scene, model: &ReducedModel) -> Vec<PairLabel> {
    let ng = model.gap_geometry.len();
    if model.gap_pairs.iter().sum::<usize>() != ng || model.gap_pairs.is_empty() {
        return vec![PairLabel {
            name: scene.contact.first().map_or_else(
                || "gap table".to_string(),
                |p| format!("{}:{} -> {}:{}", p.pad, p.pad_faces, p.rotor, p.rotor_faces),
            ),
            n_gaps: ng,
        }];
    }
    model
        .gap_pairs
        .iter()
        .enumerate()
        .map(|(i, &n_gaps)| PairLabel {
            name: scene.contact.get(i).map_or_else(
                || format!("pair {i}"),
                |p| format!("{}:{} -> {}:{}", p.pad, p.pad_faces, p.rotor, p.rotor_faces),
            ),
            n_gaps,
        })
        .collect()
}

/// Least-squares multipliers: factors `Gᵀ − D` (rigid rows) once.
struct Multipliers {
    qr: Option<faer::linalg::solvers::ColPivQr<Real>>,
    c: Option<Mat<Real>>,
}

impl Multipliers {
    fn new(sys: &CeaMatrices) -> Self {
        let n = sys.m.nrows();
        let qr = sys.g.as_ref().filter(|g| g.nrows() > 0).map(|g| {
            let a = Mat::from_fn(n, g.nrows(), |i, k| {
                g[(k, i)] - sys.d.as_ref().map_or(0.0, |d| d[(i, k)])
            });
            a.col_piv_qr()
        });
        let c = match (&sys.b, &sys.c_f) {
            (Some(b), Some(cf)) => Some(b - cf),
            (Some(b), None) => Some(b.clone()),
            (None, Some(cf)) => Some(-cf),
            (None, None) => None,
        };
        Self { qr, c }
    }

    /// ν and the eigen-equation's relative residual for (p, φ).
    fn solve(&self, sys: &CeaMatrices, p: Cplx, phi: &[Cplx]) -> (Vec<Cplx>, Real) {
        let n = phi.len();
        let re = Mat::from_fn(n, 1, |i, _| phi[i].re);
        let im = Mat::from_fn(n, 1, |i, _| phi[i].im);
        let (mr, mi) = (&sys.m * &re, &sys.m * &im);
        let (kr, ki) = (&sys.k * &re, &sys.k * &im);
        let zero = Mat::<Real>::zeros(n, 1);
        let (cr, ci) = match &self.c {
            Some(c) => (c * &re, c * &im),
            None => (zero.clone(), zero),
        };
        let p2 = p * p;
        let mphi: Vec<Cplx> = (0..n).map(|i| Cplx::new(mr[(i, 0)], mi[(i, 0)])).collect();
        let cphi: Vec<Cplx> = (0..n).map(|i| Cplx::new(cr[(i, 0)], ci[(i, 0)])).collect();
        let kphi: Vec<Cplx> = (0..n).map(|i| Cplx::new(kr[(i, 0)], ki[(i, 0)])).collect();
        let r: Vec<Cplx> = (0..n)
            .map(|i| p2 * mphi[i] + p * cphi[i] + kphi[i])
            .collect();
        let norm = |v: &[Cplx]| v.iter().map(|z| z.norm_sqr()).sum::<Real>().sqrt();
        let scale = p.norm_sqr() * norm(&mphi) + p.norm() * norm(&cphi) + norm(&kphi);
        let (nu, res) = match (&self.qr, &sys.g) {
            (Some(qr), Some(g)) => {
                let rhs = Mat::from_fn(n, 2, |i, j| if j == 0 { -r[i].re } else { -r[i].im });
                let x = qr.solve_lstsq(&rhs);
                let nu: Vec<Cplx> = (0..g.nrows())
                    .map(|k| Cplx::new(x[(k, 0)], x[(k, 1)]))
                    .collect();
                let mut tot = r.clone();
                for (k, &nk) in nu.iter().enumerate() {
                    for (i, t) in tot.iter_mut().enumerate() {
                        let a = g[(k, i)] - sys.d.as_ref().map_or(0.0, |d| d[(i, k)]);
                        if a != 0.0 {
                            *t += a * nk;
                        }
                    }
                }
                (nu, norm(&tot))
            }
            _ => (Vec::new(), norm(&r)),
        };
        (nu, if scale > 0.0 { res / scale } else { res })
    }
}

/// The energy balance of every mode of `modes` (the CEA's reported roots, shapes on the
/// reduced DOFs) for the system `sys` the CEA solved.
pub fn energies(
    scene: &Scene,
    model: &ReducedModel,
    problem: &Problem,
    lin: &Linearisation,
    sys: &CeaMatrices,
    friction_damping: bool,
    modes: &[Mode],
) -> Result<EnergyOut, PipelineError> {
    let t0 = Instant::now();
    let (parts, split, split_check, whole) = parts(scene, model, problem, lin, friction_damping)?;
    let pairs = pair_labels(scene, model);
    let pair_of: Vec<usize> = parts.gaps.iter().map(|g| g.pair).collect();
    let n_comp = parts.components.len() - usize::from(whole);
    let mult = Multipliers::new(sys);
    let mut roots = Vec::with_capacity(modes.len());
    for (index, m) in modes.iter().enumerate() {
        if m.shape.is_empty() {
            continue;
        }
        let (nu, eigen_residual) = mult.solve(sys, m.eigenvalue, &m.shape);
        let t = Triplet {
            p: m.eigenvalue,
            phi: m.shape.clone(),
            nu,
            psi: Vec::new(),
            chi: Vec::new(),
            residual: eigen_residual,
            left_residual: Real::NAN,
        };
        let e = mode_energy(&parts, &t).map_err(|source| {
            PipelineError::cea(format!("energy balance of mode {index}"), source)
        })?;
        // Per unit energy; × T for a complex root.
        let (basis, per) = if e.energy > 0.0 && e.period_s.is_finite() {
            (Basis::WorkPerCycle, e.period_s / e.energy)
        } else {
            (Basis::Power, 1.0 / e.energy.max(Real::MIN_POSITIVE))
        };
        let feed: Vec<Real> = e.friction_power.iter().map(|x| x * per).collect();
        let mut per_pair = vec![0.0; pairs.len()];
        for (g, &w) in feed.iter().enumerate() {
            if let Some(s) = per_pair.get_mut(pair_of[g]) {
                *s += w;
            }
        }
        let share = |x: Real| x / e.energy.max(Real::MIN_POSITIVE);
        roots.push(RootEnergy {
            mode: index,
            frequency_hz: m.frequency_hz,
            real_part: m.real_part,
            basis,
            feed_in_total: feed.iter().sum(),
            feed_in_per_gap: feed,
            feed_in_per_pair: per_pair,
            damping_per_component: e.damping_power[..n_comp].iter().map(|x| x * per).collect(),
            // (+ 0.0: an empty sum is −0.0.)
            damping_whole_model: e.damping_power[n_comp..].iter().sum::<Real>() * per + 0.0,
            kinetic_share: e.kinetic[..n_comp].iter().map(|&x| share(x)).collect(),
            strain_share: e.strain[..n_comp].iter().map(|&x| share(x)).collect(),
            contact_strain_share: share(e.contact_strain),
            net: e.net_power * per,
            growth: 2.0 * e.growth_rate_per_s * e.energy * per,
            identity_residual: e.identity_residual,
            eigen_residual,
        });
    }
    let max_identity_residual = roots
        .iter()
        .map(|r| r.identity_residual)
        .fold(0.0, Real::max);
    let max_eigen_residual = roots.iter().map(|r| r.eigen_residual).fold(0.0, Real::max);
    Ok(EnergyOut {
        split,
        split_check,
        components: parts.components[..n_comp]
            .iter()
            .map(|c| c.name.clone())
            .collect(),
        pairs,
        roots,
        max_identity_residual,
        max_eigen_residual,
        time_s: t0.elapsed().as_secs_f64(),
    })
}
