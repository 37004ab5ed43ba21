//! The command line of the PX4 import (`navsim import ulog`), on the
//! committed fixture; the importer's own tests are in `nav_import::ulog`.

/// `navsim import ulog FILE --out DIR` writes the directory; a missing file
/// is a one-line error naming it.
#[test]
fn the_command_line_writes_the_log_directory() {
    let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/ulog/sample_px4_events.ulg");
    let out = std::env::temp_dir().join(format!("ulog-cli-{}", std::process::id()));
    let code = crate::cli::main_with_args([
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
    let code = crate::cli::main_with_args([
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
