//! `nav-runtime`: the engine that runs models declared with [`model!`].
//!
//! Data flows one way: sensor events -> [`scheduler`] -> [`ekf`] -> estimates.
//! The model traits ([`model`](mod@model)) are the only contract between generated code and
//! this crate; the EKF core and the generated code build without `std` (libm).
//!
//! The crate has six domains, each in its folder behind a cargo feature (all
//! on by default) and re-exported flat at the root:
//!
//! | domain | folder | feature | modules |
//! |---|---|---|---|
//! | filter core | [`filter`] | always (`no_std`; the scheduler needs `std`) | `ekf`, `gate`, `lockout`, `recovery`, `error_state`, `propagation`, `stuck`, `math`, `setup_error`, `scheduler`, `smoother` |
//! | inertial navigation | `inertial` | `inertial` (`no_std`) | `earth`, `attitude`, `strapdown` |
//! | simulation | `simulation` | `simulation` | `trajectory`, `imu`, `sensors`, `vehicle`, `camera`, `stats` |
//! | guidance | `guidance` | `guidance` | `guidance` (heading QP, RRT, line of sight) |
//! | log I/O | `log` | `log` | `log` |
//! | calibration | `calibration` | `std` | `allan` (IMU noise from a static record) |
//!
//! A filter-only build (`default-features = false`, optionally with `std`)
//! compiles neither clarabel nor csv nor toml.
#![cfg_attr(not(feature = "std"), no_std)]

pub use nalgebra;
pub use nav_macros::model;

#[cfg(feature = "std")]
pub mod calibration;
pub mod filter;
#[cfg(feature = "guidance")]
pub mod guidance;
#[cfg(feature = "inertial")]
pub mod inertial;
#[cfg(feature = "log")]
pub mod log;
pub mod model;
#[cfg(feature = "simulation")]
pub mod simulation;
#[cfg(feature = "std")]
pub mod suggestion;
#[cfg(all(test, feature = "std"))]
mod testmodels;

use filter::dispatch;
pub use filter::real::Real;
pub use filter::{
    ekf, error_state, gate, innovations, lockout, math, propagation, real, recovery, setup_error,
    stuck,
};
#[cfg(feature = "std")]
pub use filter::{scheduler, smoother};
#[cfg(feature = "inertial")]
pub use inertial::{attitude, earth, strapdown};
#[cfg(all(feature = "simulation", feature = "guidance"))]
pub use simulation::camera;
#[cfg(feature = "simulation")]
pub use simulation::{imu, sensors, stats, trajectory, vehicle};
