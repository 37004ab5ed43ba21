//! SDINS-25 (docs/models/sdins25.md): the model, its simulation, the filter run
//! over a log, scoring, and the `lawnmower-*` scenarios and `sdins25` replay
//! model of `navsim`.
//!
//! A scenario run is simulate(seed) -> [`LogDir`] -> filter over the log ->
//! score against truth.csv, so `navsim simulate` followed by `navsim replay
//! --model sdins25` reproduces `navsim scenario` exactly.

pub mod clock_survey;
pub mod faults;
pub mod filter;
pub mod model;
pub mod simulation;
pub mod soak;
pub use nav_ins::{lockout, vehicle};
pub use nav_replay::ins::{
    error_values, metrics, output as replay_output, replay_loop, run_and_score_vehicle, score,
    score_smoothed, write_plots, write_smoothed_plot, InsReplay, ERROR_KEYS, SMOOTHED_TABLE,
};

#[cfg(test)]
mod model_tests;

use std::path::Path;

use nav_runtime::log::LogDir;
use nav_runtime::stats;
use serde_json::{json, Map, Value};

use crate::harness::plot;
use crate::harness::report::summary_of;
use crate::harness::{
    metric_values, RunError, RunHealth, RunOptions, RunResult, RunTable, Scenario,
};
use filter::{FilterOptions, Sdins25Run};
use score::{nees_band_95, Scored, NEES_DOF};
use simulation::SimConfig;
use vehicle::InsVehicle;

pub use model::{
    Sdins25, Sdins25Compass, Sdins25CompassSmallAngle, Sdins25Depth, Sdins25Dvl, Sdins25Usbl,
};

/// One of the `lawnmower-*` scenarios.
#[derive(Clone, Copy, Debug)]
pub struct LawnMower {
    name: &'static str,
    description: &'static str,
    /// What is simulated.
    pub config: SimConfig,
}

/// `lawnmower-imu-only`, `lawnmower-dvl`, `lawnmower-usbl`, `lawnmower-usbl-deep`.
pub fn scenarios() -> Vec<LawnMower> {
    vec![
        LawnMower {
            name: "lawnmower-imu-only",
            description: "SDINS-25 lawn-mowing survey, 500 s, IMU only (no aiding)",
            config: SimConfig::imu_only(),
        },
        LawnMower {
            name: "lawnmower-dvl",
            description: "SDINS-25 lawn-mowing survey, 500 s, IMU + DVL + depth + compass",
            config: SimConfig::dvl(),
        },
        LawnMower {
            name: "lawnmower-usbl",
            description: "SDINS-25 survey, IMU + DVL + depth + compass + Trackpoint II USBL",
            config: SimConfig::usbl(),
        },
        LawnMower {
            name: "lawnmower-usbl-deep",
            description:
                "SDINS-25 survey at 6000 m, Posidonia 6000 USBL (0.3 % range, late fixes) + DVL",
            config: SimConfig::usbl_deep(),
        },
        LawnMower {
            name: "lawnmower-usbl-10s",
            description: "SDINS-25 shallow survey, calibrated USBL (0.5 m) every 10 s + DVL",
            config: SimConfig::usbl_10s(),
        },
    ]
}

/// The scenario named `name`.
pub fn scenario(name: &str) -> Option<LawnMower> {
    scenarios().into_iter().find(|s| s.name == name)
}

/// SDINS-25 is replayed by the shared loop with every log sensor.
impl InsVehicle<25> for Sdins25 {
    const REPLAY_NAME: &'static str = "sdins25";
    const DESCRIPTION: &'static str = "SDINS-25 error-state INS over imu.csv + any of dvl/depth/heading/usbl (late USBL fixes by travel time)";
    type Depth = Sdins25Depth;
    type Dvl = Sdins25Dvl;
    type Compass = Sdins25Compass;
    type CompassSmallAngle = Sdins25CompassSmallAngle;
    type Usbl = Sdins25Usbl;
    type Gnss = vehicle::Absent;
    type Baro = vehicle::Absent;
    type Mag = vehicle::Absent;
}

/// Runs the SDINS-25 filter over `log` and scores it: [`run_and_score_vehicle`]
/// of [`Sdins25`].
pub fn run_and_score(
    log: &LogDir,
    options: &FilterOptions,
    compass_bias: Option<f64>,
) -> Result<(Sdins25Run, Option<Scored>), RunError> {
    run_and_score_vehicle::<Sdins25, 25>(log, options, compass_bias)
}

