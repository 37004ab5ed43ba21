//! The replay loop: a log's events, read as a stream ([`LogSource`]), pushed
//! into the vehicle's [`Navigator`] in delivery order, and the estimates at
//! the requested output times handed on as they become final. Nothing in it
//! grows with the log: the aiding rows still travelling, the navigator's
//! history and the requests not yet final are bounded by the latency window.
//! The same loop runs a log in memory (Monte Carlo, tests) and a log on disk
//! (`navsim replay`).

use std::cell::Cell;
use std::collections::VecDeque;
use std::iter::Peekable;
use std::time::{Duration, Instant};

use nav_runtime::log::{
    reading_time, BaroRow, DepthRow, DvlRow, Event as LogEvent, GnssRow, HeadingRow, ImuForm,
    ImuRow, LogDir, LogSource, MagRow, UsblRow, Warning, WarningKind,
};
use nav_runtime::nalgebra::Vector3;
use nav_runtime::scheduler::SchedulerError;
use nav_runtime::smoother::{observability, smooth_states, EpochFile, SmootherError, SpillFile};
use nav_runtime::strapdown::RateSamples;

use super::aiding::{place, Aiding, Travelling};
use super::own_sensors::OwnSensors;
use super::setup::{setup_error, FilterOptions, InsRun, LogFacts, LogPlan, MAX_GAP_STEPS};
use crate::innovations::SensorInnovations;
use crate::preflight::frozen_imu::Fold as FrozenImu;
use crate::preflight::{PreflightOptions, Report};
use crate::RunError;
use nav_ins::vehicle::{Layout, Slot};
use nav_ins::{
    CompassForm, Estimate, ImuSample, InsVehicle, Navigator, NavigatorError, ESTIMATE_SCALARS,
    SENSORS, SENSOR_NAMES,
};

/// Runs the filter of vehicle `V` over `log`, recording estimates at
/// `record_times` (s; each snapped to the nearest IMU sample time within half
/// a period, `None` where no IMU sample is that near). The rows of a log
/// sensor `V` has no sensor for are not used: they are counted in that
/// sensor's health as rows and skipped, and the sensor is listed in
/// [`InsRun::ignored`].
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
    let mut order: Vec<usize> = (0..record_times.len()).collect();
    order.sort_by(|&a, &b| record_times[a].total_cmp(&record_times[b]));
    let requests = Listed::new(order.iter().map(|&k| Ok((record_times[k], k))));
    let mut estimates: Vec<Option<Estimate>> = vec![None; record_times.len()];
    let mut delivered: Vec<usize> = Vec::new();
    let mut in_order: Vec<Option<Estimate>> = Vec::new();
    let mut run = replay_vehicle::<V, N, _, _>(
        &LogSource::Memory(log),
        options,
        requests,
        |k, e| {
            estimates[k] = e.copied();
            if options.smooth {
                delivered.push(k);
            }
            Ok(())
        },
        |_, e| {
            in_order.push(e.copied());
            Ok(())
        },
    )?;
    run.estimates = estimates;
    run.smoothed = options.smooth.then(|| {
        let mut by_slot = vec![None; record_times.len()];
        for (k, e) in delivered.into_iter().zip(in_order) {
            by_slot[k] = e;
        }
        by_slot
    });
    Ok(run)
}

