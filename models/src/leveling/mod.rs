//! LEVELING-6 (docs/models/leveling6.md): the model, its simulation, the filter run,
//! and the `leveling-*` scenarios and `leveling6` replay model of `navsim`.

pub mod filter;
pub mod model;
pub mod observability;
pub mod scheduled_filter;
pub mod simulation;

use crate::harness::plot::{self, Line};
use crate::harness::{
    ReplayModel, ReplayOptions, ReplayOutput, RunError, RunOptions, RunResult, RunTable, Scenario,
};
use filter::{errors_at_truth, LevelingOptions, Tuning};
use nav_replay::innovations::SensorInnovations;
use nav_runtime::imu::{ImuSpec, MG};
use nav_runtime::log::{LogDir, Warning, WarningKind};
use nav_runtime::nalgebra::{Matrix2, Vector2};
use nav_runtime::sensors::{derive_seed, normal};
use nav_runtime::stats;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use serde_json::{Map, Value};
use simulation::{Biases, Motion};
use std::path::Path;

pub use model::{Leveling6, Leveling6Moving, Leveling6Stationary};

/// Initial roll and pitch error 1-sigma of the Monte Carlo (paper: N(0, 45^2) deg).
pub const INITIAL_ERROR_SIGMA_DEG: f64 = 45.0;

/// One of the `leveling-*` scenarios.
#[derive(Clone, Copy, Debug)]
pub struct LevelingScenario {
    name: &'static str,
    motion: Motion,
}

/// `leveling-moving` (S-type), `leveling-straight`, `leveling-stationary`.
pub fn scenarios() -> Vec<LevelingScenario> {
    vec![
        LevelingScenario {
            name: "leveling-moving",
            motion: Motion::SType,
        },
        LevelingScenario {
            name: "leveling-straight",
            motion: Motion::Straight,
        },
        LevelingScenario {
            name: "leveling-stationary",
            motion: Motion::Stationary,
        },
    ]
}

fn biases(options: &RunOptions) -> Biases {
    if options.draw_biases {
        Biases::Drawn
    } else {
        Biases::OneSigma
    }
}

const TABLE: &str = "attitude";
const COLUMNS: [&str; 5] = [
    "t",
    "roll_error_deg",
    "pitch_error_deg",
    "roll_sigma_deg",
    "pitch_sigma_deg",
];

/// The initial roll and pitch guess (rad) of run `seed` of a simulated
/// `log`: drawn from `N(truth, 45 deg)` about its first truth row.
///
/// # Errors
/// The log has no truth.
pub fn initial_guess(log: &LogDir, seed: u64) -> Result<(f64, f64), RunError> {
    let truth0 = log
        .truth
        .as_ref()
        .and_then(|t| t.first().copied())
        .ok_or_else(|| RunError::Invalid("no truth".into()))?;
    let mut rng = ChaCha8Rng::seed_from_u64(derive_seed(seed, "leveling-initial-attitude"));
    let sigma = INITIAL_ERROR_SIGMA_DEG.to_radians();
    Ok((
        truth0.roll + normal(&mut rng, sigma),
        truth0.pitch + normal(&mut rng, sigma),
    ))
}

/// Simulates, runs the filter from a guess `N(truth, 45 deg)` and scores one run.
fn run_one(motion: Motion, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
    let log = simulation::simulate(motion, biases(options), seed);
    let guess = initial_guess(&log, seed)?;
    let mut opts = LevelingOptions {
        stationary: motion.is_stationary(),
        initial_attitude: Some(guess),
        tuning: Tuning::default(),
    };
    let run = filter::run(&log, &opts).map_err(|e| RunError::Invalid(e.to_string()))?;
    let mut r = score(seed, &run, &log, options.keep_series)?;
    // The same run with the horizontal accelerometer bias as states.
    opts.tuning.bias_states = true;
    let run8 = filter::run(&log, &opts).map_err(|e| RunError::Invalid(e.to_string()))?;
    for (key, value) in final_metrics(&run8, &log)? {
        r = r.with_metric(&format!("{BIAS_STATES}.{key}"), value);
    }
    for (i, key) in ["accel_bias_x", "accel_bias_y"].iter().enumerate() {
        r = r
            .with_metric(
                &format!("{BIAS_STATES}.{key}_final_mg"),
                run8.accel_bias_final[i] / MG,
            )
            .with_metric(
                &format!("{BIAS_STATES}.{key}_sigma_final_mg"),
                run8.accel_bias_final[2 + i] / MG,
            );
    }
    Ok(r)
}

