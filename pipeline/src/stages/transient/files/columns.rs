//! The columns of the history (`history.npy`) and their values at one step.

use crate::error::PipelineError;
use crate::history::{Column, RecordKind};
use crate::model::ReducedModel;
use crate::scene::Scene;
use squeal_contact::GapSet;
use squeal_reduction::superelement::DofKey;
use squeal_solver::Real;

/// Header of `energy.csv`, and the names of [`History::energy`]'s columns.
pub const ENERGY_HEADER: &str =
    "t,kinetic,strain,damping_dissipation,friction_work,external_work,constraint_work,balance";

const DIRS: [&str; 3] = ["x", "y", "z"];

/// Columns of `history.npy` for the scene's `[output]`; errors name grids without DOFs and
/// gap indices out of range.
pub fn columns(scene: &Scene, model: &ReducedModel) -> Result<Vec<Column>, PipelineError> {
    let index = model.grid_index();
    let mut grids = scene.output.grids.clone();
    if grids.is_empty() {
        let g = &model.gap_geometry.gaps;
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
    let ng = model.gap_geometry.len();
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
