//! The error estimate of the band-limited model.
//!
//! # Derivation
//! With H(s) = Σ_all c_j b_j/(s − λ_j) the displacement response to a force (no polynomial
//! part) and the band-limited H_band(s) = Σ_kept c_j b_j/(s − λ_j) + D_u, D_u = H(0) −
//! Σ_kept c_j b_j(−1/λ_j) = Σ_removed c_j b_j (−1/λ_j), the difference is exactly
//! ```text
//! H(s) − H_band(s) = Σ_removed c_j b_j [1/(s − λ_j) + 1/λ_j] = Σ_removed c_j b_j s/(λ_j (s − λ_j)),
//! ```
//! small like s/λ_j for |λ_j| ≫ |s|. The velocities' is s times it (D_v makes the modal
//! velocity the derivative of the modal displacement, and Σ_all c_j b_j = 0), the
//! multipliers' the same sum over ν_j (their instantaneous part S⁻¹ G M⁻¹ f is in both).
//! On probe inputs F (the brake load and random combinations of the contact force patterns)
//! and a frequency grid over the band, the estimate is max_ω ‖(H − H_band)(iω) F‖ /
//! max_ω ‖H(iω) F‖ for the contact velocity outputs and for the normal forces (rigid multipliers and compliant
//! springs), each in the Frobenius norm; the denominator's maximum also over the kept roots'
//! frequencies in the band (the resonance peaks of H ≈ H_band there).

use super::spectrum::Spectrum;
use super::{BandError, BandOptions};
use crate::cea::Cplx;
use crate::Real;
use faer::{c64, Mat};

use super::Inputs;

/// The estimate's numbers.
pub(crate) struct Estimate {
    /// Relative error of the contact velocities.
    pub error: Real,
    /// Relative error of the normal forces (0 without).
    pub error_force: Real,
    /// Frequency of the largest error, Hz.
    pub at_hz: Real,
    /// Band covered, Hz.
    pub band_hz: Real,
    /// The eigendecomposition's static check.
    pub static_check: Real,
}

/// A fixed-seed generator of ±1 (a 64-bit LCG): the probes are reproducible.
struct Signs(u64);

impl Signs {
    fn next(&mut self) -> Real {
        self.0 = self
            .0
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        if (self.0 >> 33) & 1 == 1 {
            1.0
        } else {
            -1.0
        }
    }
}

fn frob(z: &Mat<c64>) -> Real {
    let mut s = 0.0;
    for j in 0..z.ncols() {
        for i in 0..z.nrows() {
            s += z[(i, j)].norm_sqr();
        }
    }
    s.sqrt()
}

fn rows(z: &Mat<c64>, idx: &[usize]) -> Mat<c64> {
    Mat::from_fn(idx.len(), z.ncols(), |r, j| z[(idx[r], j)])
}

fn real_times(a: &Mat<Real>, z: &Mat<c64>) -> Mat<c64> {
    let ac = Mat::from_fn(a.nrows(), a.ncols(), |i, j| c64::new(a[(i, j)], 0.0));
    &ac * z
}

/// The kept part of the model in complex modal form (one member per pair): what H_band needs.
pub(crate) struct Kept<'a> {
    /// Kept roots (Im ≥ 0).
    pub lams: &'a [Cplx],
    /// Their displacement shapes (n × k) and inputs (k × n_in), as scaled in the model.
    pub c: &'a Mat<c64>,
    pub b: &'a Mat<c64>,
    /// Their multipliers (ng × k).
    pub nu: &'a Mat<c64>,
    /// The model's feedthroughs.
    pub d_u: &'a Mat<Real>,
    pub d_v: &'a Mat<Real>,
    pub d_n: &'a Mat<Real>,
}

