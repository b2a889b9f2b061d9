//! The whole spectrum of the contact-linearised, constrained operator with right eigenvectors
//! and left rows, in the CEA's first-order form.
//!
//! # Derivation
//! [`crate::cea::reduce`] eliminates the rigid rows exactly: u = T q, and a force f enters as
//! M_r q̈ + C_r q̇ + K_r q = Tᵀ P f (P the oblique projector of the multipliers; P f = f
//! without friction tangent D). With M_r = L Lᵀ, w = Lᵀ q and z = [w; ẇ/σ] (σ the CEA's
//! balancing scale, [`crate::cea::first_order`]):
//! ```text
//! ż = A z + [0; L⁻¹ Tᵀ P f / σ],     A = [[0, σI], [−K̂/σ, −Ĉ]]
//! u = T L⁻ᵀ [I 0] z,                 u̇ = σ T L⁻ᵀ [0 I] z
//! ```
//! With A = V Λ V⁻¹ (faer's dense real eigensolver; V from its packed real vectors), the
//! modal coordinates ξ = V⁻¹ z obey ξ̇_j = λ_j ξ_j + (V⁻¹)_j [0; L⁻¹TᵀPf/σ], and
//! u = Σ_j (T L⁻ᵀ V_w)_j ξ_j (V_w the w-rows of V): the c_j and b_j of the module docs.
//! The lower half of column j of V is λ_j/σ times its upper half, so u̇ = Σ_j λ_j c_j ξ_j.
//! The multipliers follow from G ü = 0: N = S⁻¹ G M⁻¹ (f − C u̇ − K u), S = G M⁻¹ A_r.

use crate::cea::eigen::sandwich;
use crate::cea::first_order::{balance, first_order_matrix_of, real_evd};
use crate::cea::operator::{cholesky, damping, mass_solve, ContactProjector};
use crate::cea::{reduce, CeaError, CeaMatrices, CeaOptions, Cplx};
use faer::linalg::solvers::{PartialPivLu, Solve};
use faer::{c64, Mat};

/// The eigendecomposition and the maps between forces, modal coordinates and DOFs.
pub(crate) struct Spectrum {
    /// DOFs.
    pub n: usize,
    /// Rigid rows.
    pub ng: usize,
    /// n − ng.
    pub m: usize,
    /// Basis of null(G_r) (None: no rigid row, T = I).
    t: Option<Mat<f64>>,
    /// Cholesky factor of M_r = TᵀMT.
    l: Mat<f64>,
    /// The first-order balancing scale.
    sigma: f64,
    /// The multipliers' projector (None: no rigid row).
    proj: Option<ContactProjector>,
    /// C = B − C_f (None: no damping).
    c: Option<Mat<f64>>,
    /// K (the compliant rows folded).
    k: Mat<f64>,
    /// All 2m eigenvalues.
    pub vals: Vec<Cplx>,
    /// Their right eigenvectors (columns), 2m × 2m.
    v: Mat<c64>,
    /// LU of `v`, for the left rows.
    lu: PartialPivLu<c64>,
    /// Largest |λ|.
    pub rho: f64,
}

fn cplx(re: &Mat<f64>, im: &Mat<f64>) -> Mat<c64> {
    Mat::from_fn(re.nrows(), re.ncols(), |i, j| {
        c64::new(re[(i, j)], im[(i, j)])
    })
}

fn parts(z: &Mat<c64>) -> (Mat<f64>, Mat<f64>) {
    (
        Mat::from_fn(z.nrows(), z.ncols(), |i, j| z[(i, j)].re),
        Mat::from_fn(z.nrows(), z.ncols(), |i, j| z[(i, j)].im),
    )
}

