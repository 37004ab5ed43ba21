//! `navsim replay DIR --model leveling6`: LEVELING-6 over a log's `imu.csv`
//! and `speed.csv`, with no attitude knowledge, streamed. Unless the run is
//! told it is at rest, the speed log is read once first; when it shows no
//! motion, the run at rest starts while another thread reads `imu.csv` for
//! a turning sample, and goes again in motion if it finds one
//! ([`looks_stationary`] is the same test in one thread). The run reads the
//! files as the filter goes, each estimate is compared with `truth.csv` as
//! it comes ([`TruthErrors`]), and the smoothed estimates wait in a
//! temporary file ([`SmoothedEstimates`](super::filter::SmoothedEstimates),
//! `smoothed.rs`), so memory does not grow with the log.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};

use nav_replay::innovations::SensorInnovations;
use nav_replay::output::series::SeriesSink;
use nav_runtime::log::{ImuRow, LogSource, Meta, SpeedRow, TruthRow, Warning, WarningKind};
use serde_json::{Map, Value};

use super::filter::{self, LevelingOptions, Recording, Tuning};
use super::model::Leveling6;
use super::score::{self, TruthErrors};
use super::{tilt_nees, TABLE};
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunTable};

/// `navsim replay --model leveling6`.
const NAME: &str = "leveling6";

/// `navsim replay DIR --model leveling6`: imu.csv + speed.csv, no attitude knowledge.
#[derive(Clone, Copy, Debug, Default)]
pub struct Leveling6Replay;

/// A replay's final tilt NEES (2 dof) above this (a hundred sigmas) is
/// warned.
const FINAL_NEES_WARN: f64 = 1e4;

/// Name of the table of the smoothed estimates' errors (`--smooth`).
const SMOOTHED_TABLE: &str = "smoothed_attitude";

/// Weakest directions reported by `leveling6 --observability`.
const OBSERVABILITY_DIRECTIONS: usize = 3;

/// The key of the speed log's noise sigma in `meta.toml`.
const SPEED_SIGMA_KEY: &str = "sensors.speed.noise_sigma";

/// Largest speed-log reading (m/s) and gyro rate magnitude (rad/s: 0.5
/// deg/s) of a vehicle at rest.
const AT_REST: (f64, f64) = (0.05, 0.008_726_646_259_971_648);

/// Stationarity from the data: a speed log that never reaches 0.05 m/s (or
/// none) and a gyro whose magnitude never reaches 0.5 deg/s, read the speed
/// log first and `imu.csv` only while it shows no motion, up to its first
/// turning sample.
///
/// # Errors
/// A file cannot be read (or, strict reading, has a bad row).
pub fn looks_stationary(source: &LogSource<'_>) -> Result<bool, RunError> {
    Ok(!speed_log_moves(source)? && !gyro_turns(source, &AtomicBool::new(false))?)
}

/// Whether a reading of the speed log reaches 0.05 m/s.
fn speed_log_moves(source: &LogSource<'_>) -> Result<bool, RunError> {
    if let Some(mut speed) = source.rows::<SpeedRow>()? {
        while let Some((_, r)) = speed.next_row()? {
            if r.speed.abs() >= AT_REST.0 {
                return Ok(true);
            }
        }
    }
    Ok(false)
}

/// Whether a sample of `imu.csv` turns at 0.5 deg/s or more; `turning` is
/// set as soon as one does.
fn gyro_turns(source: &LogSource<'_>, turning: &AtomicBool) -> Result<bool, RunError> {
    let mut imu = source
        .rows::<ImuRow>()?
        .ok_or_else(|| RunError::Invalid("imu.csv: no rows".into()))?;
    while let Some((_, r)) = imu.next_row()? {
        if (r.gx * r.gx + r.gy * r.gy + r.gz * r.gz).sqrt() >= AT_REST.1 {
            turning.store(true, Ordering::Relaxed);
            return Ok(true);
        }
    }
    Ok(false)
}

