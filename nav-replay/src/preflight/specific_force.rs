//! Specific force at the start against normal gravity: accelerometers in g
//! (`|f|` near 1), a scale error, and the sign of `az` (FLU instead of FRD).

use nav_runtime::earth::{normal_gravity, G0 as STANDARD_GRAVITY};
use nav_runtime::log::{ImuRow, Meta, Row, Warning, WarningKind};

use super::Report;

/// Columns named by these findings.
const KEY: &str = "ax,ay,az";

/// The largest specific force accepted in any row, m/s^2 (1000 g: beyond
/// any accelerometer's range; the gyro's bound is `gyro_rate::MAX_RATE`).
const MAX_SPECIFIC_FORCE: f64 = 1e4;

/// The sums of `ax, ay, az` over the IMU rows of the first `settle_seconds`
/// (the first row alone when no row is that early).
#[derive(Debug, Default)]
pub(super) struct Fold {
    first: Option<ImuRow>,
    sum: [f64; 3],
    n: usize,
    last_t: f64,
    /// The line of the first row, when known.
    line: Option<u64>,
    /// The largest `|f|` beyond [`MAX_SPECIFIC_FORCE`] (or not finite) and
    /// its line.
    beyond: Option<(Option<u64>, f64)>,
}

impl Fold {
    pub(super) fn imu(&mut self, settle_seconds: f64, line: Option<u64>, r: &ImuRow) {
        if self.first.is_none() {
            self.first = Some(*r);
            self.line = line;
        }
        let norm = (r.ax * r.ax + r.ay * r.ay + r.az * r.az).sqrt();
        if norm > MAX_SPECIFIC_FORCE && self.beyond.is_none_or(|(_, m)| norm > m) {
            self.beyond = Some((line, norm));
        }
        let Some(first) = self.first else { return };
        // Times increase, so the window is a prefix of the rows.
        if r.t < first.t + settle_seconds {
            self.sum[0] += r.ax;
            self.sum[1] += r.ay;
            self.sum[2] += r.az;
            self.n += 1;
            self.last_t = r.t;
        }
    }

    /// Mean specific force over the first `settle_seconds` compared with
    /// normal gravity at the initial position: `|f|` in 0.7..1.3 m/s^2 is a
    /// g-unit file, outside 0.5..1.5 g an error, outside 0.9..1.1 g a
    /// warning; a mean `az` of the sign opposite to the one FRD axes give at
    /// the initial roll and pitch is an error (z up).
    /// A row beyond [`MAX_SPECIFIC_FORCE`] anywhere is an error at its line
    /// (a 1e300 cell made the mean infinite and was blamed on the first
    /// row, or, after the first seconds, went unsaid until the filter's
    /// arithmetic failed).
    pub(super) fn finish(&self, meta: &Meta, report: &mut Report) {
        if let Some((line, norm)) = self.beyond {
            let mut w = Warning::about(
                WarningKind::Suspicious,
                <ImuRow as Row>::FILE,
                format!(
                    "|f| = {norm:.3e} m/s^2: not a physical specific force (beyond \
                     {MAX_SPECIFIC_FORCE:e} m/s^2, 1000 g)"
                ),
            )
            .with_key(KEY);
            if let Some(line) = line {
                w = w.at_line(line);
            }
            report.error(w);
            return;
        }
        let Some(first) = self.first else { return };
        let (sum, rows, last_t) = if self.n == 0 {
            ([first.ax, first.ay, first.az], 1, first.t)
        } else {
            (self.sum, self.n, self.last_t)
        };
        let span = last_t - first.t;
        check(meta, sum, rows, span, self.line.unwrap_or(2), report);
    }
}

fn check(meta: &Meta, sum: [f64; 3], rows: usize, span: f64, line: u64, report: &mut Report) {
    let n = rows as f64;
    let f = [sum[0] / n, sum[1] / n, sum[2] / n];
    let norm = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt();
    let init = &meta.initial;
    // An attitude-only meta.toml (no position): standard gravity.
    let g = match init.position() {
        Ok([lat, _, depth]) => normal_gravity(lat, -depth.clamp(-1e5, 1e5)),
        Err(_) => STANDARD_GRAVITY,
    };
    let at = |msg: String| {
        Warning::about(WarningKind::Suspicious, <ImuRow as Row>::FILE, msg)
            .at_line(line)
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
            .at_line(line)
            .with_key("az"),
        );
    }
}
