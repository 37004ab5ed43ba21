//! `navsim replay` of an INS vehicle as a stream: the log is read as the
//! filter goes ([`replay_vehicle`]), each estimate is scored against its
//! truth row and written out as it becomes final, and only bounded copies
//! of the time series are kept for the plots. Peak memory is that of the
//! latency window, whatever the log's length (with `--smooth` too: the
//! smoother's epochs, the forward estimates it corrects and the smoothed
//! estimates wait in temporary files).
//!
//! Output times: the truth rows when the log has `truth.csv`, otherwise
//! every [`OUTPUT_PERIOD_S`] from the first IMU sample.

use std::path::Path;

use nav_runtime::log::{LogSource, RowSource, TruthRow, Warning, WarningKind};
use serde_json::{json, Map, Value};

use super::constant_states::ConstantState;
use super::replay_loop::{Every, Listed};
use super::score::{Keep, Scored, Scorer, TABLE};
use super::setup::{replay_vehicle, FilterOptions, InsRun, LENIENT_IMU_STEP_PERIODS};
use super::{
    error_values, write_plots, write_smoothed_plot, write_trajectory_plots, ERROR_KEYS,
    SMOOTHED_TABLE,
};
use crate::innovations::innovations_json;
use crate::output::series::SeriesSink;
use crate::{ReplayOptions, ReplayOutput, RunError, SensorHealth};
use nav_ins::vehicle::{InsVehicle, Layout};
use nav_ins::Estimate;

/// Spacing of the output times of a log without truth, s.
pub const OUTPUT_PERIOD_S: f64 = 0.1;

/// Name of the trajectory table (`estimates.csv` under `--out`).
pub const TRAJECTORY_TABLE: &str = "estimates";

/// Name of the smoothed trajectory table (`smoothed.csv` under `--out` with
/// `--smooth`): the rows of [`TRAJECTORY_TABLE`], smoothed.
pub const SMOOTHED_TRAJECTORY_TABLE: &str = "smoothed";

/// Columns of the trajectory table: time, position, velocity, attitude and
/// their standard deviations (m, m/s, deg).
pub const TRAJECTORY_COLUMNS: [&str; 19] = [
    "t",
    "lat",
    "lon",
    "depth",
    "vn",
    "ve",
    "vd",
    "roll_deg",
    "pitch_deg",
    "yaw_deg",
    "sig_n",
    "sig_e",
    "sig_d",
    "sig_vn",
    "sig_ve",
    "sig_vd",
    "sig_roll_deg",
    "sig_pitch_deg",
    "sig_yaw_deg",
];

/// One output time and the truth row there, if the log has truth.
type OutputTime = (f64, Option<(Option<u64>, TruthRow)>);

/// The output times of a log with truth: its truth rows.
fn truth_times<'a>(
    mut rows: Box<dyn RowSource<TruthRow> + 'a>,
) -> Listed<impl Iterator<Item = Result<(f64, OutputTime), RunError>> + 'a> {
    Listed::new(std::iter::from_fn(move || {
        rows.next_row()
            .map_err(RunError::from)
            .transpose()
            .map(|r| r.map(|(line, row)| (row.t, (row.t, Some((line, row))))))
    }))
}

/// The trajectory row of an estimate.
fn trajectory_row(e: &Estimate) -> [f64; 19] {
    let s = &e.nav;
    let euler = s.euler();
    let sig = |i: usize| e.cov[(i, i)].sqrt();
    let deg = f64::to_degrees;
    [
        e.t,
        s.lat,
        s.lon,
        s.depth(),
        s.v_n.x,
        s.v_n.y,
        s.v_n.z,
        deg(euler.roll),
        deg(euler.pitch),
        deg(euler.yaw),
        sig(0),
        sig(1),
        sig(2),
        sig(3),
        sig(4),
        sig(5),
        deg(sig(6)),
        deg(sig(7)),
        deg(sig(8)),
    ]
}

fn score_error(e: super::score::ScoreError) -> RunError {
    RunError::Invalid(e.to_string())
}