/// H_band(s) W for probe weights W (inputs × np): (u, v, N) = Σ_kept [x_j/(s − λ_j) +
/// conj] + D W with x_j = (c_j, λ_j c_j, ν_j)·b_j W.
fn band_response(k: &Kept<'_>, w: &Mat<Real>, s: c64) -> (Mat<c64>, Mat<c64>, Mat<c64>) {
    let np = w.ncols();
    let wc = Mat::from_fn(w.nrows(), np, |i, j| c64::new(w[(i, j)], 0.0));
    let bw = k.b * &wc; // k × np
    let (n, ng, nk) = (k.c.nrows(), k.nu.nrows(), k.lams.len());
    // Weighted coefficients: a_j = bw_j/(s − λ_j), and for pairs conj(bw_j)/(s − conj λ_j)
    // applied to conj(c_j): together two columns per pair.
    let cols = |m: &Mat<c64>, lam_weight: bool| -> Mat<c64> {
        let mut out = Mat::<c64>::zeros(m.nrows(), np);
        for j in 0..nk {
            let l = k.lams[j];
            let f = if lam_weight { l } else { c64::new(1.0, 0.0) };
            let pair = l.im != 0.0;
            for p in 0..np {
                let a = f * bw[(j, p)] / (s - l);
                let a2 = if pair {
                    f.conj() * bw[(j, p)].conj() / (s - l.conj())
                } else {
                    c64::new(0.0, 0.0)
                };
                for i in 0..m.nrows() {
                    let x = m[(i, j)];
                    out[(i, p)] += x * a
                        + if pair {
                            x.conj() * a2
                        } else {
                            c64::new(0.0, 0.0)
                        };
                }
            }
        }
        out
    };
    let mut u = cols(k.c, false);
    let mut v = cols(k.c, true);
    let mut nn = cols(k.nu, false);
    let add = |z: &mut Mat<c64>, d: &Mat<Real>| {
        let dw = d * w;
        for j in 0..np {
            for i in 0..z.nrows() {
                z[(i, j)] += c64::new(dw[(i, j)], 0.0);
            }
        }
    };
    add(&mut u, k.d_u);
    add(&mut v, k.d_v);
    if ng > 0 {
        add(&mut nn, k.d_n);
    }
    let _ = n;
    (u, v, nn)
}

