//! `navsim replay DIR --model ahrs`: the [`Ahrs`](super::Ahrs) filter over
//! a log's `imu.csv` and `mag.csv` (`docs/ulog.md`, "Replaying an imported
//! log"), streamed: the files are read as the filter goes ([`AhrsStream`]),
//! each estimate is scored against `reference.csv` and `truth.csv` as it
//! comes ([`crate::ulog::running_score`]), and the time series are written
//! out as they grow, so memory does not grow with the log.
//!
//! Before the run the first [`PERIOD_INTERVALS`] IMU rows are read ahead
//! (the IMU period the gyro noise is discretized with), and the
//! magnetometer rows within [`DECLINATION_WINDOW_S`] of the initial time
//! (the declination, [`declination`]); both are bounded.

use std::path::Path;
use std::time::{Duration, Instant};

use nav_runtime::log::{
    Event, ImuRow, LogSource, MagRow, Prefetched, ReferenceRow, TruthRow, Warning, WarningKind,
};
use nav_runtime::nalgebra::Vector3;
use serde_json::{json, Value};

use super::nominal::AhrsNominal;
use super::outputs::{write_outputs, write_plots};
use super::settings::AhrsSettings;
use super::smoothing::{AhrsRow, ForwardRows};
use super::stream::{AhrsStream, ImuStep};
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunHealth};
use crate::sdins25::filter::{median_period, PERIOD_INTERVALS};
use crate::ulog::reference::EstimatePoint;
use crate::ulog::replay::{declination, rpy_json, DECLINATION_WINDOW_S};
use crate::ulog::running_score::{ReferenceScore, TruthScore, REFERENCE_COLUMNS, TRUTH_COLUMNS};
use nav_ins::ImuSample;
use nav_replay::innovations::SensorInnovations;
use nav_replay::output::series::SeriesSink;

/// `navsim replay --model ahrs`.
pub const NAME: &str = "ahrs";

/// The log files the model reads.
pub const FILES: &[&str] = &["imu.csv", "mag.csv", "reference.csv", "truth.csv"];

/// Name of the table of estimates (one row per gravity window).
pub const ESTIMATES_TABLE: &str = "estimates";

/// Columns of the estimates table.
pub const ESTIMATES_COLUMNS: [&str; 10] = [
    "t",
    "roll_deg",
    "pitch_deg",
    "yaw_deg",
    "gyro_bias_x_deg_s",
    "gyro_bias_y_deg_s",
    "gyro_bias_z_deg_s",
    "sig_phi_n_deg",
    "sig_phi_e_deg",
    "sig_phi_d_deg",
];

/// Weakest directions reported by `ahrs --observability`.
const OBSERVABILITY_DIRECTIONS: usize = 3;

/// The replay model `ahrs`.
#[derive(Debug, Clone, Copy, Default)]
pub struct AhrsReplay;

impl ReplayModel for AhrsReplay {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "attitude and gyro bias from gyro, accelerometer (gravity) and magnetometer (imported PX4 logs)"
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        Some(FILES)
    }
    fn can_observe(&self) -> bool {
        true
    }
    fn can_smooth(&self) -> bool {
        true
    }
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        replay_source(source, options, out)
    }
    fn shares_imu(&self) -> bool {
        true
    }
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        write_outputs(NAME, output, dir)
    }
}

/// What the run needs before its first sample: the settings (IMU period
/// and declination included) and `imu.csv` with the rows read for them
/// kept, to be streamed from its start.
fn prepare<'a>(
    source: &LogSource<'a>,
    warnings: &mut Vec<Warning>,
) -> Result<(AhrsSettings, Prefetched<'a, ImuRow>), RunError> {
    let meta = source.meta();
    let attitude = meta.initial.attitude()?;
    let mut imu = Prefetched::new(source.imu_rows()?);
    for _ in 0..=PERIOD_INTERVALS {
        if imu.read_ahead()?.is_none() {
            break;
        }
    }
    let first = *imu
        .read()
        .next()
        .ok_or_else(|| RunError::Invalid("imu.csv: no rows".into()))?;
    let period = median_period(imu.read().map(|r| r.t));
    let mut settings = AhrsSettings::of(meta, period, warnings)?;
    // The declination: the magnetometer rows around the initial time (the
    // first IMU row without `[initial] t`) against the initial attitude.
    let t0 = meta.initial.t.unwrap_or(first.t);
    let mut near = Vec::new();
    let mut any_mag = false;
    let mag_file = source.rows::<MagRow>()?;
    let has_mag = mag_file.is_some();
    if let Some(mut rows) = mag_file {
        while let Some((_, r)) = rows.next_row()? {
            any_mag = true;
            if r.t > t0 + DECLINATION_WINDOW_S {
                break;
            }
            if r.t >= t0 - DECLINATION_WINDOW_S {
                near.push(r);
            }
        }
    }
    let (found, _samples) = declination(&near, t0, attitude).unwrap_or_else(|| {
        if any_mag {
            warnings.push(Warning::about(
                WarningKind::Model,
                "mag.csv",
                "mag.csv: no sample within 1 s of the initial estimate: declination 0",
            ));
        }
        (0.0, 0)
    });
    if !has_mag {
        warnings.push(nav_replay::model_note(
            "the log has no mag.csv: the yaw is not observed (gyro only)",
        ));
    } else if !any_mag {
        // A header only (or every row skipped): as absent, and said.
        warnings.push(Warning::about(
            WarningKind::Suspicious,
            "mag.csv",
            "mag.csv has no rows: the yaw is not observed (gyro only), declination 0",
        ));
    }
    settings.declination = found;
    Ok((settings, imu))
}

