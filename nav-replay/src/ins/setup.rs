//! The INS replay set up from a log directory: the log's `meta.toml` and
//! files become a [`Navigator`] of the vehicle (initial state, IMU and one
//! settings entry per sensor), and the log's rows are pushed into it in
//! delivery order (late USBL fixes by their acoustic travel time, applied at
//! their measurement time through the navigator's history).
//!
//! **Sensor-error states.** The model writes each sensor error as the residual
//! error left in the corrected sensor output: `f~ - nabla^ = f + nabla + w`,
//! `h_meas - b^ = h + b_depth + v`, ... (error state = true bias minus the
//! running correction). Feedback therefore *adds* the estimated sensor errors
//! to the running corrections, and subtracts the navigation errors (INS minus
//! true) from the strapdown solution ([`InsNominal`]'s `inject`).

use nav_runtime::earth::{meridian_radius, Geodetic};
use nav_runtime::gate::Gate;
use nav_runtime::imu::ImuSpec;
use nav_runtime::log::{
    BaroRow, DepthRow, DvlRow, EventStream, GnssRow, HeadingRow, ImuRow, LogDir, LogSource,
    LogTable, MagRow, Meta, Prefetched, Row, SensorNoise, StreamedRow, UsblRow, Warning,
};
use nav_runtime::nalgebra::{Matrix3, Vector3};
use nav_runtime::sensors::ErrorSpec;
use nav_runtime::stuck::StuckDetector;

use nav_ins::lockout::LockoutOptions;

use super::aiding::Handles;
pub use super::replay_loop::{replay_vehicle, run_vehicle};
use crate::innovations::SensorInnovations;
use crate::RunError;
use nav_ins::RunHealth;
pub use nav_ins::{
    depth_measurement, dvl_measurement, heading_measurement, usbl_measurement, CompassForm,
    Estimate, ImuSample, InsFilter, InsNominal, SensorHealth,
};
use nav_ins::{
    BaroReading, Bounds, Builder, DepthReading, DvlReading, GnssFix, HeadingReading, ImuSettings,
    InitialSigma, InitialState, InsVehicle, MagReading, Navigator, NavigatorError,
    NavigatorOptions, SensorSettings, UsblFix, SENSORS, SENSOR_NAMES,
};

/// GNSS position noise without `[sensors.gnss]`, m (PX4's `EKF2_GPS_P_NOISE`).
pub const GNSS_NOISE_DEFAULT: f64 = 0.5;
/// Barometer noise without `[sensors.baro]`, m (PX4's `EKF2_BARO_NOISE`).
pub const BARO_NOISE_DEFAULT: f64 = 3.5;
/// Barometer bias random walk, m/s^0.5.
pub const BARO_BIAS_WALK: f64 = 0.05;
/// Magnetometer noise without `[sensors.mag]`, gauss (PX4's `EKF2_MAG_NOISE`).
pub const MAG_NOISE_DEFAULT: f64 = 0.05;
/// USBL array misalignment 1-sigma per axis without a `[sensors.usbl]`
/// bias sigma, rad: 0.5 deg, an uncalibrated mounting.
pub const USBL_MISALIGNMENT_SIGMA_DEFAULT: f64 = 0.008_726_646_259_971_648;

/// When a USBL fix reaches the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UsblDelivery {
    /// A travel time (slant range / [`super::aiding::SOUND_SPEED`]) after its measurement time,
    /// as on a real ship; the scheduler applies it at the measurement time.
    #[default]
    Acoustic,
    /// At its measurement time (for comparisons).
    OnTime,
}

