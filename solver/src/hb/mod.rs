//! Limit cycles of the band-limited model by harmonic balance (HB) with alternating
//! frequency–time (AFT) evaluation of the contact law, continued in the friction scale from the
//! Hopf point of each unstable root.
//!
//! # The method
//! 1. **Hopf point** ([`hopf`]): the band-limited model ([`crate::condense`]) linearised at its
//!    equilibrium for a friction scale s (μ → s μ), each unstable root of the operating point
//!    (s = 1) followed down in s until it crosses the imaginary axis at s_H.
//! 2. **Harmonic balance** ([`problem`]): the periodic outputs z(t) = Σ_k Ẑ_k e^{ikωt} of
//!    the contact DOFs (velocities, normal forces) satisfy Ẑ_k = z⁰ δ_k0 + H(ikω) F̂_k(Z), with
//!    H the band-limited transfer function (the states eliminated exactly per harmonic) and
//!    F̂ the harmonics of the exact contact law evaluated at N samples (AFT).
//! 3. **Continuation** ([`continuation`]): from a small cycle on the Hopf eigenvector
//!    (amplitude-parametrised), pseudo-arclength in (Z, ω, s) up to the operating point s = 1,
//!    where the cycle is solved with s fixed.
//! 4. **Harmonics** chosen by a convergence check: the solution at s = 1 is solved again with
//!    twice the harmonics (more samples with them) until its frequency and the RMS of the face
//!    velocity change by less than `harmonics_tol` (the last change is reported as the
//!    truncation estimate; the peak converges more slowly where the contact opens: the
//!    velocity then has a kink, and its harmonics decay like 1/k²).
//! 5. **Stability** ([`stability`]): Floquet multipliers from the monodromy matrix along the
//!    HB orbit.
//!
//! "How loud": the amplitude of the rotor's normal velocity on the friction face, from rows W
//! (the caller's: v_n,g = W_g · w over the model's velocity outputs w) sampled over a period:
//! its peak over the gaps and the period, and its RMS over both (as the transient's
//! `limit_cycle` monitor).
//!
//! # Reference
//! Krack & Gross, *Harmonic Balance for Nonlinear Vibration Problems*, Springer 2019 (HB, AFT,
//! condensation, continuation, stability; the NLvib tool); Cameron & Griffin, J. Appl. Mech.
//! 56 (1989) 149–154 (AFT); Coudeyras, Sinou & Nacivet, *A new treatment for predicting the
//! self-excited vibrations of nonlinear systems with frictional interfaces: the constrained
//! harmonic balance method*, J. Sound Vib. 319 (2009) 1175–1199 (brake squeal limit cycles
//! continued from the Hopf point); Seydel, *Practical Bifurcation and Stability Analysis*
//! (2010), ch. 7 (Floquet multipliers by the monodromy matrix).

pub mod continuation;
pub(crate) mod fourier;
pub mod hopf;
pub mod problem;
pub mod stability;

pub use stability::Floquet;

use crate::bsql::FrictionForces;
use crate::cea::Cplx;
use crate::condense::BandSystem;
use crate::{Real, SolverError};
use continuation::{newton, tangent, Extra, Frame};
use faer::Mat;
use problem::Hb;
use serde::{Deserialize, Serialize};
use std::time::Instant;

/// Options of the limit-cycle computation.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct HbOptions {
    /// Harmonics H of the continuation (default: 8).
    pub harmonics: usize,
    /// Most harmonics the convergence check may reach (default: 64).
    pub max_harmonics: usize,
    /// Largest relative change of the frequency and of the face velocity's RMS between H/2
    /// and H harmonics that accepts H (default: 2e-3).
    pub harmonics_tol: Real,
    /// AFT samples per coefficient: N = max(32, `samples_per_coefficient`·(2H + 1))
    /// (default: 8: a contact that opens puts a kink in the force, and with 4 the continuation
    /// of Hoffmann's model stalled where the gap starts to open).
    pub samples_per_coefficient: usize,
    /// Newton tolerance on the scaled residual, and its square root on the scaled step
    /// (default: 1e-7: a contact that opens puts a kink in the force, and Newton can end by
    /// cycling about it, the residual below 1e-7 but the next full step ~1e-6).
    pub tol: Real,
    /// Newton iterations per point (default: 12).
    pub max_newton: usize,
    /// The friction scale of the operating point (default: 1).
    pub target_scale: Real,
    /// Lowest friction scale of the Hopf search (default: 0.01).
    pub min_scale: Real,
    /// Step in s of the Hopf search (default: 0.02).
    pub hopf_step: Real,
    /// The velocity scale of the unknowns and of the start (e.g. the sliding speed) (default: 1).
    pub velocity_scale: Real,
    /// The normal forces' scale of the unknowns (default: none: the largest of the
    /// equilibrium's normal forces and of the unilateral rows' opening forces).
    pub force_scale: Option<Real>,
    /// First-harmonic amplitude of the start, × `velocity_scale` (default: 1e-4).
    pub start_amplitude: Real,
    /// Points of the branch at most (default: 400).
    pub max_points: usize,
    /// Largest arclength step, in the scaled unknowns (outputs / their scale, ω / ω_H, s)
    /// (default: 0.05).
    pub max_step: Real,
    /// RK4 steps per period of the monodromy (default: 2000; 0: no stability).
    pub floquet_steps: usize,
}