/// Runs the filter of vehicle `V` over the log of `source` and hands each
/// requested estimate to `sink` once it is final: `requests` says at which
/// IMU samples an estimate is wanted and what `sink` gets back with it
/// ([`Listed`] output times, [`Every`] period). [`InsRun::estimates`] and
/// [`InsRun::smoothed`] stay empty: with [`FilterOptions::smooth`],
/// `smoothed_sink` gets the smoothed counterpart of every estimate `sink`
/// got for a smoothed request (every request, but for the samples of
/// [`EachSample`] not chosen by [`EachSample::smoothing_every`]), with the
/// [`Smoothed`] kind of the request, in the same order, after the run.
/// Neither the forward estimates the
/// smoother needs nor the smoothed ones are kept in memory (they wait in
/// temporary files), so memory does not grow with the log.
///
/// # Errors
/// As [`run_vehicle`], a read error of the log, and the first error `sink`
/// returns.
pub fn replay_vehicle<V, const N: usize, P, Q>(
    source: &LogSource<'_>,
    options: &FilterOptions,
    requests: Q,
    mut sink: impl FnMut(P, Option<&Estimate>) -> Result<(), RunError>,
    mut smoothed_sink: impl FnMut(Smoothed, Option<&Estimate>) -> Result<(), RunError>,
) -> Result<InsRun<V, N>, RunError>
where
    V: InsVehicle<N>,
    Q: Requests<P>,
{
    Layout::of::<V, N>()?;
    source.meta().initial.position_for(V::REPLAY_NAME)?;
    let (facts, imu, heads) = LogFacts::of(source, options)?;
    let (plan, mut aiding) = plan_run::<V, N>(source, options, &facts)?;
    let mut own = OwnSensors::<V, N>::read(source)?;
    let (mut builder, handles) = plan.builder::<V, N>(options);
    own.register(&mut builder, source)?;
    super::calibration::register(&mut builder, source.meta())?;
    let samples = match source.imu_form()? {
        ImuForm::Rates => RateSamples::Instantaneous,
        ImuForm::Increments => RateSamples::IntervalAverage,
    };
    let mut nav = builder
        .rate_samples(samples)
        .build(plan.first)
        .map_err(setup_error)?;
    // The prior the observability report scales the states by.
    let prior = nav.filter().covariance();
    let prior_sigma: [f64; N] = std::array::from_fn(|i| prior[(i, i)].max(0.0).sqrt());
    let has_file = [
        source.has::<DepthRow>()?,
        source.has::<DvlRow>()?,
        source.has::<HeadingRow>()?,
        source.has::<UsblRow>()?,
        source.has::<GnssRow>()?,
        source.has::<BaroRow>()?,
        source.has::<MagRow>()?,
    ];
    let ignored = aiding.ignored(has_file);
    // A sensor of the vehicle that no file of the log feeds.
    let unfed: Vec<Warning> = (0..SENSORS)
        .filter(|&i| aiding.present[i] && !has_file[i])
        .map(|i| {
            let file = format!("{}.csv", SENSOR_NAMES[i]);
            Warning::about(
                WarningKind::MissingSensorSection,
                &file,
                format!(
                    "sensor {} of vehicle {} is fed by no file: the log has no {file}",
                    slot_sensor_name::<V, N>(i, options.compass),
                    V::REPLAY_NAME
                ),
            )
        })
        .collect();

    let mut requests = requests;
    let tolerance = 0.5 * plan.imu.period_s + 1e-9;
    let mut waiting = Waiting::default();
    // With smoothing: the estimates handed on, which the smoothed errors
    // are applied to after the run.
    let mut smoothing = options
        .smooth
        .then(|| SpillFile::create(None, SMOOTHING_RECORD))
        .transpose()
        .map_err(smoother_error)?;
    let clock = FilterTime::start();
    let mut out = |p: P, e: Option<&Estimate>, kind: Option<Smoothed>| -> Result<(), RunError> {
        if let (Some(file), Some(kind)) = (smoothing.as_mut(), kind) {
            file.push(&smoothing_record(e, kind))
                .map_err(smoother_error)?;
        }
        clock.output(|| sink(p, e))
    };

    // `imu.csv` and the aiding files continue after the rows the facts
    // were read from.
    let mut stream = heads.continue_in(source.events()?.with_rows(imu));
    let epoch = plan.initial.t;
    // IMU rows before the epoch are not used; aiding rows before the first
    // IMU row used wait in the queue.
    let mut imu_row = 0usize;
    let (first_line, first) = loop {
        let Some(ev) = stream.next_event()? else {
            return Err(RunError::Invalid("imu.csv has no rows".into()));
        };
        match ev.event {
            LogEvent::Imu(r) if r.t < epoch => imu_row += 1,
            LogEvent::Imu(r) => break (ev.line, r),
            _ => aiding.take(&ev),
        }
    };
    let mut warnings: Vec<Warning> = plan.warnings.clone();
    if imu_row > 0 {
        warnings.push(Warning::about(
            WarningKind::UnusedFile,
            "imu.csv",
            format!(
                "imu.csv: {imu_row} row(s) before the initial epoch t = {epoch} s (meta.toml initial.t) are not used"
            ),
        ));
    }
    // The first row at the epoch starts the navigator; one after it is
    // propagated to like any other.
    let mut first_to_push = (first.t > epoch).then_some((first_line, first));
    if first_to_push.is_none() {
        let next_t = stream.next_imu_t()?;
        if requests.take(first.t, next_t, tolerance, &mut waiting)? {
            waiting.request(&mut nav, first.t);
        }
        waiting.hand_unmatched(&mut out)?;
    }

    // Frozen IMU channels met on the way: a warning of the replay itself,
    // whether or not the preflight ran.
    let mut frozen = FrozenImu::new(source.meta(), &PreflightOptions::default());
    let mut samples = 1usize;
    let mut previous = ImuRow { t: epoch, ..first };
    let mut previous_line: Option<u64> = first_line;
    let mut last_input: Option<Travelling> = None;
    loop {
        // The next IMU sample; every aiding row up to its time is queued.
        let next = match first_to_push.take() {
            Some(first) => Some(first),
            None => {
                let next = stream.next_imu(|ev| aiding.take(ev))?;
                imu_row += usize::from(next.is_some());
                next
            }
        };
        let Some((line, row)) = next else { break };
        frozen.imu(line, &row);
        // Only formatted for a message.
        let here = || place("imu.csv", line, imu_row);
        if let Some(k) = options.max_imu_step {
            let step = k * plan.imu.period_s;
            let gap = row.t - previous.t;
            if gap > step {
                let steps = (gap / step).ceil();
                let lines = format!(
                    "{} to {}",
                    place("imu.csv", previous_line, imu_row - 1),
                    here()
                );
                if steps > MAX_GAP_STEPS {
                    return Err(RunError::Invalid(format!(
                        "imu.csv gap of {gap} s between {lines} is too long to propagate (more than {MAX_GAP_STEPS} steps of {step} s)"
                    )));
                }
                let mut w = Warning::about(
                    WarningKind::ImuGap,
                    "imu.csv",
                    format!(
                        "imu.csv gap of {gap} s between {lines}: propagated in {steps} steps holding the sample before it"
                    ),
                );
                w.line = line;
                if options.gap_warnings {
                    warnings.push(w);
                }
                let held = sample(&previous);
                for m in 1..steps as usize {
                    let t = previous.t + gap * (m as f64 / steps);
                    own.push_due(t, &mut nav)?;
                    while let Some(ev) = aiding.due(t) {
                        ev.push(&mut nav, &handles);
                        last_input = Some(ev);
                    }
                    nav.push_imu(t, held).map_err(|e| {
                        RunError::Invalid(format!("imu.csv gap between {lines} at t = {t} s: {e}"))
                    })?;
                    let mut result = Ok(());
                    nav.final_estimates(|_, e| {
                        if result.is_ok() {
                            result = waiting.hand(e, &mut out);
                        }
                    });
                    result?;
                }
            }
        }
        own.push_due(row.t, &mut nav)?;
        while let Some(ev) = aiding.due(row.t) {
            ev.push(&mut nav, &handles);
            last_input = Some(ev);
        }
        let next_t = stream.next_imu_t()?;
        let ticket = requests.take(row.t, next_t, tolerance, &mut waiting)?;
        if ticket {
            waiting.request(&mut nav, row.t);
        }
        waiting.hand_unmatched(&mut out)?;
        // The step and the estimates it makes final.
        let mut result = Ok(());
        let pushed = nav.push_imu(row.t, sample(&row));
        if pushed.is_ok() {
            nav.final_estimates(|_, e| {
                if result.is_ok() {
                    result = waiting.hand(e, &mut out);
                }
            });
        }
        pushed.map_err(|e| match e {
            // A refused sample; a propagation the filter could not take
            // (its own state no longer finite) is a divergence, below.
            NavigatorError::Imu(e) if !matches!(e, SchedulerError::Propagation(_)) => {
                RunError::Invalid(format!("imu.csv at t = {} s ({}): {e}", row.t, here()))
            }
            e => {
                let message = format!(
                    "{} (t = {} s): {e}{}",
                    here(),
                    row.t,
                    last_input.map_or(String::new(), |ev| format!(
                        "; latest aiding input: {}",
                        ev.place()
                    ))
                );
                if matches!(
                    e,
                    NavigatorError::OutOfBounds { .. }
                        | NavigatorError::Imu(SchedulerError::Propagation(_))
                ) {
                    RunError::Diverged {
                        message,
                        file: Some("imu.csv".into()),
                        line,
                    }
                } else {
                    RunError::Invalid(message)
                }
            }
        })?;
        if row.t > first.t {
            samples += 1;
        }
        result?;
        previous = row;
        previous_line = line;
    }
    // Rows after the last IMU sample, and fixes still travelling when the
    // IMU data ends (measured before its end).
    while let Some(ev) = stream.next_event()? {
        aiding.take(&ev);
    }
    while let Some(ev) = aiding.next() {
        ev.push(&mut nav, &handles);
    }
    own.push_rest(&mut nav)?;
    let mut result = Ok(());
    nav.flush_estimates(|_, e| {
        if result.is_ok() {
            result = waiting.hand(e, &mut out);
        }
    });
    result?;
    waiting.hand_unmatched(&mut out)?;
    let runtime_s = clock.seconds();

    let mut health = aiding.health;
    for (i, h) in health.iter_mut().enumerate() {
        let r = nav.report_of(i).health;
        h.accepted = r.accepted;
        h.gated = r.gated;
        h.rejected += r.rejected;
        h.skipped += r.skipped;
        h.stuck = r.stuck;
    }
    let mut final_filter = nav.filter().clone();
    let sensor_information = final_filter.sensor_information().cloned();
    let recording = final_filter
        .finish_recording()
        .map_err(|e| RunError::Invalid(e.to_string()))?;
    let layout = *final_filter.nominal().layout();
    let observability = match (&recording, options.observability) {
        (Some(store), true) => {
            let o = observability(
                &mut store.borrow_mut(),
                &prior_sigma,
                OBSERVABILITY_FLOOR,
                OBSERVABILITY_DIRECTIONS,
                sensor_information.as_ref(),
            )
            .map_err(smoother_error)?;
            Some(o)
        }
        _ => None,
    };
    if let (Some(store), Some(forward)) = (recording, smoothing.as_mut()) {
        let mut smoothed = smoothed_estimates(&mut store.borrow_mut(), forward, &layout)?;
        // Written latest first: popped, they come in the order handed on.
        let mut record = [0.0; SMOOTHING_RECORD];
        while smoothed.pop(&mut record).map_err(smoother_error)? {
            let (e, kind) = from_smoothing_record(&record);
            smoothed_sink(kind, e.as_ref())?;
        }
    }
    let repairs = final_filter.ekf().counters().covariance_repairs;
    let replays = nav.replays();
    let mut all_warnings = aiding.warnings;
    all_warnings.extend(warnings);
    all_warnings.append(&mut own.warnings);
    all_warnings.extend(unfed);
    all_warnings.extend(frozen_warnings(frozen));
    let recoveries = nav.recoveries().to_vec();
    all_warnings.extend(recoveries.iter().map(recovery_warning));
    // The four SDINS sensors always; the others when the vehicle has them
    // or the log has their file.
    let shown: Vec<usize> = (0..SENSORS)
        .filter(|&i| i < 4 || aiding.present[i] || has_file[i])
        .collect();
    let mut innovations: Vec<SensorInnovations> = shown
        .iter()
        .map(|&i| SensorInnovations {
            sensor: SENSOR_NAMES[i].to_string(),
            // The sigma the filter used: the section's, or the built-in
            // one a `missing_sensor_section` warning names. A GNSS fix
            // with the receiver's `eph`/`epv` has theirs, the section's as
            // a floor: no one sigma, so the innovations give a factor on
            // the sigmas used (docs/tuning.md).
            noise_sigma: (SENSOR_NAMES[i] != "gnss" || !aiding.receiver_sigmas)
                .then_some(plan.sensors[i].noise_sigma),
            gated: health[i].gated,
            setting: (
                "meta.toml".into(),
                format!("sensors.{}.noise_sigma", SENSOR_NAMES[i]),
            ),
            totals: nav.report_of(i).innovations,
        })
        .collect();
    innovations.extend(own.innovations(&nav));
    let mut health: Vec<_> = shown
        .iter()
        .map(|&i| (SENSOR_NAMES[i], health[i]))
        .collect();
    health.extend(own.health(&nav));
    Ok(InsRun {
        estimates: Vec::new(),
        imu_span: (first.t, previous.t),
        samples,
        health,
        innovations,
        magnetic_declination: facts.declination.unwrap_or((0.0, 0)),
        repairs,
        runtime_s,
        replays,
        ignored,
        smoothed: None,
        observability,
        warnings: all_warnings,
        dvl_mounting: super::calibration::DvlMounting::of(&final_filter, source.meta()),
        fix_mountings: super::calibration::FixMounting::all_of(&final_filter, source.meta()),
        bias_states: super::constant_states::constant_states(&final_filter, &prior_sigma),
        final_filter,
        recoveries,
    })
}

