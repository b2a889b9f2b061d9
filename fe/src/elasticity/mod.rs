//! Anisotropic linear elasticity: orthotropic, transversely isotropic and general (6×6)
//! constitutive matrices, material axes, and their positive-definiteness checks.
//!
//! Voigt order throughout: (11, 22, 33, 23, 13, 12) with engineering shear strains
//! γ_ij = 2 ε_ij, so σ = D ε and the strain energy density is ½ εᵀ D ε. (Nastran's MAT9
//! orders (xx, yy, zz, xy, yz, zx), Abaqus (11, 22, 33, 12, 13, 23): readers reorder.)
//!
//! # Reference
//! Engineering constants: ν_ij = −ε_j/ε_i under uniaxial stress σ_i, ν_ij/E_i = ν_ji/E_j;
//! compliance S = [[1/E1, −ν21/E2, −ν31/E3], [−ν12/E1, 1/E2, −ν32/E3], [−ν13/E1, −ν23/E2,
//! 1/E3]] ⊕ diag(1/G23, 1/G13, 1/G12), D = S⁻¹ (R. M. Jones, *Mechanics of Composite
//! Materials*, 2nd ed., §2.4; its positive-definiteness conditions §2.4.1: E_i, G_ij > 0,
//! |ν_ij| < √(E_i/E_j), 1 − ν12ν21 − ν23ν32 − ν31ν13 − 2ν21ν32ν13 > 0). Rotation of D to
//! global axes with the Bond matrix M of the rotation Q (columns: material axes in global
//! components): D_global = M D_material Mᵀ (Bond 1943; Ting, *Anisotropic Elasticity*, §2.8).

// `!(x > 0.0)` rejects NaN as well as non-positive values, deliberately.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use crate::{FeError, Material, Real};
use nalgebra::SMatrix;
use serde::{Deserialize, Serialize};

/// A 6×6 constitutive matrix (Voigt order (11, 22, 33, 23, 13, 12), engineering shears).
pub type Matrix6 = SMatrix<Real, 6, 6>;

/// Orthonormal material axes: `frame[k]` is material axis k + 1 in global components.
pub type Frame = [[Real; 3]; 3];

/// Elastic constants of a material.
#[allow(clippy::large_enum_variant)] // a 6×6 matrix, read once per block
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Elasticity {
    /// Isotropic: Young's modulus and Poisson's ratio.
    Isotropic { young: Real, poisson: Real },
    /// Orthotropic engineering constants in the material axes.
    Orthotropic(Orthotropic),
    /// Transversely isotropic: isotropic in the material 1–2 plane, axis 3 the symmetry axis
    /// (a friction lining's thickness direction).
    TransverselyIsotropic(TransverselyIsotropic),
    /// A general symmetric 6×6 matrix in the material axes (Voigt order of this module).
    Anisotropic { stiffness: [[Real; 6]; 6] },
}

/// Nine orthotropic engineering constants (ν_ij: strain in j over strain in i under σ_i).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Orthotropic {
    pub e1: Real,
    pub e2: Real,
    pub e3: Real,
    pub nu12: Real,
    pub nu13: Real,
    pub nu23: Real,
    pub g12: Real,
    pub g13: Real,
    pub g23: Real,
}

/// Transversely isotropic constants: in-plane (1–2) modulus and Poisson's ratio, transverse
/// (axis 3) modulus, ν_p3 = ν13 = ν23 and G_3 = G13 = G23; G12 = E_p / (2 (1 + ν_p)).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TransverselyIsotropic {
    /// In-plane modulus E1 = E2.
    pub e_plane: Real,
    /// Modulus along the symmetry axis, E3.
    pub e_axis: Real,
    /// In-plane Poisson's ratio ν12.
    pub nu_plane: Real,
    /// ν13 = ν23 (strain along the axis under in-plane stress).
    pub nu_plane_axis: Real,
    /// Transverse shear modulus G13 = G23.
    pub g_axis: Real,
}

impl TransverselyIsotropic {
    /// The equivalent orthotropic constants.
    pub fn orthotropic(&self) -> Orthotropic {
        Orthotropic {
            e1: self.e_plane,
            e2: self.e_plane,
            e3: self.e_axis,
            nu12: self.nu_plane,
            nu13: self.nu_plane_axis,
            nu23: self.nu_plane_axis,
            g12: self.e_plane / (2.0 * (1.0 + self.nu_plane)),
            g13: self.g_axis,
            g23: self.g_axis,
        }
    }
}

