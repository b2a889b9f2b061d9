//! Rigid-body vectors from DOF coordinates, and rigid-body mass properties.

use faer::{Mat, MatRef};
use serde::{Deserialize, Serialize};
use squeal_meshes::Real;

/// Location and direction of one DOF: node coordinates and component 0..6
/// (0–2 translations x, y, z; 3–5 rotations about x, y, z).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DofPoint {
    pub xyz: [Real; 3],
    pub comp: u8,
}

/// DOF points of `n_free` free DOFs from node coordinates and a `dof_of(free) -> (node, comp)`
/// map (e.g. `squeal_fe::DofMap::dof_of`).
pub fn dof_points(
    nodes: &[[Real; 3]],
    n_free: usize,
    dof_of: impl Fn(usize) -> (usize, usize),
) -> Vec<DofPoint> {
    (0..n_free)
        .map(|i| {
            let (node, comp) = dof_of(i);
            DofPoint {
                xyz: nodes[node],
                comp: comp as u8,
            }
        })
        .collect()
}

/// The 6 rigid-body vectors (translations x, y, z; rotations about the x, y, z axes through the
/// origin) evaluated at `points`: row i of the result is DOF i.
///
/// A small rotation θ moves a point x by θ × x: about x (0, −z, y), about y (z, 0, −x),
/// about z (−y, x, 0).
pub(crate) fn rigid_vectors(points: &[DofPoint]) -> Mat<Real> {
    let mut r = Mat::<Real>::zeros(points.len(), 6);
    for (i, p) in points.iter().enumerate() {
        let [x, y, z] = p.xyz;
        match p.comp {
            0 => {
                r[(i, 0)] = 1.0;
                r[(i, 4)] = z;
                r[(i, 5)] = -y;
            }
            1 => {
                r[(i, 1)] = 1.0;
                r[(i, 3)] = -z;
                r[(i, 5)] = x;
            }
            2 => {
                r[(i, 2)] = 1.0;
                r[(i, 3)] = y;
                r[(i, 4)] = -x;
            }
            c => r[(i, c as usize)] = 1.0,
        }
    }
    r
}

/// Rigid-body mass properties from the 6×6 rigid-body mass matrix Rᵀ M R.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RigidBodyMass {
    /// Translational masses along x, y, z (diagonal of the 6×6 matrix).
    pub mass: [Real; 3],
    /// Centre of gravity: x = M[1][5]/m_y, y = M[2][3]/m_z, z = M[0][4]/m_x.
    pub cg: [Real; 3],
    /// The 6×6 rigid-body mass matrix about the origin.
    pub matrix: [[Real; 6]; 6],
}

/// Rigid-body mass properties of the 6×6 matrix `mrb` = Rᵀ M R.
///
/// # Derivation
/// For translation t_a and rotation r_b, t_aᵀ M r_b = Σ m_p e_a·(e_b × x_p) = m e_a·(e_b × x_cg):
/// (a, b) = (y, z) gives m x_cg, (z, x) gives m y_cg, (x, y) gives m z_cg.
pub fn rigid_body_mass(mrb: MatRef<'_, Real>) -> RigidBodyMass {
    let mut matrix = [[0.0; 6]; 6];
    for (i, row) in matrix.iter_mut().enumerate() {
        for (j, v) in row.iter_mut().enumerate() {
            *v = 0.5 * (mrb[(i, j)] + mrb[(j, i)]);
        }
    }
    let mass = [matrix[0][0], matrix[1][1], matrix[2][2]];
    let cg = [
        matrix[1][5] / mass[1],
        matrix[2][3] / mass[2],
        matrix[0][4] / mass[0],
    ];
    RigidBodyMass { mass, cg, matrix }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Rotation columns are θ × x: for x = (1, 2, 3), about x (0, −3, 2), about y (3, 0, −1),
    /// about z (−2, 1, 0).
    #[test]
    fn rotation_columns_are_cross_products() {
        let pts: Vec<DofPoint> = (0..3)
            .map(|c| DofPoint {
                xyz: [1.0, 2.0, 3.0],
                comp: c,
            })
            .collect();
        let r = rigid_vectors(&pts);
        let expect = [[0.0, 3.0, -2.0], [-3.0, 0.0, 1.0], [2.0, -1.0, 0.0]]; // rows: u_x, u_y, u_z
        for comp in 0..3 {
            for rot in 0..3 {
                assert_eq!(r[(comp, 3 + rot)], expect[comp][rot]);
            }
            assert_eq!(r[(comp, comp)], 1.0);
        }
    }

    /// Two point masses m = 2 at (1, 0, 0) and (3, 2, 0): mass 4, CG (2, 1, 0).
    #[test]
    fn point_masses_give_mass_and_cg() {
        let mut pts = Vec::new();
        for xyz in [[1.0, 0.0, 0.0], [3.0, 2.0, 0.0]] {
            for comp in 0..3 {
                pts.push(DofPoint { xyz, comp });
            }
        }
        let r = rigid_vectors(&pts);
        let m = Mat::<Real>::identity(6, 6) * faer::Scale(2.0);
        let props = rigid_body_mass((r.transpose() * &m * &r).as_ref());
        assert_eq!(props.mass, [4.0, 4.0, 4.0]);
        assert_eq!(props.cg, [2.0, 1.0, 0.0]);
    }
}
