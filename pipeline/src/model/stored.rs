//! Stored reduced models: `reduced.op4` (KR, MR, BR, PBRAKE), `reduced.pch` (DMIG, rows and
//! columns = grid/component of the map; modal coordinates are scalar points numbered above
//! every grid, in map order), `dofmap.json` and `gaps.json`.

use super::gap_table::read_gaps;
use super::inputs::{check_dofmap, check_finite, check_mass, check_stiffness, symmetric};
use super::ReducedModel;
use crate::error::PipelineError;
use crate::output::RunDir;
use crate::scene::{ModelSource, Scene};
use faer::Mat;
use squeal_contact::GapSet;
use squeal_reduction::matrix::{MatrixForm, NamedMatrix};
use squeal_reduction::punch::{self, DmigMatrix, PunchWriteOptions};
use squeal_reduction::superelement::{DofKind, ReducedDofMap};
use squeal_reduction::{op4, op4::Op4WriteOptions};
use std::collections::HashMap;
use std::path::Path;

use squeal_solver::Real;

/// Paths written by [`write_stored`].
#[derive(Debug, Clone, serde::Serialize)]
pub struct StoredFiles {
    pub op4: String,
    pub punch: String,
    pub dofmap: String,
    pub gaps: String,
    /// The same gap table as CSV (with the face columns when gaps are tied to faces).
    pub gaps_csv: String,
}

fn red_err(what: String) -> impl FnOnce(squeal_reduction::ReductionError) -> PipelineError {
    move |source| PipelineError::Reduction { what, source }
}

/// Punch DOFs of the map: grids as (grid, comp), modal coordinates as scalar points
/// `base + 1 + k` (k = order among modal DOFs, base = 10^digits above the largest grid).
fn punch_dofs(dofs: &ReducedDofMap) -> Vec<(u64, u8)> {
    let max_grid = dofs
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
    dofs.dofs
        .iter()
        .map(|d| match d.kind {
            DofKind::Grid { grid, comp } => (grid, comp),
            DofKind::Modal { .. } | DofKind::Interface { .. } => {
                k += 1;
                (base + k, 0)
            }
        })
        .collect()
}

/// The matrices of `reduced.op4`: KR, MR, BR (when the model has element damping), PBRAKE.
pub(super) fn stored_matrices(model: &ReducedModel) -> Vec<NamedMatrix> {
    let n = model.n();
    let mut mats = vec![
        NamedMatrix::real("KR", model.k.clone()),
        NamedMatrix::real("MR", model.m.clone()),
    ];
    if let Some(b) = &model.b {
        mats.push(NamedMatrix::real("BR", b.clone()));
    }
    mats.push(
        NamedMatrix::real("PBRAKE", Mat::from_fn(n, 1, |i, _| model.p_brake[i]))
            .with_form(MatrixForm::Rectangular),
    );
    mats
}

/// Writes `reduced.op4`, `reduced.pch`, `dofmap.json`, and the model's `gaps` at the
/// scene's operating point as `gaps.json` and `gaps.csv`, into the run folder.
pub fn write_stored(
    model: &ReducedModel,
    gaps: &GapSet,
    dir: &RunDir,
) -> Result<StoredFiles, PipelineError> {
    let mats = stored_matrices(model);
    let refs: Vec<&NamedMatrix> = mats.iter().collect();
    let op4_bytes = op4::write_bytes(&refs, &Op4WriteOptions::default())
        .map_err(red_err("writing reduced.op4".into()))?;
    let op4_path = dir.write_bytes("reduced.op4", &op4_bytes)?;

    let rows = punch_dofs(&model.dofs);
    let dmig: Vec<DmigMatrix> = mats
        .iter()
        .map(|m| {
            let vector = m.ncols == 1;
            DmigMatrix {
                matrix: if vector {
                    m.clone().with_form(MatrixForm::PseudoIdentity)
                } else {
                    m.clone()
                },
                rows: rows.clone(),
                cols: if vector { vec![(1, 0)] } else { rows.clone() },
            }
        })
        .collect();
    let drefs: Vec<&DmigMatrix> = dmig.iter().collect();
    let text = punch::write_string(&drefs, &PunchWriteOptions::default())
        .map_err(red_err("writing reduced.pch".into()))?;
    let pch_path = dir.write_bytes("reduced.pch", text.as_bytes())?;
    let map_path = dir.write_json("dofmap.json", &model.dofs)?;
    let gaps_path = dir.write_json("gaps.json", gaps)?;
    let csv_path = dir.write_bytes(
        "gaps.csv",
        super::gap_table::gaps_csv(&gaps.gaps).as_bytes(),
    )?;
    Ok(StoredFiles {
        gaps_csv: csv_path.display().to_string(),
        op4: op4_path.display().to_string(),
        punch: pch_path.display().to_string(),
        dofmap: map_path.display().to_string(),
        gaps: gaps_path.display().to_string(),
    })
}

