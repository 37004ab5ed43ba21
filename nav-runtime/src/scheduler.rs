//! Multi-rate, out-of-order event scheduling for a filter (`std` only).
//!
//! The filter is propagated by IMU samples and corrected by aiding
//! measurements, each at its own time. Events may arrive late and in any
//! order; the result is the same as if every event had arrived on time and in
//! time order, as long as it is not older than the history.
//!
//! **Timeline.** An IMU sample stamped `t_k` holds over `(t_{k-1}, t_k]` (the
//! sample integrates that interval). The filter state is always at the time of
//! the newest IMU sample, `now`. A measurement at `t_m` is applied at exactly
//! `t_m`: the IMU interval containing it is split, `predict(t_m - t_{k-1})`,
//! update, `predict(t_k - t_m)`. Measurements at the same time are applied in
//! sensor registration order, so the result never depends on arrival order.
//!
//! **Measurements from the future** (`t_m > now`, the IMU has not reached
//! them yet) wait in a queue and are applied when the IMU passes them; this is
//! the normal path for a sensor faster to deliver than the IMU.
//!
//! **Delayed measurements** (`t_m <= now`) roll the filter back to the newest
//! checkpoint before `t_m` and replay the IMU samples and measurements since,
//! with the new one in its place (robot_localization's "history" approach;
//! PX4's EKF2 instead runs the filter on a fixed delayed horizon). Checkpoints
//! are filter clones kept in a bounded ring (every IMU step, or every `n`-th
//! with [`Scheduler::with_snapshot_every`] to save memory at the cost of longer
//! replays); the history spans the largest registered sensor latency.
//!
//! **Refusals.** Each is a typed [`SchedulerError`], counted per sensor (or for
//! the IMU), and leaves the filter bit-identical: a measurement older than its
//! sensor's latency or than the history, an IMU sample not after `now`, a
//! duplicate (same sensor and timestamp), non-finite times or values.

use std::collections::VecDeque;
use std::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use crate::ekf::{Estimator, FilterError, Propagate, UpdateReport};
use crate::model::{Record, Sensor};
use crate::stuck::StuckDetector;
pub use crate::stuck::MAX_RAW_VALUES;

/// Identifies a sensor registered with [`Scheduler::add_sensor`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct SensorId(usize);

impl SensorId {
    /// Registration index.
    pub fn index(self) -> usize {
        self.0
    }
}

/// Why an event was refused. The filter is unchanged after any of these.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
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
    /// A sensor id not returned by [`Scheduler::add_sensor`].
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
    /// explain ([`Scheduler::set_stuck_detector`]).
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

/// A measurement that can be applied to a filter of type `F`, type-erased so a
/// scenario can mix the sensors of one model in one queue.
pub trait Measurement<F> {
    /// Refuses a measurement that can never be applied (non-finite values).
    ///
    /// # Errors
    /// The [`FilterError`] the filter would return.
    fn check(&self) -> Result<(), FilterError>;
    /// Applies the measurement to `filter` at its current time.
    ///
    /// # Errors
    /// As the filter's update; the filter is unchanged on error.
    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError>;
    /// The raw values the sensor reported (at most [`MAX_RAW_VALUES`]), for the
    /// frozen-value check of [`StuckDetector`]; empty (the default) disables
    /// the check for this measurement.
    fn raw_values(&self) -> &[f64] {
        &[]
    }
}

/// The dimension-free part of an [`UpdateReport`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasurementOutcome {
    /// Passed the gate and applied.
    pub accepted: bool,
    /// Normalized innovation squared.
    pub nis: f64,
    /// Gate threshold, `None` if gating is disabled.
    pub threshold: Option<f64>,
    /// Measurement dimension (degrees of freedom of the NIS).
    pub dof: usize,
}

impl<const M: usize> From<&UpdateReport<M>> for MeasurementOutcome {
    fn from(r: &UpdateReport<M>) -> Self {
        Self {
            accepted: r.accepted,
            nis: r.nis,
            threshold: r.threshold,
            dof: M,
        }
    }
}

/// How the noise of a [`SensorUpdate`] is given, which selects the update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeasurementNoise<const M: usize> {
    /// Full covariance: batch update ([`crate::ekf::Ekf::update`]).
    Full(SMatrix<f64, M, M>),
    /// Diagonal variances: sequential scalar update
    /// ([`crate::ekf::Ekf::update_sequential`]).
    Diagonal(SVector<f64, M>),
}

/// A measurement `z` of sensor `S` with its noise and auxiliary input; the
/// [`Measurement`] implementation for any [`Estimator`] of `S`'s model.
///
/// `z` is fixed when the measurement is pushed. For an error-state filter the
/// update takes a residual (INS value minus sensor value) that depends on the
/// nominal solution at the measurement time, which a delayed measurement only
/// meets during the replay: use [`FnMeasurement`] to form it there.
pub struct SensorUpdate<S: Sensor<N, M>, const N: usize, const M: usize> {
    /// The measurement (for an error-state filter: INS value minus sensor value).
    pub z: SVector<f64, M>,
    /// Its noise.
    pub noise: MeasurementNoise<M>,
    /// The sensor's auxiliary input.
    pub aux: S::Aux,
    _sensor: PhantomData<fn() -> S>,
}

impl<S: Sensor<N, M>, const N: usize, const M: usize> SensorUpdate<S, N, M> {
    /// A measurement fused with the batch update and full covariance `r`.
    pub fn new(z: SVector<f64, M>, r: SMatrix<f64, M, M>, aux: S::Aux) -> Self {
        Self {
            z,
            noise: MeasurementNoise::Full(r),
            aux,
            _sensor: PhantomData,
        }
    }

    /// A measurement with diagonal noise, fused by sequential scalar updates.
    pub fn sequential(z: SVector<f64, M>, r_diag: SVector<f64, M>, aux: S::Aux) -> Self {
        Self {
            z,
            noise: MeasurementNoise::Diagonal(r_diag),
            aux,
            _sensor: PhantomData,
        }
    }
}

