//! Materials and material axes read from a mesh file (Nastran MAT1/MAT9 + PSOLID, Abaqus
//! *MATERIAL + *SOLID SECTION + *ORIENTATION), as plain data.
//!
//! `squeal-meshes` does not depend on `squeal-fe`: the pipeline turns a [`Section`] into fe's
//! material. The description here keeps what the file says (an isotropic pair, engineering
//! constants, or a full 6×6 stiffness) so that nothing is lost before that conversion.
//!
//! Voigt order of every 6×6 matrix here: stresses σ = [σ11, σ22, σ33, σ23, σ13, σ12] and
//! engineering strains ε = [ε11, ε22, ε33, γ23, γ13, γ12] (squeal-fe's order; Nastran's MAT9
//! order xx, yy, zz, xy, yz, zx and Abaqus's 11, 22, 33, 12, 13, 23 are permuted on reading),
//! in the section's material axes.

use crate::Real;
use serde::{Deserialize, Serialize};

/// The material and axes of the cells of one volume block (one Nastran PSOLID, one Abaqus
/// solid section).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Section {
    pub material: MaterialData,
    /// Material axes (default: None = the global axes).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axes: Option<MaterialAxes>,
    /// Where the section is defined, e.g. `deck.bdf:12: PSOLID 3`.
    pub source: String,
}

/// A linear-elastic material as the file gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MaterialData {
    /// The file's name or id for it, e.g. `MAT9 7` or `LINING`.
    pub name: String,
    /// Where it is defined (`file:line`).
    pub source: String,
    pub elastic: Elastic,
    /// Mass density ρ (None: the file gives none).
    pub density: Option<Real>,
    /// Structural loss factor η given with the material (Nastran MAT1/MAT9 GE, Abaqus
    /// `*DAMPING, STRUCTURAL=η`), finite and >= 0; None when the file gives none or 0. The
    /// pipeline adds (η/W4)·K of the material's elements to the element damping.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structural_damping: Option<Real>,
}

/// Elastic constants.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
// One per section: the size of the 6×6 variant does not matter.
#[allow(clippy::large_enum_variant)]
pub enum Elastic {
    /// Young's modulus and Poisson's ratio.
    Isotropic { young: Real, poisson: Real },
    /// Orthotropic engineering constants in the material axes: E1, E2, E3; ν12, ν13, ν23
    /// (ν_ij = −ε_j/ε_i under σ_i); G12, G13, G23.
    EngineeringConstants {
        young: [Real; 3],
        poisson: [Real; 3],
        shear: [Real; 3],
    },
    /// The 6×6 stiffness (symmetric) in the Voigt order of this module, in the material axes.
    Stiffness { c: [[Real; 6]; 6] },
}

impl Elastic {
    /// The 6×6 stiffness in this module's Voigt order (engineering constants are inverted
    /// from their compliance; None when that compliance is singular).
    pub fn stiffness(&self) -> Option<[[Real; 6]; 6]> {
        match *self {
            Elastic::Isotropic { young, poisson } => {
                let g = young / (2.0 * (1.0 + poisson));
                let f = young / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
                let mut c = [[0.0; 6]; 6];
                for i in 0..3 {
                    for j in 0..3 {
                        c[i][j] = if i == j {
                            f * (1.0 - poisson)
                        } else {
                            f * poisson
                        };
                    }
                    c[i + 3][i + 3] = g;
                }
                Some(c)
            }
            Elastic::EngineeringConstants {
                young: e,
                poisson: [n12, n13, n23],
                shear: [g12, g13, g23],
            } => {
                // Compliance, S_ij = −ν_ij / E_i (symmetric: ν_ji / E_j = ν_ij / E_i).
                let mut s = [[0.0; 3]; 3];
                s[0][0] = 1.0 / e[0];
                s[1][1] = 1.0 / e[1];
                s[2][2] = 1.0 / e[2];
                s[0][1] = -n12 / e[0];
                s[1][0] = s[0][1];
                s[0][2] = -n13 / e[0];
                s[2][0] = s[0][2];
                s[1][2] = -n23 / e[1];
                s[2][1] = s[1][2];
                let inv = invert3(s)?;
                let mut c = [[0.0; 6]; 6];
                for i in 0..3 {
                    for j in 0..3 {
                        c[i][j] = inv[i][j];
                    }
                }
                // Voigt 3 = 23, 4 = 13, 5 = 12.
                c[3][3] = g23;
                c[4][4] = g13;
                c[5][5] = g12;
                Some(c)
            }
            Elastic::Stiffness { c } => Some(c),
        }
    }
}

