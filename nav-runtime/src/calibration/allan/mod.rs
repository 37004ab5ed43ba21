//! IMU noise from a static recording by the overlapping Allan deviation
//! (docs/allan.md).
//!
//! [`analyse`] takes the samples of `imu.csv` (`gx, gy, gz` in rad/s, `ax,
//! ay, az` in m/s^2, evenly spaced by `period_s`, which [`sampling_period`]
//! finds from the time column and checks) and returns, per axis, the
//! Allan deviation curve with its confidence and the three coefficients read
//! from its slopes: white noise of the rate (angle / velocity random walk,
//! slope -1/2 read at 1 s), bias instability (the flat bottom / 0.664) and
//! rate random walk (slope +1/2 read at 3 s), each only where the curve
//! shows that slope ([`Reading::NotReached`] otherwise).
//! [`AllanReport::imu_section`] writes them as the `[sensors.imu]` section
//! of a `meta.toml` (per-sample sigmas at the file's rate,
//! docs/log-format.md). A record that is not static (the sensor turned, was
//! tilted or accelerated) is refused; slow drifts are warnings.

mod deviation;
mod imu_section;
mod reading;
mod sampling;
mod stillness;
// The tests simulate an IMU (`simulation`).
#[cfg(all(test, feature = "simulation"))]
mod tests;

pub use deviation::{cluster_sizes, curve, overlapping, phase, AllanPoint, MIN_CLUSTERS};
pub use imu_section::ImuNoiseEstimate;
pub use reading::{
    bias_instability, local_slopes, ramp, random_walk, white, Coefficient, Reading, FLICKER_FLOOR,
    MIN_SPAN, SLOPE_TOLERANCE,
};
pub use sampling::{sampling_period, MAX_STEP};

/// Fewest samples [`analyse`] accepts: about two decades of cluster sizes
/// with at least [`MIN_CLUSTERS`] clusters each.
pub const MIN_SAMPLES: usize = 100;

/// The kind of sensor of an axis, for units.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SensorKind {
    /// Rate gyro: samples in rad/s.
    Gyro,
    /// Accelerometer: specific force in m/s^2.
    Accelerometer,
}

impl SensorKind {
    /// Units of (samples and Allan deviation, white noise, bias instability,
    /// rate random walk).
    pub fn units(self) -> [&'static str; 4] {
        match self {
            SensorKind::Gyro => ["rad/s", "rad/s^(1/2)", "rad/s", "rad/s^(3/2)"],
            SensorKind::Accelerometer => ["m/s^2", "m/s^(3/2)", "m/s^2", "m/s^(5/2)"],
        }
    }
}

/// The six axes in the column order of `imu.csv`.
pub const AXES: [(&str, SensorKind); 6] = [
    ("gx", SensorKind::Gyro),
    ("gy", SensorKind::Gyro),
    ("gz", SensorKind::Gyro),
    ("ax", SensorKind::Accelerometer),
    ("ay", SensorKind::Accelerometer),
    ("az", SensorKind::Accelerometer),
];

/// The analysis of one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct AxisReport {
    /// Column name (`gx` ... `az`).
    pub name: &'static str,
    /// Gyro or accelerometer (units: [`SensorKind::units`]).
    pub kind: SensorKind,
    /// Mean of the samples (the bias plus Earth rate or gravity), unit of
    /// the samples.
    pub mean: f64,
    /// The overlapping Allan deviation, shortest cluster time first.
    pub curve: Vec<AllanPoint>,
    /// Local log-log slope at each point of `curve` ([`local_slopes`]).
    pub slopes: Vec<f64>,
    /// Angle random walk (gyro, rad/s^(1/2)) or velocity random walk
    /// (accelerometer, m/s^(3/2)): `sigma(1 s)` on the slope -1/2.
    pub white: Reading,
    /// Bias instability, unit of the samples: the flat bottom / 0.664.
    pub bias_instability: Reading,
    /// Rate random walk (gyro rad/s^(3/2), accelerometer m/s^(5/2)):
    /// `sigma(3 s)` on the slope +1/2.
    pub random_walk: Reading,
}

/// Which fitted term a plot line shows.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Term {
    /// Slope -1/2: `sigma = N / sqrt(tau)`.
    White,
    /// Flat: `sigma = 0.664 B`.
    BiasInstability,
    /// Slope +1/2: `sigma = K sqrt(tau / 3)`.
    RandomWalk,
}

