//! Imports the committed PX4 flight log (`models/tests/data/ulog/`) into a log
//! directory and prints what was written and which topics were used:
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
    match models::ulog::import(&file, &out) {
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
            println!(
                "replay: navsim replay {} --model ahrs (or --model gnss-ins)",
                out.display()
            );
            ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
