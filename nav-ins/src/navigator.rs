//! The navigator: an INS vehicle's error-state filter behind a small typed
//! surface. Build it from the vehicle, the initial state and one
//! [`SensorSettings`] per sensor; push IMU samples and sensor readings with
//! their times (late readings are applied at their own time); read the
//! estimate, the estimates requested at given times, and each sensor's report.
//! The scheduler, measurements and filter it drives stay available in
//! `nav_runtime` for programs that need them directly.

use std::cell::RefCell;
use std::collections::VecDeque;
use std::rc::Rc;

use nav_runtime::earth::{meridian_radius, transverse_radius, Geodetic, LocalNed};
use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::ErrorStateFilter;
use nav_runtime::gate::Gate;
use nav_runtime::model::Record;
use nav_runtime::nalgebra::{SMatrix, SVector};
use nav_runtime::scheduler::{
    FnMeasurement, MeasurementOutcome, Report, Scheduler, SchedulerError, SensorId,
};
use nav_runtime::smoother::EpochFile;
use nav_runtime::strapdown::{NavState, RateSamples, Strapdown};
use nav_runtime::stuck::StuckDetector;

use super::declared::{extra_noise, slot_file, DeclaredSensor};
use super::measurement::CompassForm;
use super::nominal::{Estimate, ImuSample, InsFilter, InsNominal};
use super::sensor::{Context, Handle, Reading};
use super::settings::{ImuSettings, InitialState, NavigatorOptions, SensorSettings};
use super::vehicle::{InsVehicle, Layout, Present, Slot};
use crate::health::SensorHealth;
use crate::recovery::Recovery;
use nav_runtime::innovations::InnovationTotals;

/// Smallest prior sigma of any state (in the state's units): a zero variance
/// would be "repaired" by the filter after every step. A state whose prior
/// is the floor is switched off (a bias of sigma zero).
pub const SIGMA_FLOOR: f64 = 1e-9;

/// Number of log sensors a navigator can have.
pub const SENSORS: usize = 7;

/// Sensor names in registration order (also the order of readings at equal times).
pub const SENSOR_NAMES: [&str; SENSORS] =
    ["depth", "dvl", "heading", "usbl", "gnss", "baro", "mag"];

/// Why a navigator could not be built or could not go on.
#[derive(Debug, thiserror::Error, Clone, PartialEq)]
#[non_exhaustive]
pub enum NavigatorError {
    /// The vehicle, the settings or the options do not make a filter.
    #[error("{0}")]
    Setup(String),
    /// An IMU sample was refused.
    #[error("{0}")]
    Imu(SchedulerError),
    /// The estimate left its physical bounds (see [`super::Bounds`]).
    #[error("estimate out of physical bounds at t = {t} s: {what}")]
    OutOfBounds {
        /// Time of the estimate (s).
        t: f64,
        /// Which bound, with the value.
        what: String,
    },
}

/// A ticket for an estimate requested with [`Navigator::request_estimate`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Ticket(pub u64);

/// Requested estimates not yet final, oldest first; `base` is the ticket of
/// the front.
#[derive(Debug, Default)]
struct Requests {
    base: u64,
    entries: VecDeque<(f64, Option<Estimate>)>,
}

/// An INS vehicle `V` (`N` error states) navigating from pushed samples.
pub struct Navigator<V: InsVehicle<N>, const N: usize> {
    scheduler: Scheduler<InsFilter<V, N>>,
    ids: [SensorId; SENSORS],
    record: SensorId,
    contexts: [Context; SENSORS],
    start: f64,
    /// IMU period (s): readings up to one period before the start are
    /// applied at the start.
    period_s: f64,
    options: NavigatorOptions,
    requests: Rc<RefCell<Requests>>,
    skipped: [u64; SENSORS],
    last_nis: [Option<f64>; SENSORS],
    innovations: [InnovationTotals; SENSORS],
    declared: Vec<DeclaredFeed<V, N>>,
    /// Recoveries so far, in the order they happened.
    recoveries: Vec<Recovery>,
    /// The sensor of the markers that take the filter back to the start of
    /// a run that proved it wrong (`None`: no rollback).
    rollback: Option<SensorId>,
    /// Each rollback made: the log sensor, the time of the first refusal
    /// it went back to and the time of the recovery that called it (s).
    rollbacks: Vec<(usize, f64, f64)>,
    /// How far back a rollback may go (s), and whether the history is kept
    /// for it now: while a log sensor that has given readings has had none
    /// accepted (only then can one be called).
    rollback_s: f64,
    rollback_armed: bool,
    /// Per log sensor: whether it has given a reading.
    given: [bool; SENSORS],
}

/// A declared sensor fed by name ([`Builder::declared_sensor`]).
struct DeclaredFeed<V: InsVehicle<N>, const N: usize> {
    sensor: DeclaredSensor<V, N>,
    /// Noise variance per output.
    r_diag: Vec<f64>,
    id: SensorId,
    skipped: u64,
    last_nis: Option<f64>,
    innovations: InnovationTotals,
}

/// The handle of a sensor fed by its declared name
/// ([`Builder::declared_sensor`], [`Navigator::push_declared`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct DeclaredHandle(usize);

/// How long after the start a reading of the start's IMU period is applied
/// (s): the scheduler applies readings after the time they carry, and the
/// start itself is the initial estimate.
pub const AT_START_S: f64 = 1e-9;

