//! The command line of a declared model's replay program: `replay` and
//! `check`, with the JSON of `docs/model-replay.md`, "Output".

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use clap::{Args, Parser, Subcommand};
use nav_runtime::ekf::Ekf;
use nav_runtime::model::Model;
use serde_json::{json, Map, Value};

use super::mapping::Mapping;
use super::run::{ModelRun, RunOptions, TruthScore};
use super::table::MappedRows;
use super::tuning::MappingTuning;
use super::{ModelReplay, ModelReplayError};
use crate::program::{emit, note, one_line, parse_failure, warnings_json, write_log_out};
use crate::RunError;

#[derive(Debug, Parser)]
#[command(version)]
struct Program {
    #[command(subcommand)]
    command: Command,
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Run the model's filter over a log directory.
    Replay(ReplayCommand),
    /// Check the mapping against the declaration and read every row.
    Check(CheckCommand),
    /// Identify the sensors' sigmas from the log alone (docs/tuning.md).
    Tune(TuneCommand),
}

#[derive(Debug, Args)]
struct Common {
    /// Log directory.
    dir: PathBuf,
    /// The mapping (default: `replay.toml` in the log directory).
    #[arg(long, value_name = "FILE")]
    mapping: Option<PathBuf>,
    /// Print one JSON object on stdout.
    #[arg(long)]
    json: bool,
    /// Skip (and count) bad CSV rows instead of stopping; propagate an input
    /// gap in steps (with a warning) instead of refusing it.
    #[arg(long)]
    lenient: bool,
}

#[derive(Debug, Args)]
struct ReplayCommand {
    #[command(flatten)]
    common: Common,
    /// Directory for `estimates.csv`, the plots (`state-*.svg`), with
    /// `--smooth` `smoothed.csv`, and `summary.json`.
    #[arg(long)]
    out: Option<PathBuf>,
    /// Write an estimate at most every this many seconds (0: every input sample).
    #[arg(long, default_value_t = 0.0, value_name = "S")]
    every: f64,
    /// Report what the log taught each state (docs/observability.md).
    #[arg(long)]
    observability: bool,
    /// Smooth the run after it (fixed-interval smoother, docs/smoother.md).
    #[arg(long)]
    smooth: bool,
}

/// Identify the sensors' sigmas (and, with `--params`, the `[noise]`
/// entries) of the mapping from the log alone (docs/tuning.md).
#[derive(Debug, Args)]
struct TuneCommand {
    #[command(flatten)]
    common: Common,
    #[command(flatten)]
    flags: crate::tune::TuneFlags,
}

#[derive(Debug, Args)]
struct CheckCommand {
    #[command(flatten)]
    common: Common,
}

pub(super) fn main_with<M, const N: usize, I, T>(replay: &ModelReplay<M, N>, args: I) -> ExitCode
where
    M: Model<N>,
    Ekf<M, N>: Clone,
    I: IntoIterator<Item = T>,
    T: Into<std::ffi::OsString> + Clone,
{
    let program = match Program::try_parse_from(args) {
        Ok(p) => p,
        Err(e) => return parse_failure(e),
    };
    let result = match program.command {
        Command::Replay(c) => cmd_replay(replay, &c),
        Command::Check(c) => cmd_check(replay, &c.common),
        Command::Tune(c) => cmd_tune(replay, &c),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}", one_line(&e.to_string()));
            ExitCode::FAILURE
        }
    }
}

fn invalid(e: ModelReplayError) -> RunError {
    match e {
        ModelReplayError::Log(e) => RunError::Log(e),
        e => RunError::Invalid(e.to_string()),
    }
}

