//! The replay of a declared model over a log directory: the input rows
//! propagate the filter, each sensor's rows update it at their own times
//! (through the multi-rate scheduler), the estimate after each input
//! sample's updates is scored against the truth and written out
//! (`docs/model-replay.md`, "What a replay does").
//!
//! The files are streamed: memory does not grow with the log.

use std::path::Path;
use std::time::Instant;

use nav_runtime::ekf::Ekf;
use nav_runtime::error_state::TotalState;
use nav_runtime::innovations::InnovationTotals;
use nav_runtime::log::{LogError, SkippedRow, Warning, WarningKind};
use nav_runtime::math::wrap_angle;
use nav_runtime::model::{Model, Record};
use nav_runtime::nalgebra::{Cholesky, SMatrix, SVector};
use nav_runtime::scheduler::{FnMeasurement, MeasurementOutcome, Report, Scheduler};
use nav_runtime::smoother::{observability, EpochFile, SmootherError, SpillFile};

use super::feed::Feed;
use super::mapping::Mapping;
use super::plots;
use super::smoothing::{self, Forward};
use super::table::MappedRows;
use super::{ModelFilter, ModelReplayError};
use crate::output::series::{BoundedTable, SeriesSink, PLOT_ROWS};

/// An input interval longer than this many of the shortest interval seen
/// is a gap: an error, or with [`RunOptions::lenient`] propagated in steps.
pub const MAX_GAP_PERIODS: f64 = 10.0;

/// The most steps a gap is propagated in.
pub const MAX_GAP_STEPS: f64 = 1e6;

/// Options of one replay.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RunOptions {
    /// Skip (and count) bad CSV rows instead of stopping, and propagate an
    /// input gap in steps (with a warning) instead of refusing it.
    pub lenient: bool,
    /// Write an estimate at most every this many seconds (`0`: after every
    /// input sample).
    pub output_period: f64,
    /// Record the run and report what it taught each state
    /// (`observability` of the JSON, docs/observability.md).
    pub observability: bool,
    /// Smooth the run after it (`smoothed` of the JSON, `smoothed.csv`;
    /// `docs/model-replay.md`, "Smoothing").
    pub smooth: bool,
}

/// What happened to one sensor's rows.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SensorSummary {
    /// The declared sensor name.
    pub name: &'static str,
    /// Its file (`None`: not mapped).
    pub file: Option<String>,
    /// Rows read.
    pub rows: u64,
    /// Applied.
    pub accepted: u64,
    /// Refused by the gate.
    pub gated: u64,
    /// Refused by the filter or the scheduler (non-finite values, a row
    /// before the initial epoch, an innovation covariance not positive).
    pub rejected: u64,
    /// Bad rows skipped by lenient reading.
    pub skipped_rows: u64,
    /// Mean NIS of the accepted updates (expected: `outputs`).
    pub nis_mean: Option<f64>,
    /// Number of outputs (the NIS's degrees of freedom).
    pub outputs: usize,
    /// Its gate probability (`None`: no gate).
    pub gate: Option<f64>,
    /// The innovations of its updates, applied or gated (docs/tuning.md).
    pub innovations: InnovationTotals,
}

/// The truth score of a run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct TruthScore {
    /// Input samples with a truth row within half an input period.
    pub scored: u64,
    /// `(state, RMS error)` of every state the truth file has (angles wrapped).
    pub rms: Vec<(&'static str, f64)>,
    /// Mean NEES over those states (expected: their number).
    pub nees_mean: f64,
    /// The NEES's degrees of freedom.
    pub nees_dof: usize,
}

/// The smoothed counterpart of a run ([`RunOptions::smooth`]).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SmoothedRun {
    /// Forward estimates given their smoothed counterpart.
    pub estimates: u64,
    /// Against the truth file, at the samples the forward run was scored.
    pub truth: Option<TruthScore>,
}

/// The result of a replay.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ModelRun {
    /// Input samples propagated.
    pub samples: u64,
    /// First and last input time used, s.
    pub span: (f64, f64),
    /// Seconds spent in the loop (reading included).
    pub runtime_s: f64,
    /// Per registered sensor.
    pub sensors: Vec<SensorSummary>,
    /// The final state and sigma, per state scalar.
    pub final_state: Vec<(&'static str, f64, f64)>,
    /// Against the truth file, when there is one and it scored a sample
    /// (otherwise a warning says so).
    pub truth: Option<TruthScore>,
    /// With [`RunOptions::smooth`]: the smoothed estimates (one per
    /// forward estimate) and, with a truth file, their score at the same
    /// samples as [`ModelRun::truth`].
    pub smoothed: Option<SmoothedRun>,
    /// Covariance repairs of the filter.
    pub covariance_repairs: u64,
    /// Bad rows skipped (lenient reading), per file.
    pub skipped_rows: Vec<(String, u64)>,
    /// The first reasons of the skipped rows.
    pub skip_reasons: Vec<SkippedRow>,
    /// What the user should know about the result.
    pub warnings: Vec<Warning>,
    /// What the run taught each state, as the JSON's `observability`
    /// (with [`RunOptions::observability`]).
    pub observability: Option<serde_json::Value>,
}

