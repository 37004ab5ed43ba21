//! The SDINS-25 filter run over a log directory: a strapdown INS (the nominal
//! solution) corrected by the 25-state error-state EKF of [`super::model`],
//! driven by the multi-rate scheduler (IMU samples, aiding measurements at
//! their own times, late USBL fixes applied at their measurement time through
//! the scheduler's history).
//!
//! **Sensor-error states.** The model writes each sensor error as the residual
//! error left in the corrected sensor output: `f~ - nabla^ = f + nabla + w`,
//! `h_meas - b^ = h + b_depth + v`, ... (error state = true bias minus the
//! running correction). Feedback therefore *adds* the estimated sensor errors
//! to the running corrections, and subtracts the navigation errors (INS minus
//! true) from the strapdown solution ([`Nominal::inject`]).

use std::cell::RefCell;
use std::marker::PhantomData;
use std::rc::Rc;

use nav_runtime::attitude::euler_from_c_bn;
use nav_runtime::earth::{meridian_radius, transverse_radius, Geodetic, LocalNed};
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::error_state::{ErrorStateFilter, Mechanization, NominalState};
use nav_runtime::gate::Gate;
use nav_runtime::imu::ImuSpec;
use nav_runtime::log::{LogDir, SensorNoise};
use nav_runtime::math::wrap_angle;
use nav_runtime::model::Record;
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector2, Vector3};
use nav_runtime::scheduler::{FnMeasurement, Measurement, MeasurementOutcome, Scheduler, SensorId};
use nav_runtime::sensors::ErrorSpec;
use nav_runtime::strapdown::{NavError, NavState, Strapdown};
use nav_runtime::stuck::StuckDetector;

use super::model::Sdins25;
use super::simulation::{DVL_MAX_ALTITUDE, SOUND_SPEED, TRACKPOINT_MISALIGNMENT_SIGMA};
use super::vehicle::{InsVehicle, Layout, Present, Slot};
use crate::montecarlo::RunError;

/// Number of error states of SDINS-25.
pub const N: usize = 25;

/// The error-state filter of vehicle `V` (`N` states).
pub type InsFilter<V, const N: usize> = ErrorStateFilter<V, InsNominal<V, N>, N>;

/// The error-state filter of SDINS-25.
pub type Filter = InsFilter<Sdins25, N>;

/// Which compass residual the filter uses.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CompassForm {
    /// Exact yaw of the perturbed attitude (`Sdins25Compass`).
    #[default]
    Exact,
    /// The paper's small-angle `-phi_D - b_psi` (`Sdins25CompassSmallAngle`).
    SmallAngle,
}

/// When a USBL fix reaches the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UsblDelivery {
    /// A travel time (slant range / [`SOUND_SPEED`]) after its measurement time,
    /// as on a real ship; the scheduler applies it at the measurement time.
    #[default]
    Acoustic,
    /// At its measurement time (for comparisons).
    OnTime,
}

/// Filter settings not in the log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterOptions {
    /// Compass residual.
    pub compass: CompassForm,
    /// USBL delivery.
    pub usbl_delivery: UsblDelivery,
    /// Innovation-gate probability for every sensor (`None`: no gating).
    pub gate_probability: Option<f64>,
    /// Gate lock-out release: after this many consecutive gate refusals of
    /// one sensor its next measurement is applied ([`Ekf::set_lockout_release`];
    /// `None`: never).
    pub lockout_release: Option<u32>,
    /// Use these sensors if present in the log.
    pub use_dvl: bool,
    /// Use the depth meter.
    pub use_depth: bool,
    /// Use the compass.
    pub use_compass: bool,
    /// Use the USBL.
    pub use_usbl: bool,
    /// Extra delivery delay of the DVL, depth and compass measurements
    /// (fault injection; zero in normal runs).
    pub delivery: Delivery,
    /// False-alarm probability of the frozen-value (stuck sensor) check of
    /// every aiding sensor ([`nav_runtime::stuck`], [`stuck_detector`]);
    /// `None` disables it.
    pub stuck_false_alarm: Option<f64>,
}

/// Late delivery of the 2 Hz aiding measurements (DVL, depth, compass): each
/// reaches the filter `delay_s + jitter_s u` after its measurement time, with
/// `u` uniform in [0, 1) drawn per row from `seed`. A jitter larger than the
/// sampling interval reorders the deliveries; the scheduler applies each at its
/// measurement time (rollback and replay).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Delivery {
    /// Fixed delay (s).
    pub delay_s: f64,
    /// Random extra delay, at most this (s).
    pub jitter_s: f64,
    /// Seed of the random delays.
    pub seed: u64,
}

impl Delivery {
    /// Whether measurements arrive late at all.
    pub fn is_late(&self) -> bool {
        self.delay_s > 0.0 || self.jitter_s > 0.0
    }

