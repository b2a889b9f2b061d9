//! Elimination of a diagonal block before a dense LU (the Craig–Bampton modal coordinates).
//!
//! # Reference
//! A Craig–Bampton model has, per component, the modal coordinates q of its fixed-interface
//! modes: M_qq = I, K_qq = diag ω², K_qb = 0, and element damping GE·K or G/W3·K keeps B_qq
//! diagonal; the modes couple only with their component's boundary DOFs (through M_qb, B_qb).
//! In a matrix A = c_m M + c_b B + c_k K ordered as (b, d) with A_dd diagonal,
//! $$\begin{bmatrix} A_{bb} & A_{bd} \\ A_{db} & A_{dd} \end{bmatrix}
//! \begin{bmatrix} x_b \\ x_d \end{bmatrix} = \begin{bmatrix} r_b \\ r_d \end{bmatrix}
//! \iff (A_{bb} − A_{bd} A_{dd}^{-1} A_{db})\, x_b = r_b − A_{bd} A_{dd}^{-1} r_d,\quad
//! x_d = A_{dd}^{-1} (r_d − A_{db} x_b),$$
//! so only the Schur complement S = A_bb − A_bd A_dd⁻¹ A_db (of the kept DOFs, with whatever
//! other rows and columns the caller borders it with, as long as they do not touch d) is
//! factorised. With M symmetric positive definite and B, K symmetric positive semi-definite,
//! A (c > 0) is symmetric positive definite, and eliminating any diagonal block of it is
//! stable (its Schur complement is again positive definite): no pivoting is lost.
//!
//! # Structure found, not assumed
//! [`DiagBlock::detect`] works on the union pattern of the matrices (exact zeros): a DOF can be
//! eliminated when the caller allows it (e.g. no constraint touches it, M_ii > 0) and no other
//! eliminated DOF couples with it. Among the allowed DOFs a maximal set with no coupling between
//! its members is chosen greedily, lowest degree first (a modal coordinate couples with its
//! component's boundary DOFs only, a boundary DOF with those and all its component's modes,
//! so the modes come first). The eliminated DOFs are grouped by the kept DOFs they couple
//! with (a component's modes share its boundary), so that S is updated by one matrix product
//! per group.

use faer::linalg::matmul::matmul;
use faer::{Accum, Mat, Par};

use crate::{Real, SolverError};

/// Eliminated DOFs sharing one coupling pattern.
#[derive(Debug, Clone)]
struct Group {
    /// Positions in [`DiagBlock::d`] of the group's DOFs.
    members: Vec<usize>,
    /// Positions in [`DiagBlock::kept`] of the kept DOFs the members couple with.
    rows: Vec<usize>,
    /// A[kept[rows], d[members]] (|rows| × |members|).
    u: Mat<Real>,
    /// A[d[members], kept[rows]] / a_dd, row by row (|members| × |rows|).
    w: Mat<Real>,
}

/// A diagonal block of a family of square matrices, found by pattern, with the workspace to
/// eliminate it from c_m M + c_b B + c_k K (allocated once in [`DiagBlock::detect`]).
#[derive(Debug, Clone)]
pub(crate) struct DiagBlock {
    n: usize,
    /// Eliminated DOFs, ascending.
    pub d: Vec<usize>,
    /// Kept DOFs, ascending: position p of the reduced matrix is DOF `kept[p]`.
    pub kept: Vec<usize>,
    groups: Vec<Group>,
    /// a_dd of the last [`DiagBlock::fill`] (in the order of `d`).
    diag: Vec<Real>,
    /// A_dd⁻¹ r_d of the last forward substitution.
    yd: Vec<Real>,
    /// U · W of one group.
    tmp: Mat<Real>,
    /// A group's U y or W x (the longest of its rows and members).
    work: Vec<Real>,
}