/// Builds a [`Navigator`] (see [`Navigator::builder`]).
pub struct Builder<V: InsVehicle<N>, const N: usize> {
    initial: InitialState,
    imu: ImuSettings,
    sensors: [Option<SensorSettings>; SENSORS],
    transducer: Option<Geodetic>,
    declination: f64,
    options: NavigatorOptions,
    samples: RateSamples,
    layout: Result<Layout, String>,
    present: Present,
    /// Declared sensors fed by name, with their noise sigma per output.
    declared: Vec<(DeclaredSensor<V, N>, Vec<f64>)>,
    /// Initial sigma of states the nominal does not keep, by state index.
    state_sigma: Vec<(usize, f64)>,
    /// Values of declared process noise beyond the core's, by noise index.
    process_noise: Vec<(usize, f64)>,
    vehicle: std::marker::PhantomData<fn() -> V>,
}

impl<V: InsVehicle<N>, const N: usize> Navigator<V, N> {
    /// Starts building a navigator of `V` from its initial state and IMU.
    pub fn builder(initial: InitialState, imu: ImuSettings) -> Builder<V, N> {
        Builder {
            initial,
            imu,
            sensors: [None; SENSORS],
            transducer: None,
            declination: 0.0,
            options: NavigatorOptions::default(),
            samples: RateSamples::default(),
            layout: Layout::of::<V, N>().map_err(|e| e.to_string()),
            present: Present::of::<V, N>(),
            declared: Vec::new(),
            state_sigma: Vec::new(),
            process_noise: Vec::new(),
            vehicle: std::marker::PhantomData,
        }
    }

    /// Propagates to the IMU sample at `t` (s): body rate (rad/s) and
    /// specific force (m/s^2). Readings waiting for `t` are applied.
    ///
    /// # Errors
    /// [`NavigatorError::Imu`] if the sample is refused (time not after the
    /// previous one, non-finite value, propagation failure);
    /// [`NavigatorError::OutOfBounds`] if the estimate leaves its bounds.
    pub fn push_imu(&mut self, t: f64, sample: ImuSample) -> Result<(), NavigatorError> {
        let reports = self
            .scheduler
            .push_imu(t, sample)
            .map_err(NavigatorError::Imu)?;
        self.note(&reports);
        if self.rollback_armed {
            self.keep_rollback_history();
        }
        self.check_bounds()
    }

    /// Pushes a reading of the sensor of `handle` measured at `t` (s). A
    /// reading within one IMU period before the start (or at it) is applied
    /// at the start (`AT_START_S` after it: the initial estimate is of the
    /// start, before any reading); an earlier one is counted as skipped; one
    /// older than the sensor's latency, a duplicate, a frozen value or a
    /// non-finite value is refused and counted in its report.
    pub fn push<R: Reading>(&mut self, _handle: Handle<R>, t: f64, reading: R) {
        let t = if t <= self.start {
            // A NaN time is counted as skipped too.
            if t.is_nan() || t < self.start - self.period_s {
                self.skipped[R::SLOT] += 1;
                return;
            }
            self.start + AT_START_S
        } else {
            t
        };
        if !self.given[R::SLOT] {
            self.given[R::SLOT] = true;
            self.keep_rollback_history();
        }
        let m = reading.measurement::<V, N>(&self.contexts[R::SLOT]);
        if let Ok(reports) = self.scheduler.push_measurement(self.ids[R::SLOT], t, m) {
            self.note(&reports);
        }
    }

    /// Keeps the history a rollback needs ([`LockoutOptions::rollback_s`])
    /// while one can be called, that is while a log sensor that has given
    /// readings has had none accepted, and none after: the history costs
    /// every step (docs/lockout.md, "Rollback").
    ///
    /// [`LockoutOptions::rollback_s`]: crate::lockout::LockoutOptions::rollback_s
    fn keep_rollback_history(&mut self) {
        let Some(id) = self.rollback else {
            return;
        };
        let needed = (0..SENSORS).any(|i| {
            self.given[i]
                && self
                    .scheduler
                    .sensor_stats(self.ids[i])
                    .is_some_and(|s| s.accepted == 0)
        });
        if needed != self.rollback_armed {
            let latency = if needed { self.rollback_s } else { 0.0 };
            if self.scheduler.set_latency(id, latency).is_ok() {
                self.rollback_armed = needed;
            }
        }
    }

    /// Pushes a reading of the declared sensor of `handle` measured at `t`
    /// (s): `z` one value per output, in the units of the sensor's `h`
    /// (which predicts the reading); `aux` its auxiliary inputs in declared
    /// order. Times are treated as in [`Navigator::push`]; a reading with a
    /// non-finite value or of the wrong length is refused and counted.
    pub fn push_declared(&mut self, handle: DeclaredHandle, t: f64, z: &[f64], aux: &[f64]) {
        let Some(feed) = self.declared.get_mut(handle.0) else {
            return;
        };
        let t = if t <= self.start {
            if t.is_nan() || t < self.start - self.period_s {
                feed.skipped += 1;
                return;
            }
            self.start + AT_START_S
        } else {
            t
        };
        let sensor = feed.sensor;
        let r_diag = feed.r_diag.clone();
        let mut values = z.to_vec();
        if z.len() != sensor.outputs || aux.len() != sensor.aux.len() {
            // Refused by the finiteness check as a non-finite reading.
            values.push(f64::NAN);
        }
        values.extend_from_slice(aux);
        let z_len = z.len();
        let checked = values.clone();
        let m = FnMeasurement::new(&checked, move |f: &mut InsFilter<V, N>| {
            let (z, aux) = values.split_at(z_len);
            sensor.update(f, z, &r_diag, aux)
        });
        if let Ok(reports) = self.scheduler.push_measurement(feed.id, t, Box::new(m)) {
            self.note(&reports);
        }
    }

