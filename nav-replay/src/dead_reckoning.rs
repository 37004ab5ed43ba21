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
//! filters' scoring, without the NEES (there is no covariance).

use nav_runtime::attitude::Euler;
use nav_runtime::earth::{earth_rate_n, meridian_radius, transport_rate_n, transverse_radius};
use nav_runtime::log::{DvlRow, ImuRow, LogDir, Row, Warning, WarningKind};
use nav_runtime::nalgebra::{Matrix3, Rotation3, SMatrix, Vector3};
use nav_runtime::strapdown::NavState;

use crate::ins::output::{TRAJECTORY_COLUMNS, TRAJECTORY_TABLE};
use crate::ins::score::{self, Scored};
use crate::{ReplayModel, ReplayOptions, ReplayOutput, RunError, RunTable};

/// The model's name on the command line.
pub const NAME: &str = "dvl-dr";

/// A stretch without a DVL reading longer than this is a warning, s: the
/// velocity is interpolated across it.
const GAP_WARNING_S: f64 = 10.0;

/// `navsim replay DIR --model dvl-dr`: plain DVL dead reckoning.
#[derive(Clone, Copy, Debug, Default)]
pub struct DeadReckoning;

/// One dead-reckoned solution at a time.
#[derive(Clone, Copy, Debug)]
struct Fix {
    t: f64,
    nav: NavState,
}

/// The attitude carried through the IMU rows, forward in time only.
struct Attitude<'a> {
    imu: &'a [ImuRow],
    /// Index of the IMU row whose interval holds `t`.
    k: usize,
    t: f64,
    c_bn: Matrix3<f64>,
}

impl<'a> Attitude<'a> {
    fn new(imu: &'a [ImuRow], t0: f64, c_bn: Matrix3<f64>) -> Self {
        let k = imu.partition_point(|r| r.t <= t0).saturating_sub(1);
        Attitude {
            imu,
            k,
            t: t0,
            c_bn,
        }
    }

    /// The body rate of the IMU sample held at the current time, rad/s.
    fn rate(&self) -> Vector3<f64> {
        self.imu
            .get(self.k)
            .map_or(Vector3::zeros(), |r| Vector3::new(r.gx, r.gy, r.gz))
    }

    /// Carries the attitude to `t` (not before the current time) with the
    /// navigation frame's rate at `lat`, `h` and `v_n`.
    fn advance(&mut self, t: f64, lat: f64, h: f64, v_n: &Vector3<f64>) {
        let w_in = earth_rate_n(lat) + transport_rate_n(lat, h, v_n);
        while self.t < t {
            // The end of the interval the current sample is held over.
            let boundary = self.imu.get(self.k + 1).map_or(f64::INFINITY, |r| r.t);
            let end = boundary.min(t);
            let dt = end - self.t;
            if dt > 0.0 {
                let body = Rotation3::from_scaled_axis(self.rate() * dt);
                let frame = Rotation3::from_scaled_axis(-w_in * dt);
                self.c_bn = frame.matrix() * self.c_bn * body.matrix();
                self.t = end;
            }
            if end >= boundary {
                self.k += 1;
            }
        }
    }
}

