//! What a transient run records, for either integrator: the columns of the history and
//! their values at one step, the writers of `history.npy` + `history_map.json` and
//! `energy.csv` ([`Recorder`]), the response the squeal verdict analyses ([`Response`]) and
//! its file `response.npy` ([`ResponseFile`]). A resumed run continues all of them from the
//! rows its restart file counts ([`super::restart::Records`]).

use super::driver::{ChunkView, EndView, Sink, StepView};
use super::restart::{continue_lines, Records, RunCheckpoint, RESPONSE_FILE};
use super::roots;
use super::verdict::{self, Verdict};
use crate::error::PipelineError;
use crate::history::npy::NpyAppender;
use crate::history::{Column, HistoryMap, RecordKind};
use crate::output::RunDir;
use crate::scene::Scene;
use crate::stages::model::ReducedModel;
use serde::Serialize;
use squeal_contact::GapSet;
use squeal_reduction::superelement::DofKey;
use std::io::Write;
use std::path::PathBuf;

type Real = f64;

/// Header of `energy.csv`, and the names of [`History::energy`]'s columns.
pub const ENERGY_HEADER: &str =
    "t,kinetic,strain,damping_dissipation,friction_work,external_work,constraint_work,balance";

/// The recorded history of a run, in memory: the rows `history.npy` holds, and the rows of
/// `energy.csv`.
#[derive(Debug, Clone, Default, Serialize)]
pub struct History {
    /// What each column is (column 0 is t).
    pub columns: Vec<Column>,
    /// Row-major values, `columns.len()` per row.
    pub values: Vec<Real>,
    /// One row per recorded step after the initial point: the columns of [`ENERGY_HEADER`].
    pub energy: Vec<[Real; 8]>,
}

impl History {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.values.len() / self.columns.len().max(1)
    }

    /// Column `name` as a vector (None: no such column).
    pub fn column(&self, name: &str) -> Option<Vec<Real>> {
        let c = self.columns.iter().position(|c| c.name == name)?;
        let w = self.columns.len();
        Some(self.values.iter().skip(c).step_by(w).copied().collect())
    }
}

/// The history of a run — initial point, every NOUTPT-th accepted step, the final time — and
/// its energy rows, written to `history.npy` + `history_map.json` and `energy.csv` when given a
/// folder and `output.history` is on, and kept in memory when asked ([`History`]). With
/// `output.history = false` nothing is opened, written or kept (effects on demand); the
/// columns are still known (for the verdict's response).
pub struct Recorder {
    cols: Vec<Column>,
    gaps: GapSet,
    n: usize,
    noutpt: usize,
    row: Vec<Real>,
    history: Option<NpyAppender>,
    energy: Option<std::io::BufWriter<std::fs::File>>,
    memory: Option<History>,
    history_path: PathBuf,
    energy_path: PathBuf,
    /// Time of the last history row.
    last_t: Option<Real>,
    rows: usize,
    /// Rows of the energy file.
    energy_rows: usize,
    /// The initial point was recorded (or the run resumed records that hold it).
    started: bool,
}

impl Recorder {
    /// The recorder of `scene`'s `[output]` on `model`: files in `dir` (when given; writes
    /// `history_map.json` and opens `history.npy` and `energy.csv`), rows in memory when
    /// `keep`. Errors name the grids or gaps the scene asks for that do not exist.
    pub fn open(
        scene: &Scene,
        model: &ReducedModel,
        dir: Option<&RunDir>,
        keep: bool,
    ) -> Result<Self, PipelineError> {
        Self::open_resumed(scene, model, dir, keep, None)
    }

