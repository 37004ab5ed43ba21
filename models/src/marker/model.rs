//! MARKER-9: marker-aided navigation of a hover-capable AUV near a structure
//! (docs/models/marker9.md). Total-state, discrete-time (eq. 2), states
//! `[X, Y, Z, u, v, w, phi, theta, psi]`.

nav_runtime::model! {
    /// Marker-fusion filter, eq. 2 of the marker paper, with the body-frame
    /// velocity equation completed by the transport term `-w x v` (the paper's
    /// `v_k = v_{k-1} + a dt` holds only without rotation).
    pub model Marker9 {
        states {
            /// NED position in the local structure frame, m.
            position: 3,
            /// Body-frame velocity `[u, v, w]`, m/s.
            velocity: 3,
            /// Euler angles `[roll, pitch, yaw]`, rad.
            euler: 3,
        }
        inputs {
            /// Gyro output `[p, q, r]`, rad/s.
            gyro: 3,
            /// Body-frame acceleration with gravity removed, m/s^2.
            acceleration: 3,
        }
        noise {
            /// Per-step velocity variance from accelerometer noise, (m/s)^2.
            velocity_noise: 3,
            /// Per-step attitude variance from gyro noise, rad^2.
            attitude_noise: 3,
        }
        discrete {
            let roll = euler[0];
            let pitch = euler[1];
            let p = gyro[0];
            let q = gyro[1];
            let r = gyro[2];
            position = position + euler_dcm(roll, pitch, euler[2]) * velocity * dt;
            velocity = velocity + (acceleration - cross(gyro, velocity)) * dt + velocity_noise;
            euler = euler + [
                p + (q * sin(roll) + r * cos(roll)) * tan(pitch),
                q * cos(roll) - r * sin(roll),
                (q * sin(roll) + r * cos(roll)) / cos(pitch)
            ] * dt + attitude_noise;
        }
        /// DVL body-frame velocity, m/s.
        sensor Dvl: 3 {
            h = velocity;
        }
        /// Depth meter, m (positive down).
        sensor Depth: 1 {
            h = [position[2]];
        }
        /// Horizontal position fix from a visible marker of known position (eq. 3,
        /// already in the local frame), m. The fix is resolved with the estimated
        /// attitude, so its error is correlated with the attitude error, which
        /// this form cannot express; [`Marker9MarkerRelative`] can.
        sensor MarkerFix: 2 {
            h = [position[0], position[1]];
        }
        /// The raw camera detection of a marker of known position: the marker
        /// relative to the camera in body axes, m. The attitude enters `h`, so an
        /// update correlates position and attitude errors instead of treating a
        /// fix resolved with the estimated heading as independent of it.
        sensor MarkerRelative: 3 {
            inputs {
                /// Marker position in the local (structure) frame, m.
                marker: 3,
                /// Camera position in body axes, m.
                lever_arm: 3,
            }
            h = transpose(euler_dcm(euler[0], euler[1], euler[2])) * (marker - position) - lever_arm;
        }
    }
}