fn read_text(path: &Path) -> Result<String, PipelineError> {
    std::fs::read_to_string(path).map_err(|source| PipelineError::Io {
        path: path.to_path_buf(),
        source,
    })
}

/// Reads a stored reduced model as the scene's `[model]` says; the scene's `[rotor]` sets the
/// sliding velocities, `[friction]` the law, `model.p0`/`model.temperature` override the table.
pub fn load_stored(scene: &Scene) -> Result<ReducedModel, PipelineError> {
    let spec = &scene.model;
    let need = |p: &Option<std::path::PathBuf>, f: &str| {
        p.as_ref()
            .map(|p| scene.resolve(p))
            .ok_or_else(|| PipelineError::Scene {
                field: format!("model.{f}"),
                message: "required for a stored model".into(),
            })
    };
    let mpath = need(&spec.matrices, "matrices")?;
    let dpath = need(&spec.dofmap, "dofmap")?;
    let dofs = ReducedDofMap::from_json(&read_text(&dpath)?).map_err(|e| PipelineError::Input {
        path: dpath.clone(),
        message: e.to_string(),
    })?;
    check_dofmap(&dofs, &dpath)?;
    let n = dofs.len();
    let mut named: HashMap<String, Mat<Real>> = HashMap::new();
    let shape_err = |name: &str, r: usize, c: usize| PipelineError::Input {
        path: mpath.clone(),
        message: format!("matrix {name} is {r}x{c}; the DOF map has {n} DOFs"),
    };
    match spec.from {
        ModelSource::Op4 => {
            for m in op4::read(&mpath).map_err(red_err("reading the stored model".into()))? {
                let a = m.as_real().cloned().ok_or_else(|| PipelineError::Input {
                    path: mpath.clone(),
                    message: format!("matrix {} is complex", m.name),
                })?;
                named.insert(m.name.to_ascii_uppercase(), a);
            }
        }
        _ => {
            let expected = punch_dofs(&dofs);
            // Rows are sorted by (id, comp) in the file; map them back to map order.
            let pos: HashMap<(u64, u8), usize> =
                expected.iter().enumerate().map(|(i, &d)| (d, i)).collect();
            for d in punch::read(&mpath).map_err(red_err("reading the stored model".into()))? {
                let a = d
                    .matrix
                    .as_real()
                    .cloned()
                    .ok_or_else(|| PipelineError::Input {
                        path: mpath.clone(),
                        message: format!("DMIG {} is complex", d.matrix.name),
                    })?;
                let map_idx = |dof: &(u64, u8)| {
                    pos.get(dof).copied().ok_or_else(|| PipelineError::Input {
                        path: mpath.clone(),
                        message: format!(
                            "DMIG {}: DOF ({}, {}) is not in the DOF map",
                            d.matrix.name, dof.0, dof.1
                        ),
                    })
                };
                let ri: Vec<usize> = d.rows.iter().map(map_idx).collect::<Result<_, _>>()?;
                let vector = d.cols.len() == 1 && d.cols[0].1 == 0 && !pos.contains_key(&d.cols[0]);
                let ci: Vec<usize> = if vector {
                    vec![0]
                } else {
                    d.cols.iter().map(map_idx).collect::<Result<_, _>>()?
                };
                let mut full = Mat::zeros(n, if vector { 1 } else { n });
                for (i, &r) in ri.iter().enumerate() {
                    for (j, &c) in ci.iter().enumerate() {
                        full[(r, c)] = a[(i, j)];
                    }
                }
                named.insert(d.matrix.name.to_ascii_uppercase(), full);
            }
        }
    }
    let mut take = |name: &str, required: bool| -> Result<Option<Mat<Real>>, PipelineError> {
        match named.remove(name) {
            Some(a) => {
                let cols = if name == "PBRAKE" { 1 } else { n };
                if a.nrows() != n || a.ncols() != cols {
                    return Err(shape_err(name, a.nrows(), a.ncols()));
                }
                Ok(Some(a))
            }
            None if required => Err(PipelineError::Input {
                path: mpath.clone(),
                message: format!("no matrix named {name}"),
            }),
            None => Ok(None),
        }
    };
    let k = take("KR", true)?.unwrap_or_else(|| Mat::zeros(n, n));
    let m = take("MR", true)?.unwrap_or_else(|| Mat::zeros(n, n));
    let b = take("BR", false)?;
    let p = take("PBRAKE", false)?;
    let mut warnings = Vec::new();
    let k = symmetric("KR", &k, &mpath, &mut warnings)?;
    let m = symmetric("MR", &m, &mpath, &mut warnings)?;
    check_mass("MR", &m, &mpath)?;
    check_stiffness("KR", &k, &m, &mpath)?;
    let b = b
        .map(|b| symmetric("BR", &b, &mpath, &mut warnings))
        .transpose()?;
    if let Some(p) = &p {
        check_finite("PBRAKE", p, &mpath)?;
    }
    let p_brake = p
        .map(|p| (0..n).map(|i| p[(i, 0)]).collect())
        .unwrap_or_else(|| vec![0.0; n]);

    let gaps = match &spec.gaps {
        Some(p) => read_gaps(&scene.resolve(p))?,
        None => Vec::new(),
    };
    let gaps_path = spec
        .gaps
        .as_ref()
        .map_or(dpath.clone(), |p| scene.resolve(p));
    finish(
        scene,
        (k, m, b, p_brake),
        dofs,
        gaps,
        warnings,
        (&gaps_path, &dpath),
    )
}

