//! A forward-looking camera that detects active markers of known position and
//! turns each detection into a vehicle position fix (docs/models/marker9.md, eq. 3).
//!
//! Visibility: within `[min_range, max_range]`, inside the field of view around
//! body x, the marker face turned toward the camera (angle between its normal and
//! the sight line below `max_incidence`), and the sight line not blocked by any
//! capsule of the structure.
//!
//! Measurement: the camera measures the marker position in body axes with a
//! bearing error `sigma_bearing` per axis and a range error
//! `sigma_range0 + k_range r` (pose-from-marker accuracy degrades with range).
//! The navigation computer resolves it with its *estimated* attitude,
//! `p_fix = m - C_b^n(estimate) rel_measured`, so heading error enters the fix as
//! `r delta psi`; [`Camera::fix_sigma`] gives the matching 1-sigma.

use nalgebra::{Matrix3, Vector3};
use rand::Rng;

use crate::guidance::structure::Structure;
use crate::sensors::normal;

/// Camera model settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    /// Closest usable range, m.
    pub min_range: f64,
    /// Farthest range at which a marker is detected (water clarity), m.
    pub max_range: f64,
    /// Half field of view, horizontal, rad.
    pub half_fov_h: f64,
    /// Half field of view, vertical, rad.
    pub half_fov_v: f64,
    /// Largest angle between the marker normal and the sight line, rad.
    pub max_incidence: f64,
    /// Bearing error 1-sigma per axis, rad.
    pub sigma_bearing: f64,
    /// Range error 1-sigma at zero range, m.
    pub sigma_range0: f64,
    /// Range error growth, m per m.
    pub k_range: f64,
    /// Camera position in body axes, m.
    pub lever_arm: Vector3<f64>,
    /// At most this many markers are used per frame (the nearest).
    pub max_per_frame: usize,
}

impl Default for Camera {
    fn default() -> Self {
        Self {
            min_range: 0.3,
            max_range: 6.0,
            half_fov_h: 50f64.to_radians(),
            half_fov_v: 40f64.to_radians(),
            max_incidence: 75f64.to_radians(),
            sigma_bearing: 0.3f64.to_radians(),
            sigma_range0: 0.01,
            k_range: 0.01,
            lever_arm: Vector3::new(0.3, 0.0, 0.0),
            max_per_frame: 3,
        }
    }
}

/// One marker detection, as the camera sees it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Detection {
    /// Index of the marker.
    pub marker: usize,
    /// True range to the marker, m.
    pub range: f64,
    /// Measured marker position relative to the camera, body axes, m.
    pub relative: Vector3<f64>,
    /// Covariance of `relative`: range sigma along the sight line, range times
    /// bearing sigma across it, m^2.
    pub covariance: Matrix3<f64>,
}

/// One marker detection turned into a fix.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MarkerFix {
    /// Index of the marker.
    pub marker: usize,
    /// Range to the marker, m.
    pub range: f64,
    /// Fixed vehicle position (NED, m).
    pub position: Vector3<f64>,
}

impl Camera {
    /// Indices of the markers visible from a camera at body pose
    /// (`position`, `c_bn`), nearest first, at most `max_per_frame`.
    pub fn visible(
        &self,
        s: &Structure,
        position: &Vector3<f64>,
        c_bn: &Matrix3<f64>,
    ) -> Vec<(usize, f64)> {
        let cam = position + c_bn * self.lever_arm;
        let c_nb = c_bn.transpose();
        let mut out: Vec<(usize, f64)> = Vec::new();
        for (i, m) in s.markers.iter().enumerate() {
            let d = m.position - cam;
            let range = d.norm();
            if range < self.min_range || range > self.max_range {
                continue;
            }
            // Facing: the camera is on the marker's front side.
            if (-d / range).dot(&m.normal) < self.max_incidence.cos() {
                continue;
            }
            let b = c_nb * d;
            if b.x <= 0.0
                || b.y.atan2(b.x).abs() > self.half_fov_h
                || b.z.atan2(b.x).abs() > self.half_fov_v
            {
                continue;
            }
            if s.occluded(&cam, &m.position, m.capsule) {
                continue;
            }
            out.push((i, range));
        }
        out.sort_by(|a, b| a.1.total_cmp(&b.1));
        out.truncate(self.max_per_frame);
        out
    }

    /// Detects marker `i` from the true pose: the marker relative to the camera
    /// in body axes with range and bearing noise, and that noise's covariance.
    pub fn detect<R: Rng + ?Sized>(
        &self,
        s: &Structure,
        i: usize,
        position: &Vector3<f64>,
        c_bn: &Matrix3<f64>,
        rng: &mut R,
    ) -> Detection {
        let m = s.markers[i].position;
        let cam = position + c_bn * self.lever_arm;
        let rel_b = c_bn.transpose() * (m - cam);
        let range = rel_b.norm();
        let dir = rel_b / range;
        // Range error along the sight line, bearing errors across it.
        let sr = self.sigma_range0 + self.k_range * range;
        let sb = range * self.sigma_bearing;
        let (u1, u2) = perpendiculars(&dir);
        let relative = rel_b + dir * normal(rng, sr) + u1 * normal(rng, sb) + u2 * normal(rng, sb);
        let covariance = dir * dir.transpose() * (sr * sr)
            + (Matrix3::identity() - dir * dir.transpose()) * (sb * sb);
        Detection {
            marker: i,
            range,
            relative,
            covariance,
        }
    }