/// States the model's [`Model::normalize_state`] wraps to (-pi, pi]: the
/// states declared `angle`, whose errors are wrapped too.
pub fn angle_states<M: Model<N>, const N: usize>() -> [bool; N] {
    std::array::from_fn(nav_runtime::model::is_angle_state::<M, N>)
}

/// The blocks the model's [`Model::normalize_state`] renormalizes to unit
/// norm (states declared `quaternion`), as index ranges: `q` and `-q` are
/// the same attitude, so the truth score compares the estimate with the
/// truth of the same sign.
pub fn quaternion_blocks<M: Model<N>, const N: usize>() -> Vec<std::ops::Range<usize>> {
    let mut out = Vec::new();
    let mut i = 0;
    while i < N {
        let block = super::declared::block_of(M::STATE_NAMES[i]);
        let end = (i..N)
            .find(|&j| super::declared::block_of(M::STATE_NAMES[j]) != block)
            .unwrap_or(N);
        let mut x = SVector::<f64, N>::zeros();
        x[i] = 2.0;
        M::normalize_state(&mut x);
        if end - i > 1 && (x[i] - 1.0).abs() < 1e-12 {
            out.push(i..end);
        }
        i = end;
    }
    out
}

/// The sensor rows still to be pushed: the reader and its next row.
struct Pending {
    rows: MappedRows,
    next: Option<(u64, f64)>,
}

