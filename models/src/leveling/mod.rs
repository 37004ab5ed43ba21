//! LEVELING-6 (docs/models/leveling6.md): the model, its simulation, the filter run,
//! and the `leveling-*` scenarios and `leveling6` replay model of `navsim`.

pub mod filter;
pub mod model;
pub mod observability;
mod replay;
pub mod scheduled_filter;
pub mod score;
pub mod simulation;
mod smoothed;

use crate::harness::plot::{self, Line};
use crate::harness::{RunError, RunOptions, RunResult, RunTable, Scenario};
use filter::{LevelingOptions, Tuning};
use nav_replay::output::series::SeriesSink;
use nav_runtime::imu::{ImuSpec, MG};
use nav_runtime::log::{LogDir, LogSource, TruthRow};
use nav_runtime::nalgebra::{Matrix2, Vector2};
use nav_runtime::sensors::{derive_seed, normal};
use nav_runtime::stats;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use score::{LevelScore, TruthErrors};
use serde_json::{Map, Value};
use simulation::{Biases, Motion};
use std::path::Path;

pub use model::{Leveling6, Leveling6Moving, Leveling6Stationary};
pub use replay::{looks_stationary, Leveling6Replay};

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

/// Name of the table of the roll and pitch errors.
const TABLE: &str = "attitude";

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
    let (run, scored) = scored_run(&log, &opts, options.keep_series)?;
    let mut r = score(seed, &run, scored)?;
    // The same run with the horizontal accelerometer bias as states.
    opts.tuning.bias_states = true;
    let (run8, scored8) = scored_run(&log, &opts, false)?;
    for (key, value) in final_metrics(&run8, &scored8)? {
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

/// The run over a simulated `log`, scored against its truth as it goes
/// (the error table kept with `keep_series`).
fn scored_run(
    log: &LogDir,
    options: &LevelingOptions,
    keep_series: bool,
) -> Result<(filter::LevelingRun, LevelScore), RunError> {
    let source = LogSource::Memory(log);
    let truth = source
        .rows::<TruthRow>()?
        .ok_or_else(|| RunError::Invalid("no truth".into()))?;
    let table = SeriesSink::new(TABLE, &score::COLUMNS, None, keep_series)?;
    let mut errors = TruthErrors::new(truth, table)?;
    let run = filter::run(&source, options, &mut |e| errors.push(e))?;
    let after = run.first.map_or(f64::NEG_INFINITY, |e| e.t);
    let scored = errors.finish(run.mean_period(), after)?;
    Ok((run, scored))
}

/// Prefix of the metrics of the filter with bias states.
const BIAS_STATES: &str = "accel_bias_states";

/// Final tilt magnitude (deg) and the tilt NEES (2 dof) of the last estimate,
/// plus the roll and pitch errors and sigmas (deg).
fn final_metrics(
    run: &filter::LevelingRun,
    scored: &LevelScore,
) -> Result<Vec<(&'static str, f64)>, RunError> {
    let (_, roll, pitch) = scored
        .last
        .ok_or_else(|| RunError::Invalid("no estimate at a truth time".into()))?;
    let last = run
        .last
        .ok_or_else(|| RunError::Invalid("no estimate".into()))?;
    Ok(vec![
        ("roll_error_final_deg", roll.to_degrees()),
        ("pitch_error_final_deg", pitch.to_degrees()),
        ("tilt_error_final_deg", roll.hypot(pitch).to_degrees()),
        ("roll_sigma_final_deg", last.roll_sigma.to_degrees()),
        ("pitch_sigma_final_deg", last.pitch_sigma.to_degrees()),
        ("tilt_nees_final", tilt_nees(roll, pitch, &last)),
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

fn score(seed: u64, run: &filter::LevelingRun, scored: LevelScore) -> Result<RunResult, RunError> {
    let (_, roll_final, pitch_final) = scored
        .last
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
    if let Some(last) = run.last {
        r = r
            .with_metric("roll_sigma_final_deg", last.roll_sigma.to_degrees())
            .with_metric("pitch_sigma_final_deg", last.pitch_sigma.to_degrees());
    }
    r.tables.extend(scored.table);
    Ok(r)
}

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
