//! Scenario and replay-model traits, the Monte Carlo driver, shards and merge.
//!
//! # Adding a scenario
//! Implement [`Scenario`] and add one line to [`crate::cli::scenarios`]. A run is a
//! pure function of its seed and [`RunOptions`] ([`Scenario::run_one`]); the driver
//! runs seeds `seed, seed + 1, ..., seed + runs - 1` in parallel and hands the results
//! to [`Scenario::summarize`] **in seed order**, so the JSON does not depend on the
//! number of threads or on how the seeds were split into shards.
//!
//! # Adding a replay model
//! Implement [`ReplayModel`] and add one line to [`crate::cli::replay_models`].
//! A vehicle made of the INS core block and any of the depth, DVL, compass and
//! USBL blocks needs no `ReplayModel` of its own: implement
//! [`crate::sdins25::vehicle::InsVehicle`] for it (which generated sensor reads
//! which log file) and register `crate::sdins25::InsReplay::<Vehicle, N>::new()`.
//!
//! # Shards
//! `--shard K/N` runs the seed indices `i` (0-based) with `i % N == K - 1` and writes a
//! [`ShardFile`] (`shard-K-of-N.json`) holding every per-run [`RunResult`];
//! [`merge_shards`] checks that a set of shard files covers every seed exactly once
//! and gives back the results in seed order, from which [`summary_json`] builds the
//! same JSON the unsharded run prints.

use std::collections::BTreeMap;
use std::fmt;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::str::FromStr;

pub use indicatif::ProgressBar;
use nav_runtime::log::{LogDir, LogError};
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::{Map, Value};

/// Options shared by every run of a scenario (from the command line).
#[derive(Debug, Clone, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct RunOptions {
    /// Fault names from `--faults` (each one of [`Scenario::faults`]).
    #[serde(default)]
    pub faults: Vec<String>,
    /// `--draw-biases`: draw sensor biases per run instead of using zero biases.
    #[serde(default)]
    pub draw_biases: bool,
    /// Keep per-run time series ([`RunResult::tables`]); set when `--out` is given.
    #[serde(skip)]
    pub keep_series: bool,
    /// `--smooth`: also smooth each run (fixed-interval smoother) and report
    /// the smoothed errors beside the forward ones.
    #[serde(default)]
    pub smooth: bool,
}

impl RunOptions {
    /// Whether fault `name` was requested.
    pub fn has_fault(&self, name: &str) -> bool {
        self.faults.iter().any(|f| f == name)
    }
}

/// A per-run time series, written as `run-<seed>-<name>.csv` under `--out`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunTable {
    /// Table name (part of the file name).
    pub name: String,
    /// Column names.
    pub columns: Vec<String>,
    /// Rows, each with one value per column.
    pub rows: Vec<Vec<f64>>,
}