/// The replay's tuning: the paper's ([`Tuning::default`]) with the speed
/// log's sigma from `meta.toml`'s `[sensors.speed] noise_sigma`. Its
/// `bias_sigma` is not used: the six states carry no speed-log bias, and a
/// constant one moves the velocity estimate rather than the innovations (on
/// a simulated S-track with 0.1 m/s of each, the noise alone gives a mean
/// NIS of 1, the two added as noise 0.5), so it is said in `warnings`.
/// Without the section a log with a speed log moving keeps the paper's
/// 0.15 m/s, also said. (`meta.toml` refuses a zero sigma.)
fn replay_tuning(
    meta: &Meta,
    has_speed: bool,
    stationary: bool,
    warnings: &mut Vec<Warning>,
) -> Tuning {
    let mut tuning = Tuning::default();
    let used = has_speed && !stationary;
    match meta.sensors.speed {
        Some(s) => {
            tuning.speed_sigma = s.noise_sigma;
            if used && s.bias_sigma > 0.0 {
                warnings.push(nav_replay::meta_note(
                    "sensors.speed.bias_sigma",
                    format!(
                        "leveling6 carries no speed-log bias: bias_sigma {} is not used (a \
                         constant bias moves the velocity estimate, not the innovations)",
                        s.bias_sigma
                    ),
                ));
            }
        }
        None if used => {
            warnings.push(nav_replay::missing_section(
                "speed",
                format!(
                    "meta.toml has no [sensors.speed]: the speed log's rows are weighed with \
                     the paper's {} m/s",
                    tuning.speed_sigma
                ),
            ));
        }
        None => {}
    }
    tuning
}

impl ReplayModel for Leveling6Replay {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "LEVELING-6 roll/pitch alignment over imu.csv + speed.csv (stationary detected or --stationary)"
    }
    fn has_stationary_mode(&self) -> bool {
        true
    }
    fn can_observe(&self) -> bool {
        true
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        Some(&["imu.csv", "speed.csv", "truth.csv"])
    }
    /// The speed log's noise sigma; the IMU's noise is the paper's tuning
    /// (its accelerometer density covers the bias drift the six states do
    /// not carry), not `[sensors.imu]`.
    fn uses_noise_parameter(&self, key: &str) -> bool {
        key == SPEED_SIGMA_KEY
    }
    /// The tables as CSV and, with truth, the roll and pitch errors with
    /// their `±3 sigma` bounds (`replay-roll.svg`, `replay-pitch.svg`).
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        for table in &output.tables {
            table.write_csv(&dir.join(format!("{}.csv", table.name)))?;
        }
        write_plots(&output.tables, dir)
    }
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        replay_source(source, options, out)
    }
}

/// With truth, the roll and pitch errors with their `±3 sigma` bounds
/// (`replay-roll.svg`, `replay-pitch.svg`) from the table of `tables` that
/// has them.
fn write_plots(tables: &[RunTable], dir: &Path) -> Result<(), RunError> {
    let Some(t) = tables.iter().find(|t| t.name == TABLE) else {
        return Ok(());
    };
    let time = t.column("t");
    for angle in ["roll", "pitch"] {
        nav_replay::output::plot::error_with_sigma(
            &dir.join(format!("replay-{angle}.svg")),
            &format!("{NAME}: {angle} error with ±3 sigma"),
            &format!("{angle} error [deg]"),
            &time,
            &t.column(&format!("{angle}_error_deg")),
            &t.column(&format!("{angle}_sigma_deg")),
        )?;
    }
    Ok(())
}

/// One run of the filter over the log, at rest or in motion, with its
/// settings, their warnings and the truth compared as it went.
struct Attempt<'a> {
    stationary: bool,
    opts: LevelingOptions,
    warnings: Vec<Warning>,
    run: filter::LevelingRun,
    observed: Option<nav_runtime::smoother::Observability<6>>,
    smoothed: Option<filter::SmoothedEstimates>,
    errors: Option<TruthErrors<'a>>,
}

