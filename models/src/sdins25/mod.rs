//! SDINS-25 (docs/models/sdins25.md): the model, its simulation, the filter run
//! over a log, scoring, and the `lawnmower-*` scenarios and `sdins25` replay
//! model of `navsim`.
//!
//! A scenario run is simulate(seed) -> [`LogDir`] -> filter over the log ->
//! score against truth.csv, so `navsim simulate` followed by `navsim replay
//! --model sdins25` reproduces `navsim scenario` exactly.

mod aiding;
pub mod faults;
pub mod filter;
pub mod lockout;
pub mod model;
pub mod replay_loop;
pub mod replay_output;
pub mod score;
pub mod simulation;
pub mod soak;
pub use crate::navigator::vehicle;

#[cfg(test)]
mod model_tests;

use std::marker::PhantomData;
use std::path::Path;

use nav_runtime::log::{LogDir, LogFiles, LogSource};
use nav_runtime::stats;
use serde_json::{json, Map, Value};

use crate::harness::plot::{self, Line};
use crate::harness::report::summary_of;
use crate::harness::{
    metric_values, ReplayModel, ReplayOptions, ReplayOutput, RunError, RunHealth, RunOptions,
    RunResult, RunTable, Scenario,
};
use filter::{FilterOptions, InsRun, Sdins25Run};
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

/// Runs the filter of vehicle `V` over `log` with estimates at the truth
/// times and scores it (without truth no estimates are kept: nothing is
/// sized by the log's time span). `compass_bias`: the true compass bias,
/// when known, for the bias-estimation columns.
pub fn run_and_score_vehicle<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
    compass_bias: Option<f64>,
) -> Result<(InsRun<V, N>, Option<Scored>), RunError> {
    let times: Vec<f64> = log
        .truth
        .as_ref()
        .map_or_else(Vec::new, |t| t.iter().map(|r| r.t).collect());
    let run = filter::run_vehicle::<V, N>(log, options, &times)?;
    let scored = log
        .truth
        .as_ref()
        .map(|t| score::score(&run.estimates, t, compass_bias, log.imu_time_span()))
        .transpose()
        .map_err(|e| RunError::Invalid(e.to_string()))?;
    Ok((run, scored))
}

/// The smoothed estimates of `run` (recorded with [`FilterOptions::smooth`])
/// scored against the truth of `log`, as [`run_and_score_vehicle`] scores the
/// forward ones.
pub fn score_smoothed<V: InsVehicle<N>, const N: usize>(
    run: &InsRun<V, N>,
    log: &LogDir,
    compass_bias: Option<f64>,
) -> Result<Option<Scored>, RunError> {
    let (Some(truth), Some(smoothed)) = (log.truth.as_ref(), run.smoothed.as_ref()) else {
        return Ok(None);
    };
    let mut s = score::score(smoothed, truth, compass_bias, log.imu_time_span())
        .map_err(|e| RunError::Invalid(format!("smoothed run: {e}")))?;
    s.table.name = SMOOTHED_TABLE.to_string();
    Ok(Some(s))
}

/// Name of the smoothed error table (same columns as [`score::TABLE`]).
pub const SMOOTHED_TABLE: &str = "smoothed_errors";

/// The error keys of a scored run, reported forward and (under `smoothed`)
/// smoothed.
pub(crate) const ERROR_KEYS: [&str; 4] = [
    "horizontal_error_final_m",
    "horizontal_error_rms_m",
    "depth_error_rms_m",
    "nees_mean",
];

pub(crate) fn error_values(s: &Scored) -> [f64; 4] {
    [
        s.horizontal_error_final_m,
        s.horizontal_error_rms_m,
        s.depth_error_rms_m,
        s.nees_mean,
    ]
}

