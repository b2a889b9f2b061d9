//! Files of the energy balance and of the sweep's branches: `energy_mode<k>.{png,svg}` (the
//! component shares of an unstable mode), `cea_feed_in.vtu` (the friction feed-in at the gaps
//! on the friction faces) and `mode_coupling.{png,svg}`, `mode_coupling_re.{png,svg}` (the
//! mode-coupling diagram of a sweep: frequency and Re p of each branch against μ, the
//! coalescences and veerings marked).

use super::energy::{Basis, EnergyOut, RootEnergy};
use super::outputs::data_array;
use super::sweep::{event_tracks, SweepReport, TrackOut};
use crate::error::PipelineError;
use crate::figures::{grouped_bars, write_figure, Figure, Series, SeriesStyle};
use crate::model::ReducedModel;
use crate::output::RunDir;
use squeal_solver::cea::ModeEvent;
use std::fmt::Write as _;

use squeal_solver::Real;

fn drawn(dir: &RunDir, fig: &Figure, name: &str) -> Result<Option<String>, PipelineError> {
    let stem = dir.path(name);
    let files = write_figure(fig, &stem).map_err(|e| PipelineError::Output {
        path: dir.path(&format!("{name}.png")),
        message: e.to_string(),
    })?;
    Ok(files.map(|_| stem.display().to_string()))
}

fn root_of(energy: &EnergyOut, mode: usize) -> Option<&RootEnergy> {
    energy.roots.iter().find(|r| r.mode == mode)
}

/// `energy_mode<k>.{png,svg}` for each mode `k` of `modes`: the kinetic and strain share of
/// each component (and the damping work per cycle, per unit mode energy). Returns the stems
/// written.
pub fn write_energy_bars(
    dir: &RunDir,
    energy: &EnergyOut,
    modes: &[usize],
) -> Result<Vec<String>, PipelineError> {
    let mut out = Vec::new();
    for &k in modes {
        let Some(r) = root_of(energy, k) else {
            continue;
        };
        let unit = match r.basis {
            Basis::WorkPerCycle => "per cycle",
            Basis::Power => "per second",
        };
        let title = format!(
            "Mode {k}: {:.1} Hz, Re p = {:+.2} /s; friction feed-in {:+.3e} {unit}",
            r.frequency_hz, r.real_part, r.feed_in_total
        );
        let groups: Vec<(String, Vec<Real>)> = vec![
            ("kinetic energy share".into(), r.kinetic_share.clone()),
            ("strain energy share".into(), r.strain_share.clone()),
            (
                format!("damping work {unit} (/E)"),
                r.damping_per_component.clone(),
            ),
        ];
        let fig = grouped_bars(
            &title,
            &energy.components,
            "share of the mode's energy",
            &groups,
        );
        if let Some(stem) = drawn(dir, &fig, &format!("energy_mode{k}"))? {
            out.push(stem);
        }
    }
    Ok(out)
}

/// `cea_feed_in.vtu`: one vertex per gap at its pad point (on the friction faces) with the
/// point arrays `pair`, `area` and, for each mode `k` of `modes`, `mode{k}_feed_in` (the
/// gap's friction work per cycle per unit mode energy) and `mode{k}_feed_in_density` (the
/// same per unit contact area). Returns the path (None: no gap or no mode).
pub fn write_feed_in_vtu(
    dir: &RunDir,
    model: &ReducedModel,
    energy: &EnergyOut,
    modes: &[usize],
) -> Result<Option<String>, PipelineError> {
    let gaps = &model.gap_geometry.gaps;
    let roots: Vec<&RootEnergy> = modes.iter().filter_map(|&k| root_of(energy, k)).collect();
    if gaps.is_empty() || roots.is_empty() {
        return Ok(None);
    }
    let np = gaps.len();
    let f = |x: Real| format!("{x:e}");
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{np}\">"
    );
    s.push_str("      <PointData>\n");
    let mut pair = Vec::with_capacity(np);
    for (p, lab) in energy.pairs.iter().enumerate() {
        pair.extend(std::iter::repeat_n(p.to_string(), lab.n_gaps));
    }
    pair.resize(np, "0".into());
    data_array(&mut s, "pair", "Int64", 1, &pair);
    let area: Vec<String> = gaps.iter().map(|g| f(g.area)).collect();
    data_array(&mut s, "area", "Float64", 1, &area);
    for r in &roots {
        let w: Vec<String> = r.feed_in_per_gap.iter().map(|&x| f(x)).collect();
        let dens: Vec<String> = r
            .feed_in_per_gap
            .iter()
            .zip(gaps)
            .map(|(&x, g)| f(if g.area > 0.0 { x / g.area } else { 0.0 }))
            .collect();
        data_array(&mut s, &format!("mode{}_feed_in", r.mode), "Float64", 1, &w);
        data_array(
            &mut s,
            &format!("mode{}_feed_in_density", r.mode),
            "Float64",
            1,
            &dens,
        );
    }
    s.push_str("      </PointData>\n      <Points>\n");
    let pts: Vec<String> = gaps
        .iter()
        .flat_map(|g| g.coords.iter().map(|&x| f(x)).collect::<Vec<_>>())
        .collect();
    data_array(&mut s, "Points", "Float64", 3, &pts);
    s.push_str("      </Points>\n      <Cells>\n");
    let conn: Vec<String> = (0..np).map(|i| i.to_string()).collect();
    let offs: Vec<String> = (1..=np).map(|i| i.to_string()).collect();
    let types: Vec<String> = vec!["1".to_string(); np]; // VTK_VERTEX
    data_array(&mut s, "connectivity", "Int64", 1, &conn);
    data_array(&mut s, "offsets", "Int64", 1, &offs);
    data_array(&mut s, "types", "UInt8", 1, &types);
    s.push_str("      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n");
    Ok(Some(
        dir.write_bytes("cea_feed_in.vtu", s.as_bytes())?
            .display()
            .to_string(),
    ))
}

