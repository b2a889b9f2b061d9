//! A projected friction sweep's basis enriched at other μ (a multi-point basis, as in greedy
//! reduced-basis methods): the exact eigenvectors of the least stable in-band roots at the
//! sweep's μ where the projection is worst are added to the friction-free modes until the
//! projection is within a tolerance at a μ it was not enriched at.

use super::refine::RefineRun;
use super::sweep::{refine_comparison, Solver};
use super::{CeaError, CeaMatrices, Cplx, SweepOptions};
use serde::Serialize;
use std::fmt::Display;
use std::time::Instant;

/// One μ at which the projected sweep's basis was tested (and, when the test failed,
/// enriched).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct EnrichPoint {
    /// The friction coefficient.
    pub mu: f64,
    /// Basis size when tested.
    pub n_basis: usize,
    /// In-band roots refined exactly (the `enrich_roots` projected roots with the largest
    /// Re p).
    pub n_targets: usize,
    /// Largest |p_exact − p_projected| / |p_exact| over those roots (1 for an exact unstable
    /// in-band root the projection missed, or a target whose exact root did not converge).
    pub max_rel_error: f64,
    /// Largest |Re p_exact − Re p_projected| over them, 1/s.
    pub max_real_part_error: f64,
    /// Exact unstable in-band roots the projection missed.
    pub n_missed: usize,
    /// Basis columns added here (0: the test passed, or the enrichment budget was spent).
    pub n_added: usize,
    /// Refinement shifts (complex LUs).
    pub n_shifts: usize,
    /// Wall time, seconds.
    pub time_s: f64,
}

/// The indices of `mus` in the order the enrichment tests them: the last, then the midpoints
/// of the intervals between the tested ones (breadth first), the first last; never `skip`
/// (the basis' own μ).
pub(super) fn candidates(n: usize, skip: Option<usize>) -> Vec<usize> {
    if n == 0 {
        return Vec::new();
    }
    let mut out = vec![n - 1];
    let mut queue = std::collections::VecDeque::from([(0usize, n - 1)]);
    while let Some((a, b)) = queue.pop_front() {
        if b <= a + 1 {
            continue;
        }
        let m = (a + b) / 2;
        out.push(m);
        queue.push_back((a, m));
        queue.push_back((m, b));
    }
    if n > 1 {
        out.push(0);
    }
    out.retain(|&i| Some(i) != skip);
    out
}

impl<F, E> Solver<'_, F>
where
    F: FnMut(f64) -> Result<CeaMatrices, E>,
    E: Display,
{
    /// Tests the basis at μ: the projected solve, its `enrich_roots` in-band roots with the
    /// largest Re p refined exactly. Returns the test and the exact shapes of those roots
    /// (and of any missed unstable in-band root).
    fn enrich_test(
        &mut self,
        mu: f64,
        band_hz: f64,
        opts: &SweepOptions,
    ) -> Result<(EnrichPoint, Vec<Vec<Cplx>>), CeaError> {
        let t0 = Instant::now();
        self.cea.check_interrupt("the sweep basis enrichment")?;
        let sys = self.system(mu)?;
        let basis = self
            .basis
            .as_ref()
            .expect("enrichment needs the projection basis");
        let n_basis = basis.len();
        let mut r = basis.solve(&sys, &self.cea)?;
        let thr = self.cea.unstable_tol * r.stats.spectral_radius;
        let mut targets: Vec<usize> = (0..r.modes.len())
            .filter(|&i| r.modes[i].frequency_hz <= band_hz)
            .collect();
        targets.sort_by(|&a, &b| r.modes[b].real_part.total_cmp(&r.modes[a].real_part));
        targets.truncate(opts.enrich_roots);
        let n_targets = targets.len();
        let split = self.slave_split(&sys);
        let run = RefineRun {
            band_hz,
            unstable_tol_abs: thr,
            opts: &self.cea.projection.refine,
            interrupt: &self.cea.interrupt,
            split: split.as_ref(),
            keep: false,
        };
        let st = run.targets(&sys, &mut r.modes, targets)?.0;
        let cmp = refine_comparison(&st);
        let (mut max_rel, max_re) = (cmp.max_rel_error, cmp.max_real_part_error);
        if st.n_missed > 0 || st.n_failed > 0 {
            max_rel = max_rel.max(1.0);
        }
        // The exact shapes: the modes that now carry a target's exact root or a missed one.
        let exact: Vec<Cplx> = st
            .roots
            .iter()
            .filter(|x| x.target)
            .map(|x| x.exact)
            .chain(st.missed.iter().map(|m| Cplx::new(m[0], m[1])))
            .map(|p| Cplx::new(p.re, p.im.abs()))
            .collect();
        let shapes = r
            .modes
            .iter()
            .filter(|m| exact.contains(&m.eigenvalue))
            .map(|m| m.shape.clone())
            .collect();
        Ok((
            EnrichPoint {
                mu,
                n_basis,
                n_targets,
                max_rel_error: max_rel,
                max_real_part_error: max_re,
                n_missed: st.n_missed,
                n_added: 0,
                n_shifts: st.n_shifts,
                time_s: t0.elapsed().as_secs_f64(),
            },
            shapes,
        ))
    }

    /// Greedy enrichment of the projection basis over `mus` (see [`SweepOptions::enrich_tol`]):
    /// the candidates of [`candidates`] in turn, each tested with the current basis; a
    /// test within `enrich_tol` ends it (the basis is then verified at a μ it was not
    /// enriched at); a failed test adds its exact shapes, at most `max_enrich_points` times.
    /// Returns the tests and whether the last one passed.
    pub(super) fn enrich(
        &mut self,
        mus: &[f64],
        skip: Option<usize>,
        band_hz: f64,
        opts: &SweepOptions,
    ) -> Result<(Vec<EnrichPoint>, bool), CeaError> {
        let mut points = Vec::new();
        // Every test before this one enriched the basis (a passing test returns).
        for (added_at, i) in candidates(mus.len(), skip).into_iter().enumerate() {
            let (mut pt, shapes) = self.enrich_test(mus[i], band_hz, opts)?;
            let pass = pt.max_rel_error <= opts.enrich_tol;
            if pass || added_at >= opts.max_enrich_points {
                points.push(pt);
                return Ok((points, pass));
            }
            let t = Instant::now();
            let basis = self.basis.as_mut().expect("tested above");
            pt.n_added = basis.enrich(&shapes, 1e-6)?;
            pt.time_s += t.elapsed().as_secs_f64();
            points.push(pt);
        }
        Ok((points, false))
    }
}

#[cfg(test)]
mod tests {
    use super::candidates;

    #[test]
    fn candidates_last_then_midpoints_breadth_first() {
        assert_eq!(candidates(9, Some(0)), vec![8, 4, 2, 6, 1, 3, 5, 7]);
        assert_eq!(candidates(2, Some(0)), vec![1]);
        assert_eq!(candidates(1, Some(0)), Vec::<usize>::new());
        assert_eq!(candidates(5, None), vec![4, 2, 1, 3, 0]);
    }
}
