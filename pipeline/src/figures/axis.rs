//! One plot axis (linear or log10) as a plotters coordinate: mapping, ticks, tick labels, and
//! the automatic range of a set of values.

use plotters::coord::ranged1d::{KeyPointHint, NoDefaultFormatting, Ranged, ValueFormatter};
use std::ops::Range;

/// A closed interval `[lo, hi]`, `lo < hi` (both > 0 when `log`), mapped linearly in `v` or in
/// `log10 v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Axis {
    pub lo: f64,
    pub hi: f64,
    pub log: bool,
    /// Requested number of labelled ticks (sets the tick step, hence the label precision).
    pub n_labels: usize,
}

impl Axis {
    fn t(&self, v: f64) -> f64 {
        if self.log {
            v.log10()
        } else {
            v
        }
    }

    /// Position of `v` along the axis: 0 at `lo`, 1 at `hi`.
    pub fn frac(&self, v: f64) -> f64 {
        let (a, b) = (self.t(self.lo), self.t(self.hi));
        (self.t(v) - a) / (b - a)
    }

    /// The value at position `f` (inverse of [`Axis::frac`]).
    pub fn value_at(&self, f: f64) -> f64 {
        let (a, b) = (self.t(self.lo), self.t(self.hi));
        let s = a + f * (b - a);
        if self.log {
            10f64.powf(s)
        } else {
            s
        }
    }

    /// Labelled tick values, at most `max_n` (at least two whenever possible).
    pub fn major_ticks(&self, max_n: usize) -> Vec<f64> {
        let max_n = max_n.max(2);
        if !self.log {
            return linear_ticks(self.lo, self.hi, max_n).0;
        }
        let (dlo, dhi) = decades(self.lo, self.hi);
        if dhi - dlo + 1 >= 2 {
            let count = (dhi - dlo + 1) as usize;
            let stride = count.div_ceil(max_n) as i32;
            return (dlo..=dhi)
                .filter(|d| (d - dlo) % stride == 0)
                .map(|d| 10f64.powi(d))
                .collect();
        }
        for mantissas in [
            &[1.0, 2.0, 5.0][..],
            &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0],
        ] {
            let v = self.log_candidates(mantissas);
            if v.len() >= 2 && v.len() <= max_n {
                return v;
            }
        }
        linear_ticks(self.lo, self.hi, max_n).0
    }

    /// Grid-only values between the labelled ticks (at most `max_n`, else none).
    pub fn minor_ticks(&self, max_n: usize) -> Vec<f64> {
        if !self.log {
            let (_, step) = linear_ticks(self.lo, self.hi, self.n_labels);
            let v = multiples(self.lo, self.hi, step / 5.0);
            return if v.len() <= max_n { v } else { Vec::new() };
        }
        let (dlo, dhi) = decades(self.lo, self.hi);
        if dhi - dlo + 1 > 12 {
            return Vec::new();
        }
        let v = self.log_candidates(&[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0, 9.0]);
        if v.len() <= max_n {
            v
        } else {
            Vec::new()
        }
    }

    fn log_candidates(&self, mantissas: &[f64]) -> Vec<f64> {
        let (dlo, dhi) = decades(self.lo, self.hi);
        let mut v = Vec::new();
        for d in (dlo - 1)..=(dhi + 1) {
            for m in mantissas {
                let x = m * 10f64.powi(d);
                if x >= self.lo * (1.0 - 1e-12) && x <= self.hi * (1.0 + 1e-12) {
                    v.push(x);
                }
            }
        }
        v
    }

    /// Tick label: `10ⁿ` for decades on a log axis, else a short decimal or `1.5e-3`.
    pub fn format_tick(&self, v: f64) -> String {
        if self.log {
            let d = v.log10().round();
            if (v / 10f64.powf(d) - 1.0).abs() < 1e-9 {
                return format!("10{}", superscript(d as i32));
            }
            return short(v);
        }
        let (_, step) = linear_ticks(self.lo, self.hi, self.n_labels);
        let e_step = step.log10().floor() as i32;
        let big = self.lo.abs().max(self.hi.abs());
        if (-4..=5).contains(&e_step) && big < 1e6 {
            format!("{:.*}", (-e_step).max(0) as usize, v)
        } else if v == 0.0 {
            "0".into()
        } else {
            let e_v = v.abs().log10().floor() as i32;
            format!("{:.*e}", (e_v - e_step).max(0) as usize, v)
        }
    }
}

impl Ranged for Axis {
    type FormatOption = NoDefaultFormatting;
    type ValueType = f64;

    fn map(&self, v: &f64, limit: (i32, i32)) -> i32 {
        let f = self.frac(*v);
        let f = if f.is_finite() {
            f.clamp(-1.0, 2.0)
        } else {
            0.0
        };
        limit.0 + (f * f64::from(limit.1 - limit.0)).round() as i32
    }

