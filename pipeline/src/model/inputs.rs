//! Checks of a stored reduced model's inputs (`[model] from = "op4" | "punch"`, and model-cache
//! entries): the DOF map, and the matrices KR, MR, BR, PBRAKE.
//!
//! - A DOF listed twice in the map is an error naming both entries (a duplicate would merge two
//!   rows of the matrices onto one DOF and lose the other).
//! - Every matrix entry must be finite.
//! - KR, MR, BR must be symmetric: the relative asymmetry
//!   max |a_ij − a_ji| / max |a_ij| above [`ASYMMETRY_TOLERANCE`] is an error; a nonzero one at
//!   or below it is a [`Warning`] with the measured value, and the symmetric part (A + Aᵀ)/2 is
//!   used (the solvers assume symmetric K, M, B).
//! - MR must be positive definite: a failed Cholesky factorisation is an error with the smallest
//!   eigenvalue; a factorisable MR whose smallest eigenvalue (inverse iteration on the factor)
//!   is below [`MASS_SINGULARITY_TOLERANCE`] × its largest is an error (numerically singular).
//!   The transient integrates M v' = …, and the CEA factorises M: neither has a meaning for an
//!   indefinite or singular mass.
//! - KR must be positive semi-definite (an unconstrained stiffness: rigid-body modes at 0,
//!   elastic ones above): K + s·M with s = [`STIFFNESS_INDEFINITE_TOLERANCE`] × max_i K_ii/M_ii
//!   (a lower bound of the largest eigenvalue of (K, M)) must have a Cholesky factor, else the
//!   eigenvalues of (K, M) are computed and the most negative one below
//!   −[`STIFFNESS_INDEFINITE_TOLERANCE`] × the largest is an error with its value: a negative
//!   stiffness mode grows exponentially in the transient and sits on the real axis of the CEA,
//!   whatever the friction.
//! - The DOF map must not be empty (a model with nothing to analyse).

use crate::error::PipelineError;
use crate::warning::Warning;
use faer::linalg::solvers::Solve;
use faer::{Mat, Side};
use squeal_reduction::superelement::{DofKind, ReducedDofMap};
use std::collections::HashMap;
use std::path::Path;

use squeal_solver::Real;

/// Relative asymmetry max |a_ij − a_ji| / max |a_ij| above which a stored K, M or B is rejected.
/// Symmetric matrices written by NASTRAN or squeal in OP4 (16–17 significant digits) or as
/// symmetric DMIG are symmetric to the bit; a square DMIG in small field (~5–6 digits) may
/// differ in the last written digit, well below 1e-6 of the largest entry only when the
/// entry is small, so larger values mean the matrix itself is not symmetric.
pub const ASYMMETRY_TOLERANCE: Real = 1e-6;

/// Smallest-to-largest eigenvalue ratio of MR below which it is rejected as singular.
pub const MASS_SINGULARITY_TOLERANCE: Real = 1e-12;

/// Most negative eigenvalue of (KR, MR), relative to the largest, that a stored stiffness may
/// have. The rigid-body eigenvalues of a reduced free-free model are round-off: ~1e-16 ×
/// the largest for the reduction's own products, ~1e-13 after 16-digit OP4 text; 1e-8 leaves
/// five decades to those while a physical negative stiffness (a mis-signed spring, a
/// buckled prestress) is a sizeable fraction of the elastic ones.
pub const STIFFNESS_INDEFINITE_TOLERANCE: Real = 1e-8;

fn bad(path: &Path, message: String) -> PipelineError {
    PipelineError::Input {
        path: path.to_path_buf(),
        message,
    }
}

