//! The band-limited model: kept roots as real states, input and output maps, the static
//! correction.

use super::estimate::{estimate, Estimate, Kept};
use super::spectrum::Spectrum;
use super::{BandError, BandOptions, BandStats, Root};
use crate::cea::{CeaMatrices, Cplx};
use crate::Real;
use faer::linalg::solvers::Solve;
use faer::{c64, Mat};
use std::time::Instant;

/// The inputs and contact outputs of the band-limited model: the brake load's direction, the
/// force patterns the contact's remainder acts through and the velocity rows the friction
/// reads, all on the contact DOFs (where the constraint rows and the friction act).
///
/// Without patterns and rows, a unit force at each contact DOF and each contact DOF's
/// velocity. A gap's friction acts on its pad and rotor as a pair of opposite tangential forces
/// and depends on their relative tangential velocity only, so the gaps' relative coordinates
/// (per gap: the normal row of G and two tangential rows) serve as both with a third of the
/// unknowns of a node-paired mesh's contact DOFs.
#[derive(Debug, Clone, PartialEq)]
pub struct Inputs {
    /// The brake load vector p_brake (length n; empty: no load input).
    pub load: Vec<Real>,
    /// The contact DOFs, strictly increasing.
    pub contact_dofs: Vec<usize>,
    /// Force patterns over the contact DOFs (n_c × n_p; None: a unit force at each): the
    /// remainder of the contact law lies in their span.
    pub patterns: Option<Mat<Real>>,
    /// Velocity rows over the contact DOFs (n_v × n_c, full row rank; None: each contact DOF's
    /// velocity): the friction depends on the velocities only through them.
    pub velocity_rows: Option<Mat<Real>>,
    /// Rows (ng_c × n) giving the normal forces of the compliant rows from the displacement,
    /// G_k / c_k (empty: none); only the error estimate reads them.
    pub compliant_rows: Mat<Real>,
}

impl Inputs {
    /// A unit force and the velocity at each contact DOF.
    pub fn at_dofs(load: Vec<Real>, contact_dofs: Vec<usize>, compliant_rows: Mat<Real>) -> Self {
        Self {
            load,
            contact_dofs,
            patterns: None,
            velocity_rows: None,
            compliant_rows,
        }
    }

    /// Number of force patterns n_p.
    pub fn n_patterns(&self) -> usize {
        self.patterns
            .as_ref()
            .map_or(self.contact_dofs.len(), |p| p.ncols())
    }

    /// Number of velocity outputs n_v.
    pub fn n_velocities(&self) -> usize {
        self.velocity_rows
            .as_ref()
            .map_or(self.contact_dofs.len(), |r| r.nrows())
    }

    /// Number of inputs: the load (if any), then the patterns.
    pub fn len(&self) -> usize {
        usize::from(!self.load.is_empty()) + self.n_patterns()
    }

    /// True without any input.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Column of the first pattern's input.
    pub fn first_contact(&self) -> usize {
        usize::from(!self.load.is_empty())
    }

    /// The patterns over the contact DOFs (n_c × n_p).
    pub fn pattern_matrix(&self) -> Mat<Real> {
        let nc = self.contact_dofs.len();
        self.patterns
            .clone()
            .unwrap_or_else(|| Mat::<Real>::identity(nc, nc))
    }

    /// The velocity rows over the contact DOFs (n_v × n_c).
    pub fn velocity_matrix(&self) -> Mat<Real> {
        let nc = self.contact_dofs.len();
        self.velocity_rows
            .clone()
            .unwrap_or_else(|| Mat::<Real>::identity(nc, nc))
    }

    /// The input matrix (n × len).
    pub fn matrix(&self, n: usize) -> Mat<Real> {
        let o = self.first_contact();
        let mut f = Mat::zeros(n, self.len());
        if o == 1 {
            for (i, &p) in self.load.iter().enumerate() {
                f[(i, 0)] = p;
            }
        }
        let p = self.pattern_matrix();
        for (c, &d) in self.contact_dofs.iter().enumerate() {
            for j in 0..p.ncols() {
                f[(d, o + j)] = p[(c, j)];
            }
        }
        f
    }

