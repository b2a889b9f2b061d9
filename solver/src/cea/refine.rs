//! Exact refinement of the projected in-band unstable roots by shift-invert Arnoldi on the
//! full first-order operator ([`super::shift_invert`]).

use super::eigen::normalise_shape;
use super::operator::{complex_at, complex_norm, damping, real_columns};
use super::shift_invert::{Arnoldi, Elimination, Ritz, ShiftInvert, SlaveSplit};
use super::{CeaError, CeaMatrices, Cplx, Mode};
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;
use serde::{Deserialize, Serialize, Serializer};
use std::sync::Arc;
use std::time::Instant;

/// Options of the exact refinement of projected roots (see [`RefineStats`]).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RefineOptions {
    /// Refine every in-band unstable projected root exactly (default: true).
    pub enabled: bool,
    /// First Krylov dimension per shift (default: 30).
    pub krylov_dim: usize,
    /// The Krylov space grows by this many vectors while targets near the shift are not
    /// resolved (default: 20).
    pub krylov_step: usize,
    /// Largest Krylov dimension per shift (default: 200). On the cad brake's 2 043-DOF model
    /// the μ ∈ [0.35, 0.55] rows need 172 at the most unstable root (5.4 kHz) to settle the
    /// 9.7 kHz target too; at 150 about half of them took a second shift (an LU and 40 more
    /// applications) for that one root.
    pub max_krylov_dim: usize,
    /// Vectors the operator is applied to at once (band Arnoldi, default: 4): each
    /// application reads the complex factor and M, C once for the whole block, which costs
    /// about what one vector does (the solves are bound by memory traffic); 1 is plain
    /// Arnoldi.
    pub block: usize,
    /// A Ritz value θ is converged when ‖Sx − θx‖ ≤ `tol`·|θ|·‖x‖ (default: 1e-10; the error
    /// of p = σ + 1/θ is then ≲ tol·|p − σ|).
    pub tol: f64,
    /// Most shifts (complex LU factorisations of size n + ng) per CEA (default: 40).
    pub max_shifts: usize,
    /// A projected root p̃ and an exact root p pair only when |p − p̃| ≤ `match_tol`·|p̃|
    /// (default: 0.1). A target whose disc of that radius is converged and holds no exact root
    /// is spurious (a root of the projection only) and is removed.
    pub match_tol: f64,
    /// Eliminate the constraint and the multipliers by slave DOFs before the factorisation
    /// (default: true): an LU of size n − ng instead of the bordered n + ng (the same
    /// operator; see `shift_invert::Elimination`). Falls back to the bordered LU when a slave
    /// block is ill conditioned.
    pub null_space: bool,
}

impl Default for RefineOptions {
    fn default() -> Self {
        RefineOptions {
            enabled: true,
            krylov_dim: 30,
            krylov_step: 20,
            max_krylov_dim: 200,
            block: 4,
            tol: 1e-10,
            max_shifts: 40,
            match_tol: 0.1,
            null_space: true,
        }
    }
}

impl RefineOptions {
    /// Checks the options; the error names the field.
    pub fn validate(&self) -> Result<(), CeaError> {
        let bad = |field, value: String, reason: &str| {
            Err(CeaError::InvalidOption {
                field,
                value,
                reason: reason.into(),
            })
        };
        if self.krylov_dim < 2 {
            return bad(
                "refine.krylov_dim",
                self.krylov_dim.to_string(),
                "must be >= 2",
            );
        }
        if self.max_krylov_dim < self.krylov_dim {
            return bad(
                "refine.max_krylov_dim",
                self.max_krylov_dim.to_string(),
                "must be >= krylov_dim",
            );
        }
        if self.block == 0 || self.block > self.krylov_dim {
            return bad(
                "refine.block",
                self.block.to_string(),
                "must be >= 1 and <= krylov_dim",
            );
        }
        if self.krylov_step == 0 {
            return bad("refine.krylov_step", "0".into(), "must be >= 1");
        }
        if !(self.match_tol > 0.0 && self.match_tol.is_finite()) {
            return bad(
                "refine.match_tol",
                self.match_tol.to_string(),
                "must be > 0",
            );
        }
        if !(self.tol > 0.0 && self.tol < 1.0) {
            return bad("refine.tol", self.tol.to_string(), "must be in (0, 1)");
        }
        Ok(())
    }
}

fn ser_pair<S: Serializer>(p: &Cplx, s: S) -> Result<S::Ok, S::Error> {
    [p.re, p.im].serialize(s)
}