/// Replays vehicle `V` over `source`; with `out`, the time series
/// (`errors.csv`, `estimates.csv`, with `--smooth` `smoothed.csv` and, with
/// truth, `smoothed_errors.csv`) and plots are written there as the run
/// goes; without, the error tables are kept in the output when
/// `options.keep_series`.
pub(super) fn replay_source<V: InsVehicle<N>, const N: usize>(
    source: &LogSource<'_>,
    options: &ReplayOptions,
    out: Option<&Path>,
) -> Result<ReplayOutput, RunError> {
    Layout::of::<V, N>()?;
    let filter_options = FilterOptions {
        smooth: options.smooth,
        observability: options.observability,
        max_imu_step: Some(LENIENT_IMU_STEP_PERIODS),
        gap_warnings: options.lenient,
        ..FilterOptions::default()
    };
    let truth = source.rows::<TruthRow>()?;
    let has_truth = truth.is_some();

    let keep = |name: &str| Keep::for_replay(name, out, options.keep_series);
    let mut scorer = has_truth
        .then(|| keep(TABLE))
        .transpose()?
        .map(|k| Scorer::new(None, k));
    // Written under `--out`, with a bounded copy for the plots.
    let mut trajectory = SeriesSink::new(TRAJECTORY_TABLE, &TRAJECTORY_COLUMNS, out, false)?;
    let sink = |(_, truth): OutputTime, e: Option<&Estimate>| {
        if let (true, Some(e)) = (trajectory.wanted(), e) {
            trajectory.push(&trajectory_row(e))?;
        }
        if let (Some(s), Some((line, row))) = (&mut scorer, &truth) {
            s.push(*line, row, e).map_err(score_error)?;
        }
        Ok(())
    };
    // The smoothed estimates come after the run, one per output time in the
    // same order: with truth, the output times are the truth rows, read
    // again beside them.
    let mut smoothed_scorer = (options.smooth && has_truth)
        .then(|| -> Result<_, RunError> {
            let rows = source.rows::<TruthRow>()?;
            Ok((Scorer::new(None, keep(SMOOTHED_TABLE)?), rows))
        })
        .transpose()?;
    // The smoothed trajectory: the rows of `estimates.csv`, smoothed, with
    // or without truth (a log without truth is what a user smooths most).
    let mut smoothed_trajectory = SeriesSink::new(
        SMOOTHED_TRAJECTORY_TABLE,
        &TRAJECTORY_COLUMNS,
        out.filter(|_| options.smooth),
        false,
    )?;
    let mut smoothed_estimates = 0u64;
    let smoothed_sink = |_, e: Option<&Estimate>| -> Result<(), RunError> {
        if let Some(e) = e {
            smoothed_estimates += 1;
            if smoothed_trajectory.wanted() {
                smoothed_trajectory.push(&trajectory_row(e))?;
            }
        }
        if let Some((s, Some(rows))) = &mut smoothed_scorer {
            if let Some((line, row)) = rows.next_row().map_err(RunError::from)? {
                s.push(line, &row, e).map_err(score_error)?;
            }
        }
        Ok(())
    };
    let run: InsRun<V, N> = match truth {
        Some(rows) => replay_vehicle::<V, N, _, _>(
            source,
            &filter_options,
            truth_times(rows),
            sink,
            smoothed_sink,
        )?,
        None => replay_vehicle::<V, N, _, _>(
            source,
            &filter_options,
            Every::new(OUTPUT_PERIOD_S),
            sink,
            smoothed_sink,
        )?,
    };
    let forward_track = trajectory.finish()?;
    let smoothed_track = smoothed_trajectory.finish()?;
    let span = Some(run.imu_span);
    let scored: Option<Scored> = scorer
        .map(|s| s.finish(span))
        .transpose()
        .map_err(score_error)?;
    let smoothed = match smoothed_scorer {
        Some((s, _)) => {
            let mut s = s
                .finish(span)
                .map_err(|e| RunError::Invalid(format!("smoothed run: {e}")))?;
            s.table.name = SMOOTHED_TABLE.to_string();
            Some(s)
        }
        None => None,
    };
    if let (Some(dir), Some(forward)) = (out, &forward_track) {
        write_trajectory_plots(
            V::REPLAY_NAME,
            "replay",
            forward,
            smoothed_track.as_ref(),
            dir,
        )?;
    }
    if let Some(dir) = out {
        if let Some(s) = &scored {
            write_plots(V::REPLAY_NAME, "replay", &s.table, dir)?;
            if let Some(sm) = &smoothed {
                write_smoothed_plot(
                    V::REPLAY_NAME,
                    "replay",
                    &[s.table.clone(), sm.table.clone()],
                    dir,
                )?;
            }
        }
    }
    let smoothed_estimates = options.smooth.then_some(smoothed_estimates);
    output_of::<V, N>(
        &run,
        scored,
        (smoothed, smoothed_estimates),
        options,
        out.is_none(),
    )
}