    fn validate(&self, n: usize) -> Result<(), BandError> {
        let bad = |field, value: String, reason| BandError::Option {
            field,
            value,
            reason,
        };
        if !self.load.is_empty() && self.load.len() != n {
            return Err(bad(
                "inputs.load",
                self.load.len().to_string(),
                "length must be n",
            ));
        }
        if let Some(i) = self.load.iter().position(|x| !x.is_finite()) {
            return Err(bad("inputs.load", format!("entry {i}"), "must be finite"));
        }
        for w in self.contact_dofs.windows(2) {
            if w[1] <= w[0] {
                return Err(bad(
                    "inputs.contact_dofs",
                    format!("{} then {}", w[0], w[1]),
                    "must be strictly increasing",
                ));
            }
        }
        if let Some(&d) = self.contact_dofs.last() {
            if d >= n {
                return Err(bad("inputs.contact_dofs", d.to_string(), "must be < n"));
            }
        }
        let nc = self.contact_dofs.len();
        if let Some(p) = &self.patterns {
            if p.nrows() != nc {
                return Err(bad(
                    "inputs.patterns",
                    format!("{} rows", p.nrows()),
                    "must have a row per contact DOF",
                ));
            }
        }
        if let Some(r) = &self.velocity_rows {
            if r.ncols() != nc || r.nrows() == 0 {
                return Err(bad(
                    "inputs.velocity_rows",
                    format!("{} x {}", r.nrows(), r.ncols()),
                    "must have a column per contact DOF, and rows",
                ));
            }
        }
        if self.compliant_rows.nrows() > 0 && self.compliant_rows.ncols() != n {
            return Err(bad(
                "inputs.compliant_rows",
                self.compliant_rows.ncols().to_string(),
                "must have n columns",
            ));
        }
        Ok(())
    }
}

/// A reduced model condensed to its band (see the [module docs](super)).
///
/// Real states x: per kept complex pair ξ = x_a + i x_b (ẋ_a = Re λ x_a − Im λ x_b + Re b·f,
/// ẋ_b = Im λ x_a + Re λ x_b + Im b·f), per kept real root one state. The maps below are in
/// these states, so that u = u⁰ + C_u x + D_u f, v = C_v x + D_v f, Ñ = C_N x + D_N f, with f the
/// inputs ([`Inputs`]: load factor, then the forces at the contact DOFs).
#[derive(Debug, Clone)]
#[allow(non_snake_case)]
pub struct BandModel {
    /// DOFs n.
    pub n: usize,
    /// Rigid rows (multipliers Ñ).
    pub ng: usize,
    /// The inputs.
    pub inputs: Inputs,
    /// The kept roots (Im ≥ 0), in state order.
    pub roots: Vec<Cplx>,
    /// First state of each kept root.
    pub offsets: Vec<usize>,
    /// Number of real states.
    pub n_states: usize,
    /// Input map (n_states × inputs).
    pub B_x: Mat<Real>,
    /// Displacements of the states (n × n_states).
    pub C_u: Mat<Real>,
    /// Velocities of the states (n × n_states).
    pub C_v: Mat<Real>,
    /// Multiplier increments of the states (ng × n_states).
    pub C_N: Mat<Real>,
    /// Static correction of the displacements (n × inputs).
    pub D_u: Mat<Real>,
    /// Velocity feedthrough (n × inputs).
    pub D_v: Mat<Real>,
    /// Static correction of the multipliers (ng × inputs).
    pub D_N: Mat<Real>,
    /// What was kept, removed and estimated.
    pub stats: BandStats,
}

/// ξ ↦ real states: the (Re, −Im)-doubled columns of a complex shape matrix for pairs, the
/// real part for real roots.
fn real_columns(z: &Mat<c64>, pair: &[bool], offsets: &[usize], n_x: usize) -> Mat<Real> {
    let mut out = Mat::zeros(z.nrows(), n_x);
    for (j, (&p, &o)) in pair.iter().zip(offsets).enumerate() {
        for i in 0..z.nrows() {
            if p {
                out[(i, o)] = 2.0 * z[(i, j)].re;
                out[(i, o + 1)] = -2.0 * z[(i, j)].im;
            } else {
                out[(i, o)] = z[(i, j)].re;
            }
        }
    }
    out
}

