//! Attitude representations: Euler angles, direction cosine matrices,
//! rotation vectors and quaternions, plus the small-rotation error conventions
//! of the error-state filter.
//!
//! Conventions (docs/models/conventions.md): n = North-East-Down, b = forward-right-down,
//! Z-Y-X Euler angles (yaw psi, pitch theta, roll phi) with
//! `C_n^b = C_x(phi) C_y(theta) C_z(psi)` and `C_b^n = (C_n^b)^T`. Attitude
//! errors follow SDINS-25: the computed matrix is `C^_b^n = (I - [phi x]) C_b^n`.
//!
//! `core` + libm only (via [`crate::math`]), so it builds `no_std`.

use crate::math::{abs, asin, atan2, cos, sin, sqrt};
use nalgebra::{Matrix3, Quaternion, UnitQuaternion, Vector3};

/// Z-Y-X Euler angles (rad).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Euler {
    /// Roll phi (rad), rotation about body x.
    pub roll: f64,
    /// Pitch theta (rad), rotation about the intermediate y; nose up positive.
    pub pitch: f64,
    /// Yaw / heading psi (rad), rotation about down; 0 = north, +pi/2 = east.
    pub yaw: f64,
}

impl Euler {
    /// From roll, pitch, yaw (rad).
    pub const fn new(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self { roll, pitch, yaw }
    }
    /// From roll, pitch, yaw in degrees.
    pub fn from_degrees(roll: f64, pitch: f64, yaw: f64) -> Self {
        Self {
            roll: roll.to_radians(),
            pitch: pitch.to_radians(),
            yaw: yaw.to_radians(),
        }
    }
    /// `C_n^b` (navigation to body).
    pub fn c_nb(&self) -> Matrix3<f64> {
        c_nb_from_euler(self)
    }
    /// `C_b^n` (body to navigation).
    pub fn c_bn(&self) -> Matrix3<f64> {
        c_nb_from_euler(self).transpose()
    }
}

/// Skew-symmetric matrix `[a x]`, so that `[a x] b = a x b`.
#[inline]
pub fn skew(a: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::new(0.0, -a[2], a[1], a[2], 0.0, -a[0], -a[1], a[0], 0.0)
}

/// The vector of a skew-symmetric matrix (the antisymmetric part of `m`):
/// `vee([a x]) = a`.
#[inline]
pub fn vee(m: &Matrix3<f64>) -> Vector3<f64> {
    Vector3::new(
        0.5 * (m[(2, 1)] - m[(1, 2)]),
        0.5 * (m[(0, 2)] - m[(2, 0)]),
        0.5 * (m[(1, 0)] - m[(0, 1)]),
    )
}

/// `C_n^b = C_x(phi) C_y(theta) C_z(psi)`, the matrix printed in docs/models/conventions.md.
pub fn c_nb_from_euler(e: &Euler) -> Matrix3<f64> {
    let (sf, cf) = (sin(e.roll), cos(e.roll));
    let (st, ct) = (sin(e.pitch), cos(e.pitch));
    let (sp, cp) = (sin(e.yaw), cos(e.yaw));
    Matrix3::new(
        ct * cp,
        ct * sp,
        -st,
        sf * st * cp - cf * sp,
        sf * st * sp + cf * cp,
        sf * ct,
        cf * st * cp + sf * sp,
        cf * st * sp - sf * cp,
        cf * ct,
    )
}

/// `C_b^n = (C_n^b)^T`.
pub fn c_bn_from_euler(e: &Euler) -> Matrix3<f64> {
    c_nb_from_euler(e).transpose()
}

/// Euler angles of `C_b^n`: `theta = -asin(C_b^n[2,0])`,
/// `phi = atan2(C_b^n[2,1], C_b^n[2,2])`, `psi = atan2(C_b^n[1,0], C_b^n[0,0])`
/// (yaw in (-pi, pi]). At pitch = +-90 deg roll and yaw are not separable; the
/// function then returns roll = 0 and puts the whole rotation in yaw.
pub fn euler_from_c_bn(c: &Matrix3<f64>) -> Euler {
    let s = c[(2, 0)].clamp(-1.0, 1.0);
    let pitch = -asin(s);
    if abs(s) > 1.0 - 1e-15 {
        // Gimbal lock: only psi - phi (or psi + phi) is defined; with roll := 0
        // the matrix gives C_b^n[0,1] = -sin psi, C_b^n[1,1] = cos psi.
        let yaw = atan2(-c[(0, 1)], c[(1, 1)]);
        return Euler {
            roll: 0.0,
            pitch,
            yaw,
        };
    }
    Euler {
        roll: atan2(c[(2, 1)], c[(2, 2)]),
        pitch,
        yaw: atan2(c[(1, 0)], c[(0, 0)]),
    }
}

