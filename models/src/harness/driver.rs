//! The Monte Carlo driver: the options of a scenario's runs, the seeds run in
//! parallel, and the JSON of a scenario run.

use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use serde_json::Value;

use super::{ProgressBar, RunError, RunResult, Scenario};

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
