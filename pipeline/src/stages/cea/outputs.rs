//! Files of `squeal cea`: mode shapes as VTU, tangent matrices as OP4 and punch, figures.

use super::sweep::{SweepReport, TrackOut};
use crate::error::PipelineError;
use crate::figures::{root_locus, stability_map, write_figure};
use crate::model::ReducedModel;
use crate::output::RunDir;
use crate::problem::system::Problem;
use crate::problem::tangents::Linearisation;
use faer::Mat;
use squeal_reduction::matrix::{MatrixForm, NamedMatrix};
use squeal_reduction::punch::{self, DmigMatrix, PunchWriteOptions};
use squeal_reduction::superelement::DofKind;
use squeal_reduction::{op4, op4::Op4WriteOptions};
use squeal_solver::cea::Mode;
use std::collections::BTreeMap;
use std::fmt::Write as _;

use squeal_solver::Real;

fn out_err(dir: &RunDir, name: &str) -> impl Fn(String) -> PipelineError {
    let path = dir.path(name);
    move |message| PipelineError::Output {
        path: path.clone(),
        message,
    }
}

/// Grid points that carry reduced DOFs: (grid id, coordinates, reduced index per component).
type GridDofs = Vec<(u64, [Real; 3], [Option<usize>; 3])>;

/// The grid DOFs of the reduced model with their coordinates: the merged grid table of a
/// meshed model; for a stored one the gap points, and a tied gap's rotor face nodes from the
/// gap table (`gaps.json` stores their coordinates; other grids have no known position).
fn grid_dofs(model: &ReducedModel) -> GridDofs {
    let mut coords: BTreeMap<u64, [Real; 3]> = BTreeMap::new();
    for g in &model.grids {
        coords.insert(g.grid, g.coords);
    }
    // A tied gap's rotor nodes where the gap table stores their coordinates (surface and
    // mortar pairing), before the fallback that puts a node at its gap's point.
    for g in &model.gap_geometry.gaps {
        if let Some(t) = &g.tie {
            for (&n, &x) in t.nodes.iter().zip(&t.coords) {
                if x.iter().all(|v| v.is_finite()) {
                    coords.entry(n).or_insert(x);
                }
            }
        }
    }
    for g in &model.gap_geometry.gaps {
        coords.entry(g.pad_node).or_insert(g.coords);
        coords.entry(g.rotor_node).or_insert(g.coords);
    }
    let mut dofs: BTreeMap<u64, [Option<usize>; 3]> = BTreeMap::new();
    for (i, d) in model.dofs.dofs.iter().enumerate() {
        if let DofKind::Grid { grid, comp } = d.kind {
            if (1..=3).contains(&comp) {
                dofs.entry(grid).or_insert([None; 3])[comp as usize - 1] = Some(i);
            }
        }
    }
    dofs.into_iter()
        .filter_map(|(g, idx)| coords.get(&g).map(|&x| (g, x, idx)))
        .collect()
}

pub(super) fn data_array(s: &mut String, name: &str, ty: &str, ncomp: usize, values: &[String]) {
    let _ = writeln!(
        s,
        "        <DataArray type=\"{ty}\" Name=\"{name}\" NumberOfComponents=\"{ncomp}\" format=\"ascii\">"
    );
    for chunk in values.chunks(9) {
        let _ = writeln!(s, "          {}", chunk.join(" "));
    }
    s.push_str("        </DataArray>\n");
}

/// Writes `cea_modes.vtu`: the grid points of the reduced model as vertex cells, and for each
/// mode `k` in `modes` the point arrays `mode{k}_re` and `mode{k}_im` (3 components each: the
/// real and imaginary parts of the shape at the grid's x, y, z DOFs) and `mode{k}_abs`.
/// Animate in ParaView with `cos(ωt)·re − sin(ωt)·im`.
///
/// Returns the number of points written (0: nothing written, the model has no positioned grid).
pub fn write_mode_shapes(
    dir: &RunDir,
    model: &ReducedModel,
    modes: &[(usize, &Mode)],
) -> Result<usize, PipelineError> {
    let grids = grid_dofs(model);
    if grids.is_empty() || modes.is_empty() {
        return Ok(0);
    }
    let np = grids.len();
    // Shortest round-trip representation: the values read back are the computed ones.
    let f = |x: Real| format!("{x:e}");
    let mut s = String::new();
    s.push_str("<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\">\n  <UnstructuredGrid>\n");
    let _ = writeln!(
        s,
        "    <Piece NumberOfPoints=\"{np}\" NumberOfCells=\"{np}\">"
    );
    s.push_str("      <PointData>\n");
    let ids: Vec<String> = grids.iter().map(|g| g.0.to_string()).collect();
    data_array(&mut s, "grid", "Int64", 1, &ids);
    for (k, m) in modes {
        let mut re = Vec::with_capacity(3 * np);
        let mut im = Vec::with_capacity(3 * np);
        let mut ab = Vec::with_capacity(np);
        for (_, _, idx) in &grids {
            let mut a2 = 0.0;
            for d in idx {
                let z = d.and_then(|i| m.shape.get(i)).copied().unwrap_or_default();
                re.push(f(z.re));
                im.push(f(z.im));
                a2 += z.norm_sqr();
            }
            ab.push(f(a2.sqrt()));
        }
        data_array(&mut s, &format!("mode{k}_re"), "Float64", 3, &re);
        data_array(&mut s, &format!("mode{k}_im"), "Float64", 3, &im);
        data_array(&mut s, &format!("mode{k}_abs"), "Float64", 1, &ab);
    }
    s.push_str("      </PointData>\n      <Points>\n");
    let pts: Vec<String> = grids
        .iter()
        .flat_map(|g| g.1.iter().map(|&x| f(x)).collect::<Vec<_>>())
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
    dir.write_bytes("cea_modes.vtu", s.as_bytes())?;
    Ok(np)
}