/// The warning of one recovery, about the sensor's file.
fn recovery_warning(r: &nav_ins::Recovery) -> Warning {
    let sensor = r.sensor;
    let rollback = if r.detected_s > r.t_s {
        format!(
            " here, at the run's second reading: the filter was taken back to the run's start from t = {:.3} s, where the run was found",
            r.detected_s
        )
    } else {
        String::new()
    };
    Warning::about(
        WarningKind::LockoutRecovery,
        &format!("{sensor}.csv"),
        format!(
            "t = {:.3} s: every {sensor} reading refused for {:.1} s while plausible and agreeing \
             with one another: the filter, not the {sensor}, was taken to be wrong and the \
             covariance of the states the {sensor} observes was inflated{rollback} (lock-out recovery)",
            r.t_s, r.refused_for_s
        ),
    )
}

/// The declared name of the sensor in the slot of log sensor `i` (index in
/// [`SENSOR_NAMES`]; the compass slot by `compass`).
fn slot_sensor_name<V: InsVehicle<N>, const N: usize>(
    i: usize,
    compass: CompassForm,
) -> &'static str {
    let names = nav_ins::declared::slotted_names::<V, N>();
    match i {
        0 => names[0],
        1 => names[1],
        2 if compass == CompassForm::SmallAngle => names[3],
        2 => names[2],
        k => names[k + 1],
    }
}