/// A replay's final tilt NEES (2 dof) above this (a hundred sigmas) is
/// warned.
const FINAL_NEES_WARN: f64 = 1e4;

/// Prefix of the metrics of the filter with bias states.
const BIAS_STATES: &str = "accel_bias_states";

/// Final tilt magnitude (deg) and the tilt NEES (2 dof) of the last estimate,
/// plus the roll and pitch errors and sigmas (deg).
fn final_metrics(
    run: &filter::LevelingRun,
    log: &LogDir,
) -> Result<Vec<(&'static str, f64)>, RunError> {
    let &(_, roll, pitch) = errors_at_truth(run, log)
        .last()
        .ok_or_else(|| RunError::Invalid("no estimate at a truth time".into()))?;
    let last = run
        .estimates
        .last()
        .ok_or_else(|| RunError::Invalid("no estimate".into()))?;
    Ok(vec![
        ("roll_error_final_deg", roll.to_degrees()),
        ("pitch_error_final_deg", pitch.to_degrees()),
        ("tilt_error_final_deg", roll.hypot(pitch).to_degrees()),
        ("roll_sigma_final_deg", last.roll_sigma.to_degrees()),
        ("pitch_sigma_final_deg", last.pitch_sigma.to_degrees()),
        ("tilt_nees_final", tilt_nees(roll, pitch, last)),
    ])
}

/// `e^T P^-1 e` of the roll and pitch error `e` (rad) under the estimate's
/// 2 x 2 covariance; NaN if that covariance is singular.
pub fn tilt_nees(roll_error: f64, pitch_error: f64, e: &filter::AttitudeEstimate) -> f64 {
    let p = Matrix2::new(
        e.roll_sigma * e.roll_sigma,
        e.roll_pitch_covariance,
        e.roll_pitch_covariance,
        e.pitch_sigma * e.pitch_sigma,
    );
    let v = Vector2::new(roll_error, pitch_error);
    p.try_inverse()
        .map_or(f64::NAN, |inv| (v.transpose() * inv * v)[0])
}

fn score(
    seed: u64,
    run: &filter::LevelingRun,
    log: &LogDir,
    keep_series: bool,
) -> Result<RunResult, RunError> {
    let errors = errors_at_truth(run, log);
    let &(_, roll_final, pitch_final) = errors
        .last()
        .ok_or_else(|| RunError::Invalid("no estimate at a truth time".into()))?;
    let mut r = RunResult::new(seed)
        .with_metric("roll_error_final_deg", roll_final.to_degrees())
        .with_metric("pitch_error_final_deg", pitch_final.to_degrees())
        .with_metric(
            "tilt_error_final_deg",
            roll_final.hypot(pitch_final).to_degrees(),
        )
        .with_metric("gated", run.gated as f64)
        .with_metric("rejected", run.rejected as f64)
        .with_metric("repairs", run.repairs as f64);
    if let Some(last) = run.estimates.last() {
        r = r
            .with_metric("roll_sigma_final_deg", last.roll_sigma.to_degrees())
            .with_metric("pitch_sigma_final_deg", last.pitch_sigma.to_degrees());
    }
    if keep_series {
        r.tables.push(error_table(TABLE, &run.estimates, &errors));
    }
    Ok(r)
}

