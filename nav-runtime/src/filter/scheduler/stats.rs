//! Per-sensor and scheduler-wide counts, and the report of one applied
//! measurement.

use super::{MeasurementOutcome, SensorId};
use crate::ekf::FilterError;

/// Per-sensor counts. `accepted`, `gated` and `failed` are final outcomes: a
/// measurement re-applied during a replay is counted once, with its latest
/// outcome.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SensorStats {
    /// Applied.
    pub accepted: u64,
    /// Refused by the innovation gate.
    pub gated: u64,
    /// Refused by the filter with an error (e.g. `S` not positive definite).
    pub failed: u64,
    /// Queued, waiting for the IMU to reach their time.
    pub pending: u64,
    /// Refused as older than the sensor latency or the history.
    pub too_old: u64,
    /// Refused as duplicates.
    pub duplicate: u64,
    /// Refused for non-finite time or values.
    pub invalid: u64,
    /// Refused because the pending queue was full.
    pub queue_full: u64,
    /// Refused as frozen values of a stuck sensor ([`Scheduler::set_stuck_detector`](crate::scheduler::Scheduler::set_stuck_detector)).
    pub stuck: u64,
    /// Times the sensor was declared stuck (runs of identical values that
    /// reached the detector's limit).
    pub stuck_episodes: u64,
}

/// Scheduler-wide counts.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SchedulerStats {
    /// IMU samples accepted.
    pub imu_samples: u64,
    /// IMU samples refused (time backwards, duplicate, non-finite, propagation error).
    pub imu_rejected: u64,
    /// Rollbacks for delayed measurements.
    pub replays: u64,
    /// IMU steps re-propagated during replays.
    pub replayed_steps: u64,
}

/// A measurement applied (or re-applied during a replay) by a push.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Report {
    /// The sensor.
    pub sensor: SensorId,
    /// The measurement time.
    pub time: f64,
    /// `true` if this re-applies a measurement already reported (a delayed
    /// measurement before it was inserted).
    pub replay: bool,
    /// The filter's answer.
    pub outcome: Result<MeasurementOutcome, FilterError>,
}

pub(super) fn tally(
    s: &mut SensorStats,
    outcome: Option<&Result<MeasurementOutcome, FilterError>>,
) {
    match outcome {
        None => s.pending += 1,
        Some(Ok(o)) if o.accepted => s.accepted += 1,
        Some(Ok(_)) => s.gated += 1,
        Some(Err(_)) => s.failed += 1,
    }
}
