//! `navsim import`: the command line of the importers (ULog and MCAP).

/// `navsim import ulog FILE --out DIR` writes the directory; a missing file
/// is a one-line error naming it.
#[test]
fn the_command_line_writes_the_log_directory() {
    let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../models/tests/data/ulog/sample_px4_events.ulg");
    let out = std::env::temp_dir().join(format!("ulog-cli-{}", std::process::id()));
    let code = navsim::cli::main_with_args([
        "navsim".to_string(),
        "import".to_string(),
        "ulog".to_string(),
        fixture.display().to_string(),
        "--out".to_string(),
        out.display().to_string(),
        "--json".to_string(),
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::SUCCESS)
    );
    for name in [
        "imu.csv",
        "mag.csv",
        "baro.csv",
        "gnss.csv",
        "reference.csv",
        "meta.toml",
        "noise.toml",
    ] {
        assert!(out.join(name).is_file(), "{name} not written");
    }
    let meta = std::fs::read_to_string(out.join("meta.toml")).expect("meta.toml");
    assert!(nav_runtime::log::Meta::parse(&meta).is_ok(), "{meta}");
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "ulog",
        "/nonexistent/x.ulg",
        "--out",
        "/tmp/never-written",
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::FAILURE)
    );
    assert!(!std::path::Path::new("/tmp/never-written").exists());
}

/// `navsim import mcap BAG --out DIR --json` writes the log directory of a
/// bag another tool wrote; `--mapping` with `ulog` is refused.
#[test]
fn the_command_line_imports_a_ros_bag() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let bag = root.join("nav-import/tests/fixtures/mcap/small_survey.mcap");
    let out = std::env::temp_dir().join(format!("mcap-cli-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "mcap",
        bag.to_str().unwrap(),
        "--out",
        out.to_str().unwrap(),
        "--json",
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::SUCCESS)
    );
    for name in ["imu.csv", "mag.csv", "meta.toml"] {
        assert!(out.join(name).is_file(), "{name} not written");
    }
    let _ = std::fs::remove_dir_all(&out);
    let code = navsim::cli::main_with_args([
        "navsim",
        "import",
        "ulog",
        bag.to_str().unwrap(),
        "--mapping",
        "m.toml",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(
        format!("{code:?}"),
        format!("{:?}", std::process::ExitCode::FAILURE)
    );
    assert!(!out.exists());
}