/// A DOF map's entries must be distinct (grid DOFs by grid and component 1..6, modal
/// coordinates by component and index).
pub(crate) fn check_dofmap(map: &ReducedDofMap, path: &Path) -> Result<(), PipelineError> {
    if map.dofs.is_empty() {
        return Err(bad(
            path,
            "the DOF map has no DOF: an empty model has nothing to analyse".into(),
        ));
    }
    let mut seen: HashMap<(Option<&str>, u64, u64), usize> = HashMap::new();
    for (i, d) in map.dofs.iter().enumerate() {
        let (key, what) = match d.kind {
            DofKind::Grid { grid, comp } => {
                if !(1..=6).contains(&comp) {
                    return Err(bad(
                        path,
                        format!("dofs[{i}]: grid {grid} component {comp} is not in 1..6"),
                    ));
                }
                (
                    (None, grid, comp as u64),
                    format!("grid {grid} component {comp}"),
                )
            }
            DofKind::Modal { index } => (
                (Some(d.component.as_str()), index as u64, 0),
                format!("modal coordinate {index} of component `{}`", d.component),
            ),
            DofKind::Interface { index } => (
                (Some(d.component.as_str()), index as u64, 1),
                format!(
                    "interface coordinate {index} of component `{}`",
                    d.component
                ),
            ),
        };
        if let Some(first) = seen.insert(key, i) {
            return Err(bad(
                path,
                format!("dofs[{first}] and dofs[{i}] are both {what}: a DOF may be listed once"),
            ));
        }
    }
    // Recovered grid DOFs: rows over existing DOFs, finite, not also a reduced DOF.
    let n = map.dofs.len();
    for (i, r) in map.recovered.iter().enumerate() {
        let what = format!("recovered[{i}] (grid {} component {})", r.grid, r.comp);
        if !(1..=6).contains(&r.comp) || seen.contains_key(&(None, r.grid, r.comp as u64)) {
            return Err(bad(
                path,
                format!("{what}: component not in 1..6, or the grid DOF is also a reduced DOF"),
            ));
        }
        if r.dofs.len() != r.coefs.len() {
            return Err(bad(
                path,
                format!(
                    "{what}: {} DOFs but {} coefficients",
                    r.dofs.len(),
                    r.coefs.len()
                ),
            ));
        }
        if let Some((&d, &c)) = r
            .dofs
            .iter()
            .zip(&r.coefs)
            .find(|(&d, c)| d >= n || !c.is_finite())
        {
            return Err(bad(
                path,
                format!(
                    "{what}: DOF {d} (of {n}) with coefficient {c} is out of range or not finite"
                ),
            ));
        }
    }
    Ok(())
}

/// Every entry finite.
pub(crate) fn check_finite(name: &str, a: &Mat<Real>, path: &Path) -> Result<(), PipelineError> {
    for j in 0..a.ncols() {
        for i in 0..a.nrows() {
            let v = a[(i, j)];
            if !v.is_finite() {
                return Err(bad(
                    path,
                    format!("matrix {name} entry ({}, {}) is {v}", i + 1, j + 1),
                ));
            }
        }
    }
    Ok(())
}

/// Relative asymmetry max |a_ij − a_ji| / max |a_ij| (0 for a zero matrix).
pub fn relative_asymmetry(a: &Mat<Real>) -> Real {
    let n = a.nrows();
    let (mut diff, mut big) = (0.0f64, 0.0f64);
    for j in 0..n {
        for i in 0..n {
            big = big.max(a[(i, j)].abs());
            if i > j {
                diff = diff.max((a[(i, j)] - a[(j, i)]).abs());
            }
        }
    }
    if big > 0.0 {
        diff / big
    } else {
        0.0
    }
}

/// The symmetric part of a stored square matrix after the asymmetry check (see the module
/// documentation); a tolerated asymmetry is pushed to `warnings`.
pub(crate) fn symmetric(
    name: &str,
    a: &Mat<Real>,
    path: &Path,
    warnings: &mut Vec<Warning>,
) -> Result<Mat<Real>, PipelineError> {
    check_finite(name, a, path)?;
    let r = relative_asymmetry(a);
    if r > ASYMMETRY_TOLERANCE {
        return Err(bad(
            path,
            format!(
                "matrix {name} is not symmetric: relative asymmetry max|a_ij - a_ji|/max|a_ij| = \
                 {r:.3e} > {ASYMMETRY_TOLERANCE:e}"
            ),
        ));
    }
    if r > 0.0 {
        warnings.push(Warning {
            input: format!("{}, matrix {name}", path.display()),
            message: format!(
                "relative asymmetry {r:.3e} (tolerance {ASYMMETRY_TOLERANCE:e}): its symmetric \
                 part (A + A^T)/2 is used"
            ),
            value: r,
            tolerance: ASYMMETRY_TOLERANCE,
        });
    }
    Ok(super::symmetrise(a))
}

