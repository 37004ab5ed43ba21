//! The INS replay: any vehicle of `nav_ins` (the INS error-state core plus
//! its sensor blocks) run over a log directory, scored against `truth.csv`
//! when present, with time series and plots under `--out`.
//!
//! - [`setup`]: the log's `meta.toml` and files become a navigator;
//! - [`replay_loop`]: the rows pushed in delivery order (late USBL fixes by
//!   their acoustic travel time), the smoother's record;
//! - `aiding`: the aiding rows in delivery order;
//! - [`score`]: errors and NEES against the truth;
//! - [`constant_states`]: the biases and calibrations at the end against their priors;
//! - [`output`]: the JSON metrics, tables and warnings of a replay;
//! - [`plots`]: the SVG plots of a scored run.

mod aiding;
pub mod calibration;
pub mod constant_states;
pub mod output;
mod own_sensors;
pub mod plots;
pub mod reference_point_fit;
pub mod replay_loop;
pub mod score;
pub mod setup;

use std::marker::PhantomData;
use std::path::Path;

use nav_ins::vehicle::{self, InsVehicle};
use nav_runtime::log::{LogDir, LogFiles, LogSource};

use crate::{ReplayModel, ReplayOptions, ReplayOutput, RunError};
pub use aiding::{DVL_MAX_ALTITUDE, SOUND_SPEED};
pub use plots::{write_plots, write_smoothed_plot, write_trajectory_plots};
use score::Scored;
use setup::{FilterOptions, InsRun};

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
    let run = setup::run_vehicle::<V, N>(log, options, &times)?;
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
pub const ERROR_KEYS: [&str; 5] = [
    "horizontal_error_final_m",
    "horizontal_error_rms_m",
    "depth_error_rms_m",
    "nees_mean",
    "nees_position_mean",
];

/// The values of [`ERROR_KEYS`] of a scored run.
pub fn error_values(s: &Scored) -> [f64; 5] {
    [
        s.horizontal_error_final_m,
        s.horizontal_error_rms_m,
        s.depth_error_rms_m,
        s.nees_mean,
        s.nees_position_mean,
    ]
}

/// The metrics of a run (scored when truth exists).
pub fn metrics<V: InsVehicle<N>, const N: usize>(
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
            ("nees_position_mean".into(), s.nees_position_mean),
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

/// `navsim replay DIR --model <V::REPLAY_NAME>`: the filter of vehicle `V`
/// (`N` states) over a log, scored against `truth.csv` when present. One line
/// in `navsim`'s registry registers a vehicle:
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
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        output::replay_source::<V, N>(source, options, out)
    }
    fn shares_imu(&self) -> bool {
        true
    }
    fn own_mapping(&self, files: &LogFiles) -> Result<crate::OwnMapping, RunError> {
        Ok(own_sensors::OwnSensors::<V, N>::read(&LogSource::Files(files))?.own_mapping())
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn can_observe(&self) -> bool {
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