/// Prior sigmas at most this are the navigator's floor (a state known from
/// the start): left out of the observability report.
const OBSERVABILITY_FLOOR: f64 = 1.5e-9;

/// Weakest directions reported.
const OBSERVABILITY_DIRECTIONS: usize = 3;

/// The frozen runs `frozen` met, as warnings (never errors: the replay has
/// run). The frozen stretch is propagated with the frozen values, as a gap
/// would hold the sample before it; its covariance is not inflated.
fn frozen_warnings(frozen: FrozenImu) -> Vec<Warning> {
    let mut report = Report::default();
    let options = PreflightOptions {
        lenient: true,
        ..PreflightOptions::default()
    };
    frozen.finish(&options, &mut report);
    report
        .warnings()
        .cloned()
        .map(|mut w| {
            w.message
                .push_str("; the replay propagated through it with the frozen values");
            w
        })
        .collect()
}

/// The time spent in the filter ([`InsRun::runtime_s`]): the replay loop's
/// time less the time reading and parsing the log (measured per run of
/// rows read ahead, [`reading_time`]) and the time handing estimates on to
/// the output (measured per estimate). What is left is the filter's work
/// and the loop's own bookkeeping around it. No clock is read per sample:
/// two reads cost about 46 ns on this kind of machine, 6 % of a replayed
/// SDINS-25 sample (docs/performance-replay.md); sampling one call in many
/// instead aliased with the pattern of calls (a USBL log read 0.0 s on most
/// runs).
struct FilterTime {
    start: Instant,
    reading_at_start: Duration,
    /// Time handing estimates on (writing output).
    output: Cell<Duration>,
}

