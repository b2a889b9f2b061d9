//! The harmonic-balance equations of the band-limited model, with AFT.
//!
//! # Derivation
//! The band-limited model ([`crate::condense`]) is ẋ = A x + B f(z), z = z⁰ + C x + D f(z)
//! with A block diagonal (the kept roots), z the contact outputs and f the inputs (the load
//! change, constant in a steady oscillation, and the remainder at the contact DOFs). For a
//! periodic solution of frequency ω, harmonic k of the states is X̂_k = (ikω − A)⁻¹ B F̂_k
//! (k = 0: −A⁻¹ B F̂_0), so the outputs' harmonics satisfy, with the band-limited transfer
//! function H(s) = C (s − A)⁻¹ B + D,
//! ```text
//! R̂_k = Ẑ_k − z⁰ δ_k0 − H(ikω) F̂_k(Z) = 0,      k = 0 … H,
//! ```
//! — the harmonic balance condensed on the contact outputs (the states eliminated exactly;
//! Krack & Gross 2019, §3.3 on condensation to the nonlinear DOFs). F̂_k(Z) by AFT: the
//! outputs sampled at N phases, the exact contact law and friction evaluated there, the samples
//! transformed back ([`super::fourier`]); its derivative ∂F̂/∂Z from the sampled J_r = ∂r/∂z
//! the same way. In the real coefficients (Ẑ = Z_c − i Z_s, H = H_r + i H_i):
//! R_c = Z_c − Σ_j (H_r F_cj + H_i F_sj), R_s = Z_s + Σ_j (H_i F_cj − H_r F_sj).

use super::fourier::Basis;
use crate::bsql::FrictionForces;
use crate::condense::BandSystem;
use crate::{Real, SolverError};
use faer::{c64, Mat};

/// The HB problem of a band system at evaluation time `t` (after the load ramp).
pub(crate) struct Hb<'a, F: FrictionForces> {
    pub sys: &'a mut BandSystem<F>,
    pub t: Real,
    pub basis: Basis,
    pub n_z: usize,
    pub n_in: usize,
    /// First contact input.
    pub o: usize,
    /// Force patterns (inputs after the load).
    pub n_p: usize,
    c_z: Mat<Real>,
    d_z: Mat<Real>,
    b_x: Mat<Real>,
    roots: Vec<crate::cea::Cplx>,
    offsets: Vec<usize>,
    pub z0: Vec<Real>,
}

/// What one evaluation returns: the residual and, when asked, its derivatives with respect
/// to Z (n_z(2H+1) columns), ω and s.
pub(crate) struct Eval {
    pub r: Vec<Real>,
    pub jac: Option<Mat<Real>>,
}

impl<'a, F: FrictionForces> Hb<'a, F> {
    pub(crate) fn new(sys: &'a mut BandSystem<F>, t: Real, h: usize, n: usize) -> Self {
        let (c_z, d_z) = sys.output_maps();
        let (c_z, d_z) = (c_z.clone(), d_z.clone());
        let m = sys.model();
        let (b_x, roots, offsets) = (m.B_x.clone(), m.roots.clone(), m.offsets.clone());
        let o = m.inputs.first_contact();
        let n_in = m.inputs.len();
        let z0 = sys.z_reference().to_vec();
        let n_p = sys.n_patterns();
        Self {
            n_z: z0.len(),
            sys,
            t,
            basis: Basis::new(h, n),
            n_in,
            o,
            n_p,
            c_z,
            d_z,
            b_x,
            roots,
            offsets,
            z0,
        }
    }

    /// Coefficients per signal.
    pub(crate) fn m(&self) -> usize {
        self.basis.m()
    }