    /// The report of the declared sensor of `handle`.
    pub fn report_declared(&self, handle: DeclaredHandle) -> SensorReport {
        let Some(feed) = self.declared.get(handle.0) else {
            return SensorReport::default();
        };
        let s = self.scheduler.sensor_stats(feed.id).unwrap_or_default();
        SensorReport {
            health: SensorHealth {
                rows: 0,
                accepted: s.accepted,
                gated: s.gated,
                rejected: s.failed + s.too_old + s.duplicate + s.invalid + s.queue_full,
                skipped: feed.skipped,
                stuck: s.stuck,
            },
            last_nis: feed.last_nis,
            innovations: feed.innovations,
        }
    }

    /// Asks for the estimate at `t` (s), after the readings of `t` (including
    /// late ones that arrive while `t` is in the history). At or before the
    /// current time, the current estimate is taken. Collect it with
    /// [`Navigator::final_estimates`] or [`Navigator::flush_estimates`].
    /// When the run is recorded, `t` is an epoch of the recording, so the
    /// smoother gives the estimate a smoothed counterpart.
    pub fn request_estimate(&mut self, t: f64) -> Ticket {
        self.request(t, true)
    }

    /// As [`Navigator::request_estimate`], without making `t` an epoch of
    /// the recording: for estimates wanted at a high rate (every IMU
    /// sample, say) of which the smoother is to smooth none, since each
    /// epoch costs the recording a few covariance matrices.
    pub fn request_estimate_unrecorded(&mut self, t: f64) -> Ticket {
        self.request(t, false)
    }

    fn request(&mut self, t: f64, epoch: bool) -> Ticket {
        let ticket = {
            let mut r = self.requests.borrow_mut();
            let ticket = r.base + r.entries.len() as u64;
            r.entries.push_back((t, None));
            ticket
        };
        if t <= self.scheduler.now() {
            let e = Estimate::of(self.scheduler.now(), self.scheduler.filter());
            if let Some(slot) = self.requests.borrow_mut().entries.back_mut() {
                slot.1 = Some(e);
            }
            return Ticket(ticket);
        }
        let requests = Rc::clone(&self.requests);
        let m = FnMeasurement::new(&[], move |f: &mut InsFilter<V, N>| {
            let e = Estimate::of(t, f);
            if epoch {
                f.mark_epoch(t);
            }
            let mut r = requests.borrow_mut();
            if let Some(i) = ticket.checked_sub(r.base) {
                if let Some(slot) = r.entries.get_mut(i as usize) {
                    slot.1 = Some(e);
                }
            }
            Ok(MeasurementOutcome::marker())
        });
        // A request is refused only for a non-finite time: it stays empty.
        let _ = self.scheduler.push_measurement(self.record, t, Box::new(m));
        Ticket(ticket)
    }

    /// Hands the requested estimates that no later reading can change any
    /// more (older than the history), oldest first, to `out` (`None`: the
    /// filter never reached that time).
    pub fn final_estimates(&mut self, mut out: impl FnMut(Ticket, Option<Estimate>)) {
        let oldest = self.scheduler.oldest();
        let mut r = self.requests.borrow_mut();
        while r.entries.front().is_some_and(|(t, _)| *t < oldest) {
            let (_, e) = r.entries.pop_front().unwrap_or((0.0, None));
            out(Ticket(r.base), e);
            r.base += 1;
        }
    }

    /// Every requested estimate not yet handed out, oldest first; the
    /// navigator can go on (later readings no longer change those).
    pub fn flush_estimates(&mut self, mut out: impl FnMut(Ticket, Option<Estimate>)) {
        let mut r = self.requests.borrow_mut();
        while let Some((_, e)) = r.entries.pop_front() {
            out(Ticket(r.base), e);
            r.base += 1;
        }
    }

    /// The current estimate (all readings pushed so far applied).
    pub fn estimate(&self) -> Estimate {
        Estimate::of(self.scheduler.now(), self.scheduler.filter())
    }

    /// The report of the sensor of `handle`.
    pub fn report<R: Reading>(&self, _handle: Handle<R>) -> SensorReport {
        self.report_of(R::SLOT)
    }

    /// The report of sensor `slot` (index in [`SENSOR_NAMES`]).
    pub fn report_of(&self, slot: usize) -> SensorReport {
        let s = self
            .scheduler
            .sensor_stats(self.ids[slot])
            .unwrap_or_default();
        SensorReport {
            health: SensorHealth {
                rows: 0,
                accepted: s.accepted,
                gated: s.gated,
                rejected: s.failed + s.too_old + s.duplicate + s.invalid + s.queue_full,
                skipped: self.skipped[slot],
                stuck: s.stuck,
            },
            last_nis: self.last_nis[slot],
            innovations: self.innovations[slot],
        }
    }

