//! The Allan coefficients as the noise parameters of the log format: the
//! `[sensors.imu]` section of `meta.toml` (docs/log-format.md), whose
//! sigmas are per sample at the file's rate (docs/models/conventions.md,
//! item 8: a density `q = sigma^2 dt`, so `sigma = N / sqrt(dt)`).

use core::fmt::Write;

use super::{AllanReport, SensorKind};

/// The `[sensors.imu]` values of a report; `None` where no axis of the
/// triad reached the term.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuNoiseEstimate {
    /// `gyro_noise_sigma`: the largest gyro angle random walk over
    /// `sqrt(period)`, rad/s per sample.
    pub gyro_noise_sigma: Option<f64>,
    /// `accel_noise_sigma`: the largest velocity random walk over
    /// `sqrt(period)`, m/s^2 per sample.
    pub accel_noise_sigma: Option<f64>,
    /// The largest gyro bias instability, rad/s: proposed as
    /// `gyro_bias_sigma` (see [`AllanReport::imu_section`]).
    pub gyro_bias_instability: Option<f64>,
    /// The largest accelerometer bias instability, m/s^2.
    pub accel_bias_instability: Option<f64>,
}

impl AllanReport {
    /// The noise parameters of the log format. The model has one sigma per
    /// triad, so the largest axis is taken (the filter is then never more
    /// confident than the noisiest axis warrants).
    pub fn noise(&self) -> ImuNoiseEstimate {
        let largest = |kind: SensorKind, pick: &dyn Fn(&super::AxisReport) -> Option<f64>| {
            self.axes
                .iter()
                .filter(|a| a.kind == kind)
                .filter_map(pick)
                .fold(None, |m: Option<f64>, v| Some(m.map_or(v, |m| m.max(v))))
        };
        let per_sample = 1.0 / self.period_s.sqrt();
        ImuNoiseEstimate {
            gyro_noise_sigma: largest(SensorKind::Gyro, &|a| a.white.value())
                .map(|n| n * per_sample),
            accel_noise_sigma: largest(SensorKind::Accelerometer, &|a| a.white.value())
                .map(|n| n * per_sample),
            gyro_bias_instability: largest(SensorKind::Gyro, &|a| a.bias_instability.value()),
            accel_bias_instability: largest(SensorKind::Accelerometer, &|a| {
                a.bias_instability.value()
            }),
        }
    }

    /// The `[sensors.imu]` section of a `meta.toml` (with its header line),
    /// ready to paste or to write with `--write`.
    ///
    /// The noise sigmas are the per-sample sigmas at this record's rate. The
    /// bias sigmas of the format are the prior of a constant bias, which one
    /// static record cannot measure (the turn-on bias changes from run to
    /// run); the bias instability is written in their place as the floor of
    /// that prior (the bias is never known better than it wanders), and
    /// said so in a comment. A term the curve did not reach is left out with
    /// a comment saying why: a required noise key then stays missing, and
    /// reading the file fails on it rather than on a made-up value.
    pub fn imu_section(&self) -> String {
        let e = self.noise();
        let rate = 1.0 / self.period_s;
        let mut s = String::new();
        let _ = writeln!(
            s,
            "[sensors.imu]        # from the Allan deviation of a static record: {} samples at {rate:.6} Hz",
            self.samples
        );
        let mut key = |name: &str, value: Option<f64>, note: &str| {
            let _ = match value {
                Some(v) => writeln!(s, "{name} = {v:.6e}   # {note}"),
                None => writeln!(s, "# {name}: not reached ({note}); the record is too short or another noise dominates"),
            };
        };
        key(
            "gyro_noise_sigma",
            e.gyro_noise_sigma,
            "rad/s per sample: angle random walk / sqrt(period)",
        );
        key(
            "accel_noise_sigma",
            e.accel_noise_sigma,
            "m/s^2 per sample: velocity random walk / sqrt(period)",
        );
        key(
            "gyro_bias_sigma",
            e.gyro_bias_instability,
            "rad/s: bias instability, a floor for the bias prior (the turn-on bias is not measured)",
        );
        key(
            "accel_bias_sigma",
            e.accel_bias_instability,
            "m/s^2: bias instability, a floor for the bias prior (the turn-on bias is not measured)",
        );
        s
    }
}
