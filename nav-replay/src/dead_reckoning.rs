//! Plain DVL dead reckoning (`navsim replay DIR --model dvl-dr`): the
//! baseline a DVL-aided filter has to beat on the same log
//! (docs/guide/real-logs.md, "Compare with dead reckoning"). No filter:
//!
//! - the attitude is `[initial]`'s, carried by the gyro alone (each IMU
//!   sample held over the interval that follows it, as the filters hold
//!   it), with the Earth's rate and the transport rate removed;
//! - each DVL reading with bottom lock, turned into body axes by
//!   `[sensors.dvl] misalignment` and less `omega x r` for its
//!   `lever_arm`, is rotated to north-east-down by the attitude at its time;
//! - the position is the integral of that velocity, linear between
//!   readings (the `[initial]` velocity before the first one, the last
//!   reading's after it), from the `[initial]` position at its epoch.
//!
//! The log is read as every replay reads it, so the DVL's clock, axes and
//! offsets are those the filter gets; scored against `truth.csv` with the
//! filters' scoring, without the NEES (there is no covariance). It is
//! streamed in time order: memory does not grow with the log
//! (docs/trust.md).

use std::collections::VecDeque;
use std::path::Path;

use nav_runtime::attitude::Euler;
use nav_runtime::earth::{earth_rate_n, meridian_radius, transport_rate_n, transverse_radius};
use nav_runtime::log::{DvlRow, Event, LogSource, Row, RowSource, TruthRow, Warning, WarningKind};
use nav_runtime::nalgebra::{Matrix3, Rotation3, SMatrix, Vector3};
use nav_runtime::strapdown::NavState;

use crate::ins::output::{TRAJECTORY_COLUMNS, TRAJECTORY_TABLE};
use crate::ins::score::{Keep, Scorer, TABLE};
use crate::ins::setup::Estimate;
use crate::output::series::SeriesSink;
use crate::{ReplayModel, ReplayOptions, ReplayOutput, RunError};

/// The model's name on the command line.
pub const NAME: &str = "dvl-dr";

/// A stretch without a DVL reading longer than this is a warning, s: the
/// velocity is interpolated across it.
const GAP_WARNING_S: f64 = 10.0;

/// `navsim replay DIR --model dvl-dr`: plain DVL dead reckoning.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeadReckoning;

/// A truth row waiting for the DVL reading after it (the velocity is
/// linear between readings), with the attitude at its time.
struct Waiting {
    line: Option<u64>,
    row: TruthRow,
    c_bn: Matrix3<f64>,
}

/// The dead reckoning as the log streams by, in time order: the attitude
/// carried through the IMU rows, the position integrated from one DVL
/// reading (a knot of the velocity) to the next. What it holds does not
/// grow with the log: the truth rows between two readings wait for the
/// second.
struct Reckoning {
    t0: f64,
    lat0: f64,
    h0: f64,
    misalignment: Matrix3<f64>,
    arm: Vector3<f64>,
    /// The attitude at `t_att`, and the body rate of the IMU sample held
    /// there (rad/s).
    c_bn: Matrix3<f64>,
    t_att: f64,
    rate: Vector3<f64>,
    /// The latest knot: its time and NED velocity (the epoch's before the
    /// first reading).
    knot: (f64, Vector3<f64>),
    readings: usize,
    /// The position (latitude, longitude rad; height m) integrated to
    /// `t_pos`.
    t_pos: f64,
    position: (f64, f64, f64),
    waiting: VecDeque<Waiting>,
    /// Readings since the latest IMU row: each becomes a knot at the next
    /// IMU row (which, at the reading's own time, is the sample held from
    /// it on), or at the end when within the IMU's span.
    deferred: Vec<Deferred>,
    imu: ImuSpan,
    longest_gap: (f64, f64),
}