fn cmd_replay<M: Model<N>, const N: usize>(
    replay: &ModelReplay<M, N>,
    c: &ReplayCommand,
) -> Result<(), RunError>
where
    Ekf<M, N>: Clone,
{
    if !(c.every.is_finite() && c.every >= 0.0) {
        return Err(RunError::Invalid(format!(
            "--every {}: expected seconds >= 0",
            c.every
        )));
    }
    let options = RunOptions {
        lenient: c.common.lenient,
        output_period: c.every,
        observability: c.observability,
        smooth: c.smooth,
    };
    let run = |out: Option<&Path>| {
        replay
            .replay(&c.common.dir, c.common.mapping.as_deref(), &options, out)
            .map_err(invalid)
    };
    let value = |r: &ModelRun| {
        for w in &r.warnings {
            eprintln!("warning: {}", w.message);
        }
        run_json(replay.name(), M::NAME, r, c.common.lenient)
    };
    match &c.out {
        Some(out) => {
            let mut v = Value::Null;
            let dir = write_log_out(out, &c.common.dir, |dir| {
                v = value(&run(Some(dir))?);
                let path = dir.join("summary.json");
                std::fs::write(&path, crate::output::report::json_line(&v) + "\n")
                    .map_err(|e| RunError::io(&path, e))
            })?;
            emit(&v, c.common.json);
            note(
                c.common.json,
                &format!("outputs written to {}", dir.display()),
            );
        }
        None => emit(&value(&run(None)?), c.common.json),
    }
    Ok(())
}

/// `tune`: the mapping's sigmas from the log (`crate::tune`), the tuned
/// mapping written with `--write`.
fn cmd_tune<M: Model<N>, const N: usize>(
    replay: &ModelReplay<M, N>,
    c: &TuneCommand,
) -> Result<(), RunError>
where
    Ekf<M, N>: Clone,
{
    let (name, mapping) = replay
        .mapping(&c.common.dir, c.common.mapping.as_deref())
        .map_err(invalid)?;
    let tunable = MappingTuning::new(
        replay,
        &c.common.dir,
        name.clone(),
        mapping,
        RunOptions {
            lenient: c.common.lenient,
            ..RunOptions::default()
        },
    );
    let tuning = crate::tune::tune_with_progress(&tunable, &c.flags)?;
    let mut value = tuning.json();
    let warnings = crate::tune::tuning_warnings(&tuning, c.flags.max_replays);
    if let Some(path) = &c.flags.write {
        let source = c
            .common
            .mapping
            .clone()
            .unwrap_or_else(|| c.common.dir.join(super::MAPPING_FILE));
        let text = std::fs::read_to_string(&source).map_err(|e| RunError::io(&source, e))?;
        let tuned = tunable.mapping_with(&tuning.identified_values());
        let values = crate::tune::tuned_mapping_values(&tunable, &tuning.identified_values());
        let out = crate::tune::tuned_mapping_text(&text, &name, &values)?;
        // Read back: the written mapping must give the tuned values.
        let back = super::mapping::parse(&out, &name, &replay.declared()).map_err(invalid)?;
        let same = back.sensors.iter().zip(&tuned.sensors).all(|(a, b)| {
            a.as_ref().map(|m| (&m.sigma, m.source.time_offset_s))
                == b.as_ref().map(|m| (&m.sigma, m.source.time_offset_s))
        }) && back.noise == tuned.noise;
        if !same {
            return Err(RunError::Invalid(format!(
                "{name}: the written mapping does not read back to the tuned values"
            )));
        }
        std::fs::write(path, out).map_err(|e| RunError::io(path, e))?;
        value["written"] = Value::from(path.display().to_string());
    }
    if let Value::Object(m) = &mut value {
        m.insert("warnings".into(), warnings_json(&warnings));
    }
    emit(&value, c.common.json);
    Ok(())
}

/// The keys of a truth score: `state_error_rms`, `nees_mean`, `nees_dof`,
/// `scored_samples`.
fn truth_json(t: &TruthScore, m: &mut Map<String, Value>) {
    let rms: Map<String, Value> = t
        .rms
        .iter()
        .map(|(n, v)| ((*n).to_string(), Value::from(*v)))
        .collect();
    m.insert("state_error_rms".into(), Value::Object(rms));
    m.insert("nees_mean".into(), Value::from(t.nees_mean));
    m.insert("nees_dof".into(), Value::from(t.nees_dof));
    m.insert("scored_samples".into(), Value::from(t.scored));
}

