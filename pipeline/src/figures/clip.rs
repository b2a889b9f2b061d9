//! Clipping polylines and points to the plot frame (plotters draws out-of-range data over the
//! axes otherwise).

use super::axis::Axis;

/// Pieces of the polyline `(x[i], y[i])` inside the frame `xa × ya`, cut where it crosses the
/// frame (Liang–Barsky per segment, in axis-fraction space so log axes clip correctly).
pub(crate) fn clip_polyline(x: &[f64], y: &[f64], xa: &Axis, ya: &Axis) -> Vec<Vec<(f64, f64)>> {
    let to_frac = |i: usize| (xa.frac(x[i]), ya.frac(y[i]));
    let back = |(u, v): (f64, f64)| (xa.value_at(u), ya.value_at(v));
    let mut pieces: Vec<Vec<(f64, f64)>> = Vec::new();
    let mut current: Vec<(f64, f64)> = Vec::new();
    let n = x.len().min(y.len());
    if n == 1 {
        let p = to_frac(0);
        if inside(p) {
            pieces.push(vec![(x[0], y[0])]);
        }
        return pieces;
    }
    for i in 1..n {
        let (p, q) = (to_frac(i - 1), to_frac(i));
        match clip_segment(p, q) {
            Some((a, b, a_cut, b_cut)) => {
                if current.is_empty() || a_cut {
                    if !current.is_empty() {
                        pieces.push(std::mem::take(&mut current));
                    }
                    current.push(if a_cut { back(a) } else { (x[i - 1], y[i - 1]) });
                }
                current.push(if b_cut { back(b) } else { (x[i], y[i]) });
                if b_cut {
                    pieces.push(std::mem::take(&mut current));
                }
            }
            None => {
                if !current.is_empty() {
                    pieces.push(std::mem::take(&mut current));
                }
            }
        }
    }
    if !current.is_empty() {
        pieces.push(current);
    }
    pieces
}

/// The points inside the frame.
pub(crate) fn clip_points(x: &[f64], y: &[f64], xa: &Axis, ya: &Axis) -> Vec<(f64, f64)> {
    x.iter()
        .zip(y)
        .filter(|(a, b)| inside((xa.frac(**a), ya.frac(**b))))
        .map(|(a, b)| (*a, *b))
        .collect()
}

const EPS: f64 = 1e-9;

fn inside((u, v): (f64, f64)) -> bool {
    (-EPS..=1.0 + EPS).contains(&u) && (-EPS..=1.0 + EPS).contains(&v)
}

/// The part of segment p→q inside the unit square, with flags telling whether each end was cut.
#[allow(clippy::type_complexity)]
fn clip_segment(p: (f64, f64), q: (f64, f64)) -> Option<((f64, f64), (f64, f64), bool, bool)> {
    let (dx, dy) = (q.0 - p.0, q.1 - p.1);
    let (mut t0, mut t1) = (0.0f64, 1.0f64);
    for (den, num) in [
        (-dx, p.0 + EPS),
        (dx, 1.0 + EPS - p.0),
        (-dy, p.1 + EPS),
        (dy, 1.0 + EPS - p.1),
    ] {
        if den == 0.0 {
            if num < 0.0 {
                return None;
            }
        } else {
            let r = num / den;
            if den < 0.0 {
                t0 = t0.max(r);
            } else {
                t1 = t1.min(r);
            }
        }
    }
    if t0 > t1 {
        return None;
    }
    let at = |t: f64| (p.0 + t * dx, p.1 + t * dy);
    Some((at(t0), at(t1), t0 > 0.0, t1 < 1.0))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_polyline_is_cut_at_the_frame() {
        let a = Axis {
            lo: 0.0,
            hi: 1.0,
            log: false,
            n_labels: 5,
        };
        // In, out over the top (y = 2), back in.
        let x = [0.1, 0.5, 0.9];
        let y = [0.0, 2.0, 0.0];
        let p = clip_polyline(&x, &y, &a, &a);
        assert_eq!(p.len(), 2);
        assert_eq!(p[0][0], (0.1, 0.0));
        let (cx, cy) = p[0][1];
        assert!(
            (cy - 1.0).abs() < 1e-8 && (cx - 0.3).abs() < 1e-8,
            "{cx} {cy}"
        );
        let (dx, dy) = p[1][0];
        assert!((dy - 1.0).abs() < 1e-8 && (dx - 0.7).abs() < 1e-8);
        assert_eq!(*p[1].last().unwrap(), (0.9, 0.0));
        assert_eq!(clip_points(&x, &y, &a, &a).len(), 2);
    }
}