    /// Rollbacks for late readings so far.
    pub fn replays(&self) -> u64 {
        self.scheduler.stats().replays
    }

    /// The filter (error-state EKF and nominal solution).
    pub fn filter(&self) -> &InsFilter<V, N> {
        self.scheduler.filter()
    }

    /// The scheduler underneath.
    pub fn scheduler(&self) -> &Scheduler<InsFilter<V, N>> {
        &self.scheduler
    }

    /// Time of the initial state (s).
    pub fn start(&self) -> f64 {
        self.start
    }

    /// The recoveries from a lock-out into divergence so far (each log
    /// sensor's; [`nav_runtime::recovery`]), in time order of the readings.
    pub fn recoveries(&self) -> &[Recovery] {
        &self.recoveries
    }

    /// Records the recovery a report says happened; a late reading's
    /// replay that now recovers differently replaces or removes the record
    /// of the same reading.
    fn note_recovery(&mut self, r: &Report) {
        let i = r.sensor.index();
        if self.ids.get(i) != Some(&r.sensor) {
            return;
        }
        let Some(&sensor) = SENSOR_NAMES.get(i) else {
            return;
        };
        let recovered = r.outcome.as_ref().ok().and_then(|o| o.recovered);
        let same = |e: &Recovery| e.sensor == sensor && e.t_s == r.time;
        // A recovery a rollback forced early in the run: found at the
        // reading that completed the run.
        let detected_s = self
            .rollbacks
            .iter()
            .rev()
            .find(|(slot, first, detected)| {
                *slot == i && r.time >= first - ROLLBACK_MATCH_S && r.time < *detected
            })
            .map_or(r.time, |(_, _, detected)| *detected);
        match (recovered, self.recoveries.iter().position(same)) {
            (Some(d), Some(k)) => {
                self.recoveries[k].refused_for_s = d;
                self.recoveries[k].detected_s = detected_s;
            }
            (Some(d), None) => {
                let at = self.recoveries.partition_point(|e| e.t_s <= r.time);
                self.recoveries.insert(
                    at,
                    Recovery {
                        sensor,
                        t_s: r.time,
                        refused_for_s: d,
                        detected_s,
                    },
                );
            }
            (None, Some(k)) if r.replay => {
                self.recoveries.remove(k);
            }
            (None, _) => {}
        }
    }

    fn note(&mut self, reports: &[Report]) {
        // Recoveries found now (not in a replay) of a log sensor: each takes
        // the filter back to the first refusal of its run.
        let mut found: Vec<(usize, f64, f64)> = Vec::new();
        for r in reports {
            self.note_recovery(r);
            let i = r.sensor.index();
            if let (false, true, Some(d)) = (
                r.replay,
                self.ids.get(i) == Some(&r.sensor),
                r.outcome.as_ref().ok().and_then(|o| o.recovered),
            ) {
                found.push((i, r.time, d));
            }
            if let (Some(slot), Ok(o)) = (self.last_nis.get_mut(i), &r.outcome) {
                *slot = Some(o.nis);
                if !r.replay {
                    if let Some(t) = self.innovations.get_mut(i) {
                        t.add(&o.statistics);
                    }
                }
            }
            if let (Some(feed), Ok(o)) = (
                self.declared.iter_mut().find(|d| d.id == r.sensor),
                &r.outcome,
            ) {
                feed.last_nis = Some(o.nis);
                if !r.replay {
                    feed.innovations.add(&o.statistics);
                }
            }
        }
        for (slot, t, lasted) in found {
            self.roll_back(slot, t, lasted);
        }
    }

    /// Takes the filter back to the first refusal of the run of log sensor
    /// `slot` that a recovery at `t` (s) found `lasted` s long, and makes
    /// the run recover at its second refusal (docs/lockout.md,
    /// "Rollback"): a marker just before the first, through the scheduler,
    /// which replays the readings and samples since. Only for a
    /// sensor none of whose readings has been accepted; nothing without
    /// rollback, or for a run that began before the history.
    fn roll_back(&mut self, slot: usize, t: f64, lasted: f64) {
        let Some(id) = self.rollback else {
            return;
        };
        // Only a run from before the sensor's first accepted reading: the
        // filter then rests on `[initial]` alone, which the run shows wrong.
        // After one, a run is as often a mismatch of the sensor's model (a
        // clock, a mounting, seen in turns), whose readings the rollback
        // would apply.
        if self
            .scheduler
            .sensor_stats(self.ids[slot])
            .map_or(0, |s| s.accepted)
            > 0
        {
            return;
        }
        let first = t - lasted;
        // Just before the first refusal (at the start, after the start).
        let lead = (first.abs() * 4.0 * f64::EPSILON).max(0.5 * AT_START_S);
        let at = first - lead;
        if !(at > self.start && at < t) {
            return;
        }
        let compass = self.options.compass;
        let m = FnMeasurement::new(&[], move |f: &mut InsFilter<V, N>| {
            force_recovery(slot, compass, f, lasted);
            Ok(MeasurementOutcome::marker())
        });
        self.rollbacks.push((slot, first, t));
        match self.scheduler.push_measurement(id, at, Box::new(m)) {
            Ok(reports) => self.note(&reports),
            // Older than the history: the recovery stays where it was found.
            Err(_) => {
                self.rollbacks.pop();
            }
        }
    }

