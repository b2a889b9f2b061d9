//! Errors of the figures module: bad data (named by series and index) or a failed write.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error("figure `{title}` has no series")]
    NoSeries { title: String },
    #[error("figure `{title}`, series `{series}`: no points")]
    EmptySeries { title: String, series: String },
    #[error("figure `{title}`, series `{series}`: x has {x_len} values but y has {y_len}")]
    LengthMismatch {
        title: String,
        series: String,
        x_len: usize,
        y_len: usize,
    },
    #[error("figure `{title}`, series `{series}`: {axis}[{index}] = {value} is not finite")]
    NonFinite {
        title: String,
        series: String,
        axis: &'static str,
        index: usize,
        value: f64,
    },
    #[error(
        "figure `{title}`, series `{series}`: {axis}[{index}] = {value} is not > 0 on a log axis"
    )]
    NonPositiveOnLog {
        title: String,
        series: String,
        axis: &'static str,
        index: usize,
        value: f64,
    },
    #[error("figure `{title}`: {axis} range ({lo}, {hi}) {reason}")]
    BadRange {
        title: String,
        axis: &'static str,
        lo: f64,
        hi: f64,
        reason: &'static str,
    },
    #[error("figure `{title}`: hline y = {value} {reason}")]
    BadHline {
        title: String,
        value: f64,
        reason: &'static str,
    },
    #[error("figure `{title}`: no data point lies inside the x range ({lo}, {hi})")]
    NoVisibleData { title: String, lo: f64, hi: f64 },
    #[error("figure `{title}`: image size {width}x{height} is too small (at least 200x150)")]
    BadSize {
        title: String,
        width: u32,
        height: u32,
    },
    #[error("spectrum: {0}")]
    Spectrum(String),
    #[error("{path}: {source}")]
    Io {
        path: PathBuf,
        #[source]
        source: std::io::Error,
    },
    #[error("drawing {path}: {message}")]
    Draw { path: PathBuf, message: String },
    #[error("registering the bundled font: {0}")]
    Font(String),
}
