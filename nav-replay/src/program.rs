//! The replay program of one vehicle, for a user's own binary:
//!
//! ```no_run
//! use nav_blocks::{Compass, Depth, Dvl, InsCore};
//! use nav_ins::{Absent, InsVehicle};
//!
//! nav_runtime::model! {
//!     /// The core with a depth meter, a DVL and a compass: 20 states.
//!     pub model Auv = InsCore + Depth + Dvl + Compass {
//!         allow_unused { position_error[1] }
//!     }
//! }
//!
//! impl InsVehicle<20> for Auv {
//!     const REPLAY_NAME: &'static str = "auv";
//!     const DESCRIPTION: &'static str = "INS + depth + DVL + compass";
//!     type Depth = AuvDepth;
//!     type Dvl = AuvDvl;
//!     type Compass = AuvCompass;
//!     type CompassSmallAngle = AuvCompassSmallAngle;
//!     type Usbl = Absent;
//!     type Gnss = Absent;
//!     type Baro = Absent;
//!     type Mag = Absent;
//! }
//!
//! fn main() -> std::process::ExitCode {
//!     nav_replay::program::replay_main::<Auv, 20>()
//! }
//! ```
//!
//! gives `my-vehicle replay DIR [--out OUT] [--json] [--lenient]` (the
//! `navsim replay` of that vehicle: same JSON, same time series and plots)
//! and `my-vehicle check DIR [--json] [--lenient]` (reads the log, checks
//! that the vehicle fits the replay, says which log files feed which of its
//! sensors). Registering the vehicle in `navsim` itself is one line of
//! `navsim`'s registry. See `docs/pipeline.md`.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nav_runtime::log::{LogFiles, NonPhysical, Strictness};
use serde_json::{json, Map, Value};

use nav_ins::vehicle::{Layout, Present};
use nav_ins::InsVehicle;
use nav_runtime::log::{Warning, WarningKind};

use crate::ins::InsReplay;
use crate::output::interrupt::Pending;
use crate::output::report::{self, StagedDir};
use crate::preflight::{self, LogSummary, PreflightOptions};
use crate::{ReplayModel, ReplayOptions, RunError};

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
    /// Identify the noise sigmas of meta.toml from the log alone
    /// (docs/tuning.md).
    Tune(TuneCommand),
}

#[derive(Debug, Args)]
struct TuneCommand {
    /// Log directory.
    dir: PathBuf,
    #[command(flatten)]
    flags: crate::tune::TuneFlags,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Skip (and count) bad CSV rows instead of stopping.
    #[arg(long)]
    lenient: bool,
    /// Write the log's replay.toml with the tuned sigmas of the vehicle's
    /// own sensors to this file.
    #[arg(long, value_name = "FILE")]
    write_mapping: Option<PathBuf>,
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
    /// Also report how much the log taught each state, and the weakest
    /// combinations of states.
    #[arg(long)]
    observability: bool,
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
                observability: c.observability,
            },
        ),
        Command::Check(c) => check::<V, N>(&c),
        Command::Tune(c) => crate::tune::tune_with(
            &InsReplay::<V, N>::new(),
            &crate::tune::TuneArgs {
                dir: c.dir,
                model: V::REPLAY_NAME.to_string(),
                flags: c.flags,
                json: c.json,
                lenient: c.lenient,
                max_gap_periods: 10.0,
                write_mapping: c.write_mapping,
            },
        ),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}

