//! Interface reduction at increasing polynomial degree on one factorisation.
//!
//! Choosing an interface degree to a tolerance reduces the same component with the nested
//! polynomial bases L_d ⊂ L_{d+s} ⊂ … ([`super::polynomial_basis_graded`]). Only the boundary's
//! motion changes from one degree to the next: the partition (every interface DOF is a
//! boundary DOF whatever the degree), the K_ii factor and the fixed-interface modes Φ are the
//! same, and the constraint mode of an interface column, Ψ_c = −K_ii⁻¹ K_ib,f L_c, depends on
//! that column alone. [`InterfaceLadder`] keeps all three and solves, at each degree, only the
//! columns the previous degrees did not have.

use super::interface::{polynomial_basis_graded, BasisColumn, InterfaceBasis, InterfaceDof};
use super::model::CbModel;
use super::options::CbOptions;
use super::partition::{check_square, from_columns, Sparse};
use super::reduce::{reduce_interface, Interior};
use crate::error::ReductionError;
use faer::Mat;
use squeal_meshes::Real;
use std::collections::HashMap;
use std::time::Instant;

/// A component's Craig–Bampton reduction with its interface DOFs in polynomial bases of any
/// degree, sharing one K_ii factor, one set of fixed-interface modes and the constraint modes
/// of the columns already solved.
///
/// Each [`InterfaceLadder::reduce`] gives the same model as [`reduce_interface`] with
/// [`super::polynomial_basis`] of that degree (to round-off: the same factor and modes, the
/// same columns). Memory: the constraint modes of every column solved so far (n_i × (kept +
/// the largest degree's coordinates)) and the unprojected boundary blocks (A_bb sparse),
/// besides one model's. No damping matrix.
///
/// A component that the options substructure (`substructures.above_dofs`) is reduced anew at
/// each degree by [`reduce_interface`] (the substructured path has no shared factor).
pub struct InterfaceLadder {
    boundary: Vec<usize>,
    dofs: Vec<usize>,
    points: Vec<InterfaceDof>,
    opts: CbOptions,
    inner: Inner,
    n_solves: usize,
}

enum Inner {
    Shared {
        interior: Box<Interior>,
        /// Constraint modes of the kept boundary DOFs.
        kept_psi: Mat<Real>,
        /// Per basis column: the column of L it was solved for and its constraint mode.
        solved: HashMap<BasisColumn, (Vec<Real>, Vec<Real>)>,
    },
    Rebuild {
        k: Sparse,
        m: Sparse,
        coords: Vec<[Real; 3]>,
    },
}

impl InterfaceLadder {
    /// Partitions the component (kept `boundary` DOFs, then the interface DOFs `dofs` with
    /// their `points`, in the same order), factorises K_ii, finds the fixed-interface modes and
    /// the kept DOFs' constraint modes.
    pub fn new(
        k: &Sparse,
        m: &Sparse,
        boundary: Vec<usize>,
        points: Vec<(usize, InterfaceDof)>,
        opts: &CbOptions,
        dof_coords: Option<&[[Real; 3]]>,
    ) -> Result<Self, ReductionError> {
        opts.validate()?;
        let n = k.nrows();
        check_square(k, n, "stiffness K")?;
        check_square(m, n, "mass M")?;
        if let Some(c) = dof_coords {
            if c.len() != n {
                return Err(ReductionError::InvalidOption {
                    field: "dof_coords",
                    value: c.len().to_string(),
                    reason: format!("one point per DOF: K has {n} rows"),
                });
            }
        }
        let (dofs, points): (Vec<usize>, Vec<InterfaceDof>) = points.into_iter().unzip();
        let n_interior = n.saturating_sub(boundary.len() + dofs.len());
        let substructured = matches!(
            (opts.substructures.above_dofs, dof_coords),
            (Some(above), Some(_)) if n_interior > above
        );
        let inner = match dof_coords {
            Some(c) if substructured => Inner::Rebuild {
                k: k.clone(),
                m: m.clone(),
                coords: c.to_vec(),
            },
            _ => {
                let t = Instant::now();
                let interior =
                    Interior::new(k, m, None, &boundary, &dofs, None, opts, dof_coords, t)?;
                let kept: Vec<usize> = (0..boundary.len()).collect();
                let kept_psi = interior.constraint_modes(&columns(interior.kib(), &kept), opts)?;
                Inner::Shared {
                    interior: Box::new(interior),
                    kept_psi,
                    solved: HashMap::new(),
                }
            }
        };
        let n_solves = match &inner {
            Inner::Shared { kept_psi, .. } => kept_psi.ncols(),
            Inner::Rebuild { .. } => 0,
        };
        Ok(Self {
            boundary,
            dofs,
            points,
            opts: opts.clone(),
            inner,
            n_solves,
        })
    }

