//! Mode correlation (complex MAC) and greedy assignment between neighbouring steps.

use super::Cplx;
use faer::Mat;

/// Complex modal assurance criterion `|aᴴb|² / ((aᴴa)(bᴴb))` ∈ [0, 1] (0 if either is zero).
pub fn mac(a: &[Cplx], b: &[Cplx]) -> f64 {
    let mut ab = Cplx::new(0.0, 0.0);
    let (mut aa, mut bb) = (0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        ab += x.conj() * y;
        aa += x.norm_sqr();
        bb += y.norm_sqr();
    }
    if aa == 0.0 || bb == 0.0 {
        0.0
    } else {
        ab.norm_sqr() / (aa * bb)
    }
}

/// MAC matrix between two sets of unit-norm shapes (rows: `prev`, columns: `next`), by one
/// complex matrix product.
pub(crate) fn mac_matrix(prev: &[&[Cplx]], next: &[&[Cplx]]) -> Mat<f64> {
    let n = prev.first().or(next.first()).map_or(0, |v| v.len());
    let a = Mat::from_fn(n, prev.len(), |i, j| prev[j][i]);
    let b = Mat::from_fn(n, next.len(), |i, j| next[j][i]);
    let g = a.adjoint() * &b;
    let na: Vec<f64> = prev
        .iter()
        .map(|v| v.iter().map(|z| z.norm_sqr()).sum())
        .collect();
    let nb: Vec<f64> = next
        .iter()
        .map(|v| v.iter().map(|z| z.norm_sqr()).sum())
        .collect();
    Mat::from_fn(prev.len(), next.len(), |i, j| {
        let d = na[i] * nb[j];
        if d > 0.0 {
            g[(i, j)].norm_sqr() / d
        } else {
            0.0
        }
    })
}

/// Greedy assignment: repeatedly pairs the (prev, next) with the largest score among the
/// unpaired ones with MAC ≥ `mac_min`, where the score is the MAC less `continuity_weight` ×
/// the distance of the next eigenvalue from the track's predicted one relative to |p_prev|
/// (eigenvalue continuity: near a coalescence both partners' shapes tend to the same vector
/// and their MACs to 1, and the prediction tells them apart). Equal scores go to the closer
/// eigenvalue. Returns, for each prev, its next index.
pub(crate) fn assign(
    macm: &Mat<f64>,
    prev_p: &[Cplx],
    pred_p: &[Cplx],
    next_p: &[Cplx],
    mac_min: f64,
    continuity_weight: f64,
) -> Vec<Option<usize>> {
    let (np, nn) = (macm.nrows(), macm.ncols());
    let mut pairs: Vec<(f64, f64, usize, usize)> = Vec::new();
    for i in 0..np {
        let scale = prev_p[i].norm().max(f64::MIN_POSITIVE);
        for j in 0..nn {
            let x = macm[(i, j)];
            if x >= mac_min && x > 0.0 {
                let d = (pred_p[i] - next_p[j]).norm();
                pairs.push((x - continuity_weight * d / scale, d, i, j));
            }
        }
    }
    pairs.sort_by(|a, b| b.0.total_cmp(&a.0).then(a.1.total_cmp(&b.1)));
    let mut out = vec![None; np];
    let mut used = vec![false; nn];
    for (_, _, i, j) in pairs {
        if out[i].is_none() && !used[j] {
            out[i] = Some(j);
            used[j] = true;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mac_is_phase_invariant_and_bounded() {
        let a = vec![
            Cplx::new(1.0, 2.0),
            Cplx::new(-0.5, 0.1),
            Cplx::new(0.0, 3.0),
        ];
        let ph = Cplx::from_polar(2.5, 0.7);
        let b: Vec<Cplx> = a.iter().map(|z| z * ph).collect();
        assert!((mac(&a, &b) - 1.0).abs() < 1e-14);
        let c = vec![
            Cplx::new(0.3, 0.0),
            Cplx::new(1.0, -1.0),
            Cplx::new(0.2, 0.2),
        ];
        let x = mac(&a, &c);
        assert!((0.0..1.0).contains(&x));
        let m = mac_matrix(&[&a], &[&b, &c]);
        assert!((m[(0, 0)] - 1.0).abs() < 1e-14 && (m[(0, 1)] - x).abs() < 1e-14);
    }
}
