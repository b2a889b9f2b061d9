//! Checks of a Craig–Bampton model (as pyyeti's `cbcheck`): symmetry, M_qq = I, K_bq = 0,
//! rigid-body mass and centre of gravity, free-free rigid modes, frequencies against the full model.

use super::eigen::{self, LanczosParams, Want};
use super::interface::project_blocks;
use super::model::CbModel;
use super::partition::{add_scaled, split, sym_spmm, to_dense, Partition, Sparse};
use super::rigid::{rigid_body_mass, rigid_vectors, DofPoint, RigidBodyMass};
use super::verify::{verify, Verification};
use crate::error::ReductionError;
use faer::linalg::solvers::Solve;
use faer::sparse::linalg::solvers::{Llt, SymbolicLlt};
use faer::{Mat, MatRef, Side};
use serde::{Deserialize, Serialize};
use squeal_meshes::Real;
use std::f64::consts::PI;
use std::fmt;

/// How the full component's frequencies are obtained for models above `dense_max` DOFs.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum FullMethod {
    /// One LDLᵀ of K − σM at the band's top: the Sturm count of the full modes below it, and
    /// the reduced modes refined by a few shift-invert solves ([`Verification`]).
    #[default]
    Refine,
    /// A block Lanczos solve of the full component (a second eigen-solve: slow on big models).
    Lanczos,
}

/// Options of [`check`]: what is compared, and the tolerances that decide `passed`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CheckOptions {
    /// Frequencies are compared up to this, Hz (default: none = the model's own frequency of
    /// interest, else half its cutoff, else half its highest fixed-interface frequency).
    pub frequency_of_interest_hz: Option<Real>,
    /// A reduced mode is rigid when its eigenvalue is below this × the largest (default: 1e-8).
    pub rigid_rel_tol: Real,
    /// Full models up to this many DOFs are solved densely, larger ones by `full_method`
    /// (default: 2000).
    pub dense_max: usize,
    /// How the full component's frequencies are obtained above `dense_max` (default: refine).
    pub full_method: FullMethod,
    /// Largest |frequency error| of an elastic mode below the frequency of interest, % (default: 2).
    pub max_error_pct: Real,
    /// Largest relative error of the rigid-body mass and of the centre of gravity (default: 1e-6).
    pub max_mass_rel_err: Real,
    /// Largest max |M_qq − I| and max |K_bq| / max |K_r| (default: 1e-8).
    pub max_modal_deviation: Real,
    /// Largest relative residual of the refined full-component modes: above it the
    /// verification itself is not converged (default: 1e-3).
    pub max_refined_residual: Real,
    /// Compare the rigid-body mass and centre of gravity (default: true). A component held by
    /// fixed DOFs has no rigid-body motion in its free DOFs, so the comparison means nothing
    /// there: the caller turns it off.
    pub rigid_body: bool,
}

impl Default for CheckOptions {
    fn default() -> Self {
        Self {
            frequency_of_interest_hz: None,
            rigid_rel_tol: 1e-8,
            dense_max: 2000,
            full_method: FullMethod::Refine,
            max_error_pct: 2.0,
            max_mass_rel_err: 1e-6,
            max_modal_deviation: 1e-8,
            max_refined_residual: 1e-3,
            rigid_body: true,
        }
    }
}

