//! The result of a run (a replay, or one seed of a scenario): its metrics,
//! health and time series, and the progress bar of long work.

use std::collections::BTreeMap;
use std::io::IsTerminal;
use std::path::Path;

pub use indicatif::ProgressBar;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use crate::RunError;
use nav_ins::RunHealth;

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
/// `metrics`, `health` and `extra` travel through shard files (JSON) and must hold
/// everything a scenario's summary needs; `tables` stay in memory (only with
/// `--out`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunResult {
    /// The run's seed.
    pub seed: u64,
    /// Scalar metrics of the run (e.g. `horizontal_error_final_m`). Non-finite values
    /// survive shard files (stored as strings).
    #[serde(with = "float_map")]
    pub metrics: BTreeMap<String, f64>,
    /// Integer counts: per sensor, and the filter's (empty for a scenario
    /// that keeps none).
    pub health: RunHealth,
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
            health: RunHealth::default(),
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

/// Writes every table of every run as `run-<seed>-<table>.csv` into `dir`.
pub fn write_run_tables(runs: &[RunResult], dir: &Path) -> Result<(), RunError> {
    for run in runs {
        for table in &run.tables {
            table.write_csv(&dir.join(format!("run-{}-{}.csv", run.seed, table.name)))?;
        }
    }
    Ok(())
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
