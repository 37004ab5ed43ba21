//! The replay program of one vehicle, for a user's own binary:
//!
//! ```no_run
//! fn main() -> std::process::ExitCode {
//!     models::replay::replay_main::<models::vehicles::sdins::Sdins20, 20>()
//! }
//! ```
//!
//! gives `my-vehicle replay DIR [--out OUT] [--json] [--lenient]` (the
//! `navsim replay` of that vehicle: same JSON, same time series and plots)
//! and `my-vehicle check DIR [--json] [--lenient]` (reads the log, checks
//! that the vehicle fits the replay, says which log files feed which of its
//! sensors). Registering the vehicle in `navsim` itself is one line of
//! `crate::cli::replay_models`. See `docs/pipeline.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nav_runtime::log::{LogFiles, Strictness};
use serde_json::{json, Map, Value};

use crate::cli::{one_line, parse_failure, replay_with, ReplayArgs};
use crate::harness::RunError;
use crate::navigator::vehicle::{Layout, Present};
use crate::navigator::InsVehicle;
use crate::preflight::{LogSummary, PreflightOptions};
use crate::sdins25::InsReplay;

/// The command line of a vehicle's replay program.
#[derive(Debug, Parser)]
#[command(version)]
struct Program {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the vehicle's filter over a log directory.
    Replay(ReplayCommand),
    /// Read a log directory and say what the vehicle would use of it.
    Check(CheckCommand),
}

#[derive(Debug, Args)]
struct ReplayCommand {
    /// Log directory.
    dir: PathBuf,
    /// Directory for time series and plots.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Skip (and count) bad CSV rows instead of stopping.
    #[arg(long)]
    lenient: bool,
    /// An IMU interval longer than this many IMU periods is a gap (an error,
    /// a warning with --lenient).
    #[arg(long, default_value_t = 10.0, value_name = "N")]
    max_gap_periods: f64,
    /// Also smooth the run (fixed-interval smoother) and report both.
    #[arg(long)]
    smooth: bool,
}

#[derive(Debug, Args)]
struct CheckCommand {
    /// Log directory.
    dir: PathBuf,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Skip (and count) bad CSV rows instead of stopping.
    #[arg(long)]
    lenient: bool,
}

/// The replay program of vehicle `V` (`N` error states) on the process's
/// arguments (see the module docs).
pub fn replay_main<V: InsVehicle<N>, const N: usize>() -> ExitCode {
    replay_main_with::<V, N, _, _>(std::env::args_os())
}

/// [`replay_main`] with explicit arguments (the first is the program name).
pub fn replay_main_with<V, const N: usize, I, T>(args: I) -> ExitCode
where
    V: InsVehicle<N>,
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let program = match Program::try_parse_from(args) {
        Ok(p) => p,
        Err(e) => return parse_failure(e),
    };
    let result = match program.command {
        Command::Replay(c) => replay_with(
            &InsReplay::<V, N>::new(),
            &ReplayArgs {
                dir: c.dir,
                model: V::REPLAY_NAME.to_string(),
                out: c.out,
                json: c.json,
                lenient: c.lenient,
                stationary: false,
                max_gap_periods: c.max_gap_periods,
                smooth: c.smooth,
            },
        ),
        Command::Check(c) => check::<V, N>(&c),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}

/// What `check` finds: the log as the reader validates it, and for each
/// aiding file whether the vehicle has its sensor.
fn check<V: InsVehicle<N>, const N: usize>(c: &CheckCommand) -> Result<(), RunError> {
    let strictness = if c.lenient {
        Strictness::Lenient
    } else {
        Strictness::Strict
    };
    Layout::of::<V, N>()?;
    let files = LogFiles::open(&c.dir, strictness)?;
    let (_, summary) = crate::preflight::check_files(
        &files,
        &PreflightOptions {
            lenient: c.lenient,
            ..PreflightOptions::default()
        },
    )?;
    let value = check_report::<V, N>(&summary);
    if c.json {
        println!("{}", crate::harness::report::json_line(&value));
    } else {
        print!("{}", crate::harness::report::human(&value));
    }
    Ok(())
}

/// The `check` object of a log (its streamed summary) for vehicle `V`.
pub fn check_report<V: InsVehicle<N>, const N: usize>(log: &LogSummary) -> Value {
    let has = Present::of::<V, N>();
    let rows = |file: &str| log.file(file).map(|f| f.rows);
    let files = [
        ("depth", rows("depth.csv"), has.depth),
        ("dvl", rows("dvl.csv"), has.dvl),
        (
            "heading",
            rows("heading.csv"),
            has.compass || has.compass_small_angle,
        ),
        ("usbl", rows("usbl.csv"), has.usbl),
        ("gnss", rows("gnss.csv"), has.gnss),
        ("baro", rows("baro.csv"), has.baro),
        ("mag", rows("mag.csv"), has.mag),
    ];
    let mut sensors = Map::new();
    let mut warnings: Vec<String> = Vec::new();
    for (name, rows, present) in files {
        let Some(rows) = rows else { continue };
        if !present {
            warnings.push(format!(
                "model {} has no {name} sensor: the {rows} rows of {name}.csv would not be used",
                V::REPLAY_NAME
            ));
        }
        sensors.insert(name.into(), json!({ "rows": rows, "used": present }));
    }
    for (file, n) in &log.skipped_rows {
        warnings.push(format!("{file}: {n} bad rows skipped"));
    }
    for file in &log.unknown_files {
        warnings.push(format!("ignored unknown file {file}"));
    }
    let span = log.imu_time_span();
    json!({
        "model": V::REPLAY_NAME,
        "imu_rows": log.imu_rows(),
        "imu_span_s": span.map(|(a, b)| json!([a, b])),
        "sensors": Value::Object(sensors),
        "truth_rows": rows("truth.csv"),
        "warnings": warnings,
    })
}