impl<F, S, const N: usize, const M: usize> Measurement<F> for SensorUpdate<S, N, M>
where
    S: Sensor<N, M>,
    F: Estimator<N, Model = S::Model>,
{
    fn check(&self) -> Result<(), FilterError> {
        if let Some(index) = self.z.iter().position(|v| !v.is_finite()) {
            return Err(FilterError::NonFiniteMeasurement { index });
        }
        let finite = match &self.noise {
            MeasurementNoise::Full(r) => r.iter().all(|v| v.is_finite()),
            MeasurementNoise::Diagonal(r) => r.iter().all(|v| v.is_finite()),
        };
        if !finite {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "not finite",
            });
        }
        if let Some(index) = (0..<S::Aux as Record>::LEN).find(|&i| !self.aux.get(i).is_finite()) {
            let name = <S::Aux as Record>::NAMES.get(index).copied().unwrap_or("?");
            return Err(FilterError::NonFiniteAux { index, name });
        }
        Ok(())
    }

    fn raw_values(&self) -> &[f64] {
        let z = self.z.as_slice();
        z.get(..MAX_RAW_VALUES).unwrap_or(z)
    }

    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError> {
        let report = match &self.noise {
            MeasurementNoise::Full(r) => filter.update::<S, M>(&self.z, r, &self.aux)?,
            MeasurementNoise::Diagonal(r) => {
                filter.update_sequential::<S, M>(&self.z, r, &self.aux)?
            }
        };
        Ok(MeasurementOutcome::from(&report))
    }
}

/// A measurement given as a closure that updates the filter, for what a fixed
/// `z` cannot express: an error-state residual formed from the nominal solution
/// at the measurement time (which, for a delayed measurement, is known only
/// during the replay), or a sensor-specific preprocessing step.
///
/// ```ignore
/// let m = FnMeasurement::new(&[z_depth, r_depth], move |f: &mut Esf| {
///     let residual = SVector::from([f.nominal().height() - z_depth]);
///     f.update::<Depth, 1>(&residual, &r, &()).map(|r| MeasurementOutcome::from(&r))
/// });
/// ```
pub struct FnMeasurement<C> {
    finite: bool,
    raw: [f64; MAX_RAW_VALUES],
    raw_len: usize,
    apply: C,
}

impl<C> FnMeasurement<C> {
    /// Wraps `apply`; `values` are the raw sensor values it captured, checked
    /// for finiteness so a non-finite measurement is refused before
    /// scheduling, and (the first [`MAX_RAW_VALUES`]) compared with the
    /// previous ones of the sensor by a [`StuckDetector`].
    pub fn new(values: &[f64], apply: C) -> Self {
        let mut raw = [0.0; MAX_RAW_VALUES];
        let raw_len = values.len().min(MAX_RAW_VALUES);
        raw[..raw_len].copy_from_slice(&values[..raw_len]);
        Self {
            finite: values.iter().all(|v| v.is_finite()),
            raw,
            raw_len,
            apply,
        }
    }
}

impl<F, C> Measurement<F> for FnMeasurement<C>
where
    C: Fn(&mut F) -> Result<MeasurementOutcome, FilterError>,
{
    fn check(&self) -> Result<(), FilterError> {
        if self.finite {
            Ok(())
        } else {
            Err(FilterError::NonFiniteMeasurement { index: 0 })
        }
    }

    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError> {
        (self.apply)(filter)
    }

    fn raw_values(&self) -> &[f64] {
        self.raw.get(..self.raw_len).unwrap_or(&[])
    }
}

/// A registered sensor.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorConfig {
    /// Display name.
    pub name: String,
    /// Nominal rate, Hz (for staleness checks: [`Scheduler::is_stale`]).
    pub rate_hz: f64,
    /// Largest delay, seconds, between a measurement's time and its arrival
    /// (relative to the IMU time); older measurements are refused.
    pub latency: f64,
}

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
    /// Refused as frozen values of a stuck sensor ([`Scheduler::set_stuck_detector`]).
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

/// The multi-rate scheduler (see the module docs).
pub struct Scheduler<F: Propagate + Clone> {
    filter: F,
    now: f64,
    start: f64,
    /// IMU steps, oldest first; `steps[0]` always holds a checkpoint.
    steps: VecDeque<Step<F>>,
    /// Measurements newer than `steps[0]`, sorted by (time, sensor).
    queue: Vec<Queued<F>>,
    sensors: Vec<SensorEntry>,
    window: f64,
    snapshot_every: usize,
    since_snapshot: usize,
    /// Checkpoint buffers dropped from the history, reused for new ones so
    /// that a running scheduler does not allocate for its checkpoints.
    spare: Vec<Box<F>>,
    /// Number of steps in the history holding a checkpoint (at least 1).
    checkpoints: usize,
    max_pending: usize,
    stats: SchedulerStats,
}

impl<F: Propagate + Clone> Scheduler<F> {
    /// Default limit on measurements waiting for the IMU.
    pub const DEFAULT_MAX_PENDING: usize = 4096;

    /// A scheduler whose filter `filter` is valid at time `time`.
    ///
    /// # Errors
    /// [`SchedulerError::NonFiniteTime`].
    pub fn new(filter: F, time: f64) -> Result<Self, SchedulerError> {
        if !time.is_finite() {
            return Err(SchedulerError::NonFiniteTime { time });
        }
        let mut steps = VecDeque::new();
        steps.push_back(Step {
            time,
            input: None,
            snapshot: Some(Box::new(filter.clone())),
        });
        Ok(Self {
            filter,
            now: time,
            start: time,
            steps,
            queue: Vec::new(),
            sensors: Vec::new(),
            window: 0.0,
            snapshot_every: 1,
            since_snapshot: 0,
            spare: Vec::new(),
            checkpoints: 1,
            max_pending: Self::DEFAULT_MAX_PENDING,
            stats: SchedulerStats::default(),
        })
    }

    /// Keeps a checkpoint every `n` IMU steps (`n >= 1`; default 1): memory
    /// falls by `n`, a replay re-propagates up to `n - 1` more steps. Results
    /// are identical for every `n`.
    #[must_use]
    pub fn with_snapshot_every(mut self, n: usize) -> Self {
        self.snapshot_every = n.max(1);
        self
    }

    /// Limits the number of measurements waiting for the IMU.
    #[must_use]
    pub fn with_max_pending(mut self, n: usize) -> Self {
        self.max_pending = n;
        self
    }

    /// Registers a sensor with its nominal rate (Hz) and latency (largest
    /// delay, s). The history grows to the largest latency.
    ///
    /// # Errors
    /// [`SchedulerError::InvalidConfig`] for a non-positive or non-finite rate
    /// or a negative or non-finite latency.
    pub fn add_sensor(
        &mut self,
        name: impl Into<String>,
        rate_hz: f64,
        latency: f64,
    ) -> Result<SensorId, SchedulerError> {
        if !(rate_hz.is_finite() && rate_hz > 0.0) {
            return Err(SchedulerError::InvalidConfig(
                "sensor rate must be finite and positive",
            ));
        }
        if !(latency.is_finite() && latency >= 0.0) {
            return Err(SchedulerError::InvalidConfig(
                "sensor latency must be finite and non-negative",
            ));
        }
        self.window = self.window.max(latency);
        self.sensors.push(SensorEntry {
            config: SensorConfig {
                name: name.into(),
                rate_hz,
                latency,
            },
            finalized: SensorStats::default(),
            last_time: None,
            stuck: None,
        });
        Ok(SensorId(self.sensors.len() - 1))
    }

