//! A plumbing self-test, **not** a scenario of the source papers.
//!
//! `demo-constant-velocity`: the vehicle's depth follows a constant-velocity
//! random walk (white acceleration noise); a depth sensor measures it at 10 Hz with
//! white noise; a two-state closed-form Kalman filter (depth, down velocity)
//! estimates it. The truth is sampled from exactly the filter's discrete model, so
//! the mean NEES is near 2 (the state dimension). The IMU file carries the
//! specific force of that motion at 50 Hz (the filter does not use it).
//!
//! The same filter is the replay model `demo-depth-kf`, and `run_one` runs it on
//! the very log `simulate_log` writes, so replaying `navsim simulate` output gives
//! the numbers of `navsim scenario`.
use std::collections::BTreeMap;
use std::path::Path;

use crate::harness::*;
use nav_runtime::log::{DepthRow, ImuRow, LogDir, LogSource, Meta, TruthRow};
use nav_runtime::stats;
use rand::SeedableRng;
use rand_distr::{Distribution, StandardNormal};
use serde_json::{Map, Value};

/// Scenario name.
pub const NAME: &str = "demo-constant-velocity";
/// Replay model name.
pub const MODEL: &str = "demo-depth-kf";
/// Fault: depth sensor silent from 20 s to 30 s.
pub const FAULT_DEPTH_DROPOUT: &str = "depth-dropout";
/// Process noise: white acceleration power spectral density, m^2/s^3.
pub const ACCEL_PSD: f64 = 0.01;
const DURATION_S: f64 = 60.0;
const IMU_DT: f64 = 0.02;
const DEPTH_PER_IMU: usize = 5;
const DEPTH_NOISE: f64 = 0.05;
const DEPTH_BIAS_SIGMA: f64 = 0.05;
const SIGMA_DEPTH0: f64 = 0.5;
const SIGMA_VEL0: f64 = 0.1;
const GRAVITY: f64 = 9.80665;

/// The demo scenario.
#[derive(Debug, Clone, Copy, Default)]
pub struct ConstantVelocity;

fn normal(rng: &mut rand_chacha::ChaCha8Rng) -> f64 {
    StandardNormal.sample(rng)
}

/// Builds the synthetic log of one run.
pub fn simulate(seed: u64, options: &RunOptions) -> LogDir {
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(seed);
    let mut meta = Meta::at(0.7, 0.2, 10.0);
    meta.initial.roll = Some(0.0);
    meta.initial.pitch = Some(0.0);
    meta.initial.yaw = Some(0.0);
    meta.initial_sigma = Some(nav_runtime::log::InitialSigma {
        position: Some(SIGMA_DEPTH0),
        velocity: Some(SIGMA_VEL0),
        level: None,
        heading: None,
    });
    meta.sensors.depth = Some(nav_runtime::log::SensorNoise {
        bias_sigma: if options.draw_biases {
            DEPTH_BIAS_SIGMA
        } else {
            0.0
        },
        noise_sigma: DEPTH_NOISE,
    });
    let bias = if options.draw_biases {
        DEPTH_BIAS_SIGMA * normal(&mut rng)
    } else {
        0.0
    };
    // Truth starts at the initial estimate plus a draw from its covariance.
    let mut d = meta.initial.depth + SIGMA_DEPTH0 * normal(&mut rng);
    let mut v = meta.initial.vd + SIGMA_VEL0 * normal(&mut rng);
    let dt = IMU_DT * DEPTH_PER_IMU as f64;
    // Cholesky factor of the discrete process noise of the constant-velocity model.
    let q11 = ACCEL_PSD * dt.powi(3) / 3.0;
    let q12 = ACCEL_PSD * dt.powi(2) / 2.0;
    let q22 = ACCEL_PSD * dt;
    let l11 = q11.sqrt();
    let l21 = q12 / l11;
    let l22 = (q22 - l21 * l21).sqrt();

    let steps = (DURATION_S / dt).round() as usize;
    let mut log = LogDir::new(meta);
    let mut depth = Vec::new();
    let mut truth = Vec::new();
    let truth_row =
        |t: f64, d: f64, v: f64| TruthRow::new(t, 0.7, 0.2, d, 0.0, 0.0, v, 0.0, 0.0, 0.0);
    truth.push(truth_row(0.0, d, v));
    for k in 0..steps {
        let t0 = (k * DEPTH_PER_IMU) as f64 * IMU_DT;
        let (w1, w2) = (normal(&mut rng), normal(&mut rng));
        let d_next = d + dt * v + l11 * w1;
        let v_next = v + l21 * w1 + l22 * w2;
        let accel = (v_next - v) / dt;
        for j in 0..DEPTH_PER_IMU {
            let t = (k * DEPTH_PER_IMU + j) as f64 * IMU_DT;
            log.imu
                .push(ImuRow::new(t, 0.0, 0.0, 0.0, 0.0, 0.0, accel - GRAVITY));
        }
        d = d_next;
        v = v_next;
        let t = ((k + 1) * DEPTH_PER_IMU) as f64 * IMU_DT;
        truth.push(truth_row(t, d, v));
        let dropped = options.has_fault(FAULT_DEPTH_DROPOUT) && (20.0..30.0).contains(&t0);
        let z = d + bias + DEPTH_NOISE * normal(&mut rng);
        if !dropped {
            depth.push(DepthRow::new(t, z));
        }
    }
    log.depth = Some(depth);
    log.truth = Some(truth);
    log
}