    fn check_bounds(&self) -> Result<(), NavigatorError> {
        let s = &self.scheduler.filter().nominal().ins.state;
        let b = &self.options.bounds;
        let speed2 = s.v_n.norm_squared();
        // One sum carries any NaN or infinity of the solution (a sum of
        // finite values this large overflows only outside the bounds anyway).
        let all = s.lat + s.lon + s.h + speed2 + s.c_bn.sum();
        if all.is_finite()
            && s.lat.abs() <= core::f64::consts::FRAC_PI_2
            && speed2 <= b.max_speed_mps * b.max_speed_mps
            && s.h.abs() <= b.max_height_m
        {
            return Ok(());
        }
        let speed = speed2.sqrt();
        let what = if !all.is_finite() {
            "the navigation solution is not finite".to_string()
        } else if s.lat.abs() > core::f64::consts::FRAC_PI_2 {
            format!("|latitude| {:e} rad exceeds pi/2", s.lat.abs())
        } else if speed > b.max_speed_mps {
            format!("speed {speed:e} m/s exceeds {} m/s", b.max_speed_mps)
        } else {
            format!("|height| {:e} m exceeds {} m", s.h.abs(), b.max_height_m)
        };
        Err(NavigatorError::OutOfBounds {
            t: self.scheduler.now(),
            what,
        })
    }
}

/// What one sensor did so far.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SensorReport {
    /// Counts (`rows` is 0: the navigator does not see files).
    pub health: SensorHealth,
    /// Normalized innovation squared of the latest applied or gated reading.
    pub last_nis: Option<f64>,
    /// The innovations of its readings, applied or gated, each counted when
    /// first applied (not again when a late reading replays it): the mean
    /// NIS and the noise sigma they support (docs/tuning.md).
    pub innovations: InnovationTotals,
}

impl<V: InsVehicle<N>, const N: usize> Builder<V, N> {
    /// Run-wide options (default: [`NavigatorOptions::default`]).
    pub fn options(mut self, options: NavigatorOptions) -> Self {
        self.options = options;
        self
    }

    /// What the IMU samples are (default: instantaneous rates; an IMU
    /// that delivers increments gives interval averages, increments divided
    /// by their interval, which the strapdown integrates as increments with
    /// its coning and sculling terms).
    pub fn rate_samples(mut self, samples: RateSamples) -> Self {
        self.samples = samples;
        self
    }

    /// Position of the USBL transducer (default: at the surface above the
    /// initial position).
    pub fn usbl_transducer(mut self, at: Geodetic) -> Self {
        self.transducer = Some(at);
        self
    }

    /// Magnetic declination (rad, east positive) added to the
    /// magnetometer's heading (default 0).
    pub fn magnetic_declination(mut self, declination: f64) -> Self {
        self.declination = declination;
        self
    }