    /// Refuses the frozen values of sensor `id` with `detector` (see
    /// [`crate::stuck`]): a measurement whose raw values
    /// ([`Measurement::raw_values`]) repeat those of the sensor's previous
    /// measurements (in arrival order) `detector.repeats()` times or more is
    /// refused with [`SchedulerError::Stuck`] and counted in
    /// [`SensorStats::stuck`]; the filter is unchanged. Only measurements that
    /// pass every other check reach the detector.
    ///
    /// # Errors
    /// [`SchedulerError::UnknownSensor`].
    pub fn set_stuck_detector(
        &mut self,
        id: SensorId,
        detector: StuckDetector,
    ) -> Result<(), SchedulerError> {
        let entry = self
            .sensors
            .get_mut(id.0)
            .ok_or(SchedulerError::UnknownSensor(id))?;
        entry.stuck = Some(detector);
        Ok(())
    }

    /// The filter at [`Scheduler::now`].
    pub fn filter(&self) -> &F {
        &self.filter
    }

    /// Time of the newest IMU sample (or the start time).
    pub fn now(&self) -> f64 {
        self.now
    }

    /// Measurements must be newer than this time (the oldest checkpoint).
    pub fn oldest(&self) -> f64 {
        self.steps.front().map_or(self.now, |s| s.time)
    }

    /// Number of IMU steps in the history.
    pub fn history_len(&self) -> usize {
        self.steps.len()
    }

    /// A sensor's configuration.
    pub fn sensor(&self, id: SensorId) -> Option<&SensorConfig> {
        self.sensors.get(id.0).map(|s| &s.config)
    }

    /// Scheduler-wide counts.
    pub fn stats(&self) -> SchedulerStats {
        self.stats
    }

    /// A sensor's counts (final outcomes; see [`SensorStats`]).
    pub fn sensor_stats(&self, id: SensorId) -> Option<SensorStats> {
        let entry = self.sensors.get(id.0)?;
        let mut s = entry.finalized;
        s.stuck_episodes = entry.stuck.map_or(0, |d| d.episodes());
        for q in self.queue.iter().filter(|q| q.sensor == id.0) {
            tally(&mut s, q.outcome.as_ref());
        }
        Some(s)
    }

    /// `true` if sensor `id` has produced nothing for more than two nominal
    /// periods plus its latency (never-seen sensors count from the start).
    pub fn is_stale(&self, id: SensorId) -> bool {
        let Some(entry) = self.sensors.get(id.0) else {
            return false;
        };
        let since = entry.last_time.unwrap_or(self.start);
        self.now - since > 2.0 / entry.config.rate_hz + entry.config.latency
    }

    /// Propagates to `time` with the IMU sample `input` (held over
    /// `(now, time]`), applying queued measurements in that interval at their
    /// own times. Returns their reports.
    ///
    /// # Errors
    /// Non-finite `time` or `input`, `time <= now`, or a propagation error; the
    /// filter and queue are unchanged.
    pub fn push_imu(&mut self, time: f64, input: F::Input) -> Result<Vec<Report>, SchedulerError> {
        let result = self.step_imu(time, input);
        if result.is_err() {
            self.stats.imu_rejected += 1;
        }
        result
    }

    /// Schedules measurement `m` of sensor `sensor` taken at `time`. If the IMU
    /// has already passed `time`, the filter is rolled back and replayed with
    /// `m` in place; the reports of `m` and of every later measurement
    /// re-applied are returned (empty if `m` waits for the IMU).
    ///
    /// # Errors
    /// See [`SchedulerError`]; the filter and queue are unchanged and the
    /// refusal is counted in [`Scheduler::sensor_stats`].
    pub fn push_measurement(
        &mut self,
        sensor: SensorId,
        time: f64,
        m: Box<dyn Measurement<F>>,
    ) -> Result<Vec<Report>, SchedulerError> {
        let Some(entry) = self.sensors.get(sensor.0) else {
            return Err(SchedulerError::UnknownSensor(sensor));
        };
        let latency = entry.config.latency;
        let result = self.schedule(sensor, time, latency, m);
        if let (Err(e), Some(entry)) = (&result, self.sensors.get_mut(sensor.0)) {
            let s = &mut entry.finalized;
            match e {
                SchedulerError::TooOld { .. } => s.too_old += 1,
                SchedulerError::Duplicate { .. } => s.duplicate += 1,
                SchedulerError::QueueFull { .. } => s.queue_full += 1,
                SchedulerError::Stuck { .. } => s.stuck += 1,
                SchedulerError::NonFiniteTime { .. }
                | SchedulerError::InvalidMeasurement { .. } => s.invalid += 1,
                _ => s.failed += 1,
            }
        }
        result
    }

    /// Convenience for [`Scheduler::push_measurement`] with a batch
    /// [`SensorUpdate`] of sensor type `S`.
    ///
    /// # Errors
    /// As [`Scheduler::push_measurement`].
    pub fn push_update<S, const N: usize, const M: usize>(
        &mut self,
        sensor: SensorId,
        time: f64,
        z: SVector<f64, M>,
        r: SMatrix<f64, M, M>,
        aux: S::Aux,
    ) -> Result<Vec<Report>, SchedulerError>
    where
        S: Sensor<N, M>,
        F: Estimator<N, Model = S::Model>,
    {
        self.push_measurement(
            sensor,
            time,
            Box::new(SensorUpdate::<S, N, M>::new(z, r, aux)),
        )
    }

    fn step_imu(&mut self, time: f64, input: F::Input) -> Result<Vec<Report>, SchedulerError> {
        if !time.is_finite() {
            return Err(SchedulerError::NonFiniteTime { time });
        }
        if time < self.now {
            return Err(SchedulerError::TimeWentBackwards {
                time,
                now: self.now,
            });
        }
        if time == self.now {
            return Err(SchedulerError::DuplicateImu { time });
        }
        F::check_input(&input).map_err(SchedulerError::InvalidImu)?;
        let range = self.interval(self.now, time);
        let reports = if range.is_empty() {
            // Nothing to apply: one propagation, which leaves the filter
            // unchanged on error, so it runs on the filter itself.
            self.filter
                .propagate(time - self.now, &input)
                .map_err(SchedulerError::Propagation)?;
            Vec::new()
        } else {
            // Several propagations and updates: on a copy, committed only if
            // every propagation succeeds.
            let mut next = self.filter.clone();
            let start = range.start;
            let outcomes = run_interval(&mut next, self.now, time, &input, &self.queue, range)?;
            let mut reports = Vec::with_capacity(outcomes.len());
            for (offset, outcome) in outcomes.into_iter().enumerate() {
                if let Some(q) = self.queue.get_mut(start + offset) {
                    q.outcome = Some(outcome);
                    reports.push(Report {
                        sensor: SensorId(q.sensor),
                        time: q.time,
                        replay: false,
                        outcome,
                    });
                }
            }
            self.filter = next;
            reports
        };
        self.since_snapshot += 1;
        let snapshot = if self.since_snapshot >= self.snapshot_every {
            self.since_snapshot = 0;
            Some(match self.spare.pop() {
                Some(mut buffer) => {
                    buffer.as_mut().clone_from(&self.filter);
                    buffer
                }
                None => Box::new(self.filter.clone()),
            })
        } else {
            None
        };
        self.checkpoints += usize::from(snapshot.is_some());
        self.steps.push_back(Step {
            time,
            input: Some(input),
            snapshot,
        });
        self.now = time;
        self.stats.imu_samples += 1;
        self.trim();
        Ok(reports)
    }