impl RunTable {
    /// An empty table with the given columns.
    pub fn new(name: &str, columns: &[&str]) -> Self {
        RunTable {
            name: name.to_string(),
            columns: columns.iter().map(|c| c.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row (must have one value per column).
    pub fn push(&mut self, row: &[f64]) {
        debug_assert_eq!(row.len(), self.columns.len());
        self.rows.push(row.to_vec());
    }

    /// The values of one column (empty if there is no such column).
    pub fn column(&self, name: &str) -> Vec<f64> {
        match self.columns.iter().position(|c| c == name) {
            Some(i) => self.rows.iter().map(|r| r[i]).collect(),
            None => Vec::new(),
        }
    }

    /// Writes the table as CSV.
    pub fn write_csv(&self, path: &Path) -> Result<(), RunError> {
        use std::io::Write;
        let io = |e| RunError::io(path, e);
        let mut w = std::io::BufWriter::new(std::fs::File::create(path).map_err(io)?);
        writeln!(w, "{}", self.columns.join(",")).map_err(io)?;
        for row in &self.rows {
            let cells: Vec<String> = row
                .iter()
                .map(|v| nav_runtime::log::format_f64(*v))
                .collect();
            writeln!(w, "{}", cells.join(",")).map_err(io)?;
        }
        w.flush().map_err(io)
    }
}

/// The result of one Monte Carlo run.
///
/// `metrics` and `extra` travel through shard files (JSON) and must hold everything
/// [`Scenario::summarize`] needs; `tables` stay in memory (only with `--out`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// The run's seed.
    pub seed: u64,
    /// Scalar metrics of the run (e.g. `horizontal_error_final_m`). Non-finite values
    /// survive shard files (stored as strings).
    #[serde(with = "float_map")]
    pub metrics: BTreeMap<String, f64>,
    /// Anything else `summarize` needs (free-form JSON; `null` if unused).
    #[serde(default, skip_serializing_if = "Value::is_null")]
    pub extra: Value,
    /// Time series for `--out` (not serialized).
    #[serde(skip)]
    pub tables: Vec<RunTable>,
}

impl RunResult {
    /// A result with no metrics yet.
    pub fn new(seed: u64) -> Self {
        RunResult {
            seed,
            metrics: BTreeMap::new(),
            extra: Value::Null,
            tables: Vec::new(),
        }
    }

    /// Sets a metric (builder style).
    pub fn with_metric(mut self, key: &str, value: f64) -> Self {
        self.metrics.insert(key.to_string(), value);
        self
    }

    /// A metric, NaN if absent.
    pub fn metric(&self, key: &str) -> f64 {
        self.metrics.get(key).copied().unwrap_or(f64::NAN)
    }
}

/// `metric(key)` of every run, in the order of `runs`.
pub fn metric_values(runs: &[RunResult], key: &str) -> Vec<f64> {
    runs.iter().map(|r| r.metric(key)).collect()
}

mod float_map {
    use super::*;
    use serde::de::Error as _;
    use serde::{Deserializer, Serializer};

    pub fn serialize<S: Serializer>(m: &BTreeMap<String, f64>, s: S) -> Result<S::Ok, S::Error> {
        let out: BTreeMap<&str, Value> = m
            .iter()
            .map(|(k, &v)| {
                let v = if v.is_finite() {
                    Value::from(v)
                } else if v.is_nan() {
                    Value::from("nan")
                } else if v > 0.0 {
                    Value::from("inf")
                } else {
                    Value::from("-inf")
                };
                (k.as_str(), v)
            })
            .collect();
        out.serialize(s)
    }

    pub fn deserialize<'de, D: Deserializer<'de>>(d: D) -> Result<BTreeMap<String, f64>, D::Error> {
        let raw: BTreeMap<String, Value> = BTreeMap::deserialize(d)?;
        raw.into_iter()
            .map(|(k, v)| {
                let x = match &v {
                    Value::Number(n) => n.as_f64(),
                    Value::String(s) if s == "nan" => Some(f64::NAN),
                    Value::String(s) if s == "inf" => Some(f64::INFINITY),
                    Value::String(s) if s == "-inf" => Some(f64::NEG_INFINITY),
                    _ => None,
                };
                x.map(|x| (k.clone(), x))
                    .ok_or_else(|| D::Error::custom(format!("metric `{k}`: not a number: {v}")))
            })
            .collect()
    }
}

/// Errors of scenarios, replay models and the driver. The `Display` text is one line
/// and names what is wrong (the command line prints it after `error: `).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// A bad value (option, argument, missing sensor, ...).
    #[error("{0}")]
    Invalid(String),
    /// One run failed.
    #[error("run with seed {seed} failed: {message}")]
    Failed {
        /// The run's seed.
        seed: u64,
        /// Why.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A log directory could not be read or written.
    #[error(transparent)]
    Log(#[from] LogError),
    /// A plot could not be drawn.
    #[error("plot {}: {message}", path.display())]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A shard file is unreadable or shard files do not fit together.
    #[error("{}: {message}", path.display())]
    Shard {
        /// The shard file (or directory).
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl RunError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        RunError::Io {
            path: path.into(),
            source,
        }
    }
}

/// A built-in simulation scenario.
pub trait Scenario: Send + Sync {
    /// The name used on the command line (`navsim scenario <NAME>`).
    fn name(&self) -> &'static str;
    /// One line for `navsim list`.
    fn description(&self) -> &'static str {
        ""
    }
    /// Number of Monte Carlo runs without `--runs`.
    fn default_runs(&self) -> usize;
    /// Whether `--smooth` is supported (the run can be recorded and smoothed).
    fn can_smooth(&self) -> bool {
        false
    }
    /// Fault names accepted by `--faults` (default: none).
    fn faults(&self) -> &'static [&'static str] {
        &[]
    }
    /// Runs one simulation + estimation with `seed`. Must be deterministic in
    /// `(seed, options)` and must not print to stdout.
    fn run_one(&self, seed: u64, options: &RunOptions) -> Result<RunResult, RunError>;
    /// Scenario-specific JSON keys from all runs (in seed order). The driver adds
    /// `scenario`, `runs` and `seed`.
    fn summarize(
        &self,
        runs: &[RunResult],
        options: &RunOptions,
    ) -> Result<Map<String, Value>, RunError>;
    /// Writes per-run CSV files and plots into `dir` (which exists). The default writes
    /// each run's tables as `run-<seed>-<table>.csv`.
    fn write_outputs(&self, runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
        write_run_tables(runs, dir)
    }
    /// The synthetic sensor log of run `seed` (for `navsim simulate`), if the scenario
    /// can produce one. Replaying it should reproduce [`Scenario::run_one`].
    fn simulate_log(&self, seed: u64, options: &RunOptions) -> Option<Result<LogDir, RunError>> {
        let _ = (seed, options);
        None
    }
}

/// Writes every table of every run as `run-<seed>-<table>.csv` into `dir`.
pub fn write_run_tables(runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
    for run in runs {
        for table in &run.tables {
            table.write_csv(&dir.join(format!("run-{}-{}.csv", run.seed, table.name)))?;
        }
    }
    Ok(())
}

/// Options of a replay.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct ReplayOptions {
    /// `--stationary`: use the model's stationary measurement model, if it has one.
    pub stationary: bool,
    /// Keep time series (`--out` given).
    pub keep_series: bool,
    /// `--smooth`: also smooth the run and report the smoothed errors.
    pub smooth: bool,
    /// `--lenient`: a long IMU gap is propagated in bounded steps (with a
    /// warning) instead of in one step.
    pub lenient: bool,
}

