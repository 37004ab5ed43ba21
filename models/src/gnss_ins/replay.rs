//! `navsim replay DIR --model gnss-ins`: the 16-state [`GnssIns`] filter
//! over a log's `imu.csv`, `gnss.csv`, `baro.csv` and `mag.csv`
//! (`docs/ulog.md`, "Replaying an imported log").
//!
//! The nominal solution is the strapdown INS with the running accelerometer,
//! gyro and barometer bias corrections; the error-state filter is propagated
//! at every IMU sample and each aiding sample is fused when it comes:
//! the GNSS position fix (antenna at the IMU; sigma the receiver's `eph` /
//! `epv`, at least `[sensors.gnss] noise_sigma`, as PX4's EKF2 does), the
//! barometric altitude with its drifting bias (the bias starts at the first
//! barometer sample minus the initial height) and the magnetic heading
//! (declination from the log, as for `ahrs`).

use std::path::Path;
use std::time::Instant;

use nav_runtime::attitude::Euler;
use nav_runtime::earth::{meridian_radius, transverse_radius, Geodetic};
use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::{ErrorStateFilter, NominalState};
use nav_runtime::log::{Event, LogDir};
use nav_runtime::model::{Record, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};
use nav_runtime::strapdown::{NavError, NavState, Strapdown};
use serde_json::{json, Value};

use super::model::{
    GnssIns, GnssInsBarometer, GnssInsGnssFix, GnssInsInput, GnssInsMagneticHeading, GnssInsNoise,
    GnssInsParams,
};
use crate::ahrs::magnetic_heading;
use crate::ahrs::replay::{horizontal_field, imu_period, write_outputs, MAG_NOISE_DEFAULT};
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunTable};
use crate::navigator::{Estimate, SensorHealth};
use crate::sdins25::score;
use crate::ulog::reference::EstimatePoint;
use crate::ulog::replay::{
    attitude_errors, count, declination, health_json, reference_metrics, rpy_json, wrap,
};

/// `navsim replay --model gnss-ins`.
pub const NAME: &str = "gnss-ins";
/// Number of states.
pub const N: usize = 16;

/// GNSS position noise without `[sensors.gnss]`, m (PX4's `EKF2_GPS_P_NOISE`).
pub const GNSS_NOISE_DEFAULT: f64 = 0.5;
/// Barometer noise without `[sensors.baro]`, m (PX4's `EKF2_BARO_NOISE`).
pub const BARO_NOISE_DEFAULT: f64 = 3.5;
/// Barometer bias random walk, m/s^0.5.
pub const BARO_BIAS_WALK: f64 = 0.05;
/// Initial position sigma without `[initial_sigma] position`, m.
pub const POSITION_SIGMA_DEFAULT: f64 = 1.0;
/// Initial velocity sigma without `[initial_sigma] velocity`, m/s.
pub const VELOCITY_SIGMA_DEFAULT: f64 = 0.5;
/// Initial accelerometer bias sigma without `[sensors.imu] accel_bias_sigma`, m/s^2.
pub const ACCEL_BIAS_SIGMA_DEFAULT: f64 = 0.1;
/// A truth height this far from the initial height is on another datum, m.
pub const TRUTH_DATUM_GAP_M: f64 = 100.0;
/// Files read.
pub const FILES: &[&str] = &[
    "imu.csv",
    "gnss.csv",
    "baro.csv",
    "mag.csv",
    "reference.csv",
    "truth.csv",
];

/// Where the states are (GnssIns: core 0..15, then the barometer bias).
const ACCEL_BIAS: usize = 9;
const GYRO_BIAS: usize = 12;
const BARO_BIAS: usize = 15;

/// The strapdown solution and the running sensor corrections.
#[derive(Clone, Debug)]
pub struct GnssInsNominal {
    /// The strapdown INS.
    pub ins: Strapdown,
    /// Accelerometer bias correction, m/s^2.
    pub accel_bias: Vector3<f64>,
    /// Gyro bias correction, rad/s.
    pub gyro_bias: Vector3<f64>,
    /// Barometer bias correction (barometric altitude minus height), m.
    pub baro_bias: f64,
}