/// One filter estimate.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Time, s.
    pub t: f64,
    /// State (depth m, down velocity m/s).
    pub x: [f64; 2],
    /// Covariance.
    pub p: [[f64; 2]; 2],
}

/// Runs the two-state Kalman filter over the depth samples of a log; returns the
/// prior at the first IMU time and the estimate after each depth update.
pub fn filter(log: &LogDir) -> Result<Vec<Estimate>, RunError> {
    let depth = log
        .depth
        .as_ref()
        .ok_or_else(|| RunError::Invalid(format!("model {MODEL} needs depth.csv")))?;
    let r = log
        .meta
        .sensors
        .depth
        .map(|s| s.noise_sigma * s.noise_sigma + s.bias_sigma * s.bias_sigma)
        .unwrap_or(DEPTH_NOISE * DEPTH_NOISE);
    let sig = log.meta.initial_sigma.unwrap_or_default();
    let sp = sig.position.unwrap_or(SIGMA_DEPTH0);
    let sv = sig.velocity.unwrap_or(SIGMA_VEL0);
    let t0 = log.imu.first().map_or(0.0, |r| r.t);
    let mut e = Estimate {
        t: t0,
        x: [log.meta.initial.depth, log.meta.initial.vd],
        p: [[sp * sp, 0.0], [0.0, sv * sv]],
    };
    let mut out = Vec::with_capacity(depth.len() + 1);
    out.push(e);
    for m in depth.iter().filter(|m| m.t >= t0) {
        let dt = m.t - e.t;
        // Predict.
        let [d, v] = e.x;
        let p = e.p;
        let x = [d + dt * v, v];
        let p00 =
            p[0][0] + dt * (p[1][0] + p[0][1]) + dt * dt * p[1][1] + ACCEL_PSD * dt.powi(3) / 3.0;
        let p01 = p[0][1] + dt * p[1][1] + ACCEL_PSD * dt * dt / 2.0;
        let p11 = p[1][1] + ACCEL_PSD * dt;
        // Update with z = depth.
        let s = p00 + r;
        let k0 = p00 / s;
        let k1 = p01 / s;
        let y = m.depth - x[0];
        e = Estimate {
            t: m.t,
            x: [x[0] + k0 * y, x[1] + k1 * y],
            p: [
                [(1.0 - k0) * p00, (1.0 - k0) * p01],
                [(1.0 - k0) * p01, p11 - k1 * p01],
            ],
        };
        out.push(e);
    }
    Ok(out)
}

/// Scores estimates against truth: for each truth row, the latest estimate at or
/// before it. Returns metrics and the per-time table.
pub fn score(est: &[Estimate], truth: &[TruthRow]) -> (BTreeMap<String, f64>, RunTable) {
    let mut table = RunTable::new(
        "depth",
        &[
            "t",
            "depth_true",
            "depth_est",
            "depth_sigma",
            "error",
            "nees",
        ],
    );
    let mut errors = Vec::new();
    let mut nees = Vec::new();
    let mut i = 0;
    for tr in truth {
        while i + 1 < est.len() && est[i + 1].t <= tr.t {
            i += 1;
        }
        let Some(e) = est.get(i).filter(|e| e.t <= tr.t) else {
            continue;
        };
        let ed = e.x[0] - tr.depth;
        let ev = e.x[1] - tr.vd;
        let det = e.p[0][0] * e.p[1][1] - e.p[0][1] * e.p[1][0];
        let n = (e.p[1][1] * ed * ed - 2.0 * e.p[0][1] * ed * ev + e.p[0][0] * ev * ev) / det;
        errors.push(ed);
        nees.push(n);
        table.push(&[tr.t, tr.depth, e.x[0], e.p[0][0].sqrt(), ed, n]);
    }
    let mut m = BTreeMap::new();
    m.insert("depth_error_rms_m".into(), stats::rms(&errors));
    m.insert(
        "depth_error_final_m".into(),
        errors.last().map_or(f64::NAN, |e| e.abs()),
    );
    m.insert("nees_mean".into(), stats::mean(&nees));
    (m, table)
}

