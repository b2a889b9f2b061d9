//! `write_figure`: validate a [`Figure`], fix its axes, draw it to PNG and SVG.

use super::axis::{auto_range, Axis};
use super::clip::{clip_points, clip_polyline};
use super::font::{ensure_font, FAMILY};
use super::{Figure, FigureError, FigureFiles, SeriesStyle};
use plotters::coord::Shift;
use plotters::prelude::*;
use std::path::{Path, PathBuf};

/// Colours given to series without their own (matplotlib's "tab10").
const PALETTE: [[u8; 3]; 10] = [
    [31, 119, 180],
    [255, 127, 14],
    [44, 160, 44],
    [214, 39, 40],
    [148, 103, 189],
    [140, 86, 75],
    [227, 119, 194],
    [127, 127, 127],
    [188, 189, 34],
    [23, 190, 207],
];

/// Draws `fig` to `STEM.png` and `STEM.svg` (the extension is appended to the whole stem, so
/// `out/run.v2` gives `out/run.v2.png`); creates missing parent folders.
///
/// Errors: the data problems of [`FigureError`] (checked before any file is written), or a
/// failed write.
/// Returns `Some` (always, with the feature `figures` on; see the module's documentation).
pub fn write_figure(fig: &Figure, path_stem: &Path) -> Result<Option<FigureFiles>, FigureError> {
    let (xa, ya) = axes(fig)?;
    ensure_font()?;
    let png = with_ext(path_stem, "png");
    let svg = with_ext(path_stem, "svg");
    if let Some(parent) = png.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent).map_err(|source| FigureError::Io {
            path: parent.to_path_buf(),
            source,
        })?;
    }
    let draw_err = |path: &Path| {
        let path = path.to_path_buf();
        move |message: String| FigureError::Draw { path, message }
    };
    {
        let root = BitMapBackend::new(&png, fig.size).into_drawing_area();
        draw(&root, fig, &xa, &ya).map_err(draw_err(&png))?;
        root.present().map_err(|e| draw_err(&png)(e.to_string()))?;
    }
    {
        let root = SVGBackend::new(&svg, fig.size).into_drawing_area();
        draw(&root, fig, &xa, &ya).map_err(draw_err(&svg))?;
        root.present().map_err(|e| draw_err(&svg)(e.to_string()))?;
    }
    Ok(Some(FigureFiles { png, svg }))
}

fn with_ext(stem: &Path, ext: &str) -> PathBuf {
    let mut s = stem.as_os_str().to_os_string();
    s.push(".");
    s.push(ext);
    PathBuf::from(s)
}

/// Checks the data and returns the x and y axes (given ranges, or padded data ranges).
fn axes(fig: &Figure) -> Result<(Axis, Axis), FigureError> {
    let title = || fig.title.clone();
    let (w, h) = fig.size;
    if w < 200 || h < 150 {
        return Err(FigureError::BadSize {
            title: title(),
            width: w,
            height: h,
        });
    }
    if fig.series.is_empty() {
        return Err(FigureError::NoSeries { title: title() });
    }
    for s in &fig.series {
        if s.x.len() != s.y.len() {
            return Err(FigureError::LengthMismatch {
                title: title(),
                series: s.label.clone(),
                x_len: s.x.len(),
                y_len: s.y.len(),
            });
        }
        if s.x.is_empty() {
            return Err(FigureError::EmptySeries {
                title: title(),
                series: s.label.clone(),
            });
        }
        for (axis, v, log) in [("x", &s.x, fig.x_log), ("y", &s.y, fig.y_log)] {
            for (index, &value) in v.iter().enumerate() {
                let series = s.label.clone();
                if !value.is_finite() {
                    let (title, axis) = (title(), axis);
                    return Err(FigureError::NonFinite {
                        title,
                        series,
                        axis,
                        index,
                        value,
                    });
                }
                if log && value <= 0.0 {
                    let (title, axis) = (title(), axis);
                    return Err(FigureError::NonPositiveOnLog {
                        title,
                        series,
                        axis,
                        index,
                        value,
                    });
                }
            }
        }
    }
    for &value in &fig.hlines {
        let reason = if !value.is_finite() {
            Some("is not finite")
        } else if fig.y_log && value <= 0.0 {
            Some("is not > 0 on a log axis")
        } else {
            None
        };
        if let Some(reason) = reason {
            return Err(FigureError::BadHline {
                title: title(),
                value,
                reason,
            });
        }
    }
    let n_x = (w / 110).clamp(3, 12) as usize;
    let n_y = (h / 70).clamp(3, 10) as usize;
    let (x_lo, x_hi) = match fig.x_range {
        Some(r) => checked_range(fig, "x", r, fig.x_log)?,
        None => auto_range(
            fig.series.iter().flat_map(|s| s.x.iter().copied()),
            fig.x_log,
        )
        .ok_or_else(|| FigureError::NoSeries { title: title() })?,
    };
    let (y_lo, y_hi) = match fig.y_range {
        Some(r) => checked_range(fig, "y", r, fig.y_log)?,
        None => {
            let tol = 1e-12 * (x_hi - x_lo).abs();
            let visible = fig.series.iter().flat_map(|s| {
                s.x.iter()
                    .zip(&s.y)
                    .filter(move |(x, _)| **x >= x_lo - tol && **x <= x_hi + tol)
                    .map(|(_, y)| *y)
            });
            let visible: Vec<f64> = visible.collect();
            if visible.is_empty() {
                return Err(FigureError::NoVisibleData {
                    title: title(),
                    lo: x_lo,
                    hi: x_hi,
                });
            }
            auto_range(
                visible.into_iter().chain(fig.hlines.iter().copied()),
                fig.y_log,
            )
            .ok_or_else(|| FigureError::NoSeries { title: title() })?
        }
    };
    let xa = Axis {
        lo: x_lo,
        hi: x_hi,
        log: fig.x_log,
        n_labels: n_x,
    };
    let ya = Axis {
        lo: y_lo,
        hi: y_hi,
        log: fig.y_log,
        n_labels: n_y,
    };
    Ok((xa, ya))
}