    /// (s − A)⁻¹ B_x (complex, n_x × inputs) and, when `deriv`, −(s − A)⁻² B_x.
    fn resolvent(&self, s: c64, deriv: bool) -> (Mat<c64>, Option<Mat<c64>>) {
        let (n_x, n_in) = (self.b_x.nrows(), self.n_in);
        let mut x = Mat::<c64>::zeros(n_x, n_in);
        let mut dx = deriv.then(|| Mat::<c64>::zeros(n_x, n_in));
        for (p, &o) in self.roots.iter().zip(&self.offsets) {
            if p.im != 0.0 {
                // M = [[s − σ, ω], [−ω, s − σ]], M⁻¹ = [[s − σ, −ω], [ω, s − σ]] / det.
                let (a, w) = (s - p.re, p.im);
                let det = a * a + w * w;
                let inv = [[a / det, -w / det], [w / det, a / det]];
                for j in 0..n_in {
                    let (b0, b1) = (self.b_x[(o, j)], self.b_x[(o + 1, j)]);
                    let y0 = inv[0][0] * b0 + inv[0][1] * b1;
                    let y1 = inv[1][0] * b0 + inv[1][1] * b1;
                    x[(o, j)] = y0;
                    x[(o + 1, j)] = y1;
                    if let Some(d) = dx.as_mut() {
                        d[(o, j)] = -(inv[0][0] * y0 + inv[0][1] * y1);
                        d[(o + 1, j)] = -(inv[1][0] * y0 + inv[1][1] * y1);
                    }
                }
            } else {
                let inv = 1.0 / (s - p.re);
                for j in 0..n_in {
                    let y = inv * self.b_x[(o, j)];
                    x[(o, j)] = y;
                    if let Some(d) = dx.as_mut() {
                        d[(o, j)] = -inv * y;
                    }
                }
            }
        }
        (x, dx)
    }

    /// H(ikω) = C (ikω − A)⁻¹ B + D and, when `deriv`, dH/dω = C (ik)(−(ikω − A)⁻²) B.
    pub(crate) fn transfer(&self, k: usize, w: Real, deriv: bool) -> (Mat<c64>, Option<Mat<c64>>) {
        let s = c64::new(0.0, k as Real * w);
        let (x, dx) = self.resolvent(s, deriv && k > 0);
        let cz = Mat::from_fn(self.c_z.nrows(), self.c_z.ncols(), |i, j| {
            c64::new(self.c_z[(i, j)], 0.0)
        });
        let mut h = &cz * &x;
        for j in 0..self.n_in {
            for i in 0..self.n_z {
                h[(i, j)] += c64::new(self.d_z[(i, j)], 0.0);
            }
        }
        let dh = dx.map(|d| {
            let ik = c64::new(0.0, k as Real);
            let mut out = &cz * &d;
            for v in out.col_iter_mut() {
                for z in v.iter_mut() {
                    *z *= ik;
                }
            }
            out
        });
        (h, dh)
    }

    /// The outputs z at sample i of the coefficients `zc` (n_z blocks of 2H + 1).
    pub(crate) fn sample(&self, zc: &[Real], i: usize, out: &mut [Real]) {
        let m = self.m();
        for (a, o) in out.iter_mut().enumerate() {
            *o = self.basis.sample(&zc[a * m..(a + 1) * m], i);
        }
    }

    /// AFT: the inputs' coefficients F (n_in × (2H+1), row-major by input) and, when `jac`,
    /// ∂F/∂Z, column-major: entry (row j·(2H+1) + m, column b·(2H+1) + l) at
    /// `column · n_in(2H+1) + row`.
    #[allow(clippy::type_complexity)]
    pub(crate) fn aft(
        &mut self,
        zc: &[Real],
        jac: bool,
    ) -> Result<(Vec<Real>, Option<Vec<Real>>), SolverError> {
        let (m, n_z, n_in, o) = (self.m(), self.n_z, self.n_in, self.o);
        let rows = n_in * m;
        let mut fc = vec![0.0; rows];
        let mut df = jac.then(|| vec![0.0; rows * n_z * m]);
        let mut z = vec![0.0; n_z];
        for i in 0..self.basis.n {
            self.sample(zc, i, &mut z);
            let (f, jr) = self.sys.evaluate(self.t, &z, jac)?;
            let p = self.basis.p_row(i);
            for (j, &fj) in f.iter().enumerate() {
                for (mm, &pm) in p.iter().enumerate() {
                    fc[j * m + mm] += pm * fj;
                }
            }
            if let (Some(df), Some(jr)) = (df.as_mut(), jr) {
                let e = self.basis.e_row(i);
                for b in 0..n_z {
                    for a in 0..self.n_p {
                        let jab = jr[(a, b)];
                        if jab == 0.0 {
                            continue;
                        }
                        let row0 = (o + a) * m;
                        for (l, &el) in e.iter().enumerate() {
                            let w = jab * el;
                            let col = &mut df[(b * m + l) * rows + row0..][..m];
                            for (x, &pm) in col.iter_mut().zip(p) {
                                *x += pm * w;
                            }
                        }
                    }
                }
            }
        }
        Ok((fc, df))
    }