/// Body angular rate relative to n from Euler angles and their rates,
/// `w_nb^b = [phidot - psidot sin theta, thetadot cos phi + psidot sin phi cos theta,
///  -thetadot sin phi + psidot cos phi cos theta]` (rad/s), for Z-Y-X angles
/// (Titterton & Weston ch. 3, Euler-angle propagation).
pub fn body_rate_from_euler_rates(e: &Euler, rates: &Euler) -> Vector3<f64> {
    let (sf, cf) = (sin(e.roll), cos(e.roll));
    let (st, ct) = (sin(e.pitch), cos(e.pitch));
    Vector3::new(
        rates.roll - rates.yaw * st,
        rates.pitch * cf + rates.yaw * sf * ct,
        -rates.pitch * sf + rates.yaw * cf * ct,
    )
}

/// Rotation matrix of a rotation vector (Rodrigues' formula; Titterton & Weston
/// ch. 11, attitude update with a rotation vector): `exp([phi x]) = I +
/// sin|phi|/|phi| [phi x] + (1 - cos|phi|)/|phi|^2 [phi x]^2`, with Taylor
/// coefficients for small angles.
pub fn rotation_from_rotvec(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi.norm_squared();
    let (a, b) = if t2 < 1e-8 {
        // sin t/t and (1-cos t)/t^2 to O(t^6): error < 1e-25.
        (
            1.0 - t2 / 6.0 * (1.0 - t2 / 20.0),
            0.5 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0)),
        )
    } else {
        let t = sqrt(t2);
        (sin(t) / t, (1.0 - cos(t)) / t2)
    };
    let k = skew(phi);
    Matrix3::identity() + k * a + k * k * b
}

/// Rotation vector of a rotation matrix (the inverse of [`rotation_from_rotvec`]),
/// angle in [0, pi].
pub fn rotvec_from_rotation(c: &Matrix3<f64>) -> Vector3<f64> {
    let q = quat_from_dcm(c);
    let (w, v) = (q.w, q.imag());
    let sn = v.norm();
    if sn < 1e-300 {
        return Vector3::zeros();
    }
    // angle = 2 atan2(|v|, w), taking the shorter rotation.
    let (w, v) = if w < 0.0 { (-w, -v) } else { (w, v) };
    let angle = 2.0 * atan2(sn, w);
    v * (angle / sn)
}

/// Unit quaternion of a rotation matrix (Shepperd's method, stable for any
/// rotation). For `C_b^n` the quaternion rotates body vectors into n.
pub fn quat_from_dcm(c: &Matrix3<f64>) -> UnitQuaternion<f64> {
    let tr = c[(0, 0)] + c[(1, 1)] + c[(2, 2)];
    let q = if tr > c[(0, 0)] && tr > c[(1, 1)] && tr > c[(2, 2)] {
        let s = 2.0 * sqrt(1.0 + tr);
        Quaternion::new(
            0.25 * s,
            (c[(2, 1)] - c[(1, 2)]) / s,
            (c[(0, 2)] - c[(2, 0)]) / s,
            (c[(1, 0)] - c[(0, 1)]) / s,
        )
    } else if c[(0, 0)] > c[(1, 1)] && c[(0, 0)] > c[(2, 2)] {
        let s = 2.0 * sqrt(1.0 + c[(0, 0)] - c[(1, 1)] - c[(2, 2)]);
        Quaternion::new(
            (c[(2, 1)] - c[(1, 2)]) / s,
            0.25 * s,
            (c[(0, 1)] + c[(1, 0)]) / s,
            (c[(0, 2)] + c[(2, 0)]) / s,
        )
    } else if c[(1, 1)] > c[(2, 2)] {
        let s = 2.0 * sqrt(1.0 - c[(0, 0)] + c[(1, 1)] - c[(2, 2)]);
        Quaternion::new(
            (c[(0, 2)] - c[(2, 0)]) / s,
            (c[(0, 1)] + c[(1, 0)]) / s,
            0.25 * s,
            (c[(1, 2)] + c[(2, 1)]) / s,
        )
    } else {
        let s = 2.0 * sqrt(1.0 - c[(0, 0)] - c[(1, 1)] + c[(2, 2)]);
        Quaternion::new(
            (c[(1, 0)] - c[(0, 1)]) / s,
            (c[(0, 2)] + c[(2, 0)]) / s,
            (c[(1, 2)] + c[(2, 1)]) / s,
            0.25 * s,
        )
    };
    UnitQuaternion::new_normalize(q)
}

