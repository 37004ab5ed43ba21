//! Why the scheduler refused an event.

use super::SensorId;
use crate::ekf::FilterError;

/// Why an event was refused. The filter is unchanged after any of these.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SchedulerError {
    /// A timestamp is NaN or infinite.
    #[error("timestamp {time} is not finite")]
    NonFiniteTime {
        /// The timestamp.
        time: f64,
    },
    /// An IMU sample older than the newest one.
    #[error("IMU time went backwards: {time} s before the current {now} s")]
    TimeWentBackwards {
        /// The sample's time.
        time: f64,
        /// The filter time.
        now: f64,
    },
    /// An IMU sample with the same time as the newest one.
    #[error("duplicate IMU sample at {time} s")]
    DuplicateImu {
        /// The sample's time.
        time: f64,
    },
    /// A measurement older than its sensor's latency or than the history.
    #[error("measurement of sensor {sensor:?} at {time} s is too old (now {now} s, oldest accepted {oldest} s)")]
    TooOld {
        /// The sensor.
        sensor: SensorId,
        /// The measurement time.
        time: f64,
        /// The filter time.
        now: f64,
        /// Measurements must be newer than this.
        oldest: f64,
    },
    /// A second measurement of one sensor at one timestamp.
    #[error("duplicate measurement of sensor {sensor:?} at {time} s")]
    Duplicate {
        /// The sensor.
        sensor: SensorId,
        /// The measurement time.
        time: f64,
    },
    /// A measurement with non-finite values.
    #[error("measurement of sensor {sensor:?} is invalid: {source}")]
    InvalidMeasurement {
        /// The sensor.
        sensor: SensorId,
        /// What is wrong with it.
        source: FilterError,
    },
    /// An IMU sample with non-finite values.
    #[error("invalid IMU sample: {0}")]
    InvalidImu(FilterError),
    /// A sensor id not returned by [`Scheduler::add_sensor`](crate::scheduler::Scheduler::add_sensor).
    #[error("unknown sensor {0:?}")]
    UnknownSensor(SensorId),
    /// Too many measurements waiting for the IMU to reach them.
    #[error("pending queue full ({capacity} measurements)")]
    QueueFull {
        /// The queue capacity.
        capacity: usize,
    },
    /// Invalid configuration (rates, latencies, start time).
    #[error("invalid scheduler configuration: {0}")]
    InvalidConfig(&'static str),
    /// The sensor repeated one value more often than noise and resolution
    /// explain ([`Scheduler::set_stuck_detector`](crate::scheduler::Scheduler::set_stuck_detector)).
    #[error("sensor {sensor:?} is stuck: the same value {run} times in a row")]
    Stuck {
        /// The sensor.
        sensor: SensorId,
        /// Identical samples in a row, this one included.
        run: u32,
    },
    /// The filter refused a propagation (while stepping or replaying).
    #[error("propagation failed: {0}")]
    Propagation(FilterError),
}
