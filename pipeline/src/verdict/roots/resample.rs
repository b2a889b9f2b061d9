//! The response on a uniform grid: cubic Hermite resampling of the integrator's accepted steps,
//! and the grid's spacing.

use super::options::PencilOptions;
use squeal_solver::Real;

/// Cubic Hermite interpolation of (t_i, x_i, x'_i) at the uniform times t0 + nΔt, n < count.
/// `t` must be non-decreasing; repeated times are skipped.
pub fn resample_hermite(
    t: &[Real],
    x: &[Real],
    xp: &[Real],
    t0: Real,
    dt: Real,
    count: usize,
) -> Vec<Real> {
    let mut out = Vec::with_capacity(count);
    let mut i = 0;
    for n in 0..count {
        let s = t0 + n as Real * dt;
        while i + 2 < t.len() && t[i + 1] < s {
            i += 1;
        }
        let j = (i + 1).min(t.len() - 1);
        let h = t[j] - t[i];
        if h <= 0.0 {
            out.push(x[i]);
            continue;
        }
        let u = ((s - t[i]) / h).clamp(0.0, 1.0);
        let (u2, u3) = (u * u, u * u * u);
        out.push(
            (2.0 * u3 - 3.0 * u2 + 1.0) * x[i]
                + (u3 - 2.0 * u2 + u) * h * xp[i]
                + (-2.0 * u3 + 3.0 * u2) * x[j]
                + (u3 - u2) * h * xp[j],
        );
    }
    out
}

/// The sample spacing for a window of length `span`: `samples_per_period` per period of the
/// dominant frequency `f_dom` and `band_samples_per_period` at the band's top `f_band`, no
/// finer than `span / max_samples`.
pub fn sample_spacing(
    span: Real,
    f_dom: Option<Real>,
    f_band: Option<Real>,
    o: &PencilOptions,
) -> Real {
    let mut dt = Real::INFINITY;
    if let Some(f) = f_dom.filter(|f| *f > 0.0 && f.is_finite()) {
        dt = dt.min(1.0 / (o.samples_per_period * f));
    }
    if let Some(f) = f_band.filter(|f| *f > 0.0 && f.is_finite()) {
        dt = dt.min(1.0 / (o.band_samples_per_period * f));
    }
    let finest = span / o.max_samples.max(8) as Real;
    if dt.is_finite() {
        dt.max(finest)
    } else {
        finest
    }
}