/// A punch DOF (grid or scalar point, component).
type PunchDof = (u64, u8);

/// A labelled root-locus track: (label, [(μ, frequency, Re p)]).
type LocusTrack = (String, Vec<(f64, f64, f64)>);

/// Punch DOFs of the reduced DOFs (grids as (grid, comp), modal coordinates as scalar points
/// `base + 1 + k`) and of the gaps (scalar points `2·base + 1 + g`), `base` a power of 10 above
/// every grid id (the modal numbering of `squeal reduce`'s `reduced.pch`).
fn punch_dofs(model: &ReducedModel) -> (Vec<PunchDof>, Vec<PunchDof>) {
    let max_grid = model
        .dofs
        .dofs
        .iter()
        .filter_map(|d| match d.kind {
            DofKind::Grid { grid, .. } => Some(grid),
            DofKind::Modal { .. } | DofKind::Interface { .. } => None,
        })
        .max()
        .unwrap_or(0);
    let mut base = 10u64;
    while base <= max_grid {
        base *= 10;
    }
    let mut k = 0;
    let rows = model
        .dofs
        .dofs
        .iter()
        .map(|d| match d.kind {
            DofKind::Grid { grid, comp } => (grid, comp),
            DofKind::Modal { .. } | DofKind::Interface { .. } => {
                k += 1;
                (base + k, 0)
            }
        })
        .collect();
    let gaps = (0..model.gap_geometry.len())
        .map(|g| (2 * base + 1 + g as u64, 0))
        .collect();
    (rows, gaps)
}

/// Writes `tangents.op4` and `tangents.pch`: the eigenproblem's matrices at the state —
/// `MR`, `BR`, `KR` (n×n), `GC` = G (ng×n), `DFDL` = D = ∂F_f/∂λ̇ (n×ng), `CF` = C_f (n×n),
/// `HT` = Gᵀ − D (n×ng: the paper's Hᵀ with our sign convention). In the punch file the rows and
/// columns of n-sized partitions are the reduced DOFs, those of ng-sized ones scalar points
/// numbered `2·base + 1 + gap` (see [`punch_dofs`]). Returns the two paths.
pub fn export_tangents(
    dir: &RunDir,
    model: &ReducedModel,
    problem: &Problem,
    lin: &Linearisation,
) -> Result<[String; 2], PipelineError> {
    let (n, ng) = (problem.m.nrows(), problem.g.nrows());
    let ht = Mat::from_fn(n, ng, |i, k| problem.g[(k, i)] - lin.d[(i, k)]);
    let rect =
        |name: &str, a: Mat<Real>| NamedMatrix::real(name, a).with_form(MatrixForm::Rectangular);
    let mats = [
        NamedMatrix::real("MR", problem.m.clone()),
        NamedMatrix::real("BR", problem.b.clone()),
        NamedMatrix::real("KR", problem.k.clone()),
        rect("GC", problem.g.clone()),
        rect("DFDL", lin.d.clone()),
        NamedMatrix::real("CF", lin.c_f.clone()),
        rect("HT", ht),
    ];
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    let bytes = op4::write_bytes(&refs, &Op4WriteOptions::default()).map_err(|source| {
        PipelineError::Reduction {
            what: "writing tangents.op4".into(),
            source,
        }
    })?;
    let p1 = dir.write_bytes("tangents.op4", &bytes)?;
    let (rows, gap_dofs) = punch_dofs(model);
    let dmig: Vec<DmigMatrix> = mats
        .iter()
        .filter(|m| m.nrows > 0 && m.ncols > 0)
        .map(|m| DmigMatrix {
            matrix: m.clone(),
            rows: if m.nrows == n {
                rows.clone()
            } else {
                gap_dofs.clone()
            },
            cols: if m.ncols == n {
                rows.clone()
            } else {
                gap_dofs.clone()
            },
        })
        .collect();
    let drefs: Vec<&DmigMatrix> = dmig.iter().collect();
    let text = punch::write_string(&drefs, &PunchWriteOptions::default()).map_err(|source| {
        PipelineError::Reduction {
            what: "writing tangents.pch".into(),
            source,
        }
    })?;
    let p2 = dir.write_bytes("tangents.pch", text.as_bytes())?;
    Ok([p1.display().to_string(), p2.display().to_string()])
}

