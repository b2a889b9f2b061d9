//! The critical μ of a tracked mode: located between the two sweep steps that bracket its
//! onset by Illinois regula falsi on its Re p, then (projected sweeps) moved to the crossing of
//! the exact root by a bracket search and regula falsi on the exact Re p, each value from a
//! shift-invert refinement.

use super::eigen::normalise_shape;
use super::onset::follow;
use super::operator::damping;
use super::refine::{KeptFactor, RefineOptions, RefineRun};
use super::sweep::Solver;
use super::{CeaError, CeaMatrices, Cplx, Mode, SweepOptions};
use serde::{Serialize, Serializer};
use std::fmt::Display;
use std::time::Instant;

fn ser_cplx<S: Serializer>(p: &Cplx, s: S) -> Result<S::Ok, S::Error> {
    [p.re, p.im].serialize(s)
}

/// The critical μ of the exact root (a projected sweep's crossing checked by refinement).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CriticalExact {
    /// Critical μ of the exact root: linear interpolation of the crossing in `bracket`; the
    /// projected crossing when no bracket was found.
    pub mu: f64,
    /// μ at which the exact root was stable and μ at which it was unstable, the last bracket
    /// of the search (`None`: no sign change found).
    pub bracket: Option<[f64; 2]>,
    /// The bracket is shorter than `exact_critical_tol`·max(1, |μ|).
    pub converged: bool,
    /// Exact root at the unstable end of the bracket `[re, im]`.
    #[serde(serialize_with = "ser_cplx")]
    pub eigenvalue: Cplx,
    /// Its frequency, Hz.
    pub frequency_hz: f64,
    /// Exact evaluations: a build and either a projected solve and a shift-invert
    /// refinement, or (`n_followed` of them) the root followed from the last refined state.
    pub n_solves: usize,
    /// Of those, evaluations that followed the exact root(s) from the previous trial by
    /// residual inverse iteration with that trial's LU (no new factorisation, no projected
    /// solve; [`super::onset`]).
    pub n_followed: usize,
    /// Residual inverse iterations over the followed evaluations (one solve with the kept
    /// LU for three right-hand sides each).
    pub n_follow_iterations: usize,
    /// Largest backward error of a followed root (`None`: none followed).
    pub max_followed_residual: Option<f64>,
    /// Refinement shifts (complex LUs of size n + ng) over those evaluations.
    pub n_shifts: usize,
    /// Largest |p_exact − p_projected| / |p_exact| of the tracked root over the evaluations.
    pub max_rel_root_error: f64,
    /// Largest |Re p_exact − Re p_projected| over the evaluations, 1/s.
    pub max_real_part_error: f64,
    /// `mu` minus the projected critical μ.
    pub mu_change: f64,
    /// Wall time, seconds.
    pub time_s: f64,
}

/// The tracked root at one μ: the values of a bracket.
#[derive(Debug, Clone)]
pub(super) struct Point {
    pub mu: f64,
    /// Re p − instability threshold (> 0: unstable).
    pub f: f64,
    pub p: Cplx,
}

/// The onset between two points: `lo` stable (f ≤ 0), `hi` unstable (f > 0).
#[derive(Debug, Clone)]
pub(super) struct Bracket {
    pub lo: Point,
    pub hi: Point,
}

impl Bracket {
    /// Linear interpolation of f = 0 in the bracket, and the root at the unstable end (at a
    /// coalescence the stable end still has the two separate frequencies): (μ, p).
    pub fn crossing(&self) -> (f64, Cplx) {
        let (a, b) = (&self.lo, &self.hi);
        let frac = if b.f > a.f {
            (-a.f / (b.f - a.f)).clamp(0.0, 1.0)
        } else {
            0.5
        };
        (a.mu + frac * (b.mu - a.mu), b.p)
    }

    fn width(&self) -> f64 {
        self.hi.mu - self.lo.mu
    }
}

/// First Krylov dimension of a critical-μ trial's refinement (at least two blocks).
const CRITICAL_KRYLOV_DIM: usize = 8;

/// Most residual inverse iterations when following an exact root to the next trial μ.
const FOLLOW_MAX_ITER: usize = 30;

/// Smallest MAC between a followed root's shape and its shape at the last trial (a few 1e-5
/// apart in μ the shape barely moves; a lower MAC means another root was reached).
const FOLLOW_MAC_MIN: f64 = 0.9;