/// Filter settings not in the log.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FilterOptions {
    /// Compass residual.
    pub compass: CompassForm,
    /// USBL delivery.
    pub usbl_delivery: UsblDelivery,
    /// Innovation-gate probability for every sensor (`None`: no gating).
    pub gate_probability: Option<f64>,
    /// Gate lock-out release: the rule and the per-sensor plausibility
    /// bounds ([`nav_ins::lockout`]; `None`: a refused sensor stays refused).
    pub lockout_release: Option<LockoutOptions>,
    /// Use these sensors if present in the log.
    pub use_dvl: bool,
    /// Use the depth meter.
    pub use_depth: bool,
    /// Use the compass.
    pub use_compass: bool,
    /// Use the USBL.
    pub use_usbl: bool,
    /// Use the GNSS fixes.
    pub use_gnss: bool,
    /// Use the barometer.
    pub use_baro: bool,
    /// Use the magnetometer.
    pub use_mag: bool,
    /// Extra delivery delay of the DVL, depth and compass measurements
    /// (fault injection; zero in normal runs).
    pub delivery: Delivery,
    /// False-alarm probability of the frozen-value (stuck sensor) check of
    /// every aiding sensor ([`nav_runtime::stuck`], [`stuck_detector`]);
    /// `None` disables it.
    pub stuck_false_alarm: Option<f64>,
    /// Physical bounds of the estimate: outside them the run stops with an
    /// error naming the input.
    pub bounds: Bounds,
    /// With `Some(k)`, an IMU interval longer than `k` IMU periods is
    /// propagated in equal steps of at most `k` periods, holding the sample
    /// before the gap, with a warning naming the two lines (`--lenient`);
    /// `None`: one step whatever its length.
    pub max_imu_step: Option<f64>,
    /// Whether a gap propagated in steps ([`Self::max_imu_step`]) is also a
    /// warning of the run (`false` where the preflight has listed it).
    pub gap_warnings: bool,
    /// Record the run and smooth it afterwards (fixed-interval
    /// Rauch-Tung-Striebel smoother, [`nav_runtime::smoother`]): the run then
    /// also has [`InsRun::smoothed`].
    pub smooth: bool,
    /// Record the run and report its observability afterwards
    /// ([`nav_runtime::smoother::observability`]): the run then also has
    /// [`InsRun::observability`].
    pub observability: bool,
}

/// [`FilterOptions::max_imu_step`] of the command-line replays (IMU
/// periods): a gap the preflight lets through (a short one, any with
/// `--lenient`) is propagated in steps of at most this many periods.
pub const LENIENT_IMU_STEP_PERIODS: f64 = 10.0;

/// Most steps a gap is propagated in; a longer gap is an error.
pub const MAX_GAP_STEPS: f64 = 1.0e6;

/// Late delivery of the 2 Hz aiding measurements (DVL, depth, compass): each
/// reaches the filter `delay_s + jitter_s u` after its measurement time, with
/// `u` uniform in [0, 1) drawn per row from `seed`. A jitter larger than the
/// sampling interval reorders the deliveries; the scheduler applies each at its
/// measurement time (rollback and replay).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Delivery {
    /// Fixed delay (s).
    pub delay_s: f64,
    /// Random extra delay, at most this (s).
    pub jitter_s: f64,
    /// Seed of the random delays.
    pub seed: u64,
}

impl Delivery {
    /// Whether measurements arrive late at all.
    pub fn is_late(&self) -> bool {
        self.delay_s > 0.0 || self.jitter_s > 0.0
    }

