//! The SDINS filters run over a log directory: the log's `meta.toml` and
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

use nav_runtime::earth::{meridian_radius, Geodetic, LocalNed};
use nav_runtime::gate::Gate;
use nav_runtime::imu::ImuSpec;
use nav_runtime::log::{LogDir, SensorNoise};
use nav_runtime::nalgebra::{Matrix3, Vector3};
use nav_runtime::sensors::ErrorSpec;
use nav_runtime::smoother::{smooth, EpochFile};
use nav_runtime::stuck::StuckDetector;

use super::lockout::LockoutOptions;
use crate::navigator::vehicle::Layout;

use super::model::Sdins25;
use super::simulation::{DVL_MAX_ALTITUDE, SOUND_SPEED, TRACKPOINT_MISALIGNMENT_SIGMA};
use crate::montecarlo::RunError;
pub use crate::navigator::{
    depth_measurement, dvl_measurement, heading_measurement, usbl_measurement, CompassForm,
    Estimate, ImuSample, InsFilter, InsNominal, SensorHealth,
};
use crate::navigator::{
    Bounds, Builder, DepthReading, DvlReading, HeadingReading, ImuSettings, InitialSigma,
    InitialState, InsVehicle, Navigator, NavigatorError, NavigatorOptions, SensorSettings, UsblFix,
    SENSOR_NAMES,
};

/// Number of error states of SDINS-25.
pub const N: usize = 25;

/// The error-state filter of SDINS-25.
pub type Filter = InsFilter<Sdins25, N>;

/// When a USBL fix reaches the filter.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum UsblDelivery {
    /// A travel time (slant range / [`SOUND_SPEED`]) after its measurement time,
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
    /// bounds ([`super::lockout`]; `None`: a refused sensor stays refused).
    pub lockout_release: Option<LockoutOptions>,
    /// Use these sensors if present in the log.
    pub use_dvl: bool,
    /// Use the depth meter.
    pub use_depth: bool,
    /// Use the compass.
    pub use_compass: bool,
    /// Use the USBL.
    pub use_usbl: bool,
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
    /// Record the run and smooth it afterwards (fixed-interval
    /// Rauch-Tung-Striebel smoother, [`nav_runtime::smoother`]): the run then
    /// also has [`InsRun::smoothed`].
    pub smooth: bool,
}

/// [`FilterOptions::max_imu_step`] of `--lenient` replays (IMU periods).
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
            delivery: Delivery::default(),
            stuck_false_alarm: Some(StuckDetector::DEFAULT_FALSE_ALARM),
            bounds: Bounds::default(),
            max_imu_step: None,
            smooth: false,
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

/// The nominal solution of SDINS-25.
pub type Nominal = InsNominal<Sdins25, N>;