impl Elastic {
    /// Checks that the stiffness is symmetric positive definite (a stable material), by a
    /// Cholesky factorisation of the 6×6 matrix; the error says which pivot failed.
    pub fn check(&self) -> Result<(), String> {
        if let Elastic::EngineeringConstants { young, shear, .. } = self {
            if young
                .iter()
                .chain(shear)
                .any(|&v| !(v > 0.0 && v.is_finite()))
            {
                return Err(format!(
                    "moduli E = {young:?}, G = {shear:?} must be finite and > 0"
                ));
            }
        }
        let Some(c) = self.stiffness() else {
            return Err("its compliance is singular (no stiffness)".into());
        };
        for i in 0..6 {
            for j in 0..i {
                let scale = c[i][i].abs().max(c[j][j].abs());
                if (c[i][j] - c[j][i]).abs() > 1e-12 * scale {
                    return Err(format!(
                        "its stiffness is not symmetric (entry {}{})",
                        i + 1,
                        j + 1
                    ));
                }
            }
        }
        let mut l = [[0.0; 6]; 6];
        for j in 0..6 {
            let d = c[j][j] - (0..j).map(|k| l[j][k] * l[j][k]).sum::<Real>();
            if d.is_nan() || d <= 1e-14 * c[j][j].abs() || !d.is_finite() {
                return Err(format!(
                    "its stiffness is not positive definite (Cholesky pivot {} is {d:e}): not \
                     a stable material",
                    j + 1
                ));
            }
            l[j][j] = d.sqrt();
            for i in j + 1..6 {
                l[i][j] = (c[i][j] - (0..j).map(|k| l[i][k] * l[j][k]).sum::<Real>()) / l[j][j];
            }
        }
        Ok(())
    }
}

fn invert3(a: [[Real; 3]; 3]) -> Option<[[Real; 3]; 3]> {
    let det = a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1])
        - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0]);
    if !det.is_finite() || det == 0.0 {
        return None;
    }
    let mut r = [[0.0; 3]; 3];
    for i in 0..3 {
        for j in 0..3 {
            let (i1, i2) = ((j + 1) % 3, (j + 2) % 3);
            let (j1, j2) = ((i + 1) % 3, (i + 2) % 3);
            r[i][j] = (a[i1][j1] * a[i2][j2] - a[i1][j2] * a[i2][j1]) / det;
        }
    }
    Some(r)
}

/// How the material axes vary over the body.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum AxesKind {
    /// The same axes everywhere: 1, 2, 3 = the frame's x, y, z.
    Rectangular,
    /// About the frame's z axis: 1 = radial, 2 = tangential (θ), 3 = axial (z).
    Cylindrical,
    /// About the frame's origin: 1 = radial, 2 = polar (θ, from z), 3 = azimuthal (φ).
    Spherical,
}

/// Material axes: a frame (origin and three orthonormal axes in global coordinates) and how
/// the axes follow it. At a point x the material axes are [`MaterialAxes::at`].
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct MaterialAxes {
    pub kind: AxesKind,
    pub origin: [Real; 3],
    /// Rows: the frame's unit x, y, z axes in global coordinates (a proper rotation).
    pub frame: [[Real; 3]; 3],
}

