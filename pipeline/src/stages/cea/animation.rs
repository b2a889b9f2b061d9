//! The unstable mode shapes for the user's eyes: a ParaView phase animation of every
//! component (`cea_modes.pvd`) and a figure of the top unstable mode on the rotor's friction
//! face (`mode_shape_rotor.{png,svg}`).
//!
//! A complex mode u e^{pt} moves, over one period, as `Re(u e^{iθ})`, θ = ωt ∈ [0, 2π), up to
//! the growth e^{σt}. `cea_modes.pvd` is a VTK collection whose time steps are the phases
//! θ_j = 2πj/frames: at each, one part per component (`cea_modes_phase/<component>_<j>.vtu`:
//! the component's mesh with, per mode, the 3-vector point array `mode{k}_{f}Hz` =
//! `Re u cos θ − Im u sin θ`). Open the `.pvd` in ParaView, Warp By Vector on a mode's array and
//! play: the animation time is the phase in radians.

use super::shapes::{array_stem, ComponentShapes};
use crate::error::PipelineError;
use crate::figures::{write_figure, Figure, Series, SeriesStyle};
use crate::model::ReducedModel;
use crate::output::RunDir;
use squeal_meshes::vtu::{self, PointArray};
use std::fmt::Write as _;

use squeal_solver::Real;

/// The collection file.
pub const PVD_NAME: &str = "cea_modes.pvd";
/// The folder of the phase frames.
pub const FRAME_DIR: &str = "cea_modes_phase";
/// Stem of the rotor-face figure.
pub const FIGURE_STEM: &str = "mode_shape_rotor";

/// Phase of frame `j` of `frames`, radians.
pub fn phase(j: usize, frames: usize) -> Real {
    2.0 * std::f64::consts::PI * j as Real / frames as Real
}

/// `Re(u e^{iθ}) = Re u cos θ − Im u sin θ` at each node, flat `[x0, y0, z0, x1, ...]`.
pub fn at_phase(re: &[[Real; 3]], im: &[[Real; 3]], theta: Real) -> Vec<Real> {
    let (c, s) = (theta.cos(), theta.sin());
    re.iter()
        .zip(im)
        .flat_map(|(a, b)| (0..3).map(move |k| a[k] * c - b[k] * s))
        .collect()
}

/// File name (relative to the run folder) of component `name`'s frame `j`.
pub fn frame_name(name: &str, j: usize) -> String {
    format!("{FRAME_DIR}/{name}_{j:03}.vtu")
}

/// Writes the phase frames of `shapes` (one per component the model can recover) and
/// `cea_modes.pvd`; returns the `.pvd` path, or nothing when there is no shape or
/// `frames` is 0.
pub fn write_phase_animation(
    dir: &RunDir,
    model: &ReducedModel,
    shapes: &[ComponentShapes],
    frames: usize,
) -> Result<Option<String>, PipelineError> {
    if frames == 0 || shapes.iter().all(|s| s.modes.is_empty()) {
        return Ok(None);
    }
    let folder = dir.path(FRAME_DIR);
    std::fs::create_dir_all(&folder).map_err(|e| PipelineError::Output {
        path: folder.clone(),
        message: e.to_string(),
    })?;
    let mut pvd = String::from(
        "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" \
         byte_order=\"LittleEndian\">\n  <Collection>\n",
    );
    for j in 0..frames {
        let theta = phase(j, frames);
        for (part, (comp, sh)) in model.recovery.iter().zip(shapes).enumerate() {
            let grid: Vec<Real> = sh.grid_of.iter().map(|&g| g as Real).collect();
            let names: Vec<String> = sh
                .modes
                .iter()
                .map(|m| array_stem(m.mode, m.frequency_hz))
                .collect();
            let values: Vec<Vec<Real>> = sh
                .modes
                .iter()
                .map(|m| at_phase(&m.re, &m.im, theta))
                .collect();
            let mut arrays = vec![PointArray::scalar("grid", &grid)];
            arrays.extend(
                names
                    .iter()
                    .zip(&values)
                    .map(|(n, v)| PointArray::vector(n, v)),
            );
            let name = frame_name(&comp.name, j);
            vtu::write_vtu(&dir.path(&name), &comp.mesh, &arrays, &[]).map_err(|source| {
                PipelineError::Mesh {
                    component: comp.name.clone(),
                    source,
                }
            })?;
            let _ = writeln!(
                pvd,
                "    <DataSet timestep=\"{theta:e}\" group=\"\" part=\"{part}\" name=\"{}\" file=\"{name}\"/>",
                comp.name
            );
        }
    }
    pvd.push_str("  </Collection>\n</VTKFile>\n");
    let path = dir.write_bytes(PVD_NAME, pvd.as_bytes())?;
    Ok(Some(path.display().to_string()))
}

