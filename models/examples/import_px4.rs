//! Imports the committed PX4 flight log (`models/tests/data/ulog/`) into a log
//! directory, prints what was written and which topics were used, and
//! replays it with `gnss-ins` (the JSON of `navsim replay --json`):
//!
//! ```text
//! cargo run --example import_px4 [-- FILE.ulg [OUT_DIR]]
//! ```

use std::path::PathBuf;
use std::process::ExitCode;

fn main() -> ExitCode {
    let mut args = std::env::args().skip(1);
    let file = args.next().map(PathBuf::from).unwrap_or_else(|| {
        PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("tests/data/ulog/sample_px4_events.ulg")
    });
    let out = args
        .next()
        .map(PathBuf::from)
        .unwrap_or_else(|| std::env::temp_dir().join("import_px4"));
    match nav_import::ulog::import(&file, &out) {
        Ok(log) => {
            println!("{} -> {}", file.display(), out.display());
            for f in &log.files {
                println!(
                    "  {:<14} {:>6} rows  {}",
                    f.name,
                    f.rows(),
                    f.header.join(",")
                );
            }
            for w in &log.warnings {
                println!("  warning: {w}");
            }
            // Replayed by `gnss-ins` as `navsim replay OUT_DIR --model
            // gnss-ins --json` does (`--model ahrs` is the attitude-only one).
            let model = match models::registry::find_replay_model("gnss-ins") {
                Ok(m) => m,
                Err(e) => {
                    eprintln!("error: {e}");
                    return ExitCode::FAILURE;
                }
            };
            let args = nav_replay::program::ReplayArgs {
                dir: out.clone(),
                model: "gnss-ins".into(),
                out: None,
                json: true,
                lenient: false,
                stationary: false,
                max_gap_periods: 10.0,
                smooth: false,
                observability: false,
            };
            println!("navsim replay {} --model gnss-ins --json:", out.display());
            match nav_replay::program::replay_with(model.as_ref(), &args) {
                Ok(()) => ExitCode::SUCCESS,
                Err(e) => {
                    eprintln!("error: {e}");
                    ExitCode::FAILURE
                }
            }
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