impl Spectrum {
    /// Decomposes the linear operator of `sys` (compliant rows already folded, `g`/`d` the
    /// rigid rows only).
    #[allow(non_snake_case)]
    pub(crate) fn new(sys: &CeaMatrices) -> Result<Self, CeaError> {
        let red = reduce(sys, &CeaOptions::default())?;
        let n = sys.m.nrows();
        let m = red.m_r.nrows();
        let ng = n - m;
        let llt = cholesky("T^T M T", &red.m_r)?;
        let l = llt.L().to_owned();
        let khat = sandwich(l.as_ref(), &red.k_r);
        let chat = red.c_r.as_ref().map(|c| sandwich(l.as_ref(), c));
        let sigma = balance(&khat);
        let a = first_order_matrix_of(&khat, chat.as_ref());
        let (s_re, s_im, u, rho) = real_evd(&a, true)?;
        let n2 = 2 * m;
        let mut v = Mat::<c64>::zeros(n2, n2);
        let mut vals = Vec::with_capacity(n2);
        let mut j = 0;
        while j < n2 {
            if s_im[j] == 0.0 {
                vals.push(Cplx::new(s_re[j], 0.0));
                for i in 0..n2 {
                    v[(i, j)] = c64::new(u[(i, j)], 0.0);
                }
                j += 1;
            } else {
                vals.push(Cplx::new(s_re[j], s_im[j]));
                vals.push(Cplx::new(s_re[j], -s_im[j]));
                for i in 0..n2 {
                    let z = c64::new(u[(i, j)], u[(i, j + 1)]);
                    v[(i, j)] = z;
                    v[(i, j + 1)] = z.conj();
                }
                j += 2;
            }
        }
        let lu = v.partial_piv_lu();
        let proj = match (&sys.g, ng) {
            (Some(G), ng) if ng > 0 => {
                let Gt = G.transpose().to_owned();
                let D = sys.d.clone().unwrap_or_else(|| Mat::zeros(n, ng));
                Some(ContactProjector::new(mass_solve(&sys.m, &Gt)?, &Gt, &D)?)
            }
            _ => None,
        };
        Ok(Self {
            n,
            ng,
            m,
            t: red.t,
            l,
            sigma,
            proj,
            c: damping(sys),
            k: sys.k.clone(),
            vals,
            v,
            lu,
            rho,
        })
    }

    /// The lower half of the first-order input, L⁻¹ Tᵀ P F / σ (m × k), of forces F (n × k).
    pub(crate) fn input_rows(&self, f: &Mat<f64>) -> Mat<f64> {
        let pf = match &self.proj {
            Some(p) => p.apply(f.clone()),
            None => f.clone(),
        };
        let mut x = match &self.t {
            Some(t) => t.transpose() * &pf,
            None => pf,
        };
        self.l.as_ref().solve_lower_triangular_in_place(&mut x);
        x * faer::Scale(1.0 / self.sigma)
    }

    /// Modal coordinates V⁻¹ [0; e] of first-order inputs with lower half `e` (m × k): all 2m rows.
    pub(crate) fn modal_inputs(&self, e: &Mat<f64>) -> Mat<c64> {
        let (m, k) = (self.m, e.ncols());
        let mut x = Mat::<c64>::zeros(2 * m, k);
        for j in 0..k {
            for i in 0..m {
                x[(m + i, j)] = c64::new(e[(i, j)], 0.0);
            }
        }
        self.lu.solve_in_place(&mut x);
        x
    }

    /// The rows `idx` of V⁻¹ restricted to their lower half (idx.len() × m): multiplied by a
    /// first-order input's lower half they give its modal coordinates.
    pub(crate) fn left_rows(&self, idx: &[usize]) -> Mat<c64> {
        let (n2, m) = (2 * self.m, self.m);
        let mut e = Mat::<c64>::zeros(n2, idx.len());
        for (c, &j) in idx.iter().enumerate() {
            e[(j, c)] = c64::new(1.0, 0.0);
        }
        // Vᵀ Y = E: column c of Y is row idx[c] of V⁻¹.
        self.lu.solve_transpose_in_place(&mut e);
        Mat::from_fn(idx.len(), m, |c, i| e[(m + i, c)])
    }