/// Runs the filter over `source`, at rest or in motion (`stationary`); it
/// stops with an error as soon as `abandon` is set.
fn attempt<'a>(
    source: &LogSource<'a>,
    options: &ReplayOptions,
    out: Option<&Path>,
    stationary: bool,
    has_speed: bool,
    abandon: Option<&AtomicBool>,
) -> Result<Attempt<'a>, RunError> {
    let mut warnings = Vec::new();
    let opts = LevelingOptions {
        stationary,
        initial_attitude: None,
        tuning: replay_tuning(source.meta(), has_speed, stationary, &mut warnings),
    };
    let sink = |name: &str| SeriesSink::new(name, &score::COLUMNS, out, options.keep_series);
    let mut errors = match source.rows::<TruthRow>()? {
        Some(rows) => Some(TruthErrors::new(rows, sink(TABLE)?)?),
        None => None,
    };
    let mut each = |e: &filter::AttitudeEstimate| {
        if abandon.is_some_and(|a| a.load(Ordering::Relaxed)) {
            return Err(RunError::Invalid(
                "leveling6: the gyro turns: not at rest".into(),
            ));
        }
        match errors.as_mut() {
            Some(s) => s.push(e),
            None => Ok(()),
        }
    };
    let (run, observed, smoothed) = if options.observability || options.smooth {
        let recording = Recording {
            observability: options.observability.then_some(OBSERVABILITY_DIRECTIONS),
            smooth: options.smooth,
        };
        let r = filter::run_recorded::<Leveling6, 6>(source, &opts, recording, &mut each)?;
        (r.run, r.observed, r.smoothed)
    } else {
        (filter::run(source, &opts, &mut each)?, None, None)
    };
    Ok(Attempt {
        stationary,
        opts,
        warnings,
        run,
        observed,
        smoothed,
        errors,
    })
}