impl MaterialAxes {
    /// The material's unit axes 1, 2, 3 (rows) at the global point `x`. On the axis of a
    /// cylindrical frame (or the centre of a spherical one) the radial direction is undefined:
    /// the frame's own axes are returned there.
    pub fn at(&self, x: [Real; 3]) -> [[Real; 3]; 3] {
        let d = [0, 1, 2].map(|k| x[k] - self.origin[k]);
        let l = self.frame.map(|e| e[0] * d[0] + e[1] * d[1] + e[2] * d[2]);
        let to_global = |v: [Real; 3]| -> [Real; 3] {
            [0, 1, 2].map(|k| (0..3).map(|i| v[i] * self.frame[i][k]).sum())
        };
        match self.kind {
            AxesKind::Rectangular => self.frame,
            AxesKind::Cylindrical => {
                let r = l[0].hypot(l[1]);
                if r == 0.0 {
                    return self.frame;
                }
                let (c, s) = (l[0] / r, l[1] / r);
                [
                    to_global([c, s, 0.0]),
                    to_global([-s, c, 0.0]),
                    self.frame[2],
                ]
            }
            AxesKind::Spherical => {
                let rho = l[0].hypot(l[1]);
                let r = rho.hypot(l[2]);
                if rho == 0.0 || r == 0.0 {
                    return self.frame;
                }
                let (ct, st) = (l[2] / r, rho / r);
                let (cp, sp) = (l[0] / rho, l[1] / rho);
                [
                    to_global([st * cp, st * sp, ct]),
                    to_global([ct * cp, ct * sp, -st]),
                    to_global([-sp, cp, 0.0]),
                ]
            }
        }
    }

    /// The axes after a rigid rotation `rot` (rows: the rotated images of x, y, z, i.e.
    /// x' = rot · x) followed by a translation `shift`.
    pub fn moved(&self, rot: &[[Real; 3]; 3], shift: [Real; 3]) -> MaterialAxes {
        let apply = |v: [Real; 3]| -> [Real; 3] {
            [0, 1, 2].map(|i| (0..3).map(|k| rot[i][k] * v[k]).sum())
        };
        let o = apply(self.origin);
        MaterialAxes {
            kind: self.kind,
            origin: [0, 1, 2].map(|k| o[k] + shift[k]),
            frame: self.frame.map(apply),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn engineering_constants_of_an_isotropic_material_give_its_stiffness() {
        // E = 210, ν = 0.3 written as engineering constants: the same 6×6 as the isotropic form.
        let (e, nu) = (210.0, 0.3);
        let g = e / (2.0 * (1.0 + nu));
        let a = Elastic::Isotropic {
            young: e,
            poisson: nu,
        }
        .stiffness()
        .unwrap();
        let b = Elastic::EngineeringConstants {
            young: [e; 3],
            poisson: [nu; 3],
            shear: [g; 3],
        }
        .stiffness()
        .unwrap();
        for i in 0..6 {
            for j in 0..6 {
                assert!((a[i][j] - b[i][j]).abs() < 1e-12 * e, "{i}{j}");
            }
        }
    }

    #[test]
    fn positive_definiteness() {
        let iso = |nu| Elastic::Isotropic {
            young: 1.0,
            poisson: nu,
        };
        assert!(iso(0.3).check().is_ok());
        assert!(iso(0.6).check().is_err());
        // A transversely isotropic lining is stable; with ν12 = 1.2 it is not.
        let pad = |n12| Elastic::EngineeringConstants {
            young: [4.0e9, 4.0e9, 1.2e9],
            poisson: [n12, 0.1, 0.1],
            shear: [1.6e9, 0.6e9, 0.6e9],
        };
        assert!(pad(0.25).check().is_ok());
        assert!(pad(1.2).check().is_err());
    }

    #[test]
    fn cylindrical_axes_are_radial_tangential_axial() {
        let ax = MaterialAxes {
            kind: AxesKind::Cylindrical,
            origin: [1.0, 0.0, 0.0],
            frame: [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
        };
        let a = ax.at([1.0, 2.0, 5.0]);
        assert_eq!(a[0], [0.0, 1.0, 0.0]);
        assert_eq!(a[1], [-1.0, 0.0, 0.0]);
        assert_eq!(a[2], [0.0, 0.0, 1.0]);
    }
}
