//! Interface reduction of part of a component's Craig–Bampton boundary.
//!
//! A component's boundary DOFs u_b split into DOFs kept as physical coordinates (shared with
//! other components) and *interface* DOFs that move in a given basis: u_f = L p, L of size
//! n_f × n_p with n_p ≪ n_f. The Craig–Bampton reduction then uses the boundary coordinates
//! x_b = [u_kept, p] instead of u_b: the constraint modes are Ψ = −K_ii⁻¹ K_ib L (n_p solves
//! instead of n_f), and every reduced product scales with n_p.
//!
//! [`polynomial_basis`] builds L from the interface nodes' positions: per patch and per
//! direction, tensor Legendre polynomials of total degree ≤ d in the patch's principal
//! coordinates, orthonormalised over the patch's DOFs. Degree ≥ 1 contains the rigid-body
//! motions of each patch, and as d grows the basis spans every nodal field of the patch, so
//! the reduction tends to the exact Craig–Bampton one.

use super::partition::{Blocks, Sparse};
use crate::error::ReductionError;
use faer::{Mat, MatRef, Side};
use squeal_meshes::Real;

/// The interface DOFs of a component and their basis: u[dofs] = basis · p.
#[derive(Debug, Clone)]
pub struct InterfaceBasis {
    /// Free-DOF indices of the interface DOFs (disjoint from the kept boundary DOFs).
    pub dofs: Vec<usize>,
    /// L: `dofs.len()` × n_p, orthonormal columns (LᵀL = I).
    pub basis: Mat<Real>,
}

impl InterfaceBasis {
    /// Number of interface coordinates n_p.
    pub fn n_coords(&self) -> usize {
        self.basis.ncols()
    }

    /// Checks shapes and finiteness; the error names what is wrong.
    pub fn validate(&self) -> Result<(), ReductionError> {
        if self.basis.nrows() != self.dofs.len() {
            return Err(ReductionError::ShapeMismatch {
                what: "interface basis".into(),
                rows: self.basis.nrows(),
                cols: self.basis.ncols(),
                expected_rows: self.dofs.len(),
                expected_cols: self.basis.ncols(),
            });
        }
        if self.basis.ncols() > self.dofs.len() {
            return Err(ReductionError::InvalidOption {
                field: "interface.basis",
                value: self.basis.ncols().to_string(),
                reason: format!(
                    "more interface coordinates than interface DOFs ({})",
                    self.dofs.len()
                ),
            });
        }
        for j in 0..self.basis.ncols() {
            for i in 0..self.basis.nrows() {
                let v = self.basis[(i, j)];
                if !v.is_finite() {
                    return Err(ReductionError::NonFinite {
                        what: "interface basis".into(),
                        row: i,
                        col: j,
                        value: v,
                    });
                }
            }
        }
        Ok(())
    }
}

/// One interface DOF as [`polynomial_basis`] takes it: the point of its node, its direction
/// (0, 1, 2 = x, y, z) and the patch it belongs to (patches get separate polynomials).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct InterfaceDof {
    pub point: [Real; 3],
    pub direction: usize,
    pub patch: usize,
}

/// Orthonormal polynomial interface basis of total degree ≤ `degree` per patch and direction.
///
/// For each (patch, direction) the functions P_a(s₁) P_b(s₂) P_c(s₃), a + b + c ≤ degree (P_n
/// the Legendre polynomials, s the patch's principal coordinates scaled to [−1, 1]; a
/// coordinate along which the patch is flat, extent < 1e-6 of the largest, is left out), are
/// evaluated at the DOFs of that group and orthonormalised (modified Gram–Schmidt, twice); a
/// function that is dependent on the previous ones at the nodes (norm falling below 1e-8 of
/// its own) is dropped. Columns of different groups have disjoint supports.
pub fn polynomial_basis(dofs: &[InterfaceDof], degree: usize) -> Result<Mat<Real>, ReductionError> {
    basis_in_frame(dofs, degree, false).map(|(l, _)| l)
}

