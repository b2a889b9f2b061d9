//! The squeal verdict: growth rate of the response envelope and its dominant frequency.

use serde::Serialize;

type Real = f64;

/// Verdict on one response history (after the load ramp).
#[derive(Debug, Clone, Serialize)]
pub struct Verdict {
    /// Growth rate σ of the envelope, fit of ln(peaks of |x|) = a + σ t (None: < 3 peaks).
    pub growth_rate_per_s: Option<Real>,
    /// Dominant frequency from the zero crossings of x − mean(x) (None: < 3 crossings).
    pub dominant_frequency_hz: Option<Real>,
    /// Peaks used in the fit.
    pub n_peaks: usize,
    /// Window [t_start, t_end] analysed.
    pub window: [Real; 2],
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

/// Local maxima of |x| (strict on the left), as (t, |x|).
pub fn peaks(t: &[Real], x: &[Real]) -> Vec<(Real, Real)> {
    (1..x.len().saturating_sub(1))
        .filter(|&i| x[i].abs() > x[i - 1].abs() && x[i].abs() >= x[i + 1].abs() && x[i] != 0.0)
        .map(|i| (t[i], x[i].abs()))
        .collect()
}

/// Verdict of the samples with t > `t_after`.
pub fn analyse(t: &[Real], x: &[Real], t_after: Real) -> Verdict {
    let start = t.iter().position(|&s| s > t_after).unwrap_or(t.len());
    let (t, x) = (&t[start..], &x[start..]);
    let pk = peaks(t, x);
    let (pt, pv): (Vec<Real>, Vec<Real>) = pk.iter().map(|&(a, b)| (a, b.ln())).unzip();
    let growth = if pk.len() >= 3 { slope(&pt, &pv) } else { None };
    let mean = if x.is_empty() {
        0.0
    } else {
        x.iter().sum::<Real>() / x.len() as Real
    };
    let mut crossings = Vec::new();
    for i in 1..x.len() {
        let (a, b) = (x[i - 1] - mean, x[i] - mean);
        if a * b < 0.0 || (a != 0.0 && b == 0.0) {
            crossings.push(t[i - 1] + (t[i] - t[i - 1]) * a / (a - b));
        }
    }
    let freq = if crossings.len() >= 3 {
        let span = crossings[crossings.len() - 1] - crossings[0];
        (span > 0.0).then(|| (crossings.len() - 1) as Real / (2.0 * span))
    } else {
        None
    };
    Verdict {
        growth_rate_per_s: growth,
        dominant_frequency_hz: freq,
        n_peaks: pk.len(),
        window: [
            t.first().copied().unwrap_or(0.0),
            t.last().copied().unwrap_or(0.0),
        ],
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
        let flat = analyse(&t[..5], &x[..5], 0.0);
        assert!(flat.growth_rate_per_s.is_none());
    }
}
