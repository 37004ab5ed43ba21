//! The `navsim` command line: argument parsing, the scenario and replay-model
//! registries, and the commands.
//!
//! Output rules: `--json` prints exactly one JSON object on stdout and nothing else
//! there; human text goes to stdout without `--json` and to stderr with it. Every
//! failure exits non-zero with one `error: ...` line on stderr.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nav_runtime::log::{LogFiles, Strictness, Warning, WarningKind};
use serde_json::Value;

use crate::demo;
use crate::harness::report::{self, StagedDir};
use crate::harness::{
    find_shard_files, merge_shards, progress_bar, run_seeds, seeds, summary_json, ReplayModel,
    ReplayOptions, RunError, RunOptions, Scenario, Shard, ShardFile, SHARD_FORMAT,
};
use crate::interrupt::Pending;
use crate::preflight::{self, PreflightOptions};
use crate::scenario_text::{scenario_text, Plots};
use crate::sdins25::InsReplay;
use crate::vehicles::sdins::{Sdins20, Sdins25Composed};

/// Scenario run by `navsim` without a command (when it is registered).
pub const DEFAULT_SCENARIO: &str = "lawnmower-dvl";
/// Scenario run without a command while [`DEFAULT_SCENARIO`] is not registered.
pub const FALLBACK_SCENARIO: &str = demo::NAME;
/// First seed when `--seed` is not given.
pub const DEFAULT_SEED: u64 = 1;

/// Every built-in scenario. Add new scenarios here.
pub fn scenarios() -> Vec<Box<dyn Scenario>> {
    let mut all: Vec<Box<dyn Scenario>> = vec![Box::new(demo::ConstantVelocity)];
    all.extend(
        crate::leveling::scenarios()
            .into_iter()
            .map(|s| Box::new(s) as Box<dyn Scenario>),
    );
    all.extend(
        crate::sdins25::scenarios()
            .into_iter()
            .map(|s| Box::new(s) as Box<dyn Scenario>),
    );
    all.push(Box::new(crate::marker::MarkerPath));
    all.push(Box::new(crate::vkf::VkfScenario));
    all
}

/// Every replay model. Add new models here.
pub fn replay_models() -> Vec<Box<dyn ReplayModel>> {
    vec![
        Box::new(demo::DepthKf),
        Box::new(crate::leveling::Leveling6Replay),
        Box::new(crate::sdins25::Sdins25Replay::new()),
        Box::new(InsReplay::<Sdins25Composed, 25>::new()),
        Box::new(InsReplay::<Sdins20, 20>::new()),
        Box::new(InsReplay::<crate::vehicles::pressure_auv::PressureAuv, 20>::new()),
        Box::new(crate::ahrs::AhrsReplay),
        Box::new(crate::gnss_ins::GnssInsReplay),
    ]
}

/// The scenario named `name`, or an error listing the valid names.
pub fn find_scenario(name: &str) -> Result<Box<dyn Scenario>, RunError> {
    let all = scenarios();
    let names: Vec<&str> = all.iter().map(|s| s.name()).collect();
    let valid = names.join(", ");
    all.into_iter().find(|s| s.name() == name).ok_or_else(|| {
        RunError::Invalid(format!(
            "unknown scenario `{name}`; valid scenarios: {valid}"
        ))
    })
}

/// The replay model named `name`, or an error listing the valid names.
pub fn find_replay_model(name: &str) -> Result<Box<dyn ReplayModel>, RunError> {
    let all = replay_models();
    let names: Vec<&str> = all.iter().map(|s| s.name()).collect();
    let valid = names.join(", ");
    all.into_iter()
        .find(|s| s.name() == name)
        .ok_or_else(|| RunError::Invalid(format!("unknown model `{name}`; valid models: {valid}")))
}

/// The scenario run without a command.
pub fn default_scenario() -> &'static str {
    if scenarios().iter().any(|s| s.name() == DEFAULT_SCENARIO) {
        DEFAULT_SCENARIO
    } else {
        FALLBACK_SCENARIO
    }
}