impl CheckOptions {
    /// The relative accuracy of the refined full-component frequencies (`full_method =
    /// refine`): 1e-3 of the frequency tolerance, so that no verdict turns on the refinement's
    /// own error.
    pub fn refine_frequency_tol(&self) -> Real {
        1e-3 * self.max_error_pct / 100.0
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), ReductionError> {
        if let Some(f) = self.frequency_of_interest_hz {
            if !(f.is_finite() && f > 0.0) {
                return Err(ReductionError::InvalidOption {
                    field: "frequency_of_interest_hz",
                    value: f.to_string(),
                    reason: "must be finite and > 0".into(),
                });
            }
        }
        if !(self.rigid_rel_tol > 0.0 && self.rigid_rel_tol < 1.0) {
            return Err(ReductionError::InvalidOption {
                field: "rigid_rel_tol",
                value: self.rigid_rel_tol.to_string(),
                reason: "must be in (0, 1)".into(),
            });
        }
        for (field, v) in [
            ("max_error_pct", self.max_error_pct),
            ("max_mass_rel_err", self.max_mass_rel_err),
            ("max_modal_deviation", self.max_modal_deviation),
            ("max_refined_residual", self.max_refined_residual),
        ] {
            if !(v.is_finite() && v > 0.0) {
                return Err(ReductionError::InvalidOption {
                    field,
                    value: v.to_string(),
                    reason: "must be finite and > 0".into(),
                });
            }
        }
        Ok(())
    }
}

/// Rigid-body mass of the reduced model (from the boundary rigid-body vectors) and of the full one.
#[derive(Debug, Clone, Serialize)]
pub struct RigidCheck {
    pub reduced: RigidBodyMass,
    pub full: Option<RigidBodyMass>,
    /// max_a |m_a,red − m_a,full| / m_a,full.
    pub mass_rel_err: Option<Real>,
    /// |cg_red − cg_full| / (size of the model's bounding box).
    pub cg_rel_err: Option<Real>,
    /// max |R_redᵀM̂R_red − R_fullᵀMR_full| / max |R_fullᵀMR_full|.
    pub matrix_rel_err: Option<Real>,
}

/// One row of the frequency table.
#[derive(Debug, Clone, Serialize)]
pub struct FrequencyRow {
    /// Mode number, 1-based.
    pub mode: usize,
    pub full_hz: Option<Real>,
    pub reduced_hz: Option<Real>,
    /// 100 (reduced − full)/full, for elastic modes.
    pub error_pct: Option<Real>,
}

/// Result of [`check`].
#[derive(Debug, Clone, Serialize)]
pub struct CbCheck {
    pub n_boundary: usize,
    pub n_modes: usize,
    /// max |K − Kᵀ| / max |K| of the reduced stiffness.
    pub k_asymmetry: Real,
    /// max |M − Mᵀ| / max |M| of the reduced mass.
    pub m_asymmetry: Real,
    /// max |ΦᵀM_iiΦ − I| (recomputed from the full M when given, else the stored block).
    pub mqq_max_deviation: Real,
    /// max |K_bq| / max |K_r| (recomputed as (K_ib + K_iiΨ)ᵀΦ from the full K when given).
    pub kbq_rel: Real,
    /// Free-free rigid modes of the reduced model.
    pub n_rigid_modes: usize,
    /// Frequency below which a mode counts as rigid, Hz.
    pub rigid_threshold_hz: Real,
    /// The rigid-body mass check (None: an interface basis, or `CheckOptions::rigid_body` off
    /// for a held component).
    pub rigid: Option<RigidCheck>,
    pub frequency_of_interest_hz: Real,
    pub frequencies: Vec<FrequencyRow>,
    /// Largest |error_pct| over the table.
    pub max_abs_error_pct: Option<Real>,
    /// How the full frequencies were obtained: `dense`, `refine` or `lanczos` (`none` without
    /// the full matrices).
    pub full_method: &'static str,
    /// The Sturm count and refinement, with `full_method = refine`.
    pub verification: Option<Verification>,
    /// Whether every check is within `CheckOptions`' tolerances.
    pub passed: bool,
    /// What failed, one sentence each with the numbers.
    pub failures: Vec<String>,
}

fn max_abs(a: MatRef<'_, Real>) -> Real {
    let mut m: Real = 0.0;
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            m = m.max(a[(i, j)].abs());
        }
    }
    m
}

fn asymmetry(a: MatRef<'_, Real>) -> Real {
    let d = a - a.transpose();
    let s = max_abs(a);
    if s > 0.0 {
        max_abs(d.as_ref()) / s
    } else {
        0.0
    }
}