    /// Adds the vehicle's sensor that gives readings of type `R`.
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] if `V` has no such sensor.
    pub fn sensor<R: Reading>(
        &mut self,
        settings: SensorSettings,
    ) -> Result<Handle<R>, NavigatorError> {
        if !R::present(&self.present, self.options.compass) {
            return Err(NavigatorError::Setup(format!(
                "vehicle {} has no {} sensor",
                V::REPLAY_NAME,
                R::NAME
            )));
        }
        self.sensors[R::SLOT] = Some(settings);
        Ok(Handle::new())
    }

    /// Feeds the vehicle's sensor declared as `name` by name: one that no
    /// reading kind feeds (a block of the user's own), with noise sigma
    /// `sigma` (one for every output, or one per output; in the units of
    /// its `h`). See [`crate::declared`].
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] if `V` declares no such sensor, if a
    /// reading kind feeds it, if it is fed already, or if `sigma` is not one
    /// positive finite value or one per output.
    pub fn declared_sensor(
        &mut self,
        name: &str,
        sigma: &[f64],
    ) -> Result<DeclaredHandle, NavigatorError> {
        let vehicle = V::REPLAY_NAME;
        let setup = |m: String| Err(NavigatorError::Setup(m));
        if let Some(file) = slot_file::<V, N>(name) {
            return setup(format!(
                "sensor `{name}` of vehicle {vehicle} is fed by {file}, not by name"
            ));
        }
        let Some(sensor) = DeclaredSensor::<V, N>::named(name) else {
            let names: Vec<&str> = DeclaredSensor::<V, N>::unslotted()
                .iter()
                .map(|s| s.name)
                .collect();
            let mut m =
                format!(
                "vehicle {vehicle} declares no sensor `{name}` to feed by name (those it has: {})",
                if names.is_empty() { "none".to_string() } else { names.join(", ") }
            );
            if let Some(close) = nav_runtime::suggestion::closest_name(name, &names) {
                m.push_str(&format!("; did you mean `{close}`?"));
            }
            return setup(m);
        };
        if self.declared.iter().any(|(s, _)| s.name == sensor.name) {
            return setup(format!("sensor `{name}` is fed twice"));
        }
        let sigma: Vec<f64> = match sigma.len() {
            1 => vec![sigma[0]; sensor.outputs],
            n if n == sensor.outputs => sigma.to_vec(),
            n => {
                return setup(format!(
                    "sensor `{name}` has {} outputs: {n} sigmas given (one, or one per output)",
                    sensor.outputs
                ))
            }
        };
        if let Some(bad) = sigma
            .iter()
            .find(|s| !(**s > 0.0 && (**s * **s).is_finite()))
        {
            return setup(format!(
                "sensor `{name}`: sigma {bad} is not a noise sigma (finite, > 0)"
            ));
        }
        self.declared.push((sensor, sigma));
        Ok(DeclaredHandle(self.declared.len() - 1))
    }

    /// The initial sigma of the state (a whole declared state, or one
    /// scalar `name[i]`) that the nominal solution does not keep: a state of
    /// a block the navigator does not know, in the state's units.
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] for a name that is no such state, or a
    /// sigma that is not finite and >= 0.
    pub fn state_sigma(&mut self, name: &str, sigma: f64) -> Result<(), NavigatorError> {
        let absorbed = self.absorbed()?;
        let given: Vec<usize> = (0..N).filter(|&i| !absorbed[i]).collect();
        let scalars = given_by_name::<V, N>(&V::STATE_NAMES, &given, name, "state")?;
        if !(sigma >= 0.0 && (sigma * sigma).is_finite()) {
            return Err(NavigatorError::Setup(format!(
                "state `{name}`: sigma {sigma} is not a sigma (finite, >= 0)"
            )));
        }
        set_values(&mut self.state_sigma, &scalars, sigma);
        Ok(())
    }

    /// The value of a declared process noise (a whole noise input, or one
    /// scalar) beyond the INS core's and the barometer's: a density for the
    /// vehicle's continuous model, in the units of its declaration.
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] for a name that is no such noise input, or
    /// a value that is not finite and >= 0.
    pub fn process_noise(&mut self, name: &str, value: f64) -> Result<(), NavigatorError> {
        let names = <V::Noise as Record>::NAMES;
        let scalars = given_by_name::<V, N>(names, &extra_noise::<V, N>(), name, "process noise")?;
        if !(value >= 0.0 && value.is_finite()) {
            return Err(NavigatorError::Setup(format!(
                "process noise `{name}`: {value} is not a noise intensity (finite, >= 0)"
            )));
        }
        set_values(&mut self.process_noise, &scalars, value);
        Ok(())
    }

    /// Per state: kept by the nominal solution.
    fn absorbed(&self) -> Result<[bool; N], NavigatorError> {
        self.layout
            .as_ref()
            .map(|l| l.absorbed())
            .map_err(|e| NavigatorError::Setup(e.clone()))
    }

    /// The navigator, started at the initial state with `first`, the IMU
    /// sample at the initial time (it starts the rate model of the first
    /// interval).
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] if the vehicle does not fit (see
    /// [`Layout::of`]) or a setting is invalid.
    pub fn build(self, first: ImuSample) -> Result<Navigator<V, N>, NavigatorError> {
        let filter = self.initial_filter(&first)?;
        let setup = |e: SchedulerError| NavigatorError::Setup(e.to_string());
        let window = self
            .sensors
            .iter()
            .flatten()
            .fold(0.0_f64, |a, s| a.max(s.latency_s));
        let mut scheduler = Scheduler::new(filter, self.initial.t)
            .map_err(setup)?
            .with_snapshot_every(snapshot_interval(window, self.imu.period_s));
        let mut ids = Vec::with_capacity(SENSORS);
        for (name, s) in SENSOR_NAMES.iter().zip(&self.sensors) {
            let (rate, latency) = s.map_or((2.0, 0.0), |s| (s.rate_hz, s.latency_s));
            ids.push(scheduler.add_sensor(*name, rate, latency).map_err(setup)?);
        }
        if let Some(alpha) = self.options.stuck_false_alarm {
            for (id, s) in ids.iter().zip(&self.sensors) {
                if let Some(s) = s {
                    let d = StuckDetector::for_sensor(s.noise_sigma, s.resolution, alpha);
                    scheduler.set_stuck_detector(*id, d).map_err(setup)?;
                }
            }
        }
        let record = scheduler.add_sensor("record", 10.0, 0.0).map_err(setup)?;
        // Its history is kept only while a rollback can be called
        // ([`Navigator::keep_rollback_history`]).
        let (rollback, rollback_s) = match self.options.lockout_release {
            Some(o) if o.recovery.is_some() && o.rollback_s > 0.0 => {
                if !o.rollback_s.is_finite() {
                    return Err(NavigatorError::Setup(format!(
                        "lock-out rollback_s must be finite, got {}",
                        o.rollback_s
                    )));
                }
                let id = scheduler.add_sensor("rollback", 1.0, 0.0).map_err(setup)?;
                (Some(id), o.rollback_s)
            }
            _ => (None, 0.0),
        };
        let mut declared = Vec::with_capacity(self.declared.len());
        for (sensor, sigma) in &self.declared {
            let id = scheduler.add_sensor(sensor.name, 1.0, 0.0).map_err(setup)?;
            declared.push(DeclaredFeed {
                sensor: *sensor,
                r_diag: sigma.iter().map(|s| s * s).collect(),
                id,
                skipped: 0,
                last_nis: None,
                innovations: InnovationTotals::default(),
            });
        }
        let i = &self.initial;
        let transducer =
            self.transducer
                .unwrap_or(Geodetic::new(i.position.lat, i.position.lon, 0.0));
        let frame = LocalNed::new(transducer);
        let contexts = std::array::from_fn(|k| Context {
            noise_sigma: self.sensors[k].map_or(f64::NAN, |s| s.noise_sigma),
            mounting: self.sensors[k].and_then(|s| s.mounting),
            lever_arm: self.sensors[k]
                .map_or(nav_runtime::nalgebra::Vector3::zeros(), |s| s.lever_arm),
            compass: self.options.compass,
            usbl_frame: frame,
            declination: self.declination,
        });
        Ok(Navigator {
            scheduler,
            ids: std::array::from_fn(|k| ids[k]),
            record,
            contexts,
            start: self.initial.t,
            period_s: self.imu.period_s,
            options: self.options,
            requests: Rc::new(RefCell::new(Requests::default())),
            skipped: [0; SENSORS],
            last_nis: [None; SENSORS],
            innovations: [InnovationTotals::default(); SENSORS],
            recoveries: Vec::new(),
            rollback,
            rollbacks: Vec::new(),
            rollback_s,
            rollback_armed: false,
            given: [false; SENSORS],
            declared,
        })
    }

    /// The initial filter: nominal from the initial state, covariance from its
    /// sigmas, the IMU's bias sigmas and each sensor's bias sigma (equations in
    /// `docs/pipeline.md`, section "Initial covariance").
    pub fn initial_filter(&self, first: &ImuSample) -> Result<InsFilter<V, N>, NavigatorError> {
        let layout = self.layout.clone().map_err(NavigatorError::Setup)?;
        let i = &self.initial;
        let state = NavState::new(i.position, i.velocity, &i.attitude);
        let mut ins = Strapdown::with_time(state, i.t);
        // The form first: the rate history is kept in it.
        ins.samples = self.samples;
        ins.set_previous_rates(&first.gyro, &first.accel);
        let imu = &self.imu;
        let bias = |k: usize| self.sensors[k].map_or(0.0, |s| s.bias_sigma);
        let misalignment = self.sensors[3].map_or(0.0, |s| s.misalignment_sigma);
        let sig = &i.sigma;
        let lat = state.lat;
        let mut sigma = [0.0; N];
        let (p, v, a) = (layout.position, layout.velocity, layout.attitude);
        sigma[p] = sig.position / (meridian_radius(lat) + state.h);
        sigma[p + 1] = sig.position / ((transverse_radius(lat) + state.h) * lat.cos());
        sigma[p + 2] = sig.position;
        sigma[v..v + 3].fill(sig.velocity);
        sigma[a..a + 2].fill(sig.level);
        sigma[a + 2] = sig.heading;
        sigma[layout.accel_bias..layout.accel_bias + 3].fill(imu.accel_bias_sigma);
        sigma[layout.gyro_bias..layout.gyro_bias + 3].fill(imu.gyro_bias_sigma);
        for (at, len, s) in [
            (layout.usbl_bias, 2, bias(3)),
            (layout.depth_bias, 1, bias(0)),
            (layout.dvl_bias, 3, bias(1)),
            (layout.compass_bias, 1, bias(2)),
            (layout.usbl_misalignment, 3, misalignment),
            (layout.baro_bias, 1, bias(5)),
        ] {
            if let Some(i) = at {
                sigma[i..i + len].fill(s);
            }
        }
        let absorbed = layout.absorbed::<N>();
        let missing: Vec<&str> = (0..N)
            .filter(|&i| !absorbed[i] && !self.state_sigma.iter().any(|(k, _)| *k == i))
            .map(|i| V::STATE_NAMES[i])
            .collect();
        if !missing.is_empty() {
            return Err(NavigatorError::Setup(format!(
                "vehicle {}: state {} has no initial sigma (the navigator does not know its block: give it by name, in a log replay `[initial.sigma]` of replay.toml)",
                V::REPLAY_NAME,
                nav_runtime::model::blocks(&missing).join(", ")
            )));
        }
        for (i, s) in &self.state_sigma {
            sigma[*i] = *s;
        }
        let p0 = SMatrix::<f64, N, N>::from_diagonal(&SVector::<f64, N>::from_fn(|i, _| {
            sigma[i].max(SIGMA_FLOOR).powi(2)
        }));
        // Noise densities from per-sample sigmas: q = sigma^2 dt.
        let dt = imu.period_s;
        let (qa, qg) = (
            imu.accel_noise_sigma.powi(2) * dt,
            imu.gyro_noise_sigma.powi(2) * dt,
        );
        // The INS core's noise in record order (checked by `Layout::of`).
        // The barometer block's bias walk after them (checked there too).
        let baro_walk = self.sensors[5].map_or(0.0, |s| s.bias_walk);
        let noise_names = <V::Noise as Record>::NAMES;
        let missing: Vec<&str> = extra_noise::<V, N>()
            .into_iter()
            .filter(|i| !self.process_noise.iter().any(|(k, _)| k == i))
            .map(|i| noise_names[i])
            .collect();
        if !missing.is_empty() {
            return Err(NavigatorError::Setup(format!(
                "vehicle {}: process noise {} has no value (the navigator does not know its block: give it by name, in a log replay `[noise]` of replay.toml)",
                V::REPLAY_NAME,
                nav_runtime::model::blocks(&missing).join(", ")
            )));
        }
        let noise = <V::Noise as Record>::from_fn(|i| match i {
            0..=2 => qa,
            3..=5 => qg,
            _ => self
                .process_noise
                .iter()
                .find(|(k, _)| *k == i)
                .map_or(baro_walk, |(_, q)| *q),
        });
        let name = V::REPLAY_NAME;
        let err = |e| NavigatorError::Setup(format!("{name} filter: {e}"));
        let gate = match self.options.gate_probability {
            Some(p) => Some(Gate::new(p).map_err(err)?),
            None => None,
        };
        let ekf = Ekf::<V, N>::new(SVector::zeros(), p0, V::Params::default(), noise)
            .map_err(err)?
            .with_default_gate(gate);
        let ekf =
            crate::lockout::configure::<V, N>(ekf, self.options.lockout_release).map_err(err)?;
        let t0 = ins.time;
        let mut nominal =
            InsNominal::try_new(ins).map_err(|e| NavigatorError::Setup(e.to_string()))?;
        nominal.baro_bias = self.sensors[5].map_or(0.0, |s| s.initial_bias);
        // Sensors read the nominal as corrected by the earlier readings of
        // the same epoch (docs/runtime.md, "Error-state filters").
        let mut filter =
            ErrorStateFilter::new(ekf, nominal).with_sensor_input(InsNominal::<V, N>::sensor_input);
        if self.options.smooth {
            let file = EpochFile::create(None).map_err(|e| NavigatorError::Setup(e.to_string()))?;
            filter.start_recording(file, t0).map_err(err)?;
            if self.options.sensor_information {
                filter.track_sensor_information();
            }
        }
        Ok(filter)
    }
}

