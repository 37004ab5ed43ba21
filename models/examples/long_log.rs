//! Writes a simulated survey log of any length (the SDINS-25 lawn-mower
//! pattern repeated, IMU at 100 Hz, DVL, depth and compass at 2 Hz, truth at
//! 1 Hz) without holding it in memory: the input of the long-log replay
//! measurements in `docs/trust.md`.
//!
//! ```text
//! cargo run --release -p models --example long_log -- HOURS DIR [SEED]
//! ```

use std::process::ExitCode;

use models::sdins25::soak::{write_log, SoakConfig};

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(hours), Some(dir)) = (
        args.first().and_then(|h| h.parse::<f64>().ok()),
        args.get(1),
    ) else {
        eprintln!("usage: long_log HOURS DIR [SEED]");
        return ExitCode::FAILURE;
    };
    let seed = args.get(2).and_then(|s| s.parse().ok()).unwrap_or(1);
    match write_log(&SoakConfig::hours(hours, seed), std::path::Path::new(dir)) {
        Ok(()) => {
            println!("wrote {hours} h of survey to {dir}");
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