/// Simulation, Monte Carlo evaluation and log replay of the navigation estimators.
#[derive(Debug, Parser)]
#[command(name = "navsim", version)]
pub struct Cli {
    /// The command; without one, the default scenario runs.
    #[command(subcommand)]
    pub command: Option<Command>,
}

/// The commands.
#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a built-in scenario (Monte Carlo runs with seeds SEED, SEED+1, ...).
    Scenario(ScenarioArgs),
    /// Run a model over a recorded log directory.
    Replay(ReplayArgs),
    /// Write the synthetic sensor log of one run of a scenario.
    Simulate(SimulateArgs),
    /// Combine `--shard` outputs into the JSON of the unsharded run.
    Merge(MergeArgs),
    /// List the scenarios and replay models.
    List(ListArgs),
    /// Check a log directory for unit, sign, frame and clock mistakes without
    /// running a model.
    Check(CheckArgs),
    /// Convert another tool's log into a log directory (`import ulog FILE --out DIR`).
    Import(ImportArgs),
}

/// `navsim import`.
#[derive(Debug, Args)]
pub struct ImportArgs {
    /// Format of the file: `ulog` (a PX4 flight log).
    pub format: ImportFormat,
    /// The file to import.
    pub file: PathBuf,
    /// Log directory to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The formats `navsim import` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ImportFormat {
    /// PX4 ULog (`.ulg`).
    Ulog,
}

/// `navsim import`: writes the log directory; the topics used are in the warnings.
pub fn cmd_import(args: &ImportArgs) -> Result<(), RunError> {
    let ImportFormat::Ulog = args.format;
    let log =
        crate::ulog::import(&args.file, &args.out).map_err(|e| RunError::Invalid(e.to_string()))?;
    for w in &log.warnings {
        eprintln!("warning: {w}");
    }
    let mut value = log.summary();
    value["command"] = Value::from("import");
    value["format"] = Value::from("ulog");
    value["out"] = Value::from(args.out.display().to_string());
    emit(&value, args.json);
    Ok(())
}

/// `navsim check`.
#[derive(Debug, Args)]
pub struct CheckArgs {
    /// Log directory.
    pub dir: PathBuf,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Skip (and count) bad CSV rows; IMU gaps and a frozen IMU are warnings.
    #[arg(long)]
    pub lenient: bool,
    /// An IMU interval longer than this many IMU periods is a gap.
    #[arg(long, default_value_t = 10.0, value_name = "N")]
    pub max_gap_periods: f64,
}

/// `navsim scenario`.
#[derive(Debug, Args)]
pub struct ScenarioArgs {
    /// Scenario name.
    pub name: String,
    /// First seed.
    #[arg(long, default_value_t = DEFAULT_SEED)]
    pub seed: u64,
    /// Number of Monte Carlo runs (default: the scenario's).
    #[arg(long)]
    pub runs: Option<usize>,
    /// Directory for per-run CSV time series and plots (and shard results).
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
    /// Run only the seed indices i with i % N == K - 1 and write them to --out.
    #[arg(long, value_name = "K/N")]
    pub shard: Option<Shard>,
    /// Comma-separated fault names to inject.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub faults: Vec<String>,
    /// Draw sensor biases per run.
    #[arg(long)]
    pub draw_biases: bool,
    /// Also smooth every run (fixed-interval smoother) and report both.
    #[arg(long)]
    pub smooth: bool,
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
}

/// `navsim simulate`.
#[derive(Debug, Args)]
pub struct SimulateArgs {
    /// Scenario name.
    pub name: String,
    /// Seed of the run.
    #[arg(long)]
    pub seed: u64,
    /// Log directory to write.
    #[arg(long)]
    pub out: PathBuf,
    /// Comma-separated fault names to inject.
    #[arg(long, value_name = "LIST", value_delimiter = ',')]
    pub faults: Vec<String>,
    /// Draw sensor biases.
    #[arg(long)]
    pub draw_biases: bool,
}

