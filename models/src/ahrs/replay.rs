//! `navsim replay DIR --model ahrs`: the [`Ahrs`] filter over a log's
//! `imu.csv` and `mag.csv` (`docs/ulog.md`, "Replaying an imported log").
//!
//! The nominal attitude is integrated from the bias-corrected gyro (Earth
//! rate left out, as in eq. A1); the error-state filter is propagated at
//! every IMU sample. Every [`GRAVITY_PERIOD_S`] the mean specific force of the
//! interval is fused as a gravity measurement (eq. A2) when its magnitude is
//! within [`GRAVITY_TOLERANCE`] of gravity (else the vehicle accelerates and
//! the sample is skipped); every magnetometer sample is fused as a magnetic
//! heading (eq. A3) with the declination taken from the log
//! ([`declination`]).

use std::path::Path;
use std::time::Instant;

use nav_runtime::attitude::{correct_c_bn, euler_from_c_bn, rotation_from_rotvec, Euler};
use nav_runtime::earth::normal_gravity;
use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::{ErrorStateFilter, NominalState};
use nav_runtime::log::{Event, LogDir};
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use serde_json::{json, Value};

use super::heading::magnetic_heading;
use super::model::{Ahrs, AhrsGravity, AhrsHeading, AhrsInput, AhrsNoise, AhrsParams};
use crate::harness::plot;
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunHealth, RunTable};
use crate::navigator::SensorHealth;
use crate::ulog::reference::EstimatePoint;
use crate::ulog::replay::{attitude_errors, count, declination, reference_metrics, rpy_json, wrap};

/// `navsim replay --model ahrs`.
pub const NAME: &str = "ahrs";

/// Interval of the gravity measurement (mean specific force), s.
pub const GRAVITY_PERIOD_S: f64 = 0.1;
/// A mean specific force further than this from gravity is an acceleration:
/// the gravity measurement is skipped, m/s^2.
pub const GRAVITY_TOLERANCE: f64 = 0.5;
/// Smallest sigma of the gravity measurement (the vehicle's unmodelled
/// horizontal accelerations, which averaging does not remove), m/s^2.
pub const GRAVITY_SIGMA_FLOOR: f64 = 0.2;
/// Gyro bias random walk, rad/s^1.5 (PX4 EKF2's default `EKF2_GYR_B_NOISE`).
pub const GYRO_BIAS_WALK: f64 = 1e-3;
/// Magnetometer noise when `meta.toml` has no `[sensors.mag]`, gauss
/// (PX4's default `EKF2_MAG_NOISE`).
pub const MAG_NOISE_DEFAULT: f64 = 0.05;
/// Initial roll and pitch sigma without `[initial_sigma] level`, rad.
pub const LEVEL_SIGMA_DEFAULT: f64 = 0.05;
/// Initial heading sigma without `[initial_sigma] heading`, rad.
pub const HEADING_SIGMA_DEFAULT: f64 = 0.1;
/// Initial gyro bias sigma without `[sensors.imu] gyro_bias_sigma`, rad/s.
pub const GYRO_BIAS_SIGMA_DEFAULT: f64 = 0.01;
/// An IMU interval longer than this is not propagated (a gap), s.
pub const MAX_IMU_STEP_S: f64 = 0.5;

/// The log files the model reads.
pub const FILES: &[&str] = &["imu.csv", "mag.csv", "reference.csv", "truth.csv"];

/// The nominal attitude and the running gyro bias correction.
#[derive(Clone, Debug)]
pub struct AhrsNominal {
    /// Body to NED.
    pub c_bn: Matrix3<f64>,
    /// Gyro bias correction, subtracted from the samples, rad/s.
    pub gyro_bias: Vector3<f64>,
}

impl NominalState<6> for AhrsNominal {
    fn inject(&mut self, e: &SVector<f64, 6>) {
        self.c_bn = correct_c_bn(&self.c_bn, &Vector3::new(e[0], e[1], e[2]));
        self.gyro_bias += Vector3::new(e[3], e[4], e[5]);
    }
}

impl AhrsNominal {
    /// Roll, pitch, yaw, rad.
    pub fn euler(&self) -> [f64; 3] {
        let e = euler_from_c_bn(&self.c_bn);
        [e.roll, e.pitch, e.yaw]
    }
}

/// The replay model `ahrs`.
#[derive(Debug, Clone, Copy, Default)]
pub struct AhrsReplay;