/// The estimate of nominal `n` at `t`, as the scores take it.
fn point(t: f64, n: &AhrsNominal) -> EstimatePoint {
    EstimatePoint {
        t,
        attitude: n.euler(),
        position: None,
    }
}

/// The row of the estimates table at `t`.
fn estimate_row(row: &AhrsRow) -> [f64; 10] {
    let n = &row.nominal;
    let e = n.euler().map(f64::to_degrees);
    let b = n.gyro_bias.map(f64::to_degrees);
    let s = row.attitude_sigma().map(f64::to_degrees);
    [row.t, e[0], e[1], e[2], b.x, b.y, b.z, s[0], s[1], s[2]]
}

/// Replays `source`; with `out`, the tables are written there as the run
/// goes (and plotted from bounded copies), else kept in the output when
/// `options.keep_series`.
///
/// # Errors
/// No initial attitude in `meta.toml`, no IMU rows, a bad row (strict
/// reading), a filter error.
pub fn replay_source(
    source: &LogSource<'_>,
    options: &ReplayOptions,
    out: Option<&Path>,
) -> Result<ReplayOutput, RunError> {
    let mut warnings = Vec::new();
    let (settings, imu) = prepare(source, &mut warnings)?;
    let declination_deg = settings.declination.to_degrees();
    let sink =
        |name: &str, columns: &[&str]| SeriesSink::new(name, columns, out, options.keep_series);
    let mut estimates = sink(ESTIMATES_TABLE, &ESTIMATES_COLUMNS)?;
    let mut reference = source
        .rows::<ReferenceRow>()?
        .map(|rows| -> Result<_, RunError> {
            Ok(ReferenceScore::new(
                rows,
                sink("reference_difference", &REFERENCE_COLUMNS)?,
            )?)
        })
        .transpose()?;
    let mut truth = source
        .rows::<TruthRow>()?
        .map(|rows| -> Result<_, RunError> {
            Ok(TruthScore::new(
                rows,
                sink("attitude_errors", &TRUTH_COLUMNS)?,
            )?)
        })
        .transpose()?;
    let mut stream = if options.observability || options.smooth {
        AhrsStream::recorded(settings, options.observability, options.smooth)?
    } else {
        AhrsStream::new(settings)?
    };
    let mut forward = options.smooth.then(ForwardRows::new).transpose()?;
    let mut events = source.events()?.with_rows(imu);
    let (mut baro_rows, mut gnss_rows) = (0usize, 0usize);
    let (mut first_t, mut last_t) = (None::<f64>, 0.0);
    let mut filter_time = Duration::ZERO;
    while let Some(located) = events.next_event()? {
        match located.event {
            Event::Imu(row) => {
                let sample = ImuSample {
                    gyro: Vector3::new(row.gx, row.gy, row.gz),
                    accel: Vector3::new(row.ax, row.ay, row.az),
                };
                let started = Instant::now();
                let step = stream
                    .push_imu(row.t, sample)
                    .map_err(|e| at_line(e, located.line))?;
                filter_time += started.elapsed();
                if step == ImuStep::Gap {
                    continue;
                }
                let window_closed = matches!(
                    step,
                    ImuStep::Propagated {
                        window_closed: true
                    }
                );
                if window_closed && (estimates.wanted() || forward.is_some()) {
                    let r = AhrsRow::of(row.t, stream.filter());
                    if estimates.wanted() {
                        estimates.push(&estimate_row(&r))?;
                    }
                    if let Some(f) = forward.as_mut() {
                        f.push(&r)?;
                    }
                }
                let p = point(row.t, stream.filter().nominal());
                first_t.get_or_insert(row.t);
                last_t = row.t;
                if let Some(r) = reference.as_mut() {
                    r.push(p)?;
                }
                if let Some(t) = truth.as_mut() {
                    t.push(p)?;
                }
            }
            Event::Mag(row) => {
                let started = Instant::now();
                stream.push_mag(row)?;
                filter_time += started.elapsed();
            }
            Event::Baro(_) => baro_rows += 1,
            Event::Gnss(_) => gnss_rows += 1,
            _ => {}
        }
    }
    let counts = stream.finish()?;
    let observed = match options.observability {
        true => stream.observability(OBSERVABILITY_DIRECTIONS)?,
        false => None,
    };
    let smoothed = match (forward, stream.recording()?) {
        (Some(rows), Some(recording)) => {
            let mut run = SmoothedRun::new(source, &sink)?;
            rows.smooth(&recording, |_, s| run.push(s))?;
            Some(run)
        }
        _ => None,
    };

    let mut output = ReplayOutput {
        samples: counts.samples,
        runtime_s: filter_time.as_secs_f64(),
        warnings,
        // The magnetometer's, whose sigma is `[sensors.mag] noise_sigma`;
        // a gravity window's variance is the accelerometer's over the
        // window with a floor, not one setting a factor could correct.
        innovations: vec![SensorInnovations {
            sensor: "mag".into(),
            noise_sigma: Some(stream.settings().mag_sigma),
            gated: counts.mag.gated,
            setting: ("meta.toml".into(), "sensors.mag.noise_sigma".into()),
            totals: stream.innovations().mag,
        }],
        ..Default::default()
    };
    // Per sensor with updates, as every replay with innovations reports
    // them, with a warning for a sigma they say is off (docs/tuning.md).
    output.metrics.insert(
        "innovations".into(),
        nav_replay::innovations::innovations_json(&output.innovations),
    );
    let off: Vec<Warning> = output
        .innovations
        .iter()
        .filter_map(|s| s.warning())
        .collect();
    output.warnings.extend(off);
    if let Some(o) = &observed {
        // The attitude is the solution; the gyro bias is estimated, and a
        // bias the log did not teach is said.
        let (json, unlearned) = nav_replay::observability::json(
            o,
            &<super::Ahrs as nav_runtime::model::Model<6>>::STATE_NAMES,
            |_, name| name.starts_with("gyro_bias").then_some(""),
        );
        output.metrics.insert("observability".into(), json);
        output.warnings.extend(unlearned);
    }
    for (file, rows) in [("baro.csv", baro_rows), ("gnss.csv", gnss_rows)] {
        if rows > 0 {
            output.warnings.push(Warning::about(
                WarningKind::UnusedFile,
                file,
                format!(
                    "model {NAME} has no {} sensor: the {rows} rows of {file} are not used",
                    &file[..file.len() - 4]
                ),
            ));
        }
    }
    // The tables in the order they always came: truth errors, estimates,
    // reference differences.
    let mut tables = Vec::new();
    let m = &mut output.metrics;
    let difference = match reference {
        Some(r) => r.finish(m, &mut output.warnings)?,
        None => None,
    };
    if let Some(t) = truth {
        match t.finish()? {
            Some(score) => {
                m.insert("attitude_error_rms_deg".into(), rpy_json(score.rms_deg));
                m.insert("scored_seconds".into(), Value::from(score.scored_seconds));
                tables.extend(score.table);
            }
            None => output.warnings.push(Warning::about(
                WarningKind::Suspicious,
                "truth.csv",
                "truth.csv and the estimate do not overlap: nothing scored",
            )),
        }
    }
    m.insert(
        "magnetic_declination_deg".into(),
        Value::from(declination_deg),
    );
    let span = first_t.map_or(0.0, |first| last_t - first);
    m.insert("replayed_seconds".into(), Value::from(span));
    let repairs = stream.filter().ekf().counters().covariance_repairs;
    output
        .warnings
        .extend(nav_replay::covariance_repairs(repairs));
    let health = RunHealth {
        sensors: vec![
            ("gravity".into(), counts.gravity),
            ("mag".into(), counts.mag),
        ],
        covariance_repairs: repairs,
        replays: None,
        imu_gaps: Some(counts.imu_gaps),
        // No release rule: a refused reading stays refused.
        lockout_releases: None,
    };
    m.insert("health".into(), health.json());
    let f = stream.filter().nominal();
    let e = f.euler().map(f64::to_degrees);
    let b = f.gyro_bias.map(f64::to_degrees);
    m.insert(
        "final".into(),
        json!({"roll": e[0], "pitch": e[1], "yaw": e[2],
               "gyro_bias_deg_s": [b.x, b.y, b.z]}),
    );
    tables.extend(estimates.finish()?);
    tables.extend(difference);
    if let Some(run) = smoothed {
        tables.extend(run.finish(m)?);
    }
    match out {
        Some(dir) => write_plots(NAME, &tables, dir)?,
        None => output.tables = tables,
    }
    Ok(output)
}