    fn schedule(
        &mut self,
        sensor: SensorId,
        time: f64,
        latency: f64,
        m: Box<dyn Measurement<F>>,
    ) -> Result<Vec<Report>, SchedulerError> {
        if !time.is_finite() {
            return Err(SchedulerError::NonFiniteTime { time });
        }
        m.check()
            .map_err(|source| SchedulerError::InvalidMeasurement { sensor, source })?;
        let oldest = self.oldest().max(self.now - latency);
        if time <= self.oldest() || self.now - time > latency {
            return Err(SchedulerError::TooOld {
                sensor,
                time,
                now: self.now,
                oldest,
            });
        }
        let key = (time, sensor.0);
        let at = self.queue.partition_point(|q| q.key() < key);
        if self.queue.get(at).is_some_and(|q| q.key() == key) {
            return Err(SchedulerError::Duplicate { sensor, time });
        }
        let future = time > self.now;
        if future {
            let pending = self.queue.len() - self.queue.partition_point(|q| q.time <= self.now);
            if pending >= self.max_pending {
                return Err(SchedulerError::QueueFull {
                    capacity: self.max_pending,
                });
            }
        }
        if let Some(detector) = self
            .sensors
            .get_mut(sensor.0)
            .and_then(|e| e.stuck.as_mut())
        {
            if let crate::stuck::StuckVerdict::Stuck { run } = detector.observe(m.raw_values()) {
                return Err(SchedulerError::Stuck { sensor, run });
            }
        }
        let entry = Queued {
            sensor: sensor.0,
            time,
            measurement: m,
            outcome: None,
        };
        if future {
            self.queue.insert(at, entry);
            self.note_time(sensor, time);
            return Ok(Vec::new());
        }
        self.queue.insert(at, entry);
        match self.replay(time, at) {
            Ok(reports) => {
                self.note_time(sensor, time);
                Ok(reports)
            }
            Err(e) => {
                self.queue.remove(at);
                Err(e)
            }
        }
    }

    /// Rolls back to the newest checkpoint before `time` and re-propagates to
    /// `now`, applying the queue; commits only if every propagation succeeds.
    fn replay(&mut self, time: f64, inserted: usize) -> Result<Vec<Report>, SchedulerError> {
        // `schedule` checked `time > steps[0].time`, and `steps[0]` always
        // holds a checkpoint, so this search cannot fail.
        let lost =
            SchedulerError::InvalidConfig("history has no checkpoint before the measurement");
        let base = self
            .steps
            .iter()
            .rposition(|s| s.time < time && s.snapshot.is_some())
            .ok_or(lost)?;
        let Some(mut filter) = self
            .steps
            .get(base)
            .and_then(|s| s.snapshot.as_deref().cloned())
        else {
            return Err(lost);
        };
        let mut snapshots = Vec::new();
        let mut outcomes = Vec::new();
        for i in base + 1..self.steps.len() {
            let (Some(prev), Some(step)) = (self.steps.get(i - 1), self.steps.get(i)) else {
                break;
            };
            let Some(input) = step.input.as_ref() else {
                continue;
            };
            let range = self.interval(prev.time, step.time);
            let start = range.start;
            let got = run_interval(&mut filter, prev.time, step.time, input, &self.queue, range)?;
            outcomes.extend(got.into_iter().enumerate().map(|(k, o)| (start + k, o)));
            if step.snapshot.is_some() {
                snapshots.push((i, filter.clone()));
            }
        }
        // Commit.
        self.stats.replays += 1;
        self.stats.replayed_steps += (self.steps.len() - base - 1) as u64;
        for (i, snap) in snapshots {
            if let Some(buffer) = self.steps.get_mut(i).and_then(|s| s.snapshot.as_mut()) {
                **buffer = snap;
            }
        }
        let mut reports = Vec::new();
        for (index, outcome) in outcomes {
            if let Some(q) = self.queue.get_mut(index) {
                q.outcome = Some(outcome);
                if index >= inserted {
                    reports.push(Report {
                        sensor: SensorId(q.sensor),
                        time: q.time,
                        replay: index != inserted,
                        outcome,
                    });
                }
            }
        }
        self.filter = filter;
        Ok(reports)
    }

    /// Indices of queued measurements with time in `(t0, t1]`.
    fn interval(&self, t0: f64, t1: f64) -> std::ops::Range<usize> {
        self.queue.partition_point(|q| q.time <= t0)..self.queue.partition_point(|q| q.time <= t1)
    }

    /// Drops history older than the window, keeping a checkpoint at or before
    /// `now - window`, and finalizes the measurements it contained.
    fn trim(&mut self) {
        let limit = self.now - self.window;
        // With a single checkpoint there is nothing to drop (and no need to
        // scan the history for a second one).
        while self.checkpoints >= 2 {
            let second = self
                .steps
                .iter()
                .skip(1)
                .position(|s| s.snapshot.is_some())
                .map(|i| i + 1);
            match second {
                Some(i) if self.steps.get(i).is_some_and(|s| s.time < limit) => {
                    for step in self.steps.drain(..i) {
                        if let Some(buffer) = step.snapshot {
                            self.checkpoints -= 1;
                            if self.spare.len() < MAX_SPARE_SNAPSHOTS {
                                self.spare.push(buffer);
                            }
                        }
                    }
                }
                _ => break,
            }
        }
        let base = self.oldest();
        let done = self.queue.partition_point(|q| q.time <= base);
        for q in self.queue.drain(..done) {
            if let Some(entry) = self.sensors.get_mut(q.sensor) {
                tally(&mut entry.finalized, q.outcome.as_ref());
            }
        }
    }