/// One refined root.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RefinedRoot {
    /// Projected root `[re, im]`.
    #[serde(serialize_with = "ser_pair")]
    pub projected: Cplx,
    /// Exact root `[re, im]` (shift-invert Arnoldi on the full operator).
    #[serde(serialize_with = "ser_pair")]
    pub exact: Cplx,
    /// |p_exact − p_projected|, 1/s.
    pub abs_change: f64,
    /// |p_exact − p_projected| / |p_exact|.
    pub rel_change: f64,
    /// Backward error of the exact pair: ‖Q(p)[u; N]‖ / ((|p|²‖M‖ + |p|‖C‖ + ‖K‖)‖u‖ +
    /// ‖A‖‖N‖) (Frobenius norms, N the least-squares multiplier).
    pub residual: f64,
    /// ‖G u‖ / (‖G‖ ‖u‖).
    pub constraint_residual: f64,
    /// Index of the shift that found it.
    pub shift: usize,
    /// The projected root was a target (in-band and unstable); others are projected roots
    /// near a shift, refined on the way.
    pub target: bool,
}

/// What one refinement shift cost and found.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct ShiftStats {
    /// The shift σ `[re, im]`.
    #[serde(serialize_with = "ser_pair")]
    pub sigma: Cplx,
    /// Final Krylov dimension.
    pub krylov_dim: usize,
    /// The factorisation: `"null_space"` (the constraint and multipliers eliminated, size
    /// n − ng) or `"bordered"` (size n + ng).
    pub factorisation: &'static str,
    /// Size of the complex LU.
    pub factor_size: usize,
    /// Operator applications (LU solves).
    pub n_applications: usize,
    /// Projected roots paired with an exact root at this shift.
    pub n_refined: usize,
    /// Radius of the converged disc around σ, 1/s.
    pub converged_radius: f64,
    /// Seconds: factorisation, operator applications, orthogonalisation, Ritz values.
    pub time_factor_s: f64,
    pub time_apply_s: f64,
    pub time_orth_s: f64,
    pub time_ritz_s: f64,
}

/// Statistics of the exact refinement.
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct RefineStats {
    /// Band of the targets, Hz: unstable projected roots with frequency ≤ it were refined.
    pub band_hz: f64,
    /// Number of targets (in-band unstable projected roots).
    pub n_targets: usize,
    /// Targets refined (their exact root converged).
    pub n_targets_refined: usize,
    /// Projected roots refined (targets and the other roots inside the converged discs).
    pub n_refined: usize,
    /// Targets whose exact root did not converge within `max_krylov_dim` or `max_shifts`
    /// (kept projected).
    pub n_failed: usize,
    /// Shifts used (one complex LU of size n + ng each).
    pub n_shifts: usize,
    /// Operator applications (LU solves) over all shifts.
    pub n_applications: usize,
    /// Targets that are stable exactly (the projection called them unstable).
    pub n_stability_changed: usize,
    /// Exact unstable in-band roots found near the shifts with no projected partner (the
    /// projection missed them); added to the modes and listed in `missed`.
    pub n_missed: usize,
    /// Those roots `[re, im]`.
    pub missed: Vec<[f64; 2]>,
    /// Targets with no exact root within `match_tol`·|p̃| although that disc converged: roots
    /// of the projection only, removed from the modes and listed in `spurious`.
    pub n_spurious: usize,
    /// Those projected roots `[re, im]`.
    pub spurious: Vec<[f64; 2]>,
    /// Largest |p_exact − p_projected|, 1/s.
    pub max_abs_change: f64,
    /// Largest |p_exact − p_projected| / |p_exact|.
    pub max_rel_change: f64,
    /// Largest |Re p_exact − Re p_projected|, 1/s.
    pub max_real_part_change: f64,
    /// Largest backward error of a refined pair.
    pub max_residual: f64,
    /// Largest constraint residual ‖G u‖ / (‖G‖ ‖u‖).
    pub max_constraint_residual: f64,
    /// Each refined root.
    pub roots: Vec<RefinedRoot>,
    /// Each shift.
    pub shifts: Vec<ShiftStats>,
    /// Wall time of the refinement, seconds.
    pub time_s: f64,
}

fn fro(a: &Mat<f64>) -> f64 {
    a.norm_l2()
}