    /// Delay (s) of row `row` of sensor `sensor` (index in the health order).
    pub fn delay(&self, sensor: usize, row: usize) -> f64 {
        if !self.is_late() {
            return 0.0;
        }
        let mut z = self
            .seed
            .wrapping_add((sensor as u64) << 40)
            .wrapping_add(row as u64)
            .wrapping_mul(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let u = (z >> 11) as f64 / (1u64 << 53) as f64;
        self.delay_s + self.jitter_s * u
    }

    /// Largest delay (s).
    pub fn max_delay(&self) -> f64 {
        self.delay_s + self.jitter_s
    }
}

impl Default for FilterOptions {
    fn default() -> Self {
        Self {
            compass: CompassForm::Exact,
            usbl_delivery: UsblDelivery::Acoustic,
            gate_probability: Some(Gate::DEFAULT_PROBABILITY),
            lockout_release: Some(LockoutOptions::default()),
            use_dvl: true,
            use_depth: true,
            use_compass: true,
            use_usbl: true,
            use_gnss: true,
            use_baro: true,
            use_mag: true,
            delivery: Delivery::default(),
            stuck_false_alarm: Some(StuckDetector::DEFAULT_FALSE_ALARM),
            bounds: Bounds::default(),
            max_imu_step: None,
            gap_warnings: true,
            smooth: false,
            observability: false,
        }
    }
}

/// Defaults when `[initial_sigma]` lacks a key (m, m/s, rad).
pub const DEFAULT_INITIAL_SIGMA: [f64; 4] = [
    1.0,
    0.05,
    8.726_646_259_971_648e-4,
    8.726_646_259_971_648e-3,
];

/// The result of a run of vehicle `V` over a log.
#[derive(Clone, Debug)]
pub struct InsRun<V: InsVehicle<N>, const N: usize> {
    /// Estimates at the requested times (`None` where no IMU sample is near).
    pub estimates: Vec<Option<Estimate>>,
    /// IMU samples processed.
    pub samples: usize,
    /// Time of the first and the last IMU sample used (s).
    pub imu_span: (f64, f64),
    /// Per-sensor health: depth, dvl, heading, usbl, then gnss, baro and
    /// mag when the vehicle has that sensor or the log has its file.
    pub health: Vec<(&'static str, SensorHealth)>,
    /// Each aiding sensor's innovations, in the order of `health`.
    pub innovations: Vec<SensorInnovations>,
    /// Magnetic declination used for the magnetometer (rad, east positive),
    /// and the samples it was averaged over (see
    /// [`nav_ins::heading::mean_declination`]); `(0, 0)` without them.
    pub magnetic_declination: (f64, usize),
    /// Covariance diagonal repairs.
    pub repairs: u64,
    /// Wall time in the filter loop (s).
    pub runtime_s: f64,
    /// Rollbacks for late measurements.
    pub replays: u64,
    /// The filter at the end (all measurements applied).
    pub final_filter: InsFilter<V, N>,
    /// Log sensors with rows that the vehicle has no sensor for (their rows
    /// are counted as skipped).
    pub ignored: Vec<&'static str>,
    /// Rows not used for a reason the output must show (file and line).
    pub warnings: Vec<Warning>,
    /// Recoveries from a lock-out into divergence, in time order
    /// ([`nav_ins::Recovery`]; each is also a warning).
    pub recoveries: Vec<nav_ins::Recovery>,
    /// With [`FilterOptions::smooth`]: the smoothed estimates at the same
    /// times as [`InsRun::estimates`].
    pub smoothed: Option<Vec<Option<Estimate>>>,
    /// With [`FilterOptions::observability`]: what the log taught each state.
    pub observability: Option<nav_runtime::smoother::Observability<N>>,
    /// The DVL mounting at the end of the run, for a vehicle with the DVL
    /// calibration states (`None` for the others; docs/calibration.md).
    pub dvl_mounting: Option<super::calibration::DvlMounting>,
    /// The calibrated mountings (lever arm, clock lag) of the USBL
    /// transponder and the GNSS antenna, for a vehicle that carries their
    /// states.
    pub fix_mountings: Vec<super::calibration::FixMounting>,
    /// The random-constant biases at the end of the run against their
    /// priors ([`super::constant_states`]).
    pub bias_states: Vec<super::constant_states::ConstantState>,
}

impl<V: InsVehicle<N>, const N: usize> InsRun<V, N> {
    /// The run's counts: per sensor, covariance repairs and replays.
    pub fn health_counts(&self) -> RunHealth {
        RunHealth {
            sensors: self
                .health
                .iter()
                .map(|(name, h)| ((*name).to_string(), *h))
                .collect(),
            covariance_repairs: self.repairs,
            replays: Some(self.replays),
            imu_gaps: None,
            lockout_releases: Some(self.final_filter.ekf().counters().updates_released),
        }
    }
}

fn noise_or(n: Option<SensorNoise>, spec: ErrorSpec) -> SensorNoise {
    n.unwrap_or(SensorNoise {
        bias_sigma: match spec.bias {
            nav_runtime::sensors::Draw::Gaussian(s) => s,
            _ => 0.0,
        },
        noise_sigma: spec.noise,
    })
}

/// Initial filter of vehicle `V` (nominal from `[initial]`, covariance from
/// `[initial_sigma]` and the sensor bias sigmas of `[sensors.*]`, Table 1
/// where absent), with its nominal primed by the first IMU sample.
pub fn initial_vehicle_filter<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
) -> Result<InsFilter<V, N>, RunError> {
    log.meta.initial.position_for(V::REPLAY_NAME)?;
    let (facts, _, _) = LogFacts::of(&LogSource::Memory(log), options)?;
    let plan = LogPlan::new(&log.meta, &facts, [0.0; SENSORS], V::INITIAL_SIGMA)?;
    plan.within(&options.bounds)?;
    let (mut builder, _) = plan.builder::<V, N>(options);
    super::calibration::register(&mut builder, &log.meta)?;
    builder.initial_filter(&plan.first).map_err(setup_error)
}

/// Median IMU sampling interval (s) over the first [`PERIOD_INTERVALS`]
/// intervals (0.01 s with fewer than two rows).
pub fn imu_period(log: &LogDir) -> f64 {
    median_period(log.imu.iter().map(|r| r.t))
}

/// `[initial] t` may come at most this many IMU periods before the first
/// IMU row (the initial state is carried to it with the first row's rates).
pub const MAX_EPOCH_LEAD_PERIODS: f64 = 10.0;

/// IMU intervals the median period is taken over: the start of any log, so
/// the period is known before the log is read further.
pub const PERIOD_INTERVALS: usize = 10_000;

/// The median of the first [`PERIOD_INTERVALS`] intervals of the times `t`
/// (0.01 s with fewer than two): the sampling interval, robust to the odd
/// gap or jitter at the start of a log.
pub fn median_period(t: impl Iterator<Item = f64>) -> f64 {
    let t: Vec<f64> = t.take(PERIOD_INTERVALS + 1).collect();
    let mut d: Vec<f64> = t.windows(2).map(|w| w[1] - w[0]).collect();
    if d.is_empty() {
        return 0.01;
    }
    // The middle one in order (no need to order the others).
    let middle = d.len() / 2;
    *d.select_nth_unstable_by(middle, f64::total_cmp).1
}

/// What a run needs to know of its log before it starts, read without
/// holding the log: the first IMU row, the IMU period and each aiding
/// sensor's output resolution.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct LogFacts {
    /// Epoch of the initial estimate (s): `[initial] t`, or the start of the
    /// first IMU interval (the first IMU time minus the period).
    pub(super) epoch: f64,
    /// The first IMU row at or after the epoch: its rates start the
    /// strapdown's rate model.
    pub(super) first: ImuRow,
    /// IMU rows before the epoch (not used).
    pub(super) before_epoch: usize,
    pub(super) period_s: f64,
    /// Of each sensor of [`SENSOR_NAMES`] (USBL and GNSS angles as metres),
    /// 0 when unknown.
    pub(super) resolutions: [f64; SENSORS],
    /// Magnetic declination from the magnetometer samples around the
    /// initial time and the initial attitude (rad), with the samples used.
    pub(super) declination: Option<(f64, usize)>,
    /// The first barometric altitude at or after the first IMU row (m).
    pub(super) first_baro: Option<f64>,
}