    fn note_time(&mut self, sensor: SensorId, time: f64) {
        if let Some(entry) = self.sensors.get_mut(sensor.0) {
            entry.last_time = Some(entry.last_time.map_or(time, |t| t.max(time)));
        }
    }
}

impl<F: Propagate + Clone + core::fmt::Debug> core::fmt::Debug for Scheduler<F> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Scheduler")
            .field("now", &self.now)
            .field("filter", &self.filter)
            .field("history_len", &self.steps.len())
            .field("queued", &self.queue.len())
            .field("stats", &self.stats)
            .finish_non_exhaustive()
    }
}

/// Checkpoint buffers kept for reuse (see `Scheduler::spare`).
const MAX_SPARE_SNAPSHOTS: usize = 4;

/// One IMU step: the sample held over `(previous time, time]` and, every
/// `snapshot_every` steps, the filter after the step (boxed: most steps hold
/// none, and the history moves steps around).
struct Step<F: Propagate> {
    time: f64,
    input: Option<F::Input>,
    snapshot: Option<Box<F>>,
}

struct Queued<F> {
    sensor: usize,
    time: f64,
    measurement: Box<dyn Measurement<F>>,
    outcome: Option<Result<MeasurementOutcome, FilterError>>,
}

impl<F> Queued<F> {
    fn key(&self) -> (f64, usize) {
        (self.time, self.sensor)
    }
}

struct SensorEntry {
    config: SensorConfig,
    /// Refusals, plus final outcomes of measurements that left the history.
    finalized: SensorStats,
    last_time: Option<f64>,
    stuck: Option<StuckDetector>,
}

