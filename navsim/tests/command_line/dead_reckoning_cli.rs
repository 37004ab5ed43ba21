//! `replay --model dvl-dr`: the dead-reckoning baseline through the binary,
//! on the same log a filter replays.

use crate::common;

use common::{navsim, stderr, stdout, TempDir};
use models::sdins25::simulation::{simulate, SimConfig};
use serde_json::Value;

fn replay(dir: &std::path::Path) -> Value {
    let o = navsim(&[
        "replay",
        dir.to_str().unwrap(),
        "--model",
        "dvl-dr",
        "--json",
    ]);
    assert!(o.status.success(), "{}", stderr(&o));
    serde_json::from_str(&stdout(&o)).expect("one JSON object")
}

/// Scored with the filters' keys but no NEES (no covariance); a DVL 2 m
/// ahead of the IMU that `meta.toml` does not declare costs it in the turns
/// (the simulated DVL sits at the IMU), the same arm declared costs nothing
/// more; `tune` has nothing to tune.
#[test]
fn dead_reckoning_is_scored_without_a_nees_and_takes_the_dvl_lever_arm() {
    let tmp = TempDir::new("dvl-dr");
    let dir = tmp.path().join("log");
    let config = SimConfig {
        duration: 200.0,
        ..SimConfig::dvl()
    };
    simulate(&config, 7).log.write(&dir).unwrap();
    let v = replay(&dir);
    assert_eq!(v["model"], "dvl-dr");
    let rms = v["horizontal_error_rms_m"].as_f64().unwrap();
    assert!(rms.is_finite() && rms > 0.0 && rms < 20.0, "{v}");
    for key in ["nees_mean", "nees_position_mean"] {
        assert!(v.get(key).is_none(), "{key}: {v}");
    }
    assert!(v["scored_seconds"].as_f64().unwrap() > 190.0, "{v}");

    // The readings of a DVL 2 m ahead, declared or not.
    let meta = dir.join("meta.toml");
    let text = std::fs::read_to_string(&meta).unwrap();
    let imu = std::fs::read_to_string(dir.join("imu.csv")).unwrap();
    let rates: Vec<(f64, f64)> = imu
        .lines()
        .skip(1)
        .map(|l| {
            let c: Vec<f64> = l.split(',').map(|x| x.parse().unwrap()).collect();
            (c[0], c[3])
        })
        .collect();
    let dvl = std::fs::read_to_string(dir.join("dvl.csv")).unwrap();
    let mut moved = String::from(dvl.lines().next().unwrap());
    moved.push('\n');
    for l in dvl.lines().skip(1) {
        let mut c: Vec<String> = l.split(',').map(String::from).collect();
        if let (Ok(t), Ok(vy)) = (c[0].parse::<f64>(), c[2].parse::<f64>()) {
            let k = rates.partition_point(|(ti, _)| *ti <= t).saturating_sub(1);
            // omega x r with r = (2, 0, 0): the lateral part is omega_z * 2.
            c[2] = format!("{}", vy + rates[k].1 * 2.0);
        }
        moved.push_str(&c.join(","));
        moved.push('\n');
    }
    std::fs::write(dir.join("dvl.csv"), moved).unwrap();
    let undeclared = replay(&dir)["horizontal_error_rms_m"].as_f64().unwrap();
    let declared_text = text.replacen(
        "[sensors.dvl]",
        "[sensors.dvl]\nlever_arm = [2.0, 0.0, 0.0]",
        1,
    );
    assert_ne!(declared_text, text, "the log has a [sensors.dvl] section");
    std::fs::write(&meta, declared_text).unwrap();
    let declared = replay(&dir)["horizontal_error_rms_m"].as_f64().unwrap();
    assert!(
        undeclared > rms + 0.5,
        "undeclared arm {undeclared} m against {rms} m"
    );
    assert!(
        (declared - rms).abs() < 0.01 * rms,
        "declared arm {declared} m against {rms} m"
    );

    let o = navsim(&["tune", dir.to_str().unwrap(), "--model", "dvl-dr"]);
    assert!(!o.status.success());
    assert!(
        stderr(&o).contains("no noise sigma to tune"),
        "{}",
        stderr(&o)
    );
}