impl LogFacts {
    /// Reads the first [`PERIOD_INTERVALS`] IMU rows and (for the stuck
    /// detector) the first [`RESOLUTION_ROWS`] rows of each aiding file.
    /// Also returns `imu.csv` and the aiding files with the rows read here
    /// kept, to be streamed from their start without reading them again.
    pub(super) fn of<'a>(
        source: &LogSource<'a>,
        options: &FilterOptions,
    ) -> Result<(Self, Prefetched<'a, ImuRow>, AidingHeads<'a>), RunError> {
        let mut imu = Prefetched::new(source.imu_rows()?);
        // A log in memory is looked at in place (and streamed from its start
        // again); the first rows of a log on disk are read ahead once and
        // kept in `imu`, to be streamed from there.
        let kept: Vec<ImuRow>;
        let (rows, in_memory): (&[ImuRow], bool) = match source {
            LogSource::Memory(log) => (&log.imu, true),
            LogSource::Files(_) => {
                for _ in 0..=PERIOD_INTERVALS {
                    if imu.read_ahead()?.is_none() {
                        break;
                    }
                }
                kept = imu.read().copied().collect();
                (&kept, false)
            }
        };
        let row0 = *rows
            .first()
            .ok_or_else(|| RunError::Invalid("imu.csv has no rows".into()))?;
        let t0 = row0.t;
        let period_s = median_period(rows.iter().map(|r| r.t));
        let epoch = source.meta().initial.t.unwrap_or(t0 - period_s);
        if t0 - epoch > MAX_EPOCH_LEAD_PERIODS * period_s {
            return Err(RunError::Invalid(format!(
                "meta.toml: initial.t = {epoch} s is {} s before the first IMU row (imu.csv line 2, t = {t0} s): \
                 the initial state would be carried over {} IMU periods without data (at most {MAX_EPOCH_LEAD_PERIODS})",
                t0 - epoch,
                (t0 - epoch) / period_s
            )));
        }
        // Rows before the epoch are not used: the first at or after it starts
        // the rate model.
        let mut before_epoch = rows.iter().take_while(|r| r.t < epoch).count();
        let mut first = rows.get(before_epoch).copied();
        while first.is_none() {
            let next = if in_memory { None } else { imu.read_ahead()? };
            match next {
                Some(r) if r.t < epoch => before_epoch += 1,
                Some(r) => first = Some(r),
                None => {
                    return Err(RunError::Invalid(format!(
                    "meta.toml: initial.t = {epoch} s is after the last IMU row: nothing to replay"
                )))
                }
            }
        }
        let first = first.unwrap_or(row0);
        let mut heads = AidingHeads::default();
        let resolutions = if options.stuck_false_alarm.is_some() {
            heads = AidingHeads {
                depth: prefetch(source)?,
                dvl: prefetch(source)?,
                heading: prefetch(source)?,
                usbl: prefetch(source)?,
                gnss: prefetch(source)?,
                baro: prefetch(source)?,
                mag: prefetch(source)?,
            };
            let h = &heads;
            let radius = meridian_radius(source.meta().initial.position()?[0]);
            let gnss = [
                radius * resolution(h.gnss.as_ref(), &[1, 2]),
                resolution(h.gnss.as_ref(), &[3]),
            ];
            [
                resolution(h.depth.as_ref(), &[1]),
                resolution(h.dvl.as_ref(), &[1, 2, 3]),
                resolution(h.heading.as_ref(), &[1]),
                radius * resolution(h.usbl.as_ref(), &[1, 2]),
                // The finer of the horizontal and vertical steps.
                match gnss {
                    [0.0, v] | [v, 0.0] => v,
                    [h, v] => h.min(v),
                },
                resolution(h.baro.as_ref(), &[1]),
                resolution(h.mag.as_ref(), &[1, 2, 3]),
            ]
        } else {
            [0.0; SENSORS]
        };
        // The declination: magnetometer samples around the initial time
        // (the first IMU row without `[initial] t`) against the initial attitude.
        let t0 = source.meta().initial.t.unwrap_or(t0);
        let window = nav_ins::heading::DECLINATION_WINDOW_S;
        let mut near = Vec::new();
        if let Some(mut rows) = source.rows::<MagRow>()? {
            while let Some((_, r)) = rows.next_row()? {
                if r.t > t0 + window {
                    break;
                }
                if r.t >= t0 - window {
                    near.push(r);
                }
            }
        }
        let declination = match source.meta().initial.attitude() {
            Ok(attitude) => nav_ins::heading::mean_declination(
                near.iter().map(|m| (m.t, [m.mx, m.my, m.mz])),
                t0,
                attitude,
            ),
            Err(_) => None,
        };
        let mut first_baro = None;
        if let Some(mut rows) = source.rows::<BaroRow>()? {
            while let Some((_, r)) = rows.next_row()? {
                if r.t >= row0.t {
                    first_baro = Some(r.altitude);
                    break;
                }
            }
        }
        Ok((
            LogFacts {
                epoch,
                first,
                before_epoch,
                period_s,
                resolutions,
                declination,
                first_baro,
            },
            imu,
            heads,
        ))
    }
}

