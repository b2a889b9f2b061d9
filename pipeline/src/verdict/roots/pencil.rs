//! The multi-channel matrix pencil and its refits (see the module `roots`).

use super::options::PencilOptions;
use super::resample::{resample_hermite, sample_spacing};
use faer::linalg::solvers::SolveLstsq;
use faer::Mat;
use num_complex::Complex64;
use serde::Serialize;
use squeal_solver::Real;

/// One oscillating root of the response, s = σ + iω.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Root {
    /// σ = Re s, 1/s (> 0: growing).
    pub growth_rate_per_s: Real,
    /// ω/2π, Hz.
    pub frequency_hz: Real,
    /// Amplitude of the real oscillation 2|a| at the window's start, the Euclidean norm over
    /// the channels (response units).
    pub amplitude: Real,
    /// The same at the window's end, amplitude·e^{σT}.
    pub amplitude_end: Real,
    /// amplitude_end ≥ `significance` × the largest amplitude_end.
    pub significant: bool,
    /// Found again in every refit on the later parts of the window (within
    /// `refit_frequency_tol` in frequency).
    pub consistent: bool,
    /// Smallest and largest σ of this root over the fit and the refits that found it
    /// (the spread is the fit's sensitivity to the window, not a confidence interval).
    pub growth_rate_range_per_s: [Real; 2],
}

/// What the estimator did, for `summary.json`.
#[derive(Debug, Clone, Serialize)]
pub struct PencilFit {
    /// Oscillating roots (at least one period in the window, below the resampling's Nyquist
    /// frequency and the band),
    /// largest amplitude at the window's end first.
    pub roots: Vec<Root>,
    /// Window [t0, t1] fitted.
    pub window: [Real; 2],
    /// Channels (output DOFs) fitted.
    pub channels: usize,
    /// Uniform samples per channel, and their spacing Δt.
    pub samples: usize,
    pub dt: Real,
    /// Pencil parameter L.
    pub pencil: usize,
    /// Model order M (complex roots, conjugates and real roots included).
    pub order: usize,
    /// The singular values s_k/s₁ up to M + 2.
    pub singular_values: Vec<Real>,
    /// ‖x − fit‖/‖x‖ over all channels and samples.
    pub relative_residual: Real,
}

impl PencilFit {
    /// The root that decides the verdict: the fastest-growing significant root among those
    /// found again in every refit.
    pub fn deciding(&self) -> Option<&Root> {
        self.roots
            .iter()
            .filter(|r| r.significant && r.consistent)
            .max_by(|a, b| a.growth_rate_per_s.total_cmp(&b.growth_rate_per_s))
    }
}

/// The model order from the singular values s (descending): the last gap s_k/s_{k+1} ≥
/// `gap_ratio` among those above `sv_floor`·s₁, else the count above the floor; within
/// [1, min(max_order, s.len() − 1)].
pub fn model_order(s: &[Real], o: &PencilOptions) -> usize {
    let cap = o.max_order.min(s.len().saturating_sub(1)).max(1);
    let s1 = s.first().copied().unwrap_or(0.0);
    if s1 <= 0.0 {
        return 1;
    }
    let above = s
        .iter()
        .take(cap)
        .take_while(|&&v| v >= o.sv_floor * s1)
        .count()
        .max(1);
    let gap = (1..=above)
        .rev()
        .find(|&k| k < s.len() && s[k - 1] >= o.gap_ratio * s[k].max(1e-300 * s1));
    gap.unwrap_or(above)
}

