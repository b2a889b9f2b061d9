//! Two reduced models side by side: DOF maps aligned, matrix differences, undamped modes
//! paired by MAC.
//!
//! # Reference
//! Undamped modes: K φ = ω² M φ, solved densely (`squeal_reduction::cb::dense_generalized_eigen`).
//! Modal assurance criterion of mode a of model A and mode b of model B on the common DOFs,
//! weighted by A's mass:
//! $$\mathrm{MAC}(a, b) = \frac{|φ_a^T M φ_b|^2}{(φ_a^T M φ_a)(φ_b^T M φ_b)}.$$

use crate::error::PipelineError;
use crate::model::ReducedModel;
use faer::Mat;
use serde::Serialize;
use squeal_reduction::superelement::{DofKind, ReducedDof};
use std::collections::HashMap;

use squeal_solver::Real;

/// A DOF's identity across models: a grid component, or a component's modal coordinate.
#[derive(Debug, Clone, PartialEq, Eq, Hash)]
enum DofId {
    Grid(u64, u8),
    Modal(String, usize),
    Interface(String, usize),
}

fn id(d: &ReducedDof) -> DofId {
    match d.kind {
        DofKind::Grid { grid, comp } => DofId::Grid(grid, comp),
        DofKind::Modal { index } => DofId::Modal(d.component.clone(), index),
        DofKind::Interface { index } => DofId::Interface(d.component.clone(), index),
    }
}

fn describe(d: &ReducedDof) -> String {
    match d.kind {
        DofKind::Grid { grid, comp } => format!("grid {grid} component {comp}"),
        DofKind::Modal { index } => format!("modal coordinate {index} of `{}`", d.component),
        DofKind::Interface { index } => {
            format!("interface coordinate {index} of `{}`", d.component)
        }
    }
}

/// For each DOF of A, its index in B. The maps must hold the same DOFs (in any order); else
/// an error names the first DOF one model lacks.
pub fn align(a: &ReducedModel, b: &ReducedModel) -> Result<Vec<usize>, String> {
    let index: HashMap<DofId, usize> = b
        .dofs
        .dofs
        .iter()
        .enumerate()
        .map(|(i, d)| (id(d), i))
        .collect();
    let mut perm = Vec::with_capacity(a.n());
    for (i, d) in a.dofs.dofs.iter().enumerate() {
        match index.get(&id(d)) {
            Some(&j) => perm.push(j),
            None => return Err(format!("DOF {i} of A ({}) is not a DOF of B", describe(d))),
        }
    }
    if b.n() != a.n() {
        let ids: std::collections::HashSet<DofId> = a.dofs.dofs.iter().map(id).collect();
        if let Some((j, d)) = b
            .dofs
            .dofs
            .iter()
            .enumerate()
            .find(|(_, d)| !ids.contains(&id(d)))
        {
            return Err(format!("DOF {j} of B ({}) is not a DOF of A", describe(d)));
        }
        return Err(format!(
            "A has {} DOFs, B {} (a DOF listed twice)",
            a.n(),
            b.n()
        ));
    }
    Ok(perm)
}

/// ‖A − B‖_F / ‖A‖_F of one matrix (B's rows and columns taken in A's DOF order).
#[derive(Debug, Clone, Serialize)]
pub struct MatrixDiff {
    /// KR, MR, BR, PBRAKE.
    pub name: String,
    /// ‖A‖_F and ‖B‖_F (0 for a matrix the model lacks).
    pub norm_a: Real,
    pub norm_b: Real,
    /// ‖A − B‖_F.
    pub norm_difference: Real,
    /// ‖A − B‖_F / ‖A‖_F (the difference itself when ‖A‖_F = 0).
    pub relative: Real,
    /// Largest |a_ij − b_ij| and where (row, column, DOFs of A).
    pub max_abs_difference: Real,
    pub at: Option<(usize, usize)>,
}

/// The matrix differences of A and B (B permuted by `perm`, [`align`]).
pub fn matrix_diffs(a: &ReducedModel, b: &ReducedModel, perm: &[usize]) -> Vec<MatrixDiff> {
    let n = a.n();
    let vec_mat = |p: &[Real]| Mat::from_fn(p.len(), 1, |i, _| p[i]);
    type Pair<'a> = (&'a str, Option<Mat<Real>>, Option<Mat<Real>>);
    let pairs: Vec<Pair> = vec![
        ("KR", Some(a.k.clone()), Some(b.k.clone())),
        ("MR", Some(a.m.clone()), Some(b.m.clone())),
        ("BR", a.b.clone(), b.b.clone()),
        (
            "PBRAKE",
            Some(vec_mat(&a.p_brake)),
            Some(vec_mat(&b.p_brake)),
        ),
    ];
    let mut out = Vec::new();
    for (name, ma, mb) in pairs {
        if ma.is_none() && mb.is_none() {
            continue;
        }
        let cols = if name == "PBRAKE" { 1 } else { n };
        let get_a = |i: usize, j: usize| ma.as_ref().map_or(0.0, |m| m[(i, j)]);
        let get_b = |i: usize, j: usize| {
            mb.as_ref().map_or(0.0, |m| {
                let jj = if cols == 1 { 0 } else { perm[j] };
                m[(perm[i], jj)]
            })
        };
        let (mut na, mut nb, mut nd, mut max, mut at) = (0.0, 0.0, 0.0, 0.0, None);
        for j in 0..cols {
            for i in 0..n {
                let (x, y) = (get_a(i, j), get_b(i, j));
                na += x * x;
                nb += y * y;
                let d = x - y;
                nd += d * d;
                if d.abs() > max {
                    max = d.abs();
                    at = Some((i, j));
                }
            }
        }
        let (na, nb, nd): (Real, Real, Real) = (na.sqrt(), nb.sqrt(), nd.sqrt());
        out.push(MatrixDiff {
            name: name.into(),
            norm_a: na,
            norm_b: nb,
            norm_difference: nd,
            relative: if na > 0.0 { nd / na } else { nd },
            max_abs_difference: max,
            at,
        });
    }
    out
}

