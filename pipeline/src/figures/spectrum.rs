//! Amplitude spectrum of a non-uniformly sampled signal, and its figure.
//!
//! Steps: linear interpolation onto `n` uniform times spanning `[t_0, t_end]`; mean removed;
//! Hann window; zero padding to `zero_pad ×` the next power of two; radix-2 FFT
//! ([`super::fft_in_place`]); single-sided amplitude scaled so that a sine of amplitude `A` at a
//! bin centre reads `A`; peaks = local maxima, refined by a parabola through the logarithms of
//! the three highest bins (exact for a Gaussian lobe, close for Hann's); a peak that may be a
//! side lobe of a larger one (within 2 resolution bins `1/T` of it, or under 3× Hann's
//! side-lobe envelope 0.0266·(2.36/δ)³ at δ bins) is dropped. Two components closer than about
//! 2.4/T cannot be told apart.
//!
//! Linear interpolation attenuates a sine of angular frequency ω sampled at step `h` by at most
//! about (ωh)²/8: sample the signal at ≥ 20 points per period of the highest frequency wanted.

use super::fft::fft_in_place;
use super::{Figure, FigureError, Series, SeriesStyle};
use serde::{Deserialize, Serialize};
use std::f64::consts::PI;

/// Options of [`amplitude_spectrum`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SpectrumOptions {
    /// Number of uniform samples the signal is interpolated onto (default: `None`, the next power
    /// of two ≥ the number of input samples).
    pub n_samples: Option<usize>,
    /// Zero-padding factor, a power of two ≥ 1: the FFT length is this × the next power of two
    /// ≥ `n_samples`, which makes the plotted bins finer (default: 4).
    pub zero_pad: usize,
    /// Number of peaks reported, largest first (default: 5).
    pub n_peaks: usize,
    /// Peaks below this fraction of the largest are not reported (default: 1e-3, −60 dB).
    /// Side lobes of a larger peak are never reported (see [`amplitude_spectrum`]).
    pub min_peak_ratio: f64,
    /// Highest frequency searched for peaks and plotted (default: `None`, the Nyquist frequency).
    pub f_max_hz: Option<f64>,
}

impl Default for SpectrumOptions {
    fn default() -> Self {
        Self {
            n_samples: None,
            zero_pad: 4,
            n_peaks: 5,
            min_peak_ratio: 1e-3,
            f_max_hz: None,
        }
    }
}

impl SpectrumOptions {
    /// Checks every field; the message names the field and its value.
    pub fn validate(&self) -> Result<(), FigureError> {
        let bad = |m: String| Err(FigureError::Spectrum(m));
        if let Some(n) = self.n_samples {
            if n < 4 {
                return bad(format!("n_samples = {n} must be ≥ 4"));
            }
        }
        if self.zero_pad == 0 || !self.zero_pad.is_power_of_two() || self.zero_pad > 64 {
            return bad(format!(
                "zero_pad = {} must be a power of two in 1..=64",
                self.zero_pad
            ));
        }
        if !(0.0..1.0).contains(&self.min_peak_ratio) {
            return bad(format!(
                "min_peak_ratio = {} must be in [0, 1)",
                self.min_peak_ratio
            ));
        }
        if let Some(f) = self.f_max_hz {
            if !(f.is_finite() && f > 0.0) {
                return bad(format!("f_max_hz = {f} must be finite and > 0"));
            }
        }
        Ok(())
    }
}

/// A peak of the amplitude spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Peak {
    /// Interpolated frequency (Hz when t is in seconds).
    pub freq_hz: f64,
    /// Interpolated amplitude (units of the signal).
    pub amplitude: f64,
}

/// Single-sided amplitude spectrum.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Spectrum {
    /// Bin frequencies `k·df`, k = 0..=n_fft/2.
    pub freq_hz: Vec<f64>,
    /// Amplitude per bin.
    pub amplitude: Vec<f64>,
    /// Bin spacing `1/(n_fft·dt)`.
    pub df_hz: f64,
    /// Uniform step of the interpolated signal.
    pub dt: f64,
    /// Number of uniform samples (before zero padding).
    pub n_samples: usize,
    /// FFT length (after zero padding).
    pub n_fft: usize,
    /// Largest peaks, largest first.
    pub peaks: Vec<Peak>,
}