/// Degrees of freedom of the navigation NEES (position, velocity, attitude).
const NAV_NEES_DOF: f64 = 9.0;

/// The key of the NEES warning.
pub const NEES_KEY: &str = "nees";

/// A share of gated aiding rows beyond which the innovations, not only
/// the truth, disagree with the filter.
const MAX_GATED_SHARE: f64 = 0.1;

/// A mean NEES above this many times its degrees of freedom is warned: a
/// consistent filter is near 1, a tuned-down one a few times, a truth of
/// another sign or convention hundreds of times.
const NEES_WARN_FACTOR: f64 = 10.0;

/// A warning per sensor whose rows hardly corrected the run: none applied
/// (a DVL that never had bottom lock, a noise sigma that gates every row),
/// or more refused (gated, rejected, frozen) than applied. Its health counts
/// say so too, but a result that looks aided needs the warning.
pub fn unapplied_sensors(
    health: &[(&'static str, SensorHealth)],
    ignored: &[&'static str],
) -> Vec<Warning> {
    let mut warnings = Vec::new();
    for (name, h) in health {
        if h.rows == 0 || ignored.contains(name) {
            continue;
        }
        let refused = h.gated + h.rejected + h.stuck;
        let counts = format!(
            "{} gated, {} rejected, {} frozen, {} skipped",
            h.gated, h.rejected, h.stuck, h.skipped
        );
        let file = format!("{name}.csv");
        if h.accepted == 0 {
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                &file,
                format!(
                    "sensor {name}: none of the {} rows of {file} was applied ({counts})",
                    h.rows
                ),
            ));
        } else if refused > h.accepted {
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                &file,
                format!(
                    "sensor {name}: only {} of the {} rows of {file} were applied ({counts})",
                    h.accepted, h.rows
                ),
            ));
        }
    }
    warnings
}

/// The JSON `recoveries`: each lock-out recovery's sensor, time, how long
/// the sensor had been refused and when that was found (docs/lockout.md,
/// "Recovery" and "Rollback").
pub fn recoveries_json(recoveries: &[nav_ins::Recovery]) -> Value {
    recoveries
        .iter()
        .map(|r| {
            json!({
                "sensor": r.sensor,
                "t_s": r.t_s,
                "refused_for_s": r.refused_for_s,
                "detected_s": r.detected_s,
            })
        })
        .collect()
}

