//! The streamed replay (`navsim replay`: the log read as the filter goes)
//! against the replay of the same log held in memory: the same numbers, and
//! the same time series, row for row.

use models::harness::ReplayOptions;
use models::registry::find_replay_model;
use models::sdins25::soak::{write_log, SoakConfig};
use nav_runtime::log::{LogDir, LogFiles, Strictness};

fn without_runtime(mut m: serde_json::Map<String, serde_json::Value>) -> serde_json::Value {
    m.remove("runtime_s");
    serde_json::Value::Object(m)
}

#[test]
fn a_streamed_replay_gives_what_the_replay_in_memory_gives() {
    let root = std::env::temp_dir().join(format!("stream-replay-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&root);
    std::fs::create_dir_all(&root).unwrap();
    let dir = root.join("log");
    write_log(
        &SoakConfig {
            duration: 300.0,
            ..SoakConfig::hours(1.0, 7)
        },
        &dir,
    )
    .unwrap();
    let log = LogDir::read(&dir, Strictness::Strict).unwrap();
    let files = LogFiles::open(&dir, Strictness::Strict).unwrap();
    for (model, smooth) in [("sdins25", false), ("sdins20", false), ("sdins25", true)] {
        let m = find_replay_model(model).unwrap();
        let options = ReplayOptions {
            keep_series: true,
            smooth,
            ..ReplayOptions::default()
        };
        let memory = m.replay(&log, &options).unwrap();
        let out = root.join(format!("out-{model}-{smooth}"));
        std::fs::create_dir_all(&out).unwrap();
        let streamed = m.replay_files(&files, &options, Some(&out)).unwrap();
        assert_eq!(
            without_runtime(memory.metrics.clone()),
            without_runtime(streamed.metrics.clone()),
            "{model} smooth {smooth}"
        );
        assert_eq!(memory.samples, streamed.samples);
        assert!(memory.metrics.contains_key("horizontal_error_rms_m"));
        assert_eq!(memory.tables.len(), if smooth { 2 } else { 1 });
        // The error table written as the run went is the table kept in memory.
        for table in &memory.tables {
            let path = out.join(format!("{}.csv", table.name));
            let text = std::fs::read_to_string(&path).unwrap();
            let mut expected = Vec::new();
            table.write_csv(&root.join("expected.csv")).unwrap();
            expected.extend(
                std::fs::read_to_string(root.join("expected.csv"))
                    .unwrap()
                    .lines()
                    .map(String::from),
            );
            let written: Vec<String> = text.lines().map(String::from).collect();
            assert_eq!(written, expected, "{model}: {}", table.name);
        }
        // The trajectory has one row per truth row (1 Hz over 300 s).
        let trajectory = std::fs::read_to_string(out.join("estimates.csv")).unwrap();
        assert_eq!(trajectory.lines().count(), 1 + 301, "{model}");
        assert!(out.join("replay-track.svg").exists());
    }
    std::fs::remove_dir_all(&root).unwrap();
}

/// A log whose IMU rows sit at interval midpoints and that has no
/// `[initial] t`: the initial estimate holds at the start of the first IMU
/// interval, so readings stamped at the log's start (before the first IMU
/// row) are used, not dropped; an explicit epoch after them drops them.
#[test]
fn readings_at_the_start_of_a_midpoint_log_are_used() {
    use models::sdins25::filter::{run, FilterOptions};
    use models::sdins25::simulation::{simulate, SimConfig};
    let config = SimConfig {
        duration: 30.0,
        ..SimConfig::dvl()
    };
    let mut log = simulate(&config, 4).log;
    let dt = 0.01;
    for r in &mut log.imu {
        r.t += 0.5 * dt;
    }
    // A depth reading and a compass reading at t = 0.
    let depth = log.depth.as_mut().unwrap();
    let first_depth = depth[0];
    depth.insert(
        0,
        nav_runtime::log::DepthRow {
            t: 0.0,
            ..first_depth
        },
    );
    let heading = log.heading.as_mut().unwrap();
    let first_heading = heading[0];
    heading.insert(
        0,
        nav_runtime::log::HeadingRow {
            t: 0.0,
            ..first_heading
        },
    );
    let times: Vec<f64> = (1..30).map(f64::from).collect();
    log.meta.initial.t = None;
    let from_interval_start = run(&log, &FilterOptions::default(), &times).unwrap();
    let (depth_health, heading_health) = (
        from_interval_start.health[0].1,
        from_interval_start.health[2].1,
    );
    assert_eq!(depth_health.skipped, 0, "{depth_health:?}");
    assert_eq!(heading_health.skipped, 0, "{heading_health:?}");
    assert_eq!(
        depth_health.accepted + depth_health.gated,
        depth_health.rows
    );
    // An explicit epoch at the first IMU row: the readings before it are
    // more than one IMU period older only if the epoch is later still.
    log.meta.initial.t = Some(0.5 * dt + 2.0 * dt);
    let late = run(&log, &FilterOptions::default(), &times).unwrap();
    assert_eq!(late.health[0].1.skipped, 1, "{:?}", late.health[0].1);
    assert_eq!(late.health[2].1.skipped, 1, "{:?}", late.health[2].1);
    assert!(
        late.warnings
            .iter()
            .any(|w| w.message.contains("before the initial epoch")),
        "{:?}",
        late.warnings
    );
}
