//! PX4's 24-state prediction written as a user copying a paper would: the
//! rotation as an explicit matrix of the quaternion's components instead of
//! the builtin `quat_to_dcm`, declared in this crate rather than in
//! `models` (docs/performance.md, "PX4's 24-state model"). Shared by the
//! propagation bench and `models/tests/scenarios/px4_rotation_matrix.rs`.

use models::px4_ekf24::{Px4Ekf24Input, Px4Ekf24Noise, Px4Ekf24Params};

/// One declaration per rotation matrix: the model `$name` with
/// `C_b^n = $rotation` (in terms of `q0..q3`, `[w, x, y, z]`), and
/// `$convert`, which turns the builtin model's input, parameters and noise
/// into this model's.
macro_rules! px4_with_matrix {
    ($(#[$doc:meta])* $name:ident, $input:ident, $params:ident, $noise:ident, $convert:ident, $rotation:expr) => {
        nav_runtime::model! {
            $(#[$doc])*
            pub model $name {
                states {
                    quaternion: 4,
                    velocity: 3,
                    position: 3,
                    gyro_bias: 3,
                    accel_bias: 3,
                    earth_magnetic_field: 3,
                    body_magnetic_field: 3,
                    wind_velocity: 2,
                }
                inputs {
                    delta_velocity: 3,
                    delta_velocity_dt,
                    delta_angle: 3,
                    delta_angle_dt,
                }
                parameters { gravity }
                noise { delta_velocity_noise: 3, delta_angle_noise: 3 }
                discrete {
                    let angle = delta_angle + delta_angle_noise - gyro_bias * delta_angle_dt;
                    let velocity_increment =
                        delta_velocity + delta_velocity_noise - accel_bias * delta_velocity_dt;
                    let q0 = quaternion[0];
                    let q1 = quaternion[1];
                    let q2 = quaternion[2];
                    let q3 = quaternion[3];
                    let rotation = $rotation;
                    quaternion = quat_mul(
                        quaternion,
                        [1.0, 0.5 * angle[0], 0.5 * angle[1], 0.5 * angle[2]],
                    );
                    velocity = velocity + rotation * velocity_increment
                        + [0.0, 0.0, gravity * delta_velocity_dt];
                    position = position + velocity * delta_velocity_dt;
                }
            }
        }

        /// The builtin model's input, parameters and noise as this model's.
        pub fn $convert(
            u: &Px4Ekf24Input,
            p: &Px4Ekf24Params,
            q: &Px4Ekf24Noise,
        ) -> ($input, $params, $noise) {
            (
                $input {
                    delta_velocity: u.delta_velocity,
                    delta_velocity_dt: u.delta_velocity_dt,
                    delta_angle: u.delta_angle,
                    delta_angle_dt: u.delta_angle_dt,
                },
                $params { gravity: p.gravity },
                $noise {
                    delta_velocity_noise: q.delta_velocity_noise,
                    delta_angle_noise: q.delta_angle_noise,
                },
            )
        }
    };
}

px4_with_matrix!(
    /// The textbook matrix of a unit quaternion, `1 - 2(q2² + q3²), 2(q1 q2 - q0 q3), ..`:
    /// the same function as `quat_to_dcm`, written out.
    Px4RotationMatrix,
    Px4RotationMatrixInput,
    Px4RotationMatrixParams,
    Px4RotationMatrixNoise,
    rotation_matrix_point,
    [
        [1.0 - 2.0 * (q2 * q2 + q3 * q3), 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2)],
        [2.0 * (q1 * q2 + q0 * q3), 1.0 - 2.0 * (q1 * q1 + q3 * q3), 2.0 * (q2 * q3 - q0 * q1)],
        [2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), 1.0 - 2.0 * (q1 * q1 + q2 * q2)],
    ]
);

px4_with_matrix!(
    /// The homogeneous form of PX4's own derivation, `q0² + q1² - q2² - q3², ..`
    /// on the diagonal: equal to `quat_to_dcm` on unit quaternions only, so its
    /// Jacobian differs along the quaternion's own direction.
    Px4HomogeneousMatrix,
    Px4HomogeneousMatrixInput,
    Px4HomogeneousMatrixParams,
    Px4HomogeneousMatrixNoise,
    homogeneous_matrix_point,
    [
        [q0 * q0 + q1 * q1 - q2 * q2 - q3 * q3, 2.0 * (q1 * q2 - q0 * q3), 2.0 * (q1 * q3 + q0 * q2)],
        [2.0 * (q1 * q2 + q0 * q3), q0 * q0 - q1 * q1 + q2 * q2 - q3 * q3, 2.0 * (q2 * q3 - q0 * q1)],
        [2.0 * (q1 * q3 - q0 * q2), 2.0 * (q2 * q3 + q0 * q1), q0 * q0 - q1 * q1 - q2 * q2 + q3 * q3],
    ]
);