/// The table `name` of the roll and pitch errors (deg) at the truth times
/// of `errors`, with the sigmas of the estimate in force there.
fn error_table(
    name: &str,
    estimates: &[filter::AttitudeEstimate],
    errors: &[(f64, f64, f64)],
) -> RunTable {
    let mut table = RunTable::new(name, &COLUMNS);
    for &(t, re, pe) in errors {
        let i = estimates
            .partition_point(|e| e.t <= t + 1e-9)
            .saturating_sub(1);
        let Some(e) = estimates.get(i) else { continue };
        table.push(&[
            t,
            re.to_degrees(),
            pe.to_degrees(),
            e.roll_sigma.to_degrees(),
            e.pitch_sigma.to_degrees(),
        ]);
    }
    table
}

/// RMS roll and pitch errors (deg) of the truth rows of `errors` after
/// `after` (s): the start is the initial guess, not an estimate.
fn rms_after(errors: &[(f64, f64, f64)], after: f64) -> (f64, f64) {
    let later: Vec<_> = errors.iter().filter(|e| e.0 > after + 1e-9).collect();
    let rms = |f: &dyn Fn(&(f64, f64, f64)) -> f64| {
        (later.iter().map(|e| f(e).powi(2)).sum::<f64>() / later.len() as f64)
            .sqrt()
            .to_degrees()
    };
    (rms(&|e| e.1), rms(&|e| e.2))
}

/// Name of the table of the smoothed estimates' errors (`--smooth`).
const SMOOTHED_TABLE: &str = "smoothed_attitude";

impl Scenario for LevelingScenario {
    fn name(&self) -> &'static str {
        self.name
    }
    fn description(&self) -> &'static str {
        match self.motion {
            Motion::SType => "LEVELING-6, S-type track, speed log + unit norm, 30 s",
            Motion::Straight => "LEVELING-6, straight track, speed log + unit norm, 30 s",
            Motion::Stationary => "LEVELING-6 at rest, zero velocity + unit norm, 30 s",
        }
    }
    fn default_runs(&self) -> usize {
        100
    }
    fn draws_biases(&self) -> bool {
        true
    }
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
        run_one(self.motion, seed, options)
    }
    fn summarize(
        &self,
        runs: &[RunResult],
        _options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError> {
        let roll = crate::harness::metric_values(runs, "roll_error_final_deg");
        let pitch = crate::harness::metric_values(runs, "pitch_error_final_deg");
        let mut m = Map::new();
        m.insert(
            "roll_error_mean_deg".into(),
            Value::from(stats::mean(&roll)),
        );
        m.insert(
            "pitch_error_mean_deg".into(),
            Value::from(stats::mean(&pitch)),
        );
        m.insert(
            "roll_error_std_deg".into(),
            Value::from(stats::std_dev(&roll)),
        );
        m.insert(
            "pitch_error_std_deg".into(),
            Value::from(stats::std_dev(&pitch)),
        );
        let roll_sigma = crate::harness::metric_values(runs, "roll_sigma_final_deg");
        let pitch_sigma = crate::harness::metric_values(runs, "pitch_sigma_final_deg");
        m.insert(
            "roll_sigma_filter_deg".into(),
            Value::from(stats::mean(&roll_sigma)),
        );
        m.insert(
            "pitch_sigma_filter_deg".into(),
            Value::from(stats::mean(&pitch_sigma)),
        );
        let gated: f64 = crate::harness::metric_values(runs, "gated").iter().sum();
        let rejected: f64 = crate::harness::metric_values(runs, "rejected").iter().sum();
        let repairs: f64 = crate::harness::metric_values(runs, "repairs").iter().sum();
        m.insert(
            "tilt_error_mean_deg".into(),
            Value::from(stats::mean(&crate::harness::metric_values(
                runs,
                "tilt_error_final_deg",
            ))),
        );
        m.insert(
            "mean_tilt_magnitude_deg".into(),
            Value::from(stats::mean(&roll).hypot(stats::mean(&pitch))),
        );
        m.insert(
            "two_axis_floor_deg".into(),
            Value::from(two_axis_floor_deg()),
        );
        m.insert(BIAS_STATES.into(), Value::Object(bias_states_summary(runs)));
        m.insert("health".into(), serde_json::json!({"speed": {"gated": gated, "rejected": rejected}, "covariance_repairs": repairs}));
        Ok(m)
    }
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        crate::harness::write_run_tables(runs, dir)?;
        write_ensemble(self.name, runs, dir)
    }
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        Some(Ok(simulation::simulate(self.motion, biases(options), seed)))
    }
}

