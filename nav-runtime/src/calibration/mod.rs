//! Sensor calibration from recordings (`std`): what a user measures on the
//! bench before a filter is tuned.
//!
//! - [`allan`]: IMU noise (angle and velocity random walk, bias instability,
//!   rate random walk) from the overlapping Allan deviation of a static
//!   recording (docs/allan.md).

pub mod allan;
