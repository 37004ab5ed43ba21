//! `nav-runtime`: the engine that runs models declared with [`model!`].
//!
//! Data flows one way: sensor events -> [`scheduler`] -> [`ekf`] -> estimates.
//! The model traits ([`model`]) are the only contract between generated code and
//! this crate; the EKF core and the generated code build without `std` (libm).
#![cfg_attr(not(feature = "std"), no_std)]

pub use nalgebra;
pub use nav_macros::model;

pub mod attitude;
#[cfg(feature = "std")]
pub mod camera;
mod dispatch;
pub mod earth;
pub mod ekf;
pub mod error_state;
pub mod gate;
#[cfg(feature = "std")]
pub mod guidance;
#[cfg(feature = "std")]
pub mod imu;
#[cfg(feature = "std")]
pub mod log;
pub mod math;
pub mod model;
pub mod propagation;
#[cfg(feature = "std")]
pub mod scheduler;
#[cfg(feature = "std")]
pub mod sensors;
pub mod setup_error;
#[cfg(feature = "std")]
pub mod stats;
pub mod strapdown;
pub mod stuck;
#[cfg(all(test, feature = "std"))]
mod testmodels;
#[cfg(feature = "std")]
pub mod trajectory;
#[cfg(feature = "std")]
pub mod vehicle;