impl AxisReport {
    /// The fitted line of `term` over the curve's range of cluster times, as
    /// its two end points `(tau s, sigma)`, for a log-log plot of the curve
    /// with its fits; `None` if the term was not reached.
    pub fn fit_line(&self, term: Term) -> Option<[(f64, f64); 2]> {
        let (first, last) = (self.curve.first()?.tau_s, self.curve.last()?.tau_s);
        let at = |tau: f64| -> Option<f64> {
            match term {
                Term::White => self.white.value().map(|n| n / tau.sqrt()),
                Term::BiasInstability => self.bias_instability.value().map(|b| FLICKER_FLOOR * b),
                Term::RandomWalk => self.random_walk.value().map(|k| k * (tau / 3.0).sqrt()),
            }
        };
        Some([(first, at(first)?), (last, at(last)?)])
    }
}

/// A finding that does not stop the analysis but qualifies it.
#[derive(Debug, Clone, PartialEq)]
pub enum AllanWarning {
    /// The mean specific force is not gravity: accelerometer not in m/s^2,
    /// or not at rest.
    GravityMagnitude {
        /// Norm of the mean of (ax, ay, az), m/s^2.
        norm: f64,
    },
    /// The curve of an axis climbs at slope +1 over two octaves ([`ramp`]):
    /// more low-frequency content than the noise terms make (rate random
    /// walk is +1/2): a temperature drift or a slow motion. Coefficients
    /// read at longer cluster times are upper bounds.
    Drift {
        /// Axis name.
        axis: &'static str,
        /// Mean local slope over the stretch.
        slope: f64,
        /// Cluster time where the stretch starts, s.
        tau_s: f64,
    },
}

impl core::fmt::Display for AllanWarning {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        match self {
            AllanWarning::GravityMagnitude { norm } => write!(
                f,
                "mean specific force {norm:.3} m/s^2 is not gravity (about 9.81): \
                 accelerometer units not m/s^2, or the sensor was not at rest"
            ),
            AllanWarning::Drift { axis, slope, tau_s } => write!(
                f,
                "{axis}: the Allan deviation climbs at slope {slope:.2} from {tau_s:.4} s \
                 (a rate ramp: temperature drift or slow motion); what is read beyond is an upper bound"
            ),
        }
    }
}

/// Why a record cannot be analysed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AllanError {
    /// The sampling period is not a finite positive number.
    #[error("sampling period {period_s} s: expected a finite period above 0 s")]
    InvalidPeriod {
        /// The period given, s.
        period_s: f64,
    },
    /// Too few samples for any slope.
    #[error("{samples} IMU samples: an Allan analysis needs at least {needed} (record longer, or at a higher rate)")]
    TooShort {
        /// Samples given.
        samples: usize,
        /// [`MIN_SAMPLES`].
        needed: usize,
    },
    /// A NaN or infinite value.
    #[error("sample {sample} (from 1), column {axis}: {value} is not a finite number")]
    NonFinite {
        /// 1-based sample index.
        sample: usize,
        /// Column name.
        axis: &'static str,
        /// The value.
        value: f64,
    },
    /// Time stamps that do not make an evenly sampled record.
    #[error("sample {sample} (from 1), column t: {reason}")]
    Timing {
        /// 1-based sample index.
        sample: usize,
        /// What is wrong.
        reason: String,
    },
    /// The record is not static.
    #[error("not a static recording: {reason}")]
    NotStatic {
        /// What moved, by how much.
        reason: String,
    },
    /// A period longer than any IMU's: the time stamps are in another unit.
    #[error("sampling period {period_s} s, slower than {MAX_PERIOD_S} s: times in milliseconds or microseconds?")]
    SlowSampling {
        /// The period read, s.
        period_s: f64,
    },
    /// A column that reads one value throughout: nothing to analyse, and a
    /// noise of zero would be written.
    #[error("column {axis}: {value} in every sample: a frozen or disconnected sensor")]
    Frozen {
        /// Column name.
        axis: &'static str,
        /// The value it reads.
        value: f64,
    },
    /// A mean no sensor of the kind measures: a unit or scale mistake.
    #[error("column {axis}: mean {mean:.3e} beyond {limit} {unit}: not a physical {what} (wrong unit or scale?)")]
    Unphysical {
        /// Column name.
        axis: &'static str,
        /// Its mean.
        mean: f64,
        /// The largest magnitude accepted.
        limit: f64,
        /// The unit of both.
        unit: &'static str,
        /// `rate` or `specific force`.
        what: &'static str,
    },
}