/// The result of a run of vehicle `V` over a log.
#[derive(Clone, Debug)]
pub struct InsRun<V: InsVehicle<N>, const N: usize> {
    /// Estimates at the requested times (`None` where no IMU sample is near).
    pub estimates: Vec<Option<Estimate>>,
    /// IMU samples processed.
    pub samples: usize,
    /// Per-sensor health: depth, dvl, heading, usbl.
    pub health: [(&'static str, SensorHealth); 4],
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
    pub warnings: Vec<String>,
    /// With [`FilterOptions::smooth`]: the smoothed estimates at the same
    /// times as [`InsRun::estimates`].
    pub smoothed: Option<Vec<Option<Estimate>>>,
}

/// The result of an SDINS-25 run over a log.
pub type Sdins25Run = InsRun<Sdins25, N>;

fn noise_or(n: Option<SensorNoise>, spec: ErrorSpec) -> SensorNoise {
    n.unwrap_or(SensorNoise {
        bias_sigma: match spec.bias {
            nav_runtime::sensors::Draw::Gaussian(s) => s,
            _ => 0.0,
        },
        noise_sigma: spec.noise,
    })
}

/// Initial SDINS-25 filter: [`initial_vehicle_filter`] of [`Sdins25`].
pub fn initial_filter(log: &LogDir, options: &FilterOptions) -> Result<Filter, RunError> {
    initial_vehicle_filter::<Sdins25, N>(log, options)
}

/// Initial filter of vehicle `V` (nominal from `[initial]`, covariance from
/// `[initial_sigma]` and the sensor bias sigmas of `[sensors.*]`, Table 1
/// where absent), with its nominal primed by the first IMU sample.
pub fn initial_vehicle_filter<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
) -> Result<InsFilter<V, N>, RunError> {
    let plan = LogPlan::new(log, options, [0.0; 4])?;
    let (builder, _) = plan.builder::<V, N>(options);
    builder.initial_filter(&plan.first).map_err(setup_error)
}

/// Median IMU sampling interval (s).
pub fn imu_period(log: &LogDir) -> f64 {
    let mut d: Vec<f64> = log.imu.windows(2).map(|w| w[1].t - w[0].t).collect();
    if d.is_empty() {
        return 0.01;
    }
    d.sort_by(f64::total_cmp);
    d[d.len() / 2]
}

fn setup_error(e: NavigatorError) -> RunError {
    RunError::Invalid(e.to_string())
}

/// What the log's `meta.toml` and rows say about the navigator.
struct LogPlan {
    first: ImuSample,
    initial: InitialState,
    imu: ImuSettings,
    /// Settings of depth, DVL, compass and USBL.
    sensors: [SensorSettings; 4],
    transducer: Geodetic,
}

impl LogPlan {
    /// `latencies`: of depth, DVL, compass and USBL (s).
    fn new(log: &LogDir, options: &FilterOptions, latencies: [f64; 4]) -> Result<Self, RunError> {
        let meta = &log.meta;
        let [roll, pitch, yaw] = meta.initial.attitude()?;
        let first = log
            .imu
            .first()
            .ok_or_else(|| RunError::Invalid("imu.csv has no rows".into()))?;
        let spec = ImuSpec::sdins25();
        let imu = meta.sensors.imu.unwrap_or(nav_runtime::log::ImuNoise {
            gyro_bias_sigma: spec.gyro_bias,
            gyro_noise_sigma: spec.gyro_noise,
            accel_bias_sigma: spec.accel_bias,
            accel_noise_sigma: spec.accel_noise,
        });
        let sig = meta.initial_sigma.unwrap_or_default();
        let d = InitialSigma::default();
        let initial = InitialState {
            t: first.t,
            position: Geodetic::new(meta.initial.lat, meta.initial.lon, -meta.initial.depth),
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
        ];
        let resolution = if options.stuck_false_alarm.is_some() {
            log_resolutions(log)
        } else {
            [0.0; 4]
        };
        let mut sensors: [SensorSettings; 4] = std::array::from_fn(|i| SensorSettings {
            resolution: resolution[i],
            latency_s: latencies[i],
            ..SensorSettings::new(noise[i].noise_sigma).bias(noise[i].bias_sigma)
        });
        // `[sensors.usbl] misalignment_sigma` sets the array misalignment
        // prior; without the key (older logs) an array with a bias is taken
        // as uncalibrated (Trackpoint II, 0.5 deg), one without as calibrated.
        sensors[3].misalignment_sigma = match meta.sensors.usbl_misalignment_sigma {
            Some(sigma) => sigma,
            None if noise[3].bias_sigma > 0.0 => TRACKPOINT_MISALIGNMENT_SIGMA,
            None => 0.0,
        };
        let transducer = meta.usbl.map_or(
            Geodetic::new(meta.initial.lat, meta.initial.lon, 0.0),
            |u| Geodetic::new(u.lat, u.lon, -u.depth),
        );
        Ok(Self {
            first: ImuSample {
                gyro: Vector3::new(first.gx, first.gy, first.gz),
                accel: Vector3::new(first.ax, first.ay, first.az),
            },
            initial,
            imu: ImuSettings {
                period_s: imu_period(log),
                gyro_bias_sigma: imu.gyro_bias_sigma,
                gyro_noise_sigma: imu.gyro_noise_sigma,
                accel_bias_sigma: imu.accel_bias_sigma,
                accel_noise_sigma: imu.accel_noise_sigma,
            },
            sensors,
            transducer,
        })
    }

