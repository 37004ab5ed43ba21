//! Runs LEVELING-6 over a log through the multi-rate scheduler every replay
//! uses: IMU rows drive `predict` (each sample held over the interval that
//! follows it, as the paper's filter integrates), speed-log rows (or, at
//! rest, a 10 Hz zero-velocity pseudo-measurement) drive `update` at their
//! own times, a late row by re-propagation ([`scheduled_filter`](super::scheduled_filter)).

use super::model::{
    Leveling6, Leveling6Input, Leveling6Moving, Leveling6Noise, Leveling6Params,
    Leveling6Stationary, Leveling8, Leveling8Input, Leveling8Moving, Leveling8Noise,
    Leveling8Params, Leveling8Stationary,
};
use super::scheduled_filter::{keep_upright, LevelingFilter};
pub use super::smoothed::SmoothedEstimates;
use crate::harness::{RunError, RunHealth, SensorHealth};
use nav_ins::ImuSample;
use nav_runtime::earth;
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::innovations::InnovationTotals;
use nav_runtime::log::{Event, LogDir, LogError, LogSource, Prefetched, SpeedRow};
use nav_runtime::model::{Model, Sensor};
use nav_runtime::nalgebra::{Matrix2, Matrix4, SMatrix, SVector, Vector2, Vector3, Vector4};
use nav_runtime::scheduler::{
    FnMeasurement, Measurement, MeasurementOutcome, Report, Scheduler, SchedulerError, SensorId,
};
use nav_runtime::setup_error::SetupError;
use nav_runtime::smoother::{
    observability, smooth_states, EpochFile, Recorder, SmootherError, States,
};
use std::time::{Duration, Instant};

/// How the filter is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelingOptions {
    /// Use the stationary measurement model (eqs. 32-33).
    pub stationary: bool,
    /// Initial roll and pitch guess (rad); `None` starts level (`a = [0, 0, 1]`),
    /// i.e. with no attitude knowledge.
    pub initial_attitude: Option<(f64, f64)>,
    /// Noise tuning.
    pub tuning: Tuning,
}

/// Filter tuning (documented in docs/results/leveling6.md, not fitted to a seed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tuning {
    /// Accelerometer noise density, m/s^2/sqrt(Hz); covers the unmodelled 1 mg bias drift.
    pub accel_density: f64,
    /// Gyro noise density, rad/s/sqrt(Hz).
    pub gyro_density: f64,
    /// Speed-log 1-sigma per sample, m/s (the paper's 0.15 covers its noise
    /// and bias together; the replay takes `[sensors.speed] noise_sigma`,
    /// docs/models/leveling6.md, "Replay").
    pub speed_sigma: f64,
    /// Zero-velocity pseudo-measurement 1-sigma, m/s.
    pub zero_velocity_sigma: f64,
    /// Unit-norm pseudo-measurement 1-sigma per update. The constraint is exact,
    /// but applying it at every 10 Hz update as if its errors were independent
    /// overcounts it, and linearized at a wrong `a` (45-degree initial errors)
    /// a tight sigma makes the filter confident before it has converged: with
    /// 0.01 the S-type roll std is 0.04 deg against a filter sigma of 0.02 deg;
    /// with 1.0, 0.016 deg against 0.024 deg (docs/results/leveling6.md).
    pub norm_sigma: f64,
    /// Initial velocity 1-sigma, m/s.
    pub velocity_sigma: f64,
    /// The vehicle is known to be upright (`a3 = cos(roll) cos(pitch) > 0`): an
    /// estimate with `a3 < 0` is reflected to `-a3`. In the moving model `a3`
    /// enters only through the unit norm, so its sign is unobservable and an
    /// initial error beyond 90 degrees otherwise converges to the mirror
    /// solution (roll off by 180 degrees).
    pub upright: bool,
    /// Carry the horizontal accelerometer bias as states ([`Leveling8`]); `false`
    /// is the paper's six-state filter.
    pub bias_states: bool,
    /// Initial 1-sigma of the bias states, m/s^2 (the IMU's bias specification).
    pub accel_bias_sigma: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning {
            accel_density: 2e-3,
            gyro_density: 1e-5,
            speed_sigma: 0.15,
            zero_velocity_sigma: 0.01,
            norm_sigma: 1.0,
            velocity_sigma: 0.5,
            upright: true,
            bias_states: false,
            accel_bias_sigma: nav_runtime::imu::MG,
        }
    }
}