/// The longest sampling period of an IMU record, s: an IMU samples faster
/// than 1 Hz, so a longer period is a time unit mistake (the replay's
/// preflight applies the same bound).
pub const MAX_PERIOD_S: f64 = 1.0;
/// The largest mean rate accepted, rad/s (2000 deg/s, the range of common
/// gyros; the replay's preflight uses the same).
pub const MAX_MEAN_RATE: f64 = 35.0;
/// The largest mean specific force accepted, m/s^2 (100 g: beyond any
/// static recording).
pub const MAX_MEAN_SPECIFIC_FORCE: f64 = 1000.0;

/// The analysis of a static recording.
#[derive(Debug, Clone, PartialEq)]
pub struct AllanReport {
    /// Sampling period, s.
    pub period_s: f64,
    /// Number of samples.
    pub samples: usize,
    /// The six axes, in [`AXES`] order.
    pub axes: Vec<AxisReport>,
    /// Findings that qualify the figures.
    pub warnings: Vec<AllanWarning>,
}

/// Analyses a static IMU recording: `samples` are rows `[gx, gy, gz, ax,
/// ay, az]` (rad/s, m/s^2) evenly spaced by `period_s` seconds.
///
/// # Errors
/// [`AllanError`]: a period that is not finite and positive, fewer than
/// [`MIN_SAMPLES`] samples, a non-finite value (the first one named), or a
/// record that is not static (docs/allan.md, "Recording").
pub fn analyse(samples: &[[f64; 6]], period_s: f64) -> Result<AllanReport, AllanError> {
    if !(period_s.is_finite() && period_s > 0.0) {
        return Err(AllanError::InvalidPeriod { period_s });
    }
    if samples.len() < MIN_SAMPLES {
        return Err(AllanError::TooShort {
            samples: samples.len(),
            needed: MIN_SAMPLES,
        });
    }
    for (k, row) in samples.iter().enumerate() {
        if let Some(j) = row.iter().position(|v| !v.is_finite()) {
            return Err(AllanError::NonFinite {
                sample: k + 1,
                axis: AXES[j].0,
                value: row[j],
            });
        }
    }
    if period_s > MAX_PERIOD_S {
        return Err(AllanError::SlowSampling { period_s });
    }
    let mean = |j: usize| samples.iter().map(|r| r[j]).sum::<f64>() / samples.len() as f64;
    for (j, &(axis, kind)) in AXES.iter().enumerate() {
        let value = samples[0][j];
        if samples.iter().all(|r| r[j] == value) {
            return Err(AllanError::Frozen { axis, value });
        }
        let (limit, unit, what) = match kind {
            SensorKind::Gyro => (MAX_MEAN_RATE, "rad/s", "rate"),
            SensorKind::Accelerometer => (MAX_MEAN_SPECIFIC_FORCE, "m/s^2", "specific force"),
        };
        let m = mean(j);
        if m.abs() > limit {
            return Err(AllanError::Unphysical {
                axis,
                mean: m,
                limit,
                unit,
                what,
            });
        }
    }
    stillness::check(samples)?;
    let mut warnings = Vec::new();
    let norm = (mean(3).powi(2) + mean(4).powi(2) + mean(5).powi(2)).sqrt();
    if !(8.8..=10.8).contains(&norm) {
        warnings.push(AllanWarning::GravityMagnitude { norm });
    }
    let axes = AXES
        .iter()
        .enumerate()
        .map(|(j, &(name, kind))| {
            let values: Vec<f64> = samples.iter().map(|r| r[j]).collect();
            let curve = curve(&values, period_s);
            let slopes = local_slopes(&curve);
            if let Some((slope, tau_s)) = ramp(&curve, &slopes) {
                warnings.push(AllanWarning::Drift {
                    axis: name,
                    slope,
                    tau_s,
                });
            }
            AxisReport {
                name,
                kind,
                mean: mean(j),
                white: white(&curve, &slopes),
                bias_instability: bias_instability(&curve, &slopes),
                random_walk: random_walk(&curve, &slopes),
                curve,
                slopes,
            }
        })
        .collect();
    Ok(AllanReport {
        period_s,
        samples: samples.len(),
        axes,
        warnings,
    })
}