    /// The builder with every sensor `V` has, and their handles.
    fn builder<V: InsVehicle<N>, const N: usize>(
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
                smooth: options.smooth,
            })
            .usbl_transducer(self.transducer);
        // A sensor the vehicle lacks is not added (its handle is `None`).
        let handles = Handles {
            depth: b.sensor::<DepthReading>(self.sensors[0]).ok(),
            dvl: b.sensor::<DvlReading>(self.sensors[1]).ok(),
            heading: b.sensor::<HeadingReading>(self.sensors[2]).ok(),
            usbl: b.sensor::<UsblFix>(self.sensors[3]).ok(),
        };
        (b, handles)
    }
}

/// Resolution of each sensor in this log; USBL angles converted to metres.
fn log_resolutions(log: &LogDir) -> [f64; 4] {
    let radius = meridian_radius(log.meta.initial.lat);
    [
        log.depth.as_ref().map_or(0.0, |r| {
            log_resolution(r.iter().map(|x| std::slice::from_ref(&x.depth)))
        }),
        log.dvl.as_ref().map_or(0.0, |r| {
            let v: Vec<[f64; 3]> = r.iter().filter_map(|x| x.velocity()).collect();
            log_resolution(v.iter().map(|x| x.as_slice()))
        }),
        log.heading.as_ref().map_or(0.0, |r| {
            log_resolution(r.iter().map(|x| std::slice::from_ref(&x.heading)))
        }),
        log.usbl.as_ref().map_or(0.0, |r| {
            let v: Vec<[f64; 2]> = r.iter().map(|x| [x.lat, x.lon]).collect();
            radius * log_resolution(v.iter().map(|x| x.as_slice()))
        }),
    ]
}

/// One log row of an aiding sensor: sensor index (in [`SENSOR_NAMES`]
/// order) and row index.
#[derive(Clone, Copy, Debug)]
struct Event {
    delivery: f64,
    time: f64,
    sensor: usize,
    row: usize,
}

/// Where row `row` (0-based, after the header) of `file` is, for messages:
/// its line when the reader skipped none of the file's rows.
fn place(log: &LogDir, file: &str, row: usize) -> String {
    if log.skipped_rows.get(file).copied().unwrap_or(0) == 0 {
        format!("{file} line {}", row + 2)
    } else {
        format!("{file} data row {}", row + 1)
    }
}

/// The rows of each aiding sensor the run uses, with their delivery times,
/// and the health counts of the rows not used.
struct Sources {
    events: Vec<Event>,
    health: [SensorHealth; 4],
    ignored: Vec<&'static str>,
    warnings: Vec<String>,
    /// Largest USBL travel time (s).
    usbl_latency: f64,
}

impl Sources {
    fn new<V: InsVehicle<N>, const N: usize>(
        log: &LogDir,
        options: &FilterOptions,
        transducer: Geodetic,
    ) -> Self {
        let mut s = Sources {
            events: Vec::new(),
            health: [SensorHealth::default(); 4],
            ignored: Vec::new(),
            warnings: Vec::new(),
            usbl_latency: 0.0,
        };
        let has = crate::navigator::vehicle::Present::of::<V, N>();
        let has_heading = match options.compass {
            CompassForm::Exact => has.compass,
            CompassForm::SmallAngle => has.compass_small_angle,
        };
        let rows = [
            log.depth.as_ref().map(Vec::len),
            log.dvl.as_ref().map(Vec::len),
            log.heading.as_ref().map(Vec::len),
            log.usbl.as_ref().map(Vec::len),
        ];
        let present = [has.depth, has.dvl, has_heading, has.usbl];
        let used = [
            options.use_depth,
            options.use_dvl,
            options.use_compass,
            options.use_usbl,
        ];
        for i in 0..4 {
            match rows[i] {
                // A log sensor the vehicle lacks: its rows are counted and skipped.
                Some(n) if !present[i] => {
                    s.health[i].rows = n as u64;
                    s.health[i].skipped = n as u64;
                    s.ignored.push(SENSOR_NAMES[i]);
                }
                Some(n) if used[i] => {
                    s.health[i].rows = n as u64;
                    match i {
                        0 => s.depth(log, options),
                        1 => s.dvl(log, options),
                        2 => s.heading(log, options),
                        _ => s.usbl(log, options, transducer),
                    }
                }
                _ => {}
            }
        }
        s.events.sort_by(|a, b| a.delivery.total_cmp(&b.delivery));
        s
    }