/// One estimate: time (s), roll and pitch (rad), and their 1-sigma (rad) from the
/// covariance of `a` (eq. 28 linearized).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeEstimate {
    /// Time, s.
    pub t: f64,
    /// Roll, rad.
    pub roll: f64,
    /// Pitch, rad.
    pub pitch: f64,
    /// Roll 1-sigma, rad.
    pub roll_sigma: f64,
    /// Pitch 1-sigma, rad.
    pub pitch_sigma: f64,
    /// Covariance of roll and pitch, rad^2.
    pub roll_pitch_covariance: f64,
}

/// What a run produced besides its estimates, which went to the caller
/// one by one as the run gave them ([`run`]).
#[derive(Clone, Debug, Default)]
pub struct LevelingRun {
    /// The first estimate (the initial guess, at the first IMU sample).
    pub first: Option<AttitudeEstimate>,
    /// The last estimate.
    pub last: Option<AttitudeEstimate>,
    /// Updates applied, gated.
    pub accepted: u64,
    /// Updates rejected by the gate.
    pub gated: u64,
    /// Measurements or inputs rejected as invalid.
    pub rejected: u64,
    /// Covariance repairs.
    pub repairs: u64,
    /// IMU samples processed: one estimate each.
    pub samples: usize,
    /// Per sensor (`speed`, the speed log's rows; `zero_velocity`, the
    /// pseudo-measurements at rest without one): rows given and what became
    /// of them; the covariance repairs and the scheduler's re-propagations
    /// for late rows.
    pub health: RunHealth,
    /// Times of the first and the last row of `imu.csv`, s.
    pub imu_span: Option<(f64, f64)>,
    /// Time spent in the filter (its scheduler), not reading the log or
    /// handing estimates on.
    pub filter_time: Duration,
    /// Final estimate and 1-sigma of the x and y accelerometer bias, m/s^2
    /// (with bias states; NaN without).
    pub accel_bias_final: [f64; 4],
    /// The speed log's innovations, each update counted once (none in the
    /// stationary model, where its rows are zero-velocity
    /// pseudo-measurements): its NIS and what noise tuning weighs.
    pub speed_innovations: InnovationTotals,
}

impl LevelingRun {
    /// The mean spacing of the estimates in time, s (0 for fewer than two).
    pub fn mean_period(&self) -> f64 {
        match (self.first, self.last) {
            (Some(a), Some(b)) if self.samples > 1 => (b.t - a.t) / (self.samples - 1) as f64,
            _ => 0.0,
        }
    }
}

/// Where a run hands its estimates: one per IMU sample, in time order,
/// each final (a late speed-log row has already been applied to it).
pub type EstimateSink<'s> = dyn FnMut(&AttitudeEstimate) -> Result<(), RunError> + 's;

/// Roll and pitch from `a` (eq. 28).
pub fn roll_pitch(a: &Vector3<f64>) -> (f64, f64) {
    let pitch = (-a.x / a.norm()).clamp(-1.0, 1.0).asin();
    (a.y.atan2(a.z), pitch)
}

/// `a = C_n^b [0, 0, 1]` for roll and pitch (eq. 5).
pub fn gravity_direction(roll: f64, pitch: f64) -> Vector3<f64> {
    Vector3::new(
        -pitch.sin(),
        roll.sin() * pitch.cos(),
        roll.cos() * pitch.cos(),
    )
}

fn estimate<const N: usize>(
    t: f64,
    x: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
) -> AttitudeEstimate {
    let a = Vector3::new(x[3], x[4], x[5]);
    let (roll, pitch) = roll_pitch(&a);
    let n2 = a.y * a.y + a.z * a.z;
    let j_roll = Vector3::new(0.0, a.z / n2, -a.y / n2);
    let j_pitch = Vector3::new(-1.0 / (1.0 - (a.x * a.x).min(0.999_999)).sqrt(), 0.0, 0.0);
    let pa = p.fixed_view::<3, 3>(3, 3);
    AttitudeEstimate {
        t,
        roll,
        pitch,
        roll_sigma: (j_roll.transpose() * pa * j_roll)[0].max(0.0).sqrt(),
        pitch_sigma: (j_pitch.transpose() * pa * j_pitch)[0].max(0.0).sqrt(),
        roll_pitch_covariance: (j_roll.transpose() * pa * j_pitch)[0],
    }
}

