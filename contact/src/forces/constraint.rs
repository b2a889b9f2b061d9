//! The contact constraint matrix G, eqs. (9) and (11).

use crate::{ContactError, GapSet, Real};
use faer::Mat;

impl GapSet {
    /// Triplets `(row = gap, col = DOF, value)` of G: row g is `+nᵀ` on the rotor DOFs and
    /// `−nᵀ` on the pad DOFs (fixed DOFs are skipped), so that `G u = 0` reads
    /// `(u_rotor − u_pad)·n = 0`. Checks DOF indices against `n`. A tied gap's rotor point is
    /// `Σ_a N_a(ξ*) u_a`: its row has `N_a nᵀ` on each face node (the weights sum to 1, so the
    /// row sums to zero in each direction and a rigid translation leaves `G u = 0`).
    /// Several triplets may share a (row, column) (a node tied twice); they add.
    ///
    /// # Reference
    /// $$(\vec u_d - \vec u_p)\cdot\vec n = 0 \;(9),\qquad \mathbf{G}\{\dot v\} = 0 \;(11)$$
    /// [Paper eqs. (9), (11)].
    pub fn constraint_triplets(&self, n: usize) -> Result<Vec<(usize, usize, Real)>, ContactError> {
        self.check_dofs(n)?;
        let mut t = Vec::with_capacity(6 * self.gaps.len());
        for (ig, g) in self.gaps.iter().enumerate() {
            for k in 0..3 {
                if g.normal[k] == 0.0 {
                    continue;
                }
                for (w, dofs) in g.rotor_terms() {
                    if let Some(d) = dofs[k] {
                        t.push((ig, d, w[k] * g.normal[k])); // [Paper eq. (9)]
                    }
                }
                for (w, dofs) in g.pad_terms() {
                    if let Some(d) = dofs[k] {
                        t.push((ig, d, -w[k] * g.normal[k]));
                    }
                }
            }
        }
        Ok(t)
    }

    /// Dense G (ng×n), see [`GapSet::constraint_triplets`]. [Paper eqs. (9), (11)]
    pub fn constraint_matrix(&self, n: usize) -> Result<Mat<Real>, ContactError> {
        let mut g = Mat::zeros(self.gaps.len(), n);
        for (i, j, x) in self.constraint_triplets(n)? {
            g[(i, j)] += x;
        }
        Ok(g)
    }
}