/// Σ_kept (c_j w_j b_j): 2 Re(...) over pairs, Re(...) for real roots (n × inputs).
fn kept_sum(c: &Mat<c64>, b: &Mat<c64>, w: &[c64], pair: &[bool]) -> Mat<Real> {
    let k = c.ncols();
    let cw = Mat::from_fn(c.nrows(), k, |i, j| {
        c[(i, j)] * w[j] * if pair[j] { 2.0 } else { 1.0 }
    });
    let prod = &cw * b;
    Mat::from_fn(prod.nrows(), prod.ncols(), |i, j| prod[(i, j)].re)
}

/// The eigendecomposition of a linear operator, computed once, from which band-limited models
/// with any cut-off are made ([`Condenser::model`]).
pub struct Condenser<'a> {
    sys: &'a CeaMatrices,
    spec: Spectrum,
    time_eigen_s: Real,
}

impl<'a> Condenser<'a> {
    /// Decomposes the linear operator `sys` (compliant rows folded,
    /// [`crate::bsql::compliant_cea`]; `g`/`d` the rigid rows only).
    ///
    /// # Errors
    /// A refused operator (shapes, rank, mass) or a failed decomposition.
    pub fn new(sys: &'a CeaMatrices) -> Result<Self, BandError> {
        let t0 = Instant::now();
        let spec = Spectrum::new(sys)?;
        Ok(Self {
            sys,
            spec,
            time_eigen_s: t0.elapsed().as_secs_f64(),
        })
    }

    /// Every root of the operator (one per conjugate pair, Im ≥ 0).
    pub fn roots(&self) -> Vec<Cplx> {
        self.spec
            .vals
            .iter()
            .copied()
            .filter(|p| p.im >= 0.0)
            .collect()
    }

    /// The band-limited model for the `inputs` with the cut-off and tolerance of `opts`.
    ///
    /// # Errors
    /// Bad options or inputs; a singular static operator; an ill-conditioned
    /// eigendecomposition; an error estimate above the tolerance.
    pub fn model(&self, inputs: Inputs, opts: &BandOptions) -> Result<BandModel, BandError> {
        BandModel::from_spectrum(self.sys, &self.spec, self.time_eigen_s, inputs, opts)
    }
}

impl BandModel {
    /// Condenses the linear operator `sys` (compliant rows folded, [`crate::bsql::compliant_cea`];
    /// `g`/`d` the rigid rows only) for the `inputs` (one cut-off; several: [`Condenser`]).
    ///
    /// # Errors
    /// Bad options or inputs; a refused or singular operator; an ill-conditioned
    /// eigendecomposition; an error estimate above the tolerance.
    pub fn build(sys: &CeaMatrices, inputs: Inputs, opts: &BandOptions) -> Result<Self, BandError> {
        opts.validate()?;
        inputs.validate(sys.m.nrows())?;
        Condenser::new(sys)?.model(inputs, opts)
    }