/// Runs model `M` with the sensors `feeds` over the log in `dir` as
/// `mapping` says; with `out`, writes `estimates.csv` there.
///
/// # Errors
/// A file or row the mapping cannot read, a filter set-up error, an input
/// row the filter refuses.
pub fn run<M: Model<N>, const N: usize>(
    dir: &Path,
    mapping_file: &str,
    mapping: &Mapping,
    feeds: &[Box<dyn Feed<M, N>>],
    options: &RunOptions,
    out: Option<&Path>,
) -> Result<ModelRun, ModelReplayError>
where
    Ekf<M, N>: Clone,
{
    let start = Instant::now();
    let mut run = ModelRun {
        warnings: mapping.warnings.clone(),
        ..ModelRun::default()
    };
    run.warnings.extend(mapping.unmapped_files(dir));
    let mut inputs = MappedRows::open(dir, &mapping.inputs, mapping_file, options.lenient)?
        .ok_or_else(|| ModelReplayError::Setup("no input file".into()))?;
    // Every input column, and each sensor's reading (not its auxiliary
    // inputs) and spacing, are checked as they are read.
    inputs.check(usize::MAX, false);
    let mut sensors: Vec<Option<Pending>> = Vec::with_capacity(feeds.len());
    for m in &mapping.sensors {
        sensors.push(match m {
            Some(m) => {
                MappedRows::open(dir, &m.source, mapping_file, options.lenient)?.map(|mut rows| {
                    rows.check(m.sigma.len(), true);
                    Pending { rows, next: None }
                })
            }
            None => None,
        });
    }
    let truth = MappedRows::open(dir, &mapping.truth, mapping_file, options.lenient)?;
    let angles = angle_states::<M, N>();
    let quaternions = quaternion_blocks::<M, N>();

    // The epoch: `[initial] t`, else the first input row. Input rows at or
    // before it hold over intervals that end before the filter starts.
    let mut before_epoch = 0u64;
    let first = loop {
        let Some((line, t)) = inputs.next_row()? else {
            return Err(ModelReplayError::Setup(format!(
                "{}: no input rows{}",
                inputs.file(),
                mapping.initial.t.map_or(String::new(), |t| format!(
                    " after the initial epoch t = {t} s"
                ))
            )));
        };
        match mapping.initial.t {
            Some(epoch) if t < epoch => before_epoch += 1,
            _ => break (line, t),
        }
    };
    let epoch = mapping.initial.t.unwrap_or(first.1);
    if before_epoch > 0 {
        run.warnings.push(Warning::about(
            WarningKind::OutsideImuSpan,
            inputs.file(),
            format!(
                "{}: {before_epoch} row(s) before the initial epoch t = {epoch} s are not used",
                inputs.file()
            ),
        ));
    }
    // The first input row at the epoch is the start; one after it is the
    // first interval.
    let record = |v: &[f64]| <M::Input as Record>::from_fn(|i| v[i]);
    // The first two intervals are read ahead: the first is checked for a
    // gap against the second like any other (an `[initial] t` long before
    // the first row, or a first row long before the rest, would otherwise
    // be one first-order step and the truth tolerance of its length).
    let mut ahead: std::collections::VecDeque<(u64, f64, M::Input)> =
        std::collections::VecDeque::with_capacity(2);
    if first.1 > epoch {
        ahead.push_back((first.0, first.1, record(inputs.values())));
    }
    while ahead.len() < 2 {
        match inputs.next_row()? {
            Some((line, t)) => ahead.push_back((line, t, record(inputs.values()))),
            None => break,
        }
    }
    let mut times = std::iter::once(epoch).chain(ahead.iter().map(|a| a.1));
    let mut intervals = Vec::with_capacity(2);
    let mut previous = times.next().unwrap_or(epoch);
    for t in times {
        intervals.push(t - previous);
        previous = t;
    }
    let Some(period) = intervals.iter().copied().reduce(f64::min) else {
        return Err(ModelReplayError::Setup(format!(
            "{}:{}: the only input row at or after the initial epoch t = {epoch} s: \
             nothing to propagate (a replay needs an input row after the epoch)",
            inputs.file(),
            first.0
        )));
    };

    let x0 = SVector::<f64, N>::from_iterator(mapping.initial.state.iter().copied());
    let p0 = SMatrix::<f64, N, N>::from_diagonal(&SVector::from_iterator(
        mapping.initial.sigma.iter().map(|s| s * s),
    ));
    let params = <M::Params as Record>::from_fn(|i| mapping.params[i]);
    let noise = <M::Noise as Record>::from_fn(|i| mapping.noise[i]);
    let ekf = Ekf::<M, N>::new(x0, p0, params, noise)
        .map_err(|e| ModelReplayError::Setup(format!("{mapping_file}: {e}")))?;
    let mut ekf = ModelFilter::<M, N>::new(ekf, TotalState::default());
    if options.observability || options.smooth {
        let flag = if options.smooth {
            "--smooth"
        } else {
            "--observability"
        };
        let setup = |e: String| ModelReplayError::Setup(format!("{flag}: {e}"));
        let file = EpochFile::create(None).map_err(|e| setup(e.to_string()))?;
        ekf.start_recording(file, epoch)
            .map_err(|e| setup(e.to_string()))?;
        if options.observability {
            ekf.track_sensor_information();
        }
    }
    for (feed, m) in feeds.iter().zip(&mapping.sensors) {
        if let Some(m) = m {
            feed.set_gate(&mut ekf, m.gate).map_err(|e| {
                ModelReplayError::Setup(format!("{mapping_file}: `{}.gate`: {e}", m.source.section))
            })?;
        }
    }
    run.sensors = feeds
        .iter()
        .zip(&mapping.sensors)
        .map(|(f, m)| {
            let d = f.declared();
            SensorSummary {
                name: d.name,
                file: m.as_ref().map(|m| m.source.file.clone()),
                outputs: d.outputs,
                gate: m.as_ref().and_then(|m| m.gate),
                ..SensorSummary::default()
            }
        })
        .collect();
    let mut nis_sum = vec![0.0; feeds.len()];

    // Sensor rows at or before the epoch: within one input period of it
    // they are applied at the epoch, earlier ones are refused.
    for (k, pending) in sensors.iter_mut().enumerate() {
        let Some(p) = pending else { continue };
        let Some(m) = &mapping.sensors[k] else {
            continue;
        };
        while let Some((line, t)) = p.rows.next_row()? {
            if t > epoch {
                p.next = Some((line, t));
                break;
            }
            let s = &mut run.sensors[k];
            if t < epoch - period {
                s.rejected += 1;
                continue;
            }
            match feeds[k].apply(&mut ekf, p.rows.values(), &m.sigma) {
                Ok(o) if o.accepted => {
                    s.accepted += 1;
                    nis_sum[k] += o.nis;
                    s.innovations.add(&o.statistics);
                }
                Ok(o) => {
                    s.gated += 1;
                    s.innovations.add(&o.statistics);
                }
                Err(_) => s.rejected += 1,
            }
        }
    }
    for s in &run.sensors {
        if s.rejected > 0 {
            run.warnings.push(Warning::about(
                WarningKind::OutsideImuSpan,
                s.file.as_deref().unwrap_or(""),
                format!(
                    "sensor {}: {} row(s) more than one input period before the initial epoch t = {epoch} s are not used",
                    s.name, s.rejected
                ),
            ));
        }
    }
    let before = run
        .sensors
        .iter()
        .map(|s| (s.accepted, s.gated, s.rejected))
        .collect::<Vec<_>>();

    // The initial estimate is the first the smoother corrects.
    if options.smooth {
        ekf.mark_epoch(epoch);
    }
    let mut scheduler = Scheduler::new(ekf, epoch)
        .map_err(|e| ModelReplayError::Setup(format!("scheduler: {e}")))?;
    let mut ids = Vec::with_capacity(feeds.len());
    for f in feeds {
        ids.push(
            scheduler
                .add_sensor(f.declared().name, 1.0, 0.0)
                .map_err(|e| ModelReplayError::Setup(format!("scheduler: {e}")))?,
        );
    }
    // Each estimate handed on is an epoch of the recording, marked through
    // the scheduler after the rows of its time, so that a re-propagation
    // marks it again.
    let epochs = if options.smooth {
        Some(
            scheduler
                .add_sensor("estimate epochs", 1.0, 0.0)
                .map_err(|e| ModelReplayError::Setup(format!("scheduler: {e}")))?,
        )
    } else {
        None
    };

    let columns = estimate_columns(&M::STATE_NAMES);
    let columns: Vec<&str> = columns.iter().map(String::as_str).collect();
    let mut estimates = SeriesSink::new(ESTIMATES_TABLE, &columns, out, false).map_err(output)?;
    let mut truth = truth.map(|rows| Truth { rows, next: None });
    if let Some(t) = truth.as_mut() {
        t.next = t.rows.next_row()?;
    }
    let has: Option<[bool; N]> = truth
        .as_ref()
        .map(|t| std::array::from_fn(|i| t.rows.has(i)));
    // A state whose truth column is misspelt is not scored: said.
    if let Some(t) = truth.as_ref() {
        run.warnings.extend(t.rows.near_miss_warnings());
    }
    let mut score = Score::<N>::new(has);
    // The truth rows met, thinned, for the plots.
    let truth_columns: Vec<&str> = std::iter::once("t").chain(M::STATE_NAMES).collect();
    let mut truth_plot = out
        .filter(|_| has.is_some())
        .map(|_| BoundedTable::new(TRUTH_TABLE, &truth_columns, PLOT_ROWS));
    let mut forward = options
        .smooth
        .then(Forward::<N>::create)
        .transpose()
        .map_err(|e| smoother(&e))?;
    let tolerance = 0.5 * period.max(1e-9);
    let mut last_written = f64::NEG_INFINITY;
    // Whether the estimate at `t` is written (`--every`), advancing the
    // output clock when it is.
    let mut due = |t: f64| {
        let due = t - last_written >= options.output_period * (1.0 - 1e-9);
        if due {
            last_written = t;
        }
        due
    };
    let mut t_last = epoch;
    let mut row = Vec::with_capacity(1 + 2 * N);
    // The estimate at `t`: scored, written when `due`, and handed to the
    // smoother when `marked` (an epoch of the recording).
    let mut write = |t: f64,
                     f: &ModelFilter<M, N>,
                     truth: Option<&mut Truth>,
                     due: bool,
                     marked: bool|
     -> Result<(), ModelReplayError> {
        let (x, p) = (f.ekf().state(), f.covariance());
        let values = truth.map(|tr| tr.at(t, tolerance)).transpose()?.flatten();
        if let Some(values) = values {
            score.add(x, p, values, (&angles, &quaternions));
            if let (Some(plot), Some(has)) = (truth_plot.as_mut(), &has) {
                row.clear();
                row.push(t);
                row.extend((0..N).map(|i| if has[i] { values[i] } else { f64::NAN }));
                plot.push(&row);
            }
        }
        if due && estimates.wanted() {
            estimate_row(&mut row, t, x, p);
            estimates.push(&row).map_err(output)?;
        }
        if let (Some(forward), true) = (forward.as_mut(), marked) {
            forward
                .push(t, due, x, values, has.as_ref())
                .map_err(|e| smoother(&e))?;
        }
        Ok(())
    };
    write(epoch, scheduler.filter(), truth.as_mut(), due(epoch), true)?;
    let mut shortest = if period > 0.0 { period } else { f64::INFINITY };
    // Gaps propagated in steps: how many, and the first.
    let (mut gaps, mut first_gap) = (0u64, None::<String>);

    loop {
        let (line, t, input) = match ahead.pop_front() {
            Some(h) => h,
            None => match inputs.next_row()? {
                Some((line, t)) => (line, t, record(inputs.values())),
                None => break,
            },
        };
        // Every sensor row up to this sample's time is queued first: it is
        // applied at its own time inside the interval.
        for (k, pending) in sensors.iter_mut().enumerate() {
            let (Some(p), Some(m)) = (pending.as_mut(), &mapping.sensors[k]) else {
                continue;
            };
            while let Some((_, tm)) = p.next {
                if tm > t {
                    break;
                }
                // A refusal is counted in the scheduler's sensor statistics.
                if let Ok(reports) = scheduler.push_measurement(
                    ids[k],
                    tm,
                    feeds[k].measurement(p.rows.values(), &m.sigma),
                ) {
                    add_nis(&reports, &mut nis_sum, &mut run.sensors);
                }
                p.next = p.rows.next_row()?;
            }
        }
        let refused = |e: nav_runtime::scheduler::SchedulerError| ModelReplayError::Filter {
            file: inputs.file().to_string(),
            line,
            t,
            problem: e.to_string(),
        };
        // A gap: an interval longer than MAX_GAP_PERIODS of the shortest
        // seen. One first-order step over it would be a wrong answer with
        // no warning.
        let dt = t - t_last;
        if dt > MAX_GAP_PERIODS * shortest {
            let steps = (dt / shortest).ceil();
            let problem = format!(
                "gap of {} s after t = {} s (more than {MAX_GAP_PERIODS} input periods of {} s)",
                to_micro(dt),
                to_micro(t_last),
                to_micro(shortest)
            );
            if !options.lenient || steps > MAX_GAP_STEPS {
                return Err(ModelReplayError::Filter {
                    file: inputs.file().to_string(),
                    line,
                    t,
                    problem: if options.lenient {
                        format!(
                            "{problem}: too long to propagate in steps (more than {MAX_GAP_STEPS})"
                        )
                    } else {
                        format!("{problem}; --lenient propagates it in steps of one period, holding this row's input")
                    },
                });
            }
            gaps += 1;
            first_gap.get_or_insert_with(|| format!("{}:{line}: {problem}", inputs.file()));
            for m in 1..steps as usize {
                let tm = t_last + dt * (m as f64 / steps);
                let reports = scheduler.push_imu(tm, input).map_err(refused)?;
                add_nis(&reports, &mut nis_sum, &mut run.sensors);
            }
        } else if dt > 0.0 {
            shortest = shortest.min(dt);
        }
        // The smoother corrects the estimates written or scored: only
        // those are epochs of the recording.
        let written = due(t);
        let mut marked = false;
        if let Some(id) = epochs {
            let scored = match truth.as_mut() {
                Some(tr) => tr.at(t, tolerance)?.is_some(),
                None => false,
            };
            marked = written || scored;
            if marked {
                // Refused only for a non-finite time, which the input row
                // cannot have.
                let _ = scheduler.push_measurement(id, t, Box::new(epoch_mark(t)));
            }
        }
        let reports = scheduler.push_imu(t, input).map_err(refused)?;
        add_nis(&reports, &mut nis_sum, &mut run.sensors);
        run.samples += 1;
        t_last = t;
        write(t, scheduler.filter(), truth.as_mut(), written, marked)?;
    }
    if let Some(first) = first_gap {
        run.warnings.push(Warning::about(
            WarningKind::ImuGap,
            inputs.file(),
            format!(
                "{gaps} input gap(s) propagated in steps holding the sample after each (first: {first})"
            ),
        ));
    }
    // Sensor rows after the last input sample are not used.
    for (k, pending) in sensors.iter_mut().enumerate() {
        let Some(p) = pending.as_mut() else { continue };
        let mut after = 0u64;
        while p.next.is_some() {
            after += 1;
            p.next = p.rows.next_row()?;
        }
        if after > 0 {
            run.warnings.push(Warning::about(
                WarningKind::OutsideImuSpan,
                p.rows.file(),
                format!(
                    "sensor {}: {after} row(s) after the last input sample (t = {t_last} s) are not used",
                    run.sensors[k].name
                ),
            ));
        }
        run.sensors[k].rows = p.rows.rows;
        run.sensors[k].skipped_rows = p.rows.skipped_rows;
    }
    let estimates = estimates.finish().map_err(output)?;

    let filter = scheduler.filter();
    for (k, s) in run.sensors.iter_mut().enumerate() {
        let st = scheduler.sensor_stats(ids[k]).unwrap_or_default();
        let (a, g, r) = before[k];
        s.accepted = a + st.accepted;
        s.gated = g + st.gated;
        s.rejected = r + st.failed + st.too_old + st.duplicate + st.invalid + st.queue_full;
        s.nis_mean = (s.accepted > 0).then(|| nis_sum[k] / s.accepted as f64);
    }
    run.span = (epoch, t_last);
    run.final_state = M::STATE_NAMES
        .iter()
        .enumerate()
        .map(|(i, n)| {
            (
                *n,
                filter.ekf().state()[i],
                filter.covariance()[(i, i)].sqrt(),
            )
        })
        .collect();
    run.covariance_repairs = filter.ekf().counters().covariance_repairs;
    // The recording, ended on a copy of the filter: what the run taught
    // each state, and the smoothed pass.
    let mut recorded = filter.clone();
    let information = recorded.sensor_information().cloned();
    let store = recorded.finish_recording().map_err(|e| smoother(&e))?;
    if let (true, Some(store)) = (options.observability, &store) {
        let prior: [f64; N] = std::array::from_fn(|i| mapping.initial.sigma[i]);
        let o = observability(
            &mut store.borrow_mut(),
            &prior,
            0.0,
            OBSERVABILITY_DIRECTIONS,
            information.as_ref(),
        )
        .map_err(|e| ModelReplayError::Setup(format!("--observability: {e}")))?;
        let (json, unlearned) = crate::observability::json(&o, &M::STATE_NAMES, |_, _| Some(""));
        run.observability = Some(json);
        run.warnings.extend(unlearned);
    }
    run.truth = score.finish(&M::STATE_NAMES);
    let mut smoothed = None;
    if let (Some(forward), Some(store)) = (forward.as_mut(), &store) {
        let mut sink = SeriesSink::new(SMOOTHED_TABLE, &columns, out, false).map_err(output)?;
        // The smoothed estimates come latest first: reversed through a
        // temporary file into `smoothed.csv`.
        let mut reversed = sink
            .wanted()
            .then(|| SpillFile::create(None, 1 + 2 * N))
            .transpose()
            .map_err(|e| smoother(&e))?;
        let mut smoothed_score = Score::<N>::new(has);
        let mut count = 0u64;
        let unmatched = smoothing::smooth::<M, N>(&mut store.borrow_mut(), forward, |e| {
            count += 1;
            if let Some(truth) = &e.truth {
                smoothed_score.add(&e.x, &e.p, truth, (&angles, &quaternions));
            }
            match reversed.as_mut() {
                Some(file) if e.written => {
                    estimate_row(&mut row, e.t, &e.x, &e.p);
                    file.push(&row)
                }
                _ => Ok(()),
            }
        })
        .map_err(|e| smoother(&e))?;
        if let Some(file) = reversed.as_mut() {
            row.resize(1 + 2 * N, 0.0);
            while file.pop(&mut row).map_err(|e| smoother(&e))? {
                sink.push(&row).map_err(output)?;
            }
        }
        if unmatched > 0 {
            run.warnings.push(Warning {
                kind: WarningKind::Model,
                file: None,
                line: None,
                key: None,
                message: format!(
                    "--smooth: {unmatched} estimate(s) have no epoch in the recording and no smoothed counterpart"
                ),
            });
        }
        smoothed = sink.finish().map_err(output)?;
        run.smoothed = Some(SmoothedRun {
            estimates: count,
            truth: smoothed_score.finish(&M::STATE_NAMES),
        });
    }
    if let Some(dir) = out {
        plots::write(
            dir,
            M::NAME,
            &M::STATE_NAMES,
            &plots::Tables {
                estimates: estimates.as_ref(),
                truth: truth_plot.map(BoundedTable::into_table).as_ref(),
                smoothed: smoothed.as_ref(),
            },
        )
        .map_err(output)?;
    }
    for rows in std::iter::once(&inputs)
        .chain(sensors.iter().flatten().map(|p| &p.rows))
        .chain(truth.iter().map(|t| &t.rows))
    {
        if rows.skipped_rows > 0 {
            run.skipped_rows
                .push((rows.file().to_string(), rows.skipped_rows));
            run.skip_reasons.extend(rows.skipped.iter().cloned());
        }
        // Sensor glitches: rows skipped, never fed to the filter.
        if let Some(r) = &rows.rejected {
            run.warnings.push(r.warning());
        }
        run.warnings.extend(rows.row_warnings());
    }
    warn_about_result(&mut run, truth.as_ref().map(|t| t.rows.file()));
    run.runtime_s = start.elapsed().as_secs_f64();
    Ok(run)
}

