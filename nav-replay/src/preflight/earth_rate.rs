//! The Earth's rate in the gyro at the start: any gyro that is not spinning
//! measures at least the Earth's rotation (7.29e-5 rad/s) plus its bias. A
//! mean rate well under it, measured more finely than it, is a file whose
//! rates were scaled down: rad/s values declared as deg/s (57.3 times too
//! small after the conversion).

use nav_runtime::log::{ImuRow, LogMapping, Row, Warning, WarningKind};

use super::{declared, Report};

/// The Earth's rotation rate, rad/s.
const EARTH_RATE: f64 = 7.292_115e-5;

/// A mean rate under this fraction of [`EARTH_RATE`] (beyond three standard
/// errors) does not hold the Earth's rate.
const FRACTION: f64 = 0.25;

/// Ratios of the mean rate to the Earth's rate plus the gyro bias that a
/// deg/s file gives (57.3 times).
const DEGREE_BAND: (f64, f64) = (20.0, 200.0);

/// Fewest rows over which the mean is judged.
const MIN_ROWS: usize = 50;

/// Sums of the gyro axes and their squares over the IMU rows of the first
/// `settle_seconds`.
#[derive(Debug, Default)]
pub(super) struct Fold {
    first_t: Option<f64>,
    sum: [f64; 3],
    squares: [f64; 3],
    n: usize,
    line: Option<u64>,
}

impl Fold {
    pub(super) fn imu(&mut self, settle_seconds: f64, line: Option<u64>, r: &ImuRow) {
        let t0 = *self.first_t.get_or_insert(r.t);
        if self.line.is_none() {
            self.line = line;
        }
        if r.t >= t0 + settle_seconds {
            return;
        }
        for (k, w) in [r.gx, r.gy, r.gz].into_iter().enumerate() {
            self.sum[k] += w;
            self.squares[k] += w * w;
        }
        self.n += 1;
    }

    /// The mean gyro vector over the window, its magnitude and standard
    /// error: under [`FRACTION`] of the Earth's rate by more than three
    /// standard errors is an error when `[files.imu] units` converted the
    /// rates (the declaration), a warning otherwise (rates with the Earth's
    /// rate removed, or scaled down). A gyro that reads exactly constant
    /// (a synthetic log without noise) is not judged.
    ///
    /// With `[sensors.imu] gyro_bias_sigma` (`bias`, rad/s): a mean rate
    /// [`DEGREE_BAND`] times the Earth's rate plus three bias sigmas is a
    /// warning (rates in deg/s, or turning at the start).
    pub(super) fn finish(&self, mapping: &LogMapping, bias: Option<f64>, report: &mut Report) {
        if self.n < MIN_ROWS {
            return;
        }
        let n = self.n as f64;
        let mean = self.sum.map(|s| s / n);
        let variance: f64 = (0..3)
            .map(|k| (self.squares[k] / n - mean[k] * mean[k]).max(0.0))
            .sum();
        if variance == 0.0 {
            return;
        }
        let magnitude = mean.iter().map(|m| m * m).sum::<f64>().sqrt();
        let standard_error = (variance / (n - 1.0)).sqrt();
        if let Some(bias) = bias {
            let expected = EARTH_RATE + 3.0 * bias;
            let ratio = (magnitude - 3.0 * standard_error) / expected;
            if (DEGREE_BAND.0..=DEGREE_BAND.1).contains(&ratio) {
                let mut w = Warning::about(
                    WarningKind::Suspicious,
                    <ImuRow as Row>::FILE,
                    format!(
                        "mean |omega| over the first {} rows is {magnitude:.2e} rad/s, {ratio:.0} \
                         times the Earth's rate plus three [sensors.imu] gyro_bias_sigma: {} (or \
                         turning at the start)",
                        self.n,
                        declared::scale_cause(mapping, "imu", "gx", "rad/s", "deg/s", true)
                    ),
                )
                .with_key("gx,gy,gz");
                if let Some(line) = self.line {
                    w = w.at_line(line);
                }
                report.warn(w);
                return;
            }
        }
        if magnitude + 3.0 * standard_error >= FRACTION * EARTH_RATE {
            return;
        }
        let declared = declared::unit(mapping, "imu", "gx").filter(|(_, u)| u != "rad/s");
        let cause = match &declared {
            Some(_) => declared::scale_cause(mapping, "imu", "gx", "rad/s", "deg/s", false),
            None => "the Earth's rate removed, or rates scaled down?".to_string(),
        };
        let mut w = Warning::about(
            WarningKind::Suspicious,
            <ImuRow as Row>::FILE,
            format!(
                "mean |omega| over the first {} rows is {magnitude:.2e} rad/s (standard error \
                 {standard_error:.1e}), under a quarter of the Earth's rate ({EARTH_RATE:.2e} \
                 rad/s) that a gyro not spinning measures: {cause}",
                self.n
            ),
        )
        .with_key("gx,gy,gz");
        if let Some(line) = self.line {
            w = w.at_line(line);
        }
        if declared.is_some() {
            report.error(w);
        } else {
            report.warn(w);
        }
    }
}
