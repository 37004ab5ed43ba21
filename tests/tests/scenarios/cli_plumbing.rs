//! In-process tests of the Monte Carlo plumbing (registries, shards, merge).

use models::demo;
use models::harness::*;
use models::registry::{find_replay_model, find_scenario, replay_models, scenarios};
use nav_runtime::log::{LogDir, Strictness};

#[test]
fn registry_names_are_unique_and_valid() {
    let ss = scenarios();
    let mut names: Vec<&str> = ss.iter().map(|s| s.name()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), ss.len());
    for s in &ss {
        assert!(s.default_runs() > 0, "{}", s.name());
        assert!(!s.name().contains(char::is_whitespace));
    }
    let ms = replay_models();
    let mut names: Vec<&str> = ms.iter().map(|m| m.name()).collect();
    names.sort();
    names.dedup();
    assert_eq!(names.len(), ms.len());
    assert!(find_scenario("nope").is_err());
    assert!(find_replay_model("nope").is_err());
    assert!(ss
        .iter()
        .any(|s| s.name() == models::registry::default_scenario()));
}

#[test]
fn shards_partition_the_seeds() {
    for n in 1..6 {
        let mut all: Vec<u64> = (1..=n)
            .flat_map(|k| seeds(100, 13, Some(Shard { k, n })))
            .collect();
        all.sort();
        assert_eq!(all, seeds(100, 13, None));
    }
    assert_eq!("2/4".parse::<Shard>().unwrap(), Shard { k: 2, n: 4 });
    for bad in ["0/4", "5/4", "1/0", "x/2", "3", ""] {
        assert!(bad.parse::<Shard>().is_err(), "{bad}");
    }
}

#[test]
fn shard_files_round_trip_and_merge_in_seed_order() {
    let scenario = find_scenario(demo::NAME).unwrap();
    let options = RunOptions::default();
    let bar = progress_bar(0, true);
    let all = run_seeds(scenario.as_ref(), &seeds(7, 9, None), &options, &bar).unwrap();
    let mut files = Vec::new();
    for k in (1..=3).rev() {
        let shard = Shard { k, n: 3 };
        let results =
            run_seeds(scenario.as_ref(), &seeds(7, 9, Some(shard)), &options, &bar).unwrap();
        let mut file = ShardFile {
            format: SHARD_FORMAT,
            scenario: demo::NAME.into(),
            seed: 7,
            runs: 9,
            shard: shard.to_string(),
            options: options.clone(),
            results,
        };
        // Non-finite metrics survive the JSON file.
        file.results[0].metrics.insert("odd".into(), f64::NAN);
        file.results[0].metrics.insert("big".into(), f64::INFINITY);
        let text = serde_json::to_string(&file).unwrap();
        let back: ShardFile = serde_json::from_str(&text).unwrap();
        assert!(back.results[0].metric("odd").is_nan());
        assert_eq!(back.results[0].metric("big"), f64::INFINITY);
        file.results[0].metrics.remove("odd");
        file.results[0].metrics.remove("big");
        let back: ShardFile = serde_json::from_str(&serde_json::to_string(&file).unwrap()).unwrap();
        assert_eq!(back, file);
        files.push((std::path::PathBuf::from(format!("shard{k}")), back));
    }
    let merged = merge_shards(&files).unwrap();
    assert_eq!(merged.results, all);
    let a = summary_json(scenario.as_ref(), 7, &all, &options).unwrap();
    let b = summary_json(
        scenario.as_ref(),
        merged.seed,
        &merged.results,
        &merged.options,
    )
    .unwrap();
    assert_eq!(a, b);
    assert_eq!(a["runs"], 9);

    // Mismatched runs are refused.
    let mut bad = files.clone();
    bad[1].1.seed = 8;
    assert!(merge_shards(&bad).is_err());
    assert!(merge_shards(&files[..2]).is_err());
}

#[test]
fn demo_log_written_and_read_back_replays_like_the_run() {
    let scenario = find_scenario(demo::NAME).unwrap();
    let options = RunOptions::default();
    let log = scenario.simulate_log(33, &options).unwrap().unwrap();
    let dir = std::env::temp_dir().join(format!("navsim-plumbing-{}", std::process::id()));
    log.write(&dir).unwrap();
    let back = LogDir::read(&dir, Strictness::Strict).unwrap();
    let _ = std::fs::remove_dir_all(&dir);
    assert_eq!(back, log);
    let run = scenario.run_one(33, &options).unwrap();
    let model = find_replay_model(demo::MODEL).unwrap();
    let out = model.replay(&back, &ReplayOptions::default()).unwrap();
    assert_eq!(
        out.metrics["depth_error_rms_m"].as_f64().unwrap(),
        run.metric("depth_error_rms_m")
    );
    assert_eq!(out.samples, back.imu.len());
}