    /// Depth meter (height convention).
    fn depth(&mut self, log: &LogDir, options: &FilterOptions) {
        let rows = log.depth.as_deref().unwrap_or_default();
        self.events
            .extend(rows.iter().enumerate().map(|(i, r)| Event {
                delivery: r.t + options.delivery.delay(0, i),
                time: r.t,
                sensor: 0,
                row: i,
            }));
    }

    /// DVL: valid only with bottom lock and below its range.
    fn dvl(&mut self, log: &LogDir, options: &FilterOptions) {
        let rows = log.dvl.as_deref().unwrap_or_default();
        for (i, r) in rows.iter().enumerate() {
            let in_range = altitude_at(log, r.t).is_none_or(|a| a <= DVL_MAX_ALTITUDE);
            if r.velocity().is_some() && in_range {
                self.events.push(Event {
                    delivery: r.t + options.delivery.delay(1, i),
                    time: r.t,
                    sensor: 1,
                    row: i,
                });
            } else {
                self.health[1].skipped += 1;
            }
        }
    }

    fn heading(&mut self, log: &LogDir, options: &FilterOptions) {
        let rows = log.heading.as_deref().unwrap_or_default();
        self.events
            .extend(rows.iter().enumerate().map(|(i, r)| Event {
                delivery: r.t + options.delivery.delay(2, i),
                time: r.t,
                sensor: 2,
                row: i,
            }));
    }

    /// USBL: delivered after the acoustic travel time from the transducer.
    /// A fix with a NaN cell is refused by the navigator (counted as
    /// rejected); one whose travel time is infinite (an absurd cell such as
    /// 1e300) is rejected here, with a warning naming its line.
    fn usbl(&mut self, log: &LogDir, options: &FilterOptions, transducer: Geodetic) {
        let rows = log.usbl.as_deref().unwrap_or_default();
        let frame = LocalNed::new(transducer);
        for (i, r) in rows.iter().enumerate() {
            let delay = match options.usbl_delivery {
                UsblDelivery::OnTime => 0.0,
                UsblDelivery::Acoustic => {
                    frame
                        .geodetic_to_ned(&Geodetic::new(r.lat, r.lon, -r.depth))
                        .norm()
                        / SOUND_SPEED
                }
            };
            if delay.is_infinite() {
                self.health[3].rejected += 1;
                self.warnings.push(format!(
                    "{}: the fix (lat {}, lon {}, depth {}) gives an infinite acoustic travel time; not used",
                    place(log, "usbl.csv", i),
                    r.lat,
                    r.lon,
                    r.depth
                ));
                continue;
            }
            // `max` ignores a NaN delay: that fix goes last and is refused.
            self.usbl_latency = self.usbl_latency.max(delay);
            self.events.push(Event {
                delivery: r.t + delay,
                time: r.t,
                sensor: 3,
                row: i,
            });
        }
    }

    /// Latencies of depth, DVL, compass and USBL: the history spans the
    /// largest. USBL fixes travel (plus a margin) only if there are any; the
    /// 2 Hz aiding is late only with delivery faults.
    fn latencies(&self, options: &FilterOptions) -> [f64; 4] {
        let has_usbl = self.events.iter().any(|e| e.sensor == 3);
        std::array::from_fn(|i| {
            if i == 3 {
                if has_usbl {
                    self.usbl_latency + 1.0
                } else {
                    0.0
                }
            } else if options.delivery.is_late() {
                options.delivery.max_delay() + 0.1
            } else {
                0.0
            }
        })
    }
}

