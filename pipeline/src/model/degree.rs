//! The interface degree an error estimate chooses (`[components.interface] tolerance`).
//!
//! A component with `interface = { tolerance = τ }` is reduced at its starting degree d, the
//! model built and its CEA roots found at the scene's `[cea]` state (its operating point: the
//! scene's friction law, pressure and speed); then at d + s, d + 2s, … (nested bases on one
//! K_ii factor, [`squeal_reduction::cb::InterfaceLadder`]: only the new columns' constraint
//! modes are solved) until the estimate below is at most τ. The finer model is the answer.
//! Several such components are chosen one after the other, each with the others at their
//! degree so far.
//!
//! # The estimate
//! The difference δ_k between the roots of degree d_{k−1} and of degree d_k, in the validity
//! band (`[cea]`'s band, [`crate::problem::linear::band_of`]), is the larger of
//!
//! - the root change: max over the in-band roots p of either model of |p − q| / |p|, q the
//!   nearest root of the other model (in band or above it: a root crossing the band's edge is
//!   not a change);
//! - the growth change: max over the in-band unstable roots p of either model of
//!   |Re p − Re q| / g, g the largest in-band growth rate Re p of the two models (a growth rate
//!   is measured against the most unstable root's: halving the dominant growth rate is 0.5, a
//!   marginal root's 0.1 /s wobble next to a 300 /s one is 3e-4).
//!
//! A difference alone is not an error estimate: two degrees that are both far from
//! converged can agree (on the partly covered plate of the tests, degrees 4 and 6 differ by
//! 0.14 while they are 0.68 and 0.66 off). The estimate of degree d_k's error is the geometric tail
//! from the last two differences, for the root change and the growth change apart
//! (ρ = δ_k / δ_{k−1} of each):
//!
//!   η_k = max over the two parts of δ_k · max(1, ρ / (1 − ρ)),  unresolved (none) when either
//!   part does not fall (ρ ≥ 1),
//!
//! the sum δ_{k+1} + δ_{k+2} + … if the differences keep falling by ρ (and never below the
//! last difference). Taking the parts apart matters: on that plate the root change falls from
//! degree 4 to 6 while the growth change rises, and their maximum alone would claim 0.40 for a
//! model 0.66 off. The degree rises until η_k ≤ τ, so at least three degrees are tried. It
//! is an estimate, not a proof: the test `pipeline/tests/interface_tolerance.rs` and the
//! README table compare it with the true error against exact Craig–Bampton on a patch the pad
//! only partly covers. A basis spanning every nodal field of the patch is exact Craig–Bampton:
//! its estimate is 0.

use super::cache::component::ComponentCache;
use super::from_mesh::build_once;
use super::ReducedModel;
use crate::error::PipelineError;
use crate::output::RunDir;
use crate::progress::Progress;
use crate::scene::Scene;
use serde::Serialize;
use squeal_reduction::cb::InterfaceLadder;
use squeal_reduction::{CbModel, ReductionError};
use squeal_solver::cea::Cplx;
use squeal_solver::Real;
use std::sync::Mutex;

/// One degree tried.
#[derive(Debug, Clone, Serialize)]
pub struct DegreeRow {
    pub degree: usize,
    /// Interface coordinates of the component at this degree.
    pub n_coords: usize,
    /// Difference δ from the previous degree (None for the first one) and its two parts:
    /// the relative root change and the growth-rate change.
    pub difference: Option<Real>,
    pub root_change: Option<Real>,
    pub growth_change: Option<Real>,
    /// Error estimate η of this degree (None: not yet two differences, or they do not fall).
    pub estimate: Option<Real>,
    /// In-band roots and unstable in-band roots of the model at this degree.
    pub n_in_band: usize,
    pub n_unstable: usize,
    /// Constraint-mode solves of the component so far (one per kept boundary DOF and per
    /// interface column: the columns of lower degrees are reused).
    pub constraint_solves: usize,
}