/// What the next trial of a critical-μ search needs to follow the exact roots of the last
/// refined one ([`follow`]).
pub(super) struct Follow {
    kept: KeptFactor,
    /// The exact tracked root followed, with its shape.
    root: (Cplx, Vec<Cplx>),
    /// The exact coalescing partner at the refined trial, if the tracked root had one: a
    /// followed root that moved by a quarter of the distance to it or more is refused (it may
    /// have converged to the partner, whose shape is close near a coalescence).
    partner: Option<Cplx>,
    /// The instability threshold of the refined trial (unstable_tol × its spectral radius).
    thr: f64,
}

/// A fully evaluated trial: the exact point, the projected one, the best-MAC exact shape, the
/// refinement shifts and what the next trials need to follow the root.
type ExactTrial = (Point, Point, Vec<Cplx>, usize, Option<Follow>);

/// A trial whose root was followed: the point, its shape, the backward error, the
/// iterations.
type FollowedTrial = (Point, Vec<Cplx>, f64, usize);

/// Largest relative frequency difference from the best-MAC mode of a coalescing partner in
/// [`tracked`].
const PARTNER_FREQUENCY_TOL: f64 = 0.1;

/// The tracked root among `modes`: of the modes whose MAC with `reference` is at least half
/// the best MAC and whose frequency is within [`PARTNER_FREQUENCY_TOL`] of the best-MAC
/// mode's (near a coalescence both partners qualify), the one with the largest Re p.
/// Returns (its index, the index of the best-MAC mode). (Without the frequency condition a
/// more unstable mode of another frequency whose shape happened to correlate was taken: on
/// the cad brake a 3.78 kHz onset was searched on the 2.36 kHz root, already unstable, and no
/// crossing was found.)
pub(super) fn tracked(modes: &[Mode], reference: &[Cplx]) -> Option<(usize, usize)> {
    let macs: Vec<f64> = modes
        .iter()
        .map(|m| super::mac(reference, &m.shape))
        .collect();
    let best = (0..macs.len()).max_by(|&a, &b| macs[a].total_cmp(&macs[b]))?;
    let fb = modes[best].frequency_hz;
    let top = (0..modes.len())
        .filter(|&i| {
            macs[i] >= 0.5 * macs[best]
                && (modes[i].frequency_hz - fb).abs() <= PARTNER_FREQUENCY_TOL * fb.abs()
        })
        .max_by(|&a, &b| modes[a].real_part.total_cmp(&modes[b].real_part))?;
    Some((top, best))
}

/// The next trial μ of a bracket: the regula falsi point of the (Illinois-weighted) values,
/// kept `0.5 tol` inside the bracket so that a trial next to the root shrinks it below `tol`.
fn trial(lo: f64, flo: f64, hi: f64, fhi: f64, tol: f64) -> f64 {
    let c = if fhi > flo {
        lo + (hi - lo) * (-flo / (fhi - flo))
    } else {
        0.5 * (lo + hi)
    };
    let d = 0.5 * tol;
    if hi - lo <= 2.0 * d {
        0.5 * (lo + hi)
    } else {
        c.clamp(lo + d, hi - d)
    }
}

