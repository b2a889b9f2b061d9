//! Estimators of a propensity study: probabilities with intervals (randomised QMC replicates
//! and the binomial Wilson interval), quantiles, and Saltelli's Sobol indices.

use super::design::{Design, RowKind};
use serde::{Deserialize, Serialize};
use statrs::distribution::{ContinuousCDF, StudentsT};

/// What one evaluation found (one CEA).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Outcome {
    /// Largest Re p of the roots considered (1/s).
    pub max_real_part: f64,
    /// Indices of the one-third-octave bands ([`third_octave_bands`]) holding an unstable root.
    pub unstable_bands: Vec<usize>,
    /// An unstable root anywhere in the validity band (also one outside every one-third-octave
    /// band, e.g. a real divergence root at 0 Hz).
    pub unstable: bool,
}

impl Outcome {
    /// Unstable anywhere in the validity band.
    pub fn unstable(&self) -> bool {
        self.unstable || !self.unstable_bands.is_empty()
    }
}

/// A one-third-octave band (IEC 61260-1, base 10).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    /// Exact mid-band frequency 1000·10^(k/10), Hz.
    pub center_hz: f64,
    /// Lower and upper edges, mid-band × 10^(∓1/20), Hz.
    pub lower_hz: f64,
    pub upper_hz: f64,
}

/// The one-third-octave bands whose mid-band frequencies lie in [f_lo, f_hi].
pub fn third_octave_bands(f_lo: f64, f_hi: f64) -> Vec<Band> {
    let k0 = (10.0 * (f_lo / 1000.0).log10()).ceil() as i32;
    let k1 = (10.0 * (f_hi / 1000.0).log10()).floor() as i32;
    (k0..=k1)
        .map(|k| {
            let c = 1000.0 * 10f64.powf(k as f64 / 10.0);
            Band {
                center_hz: c,
                lower_hz: c * 10f64.powf(-1.0 / 20.0),
                upper_hz: c * 10f64.powf(1.0 / 20.0),
            }
        })
        .collect()
}

/// The band holding frequency f, if any.
pub fn band_of(bands: &[Band], f: f64) -> Option<usize> {
    bands.iter().position(|b| f >= b.lower_hz && f < b.upper_hz)
}

/// A probability with its 95 % interval.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Probability {
    /// Mean over all evaluations.
    pub p: f64,
    /// 95 % interval: the union of the replicates' Student-t interval (randomised QMC) and
    /// the binomial Wilson score interval of all evaluations (conservative for QMC).
    pub interval: [f64; 2],
    /// The replicates' estimates.
    pub replicates: Vec<f64>,
}

/// First-order and total Sobol indices of one output, per input.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SobolIndices {
    /// S_i (Saltelli et al. 2010, eq. (b) of their Table 2), mean over the replicates.
    pub first_order: Vec<f64>,
    /// 95 % Student-t interval of S_i over the replicates.
    pub first_order_interval: Vec<[f64; 2]>,
    /// S_Ti (Jansen 1999), mean over the replicates.
    pub total: Vec<f64>,
    /// 95 % Student-t interval of S_Ti over the replicates.
    pub total_interval: Vec<[f64; 2]>,
    /// Variance of the output (all rows).
    pub variance: f64,
}

fn t975(dof: usize) -> f64 {
    StudentsT::new(0.0, 1.0, dof as f64)
        .map(|t| t.inverse_cdf(0.975))
        .unwrap_or(f64::INFINITY)
}

/// Mean and 95 % Student-t interval of replicate estimates.
fn mean_interval(x: &[f64]) -> (f64, [f64; 2]) {
    let r = x.len() as f64;
    let m = x.iter().sum::<f64>() / r;
    if x.len() < 2 {
        return (m, [f64::NEG_INFINITY, f64::INFINITY]);
    }
    let var = x.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (r - 1.0);
    let h = t975(x.len() - 1) * (var / r).sqrt();
    (m, [m - h, m + h])
}

/// Wilson score interval (95 %) of k successes in n trials.
fn wilson(k: usize, n: usize) -> [f64; 2] {
    let (k, n) = (k as f64, n as f64);
    let z = 1.959963984540054;
    let p = k / n;
    let den = 1.0 + z * z / n;
    let c = (p + z * z / (2.0 * n)) / den;
    let h = z * (p * (1.0 - p) / n + z * z / (4.0 * n * n)).sqrt() / den;
    [(c - h).max(0.0), (c + h).min(1.0)]
}