/// A divergence at an IMU row, with the row's line in the message and
/// the error's place (`navsim check --model` gives it in the JSON).
fn at_line(e: RunError, line: Option<u64>) -> RunError {
    match (e, line) {
        (RunError::Diverged { message, file, .. }, Some(l)) => RunError::Diverged {
            message: format!("imu.csv line {l}: {message}"),
            file,
            line: Some(l),
        },
        (e, _) => e,
    }
}

/// The smoothed rows of the estimates table (`smoothed.csv`) and their
/// differences to the reference and errors against truth, each file read
/// again beside them (`smoothed_reference_difference.csv`,
/// `smoothed_attitude_errors.csv`).
struct SmoothedRun<'a> {
    table: SeriesSink,
    reference: Option<ReferenceScore<'a>>,
    truth: Option<TruthScore<'a>>,
    estimates: u64,
}

/// Name of the table of smoothed estimates: the rows of
/// [`ESTIMATES_TABLE`], smoothed.
pub const SMOOTHED_TABLE: &str = "smoothed";

impl<'a> SmoothedRun<'a> {
    fn new(
        source: &LogSource<'a>,
        sink: &impl Fn(&str, &[&str]) -> Result<SeriesSink, RunError>,
    ) -> Result<Self, RunError> {
        let reference = match source.rows::<ReferenceRow>()? {
            Some(rows) => Some(ReferenceScore::new(
                rows,
                sink("smoothed_reference_difference", &REFERENCE_COLUMNS)?,
            )?),
            None => None,
        };
        let truth = match source.rows::<TruthRow>()? {
            Some(rows) => Some(TruthScore::new(
                rows,
                sink("smoothed_attitude_errors", &TRUTH_COLUMNS)?,
            )?),
            None => None,
        };
        Ok(SmoothedRun {
            table: sink(SMOOTHED_TABLE, &ESTIMATES_COLUMNS)?,
            reference,
            truth,
            estimates: 0,
        })
    }

