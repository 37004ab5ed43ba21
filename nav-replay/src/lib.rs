//! `nav-replay`: a log directory in, one filter over it, JSON, CSV series and
//! plots out.
//!
//! - [`allan`]: the IMU noise of a static recording (Allan deviation);
//! - [`ins`]: any INS vehicle of `nav_ins` over a log (`meta.toml` and the
//!   standard files, or a declared mapping), scored against `truth.csv`;
//! - [`model_replay`]: any declared model, not only an INS, over a log
//!   described by its `replay.toml`;
//! - [`preflight`]: units, signs, frames, gaps and frozen sensors checked
//!   on every replay and by `check`;
//! - [`output`]: report, series, plots, staged output directories;
//! - [`program`]: the replay program of a user's vehicle
//!   (`replay_main::<V, N>()`), and the command-line pieces `navsim` shares.
//!
//! A user's replay program depends on `nav-runtime`, `nav-blocks`, `nav-ins`
//! and this crate, not on the papers' estimators. See `docs/pipeline.md`.
#![warn(missing_docs)]

pub mod allan;
pub mod dead_reckoning;
mod error;
pub mod innovations;
pub mod ins;
pub mod model_replay;
pub mod observability;
pub mod output;
pub mod preflight;
pub mod program;
mod replay_model;
mod run;
#[doc(hidden)]
pub mod temp_dir;
pub mod tune;

pub use error::RunError;
pub use nav_ins::{RunHealth, SensorHealth};
pub use replay_model::{
    covariance_repairs, meta_note, missing_section, model_note, nees_not_a_number, OwnMapping,
    ReplayModel, ReplayOptions, ReplayOutput,
};
pub use run::{metric_values, progress_bar, write_run_tables, ProgressBar, RunResult, RunTable};
