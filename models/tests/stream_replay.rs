//! The streamed replay (`navsim replay`: the log read as the filter goes)
//! against the replay of the same log held in memory: the same numbers, and
//! the same time series, row for row.

use models::cli::find_replay_model;
use models::montecarlo::ReplayOptions;
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