/// Residual of an exact pair (see [`RefinedRoot::residual`]).
#[allow(non_snake_case)]
struct Residual<'a> {
    sys: &'a CeaMatrices,
    c: Option<&'a Mat<f64>>,
    A: Option<Mat<f64>>,
    qr: Option<faer::linalg::solvers::Qr<f64>>,
    norms: [f64; 5],
}

impl<'a> Residual<'a> {
    #[allow(non_snake_case)]
    fn new(sys: &'a CeaMatrices, c: Option<&'a Mat<f64>>) -> Self {
        let A = sys.g.as_ref().filter(|g| g.nrows() > 0).map(|g| {
            let gt = g.transpose().to_owned();
            match &sys.d {
                Some(d) => gt - d,
                None => gt,
            }
        });
        let qr = A.as_ref().map(|a| a.qr());
        let norms = [
            fro(&sys.m),
            c.map_or(0.0, fro),
            fro(&sys.k),
            A.as_ref().map_or(0.0, fro),
            sys.g.as_ref().map_or(0.0, fro),
        ];
        Residual {
            sys,
            c,
            A,
            qr,
            norms,
        }
    }

    /// (backward error, constraint residual) of each (p, u): the products with M, K, C and
    /// G and the least-squares multipliers for all pairs at once (each matrix read once).
    fn of_many(&self, pairs: &[(Cplx, Vec<Cplx>)]) -> Vec<(f64, f64)> {
        let Some(n) = pairs.first().map(|x| x.1.len()) else {
            return Vec::new();
        };
        let m = pairs.len();
        let u = real_columns(n, m, |j, i| pairs[j].1[i]);
        let (mu, ku) = (&self.sys.m * &u, &self.sys.k * &u);
        let cu = self.c.map(|c| c * &u);
        let mut r = real_columns(n, m, |j, i| {
            let p = pairs[j].0;
            let cu = cu
                .as_ref()
                .map_or(Cplx::new(0.0, 0.0), |cu| complex_at(cu, i, j));
            p * p * complex_at(&mu, i, j) + complex_at(&ku, i, j) + p * cu
        });
        let mut nn = vec![0.0; m];
        if let (Some(a), Some(qr)) = (&self.A, &self.qr) {
            // N = argmin ‖r + A N‖ (A real: real and imaginary parts apart).
            let nmat = qr.solve_lstsq(-&r);
            r += a * &nmat;
            for (j, x) in nn.iter_mut().enumerate() {
                *x = complex_norm(&nmat, j);
            }
        }
        let gu = self
            .sys
            .g
            .as_ref()
            .filter(|g| g.nrows() > 0)
            .map(|g| g * &u);
        let [nm, nc, nk, na, ng] = self.norms;
        (0..m)
            .map(|j| {
                let (un, rn, pa) = (complex_norm(&u, j), complex_norm(&r, j), pairs[j].0.norm());
                let scale = (pa * pa * nm + pa * nc + nk) * un + na * nn[j];
                let back = if scale > 0.0 { rn / scale } else { rn };
                let cons = match &gu {
                    Some(gu) if ng > 0.0 && un > 0.0 => complex_norm(gu, j) / (ng * un),
                    _ => 0.0,
                };
                (back, cons)
            })
            .collect()
    }
}

/// Refines every unstable mode of `modes` with frequency ≤ `band_hz` (the targets) by
/// shift-invert Arnoldi on the full first-order operator of `sys` ([`ShiftInvert`]), in place:
/// eigenvalue, frequency, real part, damping ratio, stability (Re p > `unstable_tol_abs`) and,
/// when the modes carry shapes, the shape (u of the exact eigenvector, normalised as
/// [`super::Mode::shape`]). The modes are re-sorted by frequency.
///
/// Each shift σ is the most unstable pending target. The Krylov space grows until every
/// pending target lies inside the converged disc around σ (every Ritz value nearer σ has
/// converged) or `max_krylov_dim`. Inside the disc the projected roots (targets or not) and
/// the exact ones (Im p ≥ 0) are paired one to one, nearest first, and each projected root
/// takes its exact value (pairs closer than `match_tol`·|p̃| only); an exact unstable in-band
/// root left without a projected partner is added as a new mode (`missed`); a target whose
/// match disc converged without an exact root in it is removed (`spurious`: a root of the
/// projection only). So inside the discs the result is the exact spectrum. One complex LU per
/// shift; targets near each other share it.
///
/// # Errors
/// Bad options, a singular shift (an exact root to machine precision), non-convergence of the
/// small dense eigensolver.
pub(crate) fn refine(
    sys: &CeaMatrices,
    modes: &mut Vec<Mode>,
    band_hz: f64,
    unstable_tol_abs: f64,
    opts: &RefineOptions,
    interrupt: &crate::Interrupt,
) -> Result<RefineStats, CeaError> {
    let targets: Vec<usize> = (0..modes.len())
        .filter(|&i| modes[i].unstable && modes[i].frequency_hz <= band_hz)
        .collect();
    refine_targets(
        sys,
        modes,
        targets,
        band_hz,
        unstable_tol_abs,
        opts,
        interrupt,
    )
}

