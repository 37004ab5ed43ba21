//! `gnss-ins`: the INS error-state core aided by a GNSS position fix, a
//! barometer and a magnetic heading (`docs/ulog.md`, "The `gnss-ins` model").
//! The declaration is in [`model`], its two sensor blocks in [`blocks`].

pub mod blocks;
pub mod model;
pub mod replay;

pub use model::{GnssIns, GnssInsBarometer, GnssInsGnssFix, GnssInsMagneticHeading};
pub use replay::GnssInsReplay;

#[cfg(test)]
mod tests {
    use nav_runtime::model::{Model, Sensor};
    use nav_runtime::nalgebra::SVector;

    use super::model::{GnssInsInput, GnssInsParams};
    use super::{GnssIns, GnssInsBarometer};

    #[test]
    fn sixteen_states_all_used() {
        assert_eq!(GnssIns::N, 16);
        assert!(
            GnssIns::UNUSED_STATES.is_empty(),
            "{:?}",
            GnssIns::UNUSED_STATES
        );
        assert_eq!(<GnssIns as Model<16>>::STATE_NAMES[15], "baro_bias");
    }

    /// eq. G1: INS height 2 m above truth, barometer reading 0.5 m high.
    #[test]
    fn barometer_residual_is_height_error_minus_bias() {
        let mut x = SVector::<f64, 16>::zeros();
        x[2] = 2.0;
        x[15] = 0.5;
        let h =
            GnssInsBarometer::predict(&x, &GnssInsInput::default(), &GnssInsParams::default(), &());
        assert!((h[0] - 1.5).abs() < 1e-15);
    }
}
