//! The `navsim` command line: argument parsing and the commands, over the
//! registry of built-in scenarios and replay models (`models::registry`).
//!
//! Output rules: `--json` prints exactly one JSON object on stdout and nothing else
//! there; human text goes to stdout without `--json` and to stderr with it. Every
//! failure exits non-zero with one `error: ...` line on stderr.

use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nav_runtime::log::{Warning, WarningKind};
use serde_json::Value;

use models::harness::{
    find_shard_files, merge_shards, progress_bar, run_seeds, seeds, summary_json, RunError,
    RunOptions, Scenario, Shard, ShardFile, SHARD_FORMAT,
};
pub use models::registry::{
    check_draw_biases, default_scenario, find_replay_model, find_scenario, replay_models,
    scenarios, BiasesDrawnFor, DEFAULT_SCENARIO, DEFAULT_SEED, FALLBACK_SCENARIO,
};
use nav_replay::output::report;
use nav_replay::preflight;
pub use nav_replay::program::{
    emit, note, one_line, open_log, parse_failure, preflight_options, replay_with, warnings_json,
    write_log_out, write_out, ReplayArgs,
};

use crate::scenario_text::{scenario_text, Plots};

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
    /// IMU noise from a static recording: the Allan deviation of each gyro
    /// and accelerometer axis of the log's imu.csv, and its `[sensors.imu]`.
    Allan(AllanArgs),
    /// Identify the noise sigmas of the log's meta.toml from the log alone
    /// (maximum likelihood of the innovations) and write them.
    Tune(nav_replay::tune::TuneArgs),
}

/// `navsim allan`.
#[derive(Debug, Args)]
pub struct AllanArgs {
    /// Log directory of the static recording.
    pub dir: PathBuf,
    /// First time of imu.csv analysed, s (default: its first row).
    #[arg(long, allow_negative_numbers = true)]
    pub from: Option<f64>,
    /// Last time of imu.csv analysed, s (default: its last row).
    #[arg(long, allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Write the `[sensors.imu]` section found to this file.
    #[arg(long)]
    pub write: Option<PathBuf>,
    /// Directory for the curves (CSV) and their plots.
    #[arg(long)]
    pub out: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
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
    /// `mcap`: the mapping file (which topic feeds which sensor, frames,
    /// clock; docs/mcap.md). Without it the standard message types are
    /// mapped where unambiguous.
    #[arg(long)]
    pub mapping: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    pub json: bool,
}

/// The formats `navsim import` reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, clap::ValueEnum)]
pub enum ImportFormat {
    /// PX4 ULog (`.ulg`).
    Ulog,
    /// A ROS 2 bag in MCAP with CDR messages (`.mcap`).
    Mcap,
}