/// The scalars of `names` that `name` stands for (a whole declared block
/// or one scalar), all of them among `given` (those the builder takes by
/// name); else a setup error listing those, with "did you mean".
fn given_by_name<V: InsVehicle<N>, const N: usize>(
    names: &[&str],
    given: &[usize],
    name: &str,
    what: &str,
) -> Result<Vec<usize>, NavigatorError> {
    let scalars = nav_runtime::model::scalars_of(names, name);
    if !scalars.is_empty() && scalars.iter().all(|i| given.contains(i)) {
        return Ok(scalars);
    }
    let given_names: Vec<&str> = given.iter().map(|&i| names[i]).collect();
    let blocks = nav_runtime::model::blocks(&given_names);
    let listed = if blocks.is_empty() {
        "none".to_string()
    } else {
        blocks.join(", ")
    };
    Err(NavigatorError::Setup(format!(
        "vehicle {} has no {what} `{name}` given by name (those it has: {listed}; the others come from the initial state, the IMU and the sensor settings){}",
        V::REPLAY_NAME,
        nav_runtime::suggestion::did_you_mean(name, &blocks)
    )))
}

/// Sets `value` for `scalars` in `list`, replacing earlier values.
fn set_values(list: &mut Vec<(usize, f64)>, scalars: &[usize], value: f64) {
    list.retain(|(k, _)| !scalars.contains(k));
    list.extend(scalars.iter().map(|&i| (i, value)));
}