/// Aiding rows read at most per file for the output resolution the stuck
/// detector is built with: 10,000 rows (5,000 s of a 2 Hz sensor) show a
/// sensor's output step, and the rows stay bounded in memory until the
/// replay's stream gives them again.
pub const RESOLUTION_ROWS: usize = 10_000;

/// The aiding files read ahead by [`LogFacts::of`] (`None`: absent, or not
/// read ahead).
#[derive(Default)]
pub(super) struct AidingHeads<'a> {
    depth: Option<Prefetched<'a, DepthRow>>,
    dvl: Option<Prefetched<'a, DvlRow>>,
    heading: Option<Prefetched<'a, HeadingRow>>,
    usbl: Option<Prefetched<'a, UsblRow>>,
    gnss: Option<Prefetched<'a, GnssRow>>,
    baro: Option<Prefetched<'a, BaroRow>>,
    mag: Option<Prefetched<'a, MagRow>>,
}

impl<'a> AidingHeads<'a> {
    /// `stream` with each file read ahead continued from its start.
    pub(super) fn continue_in(self, stream: EventStream<'a>) -> EventStream<'a> {
        fn with<'a, R: StreamedRow>(
            stream: EventStream<'a>,
            rows: Option<Prefetched<'a, R>>,
        ) -> EventStream<'a> {
            match rows {
                Some(rows) => stream.with_rows(rows),
                None => stream,
            }
        }
        let s = with(stream, self.depth);
        let s = with(s, self.dvl);
        let s = with(s, self.heading);
        let s = with(s, self.usbl);
        let s = with(s, self.gnss);
        let s = with(s, self.baro);
        with(s, self.mag)
    }
}