/// What `check` finds: the log as the reader and the preflight validate it
/// and as the replay reads it (a log the replay refuses is refused with
/// the same error), and for each aiding file whether the vehicle has its
/// sensor.
fn check<V: InsVehicle<N>, const N: usize>(c: &CheckCommand) -> Result<(), RunError> {
    let strictness = if c.lenient {
        Strictness::Lenient
    } else {
        Strictness::Strict
    };
    Layout::of::<V, N>()?;
    let files = open_log(&c.dir, strictness)?;
    let (report, mut summary) = crate::preflight::check_files(
        &files,
        &PreflightOptions {
            lenient: c.lenient,
            ..PreflightOptions::default()
        },
    )?;
    if let Some(refusal) = preflight::refusal(&report) {
        return Err(refusal);
    }
    summary.warnings.extend(files.rejected_warnings());
    // What the replay refuses, `check` refuses with the same error: the
    // replay itself reads the log (its outputs are discarded).
    InsReplay::<V, N>::new().replay_files(
        &open_log(&c.dir, strictness)?,
        &ReplayOptions {
            lenient: c.lenient,
            ..ReplayOptions::default()
        },
        None,
    )?;
    let value = check_report::<V, N>(&summary);
    if c.json {
        println!("{}", crate::output::report::json_line(&value));
    } else {
        print!("{}", crate::output::report::human(&value));
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

/// `navsim replay`.
#[derive(Debug, Args)]
pub struct ReplayArgs {
    /// Log directory.
    pub dir: PathBuf,
    /// Model name.
    #[arg(long)]
    pub model: String,
    /// Directory for time series and plots.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Skip (and count) bad CSV rows instead of stopping.
    #[arg(long)]
    pub lenient: bool,
    /// Use the model's stationary measurement model.
    #[arg(long)]
    pub stationary: bool,
    /// An IMU interval longer than this many IMU periods is a gap (an error,
    /// a warning with --lenient).
    #[arg(long, default_value_t = 10.0, value_name = "N")]
    pub max_gap_periods: f64,
    /// Also smooth the run (fixed-interval smoother) and report both.
    #[arg(long)]
    pub smooth: bool,
    /// Also report how much the log taught each state, and the weakest
    /// combinations of states (INS vehicles).
    #[arg(long)]
    pub observability: bool,
}

/// Prints a result: one JSON line on stdout with `json`, otherwise human text.
pub fn emit(value: &Value, json: bool) {
    if json {
        println!("{}", report::json_line(value));
    } else {
        print!("{}", report::human(value));
    }
}

/// Human note: stderr with `--json`, stdout otherwise.
pub fn note(json: bool, text: &str) {
    if json {
        eprintln!("{text}");
    } else {
        println!("{text}");
    }
}

/// `navsim replay` with `model` (`args.model` is not looked up).
pub fn replay_with(model: &dyn ReplayModel, args: &ReplayArgs) -> Result<(), RunError> {
    if args.smooth && !model.can_smooth() {
        return Err(RunError::Invalid(format!(
            "model {} cannot be smoothed",
            model.name()
        )));
    }
    if args.observability && !model.can_observe() {
        return Err(RunError::Invalid(format!(
            "--observability: model {} has no observability report yet (INS vehicles have)",
            model.name()
        )));
    }
    if args.stationary && !model.has_stationary_mode() {
        return Err(RunError::Invalid(format!(
            "--stationary: model {} has no stationary mode",
            model.name()
        )));
    }
    let (preflight_options, strictness) =
        preflight_options(args.lenient, args.max_gap_periods, model.log_files())?;
    let files = open_log(&args.dir, strictness)?;
    let options = ReplayOptions {
        stationary: args.stationary,
        keep_series: args.out.is_some(),
        smooth: args.smooth,
        lenient: args.lenient,
        observability: args.observability,
    };
    // The JSON (`warnings` included) or text of a run's output.
    let result =
        |output: &crate::ReplayOutput, report: &preflight::Report, read: &preflight::LogSummary| {
            for reason in &read.skip_reasons {
                eprintln!("warning: skipped {reason}");
            }
            for file in &read.unknown_files {
                eprintln!("warning: ignored unknown file {file}");
            }
            // A frozen IMU the preflight listed is not listed again by the
            // replay that met it.
            let preflight_frozen = report.warnings().any(|w| w.kind == WarningKind::FrozenImu);
            let mut notes: Vec<Warning> = output
                .warnings
                .iter()
                .filter(|w| !(preflight_frozen && w.kind == WarningKind::FrozenImu))
                .cloned()
                .collect();
            preflight::weigh_nees(&mut notes, report);
            // A model's notes carry their file in the message already.
            for w in &notes {
                eprintln!("warning: {}", w.message);
            }
            let rejected = files.rejected_warnings();
            for w in &rejected {
                eprintln!("warning: {w}");
            }
            let mut warnings: Vec<Warning> = read.warnings.clone();
            warnings.extend(rejected);
            warnings.extend(preflight_beside(report, &notes));
            warnings.extend(notes);
            let mut value = report::replay_json(
                model.name(),
                output,
                args.lenient,
                &read.skipped_rows,
                &read.unknown_files,
            );
            if let Value::Object(m) = &mut value {
                m.insert("warnings".into(), warnings_json(&warnings));
            }
            value
        };
    // The preflight reads the log beside the replay; a log it refuses is
    // refused with its error and the replay's output is discarded.
    let replay = |out: Option<&std::path::Path>| {
        preflight::check_alongside(&files, &preflight_options, model.shares_imu(), || {
            model.replay_files(&files, &options, out)
        })
    };
    if let Some(out) = &args.out {
        let mut value = Value::Null;
        let dir = write_log_out(out, &args.dir, |dir| {
            let (output, report, summary) = replay(Some(dir))?;
            value = result(&output, &report, &summary);
            let path = dir.join("summary.json");
            std::fs::write(&path, report::json_line(&value) + "\n")
                .map_err(|e| RunError::io(&path, e))
        })?;
        emit(&value, args.json);
        note(args.json, &format!("outputs written to {}", dir.display()));
    } else {
        let (output, report, summary) = replay(None)?;
        emit(&result(&output, &report, &summary), args.json);
    }
    Ok(())
}

/// Opens a log directory as every command reads it: a non-physical
/// reading in an aiding file (a glitch: 1e300, an infinity, a latitude past
/// the pole) is a rejected row with a warning, not a broken file, unless
/// so many are rejected that the file is (see `NonPhysical::Rejected`).
///
/// # Errors
/// As [`LogFiles::open`].
pub fn open_log(dir: &std::path::Path, strictness: Strictness) -> Result<LogFiles, RunError> {
    Ok(LogFiles::open(dir, strictness)?.with_non_physical(NonPhysical::Rejected))
}

/// The JSON `warnings` array: `{"kind","file","line","key","message"}`
/// objects (`null` for an unknown location part).
pub fn warnings_json(warnings: &[Warning]) -> Value {
    Value::Array(
        warnings
            .iter()
            .map(|w| {
                serde_json::json!({
                    "kind": w.kind.as_str(),
                    "file": w.file,
                    "line": w.line,
                    "key": w.key,
                    "message": w.message,
                })
            })
            .collect(),
    )
}

/// Writes an output directory atomically: `fill` writes into a staging
/// directory that is moved to `out` at the end, removed on error or on
/// SIGINT/SIGTERM. Errors name `out`, the path the user gave.
pub fn write_out(
    out: &std::path::Path,
    fill: impl FnOnce(&std::path::Path) -> Result<(), RunError>,
) -> Result<PathBuf, RunError> {
    let at_out = |e: RunError| match e {
        RunError::Io { source, .. } => {
            RunError::Invalid(format!("--out {}: {source}", out.display()))
        }
        // The staging's own refusals name `out` first.
        RunError::Invalid(text) => RunError::Invalid(format!("--out {text}")),
        other => other,
    };
    // Created and registered under the interrupt registry's lock, so an
    // interruption never leaves the staging directory behind.
    let (staged, pending) = Pending::create(
        || StagedDir::new(out).map_err(at_out),
        |s| s.path().to_path_buf(),
    )?;
    let staging = staged.path().display().to_string();
    fill(staged.path()).map_err(|e| match e {
        RunError::Io { source, path } => RunError::Invalid(format!(
            "--out {}: writing {}: {source}",
            out.display(),
            path.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        )),
        // Any other error naming a file being written names it under the
        // staging directory, which the user never sees: under `out`.
        other => {
            let text = other.to_string();
            if text.contains(&staging) {
                RunError::Invalid(text.replace(&staging, &out.display().to_string()))
            } else {
                other
            }
        }
    })?;
    pending.finish(|| staged.commit()).map_err(at_out)
}

/// [`write_out`] for the output of a run over the log directory `log`:
/// refused when `out` is that directory or lies inside it, where the
/// written files (`estimates.csv`, ...) would be unknown log files that
/// make every later read of the log an error.
pub fn write_log_out(
    out: &std::path::Path,
    log: &std::path::Path,
    fill: impl FnOnce(&std::path::Path) -> Result<(), RunError>,
) -> Result<PathBuf, RunError> {
    let (at, within) = (resolved(out), resolved(log));
    if at.starts_with(&within) {
        let place = if at == within { "is" } else { "lies inside" };
        return Err(RunError::Invalid(format!(
            "--out {}: {place} the log directory {}: the files written there would \
             make the log unreadable (unknown log files); choose a directory outside it",
            out.display(),
            log.display()
        )));
    }
    write_out(out, fill)
}

/// `path` made absolute, its longest existing ancestor resolved (symbolic
/// links, `..`), so that two spellings of one directory compare equal
/// whether or not it exists yet.
fn resolved(path: &std::path::Path) -> PathBuf {
    let absolute = std::path::absolute(path).unwrap_or_else(|_| path.to_path_buf());
    let mut existing = absolute.as_path();
    let mut rest = Vec::new();
    loop {
        if let Ok(found) = existing.canonicalize() {
            return rest.iter().rev().fold(found, |p, c| p.join(c));
        }
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                existing = parent;
            }
            _ => return absolute,
        }
    }
}