    fn key_points<H: KeyPointHint>(&self, hint: H) -> Vec<f64> {
        if hint.weight().allow_light_points() {
            self.minor_ticks(hint.max_num_points())
        } else {
            self.major_ticks(hint.max_num_points())
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

impl ValueFormatter<f64> for Axis {
    fn format_ext(&self, v: &f64) -> String {
        self.format_tick(*v)
    }
}

/// The padded range of `values` (already checked finite, and > 0 when `log`): 5 % of the span
/// (of the decades when `log`) on each side; a zero-width span is widened (±10 % of the value,
/// ±1 around zero, ±½ decade on a log axis). `None` when there are no values.
pub(crate) fn auto_range(values: impl Iterator<Item = f64>, log: bool) -> Option<(f64, f64)> {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        let t = if log { v.log10() } else { v };
        lo = lo.min(t);
        hi = hi.max(t);
    }
    if lo > hi {
        return None;
    }
    let scale = lo.abs().max(hi.abs());
    let (a, b) = if hi - lo <= 1e-12 * scale || hi == lo {
        let mid = 0.5 * (lo + hi);
        let half = if log {
            0.5
        } else if mid == 0.0 {
            1.0
        } else {
            0.1 * mid.abs()
        };
        (mid - half, mid + half)
    } else {
        let pad = 0.05 * (hi - lo);
        (lo - pad, hi + pad)
    };
    Some(if log {
        (10f64.powf(a), 10f64.powf(b))
    } else {
        (a, b)
    })
}

/// Multiples of a 1-2-5 step inside `[lo, hi]`, at most about `max_n`; returns (ticks, step).
fn linear_ticks(lo: f64, hi: f64, max_n: usize) -> (Vec<f64>, f64) {
    let raw = (hi - lo) / max_n.max(1) as f64;
    let mag = 10f64.powf(raw.log10().floor());
    let step = [1.0, 2.0, 5.0, 10.0]
        .iter()
        .map(|m| m * mag)
        .find(|s| *s >= raw * (1.0 - 1e-9))
        .unwrap_or(10.0 * mag);
    (multiples(lo, hi, step), step)
}

fn multiples(lo: f64, hi: f64, step: f64) -> Vec<f64> {
    if step.is_nan() || step <= 0.0 || !step.is_finite() {
        return Vec::new();
    }
    let k0 = (lo / step - 1e-9).ceil() as i64;
    let k1 = (hi / step + 1e-9).floor() as i64;
    if k1 < k0 || k1 - k0 > 10_000 {
        return Vec::new();
    }
    (k0..=k1).map(|k| k as f64 * step).collect()
}

/// Integer decades `d` with `lo <= 10^d <= hi`, as (first, last) (first > last when none).
fn decades(lo: f64, hi: f64) -> (i32, i32) {
    (
        (lo.log10() - 1e-9).ceil() as i32,
        (hi.log10() + 1e-9).floor() as i32,
    )
}

fn superscript(n: i32) -> String {
    const DIGITS: [char; 10] = ['⁰', '¹', '²', '³', '⁴', '⁵', '⁶', '⁷', '⁸', '⁹'];
    let mut s = String::new();
    if n < 0 {
        s.push('⁻');
    }
    for c in n.unsigned_abs().to_string().chars() {
        s.push(DIGITS[c.to_digit(10).unwrap_or(0) as usize]);
    }
    s
}

/// Three significant digits, fixed notation between 1e-3 and 1e5.
fn short(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let decimals = (2 - a.log10().floor() as i32).max(0) as usize;
        let s = format!("{v:.decimals$}");
        if s.contains('.') {
            s.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            s
        }
    } else {
        format!("{v:.2e}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_ticks_are_1_2_5_multiples_inside() {
        let a = Axis {
            lo: -0.13,
            hi: 1.07,
            log: false,
            n_labels: 8,
        };
        let t = a.major_ticks(8);
        assert_eq!(t.len(), 6); // step 0.2: 0.0, 0.2, .., 1.0
        assert!((t[1] - t[0] - 0.2).abs() < 1e-12);
        assert_eq!(a.format_tick(t[3]), "0.6");
    }

    #[test]
    fn log_ticks_are_decades() {
        let a = Axis {
            lo: 3e-7,
            hi: 2e-1,
            log: true,
            n_labels: 10,
        };
        let t = a.major_ticks(10);
        assert_eq!(t.len(), 6); // 1e-6 .. 1e-1
        assert_eq!(a.format_tick(t[0]), "10⁻⁶");
        assert!((a.frac(1e-6) - (1e-6f64 / 3e-7).log10() / (2e-1f64 / 3e-7).log10()).abs() < 1e-12);
        assert!((a.value_at(a.frac(1e-3)) - 1e-3).abs() < 1e-15);
    }

    #[test]
    fn degenerate_range_is_widened() {
        let (lo, hi) = auto_range([2.0, 2.0].into_iter(), false).unwrap();
        assert!((lo - 1.8).abs() < 1e-12 && (hi - 2.2).abs() < 1e-12);
        assert_eq!(auto_range([0.0].into_iter(), false), Some((-1.0, 1.0)));
        let (lo, hi) = auto_range([5.0].into_iter(), true).unwrap();
        assert!((lo * hi - 25.0).abs() < 1e-9 && hi / lo > 9.99);
        assert_eq!(auto_range(std::iter::empty(), false), None);
    }
}