impl DiagBlock {
    /// Finds the block in the union pattern of `mats` (square, of one size n). `allowed(i)`
    /// says whether DOF i may be eliminated at all. Returns None when fewer than
    /// `min_count` DOFs can be eliminated.
    pub fn detect(
        mats: &[&Mat<Real>],
        allowed: impl Fn(usize) -> bool,
        min_count: usize,
    ) -> Option<Self> {
        let n = mats.first()?.nrows();
        let nz = |i: usize, j: usize| mats.iter().any(|a| a[(i, j)] != 0.0 || a[(j, i)] != 0.0);
        // Degree of each allowed DOF in the symmetric union pattern.
        let mut cand: Vec<(usize, usize)> = (0..n)
            .filter(|&i| allowed(i))
            .map(|i| ((0..n).filter(|&j| j != i && nz(i, j)).count(), i))
            .collect();
        cand.sort_unstable();
        let mut in_d = vec![false; n];
        for &(_, i) in &cand {
            if !(0..n).any(|j| in_d[j] && nz(i, j)) {
                in_d[i] = true;
            }
        }
        let d: Vec<usize> = (0..n).filter(|&i| in_d[i]).collect();
        if d.len() < min_count.max(1) {
            return None;
        }
        let kept: Vec<usize> = (0..n).filter(|&i| !in_d[i]).collect();
        // Group the eliminated DOFs by the kept positions they couple with.
        let mut patterns: Vec<(Vec<usize>, usize)> = d
            .iter()
            .enumerate()
            .map(|(pos, &i)| {
                let rows = (0..kept.len()).filter(|&p| nz(i, kept[p])).collect();
                (rows, pos)
            })
            .collect();
        patterns.sort();
        let mut groups: Vec<Group> = Vec::new();
        for (rows, pos) in patterns {
            match groups.last_mut() {
                Some(g) if g.rows == rows => g.members.push(pos),
                _ => groups.push(Group {
                    members: vec![pos],
                    rows,
                    u: Mat::zeros(0, 0),
                    w: Mat::zeros(0, 0),
                }),
            }
        }
        let (mut max_rows, mut max_members) = (0, 0);
        for g in &mut groups {
            g.u = Mat::zeros(g.rows.len(), g.members.len());
            g.w = Mat::zeros(g.members.len(), g.rows.len());
            max_rows = max_rows.max(g.rows.len());
            max_members = max_members.max(g.members.len());
        }
        Some(Self {
            n,
            diag: vec![0.0; d.len()],
            yd: vec![0.0; d.len()],
            d,
            kept,
            groups,
            tmp: Mat::zeros(max_rows, max_rows),
            work: vec![0.0; max_rows.max(max_members)],
        })
    }

    /// Number of groups (distinct coupling patterns).
    pub fn n_groups(&self) -> usize {
        self.groups.len()
    }

    /// Multiply–adds of one [`DiagBlock::subtract_schur`] (Σ |rows|² · |members|).
    pub fn schur_flops(&self) -> usize {
        self.groups
            .iter()
            .map(|g| g.rows.len() * g.rows.len() * g.members.len())
            .sum()
    }

    /// Forms a_dd, A_bd and A_dd⁻¹ A_db of A = Σ_m coef[m] mats[m] (the matrices of
    /// [`DiagBlock::detect`]). A diagonal entry that is zero or not finite is an error naming
    /// the DOF.
    pub fn fill(
        &mut self,
        coef: &[Real],
        mats: &[&Mat<Real>],
        what: &'static str,
        t: Real,
    ) -> Result<(), SolverError> {
        let entry = |i: usize, j: usize| -> Real {
            let mut s = 0.0;
            for (c, a) in coef.iter().zip(mats) {
                s += c * a[(i, j)];
            }
            s
        };
        let mut max_diag: Real = 0.0;
        for (pos, &i) in self.d.iter().enumerate() {
            let a = entry(i, i);
            if !a.is_finite() {
                return Err(SolverError::NonFinite {
                    what,
                    t,
                    index: i,
                    value: a,
                });
            }
            self.diag[pos] = a;
            max_diag = max_diag.max(a.abs());
        }
        for (pos, &i) in self.d.iter().enumerate() {
            let a = self.diag[pos];
            if a == 0.0 || a.abs() <= self.n as Real * Real::EPSILON * max_diag {
                return Err(SolverError::SingularMatrix {
                    what,
                    t,
                    index: i,
                    pivot: a,
                    max_pivot: max_diag,
                });
            }
        }
        for g in &mut self.groups {
            for (c, &pos) in g.members.iter().enumerate() {
                let i = self.d[pos];
                let inv = 1.0 / self.diag[pos];
                for (r, &p) in g.rows.iter().enumerate() {
                    let j = self.kept[p];
                    g.u[(r, c)] = entry(j, i);
                    g.w[(c, r)] = entry(i, j) * inv;
                }
            }
        }
        Ok(())
    }

