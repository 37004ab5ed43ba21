//! The trait of a model that replays a recorded log, its options and output.

use std::path::Path;

use nav_runtime::log::{LogDir, LogFiles, LogSource, Warning, WarningKind};
use serde_json::{Map, Value};

use super::{RunError, RunTable};

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
    /// `--observability`: report how much the log taught each state and the
    /// weakest directions (`docs/observability.md`).
    pub observability: bool,
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
    /// Notes for the user (a log sensor the model does not use, a sensor
    /// none of whose rows was applied, ...), typed: printed on stderr as
    /// `warning: <message>` lines and listed in the JSON's `warnings` with
    /// their kind and file.
    pub warnings: Vec<Warning>,
    /// Each aiding sensor's innovations (empty for a model that does not
    /// report them): the JSON's `innovations`, and what noise tuning
    /// weighs.
    pub innovations: Vec<crate::innovations::SensorInnovations>,
}

/// The values a log's `replay.toml` gives a model's own sensors and noise
/// ([`ReplayModel::own_mapping`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct OwnMapping {
    /// Per sensor fed by its declared name: its sigmas, per output.
    pub sigmas: Vec<(String, Vec<f64>)>,
    /// The declared process noise beyond the core's, per scalar: its name
    /// (`current_noise[0]`) and value.
    pub noise: Vec<(String, f64)>,
    /// Per sensor fed by its declared name: the offset added to its file's
    /// times, s (`time = { .., offset_s = .. }`).
    pub clocks: Vec<(String, f64)>,
}

/// A note of a replay model about no file in particular (kind
/// [`WarningKind::Model`]).
pub fn model_note(message: impl Into<String>) -> Warning {
    Warning {
        kind: WarningKind::Model,
        file: None,
        line: None,
        key: None,
        message: message.into(),
    }
}

/// The warning that the filter repaired its covariance `repairs` times
/// (a variance not positive and finite reset: docs/runtime.md), `None`
/// for none: after a repair the sigmas, the NEES and the NIS describe a
/// covariance the filter did not compute, and its estimate may be no
/// better (absurd noise settings are the usual cause).
pub fn covariance_repairs(repairs: u64) -> Option<Warning> {
    (repairs > 0).then(|| {
        model_note(format!(
            "the filter repaired its covariance {repairs} time(s): its sigmas are not reliable \
             (a variance that was not positive and finite was reset; noise settings far from \
             the sensors'?)"
        ))
    })
}

/// The warning that the mean NEES against `file` is not a number: the
/// covariance at a scored time could not be inverted, and the scores are
/// not described by the filter's sigmas at all. It is the filter's fault,
/// not the file's, so the warning names no file.
pub fn nees_not_a_number(file: &str) -> Warning {
    model_note(format!(
        "the mean NEES against {file} is not a number: the filter's covariance at a \
         scored time was not positive definite and finite; its sigmas mean nothing here"
    ))
}

/// A note of a replay model about key `key` of `meta.toml` (kind
/// [`WarningKind::Model`]).
pub fn meta_note(key: &str, message: impl Into<String>) -> Warning {
    Warning::about(WarningKind::Model, "meta.toml", message).with_key(key)
}

/// The warning that `meta.toml` has no `[sensors.<sensor>]` section and a
/// default is used.
pub fn missing_section(sensor: &str, message: impl Into<String>) -> Warning {
    Warning::about(WarningKind::MissingSensorSection, "meta.toml", message)
        .with_key(&format!("sensors.{sensor}"))
}

/// A model that runs over a recorded log directory (`navsim replay --model <NAME>`).
pub trait ReplayModel: Send + Sync {
    /// The name used on the command line.
    fn name(&self) -> &'static str;
    /// One line for `navsim list`.
    fn description(&self) -> &'static str {
        ""
    }
    /// Whether [`ReplayOptions::observability`] is supported (refused
    /// otherwise).
    fn can_observe(&self) -> bool {
        false
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
    /// Runs the model over `source`, a log in memory or a log directory
    /// read file by file (with the meta and time offsets of its
    /// [`LogFiles`], which noise tuning sets); with `out`, writes its time
    /// series and plots there. A
    /// model that streams the log keeps its memory independent of the log's
    /// length and writes the series as they grow; one that holds it reads
    /// it whole ([`LogSource::whole`]) and writes them at the end
    /// ([`ReplayModel::write_outputs`]). Time only the filter into
    /// `runtime_s`.
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError>;
    /// Runs the model over a log in memory ([`ReplayModel::replay_source`]),
    /// its series kept in the output when `options.keep_series`.
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        self.replay_source(&LogSource::Memory(log), options, None)
    }
    /// Runs the model over the log directory of `files`
    /// ([`ReplayModel::replay_source`]); with `out`, writes its time series
    /// and plots there.
    fn replay_files(
        &self,
        files: &LogFiles,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        self.replay_source(&LogSource::Files(files), options, out)
    }
    /// Whether [`ReplayModel::replay_files`] reads `imu.csv` through
    /// [`LogSource::imu_rows`](nav_runtime::log::LogSource::imu_rows), so
    /// that the preflight beside it takes the rows it reads instead of
    /// parsing the file again. Default: no.
    fn shares_imu(&self) -> bool {
        false
    }
    /// Whether the model's filter uses noise parameter `key` of
    /// `meta.toml` (`sensors.speed.noise_sigma`): noise tuning varies only
    /// those, and `--params` naming another is an error. Default: every
    /// key.
    fn uses_noise_parameter(&self, key: &str) -> bool {
        let _ = key;
        true
    }
    /// What the log's `replay.toml` gives the model's own sensors and
    /// process noise (a vehicle's own block): what noise tuning can tune
    /// there. Default: nothing.
    ///
    /// # Errors
    /// The mapping's errors.
    fn own_mapping(&self, files: &nav_runtime::log::LogFiles) -> Result<OwnMapping, RunError> {
        let _ = files;
        Ok(OwnMapping::default())
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
