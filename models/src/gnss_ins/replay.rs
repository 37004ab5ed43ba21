//! `navsim replay DIR --model gnss-ins`: the 16-state [`GnssIns`] vehicle
//! through the shared replay loop ([`replay_vehicle`]) over a log's
//! `imu.csv`, `gnss.csv`, `baro.csv` and `mag.csv` (`docs/ulog.md`,
//! "Replaying an imported log"), compared with `reference.csv` (PX4's own
//! estimate) and scored against `truth.csv` when the log has one.
//!
//! The loop's GNSS, barometer and magnetometer slots carry the measurement
//! models: the GNSS position fix of the antenna (sigma the receiver's `eph`
//! / `epv`, at least `[sensors.gnss] noise_sigma`, as PX4's EKF2 does), the
//! barometric altitude with its drifting bias (the bias starts at the first
//! barometer sample minus the initial height) and the magnetic heading
//! (declination from the log, as for `ahrs`). An estimate is taken at every
//! IMU sample, for the comparison with the reference at its own times, and
//! at every truth row, for the INS errors.
//!
//! The replay is a stream: the files are read as the filter goes, each
//! estimate is scored as it comes ([`RunningScores`]) and the time series
//! are written out as they grow ([`SeriesSink`]), the plots drawn from
//! bounded copies, so memory does not grow with the log.

use std::path::Path;

use nav_runtime::log::{
    BaroRow, GnssRow, LogSource, MagRow, ReferenceRow, RowSource, TruthRow, Warning, WarningKind,
};
use serde_json::{json, Value};

use super::model::GnssIns;
use super::scores::RunningScores;
pub use super::scores::TRUTH_DATUM_GAP_M;
use crate::ahrs::outputs::{write_outputs, write_plots};
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunHealth};
use crate::sdins25::filter::{replay_vehicle, FilterOptions, LENIENT_IMU_STEP_PERIODS};
use crate::sdins25::replay_loop::{EachSample, Listed, Smoothed};
use crate::sdins25::score::{Keep, Scorer};
use crate::ulog::reference::EstimatePoint;
use crate::ulog::running_score::{ReferenceScore, REFERENCE_COLUMNS};
use nav_ins::Estimate;
use nav_replay::output::series::SeriesSink;

/// `navsim replay --model gnss-ins`.
pub const NAME: &str = "gnss-ins";
/// Number of states.
pub const N: usize = 16;

/// IMU intervals longer than this are counted as gaps (`health.imu_gaps`), s.
pub const IMU_GAP_S: f64 = crate::ahrs::stream::MAX_IMU_STEP_S;
/// Files read.
pub const FILES: &[&str] = &[
    "imu.csv",
    "gnss.csv",
    "baro.csv",
    "mag.csv",
    "reference.csv",
    "truth.csv",
];

/// Name of the table of estimates.
pub const ESTIMATES_TABLE: &str = "estimates";
/// Name of the table of smoothed estimates (`--smooth`): the rows of
/// [`ESTIMATES_TABLE`], smoothed.
pub const SMOOTHED_TABLE: &str = "smoothed";
/// Name of the table of the smoothed estimates' differences to PX4's
/// estimate.
pub const SMOOTHED_REFERENCE_TABLE: &str = "smoothed_reference_difference";
/// Name of the table of the smoothed estimates' errors against truth.
pub const SMOOTHED_ERRORS_TABLE: &str = nav_replay::ins::SMOOTHED_TABLE;
/// The estimates table has a row at every this many IMU samples.
pub const ESTIMATES_EVERY: usize = 10;

/// What an estimate is requested for.
enum Wanted {
    /// The estimate at an IMU sample (for the reference and the tables).
    Sample,
    /// The estimate at a truth row, with its line in `truth.csv`.
    Truth(Option<u64>, TruthRow),
}

/// Columns of the estimates table.
pub const ESTIMATES_COLUMNS: [&str; 14] = [
    "t",
    "lat",
    "lon",
    "height",
    "vn",
    "ve",
    "vd",
    "roll_deg",
    "pitch_deg",
    "yaw_deg",
    "sig_n",
    "sig_e",
    "sig_d",
    "baro_bias",
];

/// The row of the estimates table of estimate `e`.
fn table_row(e: &Estimate) -> [f64; 14] {
    let nav = &e.nav;
    let a = nav.euler();
    [
        e.t,
        nav.lat,
        nav.lon,
        nav.h,
        nav.v_n.x,
        nav.v_n.y,
        nav.v_n.z,
        a.roll.to_degrees(),
        a.pitch.to_degrees(),
        a.yaw.to_degrees(),
        e.cov[(0, 0)].sqrt(),
        e.cov[(1, 1)].sqrt(),
        e.cov[(2, 2)].sqrt(),
        e.baro_bias.0,
    ]
}