    /// a[p, q] −= (A_bd A_dd⁻¹ A_db)[p, q] over the kept positions p, q < kept.len() of `a`.
    pub fn subtract_schur(&mut self, a: &mut Mat<Real>) {
        for g in &self.groups {
            let r = g.rows.len();
            let mut tmp = self.tmp.as_mut().submatrix_mut(0, 0, r, r);
            matmul(
                tmp.as_mut(),
                Accum::Replace,
                g.u.as_ref(),
                g.w.as_ref(),
                1.0,
                Par::Seq,
            );
            for (q, &cq) in g.rows.iter().enumerate() {
                let col = tmp.as_ref().col(q);
                for (p, &cp) in g.rows.iter().enumerate() {
                    a[(cp, cq)] -= col[p];
                }
            }
        }
    }

    /// Forward substitution: y_d = A_dd⁻¹ r_d (kept), and `reduced[p]` = r_b[p] −
    /// (A_bd y_d)[p] for the kept positions (`full` has the n DOF entries first; `reduced` the
    /// kept positions first, both may carry further entries the caller handles). Per group,
    /// U y_members is formed densely (column updates on a contiguous vector), then scattered.
    pub fn forward(&mut self, full: &[Real], reduced: &mut [Real]) {
        for (p, &i) in self.kept.iter().enumerate() {
            reduced[p] = full[i];
        }
        for (pos, &i) in self.d.iter().enumerate() {
            self.yd[pos] = full[i] / self.diag[pos];
        }
        for g in &self.groups {
            let t = &mut self.work[..g.rows.len()];
            t.fill(0.0);
            for (c, &pos) in g.members.iter().enumerate() {
                let y = self.yd[pos];
                for (tr, u) in t.iter_mut().zip(g.u.col_as_slice(c)) {
                    *tr += u * y;
                }
            }
            for (&p, tr) in g.rows.iter().zip(t.iter()) {
                reduced[p] -= tr;
            }
        }
    }