/// The median IMU interval, s.
pub fn imu_period(log: &LogDir) -> f64 {
    let mut d: Vec<f64> = log
        .imu
        .windows(2)
        .take(10_000)
        .map(|w| w[1].t - w[0].t)
        .collect();
    if d.is_empty() {
        return 0.01;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

/// A run of the `ahrs` filter.
#[derive(Debug, Clone, Default)]
pub struct AhrsRun {
    /// The estimate after every IMU sample.
    pub points: Vec<EstimatePoint>,
    /// `estimates` table (every gravity interval).
    pub table: RunTable,
    /// Gravity measurement counts.
    pub gravity: SensorHealth,
    /// Magnetometer counts.
    pub mag: SensorHealth,
    /// IMU intervals not propagated (gaps, time not increasing).
    pub imu_gaps: u64,
    /// IMU samples propagated.
    pub samples: usize,
    /// Declination used, rad, and the samples it was averaged over.
    pub declination: (f64, usize),
    /// Final nominal state.
    pub final_state: Option<AhrsNominal>,
    /// Covariance repairs.
    pub covariance_repairs: u64,
    /// Filter seconds.
    pub runtime_s: f64,
    /// Notes.
    pub warnings: Vec<String>,
}

/// Runs the `ahrs` filter over `log`.
///
/// # Errors
/// No initial attitude in `meta.toml`, no IMU rows, a filter set-up error.
pub fn run(log: &LogDir) -> Result<AhrsRun, RunError> {
    let init = &log.meta.initial;
    let attitude = init.attitude()?;
    let first = log
        .imu
        .first()
        .ok_or_else(|| RunError::Invalid("imu.csv: no rows".into()))?;
    let t0 = init.t.unwrap_or(first.t);
    let mut out = AhrsRun::default();
    let imu_noise = log.meta.sensors.imu;
    let dt_imu = imu_period(log);
    let gravity = normal_gravity(init.lat, -init.depth);
    let gyro_sigma = imu_noise.map_or(1.5e-2, |n| n.gyro_noise_sigma);
    let accel_sigma = imu_noise.map_or(0.35, |n| n.accel_noise_sigma);
    let bias_sigma = imu_noise
        .map(|n| n.gyro_bias_sigma)
        .filter(|s| *s > 0.0)
        .unwrap_or(GYRO_BIAS_SIGMA_DEFAULT);
    let mag_sigma = match log.meta.sensors.mag {
        Some(n) => n.noise_sigma,
        None => {
            out.warnings.push(format!(
                "meta.toml has no [sensors.mag]: magnetometer noise {MAG_NOISE_DEFAULT} gauss (PX4's default)"
            ));
            MAG_NOISE_DEFAULT
        }
    };
    let mag_rows = log.mag.as_deref().unwrap_or_default();
    out.mag.rows = mag_rows.len() as u64;
    out.declination = match declination(mag_rows, t0, attitude) {
        Some(d) => d,
        None => {
            if !mag_rows.is_empty() {
                out.warnings.push(
                    "mag.csv: no sample within 1 s of the initial estimate: declination 0".into(),
                );
            }
            (0.0, 0)
        }
    };
    if log.mag.is_none() {
        out.warnings
            .push("the log has no mag.csv: the yaw is not observed (gyro only)".into());
    }
    let sigma = log.meta.initial_sigma.unwrap_or_default();
    let level = sigma.level.unwrap_or(LEVEL_SIGMA_DEFAULT);
    let heading = sigma.heading.unwrap_or(HEADING_SIGMA_DEFAULT);
    let p0 = SMatrix::<f64, 6, 6>::from_diagonal(&SVector::from([
        level * level,
        level * level,
        heading * heading,
        bias_sigma * bias_sigma,
        bias_sigma * bias_sigma,
        bias_sigma * bias_sigma,
    ]));
    let noise = AhrsNoise {
        gyro_noise: Vector3::repeat(gyro_sigma * gyro_sigma * dt_imu),
        gyro_bias_noise: Vector3::repeat(GYRO_BIAS_WALK * GYRO_BIAS_WALK),
    };
    let params = AhrsParams { gravity };
    let ekf = Ekf::<Ahrs, 6>::new(SVector::zeros(), p0, params, noise)
        .map_err(|e| RunError::Invalid(format!("ahrs: {e}")))?;
    let nominal = AhrsNominal {
        c_bn: Euler::new(attitude[0], attitude[1], attitude[2]).c_bn(),
        gyro_bias: Vector3::zeros(),
    };
    let mut filter = ErrorStateFilter::new(ekf, nominal);
    out.table = RunTable::new(
        "estimates",
        &[
            "t",
            "roll_deg",
            "pitch_deg",
            "yaw_deg",
            "gyro_bias_x_deg_s",
            "gyro_bias_y_deg_s",
            "gyro_bias_z_deg_s",
            "sig_phi_n_deg",
            "sig_phi_e_deg",
            "sig_phi_d_deg",
        ],
    );
    let start = Instant::now();
    let mut t_prev: Option<f64> = None;
    let (mut f_sum, mut f_n, mut window_start) = (Vector3::zeros(), 0usize, f64::NAN);
    let f_nav = Vector3::new(0.0, 0.0, -gravity);
    for event in log.events() {
        match event {
            Event::Imu(row) => {
                let Some(tp) = t_prev.replace(row.t) else {
                    window_start = row.t;
                    out.points.push(point(row.t, filter.nominal()));
                    continue;
                };
                let dt = row.t - tp;
                if !(dt > 0.0 && dt <= MAX_IMU_STEP_S) {
                    out.imu_gaps += 1;
                    window_start = row.t;
                    f_sum = Vector3::zeros();
                    f_n = 0;
                    continue;
                }
                let input = AhrsInput {
                    c_bn: filter.nominal().c_bn,
                };
                filter
                    .predict(dt, &input)
                    .map_err(|e| RunError::Invalid(format!("ahrs: imu.csv t = {}: {e}", row.t)))?;
                let n = filter.nominal_mut();
                let w = Vector3::new(row.gx, row.gy, row.gz) - n.gyro_bias;
                n.c_bn *= rotation_from_rotvec(&(w * dt));
                out.samples += 1;
                f_sum += Vector3::new(row.ax, row.ay, row.az);
                f_n += 1;
                if row.t - window_start >= GRAVITY_PERIOD_S - 1e-9 {
                    let f = f_sum / f_n as f64;
                    out.gravity.rows += 1;
                    if (f.norm() - gravity).abs() > GRAVITY_TOLERANCE {
                        out.gravity.skipped += 1;
                    } else {
                        let c = filter.nominal().c_bn;
                        let z = c.transpose() * f_nav - f;
                        let s2 = (accel_sigma * accel_sigma / f_n as f64)
                            .max(GRAVITY_SIGMA_FLOOR * GRAVITY_SIGMA_FLOOR);
                        let r = filter.update_sequential::<AhrsGravity, 3>(
                            &z,
                            &SVector::repeat(s2),
                            &(),
                        );
                        count(&mut out.gravity, r);
                    }
                    f_sum = Vector3::zeros();
                    f_n = 0;
                    window_start = row.t;
                    push_estimate(&mut out.table, row.t, &filter);
                }
                out.points.push(point(row.t, filter.nominal()));
            }
            Event::Mag(row) => {
                if t_prev.is_none() {
                    out.mag.skipped += 1;
                    continue;
                }
                let [roll, pitch, yaw] = filter.nominal().euler();
                let m = [row.mx, row.my, row.mz];
                let horizontal = horizontal_field(m, roll, pitch);
                let Some(psi) = magnetic_heading(m, roll, pitch, out.declination.0) else {
                    out.mag.skipped += 1;
                    continue;
                };
                let s = (mag_sigma / horizontal).atan();
                let z = SVector::<f64, 1>::new(wrap(yaw - psi));
                let r = filter.update_sequential::<AhrsHeading, 1>(
                    &z,
                    &SVector::<f64, 1>::new(s * s),
                    &(),
                );
                count(&mut out.mag, r);
            }
            _ => {}
        }
    }
    out.runtime_s = start.elapsed().as_secs_f64();
    out.covariance_repairs = filter.ekf().counters().covariance_repairs;
    out.final_state = Some(filter.nominal().clone());
    Ok(out)
}

/// The horizontal magnitude of the body field `m` levelled with `roll`, `pitch`.
pub fn horizontal_field(m: [f64; 3], roll: f64, pitch: f64) -> f64 {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let north = m[0] * cp + (m[1] * sr + m[2] * cr) * sp;
    let east = m[1] * cr - m[2] * sr;
    north.hypot(east)
}

fn point(t: f64, n: &AhrsNominal) -> EstimatePoint {
    EstimatePoint {
        t,
        attitude: n.euler(),
        position: None,
    }
}

fn push_estimate(table: &mut RunTable, t: f64, f: &ErrorStateFilter<Ahrs, AhrsNominal, 6>) {
    let n = f.nominal();
    let p = f.covariance();
    let e = n.euler().map(f64::to_degrees);
    let b = n.gyro_bias.map(f64::to_degrees);
    table.push(&[
        t,
        e[0],
        e[1],
        e[2],
        b.x,
        b.y,
        b.z,
        p[(0, 0)].sqrt().to_degrees(),
        p[(1, 1)].sqrt().to_degrees(),
        p[(2, 2)].sqrt().to_degrees(),
    ]);
}

impl ReplayModel for AhrsReplay {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "attitude and gyro bias from gyro, accelerometer (gravity) and magnetometer (imported PX4 logs)"
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        Some(FILES)
    }
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        let run = run(log)?;
        let mut out = ReplayOutput {
            samples: run.samples,
            runtime_s: run.runtime_s,
            warnings: run.warnings.clone(),
            ..Default::default()
        };
        for file in ["baro.csv", "gnss.csv"] {
            let rows = match file {
                "baro.csv" => log.baro.as_ref().map(Vec::len),
                _ => log.gnss.as_ref().map(Vec::len),
            };
            if let Some(rows) = rows.filter(|r| *r > 0) {
                out.warnings.push(format!(
                    "model {NAME} has no {} sensor: the {rows} rows of {file} are not used",
                    &file[..file.len() - 4]
                ));
            }
        }
        let m = &mut out.metrics;
        let diff = reference_metrics(log, &run.points, m, &mut out.warnings);
        if let Some(truth) = log.truth.as_deref() {
            match attitude_errors(truth, &run.points) {
                Some((rms, seconds, table)) => {
                    m.insert("attitude_error_rms_deg".into(), rpy_json(rms));
                    m.insert("scored_seconds".into(), Value::from(seconds));
                    if options.keep_series {
                        out.tables.push(table);
                    }
                }
                None => out
                    .warnings
                    .push("truth.csv and the estimate do not overlap: nothing scored".into()),
            }
        }
        m.insert(
            "magnetic_declination_deg".into(),
            Value::from(run.declination.0.to_degrees()),
        );
        let span = match (run.points.first(), run.points.last()) {
            (Some(a), Some(b)) => b.t - a.t,
            _ => 0.0,
        };
        m.insert("replayed_seconds".into(), Value::from(span));
        let health = RunHealth {
            sensors: vec![("gravity".into(), run.gravity), ("mag".into(), run.mag)],
            covariance_repairs: run.covariance_repairs,
            replays: None,
            imu_gaps: Some(run.imu_gaps),
        };
        m.insert("health".into(), health.json());
        if let Some(f) = &run.final_state {
            let e = f.euler().map(f64::to_degrees);
            let b = f.gyro_bias.map(f64::to_degrees);
            m.insert(
                "final".into(),
                json!({"roll": e[0], "pitch": e[1], "yaw": e[2],
                       "gyro_bias_deg_s": [b.x, b.y, b.z]}),
            );
        }
        if options.keep_series {
            out.tables.push(run.table);
            out.tables.extend(diff);
        }
        Ok(out)
    }
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        write_outputs(NAME, output, dir)
    }
}