    /// Measures marker `i` from the true pose and resolves it with the estimated
    /// attitude `c_bn_est` into a fix of the vehicle (body origin) position.
    #[allow(clippy::too_many_arguments)]
    pub fn fix<R: Rng + ?Sized>(
        &self,
        s: &Structure,
        i: usize,
        position: &Vector3<f64>,
        c_bn: &Matrix3<f64>,
        c_bn_est: &Matrix3<f64>,
        rng: &mut R,
    ) -> MarkerFix {
        let d = self.detect(s, i, position, c_bn, rng);
        let position_fix = s.markers[i].position - c_bn_est * (d.relative + self.lever_arm);
        MarkerFix {
            marker: i,
            range: d.range,
            position: position_fix,
        }
    }

    /// Horizontal 1-sigma of a fix at `range` with heading uncertainty
    /// `sigma_heading` (rad): range, bearing and `r delta psi` combined.
    pub fn fix_sigma(&self, range: f64, sigma_heading: f64) -> f64 {
        let sr = self.sigma_range0 + self.k_range * range;
        let sb = range * self.sigma_bearing;
        let sh = range * sigma_heading;
        (sr * sr + sb * sb + sh * sh).sqrt()
    }
}

/// Two unit vectors completing `d` to an orthonormal basis.
fn perpendiculars(d: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let helper = if d.z.abs() < 0.9 {
        Vector3::z()
    } else {
        Vector3::x()
    };
    let u1 = d.cross(&helper).normalize();
    let u2 = d.cross(&u1);
    (u1, u2)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::Euler;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn visibility_rules() {
        let s = Structure::test_jacket();
        let cam = Camera::default();
        // Outside the +y face at mid-depth looking south-west along the face
        // (heading -100 deg): the outward markers ahead are visible.
        let p = Vector3::new(1.0, 2.4, 16.0);
        let look = |yaw_deg: f64| Euler::from_degrees(0.0, 0.0, yaw_deg).c_bn();
        let v = cam.visible(&s, &p, &look(-135.0));
        assert!(!v.is_empty());
        for &(i, _) in &v {
            assert!(s.markers[i].normal.y > 0.0, "only outward-facing markers");
        }
        // Looking away from the structure: nothing.
        assert!(cam.visible(&s, &p, &look(90.0)).is_empty());
        // Inside the jacket: inward-facing markers only, never the outward ones
        // on the far side of a leg.
        let inside = Vector3::new(-1.5, 0.0, 16.0);
        for &(i, _) in &cam.visible(&s, &inside, &look(20.0)) {
            assert!(s.markers[i].normal.y * s.markers[i].position.y < 0.0);
        }
    }

    #[test]
    fn fix_error_matches_its_sigma() {
        let s = Structure::test_jacket();
        let cam = Camera::default();
        let p = Vector3::new(1.0, 2.4, 16.0);
        let c = Euler::from_degrees(1.0, -2.0, -135.0).c_bn();
        let (i, range) = cam.visible(&s, &p, &c)[0];
        let mut rng = ChaCha8Rng::seed_from_u64(3);
        let n = 4000;
        let mut sq = 0.0;
        for _ in 0..n {
            let f = cam.fix(&s, i, &p, &c, &c, &mut rng);
            sq += (f.position - p).norm_squared();
        }
        // Three axes; fix_sigma is per horizontal axis.
        let rms_axis = (sq / (3.0 * n as f64)).sqrt();
        let sigma = cam.fix_sigma(range, 0.0);
        assert!(
            rms_axis < 1.1 * sigma && rms_axis > 0.5 * sigma,
            "{rms_axis} vs {sigma}"
        );
        // A heading error displaces the fix by about range * error.
        let c_est = Euler::from_degrees(1.0, -2.0, -134.0).c_bn();
        let f = cam.fix(&s, i, &p, &c, &c_est, &mut rng);
        let shift = (f.position - p).norm();
        assert!((shift - range * 1f64.to_radians()).abs() < 5.0 * sigma);
    }

    /// The detection noise has the covariance `detect` reports: the mean of
    /// `e^T C^-1 e` over 4000 draws is 3 (three degrees of freedom) within
    /// its sampling error (sd of the mean sqrt(6 / 4000) = 0.039).
    #[test]
    fn detection_error_matches_its_covariance() {
        let s = Structure::test_jacket();
        let cam = Camera::default();
        let p = Vector3::new(1.0, 2.4, 16.0);
        let c = Euler::from_degrees(1.0, -2.0, -135.0).c_bn();
        let (i, _) = cam.visible(&s, &p, &c)[0];
        let truth = c.transpose() * (s.markers[i].position - (p + c * cam.lever_arm));
        let mut rng = ChaCha8Rng::seed_from_u64(5);
        let n = 4000;
        let mut nees = 0.0;
        for _ in 0..n {
            let d = cam.detect(&s, i, &p, &c, &mut rng);
            let e = d.relative - truth;
            let inv = d.covariance.try_inverse().expect("covariance invertible");
            nees += (e.transpose() * inv * e)[0];
        }
        let mean = nees / n as f64;
        assert!((mean - 3.0).abs() < 4.0 * 0.039, "mean NEES {mean}");
    }
}