/// The preflight options of a run (after checking `--max-gap-periods`) and
/// the reader's strictness.
pub fn preflight_options(
    lenient: bool,
    max_gap_periods: f64,
    model_files: Option<&'static [&'static str]>,
) -> Result<(PreflightOptions, Strictness), RunError> {
    if !(max_gap_periods.is_finite() && max_gap_periods >= 1.0) {
        return Err(RunError::Invalid(format!(
            "--max-gap-periods {max_gap_periods}: expected a number >= 1"
        )));
    }
    let strictness = if lenient {
        Strictness::Lenient
    } else {
        Strictness::Strict
    };
    let options = PreflightOptions {
        lenient,
        max_gap_periods,
        model_files,
        ..PreflightOptions::default()
    };
    Ok((options, strictness))
}

/// The preflight's warnings beside a replay's `notes`: a file the model
/// says it does not use (with its row count) is not listed again from the
/// preflight's file list.
pub fn preflight_beside(report: &preflight::Report, notes: &[Warning]) -> Vec<Warning> {
    let unused_by_model = |w: &Warning| {
        w.kind == WarningKind::UnusedFile
            && notes
                .iter()
                .any(|n| n.kind == WarningKind::UnusedFile && n.file == w.file)
    };
    report
        .warnings()
        .filter(|w| !unused_by_model(w))
        .cloned()
        .collect()
}

