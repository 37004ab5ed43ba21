//! A frozen IMU met by the replay itself (the log in memory, no preflight):
//! each row of the table freezes some channels of `imu.csv` for a while and
//! says whether the run's own warnings must list a `frozen_imu` naming the
//! channels. A run that only the preflight checked would leave a user of
//! `replay` without `check` (or of the library) unaware of it.

use models::sdins25::filter::{self, FilterOptions};
use models::sdins25::simulation::{simulate, SimConfig};
use nav_runtime::log::WarningKind;

/// (name, channels frozen (0-2 gyro, 3-5 accelerometer), first row, rows,
/// the text a `frozen_imu` warning must contain, or `None` for no warning)
type Case = (
    &'static str,
    &'static [usize],
    usize,
    usize,
    Option<&'static str>,
);

const CASES: &[Case] = &[
    (
        "gyro triple for 20 s",
        &[0, 1, 2],
        1000,
        2000,
        Some("gyro gx,gy,gz constant for 20.0 s"),
    ),
    (
        "gyro triple for 3 s",
        &[0, 1, 2],
        2500,
        300,
        Some("gyro gx,gy,gz"),
    ),
    (
        "gz alone for 10 s",
        &[2],
        1500,
        1000,
        Some("gyro gz constant"),
    ),
    (
        "accelerometer for 5 s",
        &[3, 4, 5],
        3000,
        500,
        Some("accelerometer ax,ay,az"),
    ),
    (
        "gyro triple for 0.5 s, under the 1 s floor",
        &[0, 1, 2],
        1000,
        50,
        None,
    ),
    ("nothing frozen", &[], 0, 0, None),
];

#[test]
fn the_replay_warns_of_a_frozen_imu_by_itself() {
    let config = SimConfig {
        duration: 60.0,
        ..SimConfig::usbl()
    };
    let base = simulate(&config, 11).log;
    assert!(
        base.meta.sensors.imu.is_some(),
        "the log declares its IMU noise"
    );
    let mut failures = Vec::new();
    for &(name, channels, from, rows, expected) in CASES {
        let mut log = base.clone();
        let held = log.imu[from];
        for r in &mut log.imu[from..from + rows] {
            for &c in channels {
                match c {
                    0 => r.gx = held.gx,
                    1 => r.gy = held.gy,
                    2 => r.gz = held.gz,
                    3 => r.ax = held.ax,
                    4 => r.ay = held.ay,
                    _ => r.az = held.az,
                }
            }
        }
        let run = filter::run(&log, &FilterOptions::default(), &[]).expect("replays");
        let frozen: Vec<&str> = run
            .warnings
            .iter()
            .filter(|w| w.kind == WarningKind::FrozenImu)
            .map(|w| w.message.as_str())
            .collect();
        let ok = match expected {
            Some(text) => frozen.len() == 1 && frozen[0].contains(text),
            None => frozen.is_empty(),
        };
        if !ok {
            failures.push(format!("{name}: expected {expected:?}, got {frozen:?}"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