    /// The residual at u = [Z; ω; s] (the friction scale set to s) and, when `jac`, its
    /// derivatives (n_z(2H+1) × (n_z(2H+1) + 2)).
    pub(crate) fn eval(&mut self, u: &[Real], jac: bool) -> Result<Eval, SolverError> {
        let (m, n_z, n_in, h) = (self.m(), self.n_z, self.n_in, self.basis.h);
        let nzm = n_z * m;
        let rows = n_in * m;
        let (zc, w, s) = (&u[..nzm], u[nzm], u[nzm + 1]);
        self.sys.set_friction_scale(s);
        let (fc, df) = self.aft(zc, jac)?;
        // ∂F/∂s: the remainder is affine in s.
        let dfs = if jac {
            let ds = 1e-2 * s.abs().max(1.0);
            self.sys.set_friction_scale(s + ds);
            let (f2, _) = self.aft(zc, false)?;
            self.sys.set_friction_scale(s);
            f2.iter()
                .zip(&fc)
                .map(|(a, b)| (a - b) / ds)
                .collect::<Vec<_>>()
        } else {
            Vec::new()
        };
        // H(ikω) (and dH/dω), row-major n_z × n_in.
        let mut hs: Vec<Vec<c64>> = Vec::with_capacity(h + 1);
        let mut dhs: Vec<Vec<c64>> = Vec::with_capacity(h + 1);
        for k in 0..=h {
            let (hk, dhk) = self.transfer(k, w, jac);
            hs.push((0..n_z * n_in).map(|x| hk[(x / n_in, x % n_in)]).collect());
            dhs.push(match dhk {
                Some(d) => (0..n_z * n_in).map(|x| d[(x / n_in, x % n_in)]).collect(),
                None => Vec::new(),
            });
        }
        // G = H F: the residual, and the same products for each column of the Jacobian.
        // `apply(f, out, sign)` writes −H f into the HB rows (f: an inputs' coefficient vector).
        let apply = |f: &[Real], out: &mut [Real]| {
            for a in 0..n_z {
                let h0 = &hs[0][a * n_in..(a + 1) * n_in];
                out[a * m] -= (0..n_in).map(|j| h0[j].re * f[j * m]).sum::<Real>();
                for k in 1..=h {
                    let (ic, is) = (2 * k - 1, 2 * k);
                    let hk = &hs[k][a * n_in..(a + 1) * n_in];
                    let (mut gc, mut gs) = (0.0, 0.0);
                    for j in 0..n_in {
                        let (hr, hi) = (hk[j].re, hk[j].im);
                        let (fcj, fsj) = (f[j * m + ic], f[j * m + is]);
                        gc += hr * fcj + hi * fsj;
                        gs += hi * fcj - hr * fsj;
                    }
                    out[a * m + ic] -= gc;
                    out[a * m + is] += gs;
                }
            }
        };
        let mut r = zc.to_vec();
        for a in 0..n_z {
            r[a * m] -= self.z0[a];
        }
        apply(&fc, &mut r);
        let jm = if jac {
            let df = df.expect("asked for the Jacobian");
            let mut jm = Mat::<Real>::zeros(nzm, nzm + 2);
            for col in 0..nzm {
                let c = jm.col_as_slice_mut(col);
                c[col] = 1.0;
                apply(&df[col * rows..(col + 1) * rows], c);
            }
            // ∂/∂s.
            apply(&dfs, jm.col_as_slice_mut(nzm + 1));
            // ∂/∂ω = −(dH/dω) F.
            let c = jm.col_as_slice_mut(nzm);
            for a in 0..n_z {
                for k in 1..=h {
                    let (ic, is) = (2 * k - 1, 2 * k);
                    let dk = &dhs[k][a * n_in..(a + 1) * n_in];
                    let (mut gc, mut gs) = (0.0, 0.0);
                    for j in 0..n_in {
                        let (dr, di) = (dk[j].re, dk[j].im);
                        let (fcj, fsj) = (fc[j * m + ic], fc[j * m + is]);
                        gc += dr * fcj + di * fsj;
                        gs += di * fcj - dr * fsj;
                    }
                    c[a * m + ic] = -gc;
                    c[a * m + is] = gs;
                }
            }
            Some(jm)
        } else {
            None
        };
        Ok(Eval { r, jac: jm })
    }
}