    /// Displacement shapes c_j = T L⁻ᵀ (V_w)_j of the eigenvectors `idx` (n × idx.len()).
    pub(crate) fn shapes(&self, idx: &[usize]) -> Mat<c64> {
        let m = self.m;
        let w = Mat::from_fn(m, idx.len(), |i, c| self.v[(i, idx[c])]);
        self.to_dofs(&w)
    }

    /// T L⁻ᵀ W for reduced vectors W (m × k).
    pub(crate) fn to_dofs(&self, w: &Mat<c64>) -> Mat<c64> {
        let (mut re, mut im) = parts(w);
        let lt = self.l.transpose();
        lt.solve_upper_triangular_in_place(&mut re);
        lt.solve_upper_triangular_in_place(&mut im);
        match &self.t {
            Some(t) => cplx(&(t * &re), &(t * &im)),
            None => cplx(&re, &im),
        }
    }

    /// T L⁻ᵀ V_w Y for modal amplitudes Y (2m × k): Σ_j c_j Y_j in the DOFs (n × k).
    pub(crate) fn sum_to_dofs(&self, y: &Mat<c64>) -> Mat<c64> {
        let w = self.v.subrows(0, self.m) * y;
        self.to_dofs(&w)
    }

    /// −S⁻¹ G M⁻¹ (C u_λ + K u) (ng × k): the multipliers of displacements `u` whose velocity
    /// part is `u_λ` (empty without rigid rows).
    pub(crate) fn multipliers_of(&self, u: &Mat<c64>, u_l: &Mat<c64>) -> Mat<c64> {
        let Some(p) = &self.proj else {
            return Mat::zeros(0, u.ncols());
        };
        let (ur, ui) = parts(u);
        let (lr, li) = parts(u_l);
        let mut zr = &self.k * &ur;
        let mut zi = &self.k * &ui;
        if let Some(c) = &self.c {
            zr += c * &lr;
            zi += c * &li;
        }
        let (wr, wi) = (p.coefficients(&zr), p.coefficients(&zi));
        Mat::from_fn(wr.nrows(), wr.ncols(), |i, j| {
            -c64::new(wr[(i, j)], wi[(i, j)])
        })
    }

    /// Multiplier increments of the modes `shapes` (n × k) with eigenvalues `lams`:
    /// N_j = −S⁻¹ G M⁻¹ (λ_j C + K) c_j (ng × k; empty without rigid rows).
    pub(crate) fn multipliers(&self, shapes: &Mat<c64>, lams: &[Cplx]) -> Mat<c64> {
        let Some(p) = &self.proj else {
            return Mat::zeros(0, shapes.ncols());
        };
        let (re, im) = parts(shapes);
        let (kre, kim) = (&self.k * &re, &self.k * &im);
        let (cre, cim) = match &self.c {
            Some(c) => (c * &re, c * &im),
            None => (
                Mat::zeros(self.n, re.ncols()),
                Mat::zeros(self.n, re.ncols()),
            ),
        };
        // (λC + K)x with λ = a + ib, x = xr + i xi: real part a Cxr − b Cxi + Kxr, imag
        // a Cxi + b Cxr + Kxi.
        let zr = Mat::from_fn(self.n, re.ncols(), |i, j| {
            let l = lams[j];
            l.re * cre[(i, j)] - l.im * cim[(i, j)] + kre[(i, j)]
        });
        let zi = Mat::from_fn(self.n, re.ncols(), |i, j| {
            let l = lams[j];
            l.re * cim[(i, j)] + l.im * cre[(i, j)] + kim[(i, j)]
        });
        let (wr, wi) = (p.coefficients(&zr), p.coefficients(&zi));
        Mat::from_fn(wr.nrows(), wr.ncols(), |i, j| {
            -c64::new(wr[(i, j)], wi[(i, j)])
        })
    }
}