/// A DVL reading waiting for the IMU row after it: its time, body-axes
/// velocity (m/s), the attitude at its time and the body rate held there.
struct Deferred {
    t: f64,
    v: Vector3<f64>,
    c_bn: Matrix3<f64>,
    rate: Vector3<f64>,
}

/// The IMU rows seen: the first and last time and how many.
#[derive(Clone, Copy, Default)]
struct ImuSpan {
    first: Option<f64>,
    last: f64,
    rows: usize,
}

impl ImuSpan {
    /// The end of the last row's interval: one mean interval after it.
    fn end(&self) -> f64 {
        let Some(first) = self.first else {
            return f64::NEG_INFINITY;
        };
        let period = if self.rows > 1 {
            (self.last - first) / (self.rows - 1) as f64
        } else {
            0.0
        };
        self.last + period
    }
}

/// Where the dead reckoning's solutions go: the scorer (truth rows) and
/// the track (one row per DVL reading).
struct Sinks {
    scorer: Option<Scorer>,
    track: SeriesSink,
}

impl Reckoning {
    /// # Errors
    /// `[initial]` lacks the position or the attitude.
    fn new(source: &LogSource<'_>) -> Result<Self, RunError> {
        let meta = source.meta();
        let init = &meta.initial;
        let [lat0, lon0, depth0] = init.position_for(NAME)?;
        let [roll, pitch, yaw] = init.attitude()?;
        let mounting = meta.sensors.mounting("dvl");
        let misalignment = mounting.map_or(Matrix3::identity(), |m| {
            let [roll, pitch, yaw] = m.misalignment;
            Euler { roll, pitch, yaw }.c_bn()
        });
        let t0 = init.t.unwrap_or(f64::NAN);
        Ok(Reckoning {
            t0,
            lat0,
            h0: -depth0,
            misalignment,
            arm: Vector3::from(mounting.map_or([0.0; 3], |m| m.lever_arm)),
            c_bn: Euler { roll, pitch, yaw }.c_bn(),
            t_att: t0,
            rate: Vector3::zeros(),
            knot: (t0, Vector3::new(init.vn, init.ve, init.vd)),
            readings: 0,
            t_pos: t0,
            position: (lat0, lon0, -depth0),
            waiting: VecDeque::new(),
            deferred: Vec::new(),
            imu: ImuSpan::default(),
            longest_gap: (0.0, t0),
        })
    }

    /// Carries the attitude to `t` (not before its current time) with the
    /// held sample and the navigation frame's rate at the epoch's position
    /// and the latest knot's velocity.
    fn turn_to(&mut self, t: f64) {
        let dt = t - self.t_att;
        if dt > 0.0 {
            let w_in = earth_rate_n(self.lat0) + transport_rate_n(self.lat0, self.h0, &self.knot.1);
            let body = Rotation3::from_scaled_axis(self.rate * dt);
            let frame = Rotation3::from_scaled_axis(-w_in * dt);
            self.c_bn = frame.matrix() * self.c_bn * body.matrix();
            self.t_att = t;
        }
    }

    /// An IMU row: the sample held from its time on.
    fn imu(&mut self, t: f64, rate: Vector3<f64>, sinks: &mut Sinks) -> Result<(), RunError> {
        if self.imu.first.is_none() && self.t0.is_nan() {
            // No `[initial] t`: the epoch is the first IMU row.
            self.t0 = t;
            self.t_att = t;
            self.t_pos = t;
            self.knot.0 = t;
            self.longest_gap.1 = t;
        }
        let first = self.imu.first.is_none();
        if first {
            // Before its first row the log's first sample is held.
            self.rate = rate;
        }
        self.imu.first.get_or_insert(t);
        self.imu.last = t;
        self.imu.rows += 1;
        for d in std::mem::take(&mut self.deferred) {
            let held = if d.t == t || first { rate } else { d.rate };
            self.knot_of(&d, held, sinks)?;
        }
        self.turn_to(t);
        self.rate = rate;
        Ok(())
    }

