//! Dense LU with partial pivoting on preallocated storage (no allocation per factorisation).
//!
//! The factorisation is faer's. The solve with one right-hand side (every Newton iteration)
//! is the textbook column-oriented substitution, x ← P b, then L (unit lower) forward and U
//! backward, each column an AXPY on a contiguous slice vectorised with AVX2/FMA where the CPU
//! has them ([`super::sparse::dispatch`]): for the ~200 unknowns of the study brake's reduced
//! saddle system it takes a third of the time of faer's blocked solve (which is built for
//! many right-hand sides), with the same flops in a different order (round-off).

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
    /// P b during a solve.
    work: Vec<Real>,
}

/// The substitutions of [`DenseLu::solve`], SIMD-dispatched.
struct Substitute<'a> {
    lu: &'a Mat<Real>,
    perm: &'a [usize],
    b: &'a mut [Real],
    x: &'a mut [Real],
}

impl pulp::WithSimd for Substitute<'_> {
    type Output = ();
    #[inline(always)]
    fn with_simd<S: pulp::Simd>(self, _simd: S) {
        let n = self.x.len();
        let x = self.x;
        for (xi, &p) in x.iter_mut().zip(self.perm) {
            *xi = self.b[p];
        }
        // L y = P b (unit diagonal), column by column.
        for j in 0..n {
            let xj = x[j];
            let col = &self.lu.col_as_slice(j)[j + 1..n];
            for (xi, l) in x[j + 1..n].iter_mut().zip(col) {
                *xi -= l * xj;
            }
        }
        // U x = y, column by column from the last.
        for j in (0..n).rev() {
            let col = &self.lu.col_as_slice(j)[..=j];
            x[j] /= col[j];
            let xj = x[j];
            for (xi, u) in x[..j].iter_mut().zip(col) {
                *xi -= u * xj;
            }
        }
        self.b.copy_from_slice(x);
    }
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
            work: vec![0.0; n],
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
        super::sparse::dispatch(Substitute {
            lu: &self.a,
            perm: &self.perm,
            b,
            x: &mut self.work,
        });
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

#[cfg(test)]
mod tests {
    use super::*;

    /// The substitutions against faer's solve with the same factors, and against A x = b.
    #[test]
    fn solve_matches_faer_and_the_matrix() {
        let n = 37;
        let a = Mat::from_fn(n, n, |i, j| {
            let x = ((i * 31 + j * 17) % 23) as Real / 23.0 - 0.5;
            if i == j {
                x + 0.1
            } else {
                x
            }
        });
        let mut lu = DenseLu::new(n);
        lu.a.copy_from(&a);
        lu.factor("test", 0.0).unwrap();
        let b: Vec<Real> = (0..n).map(|i| (0.3 * i as Real).sin()).collect();
        let mut x = b.clone();
        lu.solve(&mut x).unwrap();
        let mut want = Mat::from_fn(n, 1, |i, _| b[i]);
        lu.solve_mat(want.as_mut()).unwrap();
        let scale = x.iter().fold(0.0 as Real, |m, v| m.max(v.abs()));
        for i in 0..n {
            assert!((x[i] - want[(i, 0)]).abs() <= 1e-13 * scale, "{i}");
            let ax: Real = (0..n).map(|j| a[(i, j)] * x[j]).sum();
            assert!((ax - b[i]).abs() <= 1e-12 * scale, "{i}");
        }
    }
}