/// Weakest directions reported with `--observability`.
const OBSERVABILITY_DIRECTIONS: usize = 3;

/// The warnings a result needs to be read right: a sensor that never
/// corrected the filter, an NIS or NEES far from its expectation, repairs.
fn warn_about_result(run: &mut ModelRun, truth_file: Option<&str>) {
    let mut warnings = Vec::new();
    for s in &run.sensors {
        let Some(file) = &s.file else { continue };
        if s.rows == 0 {
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                file,
                format!(
                    "sensor {}: {file} has no rows: the sensor never corrected the estimate",
                    s.name
                ),
            ));
        } else if s.accepted == 0 {
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                file,
                format!(
                    "sensor {}: none of its {} rows was applied ({} gated, {} rejected)",
                    s.name, s.rows, s.gated, s.rejected
                ),
            ));
        } else if s.gated + s.rejected > s.accepted {
            // Most rows refused: the sensor hardly corrected the estimate
            // (time stamps in another unit, a wrong sigma or column).
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                file,
                format!(
                    "sensor {}: only {} of its {} rows were applied ({} gated, {} rejected)",
                    s.name, s.accepted, s.rows, s.gated, s.rejected
                ),
            ));
        }
        // More rows gated than a consistent sensor's gate would refuse (a
        // lever arm or a sign of the mapping, a sigma too small): tens of
        // times its share, and at least one in twenty.
        if let Some(p) = s.gate {
            let gated = s.gated as f64 / s.rows.max(1) as f64;
            if s.rows >= 20 && s.gated <= s.accepted && gated > (10.0 * (1.0 - p)).max(0.05) {
                warnings.push(Warning::about(
                    WarningKind::Suspicious,
                    file,
                    format!(
                        "sensor {}: {} of its {} rows were gated ({:.1} %), where its gate (p = {p}) \
                         refuses {:.2} % of a consistent sensor's: a lever arm, sign or sigma of the mapping?",
                        s.name,
                        s.gated,
                        s.rows,
                        100.0 * gated,
                        100.0 * (1.0 - p)
                    ),
                ));
            }
        }
        if let Some(nis) = s.nis_mean {
            let dof = s.outputs as f64;
            if s.accepted >= 20 && (nis > 3.0 * dof || nis < dof / 3.0) {
                warnings.push(Warning::about(
                    WarningKind::Suspicious,
                    file,
                    format!(
                        "sensor {}: mean NIS {nis:.3} for {} output{}: its sigma or the process noise does not match the log",
                        s.name,
                        s.outputs,
                        if s.outputs == 1 { "" } else { "s" }
                    ),
                ));
            }
        }
    }
    // Rows skipped by lenient reading, with their reasons (the first few of
    // each file; all are counted in `skipped_rows`).
    for r in &run.skip_reasons {
        warnings.push(Warning::about(
            WarningKind::SkippedRow,
            &r.file,
            format!("skipped {r}"),
        ));
    }
    warnings.extend(crate::covariance_repairs(run.covariance_repairs));
    if let Some(file) = truth_file {
        // The same rule as the NIS: a filter whose sigmas do not cover its
        // errors (or far exceed them) gives RMS errors that its own sigmas
        // do not describe; forward and smoothed alike.
        let nees_warning = |t: &TruthScore, which: &str| {
            let dof = t.nees_dof as f64;
            if !t.nees_mean.is_finite() {
                let mut w = crate::nees_not_a_number(file);
                w.message.insert_str(0, which);
                return Some(w);
            }
            (t.scored >= 20 && (t.nees_mean > 3.0 * dof || t.nees_mean < dof / 3.0)).then(|| {
                Warning::about(
                    WarningKind::Suspicious,
                    file,
                    format!(
                        "{which}mean NEES {:.3} for {} scored states over {} samples: the filter's sigmas do not describe its errors against {file}",
                        t.nees_mean, t.nees_dof, t.scored
                    ),
                )
            })
        };
        match &run.truth {
            Some(t) if t.scored > 0 => {
                warnings.extend(nees_warning(t, ""));
                let smoothed = run.smoothed.as_ref().and_then(|s| s.truth.as_ref());
                warnings.extend(smoothed.and_then(|s| nees_warning(s, "smoothed: ")));
            }
            _ => warnings.push(Warning::about(
                WarningKind::PartialScoring,
                file,
                format!("{file} has no row within half an input period of an input sample: nothing is scored"),
            )),
        }
    }
    run.warnings.extend(warnings);
}

