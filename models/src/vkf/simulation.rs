//! Synthetic logs of the VKF run (docs/results/vkf.md; paper section 3): 27 min
//! at 10 kn, IMU at 100 Hz (0.1 deg/h class), DVL, RPM and echo sounder at 5 Hz,
//! truth at 5 Hz, over a sea floor that takes the DVL out of range twice.
//!
//! The IMU log holds interval averages `dtheta / dt`, `dv / dt` of an integrating
//! IMU (exact increments of the truth, so the coning and sculling motion is in
//! the data); the navigator turns them back into increments.

use nav_runtime::earth::Geodetic;
use nav_runtime::imu::{self, ImuModel, ImuSpec, DEG_PER_HOUR, UG};
use nav_runtime::log::{
    AltitudeRow, DvlRow, ImuNoise, ImuRow, LogDir, Meta, RpmRow, SensorNoise, TruthRow,
};
use nav_runtime::nalgebra::Vector3;
use nav_runtime::sensors::{derive_seed, normal, Draw, ErrorSpec, ScalarSensor, SensorErrorModel};
use nav_runtime::trajectory::{scenarios, Trajectory, TruthSource};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Duration of the run (s): 27 min.
pub const DURATION: f64 = 1620.0;
/// IMU rate (Hz).
pub const IMU_RATE: f64 = 100.0;
/// DVL, RPM, echo-sounder and truth rate (Hz).
pub const AIDING_RATE: f64 = 5.0;
/// Cruise speed (m/s): 10 kn.
pub const CRUISE_SPEED: f64 = 10.0 * KNOT;
/// One knot in m/s.
pub const KNOT: f64 = 1852.0 / 3600.0;
/// Vehicle depth (m).
pub const VEHICLE_DEPTH: f64 = 30.0;
/// DVL bottom-lock range (m of altitude): beyond it the DVL output is noise.
pub const DVL_RANGE: f64 = 100.0;
/// Half-width of the uniform noise on an out-of-range DVL output (m/s, paper: about +-5).
pub const OUT_OF_RANGE_NOISE: f64 = 5.0;
/// DVL white noise per sample and axis (m/s; the paper gives none).
pub const DVL_NOISE: f64 = 0.02;
/// DVL scale-factor error half-width (fraction, paper: +-0.2 %).
pub const DVL_SCALE: f64 = 0.002;
/// Echo-sounder noise per sample (m).
pub const ALTITUDE_NOISE: f64 = 0.3;
/// RPM read-out noise per sample (rpm).
pub const RPM_NOISE: f64 = 0.5;
/// Speed disturbance (through-water speed not explained by the RPM: sea state,
/// loading), first-order Gauss-Markov: 1-sigma (m/s) and correlation time (s).
pub const SPEED_DISTURBANCE: (f64, f64) = (0.01, 120.0);

/// The DVL bias of a run, uniform per body axis within +-half-width.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DvlBias {
    /// +-0.005 m/s: a modern bottom-tracking DVL.
    Realistic,
    /// +-0.5 m/s, the paper's figure.
    Paper,
}

impl DvlBias {
    /// Half-width of the uniform bias (m/s).
    pub fn half_width(self) -> f64 {
        match self {
            DvlBias::Realistic => 0.005,
            DvlBias::Paper => 0.5,
        }
    }
}

/// The IMU: Honeywell HG1700 figures improved tenfold (paper Table 1):
/// gyro bias 0.1 deg/h, angle random walk 0.0125 deg/sqrt(h); accelerometer bias
/// 0.1 mg, velocity random walk 0.0065 m/s/sqrt(h). Per-sample 1-sigma at 100 Hz.
pub fn imu_spec() -> ImuSpec {
    let arw: f64 = 0.0125 / 60.0; // deg/sqrt(s)
    let vrw = 0.0065 / 60.0; // m/s/sqrt(s)
    let root_rate = IMU_RATE.sqrt();
    ImuSpec {
        accel_bias: 0.1e3 * UG,
        accel_noise: vrw * root_rate,
        gyro_bias: 0.1 * DEG_PER_HOUR,
        gyro_noise: arw.to_radians() * root_rate,
        accel_scale: 0.0,
        gyro_scale: 0.0,
    }
}