/// Pushes the reading of `ev` into `nav`.
fn push_reading<V: InsVehicle<N>, const N: usize>(
    nav: &mut Navigator<V, N>,
    handles: &Handles,
    log: &LogDir,
    ev: &Event,
) {
    let t = ev.time;
    match ev.sensor {
        0 => {
            let depth = log.depth.as_ref().map_or(f64::NAN, |r| r[ev.row].depth);
            if let Some(h) = handles.depth {
                nav.push(h, t, DepthReading(depth));
            }
        }
        1 => {
            let v = log
                .dvl
                .as_ref()
                .and_then(|r| r[ev.row].velocity())
                .map_or(Vector3::repeat(f64::NAN), Vector3::from);
            if let Some(h) = handles.dvl {
                nav.push(h, t, DvlReading(v));
            }
        }
        2 => {
            let psi = log.heading.as_ref().map_or(f64::NAN, |r| r[ev.row].heading);
            if let Some(h) = handles.heading {
                nav.push(h, t, HeadingReading(psi));
            }
        }
        _ => {
            let (lat, lon) = log
                .usbl
                .as_ref()
                .map_or((f64::NAN, f64::NAN), |r| (r[ev.row].lat, r[ev.row].lon));
            if let Some(h) = handles.usbl {
                nav.push(h, t, UsblFix { lat, lon });
            }
        }
    }
}

/// The handles of the sensors a vehicle has.
struct Handles {
    depth: Option<crate::navigator::Handle<DepthReading>>,
    dvl: Option<crate::navigator::Handle<DvlReading>>,
    heading: Option<crate::navigator::Handle<HeadingReading>>,
    usbl: Option<crate::navigator::Handle<UsblFix>>,
}

/// Runs the SDINS-25 filter over `log`: [`run_vehicle`] of [`Sdins25`].
pub fn run(
    log: &LogDir,
    options: &FilterOptions,
    record_times: &[f64],
) -> Result<Sdins25Run, RunError> {
    run_vehicle::<Sdins25, N>(log, options, record_times)
}

/// For each IMU row that some of `record_times` (sorted or not) snaps to, the
/// indices of those times: `(imu row, [record slots])`, by IMU row.
fn record_slots(imu_t: &[f64], record_times: &[f64], dt_imu: f64) -> Vec<(usize, Vec<usize>)> {
    let mut slots: Vec<(usize, Vec<usize>)> = Vec::new();
    for (slot, &t) in record_times.iter().enumerate() {
        let k = imu_t.partition_point(|&x| x < t);
        let best = [k.wrapping_sub(1), k]
            .into_iter()
            .filter(|&j| j < imu_t.len())
            .min_by(|&a, &b| (imu_t[a] - t).abs().total_cmp(&(imu_t[b] - t).abs()));
        if let Some(j) = best.filter(|&j| (imu_t[j] - t).abs() <= 0.5 * dt_imu + 1e-9) {
            match slots.last_mut() {
                Some((last, v)) if *last == j => v.push(slot),
                _ => slots.push((j, vec![slot])),
            }
        }
    }
    slots
}

