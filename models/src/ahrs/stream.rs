//! The `ahrs` filter driven by a log's rows as they come: IMU samples
//! propagate the error-state filter through the multi-rate scheduler, the
//! gravity window is formed from the same samples and pushed as a
//! measurement at its end time, and each magnetometer row is a measurement
//! at its own time (a late one is applied after re-propagation, with the
//! heading formed from the nominal attitude of its time).
//!
//! An IMU interval that is not increasing or longer than
//! [`MAX_IMU_STEP_S`] is a gap: it is not propagated; the filter starts
//! again at the sample after it, with the gravity window, and the
//! magnetometer rows inside the gap are applied to the estimate before it
//! (the attitude the filter has there), as are those after the last
//! sample. Until the IMU has covered a magnetometer row's time the row
//! waits here, not in the scheduler, so that a gap can still take it.

use nav_runtime::innovations::InnovationTotals;
use nav_runtime::log::MagRow;
use std::cell::RefCell;
use std::rc::Rc;

use nav_runtime::scheduler::{
    FnMeasurement, Measurement, MeasurementOutcome, Report, Scheduler, SchedulerError, SensorId,
    SensorStats,
};
use nav_runtime::smoother::{EpochFile, Observability, SmootherError};

use super::gravity_window::{GravityWindow, GRAVITY_PERIOD_S};
use super::heading::magnetic_heading;
use super::measurement::{gravity_measurement, heading_measurement};
use super::nominal::AhrsFilter;
use super::settings::AhrsSettings;
use crate::harness::{RunError, SensorHealth};
use nav_ins::ImuSample;

/// A mean specific force further than this from gravity is an acceleration:
/// the gravity measurement is skipped, m/s^2.
pub const GRAVITY_TOLERANCE: f64 = 0.5;
/// An IMU interval longer than this is not propagated (a gap), s.
pub const MAX_IMU_STEP_S: f64 = 0.5;
/// How late a magnetometer row may come and still be applied at its own
/// time (the scheduler keeps this much history), s.
pub const MAG_LATENCY_S: f64 = 0.2;
/// Nominal magnetometer rate given to the scheduler (it only decides when
/// the sensor is called stale), Hz.
const MAG_RATE_HZ: f64 = 10.0;

/// What one IMU sample did.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ImuStep {
    /// The first sample: the filter starts at its time.
    Start,
    /// A gap before it: the filter starts again at its time.
    Gap,
    /// The interval before it was propagated; `window_closed`: a gravity
    /// window ended at it (its measurement, unless skipped, applied).
    Propagated {
        /// A gravity window ended at this sample.
        window_closed: bool,
    },
}

/// The counts of a run so far.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct AhrsCounts {
    /// Gravity windows closed and what became of them.
    pub gravity: SensorHealth,
    /// Magnetometer rows and what became of them.
    pub mag: SensorHealth,
    /// IMU intervals not propagated.
    pub imu_gaps: u64,
    /// IMU intervals propagated.
    pub samples: usize,
}

/// The innovations of a run's updates, applied or gated (each counted
/// once, when first applied: a re-propagation's repeat is not), for the
/// per-sensor NIS and noise tuning (`docs/tuning.md`).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct AhrsInnovations {
    /// The magnetometer's heading updates.
    pub mag: InnovationTotals,
    /// The gravity windows' updates.
    pub gravity: InnovationTotals,
}

/// The `ahrs` filter fed row by row (see the module docs).
pub struct AhrsStream {
    settings: AhrsSettings,
    scheduler: Scheduler<AhrsFilter>,
    mag_id: SensorId,
    gravity_id: SensorId,
    /// With smoothing: the sensor whose markers make each gravity window's
    /// end an epoch of the recording.
    epoch_id: Option<SensorId>,
    window: GravityWindow,
    /// Time of the last IMU sample (the scheduler's time), once there is one.
    last_imu: Option<f64>,
    /// Magnetometer rows after the last IMU sample, in arrival order.
    waiting: Vec<MagRow>,
    /// Outcomes of schedulers replaced at a gap, and of rows applied to the
    /// estimate directly.
    settled: AhrsCounts,
    /// Rows and skips, counted here.
    counts: AhrsCounts,
    /// The updates' innovations.
    innovations: AhrsInnovations,
}

impl AhrsStream {
    /// The filter of `settings`, waiting for its first IMU sample.
    ///
    /// # Errors
    /// A filter set-up error.
    pub fn new(settings: AhrsSettings) -> Result<Self, RunError> {
        let filter = settings.filter()?;
        Self::with_filter(settings, filter)
    }

