//! Files of `squeal sweep`: `sweep.md` (the table), `sweep_indicators.{png,svg}` (largest CEA
//! real part and transient growth rate against the parameter) and `sweep_frequencies.{png,svg}`
//! (frequencies of the unstable CEA modes and the transient's dominant frequency).

use super::{SweepPoint, SweepReport};
use crate::error::PipelineError;
use crate::figures::{write_figure, Figure, Series, SeriesStyle};
use crate::output::RunDir;
use std::fmt::Write as _;

use squeal_solver::Real;

const RED: [u8; 3] = [214, 39, 40];
const BLUE: [u8; 3] = [31, 119, 180];

fn opt(x: Option<Real>, prec: usize) -> String {
    x.map_or("–".into(), |v| format!("{v:.prec$}"))
}

/// A rate: fixed with 3 decimals in [1e-3, 1e6), else in exponent form.
fn opt_e(x: Option<Real>) -> String {
    x.map_or("–".into(), |v| {
        if v == 0.0 || (1e-3..1e6).contains(&v.abs()) {
            format!("{v:.3}")
        } else {
            format!("{v:.3e}")
        }
    })
}

fn cache_text(p: &SweepPoint) -> &'static str {
    match (p.cache_hit, &p.cache_note) {
        (Some(true), _) => "hit",
        (Some(false), Some(_)) => "rebuilt",
        (Some(false), None) => "miss",
        (None, _) => "–",
    }
}

/// One line per value for the terminal.
pub fn progress_line(param: &str, p: &SweepPoint) -> String {
    let mut s = format!(
        "{param} = {}: model {} {:.2} s, analysis {:.2} s",
        p.label,
        cache_text(p),
        p.build_s,
        p.analysis_s
    );
    if let Some(c) = &p.cea {
        let _ = write!(
            s,
            "; CEA {} unstable, max Re p {} 1/s at {} Hz",
            c.n_unstable,
            opt_e(c.max_real_part),
            opt(c.max_real_part_frequency_hz, 1)
        );
    }
    if let Some(t) = &p.transient {
        let _ = write!(
            s,
            "; transient {}, growth {} 1/s, {} Hz",
            t.verdict.label(),
            opt_e(t.growth_rate_per_s),
            opt(t.dominant_frequency_hz, 1)
        );
    }
    if let Some(e) = &p.error {
        let _ = write!(s, "; error: {e}");
    }
    s
}

/// The table of `sweep.md`.
pub fn markdown(rep: &SweepReport) -> String {
    let with_cea = rep.points.iter().any(|p| p.cea.is_some()) || rep.analysis.cea();
    let with_tr =
        rep.points.iter().any(|p| p.transient.is_some()) || rep.analysis != super::Analysis::Cea;
    let mut s =
        format!(
        "# Sweep of `{}` ({})\n\nScene `{}`, {} values: models built {}, read from the cache {} \
         (`{}`).\n\n",
        rep.param,
        serde_json::to_string(&rep.analysis).unwrap_or_default().trim_matches('"'),
        rep.scene,
        rep.points.len(),
        rep.n_built,
        rep.n_cached,
        rep.cache_dir
    );
    let mut head = vec![rep.param.as_str(), "model", "build s", "analysis s"];
    if with_cea {
        head.extend([
            "unstable",
            "max Re p (1/s)",
            "at (Hz)",
            "min ζ",
            "unstable modes (Hz)",
        ]);
    }
    if with_tr {
        head.extend(["verdict", "growth (1/s)", "f dom (Hz)", "steps", "cpu s"]);
    }
    head.push("note");
    let _ = writeln!(s, "| {} |", head.join(" | "));
    let _ = writeln!(s, "|{}", "---|".repeat(head.len()));
    for p in &rep.points {
        let mut row = vec![
            format!("`{}`", p.label),
            cache_text(p).to_string(),
            format!("{:.2}", p.build_s),
            format!("{:.2}", p.analysis_s),
        ];
        if with_cea {
            match &p.cea {
                Some(c) => {
                    let freqs: Vec<String> = c
                        .unstable_modes
                        .iter()
                        .map(|m| format!("{:.0}", m.frequency_hz))
                        .collect();
                    row.extend([
                        c.n_unstable.to_string(),
                        opt_e(c.max_real_part),
                        opt(c.max_real_part_frequency_hz, 1),
                        opt(c.min_damping_ratio, 5),
                        if freqs.is_empty() {
                            "–".into()
                        } else {
                            freqs.join(", ")
                        },
                    ]);
                }
                None => row.extend(std::iter::repeat_n("–".to_string(), 5)),
            }
        }
        if with_tr {
            match &p.transient {
                Some(t) => row.extend([
                    t.verdict.label().to_string(),
                    opt_e(t.growth_rate_per_s),
                    opt(t.dominant_frequency_hz, 1),
                    t.steps.to_string(),
                    format!("{:.2}", t.cpu_s),
                ]),
                None => row.extend(std::iter::repeat_n("–".to_string(), 5)),
            }
        }
        let mut note = Vec::new();
        if let Some(t) = p.transient.as_ref().filter(|t| !t.status.is_success()) {
            note.push(format!(
                "transient: {}",
                crate::verdict::guard::status_text(&t.status)
            ));
        }
        if let Some(n) = &p.cache_note {
            note.push(n.clone());
        }
        if let Some(e) = &p.error {
            note.push(e.clone());
        }
        row.push(note.join("; ").replace('|', "/").replace('\n', " "));
        let _ = writeln!(s, "| {} |", row.join(" | "));
    }
    s.push_str(
        "\nmodel: `miss` built and stored, `hit` read from the cache, `rebuilt` an unusable \
         entry replaced. CEA columns count modes up to the scene's `cea.max_frequency_hz`; \
         ζ = −2 Re p/|Im p| (negative: unstable).\n",
    );
    s
}

