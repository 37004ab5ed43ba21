//! `navsim`: the command line of the project: the papers' scenarios
//! (Monte Carlo runs, shards, merge), log replay and checks of any
//! registered vehicle or model, log import. It is a thin layer over
//! `models` (the scenarios and built-in vehicles), `nav-replay` (the
//! replay) and the importers; see `docs/cli-and-json.md`.
#![warn(missing_docs)]

pub mod cli;
mod scenario_text;