/// Runs the filter of vehicle `V` over `log`, recording estimates at
/// `record_times` (s; each snapped to the nearest IMU sample time within half
/// a period). The rows of a log sensor `V` has no sensor for are not used:
/// they are counted in that sensor's health as rows and skipped, and the
/// sensor is listed in [`InsRun::ignored`].
///
/// # Errors
/// A setup problem, an IMU sample the filter refuses, or an estimate out of
/// its physical bounds ([`FilterOptions::bounds`]), each naming the input
/// file and line that led to it.
pub fn run_vehicle<V: InsVehicle<N>, const N: usize>(
    log: &LogDir,
    options: &FilterOptions,
    record_times: &[f64],
) -> Result<InsRun<V, N>, RunError> {
    crate::navigator::vehicle::Layout::of::<V, N>()?;
    let plan0 = LogPlan::new(log, options, [0.0; 4])?;
    let sources = Sources::new::<V, N>(log, options, plan0.transducer);
    let plan = LogPlan {
        sensors: {
            let lat = sources.latencies(options);
            let mut s = plan0.sensors;
            for (s, l) in s.iter_mut().zip(lat) {
                s.latency_s = l;
            }
            s
        },
        ..plan0
    };
    let (builder, handles) = plan.builder::<V, N>(options);
    let mut nav = builder.build(plan.first).map_err(setup_error)?;

    // Requested estimates: one request per IMU sample time that some
    // requested time snaps to.
    let imu_t: Vec<f64> = log.imu.iter().map(|r| r.t).collect();
    let slots = record_slots(&imu_t, record_times, plan.imu.period_s);
    let mut estimates: Vec<Option<Estimate>> = vec![None; record_times.len()];
    let mut slot_of_ticket: std::collections::VecDeque<usize> = Default::default();
    let mut next_slot = 0;
    let mut deliver =
        |ticket_slot: Option<usize>, e: Option<Estimate>, slots: &[(usize, Vec<usize>)]| {
            if let Some(k) = ticket_slot {
                for &s in &slots[k].1 {
                    estimates[s] = e;
                }
            }
        };
    if let Some((0, _)) = slots.first() {
        nav.request_estimate(imu_t[0]);
        slot_of_ticket.push_back(0);
        next_slot = 1;
    }

    let start = std::time::Instant::now();
    let events = &sources.events;
    let mut next = 0;
    let mut samples = 0;
    let mut last_input: Option<&Event> = None;
    let mut warnings = sources.warnings;
    for (j, row) in log.imu.iter().enumerate().skip(1) {
        let previous = &log.imu[j - 1];
        if let Some(k) = options.max_imu_step {
            let step = k * plan.imu.period_s;
            let gap = row.t - previous.t;
            if gap > step {
                let steps = (gap / step).ceil();
                let lines = format!(
                    "{} to {}",
                    place(log, "imu.csv", j - 1),
                    place(log, "imu.csv", j)
                );
                if steps > MAX_GAP_STEPS {
                    return Err(RunError::Invalid(format!(
                        "imu.csv gap of {gap} s between {lines} is too long to propagate (more than {MAX_GAP_STEPS} steps of {step} s)"
                    )));
                }
                warnings.push(format!(
                    "imu.csv gap of {gap} s between {lines}: propagated in {steps} steps holding the sample before it"
                ));
                let held = ImuSample {
                    gyro: Vector3::new(previous.gx, previous.gy, previous.gz),
                    accel: Vector3::new(previous.ax, previous.ay, previous.az),
                };
                for m in 1..steps as usize {
                    let t = previous.t + gap * (m as f64 / steps);
                    while let Some(ev) = events.get(next).filter(|e| e.delivery <= t) {
                        push_reading(&mut nav, &handles, log, ev);
                        last_input = Some(ev);
                        next += 1;
                    }
                    nav.push_imu(t, held).map_err(|e| {
                        RunError::Invalid(format!("imu.csv gap between {lines} at t = {t} s: {e}"))
                    })?;
                    nav.final_estimates(|_, e| deliver(slot_of_ticket.pop_front(), e, &slots));
                }
            }
        }
        while let Some(ev) = events.get(next).filter(|e| e.delivery <= row.t) {
            push_reading(&mut nav, &handles, log, ev);
            last_input = Some(ev);
            next += 1;
        }
        if let Some((k, _)) = slots.get(next_slot).filter(|(k, _)| *k == j) {
            nav.request_estimate(imu_t[*k]);
            slot_of_ticket.push_back(next_slot);
            next_slot += 1;
        }
        let imu = ImuSample {
            gyro: Vector3::new(row.gx, row.gy, row.gz),
            accel: Vector3::new(row.ax, row.ay, row.az),
        };
        nav.push_imu(row.t, imu).map_err(|e| match e {
            NavigatorError::Imu(e) => RunError::Invalid(format!(
                "imu.csv at t = {} s ({}): {e}",
                row.t,
                place(log, "imu.csv", j)
            )),
            e => RunError::Invalid(format!(
                "{} (t = {} s): {e}{}",
                place(log, "imu.csv", j),
                row.t,
                last_input.map_or(String::new(), |ev| format!(
                    "; latest aiding input: {}",
                    place(log, &format!("{}.csv", SENSOR_NAMES[ev.sensor]), ev.row)
                ))
            )),
        })?;
        samples += 1;
        nav.final_estimates(|_, e| deliver(slot_of_ticket.pop_front(), e, &slots));
    }
    // Fixes still travelling when the IMU data ends (measured before its end).
    for ev in &events[next..] {
        push_reading(&mut nav, &handles, log, ev);
    }
    nav.flush_estimates(|_, e| deliver(slot_of_ticket.pop_front(), e, &slots));
    let runtime_s = start.elapsed().as_secs_f64();

    let mut health = sources.health;
    for (i, h) in health.iter_mut().enumerate() {
        let r = nav.report_of(i).health;
        h.accepted = r.accepted;
        h.gated = r.gated;
        h.rejected += r.rejected;
        h.skipped += r.skipped;
        h.stuck = r.stuck;
    }
    let mut final_filter = nav.filter().clone();
    let recording = final_filter
        .finish_recording()
        .map_err(|e| RunError::Invalid(e.to_string()))?;
    let layout = *final_filter.nominal().layout();
    let smoothed = recording
        .map(|store| smoothed_estimates(&mut store.borrow_mut(), &estimates, &layout))
        .transpose()?;
    let repairs = final_filter.ekf().counters().covariance_repairs;
    let replays = nav.replays();
    Ok(InsRun {
        estimates,
        samples: samples + 1,
        health: std::array::from_fn(|i| (SENSOR_NAMES[i], health[i])),
        repairs,
        runtime_s,
        replays,
        final_filter,
        ignored: sources.ignored,
        smoothed,
        warnings,
    })
}

