//! The estimators of the source papers (docs/models/), declared with
//! `nav_runtime::model!`, with their simulations and scenarios, and the
//! built-in vehicles of `navsim` (`ahrs`, `gnss-ins`, `sdins20`,
//! `pressure-auv`, the rover). The navigator is `nav_ins`, the replay
//! library `nav_replay`, the command line `navsim`.
#![warn(missing_docs)]

pub mod ahrs;
pub mod demo;
pub mod gnss_ins;
pub mod harness;
pub mod leveling;
pub mod marker;
pub mod px4_ekf24;
pub mod registry;
pub mod sdins25;
pub mod ulog;
pub mod vehicles;
pub mod vkf;
