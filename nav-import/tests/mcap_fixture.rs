//! The committed bag written by another tool (`tests/fixtures/mcap/`, made
//! by `make_small_bag.py` with the Python `mcap-ros2-support` writer, zstd
//! chunks): read with the default mapping, ROS frames converted.

use std::path::Path;

use nav_import::mcap::{import, read, Mapping};

fn close(a: f64, b: f64, tol: f64, what: &str) {
    assert!((a - b).abs() <= tol, "{what}: {a} vs {b}");
}

#[test]
fn the_python_written_bag_imports() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fixtures/mcap/small_survey.mcap");
    let file = std::fs::File::open(&path).expect("fixture");
    let log = match read("small_survey.mcap", file, &Mapping::default()) {
        Ok(l) => l,
        Err(e) => panic!("{e}"),
    };
    let imu = log.file("imu.csv").expect("imu.csv");
    assert_eq!(imu.rows(), 50);
    close(imu.row(10)[0], 0.2, 1e-9, "t");
    // FLU +9.81 up is FRD -9.81.
    close(imu.row(0)[6], -9.81, 1e-12, "az");
    let mag = log.file("mag.csv").expect("mag.csv");
    assert_eq!(mag.rows(), 10);
    let m = mag.row(0);
    close(m[1], 0.2 * 30f64.to_radians().cos(), 1e-9, "mx gauss");
    close(m[2], -0.1, 1e-9, "my FRD");
    close(m[3], 0.4, 1e-9, "mz FRD");
    let meta =
        nav_runtime::log::Meta::parse(&log.meta).unwrap_or_else(|e| panic!("{e}\n{}", log.meta));
    close(
        meta.initial.yaw.expect("yaw"),
        30f64.to_radians(),
        1e-9,
        "yaw NED",
    );
    close(meta.initial.lat, 47.4f64.to_radians(), 1e-12, "lat");
    close(meta.initial.depth, -3.0, 1e-12, "depth");
    // Through the library call, into a directory.
    let out = std::env::temp_dir().join(format!("mcap-fixture-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&out);
    let summary = import(&path, None, &out).expect("import");
    let read_back = nav_runtime::log::LogDir::read(&out, nav_runtime::log::Strictness::Strict);
    let _ = std::fs::remove_dir_all(&out);
    assert!(
        summary.files.contains(&("imu.csv".to_string(), 50)),
        "{summary:?}"
    );
    assert_eq!(read_back.expect("read").imu.len(), 50);
}