/// A stored model: its gap geometry (with the table's own P0 and temperature; the scene's
/// operating point is applied when the problem is made, [`crate::problem::OperatingPoint`]),
/// gap DOFs from the map (`paths`: the gap table and the DOF map, named by errors).
fn finish(
    scene: &Scene,
    (k, m, b, p_brake): (Mat<Real>, Mat<Real>, Option<Mat<Real>>, Vec<Real>),
    dofs: ReducedDofMap,
    gaps: Vec<squeal_contact::Gap>,
    warnings: Vec<crate::warning::Warning>,
    (gaps_path, dpath): (&Path, &Path),
) -> Result<ReducedModel, PipelineError> {
    let spec = &scene.model;
    let gap_pairs = stored_pairs(scene, gaps.len())?;
    let gap_geometry = GapSet {
        gaps,
        law: squeal_contact::FrictionLaw::default(),
        vtol: GapSet::DEFAULT_VTOL,
    };
    let mut model = ReducedModel {
        k,
        m,
        b,
        p_brake,
        dofs,
        gap_geometry,
        gap_pairs,
        grids: Vec::new(),
        checks: Vec::new(),
        components: Vec::new(),
        recovery: Vec::new(),
        source: spec.from,
        warnings,
    };
    model.assign_gap_dofs().map_err(|e| PipelineError::Input {
        path: gaps_path.to_path_buf(),
        message: format!("{e} (DOF map {})", dpath.display()),
    })?;
    Ok(model)
}