/// The metrics of a run (scored when truth exists).
pub(crate) fn metrics<V: InsVehicle<N>, const N: usize>(
    run: &InsRun<V, N>,
    scored: Option<&Scored>,
) -> Vec<(String, f64)> {
    let mut m = vec![
        ("samples".to_string(), run.samples as f64),
        ("runtime_s".to_string(), run.runtime_s),
    ];
    if let Some(s) = scored {
        m.extend([
            (
                "horizontal_error_final_m".into(),
                s.horizontal_error_final_m,
            ),
            ("horizontal_error_rms_m".into(), s.horizontal_error_rms_m),
            ("depth_error_rms_m".into(), s.depth_error_rms_m),
            ("nees_mean".into(), s.nees_mean),
            ("scored_seconds".into(), s.scored_seconds),
            (
                "compass_bias_error_final_deg".into(),
                s.compass_bias_error_final_deg,
            ),
            (
                "compass_bias_sigma_final_deg".into(),
                s.compass_bias_sigma_final_deg,
            ),
        ]);
    }
    m
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

/// Horizontal error of the forward and the smoothed estimates with their
/// 1-sigma bands (`<prefix>-smoothed-horizontal.svg`), when `tables` holds
/// both error tables; nothing otherwise.
pub fn write_smoothed_plot(
    name: &str,
    prefix: &str,
    tables: &[RunTable],
    dir: &Path,
) -> Result<(), RunError> {
    let find = |n: &str| tables.iter().find(|t| t.name == n);
    let (Some(forward), Some(smoothed)) = (find(score::TABLE), find(SMOOTHED_TABLE)) else {
        return Ok(());
    };
    let horizontal = |t: &RunTable, a: &str, b: &str| -> Vec<f64> {
        t.column(a)
            .iter()
            .zip(t.column(b))
            .map(|(x, y)| x.hypot(y))
            .collect()
    };
    let time = forward.column("t");
    let (fe, fs) = (
        horizontal(forward, "err_n", "err_e"),
        horizontal(forward, "sig_n", "sig_e"),
    );
    let (se, ss) = (
        horizontal(smoothed, "err_n", "err_e"),
        horizontal(smoothed, "sig_n", "sig_e"),
    );
    let line = |label, y| Line { label, x: &time, y };
    plot::lines(
        &dir.join(format!("{prefix}-smoothed-horizontal.svg")),
        &format!("{name}: horizontal error, forward and smoothed, with 1-sigma"),
        "t [s]",
        "horizontal error [m]",
        &[
            line("forward error", &fe),
            line("forward 1-sigma", &fs),
            line("smoothed error", &se),
            line("smoothed 1-sigma", &ss),
        ],
    )
}

/// Runs whose plots `--out` draws (every run's CSV is written).
pub const PLOTTED_RUNS: usize = 5;

/// Track, position / velocity / attitude errors with their `±3 sigma` bounds
/// and the NEES with its 95 % band, from one run's table.
pub fn write_plots(name: &str, prefix: &str, t: &RunTable, dir: &Path) -> Result<(), RunError> {
    let time = t.column("t");
    let file = |s: &str| dir.join(format!("{prefix}-{s}.svg"));
    let (tn, te, en, ee) = (
        t.column("true_n"),
        t.column("true_e"),
        t.column("est_n"),
        t.column("est_e"),
    );
    plot::tracks(
        &file("track"),
        &format!("{name} {prefix}: horizontal track"),
        "east [m]",
        "north [m]",
        &[
            Line {
                label: "truth",
                x: &te,
                y: &tn,
            },
            Line {
                label: "estimate",
                x: &ee,
                y: &en,
            },
        ],
    )?;
    let groups = [
        (
            "position",
            "m",
            ["n", "e", "d"],
            ["north", "east", "down"],
            "",
        ),
        (
            "velocity",
            "m/s",
            ["vn", "ve", "vd"],
            ["north", "east", "down"],
            "",
        ),
        (
            "attitude",
            "deg",
            ["roll", "pitch", "yaw"],
            ["roll", "pitch", "yaw"],
            "_deg",
        ),
    ];
    for (group, unit, keys, labels, suffix) in groups {
        for (k, label) in keys.iter().zip(labels) {
            let e = t.column(&format!("err_{k}{suffix}"));
            let s = t.column(&format!("sig_{k}{suffix}"));
            plot::error_with_sigma(
                &file(&format!("{group}-{label}")),
                &format!("{name} {prefix}: {group} error, {label}, with ±3 sigma"),
                &format!("{label} error [{unit}]"),
                &time,
                &e,
                &s,
            )?;
        }
    }
    let band = (
        nav_runtime::gate::chi_square_quantile(0.025, NEES_DOF).unwrap_or(f64::NAN),
        nav_runtime::gate::chi_square_quantile(0.975, NEES_DOF).unwrap_or(f64::NAN),
    );
    plot::nees(
        &file("nees"),
        &format!("{name} {prefix}: NEES of the 9 navigation states (95 % band, 9 dof)"),
        &time,
        &t.column("nees"),
        Some(band),
    )
}

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

/// `navsim replay DIR --model <V::REPLAY_NAME>`: the filter of vehicle `V`
/// (`N` states) over a log, scored against `truth.csv` when present. One line
/// in [`crate::cli::replay_models`] registers a vehicle:
/// `Box::new(InsReplay::<Sdins20, 20>::new())`.
pub struct InsReplay<V, const N: usize>(PhantomData<fn() -> V>);

impl<V, const N: usize> InsReplay<V, N> {
    /// The replay model of `V`.
    pub const fn new() -> Self {
        Self(PhantomData)
    }
}

impl<V, const N: usize> Default for InsReplay<V, N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<V, const N: usize> Clone for InsReplay<V, N> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<V, const N: usize> Copy for InsReplay<V, N> {}

impl<V: InsVehicle<N>, const N: usize> std::fmt::Debug for InsReplay<V, N> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "InsReplay<{}>", V::NAME)
    }
}

/// `navsim replay DIR --model sdins25`.
pub type Sdins25Replay = InsReplay<Sdins25, 25>;

impl<V: InsVehicle<N>, const N: usize> ReplayModel for InsReplay<V, N> {
    fn name(&self) -> &'static str {
        V::REPLAY_NAME
    }
    fn description(&self) -> &'static str {
        V::DESCRIPTION
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        // Aiding files of sensors `V` lacks are reported by the replay itself.
        // The echo sounder's altitude gates the DVL (above its range).
        let p = vehicle::Present::of::<V, N>();
        if p.gnss || p.baro || p.mag {
            return Some(&[
                "imu.csv",
                "dvl.csv",
                "depth.csv",
                "heading.csv",
                "usbl.csv",
                "altitude.csv",
                "gnss.csv",
                "baro.csv",
                "mag.csv",
                "truth.csv",
            ]);
        }
        Some(&[
            "imu.csv",
            "dvl.csv",
            "depth.csv",
            "heading.csv",
            "usbl.csv",
            "altitude.csv",
            "truth.csv",
        ])
    }
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        replay_output::replay_source::<V, N>(&LogSource::Memory(log), options, None)
    }
    fn replay_files(
        &self,
        files: &LogFiles,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        replay_output::replay_source::<V, N>(&LogSource::Files(files), options, out)
    }
    fn shares_imu(&self) -> bool {
        true
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        for t in &output.tables {
            t.write_csv(&dir.join(format!("{}.csv", t.name)))?;
            if t.name == score::TABLE {
                write_plots(V::REPLAY_NAME, "replay", t, dir)?;
            }
        }
        write_smoothed_plot(V::REPLAY_NAME, "replay", &output.tables, dir)
    }
}