    fn push(&mut self, row: Option<&AhrsRow>) -> Result<(), RunError> {
        let Some(row) = row else { return Ok(()) };
        self.estimates += 1;
        if self.table.wanted() {
            self.table.push(&estimate_row(row))?;
        }
        let p = point(row.t, &row.nominal);
        if let Some(r) = self.reference.as_mut() {
            r.push(p)?;
        }
        if let Some(t) = self.truth.as_mut() {
            t.push(p)?;
        }
        Ok(())
    }

    /// Adds `smoothed` to `metrics` (`estimates`, and
    /// `attitude_difference_rms_deg` and `attitude_error_rms_deg` where the
    /// log has the files) and returns the tables kept.
    fn finish(
        self,
        metrics: &mut serde_json::Map<String, Value>,
    ) -> Result<Vec<crate::harness::RunTable>, RunError> {
        let mut object = serde_json::Map::new();
        object.insert("estimates".into(), Value::from(self.estimates));
        let mut tables: Vec<_> = self.table.finish()?.into_iter().collect();
        if let Some(r) = self.reference {
            // The forward run's warnings about the reference hold for
            // this one too: not said twice.
            let mut keys = serde_json::Map::new();
            tables.extend(r.finish(&mut keys, &mut Vec::new())?);
            object.extend(
                keys.into_iter()
                    .filter(|(k, _)| k == "attitude_difference_rms_deg"),
            );
        }
        if let Some(t) = self.truth {
            if let Some(score) = t.finish()? {
                object.insert("attitude_error_rms_deg".into(), rpy_json(score.rms_deg));
                tables.extend(score.table);
            }
        }
        metrics.insert("smoothed".into(), Value::Object(object));
        Ok(tables)
    }
}

#[cfg(test)]
#[path = "replay_tests.rs"]
mod tests;