/// Checks a Craig–Bampton model. `full` = the component's (K, M) the model was reduced from;
/// `points` = location of every free DOF of the component (length `model.n_dofs`), needed for the
/// rigid-body mass (the reduced one uses the boundary DOFs' points only).
pub fn check(
    model: &CbModel,
    full: Option<(&Sparse, &Sparse)>,
    points: Option<&[DofPoint]>,
    opts: &CheckOptions,
) -> Result<CbCheck, ReductionError> {
    opts.validate()?;
    let nb = model.n_boundary_coords();
    let nq = model.n_modes;
    let n = model.n_dofs;
    if let Some(p) = points {
        if p.len() != n {
            return Err(ReductionError::ShapeMismatch {
                what: "DOF points".into(),
                rows: p.len(),
                cols: 1,
                expected_rows: n,
                expected_cols: 1,
            });
        }
    }
    let k_asymmetry = asymmetry(model.k.as_ref());
    let m_asymmetry = asymmetry(model.m.as_ref());

    // M_qq = I and K_bq = 0.
    let kscale = max_abs(model.k.as_ref()).max(Real::MIN_POSITIVE);
    let (mqq, kbq) = match full {
        Some((k, m)) => {
            let all: Vec<usize> = model
                .boundary
                .iter()
                .chain(model.interface.iter().flat_map(|f| f.dofs.iter()))
                .copied()
                .collect();
            let part = Partition::new(n, &all)?;
            let project = |b| match &model.interface {
                Some(f) => project_blocks(b, model.boundary.len(), f.basis.as_ref()),
                None => b,
            };
            let kp = project(split(k, &part));
            let mp = project(split(m, &part));
            let mqq = model.phi.transpose() * sym_spmm(&mp.ii, model.phi.as_ref());
            let kbq = if nq > 0 {
                let r = sym_spmm(&kp.ii, model.psi.as_ref()) + to_dense(&kp.ib);
                r.transpose() * &model.phi
            } else {
                Mat::zeros(nb, 0)
            };
            (mqq, kbq)
        }
        None => (
            model.m.submatrix(nb, nb, nq, nq).to_owned(),
            model.k.submatrix(0, nb, nb, nq).to_owned(),
        ),
    };
    let mqq_max_deviation = max_abs((mqq - Mat::<Real>::identity(nq, nq)).as_ref());
    let kbq_rel = max_abs(kbq.as_ref()) / kscale;

    // Reduced free-free modes.
    let (red_vals, red_vecs) =
        eigen::dense_all(model.k.as_ref(), model.m.as_ref(), "reduced model")?;
    let lmax = red_vals.iter().fold(0.0, |a: Real, &v| a.max(v.abs()));
    let rigid_lambda = opts.rigid_rel_tol * lmax;
    let n_rigid_modes = red_vals.iter().filter(|&&v| v.abs() < rigid_lambda).count();
    let rigid_threshold_hz = rigid_lambda.sqrt() / (2.0 * PI);
    let hz = |l: Real| l.max(0.0).sqrt() / (2.0 * PI);

    // Rigid-body mass.
    // Rigid-body vectors in the reduced coordinates need physical boundary DOFs only: not
    // computed with an interface basis.
    let rigid = points
        .filter(|_| model.interface.is_none() && opts.rigid_body)
        .map(|pts| {
            let bpts: Vec<DofPoint> = model.boundary.iter().map(|&d| pts[d]).collect();
            let rb = rigid_vectors(&bpts);
            let mbb = model.m.submatrix(0, 0, nb, nb);
            let reduced = rigid_body_mass((rb.transpose() * mbb * &rb).as_ref());
            let full_rb = full.map(|(_, m)| {
                let r = rigid_vectors(pts);
                rigid_body_mass((r.transpose() * sym_spmm(m, r.as_ref())).as_ref())
            });
            let size = bbox_size(pts);
            let (mass_rel_err, cg_rel_err, matrix_rel_err) = match &full_rb {
                Some(f) => {
                    let me = (0..3)
                        .map(|a| ((reduced.mass[a] - f.mass[a]) / f.mass[a]).abs())
                        .fold(0.0, Real::max);
                    let ce = (0..3)
                        .map(|a| (reduced.cg[a] - f.cg[a]).powi(2))
                        .sum::<Real>()
                        .sqrt()
                        / size;
                    let fs = f
                        .matrix
                        .iter()
                        .flatten()
                        .fold(0.0, |a: Real, v| a.max(v.abs()));
                    let de = (0..36)
                        .map(|i| (reduced.matrix[i / 6][i % 6] - f.matrix[i / 6][i % 6]).abs())
                        .fold(0.0, Real::max);
                    (Some(me), Some(ce), Some(de / fs))
                }
                None => (None, None, None),
            };
            RigidCheck {
                reduced,
                full: full_rb,
                mass_rel_err,
                cg_rel_err,
                matrix_rel_err,
            }
        });

    // Frequencies against the full model.
    let foi = opts
        .frequency_of_interest_hz
        .or(model.stats.frequency_of_interest_hz)
        .or(model.stats.cutoff_hz.map(|c| 0.5 * c))
        .or(model.fixed_frequencies_hz.last().map(|f| 0.5 * f))
        .unwrap_or(Real::INFINITY);
    let red_hz: Vec<Real> = red_vals
        .iter()
        .map(|&l| hz(l))
        .filter(|&f| f <= foi)
        .collect();
    let (full_hz, full_method, verification) = match full {
        Some((k, m)) if n > opts.dense_max && foi.is_finite() => match opts.full_method {
            FullMethod::Refine => {
                let (hz, v) = verify(
                    model,
                    k,
                    m,
                    (&red_vals, red_vecs.as_ref()),
                    foi,
                    points,
                    opts.refine_frequency_tol(),
                )?;
                (hz, "refine", Some(v))
            }
            FullMethod::Lanczos => (full_frequencies(k, m, foi, opts)?, "lanczos", None),
        },
        Some((k, m)) => (full_frequencies(k, m, foi, opts)?, "dense", None),
        None => (Vec::new(), "none", None),
    };
    drop(red_vecs);
    let rows = red_hz.len().max(full_hz.len());
    let frequencies: Vec<FrequencyRow> = (0..rows)
        .map(|i| {
            let (f, r) = (full_hz.get(i).copied(), red_hz.get(i).copied());
            let error_pct = match (f, r) {
                (Some(f), Some(r)) if f > rigid_threshold_hz && r > rigid_threshold_hz => {
                    Some(100.0 * (r - f) / f)
                }
                _ => None,
            };
            FrequencyRow {
                mode: i + 1,
                full_hz: f,
                reduced_hz: r,
                error_pct,
            }
        })
        .collect();
    let max_abs_error_pct = frequencies
        .iter()
        .filter_map(|r| r.error_pct)
        .map(Real::abs)
        .reduce(Real::max);
    // The verdict.
    let mut failures = Vec::new();
    if k_asymmetry > 1e-10 || m_asymmetry > 1e-10 {
        failures.push(format!(
            "reduced matrices not symmetric: K {k_asymmetry:.2e}, M {m_asymmetry:.2e} (> 1e-10)"
        ));
    }
    if mqq_max_deviation > opts.max_modal_deviation {
        failures.push(format!(
            "max |M_qq - I| = {mqq_max_deviation:.2e} > {:.1e}: the modes are not M-orthonormal",
            opts.max_modal_deviation
        ));
    }
    if kbq_rel > opts.max_modal_deviation {
        failures.push(format!(
            "max |K_bq| / max |K| = {kbq_rel:.2e} > {:.1e}: the constraint modes are not static",
            opts.max_modal_deviation
        ));
    }
    if let Some(r) = &rigid {
        for (what, e) in [
            ("rigid-body mass", r.mass_rel_err),
            ("centre of gravity", r.cg_rel_err),
        ] {
            if let Some(e) = e.filter(|&e| e.is_nan() || e > opts.max_mass_rel_err) {
                failures.push(format!(
                    "{what}: reduced vs full relative error {e:.2e} > {:.1e}",
                    opts.max_mass_rel_err
                ));
            }
        }
    }
    if let Some(e) = max_abs_error_pct.filter(|&e| e.is_nan() || e > opts.max_error_pct) {
        let row = frequencies
            .iter()
            .find(|r| r.error_pct.is_some_and(|x| x.abs() == e));
        failures.push(format!(
            "frequency error {e:.3} % > {} % (mode {}, full {:.2} Hz): raise the cut-off",
            opts.max_error_pct,
            row.map_or(0, |r| r.mode),
            row.and_then(|r| r.full_hz).unwrap_or(Real::NAN)
        ));
    }
    if full.is_some() {
        if let Some(row) = frequencies.iter().find(|r| r.reduced_hz.is_none()) {
            failures.push(format!(
                "mode {} of the full component ({:.2} Hz) has no reduced mode below {foi} Hz",
                row.mode,
                row.full_hz.unwrap_or(Real::NAN)
            ));
        }
    }
    if let Some(v) = &verification {
        if v.n_refined_below < v.n_full_below {
            failures.push(format!(
                "{} of the {} full-component modes below {:.2} Hz (Sturm count) are missing \
                 from the reduced model's subspace (a fixed-interface mode below the cut-off \
                 not found?)",
                v.n_full_below - v.n_refined_below,
                v.n_full_below,
                v.shift_hz
            ));
        }
        if v.max_refined_residual.is_nan() || v.max_refined_residual > opts.max_refined_residual {
            failures.push(format!(
                "the refined full-component modes are not converged (relative residual {:.2e} \
                 > {:.1e}): the frequency errors are not verified",
                v.max_refined_residual, opts.max_refined_residual
            ));
        }
    }
    Ok(CbCheck {
        passed: failures.is_empty(),
        failures,
        full_method,
        verification,
        n_boundary: nb,
        n_modes: nq,
        k_asymmetry,
        m_asymmetry,
        mqq_max_deviation,
        kbq_rel,
        n_rigid_modes,
        rigid_threshold_hz,
        rigid,
        frequency_of_interest_hz: foi,
        frequencies,
        max_abs_error_pct,
    })
}