/// The truth trajectory: the `vkf_run` preset (10 kn, heading north, 30 deg
/// course changes at 600 s and 1100 s) at 30 m depth, with gentle speed changes
/// (9 to 11 kn before the first outage, 9.5 kn during the second) so that the RPM
/// map is exercised over a range of speeds.
pub fn trajectory() -> Trajectory {
    let start: Geodetic = scenarios::sdins25_start(VEHICLE_DEPTH);
    let mut spec = scenarios::vkf_run(start, 0.0);
    for (t0, delta_kn) in [
        (60.0, -1.0),
        (150.0, 2.0),
        (230.0, -1.0),
        (910.0, -0.5),
        (1000.0, 0.5),
        (1250.0, 0.5),
        (1400.0, -0.5),
    ] {
        spec.change_speed(t0, 30.0, delta_kn * KNOT);
    }
    spec.build(DURATION)
}

/// Cubic smooth step: 0 before 0, 1 after 1.
fn smooth(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    s * s * (3.0 - 2.0 * s)
}

/// Altitude of the vehicle above the sea floor along the track at time `t` (m):
/// about 80 m over the shelf, about 230 m over two trenches crossed at about
/// 295-485 s and 895-965 s (paper: 5-8 min and 15-16 min).
pub fn true_altitude(t: f64) -> f64 {
    let trench = |a: f64, b: f64| smooth((t - a) / 20.0) - smooth((t - b) / 20.0);
    80.0 + 150.0 * (trench(290.0, 470.0) + trench(890.0, 950.0)) + 4.0 * (t / 37.0).sin()
}

/// Whether the DVL has bottom lock at altitude `altitude` (m).
pub fn dvl_in_range(altitude: f64) -> bool {
    altitude <= DVL_RANGE
}

/// The propeller's true speed map `V(rpm)` (m/s) of one run: linear with a
/// slight quadratic curvature, `V = s rpm + c + k (rpm - 300)^2`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RpmMap {
    /// Slope at 300 rpm, (m/s)/rpm.
    pub slope: f64,
    /// Offset, m/s.
    pub offset: f64,
    /// Curvature, (m/s)/rpm^2.
    pub curvature: f64,
}

impl RpmMap {
    /// The design map: 10 kn at 300 rpm.
    pub const NOMINAL: RpmMap = RpmMap {
        slope: 0.018,
        offset: CRUISE_SPEED - 0.018 * 300.0,
        curvature: -1e-5,
    };

    /// A run's map: slope within 3 %, offset within 0.1 m/s of the design (1-sigma).
    pub fn drawn(seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "vkf-rpm-map"));
        let n = Self::NOMINAL;
        RpmMap {
            slope: n.slope * (1.0 + normal(&mut rng, 0.03)),
            offset: n.offset + normal(&mut rng, 0.1),
            curvature: n.curvature,
        }
    }

    /// Speed at `rpm` (m/s).
    pub fn speed(&self, rpm: f64) -> f64 {
        self.slope * rpm + self.offset + self.curvature * (rpm - 300.0).powi(2)
    }

    /// Local linearization at `rpm`: the tangent's `(sf, b)`, what the velocity
    /// filter can learn at that operating point.
    pub fn tangent(&self, rpm: f64) -> (f64, f64) {
        let sf = self.slope + 2.0 * self.curvature * (rpm - 300.0);
        (sf, self.speed(rpm) - sf * rpm)
    }

    /// RPM that gives `speed` (Newton's method; the map is monotonic here).
    pub fn rpm_for(&self, speed: f64) -> f64 {
        let mut r = (speed - self.offset) / self.slope;
        for _ in 0..8 {
            let (sf, _) = self.tangent(r);
            r -= (self.speed(r) - speed) / sf;
        }
        r
    }
}