    /// Back substitution: from the solved kept values `reduced[p]`, `full[kept[p]]` = x_b and
    /// `full[d]` = y_d − A_dd⁻¹ A_db x_b (per group, W x_rows formed densely, then scattered).
    pub fn back(&mut self, reduced: &[Real], full: &mut [Real]) {
        for (p, &i) in self.kept.iter().enumerate() {
            full[i] = reduced[p];
        }
        for (pos, &i) in self.d.iter().enumerate() {
            full[i] = self.yd[pos];
        }
        for g in &self.groups {
            let t = &mut self.work[..g.members.len()];
            t.fill(0.0);
            for (r, &p) in g.rows.iter().enumerate() {
                let x = reduced[p];
                for (tc, w) in t.iter_mut().zip(g.w.col_as_slice(r)) {
                    *tc += w * x;
                }
            }
            for (&pos, tc) in g.members.iter().zip(t.iter()) {
                full[self.d[pos]] -= tc;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::linalg::lu::DenseLu;

    /// Two "components" in Craig–Bampton form: boundary DOFs coupled densely, modal DOFs
    /// (unit mass, diagonal stiffness) coupled by mass with their own boundary only; DOFs
    /// interleaved so that the block is not a trailing one.
    fn cb_like() -> (Mat<Real>, Mat<Real>, Mat<Real>, Vec<usize>) {
        // Component 1: boundary {0, 3, 4}, modes {1, 5, 7}; component 2: boundary {2, 6},
        // modes {8, 9}; DOF 4 is shared with component 2 (interface).
        let n = 10;
        let comps: [(&[usize], &[usize]); 2] = [(&[0, 3, 4], &[1, 5, 7]), (&[2, 4, 6], &[8, 9])];
        let mut m = Mat::<Real>::zeros(n, n);
        let mut k = Mat::<Real>::zeros(n, n);
        let mut s = 7u64;
        let mut rnd = || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            (s >> 11) as Real / (1u64 << 53) as Real - 0.5
        };
        for (bnd, modes) in comps {
            for &i in bnd {
                for &j in bnd {
                    let (x, y) = (0.1 * rnd(), rnd());
                    m[(i, j)] += x;
                    m[(j, i)] += x;
                    k[(i, j)] += y;
                    k[(j, i)] += y;
                }
                m[(i, i)] += 3.0;
                k[(i, i)] += 10.0;
                for &q in modes {
                    let x = 0.2 * rnd();
                    m[(i, q)] += x;
                    m[(q, i)] += x;
                }
            }
            for (r, &q) in modes.iter().enumerate() {
                m[(q, q)] = 1.0;
                k[(q, q)] = 4.0 * (r + 1) as Real;
            }
        }
        let b = Mat::from_fn(n, n, |i, j| 0.01 * k[(i, j)]);
        (m, b, k, vec![1, 5, 7, 8, 9])
    }

    #[test]
    fn detects_the_modal_coordinates_and_groups_them_by_component() {
        let (m, b, k, modes) = cb_like();
        let blk = DiagBlock::detect(&[&m, &b, &k], |_| true, 1).unwrap();
        assert_eq!(blk.d, modes);
        assert_eq!(blk.kept, vec![0, 2, 3, 4, 6]);
        assert_eq!(blk.n_groups(), 2);
        // A DOF the caller excludes (e.g. one a constraint touches) stays.
        let blk = DiagBlock::detect(&[&m, &b, &k], |i| i != 5, 1).unwrap();
        assert_eq!(blk.d, vec![1, 7, 8, 9]);
        // Below the minimum count: no block.
        assert!(DiagBlock::detect(&[&m, &b, &k], |_| true, 6).is_none());
    }

    #[test]
    fn a_coupled_block_is_not_eliminated_whole() {
        let (mut m, b, k, _) = cb_like();
        // Couple modes 1 and 5 (as a modal damping term would): only one of them can go.
        m[(1, 5)] = 0.05;
        m[(5, 1)] = 0.05;
        let blk = DiagBlock::detect(&[&m, &b, &k], |_| true, 1).unwrap();
        assert!(blk.d.contains(&1) != blk.d.contains(&5));
        for &i in &blk.d {
            for &j in &blk.d {
                assert!(i == j || (m[(i, j)] == 0.0 && b[(i, j)] == 0.0 && k[(i, j)] == 0.0));
            }
        }
    }

    /// The Schur-complement solve of a bordered system against the dense LU of the whole.
    #[test]
    fn schur_solve_matches_the_dense_solve() {
        let (m, b, k, _) = cb_like();
        let n = m.nrows();
        let mut blk = DiagBlock::detect(&[&m, &b, &k], |_| true, 1).unwrap();
        let cj = 3.7;
        let coef = [cj, 1.0, 1.0 / cj];
        blk.fill(&coef, &[&m, &b, &k], "test", 0.0).unwrap();
        // Border: one constraint row and column on kept DOFs 0 and 6 (non-symmetric).
        let nb = blk.kept.len();
        let a_full = Mat::from_fn(n + 1, n + 1, |i, j| match (i < n, j < n) {
            (true, true) => cj * m[(i, j)] + b[(i, j)] + k[(i, j)] / cj,
            (true, false) => [0.7, 0.0, 0.0, 0.0, 0.0, 0.0, -0.4, 0.0, 0.0, 0.0][i],
            (false, true) => [1.0, 0.0, 0.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0][j],
            (false, false) => 0.0,
        });
        let rhs: Vec<Real> = (0..=n).map(|i| (i as Real * 0.7).sin()).collect();
        let mut dense = DenseLu::new(n + 1);
        dense.a.copy_from(&a_full);
        dense.factor("dense", 0.0).unwrap();
        let mut want = rhs.clone();
        dense.solve(&mut want).unwrap();
        // Reduced: kept block, border on kept positions.
        let mut red = DenseLu::new(nb + 1);
        for (p, &i) in blk.kept.iter().enumerate() {
            for (q, &j) in blk.kept.iter().enumerate() {
                red.a[(p, q)] = a_full[(i, j)];
            }
            red.a[(p, nb)] = a_full[(i, n)];
            red.a[(nb, p)] = a_full[(n, i)];
        }
        blk.subtract_schur(&mut red.a);
        red.factor("reduced", 0.0).unwrap();
        let mut r = vec![0.0; nb + 1];
        blk.forward(&rhs, &mut r);
        r[nb] = rhs[n];
        red.solve(&mut r).unwrap();
        let mut got = vec![0.0; n + 1];
        blk.back(&r, &mut got);
        got[n] = r[nb];
        for i in 0..=n {
            assert!(
                (got[i] - want[i]).abs() < 1e-12 * (1.0 + want[i].abs()),
                "{i}: {} vs {}",
                got[i],
                want[i]
            );
        }
    }

    #[test]
    fn a_zero_diagonal_entry_is_reported_with_its_dof() {
        let (m, b, mut k, _) = cb_like();
        let mut blk = DiagBlock::detect(&[&m, &b, &k], |_| true, 1).unwrap();
        // cj M + K/cj at DOF 8 with K_88 = −cj² M_88 vanishes.
        k[(8, 8)] = -4.0;
        let err = blk
            .fill(&[2.0, 0.0, 0.5], &[&m, &b, &k], "test", 0.0)
            .unwrap_err();
        assert!(
            matches!(err, SolverError::SingularMatrix { index: 8, .. }),
            "{err:?}"
        );
    }
}
