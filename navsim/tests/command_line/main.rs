//! The `navsim` command line run as a user runs it, one file per command or
//! concern. One test binary, each file a module of it, so that the suite
//! compiles and links the helpers and their dependencies once instead of
//! once per file. The filter-time test is a binary of its own
//! (`tests/filter_time.rs`): cargo runs test binaries one after another, so
//! its timings do not compete with the processes of these tests.

mod common;

mod allan_cli;
mod broken_logs;
mod cli;
mod dead_reckoning_cli;
mod import_cli;
mod name_suggestions;
mod observability_cli;
mod reference_point;
mod reliability_replay;
mod replay_vehicles;
mod smooth_cli;
mod tune_cli;
mod ulog_replay;