/// Rotation matrix of a unit quaternion.
pub fn dcm_from_quat(q: &UnitQuaternion<f64>) -> Matrix3<f64> {
    let (w, x, y, z) = (q.w, q.i, q.j, q.k);
    Matrix3::new(
        1.0 - 2.0 * (y * y + z * z),
        2.0 * (x * y - w * z),
        2.0 * (x * z + w * y),
        2.0 * (x * y + w * z),
        1.0 - 2.0 * (x * x + z * z),
        2.0 * (y * z - w * x),
        2.0 * (x * z - w * y),
        2.0 * (y * z + w * x),
        1.0 - 2.0 * (x * x + y * y),
    )
}

/// Nearest orthonormal matrix (polar factor), by the Newton-Schulz iteration
/// `C <- C (3I - C^T C)/2` (Titterton & Weston ch. 11, orthonormalization, uses its first step).
/// Converges quadratically for `|C^T C - I| < 1`; stops at 1e-15.
pub fn orthonormalize(c: &Matrix3<f64>) -> Matrix3<f64> {
    let mut x = *c;
    for _ in 0..20 {
        let e = x.transpose() * x - Matrix3::identity();
        if e.amax() < 1e-15 {
            break;
        }
        x -= x * e * 0.5;
    }
    x
}

/// Applies an attitude error to a true matrix: `C^_b^n = (I - [phi x]) C_b^n`
/// (docs/models/sdins25.md, error state 6-8), re-orthonormalized so the result is a
/// rotation. `phi` (rad) in n.
pub fn perturb_c_bn(c_bn: &Matrix3<f64>, phi: &Vector3<f64>) -> Matrix3<f64> {
    orthonormalize(&((Matrix3::identity() - skew(phi)) * c_bn))
}

/// Removes an estimated attitude error from a computed matrix, the feedback step
/// of the error-state filter: `C_b^n <- (I + [phi x]) C^_b^n`, re-orthonormalized
/// (the first-order inverse of [`perturb_c_bn`]). `phi` (rad) in n.
pub fn correct_c_bn(c_hat: &Matrix3<f64>, phi: &Vector3<f64>) -> Matrix3<f64> {
    orthonormalize(&((Matrix3::identity() + skew(phi)) * c_hat))
}

