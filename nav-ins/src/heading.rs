//! The magnetic heading measurement of eqs. A3 and G2 (`docs/ulog.md`): the
//! yaw of a magnetometer sample after removing roll and pitch, plus the
//! declination.

/// Yaw (rad, in (-pi, pi]) of the body magnetic field `mag` (any unit, body
/// FRD) levelled with `roll` and `pitch` (rad), plus `declination` (rad,
/// east positive): the heading a tilt-compensated compass reads. `None` when
/// the horizontal field is zero or a value is not finite.
pub fn magnetic_heading(mag: [f64; 3], roll: f64, pitch: f64, declination: f64) -> Option<f64> {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    // The field in the levelled frame: rotate back by roll, then by pitch.
    let north = mag[0] * cp + (mag[1] * sr + mag[2] * cr) * sp;
    let east = mag[1] * cr - mag[2] * sr;
    if !(north.is_finite() && east.is_finite()) || north.hypot(east) == 0.0 {
        return None;
    }
    let yaw = (-east).atan2(north) + declination;
    Some(yaw.sin().atan2(yaw.cos()))
}

/// The horizontal magnitude of the body field `mag` levelled with `roll`,
/// `pitch` (rad): what sets the heading's noise (a weak horizontal field
/// reads as a noisy heading).
pub fn horizontal_field(mag: [f64; 3], roll: f64, pitch: f64) -> f64 {
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let north = mag[0] * cp + (mag[1] * sr + mag[2] * cr) * sp;
    let east = mag[1] * cr - mag[2] * sr;
    north.hypot(east)
}

/// The declination (rad) that makes the first magnetometer sample agree
/// with an initial attitude (`roll`, `pitch`, `yaw`, rad): the field's
/// direction is taken from the log itself when no model of it is at hand.
pub fn declination_from(mag: [f64; 3], roll: f64, pitch: f64, yaw: f64) -> Option<f64> {
    let raw = magnetic_heading(mag, roll, pitch, 0.0)?;
    let d = yaw - raw;
    Some(d.sin().atan2(d.cos()))
}

/// Magnetometer samples averaged for the declination: those within this
/// time of the initial estimate, s.
pub const DECLINATION_WINDOW_S: f64 = 1.0;

/// The magnetic declination (rad, east positive) that makes the
/// magnetometer agree with the initial attitude (`roll`, `pitch`, `yaw`,
/// rad): the circular mean of [`declination_from`] over the samples
/// `(t, field)` within [`DECLINATION_WINDOW_S`] of `t0`, with the count
/// averaged. Logs seldom carry the declination (PX4 logs it only as a
/// parameter that SITL leaves at its default), so the field's direction is
/// taken from the log itself. `None` without a usable sample.
pub fn mean_declination(
    samples: impl IntoIterator<Item = (f64, [f64; 3])>,
    t0: f64,
    attitude: [f64; 3],
) -> Option<(f64, usize)> {
    let (mut s, mut c, mut n) = (0.0, 0.0, 0usize);
    for (_, field) in samples
        .into_iter()
        .filter(|(t, _)| *t >= t0 - DECLINATION_WINDOW_S && *t <= t0 + DECLINATION_WINDOW_S)
    {
        if let Some(d) = declination_from(field, attitude[0], attitude[1], attitude[2]) {
            s += d.sin();
            c += d.cos();
            n += 1;
        }
    }
    (n > 0).then(|| (s.atan2(c), n))
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::nalgebra::{Rotation3, Vector3};

    /// The body field of an Earth field `m_n` seen at (roll, pitch, yaw):
    /// `m_b = C_n^b m_n`; the heading recovers yaw for every attitude.
    #[test]
    fn recovers_the_yaw_of_any_attitude() {
        let m_n = Vector3::new(0.21, 0.0, 0.42); // northern hemisphere, no declination
        let cases = [
            (0.0, 0.0, 0.0),
            (0.0, 0.0, 1.0),
            (0.3, -0.2, 2.5),
            (-0.5, 0.4, -2.0),
            (0.1, 1.2, -3.1),
        ];
        for (roll, pitch, yaw) in cases {
            let c_bn = Rotation3::from_euler_angles(roll, pitch, yaw);
            let m_b = c_bn.transpose() * m_n;
            let h = magnetic_heading([m_b.x, m_b.y, m_b.z], roll, pitch, 0.0).expect("heading");
            let d = (h - yaw).sin().atan2((h - yaw).cos());
            assert!(d.abs() < 1e-12, "{roll} {pitch} {yaw}: {h}");
        }
    }

    #[test]
    fn declination_closes_the_gap_to_the_initial_yaw() {
        // A field 10 deg east of north, seen level at yaw 0: reads -10 deg.
        let dec = 10f64.to_radians();
        let mag = [dec.cos(), dec.sin(), 1.0];
        let raw = magnetic_heading(mag, 0.0, 0.0, 0.0).expect("heading");
        assert!((raw + dec).abs() < 1e-12, "{raw}");
        let d = declination_from(mag, 0.0, 0.0, 0.0).expect("declination");
        assert!((d - dec).abs() < 1e-12);
        assert_eq!(magnetic_heading([0.0, 0.0, 0.5], 0.0, 0.0, 0.0), None);
    }
}