impl Default for HbOptions {
    fn default() -> Self {
        Self {
            harmonics: 8,
            max_harmonics: 64,
            harmonics_tol: 2e-3,
            samples_per_coefficient: 8,
            tol: 1e-7,
            max_newton: 12,
            target_scale: 1.0,
            min_scale: 0.01,
            hopf_step: 0.02,
            velocity_scale: 1.0,
            force_scale: None,
            start_amplitude: 1e-4,
            max_points: 400,
            max_step: 0.5,
            floquet_steps: 2000,
        }
    }
}

#[allow(clippy::neg_cmp_op_on_partial_ord)] // `!(x > 0.0)` deliberately rejects NaN too.
impl HbOptions {
    /// Checks every field; the error names it.
    pub fn validate(&self) -> Result<(), HbError> {
        let bad = |field: &'static str, value: String, reason: &'static str| HbError::Option {
            field,
            value,
            reason,
        };
        if self.harmonics == 0 || self.max_harmonics < self.harmonics {
            return Err(bad(
                "harmonics",
                format!("{} (max {})", self.harmonics, self.max_harmonics),
                "must be >= 1 and <= max_harmonics",
            ));
        }
        for (f, v) in [
            ("harmonics_tol", self.harmonics_tol),
            ("tol", self.tol),
            ("target_scale", self.target_scale),
            ("min_scale", self.min_scale),
            ("hopf_step", self.hopf_step),
            ("velocity_scale", self.velocity_scale),
            ("start_amplitude", self.start_amplitude),
            ("max_step", self.max_step),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(bad(f, v.to_string(), "must be finite and > 0"));
            }
        }
        if self.samples_per_coefficient < 2 || self.max_newton == 0 || self.max_points < 3 {
            return Err(bad(
                "samples_per_coefficient, max_newton, max_points",
                format!(
                    "{}, {}, {}",
                    self.samples_per_coefficient, self.max_newton, self.max_points
                ),
                "must be >= 2, >= 1, >= 3",
            ));
        }
        Ok(())
    }

    fn samples(&self, h: usize) -> usize {
        (self.samples_per_coefficient * (2 * h + 1)).max(32)
    }
}

/// How a branch ended.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "status", rename_all = "snake_case")]
pub enum LimitCycleStatus {
    /// The cycle at the operating point, with its harmonics converged.
    Reached,
    /// The root stays unstable down to `min_scale`: no Hopf point to start from.
    NoHopfPoint {
        /// The lowest scale tried.
        min_scale: Real,
    },
    /// The first points of the branch did not converge.
    StartFailed,
    /// The branch stopped before the operating point.
    NotReached {
        /// The last friction scale reached.
        scale: Real,
        /// Why.
        reason: String,
    },
    /// The harmonics did not converge up to `max_harmonics`.
    HarmonicsNotConverged {
        /// The last relative change.
        change: Real,
    },
}

/// A point of a branch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BranchPoint {
    /// Friction scale s.
    pub scale: Real,
    /// Frequency, Hz.
    pub frequency_hz: Real,
    /// Peak of the face's normal velocity over the period.
    pub peak_face_velocity: Real,
}