/// Where the material axes of a block lie.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum MaterialAxes {
    /// The global x, y, z axes.
    #[default]
    Global,
    /// Fixed axes: 1 along `e1`, 2 in the plane of `e1` and `e2` (orthogonalised), 3 = 1 × 2
    /// (Abaqus *ORIENTATION, SYSTEM=RECTANGULAR; Nastran CORD2R as CORDM).
    Rectangular { e1: [Real; 3], e2: [Real; 3] },
    /// Cylindrical axes about the line through `origin` along `axis`: 1 radial, 2
    /// circumferential, 3 axial, evaluated at each integration point (a rotor's axes).
    Cylindrical { origin: [Real; 3], axis: [Real; 3] },
    /// One frame per cell of the block, in cell order (filled by mesh readers from the file's
    /// orientations; not a scene key).
    #[serde(skip)]
    PerCell(Vec<Frame>),
}

/// A block's solid material: elasticity, density and material axes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolidMaterial {
    pub elasticity: Elasticity,
    /// Mass density ρ (> 0).
    pub density: Real,
    /// Material axes (default: global; ignored for isotropic elasticity).
    #[serde(default)]
    pub axes: MaterialAxes,
}

impl From<Material> for SolidMaterial {
    fn from(m: Material) -> Self {
        SolidMaterial {
            elasticity: Elasticity::Isotropic {
                young: m.young,
                poisson: m.poisson,
            },
            density: m.density,
            axes: MaterialAxes::Global,
        }
    }
}

impl From<&Material> for SolidMaterial {
    fn from(m: &Material) -> Self {
        SolidMaterial::from(*m)
    }
}

fn invalid(field: String, value: Real, reason: &'static str) -> FeError {
    FeError::InvalidValue {
        field,
        value,
        reason,
    }
}

impl Orthotropic {
    /// Positive definiteness (Jones §2.4.1); the error names `name`, the condition and value.
    pub fn validate(&self, name: &str) -> Result<(), FeError> {
        for (k, v) in [
            ("e1", self.e1),
            ("e2", self.e2),
            ("e3", self.e3),
            ("g12", self.g12),
            ("g13", self.g13),
            ("g23", self.g23),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(invalid(format!("{name}.{k}"), v, "must be finite and > 0"));
            }
        }
        for (k, nu, ei, ej) in [
            ("nu12", self.nu12, self.e1, self.e2),
            ("nu13", self.nu13, self.e1, self.e3),
            ("nu23", self.nu23, self.e2, self.e3),
        ] {
            if !(nu.is_finite() && nu.abs() < (ei / ej).sqrt()) {
                return Err(invalid(
                    format!("{name}.{k}"),
                    nu,
                    "not positive definite: |nu_ij| must be < sqrt(E_i/E_j)",
                ));
            }
        }
        let det = self.normal_determinant();
        if !(det > 0.0) {
            return Err(invalid(
                format!("{name}: 1 - nu12 nu21 - nu23 nu32 - nu31 nu13 - 2 nu21 nu32 nu13"),
                det,
                "not positive definite: must be > 0",
            ));
        }
        Ok(())
    }

    /// 1 − ν12ν21 − ν23ν32 − ν31ν13 − 2ν21ν32ν13 (> 0 for a positive definite material).
    pub fn normal_determinant(&self) -> Real {
        let nu21 = self.nu12 * self.e2 / self.e1;
        let nu31 = self.nu13 * self.e3 / self.e1;
        let nu32 = self.nu23 * self.e3 / self.e2;
        1.0 - self.nu12 * nu21 - self.nu23 * nu32 - nu31 * self.nu13 - 2.0 * nu21 * nu32 * self.nu13
    }

    /// D = S⁻¹ in the material axes.
    pub fn matrix(&self) -> Matrix6 {
        let mut s = Matrix6::zeros();
        s[(0, 0)] = 1.0 / self.e1;
        s[(1, 1)] = 1.0 / self.e2;
        s[(2, 2)] = 1.0 / self.e3;
        s[(0, 1)] = -self.nu12 / self.e1;
        s[(0, 2)] = -self.nu13 / self.e1;
        s[(1, 2)] = -self.nu23 / self.e2;
        s[(1, 0)] = s[(0, 1)];
        s[(2, 0)] = s[(0, 2)];
        s[(2, 1)] = s[(1, 2)];
        s[(3, 3)] = 1.0 / self.g23;
        s[(4, 4)] = 1.0 / self.g13;
        s[(5, 5)] = 1.0 / self.g12;
        let d = s.try_inverse().unwrap_or_else(Matrix6::zeros);
        (d + d.transpose()) * 0.5
    }
}