/// The interface reduction of one component as built: its degree and error estimate.
#[derive(Debug, Clone, Serialize)]
pub struct InterfaceChoice {
    pub degree: usize,
    pub n_coords: usize,
    /// Rotor DOFs the interface coordinates replace.
    pub n_interface_dofs: usize,
    /// The scene's `tolerance` (None: a fixed degree).
    pub tolerance: Option<Real>,
    /// Estimated error of the in-band CEA roots of this model (module doc; None: a fixed
    /// degree, not estimated — give `tolerance`).
    pub estimate: Option<Real>,
    /// The largest in-band growth rate the growth change is measured against, 1/s (None
    /// without an unstable root).
    pub growth_scale: Option<Real>,
    /// The basis spans every nodal field of the patches: the exact Craig–Bampton reduction.
    pub exact: bool,
    /// The degrees tried, in order.
    pub history: Vec<DegreeRow>,
    /// Where the estimate comes from.
    pub note: String,
}

impl InterfaceChoice {
    /// A fixed degree: no estimate.
    pub(super) fn fixed(degree: usize, n_coords: usize, n_interface_dofs: usize) -> Self {
        Self {
            degree,
            n_coords,
            n_interface_dofs,
            tolerance: None,
            estimate: None,
            growth_scale: None,
            exact: n_coords >= n_interface_dofs,
            history: Vec::new(),
            note: "fixed degree: the interface error is not estimated (give `tolerance`)".into(),
        }
    }
}

/// The degree of each component whose interface degree is chosen by a tolerance, and its
/// ladder (the K_ii factor, modes and constraint modes shared by its degrees).
pub(super) struct Ladders {
    degrees: Vec<Option<usize>>,
    ladders: Vec<Mutex<Option<InterfaceLadder>>>,
}

impl Ladders {
    pub(super) fn new(scene: &Scene) -> Self {
        let degrees: Vec<Option<usize>> = scene
            .components
            .iter()
            .map(|c| {
                c.interface
                    .as_ref()
                    .filter(|f| f.adaptive())
                    .map(|f| f.start_degree())
            })
            .collect();
        let ladders = degrees.iter().map(|_| Mutex::new(None)).collect();
        Self { degrees, ladders }
    }

    pub(super) fn any_adaptive(&self) -> bool {
        self.degrees.iter().any(Option::is_some)
    }

    /// Component `c` reduced at its current degree on its ladder (`make` builds the ladder
    /// the first time).
    pub(super) fn reduce(
        &self,
        c: usize,
        make: impl FnOnce() -> Result<InterfaceLadder, ReductionError>,
    ) -> Result<CbModel, ReductionError> {
        let degree = self.degrees[c].ok_or(ReductionError::InvalidOption {
            field: "interface.tolerance",
            value: format!("component {c}"),
            reason: "no degree chosen by a tolerance for this component".into(),
        })?;
        let mut held = self.ladders[c].lock().unwrap_or_else(|e| e.into_inner());
        let ladder = match held.take() {
            Some(l) => l,
            None => make()?,
        };
        let ladder = held.insert(ladder);
        ladder.reduce(degree)
    }

    fn solves(&self, c: usize) -> usize {
        let held = self.ladders[c].lock().unwrap_or_else(|e| e.into_inner());
        held.as_ref()
            .map_or(0, InterfaceLadder::n_constraint_solves)
    }
}