    /// Delay (s) of row `row` of sensor `sensor` (index in the health order).
    pub fn delay(&self, sensor: usize, row: usize) -> f64 {
        if !self.is_late() {
            return 0.0;
        }
        let mut z = self
            .seed
            .wrapping_add((sensor as u64) << 40)
            .wrapping_add(row as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let u = (z >> 11) as f64 / (1u64 << 53) as f64;
        self.delay_s + self.jitter_s * u
    }

    /// Largest delay (s).
    pub fn max_delay(&self) -> f64 {
        self.delay_s + self.jitter_s
    }
}

impl Default for FilterOptions {
    fn default() -> Self {
        Self {
            compass: CompassForm::Exact,
            usbl_delivery: UsblDelivery::Acoustic,
            gate_probability: Some(Gate::DEFAULT_PROBABILITY),
            lockout_release: Some(LOCKOUT_RELEASE),
            use_dvl: true,
            use_depth: true,
            use_compass: true,
            use_usbl: true,
            delivery: Delivery::default(),
            stuck_false_alarm: Some(StuckDetector::DEFAULT_FALSE_ALARM),
        }
    }
}

/// Default [`FilterOptions::lockout_release`]: 3 refusals in a row (a
/// consistent filter refuses 3 good samples in a row with probability 1e-12).
pub const LOCKOUT_RELEASE: u32 = 3;

/// Defaults when `[initial_sigma]` lacks a key (m, m/s, rad).
pub const DEFAULT_INITIAL_SIGMA: [f64; 4] = [
    1.0,
    0.05,
    8.726_646_259_971_648e-4,
    8.726_646_259_971_648e-3,
];

/// Smallest prior sigma of any state (in the state's units): a zero variance
/// would be "repaired" by the filter after every step.
const SIGMA_FLOOR: f64 = 1e-9;

/// One IMU sample as the scheduler holds it: body rate (rad/s) and specific
/// force (m/s^2), before the bias corrections.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuSample {
    /// Gyro output.
    pub gyro: Vector3<f64>,
    /// Accelerometer output.
    pub accel: Vector3<f64>,
}

impl Record for ImuSample {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &["gx", "gy", "gz", "ax", "ay", "az"];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        Self {
            gyro: Vector3::new(f(0), f(1), f(2)),
            accel: Vector3::new(f(3), f(4), f(5)),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0..=2 => self.gyro[i],
            3..=5 => self.accel[i - 3],
            _ => f64::NAN,
        }
    }
}

/// The nominal solution of vehicle `V`: strapdown INS plus the running
/// sensor corrections (those of sensors `V` lacks stay zero).
pub struct InsNominal<V, const N: usize> {
    /// The strapdown INS.
    pub ins: Strapdown,
    /// Accelerometer bias correction, subtracted from the samples (m/s^2).
    pub accel_bias: Vector3<f64>,
    /// Gyro bias correction, subtracted from the samples (rad/s).
    pub gyro_bias: Vector3<f64>,
    /// USBL horizontal bias correction (m, N/E).
    pub usbl_bias: Vector2<f64>,
    /// Depth-meter bias correction (m, height convention: `h_meas = h + b`).
    pub depth_bias: f64,
    /// DVL bias correction (m/s, body).
    pub dvl_bias: Vector3<f64>,
    /// Compass bias correction (rad).
    pub compass_bias: f64,
    /// USBL misalignment correction (rad).
    pub usbl_misalignment: Vector3<f64>,
    /// Where `V` keeps each error state.
    layout: Layout,
    vehicle: PhantomData<fn() -> V>,
}

/// The nominal solution of SDINS-25.
pub type Nominal = InsNominal<Sdins25, N>;

impl<V, const N: usize> Clone for InsNominal<V, N> {
    fn clone(&self) -> Self {
        Self {
            ins: self.ins.clone(),
            layout: self.layout,
            vehicle: PhantomData,
            ..*self
        }
    }
}

impl<V, const N: usize> core::fmt::Debug for InsNominal<V, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("InsNominal")
            .field("ins", &self.ins)
            .field("accel_bias", &self.accel_bias)
            .field("gyro_bias", &self.gyro_bias)
            .field("usbl_bias", &self.usbl_bias)
            .field("depth_bias", &self.depth_bias)
            .field("dvl_bias", &self.dvl_bias)
            .field("compass_bias", &self.compass_bias)
            .field("usbl_misalignment", &self.usbl_misalignment)
            .field("layout", &self.layout)
            .finish()
    }
}

impl<V: InsVehicle<N>, const N: usize> InsNominal<V, N> {
    /// A nominal solution at `state` with zero corrections.
    ///
    /// # Panics
    /// If `V` does not fit the replay loop ([`Layout::of`] fails); use
    /// [`InsNominal::try_new`] to get the error.
    pub fn new(ins: Strapdown) -> Self {
        match Self::try_new(ins) {
            Ok(n) => n,
            Err(e) => panic!("{e}"),
        }
    }

    /// A nominal solution at `state` with zero corrections.
    ///
    /// # Errors
    /// As [`Layout::of`].
    pub fn try_new(ins: Strapdown) -> Result<Self, RunError> {
        Ok(Self {
            ins,
            accel_bias: Vector3::zeros(),
            gyro_bias: Vector3::zeros(),
            usbl_bias: Vector2::zeros(),
            depth_bias: 0.0,
            dvl_bias: Vector3::zeros(),
            compass_bias: 0.0,
            usbl_misalignment: Vector3::zeros(),
            layout: Layout::of::<V, N>()?,
            vehicle: PhantomData,
        })
    }