impl NominalState<N> for GnssInsNominal {
    fn inject(&mut self, e: &SVector<f64, N>) {
        self.ins.inject(&NavError::from_slice(&e.as_slice()[..9]));
        let v3 = |i: usize| Vector3::new(e[i], e[i + 1], e[i + 2]);
        self.accel_bias += v3(ACCEL_BIAS);
        self.gyro_bias += v3(GYRO_BIAS);
        self.baro_bias += e[BARO_BIAS];
    }
}

/// A run of the `gnss-ins` filter.
#[derive(Debug, Clone, Default)]
pub struct GnssInsRun {
    /// The estimate after every IMU sample.
    pub points: Vec<EstimatePoint>,
    /// The estimate at every truth row inside the run (for the scoring).
    pub at_truth: Vec<Option<Estimate>>,
    /// `estimates` table (every 10th IMU sample).
    pub table: RunTable,
    /// Per sensor counts.
    pub gnss: SensorHealth,
    /// Barometer counts.
    pub baro: SensorHealth,
    /// Magnetometer counts.
    pub mag: SensorHealth,
    /// IMU intervals not propagated.
    pub imu_gaps: u64,
    /// IMU samples propagated.
    pub samples: usize,
    /// Declination, rad, and the samples averaged.
    pub declination: (f64, usize),
    /// The final nominal solution.
    pub final_state: Option<GnssInsNominal>,
    /// Covariance repairs.
    pub covariance_repairs: u64,
    /// Filter seconds.
    pub runtime_s: f64,
    /// Notes.
    pub warnings: Vec<String>,
}

fn estimate(t: f64, f: &ErrorStateFilter<GnssIns, GnssInsNominal, N>) -> Estimate {
    let nav = f.nominal().ins.state;
    let p = f.covariance();
    let (rm, rn) = (
        meridian_radius(nav.lat) + nav.h,
        transverse_radius(nav.lat) + nav.h,
    );
    let mut scale = [1.0; 9];
    scale[0] = rm;
    scale[1] = rn * nav.lat.cos();
    scale[2] = -1.0;
    Estimate {
        t,
        nav,
        cov: SMatrix::<f64, 9, 9>::from_fn(|i, j| scale[i] * p[(i, j)] * scale[j]),
        compass_bias: (0.0, f64::NAN),
        usbl_bias_n: (0.0, f64::NAN),
    }
}

fn point(t: f64, nav: &NavState) -> EstimatePoint {
    let e = nav.euler();
    EstimatePoint {
        t,
        attitude: [e.roll, e.pitch, e.yaw],
        position: Some([nav.lat, nav.lon, nav.h]),
    }
}

