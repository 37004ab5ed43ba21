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

//!
//! The module is split by facet, re-exported flat: the scheduler itself
//! (here), its errors (`error`), the type-erased measurements (`measurement`),
//! registered sensors (`sensor`), counts and reports (`stats`) and the history
//! of IMU steps, checkpoints and queued measurements (`history`).

use std::collections::VecDeque;

use nalgebra::{SMatrix, SVector};

use crate::ekf::{Estimator, Propagate};
use crate::model::Sensor;
use crate::stuck::StuckDetector;
pub use crate::stuck::MAX_RAW_VALUES;

mod error;
mod history;
mod measurement;
mod sensor;
mod stats;
#[cfg(test)]
mod tests;

pub use error::SchedulerError;
pub use measurement::{
    FnMeasurement, Measurement, MeasurementNoise, MeasurementOutcome, SensorUpdate,
};
pub use sensor::{SensorConfig, SensorId};
pub use stats::{Report, SchedulerStats, SensorStats};

use history::{run_interval, Queued, Step, MAX_SPARE_SNAPSHOTS};
use sensor::SensorEntry;
use stats::tally;

/// The multi-rate scheduler (see the module docs).
pub struct Scheduler<F: Propagate + Clone> {
    /// Boxed so that committing a step or a replay is a pointer swap with
    /// [`Scheduler::scratch`], not a copy of the filter.
    filter: Box<F>,
    /// The buffer a step with measurements (or a replay) runs on before it
    /// is committed; reused, so a running scheduler does not allocate for it.
    scratch: Option<Box<F>>,
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
            filter: Box::new(filter),
            scratch: None,
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

    /// Changes the latency of sensor `id` (s): the history follows the
    /// largest latency of all sensors from the next step (a shorter one
    /// drops what is older; a longer one keeps history from now on).
    ///
    /// # Errors
    /// [`SchedulerError::UnknownSensor`]; [`SchedulerError::InvalidConfig`]
    /// for a negative or non-finite latency.
    pub fn set_latency(&mut self, id: SensorId, latency: f64) -> Result<(), SchedulerError> {
        if !(latency.is_finite() && latency >= 0.0) {
            return Err(SchedulerError::InvalidConfig(
                "sensor latency must be finite and non-negative",
            ));
        }
        let entry = self
            .sensors
            .get_mut(id.0)
            .ok_or(SchedulerError::UnknownSensor(id))?;
        entry.config.latency = latency;
        self.window = self
            .sensors
            .iter()
            .fold(0.0_f64, |w, s| w.max(s.config.latency));
        Ok(())
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
            // Several propagations and updates: on a copy (the reused
            // scratch buffer), committed only if every propagation succeeds.
            let mut next = self.copy_of_filter();
            let start = range.start;
            let outcomes =
                match run_interval(&mut *next, self.now, time, &input, &self.queue, range) {
                    Ok(outcomes) => outcomes,
                    Err(e) => {
                        self.scratch = Some(next);
                        return Err(e);
                    }
                };
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
            self.commit_filter(next);
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
                None => self.filter.clone(),
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
        let Some(checkpoint) = self.steps.get(base).and_then(|s| s.snapshot.as_deref()) else {
            return Err(lost);
        };
        let mut filter = match self.scratch.take() {
            Some(mut buffer) => {
                buffer.as_mut().clone_from(checkpoint);
                buffer
            }
            None => Box::new(checkpoint.clone()),
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
            let got = match run_interval(
                &mut *filter,
                prev.time,
                step.time,
                input,
                &self.queue,
                range,
            ) {
                Ok(got) => got,
                Err(e) => {
                    self.scratch = Some(filter);
                    return Err(e);
                }
            };
            outcomes.extend(got.into_iter().enumerate().map(|(k, o)| (start + k, o)));
            if step.snapshot.is_some() {
                snapshots.push((i, (*filter).clone()));
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
        self.commit_filter(filter);
        Ok(reports)
    }

    /// A copy of the filter in the scratch buffer (allocated only once).
    fn copy_of_filter(&mut self) -> Box<F> {
        match self.scratch.take() {
            Some(mut buffer) => {
                buffer.as_mut().clone_from(&self.filter);
                buffer
            }
            None => self.filter.clone(),
        }
    }

    /// Makes `next` the filter; the previous one becomes the scratch buffer.
    fn commit_filter(&mut self, next: Box<F>) {
        let previous = core::mem::replace(&mut self.filter, next);
        self.scratch = Some(previous);
    }

    /// Indices of queued measurements with time in `(t0, t1]`.
    fn interval(&self, t0: f64, t1: f64) -> std::ops::Range<usize> {
        // Most IMU steps have nothing queued after their start: no search.
        if self.queue.last().is_none_or(|q| q.time <= t0) {
            return self.queue.len()..self.queue.len();
        }
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
        if self.queue.first().is_none_or(|q| q.time > base) {
            return;
        }
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
