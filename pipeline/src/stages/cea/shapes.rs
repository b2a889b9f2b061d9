//! Unstable mode shapes on the full meshes: `cea_modes_<component>.vtu`.
//!
//! A complex reduced eigenvector u (assembled reduced DOFs) is gathered per component into its
//! Craig–Bampton coordinates (boundary grid DOFs, then modal coordinates), its real and
//! imaginary parts are recovered separately to the component's free DOFs, x = T·u_c
//! (`CbModel::recover`), and expanded to nodal 3-vectors (`DofMap::expand`, zeros at fixed
//! DOFs). The transformation is real, so Re(T u) = T Re(u) and Im(T u) = T Im(u).

use crate::error::PipelineError;
use crate::model::ReducedModel;
use crate::output::RunDir;
use squeal_meshes::vtu::{self, PointArray};
use squeal_solver::cea::Mode;

use squeal_solver::Real;

/// File name of component `name`'s full-mesh mode shapes.
pub fn file_name(name: &str) -> String {
    format!("cea_modes_{name}.vtu")
}

/// Point-array stem of mode `k` at `frequency_hz`: `mode{k}_{f}Hz` (f with one decimal);
/// the arrays are `<stem>_re` and `<stem>_im`.
pub fn array_stem(k: usize, frequency_hz: Real) -> String {
    format!("mode{k}_{frequency_hz:.1}Hz")
}

/// One mode's shape on one component's mesh.
#[derive(Debug, Clone)]
pub struct NodalShape {
    /// Index into the CEA's modes.
    pub mode: usize,
    pub frequency_hz: Real,
    /// Real and imaginary parts as nodal 3-vectors (zeros at fixed DOFs).
    pub re: Vec<[Real; 3]>,
    pub im: Vec<[Real; 3]>,
}

/// The shapes of some modes on one component's full mesh.
#[derive(Debug, Clone)]
pub struct ComponentShapes {
    pub component: String,
    /// Merged grid id of each mesh node.
    pub grid_of: Vec<u64>,
    pub modes: Vec<NodalShape>,
}

/// The shapes of `modes` recovered on every component the model can recover (meshed models;
/// none for stored matrices).
pub fn recover(
    model: &ReducedModel,
    modes: &[(usize, &Mode)],
) -> Result<Vec<ComponentShapes>, PipelineError> {
    let mut out = Vec::new();
    if modes.is_empty() {
        return Ok(out);
    }
    for comp in &model.recovery {
        let mut shapes = Vec::with_capacity(modes.len());
        for (k, m) in modes {
            let re: Vec<Real> = m.shape.iter().map(|z| z.re).collect();
            let im: Vec<Real> = m.shape.iter().map(|z| z.im).collect();
            shapes.push(NodalShape {
                mode: *k,
                frequency_hz: m.frequency_hz,
                re: comp.expand(&re)?,
                im: comp.expand(&im)?,
            });
        }
        out.push(ComponentShapes {
            component: comp.name.clone(),
            grid_of: comp.grid_of.clone(),
            modes: shapes,
        });
    }
    Ok(out)
}

/// Writes `cea_modes_<component>.vtu` for every component of `shapes` ([`recover`]; meshed
/// models; none for stored matrices): the component's mesh with the point array `grid` (merged
/// grid id of each node, as a real) and, for each mode `k` of the shapes, the 3-vector point
/// arrays `mode{k}_{f}Hz_re` and `mode{k}_{f}Hz_im` (the real and imaginary parts of the shape;
/// animate with `cos(ωt)·re − sin(ωt)·im`). Returns the paths written.
pub fn write_full_mode_shapes(
    dir: &RunDir,
    model: &ReducedModel,
    shapes: &[ComponentShapes],
) -> Result<Vec<String>, PipelineError> {
    let mut written = Vec::new();
    for (comp, shapes) in model.recovery.iter().zip(shapes) {
        let grid: Vec<Real> = shapes.grid_of.iter().map(|&g| g as Real).collect();
        let mut names = vec!["grid".to_string()];
        let mut fields: Vec<Vec<Real>> = Vec::with_capacity(2 * shapes.modes.len());
        for m in &shapes.modes {
            let stem = array_stem(m.mode, m.frequency_hz);
            for (part, nodal) in [("re", &m.re), ("im", &m.im)] {
                fields.push(nodal.iter().flat_map(|v| v.iter().copied()).collect());
                names.push(format!("{stem}_{part}"));
            }
        }
        let mut arrays = vec![PointArray::scalar(&names[0], &grid)];
        arrays.extend(
            names[1..]
                .iter()
                .zip(&fields)
                .map(|(n, v): (&String, &Vec<Real>)| PointArray::vector(n, v)),
        );
        let path = dir.path(&file_name(&comp.name));
        vtu::write_vtu(&path, &comp.mesh, &arrays, &[]).map_err(|source| PipelineError::Mesh {
            component: comp.name.clone(),
            source,
        })?;
        written.push(path.display().to_string());
    }
    Ok(written)
}