/// [`refine`] with the targets given (indices into `modes`, stable or not): the exact roots
/// of a friction sweep's critical μ, where the tracked root is refined on both sides of its
/// crossing.
pub(crate) fn refine_targets(
    sys: &CeaMatrices,
    modes: &mut Vec<Mode>,
    targets: Vec<usize>,
    band_hz: f64,
    unstable_tol_abs: f64,
    opts: &RefineOptions,
    interrupt: &crate::Interrupt,
) -> Result<RefineStats, CeaError> {
    let run = RefineRun {
        band_hz,
        unstable_tol_abs,
        opts,
        interrupt,
        split: None,
        keep: false,
    };
    Ok(run.targets(sys, modes, targets)?.0)
}

/// The first shift's factorisation of a refinement, kept ([`RefineRun::keep`]): the reduced
/// LU of `Zᵀ X(σ) T` at the state it was made for, and its elimination.
pub(crate) struct KeptFactor {
    pub(crate) elim: Elimination,
    pub(crate) lu: faer::linalg::solvers::PartialPivLu<faer::c64>,
}

/// A refinement's settings, with what a friction sweep shares between its refinements.
pub(crate) struct RefineRun<'a> {
    pub(crate) band_hz: f64,
    pub(crate) unstable_tol_abs: f64,
    pub(crate) opts: &'a RefineOptions,
    pub(crate) interrupt: &'a crate::Interrupt,
    /// The slaves of G, made once per sweep (G does not change with μ); `None`: made here.
    pub(crate) split: Option<&'a Arc<SlaveSplit>>,
    /// Return the first shift's reduced factorisation (a critical-μ search follows its root
    /// to the next trial μ with it, [`super::onset`]).
    pub(crate) keep: bool,
}

impl RefineRun<'_> {
    /// [`refine_targets`] with these settings; with `keep`, also the first shift's factor
    /// (when it is the reduced one).
    pub(crate) fn targets(
        &self,
        sys: &CeaMatrices,
        modes: &mut Vec<Mode>,
        targets: Vec<usize>,
    ) -> Result<(RefineStats, Option<KeptFactor>), CeaError> {
        let (band_hz, unstable_tol_abs, opts, interrupt) = (
            self.band_hz,
            self.unstable_tol_abs,
            self.opts,
            self.interrupt,
        );
        refine_impl(
            sys,
            modes,
            targets,
            band_hz,
            unstable_tol_abs,
            opts,
            interrupt,
            self.split,
            self.keep,
        )
    }
}