/// Propagates `filter` over `(t0, t1]` with `input`, stopping at each queued
/// measurement in `range` (all inside the interval, in order) to apply it.
fn run_interval<F: Propagate>(
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

fn tally(s: &mut SensorStats, outcome: Option<&Result<MeasurementOutcome, FilterError>>) {
    match outcome {
        None => s.pending += 1,
        Some(Ok(o)) if o.accepted => s.accepted += 1,
        Some(Ok(_)) => s.gated += 1,
        Some(Err(_)) => s.failed += 1,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::ekf::Ekf;
    use crate::error_state::ErrorStateFilter;
    use crate::testmodels::{Cvb, CvbInput, CvbNoise, Gauss, Offset, Pos, PosVel, Toy};

    type Filter = Ekf<Cvb, 3>;
    type V3 = SVector<f64, 3>;

    const DT: f64 = 0.01;
    const NOISE: CvbNoise = CvbNoise {
        q_a: 1e-2,
        q_b: 1e-6,
    };

    fn p0() -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::from_diagonal(&V3::new(4.0, 0.25, 0.01))
    }

    fn filter() -> Filter {
        Ekf::new(V3::new(0.5, 0.1, 0.0), p0(), (), NOISE).unwrap()
    }

    /// Sensor kinds of the scenarios: registered in this order.
    #[derive(Clone, Copy, Debug, PartialEq)]
    enum Kind {
        Pos,
        PosVel,
        PosVelSequential,
    }

    #[derive(Clone, Copy, Debug)]
    struct Meas {
        kind: Kind,
        time: f64,
        z: [f64; 2],
    }

    struct Scenario {
        imu: Vec<(f64, CvbInput)>,
        meas: Vec<Meas>,
    }

    /// Truth of the toy at 100 Hz; position fixes at 1 Hz, position-velocity
    /// at 2 Hz (batch) and 2 Hz (sequential), at times off the IMU grid and,
    /// for one sensor, on it.
    fn scenario(seconds: u32, seed: u64) -> Scenario {
        let mut g = Gauss::new(seed);
        let (mut p, mut v, b) = (0.0, 0.0, 0.03);
        let mut imu = Vec::new();
        let mut truth = Vec::new();
        for k in 1..=seconds * 100 {
            let t = f64::from(k) * DT;
            let a = (t * 0.3).sin();
            p += v * DT;
            v += a * DT;
            imu.push((
                t,
                CvbInput {
                    a: a + b + 0.05 * g.normal(),
                },
            ));
            truth.push((t, p, v));
        }
        let at = |t: f64| {
            truth
                .iter()
                .rev()
                .find(|s| s.0 <= t)
                .map_or((0.0, 0.0), |s| (s.1, s.2))
        };
        let mut meas = Vec::new();
        for k in 0..seconds {
            let t = f64::from(k) + 0.0037;
            let (p, _) = at(t);
            meas.push(Meas {
                kind: Kind::Pos,
                time: t,
                z: [p + 0.5 * g.normal(), 0.0],
            });
        }
        for k in 1..seconds * 2 {
            let t = f64::from(k) * 0.5 + 0.0021;
            let (p, v) = at(t);
            meas.push(Meas {
                kind: Kind::PosVel,
                time: t,
                z: [p + 0.3 * g.normal(), v + 0.05 * g.normal()],
            });
            // On the IMU grid (k * 0.5 s is a multiple of DT up to rounding of
            // the grid itself: use the grid's own value).
            let t_grid = imu[(k * 50 - 1) as usize].0;
            let (p, v) = at(t_grid);
            meas.push(Meas {
                kind: Kind::PosVelSequential,
                time: t_grid,
                z: [p + 0.3 * g.normal(), v + 0.05 * g.normal()],
            });
        }
        meas.sort_by(|a, b| a.time.total_cmp(&b.time));
        Scenario { imu, meas }
    }

    fn boxed(m: &Meas) -> Box<dyn Measurement<Filter>> {
        match m.kind {
            Kind::Pos => Box::new(SensorUpdate::<Pos, 3, 1>::new(
                SVector::<f64, 1>::new(m.z[0]),
                SMatrix::<f64, 1, 1>::new(0.25),
                Offset::default(),
            )),
            Kind::PosVel => Box::new(SensorUpdate::<PosVel, 3, 2>::new(
                SVector::<f64, 2>::new(m.z[0], m.z[1]),
                SMatrix::<f64, 2, 2>::new(0.09, 0.001, 0.001, 0.0025),
                (),
            )),
            Kind::PosVelSequential => Box::new(SensorUpdate::<PosVel, 3, 2>::sequential(
                SVector::<f64, 2>::new(m.z[0], m.z[1]),
                SVector::<f64, 2>::new(0.09, 0.0025),
                (),
            )),
        }
    }

    fn scheduler(snapshot_every: usize) -> (Scheduler<Filter>, [SensorId; 3]) {
        let mut s = Scheduler::new(filter(), 0.0)
            .unwrap()
            .with_snapshot_every(snapshot_every);
        let ids = [
            s.add_sensor("pos", 1.0, 5.0).unwrap(),
            s.add_sensor("posvel", 2.0, 5.0).unwrap(),
            s.add_sensor("posvel-seq", 2.0, 5.0).unwrap(),
        ];
        (s, ids)
    }

    fn id_of(ids: &[SensorId; 3], kind: Kind) -> SensorId {
        match kind {
            Kind::Pos => ids[0],
            Kind::PosVel => ids[1],
            Kind::PosVelSequential => ids[2],
        }
    }

    /// Runs a scenario where measurement `i` arrives at `arrival[i]` (an IMU
    /// sample at `t` arrives at `t`; measurements arriving at the same time as
    /// an IMU sample come first). Ties between measurements keep list order.
    fn run(sc: &Scenario, arrival: &[f64], snapshot_every: usize) -> Scheduler<Filter> {
        let (mut s, ids) = scheduler(snapshot_every);
        let mut order: Vec<usize> = (0..sc.meas.len()).collect();
        order.sort_by(|&a, &b| arrival[a].total_cmp(&arrival[b]));
        let mut next = 0;
        for &(t, u) in &sc.imu {
            while let Some(&i) = order.get(next) {
                if arrival[i] > t {
                    break;
                }
                let m = &sc.meas[i];
                s.push_measurement(id_of(&ids, m.kind), m.time, boxed(m))
                    .unwrap();
                next += 1;
            }
            s.push_imu(t, u).unwrap();
        }
        // Whatever arrives after the last IMU sample is still delivered.
        for &i in order.get(next..).unwrap_or(&[]) {
            let m = &sc.meas[i];
            s.push_measurement(id_of(&ids, m.kind), m.time, boxed(m))
                .unwrap();
        }
        s
    }

    fn on_time(sc: &Scenario) -> Vec<f64> {
        // Delivered before the IMU sample that covers them.
        sc.meas.iter().map(|m| m.time - DT).collect()
    }

    fn rel_diff(a: &Filter, b: &Filter) -> f64 {
        let dx = (a.state() - b.state()).amax() / (1.0 + a.state().amax());
        let dp = (a.covariance() - b.covariance()).amax() / a.covariance().amax();
        dx.max(dp)
    }

    fn bits(s: &Scheduler<Filter>) -> Vec<u64> {
        let f = s.filter();
        let mut v: Vec<u64> = f
            .state()
            .iter()
            .chain(f.covariance().iter())
            .map(|x| x.to_bits())
            .collect();
        v.push(f.input().a.to_bits());
        v.push(s.now().to_bits());
        v.push(s.history_len() as u64);
        v.push(s.queue.len() as u64);
        v
    }

    #[test]
    fn delayed_fix_equals_the_same_fix_on_time() {
        let sc = scenario(20, 1);
        let reference = run(&sc, &on_time(&sc), 1);
        let mut arrival = on_time(&sc);
        let i = sc
            .meas
            .iter()
            .position(|m| m.kind == Kind::Pos && m.time > 10.0)
            .unwrap();
        arrival[i] = sc.meas[i].time + 4.0;
        let delayed = run(&sc, &arrival, 1);
        let d = rel_diff(reference.filter(), delayed.filter());
        assert!(d < 1e-9, "relative difference {d}");
        assert_eq!(delayed.stats().replays, 1);
        // The replay covers 4 s of IMU steps.
        assert!(
            (399..=401).contains(&delayed.stats().replayed_steps),
            "{:?}",
            delayed.stats()
        );
        // Without the fix the estimate differs: the test is not vacuous.
        let mut meas = sc.meas.clone();
        meas.remove(i);
        let less = Scenario {
            imu: sc.imu.clone(),
            meas,
        };
        let without = run(&less, &on_time(&less), 1);
        assert!(rel_diff(reference.filter(), without.filter()) > 1e-6);
    }

    #[test]
    fn shuffled_arrival_within_the_history_equals_sorted_arrival() {
        let sc = scenario(30, 2);
        let reference = run(&sc, &on_time(&sc), 1);
        let mut g = Gauss::new(99);
        for snapshot_every in [1, 7] {
            // Random delays up to 3 s: arrival order is a random permutation
            // within a sliding 3 s window.
            let arrival: Vec<f64> = sc
                .meas
                .iter()
                .map(|m| m.time + 3.0 * g.normal().abs().min(1.0))
                .collect();
            let late = run(&sc, &arrival, snapshot_every);
            let d = rel_diff(reference.filter(), late.filter());
            assert!(d < 1e-12, "every {snapshot_every}: {d}");
            // Whole 2 s blocks delivered at once, shuffled.
            let mut arrival = vec![0.0; sc.meas.len()];
            let mut blocks: Vec<Vec<usize>> = vec![Vec::new(); 16];
            for (i, m) in sc.meas.iter().enumerate() {
                blocks[(m.time / 2.0) as usize].push(i);
            }
            for (b, block) in blocks.iter_mut().enumerate() {
                for k in (1..block.len()).rev() {
                    block.swap(k, g.index(k + 1));
                }
                for (rank, &i) in block.iter().enumerate() {
                    // Same arrival time for the block; `run` keeps list order
                    // for ties, so give a tiny rank offset instead.
                    arrival[i] = (b as f64 + 1.0) * 2.0 + 1e-6 * rank as f64;
                }
            }
            let shuffled = run(&sc, &arrival, snapshot_every);
            assert!(
                rel_diff(reference.filter(), shuffled.filter()) < 1e-12,
                "every {snapshot_every}"
            );
            for k in [Kind::Pos, Kind::PosVel, Kind::PosVelSequential] {
                let ids = [SensorId(0), SensorId(1), SensorId(2)];
                let a = reference.sensor_stats(id_of(&ids, k)).unwrap();
                let b = shuffled.sensor_stats(id_of(&ids, k)).unwrap();
                assert_eq!(
                    (a.accepted, a.gated, a.failed),
                    (b.accepted, b.gated, b.failed),
                    "{k:?}"
                );
            }
        }
        let s = reference.sensor_stats(SensorId(0)).unwrap();
        assert_eq!(s.accepted + s.gated, 30);
    }

    #[test]
    fn a_measurement_inside_an_imu_interval_splits_it() {
        let (mut s, ids) = scheduler(1);
        let u0 = CvbInput { a: 0.2 };
        let u1 = CvbInput { a: -0.4 };
        let z = SVector::<f64, 1>::new(0.9);
        let r = SMatrix::<f64, 1, 1>::new(0.25);
        s.push_imu(0.01, u0).unwrap();
        s.push_update::<Pos, 3, 1>(ids[0], 0.0137, z, r, Offset::default())
            .unwrap();
        let reports = s.push_imu(0.02, u1).unwrap();
        assert_eq!(reports.len(), 1);
        assert!(!reports[0].replay && reports[0].outcome.unwrap().accepted);
        let mut f = filter();
        f.predict(0.01, &u0).unwrap();
        f.predict(0.0137 - 0.01, &u1).unwrap();
        f.update::<Pos, 1>(&z, &r, &Offset::default()).unwrap();
        f.predict(0.02 - 0.0137, &u1).unwrap();
        assert_eq!(s.filter().state(), f.state());
        assert_eq!(s.filter().covariance(), f.covariance());
    }

    #[test]
    fn simultaneous_measurements_apply_in_sensor_order_whatever_the_arrival() {
        let run_with = |pos_first: bool| {
            let (mut s, ids) = scheduler(1);
            s.push_imu(0.01, CvbInput { a: 0.1 }).unwrap();
            let a = Meas {
                kind: Kind::Pos,
                time: 0.015,
                z: [1.0, 0.0],
            };
            let b = Meas {
                kind: Kind::PosVel,
                time: 0.015,
                z: [0.7, 0.2],
            };
            let (first, second) = if pos_first { (a, b) } else { (b, a) };
            s.push_measurement(id_of(&ids, first.kind), first.time, boxed(&first))
                .unwrap();
            s.push_imu(0.02, CvbInput { a: 0.1 }).unwrap();
            // The second arrives late: rollback and replay.
            let reports = s
                .push_measurement(id_of(&ids, second.kind), second.time, boxed(&second))
                .unwrap();
            (bits(&s), reports)
        };
        let (a, ra) = run_with(true);
        let (b, rb) = run_with(false);
        assert_eq!(a, b);
        // Pos (sensor 0) before PosVel (sensor 1): when Pos arrives late the
        // PosVel update after it is re-applied and reported as a replay.
        assert_eq!(ra.len(), 1);
        assert_eq!(rb.len(), 2);
        assert!(!rb[0].replay && rb[1].replay);
    }

    #[test]
    fn refused_events_leave_the_filter_bit_identical_and_are_counted() {
        let sc = scenario(12, 3);
        let mut s = run(&sc, &on_time(&sc), 1);
        let ids = [SensorId(0), SensorId(1), SensorId(2)];
        let now = s.now();
        // A pending measurement, to check that duplicates of queued ones are refused too.
        s.push_update::<Pos, 3, 1>(
            ids[0],
            now + 0.5,
            SVector::<f64, 1>::new(1.0),
            SMatrix::<f64, 1, 1>::new(1.0),
            Offset::default(),
        )
        .unwrap();
        let before = bits(&s);
        let z = SVector::<f64, 1>::new(1.0);
        let r = SMatrix::<f64, 1, 1>::new(1.0);
        let pos = |z: f64, r: f64, o: f64| -> Box<dyn Measurement<Filter>> {
            Box::new(SensorUpdate::<Pos, 3, 1>::new(
                SVector::<f64, 1>::new(z),
                SMatrix::<f64, 1, 1>::new(r),
                Offset { offset: o },
            ))
        };
        let existing = sc
            .meas
            .iter()
            .rev()
            .find(|m| m.kind == Kind::Pos)
            .unwrap()
            .time;
        let cases: Vec<(&str, Result<Vec<Report>, SchedulerError>)> = vec![
            ("imu backwards", s.push_imu(now - 0.5, CvbInput { a: 0.0 })),
            ("imu duplicate", s.push_imu(now, CvbInput { a: 0.0 })),
            ("imu NaN time", s.push_imu(f64::NAN, CvbInput { a: 0.0 })),
            (
                "imu NaN input",
                s.push_imu(now + DT, CvbInput { a: f64::NAN }),
            ),
            (
                "older than latency",
                s.push_measurement(ids[0], now - 5.5, pos(1.0, 1.0, 0.0)),
            ),
            (
                "older than history",
                s.push_measurement(ids[0], -1.0, pos(1.0, 1.0, 0.0)),
            ),
            (
                "duplicate applied",
                s.push_measurement(ids[0], existing, pos(1.0, 1.0, 0.0)),
            ),
            (
                "duplicate pending",
                s.push_measurement(ids[0], now + 0.5, pos(1.0, 1.0, 0.0)),
            ),
            (
                "NaN z",
                s.push_measurement(ids[0], now - 1.0, pos(f64::NAN, 1.0, 0.0)),
            ),
            (
                "inf R",
                s.push_measurement(ids[0], now - 1.0, pos(1.0, f64::INFINITY, 0.0)),
            ),
            (
                "NaN aux",
                s.push_measurement(ids[0], now - 1.0, pos(1.0, 1.0, f64::NAN)),
            ),
            (
                "NaN time",
                s.push_measurement(ids[0], f64::NAN, pos(1.0, 1.0, 0.0)),
            ),
            (
                "unknown sensor",
                s.push_update::<Pos, 3, 1>(SensorId(9), now - 1.0, z, r, Offset::default()),
            ),
        ];
        for (name, result) in &cases {
            assert!(result.is_err(), "{name} accepted");
            assert_eq!(bits(&s), before, "{name} changed the filter");
        }
        let st = s.sensor_stats(ids[0]).unwrap();
        assert_eq!(
            (st.too_old, st.duplicate, st.invalid, st.pending),
            (2, 2, 4, 1),
            "{st:?}"
        );
        assert_eq!(s.stats().imu_rejected, 4);
        assert!(matches!(
            cases[0].1,
            Err(SchedulerError::TimeWentBackwards { .. })
        ));
        assert!(matches!(cases[5].1, Err(SchedulerError::TooOld { .. })));
        // A measurement the filter itself refuses (singular S) is reported, not an error.
        let (mut s2, ids2) = scheduler(1);
        s2.push_imu(0.01, CvbInput { a: 0.0 }).unwrap();
        let rep = s2
            .push_measurement(ids2[0], 0.005, pos(0.0, 0.0, 0.0))
            .unwrap();
        assert!(rep[0].outcome.is_ok());
    }

    /// A frozen sensor: its repeats are refused with a typed error once the
    /// run reaches the detector's limit, counted, and leave the filter
    /// bit-identical; a changed value is taken again. Without a detector the
    /// same values are applied.
    #[test]
    fn stuck_sensor_is_refused_until_its_value_changes() {
        let fix = |z: f64| -> Box<dyn Measurement<Filter>> {
            Box::new(SensorUpdate::<Pos, 3, 1>::new(
                SVector::<f64, 1>::new(z),
                SMatrix::<f64, 1, 1>::new(0.25),
                Offset::default(),
            ))
        };
        let drive = |detect: bool| {
            let (mut s, ids) = scheduler(1);
            if detect {
                s.set_stuck_detector(ids[0], StuckDetector::new(3)).unwrap();
            }
            let mut refused = Vec::new();
            for k in 1..=100 {
                let t = f64::from(k) * DT;
                s.push_imu(t, CvbInput { a: 0.0 }).unwrap();
                if k % 10 == 5 {
                    // Fixes 0-2 vary, 3-7 are frozen at 0.7, 8-9 vary again.
                    let i = k / 10;
                    let z = if (3..=7).contains(&i) {
                        0.7
                    } else {
                        0.1 * f64::from(i)
                    };
                    let before = bits(&s);
                    match s.push_measurement(ids[0], t + 0.001, fix(z)) {
                        Err(SchedulerError::Stuck { run, .. }) => {
                            assert_eq!(bits(&s), before, "fix {i} changed the filter");
                            refused.push((i, run));
                        }
                        other => assert!(other.is_ok(), "fix {i}: {other:?}"),
                    }
                }
            }
            (s, ids, refused)
        };
        let (mut s, ids, refused) = drive(true);
        // The third identical value and later ones are refused.
        assert_eq!(refused, vec![(5, 3), (6, 4), (7, 5)]);
        let st = s.sensor_stats(ids[0]).unwrap();
        assert_eq!((st.stuck, st.stuck_episodes), (3, 1), "{st:?}");
        assert_eq!(st.accepted + st.gated + st.pending, 7, "{st:?}");
        let (plain, ids, refused) = drive(false);
        assert!(refused.is_empty());
        let st = plain.sensor_stats(ids[0]).unwrap();
        assert_eq!((st.stuck, st.accepted + st.gated + st.pending), (0, 10));
        assert_ne!(bits(&plain), bits(&s));
        assert_eq!(
            s.set_stuck_detector(SensorId(9), StuckDetector::new(3)),
            Err(SchedulerError::UnknownSensor(SensorId(9)))
        );
    }

    #[test]
    fn queue_is_bounded_and_history_is_trimmed() {
        let (s, ids) = scheduler(1);
        let mut s = s.with_max_pending(3);
        for k in 0..3 {
            s.push_update::<Pos, 3, 1>(
                ids[0],
                1.0 + f64::from(k),
                SVector::<f64, 1>::new(0.0),
                SMatrix::<f64, 1, 1>::new(1.0),
                Offset::default(),
            )
            .unwrap();
        }
        let full = s.push_update::<Pos, 3, 1>(
            ids[0],
            9.0,
            SVector::<f64, 1>::new(0.0),
            SMatrix::<f64, 1, 1>::new(1.0),
            Offset::default(),
        );
        assert_eq!(full, Err(SchedulerError::QueueFull { capacity: 3 }));
        for k in 1..=2000 {
            s.push_imu(f64::from(k) * DT, CvbInput { a: 0.0 }).unwrap();
        }
        // 5 s window at 100 Hz, plus the base checkpoint.
        assert!(
            (500..=502).contains(&s.history_len()),
            "{}",
            s.history_len()
        );
        assert!(s.oldest() < s.now() - 5.0);
        let st = s.sensor_stats(ids[0]).unwrap();
        assert_eq!(
            (st.accepted + st.gated, st.pending, st.queue_full),
            (3, 0, 1)
        );
        // Sensor 1 never reported; sensor 0 last at 3 s, 17 s ago (> 2 s + 5 s).
        assert!(s.is_stale(ids[1]) && s.is_stale(ids[0]));
        s.push_update::<Pos, 3, 1>(
            ids[0],
            19.0,
            SVector::<f64, 1>::new(0.0),
            SMatrix::<f64, 1, 1>::new(1.0),
            Offset::default(),
        )
        .unwrap();
        assert!(!s.is_stale(ids[0]));
    }

    /// An error-state filter driven by raw IMU samples through the scheduler,
    /// its residuals formed from the nominal solution at the measurement time:
    /// a delayed fix gives the on-time result, and both equal the full-state
    /// filter.
    #[test]
    fn error_state_filter_is_scheduled_with_delayed_residuals() {
        type Esf = ErrorStateFilter<Cvb, Toy, 3>;
        let sc = scenario(15, 5);
        let fixes: Vec<&Meas> = sc.meas.iter().filter(|m| m.kind == Kind::Pos).collect();
        let make = |delay_index: Option<usize>| {
            let ekf = Ekf::<Cvb, 3>::new(V3::zeros(), p0(), (), NOISE).unwrap();
            let mut s = Scheduler::new(
                ErrorStateFilter::new(
                    ekf,
                    Toy {
                        p: 0.5,
                        v: 0.1,
                        b: 0.0,
                    },
                ),
                0.0,
            )
            .unwrap();
            let id = s.add_sensor("pos", 1.0, 5.0).unwrap();
            let mut late = None;
            let mut next = 0;
            for &(t, u) in &sc.imu {
                while let Some(m) = fixes.get(next) {
                    if m.time - DT > t {
                        break;
                    }
                    let z = m.z[0];
                    let meas = FnMeasurement::new(&[z], move |f: &mut Esf| {
                        let residual = SVector::<f64, 1>::new(f.nominal().p - z);
                        f.update::<Pos, 1>(
                            &residual,
                            &SMatrix::<f64, 1, 1>::new(0.25),
                            &Offset::default(),
                        )
                        .map(|r| MeasurementOutcome::from(&r))
                    });
                    if Some(next) == delay_index {
                        late = Some((m.time, meas));
                    } else {
                        s.push_measurement(id, m.time, Box::new(meas)).unwrap();
                    }
                    next += 1;
                }
                s.push_imu(t, u).unwrap();
                if let Some((tm, _)) = &late {
                    if t >= tm + 4.0 {
                        let (tm, meas) = late.take().unwrap();
                        s.push_measurement(id, tm, Box::new(meas)).unwrap();
                    }
                }
            }
            s
        };
        let timely = make(None);
        let delayed = make(Some(6));
        let (a, b) = (timely.filter().nominal(), delayed.filter().nominal());
        let diff = (a.p - b.p)
            .abs()
            .max((a.v - b.v).abs())
            .max((a.b - b.b).abs());
        assert!(diff < 1e-9 * (1.0 + a.p.abs()), "{a:?} vs {b:?}");
        assert_eq!(delayed.stats().replays, 1);
        // Full-state filter on the same data.
        let only_fixes = Scenario {
            imu: sc.imu.clone(),
            meas: fixes.iter().map(|m| **m).collect(),
        };
        let full = run(&only_fixes, &on_time(&only_fixes), 1);
        let x = full.filter().state();
        let got = V3::new(a.p, a.v, a.b);
        assert!((got - x).amax() < 1e-9 * (1.0 + x.amax()), "{got} vs {x}");
        assert!((timely.filter().covariance() - full.filter().covariance()).amax() < 1e-12);
    }
}