/// What one column of a [`polynomial_basis_graded`] basis is: its group (patch, direction) and
/// the monomial exponents it started from (total degree = their sum).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub struct BasisColumn {
    pub patch: usize,
    pub direction: usize,
    pub powers: [usize; 3],
}

impl BasisColumn {
    /// Total polynomial degree of the column.
    pub fn degree(&self) -> usize {
        self.powers.iter().sum()
    }
}

/// [`polynomial_basis`] with each column's [`BasisColumn`].
///
/// The bases are nested column by column: within a (patch, direction) group the monomials are
/// taken by increasing total degree and orthonormalised in that order, so the columns of
/// degree ≤ d of the degree-D basis (D ≥ d) are the degree-d basis's columns, with the same
/// values — the interface ladder ([`super::InterfaceLadder`]) reuses their constraint modes.
pub fn polynomial_basis_graded(
    dofs: &[InterfaceDof],
    degree: usize,
) -> Result<(Mat<Real>, Vec<BasisColumn>), ReductionError> {
    basis_in_frame(dofs, degree, false)
}

/// [`polynomial_basis`] in each patch's two largest principal coordinates only: for surfaces
/// that are not flat at the node scale (a separator of a mesh, a layer of nodes), the
/// polynomials of the surface's plane.
pub(crate) fn polynomial_basis_2d(
    dofs: &[InterfaceDof],
    degree: usize,
) -> Result<Mat<Real>, ReductionError> {
    basis_in_frame(dofs, degree, true).map(|(l, _)| l)
}

fn basis_in_frame(
    dofs: &[InterfaceDof],
    degree: usize,
    planar: bool,
) -> Result<(Mat<Real>, Vec<BasisColumn>), ReductionError> {
    if let Some((i, d)) = dofs
        .iter()
        .enumerate()
        .find(|(_, d)| d.direction > 2 || d.point.iter().any(|x| !x.is_finite()))
    {
        return Err(ReductionError::InvalidOption {
            field: "interface dof",
            value: format!("{d:?}"),
            reason: format!("DOF {i}: direction must be 0..=2 and the point finite"),
        });
    }
    let n_patch = dofs.iter().map(|d| d.patch + 1).max().unwrap_or(0);
    let mut columns: Vec<Vec<Real>> = Vec::new();
    let mut tags: Vec<BasisColumn> = Vec::new();
    for patch in 0..n_patch {
        let members: Vec<usize> = (0..dofs.len())
            .filter(|&i| dofs[i].patch == patch)
            .collect();
        if members.is_empty() {
            continue;
        }
        let mut frame =
            PatchFrame::new(&members.iter().map(|&i| dofs[i].point).collect::<Vec<_>>())?;
        if planar {
            frame.flatten_thinnest();
        }
        for dir in 0..3 {
            let rows: Vec<usize> = members
                .iter()
                .copied()
                .filter(|&i| dofs[i].direction == dir)
                .collect();
            if rows.is_empty() {
                continue;
            }
            let coords: Vec<[Real; 3]> = rows.iter().map(|&i| frame.local(dofs[i].point)).collect();
            let mut kept: Vec<Vec<Real>> = Vec::new();
            for powers in frame.monomials(degree) {
                let mut v: Vec<Real> = coords
                    .iter()
                    .map(|s| (0..3).map(|a| legendre(powers[a], s[a])).product())
                    .collect();
                if orthonormalise(&mut v, &kept) {
                    kept.push(v);
                    tags.push(BasisColumn {
                        patch,
                        direction: dir,
                        powers,
                    });
                }
            }
            for v in kept {
                let mut col = vec![0.0; dofs.len()];
                for (&r, x) in rows.iter().zip(v) {
                    col[r] = x;
                }
                columns.push(col);
            }
        }
    }
    let l = Mat::from_fn(dofs.len(), columns.len(), |i, j| columns[j][i]);
    Ok((l, tags))
}