/// A time in a message, rounded to the microsecond (a difference of two
/// times prints as `4.2`, not `4.199999999999999`).
fn to_micro(seconds: f64) -> f64 {
    (seconds * 1e6).round() / 1e6
}

/// The accepted NIS of the reports, summed per sensor.
fn add_nis(reports: &[Report], nis_sum: &mut [f64], sensors: &mut [SensorSummary]) {
    for r in reports {
        if let Ok(o) = &r.outcome {
            if o.accepted {
                if let Some(s) = nis_sum.get_mut(r.sensor.index()) {
                    *s += o.nis;
                }
            }
            // Each update counted once, when first applied.
            if !r.replay {
                if let Some(s) = sensors.get_mut(r.sensor.index()) {
                    s.innovations.add(&o.statistics);
                }
            }
        }
    }
}

/// The truth file and its next row.
struct Truth {
    rows: MappedRows,
    next: Option<(u64, f64)>,
}

impl Truth {
    /// The truth values at `t` (the row within `tolerance`), passing the
    /// rows before it.
    fn at(&mut self, t: f64, tolerance: f64) -> Result<Option<&[f64]>, ModelReplayError> {
        while let Some((_, tt)) = self.next {
            if tt >= t - tolerance {
                break;
            }
            self.next = self.rows.next_row()?;
        }
        Ok(match self.next {
            Some((_, tt)) if (tt - t).abs() <= tolerance => Some(self.rows.values()),
            _ => None,
        })
    }
}