/// One scenario run: simulate, filter over the log, score.
pub fn run_one(config: &SimConfig, seed: u64, keep_series: bool) -> Result<RunResult, RunError> {
    let options = RunOptions {
        keep_series,
        ..RunOptions::default()
    };
    run_one_with(config, seed, &options)
}

/// The simulated log of `seed` with the data faults of `faults` applied, and
/// the number of samples each fault changed.
pub fn simulate_with_faults(
    config: &SimConfig,
    seed: u64,
    faults: &[String],
) -> Result<(simulation::Simulated, faults::Injected), RunError> {
    let mut sim = simulation::simulate(config, seed);
    let injected = faults::apply(&mut sim.log, faults, seed)?;
    Ok((sim, injected))
}

/// [`run_one`] with the faults of `options` injected (see [`faults`]).
pub fn run_one_with(
    config: &SimConfig,
    seed: u64,
    options: &RunOptions,
) -> Result<RunResult, RunError> {
    let (sim, injected) = simulate_with_faults(config, seed, &options.faults)?;
    let bias = config.compass.then_some(sim.errors.compass_bias);
    let filter_options = FilterOptions {
        delivery: faults::delivery(&options.faults, seed),
        smooth: options.smooth,
        ..FilterOptions::default()
    };
    let (run, scored) =
        run_and_score(&sim.log, &filter_options, bias).map_err(|e| RunError::Failed {
            seed,
            message: e.to_string(),
        })?;
    let mut r = RunResult::new(seed);
    for (k, v) in metrics(&run, scored.as_ref()) {
        r = r.with_metric(&k, v);
    }
    r.health = run.health_counts();
    let smoothed = score_smoothed(&run, &sim.log, bias).map_err(|e| RunError::Failed {
        seed,
        message: e.to_string(),
    })?;
    if let Some(s) = &smoothed {
        for (k, v) in ERROR_KEYS.iter().zip(error_values(s)) {
            r = r.with_metric(&format!("smoothed_{k}"), v);
        }
    }
    for (name, n) in injected {
        r = r.with_metric(&format!("fault_{name}_injected"), n as f64);
    }
    let keep_series = options.keep_series;
    if let (true, Some(s)) = (keep_series, scored) {
        r.tables.push(s.table);
        if let Some(sm) = smoothed {
            r.tables.push(sm.table);
        }
    }
    Ok(r)
}

/// The `smoothed` object of a Monte Carlo summary: the forward error keys of
/// the smoothed estimates, the NEES band, and the per-run ratio of smoothed to
/// forward horizontal RMS.
fn smoothed_summary(runs: &[RunResult]) -> Value {
    let mut m = Map::new();
    for key in &ERROR_KEYS[..3] {
        m.insert((*key).into(), summary_of(runs, &format!("smoothed_{key}")));
    }
    let nees_mean = stats::mean(&metric_values(runs, "smoothed_nees_mean"));
    let (lo, hi) = nees_band_95(NEES_DOF, runs.len());
    m.insert("nees_mean".into(), Value::from(nees_mean));
    m.insert("nees_band_95".into(), json!([lo, hi]));
    m.insert(
        "nees_consistent".into(),
        Value::from(nees_mean >= lo && nees_mean <= hi),
    );
    let ratio: Vec<f64> = metric_values(runs, "smoothed_horizontal_error_rms_m")
        .iter()
        .zip(metric_values(runs, "horizontal_error_rms_m"))
        .map(|(s, f)| s / f)
        .collect();
    m.insert(
        "horizontal_rms_ratio".into(),
        crate::harness::report::summary_value(&ratio),
    );
    Value::Object(m)
}

/// The `health` object: per-sensor totals over runs and covariance repairs.
pub(crate) fn health(runs: &[RunResult]) -> Value {
    RunHealth::total(runs.iter().map(|r| &r.health)).json()
}