/// What the run needs from a leveling model: its input, parameters, noise and
/// initial state, and its two measurement models.
pub trait LevelingModel<const N: usize>: Model<N> {
    /// Speed log and unit norm.
    type Moving: Sensor<N, 2, Model = Self, Aux = ()>;
    /// Zero velocity and unit norm.
    type Stationary: Sensor<N, 4, Model = Self, Aux = ()>;
    /// The input of one IMU sample.
    fn input(
        gyro: Vector3<f64>,
        specific_force: Vector3<f64>,
        earth_rate_body: Vector3<f64>,
    ) -> Self::Input;
    /// Parameters at local gravity `gravity` (m/s^2).
    fn params(gravity: f64) -> Self::Params;
    /// Noise intensities of `t`.
    fn noise(t: &Tuning) -> Self::Noise;
    /// Initial state and covariance from the forward speed (m/s) and `a`.
    fn initial(speed: f64, a: &Vector3<f64>, t: &Tuning) -> (SVector<f64, N>, SMatrix<f64, N, N>);
}

impl LevelingModel<6> for Leveling6 {
    type Moving = Leveling6Moving;
    type Stationary = Leveling6Stationary;
    fn input(
        gyro: Vector3<f64>,
        specific_force: Vector3<f64>,
        earth_rate_body: Vector3<f64>,
    ) -> Leveling6Input {
        Leveling6Input {
            gyro,
            specific_force,
            earth_rate_body,
        }
    }
    fn params(gravity: f64) -> Leveling6Params {
        Leveling6Params { gravity }
    }
    fn noise(t: &Tuning) -> Leveling6Noise {
        Leveling6Noise {
            accel_noise: Vector3::repeat(t.accel_density * t.accel_density),
            gyro_noise: Vector3::repeat(t.gyro_density * t.gyro_density),
        }
    }
    fn initial(speed: f64, a: &Vector3<f64>, t: &Tuning) -> (SVector<f64, 6>, SMatrix<f64, 6, 6>) {
        let x0 = SVector::<f64, 6>::from_column_slice(&[speed, 0.0, 0.0, a.x, a.y, a.z]);
        let v2 = t.velocity_sigma * t.velocity_sigma;
        let d = SVector::<f64, 6>::from_column_slice(&[v2, v2, v2, 1.0, 1.0, 1.0]);
        (x0, SMatrix::from_diagonal(&d))
    }
}

impl LevelingModel<8> for Leveling8 {
    type Moving = Leveling8Moving;
    type Stationary = Leveling8Stationary;
    fn input(
        gyro: Vector3<f64>,
        specific_force: Vector3<f64>,
        earth_rate_body: Vector3<f64>,
    ) -> Leveling8Input {
        Leveling8Input {
            gyro,
            specific_force,
            earth_rate_body,
        }
    }
    fn params(gravity: f64) -> Leveling8Params {
        Leveling8Params { gravity }
    }
    fn noise(t: &Tuning) -> Leveling8Noise {
        Leveling8Noise {
            accel_noise: Vector3::repeat(t.accel_density * t.accel_density),
            gyro_noise: Vector3::repeat(t.gyro_density * t.gyro_density),
            bias_walk: Vector2::zeros(),
        }
    }
    fn initial(speed: f64, a: &Vector3<f64>, t: &Tuning) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        let x0 = SVector::<f64, 8>::from_column_slice(&[speed, 0.0, 0.0, a.x, a.y, a.z, 0.0, 0.0]);
        let v2 = t.velocity_sigma * t.velocity_sigma;
        let b2 = t.accel_bias_sigma * t.accel_bias_sigma;
        let d = SVector::<f64, 8>::from_column_slice(&[v2, v2, v2, 1.0, 1.0, 1.0, b2, b2]);
        (x0, SMatrix::from_diagonal(&d))
    }
}