    /// Where `V` keeps each error state.
    pub fn layout(&self) -> &Layout {
        &self.layout
    }
}

impl<V: InsVehicle<N>, const N: usize> NominalState<N> for InsNominal<V, N> {
    fn inject(&mut self, e: &SVector<f64, N>) {
        let l = &self.layout;
        let nav = l.navigation().map(|i| e[i]);
        self.ins.inject(&NavError::from_slice(&nav));
        let v3 = |i: usize| Vector3::new(e[i], e[i + 1], e[i + 2]);
        self.accel_bias += v3(l.accel_bias);
        self.gyro_bias += v3(l.gyro_bias);
        if let Some(i) = l.usbl_bias {
            self.usbl_bias += Vector2::new(e[i], e[i + 1]);
        }
        if let Some(i) = l.depth_bias {
            self.depth_bias += e[i];
        }
        if let Some(i) = l.dvl_bias {
            self.dvl_bias += v3(i);
        }
        if let Some(i) = l.compass_bias {
            self.compass_bias += e[i];
        }
        if let Some(i) = l.usbl_misalignment {
            self.usbl_misalignment += v3(i);
        }
    }
}

impl<V: InsVehicle<N>, const N: usize> Mechanization<V, N> for InsNominal<V, N> {
    type Imu = ImuSample;
    fn mechanize(&mut self, dt: f64, imu: &ImuSample) -> V::Input {
        let w = imu.gyro - self.gyro_bias;
        let f = imu.accel - self.accel_bias;
        let s = &self.ins.state;
        let c = &s.c_bn;
        // The INS core's inputs in record order (checked by `Layout::of`).
        let values: [f64; 17] = [
            s.lat,
            s.h,
            s.v_n.x,
            s.v_n.y,
            s.v_n.z,
            c[(0, 0)],
            c[(0, 1)],
            c[(0, 2)],
            c[(1, 0)],
            c[(1, 1)],
            c[(1, 2)],
            c[(2, 0)],
            c[(2, 1)],
            c[(2, 2)],
            f.x,
            f.y,
            f.z,
        ];
        let input = <V::Input as Record>::from_fn(|i| values[i]);
        self.ins.update_rates(&w, &f, dt);
        input
    }
}

/// The filter's estimate at one time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Estimate {
    /// Time (s).
    pub t: f64,
    /// Corrected navigation solution.
    pub nav: NavState,
    /// Covariance of the 9 navigation errors with position in metres (N, E, D),
    /// velocity (m/s) and attitude (rad).
    pub cov: SMatrix<f64, 9, 9>,
    /// Compass bias estimate (rad) and its sigma.
    pub compass_bias: (f64, f64),
    /// USBL bias estimate (m, N) and its sigma.
    pub usbl_bias_n: (f64, f64),
}

impl Estimate {
    /// The estimate of filter `f` at time `t`. A bias the vehicle does not
    /// estimate is reported as zero with a NaN sigma.
    pub fn of<V: InsVehicle<N>, const N: usize>(t: f64, f: &InsFilter<V, N>) -> Self {
        let nav = f.nominal().ins.state;
        let p = f.covariance();
        let layout = f.nominal().layout();
        let idx = layout.navigation();
        let (rm, rn) = (
            meridian_radius(nav.lat) + nav.h,
            transverse_radius(nav.lat) + nav.h,
        );
        let mut scale = [1.0; 9];
        scale[0] = rm;
        scale[1] = rn * nav.lat.cos();
        scale[2] = -1.0;
        let cov = SMatrix::<f64, 9, 9>::from_fn(|i, j| scale[i] * p[(idx[i], idx[j])] * scale[j]);
        let sigma = |i: Option<usize>| i.map_or(f64::NAN, |i| p[(i, i)].sqrt());
        Self {
            t,
            nav,
            cov,
            compass_bias: (f.nominal().compass_bias, sigma(layout.compass_bias)),
            usbl_bias_n: (f.nominal().usbl_bias[0], sigma(layout.usbl_bias)),
        }
    }
}

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
    /// its noise and resolution explain; [`stuck_detector`]).
    pub stuck: u64,
}