/// What a replay model returns.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReplayOutput {
    /// Number of IMU samples processed.
    pub samples: usize,
    /// Seconds spent in the filter only (no file reading or writing, no scoring).
    pub runtime_s: f64,
    /// Model-specific JSON keys (e.g. `horizontal_error_final_m` when there is truth).
    pub metrics: Map<String, Value>,
    /// Time series written under `--out` as `<table>.csv`.
    pub tables: Vec<RunTable>,
    /// Notes for the user (e.g. a log sensor the model does not use), printed
    /// on stderr as `warning: ...` lines; not part of the JSON.
    pub warnings: Vec<String>,
}

/// A model that runs over a recorded log directory (`navsim replay --model <NAME>`).
pub trait ReplayModel: Send + Sync {
    /// The name used on the command line.
    fn name(&self) -> &'static str;
    /// One line for `navsim list`.
    fn description(&self) -> &'static str {
        ""
    }
    /// Whether the model has a stationary measurement model (`--stationary`
    /// is refused otherwise).
    fn has_stationary_mode(&self) -> bool {
        false
    }
    /// The log files the model reads (`imu.csv`, `dvl.csv`, ...), when it
    /// declares them: other files present are listed as unused in the
    /// warnings. `None`: not declared, nothing is listed.
    fn log_files(&self) -> Option<&'static [&'static str]> {
        None
    }
    /// Runs the model over the log. Time only the filter into `runtime_s`.
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError>;
    /// Runs the model over the log directory of `files`; with `out`, writes
    /// its time series and plots there. Default: the whole log read into
    /// memory, [`ReplayModel::replay`], then [`ReplayModel::write_outputs`];
    /// a model that streams the log (memory independent of its length)
    /// overrides it.
    fn replay_files(
        &self,
        files: &nav_runtime::log::LogFiles,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        let log = LogDir::read(files.dir(), files.strictness())?;
        let output = self.replay(&log, options)?;
        if let Some(dir) = out {
            self.write_outputs(&output, dir)?;
        }
        Ok(output)
    }
    /// Whether `--smooth` is supported.
    fn can_smooth(&self) -> bool {
        false
    }
    /// Writes time series and plots into `dir` (which exists). Default: each table
    /// as `<table>.csv`.
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        for table in &output.tables {
            table.write_csv(&dir.join(format!("{}.csv", table.name)))?;
        }
        Ok(())
    }
}

/// `--shard K/N`: the K-th (1-based) of N deterministic slices of the seeds.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Shard {
    /// 1-based shard index.
    pub k: usize,
    /// Number of shards.
    pub n: usize,
}

impl Shard {
    /// Whether seed index `i` (0-based, seed = base + i) belongs to this shard.
    pub fn contains(&self, i: usize) -> bool {
        i % self.n == self.k - 1
    }

    /// File name of this shard's results.
    pub fn file_name(&self) -> String {
        format!("shard-{}-of-{}.json", self.k, self.n)
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.k, self.n)
    }
}

impl FromStr for Shard {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        let bad = || format!("`{s}` is not K/N with 1 <= K <= N (e.g. 2/4)");
        let (k, n) = s.split_once('/').ok_or_else(bad)?;
        let k: usize = k.trim().parse().map_err(|_| bad())?;
        let n: usize = n.trim().parse().map_err(|_| bad())?;
        if n == 0 || k == 0 || k > n {
            return Err(bad());
        }
        Ok(Shard { k, n })
    }
}