/// The running truth score.
struct Score<const N: usize> {
    /// Which states the truth has (`None`: no truth file).
    has: Option<[bool; N]>,
    squares: [f64; N],
    nees: f64,
    scored: u64,
}

impl<const N: usize> Score<N> {
    fn new(has: Option<[bool; N]>) -> Self {
        Score {
            has,
            squares: [0.0; N],
            nees: 0.0,
            scored: 0,
        }
    }

    fn add(
        &mut self,
        x: &SVector<f64, N>,
        p: &SMatrix<f64, N, N>,
        truth: &[f64],
        (angles, quaternions): (&[bool; N], &[std::ops::Range<usize>]),
    ) {
        let Some(has) = self.has else { return };
        if !has.iter().any(|h| *h) {
            return;
        }
        // A truth quaternion of the other sign is the same attitude.
        let mut sign = [1.0; N];
        for q in quaternions {
            let dot: f64 = q
                .clone()
                .map(|i| x[i] * truth[i])
                .filter(|v| v.is_finite())
                .sum();
            if dot < 0.0 {
                q.clone().for_each(|i| sign[i] = -1.0);
            }
        }
        // The error of the states the truth has; the others get a unit
        // variance and no error, so the NEES is that of the scored states.
        let mut e = SVector::<f64, N>::zeros();
        let mut ps = *p;
        for i in 0..N {
            if has[i] {
                let d = x[i] - sign[i] * truth[i];
                e[i] = if angles[i] { wrap_angle(d) } else { d };
            } else {
                for j in 0..N {
                    ps[(i, j)] = 0.0;
                    ps[(j, i)] = 0.0;
                }
                ps[(i, i)] = 1.0;
            }
        }
        for i in 0..N {
            self.squares[i] += e[i] * e[i];
        }
        if let Some(c) = Cholesky::new(ps) {
            self.nees += e.dot(&c.solve(&e));
        }
        self.scored += 1;
    }