    /// [`Recorder::open`] continuing the records of a resumed run: the files get the rows
    /// `records` counts (cut back to them in the same folder, copied into a new one) and are
    /// appended to; in memory, those rows are read back.
    pub fn open_resumed(
        scene: &Scene,
        model: &ReducedModel,
        dir: Option<&RunDir>,
        keep: bool,
        records: Option<&Records>,
    ) -> Result<Self, PipelineError> {
        let cols = columns(scene, model)?;
        let noutpt = scene.transient.as_ref().map_or(1, |t| t.noutpt).max(1);
        let (history_path, energy_path) = match dir {
            Some(d) => (d.path("history.npy"), d.path("energy.csv")),
            None => (PathBuf::from("history.npy"), PathBuf::from("energy.csv")),
        };
        let on = scene.output.history;
        // What the resumed run recorded (its records, history rows, energy rows).
        let prior = match records.filter(|_| on) {
            Some(r) => {
                r.check_columns(&cols)?;
                match (r.counts.history_rows, r.counts.energy_rows) {
                    (Some(h), Some(e)) => Some((r, h, e)),
                    _ => {
                        return Err(PipelineError::Scene {
                            field: "output.history".into(),
                            message: format!(
                                "the run resumed ({}) wrote no history (output.history = false): \
                                 resume it with output.history = false too",
                                r.restart.display()
                            ),
                        })
                    }
                }
            }
            None => None,
        };
        let (mut history, mut energy) = (None, None);
        if let (Some(dir), true) = (dir, on) {
            dir.write_json(
                "history_map.json",
                &HistoryMap {
                    n_columns: cols.len(),
                    noutpt,
                    columns: cols.clone(),
                },
            )?;
            let eio = |source| PipelineError::Io {
                path: energy_path.clone(),
                source,
            };
            match prior {
                Some((r, h, e)) => {
                    history = Some(NpyAppender::resume(
                        &r.history(),
                        &history_path,
                        cols.len(),
                        h,
                    )?);
                    continue_lines(&r.energy(), &energy_path, e)?;
                    let f = std::fs::OpenOptions::new()
                        .append(true)
                        .open(&energy_path)
                        .map_err(eio)?;
                    energy = Some(std::io::BufWriter::new(f));
                }
                None => {
                    history = Some(NpyAppender::create(&history_path, cols.len())?);
                    let mut e =
                        std::io::BufWriter::new(std::fs::File::create(&energy_path).map_err(eio)?);
                    writeln!(e, "{ENERGY_HEADER}").map_err(eio)?;
                    energy = Some(e);
                }
            }
        }
        let mut memory = (keep && on).then(|| History {
            columns: cols.clone(),
            ..Default::default()
        });
        if let (Some(m), Some((r, h, e))) = (memory.as_mut(), prior) {
            read_back(r, h, e, m)?;
        }
        let (rows, energy_rows, last_t) = match prior {
            Some((r, h, e)) => (h, e, r.counts.history_last_t),
            None => (0, 0, None),
        };
        Ok(Self {
            row: Vec::with_capacity(cols.len()),
            memory,
            cols,
            gaps: model.gaps.clone(),
            n: model.n(),
            noutpt,
            history,
            energy,
            history_path,
            energy_path,
            last_t,
            rows,
            energy_rows,
            started: records.is_some(),
        })
    }

    /// The columns of the history.
    pub fn columns(&self) -> &[Column] {
        &self.cols
    }

    /// Rows recorded so far.
    pub fn rows(&self) -> usize {
        self.rows
    }

    /// The history kept in memory (None unless asked for), leaving none behind.
    pub fn take_history(&mut self) -> Option<History> {
        self.memory.take()
    }

    fn recording(&self) -> bool {
        self.history.is_some() || self.memory.is_some()
    }

    /// A history row at (t, y, y') (no energy line).
    pub fn point(&mut self, t: Real, y: &[Real], yp: &[Real]) -> Result<(), PipelineError> {
        if !self.recording() {
            return Ok(());
        }
        fill_row(&self.cols, &self.gaps, self.n, t, y, yp, &mut self.row)
            .map_err(PipelineError::Model)?;
        if let Some(h) = self.history.as_mut() {
            h.push(&self.row)?;
        }
        if let Some(m) = self.memory.as_mut() {
            m.values.extend_from_slice(&self.row);
        }
        self.last_t = Some(t);
        self.rows += 1;
        Ok(())
    }

