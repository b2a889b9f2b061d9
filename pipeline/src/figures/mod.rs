//! Figures: data in, PNG + SVG files out.
//!
//! This module knows nothing about solvers: a [`Figure`] is a title, axis labels, optional log
//! axes and ranges, and a list of [`Series`] of `(x, y)` points. [`write_figure`] draws it twice,
//! to `STEM.png` (raster, via plotters' bitmap backend) and `STEM.svg` (vector).
//!
//! Builders for the pipeline's usual plots return a [`Figure`] whose fields the caller may still
//! change (title, size, ranges) before writing it:
//! - [`time_history`]: responses against time, optionally zoomed on a window;
//! - [`stability_map`]: real part against frequency of complex modes, unstable ones in red;
//! - [`root_locus`]: tracked modes as μ varies (real part vs frequency, and vs μ);
//! - [`spectrum`]: single-sided amplitude spectrum of a non-uniformly sampled signal, with peaks;
//! - [`work_precision`]: error against CPU time, log–log;
//! - [`grouped_bars`]: values per category, one bar series per group.
//!
//! # Feature `figures`
//! Drawing needs plotters, which only the `figures` feature compiles (the `squeal` command
//! turns it on; the library and the Python package build without it). Without it
//! [`write_figure`] draws nothing and returns `Ok(None)`; the figure data is still built.
//!
//! # Text
//! Text in PNGs is rasterised by `ab_glyph` from DejaVu Sans, bundled in
//! `pipeline/assets/fonts/` (licence beside it) and registered at run time as the
//! `sans-serif` family: no system font library (fontconfig, freetype) is needed. SVGs carry text
//! as `<text font-family="sans-serif">`, drawn by the viewer's own font.
//!
//! # Validation
//! Empty series, `x`/`y` of different lengths, NaN or infinite values, non-positive values on a
//! log axis and reversed ranges are errors ([`FigureError`]) that name the series and the index.
//! Automatic ranges are padded by 5 % (of the decades, on a log axis); a range of equal values is
//! widened. Data outside a given range is clipped at the plot frame.

#[cfg(feature = "figures")]
mod axis;
mod builders;
#[cfg(feature = "figures")]
mod clip;
mod error;
mod fft;
#[cfg(feature = "figures")]
mod font;
#[cfg(feature = "figures")]
mod render;
mod spectrum;

pub use builders::{grouped_bars, root_locus, stability_map, time_history, work_precision};
pub use error::FigureError;
pub use fft::fft_in_place;
#[cfg(feature = "figures")]
pub use render::write_figure;
pub use spectrum::{amplitude_spectrum, spectrum, Peak, Spectrum, SpectrumOptions};

use std::path::PathBuf;

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum SeriesStyle {
    /// A polyline through the points, in order.
    #[default]
    Line,
    /// A marker at each point.
    Points,
    /// A polyline with a marker at each point.
    LinePoints,
    /// A filled bar from 0 to y at each x; the bar series of a figure are drawn side by side
    /// (grouped), sharing 80 % of the smallest spacing of their x values.
    Bars,
}

/// One data set of a figure.
#[derive(Debug, Clone, PartialEq)]
pub struct Series {
    /// Legend text (no legend entry when empty).
    pub label: String,
    /// Abscissae.
    pub x: Vec<f64>,
    /// Ordinates, same length as `x`.
    pub y: Vec<f64>,
    /// Line, markers or both.
    pub style: SeriesStyle,
    /// RGB colour; `None` takes the next colour of the palette (by series index).
    pub color: Option<[u8; 3]>,
}

impl Series {
    /// A series coloured from the palette.
    pub fn new(label: impl Into<String>, x: Vec<f64>, y: Vec<f64>, style: SeriesStyle) -> Self {
        Self {
            label: label.into(),
            x,
            y,
            style,
            color: None,
        }
    }

    /// The same series drawn in the given RGB colour.
    pub fn with_color(mut self, rgb: [u8; 3]) -> Self {
        self.color = Some(rgb);
        self
    }
}

/// A single-panel 2-D plot.
#[derive(Debug, Clone, PartialEq)]
pub struct Figure {
    /// Caption above the plot.
    pub title: String,
    /// Text under the x axis.
    pub x_label: String,
    /// Text beside the y axis.
    pub y_label: String,
    /// Logarithmic x axis (all x must then be > 0).
    pub x_log: bool,
    /// Logarithmic y axis (all y must then be > 0).
    pub y_log: bool,
    /// Fixed x range; `None`: the data's range, padded.
    pub x_range: Option<(f64, f64)>,
    /// Fixed y range; `None`: the range of the data inside the x range, padded.
    pub y_range: Option<(f64, f64)>,
    /// The data sets, drawn in order.
    pub series: Vec<Series>,
    /// Horizontal reference lines at these y values (e.g. `Re p = 0`).
    pub hlines: Vec<f64>,
    /// Image size in pixels (width, height), for the PNG and the SVG.
    pub size: (u32, u32),
}

/// Default image size (width, height) in pixels.
pub const DEFAULT_SIZE: (u32, u32) = (960, 600);

impl Figure {
    /// An empty linear-axes figure of [`DEFAULT_SIZE`].
    pub fn new(
        title: impl Into<String>,
        x_label: impl Into<String>,
        y_label: impl Into<String>,
    ) -> Self {
        Self {
            title: title.into(),
            x_label: x_label.into(),
            y_label: y_label.into(),
            x_log: false,
            y_log: false,
            x_range: None,
            y_range: None,
            series: Vec::new(),
            hlines: Vec::new(),
            size: DEFAULT_SIZE,
        }
    }
}

/// The files [`write_figure`] wrote.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FigureFiles {
    /// `STEM.png`.
    pub png: PathBuf,
    /// `STEM.svg`.
    pub svg: PathBuf,
}

/// Without the `figures` feature nothing is drawn: `Ok(None)` (the data is still checked by
/// the builders that made `fig`).
#[cfg(not(feature = "figures"))]
pub fn write_figure(
    _fig: &Figure,
    _path_stem: &std::path::Path,
) -> Result<Option<FigureFiles>, FigureError> {
    Ok(None)
}
