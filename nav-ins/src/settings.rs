//! What a navigator is built from besides the vehicle: the initial state with
//! its uncertainty, the IMU's error model, one entry per sensor, and the
//! run-wide options (gate, lock-out release, frozen-value check, physical
//! bounds). Units are SI with angles in radians.

use nav_runtime::attitude::Euler;
use nav_runtime::earth::Geodetic;
use nav_runtime::gate::Gate;
use nav_runtime::nalgebra::{Matrix3, Vector3};
use nav_runtime::stuck::StuckDetector;

use super::measurement::CompassForm;

/// The initial estimate and its uncertainty.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialState {
    /// Epoch of the estimate (s, log time).
    pub t: f64,
    /// Position (latitude, longitude in rad; height in m, positive up).
    pub position: Geodetic,
    /// Velocity, north-east-down (m/s).
    pub velocity: Vector3<f64>,
    /// Attitude (rad).
    pub attitude: Euler,
    /// One-sigma uncertainty.
    pub sigma: InitialSigma,
}

/// One-sigma uncertainty of the initial estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct InitialSigma {
    /// Horizontal and vertical position (m).
    pub position: f64,
    /// Velocity per axis (m/s).
    pub velocity: f64,
    /// Roll and pitch (rad).
    pub level: f64,
    /// Yaw (rad).
    pub heading: f64,
}

impl InitialSigma {
    /// 1 m, 0.05 m/s, 0.05 deg level, 0.5 deg heading.
    pub const DEFAULT: Self = Self {
        position: 1.0,
        velocity: 0.05,
        level: 8.726_646_259_971_648e-4,
        heading: 8.726_646_259_971_648e-3,
    };
}

impl Default for InitialSigma {
    /// [`InitialSigma::DEFAULT`].
    fn default() -> Self {
        Self::DEFAULT
    }
}

/// The IMU's error model (per-sample sigmas at the IMU period).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuSettings {
    /// Sampling period (s).
    pub period_s: f64,
    /// Gyro bias sigma (rad/s).
    pub gyro_bias_sigma: f64,
    /// Gyro noise sigma per sample (rad/s).
    pub gyro_noise_sigma: f64,
    /// Accelerometer bias sigma (m/s^2).
    pub accel_bias_sigma: f64,
    /// Accelerometer noise sigma per sample (m/s^2).
    pub accel_noise_sigma: f64,
}

/// One aiding sensor's settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorSettings {
    /// Noise sigma of one reading (reading units: m, m/s, rad).
    pub noise_sigma: f64,
    /// Sigma of the sensor's bias state, the prior of its covariance.
    pub bias_sigma: f64,
    /// Initial value of the sensor's bias correction (reading units), for a
    /// bias taken from the first reading (the barometer's).
    pub initial_bias: f64,
    /// Random-walk density of a bias whose block has process noise for it
    /// (the barometer's `baro_bias_noise`; reading units squared per second).
    pub bias_walk: f64,
    /// Nominal rate (Hz), for staleness.
    pub rate_hz: f64,
    /// Largest delay between a reading's time and its push (s); older
    /// readings are refused. It sets the history the navigator keeps.
    pub latency_s: f64,
    /// Output resolution (reading units; 0: full precision), for the
    /// frozen-value check.
    pub resolution: f64,
    /// Sensor-to-body rotation of a vector reading (DVL); `None`: aligned.
    pub mounting: Option<Matrix3<f64>>,
    /// Sigma of the mounting misalignment state of sensors whose block
    /// estimates one (the USBL array; rad per axis).
    pub misalignment_sigma: f64,
    /// Position of the sensor relative to the IMU, body axes (m), for
    /// sensors whose block takes a lever arm (a pressure depth sensor).
    pub lever_arm: Vector3<f64>,
}

impl SensorSettings {
    /// A sensor with reading noise `noise_sigma`, no bias, at 2 Hz, on time.
    pub fn new(noise_sigma: f64) -> Self {
        Self {
            noise_sigma,
            bias_sigma: 0.0,
            initial_bias: 0.0,
            bias_walk: 0.0,
            rate_hz: 2.0,
            latency_s: 0.0,
            resolution: 0.0,
            mounting: None,
            misalignment_sigma: 0.0,
            lever_arm: Vector3::zeros(),
        }
    }

    /// With a bias state of sigma `sigma`.
    pub fn bias(mut self, sigma: f64) -> Self {
        self.bias_sigma = sigma;
        self
    }

    /// Readings up to `seconds` late.
    pub fn latency(mut self, seconds: f64) -> Self {
        self.latency_s = seconds;
        self
    }

    /// Mounted with sensor-to-body rotation `c_bs`.
    pub fn mounting(mut self, c_bs: Matrix3<f64>) -> Self {
        self.mounting = Some(c_bs);
        self
    }

    /// At lever arm `r` from the IMU (body axes, m).
    pub fn lever_arm(mut self, r: Vector3<f64>) -> Self {
        self.lever_arm = r;
        self
    }
}

/// Limits of a physically meaningful estimate; outside them the navigator
/// stops with an error instead of producing numbers.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bounds {
    /// Largest speed over ground (m/s).
    pub max_speed_mps: f64,
    /// Largest height magnitude (m) above or below the ellipsoid.
    pub max_height_m: f64,
}

impl Default for Bounds {
    /// 300 m/s and 100 km.
    fn default() -> Self {
        Self {
            max_speed_mps: 300.0,
            max_height_m: 1.0e5,
        }
    }
}

/// Run-wide options.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavigatorOptions {
    /// Compass residual.
    pub compass: CompassForm,
    /// Innovation-gate probability of every sensor (`None`: no gate).
    pub gate_probability: Option<f64>,
    /// Gate lock-out release: rule and plausibility bounds
    /// ([`crate::lockout`]; `None`: a refused sensor stays refused).
    pub lockout_release: Option<crate::lockout::LockoutOptions>,
    /// Record the run for the fixed-interval smoother
    /// ([`nav_runtime::smoother`]).
    pub smooth: bool,
    /// With `smooth`: also keep the information each sensor's updates give
    /// ([`nav_runtime::smoother::SensorInformation`], for the per-sensor
    /// observability report).
    pub sensor_information: bool,
    /// False-alarm probability of the frozen-value check (`None`: off).
    pub stuck_false_alarm: Option<f64>,
    /// Physical bounds of the estimate.
    pub bounds: Bounds,
}

impl Default for NavigatorOptions {
    fn default() -> Self {
        Self {
            compass: CompassForm::Exact,
            gate_probability: Some(Gate::DEFAULT_PROBABILITY),
            lockout_release: Some(crate::lockout::LockoutOptions::default()),
            smooth: false,
            sensor_information: false,
            stuck_false_alarm: Some(StuckDetector::DEFAULT_FALSE_ALARM),
            bounds: Bounds::default(),
        }
    }
}