    /// On every NOUTPT-th accepted step: a history row and an energy row (the energies at `p`,
    /// the integrals of `balance`).
    fn record_step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        if s.step % self.noutpt != 0 || !self.recording() {
            return Ok(());
        }
        self.point(s.t, s.y, s.yp)?;
        let (kinetic, strain) = s.power.map_or((0.0, 0.0), |p| (p.kinetic, p.strain));
        let b = s.balance;
        let e = [
            s.t,
            kinetic,
            strain,
            b.damping_dissipated,
            b.friction_work,
            b.external_work,
            b.constraint_work,
            b.residual(),
        ];
        if let Some(m) = self.memory.as_mut() {
            m.energy.push(e);
        }
        if let Some(w) = self.energy.as_mut() {
            self.energy_rows += 1;
            writeln!(
                w,
                "{:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7]
            )
            .map_err(|source| PipelineError::Io {
                path: self.energy_path.clone(),
                source,
            })?;
        }
        Ok(())
    }

    /// Makes both files complete and valid up to the last record.
    pub fn flush(&mut self) -> Result<(), PipelineError> {
        if let Some(h) = self.history.as_mut() {
            h.flush()?;
        }
        if let Some(e) = self.energy.as_mut() {
            e.flush().map_err(|source| PipelineError::Io {
                path: self.energy_path.clone(),
                source,
            })?;
        }
        Ok(())
    }

    /// Where the history goes (for error messages).
    pub fn history_path(&self) -> &std::path::Path {
        &self.history_path
    }
}

impl Sink for Recorder {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        if self.started {
            return self.record_step(s);
        }
        self.started = true;
        self.point(s.t, s.y, s.yp)
    }

    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        match c.failed {
            // Keep what was recorded; the chunk's own error is the one reported.
            true => {
                let _ = self.flush();
                Ok(())
            }
            false => self.flush(),
        }
    }

    /// The row at the final time TFINAL (unless the last recorded step ended exactly there, as
    /// fixed steps do), and a flush.
    fn end(&mut self, e: &EndView<'_>) -> Result<(), PipelineError> {
        if e.status.is_success() && self.last_t != Some(e.tfinal) {
            self.point(e.tfinal, e.stepper.y(), e.stepper.yp())?;
        }
        self.flush()
    }

    /// The rows of the files (a recorder in memory writes none and adds nothing).
    fn checkpoint(&self, c: &mut RunCheckpoint) {
        if self.history.is_some() {
            c.records.history_rows = Some(self.rows);
            c.records.history_columns = Some(self.cols.len());
            c.records.history_last_t = self.last_t;
        }
        if self.energy.is_some() {
            c.records.energy_rows = Some(self.energy_rows);
        }
    }
}

/// The first `rows` rows of the history and `energy_rows` rows of the energy of the run `r`
/// resumes, into `m`.
fn read_back(
    r: &Records,
    rows: usize,
    energy_rows: usize,
    m: &mut History,
) -> Result<(), PipelineError> {
    let (_, cols, data) = crate::history::npy::read_npy(&r.history())?;
    m.values
        .extend_from_slice(&data[..(rows * cols).min(data.len())]);
    let p = r.energy();
    let text = std::fs::read_to_string(&p).map_err(|source| PipelineError::Io {
        path: p.clone(),
        source,
    })?;
    for (i, line) in text.lines().skip(1).take(energy_rows).enumerate() {
        let values: Option<Vec<Real>> = line.split(',').map(|x| x.parse().ok()).collect();
        let e: [Real; 8] =
            values
                .and_then(|v| v.try_into().ok())
                .ok_or_else(|| PipelineError::Input {
                    path: p.clone(),
                    message: format!("line {}: not 8 numbers: `{line}`", i + 2),
                })?;
        m.energy.push(e);
    }
    Ok(())
}

/// The velocities the squeal verdict analyses: `output.response`, or every velocity column
/// of the history (the verdict then takes the one with the largest peak after the ramp),
/// at every accepted step.
pub struct Response {
    dofs: Vec<usize>,
    t: Vec<Real>,
    v: Vec<Vec<Real>>,
    /// The accelerations v' of the same DOFs (the root estimator's Hermite resampling).
    a: Vec<Vec<Real>>,
}

