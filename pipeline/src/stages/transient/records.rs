//! What a transient run records, for either integrator: the columns of the history and
//! their values at one step, the writers of `history.npy` + `history_map.json` and
//! `energy.csv` ([`Recorder`]), and the response the squeal verdict analyses ([`Response`]).

use super::verdict::{self, Verdict};
use crate::error::PipelineError;
use crate::history::npy::NpyAppender;
use crate::history::{Column, HistoryMap, RecordKind};
use crate::output::RunDir;
use crate::scene::Scene;
use crate::stages::model::ReducedModel;
use squeal_contact::GapSet;
use squeal_reduction::superelement::DofKey;
use squeal_solver::bsql::{EnergyBalance, PowerTerms};
use std::io::Write;
use std::path::PathBuf;

type Real = f64;

/// Header of `energy.csv`.
const ENERGY_HEADER: &str =
    "t,kinetic,strain,damping_dissipation,friction_work,external_work,constraint_work,balance";

/// The history database and the energy file of a run: the initial point, every NOUTPT-th
/// accepted step and the final time. With `output.history = false` nothing is opened or
/// written (effects on demand); the columns are still known (for the verdict's response).
pub struct Recorder {
    cols: Vec<Column>,
    gaps: GapSet,
    n: usize,
    noutpt: usize,
    row: Vec<Real>,
    history: Option<NpyAppender>,
    energy: Option<std::io::BufWriter<std::fs::File>>,
    history_path: PathBuf,
    energy_path: PathBuf,
    /// Time of the last history row.
    last_t: Option<Real>,
}

impl Recorder {
    /// Writes `history_map.json` and opens `history.npy` and `energy.csv` in `dir` (when
    /// `output.history`); errors name the grids or gaps the scene asks for that do not exist.
    pub fn open(
        scene: &Scene,
        model: &ReducedModel,
        dir: &RunDir,
        noutpt: usize,
    ) -> Result<Self, PipelineError> {
        let cols = columns(scene, model)?;
        let (history_path, energy_path) = (dir.path("history.npy"), dir.path("energy.csv"));
        let (mut history, mut energy) = (None, None);
        if scene.output.history {
            dir.write_json(
                "history_map.json",
                &HistoryMap {
                    n_columns: cols.len(),
                    noutpt,
                    columns: cols.clone(),
                },
            )?;
            history = Some(NpyAppender::create(&history_path, cols.len())?);
            let eio = |source| PipelineError::Io {
                path: energy_path.clone(),
                source,
            };
            let mut e = std::io::BufWriter::new(std::fs::File::create(&energy_path).map_err(eio)?);
            writeln!(e, "{ENERGY_HEADER}").map_err(eio)?;
            energy = Some(e);
        }
        Ok(Self {
            row: Vec::with_capacity(cols.len()),
            cols,
            gaps: model.gaps.clone(),
            n: model.n(),
            noutpt: noutpt.max(1),
            history,
            energy,
            history_path,
            energy_path,
            last_t: None,
        })
    }

    /// The columns of `history.npy`.
    pub fn columns(&self) -> &[Column] {
        &self.cols
    }

    /// Rows written to `history.npy` so far.
    pub fn rows(&self) -> usize {
        self.history.as_ref().map_or(0, |h| h.rows())
    }

    /// A history row at (t, y, y') (the initial point; no energy line).
    pub fn point(&mut self, t: Real, y: &[Real], yp: &[Real]) -> Result<(), PipelineError> {
        if let Some(h) = self.history.as_mut() {
            fill_row(&self.cols, &self.gaps, self.n, t, y, yp, &mut self.row)
                .map_err(PipelineError::Model)?;
            h.push(&self.row)?;
            self.last_t = Some(t);
        }
        Ok(())
    }

    /// The row at the final time TFINAL (unless the last recorded step ended exactly there,
    /// as fixed steps do), and a flush.
    pub fn finish(&mut self, t: Real, y: &[Real], yp: &[Real]) -> Result<(), PipelineError> {
        if self.last_t != Some(t) {
            self.point(t, y, yp)?;
        }
        self.flush()
    }

    /// After accepted step number `step` (counted from the start of the run): on every
    /// NOUTPT-th, a history row and an `energy.csv` line (the energies at `p`, the integrals
    /// of `balance`).
    pub fn step(
        &mut self,
        step: usize,
        t: Real,
        y: &[Real],
        yp: &[Real],
        p: &PowerTerms,
        balance: &EnergyBalance,
    ) -> Result<(), PipelineError> {
        if step % self.noutpt != 0 || self.history.is_none() {
            return Ok(());
        }
        self.point(t, y, yp)?;
        if let Some(e) = self.energy.as_mut() {
            writeln!(
                e,
                "{t:e},{:e},{:e},{:e},{:e},{:e},{:e},{:e}",
                p.kinetic,
                p.strain,
                balance.damping_dissipated,
                balance.friction_work,
                balance.external_work,
                balance.constraint_work,
                balance.residual()
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

    /// The end of one integration chunk: flushes what was recorded (also when the chunk
    /// failed, so no output already written is lost) and maps the integrator's error — or a
    /// write error the step callback stashed in `out_err` — to the pipeline's (`what`: which
    /// integration).
    pub fn end_chunk<S>(
        &mut self,
        st: Result<S, squeal_solver::SolverError>,
        out_err: &mut Option<String>,
        what: &str,
    ) -> Result<S, PipelineError> {
        match st {
            Ok(st) => {
                self.flush()?;
                Ok(st)
            }
            Err(source) => {
                let _ = self.flush();
                Err(match out_err.take() {
                    Some(message) => PipelineError::Output {
                        path: self.history_path.clone(),
                        message,
                    },
                    None => PipelineError::Solver {
                        what: what.into(),
                        source,
                    },
                })
            }
        }
    }
}

/// The velocities the squeal verdict analyses: `output.response`, or every velocity column
/// of the history (the verdict then takes the one with the largest peak after the ramp),
/// at every accepted step.
pub struct Response {
    dofs: Vec<usize>,
    t: Vec<Real>,
    v: Vec<Vec<Real>>,
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
            dofs,
            t: Vec::new(),
        })
    }

    /// Records the velocities of y = {v, λ, u} at t.
    pub fn push(&mut self, t: Real, y: &[Real]) {
        self.t.push(t);
        for (k, &d) in self.dofs.iter().enumerate() {
            self.v[k].push(y[d]);
        }
    }

    /// The verdict on the response after `t_after` (the end of the load ramp), and the name
    /// of the history column it analysed.
    pub fn verdict(&self, t_after: Real, cols: &[Column]) -> (String, Verdict) {
        let pick = self
            .v
            .iter()
            .enumerate()
            .map(|(k, v)| {
                let peak = self
                    .t
                    .iter()
                    .zip(v)
                    .filter(|(t, _)| **t > t_after)
                    .fold(0.0f64, |m, (_, x)| m.max(x.abs()));
                (k, peak)
            })
            .max_by(|a, b| a.1.total_cmp(&b.1))
            .map(|(k, _)| k);
        match pick {
            Some(k) => {
                let d = self.dofs[k];
                let name = cols
                    .iter()
                    .find(|c| c.kind == RecordKind::Velocity && c.dof == Some(d))
                    .map(|c| c.name.clone())
                    .unwrap_or_else(|| format!("v_dof{d}"));
                (name, verdict::analyse(&self.t, &self.v[k], t_after))
            }
            None => ("none".into(), verdict::analyse(&[], &[], 0.0)),
        }
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
