//! The velocities the squeal verdict analyses, at every accepted step: `output.response`, or
//! every velocity column of the history (the verdict then takes the one with the largest peak
//! after the ramp).

use super::super::sink::{Sink, StepView};
use crate::error::PipelineError;
use crate::history::{Column, RecordKind};
use crate::model::ReducedModel;
use crate::scene::Scene;
use crate::verdict::Series;
use squeal_reduction::superelement::DofKey;
use squeal_solver::Real;
use std::path::PathBuf;

/// The response a resumed run recorded up to its restart (read back from `response.npy`).
#[derive(Debug, Clone, Default)]
pub struct Recorded {
    /// The restart file (named in errors).
    pub restart: PathBuf,
    /// The reduced DOFs of its velocity columns.
    pub dofs: Vec<usize>,
    /// Times and, per DOF, velocities and accelerations.
    pub t: Vec<Real>,
    pub v: Vec<Vec<Real>>,
    pub a: Vec<Vec<Real>>,
}

/// The response of the run resumed (from `restart`, DOFs `saved`) is that of `dofs` (an error
/// names `output.response`).
pub fn same_response(
    restart: &std::path::Path,
    saved: &[usize],
    dofs: &[usize],
) -> Result<(), PipelineError> {
    match saved == dofs {
        true => Ok(()),
        false => Err(PipelineError::Scene {
            field: "output.response".into(),
            message: format!(
                "the run resumed ({}) analysed the velocities of DOFs {saved:?}, this scene \
                 those of {dofs:?}: resume with the same output.response and output.grids",
                restart.display(),
            ),
        }),
    }
}

/// The reduced DOFs of the response: `output.response` (an error names a grid without that
/// DOF) or those of the velocity columns of `cols`.
pub fn response_dofs(
    scene: &Scene,
    model: &ReducedModel,
    cols: &[Column],
) -> Result<Vec<usize>, PipelineError> {
    Ok(match &scene.output.response {
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
    })
}

/// The velocities and accelerations of the response's DOFs at every step (a data-only sink).
pub struct Response {
    dofs: Vec<usize>,
    pub series: Series,
}

impl Response {
    /// The response of `scene` on `model`, its channels named after the velocity columns of
    /// the history `cols` (`v_dof<d>` for a DOF without one).
    pub fn new(
        scene: &Scene,
        model: &ReducedModel,
        cols: &[Column],
    ) -> Result<Self, PipelineError> {
        let dofs = response_dofs(scene, model, cols)?;
        let names = dofs
            .iter()
            .map(|&d| {
                cols.iter()
                    .find(|c| c.kind == RecordKind::Velocity && c.dof == Some(d))
                    .map(|c| c.name.clone())
                    .unwrap_or_else(|| format!("v_dof{d}"))
            })
            .collect();
        Ok(Self {
            dofs,
            series: Series::new(names),
        })
    }

    /// Continues the response of a resumed run: its rows up to the restart. The DOFs must be
    /// the same (an error names `output.response`).
    pub fn resume(&mut self, r: &Recorded) -> Result<(), PipelineError> {
        same_response(&r.restart, &r.dofs, &self.dofs)?;
        self.series.t.clone_from(&r.t);
        self.series.v.clone_from(&r.v);
        self.series.a.clone_from(&r.a);
        Ok(())
    }

    /// The reduced DOFs whose velocities it records.
    pub fn dofs(&self) -> &[usize] {
        &self.dofs
    }
}

impl Sink for Response {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        let r = &mut self.series;
        r.t.push(s.t);
        for (k, &d) in self.dofs.iter().enumerate() {
            r.v[k].push(s.y[d]);
            r.a[k].push(s.yp[d]);
        }
        Ok(())
    }
}