impl FilterTime {
    /// Starts the clock.
    fn start() -> Self {
        FilterTime {
            start: Instant::now(),
            reading_at_start: reading_time(),
            output: Cell::new(Duration::ZERO),
        }
    }

    /// Runs `f`, handing an estimate on, and counts its time as output.
    fn output<T>(&self, f: impl FnOnce() -> T) -> T {
        let t0 = Instant::now();
        let r = f();
        self.output.set(self.output.get() + t0.elapsed());
        r
    }

    /// The filter's time so far, s.
    fn seconds(&self) -> f64 {
        let reading = reading_time().saturating_sub(self.reading_at_start);
        self.start
            .elapsed()
            .saturating_sub(reading)
            .saturating_sub(self.output.get())
            .as_secs_f64()
    }
}

/// The plan of a run of `V` over `source`: each sensor's settings and
/// latency (the USBL's from the largest acoustic travel time of its fixes),
/// the queue of travelling aiding rows, and the warnings about what the log
/// leaves to defaults or the vehicle cannot represent.
fn plan_run<V: InsVehicle<N>, const N: usize>(
    source: &LogSource<'_>,
    options: &FilterOptions,
    facts: &LogFacts,
) -> Result<(LogPlan, Aiding), RunError> {
    let plan0 = LogPlan::new(source.meta(), facts, [0.0; SENSORS], V::INITIAL_SIGMA)?;
    plan0.within(&options.bounds)?;
    let aiding = Aiding::new::<V, N>(options, plan0.transducer);
    let (usbl_latency, has_usbl) = aiding.usbl_latency(source)?;
    let latencies: [f64; SENSORS] = std::array::from_fn(|i| {
        if i == 3 {
            if has_usbl {
                usbl_latency + 1.0
            } else {
                0.0
            }
        } else if options.delivery.is_late() {
            options.delivery.max_delay() + 0.1
        } else {
            0.0
        }
    });
    let mut plan = LogPlan::new(source.meta(), facts, latencies, V::INITIAL_SIGMA)?;
    // The PX4 defaults of the imported-log sensors are said when used.
    let sensors = &source.meta().sensors;
    for (present, missing, name, noise) in [
        (
            aiding.present[4],
            sensors.gnss.is_none(),
            "gnss",
            plan.sensors[4].noise_sigma,
        ),
        (
            aiding.present[5],
            sensors.baro.is_none(),
            "baro",
            plan.sensors[5].noise_sigma,
        ),
        (
            aiding.present[6],
            sensors.mag.is_none(),
            "mag",
            plan.sensors[6].noise_sigma,
        ),
    ] {
        if present && missing {
            plan.warnings.push(crate::missing_section(
                name,
                format!("meta.toml has no [sensors.{name}]: noise {noise} (PX4's default)"),
            ));
        }
    }
    // A depth lever arm is used only by a depth block that takes one.
    let lever_arm = plan.sensors[0].lever_arm;
    if lever_arm != Vector3::zeros() && <V::Depth as Slot<V, N, 1>>::AUX_NAMES.is_empty() {
        plan.warnings.push(crate::meta_note(
            "sensors.depth.lever_arm",
            format!(
                "meta.toml: sensors.depth.lever_arm {:?} m is not modelled by model {} (its depth block takes the reading at the IMU): ignored",
                lever_arm.as_slice(),
                V::REPLAY_NAME
            ),
        ));
        plan.sensors[0].lever_arm = Vector3::zeros();
    }
    Ok((plan, aiding))
}