/// Extreme eigenvalues of a symmetric matrix (dense, all of them); None if the solver fails.
fn extreme_eigenvalues(a: &Mat<Real>) -> Option<(Real, Real)> {
    let mut v = a.self_adjoint_eigenvalues(Side::Lower).ok()?;
    v.sort_by(Real::total_cmp);
    Some((*v.first()?, *v.last()?))
}

/// Checks that the (symmetric) mass `m` is positive definite and not numerically singular.
pub(crate) fn check_mass(name: &str, m: &Mat<Real>, path: &Path) -> Result<(), PipelineError> {
    let n = m.nrows();
    if n == 0 {
        return Ok(());
    }
    let llt = match m.llt(Side::Lower) {
        Ok(l) => l,
        Err(faer::linalg::cholesky::llt::factor::LltError::NonPositivePivot { index }) => {
            let detail = match extreme_eigenvalues(m) {
                Some((lo, hi)) => {
                    let kind = if lo < -MASS_SINGULARITY_TOLERANCE * hi.abs() {
                        "indefinite"
                    } else {
                        "singular"
                    };
                    format!("{kind}: smallest eigenvalue {lo:.6e}, largest {hi:.6e}")
                }
                None => "its eigenvalues could not be computed".into(),
            };
            return Err(bad(
                path,
                format!(
                    "matrix {name} is not positive definite ({detail}; Cholesky met a \
                     non-positive pivot at row {}); the transient and the CEA need a positive \
                     definite mass",
                    index + 1
                ),
            ));
        }
    };
    // Largest eigenvalue: power iteration from the all-ones vector, bounded below by the
    // largest diagonal entry; smallest: inverse iteration with the factor.
    let rayleigh = |x: &Mat<Real>| -> Real {
        let mx = m * x;
        let num: Real = (0..n).map(|i| x[(i, 0)] * mx[(i, 0)]).sum();
        let den: Real = (0..n).map(|i| x[(i, 0)] * x[(i, 0)]).sum();
        num / den
    };
    let normalise = |x: &mut Mat<Real>| {
        let s = (0..n).map(|i| x[(i, 0)] * x[(i, 0)]).sum::<Real>().sqrt();
        if s > 0.0 && s.is_finite() {
            for i in 0..n {
                x[(i, 0)] /= s;
            }
        }
    };
    // A start vector with no special symmetry: 1 + i/(n+1).
    let start = Mat::from_fn(n, 1, |i, _| 1.0 + i as Real / (n as Real + 1.0));
    let mut x = start.clone();
    for _ in 0..30 {
        x = m * &x;
        normalise(&mut x);
    }
    let diag_max = (0..n).map(|i| m[(i, i)]).fold(0.0, Real::max);
    let hi = rayleigh(&x).max(diag_max);
    let mut x = start;
    for _ in 0..30 {
        llt.solve_in_place(&mut x);
        normalise(&mut x);
    }
    let lo = rayleigh(&x);
    if lo.is_nan() || lo <= MASS_SINGULARITY_TOLERANCE * hi {
        return Err(bad(
            path,
            format!(
                "matrix {name} is numerically singular: smallest eigenvalue {lo:.3e}, largest \
                 {hi:.3e} (ratio below {MASS_SINGULARITY_TOLERANCE:e}); the transient and the \
                 CEA need a positive definite mass"
            ),
        ));
    }
    Ok(())
}

