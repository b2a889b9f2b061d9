//! Exact tangents of the gap forces: ∂F_f/∂λ̇ (the paper's ∂F_f/∂λ) and ∂F_f/∂v (C_f).

use super::kernel::evaluate_gap;
use crate::{ContactError, GapSet, Real};
use faer::Mat;

impl GapSet {
    /// Adds the exact derivatives of the friction forces of [`GapSet::add_forces`]:
    /// `d_dlam += ∂F_f/∂λ̇` (n×ng) and, if given, `d_dv += ∂F_f/∂v = C_f` (n×n).
    ///
    /// # Reference
    /// The partitions `∂F_f/∂λ` of $H^T = G^T + \partial F_f/\partial\lambda$ and
    /// $C_f = \partial F_f/\partial v$ of the iteration matrix [Paper eq. (18)] and of the
    /// complex eigenproblem [Paper eqs. (22)–(23)] (the paper writes them with the sign of the
    /// residual, eq. (16), which carries −F_f; these are the derivatives of +F_f).
    ///
    /// # Derivation
    /// Per gap, with `F = μ(p_n, s, T)·A·p_n`, `s = |V_t|`, `φ(s) = r(s)/s`, the pad force is
    /// `f_p = F φ(s) V_t` and the rotor force `f_r = −f_p`.
    ///
    /// *Multiplier.* `∂p_n/∂λ̇ = −1/A` (eq. 1 with F_z = −λ̇), so
    /// `∂F/∂λ̇ = A (μ + p_n ∂μ/∂p)(−1/A) = −(μ + p_n ∂μ/∂p)` and
    /// `∂f_p/∂λ̇ = −(μ + p_n ∂μ/∂p) φ V_t` (column g of `d_dlam` on the pad DOFs; the
    /// opposite on the rotor DOFs).
    ///
    /// *Velocities.* `∂s/∂V_t = V_tᵀ/s`, `∂F/∂s = A p_n ∂μ/∂|V_t|`, hence
    /// ```text
    /// J := ∂f_p/∂V_t = F φ I + (F φ'(s)/s + (∂F/∂s) φ/s) V_t V_tᵀ .
    /// ```
    /// `φ'(s)/s` is finite at s = 0 (φ is even and smooth, see [`super::regularisation`]), and
    /// `(∂F/∂s) φ/s · V_t V_tᵀ → 0` as s → 0 (it is O(s)), so J is evaluated without a
    /// division by zero (the last term is dropped at s = 0 exactly). By eqs. (2)–(3),
    /// `V_t = P (v_r − v_p + v_slide)` with `P = I − n nᵀ`, so
    /// `∂f_p/∂v_r = J P`, `∂f_p/∂v_p = −J P`, `∂f_r/∂v_r = −J P`, `∂f_r/∂v_p = J P`.
    /// On a tied gap v_r = Σ_a w_a v_a and f_a = w_a f_r (w_a = N_a(ξ*)), so the blocks become
    /// `∂f_p/∂v_b = w_b J P`, `∂f_a/∂v_b = −w_a w_b J P`, `∂f_a/∂v_p = w_a J P`, and the
    /// multiplier column is `−w_a ∂f_p/∂λ̇` on node a.
    /// The temperature of a gap is a parameter, not a state: ∂μ/∂T does not enter.
    ///
    /// # Errors
    /// Wrong lengths or shapes, DOF indices out of range, non-finite tangents.
    pub fn add_tangents(
        &self,
        v: &[Real],
        lambda_dot: &[Real],
        d_dlam: &mut Mat<Real>,
        mut d_dv: Option<&mut Mat<Real>>,
    ) -> Result<(), ContactError> {
        self.check_vectors(v, lambda_dot)?;
        let n = v.len();
        let ng = self.gaps.len();
        let shape_err = |what, m: &Mat<Real>, r, c| ContactError::Shape {
            what,
            rows: m.nrows(),
            cols: m.ncols(),
            expected_rows: r,
            expected_cols: c,
        };
        if d_dlam.nrows() != n || d_dlam.ncols() != ng {
            return Err(shape_err("d_dlam", d_dlam, n, ng));
        }
        if let Some(m) = d_dv.as_deref() {
            if m.nrows() != n || m.ncols() != n {
                return Err(shape_err("d_dv", m, n, n));
            }
        }
        let mut cols: Vec<(usize, [Real; 3])> = Vec::new();
        for (ig, gap) in self.gaps.iter().enumerate() {
            let o = evaluate_gap(self, gap, v, lambda_dot[ig]);
            let vt = o.slip_velocity;
            let s = o.slip_speed;
            let ev = o.friction;
            // ∂f_p/∂λ̇.
            let c_lam = -(ev.mu + o.pressure * ev.dmu_dp) * o.phi;
            for k in 0..3 {
                let x = c_lam * vt[k];
                if !x.is_finite() {
                    return Err(self.non_finite(ig, "friction tangent d/dlambda", x));
                }
                for (w, dofs) in gap.pad_terms() {
                    if let Some(d) = dofs[k] {
                        d_dlam[(d, ig)] += w[k] * x;
                    }
                }
                for (w, dofs) in gap.rotor_terms() {
                    if let Some(d) = dofs[k] {
                        d_dlam[(d, ig)] -= w[k] * x;
                    }
                }
            }
            let Some(cf) = d_dv.as_deref_mut() else {
                continue;
            };
            // J = F φ I + c2 V_t V_tᵀ.
            let f = ev.mu * gap.area * o.pressure;
            let df_ds = ev.dmu_dv * gap.area * o.pressure;
            let mut c2 = f * o.psi;
            if s > 0.0 {
                c2 += df_ds * o.phi / s;
            }
            let nn = gap.normal;
            let mut jp = [[0.0; 3]; 3];
            for i in 0..3 {
                for j in 0..3 {
                    // (J P)_ij = Σ_k J_ik (δ_kj − n_k n_j)
                    let mut x = 0.0;
                    for k in 0..3 {
                        let jik = if i == k { f * o.phi } else { 0.0 } + c2 * vt[i] * vt[k];
                        let pkj = if k == j { 1.0 } else { 0.0 } - nn[k] * nn[j];
                        x += jik * pkj;
                    }
                    if !x.is_finite() {
                        return Err(self.non_finite(ig, "friction tangent d/dv", x));
                    }
                    jp[i][j] = x;
                }
            }
            // The gap's slip velocity is Σ_c t_c v[c] over its DOFs c (t = e_k on the pad's
            // DOF k, −w_k e_k on a rotor term's DOF k; terms on the same DOF summed), so its
            // block of C_f is −Σ_ab t_aᵀ (J P) t_b: one 3-vector y_b = (J P) t_b per DOF and
            // a dot product per pair, instead of nine passes over the pairs (a gap on an
            // interface-reduced rotor has ~10² rotor terms).
            cols.clear();
            for (w, dofs) in gap.pad_terms() {
                for k in 0..3 {
                    if let Some(d) = dofs[k] {
                        let mut t = [0.0; 3];
                        t[k] = w[k];
                        cols.push((d, t));
                    }
                }
            }
            for (w, dofs) in gap.rotor_terms() {
                for k in 0..3 {
                    if let Some(d) = dofs[k] {
                        let mut t = [0.0; 3];
                        t[k] = -w[k];
                        cols.push((d, t));
                    }
                }
            }
            cols.sort_unstable_by_key(|c| c.0);
            cols.dedup_by(|b, a| {
                if a.0 == b.0 {
                    for k in 0..3 {
                        a.1[k] += b.1[k];
                    }
                    true
                } else {
                    false
                }
            });
            for &(db, tb) in cols.iter() {
                let mut y = [0.0; 3];
                for (i, yi) in y.iter_mut().enumerate() {
                    *yi = jp[i][0] * tb[0] + jp[i][1] * tb[1] + jp[i][2] * tb[2];
                }
                for &(da, ta) in cols.iter() {
                    cf[(da, db)] -= ta[0] * y[0] + ta[1] * y[1] + ta[2] * y[2];
                }
            }
        }
        Ok(())
    }
}