/// The result of a run of vehicle `V` over a log.
#[derive(Clone, Debug)]
pub struct InsRun<V: InsVehicle<N>, const N: usize> {
    /// Estimates at the requested times (`None` where no IMU sample is near).
    pub estimates: Vec<Option<Estimate>>,
    /// IMU samples processed.
    pub samples: usize,
    /// Per-sensor health: depth, dvl, heading, usbl.
    pub health: [(&'static str, SensorHealth); 4],
    /// Covariance diagonal repairs.
    pub repairs: u64,
    /// Wall time in the filter loop (s).
    pub runtime_s: f64,
    /// Rollbacks for late measurements.
    pub replays: u64,
    /// The filter at the end (all measurements applied).
    pub final_filter: InsFilter<V, N>,
    /// Log sensors with rows that the vehicle has no sensor for (their rows
    /// are counted as skipped).
    pub ignored: Vec<&'static str>,
}

/// The result of an SDINS-25 run over a log.
pub type Sdins25Run = InsRun<Sdins25, N>;

/// Sensor registration order (also the order of measurements at equal times).
const SENSORS: [&str; 4] = ["depth", "dvl", "heading", "usbl"];

fn filter_error(name: &str, e: FilterError) -> RunError {
    RunError::Invalid(format!("{name} filter: {e}"))
}

fn noise_or(n: Option<SensorNoise>, spec: ErrorSpec) -> SensorNoise {
    n.unwrap_or(SensorNoise {
        bias_sigma: match spec.bias {
            nav_runtime::sensors::Draw::Gaussian(s) => s,
            _ => 0.0,
        },
        noise_sigma: spec.noise,
    })
}

/// Initial SDINS-25 filter: [`initial_vehicle_filter`] of [`Sdins25`].
pub fn initial_filter(log: &LogDir, options: &FilterOptions) -> Result<Filter, RunError> {
    initial_vehicle_filter::<Sdins25, N>(log, options)
}

/// Initial filter of vehicle `V` (nominal from `[initial]`, covariance from
/// `[initial_sigma]` and the sensor bias sigmas of `[sensors.*]`, Table 1
/// where absent), with its nominal primed by the first IMU sample.
pub fn initial_vehicle_filter<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
) -> Result<InsFilter<V, N>, RunError> {
    let layout = Layout::of::<V, N>()?;
    let meta = &log.meta;
    let [roll, pitch, yaw] = meta.initial.attitude()?;
    let first = log
        .imu
        .first()
        .ok_or_else(|| RunError::Invalid("imu.csv has no rows".into()))?;
    let att = nav_runtime::attitude::Euler { roll, pitch, yaw };
    let state = NavState::new(
        Geodetic::new(meta.initial.lat, meta.initial.lon, -meta.initial.depth),
        Vector3::new(meta.initial.vn, meta.initial.ve, meta.initial.vd),
        &att,
    );
    let mut ins = Strapdown::with_time(state, first.t);
    // The first sample is the rate at the initial time: it starts the rate model.
    ins.set_previous_rates(
        &Vector3::new(first.gx, first.gy, first.gz),
        &Vector3::new(first.ax, first.ay, first.az),
    );

    let spec = ImuSpec::sdins25();
    let imu = meta.sensors.imu.unwrap_or(nav_runtime::log::ImuNoise {
        gyro_bias_sigma: spec.gyro_bias,
        gyro_noise_sigma: spec.gyro_noise,
        accel_bias_sigma: spec.accel_bias,
        accel_noise_sigma: spec.accel_noise,
    });
    let sig = meta.initial_sigma.unwrap_or_default();
    let [dp, dv, dl, dh] = DEFAULT_INITIAL_SIGMA;
    let (sp, sv) = (sig.position.unwrap_or(dp), sig.velocity.unwrap_or(dv));
    let (sl, sh) = (sig.level.unwrap_or(dl), sig.heading.unwrap_or(dh));
    let usbl = noise_or(meta.sensors.usbl, ErrorSpec::sdins25_usbl());
    let depth = noise_or(meta.sensors.depth, ErrorSpec::sdins25_depth());
    let dvl = noise_or(meta.sensors.dvl, ErrorSpec::sdins25_dvl());
    let heading = noise_or(meta.sensors.heading, ErrorSpec::sdins25_compass());
    // meta.toml has no key for the array misalignment: an array with a bias is
    // taken as uncalibrated (Trackpoint II, 0.5 deg), one without as calibrated.
    let misalignment = if usbl.bias_sigma > 0.0 {
        TRACKPOINT_MISALIGNMENT_SIGMA
    } else {
        0.0
    };
    let lat = state.lat;
    let mut sigma = [0.0; N];
    let (p, v, a) = (layout.position, layout.velocity, layout.attitude);
    sigma[p] = sp / (meridian_radius(lat) + state.h);
    sigma[p + 1] = sp / ((transverse_radius(lat) + state.h) * lat.cos());
    sigma[p + 2] = sp;
    sigma[v..v + 3].fill(sv);
    sigma[a..a + 2].fill(sl);
    sigma[a + 2] = sh;
    sigma[layout.accel_bias..layout.accel_bias + 3].fill(imu.accel_bias_sigma);
    sigma[layout.gyro_bias..layout.gyro_bias + 3].fill(imu.gyro_bias_sigma);
    for (at, len, s) in [
        (layout.usbl_bias, 2, usbl.bias_sigma),
        (layout.depth_bias, 1, depth.bias_sigma),
        (layout.dvl_bias, 3, dvl.bias_sigma),
        (layout.compass_bias, 1, heading.bias_sigma),
        (layout.usbl_misalignment, 3, misalignment),
    ] {
        if let Some(i) = at {
            sigma[i..i + len].fill(s);
        }
    }
    let p0 = SMatrix::<f64, N, N>::from_diagonal(&SVector::<f64, N>::from_fn(|i, _| {
        sigma[i].max(SIGMA_FLOOR).powi(2)
    }));

    // Noise densities from per-sample sigmas: q = sigma^2 dt.
    let dt = imu_period(log);
    // The INS core's noise in record order (checked by `Layout::of`).
    let (qa, qg) = (
        imu.accel_noise_sigma.powi(2) * dt,
        imu.gyro_noise_sigma.powi(2) * dt,
    );
    let noise = <V::Noise as Record>::from_fn(|i| if i < 3 { qa } else { qg });
    let name = V::REPLAY_NAME;
    let gate = match options.gate_probability {
        Some(p) => Some(Gate::new(p).map_err(|e| filter_error(name, e.into()))?),
        None => None,
    };
    let ekf = Ekf::<V, N>::new(SVector::zeros(), p0, V::Params::default(), noise)
        .map_err(|e| filter_error(name, e.into()))?
        .with_default_gate(gate)
        .with_lockout_release(options.lockout_release);
    Ok(ErrorStateFilter::new(ekf, InsNominal::try_new(ins)?))
}

/// Median IMU sampling interval (s).
pub fn imu_period(log: &LogDir) -> f64 {
    let mut d: Vec<f64> = log.imu.windows(2).map(|w| w[1].t - w[0].t).collect();
    if d.is_empty() {
        return 0.01;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

#[derive(Clone, Copy, Debug)]
enum Kind {
    Depth(usize),
    Dvl(usize),
    Heading(usize),
    Usbl(usize),
    Record(usize),
}

#[derive(Clone, Copy, Debug)]
struct Event {
    delivery: f64,
    time: f64,
    kind: Kind,
}

type Recorder = Rc<RefCell<Vec<Option<Estimate>>>>;

fn outcome<const M: usize>(
    r: Result<nav_runtime::ekf::UpdateReport<M>, FilterError>,
) -> Result<MeasurementOutcome, FilterError> {
    r.map(|rep| MeasurementOutcome::from(&rep))
}

/// A depth-meter measurement (`depth`: m, positive down) with noise sigma (m),
/// for the `Depth` sensor of vehicle `V`.
pub fn depth_measurement<V: InsVehicle<N>, const N: usize>(
    depth: f64,
    sigma: f64,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let h_meas = -depth;
    let r = SVector::<f64, 1>::new(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[h_meas],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let z = SVector::<f64, 1>::new(nom.ins.state.h - (h_meas - nom.depth_bias));
            outcome(V::Depth::update(f, &z, &r, &[]))
        },
    ))
}

/// A DVL measurement (body velocity, m/s) with noise sigma per axis (m/s),
/// for the `Dvl` sensor of vehicle `V`.
pub fn dvl_measurement<V: InsVehicle<N>, const N: usize>(
    v: Vector3<f64>,
    sigma: f64,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 3>::repeat(sigma.powi(2));
    Box::new(FnMeasurement::new(
        v.as_slice(),
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            let z = s.v_n - s.c_bn * (v - nom.dvl_bias);
            outcome(V::Dvl::update(f, &z, &r, &[]))
        },
    ))
}

