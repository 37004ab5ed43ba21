//! The `navsim` command line run as a user runs it, one file per command or
//! concern. One test binary, each file a module of it, so that the suite
//! compiles and links the helpers and their dependencies once instead of
//! once per file.

mod common;

mod allan_cli;
mod broken_logs;
mod cli;
mod filter_time;
mod import_cli;
mod name_suggestions;
mod observability_cli;
mod reference_point;
mod reliability_replay;
mod replay_vehicles;
mod smooth_cli;
mod tune_cli;
mod ulog_replay;