fn sample(r: &ImuRow) -> ImuSample {
    ImuSample {
        gyro: Vector3::new(r.gx, r.gy, r.gz),
        accel: Vector3::new(r.ax, r.ay, r.az),
    }
}

/// What a request's estimate is to the smoother, for the smoothed sink of
/// [`replay_vehicle`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Smoothed {
    /// A requested output time ([`Listed`], [`Every`], the requests inside
    /// an [`EachSample`]).
    Requested,
    /// One of the samples [`EachSample::smoothing_every`] chose.
    Sample,
}

/// One request waiting: its payload and, when it is smoothed, its kind.
type Entry<P> = (P, Option<Smoothed>);

/// Requests taken from the request stream and not yet handed on, in request
/// order: groups of requests snapped to one IMU sample (`true`: one
/// navigator ticket) and requests no sample is near (`false`: handed on with
/// `None` in turn).
pub struct Waiting<P> {
    groups: VecDeque<(bool, Vec<Entry<P>>)>,
}

impl<P> Default for Waiting<P> {
    fn default() -> Self {
        Waiting {
            groups: VecDeque::new(),
        }
    }
}

/// Where a replay wants estimates: at each IMU sample (at `t`, the next one
/// at `next`), the requests it answers, queued in request order as groups in
/// `waiting`; true when the caller must ask the navigator for the estimate
/// at `t`. The work per sample is bounded by the requests taken, never by
/// the time a sample covers.
pub trait Requests<P> {
    /// Takes the requests of the sample at `t`.
    ///
    /// # Errors
    /// A request that cannot be read (e.g. a bad truth row).
    fn take(
        &mut self,
        t: f64,
        next: Option<f64>,
        tolerance: f64,
        waiting: &mut Waiting<P>,
    ) -> Result<bool, RunError>;
}

/// Output times listed in ascending order with their payloads: each goes to
/// its nearest IMU sample (at equal distance the earlier), with `None` for
/// the estimate when that sample is further than the tolerance.
pub struct Listed<Q: Iterator>(Peekable<Q>);

impl<Q: Iterator> Listed<Q> {
    /// The requests of `times`.
    pub fn new(times: Q) -> Self {
        Listed(times.peekable())
    }
}

impl<P, Q> Requests<P> for Listed<Q>
where
    Q: Iterator<Item = Result<(f64, P), RunError>>,
{
    fn take(
        &mut self,
        t: f64,
        next: Option<f64>,
        tolerance: f64,
        waiting: &mut Waiting<P>,
    ) -> Result<bool, RunError> {
        let requests = &mut self.0;
        let mut snapped = Vec::new();
        let mut ticket = false;
        loop {
            let rt = match requests.peek() {
                None => break,
                Some(Ok((rt, _))) => *rt,
                Some(Err(_)) => match requests.next() {
                    Some(Err(e)) => return Err(e),
                    _ => break,
                },
            };
            // Requests nearer the sample before were taken there.
            let mine =
                next.is_none_or(|tn| rt <= t || (rt <= tn && (rt - t).abs() <= (tn - rt).abs()));
            if !mine {
                break;
            }
            let Some(Ok((rt, p))) = requests.next() else {
                break;
            };
            let p = (p, Some(Smoothed::Requested));
            if (rt - t).abs() <= tolerance {
                snapped.push(p);
            } else {
                // Requests stay in order: the snapped ones before this one
                // form their group first.
                if !snapped.is_empty() {
                    waiting
                        .groups
                        .push_back((true, std::mem::take(&mut snapped)));
                    ticket = true;
                }
                waiting.groups.push_back((false, vec![p]));
            }
        }
        if !snapped.is_empty() {
            waiting.groups.push_back((true, snapped));
            ticket = true;
        }
        Ok(ticket)
    }
}