impl Scenario for LawnMower {
    fn name(&self) -> &'static str {
        self.name
    }
    fn description(&self) -> &'static str {
        self.description
    }
    fn default_runs(&self) -> usize {
        100
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn faults(&self) -> &'static [&'static str] {
        let c = &self.config;
        faults::accepted(c.usbl, c.dvl || c.depth || c.compass)
    }
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError> {
        run_one_with(&self.config, seed, options)
    }
    fn summarize(
        &self,
        runs: &[RunResult],
        options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError> {
        let mut m = Map::new();
        for key in [
            "horizontal_error_final_m",
            "horizontal_error_rms_m",
            "depth_error_rms_m",
        ] {
            m.insert(key.into(), summary_of(runs, key));
        }
        let nees = metric_values(runs, "nees_mean");
        let nees_mean = stats::mean(&nees);
        let (lo, hi) = nees_band_95(NEES_DOF, runs.len());
        m.insert("nees_mean".into(), Value::from(nees_mean));
        m.insert("nees_dof".into(), Value::from(NEES_DOF));
        m.insert("nees_band_95".into(), json!([lo, hi]));
        m.insert(
            "nees_consistent".into(),
            Value::from(nees_mean >= lo && nees_mean <= hi),
        );
        if self.config.compass {
            let err: Vec<f64> = metric_values(runs, "compass_bias_error_final_deg")
                .iter()
                .map(|e| e.abs())
                .collect();
            m.insert(
                "compass_bias_error_final_deg".into(),
                crate::harness::report::summary_value(&err),
            );
            m.insert(
                "compass_bias_sigma_final_deg".into(),
                Value::from(stats::mean(&metric_values(
                    runs,
                    "compass_bias_sigma_final_deg",
                ))),
            );
        }
        m.insert("runtime_s".into(), summary_of(runs, "runtime_s"));
        m.insert("health".into(), health(runs));
        if options.smooth {
            m.insert("smoothed".into(), smoothed_summary(runs));
        }
        if !options.faults.is_empty() {
            let mut inj = Map::new();
            for f in &options.faults {
                let total: f64 = metric_values(runs, &format!("fault_{f}_injected"))
                    .iter()
                    .filter(|x| x.is_finite())
                    .sum();
                inj.insert(f.clone(), Value::from(total));
            }
            m.insert("faults_injected".into(), Value::Object(inj));
        }
        Ok(m)
    }
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        crate::harness::write_run_tables(runs, dir)?;
        for run in runs.iter().take(PLOTTED_RUNS) {
            if let Some(t) = run.tables.iter().find(|t| t.name == score::TABLE) {
                write_plots(self.name, &format!("run-{}", run.seed), t, dir)?;
            }
            write_smoothed_plot(self.name, &format!("run-{}", run.seed), &run.tables, dir)?;
        }
        write_ensemble_nees(self.name, runs, dir)
    }
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        Some(simulate_with_faults(&self.config, seed, &options.faults).map(|(sim, _)| sim.log))
    }
}

/// Runs whose plots `--out` draws (every run's CSV is written).
pub const PLOTTED_RUNS: usize = 5;

/// The NEES averaged over runs at each time, with the 95 % band of the ensemble.
fn write_ensemble_nees(name: &str, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
    let tables: Vec<&RunTable> = runs
        .iter()
        .filter_map(|r| r.tables.iter().find(|t| t.name == score::TABLE))
        .collect();
    let Some(first) = tables.first() else {
        return Ok(());
    };
    let len = tables.iter().map(|t| t.rows.len()).min().unwrap_or(0);
    let t: Vec<f64> = first.rows[..len].iter().map(|r| r[0]).collect();
    let col = COLUMNS_NEES;
    let mean: Vec<f64> = (0..len)
        .map(|i| {
            stats::mean(
                &tables
                    .iter()
                    .map(|tab| tab.rows[i][col])
                    .collect::<Vec<_>>(),
            )
        })
        .collect();
    let mut table = RunTable::new("ensemble_nees", &["t", "nees_mean"]);
    for (ti, m) in t.iter().zip(&mean) {
        table.push(&[*ti, *m]);
    }
    table.write_csv(&dir.join("ensemble-nees.csv"))?;
    plot::nees(
        &dir.join("ensemble-nees.svg"),
        &format!(
            "{name}: NEES averaged over {} runs (95 % band, 9 dof)",
            tables.len()
        ),
        &t,
        &mean,
        Some(nees_band_95(NEES_DOF, tables.len())),
    )
}

/// Index of the `nees` column in [`score::COLUMNS`].
const COLUMNS_NEES: usize = 19;

/// `navsim replay DIR --model sdins25`.
pub type Sdins25Replay = InsReplay<Sdins25, 25>;
