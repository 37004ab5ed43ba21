//! Writes the survey of `models::sdins25::clock_survey`: a lawn-mowing
//! survey with speed changes and a precise DVL whose file is stamped late
//! (the log of `scripts/clock-monte-carlo.sh`).
//!
//! ```text
//! cargo run --release -p models --example clock_survey -- SEED LATE_S DIR
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let (Some(seed), Some(late), Some(dir)) = (
        args.first().and_then(|s| s.parse::<u64>().ok()),
        args.get(1).and_then(|s| s.parse::<f64>().ok()),
        args.get(2).map(PathBuf::from),
    ) else {
        eprintln!("usage: clock_survey SEED LATE_S DIR");
        return ExitCode::from(2);
    };
    match models::sdins25::clock_survey::clock_survey(seed, late).write(&dir) {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {}: {e}", dir.display());
            ExitCode::FAILURE
        }
    }
}