/// An estimate every `period_s` (s): at the first IMU sample at or after
/// each multiple of the period from the first sample; the payload is the
/// sample's time and `None`. A gap in the IMU data gives one estimate after
/// it, not one per period it covers.
#[derive(Clone, Copy, Debug)]
pub struct Every {
    origin: Option<f64>,
    period_s: f64,
    due: f64,
}

impl Every {
    /// Every `period_s` (s) from the first IMU sample.
    pub fn new(period_s: f64) -> Self {
        Every {
            origin: None,
            period_s,
            due: f64::NEG_INFINITY,
        }
    }
}

impl<T> Requests<(f64, Option<T>)> for Every {
    fn take(
        &mut self,
        t: f64,
        _next: Option<f64>,
        tolerance: f64,
        waiting: &mut Waiting<(f64, Option<T>)>,
    ) -> Result<bool, RunError> {
        let origin = *self.origin.get_or_insert(t);
        // A sample a hair before a multiple of the period counts as on it.
        if t + 1e-6 * tolerance < self.due {
            return Ok(false);
        }
        let k = ((t - origin) / self.period_s + 1e-9).floor() + 1.0;
        self.due = origin + k * self.period_s;
        waiting
            .groups
            .push_back((true, vec![((t, None), Some(Smoothed::Requested))]));
        Ok(true)
    }
}

/// An estimate at every IMU sample (payload `every(t)`), besides the
/// requests of `inner` (e.g. the truth rows): for a replay that compares
/// with another estimator's solution at its own times, by interpolation.
pub struct EachSample<R, F> {
    inner: R,
    every: F,
    /// Samples taken so far.
    samples: usize,
    /// Every how many samples one is smoothed (`None`: none).
    smoothed_every: Option<usize>,
}

impl<R, F> EachSample<R, F> {
    /// The requests of `inner` plus `every(t)` at each sample. With
    /// smoothing, the requests of `inner` are smoothed and the samples are
    /// not: an epoch of the recording at every sample would cost the
    /// recording a few covariance matrices per sample.
    pub fn new(inner: R, every: F) -> Self {
        EachSample {
            inner,
            every,
            samples: 0,
            smoothed_every: None,
        }
    }

    /// Also smooths every `k`-th sample (the `k`-th, `2k`-th, ... counted
    /// from 1), as [`Smoothed::Sample`]; `k` of 0 smooths none.
    #[must_use]
    pub fn smoothing_every(mut self, k: usize) -> Self {
        self.smoothed_every = (k > 0).then_some(k);
        self
    }
}

impl<P, R: Requests<P>, F: FnMut(f64) -> P> Requests<P> for EachSample<R, F> {
    fn take(
        &mut self,
        t: f64,
        next: Option<f64>,
        tolerance: f64,
        waiting: &mut Waiting<P>,
    ) -> Result<bool, RunError> {
        self.samples += 1;
        let smoothed = self
            .smoothed_every
            .is_some_and(|k| self.samples.is_multiple_of(k))
            .then_some(Smoothed::Sample);
        let p = ((self.every)(t), smoothed);
        if self.inner.take(t, next, tolerance, waiting)? {
            // The newest ticket group is this sample's: one estimate for both.
            if let Some((_, ps)) = waiting.groups.iter_mut().rev().find(|(ticket, _)| *ticket) {
                ps.push(p);
                return Ok(true);
            }
        }
        waiting.groups.push_back((true, vec![p]));
        Ok(true)
    }
}

/// Where the waiting requests' estimates go: the payload, the estimate and
/// its kind for the smoother.
type Out<'a, P> = dyn FnMut(P, Option<&Estimate>, Option<Smoothed>) -> Result<(), RunError> + 'a;

impl<P> Waiting<P> {
    /// Asks `nav` for the estimate of the newest ticket group at `t`, an
    /// epoch of the recording when a request of the group is smoothed.
    fn request<V: InsVehicle<N>, const N: usize>(&self, nav: &mut Navigator<V, N>, t: f64) {
        let smoothed = self
            .groups
            .iter()
            .rev()
            .find(|(ticket, _)| *ticket)
            .is_some_and(|(_, ps)| ps.iter().any(|(_, kind)| kind.is_some()));
        if smoothed {
            nav.request_estimate(t);
        } else {
            nav.request_estimate_unrecorded(t);
        }
    }