/// The amplitude spectrum of `y(t)`, `t` strictly increasing (steps need not be uniform).
pub fn amplitude_spectrum(
    t: &[f64],
    y: &[f64],
    options: &SpectrumOptions,
) -> Result<Spectrum, FigureError> {
    options.validate()?;
    let bad = |m: String| Err(FigureError::Spectrum(m));
    if t.len() != y.len() {
        return bad(format!("t has {} values but y has {}", t.len(), y.len()));
    }
    if t.len() < 4 {
        return bad(format!("{} samples, need at least 4", t.len()));
    }
    for (i, (&ti, &yi)) in t.iter().zip(y).enumerate() {
        if !ti.is_finite() || !yi.is_finite() {
            return bad(format!("sample {i}: t = {ti}, y = {yi} is not finite"));
        }
        if i > 0 && ti <= t[i - 1] {
            return bad(format!(
                "t[{i}] = {ti} is not after t[{}] = {}",
                i - 1,
                t[i - 1]
            ));
        }
    }
    let n = options
        .n_samples
        .unwrap_or_else(|| t.len().next_power_of_two());
    let (t0, t1) = (t[0], t[t.len() - 1]);
    let dt = (t1 - t0) / (n - 1) as f64;
    // Linear interpolation onto the uniform grid (one forward pass).
    let mut u = Vec::with_capacity(n);
    let mut j = 0;
    for i in 0..n {
        let ti = if i == n - 1 { t1 } else { t0 + i as f64 * dt };
        while j + 2 < t.len() && t[j + 1] < ti {
            j += 1;
        }
        let s = ((ti - t[j]) / (t[j + 1] - t[j])).clamp(0.0, 1.0);
        u.push(y[j] + s * (y[j + 1] - y[j]));
    }
    let mean = u.iter().sum::<f64>() / n as f64;
    let n_fft = n.next_power_of_two() * options.zero_pad;
    let mut re = vec![0.0; n_fft];
    let mut im = vec![0.0; n_fft];
    let mut sum_w = 0.0;
    for i in 0..n {
        let w = 0.5 * (1.0 - (2.0 * PI * i as f64 / (n - 1) as f64).cos());
        sum_w += w;
        re[i] = w * (u[i] - mean);
    }
    fft_in_place(&mut re, &mut im)?;
    let half = n_fft / 2;
    let df_hz = 1.0 / (n_fft as f64 * dt);
    let freq_hz: Vec<f64> = (0..=half).map(|k| k as f64 * df_hz).collect();
    let amplitude: Vec<f64> = (0..=half)
        .map(|k| {
            let one_sided = if k == 0 || k == half { 1.0 } else { 2.0 };
            one_sided * re[k].hypot(im[k]) / sum_w
        })
        .collect();
    let f_max = options.f_max_hz.unwrap_or(f64::INFINITY);
    let resolution_hz = 1.0 / (n as f64 * dt);
    let peaks = find_peaks(&amplitude, df_hz, resolution_hz, f_max, options);
    Ok(Spectrum {
        freq_hz,
        amplitude,
        df_hz,
        dt,
        n_samples: n,
        n_fft,
        peaks,
    })
}

/// Local maxima of `a` up to `f_max`, refined, largest first, side lobes removed.
fn find_peaks(
    a: &[f64],
    df: f64,
    resolution_hz: f64,
    f_max: f64,
    options: &SpectrumOptions,
) -> Vec<Peak> {
    let last = a.len().saturating_sub(1).min((f_max / df).floor() as usize);
    let top = a[..=last].iter().copied().fold(0.0f64, f64::max);
    let mut peaks: Vec<Peak> = (1..last)
        .filter(|&k| a[k] > a[k - 1] && a[k] >= a[k + 1] && a[k] >= options.min_peak_ratio * top)
        .map(|k| {
            let (l, c, r) = (a[k - 1], a[k], a[k + 1]);
            if l > 0.0 && r > 0.0 {
                let (l, c, r) = (l.ln(), c.ln(), r.ln());
                let den = l - 2.0 * c + r;
                let d = if den < 0.0 {
                    (0.5 * (l - r) / den).clamp(-0.5, 0.5)
                } else {
                    0.0
                };
                Peak {
                    freq_hz: (k as f64 + d) * df,
                    amplitude: (c - 0.25 * (l - r) * d).exp(),
                }
            } else {
                Peak {
                    freq_hz: k as f64 * df,
                    amplitude: c,
                }
            }
        })
        .collect();
    peaks.sort_by(|p, q| q.amplitude.total_cmp(&p.amplitude));
    let mut kept: Vec<Peak> = Vec::with_capacity(options.n_peaks);
    for q in peaks {
        if kept.len() == options.n_peaks {
            break;
        }
        if !kept.iter().any(|p| is_side_lobe(q, *p, resolution_hz)) {
            kept.push(q);
        }
    }
    kept
}

/// Highest side lobe of the Hann window relative to its main lobe (−31.5 dB)...
const HANN_SIDE_LOBE: f64 = 0.0266;
/// ...at this distance from the main lobe's centre, in resolution bins `1/T`.
const HANN_SIDE_LOBE_BINS: f64 = 2.36;
/// Margin over the side-lobe envelope (non-stationary signals, interpolation errors).
const SIDE_LOBE_MARGIN: f64 = 3.0;

/// Whether `q` may be a side lobe of the larger peak `p`: within the main lobe (2 resolution
/// bins), or below `SIDE_LOBE_MARGIN ×` Hann's side-lobe envelope, which falls off as δ⁻³
/// (18 dB per octave) with the distance δ in resolution bins.
fn is_side_lobe(q: Peak, p: Peak, resolution_hz: f64) -> bool {
    let d = (q.freq_hz - p.freq_hz).abs() / resolution_hz;
    d < 2.0
        || q.amplitude
            < SIDE_LOBE_MARGIN * HANN_SIDE_LOBE * (HANN_SIDE_LOBE_BINS / d).powi(3) * p.amplitude
}

/// The spectrum figure of `y(t)` (amplitude vs frequency up to `f_max_hz`, peaks marked) and
/// the [`Spectrum`] it shows.
pub fn spectrum(
    t: &[f64],
    y: &[f64],
    options: &SpectrumOptions,
) -> Result<(Figure, Spectrum), FigureError> {
    let s = amplitude_spectrum(t, y, options)?;
    let nyquist = *s.freq_hz.last().unwrap_or(&1.0);
    let f_max = options.f_max_hz.unwrap_or(nyquist).min(nyquist);
    let mut fig = Figure::new("Amplitude spectrum", "frequency (Hz)", "amplitude");
    fig.x_range = Some((0.0, f_max));
    fig.series.push(Series::new(
        "amplitude",
        s.freq_hz.clone(),
        s.amplitude.clone(),
        SeriesStyle::Line,
    ));
    if !s.peaks.is_empty() {
        let (px, py) = s.peaks.iter().map(|p| (p.freq_hz, p.amplitude)).unzip();
        let label = format!("{} largest peaks", s.peaks.len());
        fig.series
            .push(Series::new(label, px, py, SeriesStyle::Points).with_color([214, 39, 40]));
    }
    Ok((fig, s))
}
