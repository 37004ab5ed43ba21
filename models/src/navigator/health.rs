//! Per-sensor counts of a run: a typed struct with integer counts.

/// Counts of one aiding sensor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct SensorHealth {
    /// Rows in the log.
    pub rows: u64,
    /// Applied.
    pub accepted: u64,
    /// Refused by the innovation gate.
    pub gated: u64,
    /// Refused by the filter or the scheduler (error, too old, duplicate, invalid).
    pub rejected: u64,
    /// Not used: no bottom lock, above the DVL range, or before the start.
    pub skipped: u64,
    /// Refused as frozen values (the sensor repeated one value more often than
    /// its noise and resolution explain; [`stuck_detector`](crate::sdins25::filter::stuck_detector)).
    pub stuck: u64,
}