/// The model with every tolerance-driven interface degree chosen (module doc).
pub(super) fn build_adaptive(
    scene: &Scene,
    dir: &RunDir,
    progress: &Progress,
    cache: Option<&ComponentCache>,
    mut ladders: Ladders,
) -> Result<ReducedModel, PipelineError> {
    let mut model = build_once(scene, dir, progress, cache, &ladders)?;
    let mut roots = Roots::of(scene, &model, progress)?;
    let adaptive: Vec<usize> = (0..ladders.degrees.len())
        .filter(|&c| ladders.degrees[c].is_some())
        .collect();
    let mut choices = Vec::new();
    for c in adaptive {
        let spec = scene.components[c].interface.clone().unwrap_or_else(|| {
            unreachable!("a component with a ladder degree has an interface table")
        });
        let tol = spec.tolerance.unwrap_or(0.0);
        let (max, step) = (spec.max_degree(), spec.step());
        let name = scene.components[c].name.clone();
        let counts = |m: &ReducedModel| {
            m.components[c]
                .cb_stats
                .as_ref()
                .map_or((0, 0), |s| (s.n_interface_coords, s.n_interface_dofs))
        };
        let row = |degree, m: &ReducedModel, r: &Roots, e: Option<&Estimate>, solves| DegreeRow {
            degree,
            n_coords: counts(m).0,
            difference: e.map(|e| e.value),
            root_change: e.map(|e| e.root_change),
            growth_change: e.map(|e| e.growth_change),
            estimate: e.and_then(|e| e.bound.is_finite().then_some(e.bound)),
            n_in_band: r.in_band.len(),
            n_unstable: r.in_band.iter().filter(|x| x.1).count(),
            constraint_solves: solves,
        };
        let mut degree = spec.start_degree();
        let mut history = vec![row(degree, &model, &roots, None, ladders.solves(c))];
        let mut last: Option<Estimate> = None;
        let exact = loop {
            let (nc, nf) = counts(&model);
            if nc >= nf {
                break true;
            }
            if last.as_ref().is_some_and(|e| e.bound <= tol) {
                break false;
            }
            if degree >= max {
                let tried: Vec<String> = history
                    .iter()
                    .map(|r| {
                        let f = |x: Option<Real>| x.map_or("—".into(), |x| format!("{x:.2e}"));
                        format!(
                            "degree {} ({} coordinates): difference {}, estimate {}",
                            r.degree,
                            r.n_coords,
                            f(r.difference),
                            f(r.estimate)
                        )
                    })
                    .collect();
                return Err(PipelineError::Scene {
                    field: format!("components[{c}].interface.tolerance"),
                    message: format!(
                        "{tol:e} not reached on `{name}` by max_degree = {max}: estimates {}; \
                         raise `max_degree` (≤ 30) or the tolerance",
                        tried.join(", ")
                    ),
                });
            }
            degree = (degree + step).min(max);
            ladders.degrees[c] = Some(degree);
            let finer = build_once(scene, dir, progress, cache, &ladders)?;
            let finer_roots = Roots::of(scene, &finer, progress)?;
            let mut e = difference(&roots, &finer_roots);
            e.bound = match &last {
                Some(prev) => tail(e.root_change, prev.root_change)
                    .max(tail(e.growth_change, prev.growth_change)),
                None => Real::INFINITY,
            };
            progress.info(format!(
                "component `{name}`: interface degree {degree} ({} coordinates): difference \
                 {:.2e} (roots {:.2e}, growth {:.2e}), estimate {:.2e} (tolerance {tol:.1e})",
                counts(&finer).0,
                e.value,
                e.root_change,
                e.growth_change,
                e.bound
            ));
            history.push(row(
                degree,
                &finer,
                &finer_roots,
                Some(&e),
                ladders.solves(c),
            ));
            model = finer;
            roots = finer_roots;
            last = Some(e);
        };
        let (nc, nf) = counts(&model);
        let note = match (exact, history.len()) {
            (true, _) => "the basis spans every nodal field of the patches: exact \
                                  Craig–Bampton"
                .into(),
            (false, n) => format!(
                "geometric tail of the in-band CEA roots' differences from degree {} \
                     to {degree} at the scene's [cea] state (model/degree.rs)",
                history[n.saturating_sub(3)].degree
            ),
        };
        choices.push((
            c,
            InterfaceChoice {
                degree,
                n_coords: nc,
                n_interface_dofs: nf,
                tolerance: Some(tol),
                estimate: Some(if exact {
                    0.0
                } else {
                    last.as_ref().map_or(0.0, |e| e.bound)
                }),
                growth_scale: last.as_ref().and_then(|e| e.growth_scale),
                exact,
                history,
                note,
            },
        ));
    }
    for (c, choice) in choices {
        model.components[c].interface = Some(choice);
    }
    Ok(model)
}

/// The roots of a model at the scene's `[cea]` state: in band (with their unstable flag) and
/// every root (the pool a root is matched in).
struct Roots {
    in_band: Vec<(Cplx, bool)>,
    all: Vec<Cplx>,
}

impl Roots {
    fn of(scene: &Scene, model: &ReducedModel, progress: &Progress) -> Result<Self, PipelineError> {
        let mut spec = scene.cea.clone().unwrap_or_default();
        spec.sweep = None;
        spec.validate()?;
        spec.solver.interrupt = progress.solver_interrupt();
        let problem = crate::problem::system::problem(scene, model)?;
        let r = crate::problem::linear::roots(scene, &spec, &problem, model, &Progress::quiet())?;
        let in_band: Vec<(Cplx, bool)> =
            r.kept.iter().map(|m| (m.eigenvalue, m.unstable)).collect();
        let all = r
            .kept
            .iter()
            .chain(&r.above)
            .map(|m| m.eigenvalue)
            .collect();
        Ok(Self { in_band, all })
    }
}

