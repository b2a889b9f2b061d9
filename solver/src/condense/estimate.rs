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
//! On probe inputs F (the brake load and random combinations of the contact DOFs' forces) and a
//! frequency grid over the band (plus the kept roots' frequencies in it), the estimate is
//! max_ω ‖(H − H_band)(iω) F‖ / max_ω ‖H(iω) F‖ for the contact DOFs' velocities and for the
//! normal forces (rigid multipliers and compliant springs), each in the Frobenius norm.

use super::spectrum::Spectrum;
use super::{BandError, BandOptions};
use crate::cea::{CeaMatrices, Cplx};
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

/// The estimate for the model whose removed eigenvalue indices (both members of a pair) are
/// `removed`; `F` the input matrix and `u_stat` its static response.
#[allow(non_snake_case)]
pub(crate) fn estimate(
    spec: &Spectrum,
    sys: &CeaMatrices,
    inputs: &Inputs,
    F: &Mat<Real>,
    u_stat: &Mat<Real>,
    removed: &[usize],
    opts: &BandOptions,
) -> Result<Estimate, BandError> {
    let _ = sys;
    let n_in = F.ncols();
    let o = inputs.first_contact();
    let nc = inputs.contact_dofs.len();
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
    let kept_max = spec
        .vals
        .iter()
        .enumerate()
        .filter(|(j, _)| !removed.contains(j))
        .map(|(_, p)| p.im.abs() / two_pi)
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
    let m = spec.m;
    let n2 = 2 * m;
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

    let mut is_removed = vec![false; n2];
    for &j in removed {
        is_removed[j] = true;
    }
    // The frequency grid.
    let k = opts.estimate_points;
    let mut freqs: Vec<Real> = (0..k)
        .map(|i| band_hz * i as Real / (k - 1) as Real)
        .collect();
    for (j, p) in spec.vals.iter().enumerate() {
        let f = p.im / two_pi;
        if !is_removed[j] && f > 0.0 && f <= band_hz {
            freqs.push(f);
        }
    }
    let force_direct = spec.instantaneous_multipliers(&Fp);
    let rc = &inputs.compliant_rows;
    let (mut ev, mut hv, mut ef, mut hf) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    let (mut at_v, mut at_f) = (0.0, 0.0);
    for &f in &freqs {
        let s = c64::new(0.0, two_pi * f);
        let g = |j: usize| -> Option<Cplx> {
            is_removed[j].then(|| {
                let l = spec.vals[j];
                s / (l * (s - l))
            })
        };
        let h = |j: usize| -> Option<Cplx> { Some(1.0 / (s - spec.vals[j])) };
        let ue = vw(&g);
        let ue_l = vw(&|j| g(j).map(|w| w * spec.vals[j]));
        let uh = vw(&h);
        let uh_l = vw(&|j| h(j).map(|w| w * spec.vals[j]));
        // Velocities at the contact DOFs: s·E and Σ λ c b/(s − λ).
        let e_v = frob(&rows(&ue, &inputs.contact_dofs)) * s.norm();
        let h_v = frob(&rows(&uh_l, &inputs.contact_dofs));
        if e_v > ev {
            ev = e_v;
            at_v = f;
        }
        hv = hv.max(h_v);
        // Normal forces: the rigid multipliers and the compliant springs.
        let mut e_f2 = 0.0;
        let mut h_f2 = 0.0;
        if spec.ng > 0 {
            let ne = spec.multipliers_of(&ue, &ue_l);
            let mut nh = spec.multipliers_of(&uh, &uh_l);
            for j in 0..np {
                for i in 0..spec.ng {
                    nh[(i, j)] += c64::new(force_direct[(i, j)], 0.0);
                }
            }
            e_f2 += frob(&ne).powi(2);
            h_f2 += frob(&nh).powi(2);
        }
        if rc.nrows() > 0 {
            e_f2 += frob(&real_times(rc, &ue)).powi(2);
            h_f2 += frob(&real_times(rc, &uh)).powi(2);
        }
        if e_f2.sqrt() > ef {
            ef = e_f2.sqrt();
            at_f = f;
        }
        hf = hf.max(h_f2.sqrt());
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