/// Legendre polynomial P_n(x) (three-term recurrence).
fn legendre(n: usize, x: Real) -> Real {
    let (mut p0, mut p1) = (1.0, x);
    if n == 0 {
        return p0;
    }
    for k in 1..n {
        let k = k as Real;
        let p2 = ((2.0 * k + 1.0) * x * p1 - k * p0) / (k + 1.0);
        p0 = p1;
        p1 = p2;
    }
    p1
}

/// Makes `v` orthonormal to the unit vectors `basis` (modified Gram–Schmidt, two passes) and
/// normalises it; false when it is dependent on them (or zero).
fn orthonormalise(v: &mut [Real], basis: &[Vec<Real>]) -> bool {
    let norm0 = v.iter().map(|x| x * x).sum::<Real>().sqrt();
    if norm0 == 0.0 {
        return false;
    }
    for _ in 0..2 {
        for b in basis {
            let d: Real = v.iter().zip(b).map(|(x, y)| x * y).sum();
            v.iter_mut().zip(b).for_each(|(x, y)| *x -= d * y);
        }
    }
    let norm = v.iter().map(|x| x * x).sum::<Real>().sqrt();
    if norm < 1e-8 * norm0 {
        return false;
    }
    v.iter_mut().for_each(|x| *x /= norm);
    true
}

/// A patch's principal frame: centroid, principal axes, half-extents.
struct PatchFrame {
    centre: [Real; 3],
    axes: [[Real; 3]; 3],
    half: [Real; 3],
}

impl PatchFrame {
    fn new(points: &[[Real; 3]]) -> Result<Self, ReductionError> {
        let n = points.len() as Real;
        let mut centre = [0.0; 3];
        for p in points {
            (0..3).for_each(|a| centre[a] += p[a] / n);
        }
        let mut cov = Mat::<Real>::zeros(3, 3);
        for p in points {
            for a in 0..3 {
                for b in 0..3 {
                    cov[(a, b)] += (p[a] - centre[a]) * (p[b] - centre[b]);
                }
            }
        }
        let eig = cov
            .self_adjoint_eigen(Side::Lower)
            .map_err(|e| ReductionError::Eigen {
                what: "principal axes of an interface patch".into(),
                n: 3,
                detail: format!("{e:?}"),
            })?;
        let u = eig.U();
        let mut axes = [[0.0; 3]; 3];
        for (c, axis) in axes.iter_mut().enumerate() {
            *axis = [u[(0, c)], u[(1, c)], u[(2, c)]];
        }
        let mut half = [0.0; 3];
        for p in points {
            for a in 0..3 {
                let s: Real = (0..3).map(|k| (p[k] - centre[k]) * axes[a][k]).sum();
                half[a] = Real::max(half[a], s.abs());
            }
        }
        Ok(Self { centre, axes, half })
    }

    /// Treats the patch's smallest principal extent as flat.
    fn flatten_thinnest(&mut self) {
        let k = (0..3)
            .min_by(|&a, &b| self.half[a].total_cmp(&self.half[b]))
            .unwrap_or(0);
        self.half[k] = 0.0;
    }

    /// Principal coordinates scaled to [−1, 1] (0 along a flat direction).
    fn local(&self, p: [Real; 3]) -> [Real; 3] {
        let big = self.half.iter().fold(0.0, |a: Real, &b| a.max(b));
        let mut s = [0.0; 3];
        for a in 0..3 {
            if self.half[a] > 1e-6 * big {
                let x: Real = (0..3)
                    .map(|k| (p[k] - self.centre[k]) * self.axes[a][k])
                    .sum();
                s[a] = x / self.half[a];
            }
        }
        s
    }

    /// Exponents (a, b, c) of total degree ≤ `degree`, by increasing degree; none along a
    /// flat direction.
    fn monomials(&self, degree: usize) -> Vec<[usize; 3]> {
        let big = self.half.iter().fold(0.0, |a: Real, &b| a.max(b));
        let live: Vec<bool> = self.half.iter().map(|&h| h > 1e-6 * big).collect();
        let mut out = Vec::new();
        for total in 0..=degree {
            for a in 0..=total {
                for b in 0..=(total - a) {
                    let c = total - a - b;
                    let e = [a, b, c];
                    if (0..3).all(|k| live[k] || e[k] == 0) {
                        out.push(e);
                    }
                }
            }
        }
        out
    }
}

