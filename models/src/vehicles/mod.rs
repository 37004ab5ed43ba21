//! Vehicles assembled from model blocks: a new vehicle is one composition line.
//!
//! - [`blocks`]: `BlockCatalog`, every block of the `nav_blocks` crate (the
//!   INS error-state core; USBL, depth, DVL, calibrated DVL, compass, surface
//!   GNSS fix, RPM speed map) once, so that their generated tests run.
//! - [`sdins`]: SDINS-25 as core + USBL + depth + DVL + compass (equal to the
//!   monolithic `crate::sdins25::model::Sdins25`, tested), and the 20-state
//!   variant without USBL.
//! - [`pressure_auv`]: the walk-through of docs/guide/building-a-vehicle.md: a new
//!   pressure-sensor block with a lever arm, a vehicle using it, and its filter
//!   run through [`nav_runtime::ekf::Ekf`].
//! - [`rover`]: a wheeled rover, not an INS, replayed from a log with
//!   [`nav_replay::model_replay`].

pub mod blocks;
pub mod pressure_auv;
pub mod rover;
pub mod sdins;