    /// The knot of reading `d` with the body rate `rate` held at its time:
    /// the reading less `omega x r`, turned to north-east-down.
    fn knot_of(
        &mut self,
        d: &Deferred,
        rate: Vector3<f64>,
        sinks: &mut Sinks,
    ) -> Result<(), RunError> {
        let body = self.misalignment * d.v - rate.cross(&self.arm);
        self.knot_at(d.t, d.c_bn * body, d.c_bn, sinks)
    }

    /// A DVL reading with bottom lock at `t`, body axes (m/s).
    fn reading(&mut self, t: f64, v: [f64; 3]) {
        // Before the epoch (or, without `[initial] t`, before the first
        // IMU row: the epoch is still NaN) there is nothing to carry.
        if self.t0.is_nan() || t < self.t0 {
            return;
        }
        self.turn_to(t);
        self.deferred.push(Deferred {
            t,
            v: Vector3::from(v),
            c_bn: self.c_bn,
            rate: self.rate,
        });
    }

    /// A knot of the velocity at `t`: the truth rows waiting before it
    /// get their solutions, the track its row.
    fn knot_at(
        &mut self,
        t: f64,
        v_n: Vector3<f64>,
        c_bn: Matrix3<f64>,
        sinks: &mut Sinks,
    ) -> Result<(), RunError> {
        let (t_a, _) = self.knot;
        if self.readings > 0 && t - t_a > self.longest_gap.0 {
            self.longest_gap = (t - t_a, t_a);
        }
        let next = (t, v_n);
        while self.waiting.front().is_some_and(|w| w.row.t <= t) {
            let w = self.waiting.pop_front().unwrap_or_else(|| unreachable!());
            self.integrate_to(w.row.t, Some(next));
            let fix = self.fix(w.row.t, Some(next), w.c_bn);
            score(sinks, w.line, &w.row, Some(&fix))?;
        }
        self.integrate_to(t, Some(next));
        self.knot = next;
        self.readings += 1;
        if sinks.track.wanted() {
            let fix = self.fix(t, None, c_bn);
            sinks.track.push(&track_row(&fix.nav, t))?;
        }
        Ok(())
    }

    /// The velocity at `t`: linear from the latest knot to `next`, held
    /// after the latest knot without one.
    fn velocity(&self, t: f64, next: Option<(f64, Vector3<f64>)>) -> Vector3<f64> {
        let (ta, va) = self.knot;
        match next {
            Some((tb, vb)) if tb > ta => va + (vb - va) * ((t - ta) / (tb - ta)),
            _ => va,
        }
    }

    /// Integrates the position to `t` (the velocity is linear between the
    /// knots, so the trapezoid is exact).
    fn integrate_to(&mut self, t: f64, next: Option<(f64, Vector3<f64>)>) {
        if t <= self.t_pos {
            return;
        }
        let v = (self.velocity(self.t_pos, next) + self.velocity(t, next)) * 0.5;
        let dt = t - self.t_pos;
        let (lat, lon, h) = &mut self.position;
        *lat += v.x * dt / (meridian_radius(*lat) + *h);
        *lon += v.y * dt / ((transverse_radius(*lat) + *h) * lat.cos());
        *h -= v.z * dt;
        self.t_pos = t;
    }

    /// The solution at `t` (the position integrated to it), with attitude
    /// `c_bn`.
    fn fix(&self, t: f64, next: Option<(f64, Vector3<f64>)>, c_bn: Matrix3<f64>) -> Estimate {
        let (lat, lon, h) = self.position;
        Estimate {
            t,
            nav: NavState {
                lat,
                lon,
                h,
                v_n: self.velocity(t, next),
                c_bn,
            },
            cov: SMatrix::<f64, 9, 9>::repeat(f64::NAN),
            compass_bias: (0.0, f64::NAN),
            usbl_bias_n: (0.0, f64::NAN),
            baro_bias: (0.0, f64::NAN),
        }
    }