/// A compass measurement (heading `psi`, rad) with noise sigma (rad), for the
/// `Compass` or `CompassSmallAngle` sensor of vehicle `V`.
pub fn heading_measurement<V: InsVehicle<N>, const N: usize>(
    psi: f64,
    sigma: f64,
    form: CompassForm,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 1>::new(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[psi],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let yaw = euler_from_c_bn(&nom.ins.state.c_bn).yaw;
            let z = SVector::<f64, 1>::new(wrap_angle(yaw - (psi - nom.compass_bias)));
            match form {
                CompassForm::Exact => outcome(V::Compass::update(f, &z, &r, &[])),
                CompassForm::SmallAngle => outcome(V::CompassSmallAngle::update(f, &z, &r, &[])),
            }
        },
    ))
}

/// A USBL fix (`lat`, `lon`: rad) with noise sigma per axis (m) from the
/// transducer at the origin of `frame`, for the `Usbl` sensor of vehicle `V`.
pub fn usbl_measurement<V: InsVehicle<N>, const N: usize>(
    lat: f64,
    lon: f64,
    sigma: f64,
    frame: LocalNed,
) -> Box<dyn Measurement<InsFilter<V, N>>> {
    let r = SVector::<f64, 2>::repeat(sigma.powi(2));
    Box::new(FnMeasurement::new(
        &[lat, lon],
        move |f: &mut InsFilter<V, N>| {
            let nom = f.nominal();
            let s = &nom.ins.state;
            let rel = frame.geodetic_to_ned(&s.position());
            let dn = (meridian_radius(s.lat) + s.h) * (s.lat - lat);
            let de = (transverse_radius(s.lat) + s.h) * s.lat.cos() * wrap_angle(s.lon - lon);
            let tilt = nom.usbl_misalignment.cross(&rel);
            let z = Vector2::new(dn, de) + nom.usbl_bias + Vector2::new(tilt.x, tilt.y);
            outcome(V::Usbl::update(f, &z, &r, rel.as_slice()))
        },
    ))
}