    /// The score; `None` without a truth file or when nothing was scored
    /// (an RMS of zero samples is not a number to print).
    fn finish(self, names: &[&'static str; N]) -> Option<TruthScore> {
        let has = self.has?;
        if self.scored == 0 {
            return None;
        }
        let n = self.scored as f64;
        Some(TruthScore {
            scored: self.scored,
            rms: (0..N)
                .filter(|&i| has[i])
                .map(|i| (names[i], (self.squares[i] / n).sqrt()))
                .collect(),
            nees_mean: self.nees / n,
            nees_dof: has.iter().filter(|h| **h).count(),
        })
    }
}

/// Name of the table of forward estimates (`estimates.csv`).
pub const ESTIMATES_TABLE: &str = "estimates";

/// Name of the table of smoothed estimates (`smoothed.csv`, `--smooth`).
pub const SMOOTHED_TABLE: &str = "smoothed";

/// Name of the thinned table of truth rows the plots draw.
const TRUTH_TABLE: &str = "truth";

/// The columns of `estimates.csv` and `smoothed.csv`: time, each state, and
/// each state's sigma (`sigma_<state>`).
fn estimate_columns(names: &[&str]) -> Vec<String> {
    std::iter::once("t".to_string())
        .chain(names.iter().map(|n| (*n).to_string()))
        .chain(names.iter().map(|n| format!("sigma_{n}")))
        .collect()
}

/// One row of `estimates.csv` (see [`estimate_columns`]) into `row`.
fn estimate_row<const N: usize>(
    row: &mut Vec<f64>,
    t: f64,
    x: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
) {
    row.clear();
    row.push(t);
    row.extend(x.iter());
    row.extend((0..N).map(|i| p[(i, i)].sqrt()));
}

/// An output file that could not be written.
fn output(e: crate::RunError) -> ModelReplayError {
    match e {
        crate::RunError::Io { path, source } => LogError::Io { path, source }.into(),
        e => ModelReplayError::Setup(e.to_string()),
    }
}

/// A failure of the recording or of the smoother's temporary files.
fn smoother(e: &SmootherError) -> ModelReplayError {
    ModelReplayError::Setup(format!("--smooth: {e}"))
}

/// The scheduler's measurement that marks the estimate at `t` as an epoch
/// of the recording ([`RunOptions::smooth`]).
fn epoch_mark<M: Model<N>, const N: usize>(
    t: f64,
) -> FnMeasurement<
    impl Fn(&mut ModelFilter<M, N>) -> Result<MeasurementOutcome, nav_runtime::ekf::FilterError>,
> {
    FnMeasurement::new(&[], move |f: &mut ModelFilter<M, N>| {
        f.mark_epoch(t);
        Ok(MeasurementOutcome::marker())
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A mean NEES outside a factor of three of its degrees of freedom is a
    /// warning, forward and smoothed alike, each saying which it is.
    #[test]
    fn a_nees_off_by_three_is_said_forward_and_smoothed() {
        let score = |nees_mean: f64| TruthScore {
            scored: 100,
            rms: Vec::new(),
            nees_mean,
            nees_dof: 2,
        };
        // (forward NEES, smoothed NEES, the warnings' messages begin with)
        let cases: [(f64, Option<f64>, &[&str]); 5] = [
            (2.0, None, &[]),
            (2.0, Some(2.5), &[]),
            (7.0, Some(2.0), &["mean NEES 7.000"]),
            (2.0, Some(9000.0), &["smoothed: mean NEES 9000.000"]),
            (
                0.5,
                Some(0.1),
                &["mean NEES 0.500", "smoothed: mean NEES 0.100"],
            ),
        ];
        for (forward, smoothed, expected) in cases {
            let mut run = ModelRun {
                truth: Some(score(forward)),
                smoothed: smoothed.map(|s| SmoothedRun {
                    estimates: 100,
                    truth: Some(score(s)),
                }),
                ..ModelRun::default()
            };
            warn_about_result(&mut run, Some("truth.csv"));
            let got: Vec<&str> = run.warnings.iter().map(|w| w.message.as_str()).collect();
            assert_eq!(got.len(), expected.len(), "{forward} {smoothed:?}: {got:?}");
            for (w, e) in got.iter().zip(expected) {
                assert!(w.starts_with(e), "{w} against {e}");
            }
        }
    }
}