fn bbox_size(pts: &[DofPoint]) -> Real {
    let mut lo = [Real::INFINITY; 3];
    let mut hi = [Real::NEG_INFINITY; 3];
    for p in pts {
        for a in 0..3 {
            lo[a] = lo[a].min(p.xyz[a]);
            hi[a] = hi[a].max(p.xyz[a]);
        }
    }
    let d = (0..3).map(|a| (hi[a] - lo[a]).powi(2)).sum::<Real>().sqrt();
    if d > 0.0 {
        d
    } else {
        1.0
    }
}

/// Free-free frequencies of the full model up to `foi` Hz (dense, or block Lanczos about a
/// negative shift σ = −(0.1 · 2π foi)², which makes K − σM positive definite).
fn full_frequencies(
    k: &Sparse,
    m: &Sparse,
    foi: Real,
    opts: &CheckOptions,
) -> Result<Vec<Real>, ReductionError> {
    let n = k.nrows();
    let lambda_max = if foi.is_finite() {
        Some((2.0 * PI * foi).powi(2))
    } else {
        None
    };
    let want = Want {
        lambda_max,
        n_max: None,
    };
    let pairs = if n <= opts.dense_max || lambda_max.is_none() {
        eigen::dense(
            to_dense(k).as_ref(),
            to_dense(m).as_ref(),
            want,
            "full model",
        )?
    } else {
        let sigma = -(0.1 * 2.0 * PI * foi).powi(2);
        let shifted = add_scaled(k, m, -sigma);
        let ferr = |e: String| ReductionError::Factorization {
            what: "full K − σM".into(),
            n,
            detail: e,
        };
        let sym = SymbolicLlt::try_new(shifted.symbolic(), Side::Lower)
            .map_err(|e| ferr(format!("{e:?}")))?;
        let llt = Llt::try_new_with_symbolic(sym, shifted.as_ref(), Side::Lower)
            .map_err(|e| ferr(format!("{e:?}")))?;
        let solve = |x: faer::MatMut<'_, Real>| llt.solve_in_place(x);
        let params = LanczosParams {
            block: 6,
            max_dim: 900,
            tol: 1e-9,
        };
        eigen::lanczos(
            &solve,
            m,
            sigma,
            want,
            params,
            "full model",
            &squeal_fe::Interrupt::never(),
        )?
    };
    Ok(pairs
        .values
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * PI))
        .collect())
}