impl Response {
    /// The DOFs of `output.response` (an error names a grid without that DOF) or of the
    /// velocity columns of `cols`.
    pub fn new(
        scene: &Scene,
        model: &ReducedModel,
        cols: &[Column],
    ) -> Result<Self, PipelineError> {
        let dofs: Vec<usize> = match &scene.output.response {
            Some(r) => {
                let comp = match r.dof.as_str() {
                    "x" => 1,
                    "y" => 2,
                    _ => 3,
                };
                vec![*model
                    .grid_index()
                    .get(&DofKey { grid: r.grid, comp })
                    .ok_or_else(|| PipelineError::Scene {
                        field: "output.response".into(),
                        message: format!(
                            "grid {} {} is not a DOF of the reduced model",
                            r.grid, r.dof
                        ),
                    })?]
            }
            None => cols
                .iter()
                .filter(|c| c.kind == RecordKind::Velocity)
                .map(|c| c.dof.unwrap_or(0))
                .collect(),
        };
        Ok(Self {
            v: vec![Vec::new(); dofs.len()],
            a: vec![Vec::new(); dofs.len()],
            dofs,
            t: Vec::new(),
        })
    }

    /// Continues the response of a resumed run: its rows up to the restart. The DOFs must be
    /// the same (an error names `output.response`).
    pub fn resume(&mut self, r: &Records) -> Result<(), PipelineError> {
        same_response(r, &self.dofs)?;
        self.t.clone_from(&r.response_t);
        self.v.clone_from(&r.response_v);
        self.a.clone_from(&r.response_a);
        Ok(())
    }

    /// The reduced DOFs whose velocities it records.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }

    /// Records the velocities of y = {v, λ, u} and their derivatives at t.
    pub fn push(&mut self, t: Real, y: &[Real], yp: &[Real]) {
        self.t.push(t);
        for (k, &d) in self.dofs.iter().enumerate() {
            self.v[k].push(y[d]);
            self.a[k].push(yp[d]);
        }
    }

    /// Times of the recorded steps.
    pub fn times(&self) -> &[Real] {
        &self.t
    }

    /// The verdict on the response after `t_after` (the end of the load ramp), and the name
    /// of the history column of its envelope cross-check.
    ///
    /// The roots are fitted on every recorded DOF over [t_after, end] ([`roots::estimate`],
    /// `band_hz` bounds the sampling and the roots kept); the envelope on the DOF with the
    /// largest peak after the ramp.
    ///
    /// With `stall_h`, only the growth phase is analysed: the steps up to the first one
    /// shorter than `stall_h` after the ramp (where a squealing response reaches slip reversal
    /// and the step collapses).
    ///
    /// With `t_stop`, only the steps before it are analysed (the contact went tensile there).
    #[allow(clippy::too_many_arguments)]
    pub fn verdict(
        &self,
        t_after: Real,
        stall_h: Option<Real>,
        t_stop: Option<Real>,
        cols: &[Column],
        band_hz: Option<Real>,
        opts: &roots::PencilOptions,
    ) -> (String, Verdict) {
        let t = &self.t;
        let stall = stall_h
            .and_then(|h| (1..t.len()).find(|&i| t[i] > t_after && t[i] - t[i - 1] < h))
            .unwrap_or(t.len());
        let stop = t_stop.map_or(t.len(), |ts| t.partition_point(|&x| x < ts));
        let end = stall.min(stop);
        let (t, v, a): (&[Real], Vec<&[Real]>, Vec<&[Real]>) = (
            &t[..end],
            self.v.iter().map(|v| &v[..end]).collect(),
            self.a.iter().map(|a| &a[..end]).collect(),
        );
        let pick = v
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let peak = t
                    .iter()
                    .zip(v.iter())
                    .filter(|(t, _)| **t > t_after)
                    .fold(0.0f64, |m, (_, x)| m.max(x.abs()));
                (k, peak)
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k);
        let (name, envelope) = match pick {
            Some(k) => {
                let d = self.dofs[k];
                let name = cols
                    .iter()
                    .find(|c| c.kind == RecordKind::Velocity && c.dof == Some(d))
                    .map(|c| c.name.clone())
                    .unwrap_or_else(|| format!("v_dof{d}"));
                (name, verdict::analyse(t, v[k], t_after))
            }
            None => ("none".into(), verdict::analyse(&[], &[], 0.0)),
        };
        // The window after the ramp (the first sample at or after t_after).
        let first = t.partition_point(|&s| s < t_after);
        let window = match (t.get(first), t.last()) {
            (Some(&a), Some(&b)) if b > a => [a, b],
            _ => [t_after, t_after],
        };
        let fit = roots::estimate(
            &t[first..],
            &v.iter().map(|v| &v[first..]).collect::<Vec<_>>(),
            &a.iter().map(|a| &a[first..]).collect::<Vec<_>>(),
            window,
            envelope.dominant_frequency_hz,
            band_hz,
            opts,
        );
        let h_max = (first.max(1)..t.len())
            .map(|i| t[i] - t[i - 1])
            .fold(None, |m: Option<Real>, h| Some(m.map_or(h, |m| m.max(h))));
        (name, Verdict::new(fit, envelope, window, h_max))
    }
}