/// The tilt an uncompensated 1-sigma accelerometer bias on x and y causes at
/// rest, `sqrt(2) b / g` (deg; 1 mg at the scenarios' start: 0.081 deg).
pub fn two_axis_floor_deg() -> f64 {
    let start = simulation::trajectory(Motion::Stationary).spec().start;
    let g = nav_runtime::earth::normal_gravity(start.lat, start.h);
    (std::f64::consts::SQRT_2 * ImuSpec::leveling6().accel_bias / g).to_degrees()
}

/// The JSON of the filter with bias states: roll, pitch and tilt statistics
/// over the runs, the mean filter sigma, the tilt NEES and the bias estimates.
fn bias_states_summary(runs: &[RunResult]) -> Map<String, Value> {
    let col = |k: &str| crate::harness::metric_values(runs, &format!("{BIAS_STATES}.{k}"));
    let (roll, pitch) = (col("roll_error_final_deg"), col("pitch_error_final_deg"));
    let nees: Vec<f64> = col("tilt_nees_final")
        .into_iter()
        .filter(|x| x.is_finite())
        .collect();
    let mut m = Map::new();
    for (key, value) in [
        ("roll_error_mean_deg", stats::mean(&roll)),
        ("pitch_error_mean_deg", stats::mean(&pitch)),
        ("roll_error_std_deg", stats::std_dev(&roll)),
        ("pitch_error_std_deg", stats::std_dev(&pitch)),
        (
            "tilt_error_mean_deg",
            stats::mean(&col("tilt_error_final_deg")),
        ),
        (
            "tilt_error_rms_deg",
            stats::rms(&col("tilt_error_final_deg")),
        ),
        (
            "mean_tilt_magnitude_deg",
            stats::mean(&roll).hypot(stats::mean(&pitch)),
        ),
        (
            "roll_sigma_filter_deg",
            stats::mean(&col("roll_sigma_final_deg")),
        ),
        (
            "pitch_sigma_filter_deg",
            stats::mean(&col("pitch_sigma_final_deg")),
        ),
        ("tilt_nees_mean", stats::mean(&nees)),
        (
            "accel_bias_x_mean_mg",
            stats::mean(&col("accel_bias_x_final_mg")),
        ),
        (
            "accel_bias_y_mean_mg",
            stats::mean(&col("accel_bias_y_final_mg")),
        ),
        (
            "accel_bias_x_sigma_mg",
            stats::mean(&col("accel_bias_x_sigma_final_mg")),
        ),
        (
            "accel_bias_y_sigma_mg",
            stats::mean(&col("accel_bias_y_sigma_final_mg")),
        ),
    ] {
        m.insert(key.into(), Value::from(value));
    }
    m
}