/// The figure of one mode on a face set of a component: the face's element outlines (from the
/// mesh, corner to corner) and its nodes coloured by the out-of-plane displacement
/// `Re(u_n e^{iθ*})` at the phase θ* where the face's largest out-of-plane amplitude peaks
/// (blue negative, red positive, nine classes of equal width), drawn in the face's plane (the
/// two coordinates of largest spread). `None` when the component or face set is unknown or the
/// mode has no shape there.
pub fn face_figure(
    model: &ReducedModel,
    shapes: &[ComponentShapes],
    component: &str,
    face: &str,
    mode: usize,
    title: &str,
) -> Option<Figure> {
    let ci = model.recovery.iter().position(|c| c.name == component)?;
    let (comp, sh) = (&model.recovery[ci], shapes.get(ci)?);
    let m = sh.modes.get(mode)?;
    let block = comp.mesh.faces.get(face)?;
    let nodes: Vec<usize> = block.nodes();
    if nodes.is_empty() {
        return None;
    }
    let x = &comp.mesh.nodes;
    let spread = |k: usize| {
        let (lo, hi) = nodes
            .iter()
            .fold((Real::INFINITY, Real::NEG_INFINITY), |a, &i| {
                (a.0.min(x[i][k]), a.1.max(x[i][k]))
            });
        hi - lo
    };
    let mut axes = [0usize, 1, 2];
    axes.sort_by(|&a, &b| spread(b).total_cmp(&spread(a)));
    let (ax, ay, an) = (axes[0], axes[1], axes[2]);
    // The phase of the largest out-of-plane amplitude (node of largest |u_n|).
    let imax = *nodes
        .iter()
        .max_by(|&&a, &&b| {
            let h = |i: usize| m.re[i][an].hypot(m.im[i][an]);
            h(a).total_cmp(&h(b))
        })
        .expect("nodes is not empty");
    let theta = -m.im[imax][an].atan2(m.re[imax][an]);
    let w: Vec<Real> = nodes
        .iter()
        .map(|&i| m.re[i][an] * theta.cos() - m.im[i][an] * theta.sin())
        .collect();
    let wmax = w.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let axis_name = ["x", "y", "z"];
    let mut fig = Figure::new(title, axis_name[ax], axis_name[ay]);
    fig.size = (900, 900);
    for f in block.iter() {
        let corners = &f.nodes[..f.kind.n_corners()];
        let mut px: Vec<Real> = corners.iter().map(|&i| x[i][ax]).collect();
        let mut py: Vec<Real> = corners.iter().map(|&i| x[i][ay]).collect();
        px.push(px[0]);
        py.push(py[0]);
        fig.series
            .push(Series::new("", px, py, SeriesStyle::Line).with_color([200, 200, 200]));
    }
    const CLASSES: usize = 9;
    for c in 0..CLASSES {
        let lo = -wmax + 2.0 * wmax * c as Real / CLASSES as Real;
        let hi = lo + 2.0 * wmax / CLASSES as Real;
        let (mut px, mut py) = (Vec::new(), Vec::new());
        for (k, &i) in nodes.iter().enumerate() {
            let v = w[k];
            let last = c == CLASSES - 1;
            if v >= lo && (v < hi || (last && v <= hi)) {
                px.push(x[i][ax]);
                py.push(x[i][ay]);
            }
        }
        if px.is_empty() {
            continue;
        }
        // Blue (negative) through white to red (positive).
        let t = (c as Real + 0.5) / CLASSES as Real * 2.0 - 1.0;
        let fade = |t: Real| (255.0 * (1.0 - t.abs())) as u8;
        let rgb = if t < 0.0 {
            [fade(t), fade(t), 255]
        } else {
            [255, fade(t), fade(t)]
        };
        let label = format!("u_{} {:+.2}..{:+.2}", axis_name[an], lo / wmax, hi / wmax);
        fig.series
            .push(Series::new(label, px, py, SeriesStyle::Points).with_color(rgb));
    }
    Some(fig)
}

/// Draws [`face_figure`] of the first mode of `shapes` (the most unstable) to
/// `mode_shape_rotor.{png,svg}`; returns the stem written (nothing without the `figures`
/// feature or without a figure).
pub fn write_face_figure(
    dir: &RunDir,
    model: &ReducedModel,
    shapes: &[ComponentShapes],
    face: Option<(&str, &str)>,
    title: &str,
) -> Result<Option<String>, PipelineError> {
    let Some((component, set)) = face else {
        return Ok(None);
    };
    let Some(fig) = face_figure(model, shapes, component, set, 0, title) else {
        return Ok(None);
    };
    let stem = dir.path(FIGURE_STEM);
    let drawn = write_figure(&fig, &stem).map_err(|e| PipelineError::Output {
        path: dir.path(&format!("{FIGURE_STEM}.png")),
        message: e.to_string(),
    })?;
    Ok(drawn.map(|_| stem.display().to_string()))
}
