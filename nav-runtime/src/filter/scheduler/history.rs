//! The history: IMU steps with their checkpoints, queued measurements, and
//! the propagation over one IMU interval that applies them.

use super::{Measurement, MeasurementOutcome, SchedulerError};
use crate::ekf::{FilterError, Propagate};

/// Checkpoint buffers kept for reuse (see `Scheduler::spare`).
pub(super) const MAX_SPARE_SNAPSHOTS: usize = 4;

/// One IMU step: the sample held over `(previous time, time]` and, every
/// `snapshot_every` steps, the filter after the step (boxed: most steps hold
/// none, and the history moves steps around).
pub(super) struct Step<F: Propagate> {
    pub(super) time: f64,
    pub(super) input: Option<F::Input>,
    pub(super) snapshot: Option<Box<F>>,
}

pub(super) struct Queued<F> {
    pub(super) sensor: usize,
    pub(super) time: f64,
    pub(super) measurement: Box<dyn Measurement<F>>,
    pub(super) outcome: Option<Result<MeasurementOutcome, FilterError>>,
}

impl<F> Queued<F> {
    pub(super) fn key(&self) -> (f64, usize) {
        (self.time, self.sensor)
    }
}

/// Propagates `filter` over `(t0, t1]` with `input`, stopping at each queued
/// measurement in `range` (all inside the interval, in order) to apply it.
pub(super) fn run_interval<F: Propagate>(
    filter: &mut F,
    t0: f64,
    t1: f64,
    input: &F::Input,
    queue: &[Queued<F>],
    range: std::ops::Range<usize>,
) -> Result<Vec<Result<MeasurementOutcome, FilterError>>, SchedulerError> {
    let mut t = t0;
    let mut outcomes = Vec::with_capacity(range.len());
    for q in queue.get(range).unwrap_or(&[]) {
        if q.time > t {
            filter
                .propagate(q.time - t, input)
                .map_err(SchedulerError::Propagation)?;
            t = q.time;
        }
        outcomes.push(q.measurement.apply(filter));
    }
    if t1 > t {
        filter
            .propagate(t1 - t, input)
            .map_err(SchedulerError::Propagation)?;
    }
    Ok(outcomes)
}
