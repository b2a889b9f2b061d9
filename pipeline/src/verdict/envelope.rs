//! The envelope of one DOF's response: its growth and zero-crossing frequency, the cross-check
//! of the root estimator.

use serde::Serialize;
use squeal_solver::Real;

/// The growth of one DOF's envelope and its zero-crossing frequency (the cross-check of the
/// root estimator; blind to growth below ln 2 / window and biased by beating roots).
#[derive(Debug, Clone, Serialize)]
pub struct Envelope {
    /// Growth rate σ of the envelope: least-squares fit of ln h_k = a + σ t_k over the half
    /// peak-to-peak amplitudes h_k = |x_{k+1} − x_k|/2 of consecutive extremes, placed at their
    /// mid-times (None: < 3 of them). For c + A e^{σt} sin(ωt + φ) these are exactly
    /// proportional to e^{σ t_k}, whatever the static offset c.
    pub growth_rate_per_s: Option<Real>,
    /// Dominant frequency from the spacing of the extremes of x, i.e. the zero crossings of
    /// dx/dt (None: < 3 crossings). The extremes of c + e^{σt} sin(ωt + φ) are exactly π/ω
    /// apart whatever the offset c and growth σ, which the crossings of x − mean(x) are not
    /// (on a growing signal the window mean is biased by ≈ σ/ω of the last amplitude).
    pub dominant_frequency_hz: Option<Real>,
    /// Growth of the fitted envelope over the fitted amplitudes' span, e^{σ (t_last − t_first)}
    /// (None: no growth rate).
    pub growth_factor: Option<Real>,
    /// Half peak-to-peak amplitudes used in the fit.
    pub n_peaks: usize,
    /// Window [t_start, t_end] analysed (the later half after the ramp).
    pub window: [Real; 2],
    /// Largest accepted step in the window.
    pub h_max_window: Option<Real>,
}

impl Envelope {
    /// A clear growth: the envelope grows faster than `rate` (per unit time) and by at least
    /// `min_factor` over the analysed window.
    pub fn is_squeal(&self, rate: Real, min_factor: Real) -> bool {
        match (self.growth_rate_per_s, self.growth_factor) {
            (Some(g), Some(f)) => g > rate && f >= min_factor,
            _ => false,
        }
    }
}

