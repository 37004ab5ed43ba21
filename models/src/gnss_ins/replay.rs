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
//! IMU sample, for the comparison with the reference at its own times.

use std::path::Path;

use nav_runtime::log::{LogDir, LogSource, TruthRow};
use serde_json::{json, Map, Value};

use super::model::GnssIns;
use crate::ahrs::outputs::write_outputs;
use crate::harness::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunHealth, RunTable};
use crate::navigator::{Estimate, SensorHealth};
use crate::sdins25::filter::{replay_vehicle, FilterOptions, LENIENT_IMU_STEP_PERIODS};
use crate::sdins25::replay_loop::{EachSample, Listed};
use crate::sdins25::score;
use crate::ulog::reference::EstimatePoint;
use crate::ulog::replay::{attitude_errors, reference_metrics, rpy_json};

/// `navsim replay --model gnss-ins`.
pub const NAME: &str = "gnss-ins";
/// Number of states.
pub const N: usize = 16;

/// A truth height this far from the initial height is on another datum, m.
pub const TRUTH_DATUM_GAP_M: f64 = 100.0;
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

/// What an estimate is requested for.
enum Wanted {
    /// The estimate at an IMU sample (for the reference and the tables).
    Sample,
    /// The estimate at truth row `k`.
    Truth(usize),
}