/// Why a run stopped: the filter refused its set-up, the scheduler its
/// start (a first IMU time that is not finite), a file of the log a row
/// (strict reading), or the caller an estimate (a file it writes).
#[derive(Debug, thiserror::Error)]
pub enum LevelingError {
    /// The filter refused its initial state or covariance.
    #[error(transparent)]
    Setup(#[from] SetupError),
    /// The filter refused a state or covariance it was set to.
    #[error(transparent)]
    Filter(#[from] FilterError),
    /// The scheduler refused its start or a sensor.
    #[error(transparent)]
    Scheduler(#[from] SchedulerError),
    /// The recording for the smoother or the observability report failed.
    #[error(transparent)]
    Recording(#[from] SmootherError),
    /// A row of the log could not be read.
    #[error(transparent)]
    Log(#[from] LogError),
    /// The caller refused an estimate.
    #[error(transparent)]
    Output(#[from] RunError),
}

impl From<LevelingError> for RunError {
    /// A bad row keeps its file and line; the caller's own error is given
    /// back; the rest is the run's refusal, as text.
    fn from(e: LevelingError) -> RunError {
        match e {
            LevelingError::Log(e) => RunError::Log(e),
            LevelingError::Output(e) => e,
            e => RunError::Invalid(e.to_string()),
        }
    }
}

/// Runs the filter over `source`, [`Leveling6`], or [`Leveling8`] with
/// `options.tuning.bias_states`, handing each estimate to `each`.
///
/// # Errors
/// The filter or the scheduler refuses its set-up, a row of the log (strict
/// reading) or `each` an estimate.
pub fn run(
    source: &LogSource<'_>,
    options: &LevelingOptions,
    each: &mut EstimateSink<'_>,
) -> Result<LevelingRun, LevelingError> {
    if options.tuning.bias_states {
        run_model::<Leveling8, 8>(source, options, None, each).map(|(run, _)| run)
    } else {
        run_model::<Leveling6, 6>(source, options, None, each).map(|(run, _)| run)
    }
}

/// What a run of [`Leveling8`] over `log` taught each of its states
/// (`velocity[0..3]`, `gravity_direction[0..3]`, `accel_bias[0..2]`, in
/// that order) and its weakest `directions`, by the same recording and
/// analysis as an INS replay's `--observability` (docs/observability.md):
/// the generic report checked against the leveling work's known answer.
///
/// # Errors
/// A filter error of the run, or a recording error (as text).
pub fn observability_of_run(
    log: &LogDir,
    options: &LevelingOptions,
    directions: usize,
) -> Result<nav_runtime::smoother::Observability<8>, String> {
    let recording = Recording {
        observability: Some(directions),
        smooth: false,
    };
    let recorded =
        run_recorded::<Leveling8, 8>(&LogSource::Memory(log), options, recording, &mut |_| Ok(()))
            .map_err(|e| e.to_string())?;
    recorded
        .observed
        .ok_or_else(|| "the run taught nothing: no IMU sample".to_string())
}

/// What a recorded run is for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Recording {
    /// What the run taught each state and this many weakest directions
    /// (docs/observability.md).
    pub observability: Option<usize>,
    /// The smoothed estimate at every IMU sample after the first
    /// ([`Recorded::smoothed`]): each sample is an epoch of the recording,
    /// corrected by the fixed-interval smoother every replay uses
    /// (docs/smoother.md).
    pub smooth: bool,
}

/// A recorded run: the run, the observability report when asked for
/// (`None` for a log without IMU samples), and the smoothed estimates when
/// asked for.
#[derive(Debug)]
pub struct Recorded<const N: usize> {
    /// The run.
    pub run: LevelingRun,
    /// What it taught each state.
    pub observed: Option<nav_runtime::smoother::Observability<N>>,
    /// Its smoothed estimates.
    pub smoothed: Option<SmoothedEstimates>,
}

/// The run of `M` over `source`, recorded for `recording`, each estimate
/// handed to `each`.
///
/// # Errors
/// As [`run`], and a recording error.
pub fn run_recorded<M: LevelingModel<N>, const N: usize>(
    source: &LogSource<'_>,
    options: &LevelingOptions,
    recording: Recording,
    each: &mut EstimateSink<'_>,
) -> Result<Recorded<N>, LevelingError> {
    let file = EpochFile::<N, N>::create(None)?;
    let (run, recorder) = run_model::<M, N>(source, options, Some((file, recording)), each)?;
    let Some(mut recorder) = recorder else {
        return Ok(Recorded {
            run,
            observed: None,
            smoothed: None,
        });
    };
    recorder.finish()?;
    let information = recorder.sensor_information().cloned();
    let store = recorder.store();
    let mut file = store.borrow_mut();
    let observed = match recording.observability {
        Some(directions) => {
            let (_, p0) = M::initial(0.0, &Vector3::z(), &options.tuning);
            let prior_sigma: [f64; N] = std::array::from_fn(|i| p0[(i, i)].sqrt());
            Some(observability(
                &mut file,
                &prior_sigma,
                0.0,
                directions,
                information.as_ref(),
            )?)
        }
        None => None,
    };
    let smoothed = match recording.smooth {
        true => {
            // The backward pass meets the epochs latest first; the smoothed
            // state is the recorded one with its smoothed error removed.
            let first = run.first.map_or(f64::NEG_INFINITY, |e| e.t);
            let mut smoothed = SmoothedEstimates::new()?;
            smooth_states(&mut file, &States::all(), |epoch| {
                if epoch.time > first + 1e-9 {
                    let x = epoch.snapshot - epoch.error;
                    smoothed.push_earlier(&estimate(epoch.time, &x, &epoch.covariance))?;
                }
                Ok(())
            })?;
            Some(smoothed)
        }
        false => None,
    };
    drop(file);
    Ok(Recorded {
        run,
        observed,
        smoothed,
    })
}

/// How late a speed-log row may come and still be applied at its own time
/// (the scheduler keeps this much history), s.
pub const SPEED_LATENCY_S: f64 = 1.0;
/// Period of the zero-velocity pseudo-measurement at rest without a speed
/// log, s.
pub const ZERO_VELOCITY_PERIOD_S: f64 = 0.1;

/// A boxed measurement of the leveling filter.
type LevelingMeasurement<M, const N: usize> = Box<dyn Measurement<LevelingFilter<M, N>>>;

/// The run of `M` over `log` through the multi-rate scheduler: each IMU
/// sample is held over the interval that follows it, a speed-log row is
/// applied at its own time (a late one by re-propagation), the
/// zero-velocity pseudo-measurement at the first sample at or after each
/// tenth of a second. Returns the run and the final filter's recorder.
fn run_model<M: LevelingModel<N>, const N: usize>(
    source: &LogSource<'_>,
    options: &LevelingOptions,
    recording: Option<(EpochFile<N, N>, Recording)>,
    each: &mut EstimateSink<'_>,
) -> Result<(LevelingRun, Option<Recorder<N, N>>), LevelingError> {
    let init = &source.meta().initial;
    let lat = init.lat;
    let height = -init.depth;
    let t = options.tuning;
    let (roll0, pitch0) = options.initial_attitude.unwrap_or((0.0, 0.0));
    let a0 = gravity_direction(roll0, pitch0);
    let speed0 = if options.stationary {
        0.0
    } else {
        (init.vn * init.vn + init.ve * init.ve).sqrt()
    };
    let (x0, p0) = M::initial(speed0, &a0, &t);
    let params = M::params(earth::normal_gravity(lat, height));
    let noise = M::noise(&t);
    // No innovation gate: during convergence from a 45-degree error the linearized
    // S understates the innovation and a gate would reject the very measurements
    // that make the attitude observable (the paper uses none).
    let mut ekf = Ekf::<M, N>::new(x0, p0, params, noise)?.with_default_gate(None);
    if t.upright {
        keep_upright(&mut ekf)?;
    }
    // The run starts at the first IMU row (the first step follows the second).
    let mut imu = Prefetched::new(source.imu_rows()?);
    let start = imu.read_ahead()?.map_or(0.0, |row| row.t);
    let has_speed = source.has::<SpeedRow>()?;
    let smooth = recording.as_ref().is_some_and(|(_, r)| r.smooth);
    let recorder = recording.map(|(file, r)| {
        let mut recorder = Recorder::new(file, start, ekf.covariance(), *ekf.state());
        if r.observability.is_some() {
            recorder.track_sensor_information();
        }
        recorder
    });
    // Yaw is not estimated; it is carried by integrating the Euler yaw rate from
    // [initial].yaw so that the Earth-rate input W^b (eq. 16) follows the turns.
    let mut filter = Some(LevelingFilter::new(
        ekf,
        init.yaw.unwrap_or(0.0),
        earth::earth_rate_n(lat),
        t.upright,
        recorder,
    ));

    let mut out = LevelingRun::default();
    let r_moving =
        Matrix2::from_diagonal(&Vector2::new(t.speed_sigma.powi(2), t.norm_sigma.powi(2)));
    let zv = t.zero_velocity_sigma.powi(2);
    let r_stationary = Matrix4::from_diagonal(&Vector4::new(zv, zv, zv, t.norm_sigma.powi(2)));
    let zero_velocity = |values: &[f64], reflect: bool| -> LevelingMeasurement<M, N> {
        Box::new(FnMeasurement::new(
            values,
            move |f: &mut LevelingFilter<M, N>| {
                let z = Vector4::new(0.0, 0.0, 0.0, 1.0);
                f.update::<M::Stationary, 4>(&z, &r_stationary, reflect)
            },
        ))
    };
    // The scheduler starts at the first IMU sample, with the filter.
    let mut run: Option<Running<M, N>> = None;
    let mut next_zero_velocity = ZERO_VELOCITY_PERIOD_S;
    // The latest estimate waits until the next sample: a late speed-log row
    // still changes it.
    let mut latest: Option<AttitudeEstimate> = None;
    // What each sensor was given: the speed log's rows, the zero-velocity
    // pseudo-measurements made without one.
    let (mut speed_rows, mut zero_velocity_rows) =
        (SensorHealth::default(), SensorHealth::default());
    let mut events = source.events()?.with_rows(imu);
    while let Some(located) = events.next_event()? {
        match located.event {
            Event::Imu(row) => {
                out.imu_span = Some(out.imu_span.map_or((row.t, row.t), |(a, _)| (a, row.t)));
                let sample = ImuSample {
                    gyro: Vector3::new(row.gx, row.gy, row.gz),
                    accel: Vector3::new(row.ax, row.ay, row.az),
                };
                let r = match (run.as_mut(), filter.take()) {
                    (Some(r), _) => r,
                    (None, Some(f)) => run.insert(Running::start(
                        f,
                        row.t,
                        sample,
                        smooth,
                        !options.stationary,
                    )?),
                    (None, None) => continue,
                };
                if r.started_at != row.t {
                    if options.stationary && !has_speed && row.t + 1e-9 >= next_zero_velocity {
                        next_zero_velocity += ZERO_VELOCITY_PERIOD_S;
                        // Queued at the sample's time, applied after the step
                        // to it; a refusal is counted by the scheduler.
                        let m = zero_velocity(&[], false);
                        zero_velocity_rows.rows += 1;
                        let _ = r.scheduler.push_measurement(r.zero_velocity, row.t, m);
                    }
                    if let Some(id) = r.epoch {
                        // Registered last: after the updates of the time.
                        let t = row.t;
                        let m = FnMeasurement::new(&[], move |f: &mut LevelingFilter<M, N>| {
                            f.mark_epoch(t);
                            Ok(MeasurementOutcome::marker())
                        });
                        let _ = r.scheduler.push_measurement(id, row.t, Box::new(m));
                    }
                    // The previous sample holds over the interval it starts.
                    let started = Instant::now();
                    let pushed = r.scheduler.push_imu(row.t, r.held);
                    out.filter_time += started.elapsed();
                    let Ok(reports) = pushed else {
                        out.rejected += 1;
                        continue;
                    };
                    r.note(&reports, &mut out.speed_innovations);
                    r.held = sample;
                }
                out.samples += 1;
                let f = r.scheduler.filter();
                let e = estimate(row.t, f.ekf.state(), f.ekf.covariance());
                if let Some(done) = latest.replace(e) {
                    out.first.get_or_insert(done);
                    each(&done)?;
                }
            }
            Event::Speed(row) => {
                speed_rows.rows += 1;
                let Some(r) = run.as_mut() else {
                    // Before the first IMU sample: not used.
                    speed_rows.skipped += 1;
                    continue;
                };
                let m = if options.stationary {
                    zero_velocity(&[row.speed], true)
                } else {
                    let z = Vector2::new(row.speed, 1.0);
                    Box::new(FnMeasurement::new(
                        &[row.speed],
                        move |f: &mut LevelingFilter<M, N>| f.update_speed(&z, &r_moving),
                    ))
                };
                // A refusal is counted by the scheduler; a row at or before
                // the last sample is applied at its own time by
                // re-propagation, and the estimate there is the new one.
                let started = Instant::now();
                let pushed = r.scheduler.push_measurement(r.speed, row.t, m);
                out.filter_time += started.elapsed();
                if let Ok(reports) = pushed {
                    r.note(&reports, &mut out.speed_innovations);
                }
                if let Some(last) = latest.as_mut() {
                    let f = r.scheduler.filter();
                    *last = estimate(last.t, f.ekf.state(), f.ekf.covariance());
                }
            }
            _ => {}
        }
    }
    if let Some(done) = latest {
        out.first.get_or_insert(done);
        out.last = Some(done);
        each(&done)?;
    }
    let Some(r) = run else {
        return Ok((out, filter.and_then(|f| f.recorder)));
    };
    for (name, id, mut health) in [
        ("speed", r.speed, speed_rows),
        ("zero_velocity", r.zero_velocity, zero_velocity_rows),
    ] {
        let s = r.scheduler.sensor_stats(id).unwrap_or_default();
        health.accepted = s.accepted;
        health.gated = s.gated;
        health.rejected = s.failed + s.too_old + s.duplicate + s.invalid + s.queue_full;
        // Still waiting at the end: after the last IMU sample, not used.
        health.skipped += s.pending;
        health.stuck = s.stuck;
        // The scenarios' totals count the waiting ones as refused.
        out.accepted += health.accepted;
        out.gated += health.gated;
        out.rejected += health.rejected + s.pending;
        if health.rows > 0 {
            out.health.sensors.push((name.into(), health));
        }
    }
    let f = r.scheduler.filter();
    out.repairs = f.ekf.counters().covariance_repairs;
    out.health.covariance_repairs = out.repairs;
    out.health.replays = Some(r.scheduler.stats().replays);
    out.accel_bias_final = if N >= 8 {
        let (x, p) = (f.ekf.state(), f.ekf.covariance());
        [
            x[6],
            x[7],
            p[(6, 6)].max(0.0).sqrt(),
            p[(7, 7)].max(0.0).sqrt(),
        ]
    } else {
        [f64::NAN; 4]
    };
    Ok((out, f.recorder.clone()))
}

/// A run under way: the scheduler, its two sensors and the IMU sample that
/// holds over the coming interval.
struct Running<M: LevelingModel<N>, const N: usize> {
    scheduler: Scheduler<LevelingFilter<M, N>>,
    speed: SensorId,
    zero_velocity: SensorId,
    /// With smoothing: the markers that make each sample an epoch.
    epoch: Option<SensorId>,
    held: ImuSample,
    started_at: f64,
    /// The speed log's rows are its updates (not zero-velocity ones).
    moving: bool,
}

impl<M: LevelingModel<N>, const N: usize> Running<M, N> {
    fn start(
        filter: LevelingFilter<M, N>,
        t: f64,
        first: ImuSample,
        smooth: bool,
        moving: bool,
    ) -> Result<Self, LevelingError> {
        let mut scheduler = Scheduler::new(filter, t)?;
        let speed = scheduler.add_sensor("speed", 1.0, SPEED_LATENCY_S)?;
        let zero_velocity =
            scheduler.add_sensor("zero_velocity", 1.0 / ZERO_VELOCITY_PERIOD_S, 0.0)?;
        let epoch = match smooth {
            true => Some(scheduler.add_sensor("epoch", 1.0, 0.0)?),
            false => None,
        };
        Ok(Running {
            scheduler,
            speed,
            zero_velocity,
            epoch,
            held: first,
            started_at: t,
            moving,
        })
    }

    /// Adds the speed log's innovations of the updates the scheduler
    /// reports (each once: a re-propagation's repeat is not counted again).
    fn note(&self, reports: &[Report], speed: &mut InnovationTotals) {
        if !self.moving {
            return;
        }
        for r in reports
            .iter()
            .filter(|r| r.sensor == self.speed && !r.replay)
        {
            if let Ok(o) = &r.outcome {
                speed.add(&o.statistics);
            }
        }
    }
}