/// Runs the SDINS-25 filter over `log`: [`run_vehicle`] of [`Sdins25`].
pub fn run(
    log: &LogDir,
    options: &FilterOptions,
    record_times: &[f64],
) -> Result<Sdins25Run, RunError> {
    run_vehicle::<Sdins25, N>(log, options, record_times)
}

/// Runs the filter of vehicle `V` over `log`, recording estimates at
/// `record_times` (s; each snapped to the nearest IMU sample time within half
/// a period). The rows of a log sensor `V` has no sensor for are not used:
/// they are counted in that sensor's health as rows and skipped, and the
/// sensor is listed in [`InsRun::ignored`].
pub fn run_vehicle<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
    record_times: &[f64],
) -> Result<InsRun<V, N>, RunError> {
    let filter = initial_vehicle_filter::<V, N>(log, options)?;
    let has = Present::of::<V, N>();
    let has_heading = match options.compass {
        CompassForm::Exact => has.compass,
        CompassForm::SmallAngle => has.compass_small_angle,
    };
    let t0 = filter.nominal().ins.time;
    let dt_imu = imu_period(log);
    let imu_t: Vec<f64> = log.imu.iter().map(|r| r.t).collect();
    let mut health = [SensorHealth::default(); 4];
    let mut ignored = Vec::new();
    let mut events: Vec<Event> = Vec::new();
    // A log sensor the vehicle lacks: its rows are counted and skipped.
    let mut lacking = |i: usize, present: bool, rows: Option<usize>| -> bool {
        match rows {
            Some(n) if !present => {
                health[i].rows = n as u64;
                health[i].skipped = n as u64;
                ignored.push(SENSORS[i]);
                true
            }
            _ => !present,
        }
    };
    let skip_depth = lacking(0, has.depth, log.depth.as_ref().map(Vec::len));
    let skip_dvl = lacking(1, has.dvl, log.dvl.as_ref().map(Vec::len));
    let skip_heading = lacking(2, has_heading, log.heading.as_ref().map(Vec::len));
    let skip_usbl = lacking(3, has.usbl, log.usbl.as_ref().map(Vec::len));

    // Depth meter (height convention).
    let depth_noise = noise_or(log.meta.sensors.depth, ErrorSpec::sdins25_depth());
    if let (true, false, Some(rows)) = (options.use_depth, skip_depth, &log.depth) {
        health[0].rows = rows.len() as u64;
        events.extend(rows.iter().enumerate().map(|(i, r)| Event {
            delivery: r.t + options.delivery.delay(0, i),
            time: r.t,
            kind: Kind::Depth(i),
        }));
    }
    // DVL: valid only with bottom lock and below its range.
    let dvl_noise = noise_or(log.meta.sensors.dvl, ErrorSpec::sdins25_dvl());
    if let (true, false, Some(rows)) = (options.use_dvl, skip_dvl, &log.dvl) {
        health[1].rows = rows.len() as u64;
        for (i, r) in rows.iter().enumerate() {
            let in_range = altitude_at(log, r.t).is_none_or(|a| a <= DVL_MAX_ALTITUDE);
            if r.velocity().is_some() && in_range {
                events.push(Event {
                    delivery: r.t + options.delivery.delay(1, i),
                    time: r.t,
                    kind: Kind::Dvl(i),
                });
            } else {
                health[1].skipped += 1;
            }
        }
    }
    let heading_noise = noise_or(log.meta.sensors.heading, ErrorSpec::sdins25_compass());
    if let (true, false, Some(rows)) = (options.use_compass, skip_heading, &log.heading) {
        health[2].rows = rows.len() as u64;
        events.extend(rows.iter().enumerate().map(|(i, r)| Event {
            delivery: r.t + options.delivery.delay(2, i),
            time: r.t,
            kind: Kind::Heading(i),
        }));
    }
    // USBL: transducer from [usbl], else at the surface above the start.
    let usbl_noise = noise_or(log.meta.sensors.usbl, ErrorSpec::sdins25_usbl());
    let transducer = log.meta.usbl.map_or(
        Geodetic::new(log.meta.initial.lat, log.meta.initial.lon, 0.0),
        |u| Geodetic::new(u.lat, u.lon, -u.depth),
    );
    let frame = LocalNed::new(transducer);
    let mut usbl_latency: f64 = 0.0;
    if let (true, false, Some(rows)) = (options.use_usbl, skip_usbl, &log.usbl) {
        health[3].rows = rows.len() as u64;
        for (i, r) in rows.iter().enumerate() {
            let delay = match options.usbl_delivery {
                UsblDelivery::OnTime => 0.0,
                UsblDelivery::Acoustic => {
                    frame
                        .geodetic_to_ned(&Geodetic::new(r.lat, r.lon, -r.depth))
                        .norm()
                        / SOUND_SPEED
                }
            };
            usbl_latency = usbl_latency.max(delay);
            events.push(Event {
                delivery: r.t + delay,
                time: r.t,
                kind: Kind::Usbl(i),
            });
        }
    }

    // Recorders: one per IMU sample time that some requested time snaps to.
    let mut slots: Vec<(usize, Vec<usize>)> = Vec::new();
    for (slot, &t) in record_times.iter().enumerate() {
        let k = imu_t.partition_point(|&x| x < t);
        let best = [k.wrapping_sub(1), k]
            .into_iter()
            .filter(|&j| j < imu_t.len())
            .min_by(|&a, &b| (imu_t[a] - t).abs().total_cmp(&(imu_t[b] - t).abs()));
        if let Some(j) = best.filter(|&j| (imu_t[j] - t).abs() <= 0.5 * dt_imu + 1e-9) {
            match slots.last_mut() {
                Some((last, v)) if *last == j => v.push(slot),
                _ => slots.push((j, vec![slot])),
            }
        }
    }
    let recorded: Recorder = Rc::new(RefCell::new(vec![None; record_times.len()]));
    let mut slot_lists = Vec::new();
    for (j, list) in slots {
        if j == 0 {
            let e = Estimate::of(imu_t[0], &filter);
            for &s in &list {
                recorded.borrow_mut()[s] = Some(e);
            }
        } else {
            events.push(Event {
                delivery: imu_t[j],
                time: imu_t[j],
                kind: Kind::Record(slot_lists.len()),
            });
            slot_lists.push(Rc::<[usize]>::from(list));
        }
    }
    events.sort_by(|a, b| a.delivery.total_cmp(&b.delivery));

    // Latencies: the history spans the largest. USBL fixes travel (plus a
    // margin) only if there are any; the 2 Hz aiding is late only with
    // delivery faults.
    let has_usbl = events.iter().any(|e| matches!(e.kind, Kind::Usbl(_)));
    let latencies: [f64; 4] = std::array::from_fn(|i| {
        if i == 3 {
            if has_usbl {
                usbl_latency + 1.0
            } else {
                0.0
            }
        } else if options.delivery.is_late() {
            options.delivery.max_delay() + 0.1
        } else {
            0.0
        }
    });
    let mut sched = Scheduler::new(filter, t0)
        .map_err(|e| RunError::Invalid(e.to_string()))?
        .with_snapshot_every(snapshot_interval(
            latencies.iter().fold(0.0, |a, &b| a.max(b)),
            dt_imu,
        ));
    let mut ids: Vec<SensorId> = Vec::new();
    for (i, name) in SENSORS.iter().enumerate() {
        let latency = latencies[i];
        ids.push(
            sched
                .add_sensor(*name, 2.0, latency)
                .map_err(|e| RunError::Invalid(e.to_string()))?,
        );
    }
    if let Some(alpha) = options.stuck_false_alarm {
        // Resolution of each sensor in this log; USBL angles converted to metres.
        let radius = meridian_radius(log.meta.initial.lat);
        let q = [
            log.depth.as_ref().map_or(0.0, |r| {
                log_resolution(r.iter().map(|x| std::slice::from_ref(&x.depth)))
            }),
            log.dvl.as_ref().map_or(0.0, |r| {
                let v: Vec<[f64; 3]> = r.iter().filter_map(|x| x.velocity()).collect();
                log_resolution(v.iter().map(|x| x.as_slice()))
            }),
            log.heading.as_ref().map_or(0.0, |r| {
                log_resolution(r.iter().map(|x| std::slice::from_ref(&x.heading)))
            }),
            log.usbl.as_ref().map_or(0.0, |r| {
                let v: Vec<[f64; 2]> = r.iter().map(|x| [x.lat, x.lon]).collect();
                radius * log_resolution(v.iter().map(|x| x.as_slice()))
            }),
        ];
        let sigma = [
            depth_noise.noise_sigma,
            dvl_noise.noise_sigma,
            heading_noise.noise_sigma,
            usbl_noise.noise_sigma,
        ];
        for i in 0..4 {
            sched
                .set_stuck_detector(ids[i], stuck_detector(sigma[i], q[i], alpha))
                .map_err(|e| RunError::Invalid(e.to_string()))?;
        }
    }
    let rec_id = sched
        .add_sensor("record", 10.0, 0.0)
        .map_err(|e| RunError::Invalid(e.to_string()))?;

    let make = |ev: &Event| -> (SensorId, Box<dyn Measurement<InsFilter<V, N>>>) {
        match ev.kind {
            Kind::Depth(i) => {
                let depth = log.depth.as_ref().map_or(f64::NAN, |r| r[i].depth);
                (ids[0], depth_measurement(depth, depth_noise.noise_sigma))
            }
            Kind::Dvl(i) => {
                let v = log
                    .dvl
                    .as_ref()
                    .and_then(|r| r[i].velocity())
                    .map_or(Vector3::repeat(f64::NAN), Vector3::from);
                (ids[1], dvl_measurement(v, dvl_noise.noise_sigma))
            }
            Kind::Heading(i) => {
                let psi = log.heading.as_ref().map_or(f64::NAN, |r| r[i].heading);
                (
                    ids[2],
                    heading_measurement(psi, heading_noise.noise_sigma, options.compass),
                )
            }
            Kind::Usbl(i) => {
                let row = log.usbl.as_ref().map(|r| r[i]);
                let (lat, lon) = row.map_or((f64::NAN, f64::NAN), |r| (r.lat, r.lon));
                (
                    ids[3],
                    usbl_measurement(lat, lon, usbl_noise.noise_sigma, frame),
                )
            }
            Kind::Record(k) => {
                let rec = Rc::clone(&recorded);
                let list = Rc::clone(&slot_lists[k]);
                let t = ev.time;
                let m = FnMeasurement::new(&[], move |f: &mut InsFilter<V, N>| {
                    let e = Estimate::of(t, f);
                    let mut v = rec.borrow_mut();
                    for &s in list.iter() {
                        v[s] = Some(e);
                    }
                    Ok(MeasurementOutcome {
                        accepted: true,
                        nis: 0.0,
                        threshold: None,
                        dof: 0,
                    })
                });
                (rec_id, Box::new(m))
            }
        }
    };

    let start = std::time::Instant::now();
    let mut next = 0;
    let mut samples = 0;
    let mut skipped_early = [0u64; 4];
    let mut push = |sched: &mut Scheduler<InsFilter<V, N>>, ev: &Event| {
        let (id, m) = make(ev);
        if ev.time <= t0 {
            if id.index() < 4 {
                skipped_early[id.index()] += 1;
            }
            return;
        }
        // Refusals are counted by the scheduler per sensor.
        let _ = sched.push_measurement(id, ev.time, m);
    };
    for row in log.imu.iter().skip(1) {
        while let Some(ev) = events.get(next).filter(|e| e.delivery <= row.t) {
            push(&mut sched, ev);
            next += 1;
        }
        let imu = ImuSample {
            gyro: Vector3::new(row.gx, row.gy, row.gz),
            accel: Vector3::new(row.ax, row.ay, row.az),
        };
        sched
            .push_imu(row.t, imu)
            .map_err(|e| RunError::Invalid(format!("imu.csv at t = {} s: {e}", row.t)))?;
        samples += 1;
    }
    // Fixes still travelling when the IMU data ends (measured before its end).
    for ev in &events[next..] {
        push(&mut sched, ev);
    }
    let runtime_s = start.elapsed().as_secs_f64();

    for (i, h) in health.iter_mut().enumerate() {
        if let Some(s) = sched.sensor_stats(ids[i]) {
            h.accepted = s.accepted;
            h.gated = s.gated;
            h.rejected = s.failed + s.too_old + s.duplicate + s.invalid + s.queue_full;
            h.skipped += skipped_early[i];
            h.stuck = s.stuck;
        }
    }
    let final_filter = sched.filter().clone();
    let repairs = final_filter.ekf().counters().covariance_repairs;
    let replays = sched.stats().replays;
    drop(sched);
    let estimates = Rc::try_unwrap(recorded)
        .map(RefCell::into_inner)
        .unwrap_or_else(|rc| rc.borrow().clone());
    Ok(InsRun {
        estimates,
        samples: samples + 1,
        health: [
            (SENSORS[0], health[0]),
            (SENSORS[1], health[1]),
            (SENSORS[2], health[2]),
            (SENSORS[3], health[3]),
        ],
        repairs,
        runtime_s,
        replays,
        final_filter,
        ignored,
    })
}

