//! The BDF's steps by order after the load ramp ([`StepsByOrder`]), counted at chunk ends.

use super::super::sink::{Checkpoint, ChunkView, EndView, Saved, Sink, StepView};
use crate::error::PipelineError;
use crate::verdict::guard::StepsByOrder;
use serde::{Deserialize, Serialize};
use squeal_solver::Real;

/// The tally's part of a checkpoint.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct OrdersPart {
    /// The BDF's order histogram at the last chunk end at or before the end of the load ramp,
    /// and its time, where the count by order starts (None in older files).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub orders_at_ramp: Option<(Real, Vec<u64>)>,
}

impl OrdersPart {
    /// The part saved in a checkpoint.
    pub fn restore(s: &Saved<'_>) -> Result<Self, PipelineError> {
        s.part(None)
    }
}

/// A driver sink that counts the BDF's steps by order after the load ramp ([`StepsByOrder`]).
///
/// The order histogram is read at chunk ends (every chunk of steps and at restart points); the
/// count starts at the last chunk end at or before the end of the ramp, so it may include up
/// to one chunk of ramp steps (more steps: more decay, the conservative side). It does not stop
/// the integrator there (a stop at a given time changes the BDF's steps). A restart carries
/// the start point over: chunks restart at restart points in the uninterrupted run too, so a
/// resumed run counts from the same step.
pub struct OrderTally {
    t_after: Real,
    /// (time, cumulative order histogram) at the last chunk end at or before `t_after`.
    before: (Real, Vec<u64>),
    pub result: Option<StepsByOrder>,
}

impl OrderTally {
    /// Counts from `t_after` (the end of the ramp) in a run that started at `t_start`,
    /// continuing `resumed` (a restart checkpoint's part).
    pub fn new(t_start: Real, t_after: Real, resumed: Option<&OrdersPart>) -> Self {
        Self {
            t_after,
            before: resumed
                .and_then(|p| p.orders_at_ramp.clone())
                .unwrap_or((t_start, Vec::new())),
            result: None,
        }
    }
}

impl Sink for OrderTally {
    fn step(&mut self, _s: &StepView<'_>) -> Result<(), PipelineError> {
        Ok(())
    }
    fn chunk_end(&mut self, c: &ChunkView<'_>) -> Result<(), PipelineError> {
        if c.t <= self.t_after {
            if let Some(h) = c.order_histogram {
                self.before = (c.t, h.to_vec());
            }
        }
        Ok(())
    }
    fn end(&mut self, e: &EndView<'_>) -> Result<(), PipelineError> {
        let (t0, before) = &self.before;
        self.result = e.order_histogram.map(|end| StepsByOrder {
            counts: end
                .iter()
                .enumerate()
                .map(|(k, &n)| n.saturating_sub(before.get(k).copied().unwrap_or(0)))
                .collect(),
            t0: *t0,
            t1: e.t,
        });
        Ok(())
    }
    fn save(&self, c: &mut Checkpoint) -> Result<(), PipelineError> {
        c.save(
            None,
            &OrdersPart {
                orders_at_ramp: Some(self.before.clone()),
            },
        )
    }
}