/// The boundary blocks in the coordinates x_b = [u_kept, p]: A_ib → A_ib L and
/// A_bb → Lᵀ A_bb L, with L = blockdiag(I_{n_kept}, `basis`) (the interface DOFs are the
/// boundary positions n_kept.. in `blocks`).
pub(crate) fn project_blocks(blocks: Blocks, n_kept: usize, basis: MatRef<'_, Real>) -> Blocks {
    let (ib, bb) = project_ib_bb(&blocks.ib, BbRef::Dense(&blocks.bb), n_kept, basis);
    Blocks {
        ii: blocks.ii,
        ib,
        bb,
    }
}

/// The boundary blocks of [`project_blocks`] alone, from borrowed A_ib and A_bb.
pub(crate) fn project_ib_bb(
    ib: &Sparse,
    bb: BbRef<'_>,
    n_kept: usize,
    basis: MatRef<'_, Real>,
) -> (Sparse, Mat<Real>) {
    let (nb, np) = (ib.ncols(), basis.ncols());
    let nx = n_kept + np;
    let ni = ib.nrows();
    let (cp, ri, v) = (ib.symbolic().col_ptr(), ib.symbolic().row_idx(), ib.val());
    // Interior rows touched by the interface columns, and A_ib,f L on them (dense).
    let mut row_slot = vec![usize::MAX; ni];
    let mut rows = Vec::new();
    for j in n_kept..nb {
        for p in cp[j]..cp[j + 1] {
            if row_slot[ri[p]] == usize::MAX {
                row_slot[ri[p]] = rows.len();
                rows.push(ri[p]);
            }
        }
    }
    let mut dense = Mat::<Real>::zeros(rows.len(), np);
    for j in n_kept..nb {
        let lrow = basis.row(j - n_kept);
        for p in cp[j]..cp[j + 1] {
            let r = row_slot[ri[p]];
            for c in 0..np {
                dense[(r, c)] += v[p] * lrow[c];
            }
        }
    }
    let mut cols: Vec<Vec<(usize, Real)>> = Vec::with_capacity(nx);
    for j in 0..n_kept {
        cols.push((cp[j]..cp[j + 1]).map(|p| (ri[p], v[p])).collect());
    }
    for c in 0..np {
        let mut col: Vec<(usize, Real)> = rows
            .iter()
            .enumerate()
            .filter(|&(r, _)| dense[(r, c)] != 0.0)
            .map(|(r, &i)| (i, dense[(r, c)]))
            .collect();
        col.sort_by_key(|e| e.0);
        cols.push(col);
    }
    let ib = super::partition::from_columns(ni, cols);
    // Lᵀ A_bb L.
    let nf = nb - n_kept;
    let mut out = Mat::<Real>::zeros(nx, nx);
    let (kf, ff_w) = match bb {
        BbRef::Dense(bb) => {
            let a_kk = bb.submatrix(0, 0, n_kept, n_kept);
            out.submatrix_mut(0, 0, n_kept, n_kept).copy_from(a_kk);
            let a_kf = bb.submatrix(0, n_kept, n_kept, nf);
            let a_ff = bb.submatrix(n_kept, n_kept, nf, nf);
            (a_kf * basis, a_ff * basis)
        }
        BbRef::Sparse(bb) => {
            // A_kf L and A_ff L from the stored entries (A_bb symmetric, full storage).
            let (cp, ri, v) = (bb.symbolic().col_ptr(), bb.symbolic().row_idx(), bb.val());
            let mut kf = Mat::<Real>::zeros(n_kept, np);
            let mut ffw = Mat::<Real>::zeros(nf, np);
            for j in 0..nb {
                for p in cp[j]..cp[j + 1] {
                    let (i, a) = (ri[p], v[p]);
                    match (i < n_kept, j < n_kept) {
                        (true, true) => out[(i, j)] = a,
                        (_, true) => {}
                        (true, false) => {
                            let l = basis.row(j - n_kept);
                            for c in 0..np {
                                kf[(i, c)] += a * l[c];
                            }
                        }
                        (false, false) => {
                            let l = basis.row(j - n_kept);
                            for c in 0..np {
                                ffw[(i - n_kept, c)] += a * l[c];
                            }
                        }
                    }
                }
            }
            (kf, ffw)
        }
    };
    if np > 0 {
        out.submatrix_mut(0, n_kept, n_kept, np).copy_from(&kf);
        out.submatrix_mut(n_kept, 0, np, n_kept)
            .copy_from(kf.transpose());
        let ff = basis.transpose() * ff_w;
        out.submatrix_mut(n_kept, n_kept, np, np).copy_from(&ff);
    }
    (ib, out)
}

