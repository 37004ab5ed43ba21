//! Synthetic logs for the leveling scenarios (docs/models/leveling6.md, leveling paper
//! section IV): 30 s, IMU at 100 Hz, speed log at 10 Hz, truth at 10 Hz.

use nav_runtime::earth::Geodetic;
use nav_runtime::imu::{self, ImuErrors, ImuModel, ImuSpec};
use nav_runtime::log::ImuNoise;
use nav_runtime::log::{ImuRow, LogDir, Meta, SensorNoise, SpeedRow, TruthRow};
use nav_runtime::nalgebra::Vector3;
use nav_runtime::sensors::{derive_seed, Draw, ErrorSpec, ScalarSensor};
use nav_runtime::trajectory::{scenarios, Trajectory, TruthSource};

/// Duration of one leveling run (s), as in the paper.
pub const DURATION: f64 = 30.0;
/// IMU rate (Hz).
pub const IMU_RATE: f64 = 100.0;
/// Speed-log rate (Hz).
pub const SPEED_RATE: f64 = 10.0;
/// Cruise speed of the moving cases (m/s); the paper gives none.
pub const SPEED: f64 = 2.0;
/// Heading-rate amplitude of the S-type track (rad/s) and its period (s): the
/// heading weaves by +-amp period / pi = +-38 deg.
pub const S_TYPE_AMPLITUDE: f64 = 0.104_719_755_119_659_77; // 6 deg/s, the vehicle's turn-rate limit
/// Period of the S-type weave (s).
pub const S_TYPE_PERIOD: f64 = 20.0;

/// The three motions of the paper.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Motion {
    /// S-type (weaving) track, Fig. 5(b): the moving case of Figs. 6-7.
    SType,
    /// Straight track, Fig. 5(a).
    Straight,
    /// At rest (Figs. 8-9).
    Stationary,
}

impl Motion {
    /// Whether the stationary measurement model applies.
    pub fn is_stationary(self) -> bool {
        self == Motion::Stationary
    }
}

/// How the run's constant sensor errors are chosen.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Biases {
    /// The paper's 1-sigma values on every axis in every run (1 mg, 1 deg/h,
    /// 0.1 m/s): only noise and initial errors vary, as the paper's tiny
    /// stationary spread implies.
    OneSigma,
    /// A new draw per run from the 1-sigma values.
    Drawn,
}

/// The truth trajectory of a motion: from the SDINS-25 start point at 10 m depth,
/// heading north.
pub fn trajectory(motion: Motion) -> Trajectory {
    let start: Geodetic = scenarios::sdins25_start(10.0);
    let spec = match motion {
        Motion::SType => scenarios::s_type(start, 0.0, SPEED, S_TYPE_AMPLITUDE, S_TYPE_PERIOD),
        Motion::Straight => scenarios::straight(start, 0.0, SPEED),
        Motion::Stationary => scenarios::straight(start, 0.0, 0.0),
    };
    spec.build(DURATION)
}

/// A seeded log of one run: imu.csv, speed.csv (zero when stationary), truth.csv
/// and meta.toml (initial position, velocity and yaw; roll and pitch are left out:
/// leveling starts with no attitude knowledge).
pub fn simulate(motion: Motion, biases: Biases, seed: u64) -> LogDir {
    let truth = trajectory(motion);
    let spec = ImuSpec::leveling6();
    let imu_seed = derive_seed(seed, "leveling-imu");
    let mut imu_model = match biases {
        Biases::OneSigma => ImuModel::with_errors(
            spec,
            ImuErrors {
                accel_bias: Vector3::repeat(spec.accel_bias),
                gyro_bias: Vector3::repeat(spec.gyro_bias),
                ..ImuErrors::default()
            },
            imu_seed,
        ),
        Biases::Drawn => ImuModel::new(spec, imu_seed),
    };
    let speed_spec = match biases {
        Biases::OneSigma => ErrorSpec {
            bias: Draw::Fixed(0.1),
            scale: Draw::Zero,
            noise: 0.1,
        },
        Biases::Drawn => ErrorSpec::leveling6_speed_log(),
    };
    let mut speed_log = ScalarSensor::new(speed_spec, derive_seed(seed, "leveling-speed"));

    let imu_rows: Vec<ImuRow> = imu::rates(&truth, IMU_RATE, DURATION)
        .map(|r| ImuRow::from(&imu_model.corrupt_rate(&r)))
        .collect();
    let n_speed = (DURATION * SPEED_RATE).round() as usize;
    let speed_rows: Vec<SpeedRow> = (1..=n_speed)
        .map(|k| {
            let t = k as f64 / SPEED_RATE;
            let s = truth.truth(t);
            // A stationary vehicle's log reads exactly zero (paper section IV.3).
            let v = if motion.is_stationary() {
                0.0
            } else {
                speed_log.measure_scalar(s.v_body().x)
            };
            SpeedRow::new(t, v)
        })
        .collect();
    let truth_rows: Vec<TruthRow> = (0..=n_speed)
        .map(|k| TruthRow::from(&truth.truth(k as f64 / SPEED_RATE)))
        .collect();

    let s0 = truth.truth(0.0);
    let mut meta = Meta::at(s0.lat, s0.lon, s0.depth());
    meta.initial.vn = s0.v_n.x;
    meta.initial.ve = s0.v_n.y;
    meta.initial.vd = s0.v_n.z;
    meta.initial.yaw = Some(s0.euler.yaw);
    meta.sensors.imu = Some(ImuNoise {
        gyro_bias_sigma: spec.gyro_bias,
        gyro_noise_sigma: spec.gyro_noise,
        accel_bias_sigma: spec.accel_bias,
        accel_noise_sigma: spec.accel_noise,
    });
    meta.sensors.speed = Some(SensorNoise {
        bias_sigma: 0.1,
        noise_sigma: 0.1,
    });

    let mut log = LogDir::new(meta);
    log.imu = imu_rows;
    log.speed = Some(speed_rows);
    log.truth = Some(truth_rows);
    log
}