/// Checks that the (symmetric) stiffness `k` is positive semi-definite with respect to the
/// (positive definite) mass `m` (module documentation); the error names the matrix and its
/// most negative eigenvalue.
pub(crate) fn check_stiffness(
    name: &str,
    k: &Mat<Real>,
    m: &Mat<Real>,
    path: &Path,
) -> Result<(), PipelineError> {
    let n = k.nrows();
    let scale = (0..n)
        .filter(|&i| m[(i, i)] > 0.0)
        .map(|i| k[(i, i)] / m[(i, i)])
        .fold(0.0, Real::max);
    let shifted = Mat::from_fn(n, n, |i, j| {
        k[(i, j)] + STIFFNESS_INDEFINITE_TOLERANCE * scale * m[(i, j)]
    });
    if n == 0 || (scale > 0.0 && shifted.llt(Side::Lower).is_ok()) {
        return Ok(());
    }
    let (vals, _) =
        squeal_reduction::cb::dense_generalized_eigen(k.as_ref(), m.as_ref()).map_err(|e| {
            bad(
                path,
                format!("matrix {name}: the eigenvalues of ({name}, MR) failed: {e}"),
            )
        })?;
    let lo = vals.iter().copied().fold(Real::INFINITY, Real::min);
    let hi = vals.iter().copied().fold(Real::NEG_INFINITY, Real::max);
    if lo < -STIFFNESS_INDEFINITE_TOLERANCE * hi.abs().max(Real::MIN_POSITIVE) {
        let count = vals
            .iter()
            .filter(|&&v| v < -STIFFNESS_INDEFINITE_TOLERANCE * hi.abs())
            .count();
        return Err(bad(
            path,
            format!(
                "matrix {name} is indefinite: the most negative eigenvalue of ({name}, MR) is \
                 {lo:.6e} (largest {hi:.6e}; {count} below -{STIFFNESS_INDEFINITE_TOLERANCE:e} \
                 x the largest): a negative-stiffness mode grows in the transient and in the CEA \
                 whatever the friction; a stiffness must be positive semi-definite"
            ),
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A diagonal (K, M) with a negative entry is refused naming it; rigid-body round-off and
    /// a zero eigenvalue pass. Reference: the eigenvalues of diagonal pencils are k_i/m_i.
    #[test]
    fn indefinite_stiffness_is_refused_with_its_eigenvalue() {
        let p = Path::new("k.op4");
        let diag =
            |d: &[Real]| Mat::from_fn(d.len(), d.len(), |i, j| if i == j { d[i] } else { 0.0 });
        let m = diag(&[2.0, 1.0, 1.0]);
        assert!(check_stiffness("KR", &diag(&[0.0, 4.0, 9.0]), &m, p).is_ok());
        assert!(check_stiffness("KR", &diag(&[-1e-12, 4.0, 9.0]), &m, p).is_ok());
        let e = check_stiffness("KR", &diag(&[-3.0, 4.0, 9.0]), &m, p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("KR") && e.contains("indefinite") && e.contains("-1.500000e0"),
            "{e}"
        );
        // A rotated (non-diagonal) indefinite pencil: eigenvalues 5 and -1 of [[2, 3], [3, 2]].
        let k = Mat::from_fn(2, 2, |i, j| if i == j { 2.0 } else { 3.0 });
        let e = check_stiffness("KR", &k, &diag(&[1.0, 1.0]), p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("-1.000000e0") && e.contains("5.000000e0"), "{e}");
    }

    #[test]
    fn mass_check_measures_the_extreme_eigenvalues() {
        let p = Path::new("m.op4");
        let diag =
            |d: &[Real]| Mat::from_fn(d.len(), d.len(), |i, j| if i == j { d[i] } else { 0.0 });
        assert!(check_mass("MR", &diag(&[1.0, 2.0, 1e-6]), p).is_ok());
        let e = check_mass("MR", &diag(&[1.0, -0.5, 2.0]), p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("indefinite") && e.contains("-5.000000e-1"),
            "{e}"
        );
        let e = check_mass("MR", &diag(&[1.0, 0.0, 2.0]), p)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("singular") && e.contains("MR") && e.contains("m.op4"),
            "{e}"
        );
        // Factorisable, but its eigenvalues span 14 decades.
        let e = check_mass("MR", &diag(&[1.0, 1e-14, 2.0]), p)
            .unwrap_err()
            .to_string();
        assert!(e.contains("numerically singular"), "{e}");
    }

    #[test]
    fn asymmetry_is_relative_to_the_largest_entry() {
        let a = Mat::from_fn(2, 2, |i, j| [[4.0, 1.0], [1.0 + 4e-7, 2.0]][i][j]);
        assert!((relative_asymmetry(&a) - 1e-7).abs() < 1e-12);
        let mut w = Vec::new();
        let s = symmetric("KR", &a, Path::new("k.op4"), &mut w).unwrap();
        assert_eq!(s[(0, 1)], s[(1, 0)]);
        assert_eq!(w.len(), 1);
        assert!((w[0].value - 1e-7).abs() < 1e-12);
        let b = Mat::from_fn(2, 2, |i, j| [[4.0, 1.0], [1.1, 2.0]][i][j]);
        let e = symmetric("KR", &b, Path::new("k.op4"), &mut w)
            .unwrap_err()
            .to_string();
        assert!(e.contains("KR") && e.contains("2.500e-2"), "{e}");
    }
}
