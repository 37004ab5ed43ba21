//! Specific force at the start against normal gravity: accelerometers in g
//! (`|f|` near 1), a scale error, and the sign of `az` (FLU instead of FRD).

use nav_runtime::earth::normal_gravity;
use nav_runtime::log::{ImuRow, LogDir, Row, Warning, WarningKind};

use super::{rows_until, PreflightOptions, Report};

/// Columns named by these findings.
const KEY: &str = "ax,ay,az";

/// Mean specific force over the first `settle_seconds` compared with normal
/// gravity at the initial position: `|f|` in 0.7..1.3 m/s^2 is a g-unit file,
/// outside 0.5..1.5 g an error, outside 0.9..1.1 g a warning; a mean `az` of
/// the sign opposite to the one FRD axes give at the initial roll and pitch is
/// an error (z up).
pub(super) fn check(log: &LogDir, options: &PreflightOptions, report: &mut Report) {
    let Some(first) = log.imu.first() else { return };
    let rows = rows_until(&log.imu, first.t + options.settle_seconds);
    let rows = if rows.is_empty() { &log.imu[..1] } else { rows };
    let n = rows.len() as f64;
    let mean = |f: fn(&ImuRow) -> f64| rows.iter().map(f).sum::<f64>() / n;
    let f = [mean(|r| r.ax), mean(|r| r.ay), mean(|r| r.az)];
    let norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let init = &log.meta.initial;
    let g = normal_gravity(init.lat, -init.depth.clamp(-1e5, 1e5));
    let span = rows.last().map_or(0.0, |r| r.t) - first.t;
    let at = |msg: String| {
        Warning::about(WarningKind::Suspicious, <ImuRow as Row>::FILE, msg)
            .at_line(2)
            .with_key(KEY)
    };
    let ratio = norm / g;
    if (0.7..=1.3).contains(&norm) {
        report.error(at(format!(
            "|f| = {norm:.2} at rest (mean over the first {span:.1} s; normal gravity \
             here is {g:.2} m/s^2): g units? the format is m/s^2"
        )));
        return;
    }
    if !(0.5..=1.5).contains(&ratio) {
        report.error(at(format!(
            "|f| = {norm:.3} m/s^2 (mean over the first {span:.1} s) against normal \
             gravity {g:.3} m/s^2: wrong unit or scale? the format is m/s^2"
        )));
        return;
    }
    if !(0.9..=1.1).contains(&ratio) {
        report.warn(at(format!(
            "|f| = {norm:.3} m/s^2 (mean over the first {span:.1} s) is {:.0} % off \
             normal gravity {g:.3} m/s^2: accelerating at the start, or a scale error",
            (ratio - 1.0) * 100.0
        )));
    }
    let (roll, pitch) = (init.roll.unwrap_or(0.0), init.pitch.unwrap_or(0.0));
    let expected_az = -g * roll.cos() * pitch.cos();
    if expected_az.abs() > 0.5 * g && f[2].abs() > 0.5 * g && f[2].signum() != expected_az.signum()
    {
        report.error(
            Warning::about(
                WarningKind::Suspicious,
                <ImuRow as Row>::FILE,
                format!(
                    "mean az = {:+.2} m/s^2 over the first {span:.1} s where FRD axes give \
                     {expected_az:+.2} at the initial roll and pitch: FLU axes (z up)? the \
                     format is FRD (x forward, y right, z down)",
                    f[2]
                ),
            )
            .at_line(2)
            .with_key("az"),
        );
    }
}