/// A stored gap table is one contact pair: the settings the later stages read per
/// `[[contact]]` pair (`separation`, `normal_stiffness`) apply to all its gaps when the scene
/// has one `[[contact]]` table. More tables have nothing to attach to, and the meshing
/// settings of a pair that would change P0 or temperatures (the table's values, or
/// `model.p0` / `model.temperature`, hold them) would be ignored: both are errors naming the
/// key.
fn stored_pairs(scene: &Scene, n_gaps: usize) -> Result<Vec<usize>, PipelineError> {
    if scene.contact.len() > 1 {
        return Err(PipelineError::Scene {
            field: "contact[1]".into(),
            message: format!(
                "a stored model's gap table is one contact pair; give at most one \
                 [[contact]] table (its `separation` and `normal_stiffness` apply to all {n_gaps} \
                 gaps), not {}",
                scene.contact.len()
            ),
        });
    }
    if let Some(c) = scene.contact.first() {
        let ignored = [
            ("p0", c.p0 != 0.0, "model.p0 or the gap table's p0"),
            (
                "temperature",
                c.temperature != 0.0 || !c.grid_temperatures.is_empty(),
                "model.temperature or the gap table's temperature",
            ),
        ];
        if let Some((key, _, instead)) = ignored.iter().find(|(_, set, _)| *set) {
            return Err(PipelineError::Scene {
                field: format!("contact[0].{key}"),
                message: format!(
                    "is not read for a stored model (its gaps come from the gap table): use \
                     {instead}"
                ),
            });
        }
    }
    Ok(if n_gaps > 0 { vec![n_gaps] } else { Vec::new() })
}

/// The stored model of a scene with `model.from = "arrays"` ([`crate::scene::StoredArrays`]),
/// checked as [`load_stored`] checks files: the DOF map, shapes against it, finite entries,
/// symmetry of KR, MR, BR, MR positive definite, gap values (unit normals). Errors name the
/// array as `<arrays>.K`, `<arrays>.dofs`, `<arrays>.gaps`.
pub fn load_arrays(scene: &Scene) -> Result<ReducedModel, PipelineError> {
    let a = scene
        .model
        .arrays
        .as_ref()
        .ok_or_else(|| PipelineError::Scene {
            field: "model.from".into(),
            message: "`arrays` without arrays in memory".into(),
        })?;
    let a = &a.0;
    let path = |what: &str| std::path::PathBuf::from(format!("<arrays>.{what}"));
    let dpath = path("dofs");
    check_dofmap(&a.dofs, &dpath)?;
    let n = a.dofs.len();
    let shape = |name: &str, r: usize, c: usize, want: usize| {
        if r != n || c != want {
            Err(PipelineError::Input {
                path: path(name),
                message: format!("is {r}x{c}; the DOF map has {n} DOFs, expected {n}x{want}"),
            })
        } else {
            Ok(())
        }
    };
    shape("K", a.k.nrows(), a.k.ncols(), n)?;
    shape("M", a.m.nrows(), a.m.ncols(), n)?;
    if let Some(b) = &a.b {
        shape("B", b.nrows(), b.ncols(), n)?;
    }
    let mut warnings = Vec::new();
    let k = symmetric("KR", &a.k, &path("K"), &mut warnings)?;
    let m = symmetric("MR", &a.m, &path("M"), &mut warnings)?;
    check_mass("MR", &m, &path("M"))?;
    check_stiffness("KR", &k, &m, &path("K"))?;
    let b =
        a.b.as_ref()
            .map(|b| symmetric("BR", b, &path("B"), &mut warnings))
            .transpose()?;
    let p_brake = match &a.p_brake {
        Some(p) => {
            let pm = Mat::from_fn(p.len(), 1, |i, _| p[i]);
            shape("p_brake", p.len(), 1, 1)?;
            check_finite("PBRAKE", &pm, &path("p_brake"))?;
            p.clone()
        }
        None => vec![0.0; n],
    };
    let gpath = path("gaps");
    let places: Vec<String> = (0..a.gaps.len()).map(|i| format!("row {i}")).collect();
    super::gap_table::check_gaps(&a.gaps, &places, true, true).map_err(|message| {
        PipelineError::Input {
            path: gpath.clone(),
            message,
        }
    })?;
    finish(
        scene,
        (k, m, b, p_brake),
        a.dofs.clone(),
        a.gaps.clone(),
        warnings,
        (&gpath, &dpath),
    )
}