/// The geometric tail δ · max(1, ρ / (1 − ρ)), ρ = δ / δ_prev, of a difference that falls
/// (0 for no difference; infinite when it does not fall).
fn tail(delta: Real, prev: Real) -> Real {
    if delta == 0.0 {
        0.0
    } else if delta < prev {
        let rho = delta / prev;
        delta * (rho / (1.0 - rho)).max(1.0)
    } else {
        Real::INFINITY
    }
}

/// The difference between two degrees' roots and the finer one's estimate (module doc).
#[derive(Debug, Clone)]
struct Estimate {
    /// δ = max(root_change, growth_change).
    value: Real,
    root_change: Real,
    growth_change: Real,
    growth_scale: Option<Real>,
    /// η (infinite: unresolved).
    bound: Real,
}

fn difference(coarse: &Roots, fine: &Roots) -> Estimate {
    let both = || coarse.in_band.iter().chain(&fine.in_band);
    let pmax = both().map(|x| x.0.norm()).fold(0.0, Real::max);
    let floor = 1e-12 * pmax.max(Real::MIN_POSITIVE);
    let g = both().filter(|x| x.1).map(|x| x.0.re).fold(0.0, Real::max);
    let (mut root_change, mut growth_change) = (0.0 as Real, 0.0 as Real);
    for (set, other) in [(fine, coarse), (coarse, fine)] {
        for &(p, unstable) in &set.in_band {
            let Some(q) = other
                .all
                .iter()
                .copied()
                .min_by(|a, b| (a - p).norm().total_cmp(&(b - p).norm()))
            else {
                // No root on the other side at all: as far from it as it can be.
                root_change = Real::INFINITY;
                continue;
            };
            root_change = root_change.max((p - q).norm() / p.norm().max(floor));
            if unstable && g > 0.0 {
                growth_change = growth_change.max((p.re - q.re).abs() / g);
            }
        }
    }
    Estimate {
        value: root_change.max(growth_change),
        root_change,
        growth_change,
        growth_scale: (g > 0.0).then_some(g),
        bound: Real::INFINITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn roots(list: &[(Real, Real, bool)]) -> Roots {
        let in_band: Vec<(Cplx, bool)> = list
            .iter()
            .map(|&(re, im, u)| (Cplx::new(re, im), u))
            .collect();
        let all = in_band.iter().map(|x| x.0).collect();
        Roots { in_band, all }
    }

    /// By hand: the same roots differ by 0; halving the dominant growth rate is a growth
    /// change of 0.5 (against that rate) and a root change of 10 / |10 + 500i| (larger than
    /// the other root's 1 / |−1 + 101i|).
    #[test]
    fn difference_by_hand() {
        let a = roots(&[(-1.0, 100.0, false), (20.0, 500.0, true)]);
        let e = difference(&a, &a);
        assert_eq!((e.value, e.root_change, e.growth_change), (0.0, 0.0, 0.0));
        let b = roots(&[(-1.0, 101.0, false), (10.0, 500.0, true)]);
        let e = difference(&a, &b);
        assert!((e.growth_change - 0.5).abs() < 1e-12, "{e:?}");
        assert_eq!(e.growth_scale, Some(20.0));
        let r = 10.0 / Cplx::new(10.0, 500.0).norm();
        assert!(r > 1.0 / Cplx::new(-1.0, 101.0).norm());
        assert!((e.root_change - r).abs() < 1e-12, "{e:?}");
        assert_eq!(e.value, 0.5);
        // A spurious marginal unstable root next to a dominant one: measured against it.
        let c = roots(&[(0.1, 100.0, true), (20.0, 500.0, true)]);
        let e = difference(&a, &c);
        assert!((e.growth_change - 1.1 / 20.0).abs() < 1e-12, "{e:?}");
    }

    /// The geometric tail: differences falling by ρ = 1/2 sum to the last one, by 3/4 to three
    /// times it; a difference that does not fall is unresolved.
    #[test]
    fn tail_by_hand() {
        assert_eq!(tail(0.1, 0.2), 0.1);
        assert!((tail(0.075, 0.1) - 0.225).abs() < 1e-15);
        assert_eq!(tail(0.01, 1.0), 0.01);
        assert!(tail(0.2, 0.1).is_infinite() && tail(0.1, 0.1).is_infinite());
        assert_eq!(tail(0.0, 0.0), 0.0);
    }
}
