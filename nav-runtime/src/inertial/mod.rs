//! Inertial navigation (feature `inertial`, `no_std`): the WGS-84 Earth model
//! and gravity, attitude representations, and the strapdown mechanization.
//!
//! Re-exported at the crate root as `nav_runtime::earth`,
//! `nav_runtime::attitude` and `nav_runtime::strapdown`.

pub mod attitude;
pub mod earth;
pub mod strapdown;
