//! Registered sensors: their handle, configuration and bookkeeping.

use super::SensorStats;
use crate::stuck::StuckDetector;

/// Identifies a sensor registered with [`Scheduler::add_sensor`](crate::scheduler::Scheduler::add_sensor).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SensorId(pub(super) usize);

impl SensorId {
    /// Registration index.
    pub fn index(self) -> usize {
        self.0
    }
}

/// A registered sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorConfig {
    /// Display name.
    pub name: String,
    /// Nominal rate, Hz (for staleness checks: [`Scheduler::is_stale`](crate::scheduler::Scheduler::is_stale)).
    pub rate_hz: f64,
    /// Largest delay, seconds, between a measurement's time and its arrival
    /// (relative to the IMU time); older measurements are refused.
    pub latency: f64,
}

pub(super) struct SensorEntry {
    pub(super) config: SensorConfig,
    /// Refusals, plus final outcomes of measurements that left the history.
    pub(super) finalized: SensorStats,
    pub(super) last_time: Option<f64>,
    pub(super) stuck: Option<StuckDetector>,
}