impl<F, E> Solver<'_, F>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    /// The tracked root at μ (a solve of the sweep's method): the point and the shape of
    /// the best-MAC mode (the next reference).
    fn point(&mut self, mu: f64, reference: &[Cplx]) -> Result<(Point, Vec<Cplx>), CeaError> {
        let r = self.solve(mu)?;
        let thr = self.cea.unstable_tol * r.stats.spectral_radius;
        let (top, best) = tracked(&r.modes, reference).ok_or(CeaError::NoConvergence {
            what: "friction sweep: no mode to track at a critical-mu trial",
            n: 0,
        })?;
        let m = &r.modes[top];
        Ok((
            Point {
                mu,
                f: m.real_part - thr,
                p: m.eigenvalue,
            },
            r.modes[best].shape.clone(),
        ))
    }

    /// Illinois regula falsi on the tracked root's Re p − threshold in `br` until the bracket
    /// is shorter than `bisection_tol`·max(1, |μ|) or `max_bisection` solves, with a bisection
    /// step whenever two trials did not halve the bracket (Re p grows like √(μ − μc) past an
    /// undamped coalescence, where regula falsi alone creeps along the stable end). The
    /// reference shape follows the stable end. Returns the final bracket and the solves spent.
    pub(super) fn locate(
        &mut self,
        mut br: Bracket,
        mut reference: Vec<Cplx>,
        opts: &SweepOptions,
    ) -> Result<(Bracket, usize), CeaError> {
        let mut count = 0;
        let (mut wlo, mut whi) = (br.lo.f, br.hi.f);
        let mut side = 0i8;
        let mut widths = vec![br.width()];
        loop {
            let tol = opts.bisection_tol * br.hi.mu.abs().max(1.0);
            if br.width() <= tol || count >= opts.max_bisection {
                break;
            }
            let slow = count >= 2 && br.width() > 0.5 * widths[count - 2];
            let mu = if slow {
                0.5 * (br.lo.mu + br.hi.mu)
            } else {
                trial(br.lo.mu, wlo, br.hi.mu, whi, tol)
            };
            let (pt, shape) = self.point(mu, &reference)?;
            count += 1;
            if pt.f > 0.0 {
                whi = pt.f;
                br.hi = pt;
                if side == 1 {
                    wlo *= 0.5;
                }
                side = 1;
            } else {
                wlo = pt.f;
                br.lo = pt;
                reference = shape;
                if side == -1 {
                    whi *= 0.5;
                }
                side = -1;
            }
            widths.push(br.width());
        }
        Ok((br, count))
    }

    /// The exact tracked root at μ: the system built, projected on the basis, the tracked
    /// root (and the best-MAC mode, its coalescing partner near an onset) refined by
    /// shift-invert Arnoldi. Returns the exact point, the projected one, the best-MAC exact
    /// shape, the shifts and what the next trials need to follow those roots without a new
    /// factorisation (`None` when the factorisation was not the reduced one).
    fn exact_point(
        &mut self,
        mu: f64,
        reference: &[Cplx],
        band_hz: f64,
    ) -> Result<ExactTrial, CeaError> {
        self.cea.check_interrupt("the exact critical-mu search")?;
        let sys = self.system(mu)?;
        let Some(basis) = self.basis.as_ref() else {
            return Err(CeaError::InvalidOption {
                field: "sweep.refine_critical",
                value: "true".into(),
                reason: "the exact critical mu needs the projection method".into(),
            });
        };
        let mut r = basis.solve(&sys, &self.cea)?;
        let thr = self.cea.unstable_tol * r.stats.spectral_radius;
        let none = || CeaError::NoConvergence {
            what: "friction sweep: no mode to track at an exact critical-mu trial",
            n: 0,
        };
        let (top, best) = tracked(&r.modes, reference).ok_or_else(none)?;
        let projected = Point {
            mu,
            f: r.modes[top].real_part - thr,
            p: r.modes[top].eigenvalue,
        };
        let targets: Vec<usize> = if top == best {
            vec![top]
        } else {
            vec![top, best]
        };
        let split = self.slave_split(&sys);
        // One or two targets next to the shift (the projected root, ~1e-5 off on an enriched
        // basis): the first Krylov space need not be the default's; it grows by
        // `krylov_step` while a target is not settled, as always.
        let ro = &self.cea.projection.refine;
        let ro = RefineOptions {
            krylov_dim: ro.krylov_dim.min(CRITICAL_KRYLOV_DIM.max(2 * ro.block)),
            ..ro.clone()
        };
        // The band only decides which exact roots found near the shift are added as missed.
        let run = RefineRun {
            band_hz,
            unstable_tol_abs: thr,
            opts: &ro,
            interrupt: &self.cea.interrupt,
            split: split.as_ref(),
            keep: true,
        };
        let (st, kept) = run.targets(&sys, &mut r.modes, targets)?;
        let (top, best) = tracked(&r.modes, reference).ok_or_else(none)?;
        let m = &r.modes[top];
        // Follow the refined roots only (a root the refinement did not converge is not exact).
        let exact_root = |i: usize| {
            st.roots.iter().any(|x| {
                x.exact.re == r.modes[i].eigenvalue.re
                    && x.exact.im.abs() == r.modes[i].eigenvalue.im
            })
        };
        // Only the tracked (more unstable) root is followed: the LU is shifted at it, and a
        // coalescing partner (the stabilised member of the pair past the onset) would not
        // converge with it.
        let follow = match kept {
            Some(kept) if exact_root(top) => Some(Follow {
                kept,
                root: (r.modes[top].eigenvalue, r.modes[top].shape.clone()),
                partner: (best != top && exact_root(best)).then(|| r.modes[best].eigenvalue),
                thr,
            }),
            _ => None,
        };
        Ok((
            Point {
                mu,
                f: m.real_part - thr,
                p: m.eigenvalue,
            },
            projected,
            r.modes[best].shape.clone(),
            st.n_shifts,
            follow,
        ))
    }

    /// The exact tracked root at μ followed from the last refined trial ([`follow`]) by
    /// residual inverse iteration with that trial's LU. `None` (the caller then refines
    /// afresh, with the system built here) when the iteration did not converge, the shape
    /// moved (MAC with the last one below [`FOLLOW_MAC_MIN`]: another root was reached) or
    /// the root moved a quarter of the way to its coalescing partner or more.
    /// Returns the point, its shape (the next reference), the backward error and the
    /// iterations.
    fn follow_point(
        &mut self,
        mu: f64,
        fw: &mut Follow,
    ) -> Result<Option<FollowedTrial>, CeaError> {
        self.cea.check_interrupt("the exact critical-mu search")?;
        let sys = self.system(mu)?;
        let same_g = match (&sys.g, self.basis.as_ref().and_then(|b| b.g_ref.as_ref())) {
            (Some(a), Some(b)) => a == b,
            _ => false,
        };
        let tol = self.cea.projection.refine.tol;
        let x = if same_g {
            let c = damping(&sys);
            let (p0, u0) = &fw.root;
            let near = |p: Cplx| {
                fw.partner
                    .is_none_or(|q| (p - p0).norm() < 0.25 * (q - p0).norm())
            };
            follow(&fw.kept, &sys, c.as_ref(), *p0, u0, tol, FOLLOW_MAX_ITER)?
                .filter(|x| super::mac(u0, &x.u) >= FOLLOW_MAC_MIN && near(x.p))
        } else {
            None
        };
        let Some(x) = x else {
            // Keep the system for the refinement that follows.
            self.put_back(mu, sys);
            return Ok(None);
        };
        let p = Cplx::new(x.p.re, x.p.im.abs());
        let u = if x.p.im < 0.0 {
            x.u.iter().map(|z| z.conj()).collect()
        } else {
            x.u
        };
        fw.root = (p, normalise_shape(u));
        Ok(Some((
            Point {
                mu,
                f: p.re - fw.thr,
                p,
            },
            fw.root.1.clone(),
            x.residual,
            x.iterations,
        )))
    }

    /// The crossing of the exact root near the projected one (`projected`, the final bracket
    /// of [`Solver::locate`]), from exact evaluations only (the tracked root refined by
    /// shift-invert Arnoldi at each trial μ): the first trial is the projected critical μ; the
    /// next steps towards the crossing by the exact value over the projected slope (×1.5, so
    /// that it overshoots; at least `exact_critical_tol`), growing 4× until the sign changes,
    /// within one sweep step of the bracketing steps; then Illinois regula falsi with bisection steps, as
    /// [`Solver::locate`], until the exact bracket is shorter than
    /// `exact_critical_tol`·max(1, |μ|) (`converged`), or `max_exact_critical` evaluations.
    /// (Re p of a nearly neutral root is ~1e-7 of |p|: the roots of a projection, even one
    /// augmented with exact shapes, are not accurate enough to locate its crossing.)
    pub(super) fn refine_critical(
        &mut self,
        projected: &Bracket,
        reference: Vec<Cplx>,
        steps: (f64, f64),
        band_hz: f64,
        opts: &SweepOptions,
    ) -> Result<CriticalExact, CeaError> {
        let t0 = Instant::now();
        let (mu_p, p_p) = projected.crossing();
        let h = steps.1 - steps.0;
        let bounds = (steps.0 - h, steps.1 + h);
        let slope_p = (projected.hi.f - projected.lo.f) / projected.width();
        let mut out = CriticalExact {
            mu: mu_p,
            bracket: None,
            converged: false,
            eigenvalue: p_p,
            frequency_hz: p_p.im.abs() / (2.0 * std::f64::consts::PI),
            n_solves: 0,
            n_followed: 0,
            n_follow_iterations: 0,
            max_followed_residual: None,
            n_shifts: 0,
            max_rel_root_error: 0.0,
            max_real_part_error: 0.0,
            mu_change: 0.0,
            time_s: 0.0,
        };
        let mut reference = reference;
        let mut cont: Option<Follow> = None;
        let mut eval =
            |s: &mut Self, mu: f64, reference: &mut Vec<Cplx>, out: &mut CriticalExact| {
                if let Some(fw) = cont.as_mut() {
                    if let Some((e, shape, residual, its)) = s.follow_point(mu, fw)? {
                        out.n_solves += 1;
                        out.n_followed += 1;
                        out.n_follow_iterations += its;
                        out.max_followed_residual =
                            Some(out.max_followed_residual.unwrap_or(0.0).max(residual));
                        *reference = shape;
                        return Ok::<Point, CeaError>(e);
                    }
                }
                let (e, pr, shape, shifts, follow) = s.exact_point(mu, reference, band_hz)?;
                cont = follow;
                out.n_solves += 1;
                out.n_shifts += shifts;
                let err = (e.p - pr.p).norm();
                out.max_rel_root_error = out
                    .max_rel_root_error
                    .max(err / e.p.norm().max(f64::MIN_POSITIVE));
                out.max_real_part_error = out.max_real_part_error.max((e.p.re - pr.p.re).abs());
                *reference = shape;
                Ok::<Point, CeaError>(e)
            };
        // Bracket the exact crossing.
        let mut a = eval(self, mu_p, &mut reference, &mut out)?;
        let dir = if a.f > 0.0 { -1.0 } else { 1.0 };
        let tol = |mu: f64| opts.exact_critical_tol * mu.abs().max(1.0);
        let mut d = if slope_p.is_finite() && slope_p > 0.0 {
            1.5 * a.f.abs() / slope_p
        } else {
            h / 16.0
        };
        // At least the tolerance: an accurate projection (an enriched basis) puts the
        // crossing within it, and the first step then closes the bracket.
        d = d.clamp(tol(mu_p).min(h), h);
        let mut br = None;
        while out.n_solves < opts.max_exact_critical {
            let mu = a.mu + dir * d;
            if !(bounds.0..=bounds.1).contains(&mu) {
                break;
            }
            let b = eval(self, mu, &mut reference, &mut out)?;
            if (b.f > 0.0) != (a.f > 0.0) {
                br = Some(if dir > 0.0 {
                    Bracket { lo: a, hi: b }
                } else {
                    Bracket { lo: b, hi: a }
                });
                break;
            }
            a = b;
            d *= 4.0;
        }
        // Shrink it: Illinois regula falsi with bisection steps.
        if let Some(mut br) = br {
            let (mut wlo, mut whi) = (br.lo.f, br.hi.f);
            let mut side = 0i8;
            let mut widths = vec![br.width()];
            loop {
                let t = tol(br.hi.mu);
                if br.width() <= t {
                    out.converged = true;
                    break;
                }
                if out.n_solves >= opts.max_exact_critical {
                    break;
                }
                let k = widths.len() - 1;
                let slow = k >= 2 && br.width() > 0.5 * widths[k - 2];
                let mu = if slow {
                    0.5 * (br.lo.mu + br.hi.mu)
                } else {
                    trial(br.lo.mu, wlo, br.hi.mu, whi, t)
                };
                let e = eval(self, mu, &mut reference, &mut out)?;
                if e.f > 0.0 {
                    whi = e.f;
                    br.hi = e;
                    if side == 1 {
                        wlo *= 0.5;
                    }
                    side = 1;
                } else {
                    wlo = e.f;
                    br.lo = e;
                    if side == -1 {
                        whi *= 0.5;
                    }
                    side = -1;
                }
                widths.push(br.width());
            }
            out.bracket = Some([br.lo.mu, br.hi.mu]);
            let (m, p) = br.crossing();
            out.mu = m;
            out.eigenvalue = p;
        }
        out.frequency_hz = out.eigenvalue.im.abs() / (2.0 * std::f64::consts::PI);
        out.mu_change = out.mu - mu_p;
        out.time_s = t0.elapsed().as_secs_f64();
        Ok(out)
    }
}