    /// As [`AhrsStream::new`], with the run recorded (and each sensor's
    /// information kept) for [`AhrsStream::observability`].
    ///
    /// # Errors
    /// A filter set-up error, or an epoch file that cannot be made.
    pub fn observed(settings: AhrsSettings) -> Result<Self, RunError> {
        Self::recorded(settings, true, false)
    }

    /// As [`AhrsStream::new`], with the run recorded: with `observability`
    /// each sensor's information is kept too ([`AhrsStream::observability`]);
    /// with `smoothing` the end of every gravity window (each row of the
    /// estimates table) is an epoch of the recording, whether or not its
    /// measurement is applied, for [`AhrsStream::recording`].
    ///
    /// # Errors
    /// A filter set-up error, or an epoch file that cannot be made.
    pub fn recorded(
        settings: AhrsSettings,
        observability: bool,
        smoothing: bool,
    ) -> Result<Self, RunError> {
        let setup = |e: String| RunError::Invalid(format!("ahrs: {e}"));
        let mut filter = settings.filter()?;
        let file = EpochFile::create(None).map_err(|e| setup(e.to_string()))?;
        filter
            .start_recording(file, 0.0)
            .map_err(|e| setup(e.to_string()))?;
        if observability {
            filter.track_sensor_information();
        }
        let mut stream = Self::with_filter(settings, filter)?;
        if smoothing {
            stream.epoch_id = Some(stream.add_epoch_sensor()?);
        }
        Ok(stream)
    }

    /// The recording of the run, ended (every epoch written), for the
    /// smoother; `None` unless the stream was made by
    /// [`AhrsStream::recorded`]. Call after [`AhrsStream::finish`].
    ///
    /// # Errors
    /// A recording that failed.
    #[allow(clippy::type_complexity)]
    pub fn recording(&self) -> Result<Option<Rc<RefCell<EpochFile<6, 0>>>>, RunError> {
        let mut filter = self.filter().clone();
        filter
            .finish_recording()
            .map_err(|e| RunError::Invalid(format!("ahrs: recording: {e}")))
    }

    fn add_epoch_sensor(&mut self) -> Result<SensorId, RunError> {
        // Registered last: at the end of a window it follows the gravity
        // measurement of the same time.
        self.scheduler
            .add_sensor("epoch", 1.0 / GRAVITY_PERIOD_S, 0.0)
            .map_err(|e| RunError::Invalid(format!("ahrs: {e}")))
    }

    /// What the recorded run taught each state and the `directions`
    /// weakest combinations (docs/observability.md); `None` unless the
    /// stream was made by [`AhrsStream::observed`]. Call after
    /// [`AhrsStream::finish`].
    ///
    /// # Errors
    /// A recording that failed, or information that is not finite.
    pub fn observability(&self, directions: usize) -> Result<Option<Observability<6>>, RunError> {
        let fail = |e: SmootherError| RunError::Invalid(format!("ahrs: observability: {e}"));
        let s = &self.settings;
        let (level, heading, bias) = (s.level_sigma, s.heading_sigma, s.gyro_bias_sigma);
        let prior = [level, level, heading, bias, bias, bias];
        let mut filter = self.filter().clone();
        filter
            .finish_observed(&prior, 0.0, directions)
            .map_err(fail)
    }

    fn with_filter(settings: AhrsSettings, filter: AhrsFilter) -> Result<Self, RunError> {
        let (scheduler, mag_id, gravity_id) = scheduler_at(filter, 0.0)?;
        Ok(AhrsStream {
            settings,
            scheduler,
            mag_id,
            gravity_id,
            epoch_id: None,
            window: GravityWindow::starting_at(0.0),
            last_imu: None,
            waiting: Vec::new(),
            settled: AhrsCounts::default(),
            counts: AhrsCounts::default(),
            innovations: AhrsInnovations::default(),
        })
    }

    /// The filter at the last IMU sample.
    pub fn filter(&self) -> &AhrsFilter {
        self.scheduler.filter()
    }

    /// The settings.
    pub fn settings(&self) -> &AhrsSettings {
        &self.settings
    }

    /// Time of the last IMU sample.
    pub fn now(&self) -> Option<f64> {
        self.last_imu
    }