/// Largest difference between the time of a run's first refusal as a
/// recovery gives it (its time less the run's duration) and the reading's
/// own time, s: sums of the same steps, in another order.
const ROLLBACK_MATCH_S: f64 = 1e-6;

/// Makes the second refused reading of log sensor `slot` ([`SENSOR_NAMES`])
/// from now recover at once ([`Slot::force_recovery`]).
fn force_recovery<V: InsVehicle<N>, const N: usize>(
    slot: usize,
    compass: CompassForm,
    f: &mut InsFilter<V, N>,
    lasted: f64,
) {
    match slot {
        0 => <V::Depth as Slot<V, N, 1>>::force_recovery(f, lasted),
        1 => <V::Dvl as Slot<V, N, 3>>::force_recovery(f, lasted),
        // The form the compass's readings go to (a chain for the other
        // would take one of the filter's few places).
        2 if compass == CompassForm::SmallAngle => {
            <V::CompassSmallAngle as Slot<V, N, 1>>::force_recovery(f, lasted)
        }
        2 => <V::Compass as Slot<V, N, 1>>::force_recovery(f, lasted),
        3 => <V::Usbl as Slot<V, N, 2>>::force_recovery(f, lasted),
        4 => <V::Gnss as Slot<V, N, 3>>::force_recovery(f, lasted),
        5 => <V::Baro as Slot<V, N, 1>>::force_recovery(f, lasted),
        6 => <V::Mag as Slot<V, N, 1>>::force_recovery(f, lasted),
        _ => {}
    }
}

/// IMU steps between the scheduler's checkpoints for a history of `window`
/// seconds at IMU period `dt` (s). A checkpoint (a copy of the whole filter)
/// every step costs more than the steps themselves save: a late measurement
/// re-propagates from the newest checkpoint before it, so spacing them by a
/// tenth of the window adds at most a tenth of the window to a replay, while
/// copying the filter ten times less often. Without late sensors (`window`
/// 0) a replay can only be for a measurement at the current IMU time, which
/// the replay loop always delivers before that sample: one checkpoint a
/// second. Results do not depend on the spacing (the replay recomputes the
/// same steps); see [`Scheduler::with_snapshot_every`].
fn snapshot_interval(window: f64, dt: f64) -> usize {
    let steps = if window > 0.0 { window / 10.0 } else { 1.0 } / dt;
    if steps.is_finite() {
        (steps.ceil() as usize).clamp(1, 1000)
    } else {
        1
    }
}
