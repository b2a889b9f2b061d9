//! The rotor friction face's normal velocity at every accepted step, for the limit cycle of a
//! run with separation ([`crate::stages::transient::limit_cycle`]).

use super::super::sink::{Sink, StepView};
use crate::error::PipelineError;
use crate::verdict::limit_cycle::FaceSeries;
use squeal_contact::GapSet;
use squeal_solver::Real;

/// Records v_n,g = v_rotor,g · n_g of every gap as its largest magnitude and its mean square
/// over the gaps, per step.
pub struct FaceMonitor {
    /// (DOF, weight) pairs per gap: v_n,g = Σ weight · v[DOF].
    rows: Vec<Vec<(usize, Real)>>,
    pub series: FaceSeries,
}

impl FaceMonitor {
    /// The monitor of the rotor side of `gaps`.
    pub fn new(gaps: &GapSet) -> Self {
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
        let f = &mut self.series;
        f.t.push(s.t);
        f.peak.push(peak);
        f.mean_square.push(ms);
        Ok(())
    }
}
