//! Line-of-sight course laws (docs/models/marker9.md, eq. 4; docs/guidance.md).
//!
//! Eq. 4 (enclosure LOS): `chi_d = chi_p + chi_r`, `chi_r = atan(-e / Delta)`,
//! `Delta = sqrt(R^2 - e^2)`: the vehicle steers at the point where a circle of
//! radius `R` around it meets the path. With `|e| >= R` the circle misses the path;
//! plain LOS then steers straight for the segment's end waypoint, which is what
//! cuts corners after a waypoint switch. The improved LOS of the source paper
//! steers along the path normal whenever `|e|` exceeds the minimum turning
//! radius, and uses eq. 4 otherwise.

use core::f64::consts::FRAC_PI_2;

use nalgebra::Vector2;

use super::{Path, SegmentErrors};

/// Eq. 4: course to the intersection of the enclosure circle of radius `r` with the
/// path, or `None` when `|e| >= r` (no intersection).
pub fn enclosure_course(e: &SegmentErrors, r: f64) -> Option<f64> {
    if e.cross.abs() >= r {
        return None;
    }
    let delta = (r * r - e.cross * e.cross).sqrt();
    Some(e.path_angle + (-e.cross / delta).atan())
}

/// Plain LOS: eq. 4, or the bearing to the end waypoint of the segment when the
/// enclosure circle misses the path.
pub fn los_course(path: &Path, e: &SegmentErrors, p: &Vector2<f64>, r: f64) -> f64 {
    enclosure_course(e, r).unwrap_or_else(|| {
        let w = path.points[e.segment + 1];
        (w.y - p.y).atan2(w.x - p.x)
    })
}

/// Improved LOS: along the normal toward the path when `|e|` exceeds
/// `turning_radius`, else eq. 4 with `R = max(r, 1.01 |e|)`.
pub fn improved_los_course(e: &SegmentErrors, r: f64, turning_radius: f64) -> f64 {
    if e.cross.abs() > turning_radius {
        return e.path_angle - FRAC_PI_2 * e.cross.signum();
    }
    let r = r.max(1.01 * e.cross.abs());
    enclosure_course(e, r).unwrap_or(e.path_angle - FRAC_PI_2 * e.cross.signum())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn north() -> Path {
        Path::new(vec![
            Vector3::new(0.0, 0.0, 10.0),
            Vector3::new(10.0, 0.0, 10.0),
        ])
    }

    /// (position, R, expected LOS course in degrees): geometry of eq. 4 on a
    /// northbound leg; cross-track positive to the east, so an eastward offset
    /// steers west of north.
    #[test]
    fn los_geometry_table() {
        let path = north();
        let cases = [
            ([2.0, 0.0], 1.0, 0.0),
            ([2.0, 0.5], 1.0, -30.0),
            ([2.0, -0.5], 1.0, 30.0),
            ([2.0, 2f64.sqrt() / 2.0], 1.0, -45.0),
            // Circle misses the path: head for the waypoint (10, 0).
            ([2.0, 8.0], 1.0, -45.0),
        ];
        for (xy, r, want) in cases {
            let p = Vector2::new(xy[0], xy[1]);
            let e = path.errors(0, &p);
            let got = los_course(&path, &e, &p, r).to_degrees();
            assert!((got - want).abs() < 1e-9, "{xy:?}: {got} vs {want}");
        }
    }

    #[test]
    fn improved_los_approaches_along_the_normal() {
        let path = north();
        let e = path.errors(0, &Vector2::new(2.0, 3.0));
        assert!((improved_los_course(&e, 1.0, 0.5).to_degrees() + 90.0).abs() < 1e-9);
        let e = path.errors(0, &Vector2::new(2.0, -3.0));
        assert!((improved_los_course(&e, 1.0, 0.5).to_degrees() - 90.0).abs() < 1e-9);
        // Inside the turning radius it is eq. 4.
        let e = path.errors(0, &Vector2::new(2.0, 0.5));
        assert!((improved_los_course(&e, 1.0, 0.8).to_degrees() + 30.0).abs() < 1e-9);
        // The course always reduces |e|: its cross-track component opposes e.
        for y in [-2.0, -0.7, -0.1, 0.1, 0.7, 2.0] {
            let e = path.errors(0, &Vector2::new(2.0, y));
            let chi = improved_los_course(&e, 1.0, 0.8);
            assert!(chi.sin() * y < 0.0, "y {y}: chi {chi}");
        }
    }
}