fn checked_range(
    fig: &Figure,
    axis: &'static str,
    (lo, hi): (f64, f64),
    log: bool,
) -> Result<(f64, f64), FigureError> {
    let reason = if !lo.is_finite() || !hi.is_finite() {
        Some("is not finite")
    } else if lo >= hi {
        Some("is empty or reversed (need lo < hi)")
    } else if log && lo <= 0.0 {
        Some("must be > 0 on a log axis")
    } else {
        None
    };
    match reason {
        Some(reason) => Err(FigureError::BadRange {
            title: fig.title.clone(),
            axis,
            lo,
            hi,
            reason,
        }),
        None => Ok((lo, hi)),
    }
}

/// Draws the whole figure on one backend.
fn draw<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    fig: &Figure,
    xa: &Axis,
    ya: &Axis,
) -> Result<(), String> {
    let e = |e: DrawingAreaErrorKind<DB::ErrorType>| e.to_string();
    root.fill(&WHITE).map_err(e)?;
    let (w, h) = fig.size;
    let base = (f64::from(w.min(h)) / 38.0).clamp(11.0, 30.0);
    let y_tick_chars = ya
        .major_ticks(ya.n_labels)
        .iter()
        .map(|v| ya.format_tick(*v).chars().count())
        .max()
        .unwrap_or(4);
    let y_area = (y_tick_chars as f64 * base * 0.62 + base * 2.6) as u32;
    let mut chart = ChartBuilder::on(root)
        .caption(&fig.title, (FAMILY, base * 1.35))
        .margin((base * 0.8) as u32)
        .margin_right((base * 2.2) as u32)
        .x_label_area_size((base * 3.0) as u32)
        .y_label_area_size(y_area)
        .build_cartesian_2d(*xa, *ya)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_labels(xa.n_labels)
        .y_labels(ya.n_labels)
        .x_desc(fig.x_label.as_str())
        .y_desc(fig.y_label.as_str())
        .label_style((FAMILY, base))
        .axis_desc_style((FAMILY, base * 1.1))
        .light_line_style(RGBColor(238, 238, 238))
        .bold_line_style(RGBColor(205, 205, 205))
        .draw()
        .map_err(e)?;
    for &y in &fig.hlines {
        if y >= ya.lo && y <= ya.hi {
            let line = [(xa.lo, y), (xa.hi, y)];
            chart
                .draw_series(LineSeries::new(line, BLACK.stroke_width(1)))
                .map_err(e)?;
        }
    }
    let line_w = (base / 8.0).round().max(1.0) as u32;
    let radius = (base / 4.5).round().max(2.0) as i32;
    let mut any_label = false;
    let n_bars = fig
        .series
        .iter()
        .filter(|s| s.style == SeriesStyle::Bars)
        .count();
    let mut bar_index = 0usize;
    for (i, s) in fig.series.iter().enumerate() {
        let [r, g, b] = s.color.unwrap_or(PALETTE[i % PALETTE.len()]);
        let color = RGBColor(r, g, b);
        let lines = matches!(s.style, SeriesStyle::Line | SeriesStyle::LinePoints);
        let points = matches!(
            s.style,
            SeriesStyle::Points | SeriesStyle::LinePoints | SeriesStyle::Bars
        );
        if s.style == SeriesStyle::Bars {
            let bars = bar_rects(&s.x, &s.y, bar_index, n_bars, xa, ya);
            bar_index += 1;
            let rects = bars.into_iter().map(|r| Rectangle::new(r, color.filled()));
            chart.draw_series(rects).map_err(e)?;
        }
        if lines {
            for piece in clip_polyline(&s.x, &s.y, xa, ya) {
                let series = LineSeries::new(piece, color.stroke_width(line_w));
                chart.draw_series(series).map_err(e)?;
            }
        }
        if points && s.style != SeriesStyle::Bars {
            let pts = clip_points(&s.x, &s.y, xa, ya);
            let marks = pts
                .into_iter()
                .map(|p| Circle::new(p, radius, color.filled()));
            chart.draw_series(marks).map_err(e)?;
        }
        if !s.label.is_empty() {
            any_label = true;
            // An empty series carries the legend entry, whether or not any data is visible.
            let legend = chart.draw_series(std::iter::empty::<Circle<(f64, f64), i32>>());
            let half = (base * 0.8) as i32;
            legend
                .map_err(e)?
                .label(s.label.as_str())
                .legend(move |(x, y)| {
                    let style = color.stroke_width(line_w);
                    let end = if lines { x + 2 * half } else { x };
                    let line = PathElement::new(vec![(x, y), (end, y)], style);
                    let mark = Circle::new(
                        (x + half, y),
                        if points { radius } else { 0 },
                        color.filled(),
                    );
                    EmptyElement::at((0, 0)) + line + mark
                });
        }
    }
    if any_label {
        chart
            .configure_series_labels()
            .position(legend_corner(fig, xa, ya))
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font((FAMILY, base))
            .draw()
            .map_err(e)?;
    }
    Ok(())
}