/// The replay output of a run: metrics, warnings and (with `tables`) the
/// error tables; `smoothed` is the smoothed run's scores (with truth) and,
/// with `--smooth`, how many estimates got a smoothed counterpart.
pub(super) fn output_of<V: InsVehicle<N>, const N: usize>(
    run: &InsRun<V, N>,
    scored: Option<Scored>,
    (smoothed, smoothed_estimates): (Option<Scored>, Option<u64>),
    options: &ReplayOptions,
    tables: bool,
) -> Result<ReplayOutput, RunError> {
    let mut out = ReplayOutput {
        samples: run.samples,
        runtime_s: run.runtime_s,
        ..Default::default()
    };
    for name in &run.ignored {
        let rows = run
            .health
            .iter()
            .find(|(n, _)| n == name)
            .map_or(0, |(_, h)| h.rows);
        let file = format!("{name}.csv");
        out.warnings.push(Warning::about(
            WarningKind::UnusedFile,
            &file,
            format!(
                "model {} has no {name} sensor: the {rows} rows of {file} are not used",
                V::REPLAY_NAME
            ),
        ));
    }
    out.warnings.extend(run.warnings.iter().cloned());
    out.warnings
        .extend(unapplied_sensors(&run.health, &run.ignored));
    out.warnings.extend(crate::covariance_repairs(run.repairs));
    if let Some(s) = &scored {
        insert_scores(&mut out, s, true);
        // Errors far beyond the filter's own sigmas. Whose fault it is
        // the innovations tell: a filter whose aiding innovations were
        // bad too (many rows gated) is wrong itself (or its inputs are);
        // with innovations in line, the truth does not describe this run.
        if !s.nees_mean.is_finite() {
            out.warnings.push(crate::nees_not_a_number("truth.csv"));
        } else if s.nees_mean > NEES_WARN_FACTOR * NAV_NEES_DOF {
            let (gated, applied) = run.health.iter().fold((0u64, 0u64), |(g, a), (_, h)| {
                (g + h.gated, a + h.accepted + h.gated)
            });
            let gated_share = if applied > 0 {
                gated as f64 / applied as f64
            } else {
                0.0
            };
            let (file, cause) = if gated_share > MAX_GATED_SHARE {
                (
                    None,
                    format!(
                        "the aiding innovations were bad too ({:.0} % of {applied} aiding rows \
                         gated): the filter or its inputs (units, frames, noise sections of \
                         meta.toml) are wrong, more likely than truth.csv",
                        100.0 * gated_share
                    ),
                )
            } else {
                (
                    Some("truth.csv"),
                    format!(
                        "the aiding innovations were in line ({:.1} % of {applied} aiding rows \
                         gated): a sign, unit, convention or clock of truth.csv?",
                        100.0 * gated_share
                    ),
                )
            };
            let message = format!(
                "mean NEES {:.1} over the {NAV_NEES_DOF} navigation states against truth.csv, \
                 more than {NEES_WARN_FACTOR} times its expectation: the errors are far beyond \
                 the filter's sigmas; {cause}",
                s.nees_mean
            );
            // Key `nees`: the replay weighs it against the preflight's
            // doubts about the inputs (`preflight::weigh_nees`).
            out.warnings.push(Warning {
                kind: WarningKind::Suspicious,
                file: file.map(String::from),
                line: None,
                key: Some(NEES_KEY.into()),
                message,
            });
        }
    }
    if let Some(count) = smoothed_estimates {
        let mut object: Map<String, Value> = match &smoothed {
            Some(s) => ERROR_KEYS
                .iter()
                .zip(error_values(s))
                .map(|(k, v)| ((*k).to_string(), Value::from(v)))
                .collect(),
            None => {
                out.warnings.push(crate::model_note(
                    "the log has no truth.csv: the smoothed run is not scored \
                     (with --out, smoothed.csv holds it)",
                ));
                Map::new()
            }
        };
        object.insert("estimates".into(), Value::from(count));
        out.metrics.insert("smoothed".into(), Value::Object(object));
    }
    out.metrics
        .insert("health".into(), run.health_counts().json());
    out.metrics
        .insert("innovations".into(), innovations_json(&run.innovations));
    out.warnings
        .extend(run.innovations.iter().filter_map(|s| s.warning()));
    out.innovations = run.innovations.clone();
    out.metrics
        .insert("recoveries".into(), recoveries_json(&run.recoveries));
    let last = run.final_filter.nominal().ins.state;
    let e = last.euler();
    out.metrics.insert(
        "final".into(),
        json!({
            "lat": last.lat, "lon": last.lon, "depth": last.depth(),
            "vn": last.v_n.x, "ve": last.v_n.y, "vd": last.v_n.z,
            "roll": e.roll.to_degrees(), "pitch": e.pitch.to_degrees(), "yaw": e.yaw.to_degrees(),
        }),
    );
    // The states the nominal solution does not keep (a user block's own:
    // a water current, a scale factor): the filter's final estimate and
    // sigma of each, by declared name.
    let absorbed = run.final_filter.nominal().layout().absorbed::<N>();
    let x = run.final_filter.ekf().state();
    let p = run.final_filter.covariance();
    let own: Map<String, Value> = (0..N)
        .filter(|&i| !absorbed[i])
        .map(|i| {
            (
                V::STATE_NAMES[i].to_string(),
                json!({"value": x[i], "sigma": p[(i, i)].max(0.0).sqrt()}),
            )
        })
        .collect();
    if !own.is_empty() {
        out.metrics.insert("own_states".into(), Value::Object(own));
    }
    // The biases and the calibrations against their priors
    // (docs/trust.md, "A bias beyond its prior").
    super::constant_states::report(&run.bias_states, &mut out.metrics, &mut out.warnings);
    if let Some(m) = &run.dvl_mounting {
        out.metrics.insert("dvl_calibration".into(), m.json());
        out.warnings
            .extend(m.checks().iter().filter_map(ConstantState::warning));
        out.warnings.extend(m.sigma_warning(&run.innovations));
    }
    for m in &run.fix_mountings {
        out.metrics
            .insert(format!("{}_calibration", m.sensor), m.json());
        out.warnings
            .extend(m.checks().iter().filter_map(ConstantState::warning));
    }
    if let Some(o) = &run.observability {
        let (json, unlearned) = crate::observability::json(o, &V::STATE_NAMES, |i, name| {
            let navigation = ["position_error", "velocity_error", "attitude_error"]
                .iter()
                .any(|n| name.starts_with(n));
            match (navigation, absorbed[i]) {
                (true, _) => None,
                (false, true) => Some(""),
                (false, false) => Some(" (a state of the vehicle's own block)"),
            }
        });
        out.metrics.insert("observability".into(), json);
        out.warnings.extend(unlearned);
    }
    if let (true, true, Some(s)) = (tables, options.keep_series, scored) {
        out.tables.push(s.table);
        if let Some(sm) = smoothed {
            out.tables.push(sm.table);
        }
    }
    if !out.warnings.is_empty() {
        let list = out
            .warnings
            .iter()
            .map(|w| Value::from(w.message.as_str()))
            .collect();
        out.metrics.insert("warnings".into(), Value::Array(list));
    }
    Ok(out)
}

