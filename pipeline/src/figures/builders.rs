//! Ready-made figures for the pipeline's outputs. Each returns a [`Figure`] the caller may still
//! adjust (title, labels, size, ranges) before [`super::write_figure`]; bad data is reported
//! when the figure is written.

use super::{Figure, Series, SeriesStyle};

/// Red used for unstable modes.
const UNSTABLE_RGB: [u8; 3] = [214, 39, 40];
/// Blue used for stable modes.
const STABLE_RGB: [u8; 3] = [31, 119, 180];

/// Responses `(label, y)` against time `t`, one line each; `window = Some((t0, t1))` zooms on
/// that interval (the y range then fits the data inside it), e.g. the last part of a transient.
pub fn time_history<L: AsRef<str>, Y: AsRef<[f64]>>(
    title: &str,
    t: &[f64],
    curves: &[(L, Y)],
    window: Option<(f64, f64)>,
) -> Figure {
    let mut fig = Figure::new(title, "time (s)", "response");
    fig.x_range = window;
    for (label, y) in curves {
        let s = Series::new(
            label.as_ref(),
            t.to_vec(),
            y.as_ref().to_vec(),
            SeriesStyle::Line,
        );
        fig.series.push(s);
    }
    fig
}

/// Complex modes `(frequency_hz, real_part, unstable)`: real part against frequency, unstable
/// modes in red, stable ones in blue, a line at `Re = 0`.
pub fn stability_map(modes: &[(f64, f64, bool)]) -> Figure {
    let mut fig = Figure::new("Stability map", "frequency (Hz)", "real part (1/s)");
    fig.hlines.push(0.0);
    for (unstable, label, rgb) in [
        (false, "stable", STABLE_RGB),
        (true, "unstable", UNSTABLE_RGB),
    ] {
        let (x, y): (Vec<f64>, Vec<f64>) = modes
            .iter()
            .filter(|m| m.2 == unstable)
            .map(|m| (m.0, m.1))
            .unzip();
        if !x.is_empty() {
            fig.series
                .push(Series::new(label, x, y, SeriesStyle::Points).with_color(rgb));
        }
    }
    fig
}

/// Tracked modes `(label, [(mu, frequency_hz, real_part)])` as the friction coefficient μ varies:
/// returns two figures, (real part vs frequency, real part vs μ), each with a line at `Re = 0`.
pub fn root_locus<L: AsRef<str>, P: AsRef<[(f64, f64, f64)]>>(
    tracks: &[(L, P)],
) -> (Figure, Figure) {
    let mut by_freq = Figure::new("Root locus", "frequency (Hz)", "real part (1/s)");
    let mut by_mu = Figure::new(
        "Root locus against μ",
        "friction coefficient μ",
        "real part (1/s)",
    );
    for (label, points) in tracks {
        let p = points.as_ref();
        let mu: Vec<f64> = p.iter().map(|q| q.0).collect();
        let f: Vec<f64> = p.iter().map(|q| q.1).collect();
        let re: Vec<f64> = p.iter().map(|q| q.2).collect();
        by_freq.series.push(Series::new(
            label.as_ref(),
            f,
            re.clone(),
            SeriesStyle::LinePoints,
        ));
        by_mu
            .series
            .push(Series::new(label.as_ref(), mu, re, SeriesStyle::LinePoints));
    }
    by_freq.hlines.push(0.0);
    by_mu.hlines.push(0.0);
    (by_freq, by_mu)
}

/// Work–precision diagram: runs `(label, [(cpu_s, error)])`, log–log.
pub fn work_precision<L: AsRef<str>, P: AsRef<[(f64, f64)]>>(runs: &[(L, P)]) -> Figure {
    let mut fig = Figure::new("Work–precision", "CPU time (s)", "error");
    fig.x_log = true;
    fig.y_log = true;
    for (label, points) in runs {
        let (x, y) = points.as_ref().iter().copied().unzip();
        fig.series
            .push(Series::new(label.as_ref(), x, y, SeriesStyle::LinePoints));
    }
    fig
}

/// Grouped bar chart: `categories` along x (at 0, 1, …; named in the x label), one bar series
/// per `(label, values)` group (a value per category), a line at 0.
pub fn grouped_bars<L: AsRef<str>, V: AsRef<[f64]>>(
    title: &str,
    categories: &[String],
    y_label: &str,
    groups: &[(L, V)],
) -> Figure {
    let names: Vec<String> = categories
        .iter()
        .enumerate()
        .map(|(i, c)| format!("{i} = {c}"))
        .collect();
    let mut fig = Figure::new(title, names.join(", "), y_label);
    fig.hlines.push(0.0);
    let x: Vec<f64> = (0..categories.len()).map(|i| i as f64).collect();
    for (label, values) in groups {
        fig.series.push(Series::new(
            label.as_ref(),
            x.clone(),
            values.as_ref().to_vec(),
            SeriesStyle::Bars,
        ));
    }
    let n = categories.len().max(1) as f64;
    fig.x_range = Some((-0.6, n - 0.4));
    fig
}