/// Output resolution of a sensor in a log: the smallest non-zero change
/// between consecutive values of any component (a multiple of the
/// quantization step, so never finer than it); 0 if no value changes.
pub fn log_resolution<'a>(values: impl Iterator<Item = &'a [f64]>) -> f64 {
    let mut previous: Option<&[f64]> = None;
    let mut q = f64::INFINITY;
    for v in values {
        if let Some(p) = previous {
            for (a, b) in p.iter().zip(v) {
                let d = (a - b).abs();
                if d > 0.0 && d.is_finite() {
                    q = q.min(d);
                }
            }
        }
        previous = Some(v);
    }
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

/// The frozen-value detector of a sensor with per-sample noise `noise_sigma`
/// and log resolution `resolution` (same units) at false-alarm probability
/// `false_alarm`: see [`StuckDetector::for_sensor`]. With full-precision logs
/// (simulation) this is [`StuckDetector::MIN_REPEATS`] identical samples.
pub fn stuck_detector(noise_sigma: f64, resolution: f64, false_alarm: f64) -> StuckDetector {
    StuckDetector::for_sensor(noise_sigma, resolution, false_alarm)
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

/// Echo-sounder altitude at `t`: the latest row at or before `t` (m).
fn altitude_at(log: &LogDir, t: f64) -> Option<f64> {
    let rows = log.altitude.as_ref()?;
    let k = rows.partition_point(|r| r.t <= t + 1e-9);
    rows.get(k.checked_sub(1)?).map(|r| r.altitude)
}

/// `C_b^n` from Euler angles (rad).
pub fn c_bn(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    nav_runtime::attitude::Euler { roll, pitch, yaw }.c_bn()
}