/// The rectangles of bar series `j` of `nb` (grouped side by side), clamped to the axes.
fn bar_rects(
    x: &[f64],
    y: &[f64],
    j: usize,
    nb: usize,
    xa: &Axis,
    ya: &Axis,
) -> Vec<[(f64, f64); 2]> {
    let mut xs: Vec<f64> = x.to_vec();
    xs.sort_by(f64::total_cmp);
    let spacing = xs
        .windows(2)
        .map(|w| w[1] - w[0])
        .filter(|d| *d > 0.0)
        .fold(f64::INFINITY, f64::min);
    let spacing = if spacing.is_finite() { spacing } else { 1.0 };
    let w = 0.8 * spacing / nb.max(1) as f64;
    let off = (j as f64 - 0.5 * (nb.max(1) as f64 - 1.0)) * w;
    let cx = |v: f64| v.clamp(xa.lo, xa.hi);
    let cy = |v: f64| v.clamp(ya.lo, ya.hi);
    let base = if ya.log { ya.lo } else { 0.0 };
    x.iter()
        .zip(y)
        .map(|(&xi, &yi)| {
            let c = xi + off;
            [(cx(c - 0.5 * w), cy(base)), (cx(c + 0.5 * w), cy(yi))]
        })
        .collect()
}

/// The plot corner whose legend-sized box holds the fewest data points (upper right first).
fn legend_corner(fig: &Figure, xa: &Axis, ya: &Axis) -> SeriesLabelPosition {
    let n_labels = fig.series.iter().filter(|s| !s.label.is_empty()).count() as f64;
    let (w, h) = (0.35, (0.07 * n_labels + 0.05).min(0.6));
    let corners = [
        (
            SeriesLabelPosition::UpperRight,
            (1.0 - w, 1.0),
            (1.0 - h, 1.0),
        ),
        (SeriesLabelPosition::UpperLeft, (0.0, w), (1.0 - h, 1.0)),
        (SeriesLabelPosition::LowerRight, (1.0 - w, 1.0), (0.0, h)),
        (SeriesLabelPosition::LowerLeft, (0.0, w), (0.0, h)),
    ];
    let count = |(u0, u1): (f64, f64), (v0, v1): (f64, f64)| {
        let inside = |(x, y): (&f64, &f64)| {
            let (u, v) = (xa.frac(*x), ya.frac(*y));
            u >= u0 && u <= u1 && v >= v0 && v <= v1
        };
        fig.series
            .iter()
            .map(|s| s.x.iter().zip(&s.y).filter(|p| inside(*p)).count())
            .sum::<usize>()
    };
    let mut best = (usize::MAX, SeriesLabelPosition::UpperRight);
    for (pos, xr, yr) in corners {
        let c = count(xr, yr);
        if c < best.0 {
            best = (c, pos);
        }
    }
    best.1
}
