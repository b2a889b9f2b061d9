//! The roots and the envelope of a recorded response over a window: one verdict before the
//! guard has judged it.

use super::envelope::analyse;
use super::outcome::Verdict;
use super::roots::{estimate, PencilOptions};
use squeal_solver::Real;

/// The velocities the verdict analyses, at every accepted step: the times and, per channel
/// (a reduced DOF), its velocity, its acceleration (the Hermite resampling of the root
/// estimator reads both) and the name of its history column.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Series {
    pub t: Vec<Real>,
    pub v: Vec<Vec<Real>>,
    pub a: Vec<Vec<Real>>,
    pub names: Vec<String>,
}

impl Series {
    /// An empty series of channels named `names`.
    pub fn new(names: Vec<String>) -> Self {
        Self {
            t: Vec::new(),
            v: vec![Vec::new(); names.len()],
            a: vec![Vec::new(); names.len()],
            names,
        }
    }
}

/// The verdict on `s` after `t_after` (the end of the load ramp), and the name of the channel
/// of its envelope cross-check.
///
/// The roots are fitted on every channel over [t_after, end] ([`estimate`], `band_hz` bounds
/// the sampling and the roots kept); the envelope on the channel with the largest peak after
/// the ramp.
///
/// With `stall_h`, only the growth phase is analysed: the steps up to the first one shorter
/// than `stall_h` after the ramp (where a squealing response reaches slip reversal and the
/// step collapses).
///
/// With `t_stop`, only the steps before it are analysed (the contact went tensile there).
pub fn fit(
    s: &Series,
    t_after: Real,
    stall_h: Option<Real>,
    t_stop: Option<Real>,
    band_hz: Option<Real>,
    opts: &PencilOptions,
) -> (String, Verdict) {
    let t = &s.t;
    let stall = stall_h
        .and_then(|h| (1..t.len()).find(|&i| t[i] > t_after && t[i] - t[i - 1] < h))
        .unwrap_or(t.len());
    let stop = t_stop.map_or(t.len(), |ts| t.partition_point(|&x| x < ts));
    let end = stall.min(stop);
    let (t, v, a): (&[Real], Vec<&[Real]>, Vec<&[Real]>) = (
        &t[..end],
        s.v.iter().map(|v| &v[..end]).collect(),
        s.a.iter().map(|a| &a[..end]).collect(),
    );
    let pick = v
        .iter()
        .enumerate()
        .map(|(k, v)| {
            let peak = t
                .iter()
                .zip(v.iter())
                .filter(|(t, _)| **t > t_after)
                .fold(0.0f64, |m, (_, x)| m.max(x.abs()));
            (k, peak)
        })
        .max_by(|a, b| a.1.total_cmp(&b.1))
        .map(|(k, _)| k);
    let (name, envelope) = match pick {
        Some(k) => (s.names[k].clone(), analyse(t, v[k], t_after)),
        None => ("none".into(), analyse(&[], &[], 0.0)),
    };
    // The window after the ramp (the first sample at or after t_after).
    let first = t.partition_point(|&s| s < t_after);
    let window = match (t.get(first), t.last()) {
        (Some(&a), Some(&b)) if b > a => [a, b],
        _ => [t_after, t_after],
    };
    let fit = estimate(
        &t[first..],
        &v.iter().map(|v| &v[first..]).collect::<Vec<_>>(),
        &a.iter().map(|a| &a[first..]).collect::<Vec<_>>(),
        window,
        envelope.dominant_frequency_hz,
        band_hz,
        opts,
    );
    let h_max = (first.max(1)..t.len())
        .map(|i| t[i] - t[i - 1])
        .fold(None, |m: Option<Real>, h| Some(m.map_or(h, |m| m.max(h))));
    (name, Verdict::new(fit, envelope, window, h_max))
}
