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

use super::nominal::{Estimate, ImuSample, InsFilter, InsNominal};
use super::sensor::{Context, Handle, Reading};
use super::settings::{ImuSettings, InitialState, NavigatorOptions, SensorSettings};
use super::vehicle::{InsVehicle, Layout, Present};
use crate::harness::SensorHealth;

/// Smallest prior sigma of any state (in the state's units): a zero variance
/// would be "repaired" by the filter after every step.
const SIGMA_FLOOR: f64 = 1e-9;

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
}

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
        let m = reading.measurement::<V, N>(&self.contexts[R::SLOT]);
        if let Ok(reports) = self.scheduler.push_measurement(self.ids[R::SLOT], t, m) {
            self.note(&reports);
        }
    }

    /// Asks for the estimate at `t` (s), after the readings of `t` (including
    /// late ones that arrive while `t` is in the history). At or before the
    /// current time, the current estimate is taken. Collect it with
    /// [`Navigator::final_estimates`] or [`Navigator::flush_estimates`].
    pub fn request_estimate(&mut self, t: f64) -> Ticket {
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
            f.mark_epoch(t);
            let mut r = requests.borrow_mut();
            if let Some(i) = ticket.checked_sub(r.base) {
                if let Some(slot) = r.entries.get_mut(i as usize) {
                    slot.1 = Some(e);
                }
            }
            Ok(MeasurementOutcome {
                accepted: true,
                nis: 0.0,
                threshold: None,
                dof: 0,
            })
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

    fn note(&mut self, reports: &[Report]) {
        for r in reports {
            let i = r.sensor.index();
            if let (Some(slot), Ok(o)) = (self.last_nis.get_mut(i), &r.outcome) {
                *slot = Some(o.nis);
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
        let noise = <V::Noise as Record>::from_fn(|i| match i {
            0..=2 => qa,
            3..=5 => qg,
            _ => baro_walk,
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
        let ekf = crate::sdins25::lockout::configure::<V, N>(ekf, self.options.lockout_release)
            .map_err(err)?;
        let t0 = ins.time;
        let mut nominal =
            InsNominal::try_new(ins).map_err(|e| NavigatorError::Setup(e.to_string()))?;
        nominal.baro_bias = self.sensors[5].map_or(0.0, |s| s.initial_bias);
        let mut filter = ErrorStateFilter::new(ekf, nominal);
        if self.options.smooth {
            let file = EpochFile::create(None).map_err(|e| NavigatorError::Setup(e.to_string()))?;
            filter.start_recording(file, t0).map_err(err)?;
        }
        Ok(filter)
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::navigator::prelude::*;
    use crate::sdins25::Sdins25;
    use crate::vehicles::sdins::Sdins20;
    use nav_runtime::earth::normal_gravity;

    fn initial() -> InitialState {
        InitialState {
            t: 0.0,
            position: Geodetic::new(0.7, 2.2, -50.0),
            velocity: Vector3::zeros(),
            attitude: Euler {
                roll: 0.0,
                pitch: 0.0,
                yaw: 0.3,
            },
            sigma: InitialSigma::default(),
        }
    }

    fn imu() -> ImuSettings {
        ImuSettings {
            period_s: 0.01,
            gyro_bias_sigma: 1e-6,
            gyro_noise_sigma: 1e-6,
            accel_bias_sigma: 1e-3,
            accel_noise_sigma: 1e-3,
        }
    }

    fn at_rest() -> ImuSample {
        ImuSample {
            gyro: Vector3::zeros(),
            accel: Vector3::new(0.0, 0.0, -normal_gravity(0.7, -50.0)),
        }
    }

    #[test]
    fn readings_are_applied_and_reported_per_sensor() {
        let mut b = Navigator::<Sdins25, 25>::builder(initial(), imu());
        let depth = b.sensor::<DepthReading>(SensorSettings::new(0.05)).unwrap();
        let heading = b
            .sensor::<HeadingReading>(SensorSettings::new(0.01))
            .unwrap();
        let mut nav = b.build(at_rest()).unwrap();
        // A reading more than one IMU period before the start is skipped;
        // one within it is applied at the start.
        nav.push(depth, -0.02, DepthReading(50.0));
        nav.push(heading, -0.005, HeadingReading(0.3));
        let ticket = nav.request_estimate(5.0);
        for k in 1..=1000 {
            let t = k as f64 * 0.01;
            if k % 50 == 0 {
                // Varying readings (identical ones would be frozen values).
                let wiggle = (k as f64).sin();
                nav.push(depth, t, DepthReading(50.0 + 0.02 * wiggle));
                nav.push(heading, t, HeadingReading(0.3 + 0.005 * wiggle));
            }
            nav.push_imu(t, at_rest()).unwrap();
        }
        let d = nav.report(depth);
        assert_eq!(d.health.accepted, 20);
        assert_eq!(d.health.skipped, 1);
        assert_eq!(nav.report(heading).health.accepted, 21);
        assert_eq!(nav.report(heading).health.skipped, 0);
        assert!(d.last_nis.is_some_and(|x| x.is_finite() && x >= 0.0));
        let e = nav.estimate();
        assert!((e.nav.depth() - 50.0).abs() < 0.2, "{}", e.nav.depth());
        let mut got = Vec::new();
        nav.flush_estimates(|t, e| got.push((t, e)));
        assert_eq!(got.len(), 1);
        assert_eq!(got[0].0, ticket);
        assert!(got[0].1.is_some_and(|e| (e.t - 5.0).abs() < 1e-9));
    }

    #[test]
    fn a_sensor_the_vehicle_lacks_is_a_setup_error() {
        let mut b = Navigator::<Sdins20, 20>::builder(initial(), imu());
        let e = b.sensor::<UsblFix>(SensorSettings::new(1.0)).unwrap_err();
        assert!(e.to_string().contains("sdins20 has no usbl sensor"), "{e}");
    }

    #[test]
    fn an_estimate_out_of_bounds_stops_the_navigator() {
        let cases: [(ImuSample, &str); 3] = [
            (
                ImuSample {
                    accel: Vector3::new(1e6, 0.0, -9.8),
                    ..at_rest()
                },
                "speed",
            ),
            (
                ImuSample {
                    gyro: Vector3::new(1e300, 0.0, 0.0),
                    ..at_rest()
                },
                "not finite",
            ),
            (
                ImuSample {
                    accel: Vector3::new(0.0, 0.0, 1e5),
                    ..at_rest()
                },
                "exceeds",
            ),
        ];
        for (sample, expected) in cases {
            let mut nav = Navigator::<Sdins25, 25>::builder(initial(), imu())
                .build(at_rest())
                .unwrap();
            nav.push_imu(0.01, at_rest()).unwrap();
            let e = nav.push_imu(0.02, sample).unwrap_err();
            assert!(
                matches!(e, NavigatorError::OutOfBounds { .. }) && e.to_string().contains(expected),
                "{e}"
            );
        }
    }

    /// The barometer port's lever arm carries the INS height to the port:
    /// a port 1.5 m below the IMU of a level vehicle reads 1.5 m low. With
    /// the lever arm declared the height estimate stays at the truth; with
    /// none it is pulled to the port's height.
    #[test]
    fn baro_lever_arm_carries_the_height_to_the_port() {
        use crate::gnss_ins::GnssIns;
        // (port lever arm down, m; expected height error, m)
        for (arm_down, expected) in [(1.5, 0.0), (0.0, -1.5)] {
            let mut start = initial();
            start.sigma.position = 5.0;
            let p = start.position;
            let mut b = Navigator::<GnssIns, 16>::builder(start, imu());
            let mut settings = SensorSettings::new(0.5)
                .bias(0.01)
                .lever_arm(Vector3::new(0.0, 0.0, arm_down));
            settings.initial_bias = 3.0;
            let baro = b.sensor::<BaroReading>(settings).unwrap();
            let mut nav = b.build(at_rest()).unwrap();
            for k in 1..=500 {
                let t = k as f64 * 0.01;
                if k % 20 == 0 {
                    let w = 1e-3 * (k as f64).sin();
                    nav.push(baro, t, BaroReading(p.h - 1.5 + 3.0 + w));
                }
                nav.push_imu(t, at_rest()).unwrap();
            }
            assert_eq!(nav.report(baro).health.accepted, 25);
            let dh = nav.estimate().nav.h - p.h;
            assert!(
                (dh - expected).abs() < 0.15,
                "port {arm_down} m down: height error {dh} m"
            );
        }
    }

    /// The GNSS, barometer and magnetometer slots of `gnss-ins`: fixes of an
    /// antenna 2 m forward of the IMU (heading north) at 2 m north of the
    /// true IMU position, a barometer reading 3 m high with that bias known,
    /// and the field of a level vehicle heading north keep the estimate where
    /// it is; a fix with a NaN latitude is refused and counted, not applied.
    #[test]
    fn gnss_baro_and_mag_slots_apply_their_readings() {
        use crate::gnss_ins::GnssIns;
        let mut start = initial();
        start.attitude.yaw = 0.0;
        start.sigma.position = 5.0;
        let p = start.position;
        let mut b = Navigator::<GnssIns, 16>::builder(start, imu());
        let arm = Vector3::new(2.0, 0.0, 0.0);
        let gnss = b
            .sensor::<GnssFix>(SensorSettings::new(0.1).lever_arm(arm))
            .unwrap();
        let mut baro_settings = SensorSettings::new(0.5).bias(0.1);
        baro_settings.initial_bias = 3.0;
        let baro = b.sensor::<BaroReading>(baro_settings).unwrap();
        let mag = b.sensor::<MagReading>(SensorSettings::new(0.01)).unwrap();
        let mut nav = b.build(at_rest()).unwrap();
        let north = 2.0 / (meridian_radius(p.lat) + p.h);
        for k in 1..=500 {
            let t = k as f64 * 0.01;
            if k % 20 == 0 {
                // Varying readings (identical ones would be frozen values).
                let w = 1e-3 * (k as f64).sin();
                let fix = GnssFix {
                    lat: p.lat + north,
                    lon: p.lon,
                    height: p.h + w,
                    eph: None,
                    epv: None,
                };
                nav.push(gnss, t, fix);
                nav.push(baro, t, BaroReading(p.h + 3.0 + w));
                nav.push(mag, t, MagReading(Vector3::new(0.2, w, 0.4)));
            }
            nav.push_imu(t, at_rest()).unwrap();
        }
        let bad = GnssFix {
            lat: f64::NAN,
            ..GnssFix {
                lat: p.lat,
                lon: p.lon,
                height: p.h,
                eph: None,
                epv: None,
            }
        };
        nav.push(gnss, 5.005, bad);
        nav.push_imu(5.01, at_rest()).unwrap();
        for (name, r) in [
            ("gnss", nav.report(gnss)),
            ("baro", nav.report(baro)),
            ("mag", nav.report(mag)),
        ] {
            assert_eq!(r.health.accepted, 25, "{name}: {r:?}");
        }
        assert_eq!(nav.report(gnss).health.rejected, 1);
        let e = nav.estimate();
        let dn = (e.nav.lat - p.lat) * (meridian_radius(p.lat) + p.h);
        assert!(dn.abs() < 0.05, "north error {dn} m (the lever arm is 2 m)");
        assert!((e.nav.h - p.h).abs() < 0.05, "height {}", e.nav.h - p.h);
        assert!((e.baro_bias.0 - 3.0).abs() < 0.05, "{:?}", e.baro_bias);
        assert!(e.nav.euler().yaw.abs() < 3e-3, "{}", e.nav.euler().yaw);
    }

    /// A vehicle at rest heading 0.3 rad with its USBL transponder 2 m
    /// forward and 1 m to starboard: the fixes are of the transponder. With
    /// the lever arm the position estimate stays at the IMU; without it the
    /// fixes pull it towards the transponder, 2.2 m away.
    #[test]
    fn a_usbl_transponder_at_a_lever_arm_is_fixed_where_it_is() {
        let arm = Vector3::new(2.0, 1.0, 0.0);
        let start = initial();
        let p = start.position;
        let c_bn = start.attitude.c_bn();
        let offset = c_bn * arm;
        let error = |lever_arm: Vector3<f64>| {
            let mut b = Navigator::<Sdins25, 25>::builder(start, imu()).options(NavigatorOptions {
                gate_probability: None,
                ..NavigatorOptions::default()
            });
            let usbl = b
                .sensor::<UsblFix>(SensorSettings::new(0.3).lever_arm(lever_arm))
                .unwrap();
            let mut nav = b.build(at_rest()).unwrap();
            let rm = meridian_radius(p.lat) + p.h;
            let rn = transverse_radius(p.lat) + p.h;
            for k in 1..=1000 {
                let t = k as f64 * 0.01;
                if k % 50 == 0 {
                    let w = 1e-3 * (k as f64).sin();
                    let fix = UsblFix {
                        lat: p.lat + (offset.x + w) / rm,
                        lon: p.lon + offset.y / (rn * p.lat.cos()),
                    };
                    nav.push(usbl, t, fix);
                }
                nav.push_imu(t, at_rest()).unwrap();
            }
            assert_eq!(nav.report(usbl).health.accepted, 20);
            let e = nav.estimate().nav;
            let dn = (e.lat - p.lat) * rm;
            let de = (e.lon - p.lon) * rn * p.lat.cos();
            dn.hypot(de)
        };
        let with_arm = error(arm);
        assert!(with_arm < 0.2, "{with_arm} m");
        let without = error(Vector3::zeros());
        assert!(without > 1.5, "{without} m");
    }

    /// A vehicle turning in place at 0.2 rad/s with its DVL 1.5 m forward:
    /// the DVL reads `omega x r` = 0.3 m/s to starboard. With the lever arm
    /// the velocity estimate stays at rest; without it the reading pulls it
    /// towards 0.3 m/s.
    #[test]
    fn a_dvl_at_a_lever_arm_reads_the_turn_rate_times_the_arm() {
        let omega = 0.2;
        let arm = Vector3::new(1.5, 0.0, 0.0);
        let turning = ImuSample {
            gyro: Vector3::new(0.0, 0.0, omega),
            ..at_rest()
        };
        let speed = |lever_arm: Vector3<f64>| {
            // No gate: the readings without the arm are applied, not refused.
            let mut b =
                Navigator::<Sdins20, 20>::builder(initial(), imu()).options(NavigatorOptions {
                    gate_probability: None,
                    ..NavigatorOptions::default()
                });
            let dvl = b
                .sensor::<DvlReading>(SensorSettings::new(0.05).lever_arm(lever_arm))
                .unwrap();
            let mut nav = b.build(turning).unwrap();
            for k in 1..=1000 {
                let t = k as f64 * 0.01;
                if k % 50 == 0 {
                    let w = 1e-4 * (k as f64).sin();
                    let reading = Vector3::new(w, omega * arm.x, 0.0);
                    nav.push(dvl, t, DvlReading(reading));
                }
                nav.push_imu(t, turning).unwrap();
            }
            let r = nav.report(dvl);
            assert_eq!(r.health.accepted, 20, "{r:?}");
            nav.estimate().nav.v_n.norm()
        };
        let with_arm = speed(arm);
        assert!(with_arm < 0.02, "{with_arm} m/s");
        let without = speed(Vector3::zeros());
        assert!(without > 0.1, "{without} m/s");
    }
}