    /// Hands on the groups at the front that wait for no estimate.
    fn hand_unmatched(&mut self, out: &mut Out<'_, P>) -> Result<(), RunError> {
        while self.groups.front().is_some_and(|(ticket, _)| !ticket) {
            if let Some((_, ps)) = self.groups.pop_front() {
                for (p, kind) in ps {
                    out(p, None, kind)?;
                }
            }
        }
        Ok(())
    }

    /// Hands on the estimate of the oldest ticket (and the unmatched groups
    /// before and after it).
    fn hand(&mut self, e: Option<Estimate>, out: &mut Out<'_, P>) -> Result<(), RunError> {
        self.hand_unmatched(out)?;
        if let Some((_, ps)) = self.groups.pop_front() {
            for (p, kind) in ps {
                out(p, e.as_ref(), kind)?;
            }
        }
        self.hand_unmatched(out)
    }
}

fn smoother_error(e: SmootherError) -> RunError {
    RunError::Invalid(e.to_string())
}

/// The smoothed counterpart of each estimate of `forward` (written in the
/// order handed on), from the recorded epochs of `file` (every output time is
/// an epoch of the recording): the backward pass meets the epochs latest
/// first and the estimates are taken off the end of `forward` to match, so
/// the smoothed ones come latest first too, into the returned file.
fn smoothed_estimates<const N: usize>(
    file: &mut EpochFile<N, 0>,
    forward: &mut SpillFile,
    layout: &Layout,
) -> Result<SpillFile, RunError> {
    let mut out = SpillFile::create(None, SMOOTHING_RECORD).map_err(smoother_error)?;
    let mut record = [0.0; SMOOTHING_RECORD];
    // The latest estimate not yet matched (`None` inside: an estimate that
    // was not available) and its kind.
    let mut pop = |forward: &mut SpillFile| -> Result<Option<_>, SmootherError> {
        Ok(forward
            .pop(&mut record)?
            .then(|| from_smoothing_record(&record)))
    };
    let mut pending = pop(forward).map_err(smoother_error)?;
    // Only the covariance entries an estimate reports are smoothed at the
    // output epochs.
    let states = Estimate::covariance_states::<N>(layout);
    smooth_states(file, &states, |epoch| {
        // Later estimates than this epoch have no epoch; several requested
        // times may snap to one epoch.
        while let Some((e, kind)) = &pending {
            match e {
                Some(e) if e.t < epoch.time - 1e-9 => break,
                Some(e) if (e.t - epoch.time).abs() <= 1e-9 => {
                    let s = e.smoothed(&epoch.error, &epoch.covariance, layout);
                    out.push(&smoothing_record(Some(&s), *kind))?;
                }
                _ => out.push(&smoothing_record(None, *kind))?,
            }
            pending = pop(forward)?;
        }
        Ok(())
    })
    .map_err(smoother_error)?;
    while let Some((_, kind)) = pending {
        out.push(&smoothing_record(None, kind))
            .map_err(smoother_error)?;
        pending = pop(forward).map_err(smoother_error)?;
    }
    Ok(out)
}

/// Scalars of a record of the smoothing's spill files: an estimate
/// ([`Estimate::to_scalars`]) and its [`Smoothed`] kind.
const SMOOTHING_RECORD: usize = ESTIMATE_SCALARS + 1;

fn smoothing_record(e: Option<&Estimate>, kind: Smoothed) -> [f64; SMOOTHING_RECORD] {
    let mut record = [0.0; SMOOTHING_RECORD];
    record[..ESTIMATE_SCALARS].copy_from_slice(&Estimate::to_scalars(e));
    record[ESTIMATE_SCALARS] = match kind {
        Smoothed::Requested => 0.0,
        Smoothed::Sample => 1.0,
    };
    record
}

fn from_smoothing_record(record: &[f64; SMOOTHING_RECORD]) -> (Option<Estimate>, Smoothed) {
    let mut scalars = [0.0; ESTIMATE_SCALARS];
    scalars.copy_from_slice(&record[..ESTIMATE_SCALARS]);
    let kind = if record[ESTIMATE_SCALARS] == 0.0 {
        Smoothed::Requested
    } else {
        Smoothed::Sample
    };
    (Estimate::from_scalars(&scalars), kind)
}