/// The smoothed counterpart of each estimate, from the recorded epochs of
/// `file` (every output time is an epoch of the recording): the backward pass
/// meets the epochs latest first and the estimates are matched from the end,
/// so nothing but the smoothed estimates is kept.
fn smoothed_estimates<const N: usize>(
    file: &mut EpochFile<N, 0>,
    estimates: &[Option<Estimate>],
    layout: &Layout,
) -> Result<Vec<Option<Estimate>>, RunError> {
    let mut out = vec![None; estimates.len()];
    let mut k = estimates.len();
    smooth(file, |epoch| {
        while k > 0 {
            match &estimates[k - 1] {
                Some(e) if e.t > epoch.time + 1e-9 => k -= 1,
                None => k -= 1,
                Some(e) => {
                    if (e.t - epoch.time).abs() <= 1e-9 {
                        out[k - 1] = Some(e.smoothed(&epoch.error, &epoch.covariance, layout));
                        k -= 1;
                        // Several requested times may snap to one epoch.
                        while let Some(Some(same)) = estimates.get(k.wrapping_sub(1)) {
                            if (same.t - epoch.time).abs() > 1e-9 {
                                break;
                            }
                            out[k - 1] =
                                Some(same.smoothed(&epoch.error, &epoch.covariance, layout));
                            k -= 1;
                        }
                    }
                    break;
                }
            }
        }
        Ok(())
    })
    .map_err(|e| RunError::Invalid(e.to_string()))?;
    Ok(out)
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

/// IMU steps between the scheduler's checkpoints for a history of `window`
/// seconds at IMU period `dt` (s). A checkpoint (a copy of the whole filter)
/// every step costs more than the steps themselves save: a late measurement
/// re-propagates from the newest checkpoint before it, so spacing them by a
/// tenth of the window adds at most a tenth of the window to a replay, while
/// copying the filter ten times less often. Without late sensors (`window`
/// 0) a replay can only be for a measurement at the current IMU time, which
/// the replay loop always delivers before that sample: one checkpoint a
/// second. Results do not depend on the spacing (the replay recomputes the
/// Echo-sounder altitude at `t`: the latest row at or before `t` (m).
fn altitude_at(log: &LogDir, t: f64) -> Option<f64> {
    let rows = log.altitude.as_ref()?;
    let k = rows.partition_point(|r| r.t <= t + 1e-9);
    rows.get(k.checked_sub(1)?).map(|r| r.altitude)
}

/// `C_b^n` from Euler angles (rad).
pub fn c_bn(roll: f64, pitch: f64, yaw: f64) -> Matrix3<f64> {
    nav_runtime::attitude::Euler { roll, pitch, yaw }.c_bn()
}