/// The seeds of a (possibly sharded) run, in increasing index order.
pub fn seeds(seed: u64, runs: usize, shard: Option<Shard>) -> Vec<u64> {
    (0..runs)
        .filter(|&i| match shard {
            None => true,
            Some(s) => s.contains(i),
        })
        .map(|i| seed.wrapping_add(i as u64))
        .collect()
}

/// A progress bar on stderr, hidden when stderr is not a terminal or `hidden` is set.
pub fn progress_bar(len: usize, hidden: bool) -> ProgressBar {
    if hidden || !std::io::stderr().is_terminal() {
        return indicatif::ProgressBar::hidden();
    }
    let bar = indicatif::ProgressBar::with_draw_target(
        Some(len as u64),
        indicatif::ProgressDrawTarget::stderr(),
    );
    if let Ok(style) = indicatif::ProgressStyle::default_bar()
        .template("{spinner} [{elapsed_precise}] {bar:40} {pos}/{len} runs (eta {eta})")
    {
        bar.set_style(style);
    }
    bar
}

/// Runs `seeds` in parallel and returns the results in the order of `seeds`. If some
/// runs fail, the error of the first failing seed (in that order) is returned.
pub fn run_seeds(
    scenario: &dyn Scenario,
    seeds: &[u64],
    options: &RunOptions,
    progress: &ProgressBar,
) -> Result<Vec<RunResult>, RunError> {
    let results: Vec<Result<RunResult, RunError>> = seeds
        .par_iter()
        .map(|&seed| {
            let r = scenario.run_one(seed, options).map(|mut r| {
                r.seed = seed;
                if !options.keep_series {
                    r.tables.clear();
                }
                r
            });
            progress.inc(1);
            r
        })
        .collect();
    progress.finish_and_clear();
    results.into_iter().collect()
}

/// Builds the JSON object of a scenario run: `scenario`, `runs`, `seed`, the
/// scenario's keys and, when used, `faults` and `draw_biases`.
pub fn summary_json(
    scenario: &dyn Scenario,
    seed: u64,
    runs: &[RunResult],
    options: &RunOptions,
) -> Result<Value, RunError> {
    let mut map = scenario.summarize(runs, options)?;
    map.insert("scenario".into(), Value::from(scenario.name()));
    map.insert("runs".into(), Value::from(runs.len()));
    map.insert("seed".into(), Value::from(seed));
    if !options.faults.is_empty() {
        map.insert("faults".into(), Value::from(options.faults.clone()));
    }
    if options.draw_biases {
        map.insert("draw_biases".into(), Value::from(true));
    }
    Ok(Value::Object(map))
}

/// The content of a shard file (`shard-K-of-N.json`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ShardFile {
    /// Format version (1).
    pub format: u32,
    /// Scenario name.
    pub scenario: String,
    /// First seed of the whole (unsharded) run.
    pub seed: u64,
    /// Number of runs of the whole (unsharded) run.
    pub runs: usize,
    /// `K/N`.
    pub shard: String,
    /// Options of the run.
    pub options: RunOptions,
    /// This shard's runs, in seed order.
    pub results: Vec<RunResult>,
}

/// Current [`ShardFile::format`].
pub const SHARD_FORMAT: u32 = 1;

impl ShardFile {
    /// Reads a shard file.
    pub fn read(path: &Path) -> Result<ShardFile, RunError> {
        let text = std::fs::read_to_string(path).map_err(|e| RunError::io(path, e))?;
        let file: ShardFile = serde_json::from_str(&text).map_err(|e| RunError::Shard {
            path: path.to_path_buf(),
            message: format!("not a shard file: {e}"),
        })?;
        if file.format != SHARD_FORMAT {
            return Err(RunError::Shard {
                path: path.to_path_buf(),
                message: format!("unsupported shard format {}", file.format),
            });
        }
        Ok(file)
    }

    /// Writes the shard file as JSON.
    pub fn write(&self, path: &Path) -> Result<(), RunError> {
        let text = serde_json::to_string(self).map_err(|e| RunError::Shard {
            path: path.to_path_buf(),
            message: e.to_string(),
        })?;
        std::fs::write(path, text + "\n").map_err(|e| RunError::io(path, e))
    }
}