/// `navsim merge`.
#[derive(Debug, Args)]
pub struct MergeArgs {
    /// Shard output directories (or shard files).
    #[arg(required = true)]
    pub dirs: Vec<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// `navsim list`.
#[derive(Debug, Args)]
pub struct ListArgs {
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// Prints a result: one JSON line on stdout with `json`, otherwise human text.
pub(crate) fn emit(value: &Value, json: bool) {
    if json {
        println!("{}", report::json_line(value));
    } else {
        print!("{}", report::human(value));
    }
}

/// Human note: stderr with `--json`, stdout otherwise.
pub(crate) fn note(json: bool, text: &str) {
    if json {
        eprintln!("{text}");
    } else {
        println!("{text}");
    }
}

fn run_options(
    scenario: &dyn Scenario,
    faults: &[String],
    draw_biases: bool,
    smooth: bool,
) -> Result<RunOptions, RunError> {
    if smooth && !scenario.can_smooth() {
        return Err(RunError::Invalid(format!(
            "scenario {} cannot be smoothed (--smooth is supported by the lawnmower-* scenarios)",
            scenario.name()
        )));
    }
    let mut list: Vec<String> = Vec::new();
    for f in faults.iter().map(|f| f.trim()).filter(|f| !f.is_empty()) {
        if !scenario.faults().contains(&f) {
            let valid = if scenario.faults().is_empty() {
                "none".to_string()
            } else {
                scenario.faults().join(", ")
            };
            return Err(RunError::Invalid(format!(
                "unknown fault `{f}` for scenario {}; valid faults: {valid}",
                scenario.name()
            )));
        }
        if !list.iter().any(|x| x == f) {
            list.push(f.to_string());
        }
    }
    Ok(RunOptions {
        faults: list,
        draw_biases,
        keep_series: false,
        smooth,
    })
}

/// `navsim scenario`.
pub fn cmd_scenario(args: &ScenarioArgs) -> Result<(), RunError> {
    let scenario = find_scenario(&args.name)?;
    let runs = args.runs.unwrap_or_else(|| scenario.default_runs());
    if runs == 0 {
        return Err(RunError::Invalid("--runs must be at least 1".into()));
    }
    let mut options = run_options(
        scenario.as_ref(),
        &args.faults,
        args.draw_biases,
        args.smooth,
    )?;
    if args.shard.is_some() && args.out.is_none() {
        return Err(RunError::Invalid(
            "--shard needs --out DIR for the shard's results".into(),
        ));
    }
    options.keep_series = args.out.is_some();
    let seed_list = seeds(args.seed, runs, args.shard);
    let bar = progress_bar(seed_list.len(), args.json);
    let results = run_seeds(scenario.as_ref(), &seed_list, &options, &bar)?;

    if let Some(shard) = args.shard {
        let out = args.out.as_ref().expect("checked above");
        let staged = StagedDir::new(out)?;
        let file = ShardFile {
            format: SHARD_FORMAT,
            scenario: scenario.name().to_string(),
            seed: args.seed,
            runs,
            shard: shard.to_string(),
            options: options.clone(),
            results,
        };
        file.write(&staged.path().join(shard.file_name()))?;
        scenario.write_outputs(&file.results, staged.path())?;
        let dir = staged.commit()?;
        let path = dir.join(shard.file_name());
        let mut m = serde_json::Map::new();
        m.insert("scenario".into(), Value::from(scenario.name()));
        m.insert("runs".into(), Value::from(runs));
        m.insert("seed".into(), Value::from(args.seed));
        m.insert("shard".into(), Value::from(shard.to_string()));
        m.insert("shard_runs".into(), Value::from(file.results.len()));
        m.insert("file".into(), Value::from(path.display().to_string()));
        emit(&Value::Object(m), args.json);
        return Ok(());
    }

    let summary = summary_json(scenario.as_ref(), args.seed, &results, &options)?;
    if let Some(out) = &args.out {
        let staged = StagedDir::new(out)?;
        scenario.write_outputs(&results, staged.path())?;
        let path = staged.path().join("summary.json");
        std::fs::write(&path, report::json_line(&summary) + "\n")
            .map_err(|e| RunError::io(&path, e))?;
        let dir = staged.commit()?;
        emit_scenario(&summary, args.json, Plots::WrittenTo(&dir));
    } else {
        emit_scenario(&summary, args.json, Plots::NotWritten);
    }
    Ok(())
}

/// Prints a scenario result: one JSON line on stdout with `json` (and where the
/// outputs went on stderr), otherwise the scenario text.
fn emit_scenario(value: &Value, json: bool, plots: Plots<'_>) {
    if json {
        println!("{}", report::json_line(value));
        if let Plots::WrittenTo(dir) = plots {
            eprintln!("outputs written to {}", dir.display());
        }
    } else {
        print!("{}", scenario_text(value, plots));
    }
}

/// `navsim replay`.
pub fn cmd_replay(args: &ReplayArgs) -> Result<(), RunError> {
    let model = find_replay_model(&args.model)?;
    replay_with(model.as_ref(), args)
}

/// `navsim replay` with `model` (`args.model` is not looked up).
pub fn replay_with(model: &dyn ReplayModel, args: &ReplayArgs) -> Result<(), RunError> {
    if args.smooth && !model.can_smooth() {
        return Err(RunError::Invalid(format!(
            "model {} cannot be smoothed",
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
    let files = LogFiles::open(&args.dir, strictness)?;
    let options = ReplayOptions {
        stationary: args.stationary,
        keep_series: args.out.is_some(),
        smooth: args.smooth,
        lenient: args.lenient,
    };
    // The JSON (`warnings` included) or text of a run's output.
    let result = |output: &crate::harness::ReplayOutput,
                  report: &preflight::Report,
                  read: &preflight::LogSummary| {
        for reason in &read.skip_reasons {
            eprintln!("warning: skipped {reason}");
        }
        for file in &read.unknown_files {
            eprintln!("warning: ignored unknown file {file}");
        }
        for w in &output.warnings {
            eprintln!("warning: {w}");
        }
        let mut warnings: Vec<Warning> = read.warnings.clone();
        warnings.extend(report.warnings().cloned());
        warnings.extend(output.warnings.iter().map(|w| model_warning(w)));
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
        let dir = write_out(out, |dir| {
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

/// A replay model's note as a warning: a file the model does not use (or
/// scores only in part) names it.
fn model_warning(text: &str) -> Warning {
    let file = text
        .split_whitespace()
        .map(|w| w.trim_matches(|c: char| !c.is_alphanumeric() && c != '.' && c != '_'))
        .find(|w| w.ends_with(".csv"));
    match file {
        Some(f) if text.contains("not used") => Warning::about(WarningKind::UnusedFile, f, text),
        Some(f) if text.contains("are scored") => {
            Warning::about(WarningKind::PartialScoring, f, text)
        }
        // A sensor whose rows (hardly) corrected the run.
        Some(f)
            if text.contains("applied (")
                || text.contains("has no rows")
                || text.contains("mean NEES")
                || text.contains("of the filter's sigmas") =>
        {
            Warning::about(WarningKind::Suspicious, f, text)
        }
        _ => Warning {
            kind: WarningKind::Model,
            file: None,
            line: None,
            key: None,
            message: text.to_string(),
        },
    }
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
pub(crate) fn write_out(
    out: &std::path::Path,
    fill: impl FnOnce(&std::path::Path) -> Result<(), RunError>,
) -> Result<PathBuf, RunError> {
    let at_out = |e: RunError| match e {
        RunError::Io { source, .. } => {
            RunError::Invalid(format!("--out {}: {source}", out.display()))
        }
        other => other,
    };
    // Created and registered under the interrupt registry's lock, so an
    // interruption never leaves the staging directory behind.
    let (staged, pending) = Pending::create(
        || StagedDir::new(out).map_err(at_out),
        |s| s.path().to_path_buf(),
    )?;
    fill(staged.path()).map_err(|e| match e {
        RunError::Io { source, path } => RunError::Invalid(format!(
            "--out {}: writing {}: {source}",
            out.display(),
            path.file_name()
                .map(|n| n.to_string_lossy().into_owned())
                .unwrap_or_default()
        )),
        other => other,
    })?;
    pending.finish(|| staged.commit()).map_err(at_out)
}

/// The preflight options of a run (after checking `--max-gap-periods`) and
/// the reader's strictness.
fn preflight_options(
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

/// `navsim check`: runs the preflight over the log as a stream (the log is
/// not loaded) and prints every finding; fails when there is an error.
pub fn cmd_check(args: &CheckArgs) -> Result<(), RunError> {
    let (options, strictness) = preflight_options(args.lenient, args.max_gap_periods, None)?;
    let files = LogFiles::open(&args.dir, strictness)?;
    let (report, summary) = preflight::check_files(&files, &options)?;
    let errors: Vec<Warning> = report.errors().cloned().collect();
    let mut warnings = summary.warnings.clone();
    warnings.extend(report.warnings().cloned());
    let span = summary.imu_time_span();
    let imu_rows = summary.imu_rows();
    let value = serde_json::json!({
        "dir": args.dir.display().to_string(),
        "ok": errors.is_empty(),
        "imu_rows": imu_rows,
        "imu_span_s": span.map(|(a, b)| b - a),
        "errors": warnings_json(&errors),
        "warnings": warnings_json(&warnings),
    });
    if args.json {
        println!("{}", report::json_line(&value));
    } else {
        println!(
            "{}: {} IMU rows over {:.3} s",
            args.dir.display(),
            imu_rows,
            span.map_or(0.0, |(a, b)| b - a)
        );
        for e in &errors {
            println!("error: {e}");
        }
        for w in &warnings {
            println!("warning: {w}");
        }
        if errors.is_empty() && warnings.is_empty() {
            println!("no problems found");
        }
    }
    match errors.len() {
        0 => Ok(()),
        n => Err(RunError::Invalid(format!(
            "{n} problem(s) found; first: {}",
            errors[0]
        ))),
    }
}

/// `navsim simulate`.
pub fn cmd_simulate(args: &SimulateArgs) -> Result<(), RunError> {
    let scenario = find_scenario(&args.name)?;
    let options = run_options(scenario.as_ref(), &args.faults, args.draw_biases, false)?;
    let log = scenario.simulate_log(args.seed, &options).ok_or_else(|| {
        RunError::Invalid(format!(
            "scenario {} cannot write a sensor log",
            scenario.name()
        ))
    })??;
    log.write(&args.out)?;
    println!(
        "wrote the sensor log of {} seed {} to {}",
        scenario.name(),
        args.seed,
        args.out.display()
    );
    Ok(())
}

/// `navsim merge`.
pub fn cmd_merge(args: &MergeArgs) -> Result<(), RunError> {
    let paths = find_shard_files(&args.dirs)?;
    let files = paths
        .into_iter()
        .map(|p| ShardFile::read(&p).map(|f| (p, f)))
        .collect::<Result<Vec<_>, _>>()?;
    let merged = merge_shards(&files)?;
    let scenario = find_scenario(&merged.scenario)?;
    let summary = summary_json(
        scenario.as_ref(),
        merged.seed,
        &merged.results,
        &merged.options,
    )?;
    emit_scenario(&summary, args.json, Plots::InShards);
    Ok(())
}

/// `navsim list`.
pub fn cmd_list(args: &ListArgs) -> Result<(), RunError> {
    let ss = scenarios();
    let ms = replay_models();
    if args.json {
        let sc: Vec<Value> = ss
            .iter()
            .map(|s| {
                serde_json::json!({"name": s.name(), "default_runs": s.default_runs(),
                    "faults": s.faults(), "description": s.description()})
            })
            .collect();
        let mo: Vec<Value> = ms
            .iter()
            .map(|m| serde_json::json!({"name": m.name(), "description": m.description()}))
            .collect();
        let v = serde_json::json!({"scenarios": sc, "models": mo, "default_scenario": default_scenario()});
        println!("{}", report::json_line(&v));
    } else {
        println!("scenarios:");
        for s in &ss {
            println!("  {:28} {}", s.name(), s.description());
        }
        println!("replay models:");
        for m in &ms {
            println!("  {:28} {}", m.name(), m.description());
        }
    }
    Ok(())
}

/// Runs a parsed command line.
pub fn run(cli: &Cli) -> Result<(), RunError> {
    match &cli.command {
        Some(Command::Scenario(a)) => cmd_scenario(a),
        Some(Command::Replay(a)) => cmd_replay(a),
        Some(Command::Simulate(a)) => cmd_simulate(a),
        Some(Command::Merge(a)) => cmd_merge(a),
        Some(Command::List(a)) => cmd_list(a),
        Some(Command::Check(a)) => cmd_check(a),
        Some(Command::Import(a)) => cmd_import(a),
        None => cmd_scenario(&ScenarioArgs {
            name: default_scenario().to_string(),
            seed: DEFAULT_SEED,
            runs: None,
            out: None,
            json: false,
            shard: None,
            faults: Vec::new(),
            draw_biases: false,
            smooth: false,
        }),
    }
}

/// Collapses a message to one line.
pub(crate) fn one_line(text: &str) -> String {
    text.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The `navsim` entry point: parses `std::env::args`, runs, reports errors.
pub fn main() -> ExitCode {
    main_with_args(std::env::args_os())
}

/// [`main`] with explicit arguments (the first is the program name).
pub fn main_with_args<I, T>(args: I) -> ExitCode
where
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let cli = match Cli::try_parse_from(args) {
        Ok(cli) => cli,
        Err(e) => return parse_failure(e),
    };
    match run(&cli) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}

/// Help and version on stdout (success); a usage error as one `error:` line
/// on stderr (exit code 2).
pub(crate) fn parse_failure(e: clap::Error) -> ExitCode {
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

    /// The notes of the replay models become warnings of the right kind
    /// naming their file (the JSON's `kind` and `file`).
    #[test]
    fn model_notes_become_warnings_naming_their_file() {
        let cases: &[(&str, &str, Option<&str>)] = &[
            ("mag.csv is not used by this model", "unused_file", Some("mag.csv")),
            (
                "truth.csv: only its rows up to t = 3 s (3 of 9) are scored, 57.0 s before the end",
                "partial_scoring",
                Some("truth.csv"),
            ),
            (
                "dvl.csv: none of its 120 rows was applied (120 gated, 0 rejected)",
                "suspicious",
                Some("dvl.csv"),
            ),
            (
                "truth.csv: mean NEES 585.0 over the 9 navigation states, more than 10 times",
                "suspicious",
                Some("truth.csv"),
            ),
            (
                "truth.csv: the final tilt error, 28.648 deg at t = 30 s, is 10006 of the filter's \
                 sigmas (tilt NEES 100115513)",
                "suspicious",
                Some("truth.csv"),
            ),
            ("the filter repaired its covariance 2 time(s)", "model", None),
        ];
        for &(text, kind, file) in cases {
            let w = model_warning(text);
            assert_eq!((w.kind.as_str(), w.file.as_deref()), (kind, file), "{text}");
            assert_eq!(w.message, text);
        }
    }
}