    /// The IMU sample `imu` ending its interval at `t`.
    ///
    /// # Errors
    /// A sample the scheduler refuses (not finite) or a propagation error.
    pub fn push_imu(&mut self, t: f64, imu: ImuSample) -> Result<ImuStep, RunError> {
        let Some(previous) = self.last_imu.replace(t) else {
            self.start_at(t, None)?;
            return Ok(ImuStep::Start);
        };
        let dt = t - previous;
        if !(dt > 0.0 && dt <= MAX_IMU_STEP_S) {
            self.counts.imu_gaps += 1;
            self.start_at(t, Some(previous))?;
            return Ok(ImuStep::Gap);
        }
        let closed = self.window.add(t, imu.accel);
        if let Some(mean) = closed {
            self.counts.gravity.rows += 1;
            if (mean.force.norm() - self.settings.gravity).abs() > GRAVITY_TOLERANCE {
                self.counts.gravity.skipped += 1;
            } else {
                let m = gravity_measurement(
                    mean.force,
                    mean.samples,
                    self.settings.gravity,
                    self.settings.accel_sigma,
                );
                // After the last sample: queued, applied at `t` by `push_imu`.
                // A refusal is counted in the scheduler's statistics.
                if let Ok(reports) = self.scheduler.push_measurement(self.gravity_id, t, m) {
                    self.note(&reports);
                }
            }
            if let Some(id) = self.epoch_id {
                let marker = FnMeasurement::new(&[], move |f: &mut AhrsFilter| {
                    f.mark_epoch(t);
                    Ok(MeasurementOutcome::marker())
                });
                // Refused only for a time the IMU sample itself would refuse.
                let _ = self.scheduler.push_measurement(id, t, Box::new(marker));
            }
        }
        self.hand_over_waiting(t);
        let reports = self.scheduler.push_imu(t, imu).map_err(|e| match e {
            // The filter's own state stopped being finite: a divergence
            // (the replay adds the line and weighs the inputs).
            SchedulerError::Propagation(_) => RunError::Diverged {
                message: format!("ahrs: the estimate stopped being finite at t = {t} s: {e}"),
                file: Some("imu.csv".into()),
                line: None,
            },
            e => RunError::Invalid(format!("ahrs: imu.csv t = {t}: {e}")),
        })?;
        self.note(&reports);
        self.counts.samples += 1;
        Ok(ImuStep::Propagated {
            window_closed: closed.is_some(),
        })
    }

    /// A magnetometer row, on time or late.
    ///
    /// # Errors
    /// A filter set-up error when the filter starts again after a gap.
    pub fn push_mag(&mut self, row: MagRow) -> Result<(), RunError> {
        self.counts.mag.rows += 1;
        let Some(now) = self.last_imu else {
            self.counts.mag.skipped += 1;
            return Ok(());
        };
        let field = [row.mx, row.my, row.mz];
        let [roll, pitch, _] = self.filter().nominal().euler();
        if magnetic_heading(field, roll, pitch, 0.0).is_none() {
            self.counts.mag.skipped += 1;
            return Ok(());
        }
        if row.t <= now {
            // Late: applied at its time by re-propagation (or refused as
            // too old, counted by the scheduler).
            if let Ok(reports) = self.scheduler.push_measurement(
                self.mag_id,
                row.t,
                heading_of(&self.settings, &row),
            ) {
                self.note(&reports);
            }
            return Ok(());
        }
        self.waiting.push(row);
        if row.t > now + MAX_IMU_STEP_S {
            // The interval that will hold it is longer than a step: a gap.
            self.apply_waiting_at(now)?;
        }
        Ok(())
    }

    /// Ends the run: rows after the last IMU sample are applied to the
    /// estimate there. Returns the counts.
    ///
    /// # Errors
    /// A filter set-up error.
    pub fn finish(&mut self) -> Result<AhrsCounts, RunError> {
        if let Some(now) = self.last_imu {
            self.apply_waiting_at(now)?;
        }
        Ok(self.counts())
    }

    /// The counts so far (rows waiting for the IMU not yet counted as
    /// applied or refused).
    pub fn counts(&self) -> AhrsCounts {
        let mut c = self.counts;
        c.mag += self.settled.mag;
        c.gravity += self.settled.gravity;
        add_outcomes(&mut c.mag, self.scheduler.sensor_stats(self.mag_id));
        add_outcomes(&mut c.gravity, self.scheduler.sensor_stats(self.gravity_id));
        c
    }

    /// The innovations of the updates so far.
    pub fn innovations(&self) -> AhrsInnovations {
        self.innovations
    }

    /// Adds the innovations of the updates the scheduler reports (each
    /// once: a re-propagation's repeat is not counted again).
    fn note(&mut self, reports: &[Report]) {
        for r in reports.iter().filter(|r| !r.replay) {
            let Ok(o) = &r.outcome else { continue };
            if r.sensor == self.mag_id {
                self.innovations.mag.add(&o.statistics);
            } else if r.sensor == self.gravity_id {
                self.innovations.gravity.add(&o.statistics);
            }
        }
    }