    /// A truth row: before the epoch it is counted, not scored; else it
    /// waits, with the attitude at its time, for the next reading.
    fn truth(
        &mut self,
        line: Option<u64>,
        row: TruthRow,
        sinks: &mut Sinks,
    ) -> Result<(), RunError> {
        // (Without `[initial] t` the epoch is NaN until the first IMU row:
        // a truth row before it is not scored.)
        if self.t0.is_nan() || row.t < self.t0 - 1e-9 {
            return score(sinks, line, &row, None);
        }
        self.turn_to(row.t);
        self.waiting.push_back(Waiting {
            line,
            row,
            c_bn: self.c_bn,
        });
        Ok(())
    }

    /// The end of the log: the truth rows still waiting get the last
    /// reading's velocity up to the end of the IMU, none after it.
    ///
    /// # Errors
    /// No IMU rows, or no DVL reading with bottom lock in the IMU's span.
    fn finish(&mut self, sinks: &mut Sinks) -> Result<(), RunError> {
        if self.imu.first.is_none() {
            return Err(RunError::Invalid(format!(
                "imu.csv: no rows: model {NAME} carries the attitude with the gyro"
            )));
        }
        let end = self.imu.end();
        for d in std::mem::take(&mut self.deferred) {
            if d.t <= end {
                self.knot_of(&d, d.rate, sinks)?;
            }
        }
        if self.readings == 0 {
            return Err(RunError::Invalid(format!(
                "dvl.csv: no reading with bottom lock between t = {} s and the last IMU row: nothing to dead-reckon",
                self.t0
            )));
        }
        while let Some(w) = self.waiting.pop_front() {
            if w.row.t > end + 1e-9 {
                score(sinks, w.line, &w.row, None)?;
                continue;
            }
            self.integrate_to(w.row.t, None);
            let fix = self.fix(w.row.t, None, w.c_bn);
            score(sinks, w.line, &w.row, Some(&fix))?;
        }
        Ok(())
    }

    /// The warning of a long stretch without readings, if there was one.
    fn gap_warning(&self) -> Option<Warning> {
        (self.longest_gap.0 > GAP_WARNING_S).then(|| {
            Warning::about(
                WarningKind::Suspicious,
                DvlRow::FILE,
                format!(
                    "no DVL reading with bottom lock for {:.1} s after t = {} s: the velocity is interpolated across the gap",
                    self.longest_gap.0, self.longest_gap.1
                ),
            )
        })
    }
}

/// Scores `estimate` at truth row `row` when there is a truth file.
fn score(
    sinks: &mut Sinks,
    line: Option<u64>,
    row: &TruthRow,
    estimate: Option<&Estimate>,
) -> Result<(), RunError> {
    match sinks.scorer.as_mut() {
        Some(s) => s
            .push(line, row, estimate)
            .map_err(|e| RunError::Invalid(e.to_string())),
        None => Ok(()),
    }
}

/// The track's row of `nav` at `t`: the first ten of the filters'
/// [`TRAJECTORY_COLUMNS`] (time, position, velocity, attitude in degrees).
fn track_row(nav: &NavState, t: f64) -> [f64; 10] {
    let e = nav.euler();
    [
        t,
        nav.lat,
        nav.lon,
        nav.depth(),
        nav.v_n.x,
        nav.v_n.y,
        nav.v_n.z,
        e.roll.to_degrees(),
        e.pitch.to_degrees(),
        e.yaw.to_degrees(),
    ]
}