    /// Interface DOFs (rows of every degree's basis).
    pub fn n_interface_dofs(&self) -> usize {
        self.dofs.len()
    }

    /// Constraint-mode solves made so far: the kept DOFs once, each interface column once (a
    /// rebuilt, substructured component: every reduction's boundary coordinates).
    pub fn n_constraint_solves(&self) -> usize {
        self.n_solves
    }

    /// The reduction with the interface DOFs in [`super::polynomial_basis`] of total degree ≤
    /// `degree`; only the columns no earlier call solved get new constraint modes.
    pub fn reduce(&mut self, degree: usize) -> Result<CbModel, ReductionError> {
        let t_start = Instant::now();
        let (l, tags) = polynomial_basis_graded(&self.points, degree)?;
        let basis = InterfaceBasis {
            dofs: self.dofs.clone(),
            basis: l,
        };
        basis.validate()?;
        match &mut self.inner {
            Inner::Rebuild { k, m, coords } => {
                let model = reduce_interface(
                    k,
                    m,
                    None,
                    &self.boundary,
                    Some(&basis),
                    &self.opts,
                    Some(coords),
                )?;
                self.n_solves += model.n_boundary_coords();
                Ok(model)
            }
            Inner::Shared {
                interior,
                kept_psi,
                solved,
            } => {
                let (kib, kbb) = interior.project_k(Some(basis.basis.as_ref()));
                let nk = self.boundary.len();
                // A column is reused when the same (group, monomial) was solved for the very
                // same values (nested bases: always; checked all the same).
                let fresh: Vec<usize> = (0..tags.len())
                    .filter(|&c| {
                        solved.get(&tags[c]).is_none_or(|(lc, _)| {
                            lc.iter()
                                .enumerate()
                                .any(|(r, &x)| x != basis.basis[(r, c)])
                        })
                    })
                    .collect();
                let t = Instant::now();
                let cols: Vec<usize> = fresh.iter().map(|&c| nk + c).collect();
                let psi_new = interior.constraint_modes(&columns(&kib, &cols), &self.opts)?;
                for (j, &c) in fresh.iter().enumerate() {
                    let lc = basis.basis.col(c).iter().copied().collect();
                    let pc = psi_new.col(j).iter().copied().collect();
                    solved.insert(tags[c], (lc, pc));
                }
                let solve_s = t.elapsed().as_secs_f64();
                self.n_solves += fresh.len();
                let ni = interior.n_interior();
                let mut psi = Mat::<Real>::zeros(ni, nk + tags.len());
                psi.submatrix_mut(0, 0, ni, nk).copy_from(&*kept_psi);
                for (c, tag) in tags.iter().enumerate() {
                    let (_, pc) = &solved[tag];
                    psi.col_mut(nk + c)
                        .iter_mut()
                        .zip(pc)
                        .for_each(|(a, b)| *a = *b);
                }
                interior.finish(
                    &self.boundary,
                    Some(&basis),
                    (kib, kbb),
                    psi,
                    (solve_s, fresh.len()),
                    &self.opts,
                    t_start,
                )
            }
        }
    }
}

/// The columns `cols` of `a`.
fn columns(a: &Sparse, cols: &[usize]) -> Sparse {
    let (cp, ri, v) = (a.symbolic().col_ptr(), a.symbolic().row_idx(), a.val());
    let out = cols
        .iter()
        .map(|&j| (cp[j]..cp[j + 1]).map(|p| (ri[p], v[p])).collect())
        .collect();
    from_columns(a.nrows(), out)
}