/// Finds shard files: each path is a shard file or a directory whose
/// `shard-*-of-*.json` files are taken (sorted by name).
pub fn find_shard_files(paths: &[PathBuf]) -> Result<Vec<PathBuf>, RunError> {
    let mut out = Vec::new();
    for p in paths {
        let meta = std::fs::metadata(p).map_err(|e| RunError::io(p, e))?;
        if meta.is_dir() {
            let mut found: Vec<PathBuf> = std::fs::read_dir(p)
                .map_err(|e| RunError::io(p, e))?
                .filter_map(|e| e.ok().map(|e| e.path()))
                .filter(|f| {
                    f.file_name().and_then(|n| n.to_str()).is_some_and(|n| {
                        n.starts_with("shard-") && n.contains("-of-") && n.ends_with(".json")
                    })
                })
                .collect();
            if found.is_empty() {
                return Err(RunError::Shard {
                    path: p.clone(),
                    message: "no shard-K-of-N.json files in this directory".into(),
                });
            }
            found.sort();
            out.extend(found);
        } else {
            out.push(p.clone());
        }
    }
    Ok(out)
}

/// Merged shards: the whole run's parameters and every result in seed order.
#[derive(Debug, Clone, PartialEq)]
pub struct Merged {
    /// Scenario name.
    pub scenario: String,
    /// First seed.
    pub seed: u64,
    /// Options of the run.
    pub options: RunOptions,
    /// All results, in seed order.
    pub results: Vec<RunResult>,
}

/// Checks that shard files belong to one run and cover each of its seeds exactly
/// once; returns the results in seed order.
pub fn merge_shards(files: &[(PathBuf, ShardFile)]) -> Result<Merged, RunError> {
    let Some((first_path, first)) = files.first() else {
        return Err(RunError::Invalid("no shard files to merge".into()));
    };
    let mut by_index: BTreeMap<u64, (&Path, &RunResult)> = BTreeMap::new();
    for (path, f) in files {
        let mismatch = |what: &str, a: String, b: String| RunError::Shard {
            path: path.clone(),
            message: format!(
                "{what} is {b} but {} has {a}: shards of different runs",
                first_path.display()
            ),
        };
        if f.scenario != first.scenario {
            return Err(mismatch(
                "scenario",
                first.scenario.clone(),
                f.scenario.clone(),
            ));
        }
        if f.seed != first.seed {
            return Err(mismatch("seed", first.seed.to_string(), f.seed.to_string()));
        }
        if f.runs != first.runs {
            return Err(mismatch("runs", first.runs.to_string(), f.runs.to_string()));
        }
        if f.options != first.options {
            return Err(mismatch(
                "options",
                format!("{:?}", first.options),
                format!("{:?}", f.options),
            ));
        }
        for r in &f.results {
            let index = r.seed.wrapping_sub(f.seed);
            if index >= f.runs as u64 {
                return Err(RunError::Shard {
                    path: path.clone(),
                    message: format!("seed {} is outside of the run's seeds", r.seed),
                });
            }
            if let Some((other, _)) = by_index.insert(index, (path, r)) {
                return Err(RunError::Shard {
                    path: path.clone(),
                    message: format!("seed {} is also in {}", r.seed, other.display()),
                });
            }
        }
    }
    if by_index.len() != first.runs {
        let missing: Vec<String> = (0..first.runs as u64)
            .filter(|i| !by_index.contains_key(i))
            .take(5)
            .map(|i| first.seed.wrapping_add(i).to_string())
            .collect();
        return Err(RunError::Shard {
            path: first_path.clone(),
            message: format!(
                "shards cover {} of {} runs; missing seeds include {}",
                by_index.len(),
                first.runs,
                missing.join(", ")
            ),
        });
    }
    Ok(Merged {
        scenario: first.scenario.clone(),
        seed: first.seed,
        options: first.options.clone(),
        results: by_index.into_values().map(|(_, r)| r.clone()).collect(),
    })
}

pub mod demo {
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
    use super::*;
    use nav_runtime::log::{DepthRow, ImuRow, Meta, TruthRow};
    use nav_runtime::stats;
    use rand::SeedableRng;
    use rand_distr::{Distribution, StandardNormal};

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
            let p00 = p[0][0]
                + dt * (p[1][0] + p[0][1])
                + dt * dt * p[1][1]
                + ACCEL_PSD * dt.powi(3) / 3.0;
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
                m.insert(key.into(), crate::report::summary_of(runs, key));
            }
            m.insert(
                "nees_mean".into(),
                Value::from(stats::mean(&metric_values(runs, "nees_mean"))),
            );
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
            crate::plot::error_with_sigma(
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
            crate::plot::nees(
                &dir.join("nees.svg"),
                &format!("{NAME}: average NEES over {} runs", tables.len()),
                &t[..len.min(t.len())],
                &avg,
                Some(band),
            )
        }
        fn simulate_log(
            &self,
            seed: u64,
            options: &RunOptions,
        ) -> Option<Result<LogDir, RunError>> {
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
        fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
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
    }
}
