//! The replay program of a declared model that is not an INS: the rover of
//! `models/src/vehicles/rover.rs` (wheel speed and yaw rate in, a position
//! fix, a range-bearing to a beacon and ranges to surveyed landmarks
//! given with each reading), fed from a log directory by its
//! `replay.toml` (`docs/model-replay.md`).
//!
//! ```text
//! cargo run --release -p models --example replay_model -- replay models/tests/fixtures/rover
//! cargo run --release -p models --example replay_model -- replay models/tests/fixtures/rover --json --out /tmp/rover
//! cargo run --release -p models --example replay_model -- check models/tests/fixtures/rover
//! ```

use models::vehicles::rover::{Rover, RoverFix, RoverLandmarkRange, RoverRangeBearing};
use nav_replay::model_replay::ModelReplay;

fn main() -> std::process::ExitCode {
    ModelReplay::<Rover, 3>::new("rover")
        .sensor::<RoverFix, 2>()
        .sensor::<RoverRangeBearing, 2>()
        .sensor::<RoverLandmarkRange, 1>()
        .main()
}
