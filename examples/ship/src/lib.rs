//! A ship, declared as a user declares a vehicle in their own crate: the INS
//! core, a GNSS antenna on a mast (lever arm), a gyrocompass, and a speed log
//! (speed through water) whose block is written here, with the water current
//! and the log's scale error as states of its own and the current's random
//! walk as process noise of its own. `src/main.rs` is its replay program;
//! `tests/ship_replay.rs` replays a simulated voyage through it.
//!
//! The speed log is fed by its declared name from the log's `replay.toml`
//! (`docs/pipeline.md`, "Sensors of your own"):
//!
//! ```toml
//! [sensors.WaterSpeed]
//! file = "water_speed.csv"
//! z = "speed"
//! sigma = 0.03
//!
//! [noise]
//! current_noise = 1e-7
//!
//! [initial.sigma]
//! current = 1.0
//! log_scale = 0.05
//! ```

use nav_blocks::{Compass, GnssFix, GnssFixCalibrated, InsCore};
use nav_ins::{Absent, InsVehicle};

nav_runtime::model! {
    /// Speed through water from a speed log with a scale error, and the
    /// horizontal water current as a random walk.
    pub block WaterSpeed {
        states {
            /// Water current, north and east, m/s.
            current: 2,
            /// Scale error of the speed log (dimensionless).
            log_scale,
        }
        needs { velocity: 3, c_bn: 3x3, velocity_error: 3, attitude_error: 3 }
        noise {
            /// Water-current random walk, (m/s)^2/s.
            current_noise: 2,
        }
        continuous {
            d/dt current = current_noise;
        }
        /// What the log reads: `(1 + s) (C^T (V - [c_N, c_E, 0]))_x`, the
        /// forward speed through water of the true state (m/s).
        sensor WaterSpeed: 1 {
            let c_true = c_bn + skew(attitude_error) * c_bn;
            let through_water = transpose(c_true) * (velocity - velocity_error - [current[0], current[1], 0.0]);
            h = [(1.0 + log_scale) * through_water[0]];
        }
    }
}

nav_runtime::model! {
    /// The ship: INS, GNSS antenna at a lever arm, gyrocompass, speed log.
    pub model Ship = InsCore + GnssFix + Compass + WaterSpeed;
}

nav_runtime::model! {
    /// The ship's INS, gyrocompass and GNSS antenna, with the error of the
    /// antenna's given lever arm as states (`[sensors.gnss] estimate =
    /// ["lever_arm"]`, docs/calibration.md); without the speed log.
    pub model ShipGnssCal = InsCore + GnssFixCalibrated + Compass;
}

/// Number of states of [`Ship`].
pub const N: usize = Ship::N;

/// The reading kinds the navigator knows feed the GNSS fix and the
/// compass; the speed log has no slot: it is fed by name.
impl InsVehicle<N> for Ship {
    const REPLAY_NAME: &'static str = "ship";
    const DESCRIPTION: &'static str =
        "INS + GNSS antenna on a mast + gyrocompass + speed log with water current";
    type Depth = Absent;
    type Dvl = Absent;
    type Compass = ShipCompass;
    type CompassSmallAngle = ShipCompassSmallAngle;
    type Usbl = Absent;
    type Gnss = ShipGnssFix;
    type Baro = Absent;
    type Mag = Absent;
}

impl InsVehicle<{ ShipGnssCal::N }> for ShipGnssCal {
    const REPLAY_NAME: &'static str = "ship-gnss-cal";
    const DESCRIPTION: &'static str =
        "the ship's INS, GNSS and gyrocompass with the antenna's lever arm as states";
    const GNSS_SENSOR: &'static str = "GnssFixCalibrated";
    type Depth = Absent;
    type Dvl = Absent;
    type Compass = ShipGnssCalCompass;
    type CompassSmallAngle = ShipGnssCalCompassSmallAngle;
    type Usbl = Absent;
    type Gnss = ShipGnssCalGnssFixCalibrated;
    type Baro = Absent;
    type Mag = Absent;
}