impl Sink for Response {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        self.push(s.t, s.y, s.yp);
        Ok(())
    }
}

/// The response of the run `r` resumes is that of `dofs` (an error names `output.response`).
fn same_response(r: &Records, dofs: &[usize]) -> Result<(), PipelineError> {
    match r.counts.response_dofs == dofs {
        true => Ok(()),
        false => Err(PipelineError::Scene {
            field: "output.response".into(),
            message: format!(
                "the run resumed ({}) analysed the velocities of DOFs {:?}, this scene those of \
                 {dofs:?}: resume with the same output.response and output.grids",
                r.restart.display(),
                r.counts.response_dofs,
            ),
        }),
    }
}

/// `response.npy`: the response of [`Response`] (t, then its velocities, then their
/// accelerations) at every accepted step, the record a resumed run's verdict reads back.
/// Written beside `restart.json`.
pub struct ResponseFile {
    dofs: Vec<usize>,
    file: NpyAppender,
    row: Vec<Real>,
}

impl ResponseFile {
    /// Creates `response.npy` in `dir` for the velocities of `dofs`, or continues the rows of
    /// the run `records` resumes.
    pub fn open(
        dir: &RunDir,
        dofs: &[usize],
        records: Option<&Records>,
    ) -> Result<Self, PipelineError> {
        let path = dir.path(RESPONSE_FILE);
        let cols = 2 * dofs.len() + 1;
        let file = match records.and_then(|r| r.counts.response_rows.map(|k| (r, k))) {
            Some((r, rows)) => {
                same_response(r, dofs)?;
                NpyAppender::resume(&r.response(), &path, cols, rows)?
            }
            None => NpyAppender::create(&path, cols)?,
        };
        Ok(Self {
            dofs: dofs.to_vec(),
            file,
            row: Vec::with_capacity(cols),
        })
    }
}

impl Sink for ResponseFile {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        self.row.clear();
        self.row.push(s.t);
        self.row.extend(self.dofs.iter().map(|&d| s.y[d]));
        self.row.extend(self.dofs.iter().map(|&d| s.yp[d]));
        self.file.push(&self.row)
    }
    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        match c.failed {
            true => {
                let _ = self.file.flush();
                Ok(())
            }
            false => self.file.flush(),
        }
    }
    fn end(&mut self, _: &EndView<'_>) -> Result<(), PipelineError> {
        self.file.flush()
    }
    fn checkpoint(&self, c: &mut RunCheckpoint) {
        c.records.response_rows = Some(self.file.rows());
        c.records.response_dofs = self.dofs.clone();
    }
}

const DIRS: [&str; 3] = ["x", "y", "z"];

