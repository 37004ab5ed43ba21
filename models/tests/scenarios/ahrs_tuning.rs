//! The `ahrs` model's magnetometer sigma identified from a log alone
//! (`docs/tuning.md`, "`navsim tune`"): simulated flights turning at
//! 0.1 rad/s with a fixed roll and pitch (IMU at 100 Hz, magnetometer at
//! 10 Hz with a known noise), `meta.toml` giving the magnetometer's sigma
//! 10 times too large or too small.

use crate::turning_flight;

use models::ahrs::replay::AhrsReplay;
use nav_replay::temp_dir::TempDir;
use nav_replay::tune::{tune, LogTuning, TuneOptions, Tuning};
use nav_replay::ReplayOptions;
use nav_runtime::log::{ImuRow, LogDir, LogFiles, MagRow, Meta, Strictness};
use nav_runtime::nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::path::Path;
use turning_flight::{
    imu, mag, ACCEL_SIGMA, BIAS_SIGMA, DURATION, GYRO_SIGMA, MAG_SIGMA, PERIOD, PITCH, ROLL, YAW,
};

/// Writes the flight of `seed` into `dir`, `meta.toml` giving the
/// magnetometer sigma `given`.
fn write_flight(dir: &Path, seed: u64, given: f64) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut n = || -> f64 { StandardNormal.sample(&mut rng) };
    let meta = format!(
        "[initial]\nt = 0.0\nroll = {ROLL:?}\npitch = {PITCH:?}\nyaw = {YAW:?}\n\n\
         [initial_sigma]\nlevel = 0.05\nheading = 0.2\n\n\
         [sensors.imu]\ngyro_bias_sigma = {BIAS_SIGMA:?}\ngyro_noise_sigma = {GYRO_SIGMA:?}\n\
         accel_bias_sigma = 0.0\naccel_noise_sigma = {ACCEL_SIGMA:?}\n\n\
         [sensors.mag]\nbias_sigma = 0.0\nnoise_sigma = {given:?}\n"
    );
    let mut log = LogDir::new(Meta::parse(&meta).unwrap());
    let bias = Vector3::new(n(), n(), n()) * BIAS_SIGMA;
    let mut rows = Vec::new();
    let steps = (DURATION / PERIOD).round() as usize;
    for k in 0..=steps {
        let t = k as f64 * PERIOD;
        let s = imu(t, &bias, &mut n);
        let (w, f) = (s.gyro, s.accel);
        log.imu.push(ImuRow::new(t, w.x, w.y, w.z, f.x, f.y, f.z));
        if k % 10 == 5 {
            let m = mag(t, &mut n);
            rows.push(MagRow::new(t, m.x, m.y, m.z));
        }
    }
    log.mag = Some(rows);
    log.write(dir).unwrap();
}

/// The tuning of the flight of `seed` from the sigma `given`.
fn tuned(seed: u64, given: f64) -> Tuning {
    let dir = TempDir::new(&format!("ahrs-tune-{seed}"));
    write_flight(&dir.0, seed, given);
    let files = LogFiles::open(&dir.0, Strictness::Strict).unwrap();
    let model = AhrsReplay;
    let t = LogTuning::new(&model, &files, ReplayOptions::default()).unwrap();
    tune(&t, &TuneOptions::default(), &|_, _| {}).unwrap()
}

/// The magnetometer sigma tuned, over the given one and over the truth.
fn mag_sigma(t: &Tuning) -> f64 {
    let p = t
        .parameters
        .iter()
        .find(|p| p.key == "sensors.mag.noise_sigma")
        .expect("the magnetometer sigma is in the default set");
    assert!(p.not_identifiable.is_none(), "{p:?}");
    p.value
}

/// Two flights (seeds 1 and 2), from 10 times too large and too small.
#[test]
fn the_ahrs_magnetometer_sigma_is_tuned_from_its_log() {
    for (seed, factor) in [(1u64, 10.0), (2, 0.1)] {
        let t = tuned(seed, MAG_SIGMA * factor);
        let ratio = mag_sigma(&t) / MAG_SIGMA;
        assert!(
            (0.75..1.25).contains(&ratio),
            "seed {seed}, x{factor}: {ratio}"
        );
        assert!(t.replays <= 30, "{}", t.replays);
        let (_, after) = t.nis["mag"];
        assert!((0.7..1.3).contains(&after.unwrap()), "{:?}", t.nis);
    }
}

/// Monte Carlo over seeds 9800-9899 (not used while building it; even
/// seeds start 10 times too large, odd ones too small): how many tuned
/// sigmas are within 25 % of the truth, and the median and largest
/// relative error (`docs/tuning.md`). Ignored: run by hand, in release.
#[test]
#[ignore = "Monte Carlo, 100 tunings: cargo test --release -p models --test scenarios ahrs_tuning:: -- --ignored"]
fn ahrs_tuning_monte_carlo() {
    use nav_runtime::simulation::stats::{median, percentile};
    let mut errors = Vec::new();
    let mut replays = Vec::new();
    for seed in 9800..9900u64 {
        let factor = if seed % 2 == 0 { 10.0 } else { 0.1 };
        let t = tuned(seed, MAG_SIGMA * factor);
        errors.push((mag_sigma(&t) / MAG_SIGMA - 1.0).abs());
        replays.push(t.replays as f64);
    }
    let within = errors.iter().filter(|e| **e < 0.25).count();
    eprintln!(
        "ahrs magnetometer sigma, seeds 9800-9899: within 25 % {within}/100; |tuned/true - 1| \
         median {:.3}, p95 {:.3}, max {:.3}; replays median {}, max {}",
        median(&errors),
        percentile(&errors, 95.0),
        errors.iter().copied().fold(0.0, f64::max),
        median(&replays),
        replays.iter().copied().fold(0.0, f64::max)
    );
    assert_eq!(within, 100, "{errors:?}");
}