/// Undamped modes of (K, M): frequencies (Hz) and M-normalised shapes (columns).
pub fn modes(m: &ReducedModel, what: &str) -> Result<(Vec<Real>, Mat<Real>), PipelineError> {
    let (vals, vecs) = squeal_reduction::cb::dense_generalized_eigen(m.k.as_ref(), m.m.as_ref())
        .map_err(|source| PipelineError::Reduction {
            what: format!("modes of {what}"),
            source,
        })?;
    let f = vals
        .iter()
        .map(|&l| l.max(0.0).sqrt() / (2.0 * std::f64::consts::PI))
        .collect();
    Ok((f, vecs))
}

/// One mode of A and the mode of B it pairs with.
#[derive(Debug, Clone, Serialize)]
pub struct ModePair {
    /// Mode of A (0-based, by frequency).
    pub mode_a: usize,
    pub frequency_a_hz: Real,
    /// Paired mode of B (None: no mode of B with MAC at or above the pairing threshold).
    pub mode_b: Option<usize>,
    pub frequency_b_hz: Option<Real>,
    /// (f_B − f_A)/f_A (f_A floored at 1e-6 of A's highest frequency compared: rigid modes).
    pub relative_frequency_difference: Option<Real>,
    /// MAC with the paired mode (unpaired: the largest MAC with any mode of B).
    pub mac: Real,
}

/// The modes of A paired with those of B: greedily by the largest MAC over all pairs, each
/// mode used once, pairs below `min_mac` left unpaired.
pub fn pair_modes(
    a: &ReducedModel,
    (fa, va): &(Vec<Real>, Mat<Real>),
    (fb, vb): &(Vec<Real>, Mat<Real>),
    perm: &[usize],
    count: usize,
    min_mac: Real,
) -> Vec<ModePair> {
    let n = a.n();
    let (na, nb) = (count.min(fa.len()), count.min(fb.len()));
    // M φ for A's modes and B's (in A's DOF order), then the mass products.
    let mphi = |v: &dyn Fn(usize, usize) -> Real, k: usize| -> Vec<Real> {
        (0..n)
            .map(|i| (0..n).map(|j| a.m[(i, j)] * v(j, k)).sum())
            .collect()
    };
    let a_of = |i: usize, k: usize| va[(i, k)];
    let b_of = |i: usize, k: usize| vb[(perm[i], k)];
    let ma: Vec<Vec<Real>> = (0..na).map(|k| mphi(&a_of, k)).collect();
    let dot = |x: &[Real], v: &dyn Fn(usize, usize) -> Real, k: usize| -> Real {
        x.iter().enumerate().map(|(i, xi)| xi * v(i, k)).sum()
    };
    let aa: Vec<Real> = (0..na).map(|k| dot(&ma[k], &a_of, k)).collect();
    let bb: Vec<Real> = (0..nb).map(|k| dot(&mphi(&b_of, k), &b_of, k)).collect();
    let mut macs = Vec::with_capacity(na * nb);
    for i in 0..na {
        for j in 0..nb {
            let ab = dot(&ma[i], &b_of, j);
            macs.push((ab * ab / (aa[i] * bb[j]), i, j));
        }
    }
    macs.sort_by(|x, y| y.0.total_cmp(&x.0));
    let mut of_a: Vec<Option<(usize, Real)>> = vec![None; na];
    let mut used_b = vec![false; nb];
    let mut best_a = vec![0.0f64; na];
    for &(mac, i, j) in &macs {
        best_a[i] = best_a[i].max(mac);
        if mac >= min_mac && of_a[i].is_none() && !used_b[j] {
            of_a[i] = Some((j, mac));
            used_b[j] = true;
        }
    }
    // Rigid-body modes (f ≈ 0) are compared relative to 1e-6 of the highest frequency.
    let floor = 1e-6 * fa.iter().take(na).fold(0.0f64, |m, &f| m.max(f));
    (0..na)
        .map(|i| match of_a[i] {
            Some((j, mac)) => ModePair {
                mode_a: i,
                frequency_a_hz: fa[i],
                mode_b: Some(j),
                frequency_b_hz: Some(fb[j]),
                relative_frequency_difference: Some((fb[j] - fa[i]) / fa[i].abs().max(floor)),
                mac,
            },
            None => ModePair {
                mode_a: i,
                frequency_a_hz: fa[i],
                mode_b: None,
                frequency_b_hz: None,
                relative_frequency_difference: None,
                mac: best_a[i],
            },
        })
        .collect()
}

/// (b − a)/|a|, (b − a) when a = 0.
pub fn relative(a: Real, b: Real) -> Real {
    if a != 0.0 {
        (b - a) / a.abs()
    } else {
        b - a
    }
}