    #[allow(non_snake_case)]
    fn from_spectrum(
        sys: &CeaMatrices,
        spec: &Spectrum,
        time_eigen_s: Real,
        inputs: Inputs,
        opts: &BandOptions,
    ) -> Result<Self, BandError> {
        opts.validate()?;
        let n = sys.m.nrows();
        inputs.validate(n)?;
        let t1 = Instant::now();
        let two_pi = 2.0 * std::f64::consts::PI;
        let freq = |p: Cplx| {
            if p.im == 0.0 {
                p.re.abs() / two_pi
            } else {
                p.im.abs() / two_pi
            }
        };
        let unstable = |p: Cplx| p.re > opts.unstable_tol * spec.rho;
        // One representative per root (Im ≥ 0), kept or removed.
        let mut kept_idx = Vec::new();
        let mut removed_all = Vec::new();
        let mut removed_rep = Vec::new();
        for (j, &p) in spec.vals.iter().enumerate() {
            let keep = freq(p) <= opts.cutoff_hz;
            if !keep {
                removed_all.push(j);
            }
            if p.im >= 0.0 {
                if keep {
                    kept_idx.push(j);
                } else {
                    removed_rep.push(j);
                }
            }
        }
        kept_idx.sort_by(|&a, &b| freq(spec.vals[a]).total_cmp(&freq(spec.vals[b])));
        let lams: Vec<Cplx> = kept_idx.iter().map(|&j| spec.vals[j]).collect();
        let pair: Vec<bool> = lams.iter().map(|p| p.im != 0.0).collect();
        let mut offsets = Vec::with_capacity(lams.len());
        let mut n_x = 0;
        for &p in &pair {
            offsets.push(n_x);
            n_x += if p { 2 } else { 1 };
        }

        // Input and output maps of the kept roots.
        let F = inputs.matrix(n);
        let e = spec.input_rows(&F);
        let left = spec.left_rows(&kept_idx);
        let mut b = &left * &Mat::from_fn(e.nrows(), e.ncols(), |i, j| c64::new(e[(i, j)], 0.0));
        let mut c = spec.shapes(&kept_idx);
        // Scale each mode so that its state is a velocity amplitude: max |v| of a unit state 1.
        for (j, &p) in lams.iter().enumerate() {
            let vmax = (0..n).fold(0.0f64, |m, i| m.max((c[(i, j)] * p).norm()));
            let s = if vmax > 0.0 {
                1.0 / ((if pair[j] { 2.0 } else { 1.0 }) * vmax)
            } else {
                1.0
            };
            for i in 0..n {
                c[(i, j)] *= s;
            }
            for i in 0..b.ncols() {
                b[(j, i)] *= 1.0 / s;
            }
        }
        let nu = spec.multipliers(&c, &lams);
        let cv = Mat::from_fn(n, lams.len(), |i, j| c[(i, j)] * lams[j]);
        let C_u = real_columns(&c, &pair, &offsets, n_x);
        let C_v = real_columns(&cv, &pair, &offsets, n_x);
        let C_N = real_columns(&nu, &pair, &offsets, n_x);
        let mut B_x = Mat::zeros(n_x, F.ncols());
        for (j, (&p, &o)) in pair.iter().zip(&offsets).enumerate() {
            for i in 0..F.ncols() {
                B_x[(o, i)] = b[(j, i)].re;
                if p {
                    B_x[(o + 1, i)] = b[(j, i)].im;
                }
            }
        }

        // The static correction.
        let (u_stat, n_stat) = static_response(sys, &F)?;
        let neg_inv: Vec<c64> = lams.iter().map(|&p| -1.0 / p).collect();
        let one = vec![c64::new(1.0, 0.0); lams.len()];
        let D_u = &u_stat - kept_sum(&c, &b, &neg_inv, &pair);
        let D_v = kept_sum(&c, &b, &one, &pair);
        let D_N = if spec.ng > 0 {
            &n_stat - kept_sum(&nu, &b, &neg_inv, &pair)
        } else {
            Mat::zeros(0, F.ncols())
        };

        let kept = Kept {
            lams: &lams,
            c: &c,
            b: &b,
            nu: &nu,
            d_u: &D_u,
            d_v: &D_v,
            d_n: &D_N,
        };
        let est: Estimate = estimate(spec, &kept, &inputs, &F, &u_stat, &removed_all, opts)?;
        let mut stats = BandStats {
            n,
            n_rigid_rows: spec.ng,
            n_roots: kept_idx.len() + removed_rep.len(),
            kept: kept_idx.len(),
            n_states: n_x,
            removed: removed_rep.len(),
            cutoff_hz: opts.cutoff_hz,
            band_hz: est.band_hz,
            error_estimate: est.error.max(est.error_force),
            error_velocity: est.error,
            error_force: est.error_force,
            error_at_hz: est.at_hz,
            static_check: est.static_check,
            time_eigen_s,
            ..Default::default()
        };
        stats.kept_max_frequency_hz = lams.iter().map(|&p| freq(p)).fold(0.0, Real::max);
        stats.removed_min_frequency_hz = removed_rep
            .iter()
            .map(|&j| freq(spec.vals[j]))
            .min_by(Real::total_cmp);
        let mut ru: Vec<Root> = removed_rep
            .iter()
            .map(|&j| spec.vals[j])
            .filter(|&p| unstable(p))
            .map(Root::of)
            .collect();
        ru.sort_by(|a, b| a.frequency_hz.total_cmp(&b.frequency_hz));
        stats.removed_unstable = ru.len();
        stats.largest_removed_unstable = ru
            .iter()
            .copied()
            .max_by(|a, b| a.real_part.total_cmp(&b.real_part));
        stats.removed_unstable_roots = ru;
        stats.kept_unstable = lams
            .iter()
            .copied()
            .filter(|&p| unstable(p))
            .map(Root::of)
            .collect();
        stats.time_maps_s = t1.elapsed().as_secs_f64();
        let limit = 1e-6;
        if est.static_check > limit {
            return Err(BandError::IllConditioned {
                error: est.static_check,
                limit,
            });
        }
        if stats.error_estimate > opts.tolerance {
            return Err(BandError::EstimateAboveTolerance {
                estimate: stats.error_estimate,
                at_hz: est.at_hz,
                tolerance: opts.tolerance,
                cutoff_hz: opts.cutoff_hz,
                removed_min_hz: stats.removed_min_frequency_hz.unwrap_or(Real::NAN),
            });
        }
        Ok(Self {
            n,
            ng: spec.ng,
            inputs,
            roots: lams,
            offsets,
            n_states: n_x,
            B_x,
            C_u,
            C_v,
            C_N,
            D_u,
            D_v,
            D_N,
            stats,
        })
    }

