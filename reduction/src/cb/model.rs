//! The reduced Craig–Bampton model, its statistics and data recovery.

use crate::error::ReductionError;
use faer::Mat;
use serde::Serialize;
use squeal_meshes::Real;

/// How the fixed-interface eigenproblem was solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum EigenMethod {
    /// Dense: Cholesky of M_ii, self-adjoint eigen of L⁻¹ K_ii L⁻ᵀ.
    Dense,
    /// Shift-invert block Lanczos reusing the Cholesky factor of K_ii.
    BlockLanczos,
    /// Substructured: the substructures' modes and separator shapes, then a dense second
    /// level (`CbStats::multilevel`).
    Substructured,
    /// No interior DOFs, or no modes asked for.
    None,
}

/// Statistics of one Craig–Bampton reduction (wall times in seconds).
#[derive(Debug, Clone, Serialize)]
pub struct CbStats {
    pub n_dofs: usize,
    /// Boundary coordinates: kept boundary DOFs + interface coordinates.
    pub n_boundary: usize,
    /// Boundary DOFs reduced to the interface basis (0: exact Craig–Bampton).
    pub n_interface_dofs: usize,
    /// Interface coordinates they were reduced to.
    pub n_interface_coords: usize,
    pub n_interior: usize,
    pub n_modes: usize,
    /// Nonzeros of the interior stiffness K_ii.
    pub nnz_kii: usize,
    /// Frequency of interest given in the options, Hz.
    pub frequency_of_interest_hz: Option<Real>,
    /// Cutoff used, Hz (None when only a mode count was asked for).
    pub cutoff_hz: Option<Real>,
    pub eigen_method: EigenMethod,
    /// Krylov dimension reached by the block Lanczos (0 when dense).
    pub krylov_dim: usize,
    /// Right-hand sides solved with the K_ii factor (constraint modes + Lanczos).
    pub n_solves: usize,
    pub partition_s: Real,
    /// Fill-reducing ordering of the K_ii factor (nested dissection with DOF coordinates on
    /// at least 20 000 interior DOFs, else AMD).
    pub ordering: super::factor::KiiOrdering,
    /// Seconds computing the nested-dissection ordering (part of `factor_s`; 0 for AMD).
    pub ordering_s: Real,
    /// Stored entries of the nested-dissection factor (0 when faer's AMD path does not say).
    pub factor_nnz: usize,
    pub factor_s: Real,
    pub constraint_modes_s: Real,
    pub eigen_s: Real,
    /// Part of `eigen_s` spent solving with the K_ii factor (block Lanczos).
    pub eigen_solve_s: Real,
    /// Part of `eigen_s` spent reorthogonalising against the Krylov basis (block Lanczos).
    pub eigen_orth_s: Real,
    /// Part of `eigen_s` spent M-orthonormalising new blocks, M products included (block Lanczos).
    pub eigen_qr_s: Real,
    pub products_s: Real,
    pub total_s: Real,
    /// Peak resident memory (VmHWM, KiB) after each phase, when /proc/self/status is readable.
    pub peak_rss_kib: PhaseMemory,
    /// The substructured reduction's substructures, separators and error estimates, when it
    /// was used.
    pub multilevel: Option<super::multilevel::MultilevelStats>,
}

/// Peak resident set size after each phase, KiB (None off Linux).
#[derive(Debug, Clone, Default, Serialize)]
pub struct PhaseMemory {
    pub partition: Option<u64>,
    pub factor: Option<u64>,
    pub constraint_modes: Option<u64>,
    pub eigen: Option<u64>,
    pub products: Option<u64>,
}

/// Peak resident set size of this process so far (VmHWM of /proc/self/status), KiB.
pub fn peak_rss_kib() -> Option<u64> {
    let s = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = s.lines().find(|l| l.starts_with("VmHWM:"))?;
    line.split_whitespace().nth(1)?.parse().ok()
}

/// A Craig–Bampton reduced component.
///
/// Reduced coordinates are ordered `[u_b (boundary DOFs, in the order given), p (interface
/// coordinates, with an interface basis), q (modal)]`; the transformation to the component's
/// free DOFs is u_b = u_b, u_f = L p, u_i = Ψ [u_b; p] + Φ q.
#[derive(Debug, Clone)]
pub struct CbModel {
    /// Reduced stiffness [[K_bb + K_bi Ψ, 0], [0, diag ω²]].
    pub k: Mat<Real>,
    /// Reduced mass [[M̂_bb, M_bq], [M_qb, I]].
    pub m: Mat<Real>,
    /// Reduced damping Tᵀ B T, when a damping matrix was given.
    pub b: Option<Mat<Real>>,
    /// Boundary free-DOF indices kept as physical coordinates, in reduced order.
    pub boundary: Vec<usize>,
    /// Interface DOFs reduced to a basis, u_f = L p (None: exact Craig–Bampton).
    pub interface: Option<super::InterfaceBasis>,
    /// Interior free-DOF indices (increasing), the rows of `psi` and `phi`.
    pub interior: Vec<usize>,
    /// Number of fixed-interface modes kept.
    pub n_modes: usize,
    /// Their natural frequencies, Hz, ascending.
    pub fixed_frequencies_hz: Vec<Real>,
    /// Constraint modes Ψ = −K_ii⁻¹ K_ib L̂ (n_interior × boundary coordinates).
    pub psi: Mat<Real>,
    /// Fixed-interface modes Φ, M_ii-orthonormal (n_interior × n_modes).
    pub phi: Mat<Real>,
    /// Free DOFs of the full component.
    pub n_dofs: usize,
    pub stats: CbStats,
}