/// Estimate `e` as the comparison with another solution reads it.
fn point(e: &Estimate) -> EstimatePoint {
    let a = e.nav.euler();
    EstimatePoint {
        t: e.t,
        attitude: [a.roll, a.pitch, a.yaw],
        position: Some([e.nav.lat, e.nav.lon, e.nav.h]),
    }
}

/// The truth rows of `rows` (none without `truth.csv`) as output times.
fn truth_requests<'a>(
    mut rows: Option<Box<dyn RowSource<TruthRow> + 'a>>,
) -> Listed<impl Iterator<Item = Result<(f64, Wanted), RunError>> + 'a> {
    Listed::new(std::iter::from_fn(move || {
        rows.as_mut()?
            .next_row()
            .map_err(RunError::from)
            .transpose()
            .map(|r| r.map(|(line, row)| (row.t, Wanted::Truth(line, row))))
    }))
}

/// What the run keeps of the estimates at the IMU samples: only their
/// count, span and the last one.
#[derive(Debug, Default)]
struct SampleTally {
    samples: usize,
    first_t: Option<f64>,
    last_t: Option<f64>,
    imu_gaps: u64,
    last: Option<Estimate>,
}

/// Replays `source`; with `out`, the tables are written there as the run
/// goes and plotted from bounded copies, else kept in the output when
/// `options.keep_series`.
///
/// # Errors
/// As [`replay_vehicle`]: no initial attitude, no IMU rows, a setup error,
/// a bad row (strict reading), an IMU row the filter refuses or an estimate
/// out of its bounds; a table that cannot be written.
pub fn replay_source(
    source: &LogSource<'_>,
    options: &ReplayOptions,
    out: Option<&Path>,
) -> Result<ReplayOutput, RunError> {
    let filter_options = FilterOptions {
        max_imu_step: Some(LENIENT_IMU_STEP_PERIODS),
        gap_warnings: options.lenient,
        observability: options.observability,
        smooth: options.smooth,
        ..FilterOptions::default()
    };
    // Its only position and velocity aiding: without it the INS drifts
    // freely until the estimate leaves its bounds, far from the cause.
    if !source.has::<GnssRow>()? {
        return Err(RunError::Invalid(format!(
            "gnss.csv: missing: model {NAME} needs GNSS fixes (its only position and velocity \
             aiding); replay an INS-only log with another model"
        )));
    }
    let meta = source.meta();
    let mut scores = RunningScores::new(source, out, options.keep_series, -meta.initial.depth)?;
    let mut estimates = SeriesSink::new(
        ESTIMATES_TABLE,
        &ESTIMATES_COLUMNS,
        out,
        options.keep_series,
    )?;
    let mut tally = SampleTally::default();
    // With smoothing, the truth rows and the rows of the estimates table
    // are smoothed (epochs of the recording), not every sample.
    let requests = EachSample::new(truth_requests(source.rows::<TruthRow>()?), |_| {
        Wanted::Sample
    })
    .smoothing_every(ESTIMATES_EVERY);
    let mut smoothed = options
        .smooth
        .then(|| SmoothedRun::new(source, out, options.keep_series))
        .transpose()?;
    let run = replay_vehicle::<GnssIns, N, _, _>(
        source,
        &filter_options,
        requests,
        |wanted, e| match (wanted, e) {
            (Wanted::Truth(line, row), e) => scores.push_truth(line, &row, e),
            (Wanted::Sample, Some(e)) => {
                if tally.last_t.is_some_and(|t| e.t - t > IMU_GAP_S) {
                    tally.imu_gaps += 1;
                }
                tally.first_t.get_or_insert(e.t);
                tally.last_t = Some(e.t);
                tally.samples += 1;
                tally.last = Some(*e);
                if tally.samples.is_multiple_of(ESTIMATES_EVERY) && estimates.wanted() {
                    estimates.push(&table_row(e))?;
                }
                scores.push_sample(point(e))
            }
            (Wanted::Sample, None) => Ok(()),
        },
        |kind, e| match smoothed.as_mut() {
            Some(s) => s.push(kind, e),
            None => Ok(()),
        },
    )?;

    let mut output = ReplayOutput {
        samples: run.samples,
        runtime_s: run.runtime_s,
        ..Default::default()
    };
    if let Some(o) = &run.observability {
        // The navigation errors are the solution; the biases are estimated,
        // and one the log did not teach is said.
        let navigation = ["position_error", "velocity_error", "attitude_error"];
        let (json, unlearned) = nav_replay::observability::json(
            o,
            &<GnssIns as nav_runtime::model::Model<N>>::STATE_NAMES,
            |_, name| (!navigation.iter().any(|n| name.starts_with(n))).then_some(""),
        );
        output.metrics.insert("observability".into(), json);
        output.warnings.extend(unlearned);
    }
    let warnings = &mut output.warnings;
    for name in &run.ignored {
        let rows = run
            .health
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0, |(_, h)| h.rows);
        let file = format!("{name}.csv");
        warnings.push(Warning::about(
            WarningKind::UnusedFile,
            &file,
            format!("model {NAME} has no {name} sensor: the {rows} rows of {file} are not used"),
        ));
    }
    warnings.extend(run.warnings.iter().cloned());
    warnings.extend(crate::sdins25::replay_output::unapplied_sensors(
        &run.health,
        &run.ignored,
    ));
    for (name, present) in [
        ("gnss", source.has::<GnssRow>()?),
        ("baro", source.has::<BaroRow>()?),
        ("mag", source.has::<MagRow>()?),
    ] {
        let rows = run
            .health
            .iter()
            .find(|(n, _)| *n == name)
            .map_or(0, |(_, h)| h.rows);
        if !present {
            warnings.push(nav_replay::model_note(format!(
                "the log has no {name}.csv: that aiding is absent"
            )));
        } else if rows == 0 {
            // A header only (or every row skipped): as absent, and said.
            let file = format!("{name}.csv");
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                &file,
                format!("{file} has no rows: that aiding is absent"),
            ));
        }
    }
    warnings.extend(nav_replay::covariance_repairs(run.repairs));
    // Per sensor with updates, as every replay with innovations reports
    // them (the NIS and gated share, a warning for a sigma they say is
    // off; what `navsim tune` fits: docs/tuning.md).
    output.innovations = run
        .innovations
        .iter()
        .filter(|s| ["gnss", "baro", "mag"].contains(&s.sensor.as_str()))
        .cloned()
        .collect();
    warnings.extend(output.innovations.iter().filter_map(|s| s.warning()));
    let m = &mut output.metrics;
    m.insert(
        "innovations".into(),
        nav_replay::innovations::innovations_json(&output.innovations),
    );
    m.insert(
        "recoveries".into(),
        nav_replay::ins::output::recoveries_json(&run.recoveries),
    );
    nav_replay::ins::constant_states::report(&run.bias_states, m, warnings);
    let scored = scores.finish(Some(run.imu_span), m, warnings)?;
    let smoothed = smoothed
        .map(|s| s.finish(run.imu_span, m, warnings))
        .transpose()?;
    m.insert(
        "magnetic_declination_deg".into(),
        Value::from(run.magnetic_declination.0.to_degrees()),
    );
    let span = match (tally.first_t, tally.last_t) {
        (Some(a), Some(b)) => b - a,
        _ => 0.0,
    };
    m.insert("replayed_seconds".into(), Value::from(span));
    let health = RunHealth {
        sensors: run
            .health
            .iter()
            .filter(|(name, _)| ["gnss", "baro", "mag"].contains(name))
            .map(|(name, h)| ((*name).to_string(), *h))
            .collect(),
        covariance_repairs: run.repairs,
        replays: None,
        imu_gaps: Some(tally.imu_gaps),
        lockout_releases: Some(run.final_filter.ekf().counters().updates_released),
    };
    m.insert("health".into(), health.json());
    if let Some(e) = &tally.last {
        let s = e.nav;
        let a = s.euler();
        m.insert(
            "final".into(),
            json!({
                "lat": s.lat, "lon": s.lon, "height": s.h,
                "vn": s.v_n.x, "ve": s.v_n.y, "vd": s.v_n.z,
                "roll": a.roll.to_degrees(), "pitch": a.pitch.to_degrees(), "yaw": a.yaw.to_degrees(),
                "baro_bias_m": e.baro_bias.0,
            }),
        );
    }
    // The tables in the order they always came: truth errors, estimates,
    // reference differences.
    let mut tables = scored.truth;
    tables.extend(estimates.finish()?);
    tables.extend(scored.reference);
    tables.extend(smoothed.into_iter().flatten());
    match out {
        Some(dir) => {
            write_plots(NAME, &tables, dir)?;
            nav_replay::ins::write_smoothed_plot(NAME, "replay", &tables, dir)?;
        }
        None => output.tables = tables,
    }
    Ok(output)
}

