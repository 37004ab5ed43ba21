//! Simulation (feature `simulation`, needs `std`): reference trajectories, IMU
//! and aiding-sensor error models, the vehicle dynamics, the camera (with
//! the `guidance` feature, which describes the structures it sees) and the
//! ensemble statistics of Monte Carlo runs.
//!
//! Re-exported at the crate root as `nav_runtime::trajectory`,
//! `nav_runtime::imu`, `nav_runtime::sensors`, `nav_runtime::vehicle`,
//! `nav_runtime::camera` and `nav_runtime::stats`.

#[cfg(feature = "guidance")]
pub mod camera;
pub mod imu;
pub mod sensors;
pub mod stats;
pub mod trajectory;
pub mod vehicle;