/// The estimate for the model whose removed eigenvalue indices (both members of a pair) are
/// `removed`; `F` the input matrix and `u_stat` its static response. The removed part
/// E(iω) W is summed over the removed modes on a grid of `estimate_points` frequencies (it is
/// smooth in ω: its poles are outside the band); the band-limited part H_band(iω) W (cheap:
/// the kept modes) on the grid and at the kept roots' frequencies in the band, where the
/// response peaks.
#[allow(non_snake_case)]
pub(crate) fn estimate(
    spec: &Spectrum,
    kept: &Kept<'_>,
    inputs: &Inputs,
    F: &Mat<Real>,
    u_stat: &Mat<Real>,
    removed: &[usize],
    opts: &BandOptions,
) -> Result<Estimate, BandError> {
    let n_in = F.ncols();
    let o = inputs.first_contact();
    let nc = inputs.n_patterns();
    let n2 = 2 * spec.m;
    let mut is_removed = vec![false; n2];
    for &j in removed {
        is_removed[j] = true;
    }
    // Probe weights over the inputs.
    let mut cols: Vec<Vec<Real>> = Vec::new();
    if o == 1 {
        let mut w = vec![0.0; n_in];
        w[0] = 1.0;
        cols.push(w);
    }
    let mut sg = Signs(0x5eed_ba5e);
    if nc > 0 {
        for _ in 0..opts.probes {
            let mut w = vec![0.0; n_in];
            for x in &mut w[o..] {
                *x = sg.next();
            }
            cols.push(w);
        }
    }
    let np = cols.len();
    let two_pi = 2.0 * std::f64::consts::PI;
    let kept_max = kept
        .lams
        .iter()
        .map(|p| p.im.abs() / two_pi)
        .fold(0.0, Real::max);
    let band_hz = opts.band_hz.unwrap_or(if opts.cutoff_hz.is_finite() {
        opts.cutoff_hz
    } else {
        kept_max
    });
    if np == 0 {
        return Ok(Estimate {
            error: 0.0,
            error_force: 0.0,
            at_hz: 0.0,
            band_hz,
            static_check: 0.0,
        });
    }
    let W = Mat::from_fn(n_in, np, |i, j| cols[j][i]);
    let Fp = F * &W;
    let u_p = u_stat * &W;
    let X = spec.modal_inputs(&spec.input_rows(&Fp));
    let vw = |weights: &dyn Fn(usize) -> Option<Cplx>| -> Mat<c64> {
        // Σ_j V_w,j w_j X_j over the j with a weight, then to the DOFs.
        let y = Mat::from_fn(n2, np, |j, c| match weights(j) {
            Some(w) => X[(j, c)] * w,
            None => c64::new(0.0, 0.0),
        });
        spec.sum_to_dofs(&y)
    };
    // The static check: Σ_all c_j b_j (−1/λ_j) F = H(0) F.
    let u0 = vw(&|j| Some(-1.0 / spec.vals[j]));
    let mut num = 0.0;
    let mut den = 0.0;
    for j in 0..np {
        for i in 0..spec.n {
            num += (u0[(i, j)] - c64::new(u_p[(i, j)], 0.0)).norm_sqr();
            den += u_p[(i, j)] * u_p[(i, j)];
        }
    }
    let static_check = if den > 0.0 { (num / den).sqrt() } else { 0.0 };

    let rc = &inputs.compliant_rows;
    let contact = &inputs.contact_dofs;
    let vr = inputs.velocity_matrix();
    // Velocity (the velocity rows') and force norms of a response (u, v, N).
    let norms = |u: &Mat<c64>, v: &Mat<c64>, nn: &Mat<c64>| -> (Real, Real) {
        let nv = frob(&real_times(&vr, &rows(v, contact)));
        let mut f2 = 0.0;
        if spec.ng > 0 {
            f2 += frob(nn).powi(2);
        }
        if rc.nrows() > 0 {
            f2 += frob(&real_times(rc, u)).powi(2);
        }
        (nv, f2.sqrt())
    };
    let k = opts.estimate_points;
    let grid: Vec<Real> = (0..k)
        .map(|i| band_hz * i as Real / (k - 1) as Real)
        .collect();
    let (mut ev, mut hv, mut ef, mut hf) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut at_v, mut at_f) = (0.0, 0.0);
    for &f in &grid {
        let s = c64::new(0.0, two_pi * f);
        let g = |j: usize| -> Option<Cplx> {
            is_removed[j].then(|| {
                let l = spec.vals[j];
                s / (l * (s - l))
            })
        };
        let ue = vw(&g);
        let ve = Mat::from_fn(ue.nrows(), np, |i, j| ue[(i, j)] * s);
        let ne = if spec.ng > 0 {
            let ue_l = vw(&|j| g(j).map(|w| w * spec.vals[j]));
            spec.multipliers_of(&ue, &ue_l)
        } else {
            Mat::zeros(0, np)
        };
        let (e_v, e_f) = norms(&ue, &ve, &ne);
        let (ub, vb, nb) = band_response(kept, &W, s);
        let (h_v, h_f) = norms(&(&ub + &ue), &(&vb + &ve), &(&nb + &ne));
        if e_v > ev {
            ev = e_v;
            at_v = f;
        }
        if e_f > ef {
            ef = e_f;
            at_f = f;
        }
        hv = hv.max(h_v);
        hf = hf.max(h_f);
    }
    // The band-limited response at the kept roots in the band (its peaks).
    for p in kept.lams {
        let f = p.im / two_pi;
        if f > 0.0 && f <= band_hz {
            let (ub, vb, nb) = band_response(kept, &W, c64::new(0.0, p.im));
            let (h_v, h_f) = norms(&ub, &vb, &nb);
            hv = hv.max(h_v);
            hf = hf.max(h_f);
        }
    }
    let error = if hv > 0.0 { ev / hv } else { 0.0 };
    let error_force = if hf > 0.0 { ef / hf } else { 0.0 };
    Ok(Estimate {
        error,
        error_force,
        at_hz: if error >= error_force { at_v } else { at_f },
        band_hz,
        static_check,
    })
}