/// The attitude error of a computed matrix relative to the true one, exact
/// (not first-order): the `phi` with `C^_b^n = exp(-[phi x]) C_b^n`, i.e.
/// `phi = log(C_b^n C^_b^n^T)` (rad, in n).
pub fn attitude_error(c_hat: &Matrix3<f64>, c_true: &Matrix3<f64>) -> Vector3<f64> {
    rotvec_from_rotation(&(c_true * c_hat.transpose()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use core::f64::consts::PI;

    fn rotx(a: f64) -> Matrix3<f64> {
        // Frame rotation (passive), as in C_x(phi) of docs/models/conventions.md.
        Matrix3::new(1.0, 0.0, 0.0, 0.0, a.cos(), a.sin(), 0.0, -a.sin(), a.cos())
    }
    fn roty(a: f64) -> Matrix3<f64> {
        Matrix3::new(a.cos(), 0.0, -a.sin(), 0.0, 1.0, 0.0, a.sin(), 0.0, a.cos())
    }
    fn rotz(a: f64) -> Matrix3<f64> {
        Matrix3::new(a.cos(), a.sin(), 0.0, -a.sin(), a.cos(), 0.0, 0.0, 0.0, 1.0)
    }

    #[test]
    fn c_nb_is_the_product_of_elementary_rotations() {
        let e = Euler::from_degrees(12.0, -33.0, 147.0);
        let want = rotx(e.roll) * roty(e.pitch) * rotz(e.yaw);
        assert!((c_nb_from_euler(&e) - want).norm() < 1e-15);
        // Body x of a vehicle at yaw 90 deg, level, points east.
        let c = Euler::from_degrees(0.0, 0.0, 90.0).c_bn();
        assert!((c * Vector3::x() - Vector3::y()).norm() < 1e-15);
        // Nose up: body x has a negative down component.
        let c = Euler::from_degrees(0.0, 10.0, 0.0).c_bn();
        assert!((c * Vector3::x())[2] < 0.0);
    }

    #[test]
    fn euler_dcm_round_trip() {
        for r in [-170.0, -45.0, 0.0, 30.0, 179.0] {
            for p in [-89.0, -30.0, 0.0, 10.0, 89.9] {
                for y in [-179.5, -90.0, 0.0, 45.0, 180.0] {
                    let e = Euler::from_degrees(r, p, y);
                    let back = euler_from_c_bn(&e.c_bn());
                    assert!((back.roll - e.roll).abs() < 1e-9, "{r} {p} {y}: {back:?}");
                    assert!((back.pitch - e.pitch).abs() < 1e-9);
                    assert!(crate::math::wrap_angle(back.yaw - e.yaw).abs() < 1e-9);
                }
            }
        }
        // Gimbal lock: the matrix is still reproduced.
        let e = Euler::from_degrees(20.0, 90.0, 30.0);
        let back = euler_from_c_bn(&e.c_bn());
        assert!((back.c_bn() - e.c_bn()).norm() < 1e-7);
    }

    #[test]
    fn quaternion_and_rotvec_round_trips() {
        for e in [
            Euler::from_degrees(10.0, 20.0, 30.0),
            Euler::from_degrees(179.0, -5.0, -179.0),
            Euler::default(),
        ] {
            let c = e.c_bn();
            let q = quat_from_dcm(&c);
            assert!((dcm_from_quat(&q) - c).norm() < 1e-14);
            // Same as nalgebra's rotation matrix of the quaternion.
            assert!((q.to_rotation_matrix().into_inner() - c).norm() < 1e-14);
            let v = rotvec_from_rotation(&c);
            assert!((rotation_from_rotvec(&v) - c).norm() < 1e-14);
        }
        let v = Vector3::new(0.3, -1.2, 2.0);
        assert!((rotvec_from_rotation(&rotation_from_rotvec(&v)) - v).norm() < 1e-13);
        let v = Vector3::new(1e-7, 2e-7, -3e-9);
        assert!((rotvec_from_rotation(&rotation_from_rotvec(&v)) - v).norm() < 1e-20);
        let big = Vector3::new(0.0, 0.0, PI - 1e-9);
        assert!((rotvec_from_rotation(&rotation_from_rotvec(&big)) - big).norm() < 1e-8);
    }

    #[test]
    fn euler_rates_match_dcm_derivative() {
        // Cdot_b^n = C_b^n [w_nb^b x]; compare with a central difference.
        let e = Euler::new(0.3, -0.4, 2.0);
        let rates = Euler::new(0.05, -0.02, 0.1);
        let dt = 1e-6;
        let at = |s: f64| {
            Euler::new(
                e.roll + s * rates.roll,
                e.pitch + s * rates.pitch,
                e.yaw + s * rates.yaw,
            )
            .c_bn()
        };
        let cdot = (at(dt) - at(-dt)) / (2.0 * dt);
        let w = body_rate_from_euler_rates(&e, &rates);
        assert!((cdot - e.c_bn() * skew(&w)).norm() < 1e-9);
    }

    #[test]
    fn small_rotation_perturb_and_correct() {
        let c = Euler::from_degrees(5.0, -3.0, 77.0).c_bn();
        let phi = Vector3::new(1e-3, -2e-3, 5e-3);
        let c_hat = perturb_c_bn(&c, &phi);
        assert!((c_hat.transpose() * c_hat - Matrix3::identity()).amax() < 1e-15);
        // The measured error is phi to first order (the polar factor of (I - [phi x])
        // is a rotation by atan|phi| about phi).
        let err = attitude_error(&c_hat, &c);
        assert!((err - phi).norm() < phi.norm().powi(3), "{err:?}");
        // Correction inverts the perturbation to second order in phi.
        let back = correct_c_bn(&c_hat, &phi);
        assert!(attitude_error(&back, &c).norm() < phi.norm().powi(2));
        // skew/vee
        let a = Vector3::new(1.0, 2.0, 3.0);
        let b = Vector3::new(-0.5, 0.25, 4.0);
        assert!((skew(&a) * b - a.cross(&b)).norm() < 1e-15);
        assert_eq!(vee(&skew(&a)), a);
    }

    #[test]
    fn orthonormalize_restores_rotation() {
        let c = Euler::from_degrees(40.0, 20.0, -100.0).c_bn();
        let noisy = c + Matrix3::new(1e-4, -2e-4, 0.0, 3e-4, 0.0, 1e-4, 0.0, -1e-4, 2e-4);
        let o = orthonormalize(&noisy);
        assert!((o.transpose() * o - Matrix3::identity()).amax() < 1e-15);
        assert!((o - c).norm() < 1e-3);
        assert!((o.determinant() - 1.0).abs() < 1e-14);
    }
}