/// Matrix pencil of uniformly sampled channels (each `x[c]` of the same length N, spacing
/// `dt`, the first sample at `t0`); `f_max` drops roots above it. None: fewer than 8 samples,
/// no signal, or a failed factorisation.
pub fn matrix_pencil(
    x: &[Vec<Real>],
    dt: Real,
    t0: Real,
    f_max: Option<Real>,
    o: &PencilOptions,
) -> Option<PencilFit> {
    let n = x.first()?.len();
    if n < 8 || x.iter().any(|c| c.len() != n) || dt.is_nan() || dt <= 0.0 {
        return None;
    }
    let nc = x.len();
    let l = (n / 3).clamp(2, o.max_pencil.max(2));
    let rows = n - l;
    // Stacked Hankel blocks, (nc·rows) × (L + 1).
    let y = Mat::<Real>::from_fn(nc * rows, l + 1, |r, j| x[r / rows][r % rows + j]);
    let svd = y.thin_svd().ok()?;
    let sv: Vec<Real> = (0..l + 1).map(|k| svd.S().column_vector()[k]).collect();
    if !(sv[0] > 0.0 && sv[0].is_finite()) {
        return None;
    }
    let m = model_order(&sv, o).min(l);
    let v = svd.V();
    let v1 = Mat::<Real>::from_fn(l, m, |i, k| v[(i, k)]);
    let v2 = Mat::<Real>::from_fn(l, m, |i, k| v[(i + 1, k)]);
    let a = v1.qr().solve_lstsq(&v2);
    let z = a.eigenvalues().ok()?;
    // Amplitudes: least squares on the Vandermonde matrix of the roots, every channel.
    let vand = Mat::<Complex64>::from_fn(n, m, |i, k| z[k].powu(i as u32));
    let rhs = Mat::<Complex64>::from_fn(n, nc, |i, c| Complex64::new(x[c][i], 0.0));
    let amp = vand.qr().solve_lstsq(&rhs);
    let fit = &vand * &amp;
    let (mut res, mut tot) = (0.0, 0.0);
    for c in 0..nc {
        for i in 0..n {
            res += (fit[(i, c)].re - x[c][i]).powi(2);
            tot += x[c][i].powi(2);
        }
    }
    let span = (n - 1) as Real * dt;
    let nyquist = 0.5 / dt;
    let mut roots: Vec<Root> = (0..m)
        .filter_map(|k| {
            let s = z[k].ln() / dt;
            let f = s.im / (2.0 * std::f64::consts::PI);
            // At least one period in the window: slower roots are the static creep of the
            // state, not an oscillation (a real root shows up with a tiny Im part).
            let keep = s.re.is_finite()
                && f * span >= 1.0
                && f < 0.95 * nyquist
                && f_max.is_none_or(|fm| f <= fm);
            keep.then(|| {
                let a: Real = (0..nc)
                    .map(|c| (2.0 * amp[(k, c)].norm()).powi(2))
                    .sum::<Real>()
                    .sqrt();
                Root {
                    growth_rate_per_s: s.re,
                    frequency_hz: f,
                    amplitude: a,
                    amplitude_end: a * (s.re * span).exp(),
                    significant: false,
                    consistent: true,
                    growth_rate_range_per_s: [s.re, s.re],
                }
            })
        })
        .collect();
    roots.sort_by(|a, b| b.amplitude_end.total_cmp(&a.amplitude_end));
    let top = roots.first().map_or(0.0, |r| r.amplitude_end);
    for r in &mut roots {
        r.significant = r.amplitude_end >= o.significance * top && r.amplitude_end > 0.0;
    }
    Some(PencilFit {
        roots,
        window: [t0, t0 + span],
        channels: nc,
        samples: n,
        dt,
        pencil: l,
        order: m,
        singular_values: sv.iter().take(m + 2).map(|s| s / sv[0]).collect(),
        relative_residual: if tot > 0.0 { (res / tot).sqrt() } else { 0.0 },
    })
}

/// The roots of the channels `x[c]` (with derivatives `xp[c]`) recorded at the times `t`, over
/// the window [t0, t1]: resampled at [`sample_spacing`] (`f_dom`: a first estimate of the
/// dominant frequency; `f_band`: the model's band, which also bounds the roots kept).
#[allow(clippy::too_many_arguments)]
pub fn estimate(
    t: &[Real],
    x: &[&[Real]],
    xp: &[&[Real]],
    window: [Real; 2],
    f_dom: Option<Real>,
    f_band: Option<Real>,
    o: &PencilOptions,
) -> Option<PencilFit> {
    let [t0, t1] = window;
    let span = t1 - t0;
    if span.is_nan() || span <= 0.0 || t.len() < 2 || x.is_empty() {
        return None;
    }
    let dt = sample_spacing(span, f_dom, f_band, o);
    let count = (span / dt).floor() as usize + 1;
    let u: Vec<Vec<Real>> = x
        .iter()
        .zip(xp)
        .map(|(x, xp)| resample_hermite(t, x, xp, t0, dt, count))
        .collect();
    let mut fit = matrix_pencil(&u, dt, t0, f_band, o)?;
    // Refits on the later parts of the window, on the same samples.
    let refits: Vec<Option<PencilFit>> = (1..=o.refits)
        .map(|k| {
            let skip = (count * k) / (3 * o.refits);
            let tail: Vec<Vec<Real>> = u.iter().map(|c| c[skip..].to_vec()).collect();
            matrix_pencil(&tail, dt, t0 + skip as Real * dt, f_band, o)
        })
        .collect();
    mark_consistency(
        &mut fit.roots,
        &refits,
        o.refit_frequency_tol,
        o.refit_resolution_fraction,
    );
    Some(fit)
}

/// Marks each root found again in every refit (a refit root within `tol` × its frequency or
/// `resolution_fraction`/T_r Hz, T_r the refit's window, whichever is larger) and records its
/// range of σ over the fits (of the refit root nearest in the complex plane among those). A
/// refit that failed finds nothing.
pub fn mark_consistency(
    roots: &mut [Root],
    refits: &[Option<PencilFit>],
    tol: Real,
    resolution_fraction: Real,
) {
    let dist = |a: &Root, b: &Root| {
        (a.growth_rate_per_s - b.growth_rate_per_s)
            .hypot(2.0 * std::f64::consts::PI * (a.frequency_hz - b.frequency_hz))
    };
    for r in roots.iter_mut() {
        let mut range = [r.growth_rate_per_s, r.growth_rate_per_s];
        let mut found = true;
        for refit in refits {
            let near = refit.as_ref().and_then(|f| {
                let span = f.window[1] - f.window[0];
                let df = (tol * r.frequency_hz).max(resolution_fraction / span);
                f.roots
                    .iter()
                    .filter(|q| (q.frequency_hz - r.frequency_hz).abs() <= df)
                    .min_by(|a, b| dist(a, r).total_cmp(&dist(b, r)))
            });
            match near {
                Some(q) => {
                    range[0] = range[0].min(q.growth_rate_per_s);
                    range[1] = range[1].max(q.growth_rate_per_s);
                }
                None => found = false,
            }
        }
        r.consistent = found;
        r.growth_rate_range_per_s = range;
    }
}
