//! A survey whose DVL file runs on another clock: the lawn-mowing survey of
//! [`super::simulation`] with a speed change every 40 s, so that the
//! body-frame velocity changes (a DVL's clock offset shows only then: a
//! reading of a constant body velocity is the same at any time), a precise
//! bottom-tracking DVL (0.01 m/s noise, no bias, 1 Hz) whose rows are stamped
//! `late_s` seconds after the time they measure, a depth meter and a
//! compass (docs/tuning.md, "Clock offsets"). The true correction of the
//! DVL file's `time.offset_s` is `-late_s`.

use nav_runtime::imu::{self, ImuModel, ImuSpec};
use nav_runtime::log::{
    DepthRow, DvlRow, HeadingRow, ImuNoise, ImuRow, LogDir, SensorNoise, TruthRow,
};
use nav_runtime::sensors::{derive_seed, normal, ErrorSpec, SensorErrorModel};
use nav_runtime::trajectory::{scenarios, TruthSource};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::simulation::{initial_meta, sensor_noise, DURATION, IMU_RATE, TRUTH_RATE};

/// The DVL's noise, m/s (a bottom-tracking DVL at a few metres' altitude).
pub const DVL_NOISE: f64 = 0.01;

/// The speed changes: +-0.8 m/s over 4 s, alternating, every 40 s from 15 s.
const SPEED_STEP: f64 = 0.8;

/// The log of `seed` with the DVL stamped `late_s` late.
pub fn clock_survey(seed: u64, late_s: f64) -> LogDir {
    let mut spec = scenarios::sdins25_lawn_mower();
    for k in 0..12 {
        let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
        spec.change_speed(15.0 + 40.0 * k as f64, 4.0, sign * SPEED_STEP);
    }
    let truth = spec.build(DURATION);
    let imu_spec = ImuSpec::sdins25();
    let mut imu_model = ImuModel::new(imu_spec, derive_seed(seed, "clock-survey-imu"));
    let imu_rows: Vec<ImuRow> = imu::rates(&truth, IMU_RATE, DURATION)
        .map(|r| ImuRow::from(&imu_model.corrupt_rate(&r)))
        .collect();
    let mut meta = initial_meta(&truth.truth(0.0), seed);
    meta.sensors.imu = Some(ImuNoise {
        gyro_bias_sigma: imu_spec.gyro_bias,
        gyro_noise_sigma: imu_spec.gyro_noise,
        accel_bias_sigma: imu_spec.accel_bias,
        accel_noise_sigma: imu_spec.accel_noise,
    });
    let mut log = LogDir::new(meta);
    let seconds: Vec<f64> = (1..=DURATION as usize).map(|k| k as f64).collect();
    let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "clock-survey-dvl"));
    log.dvl = Some(
        seconds
            .iter()
            .map(|&t| {
                let v = truth.truth(t).v_body();
                let mut n = || normal(&mut rng, DVL_NOISE);
                DvlRow::new(
                    t + late_s,
                    Some(v.x + n()),
                    Some(v.y + n()),
                    Some(v.z + n()),
                )
            })
            .collect(),
    );
    log.meta.sensors.dvl = Some(SensorNoise {
        bias_sigma: 0.003,
        noise_sigma: DVL_NOISE,
    });
    let depth_spec = ErrorSpec::sdins25_depth();
    let mut depth = SensorErrorModel::<1>::new(depth_spec, derive_seed(seed, "clock-survey-depth"));
    log.depth = Some(
        seconds
            .iter()
            .map(|&t| DepthRow::new(t, depth.measure_scalar(truth.truth(t).depth())))
            .collect(),
    );
    log.meta.sensors.depth = Some(sensor_noise(&depth_spec));
    let compass_spec = ErrorSpec::sdins25_compass();
    let mut compass =
        SensorErrorModel::<1>::new(compass_spec, derive_seed(seed, "clock-survey-compass"));
    log.heading = Some(
        seconds
            .iter()
            .map(|&t| HeadingRow::new(t, compass.measure_angle(truth.truth(t).euler.yaw)))
            .collect(),
    );
    log.meta.sensors.heading = Some(sensor_noise(&compass_spec));
    let n_truth = (DURATION * TRUTH_RATE) as usize;
    log.truth = Some(
        (0..=n_truth)
            .map(|k| TruthRow::from(&truth.truth(k as f64 / TRUTH_RATE)))
            .collect(),
    );
    log.imu = imu_rows;
    log
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_dvl_is_stamped_late_and_the_speed_changes() {
        let late = clock_survey(3, 0.7);
        let on_time = clock_survey(3, 0.0);
        let (a, b) = (late.dvl.as_ref().unwrap(), on_time.dvl.as_ref().unwrap());
        assert_eq!(a.len(), 500);
        for (x, y) in a.iter().zip(b) {
            assert!((x.t - y.t - 0.7).abs() < 1e-12);
            assert_eq!((x.vx, x.vy, x.vz), (y.vx, y.vy, y.vz));
        }
        // Forward speed from 1.5 m/s to 2.3 m/s and back.
        let forward: Vec<f64> = b.iter().map(|r| r.vx.unwrap()).collect();
        let (lo, hi) = forward
            .iter()
            .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
        assert!(lo < 1.55 && hi > 2.25, "{lo} {hi}");
        assert_eq!(late.imu, on_time.imu);
    }
}