/// Columns of `history.npy` for the scene's `[output]`; errors name grids without DOFs and
/// gap indices out of range.
pub fn columns(scene: &Scene, model: &ReducedModel) -> Result<Vec<Column>, PipelineError> {
    let index = model.grid_index();
    let mut grids = scene.output.grids.clone();
    if grids.is_empty() {
        let g = &model.gaps.gaps;
        if !g.is_empty() {
            for i in [0, g.len() / 2, g.len() - 1] {
                if !grids.contains(&g[i].pad_node) {
                    grids.push(g[i].pad_node);
                }
            }
        } else if let Some(k) = index.keys().min() {
            grids.push(k.grid);
        }
    }
    let mut cols = vec![Column {
        column: 0,
        name: "t".into(),
        kind: RecordKind::Time,
        grid: None,
        component: None,
        gap: None,
        dof: None,
    }];
    let mut missing = Vec::new();
    for &grid in &grids {
        let dofs: Vec<(usize, usize)> = (0..3)
            .filter_map(|c| {
                index
                    .get(&DofKey {
                        grid,
                        comp: c as u8 + 1,
                    })
                    .map(|&i| (c, i))
            })
            .collect();
        if dofs.is_empty() {
            missing.push(grid);
        }
        for (kind, short) in [
            (RecordKind::Displacement, "u"),
            (RecordKind::Velocity, "v"),
            (RecordKind::Acceleration, "a"),
        ] {
            for &(c, i) in &dofs {
                cols.push(Column {
                    column: cols.len(),
                    name: format!("{short}_{grid}_{}", DIRS[c]),
                    kind,
                    grid: Some(grid),
                    component: Some(DIRS[c].into()),
                    gap: None,
                    dof: Some(i),
                });
            }
        }
    }
    if !missing.is_empty() {
        return Err(PipelineError::Scene {
            field: "output.grids".into(),
            message: format!(
                "grids {missing:?} have no DOF in the reduced model (only boundary grids — contact \
                 and shared nodes — are reduced DOFs; see grids.json / dofmap.json)"
            ),
        });
    }
    let ng = model.gaps.len();
    let gaps: Vec<usize> = scene
        .output
        .gaps
        .clone()
        .unwrap_or_else(|| (0..ng).collect());
    if let Some(&bad) = gaps.iter().find(|&&g| g >= ng) {
        return Err(PipelineError::Scene {
            field: "output.gaps".into(),
            message: format!("gap {bad} is out of range (the model has {ng} gaps, 0-based)"),
        });
    }
    for &g in &gaps {
        for (kind, short) in [
            (RecordKind::ContactForce, "contact_force"),
            (RecordKind::Pressure, "pressure"),
            (RecordKind::FrictionForce, "friction_force"),
            (RecordKind::FrictionCoefficient, "friction_coefficient"),
            (RecordKind::SlipSpeed, "slip_speed"),
        ] {
            cols.push(Column {
                column: cols.len(),
                name: format!("gap{g}_{short}"),
                kind,
                grid: None,
                component: None,
                gap: Some(g),
                dof: None,
            });
        }
    }
    Ok(cols)
}

/// Values of every column at (t, y, y'), y = {v, λ, u}; `row` gets one value per column.
pub fn fill_row(
    cols: &[Column],
    gaps: &GapSet,
    n: usize,
    t: Real,
    y: &[Real],
    yp: &[Real],
    row: &mut Vec<Real>,
) -> Result<(), String> {
    let ng = gaps.len();
    let v = &y[..n];
    let u = &y[n + ng..];
    let lamp = &yp[n..n + ng];
    row.clear();
    let mut last_gap: Option<(usize, squeal_contact::GapOutput)> = None;
    for c in cols {
        let value = match c.kind {
            RecordKind::Time => t,
            RecordKind::Displacement => u[c.dof.unwrap_or(0)],
            RecordKind::Velocity => v[c.dof.unwrap_or(0)],
            RecordKind::Acceleration => yp[c.dof.unwrap_or(0)],
            kind => {
                let g = c.gap.unwrap_or(0);
                let out = match last_gap {
                    Some((lg, o)) if lg == g => o,
                    _ => {
                        let o = gaps.gap_output(g, v, lamp).map_err(|e| e.to_string())?;
                        last_gap = Some((g, o));
                        o
                    }
                };
                let area = gaps.gaps[g].area;
                let normal = out.pressure * area;
                match kind {
                    RecordKind::ContactForce => normal,
                    RecordKind::Pressure => out.pressure,
                    RecordKind::FrictionForce => out.friction_force,
                    RecordKind::FrictionCoefficient => {
                        if normal != 0.0 {
                            out.friction_force / normal
                        } else {
                            0.0
                        }
                    }
                    _ => out.slip_speed,
                }
            }
        };
        row.push(value);
    }
    Ok(())
}
