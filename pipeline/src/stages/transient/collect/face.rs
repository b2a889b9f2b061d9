//! The rotor friction face's normal velocity at every accepted step, for the limit cycle of a
//! run with separation ([`crate::stages::transient::limit_cycle`]).

use super::super::sink::{Sink, StepView};
use super::contact::tensile_band;
use crate::error::PipelineError;
use crate::verdict::limit_cycle::FaceSeries;
use squeal_contact::GapSet;
use squeal_solver::Real;

/// Records v_n,g = v_rotor,g · n_g of every gap as its largest magnitude and its mean square
/// over the gaps, and the gaps that are open (p_n A within the contact monitor's round-off band
/// of zero, or below), per step.
pub struct FaceMonitor {
    /// (DOF, weight) pairs per gap: v_n,g = Σ weight · v[DOF].
    rows: Vec<Vec<(usize, Real)>>,
    area: Vec<Real>,
    p0: Vec<Real>,
    /// Offset of λ̇ in y' (= n).
    offset: usize,
    pub series: FaceSeries,
}

impl FaceMonitor {
    /// The monitor of the rotor side of `gaps` in a model of `n` DOFs.
    pub fn new(gaps: &GapSet, n: usize) -> Self {
        let rows = gaps
            .gaps
            .iter()
            .map(|g| {
                g.rotor_terms()
                    .flat_map(|(w, dofs)| {
                        (0..3).filter_map(move |k| dofs[k].map(|d| (d, w[k] * g.normal[k])))
                    })
                    .collect()
            })
            .collect();
        Self {
            rows,
            area: gaps.gaps.iter().map(|g| g.area).collect(),
            p0: gaps.gaps.iter().map(|g| g.p0).collect(),
            offset: n,
            series: FaceSeries::default(),
        }
    }
}

impl Sink for FaceMonitor {
    fn step(&mut self, s: &StepView<'_>) -> Result<(), PipelineError> {
        let (mut peak, mut ms): (Real, Real) = (0.0, 0.0);
        for row in &self.rows {
            let vn: Real = row.iter().map(|&(d, w)| w * s.y[d]).sum();
            peak = peak.max(vn.abs());
            ms += vn * vn;
        }
        if !self.rows.is_empty() {
            ms /= self.rows.len() as Real;
        }
        let lam = &s.yp[self.offset..self.offset + self.area.len()];
        let band = tensile_band(lam, &self.area, &self.p0);
        let open = (self.area.iter().zip(&self.p0).zip(lam))
            .filter(|((&a, &p0), &l)| (-l / a + p0) * a <= band) // [Paper eq. (1)]
            .count();
        let f = &mut self.series;
        f.open.push(open as u32);
        f.t.push(s.t);
        f.peak.push(peak);
        f.mean_square.push(ms);
        Ok(())
    }
}