/// The paper's Figs. 6-9: ensemble mean and std of the roll and pitch errors
/// over time, with the filter's mean predicted sigma.
fn write_ensemble(name: &str, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
    let tables: Vec<&RunTable> = runs
        .iter()
        .filter_map(|r| r.tables.iter().find(|t| t.name == TABLE))
        .collect();
    let Some(first) = tables.first() else {
        return Ok(());
    };
    let len = tables.iter().map(|t| t.rows.len()).min().unwrap_or(0);
    let t: Vec<f64> = first.rows[..len].iter().map(|r| r[0]).collect();
    let column = |c: usize, f: fn(&[f64]) -> f64| -> Vec<f64> {
        (0..len)
            .map(|i| f(&tables.iter().map(|tab| tab.rows[i][c]).collect::<Vec<_>>()))
            .collect()
    };
    let (roll_mean, pitch_mean) = (column(1, stats::mean), column(2, stats::mean));
    let (roll_std, pitch_std) = (column(1, stats::std_dev), column(2, stats::std_dev));
    let (roll_sig, pitch_sig) = (column(3, stats::mean), column(4, stats::mean));
    let mut ensemble = RunTable::new(
        "ensemble",
        &[
            "t",
            "roll_mean_deg",
            "pitch_mean_deg",
            "roll_std_deg",
            "pitch_std_deg",
            "roll_sigma_deg",
            "pitch_sigma_deg",
        ],
    );
    for i in 0..len {
        ensemble.push(&[
            t[i],
            roll_mean[i],
            pitch_mean[i],
            roll_std[i],
            pitch_std[i],
            roll_sig[i],
            pitch_sig[i],
        ]);
    }
    ensemble.write_csv(&dir.join("ensemble.csv"))?;
    plot::lines(
        &dir.join("ensemble-mean.svg"),
        &format!(
            "{name}: ensemble mean of the level errors ({} runs)",
            tables.len()
        ),
        "t [s]",
        "error [deg]",
        &[
            Line {
                label: "roll",
                x: &t,
                y: &roll_mean,
            },
            Line {
                label: "pitch",
                x: &t,
                y: &pitch_mean,
            },
        ],
    )?;
    plot::lines(
        &dir.join("ensemble-std.svg"),
        &format!(
            "{name}: ensemble std vs filter sigma ({} runs)",
            tables.len()
        ),
        "t [s]",
        "std [deg]",
        &[
            Line {
                label: "roll std",
                x: &t,
                y: &roll_std,
            },
            Line {
                label: "pitch std",
                x: &t,
                y: &pitch_std,
            },
            Line {
                label: "roll sigma (filter)",
                x: &t,
                y: &roll_sig,
            },
            Line {
                label: "pitch sigma (filter)",
                x: &t,
                y: &pitch_sig,
            },
        ],
    )
}

/// `navsim replay DIR --model leveling6`: imu.csv + speed.csv, no attitude knowledge.
#[derive(Clone, Copy, Debug, Default)]
pub struct Leveling6Replay;

/// Stationarity from the data: a speed log that never exceeds 0.05 m/s and a gyro
/// whose magnitude never exceeds 0.5 deg/s.
pub fn looks_stationary(log: &LogDir) -> bool {
    let slow = log
        .speed
        .as_ref()
        .is_none_or(|s| s.iter().all(|r| r.speed.abs() < 0.05));
    let still = log
        .imu
        .iter()
        .all(|r| (r.gx * r.gx + r.gy * r.gy + r.gz * r.gz).sqrt() < 0.5f64.to_radians());
    slow && still
}

/// Weakest directions reported by `leveling6 --observability`.
const OBSERVABILITY_DIRECTIONS: usize = 3;

/// The key of the speed log's noise sigma in `meta.toml`.
const SPEED_SIGMA_KEY: &str = "sensors.speed.noise_sigma";

/// The replay's tuning: the paper's ([`Tuning::default`]) with the speed
/// log's sigma from `meta.toml`'s `[sensors.speed] noise_sigma`. Its
/// `bias_sigma` is not used: the six states carry no speed-log bias, and a
/// constant one moves the velocity estimate rather than the innovations (on
/// a simulated S-track with 0.1 m/s of each, the noise alone gives a mean
/// NIS of 1, the two added as noise 0.5), so it is said in `warnings`.
/// Without the section a log with a speed log moving keeps the paper's
/// 0.15 m/s, also said. (`meta.toml` refuses a zero sigma.)
fn replay_tuning(log: &LogDir, stationary: bool, warnings: &mut Vec<Warning>) -> Tuning {
    let mut tuning = Tuning::default();
    let used = log.speed.is_some() && !stationary;
    match log.meta.sensors.speed {
        Some(s) => {
            tuning.speed_sigma = s.noise_sigma;
            if used && s.bias_sigma > 0.0 {
                warnings.push(nav_replay::meta_note(
                    "sensors.speed.bias_sigma",
                    format!(
                        "leveling6 carries no speed-log bias: bias_sigma {} is not used (a \
                         constant bias moves the velocity estimate, not the innovations)",
                        s.bias_sigma
                    ),
                ));
            }
        }
        None if used => {
            warnings.push(nav_replay::missing_section(
                "speed",
                format!(
                    "meta.toml has no [sensors.speed]: the speed log's rows are weighed with \
                     the paper's {} m/s",
                    tuning.speed_sigma
                ),
            ));
        }
        None => {}
    }
    tuning
}