/// The abscissa of each point: the value when every value is a number, else the index.
fn abscissae(rep: &SweepReport) -> (Vec<Real>, String) {
    let nums: Option<Vec<Real>> = rep.points.iter().map(|p| p.value.as_f64()).collect();
    match nums {
        Some(x) => (x, rep.param.clone()),
        None => (
            rep.points.iter().map(|p| p.index as Real).collect(),
            format!("{} (value index, see sweep.md)", rep.param),
        ),
    }
}

fn write_fig(dir: &RunDir, fig: &Figure, stem: &str) -> Result<Vec<String>, PipelineError> {
    if fig.series.is_empty() {
        return Ok(Vec::new());
    }
    let files = write_figure(fig, &dir.path(stem)).map_err(|e| PipelineError::Output {
        path: dir.path(&format!("{stem}.png")),
        message: e.to_string(),
    })?;
    Ok(files
        .map(|f| vec![f.png.display().to_string(), f.svg.display().to_string()])
        .unwrap_or_default())
}

/// Writes `sweep.md` and the figures; returns the paths written.
pub fn write(dir: &RunDir, rep: &SweepReport) -> Result<Vec<String>, PipelineError> {
    let mut files = vec![dir
        .write_bytes("sweep.md", markdown(rep).as_bytes())?
        .display()
        .to_string()];
    let (x, x_label) = abscissae(rep);
    let pick = |f: &dyn Fn(&SweepPoint) -> Option<Real>| -> (Vec<Real>, Vec<Real>) {
        rep.points
            .iter()
            .zip(&x)
            .filter_map(|(p, &xi)| f(p).filter(|v| v.is_finite()).map(|v| (xi, v)))
            .unzip()
    };

    let mut rates = Figure::new(
        format!("Squeal indicators against {}", rep.param),
        x_label.clone(),
        "growth rate (1/s)",
    );
    rates.hlines.push(0.0);
    let (cx, cy) = pick(&|p| p.cea.as_ref().and_then(|c| c.max_real_part));
    if !cx.is_empty() {
        rates.series.push(
            Series::new("CEA: largest Re p", cx, cy, SeriesStyle::LinePoints).with_color(RED),
        );
    }
    let (tx, ty) = pick(&|p| p.transient.as_ref().and_then(|t| t.growth_rate_per_s));
    if !tx.is_empty() {
        rates.series.push(
            Series::new("transient: growth rate", tx, ty, SeriesStyle::LinePoints).with_color(BLUE),
        );
    }
    files.extend(write_fig(dir, &rates, "sweep_indicators")?);

    let mut freqs = Figure::new(
        format!("Unstable frequencies against {}", rep.param),
        x_label,
        "frequency (Hz)",
    );
    let (ux, uy): (Vec<Real>, Vec<Real>) = rep
        .points
        .iter()
        .zip(&x)
        .flat_map(|(p, &xi)| {
            p.cea
                .iter()
                .flat_map(|c| c.unstable_modes.iter())
                .map(move |m| (xi, m.frequency_hz))
        })
        .unzip();
    if !ux.is_empty() {
        freqs
            .series
            .push(Series::new("CEA: unstable modes", ux, uy, SeriesStyle::Points).with_color(RED));
    }
    let (dx, dy) = pick(&|p| p.transient.as_ref().and_then(|t| t.dominant_frequency_hz));
    if !dx.is_empty() {
        freqs.series.push(
            Series::new("transient: dominant frequency", dx, dy, SeriesStyle::Points)
                .with_color(BLUE),
        );
    }
    files.extend(write_fig(dir, &freqs, "sweep_frequencies")?);
    Ok(files)
}
