//! Load vectors over the free DOFs and lumped face area vectors.

mod faces;

pub use faces::face_areas;

use crate::{DofMap, FeError, Mesh, Real};

/// Consistent nodal forces of a uniform pressure `pressure` on the face set `face_set`,
/// acting into the body: traction t = −p n with n the outward normal, f_a = −p ∫ N_a n dA.
///
/// The outward direction of each face is decided from the adjacent volume cell's centroid,
/// not from the face's node order. Returns a vector over the free DOFs of `dofs`
/// (components at fixed DOFs are dropped).
pub fn pressure_load(
    mesh: &Mesh,
    face_set: &str,
    pressure: Real,
    dofs: &DofMap,
) -> Result<Vec<Real>, FeError> {
    if dofs.n_nodes() != mesh.nodes.len() {
        return Err(FeError::DofMapMismatch {
            dof_nodes: dofs.n_nodes(),
            mesh_nodes: mesh.nodes.len(),
        });
    }
    if !pressure.is_finite() {
        return Err(FeError::InvalidValue {
            field: "pressure".to_string(),
            value: pressure,
            reason: "must be finite",
        });
    }
    let mut f = vec![0.0; dofs.n_free()];
    for (node, s) in face_areas(mesh, face_set)? {
        for c in 0..3 {
            if let Some(i) = dofs.free(node, c) {
                f[i] -= pressure * s[c];
            }
        }
    }
    Ok(f)
}

/// A point force of `magnitude` along `direction` (normalised here) at `node`, over the free
/// DOFs (components at fixed DOFs are dropped).
pub fn nodal_force(
    node: usize,
    direction: [Real; 3],
    magnitude: Real,
    dofs: &DofMap,
) -> Result<Vec<Real>, FeError> {
    if node >= dofs.n_nodes() {
        return Err(FeError::NodeOutOfRange {
            node,
            n_nodes: dofs.n_nodes(),
            context: "nodal_force".to_string(),
        });
    }
    let len = (direction[0].powi(2) + direction[1].powi(2) + direction[2].powi(2)).sqrt();
    if len.is_nan() || len <= 0.0 || !len.is_finite() || !magnitude.is_finite() {
        return Err(FeError::InvalidValue {
            field: "nodal_force.direction length".to_string(),
            value: len,
            reason: "direction must be finite and non-zero, magnitude finite",
        });
    }
    let mut f = vec![0.0; dofs.n_free()];
    for c in 0..3 {
        if let Some(i) = dofs.free(node, c) {
            f[i] = magnitude * direction[c] / len;
        }
    }
    Ok(f)
}
