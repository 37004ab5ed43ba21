//! A user's own replay program: the walk-through's AUV with a pressure
//! sensor at a lever arm (`models::vehicles::pressure_auv`) gets the whole
//! `navsim replay` (`replay`, `check`, `--json`, `--out` with time series and
//! plots, `--lenient`, `--smooth`) from one call in `main`:
//!
//! ```text
//! cargo run --release -p models --bin navsim -- simulate lawnmower-dvl --seed 3 --out /tmp/lm3
//! cargo run --release -p models --example replay_vehicle -- replay /tmp/lm3 --json
//! ```
//!
//! A vehicle of a user's crate is registered the same way: an `InsVehicle`
//! impl naming its sensors ([`nav_ins::InsVehicle`]), then this
//! `main`.

use std::process::ExitCode;

use models::vehicles::pressure_auv::PressureAuv;
use nav_replay::program::replay_main;

fn main() -> ExitCode {
    replay_main::<PressureAuv, 20>()
}