/// Runs the `gnss-ins` filter over `log`.
///
/// # Errors
/// No initial attitude, no IMU rows, a filter set-up error.
pub fn run(log: &LogDir) -> Result<GnssInsRun, RunError> {
    let init = &log.meta.initial;
    let attitude = init.attitude()?;
    let first = log
        .imu
        .first()
        .ok_or_else(|| RunError::Invalid("imu.csv: no rows".into()))?;
    let t0 = init.t.unwrap_or(first.t);
    let mut out = GnssInsRun::default();
    let sensors = &log.meta.sensors;
    let dt_imu = imu_period(log);
    let imu = sensors.imu;
    let gyro_sigma = imu.map_or(1.5e-2, |n| n.gyro_noise_sigma);
    let accel_sigma = imu.map_or(0.35, |n| n.accel_noise_sigma);
    let gyro_bias_sigma = imu
        .map(|n| n.gyro_bias_sigma)
        .filter(|s| *s > 0.0)
        .unwrap_or(crate::ahrs::replay::GYRO_BIAS_SIGMA_DEFAULT);
    let accel_bias_sigma = imu
        .map(|n| n.accel_bias_sigma)
        .filter(|s| *s > 0.0)
        .unwrap_or(ACCEL_BIAS_SIGMA_DEFAULT);
    let mut noise_of = |name: &str, n: Option<nav_runtime::log::SensorNoise>, default: f64| {
        n.map(|n| n.noise_sigma).unwrap_or_else(|| {
            out.warnings.push(format!(
                "meta.toml has no [sensors.{name}]: noise {default} (PX4's default)"
            ));
            default
        })
    };
    let gnss_sigma = noise_of("gnss", sensors.gnss, GNSS_NOISE_DEFAULT);
    let baro_sigma = noise_of("baro", sensors.baro, BARO_NOISE_DEFAULT);
    let mag_sigma = noise_of("mag", sensors.mag, MAG_NOISE_DEFAULT);
    let mag_rows = log.mag.as_deref().unwrap_or_default();
    let baro_rows = log.baro.as_deref().unwrap_or_default();
    let gnss_rows = log.gnss.as_deref().unwrap_or_default();
    out.mag.rows = mag_rows.len() as u64;
    out.baro.rows = baro_rows.len() as u64;
    out.gnss.rows = gnss_rows.len() as u64;
    for (file, missing) in [
        ("gnss.csv", log.gnss.is_none()),
        ("baro.csv", log.baro.is_none()),
        ("mag.csv", log.mag.is_none()),
    ] {
        if missing {
            out.warnings
                .push(format!("the log has no {file}: that aiding is absent"));
        }
    }
    out.declination = declination(mag_rows, t0, attitude).unwrap_or((0.0, 0));
    let h0 = -init.depth;
    let baro0 = baro_rows
        .iter()
        .find(|b| b.t >= first.t)
        .map_or(0.0, |b| b.altitude - h0);

    let sigma = log.meta.initial_sigma.unwrap_or_default();
    let pos = sigma.position.unwrap_or(POSITION_SIGMA_DEFAULT);
    let vel = sigma.velocity.unwrap_or(VELOCITY_SIGMA_DEFAULT);
    let level = sigma
        .level
        .unwrap_or(crate::ahrs::replay::LEVEL_SIGMA_DEFAULT);
    let heading = sigma
        .heading
        .unwrap_or(crate::ahrs::replay::HEADING_SIGMA_DEFAULT);
    let (rm, rn) = (
        meridian_radius(init.lat) + h0,
        transverse_radius(init.lat) + h0,
    );
    let mut d = [0.0; N];
    d[0] = (pos / rm).powi(2);
    d[1] = (pos / (rn * init.lat.cos())).powi(2);
    d[2] = pos * pos;
    for v in &mut d[3..6] {
        *v = vel * vel;
    }
    d[6] = level * level;
    d[7] = level * level;
    d[8] = heading * heading;
    for v in &mut d[ACCEL_BIAS..ACCEL_BIAS + 3] {
        *v = accel_bias_sigma * accel_bias_sigma;
    }
    for v in &mut d[GYRO_BIAS..GYRO_BIAS + 3] {
        *v = gyro_bias_sigma * gyro_bias_sigma;
    }
    d[BARO_BIAS] = baro_sigma * baro_sigma;
    let p0 = SMatrix::<f64, N, N>::from_diagonal(&SVector::from(d));
    let noise = GnssInsNoise {
        accel_noise: Vector3::repeat(accel_sigma * accel_sigma * dt_imu),
        gyro_noise: Vector3::repeat(gyro_sigma * gyro_sigma * dt_imu),
        baro_bias_noise: BARO_BIAS_WALK * BARO_BIAS_WALK,
    };
    let ekf = Ekf::<GnssIns, N>::new(SVector::zeros(), p0, GnssInsParams::default(), noise)
        .map_err(|e| RunError::Invalid(format!("{NAME}: {e}")))?;
    let state = NavState::new(
        Geodetic::new(init.lat, init.lon, h0),
        Vector3::new(init.vn, init.ve, init.vd),
        &Euler::new(attitude[0], attitude[1], attitude[2]),
    );
    let nominal = GnssInsNominal {
        ins: Strapdown::new(state),
        accel_bias: Vector3::zeros(),
        gyro_bias: Vector3::zeros(),
        baro_bias: baro0,
    };
    let mut filter = ErrorStateFilter::new(ekf, nominal);
    let antenna = <<GnssInsGnssFix as Sensor<N, 3>>::Aux as Record>::from_fn(|_| 0.0);
    out.table = RunTable::new(
        "estimates",
        &[
            "t",
            "lat",
            "lon",
            "height",
            "vn",
            "ve",
            "vd",
            "roll_deg",
            "pitch_deg",
            "yaw_deg",
            "sig_n",
            "sig_e",
            "sig_d",
            "baro_bias",
        ],
    );
    let truth = log.truth.as_deref().unwrap_or_default();
    out.at_truth = vec![None; truth.len()];
    let mut next_truth = 0usize;
    let start = Instant::now();
    let mut t_prev: Option<f64> = None;
    for event in log.events() {
        match event {
            Event::Imu(row) => {
                let Some(tp) = t_prev.replace(row.t) else {
                    let nav = filter.nominal().ins.state;
                    out.points.push(point(row.t, &nav));
                    while next_truth < truth.len() && truth[next_truth].t < row.t {
                        next_truth += 1;
                    }
                    continue;
                };
                let dt = row.t - tp;
                if !(dt > 0.0 && dt <= crate::ahrs::replay::MAX_IMU_STEP_S) {
                    out.imu_gaps += 1;
                    continue;
                }
                let n = filter.nominal();
                let w = Vector3::new(row.gx, row.gy, row.gz) - n.gyro_bias;
                let f = Vector3::new(row.ax, row.ay, row.az) - n.accel_bias;
                let s = &n.ins.state;
                let input = GnssInsInput {
                    latitude: s.lat,
                    height: s.h,
                    velocity: s.v_n,
                    c_bn: s.c_bn,
                    specific_force: f,
                };
                filter.predict(dt, &input).map_err(|e| {
                    RunError::Invalid(format!("{NAME}: imu.csv t = {}: {e}", row.t))
                })?;
                filter.nominal_mut().ins.update_rates(&w, &f, dt);
                out.samples += 1;
                let nav = filter.nominal().ins.state;
                out.points.push(point(row.t, &nav));
                // Truth rows up to this sample take the estimate after it
                // (within one IMU interval).
                while next_truth < truth.len() && truth[next_truth].t <= row.t {
                    if row.t - truth[next_truth].t <= dt {
                        out.at_truth[next_truth] = Some(estimate(truth[next_truth].t, &filter));
                    }
                    next_truth += 1;
                }
                if out.samples % 10 == 0 {
                    let e = nav.euler();
                    let p = filter.covariance();
                    out.table.push(&[
                        row.t,
                        nav.lat,
                        nav.lon,
                        nav.h,
                        nav.v_n.x,
                        nav.v_n.y,
                        nav.v_n.z,
                        e.roll.to_degrees(),
                        e.pitch.to_degrees(),
                        e.yaw.to_degrees(),
                        p[(0, 0)].sqrt() * (meridian_radius(nav.lat) + nav.h),
                        p[(1, 1)].sqrt() * (transverse_radius(nav.lat) + nav.h) * nav.lat.cos(),
                        p[(2, 2)].sqrt(),
                        filter.nominal().baro_bias,
                    ]);
                }
            }
            Event::Gnss(row) => {
                if t_prev.is_none() {
                    out.gnss.skipped += 1;
                    continue;
                }
                let s = filter.nominal().ins.state;
                let (rm, rn) = (meridian_radius(s.lat) + s.h, transverse_radius(s.lat) + s.h);
                let z = SVector::<f64, 3>::new(
                    rm * (s.lat - row.lat),
                    rn * s.lat.cos() * wrap(s.lon - row.lon),
                    s.h - row.height,
                );
                let sh = row.eph.map_or(gnss_sigma, |e| e.max(gnss_sigma));
                let sv = row.epv.map_or(gnss_sigma, |e| e.max(gnss_sigma));
                let r = SVector::<f64, 3>::new(sh * sh, sh * sh, sv * sv);
                let res = filter.update_sequential::<GnssInsGnssFix, 3>(&z, &r, &antenna);
                count(&mut out.gnss, res);
            }
            Event::Baro(row) => {
                if t_prev.is_none() {
                    out.baro.skipped += 1;
                    continue;
                }
                let n = filter.nominal();
                let z = SVector::<f64, 1>::new(n.ins.state.h - (row.altitude - n.baro_bias));
                let res = filter.update_sequential::<GnssInsBarometer, 1>(
                    &z,
                    &SVector::<f64, 1>::new(baro_sigma * baro_sigma),
                    &(),
                );
                count(&mut out.baro, res);
            }
            Event::Mag(row) => {
                if t_prev.is_none() {
                    out.mag.skipped += 1;
                    continue;
                }
                let e = filter.nominal().ins.state.euler();
                let m = [row.mx, row.my, row.mz];
                let Some(psi) = magnetic_heading(m, e.roll, e.pitch, out.declination.0) else {
                    out.mag.skipped += 1;
                    continue;
                };
                let s = (mag_sigma / horizontal_field(m, e.roll, e.pitch)).atan();
                let z = SVector::<f64, 1>::new(wrap(e.yaw - psi));
                let res = filter.update_sequential::<GnssInsMagneticHeading, 1>(
                    &z,
                    &SVector::<f64, 1>::new(s * s),
                    &(),
                );
                count(&mut out.mag, res);
            }
            _ => {}
        }
    }
    out.runtime_s = start.elapsed().as_secs_f64();
    out.covariance_repairs = filter.ekf().counters().covariance_repairs;
    out.final_state = Some(filter.nominal().clone());
    Ok(out)
}