/// The probability that `event` holds, over the evaluated rows (None: failed).
pub fn probability(
    design: &Design,
    out: &[Option<Outcome>],
    event: impl Fn(&Outcome) -> bool,
) -> Probability {
    let mut reps = vec![(0usize, 0usize); design.replicates];
    for (row, o) in design.rows.iter().zip(out) {
        if let Some(o) = o {
            let r = &mut reps[row.replicate];
            r.1 += 1;
            if event(o) {
                r.0 += 1;
            }
        }
    }
    let est: Vec<f64> = reps
        .iter()
        .map(|&(k, n)| if n > 0 { k as f64 / n as f64 } else { f64::NAN })
        .collect();
    let (k, n) = reps.iter().fold((0, 0), |(a, b), &(k, n)| (a + k, b + n));
    let p = k as f64 / n.max(1) as f64;
    let (_, t) = mean_interval(&est);
    let w = wilson(k, n.max(1));
    Probability {
        p,
        interval: [t[0].min(w[0]).max(0.0), t[1].max(w[1]).min(1.0)],
        replicates: est,
    }
}

/// Empirical quantile (linear interpolation between order statistics, type 7).
pub fn quantile(sorted: &[f64], q: f64) -> f64 {
    if sorted.is_empty() {
        return f64::NAN;
    }
    let h = (sorted.len() - 1) as f64 * q;
    let (i, f) = (h.floor() as usize, h.fract());
    if i + 1 < sorted.len() {
        sorted[i] + f * (sorted[i + 1] - sorted[i])
    } else {
        sorted[i]
    }
}

/// First-order and total Sobol indices of the output `y` (per design row; None: failed).
/// A base point with a failed row is left out of its replicate's estimate.
///
/// # Reference
/// Saltelli, Annoni, Azzini, Campolongo, Ratto & Tarantola (2010), *Variance based
/// sensitivity analysis of model output. Design and estimator for the total sensitivity
/// index*, Comput. Phys. Commun. 181: with f_A, f_B, f_ABi the outputs of the rows of A, B
/// and A_B^(i),
/// $$S_i = \frac{\frac1N\sum f_B (f_{AB_i} - f_A)}{V},\qquad
///   S_{Ti} = \frac{\frac1{2N}\sum (f_A - f_{AB_i})^2}{V}$$
/// (their Table 2, (b) and (f); the latter is Jansen's 1999 estimator), V the variance of
/// the A and B outputs.
pub fn sobol_indices(design: &Design, y: &[Option<f64>], d: usize) -> Option<SobolIndices> {
    if !design.indices {
        return None;
    }
    let (nb, nr) = (design.n_base, design.replicates);
    // Per replicate and base index: f_A, f_B, f_ABi.
    let mut fa = vec![vec![None; nb]; nr];
    let mut fb = vec![vec![None; nb]; nr];
    let mut fab = vec![vec![vec![None; d]; nb]; nr];
    for (row, v) in design.rows.iter().zip(y) {
        let (r, i) = (row.replicate, row.index);
        match row.kind {
            RowKind::A => fa[r][i] = *v,
            RowKind::B => fb[r][i] = *v,
            RowKind::Ab(j) => fab[r][i][j] = *v,
        }
    }
    let all: Vec<f64> = fa.iter().chain(&fb).flatten().flatten().copied().collect();
    let m = all.iter().sum::<f64>() / all.len().max(1) as f64;
    let variance = all.iter().map(|v| (v - m).powi(2)).sum::<f64>() / all.len().max(1) as f64;
    let (mut s1, mut st) = (vec![Vec::new(); d], vec![Vec::new(); d]);
    for r in 0..nr {
        let ok: Vec<usize> = (0..nb)
            .filter(|&i| {
                fa[r][i].is_some() && fb[r][i].is_some() && fab[r][i].iter().all(|x| x.is_some())
            })
            .collect();
        if ok.is_empty() {
            continue;
        }
        let vals: Vec<f64> = ok
            .iter()
            .flat_map(|&i| [fa[r][i].unwrap(), fb[r][i].unwrap()])
            .collect();
        let mr = vals.iter().sum::<f64>() / vals.len() as f64;
        let vr = vals.iter().map(|v| (v - mr).powi(2)).sum::<f64>() / vals.len() as f64;
        let n = ok.len() as f64;
        for j in 0..d {
            let (mut a1, mut a2) = (0.0, 0.0);
            for &i in &ok {
                let (a, b, ab) = (fa[r][i].unwrap(), fb[r][i].unwrap(), fab[r][i][j].unwrap());
                a1 += b * (ab - a);
                a2 += (a - ab).powi(2);
            }
            if vr > 0.0 {
                s1[j].push(a1 / n / vr);
                st[j].push(a2 / (2.0 * n) / vr);
            }
        }
    }
    if s1.iter().any(|v| v.is_empty()) {
        return None;
    }
    let (first_order, first_order_interval): (Vec<f64>, Vec<[f64; 2]>) =
        s1.iter().map(|v| mean_interval(v)).unzip();
    let (total, total_interval): (Vec<f64>, Vec<[f64; 2]>) =
        st.iter().map(|v| mean_interval(v)).unzip();
    Some(SobolIndices {
        first_order,
        first_order_interval,
        total,
        total_interval,
        variance,
    })
}
