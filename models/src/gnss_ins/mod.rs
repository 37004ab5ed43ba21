//! `gnss-ins`: the INS error-state core aided by a GNSS position fix, a
//! barometer and a magnetic heading (`docs/ulog.md`, "The `gnss-ins` model").
//! The declaration is in [`model`], its two sensor blocks (`Barometer`, `MagneticHeading`) in `nav_blocks`, the
//! replay in [`replay`] with its running scores in [`scores`].

pub mod model;
pub mod replay;
pub mod scores;

pub use model::{GnssIns, GnssInsBarometer, GnssInsGnssFix, GnssInsMagneticHeading};
pub use replay::GnssInsReplay;

use nav_ins::{Absent, InitialSigma, InsVehicle};

/// `gnss-ins` is replayed by the shared loop with its GNSS, barometer and
/// magnetometer slots.
impl InsVehicle<16> for GnssIns {
    const REPLAY_NAME: &'static str = replay::NAME;
    const DESCRIPTION: &'static str =
        "16-state INS with GNSS position, barometer and magnetic heading (imported PX4 logs)";
    type Depth = Absent;
    type Dvl = Absent;
    type Compass = Absent;
    type CompassSmallAngle = Absent;
    type Usbl = Absent;
    type Gnss = GnssInsGnssFix;
    type Baro = GnssInsBarometer;
    type Mag = GnssInsMagneticHeading;
    /// 1 m, 0.5 m/s, 0.05 rad level, 0.1 rad heading: a PX4 log's initial
    /// state is PX4's own estimate at switch-on, far less certain than an
    /// aligned survey INS.
    const INITIAL_SIGMA: InitialSigma = InitialSigma {
        position: 1.0,
        velocity: 0.5,
        level: crate::ahrs::settings::LEVEL_SIGMA_DEFAULT,
        heading: crate::ahrs::settings::HEADING_SIGMA_DEFAULT,
    };
}

#[cfg(test)]
mod tests {
    use nav_runtime::model::{Model, Sensor};
    use nav_runtime::nalgebra::SVector;

    use super::model::{GnssInsInput, GnssInsParams};
    use super::{GnssIns, GnssInsBarometer};

    #[test]
    fn the_vehicle_fits_the_replay_loop() {
        let l = nav_ins::vehicle::Layout::of::<GnssIns, 16>().unwrap();
        assert_eq!(l.baro_bias, Some(15));
        let p = nav_ins::vehicle::Present::of::<GnssIns, 16>();
        assert!(p.gnss && p.baro && p.mag && !p.depth && !p.usbl);
    }

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