    /// Pushes the waiting rows up to `t` to the scheduler (queued, applied
    /// inside the coming interval at their own times).
    fn hand_over_waiting(&mut self, t: f64) {
        if self.waiting.is_empty() {
            return;
        }
        let mut waiting = std::mem::take(&mut self.waiting);
        let mut reports = Vec::new();
        waiting.retain(|row| {
            if row.t > t {
                return true;
            }
            let m = heading_of(&self.settings, row);
            // A refusal is counted in the scheduler's statistics.
            if let Ok(r) = self.scheduler.push_measurement(self.mag_id, row.t, m) {
                reports.extend(r);
            }
            false
        });
        self.note(&reports);
        self.waiting = waiting;
    }

    /// The filter starts at `t` (the first sample, or the one after a gap
    /// that began at `gap_start`); the rows waiting are applied first to the
    /// estimate before the gap.
    fn start_at(&mut self, t: f64, gap_start: Option<f64>) -> Result<(), RunError> {
        if let Some(before) = gap_start {
            self.apply_waiting_at(before)?;
        }
        self.restart(self.filter().clone(), t)?;
        self.window = GravityWindow::starting_at(t);
        Ok(())
    }

    /// Applies the waiting rows, in time order, to the estimate at the last
    /// IMU sample (`now`), without propagation: the IMU will not cover them.
    fn apply_waiting_at(&mut self, now: f64) -> Result<(), RunError> {
        if self.waiting.is_empty() {
            return Ok(());
        }
        self.waiting.sort_by(|a, b| a.t.total_cmp(&b.t));
        let mut filter = self.filter().clone();
        let waiting = std::mem::take(&mut self.waiting);
        for row in &waiting {
            let m = heading_of(&self.settings, row);
            let outcome = m.check().and_then(|()| m.apply(&mut filter));
            if let Ok(o) = &outcome {
                self.innovations.mag.add(&o.statistics);
            }
            count_outcome(&mut self.settled.mag, outcome);
        }
        self.waiting = waiting;
        self.waiting.clear();
        self.restart(filter, now)
    }

    /// A new scheduler with `filter` at `t`; the old one's counts are kept.
    fn restart(&mut self, filter: AhrsFilter, t: f64) -> Result<(), RunError> {
        let (scheduler, mag_id, gravity_id) = scheduler_at(filter, t)?;
        let old = std::mem::replace(&mut self.scheduler, scheduler);
        add_outcomes(&mut self.settled.mag, old.sensor_stats(self.mag_id));
        add_outcomes(&mut self.settled.gravity, old.sensor_stats(self.gravity_id));
        self.mag_id = mag_id;
        self.gravity_id = gravity_id;
        if self.epoch_id.is_some() {
            self.epoch_id = Some(self.add_epoch_sensor()?);
        }
        Ok(())
    }
}

/// The heading measurement of magnetometer row `row`.
fn heading_of(settings: &AhrsSettings, row: &MagRow) -> Box<dyn Measurement<AhrsFilter>> {
    heading_measurement(
        [row.mx, row.my, row.mz],
        settings.mag_sigma,
        settings.declination,
    )
}

/// A scheduler with `filter` at `t` and the two sensors (the magnetometer
/// first: at equal times it is applied before the gravity window).
fn scheduler_at(
    filter: AhrsFilter,
    t: f64,
) -> Result<(Scheduler<AhrsFilter>, SensorId, SensorId), RunError> {
    let setup = |e: nav_runtime::scheduler::SchedulerError| RunError::Invalid(format!("ahrs: {e}"));
    let mut scheduler = Scheduler::new(filter, t).map_err(setup)?;
    let mag = scheduler
        .add_sensor("mag", MAG_RATE_HZ, MAG_LATENCY_S)
        .map_err(setup)?;
    let gravity = scheduler
        .add_sensor("gravity", 1.0 / GRAVITY_PERIOD_S, 0.0)
        .map_err(setup)?;
    Ok((scheduler, mag, gravity))
}

/// Adds a scheduler's final outcomes; a measurement still waiting in it is
/// counted as refused (it was never applied).
fn add_outcomes(into: &mut SensorHealth, stats: Option<SensorStats>) {
    let s = stats.unwrap_or_default();
    into.accepted += s.accepted;
    into.gated += s.gated;
    into.rejected += s.failed + s.pending + s.too_old + s.duplicate + s.invalid + s.queue_full;
    into.stuck += s.stuck;
}

fn count_outcome(
    h: &mut SensorHealth,
    outcome: Result<MeasurementOutcome, nav_runtime::ekf::FilterError>,
) {
    match outcome {
        Ok(o) if o.accepted => h.accepted += 1,
        Ok(_) => h.gated += 1,
        Err(_) => h.rejected += 1,
    }
}

#[cfg(test)]
#[path = "stream_tests.rs"]
mod tests;