/// Writes every table as CSV and the plots of the reference differences
/// (`attitude_difference.svg`, `horizontal_difference.svg` with positions)
/// and of the truth errors (`attitude_errors.svg`).
pub fn write_outputs(name: &str, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
    for t in &output.tables {
        t.write_csv(&dir.join(format!("{}.csv", t.name)))?;
        let time = t.column("t");
        let plot3 = |file: &str, title: &str, y: &str, cols: [&str; 3]| -> Result<(), RunError> {
            let ys: Vec<Vec<f64>> = cols.iter().map(|c| t.column(c)).collect();
            let labels = ["roll", "pitch", "yaw"];
            let lines: Vec<plot::Line<'_>> = ys
                .iter()
                .zip(labels)
                .map(|(y, label)| plot::Line { label, x: &time, y })
                .collect();
            plot::lines(&dir.join(file), title, "t [s]", y, &lines)
        };
        match t.name.as_str() {
            "reference_difference" => {
                plot3(
                    "attitude_difference.svg",
                    &format!("{name}: attitude minus PX4's estimate"),
                    "difference [deg]",
                    ["diff_roll_deg", "diff_pitch_deg", "diff_yaw_deg"],
                )?;
                let (n, e) = (t.column("diff_n_m"), t.column("diff_e_m"));
                if n.iter().any(|v| v.is_finite()) {
                    let lines = [
                        plot::Line {
                            label: "north",
                            x: &time,
                            y: &n,
                        },
                        plot::Line {
                            label: "east",
                            x: &time,
                            y: &e,
                        },
                    ];
                    plot::lines(
                        &dir.join("horizontal_difference.svg"),
                        &format!("{name}: position minus PX4's estimate"),
                        "t [s]",
                        "difference [m]",
                        &lines,
                    )?;
                }
            }
            "attitude_errors" => plot3(
                "attitude_errors.svg",
                &format!("{name}: attitude error against truth.csv"),
                "error [deg]",
                ["err_roll_deg", "err_pitch_deg", "err_yaw_deg"],
            )?,
            _ => {}
        }
    }
    Ok(())
}
