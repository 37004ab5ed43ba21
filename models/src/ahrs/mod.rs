//! `ahrs`: attitude and gyro bias from gyro, accelerometer and magnetometer
//! (`docs/ulog.md`, "The `ahrs` model"). The declaration is in [`model`].

pub mod gravity_window;
pub use nav_ins::heading;
pub mod measurement;
pub mod model;
pub mod nominal;
pub mod outputs;
pub mod replay;
pub mod settings;
pub mod smoothing;
pub mod stream;

pub use heading::{declination_from, horizontal_field, magnetic_heading};
pub use model::{Ahrs, AhrsGravity, AhrsHeading};
pub use nominal::{AhrsFilter, AhrsNominal};
pub use replay::AhrsReplay;
pub use settings::AhrsSettings;
pub use stream::AhrsStream;

#[cfg(test)]
mod tests {
    use nav_runtime::model::Sensor;
    use nav_runtime::nalgebra::{SMatrix, SVector};

    use super::model::{AhrsInput, AhrsParams};
    use super::{AhrsGravity, AhrsHeading};

    /// At a level attitude `h = phi x [0, 0, -g]` exactly (eq. A2 is linear
    /// in `phi` there): a roll error moves gravity into the body y axis.
    #[test]
    fn attitude_errors_move_the_predicted_gravity_and_heading() {
        let u = AhrsInput {
            c_bn: SMatrix::identity(),
        };
        let p = AhrsParams { gravity: 9.8 };
        // (attitude error, expected gravity residual, expected heading residual)
        let cases = [
            ([0.01, 0.0, 0.0], [0.0, 0.098, 0.0], 0.0),
            ([0.0, 0.01, 0.0], [-0.098, 0.0, 0.0], 0.0),
            ([0.0, 0.0, 0.01], [0.0, 0.0, 0.0], -(0.01f64.atan())),
        ];
        for (phi, gravity, heading) in cases {
            let x = SVector::<f64, 6>::from([phi[0], phi[1], phi[2], 0.0, 0.0, 0.0]);
            let h = AhrsGravity::predict(&x, &u, &p, &());
            for i in 0..3 {
                assert!((h[i] - gravity[i]).abs() < 1e-12, "{phi:?}: {h}");
            }
            let psi = AhrsHeading::predict(&x, &u, &p, &());
            assert!((psi[0] - heading).abs() < 1e-12, "{phi:?}: {psi}");
        }
    }
}
