//! `BlockCatalog`: every standard block of `nav_blocks` once (with the
//! calibrated DVL), a vehicle that exists so that each block's generated code
//! is compiled and tested (finite-difference Jacobians of every sensor) from
//! a crate other than the one that defines the blocks.

use nav_blocks::{Compass, Depth, DvlCalibrated, GnssFix, InsCore, RpmSpeed, Usbl};

nav_runtime::model! {
    /// Every block once (with the calibrated DVL): a vehicle that exists so that
    /// each block's generated code is compiled and tested (finite-difference
    /// Jacobians of every sensor).
    pub model BlockCatalog = InsCore + Usbl + Depth + DvlCalibrated + Compass + GnssFix + RpmSpeed;
}
