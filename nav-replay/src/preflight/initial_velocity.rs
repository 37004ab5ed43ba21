//! `[initial]` velocity against the DVL reading nearest the initial epoch,
//! rotated to north-east-down by the initial attitude. A velocity of the
//! wrong sign, in knots or copied from another column starts the filter
//! metres per second off: the DVL rows are then refused until a recovery,
//! the position runs off meanwhile, and nothing but truth (when there is
//! one) shows it afterwards (lawnmower-dvl seed 3 with `ve = -1.48` for
//! 0.01: a horizontal RMS error of 18 m instead of 3.2 m and no warning).

use nav_ins::InitialSigma;
use nav_runtime::attitude::Euler;
use nav_runtime::log::{DvlRow, LogDir, Meta, Row, Warning, WarningKind, META_FILE};
use nav_runtime::nalgebra::{Matrix3, Vector3};

use super::aiding_plausibility::MAX_DVL_SPEED;
use super::Report;

/// The DVL reading compared is at most this far from the initial epoch, s.
const MAX_DISTANCE_S: f64 = 5.0;

/// Largest acceleration of a vehicle carrying a DVL, m/s^2: the velocity
/// may change by this much per second between the epoch and the reading.
const MAX_ACCELERATION: f64 = 1.0;

/// Largest distance of a DVL (or of the point an `[initial]` velocity was
/// copied from) from the IMU, m: the body rate times it bounds the
/// `omega x r` the comparison leaves out.
const MAX_ARM_M: f64 = 3.0;

/// Sigmas of the initial velocity and the reading a difference must exceed.
const SIGMAS: f64 = 5.0;

/// The DVL row with a velocity (bottom lock) nearest the initial epoch,
/// within [`MAX_DISTANCE_S`], as read.
#[derive(Debug, Default)]
pub(super) struct Fold {
    nearest: Option<(f64, Option<u64>, DvlRow)>,
}

impl Fold {
    /// One DVL row on `line` (when known); `epoch` the initial epoch.
    pub(super) fn dvl(&mut self, epoch: f64, line: Option<u64>, r: &DvlRow) {
        let distance = (r.t - epoch).abs();
        let readable = r
            .velocity()
            .is_some_and(|v| v.iter().all(|x| x.is_finite()));
        if readable
            && distance <= MAX_DISTANCE_S
            && self.nearest.is_none_or(|(d, _, _)| distance < d)
        {
            self.nearest = Some((distance, line, *r));
        }
    }

    /// Compares `[initial]` `vn`, `ve`, `vd` with the nearest reading,
    /// taken into body axes at the IMU as the filters take it (the declared
    /// `[sensors.dvl]` misalignment and lever arm) and rotated by the
    /// initial roll, pitch and yaw (the check is skipped without them). The band is [`SIGMAS`] times the combined sigma of the
    /// initial velocity (`[initial_sigma] velocity`, else the filters'
    /// default) and the DVL (noise and bias), plus the speed times [`SIGMAS`]
    /// attitude sigmas, the change at [`MAX_ACCELERATION`] over the time
    /// between them and the body rate (the `head` IMU row nearest the
    /// reading) times [`MAX_ARM_M`]. Beyond it a warning keyed by the
    /// component that differs most; beyond it by more than
    /// [`MAX_DVL_SPEED`] an error.
    pub(super) fn finish(&self, head: &LogDir, meta: &Meta, epoch: f64, report: &mut Report) {
        let Some((_, line, row)) = self.nearest else {
            return;
        };
        check(head, meta, epoch, line, &row, report);
    }
}

fn check(
    head: &LogDir,
    meta: &Meta,
    epoch: f64,
    line: Option<u64>,
    row: &DvlRow,
    report: &mut Report,
) {
    let initial = &meta.initial;
    let (Some(roll), Some(pitch), Some(yaw)) = (initial.roll, initial.pitch, initial.yaw) else {
        return;
    };
    let Some(reading) = row.velocity().map(Vector3::from) else {
        return;
    };
    // In body axes at the IMU, as the filters take it: the declared
    // mounting's rotation, less `omega x r` of the declared arm.
    let rate = body_rate(head, row.t);
    let mounting = meta.sensors.mounting("dvl");
    let rotation = mounting.map_or(Matrix3::identity(), |m| {
        let [roll, pitch, yaw] = m.misalignment;
        Euler::new(roll, pitch, yaw).c_bn()
    });
    let arm = Vector3::from(mounting.map_or([0.0; 3], |m| m.lever_arm));
    let v_body = rotation * reading - rate.cross(&arm);
    let c_bn = Euler::new(roll, pitch, yaw).c_bn();
    let measured = c_bn * v_body;
    let given = Vector3::new(initial.vn, initial.ve, initial.vd);
    let difference = given - measured;
    let d = difference.norm();
    if !d.is_finite() {
        return;
    }
    let defaults = InitialSigma::DEFAULT;
    let sigma = meta.initial_sigma.unwrap_or_default();
    let velocity_sigma = sigma.velocity.unwrap_or(defaults.velocity);
    let attitude_sigma = sigma
        .heading
        .unwrap_or(defaults.heading)
        .max(sigma.level.unwrap_or(defaults.level));
    let reading_sigma = meta
        .sensors
        .dvl
        .map_or(0.0, |n| n.noise_sigma.hypot(n.bias_sigma));
    let dt = (row.t - epoch).abs();
    let band = SIGMAS * velocity_sigma.hypot(reading_sigma)
        + SIGMAS * attitude_sigma * v_body.norm()
        + MAX_ACCELERATION * dt
        + rate.norm() * MAX_ARM_M;
    if d <= band {
        return;
    }
    let (axis, _) = difference.iamax_full();
    let key = ["initial.vn", "initial.ve", "initial.vd"][axis];
    let gross = d > band + MAX_DVL_SPEED;
    let message = format!(
        "[initial] velocity (vn, ve, vd) = ({:.3}, {:.3}, {:.3}) m/s is {d:.2} m/s from the \
         dvl.csv reading at t = {} s{} rotated by the initial roll, pitch and yaw, ({:.3}, {:.3}, \
         {:.3}) m/s; the band is {band:.2} m/s ({SIGMAS} sigma of both, the attitude's sigma, \
         {MAX_ACCELERATION} m/s^2 over the {dt:.2} s between them, the body rate at a {MAX_ARM_M} m \
         arm): {}",
        given.x,
        given.y,
        given.z,
        row.t,
        line.map_or(String::new(), |l| format!(" (line {l})")),
        measured.x,
        measured.y,
        measured.z,
        if gross {
            "no vehicle carrying a DVL is that far off; a unit (knots, km/h), a sign or a column of [initial]?"
        } else {
            "a sign, a unit or a swapped column of [initial] velocity, or a wrong initial yaw? The filter starts that far off and refuses the DVL until it recovers"
        }
    );
    let w = Warning::about(WarningKind::Suspicious, META_FILE, message).with_key(key);
    if gross {
        report.error(w);
    } else {
        report.warn(w);
    }
}

/// The gyro reading of the IMU row nearest `t` (zero without one), rad/s.
fn body_rate(head: &LogDir, t: f64) -> Vector3<f64> {
    let imu = &head.imu;
    let i = imu.partition_point(|r| r.t() < t);
    [i.checked_sub(1), Some(i)]
        .into_iter()
        .flatten()
        .filter_map(|k| imu.get(k))
        .min_by(|a, b| (a.t - t).abs().total_cmp(&(b.t - t).abs()))
        .map_or(Vector3::zeros(), |r| Vector3::new(r.gx, r.gy, r.gz))
}
