//! A component's fixed DOFs: its `fixed` sets and its file's own constraints.

use crate::error::PipelineError;
use crate::scene::{ComponentSpec, Scene};
use squeal_meshes::Mesh;

/// The fixed (node, component) pairs of a component's `fixed` sets and of its file's
/// constraints, sorted and unique.
pub fn fixed_dofs(c: &ComponentSpec, mesh: &Mesh) -> Result<Vec<(usize, usize)>, PipelineError> {
    let mut fixed = Vec::new();
    for f in &c.fixed {
        let nodes = mesh
            .node_sets
            .get(&f.set)
            .ok_or_else(|| PipelineError::Scene {
                field: format!("components[name = {}].fixed.set", c.name),
                message: format!(
                    "the mesh has no node set `{}` (it has: {})",
                    f.set,
                    mesh.node_sets
                        .keys()
                        .cloned()
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            })?;
        let comps = f.components()?;
        for &n in nodes {
            for &k in &comps {
                fixed.push((n, k));
            }
        }
    }
    // The file's own constraints (Nastran SPC sets, Abaqus *BOUNDARY).
    fixed.extend(mesh.fixed.iter().copied());
    fixed.sort_unstable();
    fixed.dedup();
    Ok(fixed)
}

/// A component whose `fixed` sets hold every DOF of its mesh has nothing left to move (and
/// the first factorisation or gap assignment would fail naming neither): an error naming the
/// component, its fixed sets and the mesh file.
pub fn check_not_all_fixed(
    scene: &Scene,
    c: &ComponentSpec,
    mesh: &Mesh,
    fixed: &[(usize, usize)],
    mesh_file: &str,
) -> Result<(), PipelineError> {
    let n = mesh.nodes.len();
    let mut held = vec![false; 3 * n];
    for &(node, k) in fixed {
        if node < n && k < 3 {
            held[3 * node + k] = true;
        }
    }
    if held.iter().all(|&h| h) {
        let i = scene
            .components
            .iter()
            .position(|x| x.name == c.name)
            .unwrap_or(0);
        let sets: Vec<String> = c
            .fixed
            .iter()
            .map(|f| format!("`{}` ({})", f.set, f.dofs))
            .collect();
        return Err(PipelineError::Scene {
            field: format!("components[{i}].fixed"),
            message: format!(
                "the fixed set(s) {} of `{}` hold every DOF of its {n} nodes (mesh {mesh_file}): \
                 the component has no free DOF; fix only where it is held (e.g. a hub or an \
                 abutment set)",
                sets.join(", "),
                c.name
            ),
        });
    }
    Ok(())
}