#[allow(clippy::too_many_arguments)]
fn refine_impl(
    sys: &CeaMatrices,
    modes: &mut Vec<Mode>,
    targets: Vec<usize>,
    band_hz: f64,
    unstable_tol_abs: f64,
    opts: &RefineOptions,
    interrupt: &crate::Interrupt,
    split: Option<&Arc<SlaveSplit>>,
    keep: bool,
) -> Result<(RefineStats, Option<KeptFactor>), CeaError> {
    opts.validate()?;
    let t0 = Instant::now();
    let c = damping(sys);
    let res = Residual::new(sys, c.as_ref());
    let elim = match (opts.null_space, split) {
        (false, _) => None,
        (true, Some(sp)) => Elimination::with_split(sys, sp.clone()),
        (true, None) => Elimination::new(sys),
    };
    let mut kept_lu = None;
    let mut st = RefineStats {
        band_hz,
        ..RefineStats::default()
    };
    let with_shapes = modes.iter().any(|m| !m.shape.is_empty());
    let mut pending = targets;
    pending.sort_by(|&a, &b| modes[b].real_part.total_cmp(&modes[a].real_part));
    st.n_targets = pending.len();
    let is_target: Vec<bool> = (0..modes.len()).map(|i| pending.contains(&i)).collect();
    let mut done = vec![false; modes.len()];
    let mut found: Vec<Cplx> = Vec::new();
    let mut added: Vec<Mode> = Vec::new();
    let mut removed: Vec<usize> = Vec::new();
    while let Some(&first) = pending.first() {
        if st.n_shifts >= opts.max_shifts {
            break;
        }
        super::options::check_interrupt(interrupt, "the exact refinement of the roots")?;
        let sigma = modes[first].eigenvalue;
        let tf = Instant::now();
        let op = ShiftInvert::new(sys, c.as_ref(), sigma, elim.as_ref())?;
        let mut sh = ShiftStats {
            sigma,
            factorisation: op.kind(),
            factor_size: op.factor_size(),
            time_factor_s: tf.elapsed().as_secs_f64(),
            ..ShiftStats::default()
        };
        let shift = st.n_shifts;
        st.n_shifts += 1;
        let mut arn = Arnoldi::new(&op, opts.block);
        let mut k = opts.krylov_dim;
        let (ritz, pairs, exact, spurious) = loop {
            arn.grow(&op, k);
            let tr = Instant::now();
            let ritz = arn.ritz(op.sigma())?;
            let r_c = converged_radius(&ritz, sigma, opts.tol);
            sh.converged_radius = r_c;
            sh.time_ritz_s += tr.elapsed().as_secs_f64();
            // Exact roots in the disc, upper half plane (the conjugates are nearer σ's
            // mirror), not found by an earlier shift.
            let exact: Vec<usize> = (0..ritz.len())
                .filter(|&r| {
                    let p = ritz[r].p;
                    (p - sigma).norm() < r_c
                        && p.im >= -1e-8 * p.norm()
                        && !found
                            .iter()
                            .any(|q| (q - p).norm() <= 1e-8 * p.norm().max(1.0))
                })
                .collect();
            let proj: Vec<usize> = (0..modes.len())
                .filter(|&i| !done[i] && (modes[i].eigenvalue - sigma).norm() < r_c)
                .collect();
            let pairs = pair_nearest(&ritz, &exact, &proj, modes, opts.match_tol);
            // A target is settled when paired, or when its match disc lies inside the
            // converged disc (then it has no exact root: spurious).
            let settled = |t: usize| {
                pairs.iter().any(|m| m.0 == t)
                    || (modes[t].eigenvalue - sigma).norm()
                        + opts.match_tol * modes[t].eigenvalue.norm()
                        < r_c
            };
            if (settled(first) && pending.iter().all(|&t| settled(t)))
                || arn.exhausted
                || arn.dim() >= opts.max_krylov_dim
            {
                let spurious: Vec<usize> = pending
                    .iter()
                    .copied()
                    .filter(|&t| !pairs.iter().any(|m| m.0 == t) && settled(t))
                    .collect();
                break (ritz, pairs, exact, spurious);
            }
            k = (k + opts.krylov_step).min(opts.max_krylov_dim);
        };
        st.n_applications += arn.applications;
        sh.krylov_dim = arn.dim();
        sh.n_applications = arn.applications;
        sh.n_refined = pairs.len();
        sh.time_apply_s = arn.time_apply_s;
        sh.time_orth_s = arn.time_orth_s;
        st.shifts.push(sh);
        let shape_of = |r: usize| {
            let x = arn.vector(&ritz[r]);
            normalise_shape(x[..x.len() / 2].to_vec())
        };
        let refined: Vec<(Cplx, Vec<Cplx>)> = pairs
            .iter()
            .map(|&(_, r)| (ritz[r].p, shape_of(r)))
            .collect();
        let residuals = res.of_many(&refined);
        for ((&(t, _), (p, u)), (back, cons)) in pairs.iter().zip(refined).zip(residuals) {
            let old = modes[t].eigenvalue;
            let abs = (p - old).norm();
            st.roots.push(RefinedRoot {
                projected: old,
                exact: p,
                abs_change: abs,
                rel_change: abs / p.norm().max(f64::MIN_POSITIVE),
                residual: back,
                constraint_residual: cons,
                shift,
                target: is_target[t],
            });
            set_mode(&mut modes[t], p, u, with_shapes, unstable_tol_abs);
            done[t] = true;
            found.push(p);
        }
        for &r in &exact {
            if pairs.iter().any(|m| m.1 == r) {
                continue;
            }
            let p = ritz[r].p;
            found.push(p);
            if p.im / (2.0 * std::f64::consts::PI) <= band_hz && p.re > unstable_tol_abs {
                st.missed.push([p.re, p.im]);
                let mut md = modes[first].clone();
                set_mode(&mut md, p, shape_of(r), with_shapes, unstable_tol_abs);
                added.push(md);
            }
        }
        for &t in &spurious {
            st.spurious
                .push([modes[t].eigenvalue.re, modes[t].eigenvalue.im]);
            done[t] = true;
            removed.push(t);
        }
        if !done[first] {
            st.n_failed += 1;
        }
        pending.retain(|&t| t != first && !done[t]);
        if keep && shift == 0 {
            kept_lu = op.into_reduced_lu();
        }
    }
    st.n_failed += pending.len();
    st.n_refined = st.roots.len();
    st.n_targets_refined = st.roots.iter().filter(|r| r.target).count();
    st.n_missed = st.missed.len();
    for r in &st.roots {
        st.max_abs_change = st.max_abs_change.max(r.abs_change);
        st.max_rel_change = st.max_rel_change.max(r.rel_change);
        st.max_real_part_change = st
            .max_real_part_change
            .max((r.exact.re - r.projected.re).abs());
        st.max_residual = st.max_residual.max(r.residual);
        st.max_constraint_residual = st.max_constraint_residual.max(r.constraint_residual);
        if r.target && r.exact.re <= unstable_tol_abs {
            st.n_stability_changed += 1;
        }
    }
    st.n_spurious = st.spurious.len();
    removed.sort_unstable();
    for &t in removed.iter().rev() {
        modes.remove(t);
    }
    modes.extend(added);
    modes.sort_by(|x, y| {
        x.frequency_hz
            .total_cmp(&y.frequency_hz)
            .then(x.real_part.total_cmp(&y.real_part))
    });
    st.time_s = t0.elapsed().as_secs_f64();
    let kept = match (kept_lu, elim) {
        (Some(lu), Some(elim)) => Some(KeptFactor { elim, lu }),
        _ => None,
    };
    Ok((st, kept))
}

