//! The estimators of the source papers (docs/models/), declared with `nav_runtime::model!`.
#![warn(missing_docs)]

pub mod ahrs;
pub mod cli;
pub mod demo;
pub mod gnss_ins;
pub mod harness;
pub mod interrupt;
pub mod leveling;
pub mod marker;
pub mod model_replay;
pub mod navigator;
pub mod preflight;
pub mod px4_ekf24;
pub mod replay;
pub mod scenario_text;
pub mod sdins25;
pub mod series;
pub mod ulog;
pub mod vehicles;
pub mod vkf;