/// The first [`RESOLUTION_ROWS`] rows of `R`'s file, read ahead.
fn prefetch<'a, R: LogTable>(
    source: &LogSource<'a>,
) -> Result<Option<Prefetched<'a, R>>, RunError> {
    let Some(rows) = source.rows::<R>()? else {
        return Ok(None);
    };
    let mut rows = Prefetched::new(rows);
    for _ in 0..RESOLUTION_ROWS {
        if rows.read_ahead()?.is_none() {
            break;
        }
    }
    Ok(Some(rows))
}

/// Output resolution of `columns` of the rows read ahead of a file: the
/// smallest non-zero change between consecutive values of any of them (an
/// empty cell passed over; see [`log_resolution`]); 0 if no value changes or
/// there is no file.
fn resolution<R: Row>(rows: Option<&Prefetched<'_, R>>, columns: &[usize]) -> f64 {
    let Some(rows) = rows else {
        return 0.0;
    };
    let mut last: Vec<Option<f64>> = vec![None; R::COLUMNS.len()];
    let mut q = f64::INFINITY;
    for r in rows.read() {
        for (i, cell) in r.to_cells().into_iter().enumerate() {
            let Some(v) = cell.filter(|_| columns.contains(&i)) else {
                continue;
            };
            if let Some(p) = last[i] {
                let d = (v - p).abs();
                if d > 0.0 && d.is_finite() {
                    q = q.min(d);
                }
            }
            last[i] = Some(v);
        }
    }
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

pub(super) fn setup_error(e: NavigatorError) -> RunError {
    RunError::Invalid(e.to_string())
}

/// What the log's `meta.toml` and rows say about the navigator.
pub(super) struct LogPlan {
    pub(super) first: ImuSample,
    pub(super) initial: InitialState,
    pub(super) imu: ImuSettings,
    /// Settings of each sensor of [`SENSOR_NAMES`].
    pub(super) sensors: [SensorSettings; SENSORS],
    pub(super) declination: f64,
    pub(super) transducer: Geodetic,
    /// Mounting keys of `meta.toml` the vehicle's models do not represent.
    pub(super) warnings: Vec<Warning>,
}

impl LogPlan {
    /// `latencies`: of each sensor of [`SENSOR_NAMES`] (s); `defaults`:
    /// the vehicle's initial sigmas where `[initial_sigma]` has no key.
    pub(super) fn new(
        meta: &Meta,
        facts: &LogFacts,
        latencies: [f64; SENSORS],
        defaults: InitialSigma,
    ) -> Result<Self, RunError> {
        let [roll, pitch, yaw] = meta.initial.attitude()?;
        let [lat, lon, depth] = meta.initial.position()?;
        let first = &facts.first;
        let spec = ImuSpec::sdins25();
        let imu = meta.sensors.imu.unwrap_or(nav_runtime::log::ImuNoise {
            gyro_bias_sigma: spec.gyro_bias,
            gyro_noise_sigma: spec.gyro_noise,
            accel_bias_sigma: spec.accel_bias,
            accel_noise_sigma: spec.accel_noise,
        });
        let sig = meta.initial_sigma.unwrap_or_default();
        let d = defaults;
        let initial = InitialState {
            t: facts.epoch,
            position: Geodetic::new(lat, lon, -depth),
            velocity: Vector3::new(meta.initial.vn, meta.initial.ve, meta.initial.vd),
            attitude: nav_runtime::attitude::Euler { roll, pitch, yaw },
            sigma: InitialSigma {
                position: sig.position.unwrap_or(d.position),
                velocity: sig.velocity.unwrap_or(d.velocity),
                level: sig.level.unwrap_or(d.level),
                heading: sig.heading.unwrap_or(d.heading),
            },
        };
        let noise = [
            noise_or(meta.sensors.depth, ErrorSpec::sdins25_depth()),
            noise_or(meta.sensors.dvl, ErrorSpec::sdins25_dvl()),
            noise_or(meta.sensors.heading, ErrorSpec::sdins25_compass()),
            noise_or(meta.sensors.usbl, ErrorSpec::sdins25_usbl()),
            meta.sensors.gnss.unwrap_or(SensorNoise {
                bias_sigma: 0.0,
                noise_sigma: GNSS_NOISE_DEFAULT,
            }),
            meta.sensors.baro.unwrap_or(SensorNoise {
                bias_sigma: 0.0,
                noise_sigma: BARO_NOISE_DEFAULT,
            }),
            meta.sensors.mag.unwrap_or(SensorNoise {
                bias_sigma: 0.0,
                noise_sigma: MAG_NOISE_DEFAULT,
            }),
        ];
        let resolution = facts.resolutions;
        let mut sensors: [SensorSettings; SENSORS] = std::array::from_fn(|i| SensorSettings {
            resolution: resolution[i],
            latency_s: latencies[i],
            ..SensorSettings::new(noise[i].noise_sigma).bias(noise[i].bias_sigma)
        });
        // `[sensors.usbl] misalignment_sigma` sets the array misalignment
        // prior; without the key (older logs) an array with a bias is taken
        // as uncalibrated (Trackpoint II, 0.5 deg), one without as calibrated.
        sensors[3].misalignment_sigma = match meta.sensors.usbl_misalignment_sigma {
            Some(sigma) => sigma,
            None if noise[3].bias_sigma > 0.0 => USBL_MISALIGNMENT_SIGMA_DEFAULT,
            None => 0.0,
        };
        // The barometer bias starts at the first reading minus the initial
        // height, so its prior is one reading's noise unless the log gives one;
        // it walks by `BARO_BIAS_WALK`.
        let baro = &mut sensors[5];
        if baro.bias_sigma <= 0.0 {
            baro.bias_sigma = baro.noise_sigma;
        }
        baro.bias_walk = BARO_BIAS_WALK * BARO_BIAS_WALK;
        baro.initial_bias = facts.first_baro.map_or(0.0, |a| a - initial.position.h);
        // Mountings: the DVL's and the magnetometer's misalignments turn
        // their readings into body axes, the DVL's lever arm corrects its
        // reading by `omega x r`, the USBL transponder's moves the INS
        // position compared with the fix by `C_b^n r`, the barometer port's
        // its height by `(C_b^n r)_D`, the depth sensor's and the GNSS
        // antenna's go to blocks that take one; a compass or magnetometer
        // measures a direction, which a lever arm does not change; what the
        // models do not represent is said, not dropped.
        let mut warnings = Vec::new();
        for (i, name) in SENSOR_NAMES.into_iter().enumerate() {
            let Some(m) = meta.sensors.mounting(name) else {
                continue;
            };
            if i != 2 && i != 6 {
                // The depth slot's block may take it (checked per vehicle);
                // the DVL reading is corrected by `omega x r`, the USBL fix
                // by `C_b^n r`, the barometer's height by `(C_b^n r)_D`; the
                // GNSS block takes the antenna's.
                sensors[i].lever_arm = Vector3::from(m.lever_arm);
            } else if m.lever_arm != [0.0; 3] {
                warnings.push(crate::meta_note(
                    &format!("sensors.{name}.lever_arm"),
                    format!(
                        "meta.toml: sensors.{name}.lever_arm {:?} m has no effect: the {name} measures a direction, the same anywhere on the vehicle",
                        m.lever_arm
                    ),
                ));
            }
            if m.misalignment != [0.0; 3] {
                if i == 1 || i == 6 {
                    let [roll, pitch, yaw] = m.misalignment;
                    sensors[i].mounting =
                        Some(nav_runtime::attitude::Euler { roll, pitch, yaw }.c_bn());
                } else {
                    warnings.push(crate::meta_note(
                        &format!("sensors.{name}.misalignment"),
                        format!(
                            "meta.toml: sensors.{name}.misalignment {:?} rad is not modelled by this replay: ignored",
                            m.misalignment
                        ),
                    ));
                }
            }
        }
        let transducer = meta.usbl.map_or(Geodetic::new(lat, lon, 0.0), |u| {
            Geodetic::new(u.lat, u.lon, -u.depth)
        });
        Ok(Self {
            warnings,
            first: ImuSample {
                gyro: Vector3::new(first.gx, first.gy, first.gz),
                accel: Vector3::new(first.ax, first.ay, first.az),
            },
            initial,
            imu: ImuSettings {
                period_s: facts.period_s,
                gyro_bias_sigma: imu.gyro_bias_sigma,
                gyro_noise_sigma: imu.gyro_noise_sigma,
                accel_bias_sigma: imu.accel_bias_sigma,
                accel_noise_sigma: imu.accel_noise_sigma,
            },
            sensors,
            transducer,
            declination: facts.declination.map_or(0.0, |d| d.0),
        })
    }

    /// An error naming the `[initial]` key when the initial state is
    /// already outside `bounds`: the run would stop at its first sample
    /// with a divergence blamed on the noise settings.
    pub(super) fn within(&self, bounds: &Bounds) -> Result<(), RunError> {
        let v = self.initial.velocity;
        let speed = v.norm();
        if speed > bounds.max_speed_mps {
            let key = ["vn", "ve", "vd"][v.iamax()];
            return Err(nav_runtime::log::LogError::Meta {
                key: format!("initial.{key}"),
                line: None,
                problem: format!(
                    "the initial speed |(vn, ve, vd)| = {speed} m/s exceeds the {} m/s of a physical estimate (FilterOptions::bounds): the run would stop at its first sample",
                    bounds.max_speed_mps
                ),
            }
            .into());
        }
        Ok(())
    }

    /// The builder with every sensor `V` has, and their handles.
    pub(super) fn builder<V: InsVehicle<N>, const N: usize>(
        &self,
        options: &FilterOptions,
    ) -> (Builder<V, N>, Handles) {
        let mut b = Navigator::<V, N>::builder(self.initial, self.imu)
            .options(NavigatorOptions {
                compass: options.compass,
                gate_probability: options.gate_probability,
                lockout_release: options.lockout_release,
                stuck_false_alarm: options.stuck_false_alarm,
                bounds: options.bounds,
                smooth: options.smooth || options.observability,
                sensor_information: options.observability,
            })
            .usbl_transducer(self.transducer)
            .magnetic_declination(self.declination);
        // A sensor the vehicle lacks is not added (its handle is `None`).
        let handles = Handles {
            depth: b.sensor::<DepthReading>(self.sensors[0]).ok(),
            dvl: b.sensor::<DvlReading>(self.sensors[1]).ok(),
            heading: b.sensor::<HeadingReading>(self.sensors[2]).ok(),
            usbl: b.sensor::<UsblFix>(self.sensors[3]).ok(),
            gnss: b.sensor::<GnssFix>(self.sensors[4]).ok(),
            baro: b.sensor::<BaroReading>(self.sensors[5]).ok(),
            mag: b.sensor::<MagReading>(self.sensors[6]).ok(),
        };
        (b, handles)
    }
}

/// Output resolution of a sensor in a log: the smallest non-zero change
/// between consecutive values of any component (a multiple of the
/// quantization step, so never finer than it); 0 if no value changes.
pub fn log_resolution<'a>(values: impl Iterator<Item = &'a [f64]>) -> f64 {
    let mut previous: Option<&[f64]> = None;
    let mut q = f64::INFINITY;
    for v in values {
        if let Some(p) = previous {
            for (a, b) in p.iter().zip(v) {
                let d = (a - b).abs();
                if d > 0.0 && d.is_finite() {
                    q = q.min(d);
                }
            }
        }
        previous = Some(v);
    }
    if q.is_finite() {
        q
    } else {
        0.0
    }
}

/// The frozen-value detector of a sensor with per-sample noise `noise_sigma`
/// and log resolution `resolution` (same units) at false-alarm probability
/// `false_alarm`: see [`StuckDetector::for_sensor`]. With full-precision logs
/// (simulation) this is [`StuckDetector::MIN_REPEATS`] identical samples.
pub fn stuck_detector(noise_sigma: f64, resolution: f64, false_alarm: f64) -> StuckDetector {
    StuckDetector::for_sensor(noise_sigma, resolution, false_alarm)
}

/// `C_b^n` from Euler angles (rad).
pub fn c_bn(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    nav_runtime::attitude::Euler { roll, pitch, yaw }.c_bn()
}