/// The dead-reckoned solution at each time of `times` (ascending), `None`
/// where it has none (before the epoch, after the last IMU row), and the
/// warnings of the run.
///
/// # Errors
/// `[initial]` lacks the position or the attitude; the log has no IMU
/// rows, no DVL file or no DVL reading with bottom lock.
fn dead_reckon(log: &LogDir, times: &[f64]) -> Result<(Vec<Option<Fix>>, Vec<Warning>), RunError> {
    let init = &log.meta.initial;
    let [lat0, lon0, depth0] = init.position_for(NAME)?;
    let [roll, pitch, yaw] = init.attitude()?;
    let (Some(first), Some(last)) = (log.imu.first(), log.imu.last()) else {
        return Err(RunError::Invalid(format!(
            "imu.csv: no rows: model {NAME} carries the attitude with the gyro"
        )));
    };
    let dvl = log.dvl.as_deref().ok_or_else(|| {
        RunError::Invalid(format!(
            "dvl.csv: missing: model {NAME} integrates the DVL's velocity (map a file to it with [files.dvl])"
        ))
    })?;
    let t0 = init.t.unwrap_or(first.t);
    // The IMU's last sample is held over one mean interval.
    let rows = log.imu.len();
    let period = if rows > 1 {
        (last.t - first.t) / (rows - 1) as f64
    } else {
        0.0
    };
    let t_end = last.t + period;
    let mounting = log.meta.sensors.mounting("dvl");
    let misalignment = mounting.map_or(Matrix3::identity(), |m| {
        let [roll, pitch, yaw] = m.misalignment;
        Euler { roll, pitch, yaw }.c_bn()
    });
    let arm = Vector3::from(mounting.map_or([0.0; 3], |m| m.lever_arm));

    // The velocity knots: the epoch's, then each reading's, in NED.
    let c_bn0 = Euler { roll, pitch, yaw }.c_bn();
    let mut attitude = Attitude::new(&log.imu, t0, c_bn0);
    let h0 = -depth0;
    let v0 = Vector3::new(init.vn, init.ve, init.vd);
    let mut knots = vec![(t0, v0)];
    let mut longest_gap = (0.0, t0);
    for r in dvl.iter().filter(|r| r.t >= t0 && r.t <= t_end) {
        let Some(v) = r.velocity() else { continue };
        let (t_prev, v_prev) = knots[knots.len() - 1];
        attitude.advance(r.t, lat0, h0, &v_prev);
        let body = misalignment * Vector3::from(v) - attitude.rate().cross(&arm);
        let v_n = attitude.c_bn * body;
        if r.t - t_prev > longest_gap.0 && knots.len() > 1 {
            longest_gap = (r.t - t_prev, t_prev);
        }
        knots.push((r.t, v_n));
    }
    if knots.len() < 2 {
        return Err(RunError::Invalid(format!(
            "dvl.csv: no reading with bottom lock between t = {t0} s and the last IMU row: nothing to dead-reckon"
        )));
    }
    let mut warnings = Vec::new();
    if longest_gap.0 > GAP_WARNING_S {
        warnings.push(Warning::about(
            WarningKind::Suspicious,
            DvlRow::FILE,
            format!(
                "no DVL reading with bottom lock for {:.1} s after t = {} s: the velocity is interpolated across the gap",
                longest_gap.0, longest_gap.1
            ),
        ));
    }

    // The position, integrated knot to knot; the solutions at `times`.
    let mut attitude = Attitude::new(&log.imu, t0, c_bn0);
    let (mut lat, mut lon, mut h) = (lat0, lon0, h0);
    let mut at = 0usize;
    let mut t = t0;
    let mut fixes = Vec::with_capacity(times.len());
    let velocity = |t: f64| -> Vector3<f64> {
        let i = knots.partition_point(|(tk, _)| *tk <= t);
        match (knots.get(i.wrapping_sub(1)), knots.get(i)) {
            (Some(&(ta, va)), Some(&(tb, vb))) if tb > ta => {
                va + (vb - va) * ((t - ta) / (tb - ta))
            }
            (Some(&(_, va)), _) => va,
            (None, _) => v0,
        }
    };
    for &tq in times {
        if tq < t0 - 1e-9 || tq > t_end + 1e-9 {
            fixes.push(None);
            continue;
        }
        // Integrate to `tq` through every knot on the way (the velocity is
        // linear between them, so the trapezoid is exact).
        while t < tq {
            while knots.get(at).is_some_and(|(tk, _)| *tk <= t) {
                at += 1;
            }
            let next = knots.get(at).map_or(tq, |(tk, _)| tk.min(tq));
            let v = (velocity(t) + velocity(next)) * 0.5;
            let dt = next - t;
            lat += v.x * dt / (meridian_radius(lat) + h);
            lon += v.y * dt / ((transverse_radius(lat) + h) * lat.cos());
            h -= v.z * dt;
            t = next;
        }
        let v_n = velocity(tq);
        attitude.advance(tq, lat0, h0, &v_n);
        fixes.push(Some(Fix {
            t: tq,
            nav: NavState {
                lat,
                lon,
                h,
                v_n,
                c_bn: attitude.c_bn,
            },
        }));
    }
    Ok((fixes, warnings))
}

/// The table of `fixes` (those there are): the first ten of the filters'
/// [`TRAJECTORY_COLUMNS`] (time, position, velocity, attitude in degrees).
fn trajectory(fixes: &[Option<Fix>]) -> RunTable {
    let mut table = RunTable::new(TRAJECTORY_TABLE, &TRAJECTORY_COLUMNS[..10]);
    for f in fixes.iter().flatten() {
        let n = &f.nav;
        let e = n.euler();
        table.push(&[
            f.t,
            n.lat,
            n.lon,
            n.depth(),
            n.v_n.x,
            n.v_n.y,
            n.v_n.z,
            e.roll.to_degrees(),
            e.pitch.to_degrees(),
            e.yaw.to_degrees(),
        ]);
    }
    table
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
    fn replay(&self, log: &LogDir, options: &ReplayOptions) -> Result<ReplayOutput, RunError> {
        let start = std::time::Instant::now();
        let truth = log.truth.as_deref().unwrap_or_default();
        let times: Vec<f64> = truth.iter().map(|r| r.t).collect();
        let (fixes, warnings) = dead_reckon(log, &times)?;
        let mut out = ReplayOutput {
            samples: log.imu.len(),
            runtime_s: start.elapsed().as_secs_f64(),
            warnings,
            ..Default::default()
        };
        if options.keep_series {
            // The track at each DVL reading, as the filters' `estimates.csv`
            // without the sigmas.
            let readings: Vec<f64> = log
                .dvl
                .iter()
                .flatten()
                .filter(|r| r.velocity().is_some())
                .map(|r| r.t)
                .collect();
            let (track, _) = dead_reckon(log, &readings)?;
            out.tables.push(trajectory(&track));
        }
        if log.truth.is_none() {
            return Ok(out);
        }
        let estimates: Vec<Option<crate::ins::setup::Estimate>> = fixes
            .iter()
            .map(|f| {
                f.map(|f| crate::ins::setup::Estimate {
                    t: f.t,
                    nav: f.nav,
                    cov: SMatrix::<f64, 9, 9>::repeat(f64::NAN),
                    compass_bias: (0.0, f64::NAN),
                    usbl_bias_n: (0.0, f64::NAN),
                    baro_bias: (0.0, f64::NAN),
                })
            })
            .collect();
        let span = log
            .imu
            .first()
            .zip(log.imu.last())
            .map(|(a, b)| (a.t(), b.t()));
        let scored: Scored = score::score(&estimates, truth, None, span)
            .map_err(|e| RunError::Invalid(e.to_string()))?;
        crate::ins::output::insert_scores(&mut out, &scored, false);
        if options.keep_series {
            out.tables.push(scored.table);
        }
        Ok(out)
    }
}

#[cfg(test)]
#[path = "dead_reckoning_tests.rs"]
mod tests;