/// `navsim import`: writes the log directory; the topics used are in the warnings.
pub fn cmd_import(args: &ImportArgs) -> Result<(), RunError> {
    let (mut value, format) = match args.format {
        ImportFormat::Ulog => {
            if args.mapping.is_some() {
                return Err(RunError::Invalid(
                    "--mapping: only `import mcap` takes a mapping".into(),
                ));
            }
            let log = nav_import::ulog::import(&args.file, &args.out)
                .map_err(|e| RunError::Invalid(e.to_string()))?;
            for w in &log.warnings {
                eprintln!("warning: {w}");
            }
            (log.summary(), "ulog")
        }
        ImportFormat::Mcap => {
            let summary = nav_import::mcap::import(&args.file, args.mapping.as_deref(), &args.out)
                .map_err(|e| RunError::Invalid(e.to_string()))?;
            for w in &summary.warnings {
                eprintln!("warning: {w}");
            }
            (summary.json(), "mcap")
        }
    };
    value["command"] = Value::from("import");
    value["format"] = Value::from(format);
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
    /// Also read the log as `replay --model NAME` does: the model's own
    /// files, initial state and input checks, with the replay's code (the
    /// model is run; its outputs are discarded), so that a log the replay
    /// refuses is refused here with the same error.
    #[arg(long)]
    pub model: Option<String>,
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

/// The run options of the command line, checked against `scenario`:
/// `draw_biases` is `--draw-biases` with what it would change.
fn run_options(
    scenario: &dyn Scenario,
    faults: &[String],
    draw_biases: Option<BiasesDrawnFor>,
    smooth: bool,
) -> Result<RunOptions, RunError> {
    if let Some(drawn) = draw_biases {
        check_draw_biases(scenario, drawn)?;
    }
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
                "unknown fault `{f}` for scenario {}; valid faults: {valid}{}",
                scenario.name(),
                nav_runtime::log::did_you_mean(f, scenario.faults())
            )));
        }
        if !list.iter().any(|x| x == f) {
            list.push(f.to_string());
        }
    }
    Ok(RunOptions {
        faults: list,
        draw_biases: draw_biases.is_some(),
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
    // The seeds are `seed .. seed + runs - 1`: past u64's end they wrapped
    // to 0 with no word (and the summary named a meaningless range).
    if args.seed.checked_add(runs as u64 - 1).is_none() {
        return Err(RunError::Invalid(format!(
            "--seed {} with --runs {runs}: the last seed would pass {}; give a smaller --seed",
            args.seed,
            u64::MAX
        )));
    }
    let draw_biases = args.draw_biases.then_some(BiasesDrawnFor::Runs);
    let mut options = run_options(scenario.as_ref(), &args.faults, draw_biases, args.smooth)?;
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
        let file = ShardFile {
            format: SHARD_FORMAT,
            scenario: scenario.name().to_string(),
            seed: args.seed,
            runs,
            shard: shard.to_string(),
            options: options.clone(),
            results,
        };
        // Staged, and removed on an interruption, as every --out is.
        let dir = write_out(out, |dir| {
            file.write(&dir.join(shard.file_name()))?;
            scenario.write_outputs(&file.results, dir)
        })?;
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
        let dir = write_out(out, |dir| {
            scenario.write_outputs(&results, dir)?;
            let path = dir.join("summary.json");
            std::fs::write(&path, report::json_line(&summary) + "\n")
                .map_err(|e| RunError::io(&path, e))
        })?;
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

/// `navsim tune`: the noise sigmas of the log's `meta.toml` identified from
/// the log by the model's own replays (docs/tuning.md).
pub fn cmd_tune(args: &nav_replay::tune::TuneArgs) -> Result<(), RunError> {
    let model = find_replay_model(&args.model)?;
    nav_replay::tune::tune_with(model.as_ref(), args)
}

/// `navsim check`: runs the preflight over the log as a stream (the log is
/// not loaded) and prints every finding; fails when there is an error.
pub fn cmd_check(args: &CheckArgs) -> Result<(), RunError> {
    let model = args.model.as_deref().map(find_replay_model).transpose()?;
    let (options, strictness) = preflight_options(
        args.lenient,
        args.max_gap_periods,
        model.as_ref().and_then(|m| m.log_files()),
    )?;
    let files = open_log(&args.dir, strictness)?;
    let (report, summary) = preflight::check_files(&files, &options)?;
    let mut errors: Vec<Warning> = report.errors().cloned().collect();
    let mut warnings = summary.warnings.clone();
    warnings.extend(files.rejected_warnings());
    let mut notes = Vec::new();
    if let Some(model) = &model {
        // The preflight refuses first, as in `replay`.
        if errors.is_empty() {
            match check_with_model(model.as_ref(), args, strictness) {
                Ok(n) => notes = n,
                Err(e) => {
                    let e = preflight::explained(e, &report);
                    errors.push(e.finding(WarningKind::Model));
                }
            }
        }
    }
    warnings.extend(nav_replay::program::preflight_beside(&report, &notes));
    warnings.extend(notes);
    let span = summary.imu_time_span();
    let imu_rows = summary.imu_rows();
    let mut value = serde_json::json!({
        "dir": args.dir.display().to_string(),
        "ok": errors.is_empty(),
        "imu_rows": imu_rows,
        "imu_span_s": span.map(|(a, b)| b - a),
        "errors": warnings_json(&errors),
        "warnings": warnings_json(&warnings),
    });
    if let Some(model) = &model {
        value["model"] = Value::from(model.name());
    }
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

/// The replay of `model` over the log of `args`, as `navsim replay` runs it
/// (its own reading of the log, its setup and input checks, the filter),
/// with nothing kept: its notes, or the error the replay gives.
fn check_with_model(
    model: &dyn nav_replay::ReplayModel,
    args: &CheckArgs,
    strictness: nav_runtime::log::Strictness,
) -> Result<Vec<Warning>, RunError> {
    let files = open_log(&args.dir, strictness)?;
    let options = nav_replay::ReplayOptions {
        lenient: args.lenient,
        ..Default::default()
    };
    Ok(model.replay_files(&files, &options, None)?.warnings)
}

/// `navsim simulate`.
pub fn cmd_simulate(args: &SimulateArgs) -> Result<(), RunError> {
    let scenario = find_scenario(&args.name)?;
    let draw_biases = args.draw_biases.then_some(BiasesDrawnFor::Log);
    let options = run_options(scenario.as_ref(), &args.faults, draw_biases, false)?;
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
        Some(Command::Allan(a)) => cmd_allan(a),
        Some(Command::Tune(a)) => cmd_tune(a),
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

/// `navsim allan`: the Allan analysis of the log's IMU (docs/allan.md).
pub fn cmd_allan(args: &AllanArgs) -> Result<(), RunError> {
    use nav_replay::allan;
    let files = open_log(&args.dir, nav_runtime::log::Strictness::Strict)?;
    let stretch = allan::Stretch {
        from_s: args.from,
        to_s: args.to,
    };
    let report = allan::analyse_log(&files, stretch)?;
    let mut value = allan::report_json(&report);
    if let Some(path) = &args.write {
        std::fs::write(path, report.imu_section()).map_err(|e| RunError::io(path, e))?;
        value["written"] = serde_json::Value::from(path.display().to_string());
    }
    if let Some(out) = &args.out {
        let dir = write_log_out(out, &args.dir, |dir| {
            for a in &report.axes {
                let mut t = nav_replay::RunTable::new(
                    &format!("allan-{}", a.name),
                    &["tau_s", "deviation", "relative_error", "clusters"],
                );
                for p in &a.curve {
                    t.push(&[p.tau_s, p.deviation, p.relative_error, p.clusters as f64]);
                }
                t.write_csv(&dir.join(format!("allan-{}.csv", a.name)))?;
            }
            allan::write_plots(&report, dir)
        })?;
        value["out"] = serde_json::Value::from(dir.display().to_string());
    }
    for w in &report.warnings {
        eprintln!("warning: {w}");
    }
    if args.json {
        println!("{}", report::json_line(&value));
        return Ok(());
    }
    println!(
        "{}: {} IMU samples every {} s ({:.1} s)",
        args.dir.display(),
        report.samples,
        report.period_s,
        report.period_s * report.samples as f64
    );
    for a in &report.axes {
        let units = a.kind.units();
        let show = |r: &nav_runtime::calibration::allan::Reading, unit: &str| match r {
            nav_runtime::calibration::allan::Reading::Found(c) => {
                format!(
                    "{:.4e} {unit} (+-{:.1} %)",
                    c.value,
                    100.0 * c.relative_error
                )
            }
            nav_runtime::calibration::allan::Reading::NotReached(why) => {
                format!("not reached ({why})")
            }
        };
        println!(
            "{}: white {}; bias instability {}; random walk {}",
            a.name,
            show(&a.white, units[1]),
            show(&a.bias_instability, units[2]),
            show(&a.random_walk, units[3])
        );
    }
    print!("{}", report.imu_section());
    Ok(())
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
