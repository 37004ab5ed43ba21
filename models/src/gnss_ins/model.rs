//! The `gnss-ins` declaration: the standard INS core and GNSS fix blocks plus
//! [`super::blocks`]' barometer and magnetic heading: 16 states.

use super::blocks::{Barometer, MagneticHeading};
use nav_blocks::{GnssFix, InsCore};

nav_runtime::model! {
    /// INS core (15 states) + GNSS position fix + barometer bias (16 states).
    pub model GnssIns = InsCore + GnssFix + Barometer + MagneticHeading;
}
