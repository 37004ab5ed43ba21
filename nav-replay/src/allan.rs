//! `allan`: the IMU noise of a static recording in a log directory
//! (docs/allan.md). The samples of `imu.csv` (or of a stretch of it) go to
//! [`nav_runtime::calibration::allan::analyse`]; the result is a JSON
//! report, a `[sensors.imu]` section for `meta.toml`, and plots of the six
//! curves with their fitted slopes.

use std::path::Path;

use nav_runtime::calibration::allan::{
    analyse, sampling_period, AllanReport, AxisReport, Reading, SensorKind, Term,
};
use nav_runtime::log::LogFiles;
use serde_json::{json, Map, Value};

use crate::output::plot::{self, Line};
use crate::RunError;

/// The stretch of `imu.csv` analysed, s in the log's time base (both
/// ends included; `None`: from the first or to the last row).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Stretch {
    /// First time analysed, s.
    pub from_s: Option<f64>,
    /// Last time analysed, s.
    pub to_s: Option<f64>,
}

/// The Allan analysis of the IMU rows of `files` within `stretch`.
///
/// # Errors
/// The log's errors; a stretch that is empty or reversed; the analysis's
/// refusals ([`nav_runtime::calibration::allan::AllanError`]: too short,
/// not evenly sampled, not static), each naming the row.
pub fn analyse_log(files: &LogFiles, stretch: Stretch) -> Result<AllanReport, RunError> {
    for (flag, bound) in [("--from", stretch.from_s), ("--to", stretch.to_s)] {
        if let Some(v) = bound.filter(|v| !v.is_finite()) {
            return Err(RunError::Invalid(format!(
                "{flag} {v}: expected a finite time, s"
            )));
        }
    }
    if let (Some(a), Some(b)) = (stretch.from_s, stretch.to_s) {
        if a.partial_cmp(&b) != Some(std::cmp::Ordering::Less) {
            return Err(RunError::Invalid(format!(
                "--from {a} --to {b}: expected a stretch with from before to"
            )));
        }
    }
    let mut rows = files.imu()?;
    let (mut times, mut samples) = (Vec::new(), Vec::new());
    while let Some((_, r)) = rows.next_row()? {
        if stretch.from_s.is_some_and(|a| r.t < a) {
            continue;
        }
        if stretch.to_s.is_some_and(|b| r.t > b) {
            break;
        }
        times.push(r.t);
        samples.push([r.gx, r.gy, r.gz, r.ax, r.ay, r.az]);
    }
    if samples.is_empty() {
        return Err(RunError::Invalid(
            "imu.csv: no row in the stretch analysed (--from, --to)".into(),
        ));
    }
    let at_file =
        |e: nav_runtime::calibration::allan::AllanError| RunError::Invalid(format!("imu.csv: {e}"));
    let period = sampling_period(&times).map_err(at_file)?;
    analyse(&samples, period).map_err(at_file)
}

/// One coefficient as JSON: `{"value", "relative_error", "tau_range_s"}`,
/// or `{"not_reached": why}`.
fn reading_json(r: &Reading) -> Value {
    match r {
        Reading::Found(c) => json!({
            "value": c.value,
            "relative_error": c.relative_error,
            "tau_range_s": [c.tau_range_s.0, c.tau_range_s.1],
        }),
        Reading::NotReached(why) => json!({ "not_reached": why }),
    }
}

fn axis_json(a: &AxisReport) -> Value {
    let units = a.kind.units();
    let (white, random_walk) = match a.kind {
        SensorKind::Gyro => ("angle_random_walk", "rate_random_walk"),
        SensorKind::Accelerometer => ("velocity_random_walk", "acceleration_random_walk"),
    };
    let mut m = Map::new();
    m.insert("mean".into(), Value::from(a.mean));
    m.insert(white.into(), reading_json(&a.white));
    m.insert("bias_instability".into(), reading_json(&a.bias_instability));
    m.insert(random_walk.into(), reading_json(&a.random_walk));
    m.insert(
        "units".into(),
        json!({ "samples": units[0], white: units[1], "bias_instability": units[2], random_walk: units[3] }),
    );
    m.insert(
        "curve".into(),
        Value::Array(
            a.curve
                .iter()
                .map(|p| json!([p.tau_s, p.deviation, p.relative_error]))
                .collect(),
        ),
    );
    Value::Object(m)
}

/// The JSON of a report: `period_s`, `samples`, `axes` (per column `gx` ...
/// `az`: mean, the three coefficients, their units and the curve as `[tau
/// s, deviation, relative error]` points), `imu_section` (the `meta.toml`
/// text) and `warnings`.
pub fn report_json(report: &AllanReport) -> Value {
    let axes: Map<String, Value> = report
        .axes
        .iter()
        .map(|a| (a.name.to_string(), axis_json(a)))
        .collect();
    json!({
        "period_s": report.period_s,
        "samples": report.samples,
        "span_s": report.period_s * report.samples as f64,
        "axes": axes,
        "imu_section": report.imu_section(),
        "warnings": report.warnings.iter().map(|w| w.to_string()).collect::<Vec<_>>(),
    })
}

/// `allan-gyro.svg` and `allan-accel.svg` in `dir`: log10 of the Allan
/// deviation against log10 of the cluster time, each axis with the lines of
/// the terms it reached.
///
/// # Errors
/// [`RunError::Plot`] naming the file.
pub fn write_plots(report: &AllanReport, dir: &Path) -> Result<(), RunError> {
    for (kind, file, what) in [
        (SensorKind::Gyro, "allan-gyro.svg", "gyro, rad/s"),
        (
            SensorKind::Accelerometer,
            "allan-accel.svg",
            "accelerometer, m/s^2",
        ),
    ] {
        let mut series: Vec<(String, Vec<f64>, Vec<f64>)> = Vec::new();
        for a in report.axes.iter().filter(|a| a.kind == kind) {
            let (x, y) = a
                .curve
                .iter()
                .map(|p| (p.tau_s.log10(), p.deviation.log10()))
                .unzip();
            series.push((a.name.to_string(), x, y));
            for (term, label) in [
                (Term::White, "white"),
                (Term::BiasInstability, "bias instability"),
                (Term::RandomWalk, "random walk"),
            ] {
                if let Some([(t0, s0), (t1, s1)]) = a.fit_line(term) {
                    series.push((
                        format!("{} {label}", a.name),
                        vec![t0.log10(), t1.log10()],
                        vec![s0.log10(), s1.log10()],
                    ));
                }
            }
        }
        let lines: Vec<Line<'_>> = series
            .iter()
            .map(|(label, x, y)| Line { label, x, y })
            .collect();
        plot::lines(
            &dir.join(file),
            &format!("Allan deviation, {what}, with the fitted terms"),
            "log10 cluster time [s]",
            "log10 Allan deviation",
            &lines,
        )?;
    }
    Ok(())
}