/// A boundary block A_bb as [`project_ib_bb`] reads it: dense, or sparse (full symmetric
/// storage; the interface ladder keeps it so over every interface DOF).
#[derive(Clone, Copy)]
pub(crate) enum BbRef<'a> {
    Dense(&'a Mat<Real>),
    Sparse(&'a Sparse),
}

/// The nonzeros of a dense matrix as a sparse one.
pub(crate) fn sparse_of(a: &Mat<Real>) -> Sparse {
    let cols = (0..a.ncols())
        .map(|j| {
            (0..a.nrows())
                .filter(|&i| a[(i, j)] != 0.0)
                .map(|i| (i, a[(i, j)]))
                .collect()
        })
        .collect();
    super::partition::from_columns(a.nrows(), cols)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The three DOFs of every node of an nx × ny grid in the plane at height z, one patch.
    fn grid_dofs(nx: usize, ny: usize, z: Real) -> Vec<InterfaceDof> {
        (0..nx * ny)
            .map(|k| [(k % nx) as Real * 0.1, (k / nx) as Real * 0.07, z])
            .flat_map(|p| {
                (0..3).map(move |d| InterfaceDof {
                    point: p,
                    direction: d,
                    patch: 0,
                })
            })
            .collect()
    }

    #[test]
    fn basis_is_orthonormal_and_counts_monomials_of_a_flat_patch() {
        let dofs = grid_dofs(6, 5, 0.3);
        for (degree, per_dir) in [(0, 1), (1, 3), (2, 6), (3, 10)] {
            let l = polynomial_basis(&dofs, degree).unwrap();
            assert_eq!(l.ncols(), 3 * per_dir, "degree {degree}");
            let g = l.transpose() * &l;
            let e = (g - Mat::<Real>::identity(l.ncols(), l.ncols())).norm_max();
            assert!(e < 1e-12, "LᵀL − I = {e:e}");
        }
        // A basis spanning every nodal field: 30 nodes per direction.
        let l = polynomial_basis(&dofs, 12).unwrap();
        assert_eq!(l.ncols(), 90);
    }

    #[test]
    fn degree_one_contains_rigid_rotations() {
        let dofs = grid_dofs(5, 4, 0.0);
        let l = polynomial_basis(&dofs, 1).unwrap();
        // u = ω × x with ω = (0.3, −0.2, 0.5).
        let w = [0.3, -0.2, 0.5];
        let u: Vec<Real> = dofs
            .iter()
            .map(|d| {
                let x = d.point;
                let r = [
                    w[1] * x[2] - w[2] * x[1],
                    w[2] * x[0] - w[0] * x[2],
                    w[0] * x[1] - w[1] * x[0],
                ];
                r[d.direction]
            })
            .collect();
        let uu = Mat::from_fn(u.len(), 1, |i, _| u[i]);
        let resid = &uu - &l * (l.transpose() * &uu);
        assert!(resid.norm_l2() < 1e-12 * uu.norm_l2());
    }
}