    /// ẋ = A_x x + B_x f: the linear part A_x x added into `out` (length n_states).
    pub fn add_linear(&self, x: &[Real], out: &mut [Real]) {
        for (p, &o) in self.roots.iter().zip(&self.offsets) {
            if p.im != 0.0 {
                let (a, b) = (x[o], x[o + 1]);
                out[o] += p.re * a - p.im * b;
                out[o + 1] += p.im * a + p.re * b;
            } else {
                out[o] += p.re * x[o];
            }
        }
    }
}

/// The static response [u; N] of [K_c, A_r; G_r, 0][u; N] = [F; 0] (u: n × k, N: ng × k), the
/// constraint rows scaled to K's diagonal.
#[allow(non_snake_case)]
pub(crate) fn static_response(
    sys: &CeaMatrices,
    F: &Mat<Real>,
) -> Result<(Mat<Real>, Mat<Real>), BandError> {
    let n = sys.m.nrows();
    let ng = sys.g.as_ref().map_or(0, |g| g.nrows());
    let kmax = (0..n).fold(0.0f64, |m, i| m.max(sys.k[(i, i)].abs()));
    let gmax = sys.g.as_ref().map_or(1.0, |g| {
        let mut x = 0.0f64;
        for j in 0..n {
            for i in 0..ng {
                x = x.max(g[(i, j)].abs());
            }
        }
        x
    });
    let s = if kmax > 0.0 && gmax > 0.0 {
        kmax / gmax
    } else {
        1.0
    };
    let a = Mat::from_fn(n + ng, n + ng, |i, j| match (i < n, j < n) {
        (true, true) => sys.k[(i, j)],
        (true, false) => {
            let g = sys.g.as_ref().map_or(0.0, |g| g[(j - n, i)]);
            s * (g - sys.d.as_ref().map_or(0.0, |d| d[(i, j - n)]))
        }
        (false, true) => s * sys.g.as_ref().map_or(0.0, |g| g[(i - n, j)]),
        (false, false) => 0.0,
    });
    let lu = a.partial_piv_lu();
    let ratio = crate::cea::operator::pivot_ratio(lu.U(), |x: &f64| x.abs());
    if ratio <= 1e3 * f64::EPSILON {
        return Err(BandError::SingularStatic(format!(
            "min/max |pivot| = {ratio:e} (size {})",
            n + ng
        )));
    }
    let mut x = Mat::zeros(n + ng, F.ncols());
    for j in 0..F.ncols() {
        for i in 0..n {
            x[(i, j)] = F[(i, j)];
        }
    }
    lu.solve_in_place(&mut x);
    let u_stat = Mat::from_fn(n, F.ncols(), |i, j| x[(i, j)]);
    let n_stat = Mat::from_fn(ng, F.ncols(), |i, j| s * x[(n + i, j)]);
    Ok((u_stat, n_stat))
}