/// The JSON object of a run (`docs/model-replay.md`, "Output").
pub fn run_json(name: &str, model: &str, run: &ModelRun, lenient: bool) -> Value {
    let mut sensors = Map::new();
    for s in &run.sensors {
        sensors.insert(
            s.name.into(),
            json!({
                "file": s.file,
                "rows": s.rows,
                "accepted": s.accepted,
                "gated": s.gated,
                "rejected": s.rejected,
                "skipped_rows": s.skipped_rows,
                "nis_mean": s.nis_mean,
                "outputs": s.outputs,
            }),
        );
    }
    let state: Map<String, Value> = run
        .final_state
        .iter()
        .map(|(n, v, _)| ((*n).to_string(), Value::from(*v)))
        .collect();
    let sigma: Map<String, Value> = run
        .final_state
        .iter()
        .map(|(n, _, s)| ((*n).to_string(), Value::from(*s)))
        .collect();
    let mut m = Map::new();
    m.insert("model".into(), Value::from(name));
    m.insert("declared_model".into(), Value::from(model));
    m.insert("samples".into(), Value::from(run.samples));
    m.insert(
        "replayed_seconds".into(),
        Value::from(run.span.1 - run.span.0),
    );
    m.insert("runtime_s".into(), Value::from(run.runtime_s));
    m.insert("sensors".into(), Value::Object(sensors));
    // Each sensor's innovations (docs/tuning.md): its sigmas are per
    // output, so the supported sigma is a factor on them.
    let innovations: Vec<crate::innovations::SensorInnovations> = run
        .sensors
        .iter()
        .map(|s| crate::innovations::SensorInnovations {
            sensor: s.name.to_string(),
            noise_sigma: None,
            gated: s.gated,
            setting: (String::new(), format!("sensors.{}.sigma", s.name)),
            totals: s.innovations,
        })
        .collect();
    m.insert(
        "innovations".into(),
        crate::innovations::innovations_json(&innovations),
    );
    m.insert(
        "final".into(),
        json!({ "t": run.span.1, "state": state, "sigma": sigma }),
    );
    if let Some(t) = &run.truth {
        truth_json(t, &mut m);
    }
    if let Some(s) = &run.smoothed {
        let mut smoothed = Map::new();
        smoothed.insert("estimates".into(), Value::from(s.estimates));
        if let Some(t) = &s.truth {
            truth_json(t, &mut smoothed);
        }
        m.insert("smoothed".into(), Value::Object(smoothed));
    }
    m.insert(
        "health".into(),
        json!({ "covariance_repairs": run.covariance_repairs }),
    );
    m.insert("lenient".into(), Value::from(lenient));
    let skipped: Map<String, Value> = run
        .skipped_rows
        .iter()
        .map(|(f, n)| (f.clone(), Value::from(*n)))
        .collect();
    m.insert("skipped_rows".into(), Value::Object(skipped));
    if let Some(o) = &run.observability {
        m.insert("observability".into(), o.clone());
    }
    m.insert("warnings".into(), warnings_json(&run.warnings));
    Value::Object(m)
}

fn cmd_check<M: Model<N>, const N: usize>(
    replay: &ModelReplay<M, N>,
    c: &Common,
) -> Result<(), RunError>
where
    Ekf<M, N>: Clone,
{
    let (name, mapping) = replay
        .mapping(&c.dir, c.mapping.as_deref())
        .map_err(invalid)?;
    let value = check_json(replay, &c.dir, &name, &mapping, c.lenient).map_err(invalid)?;
    // What the replay refuses (an input gap, an initial state it cannot
    // use), `check` refuses with the same error: the replay itself runs
    // (its outputs are discarded).
    let options = RunOptions {
        lenient: c.lenient,
        ..RunOptions::default()
    };
    replay
        .replay(&c.dir, c.mapping.as_deref(), &options, None)
        .map_err(invalid)?;
    if let Some(w) = value["warnings"].as_array() {
        for w in w {
            eprintln!("warning: {}", w["message"].as_str().unwrap_or_default());
        }
    }
    emit(&value, c.json);
    Ok(())
}