/// Re p of branch `t` at μ, linearly interpolated between its points.
fn re_at(t: &TrackOut, mu: Real) -> Option<Real> {
    let p = &t.points;
    let k = p.windows(2).position(|w| w[0].mu <= mu && mu <= w[1].mu)?;
    let (a, b) = (&p[k], &p[k + 1]);
    let s = if b.mu > a.mu {
        (mu - a.mu) / (b.mu - a.mu)
    } else {
        0.0
    };
    Some(a.real_part + s * (b.real_part - a.real_part))
}

/// `mode_coupling.{png,svg}` (frequency against μ) and `mode_coupling_re.{png,svg}` (Re p
/// against μ) of the branches of a sweep, coalescences marked in black, veerings in grey.
/// Returns the stems written.
pub fn write_mode_coupling(dir: &RunDir, rep: &SweepReport) -> Result<Vec<String>, PipelineError> {
    let branches = super::outputs::drawn_tracks(rep, rep.events.iter().flat_map(event_tracks));
    if branches.is_empty() {
        return Ok(Vec::new());
    }
    let mut by_f = Figure::new(
        "Mode-coupling diagram: frequency",
        "friction coefficient μ",
        "frequency (Hz)",
    );
    let mut by_re = Figure::new(
        "Mode-coupling diagram: real part",
        "friction coefficient μ",
        "real part (1/s)",
    );
    by_re.hlines.push(0.0);
    for t in &branches {
        let label = format!("branch {} ({:.0} Hz)", t.id, t.points[0].frequency_hz);
        let mu: Vec<Real> = t.points.iter().map(|p| p.mu).collect();
        let f: Vec<Real> = t.points.iter().map(|p| p.frequency_hz).collect();
        let re: Vec<Real> = t.points.iter().map(|p| p.real_part).collect();
        by_f.series
            .push(Series::new(label.clone(), mu.clone(), f, SeriesStyle::Line));
        by_re
            .series
            .push(Series::new(label, mu, re, SeriesStyle::Line));
    }
    for (kind, rgb) in [("coalescence", [0, 0, 0]), ("veering", [150, 150, 150])] {
        let (mut x, mut yf, mut yr) = (Vec::new(), Vec::new(), Vec::new());
        for e in &rep.events {
            let (mu, f) = match (kind, e) {
                (
                    "coalescence",
                    ModeEvent::Coalescence {
                        mu, frequency_hz, ..
                    },
                )
                | (
                    "veering",
                    ModeEvent::Veering {
                        mu, frequency_hz, ..
                    },
                ) => (*mu, *frequency_hz),
                _ => continue,
            };
            let re: Vec<Real> = event_tracks(e)
                .iter()
                .filter_map(|&id| branches.iter().find(|t| t.id == id))
                .filter_map(|t| re_at(t, mu))
                .collect();
            x.push(mu);
            yf.push(f);
            yr.push(if re.is_empty() {
                0.0
            } else {
                re.iter().sum::<Real>() / re.len() as Real
            });
        }
        if !x.is_empty() {
            by_f.series
                .push(Series::new(kind, x.clone(), yf, SeriesStyle::Points).with_color(rgb));
            by_re
                .series
                .push(Series::new(kind, x, yr, SeriesStyle::Points).with_color(rgb));
        }
    }
    let mut out = Vec::new();
    for (fig, name) in [(by_f, "mode_coupling"), (by_re, "mode_coupling_re")] {
        if let Some(stem) = drawn(dir, &fig, name)? {
            out.push(stem);
        }
    }
    Ok(out)
}
