//! A user's mesh (`kind = "msh"`, `"geo"`, `"bdf"` or `"inp"`) against what the scene asks of
//! it: every physical
//! group the scene names for the component — fixed sets, friction faces, load faces and load
//! node sets — must be in the file; and the rigid rotation `rotate_deg` of a component's nodes.

use crate::error::PipelineError;
use crate::scene::{ComponentSpec, Scene};
use squeal_meshes::Mesh;
use std::path::Path;

use squeal_solver::Real;

/// What the scene asks of one physical group of a component.
enum Need {
    /// A physical surface of quad4/quad8 faces (friction faces, pressure faces).
    Surface,
    /// A physical group of any dimension (its nodes: fixed sets, force node sets).
    Nodes,
}

/// Checks that `mesh`, read from the user's `file`, has every physical group the scene names
/// for component `c`: `fixed[j].set` (any physical group), `contact[i].pad_faces` /
/// `rotor_faces` where `c` is the pad / rotor (physical surfaces), `loads.pressure[i].faces`
/// (a physical surface) and `loads.force[i].nodes` (any group). The error names the file, the
/// missing group, the scene key that asks for it and the groups the file has.
pub fn check_groups(
    scene: &Scene,
    c: &ComponentSpec,
    mesh: &Mesh,
    file: &Path,
) -> Result<(), PipelineError> {
    let mut wanted: Vec<(String, &str, Need)> = Vec::new();
    for (j, f) in c.fixed.iter().enumerate() {
        wanted.push((
            format!("components[name = {}].fixed[{j}].set", c.name),
            &f.set,
            Need::Nodes,
        ));
    }
    for (i, p) in scene.contact.iter().enumerate() {
        if p.pad == c.name {
            wanted.push((
                format!("contact[{i}].pad_faces (the pad's friction face)"),
                &p.pad_faces,
                Need::Surface,
            ));
        }
        if p.rotor == c.name {
            wanted.push((
                format!("contact[{i}].rotor_faces (the rotor's friction face)"),
                &p.rotor_faces,
                Need::Surface,
            ));
        }
    }
    if let Some(loads) = &scene.loads {
        for (i, p) in loads.pressure.iter().enumerate() {
            if p.component == c.name {
                wanted.push((
                    format!("loads.pressure[{i}].faces (a load face)"),
                    &p.faces,
                    Need::Surface,
                ));
            }
        }
        for (i, f) in loads.force.iter().enumerate() {
            if f.component == c.name {
                wanted.push((
                    format!("loads.force[{i}].nodes (a loaded node set)"),
                    &f.nodes,
                    Need::Nodes,
                ));
            }
        }
    }
    let surfaces = || list(mesh.faces.keys());
    // gmsh calls its sets physical groups; Nastran and Abaqus files have node and face sets.
    let (group, surface) = if c.geometry.file_has_materials() {
        ("node set", "face set")
    } else {
        ("physical group", "physical surface")
    };
    for (key, name, need) in wanted {
        let found = match need {
            Need::Surface => mesh.faces.get(name).is_some_and(|b| !b.is_empty()),
            Need::Nodes => mesh.node_sets.get(name).is_some_and(|s| !s.is_empty()),
        };
        if found {
            continue;
        }
        let message = match need {
            Need::Surface if mesh.node_sets.contains_key(name) => format!(
                "component `{}`: {group} `{name}` ({key}) has no quad4/quad8 faces; it must \
                 be a {surface} of the volume cells' faces (the file's {surface}s: {})",
                c.name,
                surfaces()
            ),
            Need::Surface => format!(
                "component `{}`: no {surface} `{name}` ({key}); the file's {surface}s: {}",
                c.name,
                surfaces()
            ),
            Need::Nodes => format!(
                "component `{}`: no {group} `{name}` ({key}); the file's {group}s: {}",
                c.name,
                list(mesh.node_sets.keys())
            ),
        };
        return Err(PipelineError::Input {
            path: file.to_path_buf(),
            message,
        });
    }
    Ok(())
}

fn list<'a>(names: impl Iterator<Item = &'a String>) -> String {
    let v: Vec<&str> = names.map(String::as_str).collect();
    if v.is_empty() {
        "none".into()
    } else {
        v.join(", ")
    }
}

/// Turns every node of `mesh` (and the material axes of its sections) by `deg` degrees about
/// the unit `axis` through `origin` (right hand), by Rodrigues' formula
///
/// $$ x' = o + d\cos\theta + (a\times d)\sin\theta + a\,(a\cdot d)(1-\cos\theta),\quad d = x - o. $$
///
/// The rotation is orthogonal, so cell Jacobians keep their sign and every set keeps its nodes.
pub fn rotate_nodes(mesh: &mut Mesh, deg: Real, axis: [Real; 3], origin: [Real; 3]) {
    let n = (axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]).sqrt();
    let a = axis.map(|x| x / n);
    let (s, c) = deg.to_radians().sin_cos();
    for x in &mut mesh.nodes {
        let d = [x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]];
        let cross = [
            a[1] * d[2] - a[2] * d[1],
            a[2] * d[0] - a[0] * d[2],
            a[0] * d[1] - a[1] * d[0],
        ];
        let dot = a[0] * d[0] + a[1] * d[1] + a[2] * d[2];
        for k in 0..3 {
            x[k] = origin[k] + d[k] * c + cross[k] * s + a[k] * dot * (1.0 - c);
        }
    }
    if mesh.sections.values().any(|s| s.axes.is_some()) {
        // The same rotation as a matrix: x' = R x + (o − R o).
        let rot: [[Real; 3]; 3] = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let id = if i == j { 1.0 } else { 0.0 };
                let k = [[0.0, -a[2], a[1]], [a[2], 0.0, -a[0]], [-a[1], a[0], 0.0]];
                c * id + s * k[i][j] + (1.0 - c) * a[i] * a[j]
            })
        });
        let ro: [Real; 3] = std::array::from_fn(|i| (0..3).map(|j| rot[i][j] * origin[j]).sum());
        let shift: [Real; 3] = std::array::from_fn(|i| origin[i] - ro[i]);
        for sec in mesh.sections.values_mut() {
            if let Some(ax) = &mut sec.axes {
                *ax = ax.moved(&rot, shift);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rotation_about_an_offset_axis() {
        let mut m = Mesh {
            nodes: vec![[2.0, 0.0, 0.5], [1.0, 1.0, -1.0]],
            ..Default::default()
        };
        // 90° about z through (1, 0, 0): (2,0) → (1,1); (1,1) → (0,0).
        rotate_nodes(&mut m, 90.0, [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]);
        let want = [[1.0, 1.0, 0.5], [0.0, 0.0, -1.0]];
        for (x, w) in m.nodes.iter().zip(&want) {
            for k in 0..3 {
                assert!((x[k] - w[k]).abs() < 1e-14, "{x:?} vs {w:?}");
            }
        }
        // A full turn in 7 uneven steps comes back; distances to the axis are kept.
        let start = m.nodes.clone();
        for deg in [10.0, 50.0, 33.3, 66.7, 100.0, 70.0, 30.0] {
            rotate_nodes(&mut m, deg, [0.0, 0.6, 0.8], [0.0, 0.0, 0.0]);
        }
        for (x, w) in m.nodes.iter().zip(&start) {
            for k in 0..3 {
                assert!((x[k] - w[k]).abs() < 1e-12, "{x:?} vs {w:?}");
            }
        }
    }
}