/// The isotropic D for Lamé constants (λ, μ).
pub fn isotropic_matrix(lambda: Real, mu: Real) -> Matrix6 {
    let mut d = Matrix6::zeros();
    for i in 0..3 {
        for j in 0..3 {
            d[(i, j)] = lambda;
        }
        d[(i, i)] += 2.0 * mu;
        d[(i + 3, i + 3)] = mu;
    }
    d
}

impl Elasticity {
    /// Checks the constants; the error names `name` (the material) and the failing value.
    pub fn validate(&self, name: &str) -> Result<(), FeError> {
        match self {
            Elasticity::Isotropic { young, poisson } => Material {
                young: *young,
                poisson: *poisson,
                density: 1.0,
            }
            .validate()
            .map_err(|e| match e {
                FeError::InvalidValue {
                    field,
                    value,
                    reason,
                } => invalid(
                    format!("{name}.{}", field.trim_start_matches("material.")),
                    value,
                    reason,
                ),
                other => other,
            }),
            Elasticity::Orthotropic(o) => o.validate(name),
            Elasticity::TransverselyIsotropic(t) => t.orthotropic().validate(name),
            Elasticity::Anisotropic { stiffness } => {
                let d = Matrix6::from_fn(|i, j| stiffness[i][j]);
                if let Some(v) = d.iter().find(|v| !v.is_finite()) {
                    return Err(invalid(format!("{name}.stiffness"), *v, "must be finite"));
                }
                let asym = (d - d.transpose()).amax();
                if asym > 1e-12 * d.amax() {
                    return Err(invalid(
                        format!("{name}.stiffness: largest |D_ij - D_ji|"),
                        asym,
                        "the 6x6 matrix must be symmetric",
                    ));
                }
                let e = d.symmetric_eigenvalues();
                let min = e.iter().copied().fold(Real::INFINITY, Real::min);
                if !(min > 1e-14 * d.amax()) {
                    return Err(invalid(
                        format!("{name}.stiffness: smallest eigenvalue"),
                        min,
                        "not positive definite: the 6x6 matrix needs eigenvalues > 0",
                    ));
                }
                Ok(())
            }
        }
    }

    /// D in the material axes.
    pub fn matrix(&self) -> Matrix6 {
        match self {
            Elasticity::Isotropic { young, poisson } => {
                let mu = young / (2.0 * (1.0 + poisson));
                let lambda = young * poisson / ((1.0 + poisson) * (1.0 - 2.0 * poisson));
                isotropic_matrix(lambda, mu)
            }
            Elasticity::Orthotropic(o) => o.matrix(),
            Elasticity::TransverselyIsotropic(t) => t.orthotropic().matrix(),
            Elasticity::Anisotropic { stiffness } => Matrix6::from_fn(|i, j| stiffness[i][j]),
        }
    }
}