/// Least-squares slope of y against x.
pub fn slope(x: &[Real], y: &[Real]) -> Option<Real> {
    let n = x.len() as Real;
    if x.len() < 2 {
        return None;
    }
    let mx = x.iter().sum::<Real>() / n;
    let my = y.iter().sum::<Real>() / n;
    let sxx: Real = x.iter().map(|a| (a - mx).powi(2)).sum();
    let sxy: Real = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// Envelope of the later half of the samples with t > `t_after`.
///
/// Only the later half is analysed: right after the load ramp the response holds every excited
/// mode, and a self-excited pair (σ ± iω) comes with a stable partner (−σ ± iω) of the same
/// frequency whose beating biases an envelope fit; by the second half the partner has decayed
/// by e^{−σT/2} relative to the growing mode.
pub fn analyse(t: &[Real], x: &[Real], t_after: Real) -> Envelope {
    let first = t.iter().position(|&s| s > t_after).unwrap_or(t.len());
    let t_mid = match (t.get(first), t.last()) {
        (Some(&a), Some(&b)) => 0.5 * (a + b),
        _ => t_after,
    };
    let start = t
        .iter()
        .position(|&s| s >= t_mid)
        .unwrap_or(t.len())
        .max(first);
    let (t, x) = (&t[start..], &x[start..]);
    // Slopes between samples, located at the interval midpoints; their sign changes are the
    // extremes of x.
    let slopes: Vec<(Real, Real)> = (1..x.len())
        .filter(|&i| t[i] > t[i - 1])
        .map(|i| {
            (
                0.5 * (t[i] + t[i - 1]),
                (x[i] - x[i - 1]) / (t[i] - t[i - 1]),
            )
        })
        .collect();
    let mut crossings = Vec::new();
    for w in slopes.windows(2) {
        let ((ta, a), (tb, b)) = (w[0], w[1]);
        if a * b < 0.0 || (a != 0.0 && b == 0.0) {
            crossings.push(ta + (tb - ta) * a / (a - b));
        }
    }
    let freq = if crossings.len() >= 3 {
        let span = crossings[crossings.len() - 1] - crossings[0];
        (span > 0.0).then(|| (crossings.len() - 1) as Real / (2.0 * span))
    } else {
        None
    };
    // Extremes: the sample between two slopes of opposite sign.
    let mut extremes: Vec<(Real, Real)> = Vec::new();
    for i in 1..x.len().saturating_sub(1) {
        let (a, b) = (x[i] - x[i - 1], x[i + 1] - x[i]);
        if a * b < 0.0 || (a != 0.0 && b == 0.0) {
            extremes.push((t[i], x[i]));
        }
    }
    let (pt, pv): (Vec<Real>, Vec<Real>) = extremes
        .windows(2)
        .filter(|w| w[1].1 != w[0].1)
        .map(|w| {
            (
                0.5 * (w[0].0 + w[1].0),
                (0.5 * (w[1].1 - w[0].1).abs()).ln(),
            )
        })
        .unzip();
    let growth = if pt.len() >= 3 { slope(&pt, &pv) } else { None };
    let span = match (pt.first(), pt.last()) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    Envelope {
        growth_rate_per_s: growth,
        growth_factor: growth.map(|g| (g * span).exp()),
        dominant_frequency_hz: freq,
        n_peaks: pt.len(),
        window: [
            t.first().copied().unwrap_or(0.0),
            t.last().copied().unwrap_or(0.0),
        ],
        h_max_window: (1..t.len())
            .map(|i| t[i] - t[i - 1])
            .fold(None, |m: Option<Real>, h| Some(m.map_or(h, |m| m.max(h)))),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// x = e^{σt} sin(2πft) sampled finely: the fit returns σ and f (analytic reference).
    #[test]
    fn growth_and_frequency_of_a_growing_sine() {
        let (sigma, f) = (3.0, 50.0);
        let t: Vec<Real> = (0..20000).map(|i| i as Real * 1e-5).collect();
        let x: Vec<Real> = t
            .iter()
            .map(|&s| (sigma * s).exp() * (2.0 * std::f64::consts::PI * f * s).sin())
            .collect();
        let v = analyse(&t, &x, 0.0);
        assert!(
            (v.growth_rate_per_s.unwrap() - sigma).abs() < 0.01 * sigma,
            "{v:?}"
        );
        assert!(
            (v.dominant_frequency_hz.unwrap() - f).abs() < 1e-3 * f,
            "{v:?}"
        );
        // A static offset and a fast growth (σ/ω ≈ 0.1) do not bias the frequency.
        let (sigma, f) = (30.0, 50.0);
        let x: Vec<Real> = t
            .iter()
            .map(|&s| 5.0 + (sigma * s).exp() * (2.0 * std::f64::consts::PI * f * s + 0.3).sin())
            .collect();
        let v = analyse(&t, &x, 0.0);
        assert!(
            (v.dominant_frequency_hz.unwrap() - f).abs() < 1e-3 * f,
            "{v:?}"
        );
        assert!(
            (v.growth_rate_per_s.unwrap() - sigma).abs() < 0.01 * sigma,
            "{v:?}"
        );
        let flat = analyse(&t[..5], &x[..5], 0.0);
        assert!(flat.growth_rate_per_s.is_none());
        assert!(!flat.is_squeal(0.0, 1.0));
    }

    /// The growth factor is e^{σ·span} of the fitted amplitudes; a slow growth over a short
    /// window is not a clear growth, the same growth over a long window is.
    #[test]
    fn growth_factor_decides_a_clear_growth() {
        let (sigma, f) = (50.0, 2000.0);
        let signal = |tf: Real| {
            let t: Vec<Real> = (0..(tf / 1e-6) as usize)
                .map(|i| i as Real * 1e-6)
                .collect();
            let x: Vec<Real> = t
                .iter()
                .map(|&s| (sigma * s).exp() * (2.0 * std::f64::consts::PI * f * s).sin())
                .collect();
            (t, x)
        };
        // Later half of 6 ms: the amplitudes span 2.5 ms (half-periods 0.25 ms apart), factor
        // e^{0.125} ≈ 1.13.
        let (t, x) = signal(0.006);
        let v = analyse(&t, &x, 0.0);
        let g = v.growth_factor.unwrap();
        assert!((g.ln() / sigma - 0.0025).abs() < 1e-5, "{v:?}");
        assert!(v.is_squeal(0.0, 1.0) && !v.is_squeal(0.0, 2.0), "{v:?}");
        // Later half of 40 ms: factor e^{1.0} ≈ 2.7.
        let (t, x) = signal(0.04);
        let v = analyse(&t, &x, 0.0);
        assert!(v.is_squeal(0.0, 2.0), "{v:?}");
    }
}