/// `stability_map.{png,svg}` of the reported modes (real roots left out), with the validity
/// band's top as a grey line. Returns the stem.
pub fn write_stability_map(
    dir: &RunDir,
    modes: &[&Mode],
    band_hz: Option<f64>,
    title: &str,
) -> Result<Option<String>, PipelineError> {
    let pts: Vec<(f64, f64, bool)> = modes
        .iter()
        .filter(|m| m.eigenvalue.im != 0.0)
        .map(|m| (m.frequency_hz, m.real_part, m.unstable))
        .collect();
    if pts.is_empty() {
        return Ok(None);
    }
    let mut fig = stability_map(&pts);
    fig.title = title.to_string();
    if let Some(b) = band_hz.filter(|b| b.is_finite()) {
        // The band's top as a vertical line over the data's range of Re p.
        let (lo, hi) = pts
            .iter()
            .fold((0.0f64, 0.0f64), |(l, h), p| (l.min(p.1), h.max(p.1)));
        fig.series.push(
            crate::figures::Series::new(
                format!("band top {b:.0} Hz"),
                vec![b, b],
                vec![lo, hi.max(lo + 1.0)],
                crate::figures::SeriesStyle::Line,
            )
            .with_color([127, 127, 127]),
        );
    }
    let stem = dir.path("stability_map");
    let drawn =
        write_figure(&fig, &stem).map_err(|e| out_err(dir, "stability_map.png")(e.to_string()))?;
    Ok(drawn.map(|_| stem.display().to_string()))
}

/// The tracks a sweep figure draws: `first` (e.g. the tracks of the sweep's events), then those
/// in a coupling (a critical μ and its partner) and those unstable from the start, each once,
/// at most 16; with none, the 8 tracks of largest Re p. Tracks without points are left out.
pub(super) fn drawn_tracks(
    rep: &SweepReport,
    first: impl IntoIterator<Item = usize>,
) -> Vec<&TrackOut> {
    let mut ids: Vec<usize> = first.into_iter().collect();
    for c in &rep.couplings {
        ids.push(c.track);
        ids.extend(c.partner);
    }
    ids.extend(
        rep.tracks
            .iter()
            .filter(|t| t.unstable_at_start)
            .map(|t| t.id),
    );
    let mut seen = std::collections::HashSet::new();
    ids.retain(|i| seen.insert(*i));
    if ids.is_empty() {
        let mut by_re: Vec<(usize, f64)> = rep
            .tracks
            .iter()
            .map(|t| {
                let re = t
                    .points
                    .iter()
                    .map(|p| p.real_part)
                    .fold(f64::MIN, f64::max);
                (t.id, re)
            })
            .collect();
        by_re.sort_by(|a, b| b.1.total_cmp(&a.1));
        ids = by_re.iter().take(8).map(|x| x.0).collect();
    }
    ids.truncate(16);
    ids.iter()
        .filter_map(|&id| rep.tracks.iter().find(|t| t.id == id))
        .filter(|t| !t.points.is_empty())
        .collect()
}

/// `root_locus.{png,svg}` (Re p vs frequency) and `root_locus_mu.{png,svg}` (Re p vs μ) of the
/// tracks that take part in a coupling (those with a critical μ, their partners, and those
/// unstable from the start), at most 16; with none, the 8 tracks of largest Re p.
pub fn write_root_locus(dir: &RunDir, rep: &SweepReport) -> Result<Vec<String>, PipelineError> {
    let tracks: Vec<LocusTrack> = drawn_tracks(rep, [])
        .into_iter()
        .map(|t| {
            let f0 = t.points[0].frequency_hz;
            (
                format!("track {} ({:.0} Hz at mu = {})", t.id, f0, t.points[0].mu),
                t.points
                    .iter()
                    .map(|p| (p.mu, p.frequency_hz, p.real_part))
                    .collect(),
            )
        })
        .collect();
    if tracks.is_empty() {
        return Ok(Vec::new());
    }
    let (by_f, by_mu) = root_locus(&tracks);
    let mut out = Vec::new();
    for (fig, name) in [(by_f, "root_locus"), (by_mu, "root_locus_mu")] {
        let stem = dir.path(name);
        if write_figure(&fig, &stem)
            .map_err(|e| out_err(dir, &format!("{name}.png"))(e.to_string()))?
            .is_some()
        {
            out.push(stem.display().to_string());
        }
    }
    Ok(out)
}