impl fmt::Display for CbCheck {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Craig–Bampton check: {} boundary DOFs, {} modes",
            self.n_boundary, self.n_modes
        )?;
        writeln!(f, "  K asymmetry (rel)        {:.3e}", self.k_asymmetry)?;
        writeln!(f, "  M asymmetry (rel)        {:.3e}", self.m_asymmetry)?;
        writeln!(
            f,
            "  max |M_qq - I|           {:.3e}",
            self.mqq_max_deviation
        )?;
        writeln!(f, "  max |K_bq| / max |K|     {:.3e}", self.kbq_rel)?;
        writeln!(
            f,
            "  free-free rigid modes    {} (below {:.3e} Hz)",
            self.n_rigid_modes, self.rigid_threshold_hz
        )?;
        if let Some(r) = &self.rigid {
            let m = r.reduced.mass;
            let c = r.reduced.cg;
            writeln!(
                f,
                "  rigid mass (reduced)     [{:.6e}, {:.6e}, {:.6e}]",
                m[0], m[1], m[2]
            )?;
            writeln!(
                f,
                "  CG (reduced)             [{:.6e}, {:.6e}, {:.6e}]",
                c[0], c[1], c[2]
            )?;
            if let Some(fu) = &r.full {
                let (m, c) = (fu.mass, fu.cg);
                writeln!(
                    f,
                    "  rigid mass (full)        [{:.6e}, {:.6e}, {:.6e}]",
                    m[0], m[1], m[2]
                )?;
                writeln!(
                    f,
                    "  CG (full)                [{:.6e}, {:.6e}, {:.6e}]",
                    c[0], c[1], c[2]
                )?;
            }
            if let (Some(me), Some(ce)) = (r.mass_rel_err, r.cg_rel_err) {
                writeln!(f, "  mass rel. error {me:.3e}, CG error / size {ce:.3e}")?;
            }
        }
        writeln!(
            f,
            "  frequencies up to {:.6} Hz:",
            self.frequency_of_interest_hz
        )?;
        writeln!(
            f,
            "  {:>5} {:>14} {:>14} {:>10}",
            "mode", "full Hz", "reduced Hz", "error %"
        )?;
        let opt = |v: Option<Real>, p: usize| v.map_or("-".to_string(), |x| format!("{x:.p$}"));
        for r in &self.frequencies {
            writeln!(
                f,
                "  {:>5} {:>14} {:>14} {:>10}",
                r.mode,
                opt(r.full_hz, 4),
                opt(r.reduced_hz, 4),
                opt(r.error_pct, 4)
            )?;
        }
        if let Some(e) = self.max_abs_error_pct {
            writeln!(f, "  max |error| {e:.4} %")?;
        }
        writeln!(f, "  full frequencies by      {}", self.full_method)?;
        if let Some(v) = &self.verification {
            writeln!(
                f,
                "  modes below {:.2} Hz: full {} (Sturm count), reduced {}, refined {} \
                 (residual {:.1e}, {} solves, last step moved them {})",
                v.shift_hz,
                v.n_full_below,
                v.n_reduced_below,
                v.n_refined_below,
                v.max_refined_residual,
                v.n_solves,
                v.frequency_change
                    .map_or("-".to_string(), |c| format!("{:.1e}", c))
            )?;
        }
        if self.passed {
            writeln!(f, "  passed")?;
        } else {
            for x in &self.failures {
                writeln!(f, "  FAILED: {x}")?;
            }
        }
        Ok(())
    }
}