/// The limit cycle of one unstable root.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct LimitCycle {
    /// The unstable root at the operating point (Im > 0).
    pub root: [Real; 2],
    /// The root's frequency there, Hz.
    pub root_frequency_hz: Real,
    /// Friction scale of the Hopf point (None: not found).
    pub hopf_scale: Option<Real>,
    /// Frequency at the Hopf point, Hz.
    pub hopf_frequency_hz: Option<Real>,
    /// How it ended.
    pub status: LimitCycleStatus,
    /// Friction scale of the solution reported (the operating point when reached).
    pub scale: Real,
    /// Its frequency, Hz.
    pub frequency_hz: Real,
    /// Harmonics of the solution reported.
    pub harmonics: usize,
    /// Relative change of frequency / RMS from H/2 to H (the truncation estimate).
    pub harmonics_change: Real,
    /// Peak of the face's normal velocity over the gaps and the period.
    pub peak_face_velocity: Real,
    /// RMS of the face's normal velocity over the gaps and the period.
    pub rms_face_velocity: Real,
    /// Stability of the reported solution (None: not computed).
    pub floquet: Option<Floquet>,
    /// The branch from the Hopf point.
    pub branch: Vec<BranchPoint>,
    /// Coefficients of the outputs z (n_z × (2H + 1), row-major by output).
    pub coefficients: Vec<Real>,
    /// Newton iterations over the whole computation.
    pub newton_iterations: usize,
    /// Wall time, s.
    pub time_s: Real,
}