impl ReplayModel for Leveling6Replay {
    fn name(&self) -> &'static str {
        "leveling6"
    }
    fn description(&self) -> &'static str {
        "LEVELING-6 roll/pitch alignment over imu.csv + speed.csv (stationary detected or --stationary)"
    }
    fn has_stationary_mode(&self) -> bool {
        true
    }
    fn can_observe(&self) -> bool {
        true
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        Some(&["imu.csv", "speed.csv", "truth.csv"])
    }
    /// The speed log's noise sigma; the IMU's noise is the paper's tuning
    /// (its accelerometer density covers the bias drift the six states do
    /// not carry), not `[sensors.imu]`.
    fn uses_noise_parameter(&self, key: &str) -> bool {
        key == SPEED_SIGMA_KEY
    }
    /// The tables as CSV and, with truth, the roll and pitch errors with
    /// their `±3 sigma` bounds (`replay-roll.svg`, `replay-pitch.svg`).
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        for table in &output.tables {
            table.write_csv(&dir.join(format!("{}.csv", table.name)))?;
        }
        let Some(t) = output.tables.iter().find(|t| t.name == TABLE) else {
            return Ok(());
        };
        let time = t.column("t");
        for angle in ["roll", "pitch"] {
            nav_replay::output::plot::error_with_sigma(
                &dir.join(format!("replay-{angle}.svg")),
                &format!("{}: {angle} error with ±3 sigma", self.name()),
                &format!("{angle} error [deg]"),
                &time,
                &t.column(&format!("{angle}_error_deg")),
                &t.column(&format!("{angle}_sigma_deg")),
            )?;
        }
        Ok(())
    }
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        // Gravity and the earth rate at the initial latitude and height.
        log.meta.initial.position_for(self.name())?;
        let stationary = options.stationary || looks_stationary(log);
        let mut warnings = Vec::new();
        let opts = LevelingOptions {
            stationary,
            initial_attitude: None,
            tuning: replay_tuning(log, stationary, &mut warnings),
        };
        let start = std::time::Instant::now();
        let (run, observed) = if options.observability || options.smooth {
            let recording = filter::Recording {
                observability: options.observability.then_some(OBSERVABILITY_DIRECTIONS),
                smooth: options.smooth,
            };
            filter::run_recorded::<model::Leveling6, 6>(log, &opts, recording)
                .map_err(RunError::Invalid)?
        } else {
            let run = filter::run(log, &opts).map_err(|e| RunError::Invalid(e.to_string()))?;
            (run, None)
        };
        let runtime_s = start.elapsed().as_secs_f64();
        warnings.extend(nav_replay::covariance_repairs(run.repairs));
        let mut out = ReplayOutput {
            samples: run.samples,
            runtime_s,
            warnings,
            ..Default::default()
        };
        if !stationary && log.speed.is_some() {
            // The speed log's innovations, as every replay with innovations
            // reports them, with a warning for a sigma they say is off
            // (docs/tuning.md).
            out.innovations.push(SensorInnovations {
                sensor: "speed".into(),
                noise_sigma: Some(opts.tuning.speed_sigma),
                gated: run.gated,
                setting: ("meta.toml".into(), SPEED_SIGMA_KEY.into()),
                totals: run.speed_innovations,
            });
            out.metrics.insert(
                "innovations".into(),
                nav_replay::innovations::innovations_json(&out.innovations),
            );
            let off = out.innovations.iter().filter_map(|s| s.warning());
            out.warnings.extend(off.collect::<Vec<_>>());
        }
        if let Some(o) = &observed {
            // Velocity and gravity direction: the solution itself, no
            // estimated sensor state to warn about.
            let (json, _) = nav_replay::observability::json(
                o,
                &<model::Leveling6 as nav_runtime::model::Model<6>>::STATE_NAMES,
                |_, _| None,
            );
            out.metrics.insert("observability".into(), json);
        }
        out.metrics
            .insert("stationary".into(), Value::from(stationary));
        if let Some(truth) = &log.truth {
            // The final errors are those at the last truth row with an
            // estimate: said when that is not the end of the run.
            let errors = errors_at_truth(&run, log);
            // The first estimate is the initial guess: fewer than two truth
            // rows after it score nothing (no final error of 0, no RMS of
            // nothing), as for every other model.
            let start = run.estimates.first().map_or(f64::NEG_INFINITY, |e| e.t);
            let rows = errors.iter().filter(|e| e.0 > start + 1e-9).count();
            if rows < 2 {
                let span = |t: &mut dyn Iterator<Item = f64>| {
                    let first = t.next().unwrap_or(f64::NAN);
                    (first, t.last().unwrap_or(first))
                };
                let (truth_start, truth_end) = span(&mut truth.iter().map(|r| r.t));
                let (imu_start, imu_end) = span(&mut log.imu.iter().map(|r| r.t));
                let why = nav_replay::ins::score::ScoreError::NoOverlap {
                    truth_start,
                    truth_end,
                    imu_start,
                    imu_end,
                    rows,
                };
                return Err(RunError::Invalid(why.to_string()));
            }
            if let (Some(&(t, roll, pitch)), Some(first), Some(last)) =
                (errors.last(), run.estimates.first(), run.estimates.last())
            {
                // A final error of a hundred of the filter's sigmas is not
                // the filter's (the bias floor of a 1 mg accelerometer at
                // rest is 28, tilt NEES 806): a truth of another
                // convention, offset or clock.
                let nees = tilt_nees(roll, pitch, last);
                if nees > FINAL_NEES_WARN {
                    out.warnings.push(Warning::about(
                        WarningKind::Suspicious,
                        "truth.csv",
                        format!(
                            "truth.csv: the final tilt error, {:.3} deg at t = {t} s, is {:.0} of \
                             the filter's sigmas (tilt NEES {nees:.0}): a truth of another \
                             convention, offset or clock, or an error the filter does not model",
                            roll.hypot(pitch).to_degrees(),
                            nees.sqrt()
                        ),
                    ));
                }
                let early = last.t - t;
                if early > (0.05 * (last.t - first.t)).max(1.0) {
                    out.warnings.push(Warning::about(
                        WarningKind::PartialScoring,
                        "truth.csv",
                        format!(
                            "truth.csv: only its rows up to t = {t} s ({} of {}) are scored, \
                             {early:.1} s before the end of the run (t = {} s): the final errors \
                             are not at the end",
                            errors.len(),
                            truth.len(),
                            last.t
                        ),
                    ));
                }
            }
            let scored = score(0, &run, log, options.keep_series)?;
            for key in ["roll_error_final_deg", "pitch_error_final_deg"] {
                out.metrics
                    .insert(key.into(), Value::from(scored.metric(key)));
            }
            out.tables = scored.tables;
            let (roll, pitch) = rms_after(&errors, start);
            out.metrics
                .insert("roll_error_rms_deg".into(), Value::from(roll));
            out.metrics
                .insert("pitch_error_rms_deg".into(), Value::from(pitch));
        }
        if options.smooth {
            let mut smoothed = Map::new();
            smoothed.insert("estimates".into(), Value::from(run.smoothed.len()));
            if log.truth.is_some() {
                let errors = filter::errors_of(&run.smoothed, log);
                let start = run.estimates.first().map_or(f64::NEG_INFINITY, |e| e.t);
                let (roll, pitch) = rms_after(&errors, start);
                smoothed.insert("roll_error_rms_deg".into(), Value::from(roll));
                smoothed.insert("pitch_error_rms_deg".into(), Value::from(pitch));
                if options.keep_series {
                    out.tables
                        .push(error_table(SMOOTHED_TABLE, &run.smoothed, &errors));
                }
            }
            out.metrics
                .insert("smoothed".into(), Value::Object(smoothed));
        }
        Ok(out)
    }
}