/// The warning for a truth that seems to describe another point of the
/// vehicle than the IMU (docs/log-format.md, "truth.csv").
/// The scores of `s` into `out`: the error keys (and the NEES keys when
/// `with_nees`: a run with a covariance), and a partial scoring and a
/// reference point other than the IMU as warnings.
pub(crate) fn insert_scores(out: &mut ReplayOutput, s: &Scored, with_nees: bool) {
    let nees = [
        ("nees_mean", s.nees_mean),
        ("nees_position_mean", s.nees_position_mean),
    ];
    let errors = [
        ("horizontal_error_final_m", s.horizontal_error_final_m),
        ("horizontal_error_rms_m", s.horizontal_error_rms_m),
        ("depth_error_rms_m", s.depth_error_rms_m),
        ("scored_seconds", s.scored_seconds),
    ];
    let keys = errors
        .into_iter()
        .chain(nees.into_iter().filter(|_| with_nees));
    for (k, v) in keys {
        out.metrics.insert(k.into(), Value::from(v));
    }
    out.warnings.extend(
        s.partial
            .iter()
            .map(|p| Warning::about(WarningKind::PartialScoring, "truth.csv", p.clone())),
    );
    if let Some(point) = &s.reference_point {
        out.warnings.push(reference_point_warning(point));
    }
}

fn reference_point_warning(point: &super::reference_point_fit::FittedPoint) -> Warning {
    let component = |k: usize| {
        let (v, s) = (point.arm[k], point.sigma[k]);
        if s.is_finite() {
            format!("{v:.2} +- {s:.2}")
        } else {
            "(not shown by the motion)".to_string()
        }
    };
    let (x, y, z) = (component(0), component(1), component(2));
    Warning::about(
        WarningKind::Suspicious,
        "truth.csv",
        format!(
            "its velocities in turns differ from the estimate's as a point {x}, {y}, {z} m \
             (forward, right, down) from the IMU would \
             (fitted over {} rows): it seems to describe that point, not the IMU the filter \
             estimates, and the scores then carry the arm's turning as error. Declare \
             `[files.truth] lever_arm` (added to any arm declared there), and `[initial] \
             lever_arm` if the initial position was copied from it",
            point.rows
        ),
    )
    .with_key("files.truth.lever_arm")
}