/// What `check` finds: every mapped file read through (rows, time span).
pub(super) fn check_json<M: Model<N>, const N: usize>(
    replay: &ModelReplay<M, N>,
    dir: &Path,
    name: &str,
    mapping: &Mapping,
    lenient: bool,
) -> Result<Value, ModelReplayError>
where
    Ekf<M, N>: Clone,
{
    let mut files = Map::new();
    let declared = replay.declared();
    // (what the file feeds, its source, the checks of its rows as the
    // replay makes them: cells checked for a constant, and the spacing)
    let mut feeds = vec![("inputs".to_string(), &mapping.inputs, usize::MAX, false)];
    for (s, m) in declared.sensors.iter().zip(&mapping.sensors) {
        if let Some(m) = m {
            feeds.push((format!("sensor {}", s.name), &m.source, m.sigma.len(), true));
        }
    }
    feeds.push(("truth".to_string(), &mapping.truth, 0, false));
    let mut warnings = mapping.warnings.clone();
    warnings.extend(mapping.unmapped_files(dir));
    // The inputs' span (read first): a sensor's rows outside it are never used.
    let mut inputs_span: Option<(f64, f64)> = None;
    for (what, source, cells, intervals) in feeds {
        let Some(mut rows) = MappedRows::open(dir, source, name, lenient)? else {
            continue;
        };
        rows.check(cells, intervals);
        let mut span: Option<(f64, f64)> = None;
        while let Some((_, t)) = rows.next_row()? {
            span = Some(span.map_or((t, t), |(a, _)| (a, t)));
        }
        if what == "inputs" {
            inputs_span = span;
        }
        // What the replay would say of a sensor's file: glitches, no rows,
        // no row within the inputs' span.
        if let Some(r) = &rows.rejected {
            warnings.push(r.warning());
        }
        if intervals {
            let file = &source.file;
            let outside = match (span, inputs_span) {
                (Some((a, b)), Some((start, end))) => b < start || a > end,
                _ => false,
            };
            if span.is_none() {
                warnings.push(nav_runtime::log::Warning::about(
                    nav_runtime::log::WarningKind::Suspicious,
                    file,
                    format!(
                        "{what}: {file} has no rows: the sensor would never correct the estimate"
                    ),
                ));
            } else if outside {
                let (start, end) = inputs_span.unwrap_or_default();
                warnings.push(nav_runtime::log::Warning::about(
                    nav_runtime::log::WarningKind::OutsideImuSpan,
                    file,
                    format!("{what}: no row of {file} lies within the inputs' span, {start} to {end} s: none would be used (times in another unit or clock?)"),
                ));
            }
        }
        for s in &rows.skipped {
            warnings.push(nav_runtime::log::Warning::about(
                nav_runtime::log::WarningKind::SkippedRow,
                &s.file,
                format!("skipped {s}"),
            ));
        }
        warnings.extend(rows.row_warnings());
        warnings.extend(rows.near_miss_warnings());
        files.insert(
            source.file.clone(),
            json!({
                "feeds": what,
                "rows": rows.rows,
                "skipped_rows": rows.skipped_rows,
                "span_s": span.map(|(a, b)| json!([a, b])),
            }),
        );
    }
    Ok(json!({
        "model": replay.name(),
        "declared_model": M::NAME,
        "mapping": name,
        "files": Value::Object(files),
        "warnings": warnings_json(&warnings),
    }))
}
