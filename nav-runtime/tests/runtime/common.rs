//! Helpers shared by the log tests.
#![allow(dead_code)]

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use nav_runtime::log::*;

/// A fresh, empty temporary directory, removed on drop.
pub struct TempDir(pub PathBuf);

impl TempDir {
    pub fn new(tag: &str) -> TempDir {
        static N: AtomicUsize = AtomicUsize::new(0);
        let p = std::env::temp_dir().join(format!(
            "nav-log-test-{}-{tag}-{}",
            std::process::id(),
            N.fetch_add(1, Ordering::Relaxed)
        ));
        let _ = std::fs::remove_dir_all(&p);
        std::fs::create_dir_all(&p).unwrap();
        TempDir(p)
    }
    pub fn path(&self) -> &Path {
        &self.0
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A small log with every sensor, DVL lock gaps and awkward float values.
pub fn sample_log() -> LogDir {
    let mut meta = Meta::at(0.7, -0.3, 12.5);
    meta.initial.vn = 1.25;
    meta.initial.roll = Some(0.01);
    meta.initial.pitch = Some(-0.02);
    meta.initial.yaw = Some(3.0);
    meta.initial_sigma = Some(InitialSigma {
        position: Some(2.0),
        velocity: Some(0.1),
        level: Some(0.001),
        heading: None,
    });
    meta.sensors.imu = Some(ImuNoise {
        gyro_bias_sigma: 1e-5,
        gyro_noise_sigma: 3.3e-7,
        accel_bias_sigma: 0.001,
        accel_noise_sigma: 0.0123,
    });
    meta.sensors.dvl = Some(SensorNoise {
        bias_sigma: 0.0,
        noise_sigma: 0.01,
    });
    meta.sensors.usbl = Some(SensorNoise {
        bias_sigma: 0.5,
        noise_sigma: 2.0,
    });
    meta.usbl = Some(UsblTransducer {
        lat: 0.7001,
        lon: -0.3001,
        depth: 1.5,
    });
    let mut log = LogDir::new(meta);
    for i in 0..40 {
        let t = i as f64 * 0.01;
        log.imu.push(ImuRow::new(
            t,
            1e-300 * i as f64,
            -0.1 + 0.2,
            7.0e20,
            0.1 * t,
            -0.0,
            -9.81,
        ));
    }
    log.dvl = Some(vec![
        DvlRow::new(0.05, Some(1.0), Some(0.01), Some(-0.002)),
        DvlRow::new(0.15, None, None, None),
        DvlRow::new(0.25, Some(1.1), None, Some(0.0)),
    ]);
    log.depth = Some(vec![DepthRow::new(0.1, 12.5), DepthRow::new(0.2, 12.51)]);
    log.heading = Some(vec![HeadingRow::new(0.1, -3.1)]);
    log.usbl = Some(vec![UsblRow::new(0.3, 0.7, -0.3, 12.4)]);
    log.speed = Some(vec![SpeedRow::new(0.0, 1.2)]);
    log.rpm = Some(vec![]);
    log.altitude = Some(vec![AltitudeRow::new(0.35, 20.0)]);
    log.truth = Some(vec![
        TruthRow::new(0.0, 0.7, -0.3, 12.5, 1.2, 0.0, 0.0, 0.0, 0.0, 3.0),
        TruthRow::new(0.2, 0.7000001, -0.3, 12.5, 1.2, 0.0, 0.0, 0.0, 0.0, 3.0),
    ]);
    log
}

/// Writes `sample_log` into a fresh temp dir.
pub fn sample_dir(tag: &str) -> TempDir {
    let dir = TempDir::new(tag);
    sample_log().write(dir.path()).unwrap();
    dir
}