/// Dead-reckons `source` as it streams; with `out`, the track and the
/// errors are written there as the run goes, else kept in the output
/// when `options.keep_series`.
///
/// # Errors
/// `[initial]` lacks the position or the attitude; the log has no IMU
/// rows, no DVL file or no DVL reading with bottom lock; a bad row (strict
/// reading); an output file cannot be written.
fn dead_reckon(
    source: &LogSource<'_>,
    options: &ReplayOptions,
    out: Option<&Path>,
) -> Result<ReplayOutput, RunError> {
    let start = std::time::Instant::now();
    let mut reckoning = Reckoning::new(source)?;
    if source.rows::<DvlRow>()?.is_none() {
        return Err(RunError::Invalid(format!(
            "dvl.csv: missing: model {NAME} integrates the DVL's velocity (map a file to it with [files.dvl])"
        )));
    }
    let mut truth = source.rows::<TruthRow>()?;
    let keep = Keep::for_replay(TABLE, out, options.keep_series)?;
    let mut sinks = Sinks {
        scorer: truth.is_some().then(|| Scorer::new(None, keep)),
        track: SeriesSink::new(
            TRAJECTORY_TABLE,
            &TRAJECTORY_COLUMNS[..10],
            out,
            options.keep_series,
        )?,
    };
    let mut next_truth = match truth.as_mut() {
        Some(rows) => rows.next_row()?,
        None => None,
    };
    let mut events = source.events()?;
    while let Some(located) = events.next_event()? {
        let t = located.event.t();
        // The truth rows before this event (at a tie, the truth first: a
        // reading at a truth row's time is its knot).
        while let Some((line, row)) = next_truth.take_if(|(_, r)| r.t <= t) {
            reckoning.truth(line, row, &mut sinks)?;
            next_truth = truth.as_mut().map_or(Ok(None), |r| r.next_row())?;
        }
        match located.event {
            Event::Imu(r) => reckoning.imu(r.t, Vector3::new(r.gx, r.gy, r.gz), &mut sinks)?,
            Event::Dvl(r) => {
                if let Some(v) = r.velocity() {
                    reckoning.reading(r.t, v);
                }
            }
            _ => {}
        }
    }
    while let Some((line, row)) = next_truth.take() {
        reckoning.truth(line, row, &mut sinks)?;
        next_truth = truth.as_mut().map_or(Ok(None), |r| r.next_row())?;
    }
    reckoning.finish(&mut sinks)?;
    let mut output = ReplayOutput {
        samples: reckoning.imu.rows,
        runtime_s: start.elapsed().as_secs_f64(),
        warnings: reckoning.gap_warning().into_iter().collect(),
        ..Default::default()
    };
    let track = sinks.track.finish()?;
    if let Some(scorer) = sinks.scorer {
        let span = reckoning.imu.first.map(|first| (first, reckoning.imu.last));
        let scored = scorer
            .finish(span)
            .map_err(|e| RunError::Invalid(e.to_string()))?;
        crate::ins::output::insert_scores(&mut output, &scored, false);
        if out.is_none() && options.keep_series {
            output.tables.extend(track);
            output.tables.push(scored.table);
        }
    } else if out.is_none() {
        output.tables.extend(track);
    }
    Ok(output)
}

impl ReplayModel for DeadReckoning {
    fn name(&self) -> &'static str {
        NAME
    }
    fn description(&self) -> &'static str {
        "plain DVL dead reckoning, the baseline: gyro attitude from [initial], DVL velocity rotated and integrated (no filter)"
    }
    fn log_files(&self) -> Option<&'static [&'static str]> {
        Some(&["imu.csv", "dvl.csv", "truth.csv"])
    }
    /// No noise setting: nothing to tune.
    fn uses_noise_parameter(&self, _key: &str) -> bool {
        false
    }
    /// Streamed: the memory does not grow with the log; with `out`, the
    /// track and the errors are written as the run goes.
    fn replay_source(
        &self,
        source: &LogSource<'_>,
        options: &ReplayOptions,
        out: Option<&Path>,
    ) -> Result<ReplayOutput, RunError> {
        dead_reckon(source, options, out)
    }
}

#[cfg(test)]
#[path = "dead_reckoning_tests.rs"]
mod tests;
