//! The truth of a log taken to the IMU: `[files.truth] lever_arm` says
//! where on the vehicle the point `truth.csv` describes sits (body axes,
//! FRD, from the IMU, m), as a post-processed reference often describes
//! the vehicle's reference point or an antenna rather than the IMU. The
//! filter estimates the IMU's position and velocity, so the truth is moved
//! there before it is compared (docs/log-format.md, "truth.csv"):
//!
//! - position: `p_imu = p_ref - C_b^n r`;
//! - velocity: `v_imu = v_ref - C_b^n (omega x r)`, with the body rate
//!   `omega` from the attitudes of the rows before and after (one-sided at
//!   the ends of the file, zero in a file of one row).
//!
//! Without the arm the rows are as read. Attitude is the same at every
//! point of a rigid body.

use nalgebra::{Matrix3, Vector3};

use super::stream::RowSource;
use super::{LogError, TruthRow};
use crate::attitude::{rotvec_from_rotation, Euler};
use crate::earth::{meridian_radius, transverse_radius};

/// Moves truth rows from the point the lever arm gives to the IMU.
#[derive(Clone, Copy, Debug)]
pub struct ReferencePoint {
    arm: Vector3<f64>,
}

fn c_bn(row: &TruthRow) -> Matrix3<f64> {
    Euler {
        roll: row.roll,
        pitch: row.pitch,
        yaw: row.yaw,
    }
    .c_bn()
}

impl ReferencePoint {
    /// The transport for lever arm `arm` (body axes, m); `None` for a zero
    /// arm (the truth is of the IMU).
    pub fn new(arm: [f64; 3]) -> Option<Self> {
        (arm != [0.0; 3]).then(|| ReferencePoint {
            arm: Vector3::from(arm),
        })
    }

    /// `row` moved to the IMU; `before` and `after` are the rows next to
    /// it in the file (for the body rate).
    pub fn to_imu(
        &self,
        before: Option<&TruthRow>,
        row: &TruthRow,
        after: Option<&TruthRow>,
    ) -> TruthRow {
        let c = c_bn(row);
        let (a, b) = (before.unwrap_or(row), after.unwrap_or(row));
        // The body rate over the rows around this one (rad/s).
        let omega = if b.t > a.t {
            rotvec_from_rotation(&(c_bn(a).transpose() * c_bn(b))) / (b.t - a.t)
        } else {
            Vector3::zeros()
        };
        let velocity = c * omega.cross(&self.arm);
        let [lat, lon, depth] = self.position_to_imu([row.lat, row.lon, row.depth], &c);
        TruthRow {
            lat,
            lon,
            depth,
            vn: row.vn - velocity.x,
            ve: row.ve - velocity.y,
            vd: row.vd - velocity.z,
            ..*row
        }
    }

    /// Latitude, longitude (rad) and depth (m) of the point, moved to the
    /// IMU: `p - C_b^n r`, with `c_bn` the body-to-NED rotation.
    pub fn position_to_imu(&self, [lat, lon, depth]: [f64; 3], c_bn: &Matrix3<f64>) -> [f64; 3] {
        let offset = c_bn * self.arm;
        let h = -depth;
        [
            lat - offset.x / (meridian_radius(lat) + h),
            lon - offset.y / ((transverse_radius(lat) + h) * lat.cos()),
            depth - offset.z,
        ]
    }

    /// Every row of `rows` (in time order) moved to the IMU.
    pub fn move_all(&self, rows: &mut [TruthRow]) {
        // The row before, as read (the rows after are not moved yet).
        let mut before: Option<TruthRow> = None;
        for i in 0..rows.len() {
            let read = rows[i];
            rows[i] = self.to_imu(before.as_ref(), &read, rows.get(i + 1));
            before = Some(read);
        }
    }
}

/// A source of truth rows moved to the IMU by a [`ReferencePoint`], read
/// one row ahead (the body rate needs the row after).
pub struct AtImu<S> {
    source: S,
    point: ReferencePoint,
    before: Option<TruthRow>,
    next: Option<(Option<u64>, TruthRow)>,
    started: bool,
}

impl<S> AtImu<S> {
    /// `source`'s rows moved by `point`.
    pub fn new(source: S, point: ReferencePoint) -> Self {
        AtImu {
            source,
            point,
            before: None,
            next: None,
            started: false,
        }
    }
}

