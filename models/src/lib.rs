//! The estimators of the source papers (MODELS.md), declared with `nav_runtime::model!`.

pub mod cli;
pub mod leveling;
pub mod marker;
pub mod montecarlo;
pub mod navigator;
pub mod plot;
pub mod replay;
pub mod report;
pub mod sdins25;
pub mod vehicles;
pub mod vkf;