/// The smoothed run (`--smooth`), taken after the forward one: the rows of
/// the estimates table smoothed (`smoothed.csv`), and with truth the
/// smoothed estimates at the truth rows scored (`smoothed_errors.csv`, the
/// `smoothed` keys), the truth rows read again beside them.
struct SmoothedRun<'a> {
    table: SeriesSink,
    truth: Option<(Scorer, Box<dyn RowSource<TruthRow> + 'a>)>,
    /// The smoothed rows against PX4's estimate, `reference.csv` read
    /// again beside them.
    reference: Option<ReferenceScore<'a>>,
    estimates: u64,
}

impl<'a> SmoothedRun<'a> {
    fn new(
        source: &LogSource<'a>,
        out: Option<&Path>,
        keep_series: bool,
    ) -> Result<Self, RunError> {
        let truth = match source.rows::<TruthRow>()? {
            Some(rows) => Some((
                Scorer::new(
                    None,
                    Keep::for_replay(SMOOTHED_ERRORS_TABLE, out, keep_series)?,
                ),
                rows,
            )),
            None => None,
        };
        let reference = match source.rows::<ReferenceRow>()? {
            Some(rows) => Some(ReferenceScore::new(
                rows,
                SeriesSink::new(
                    SMOOTHED_REFERENCE_TABLE,
                    &REFERENCE_COLUMNS,
                    out,
                    keep_series,
                )?,
            )?),
            None => None,
        };
        Ok(SmoothedRun {
            table: SeriesSink::new(SMOOTHED_TABLE, &ESTIMATES_COLUMNS, out, keep_series)?,
            truth,
            reference,
            estimates: 0,
        })
    }