/// Replays `source`; with `out`, the tables are written there (the
/// compared rows, kept on disk during the run, at its end) and plotted
/// from bounded copies, else kept in the output when `options.keep_series`.
///
/// # Errors
/// No initial position in `meta.toml`, a bad row (strict reading), a filter
/// error, truth that does not overlap the run.
fn replay_source(
    source: &LogSource<'_>,
    options: &ReplayOptions,
    out: Option<&Path>,
) -> Result<ReplayOutput, RunError> {
    // Gravity and the earth rate at the initial latitude and height.
    source.meta().initial.position_for(NAME)?;
    let has_speed = source.has::<SpeedRow>()?;
    let decided = match options.stationary {
        true => Some(true),
        false => speed_log_moves(source)?.then_some(false),
    };
    let Attempt {
        stationary,
        opts,
        mut warnings,
        run,
        observed,
        smoothed,
        errors,
    } = match decided {
        Some(stationary) => attempt(source, options, out, stationary, has_speed, None)?,
        // At rest unless the gyro turns, which only the whole of imu.csv
        // tells: the run at rest goes while another thread reads the file,
        // and stops to go again in motion if it finds a turning sample.
        None => {
            let turning = AtomicBool::new(false);
            std::thread::scope(|scope| {
                let scan = scope.spawn(|| gyro_turns(source, &turning));
                let at_rest = attempt(source, options, out, true, has_speed, Some(&turning));
                let turns = scan
                    .join()
                    .map_err(|_| RunError::Invalid("leveling6: reading imu.csv failed".into()))??;
                match turns {
                    true => attempt(source, options, out, false, has_speed, None),
                    false => at_rest,
                }
            })?
        }
    };
    let runtime_s = run.filter_time.as_secs_f64();
    warnings.extend(nav_replay::covariance_repairs(run.repairs));
    let mut output = ReplayOutput {
        samples: run.samples,
        runtime_s,
        warnings,
        ..Default::default()
    };
    if !stationary && has_speed {
        // The speed log's innovations, as every replay with innovations
        // reports them, with a warning for a sigma they say is off
        // (docs/tuning.md).
        output.innovations.push(SensorInnovations {
            sensor: "speed".into(),
            noise_sigma: Some(opts.tuning.speed_sigma),
            gated: run.gated,
            setting: ("meta.toml".into(), SPEED_SIGMA_KEY.into()),
            totals: run.speed_innovations,
        });
        output.metrics.insert(
            "innovations".into(),
            nav_replay::innovations::innovations_json(&output.innovations),
        );
        let off = output.innovations.iter().filter_map(|s| s.warning());
        output.warnings.extend(off.collect::<Vec<_>>());
    }
    if let Some(o) = &observed {
        // Velocity and gravity direction: the solution itself, no
        // estimated sensor state to warn about.
        let (json, _) = nav_replay::observability::json(
            o,
            &<Leveling6 as nav_runtime::model::Model<6>>::STATE_NAMES,
            |_, _| None,
        );
        output.metrics.insert("observability".into(), json);
    }
    output
        .metrics
        .insert("stationary".into(), Value::from(stationary));
    output.metrics.insert("health".into(), run.health.json());
    let mut tables = Vec::new();
    // The RMS leaves out the initial guess.
    let after = run.first.map_or(f64::NEG_INFINITY, |e| e.t);
    if let Some(errors) = errors {
        let scored = errors.finish(run.mean_period(), after)?;
        // The first estimate is the initial guess: fewer than two truth
        // rows after it score nothing (no final error of 0, no RMS of
        // nothing), as for every other model.
        if scored.scored_after < 2 {
            let (truth_start, truth_end) = scored.truth_span.unwrap_or((f64::NAN, f64::NAN));
            let (imu_start, imu_end) = run.imu_span.unwrap_or((f64::NAN, f64::NAN));
            let why = nav_replay::ins::score::ScoreError::NoOverlap {
                truth_start,
                truth_end,
                imu_start,
                imu_end,
                rows: scored.scored_after,
            };
            return Err(RunError::Invalid(why.to_string()));
        }
        // The final errors are those at the last truth row with an
        // estimate: said when that is not the end of the run.
        if let (Some((t, roll, pitch)), Some(first), Some(last)) =
            (scored.last, run.first, run.last)
        {
            // A final error of a hundred of the filter's sigmas is not
            // the filter's (the bias floor of a 1 mg accelerometer at
            // rest is 28, tilt NEES 806): a truth of another
            // convention, offset or clock.
            let nees = tilt_nees(roll, pitch, &last);
            if nees > FINAL_NEES_WARN {
                output.warnings.push(Warning::about(
                    WarningKind::Suspicious,
                    "truth.csv",
                    format!(
                        "truth.csv: the final tilt error, {:.3} deg at t = {t} s, is {:.0} of \
                         the filter's sigmas (tilt NEES {nees:.0}): a truth of another \
                         convention, offset or clock, or an error the filter does not model",
                        roll.hypot(pitch).to_degrees(),
                        nees.sqrt()
                    ),
                ));
            }
            let early = last.t - t;
            if early > (0.05 * (last.t - first.t)).max(1.0) {
                output.warnings.push(Warning::about(
                    WarningKind::PartialScoring,
                    "truth.csv",
                    format!(
                        "truth.csv: only its rows up to t = {t} s ({} of {}) are scored, \
                         {early:.1} s before the end of the run (t = {} s): the final errors \
                         are not at the end",
                        scored.scored, scored.truth_rows, last.t
                    ),
                ));
            }
            let m = &mut output.metrics;
            m.insert(
                "roll_error_final_deg".into(),
                Value::from(roll.to_degrees()),
            );
            m.insert(
                "pitch_error_final_deg".into(),
                Value::from(pitch.to_degrees()),
            );
        }
        let (roll, pitch) = scored.rms_deg();
        let m = &mut output.metrics;
        m.insert("roll_error_rms_deg".into(), Value::from(roll));
        m.insert("pitch_error_rms_deg".into(), Value::from(pitch));
        tables.extend(scored.table);
    }
    if let Some(smoothed) = smoothed {
        let mut m = Map::new();
        m.insert("estimates".into(), Value::from(smoothed.len()));
        if let Some(truth) = source.rows::<TruthRow>()? {
            let period = smoothed.mean_period();
            let sink = SeriesSink::new(SMOOTHED_TABLE, &score::COLUMNS, out, options.keep_series)?;
            let mut errors = TruthErrors::new(truth, sink)?;
            smoothed.for_each(|e| errors.push(e))?;
            let scored = errors.finish(period, after)?;
            let (roll, pitch) = scored.rms_deg();
            m.insert("roll_error_rms_deg".into(), Value::from(roll));
            m.insert("pitch_error_rms_deg".into(), Value::from(pitch));
            tables.extend(scored.table);
        }
        output.metrics.insert("smoothed".into(), Value::Object(m));
    }
    match out {
        Some(dir) => write_plots(&tables, dir)?,
        None => output.tables = tables,
    }
    Ok(output)
}
