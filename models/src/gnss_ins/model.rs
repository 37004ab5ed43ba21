//! The `gnss-ins` declaration: the standard INS core and GNSS fix blocks plus
//! the barometer and magnetic heading blocks: 16 states.

use nav_blocks::{Barometer, GnssFix, InsCore, MagneticHeading};

nav_runtime::model! {
    /// INS core (15 states) + GNSS position fix + barometer bias (16 states).
    pub model GnssIns = InsCore + GnssFix + Barometer + MagneticHeading;
}