/// Errors of the limit-cycle computation.
#[derive(Debug, thiserror::Error)]
pub enum HbError {
    /// An option is out of range.
    #[error("invalid limit-cycle option `{field}` = {value}: {reason}")]
    Option {
        /// The field.
        field: &'static str,
        /// Its value.
        value: String,
        /// What was expected.
        reason: &'static str,
    },
    /// A callback or a solve failed.
    #[error(transparent)]
    Solver(#[from] SolverError),
}

/// The face's normal velocity (rows `face` over the contact DOFs' velocities) of the
/// coefficients `z` sampled `samples` times over a period: (peak, RMS).
fn face_amplitude(z: &[Real], m: usize, face: &Mat<Real>, samples: usize) -> (Real, Real) {
    let nc = face.ncols();
    let (mut peak, mut sum) = (0.0f64, 0.0);
    let mut v = vec![0.0; nc];
    for i in 0..samples {
        let th = 2.0 * std::f64::consts::PI * i as Real / samples as Real;
        for (a, x) in v.iter_mut().enumerate() {
            *x = fourier::evaluate(&z[a * m..(a + 1) * m], th);
        }
        for g in 0..face.nrows() {
            let vn: Real = (0..nc).map(|a| face[(g, a)] * v[a]).sum();
            peak = peak.max(vn.abs());
            sum += vn * vn;
        }
    }
    let count = (samples * face.nrows()).max(1) as Real;
    (peak, (sum / count).sqrt())
}

/// The coefficients `u` of H harmonics padded (or cut) to `h2`.
fn resize(u: &[Real], n_z: usize, h: usize, h2: usize) -> Vec<Real> {
    let (m, m2) = (2 * h + 1, 2 * h2 + 1);
    let mut out = vec![0.0; n_z * m2 + 2];
    for a in 0..n_z {
        for c in 0..m.min(m2) {
            out[a * m2 + c] = u[a * m + c];
        }
    }
    out[n_z * m2] = u[n_z * m];
    out[n_z * m2 + 1] = u[n_z * m + 1];
    out
}

fn frame_for(
    n_z: usize,
    n_c: usize,
    m: usize,
    v_scale: Real,
    f_scale: Real,
    w: Real,
    p: usize,
) -> Frame {
    let mut scale = Vec::with_capacity(n_z * m + 2);
    for a in 0..n_z {
        let s = if a < n_c { v_scale } else { f_scale };
        scale.extend(std::iter::repeat_n(s, m));
    }
    scale.push(w);
    scale.push(1.0);
    Frame {
        scale,
        p_c1: p * m + 1,
    }
}

/// The limit cycle of the unstable root `root` (a kept root of the model, Im > 0) of the band
/// system, the contact law evaluated at time `t` (after the load ramp), the face rows `face`
/// (n_face × n_v) over the model's velocity outputs.
///
/// # Errors
/// Bad options; a callback failure (a failed Newton is a status, not an error).
pub fn limit_cycle<F: FrictionForces>(
    sys: &mut BandSystem<F>,
    t: Real,
    root: Cplx,
    face: &Mat<Real>,
    opts: &HbOptions,
) -> Result<LimitCycle, HbError> {
    opts.validate()?;
    let clock = Instant::now();
    let two_pi = 2.0 * std::f64::consts::PI;
    let n_c = sys.n_velocities();
    let n_z = n_c + sys.n_rows();
    let mut out = LimitCycle {
        root: [root.re, root.im],
        root_frequency_hz: root.im / two_pi,
        hopf_scale: None,
        hopf_frequency_hz: None,
        status: LimitCycleStatus::StartFailed,
        scale: Real::NAN,
        frequency_hz: Real::NAN,
        harmonics: opts.harmonics,
        harmonics_change: Real::NAN,
        peak_face_velocity: Real::NAN,
        rms_face_velocity: Real::NAN,
        floquet: None,
        branch: Vec::new(),
        coefficients: Vec::new(),
        newton_iterations: 0,
        time_s: 0.0,
    };
    let hopf = hopf::find_hopf(
        sys,
        t,
        root,
        opts.target_scale,
        opts.min_scale,
        opts.hopf_step,
    )?;
    let Some(hopf) = hopf else {
        out.status = LimitCycleStatus::NoHopfPoint {
            min_scale: opts.min_scale,
        };
        sys.set_friction_scale(1.0);
        return Ok(out);
    };
    out.hopf_scale = Some(hopf.s);
    out.hopf_frequency_hz = Some(hopf.root.im / two_pi);
    let w_h = hopf.root.im;
    // The normal forces' scale: the largest of the equilibrium's and of the opening forces.
    let f_scale = hopf.z[n_c..]
        .iter()
        .chain(sys.contact().open_force.iter().flatten())
        .fold(0.0f64, |m, x| m.max(x.abs()))
        .max(opts.force_scale.unwrap_or(0.0))
        .max(Real::MIN_POSITIVE);
    let v_scale = opts.velocity_scale;
    // The phase output: the velocity the Hopf eigenvector moves most.
    let p = (0..n_c)
        .max_by(|&a, &b| hopf.z1[a].norm().total_cmp(&hopf.z1[b].norm()))
        .unwrap_or(0);
    let rot = hopf.z1[p].conj() / hopf.z1[p].norm();
    let mut h = opts.harmonics;
    let mut hb = Hb::new(sys, t, h, opts.samples(h));
    let m = hb.m();
    let frame = frame_for(n_z, n_c, m, v_scale, f_scale, w_h, p);
    let a0 = opts.start_amplitude * v_scale;
    let guess = |amp: Real| -> Vec<Real> {
        let mut u = vec![0.0; n_z * m + 2];
        let k = amp / hopf.z1[p].norm();
        for a in 0..n_z {
            u[a * m] = hopf.z[a];
            let z = hopf.z1[a] * rot * k;
            u[a * m + 1] = z.re;
            u[a * m + 2] = -z.im;
        }
        u[n_z * m] = w_h;
        u[n_z * m + 1] = hopf.s;
        u
    };
    let mut iters = 0;
    let mut u1 = guess(a0);
    let Some(i1) = newton(&mut hb, &mut u1, &Extra::Amplitude(a0), &frame, opts)? else {
        drop(hb);
        sys.set_friction_scale(1.0);
        out.time_s = clock.elapsed().as_secs_f64();
        return Ok(out);
    };
    let mut u2 = u1.clone();
    for a in 0..n_z {
        for c in 1..m {
            u2[a * m + c] *= 2.0;
        }
    }
    let Some(i2) = newton(&mut hb, &mut u2, &Extra::Amplitude(2.0 * a0), &frame, opts)? else {
        drop(hb);
        sys.set_friction_scale(1.0);
        out.time_s = clock.elapsed().as_secs_f64();
        return Ok(out);
    };
    iters += i1 + i2;
    let nn = u1.len();
    let scaled_diff = |a: &[Real], b: &[Real]| -> Vec<Real> {
        (0..nn).map(|j| (a[j] - b[j]) / frame.scale[j]).collect()
    };
    let norm = |v: &[Real]| v.iter().map(|x| x * x).sum::<Real>().sqrt();
    let mut tau = scaled_diff(&u2, &u1);
    let mut ds = norm(&tau);
    for x in &mut tau {
        *x /= ds;
    }
    let ds_max = opts.max_step;
    let ds_min = 1e-6 * ds;
    let target = opts.target_scale;
    let mut pts = vec![u1, u2];
    let record = |u: &[Real], m: usize| -> BranchPoint {
        let (pk, _) = face_amplitude(&u[..n_z * m], m, face, 4 * (2 * ((m - 1) / 2) + 1).max(32));
        BranchPoint {
            scale: u[n_z * m + 1],
            frequency_hz: u[n_z * m] / two_pi,
            peak_face_velocity: pk,
        }
    };
    out.branch = pts.iter().map(|u| record(u, m)).collect();
    let mut end: Option<Vec<Real>> = None;
    let mut stop_reason = String::new();
    while pts.len() < opts.max_points {
        let u = pts.last().unwrap().clone();
        let s_now = u[nn - 1];
        let pred: Vec<Real> = (0..nn)
            .map(|j| u[j] + ds * tau[j] * frame.scale[j])
            .collect();
        let mut cand = pred.clone();
        let r = newton(
            &mut hb,
            &mut cand,
            &Extra::Arclength {
                tangent: &tau,
                pred: &pred,
            },
            &frame,
            opts,
        )?;
        let Some(it) = r else {
            ds *= 0.5;
            if ds < ds_min {
                stop_reason = format!("step below {ds_min:e} at s = {s_now:.6}");
                break;
            }
            continue;
        };
        iters += it;
        let s_new = cand[nn - 1];
        if (s_now - target) * (s_new - target) <= 0.0 {
            // Crossed the operating point: solve there from the interpolation.
            let w = (target - s_now) / (s_new - s_now);
            let mut ue: Vec<Real> = (0..nn).map(|j| u[j] + w * (cand[j] - u[j])).collect();
            if let Some(it) = newton(&mut hb, &mut ue, &Extra::FixedS(target), &frame, opts)? {
                iters += it;
                end = Some(ue);
                break;
            }
        }
        if s_new < opts.min_scale
            || cand[nn - 2].partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater)
        {
            stop_reason = format!("left the range at s = {s_new:.6}, ω = {:.6}", cand[nn - 2]);
            break;
        }
        let t_new = tangent(&mut hb, &cand, &tau, &frame)?;
        tau = t_new;
        out.branch.push(record(&cand, m));
        pts.push(cand);
        ds = if it <= 2 {
            (2.0 * ds).min(ds_max)
        } else if it <= 3 {
            (1.5 * ds).min(ds_max)
        } else if it >= 7 {
            0.6 * ds
        } else {
            ds
        };
    }
    let Some(mut ue) = end else {
        let last = pts.last().unwrap();
        out.status = LimitCycleStatus::NotReached {
            scale: last[nn - 1],
            reason: if stop_reason.is_empty() {
                format!("{} points", opts.max_points)
            } else {
                stop_reason
            },
        };
        out.scale = last[nn - 1];
        out.frequency_hz = last[nn - 2] / two_pi;
        out.newton_iterations = iters;
        drop(hb);
        sys.set_friction_scale(1.0);
        out.time_s = clock.elapsed().as_secs_f64();
        return Ok(out);
    };
    out.branch.push(record(&ue, m));
    // The harmonics: twice as many until the frequency and the peak settle.
    let fine = |h: usize| 8 * (2 * h + 1);
    let (_, mut rms) = face_amplitude(&ue[..n_z * m], m, face, fine(h));
    let mut freq = ue[ue.len() - 2] / two_pi;
    let mut change = Real::INFINITY;
    let mut converged = false;
    drop(hb);
    while 2 * h <= opts.max_harmonics {
        let h2 = 2 * h;
        let mut hb2 = Hb::new(sys, t, h2, opts.samples(h2));
        let m2 = hb2.m();
        let fr2 = frame_for(n_z, n_c, m2, v_scale, f_scale, w_h, p);
        let mut u2 = resize(&ue, n_z, h, h2);
        let Some(it) = newton(&mut hb2, &mut u2, &Extra::FixedS(target), &fr2, opts)? else {
            break;
        };
        iters += it;
        let (_, rms2) = face_amplitude(&u2[..n_z * m2], m2, face, fine(h2));
        let f2 = u2[u2.len() - 2] / two_pi;
        change = ((f2 - freq) / f2).abs().max(((rms2 - rms) / rms2).abs());
        ue = u2;
        h = h2;
        rms = rms2;
        freq = f2;
        if change <= opts.harmonics_tol {
            converged = true;
            break;
        }
    }
    let m = 2 * h + 1;
    out.harmonics = h;
    out.harmonics_change = change;
    out.scale = target;
    out.frequency_hz = freq;
    let (pk, rms) = face_amplitude(&ue[..n_z * m], m, face, fine(h));
    out.peak_face_velocity = pk;
    out.rms_face_velocity = rms;
    out.status = if converged {
        LimitCycleStatus::Reached
    } else {
        LimitCycleStatus::HarmonicsNotConverged { change }
    };
    if opts.floquet_steps > 0 {
        let mut hb = Hb::new(sys, t, h, opts.samples(h));
        out.floquet = Some(stability::floquet(&mut hb, &ue, opts.floquet_steps)?);
    }
    out.coefficients = ue[..n_z * m].to_vec();
    out.newton_iterations = iters;
    sys.set_friction_scale(1.0);
    out.time_s = clock.elapsed().as_secs_f64();
    Ok(out)
}