fn norm(v: [Real; 3]) -> Real {
    (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt()
}

fn cross(a: [Real; 3], b: [Real; 3]) -> [Real; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Orthonormal right-handed frame from a first axis and a vector in the 1–2 plane; `None`
/// when they are (nearly) parallel or zero.
pub fn frame_from(e1: [Real; 3], e2: [Real; 3]) -> Option<Frame> {
    let n1 = norm(e1);
    if !(n1 > 0.0 && n1.is_finite()) {
        return None;
    }
    let a = e1.map(|v| v / n1);
    let d = a[0] * e2[0] + a[1] * e2[1] + a[2] * e2[2];
    let b = [e2[0] - d * a[0], e2[1] - d * a[1], e2[2] - d * a[2]];
    let nb = norm(b);
    if !(nb > 1e-9 * norm(e2)) || !nb.is_finite() {
        return None;
    }
    let b = b.map(|v| v / nb);
    Some([a, b, cross(a, b)])
}

/// Bond matrix M of the rotation whose columns are the frame's axes (material → global
/// components): σ_global = M σ_material, D_global = M D Mᵀ.
pub fn bond(frame: &Frame) -> Matrix6 {
    // q[i][k]: global component i of material axis k.
    let q = |i: usize, k: usize| frame[k][i];
    const PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (1, 2), (0, 2), (0, 1)];
    Matrix6::from_fn(|v, w| {
        let ((i, j), (k, l)) = (PAIRS[v], PAIRS[w]);
        if k == l {
            q(i, k) * q(j, l)
        } else {
            q(i, k) * q(j, l) + q(i, l) * q(j, k)
        }
    })
}

/// D rotated from the material axes `frame` to the global axes.
pub fn rotate(d: &Matrix6, frame: &Frame) -> Matrix6 {
    let m = bond(frame);
    let r = m * d * m.transpose();
    (r + r.transpose()) * 0.5
}

/// The cylindrical frame (radial, circumferential, axial) at `x`, or `None` on the axis.
pub fn cylindrical_frame(origin: [Real; 3], axis: [Real; 3], x: [Real; 3]) -> Option<Frame> {
    let na = norm(axis);
    if !(na > 0.0 && na.is_finite()) {
        return None;
    }
    let e3 = axis.map(|v| v / na);
    let r = [x[0] - origin[0], x[1] - origin[1], x[2] - origin[2]];
    let d = r[0] * e3[0] + r[1] * e3[1] + r[2] * e3[2];
    let rp = [r[0] - d * e3[0], r[1] - d * e3[1], r[2] - d * e3[2]];
    let nr = norm(rp);
    if !(nr > 1e-12 * norm(r).max(na)) {
        return None;
    }
    let e1 = rp.map(|v| v / nr);
    Some([e1, cross(e3, e1), e3])
}

impl SolidMaterial {
    /// Checks density, elastic constants and axes; errors name `name` and the value.
    pub fn validate(&self, name: &str) -> Result<(), FeError> {
        if !(self.density > 0.0 && self.density.is_finite()) {
            return Err(invalid(
                format!("{name}.density"),
                self.density,
                "must be finite and > 0",
            ));
        }
        self.elasticity.validate(name)?;
        match &self.axes {
            MaterialAxes::Global => {}
            MaterialAxes::Rectangular { e1, e2 } => {
                if frame_from(*e1, *e2).is_none() {
                    return Err(invalid(
                        format!("{name}.axes: |e1 x e2| / (|e1| |e2|)"),
                        norm(cross(*e1, *e2)) / (norm(*e1) * norm(*e2)),
                        "e1 and e2 must be non-zero and not parallel",
                    ));
                }
            }
            MaterialAxes::Cylindrical { axis, origin } => {
                let n = norm(*axis);
                if !(n > 0.0 && n.is_finite()) || origin.iter().any(|v| !v.is_finite()) {
                    return Err(invalid(
                        format!("{name}.axes.axis length"),
                        n,
                        "the axis must be finite and non-zero, the origin finite",
                    ));
                }
            }
            MaterialAxes::PerCell(frames) => {
                for (c, f) in frames.iter().enumerate() {
                    let mut err: Real = 0.0;
                    for a in 0..3 {
                        for b in 0..3 {
                            let d: Real = (0..3).map(|i| f[a][i] * f[b][i]).sum();
                            err = err.max((d - if a == b { 1.0 } else { 0.0 }).abs());
                        }
                    }
                    let handed = cross(f[0], f[1]);
                    let det: Real = (0..3).map(|i| handed[i] * f[2][i]).sum();
                    if !(err < 1e-9) || !(det > 0.0) {
                        return Err(invalid(
                            format!("{name}.axes of cell {c}: largest |e_a . e_b - delta_ab|"),
                            err,
                            "each cell's frame must be orthonormal and right-handed",
                        ));
                    }
                }
            }
        }
        Ok(())
    }

    /// Lamé constants when the material is isotropic.
    pub fn isotropic_lame(&self) -> Option<(Real, Real)> {
        match self.elasticity {
            Elasticity::Isotropic { young, poisson } => Some(
                Material {
                    young,
                    poisson,
                    density: self.density,
                }
                .lame(),
            ),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests;