/// Collapses a message to one line.
pub fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// Help and version on stdout (success); a usage error as one `error:` line
/// on stderr (exit code 2).
pub fn parse_failure(e: clap::Error) -> ExitCode {
    use clap::error::ErrorKind;
    if matches!(e.kind(), ErrorKind::DisplayHelp | ErrorKind::DisplayVersion) {
        let _ = e.print();
        return ExitCode::SUCCESS;
    }
    if e.kind() == ErrorKind::DisplayHelpOnMissingArgumentOrSubcommand {
        let _ = e.print();
        return ExitCode::from(2);
    }
    let rendered = e.render().to_string();
    let body = rendered
        .split("\n\nUsage:")
        .next()
        .unwrap_or("")
        .split("\n\nFor more information")
        .next()
        .unwrap_or("");
    let body = one_line(body);
    let body = body.strip_prefix("error:").unwrap_or(&body).trim();
    eprintln!("error: {body}");
    ExitCode::from(2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::Path;

    /// An error while `--out` is written (a full disk, say) names the path
    /// the user gave, whatever form it takes, never the staging directory.
    #[test]
    fn out_errors_name_the_out_path_not_the_staging_directory() {
        let tmp = crate::temp_dir::TempDir::new("write-out");
        let out = tmp.0.join("results");
        const FULL: &str = "No space left on device";
        let cases: [fn(&Path) -> RunError; 3] = [
            |d| RunError::io(d.join("estimates.csv"), std::io::Error::other(FULL)),
            |d| RunError::Invalid(format!("{}: {FULL}", d.join("estimates.csv").display())),
            |d| RunError::Plot {
                path: d.join("track.png"),
                message: FULL.into(),
            },
        ];
        for (k, make) in cases.into_iter().enumerate() {
            let e = write_out(&out, |d| Err(make(d))).unwrap_err().to_string();
            assert!(
                e.contains(&out.display().to_string()) && e.contains(FULL),
                "case {k}: {e}"
            );
            assert!(!e.contains(".partial"), "case {k}: {e}");
            assert!(!out.exists(), "case {k}");
        }
    }
}