impl CbModel {
    /// Size of the reduced model (boundary coordinates + modes).
    pub fn n_reduced(&self) -> usize {
        self.n_boundary_coords() + self.n_modes
    }

    /// Boundary coordinates: kept boundary DOFs + interface coordinates (the columns of Ψ).
    pub fn n_boundary_coords(&self) -> usize {
        self.boundary.len() + self.n_interface()
    }

    /// Interface coordinates (0 without an interface basis).
    pub fn n_interface(&self) -> usize {
        self.interface.as_ref().map_or(0, |f| f.n_coords())
    }

    /// Data recovery: the full free-DOF vector of a reduced vector `[u_b, p, q]`:
    /// u_b on the kept boundary, L p on the interface DOFs, Ψ [u_b; p] + Φ q inside.
    pub fn recover(&self, x_reduced: &[Real]) -> Result<Vec<Real>, ReductionError> {
        let nb = self.n_boundary_coords();
        if x_reduced.len() != self.n_reduced() {
            return Err(ReductionError::ShapeMismatch {
                what: "reduced vector".into(),
                rows: x_reduced.len(),
                cols: 1,
                expected_rows: self.n_reduced(),
                expected_cols: 1,
            });
        }
        let (ub, q) = x_reduced.split_at(nb);
        let mut full = vec![0.0; self.n_dofs];
        for (&dof, &u) in self.boundary.iter().zip(ub) {
            full[dof] = u;
        }
        if let Some(f) = &self.interface {
            let p = &ub[self.boundary.len()..];
            for (r, &dof) in f.dofs.iter().enumerate() {
                full[dof] = (0..p.len()).map(|c| f.basis[(r, c)] * p[c]).sum();
            }
        }
        for (r, &dof) in self.interior.iter().enumerate() {
            let mut acc = 0.0;
            for (c, &u) in ub.iter().enumerate() {
                acc += self.psi[(r, c)] * u;
            }
            for (c, &qc) in q.iter().enumerate() {
                acc += self.phi[(r, c)] * qc;
            }
            full[dof] = acc;
        }
        Ok(full)
    }

    /// Data recovery of several reduced vectors at once (the columns of `y`, n_reduced × c):
    /// T y, n_dofs × c, by two matrix products with Ψ and Φ.
    pub fn expand(&self, y: faer::MatRef<'_, Real>) -> Mat<Real> {
        let nb = self.n_boundary_coords();
        let c = y.ncols();
        let mut full = Mat::<Real>::zeros(self.n_dofs, c);
        for (r, &dof) in self.boundary.iter().enumerate() {
            for j in 0..c {
                full[(dof, j)] = y[(r, j)];
            }
        }
        if let Some(f) = &self.interface {
            let p = y.subrows(self.boundary.len(), f.n_coords());
            let lp = &f.basis * p;
            for (r, &dof) in f.dofs.iter().enumerate() {
                for j in 0..c {
                    full[(dof, j)] = lp[(r, j)];
                }
            }
        }
        let mut inner = Mat::<Real>::zeros(self.interior.len(), c);
        let par = faer::get_global_parallelism();
        faer::linalg::matmul::matmul(
            inner.as_mut(),
            faer::Accum::Replace,
            self.psi.as_ref(),
            y.subrows(0, nb),
            1.0,
            par,
        );
        if self.n_modes > 0 {
            faer::linalg::matmul::matmul(
                inner.as_mut(),
                faer::Accum::Add,
                self.phi.as_ref(),
                y.subrows(nb, self.n_modes),
                1.0,
                par,
            );
        }
        for (r, &dof) in self.interior.iter().enumerate() {
            for j in 0..c {
                full[(dof, j)] = inner[(r, j)];
            }
        }
        full
    }

    /// The transformation T (n_dofs × n_reduced) with u_full = T x_reduced (dense; small models).
    pub fn transformation(&self) -> Mat<Real> {
        let nb = self.n_boundary_coords();
        let mut t = Mat::<Real>::zeros(self.n_dofs, self.n_reduced());
        for (c, &dof) in self.boundary.iter().enumerate() {
            t[(dof, c)] = 1.0;
        }
        if let Some(f) = &self.interface {
            let c0 = self.boundary.len();
            for (r, &dof) in f.dofs.iter().enumerate() {
                for c in 0..f.n_coords() {
                    t[(dof, c0 + c)] = f.basis[(r, c)];
                }
            }
        }
        for (r, &dof) in self.interior.iter().enumerate() {
            for c in 0..nb {
                t[(dof, c)] = self.psi[(r, c)];
            }
            for c in 0..self.n_modes {
                t[(dof, nb + c)] = self.phi[(r, c)];
            }
        }
        t
    }
}