/// The replay model `gnss-ins`.
#[derive(Debug, Clone, Copy, Default)]
pub struct GnssInsReplay;

impl ReplayModel for GnssInsReplay {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "16-state INS with GNSS position, barometer and magnetic heading (imported PX4 logs)"
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
        let m = &mut out.metrics;
        let diff = reference_metrics(log, &run.points, m, &mut out.warnings);
        if let Some(truth) = log.truth.as_deref() {
            let h0 = -log.meta.initial.depth;
            if let Some(r) = truth
                .first()
                .filter(|r| (-r.depth - h0).abs() > TRUTH_DATUM_GAP_M)
            {
                out.warnings.push(format!(
                    "truth.csv: height {:.1} m at t = {} s, the initial height {h0:.1} m: the truth's \
                     vertical datum differs (depth_error_rms_m and nees_mean are not meaningful)",
                    -r.depth, r.t
                ));
            }
            match score::score(&run.at_truth, truth, None, log.imu_time_span()) {
                Ok(s) => {
                    for (k, v) in [
                        ("horizontal_error_final_m", s.horizontal_error_final_m),
                        ("horizontal_error_rms_m", s.horizontal_error_rms_m),
                        ("depth_error_rms_m", s.depth_error_rms_m),
                        ("nees_mean", s.nees_mean),
                        ("scored_seconds", s.scored_seconds),
                    ] {
                        m.insert(k.into(), Value::from(v));
                    }
                    out.warnings.extend(s.partial.clone());
                    if options.keep_series {
                        out.tables.push(s.table);
                    }
                }
                Err(e) => out.warnings.push(format!("not scored against truth: {e}")),
            }
            if let Some((rms, _, table)) = attitude_errors(truth, &run.points) {
                m.insert("attitude_error_rms_deg".into(), rpy_json(rms));
                if options.keep_series {
                    out.tables.push(table);
                }
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
        let mut health = health_json(&[("gnss", run.gnss), ("baro", run.baro), ("mag", run.mag)]);
        health["imu_gaps"] = Value::from(run.imu_gaps);
        health["covariance_repairs"] = Value::from(run.covariance_repairs);
        m.insert("health".into(), health);
        if let Some(f) = &run.final_state {
            let s = f.ins.state;
            let e = s.euler();
            m.insert(
                "final".into(),
                json!({
                    "lat": s.lat, "lon": s.lon, "height": s.h,
                    "vn": s.v_n.x, "ve": s.v_n.y, "vd": s.v_n.z,
                    "roll": e.roll.to_degrees(), "pitch": e.pitch.to_degrees(), "yaw": e.yaw.to_degrees(),
                    "baro_bias_m": f.baro_bias,
                }),
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
