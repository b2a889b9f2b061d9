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
            let (dlam, jp) = self.gap_tangent(ig, v, lambda_dot[ig], d_dv.is_some())?;
            for k in 0..3 {
                for (w, dofs) in gap.pad_terms() {
                    if let Some(d) = dofs[k] {
                        d_dlam[(d, ig)] += w[k] * dlam[k];
                    }
                }
                for (w, dofs) in gap.rotor_terms() {
                    if let Some(d) = dofs[k] {
                        d_dlam[(d, ig)] -= w[k] * dlam[k];
                    }
                }
            }
            let Some(cf) = d_dv.as_deref_mut() else {
                continue;
            };
            slip_map(gap, &mut cols);
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

    /// Gap `ig`'s tangents at (v, λ̇): `∂f_p/∂λ̇` (a 3-vector on the pad; the rotor terms get
    /// `−w_k` times it) and, when `with_v`, the 3×3 `J P` of [`GapSet::add_tangents`]'s
    /// derivation (zero otherwise).
    fn gap_tangent(
        &self,
        ig: usize,
        v: &[Real],
        lambda_dot: Real,
        with_v: bool,
    ) -> Result<([Real; 3], [[Real; 3]; 3]), ContactError> {
        let gap = &self.gaps[ig];
        let o = evaluate_gap(self, gap, v, lambda_dot);
        let vt = o.slip_velocity;
        let s = o.slip_speed;
        let ev = o.friction;
        // ∂f_p/∂λ̇.
        let c_lam = -(ev.mu + o.pressure * ev.dmu_dp) * o.phi;
        let mut dlam = [0.0; 3];
        for k in 0..3 {
            dlam[k] = c_lam * vt[k];
            if !dlam[k].is_finite() {
                return Err(self.non_finite(ig, "friction tangent d/dlambda", dlam[k]));
            }
        }
        let mut jp = [[0.0; 3]; 3];
        if !with_v {
            return Ok((dlam, jp));
        }
        // J = F φ I + c2 V_t V_tᵀ.
        let f = ev.mu * gap.area * o.pressure;
        let df_ds = ev.dmu_dv * gap.area * o.pressure;
        let mut c2 = f * o.psi;
        if s > 0.0 {
            c2 += df_ds * o.phi / s;
        }
        let nn = gap.normal;
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
        Ok((dlam, jp))
    }

    /// Each gap's own blocks of G, D and C_f at (v, λ̇): what [`GapSet::constraint_matrix`]
    /// and [`GapSet::add_tangents`] add for that gap, on the DOFs it touches (their sums over
    /// the gaps are those matrices). For the energy balance of a mode per gap.
    ///
    /// # Errors
    /// As [`GapSet::add_tangents`].
    pub fn gap_blocks(
        &self,
        v: &[Real],
        lambda_dot: &[Real],
    ) -> Result<Vec<GapBlock>, ContactError> {
        self.check_vectors(v, lambda_dot)?;
        self.check_dofs(v.len())?;
        let mut cols: Vec<(usize, [Real; 3])> = Vec::new();
        let mut out = Vec::with_capacity(self.gaps.len());
        for (ig, gap) in self.gaps.iter().enumerate() {
            let (dlam, jp) = self.gap_tangent(ig, v, lambda_dot[ig], true)?;
            slip_map(gap, &mut cols);
            let r = cols.len();
            let dofs: Vec<usize> = cols.iter().map(|c| c.0).collect();
            // t_c is the DOF's share of V_t = Σ_c t_c v_c (pad: +e_k, rotor: −w e_k). As in
            // add_tangents the pad DOF k gets +dlam_k and a rotor term −w_k dlam_k, i.e. the
            // column of D is t_c·dlam; G's row is n·(u_r − u_p) = −Σ_c (t_c·n) u_c.
            let d: Vec<Real> = cols
                .iter()
                .map(|(_, t)| t[0] * dlam[0] + t[1] * dlam[1] + t[2] * dlam[2])
                .collect();
            let nn = gap.normal;
            let g: Vec<Real> = cols
                .iter()
                .map(|(_, t)| -(t[0] * nn[0] + t[1] * nn[1] + t[2] * nn[2]))
                .collect();
            let c_f = Mat::from_fn(r, r, |a, b| {
                let (ta, tb) = (cols[a].1, cols[b].1);
                let mut x = 0.0;
                for i in 0..3 {
                    let y = jp[i][0] * tb[0] + jp[i][1] * tb[1] + jp[i][2] * tb[2];
                    x -= ta[i] * y;
                }
                x
            });
            out.push(GapBlock { dofs, g, d, c_f });
        }
        Ok(out)
    }
}

/// One gap's blocks of G, D = ∂F_f/∂λ̇ and C_f = ∂F_f/∂v on the DOFs it touches.
#[derive(Debug, Clone)]
pub struct GapBlock {
    /// The DOFs (sorted, unique).
    pub dofs: Vec<usize>,
    /// The gap's row of G on `dofs`.
    pub g: Vec<Real>,
    /// The gap's column of D on `dofs`.
    pub d: Vec<Real>,
    /// The gap's block of C_f (`dofs` × `dofs`).
    pub c_f: Mat<Real>,
}

/// The gap's slip velocity as `Σ_c t_c v[c]` over its DOFs c (`t = e_k` on the pad's DOF k,
/// `−w_k e_k` on a rotor term's DOF k; terms on the same DOF summed), sorted by DOF.
fn slip_map(gap: &crate::Gap, cols: &mut Vec<(usize, [Real; 3])>) {
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
}