impl<S: RowSource<TruthRow>> RowSource<TruthRow> for AtImu<S> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, TruthRow)>, LogError> {
        if !self.started {
            self.started = true;
            self.next = self.source.next_row()?;
        }
        let Some((line, row)) = self.next.take() else {
            return Ok(None);
        };
        self.next = self.source.next_row()?;
        let after = self.next.as_ref().map(|(_, r)| r);
        let moved = self.point.to_imu(self.before.as_ref(), &row, after);
        self.before = Some(row);
        Ok(Some((line, moved)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::earth::{Geodetic, LocalNed};
    use crate::trajectory::{Trajectory, TrajectorySpec, TruthSource};

    /// The truth of a vehicle turning at up to 0.1 rad/s, 10 rows a second,
    /// written at a point 1.85 m ahead of and 0.3 m below the IMU (moved
    /// through the local level frame, independently of the transport), is
    /// taken back to the IMU to a millimetre and 1 cm/s.
    #[test]
    fn a_reference_point_is_moved_back_to_the_imu() {
        let arm = Vector3::new(1.85, 0.0, 0.3);
        let mut spec = TrajectorySpec::new(Geodetic::new(0.6, 2.2, -40.0), 0.3, 1.5);
        let mut t = 20.0;
        for delta in [1.6, -2.1, 3.0] {
            t = spec.turn(t, delta) + 15.0;
        }
        let traj = Trajectory::new(spec, 120.0, 0.1);
        let point = ReferencePoint::new([arm.x, arm.y, arm.z]).unwrap();
        let states: Vec<_> = (0..1200).map(|k| traj.truth(k as f64 * 0.1)).collect();
        let (mut imu_rows, mut rows) = (Vec::new(), Vec::new());
        for s in &states {
            let imu = TruthRow::from(s);
            let frame = LocalNed::new(Geodetic::new(s.lat, s.lon, s.h));
            let at = frame.ned_to_geodetic(&(s.c_bn * arm));
            let v = s.v_n + s.c_bn * s.w_nb_b.cross(&arm);
            let reference = TruthRow {
                lat: at.lat,
                lon: at.lon,
                depth: -at.h,
                vn: v.x,
                ve: v.y,
                vd: v.z,
                ..imu
            };
            imu_rows.push(imu);
            rows.push(reference);
        }
        // Streamed as the replay reads them, and all at once as a log read
        // whole is: the same rows.
        let mut streamed = AtImu::new(Rows(rows.clone().into_iter()), point);
        let mut whole = rows.clone();
        point.move_all(&mut whole);
        let (mut position, mut velocity) = (0.0f64, 0.0f64);
        for (k, (s, imu)) in states.iter().zip(&imu_rows).enumerate() {
            let back = streamed.next_row().unwrap().unwrap().1;
            assert_eq!(back, whole[k]);
            let (rm, rn) = (meridian_radius(s.lat) + s.h, transverse_radius(s.lat) + s.h);
            let d = Vector3::new(
                (back.lat - imu.lat) * rm,
                (back.lon - imu.lon) * rn * s.lat.cos(),
                back.depth - imu.depth,
            );
            position = position.max(d.norm());
            if k > 0 && k + 1 < states.len() {
                let dv = Vector3::new(back.vn - imu.vn, back.ve - imu.ve, back.vd - imu.vd);
                velocity = velocity.max(dv.norm());
            }
            assert_eq!(
                (back.t, back.roll, back.pitch, back.yaw),
                (imu.t, imu.roll, imu.pitch, imu.yaw)
            );
        }
        assert!(streamed.next_row().unwrap().is_none());
        assert!(position < 1e-3, "position {position} m");
        assert!(velocity < 0.01, "velocity {velocity} m/s");
    }

    /// Rows in memory as a source.
    struct Rows(std::vec::IntoIter<TruthRow>);

    impl RowSource<TruthRow> for Rows {
        fn next_row(&mut self) -> Result<Option<(Option<u64>, TruthRow)>, LogError> {
            Ok(self.0.next().map(|r| (None, r)))
        }
    }

    /// `[initial] lever_arm`: an initial position copied from such a
    /// reference (mid-turn, pitched and rolled) is moved to the IMU's to a
    /// millimetre; the velocity is kept as given.
    #[test]
    fn an_initial_position_of_the_reference_point_is_moved_to_the_imu() {
        use crate::log::Meta;
        let arm = Vector3::new(1.85, -0.4, 0.3);
        let mut spec = TrajectorySpec::new(Geodetic::new(0.6, 2.2, -40.0), 0.3, 1.5);
        spec.turn(5.0, 2.0);
        let s = Trajectory::new(spec, 30.0, 0.1).truth(7.0);
        let attitude = s.euler;
        let frame = LocalNed::new(Geodetic::new(s.lat, s.lon, s.h));
        let at = frame.ned_to_geodetic(&(s.c_bn * arm));
        let text = format!(
            "[initial]\nlat = {:?}\nlon = {:?}\ndepth = {:?}\nvn = 1.25\nroll = {:?}\n\
             pitch = {:?}\nyaw = {:?}\nlever_arm = [{:?}, {:?}, {:?}]\n",
            at.lat, at.lon, -at.h, attitude.roll, attitude.pitch, attitude.yaw, arm.x, arm.y, arm.z
        );
        let initial = Meta::parse(&text).unwrap().initial;
        let (rm, rn) = (meridian_radius(s.lat) + s.h, transverse_radius(s.lat) + s.h);
        let d = Vector3::new(
            (initial.lat - s.lat) * rm,
            (initial.lon - s.lon) * rn * s.lat.cos(),
            initial.depth + s.h,
        );
        assert!(d.norm() < 1e-3, "{d:?}");
        assert!(s.c_bn * arm != Vector3::zeros() && (s.c_bn * arm).norm() > 1.0);
        assert_eq!(initial.vn, 1.25);
    }

    #[test]
    fn a_zero_arm_moves_nothing() {
        assert!(ReferencePoint::new([0.0; 3]).is_none());
    }
}