/// A run of the `gnss-ins` vehicle over a log.
#[derive(Debug, Clone, Default)]
pub struct GnssInsRun {
    /// The estimate at every IMU sample.
    pub points: Vec<EstimatePoint>,
    /// The estimate at every truth row (`None` where no IMU sample is near).
    pub at_truth: Vec<Option<Estimate>>,
    /// `estimates` table (every 10th IMU sample).
    pub table: RunTable,
    /// GNSS, barometer and magnetometer counts.
    pub health: Vec<(&'static str, SensorHealth)>,
    /// IMU intervals longer than [`IMU_GAP_S`].
    pub imu_gaps: u64,
    /// IMU samples propagated.
    pub samples: usize,
    /// Declination, rad, and the samples averaged.
    pub declination: (f64, usize),
    /// The final estimate.
    pub final_estimate: Option<Estimate>,
    /// Covariance repairs.
    pub covariance_repairs: u64,
    /// Filter seconds.
    pub runtime_s: f64,
    /// Notes.
    pub warnings: Vec<String>,
}

const TABLE_COLUMNS: [&str; 14] = [
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

/// Runs the `gnss-ins` vehicle over `log` through the shared replay loop.
///
/// # Errors
/// As [`replay_vehicle`]: no initial attitude, no IMU rows, a setup error,
/// an IMU row the filter refuses or an estimate out of its bounds.
pub fn run(log: &LogDir, options: &ReplayOptions) -> Result<GnssInsRun, RunError> {
    let filter_options = FilterOptions {
        max_imu_step: options.lenient.then_some(LENIENT_IMU_STEP_PERIODS),
        ..FilterOptions::default()
    };
    let truth = log.truth.as_deref().unwrap_or_default();
    let mut out = GnssInsRun {
        at_truth: vec![None; truth.len()],
        table: RunTable::new("estimates", &TABLE_COLUMNS),
        ..GnssInsRun::default()
    };
    let mut order: Vec<usize> = (0..truth.len()).collect();
    order.sort_by(|&a, &b| truth[a].t.total_cmp(&truth[b].t));
    let requests = EachSample::new(
        Listed::new(
            order
                .into_iter()
                .map(|k| Ok((truth[k].t, Wanted::Truth(k)))),
        ),
        |_| Wanted::Sample,
    );
    let mut last: Option<f64> = None;
    let run = replay_vehicle::<GnssIns, N, _, _>(
        &LogSource::Memory(log),
        &filter_options,
        requests,
        |wanted, e| {
            match (wanted, e) {
                (Wanted::Truth(k), e) => out.at_truth[k] = e.copied(),
                (Wanted::Sample, Some(e)) => {
                    if last.is_some_and(|t| e.t - t > IMU_GAP_S) {
                        out.imu_gaps += 1;
                    }
                    last = Some(e.t);
                    let a = e.nav.euler();
                    out.points.push(EstimatePoint {
                        t: e.t,
                        attitude: [a.roll, a.pitch, a.yaw],
                        position: Some([e.nav.lat, e.nav.lon, e.nav.h]),
                    });
                    if out.points.len().is_multiple_of(10) {
                        out.table.push(&table_row(e));
                    }
                    out.final_estimate = Some(*e);
                }
                (Wanted::Sample, None) => {}
            }
            Ok(())
        },
        // Not smoothed (`FilterOptions::smooth` is off).
        |_| Ok(()),
    )?;
    out.samples = run.samples;
    out.runtime_s = run.runtime_s;
    out.covariance_repairs = run.repairs;
    out.declination = run.magnetic_declination;
    out.health = run
        .health
        .iter()
        .filter(|(name, _)| ["gnss", "baro", "mag"].contains(name))
        .copied()
        .collect();
    for name in &run.ignored {
        let rows = run
            .health
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0, |(_, h)| h.rows);
        out.warnings.push(format!(
            "model {NAME} has no {name} sensor: the {rows} rows of {name}.csv are not used"
        ));
    }
    out.warnings.extend(run.warnings);
    for (file, missing) in [
        ("gnss.csv", log.gnss.is_none()),
        ("baro.csv", log.baro.is_none()),
        ("mag.csv", log.mag.is_none()),
    ] {
        if missing {
            out.warnings
                .push(format!("the log has no {file}: that aiding is absent"));
        }
    }
    Ok(out)
}

fn health_json(run: &GnssInsRun) -> Value {
    RunHealth {
        sensors: run
            .health
            .iter()
            .map(|(name, h)| ((*name).to_string(), *h))
            .collect(),
        covariance_repairs: run.covariance_repairs,
        replays: None,
        imu_gaps: Some(run.imu_gaps),
    }
    .json()
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
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        let run = run(log, options)?;
        let mut out = ReplayOutput {
            samples: run.samples,
            runtime_s: run.runtime_s,
            warnings: run.warnings.clone(),
            ..Default::default()
        };
        let m = &mut out.metrics;
        let diff = reference_metrics(log, &run.points, m, &mut out.warnings);
        if let Some(truth) = log.truth.as_deref() {
            scored_against(
                truth,
                log,
                &run,
                options,
                m,
                &mut out.warnings,
                &mut out.tables,
            );
        }
        m.insert(
            "magnetic_declination_deg".into(),
            Value::from(run.declination.0.to_degrees()),
        );
        let span = match (run.points.first(), run.points.last()) {
            (Some(a), Some(b)) => b.t - a.t,
            _ => 0.0,
        };
        m.insert("replayed_seconds".into(), Value::from(span));
        m.insert("health".into(), health_json(&run));
        if let Some(e) = &run.final_estimate {
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
        if options.keep_series {
            out.tables.push(run.table);
            out.tables.extend(diff);
        }
        Ok(out)
    }
    fn write_outputs(&self, output: &ReplayOutput, dir: &Path) -> Result<(), RunError> {
        write_outputs(NAME, output, dir)
    }
}

/// The usual error keys against `truth.csv` and the attitude errors.
fn scored_against(
    truth: &[TruthRow],
    log: &LogDir,
    run: &GnssInsRun,
    options: &ReplayOptions,
    m: &mut Map<String, Value>,
    warnings: &mut Vec<String>,
    tables: &mut Vec<RunTable>,
) {
    let h0 = -log.meta.initial.depth;
    if let Some(r) = truth
        .first()
        .filter(|r| (-r.depth - h0).abs() > TRUTH_DATUM_GAP_M)
    {
        warnings.push(format!(
            "truth.csv: height {:.1} m at t = {} s, the initial height {h0:.1} m: the truth's \
             vertical datum differs (depth_error_rms_m and nees_mean are not meaningful)",
            -r.depth, r.t
        ));
    }
    match score::score(&run.at_truth, truth, None, log.imu_time_span()) {
        Ok(s) => {
            for (k, v) in [
                ("horizontal_error_final_m", s.horizontal_error_final_m),
                ("horizontal_error_rms_m", s.horizontal_error_rms_m),
                ("depth_error_rms_m", s.depth_error_rms_m),
                ("nees_mean", s.nees_mean),
                ("scored_seconds", s.scored_seconds),
            ] {
                m.insert(k.into(), Value::from(v));
            }
            warnings.extend(s.partial.clone());
            if options.keep_series {
                tables.push(s.table);
            }
        }
        Err(e) => warnings.push(format!("not scored against truth: {e}")),
    }
    if let Some((rms, _, table)) = attitude_errors(truth, &run.points) {
        m.insert("attitude_error_rms_deg".into(), rpy_json(rms));
        if options.keep_series {
            tables.push(table);
        }
    }
}