/// One run's truth-side constants, kept for scoring and plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RunTruth {
    /// The RPM map.
    pub map: RpmMap,
    /// DVL bias per body axis (m/s) of the realistic variant (the paper variant's
    /// is 100 times larger: the same uniform draw).
    pub dvl_bias: Vector3<f64>,
    /// DVL scale-factor error per body axis.
    pub dvl_scale: Vector3<f64>,
}

/// The logs of one run: the same IMU, RPM, echo sounder, DVL noise and truth,
/// with the realistic and the paper DVL bias.
#[derive(Clone, Debug)]
pub struct RunLogs {
    /// Realistic DVL bias (+-0.005 m/s).
    pub realistic: LogDir,
    /// The paper's DVL bias (+-0.5 m/s).
    pub paper: LogDir,
    /// Truth-side constants.
    pub truth: RunTruth,
}

/// Simulates run `seed`.
pub fn simulate(seed: u64) -> RunLogs {
    let truth = trajectory();
    let spec = imu_spec();
    let mut imu_model = ImuModel::new(spec, derive_seed(seed, "vkf-imu"));
    let imu_rows: Vec<ImuRow> = imu::increments(&truth, IMU_RATE, DURATION)
        .map(|inc| {
            let m = imu_model.corrupt_increment(&inc);
            let (w, f) = (m.dtheta / m.dt, m.dv / m.dt);
            ImuRow::new(m.t, w.x, w.y, w.z, f.x, f.y, f.z)
        })
        .collect();

    let map = RpmMap::drawn(seed);
    let mut rpm_rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "vkf-rpm"));
    let mut alt_sensor = ScalarSensor::new(
        ErrorSpec::gaussian(0.0, ALTITUDE_NOISE),
        derive_seed(seed, "vkf-altitude"),
    );
    let dvl_spec = |half: f64| ErrorSpec {
        bias: Draw::Uniform(half),
        scale: Draw::Uniform(DVL_SCALE),
        noise: DVL_NOISE,
    };
    let dvl_seed = derive_seed(seed, "vkf-dvl");
    let mut dvl_real =
        SensorErrorModel::<3>::new(dvl_spec(DvlBias::Realistic.half_width()), dvl_seed);
    let mut dvl_paper = SensorErrorModel::<3>::new(dvl_spec(DvlBias::Paper.half_width()), dvl_seed);
    let mut garbage_rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "vkf-dvl-out-of-range"));

    let (sigma_d, tau_d) = SPEED_DISTURBANCE;
    let phi = (-1.0 / (AIDING_RATE * tau_d)).exp();
    let mut disturbance = normal(&mut rpm_rng, sigma_d);

    let n = (DURATION * AIDING_RATE).round() as usize;
    let mut dvl_r = Vec::with_capacity(n);
    let mut dvl_p = Vec::with_capacity(n);
    let mut rpm_rows = Vec::with_capacity(n);
    let mut alt_rows = Vec::with_capacity(n);
    let mut truth_rows = Vec::with_capacity(n + 1);
    for k in 0..=n {
        let t = k as f64 / AIDING_RATE;
        let s = truth.truth(t);
        truth_rows.push(TruthRow::from(&s));
        if k == 0 {
            continue;
        }
        // RPM: the through-water speed minus the disturbance, through the inverse map.
        disturbance = phi * disturbance + normal(&mut rpm_rng, sigma_d * (1.0 - phi * phi).sqrt());
        let v_b = s.v_body();
        let rpm = map.rpm_for(v_b.x - disturbance) + normal(&mut rpm_rng, RPM_NOISE);
        rpm_rows.push(RpmRow::new(t, rpm));
        let alt = true_altitude(t);
        alt_rows.push(AltitudeRow::new(t, alt_sensor.measure_scalar(alt).max(0.0)));
        // DVL: one noise draw shared by both bias variants; out of range the
        // output gets uniform noise within +-5 m/s per axis.
        let mut zr = dvl_real.measure(&v_b);
        let mut zp = dvl_paper.measure(&v_b);
        if !dvl_in_range(alt) {
            let junk = Vector3::from_fn(|_, _| {
                OUT_OF_RANGE_NOISE * (2.0 * garbage_rng.random::<f64>() - 1.0)
            });
            zr += junk;
            zp += junk;
        }
        dvl_r.push(DvlRow::new(t, Some(zr.x), Some(zr.y), Some(zr.z)));
        dvl_p.push(DvlRow::new(t, Some(zp.x), Some(zp.y), Some(zp.z)));
    }

    let s0 = truth.truth(0.0);
    let mut meta = Meta::at(s0.lat, s0.lon, s0.depth());
    meta.initial.vn = s0.v_n.x;
    meta.initial.ve = s0.v_n.y;
    meta.initial.vd = s0.v_n.z;
    meta.initial.roll = Some(s0.euler.roll);
    meta.initial.pitch = Some(s0.euler.pitch);
    meta.initial.yaw = Some(s0.euler.yaw);
    meta.sensors.imu = Some(ImuNoise {
        gyro_bias_sigma: spec.gyro_bias,
        gyro_noise_sigma: spec.gyro_noise,
        accel_bias_sigma: spec.accel_bias,
        accel_noise_sigma: spec.accel_noise,
    });
    meta.sensors.rpm = Some(SensorNoise {
        bias_sigma: 0.0,
        noise_sigma: RPM_NOISE,
    });
    meta.sensors.altitude = Some(SensorNoise {
        bias_sigma: 0.0,
        noise_sigma: ALTITUDE_NOISE,
    });
    let log_with = |dvl: Vec<DvlRow>, bias: DvlBias| {
        let mut m = meta;
        m.sensors.dvl = Some(SensorNoise {
            bias_sigma: bias.half_width() / 3f64.sqrt(),
            noise_sigma: DVL_NOISE,
        });
        let mut log = LogDir::new(m);
        log.imu = imu_rows.clone();
        log.dvl = Some(dvl);
        log.rpm = Some(rpm_rows.clone());
        log.altitude = Some(alt_rows.clone());
        log.truth = Some(truth_rows.clone());
        log
    };
    RunLogs {
        realistic: log_with(dvl_r, DvlBias::Realistic),
        paper: log_with(dvl_p, DvlBias::Paper),
        truth: RunTruth {
            map,
            dvl_bias: dvl_real.bias,
            dvl_scale: dvl_real.scale,
        },
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outages_where_the_paper_has_them() {
        // Out of range during about 5-8 min and 15-16 min, in range elsewhere.
        let out: Vec<f64> = (0..=16200)
            .map(|k| k as f64 * 0.1)
            .filter(|&t| !dvl_in_range(true_altitude(t)))
            .collect();
        let total = out.len() as f64 * 0.1;
        assert!((240.0..300.0).contains(&total), "{total}");
        assert!(out
            .iter()
            .all(|&t| (285.0..500.0).contains(&t) || (885.0..980.0).contains(&t)));
        assert!(!dvl_in_range(true_altitude(400.0)) && !dvl_in_range(true_altitude(930.0)));
        assert!(dvl_in_range(true_altitude(200.0)) && dvl_in_range(true_altitude(1500.0)));
    }

    #[test]
    fn rpm_map_inverts_and_linearizes() {
        let m = RpmMap::drawn(3);
        for v in [4.0, 5.144, 6.0] {
            assert!((m.speed(m.rpm_for(v)) - v).abs() < 1e-12);
        }
        let (sf, b) = m.tangent(320.0);
        assert!((sf * 320.0 + b - m.speed(320.0)).abs() < 1e-12);
        assert!((RpmMap::NOMINAL.speed(300.0) - CRUISE_SPEED).abs() < 1e-12);
    }
}