/// Gives `md` the exact root p (Im p ≥ 0 kept) and, with shapes, the shape u.
fn set_mode(md: &mut Mode, p: Cplx, u: Vec<Cplx>, with_shapes: bool, unstable_tol_abs: f64) {
    md.eigenvalue = Cplx::new(p.re, p.im.abs());
    md.frequency_hz = p.im.abs() / (2.0 * std::f64::consts::PI);
    md.real_part = p.re;
    md.damping_ratio = (p.im != 0.0).then(|| -2.0 * p.re / p.im.abs());
    md.unstable = p.re > unstable_tol_abs;
    md.shape = if !with_shapes {
        Vec::new()
    } else if p.im < 0.0 {
        normalise_shape(u.iter().map(|z| z.conj()).collect())
    } else {
        u
    };
}

/// Distance from σ within which every Ritz value is converged.
fn converged_radius(ritz: &[Ritz], sigma: Cplx, tol: f64) -> f64 {
    let mut by_dist: Vec<(f64, bool)> = ritz
        .iter()
        .map(|r| ((r.p - sigma).norm(), r.rel_residual <= tol))
        .collect();
    by_dist.sort_by(|a, b| a.0.total_cmp(&b.0));
    match by_dist.iter().position(|x| !x.1) {
        Some(i) => by_dist[i].0,
        None => by_dist.last().map_or(0.0, |x| x.0 * (1.0 + 1e-12)),
    }
}

/// One-to-one pairs (mode index, Ritz index) of the projected roots `proj` and the exact ones
/// `exact` within `match_tol`·|p̃| of each other, nearest first.
fn pair_nearest(
    ritz: &[Ritz],
    exact: &[usize],
    proj: &[usize],
    modes: &[Mode],
    match_tol: f64,
) -> Vec<(usize, usize)> {
    let mut all: Vec<(f64, usize, usize)> = Vec::with_capacity(exact.len() * proj.len());
    for &t in proj {
        let pt = modes[t].eigenvalue;
        for &r in exact {
            let d = (ritz[r].p - pt).norm();
            if d <= match_tol * pt.norm() {
                all.push((d, t, r));
            }
        }
    }
    all.sort_by(|a, b| a.0.total_cmp(&b.0));
    let (mut used_t, mut used_r) = (Vec::new(), Vec::new());
    let mut out = Vec::new();
    for (_, t, r) in all {
        if !used_t.contains(&t) && !used_r.contains(&r) {
            used_t.push(t);
            used_r.push(r);
            out.push((t, r));
        }
    }
    out
}
