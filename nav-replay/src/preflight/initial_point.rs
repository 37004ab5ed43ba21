//! `[initial]` position against the truth at the epoch when the truth
//! describes another point of the vehicle (`[files.truth] lever_arm`). A
//! real log's initial position is often copied from the first reference
//! row: without `[initial] lever_arm` the filter then starts off by the arm,
//! an offset that neither a DVL nor any velocity aiding can remove, and
//! every score carries it (docs/log-format.md, "truth.csv").

use nav_runtime::attitude::Euler;
use nav_runtime::earth::{meridian_radius, transverse_radius};
use nav_runtime::log::{Meta, Row, TruthRow, Warning, WarningKind};
use nav_runtime::nalgebra::Vector3;

use super::Report;

/// The truth row nearest the epoch is used if it is at most this far from
/// it, s (its position is carried to the epoch with its velocity).
const MAX_DISTANCE_S: f64 = 5.0;

/// Offsets between the two candidate points below this are not told
/// apart, m.
const MIN_ARM_M: f64 = 0.1;

/// The truth row nearest the initial epoch, as read from the file (the
/// preflight reads the files as they are; a log in memory carries no
/// mapping, hence no arm, and is not checked).
#[derive(Debug, Default)]
pub(super) struct Fold {
    nearest: Option<(f64, TruthRow)>,
}

impl Fold {
    /// One truth row as read; `epoch` the initial epoch.
    pub(super) fn row(&mut self, epoch: f64, r: &TruthRow) {
        let distance = (r.t - epoch).abs();
        if distance <= MAX_DISTANCE_S && self.nearest.is_none_or(|(d, _)| distance < d) {
            self.nearest = Some((distance, *r));
        }
    }

    /// A warning when the initial position is nearer the point the truth
    /// describes (`arm`, body axes from the IMU, m) than the IMU: by less
    /// than half the distance, and the two more than [`MIN_ARM_M`] apart.
    pub(super) fn finish(&self, meta: &Meta, epoch: f64, arm: [f64; 3], report: &mut Report) {
        let initial = &meta.initial;
        let Some((_, row)) = self.nearest else { return };
        if arm == [0.0; 3] || !initial.has_position() {
            return;
        }
        // The truth's position carried to the epoch, north-east-down from
        // the initial position (m): that of the point it describes (the
        // rows are read as they are in the file) and the IMU's.
        let dt = epoch - row.t;
        let h = -initial.depth;
        let at_point = Vector3::new(
            (row.lat - initial.lat) * (meridian_radius(initial.lat) + h) + row.vn * dt,
            (row.lon - initial.lon) * (transverse_radius(initial.lat) + h) * initial.lat.cos()
                + row.ve * dt,
            row.depth - initial.depth + row.vd * dt,
        );
        let offset = Euler::new(row.roll, row.pitch, row.yaw).c_bn() * Vector3::from(arm);
        let (from_imu, from_point) = ((at_point - offset).norm(), at_point.norm());
        if offset.norm() < MIN_ARM_M || from_point >= 0.5 * from_imu {
            return;
        }
        report.warn(
            Warning::about(
                WarningKind::Suspicious,
                "meta.toml",
                format!(
                    "the initial position is {from_point:.2} m from the point {} describes \
                     (`[files.truth] lever_arm`) at the epoch and {from_imu:.2} m from the IMU: \
                     it seems taken from that point; the filter estimates the IMU, so it would \
                     start {from_imu:.2} m off and stay off (no velocity aiding removes it). \
                     Declare `[initial] lever_arm = [{:?}, {:?}, {:?}]` to move it to the IMU",
                    TruthRow::FILE,
                    arm[0],
                    arm[1],
                    arm[2]
                ),
            )
            .with_key("initial.lever_arm"),
        );
    }
}