impl Scenario for ConstantVelocity {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "plumbing self-test: 1-D constant-velocity depth, noisy depth sensor, 2-state Kalman filter"
    }
    fn default_runs(&self) -> usize {
        20
    }
    fn faults(&self) -> &'static [&'static str] {
        &[FAULT_DEPTH_DROPOUT]
    }
    fn draws_biases(&self) -> bool {
        true
    }
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
        let log = simulate(seed, options);
        let est = filter(&log)?;
        let (metrics, table) = score(&est, log.truth.as_deref().unwrap_or(&[]));
        let mut r = RunResult::new(seed);
        r.metrics = metrics;
        if options.keep_series {
            r.tables.push(table);
        }
        Ok(r)
    }
    fn summarize(
        &self,
        runs: &[RunResult],
        _options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError> {
        let mut m = Map::new();
        for key in ["depth_error_rms_m", "depth_error_final_m"] {
            m.insert(key.into(), crate::harness::report::summary_of(runs, key));
        }
        m.insert(
            "nees_mean".into(),
            Value::from(stats::mean(&metric_values(runs, "nees_mean"))),
        );
        // Depth and its rate.
        m.insert("nees_dof".into(), Value::from(2));
        Ok(m)
    }
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        write_run_tables(runs, dir)?;
        let Some(first) = runs
            .iter()
            .find_map(|r| r.tables.first().map(|t| (r.seed, t)))
        else {
            return Ok(());
        };
        let (seed, table) = first;
        let t = table.column("t");
        crate::harness::plot::error_with_sigma(
            &dir.join(format!("run-{seed}-depth-error.svg")),
            &format!("{NAME}: depth error, seed {seed}"),
            "depth error [m]",
            &t,
            &table.column("error"),
            &table.column("depth_sigma"),
        )?;
        // Average NEES over runs (tables share the time grid).
        let tables: Vec<&RunTable> = runs.iter().filter_map(|r| r.tables.first()).collect();
        let len = tables.iter().map(|t| t.rows.len()).min().unwrap_or(0);
        let avg: Vec<f64> = (0..len)
            .map(|i| tables.iter().map(|t| t.rows[i][5]).sum::<f64>() / tables.len() as f64)
            .collect();
        let band = nees_band_95(2, tables.len());
        crate::harness::plot::nees(
            &dir.join("nees.svg"),
            &format!("{NAME}: average NEES over {} runs", tables.len()),
            &t[..len.min(t.len())],
            &avg,
            Some(band),
        )
    }
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        Some(Ok(simulate(seed, options)))
    }
}

/// Approximate two-sided 95 % band of the NEES averaged over `runs` runs for a
/// `dim`-state filter (Wilson-Hilferty approximation of chi-square quantiles; the
/// filter code has exact bands, this keeps the demo self-contained).
fn nees_band_95(dim: usize, runs: usize) -> (f64, f64) {
    let k = (dim * runs.max(1)) as f64;
    let q = |z: f64| k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3);
    let n = runs.max(1) as f64;
    (q(-1.959964) / n, q(1.959964) / n)
}

/// The demo replay model: the same filter over `depth.csv`.
#[derive(Debug, Clone, Copy, Default)]
pub struct DepthKf;

impl ReplayModel for DepthKf {
    fn name(&self) -> &'static str {
        MODEL
    }
    fn description(&self) -> &'static str {
        "plumbing self-test: 2-state depth Kalman filter over depth.csv"
    }
    /// The log read whole.
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        let output = replay_depth(&*source.whole()?, options)?;
        if let Some(dir) = out {
            self.write_outputs(&output, dir)?;
        }
        Ok(output)
    }
}

/// The depth filter over `log`, scored against its truth.
fn replay_depth(log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
    // The initial depth is the filter's first estimate.
    log.meta.initial.position_for(MODEL)?;
    let start = std::time::Instant::now();
    let est = filter(log)?;
    let runtime_s = start.elapsed().as_secs_f64();
    let mut out = ReplayOutput {
        samples: log.imu.len(),
        runtime_s,
        ..Default::default()
    };
    if let Some(truth) = &log.truth {
        let (metrics, table) = score(&est, truth);
        for (k, v) in metrics {
            out.metrics.insert(k, Value::from(v));
        }
        if options.keep_series {
            out.tables.push(table);
        }
    }
    Ok(out)
}
