//! Dense LU with partial pivoting on preallocated storage (no allocation per factorisation).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::lu::partial_pivoting::{factor, solve};
use faer::perm::PermRef;
use faer::{Mat, MatMut, Par};

use crate::{Real, SolverError};

/// A square matrix, filled by the caller, factorised in place as P A = L U.
pub(crate) struct DenseLu {
    /// The matrix before `factor`, its L\U factors after.
    pub a: Mat<Real>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
    factored: bool,
}

impl DenseLu {
    pub fn new(n: usize) -> Self {
        let req = factor::lu_in_place_scratch::<usize, Real>(n, n, Par::Seq, Default::default())
            .or(solve::solve_in_place_scratch::<usize, Real>(n, 1, Par::Seq));
        Self {
            a: Mat::zeros(n, n),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
            factored: false,
        }
    }

    /// Factorise `a` in place. A pivot that is not finite or below n·ε·(largest pivot)
    /// is reported as singular.
    pub fn factor(&mut self, what: &'static str, t: Real) -> Result<(), SolverError> {
        self.factored = false;
        let n = self.a.nrows();
        let stack = MemStack::new(&mut self.mem);
        factor::lu_in_place(
            self.a.as_mut(),
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            stack,
            Default::default(),
        );
        let mut max_pivot: Real = 0.0;
        for i in 0..n {
            let p = self.a[(i, i)];
            if !p.is_finite() {
                return Err(SolverError::NonFinite {
                    what,
                    t,
                    index: i,
                    value: p,
                });
            }
            max_pivot = max_pivot.max(p.abs());
        }
        let floor = n as Real * Real::EPSILON * max_pivot;
        for i in 0..n {
            let p = self.a[(i, i)];
            if p.abs() <= floor || p == 0.0 {
                return Err(SolverError::SingularMatrix {
                    what,
                    t,
                    index: i,
                    pivot: p,
                    max_pivot,
                });
            }
        }
        self.factored = true;
        Ok(())
    }

    /// Solve A x = b in place.
    pub fn solve(&mut self, b: &mut [Real]) -> Result<(), SolverError> {
        let n = self.a.nrows();
        if !self.factored {
            return Err(SolverError::Callback {
                t: Real::NAN,
                message: "solve requested before a successful factorisation".into(),
            });
        }
        if b.len() != n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand side of the dense LU solve",
                expected: n,
                got: b.len(),
            });
        }
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        let stack = MemStack::new(&mut self.mem);
        solve::solve_in_place(self.a.as_ref(), self.a.as_ref(), perm, rhs, Par::Seq, stack);
        Ok(())
    }

    /// Solve A X = B in place for the columns of `b` (scratch allocated per call: for the
    /// many right-hand sides of a set-up, not for every Newton iteration).
    pub fn solve_mat(&mut self, b: MatMut<'_, Real>) -> Result<(), SolverError> {
        let n = self.a.nrows();
        if !self.factored {
            return Err(SolverError::Callback {
                t: Real::NAN,
                message: "solve requested before a successful factorisation".into(),
            });
        }
        if b.nrows() != n {
            return Err(SolverError::DimensionMismatch {
                what: "right-hand sides of the dense LU solve",
                expected: n,
                got: b.nrows(),
            });
        }
        let perm = PermRef::new_checked(&self.perm, &self.perm_inv, n);
        let mut mem = MemBuffer::new(solve::solve_in_place_scratch::<usize, Real>(
            n,
            b.ncols(),
            Par::Seq,
        ));
        let stack = MemStack::new(&mut mem);
        solve::solve_in_place(self.a.as_ref(), self.a.as_ref(), perm, b, Par::Seq, stack);
        Ok(())
    }
}