    /// The smoothed counterpart of the next smoothed request.
    fn push(&mut self, kind: Smoothed, e: Option<&Estimate>) -> Result<(), RunError> {
        self.estimates += u64::from(e.is_some());
        match kind {
            Smoothed::Sample => {
                let Some(e) = e else { return Ok(()) };
                if self.table.wanted() {
                    self.table.push(&table_row(e))?;
                }
                match self.reference.as_mut() {
                    Some(r) => r.push(point(e)),
                    None => Ok(()),
                }
            }
            Smoothed::Requested => {
                let Some((scorer, rows)) = self.truth.as_mut() else {
                    return Ok(());
                };
                match rows.next_row().map_err(RunError::from)? {
                    Some((line, row)) => scorer
                        .push(line, &row, e)
                        .map_err(|e| RunError::Invalid(format!("smoothed run: {e}"))),
                    None => Ok(()),
                }
            }
        }
    }

    /// Adds `smoothed` to `metrics` (`estimates`, and with truth the
    /// error keys) and returns the tables.
    fn finish(
        self,
        imu_span: (f64, f64),
        metrics: &mut serde_json::Map<String, Value>,
        warnings: &mut Vec<Warning>,
    ) -> Result<Vec<nav_replay::RunTable>, RunError> {
        let mut object = serde_json::Map::new();
        object.insert("estimates".into(), Value::from(self.estimates));
        let mut tables: Vec<_> = self.table.finish()?.into_iter().collect();
        if let Some(r) = self.reference {
            // The forward run's warnings about the reference hold for this
            // one too: not said twice.
            let mut keys = serde_json::Map::new();
            tables.extend(r.finish(&mut keys, &mut Vec::new())?);
            object.extend(keys.into_iter().filter(|(k, _)| {
                k.ends_with("_difference_rms_m") || k.ends_with("_difference_rms_deg")
            }));
        }
        match self.truth.map(|(s, _)| s.finish(Some(imu_span))) {
            Some(Ok(mut s)) => {
                for (k, v) in nav_replay::ins::ERROR_KEYS
                    .iter()
                    .zip(nav_replay::ins::error_values(&s))
                {
                    object.insert((*k).into(), Value::from(v));
                }
                s.table.name = SMOOTHED_ERRORS_TABLE.into();
                tables.push(s.table);
            }
            Some(Err(e)) => warnings.push(Warning::about(
                WarningKind::Suspicious,
                "truth.csv",
                format!("smoothed run not scored against truth: {e}"),
            )),
            None => {}
        }
        metrics.insert("smoothed".into(), Value::Object(object));
        Ok(tables)
    }
}

/// The replay model `gnss-ins`.
#[derive(Debug, Clone, Copy, Default)]
pub struct GnssInsReplay;

impl ReplayModel for GnssInsReplay {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "16-state INS with GNSS position, barometer and magnetic heading (imported PX4 logs)"
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
    /// The replay loop reads `imu.csv` through `LogSource::imu_rows`.
    fn shares_imu(&self) -> bool {
        true
    }
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        write_outputs(NAME, output, dir)
    }
}

#[cfg(test)]
#[path = "replay_tests.rs"]
mod tests;
