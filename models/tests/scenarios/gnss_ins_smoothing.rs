//! `gnss-ins --smooth` against a known truth: a simulated vehicle that
//! turns, with the IMU of the SDINS-25 papers at 100 Hz and GNSS position
//! fixes once a second (1.5 m per axis), no barometer or magnetometer, so
//! the heading comes from the fixes through the turns. The imported PX4
//! fixture has only PX4's own estimate to compare with; this log has the
//! truth. Printed with `--nocapture`.

use models::gnss_ins::replay::GnssInsReplay;
use models::harness::{ReplayModel, ReplayOptions};
use nav_runtime::earth::Geodetic;
use nav_runtime::log::{GnssRow, ImuRow, LogDir, Meta, TruthRow};
use nav_runtime::nalgebra::Vector3;
use nav_runtime::sensors::normal;
use nav_runtime::simulation::imu::{rates, ImuModel, ImuSpec};
use nav_runtime::simulation::trajectory::{Trajectory, TrajectorySpec, TruthSource};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Length of each simulated run, s.
const DURATION: f64 = 300.0;
/// GNSS noise per axis, m.
const GNSS_SIGMA: f64 = 1.5;

/// The log of `seed`: imu.csv, gnss.csv and truth.csv.
fn drive(seed: u64) -> LogDir {
    let start = Geodetic::new(0.6, 2.2, 50.0);
    let mut spec = TrajectorySpec::new(start, 0.3, 6.0);
    let mut t = 40.0;
    for delta in [1.6, -2.1, 1.2, -1.0] {
        t = spec.turn(t, delta) + 40.0;
    }
    let traj = Trajectory::new(spec, DURATION, 0.1);
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let imu_spec = ImuSpec::sdins25();
    let s0 = traj.truth(0.0);
    let meta = format!(
        "[initial]\nt = 0.0\nlat = {:?}\nlon = {:?}\ndepth = {:?}\nvn = {:?}\nve = {:?}\nvd = 0.0\n\
         roll = {:?}\npitch = {:?}\nyaw = {:?}\n\n\
         [initial_sigma]\nposition = 3.0\nvelocity = 0.5\nlevel = 0.01\nheading = 0.05\n\n\
         [sensors.imu]\ngyro_bias_sigma = {:?}\ngyro_noise_sigma = {:?}\naccel_bias_sigma = {:?}\n\
         accel_noise_sigma = {:?}\n\n\
         [sensors.gnss]\nbias_sigma = 0.0\nnoise_sigma = {GNSS_SIGMA:?}\n",
        s0.lat,
        s0.lon,
        s0.depth(),
        s0.v_n.x,
        s0.v_n.y,
        s0.euler.roll + normal(&mut rng, 0.01),
        s0.euler.pitch + normal(&mut rng, 0.01),
        s0.euler.yaw + normal(&mut rng, 0.05),
        imu_spec.gyro_bias,
        imu_spec.gyro_noise,
        imu_spec.accel_bias,
        imu_spec.accel_noise,
    );
    let mut log = LogDir::new(Meta::parse(&meta).unwrap());
    let mut imu = ImuModel::new(imu_spec, seed);
    log.imu = rates(&traj, 100.0, DURATION)
        .map(|r| ImuRow::from(&imu.corrupt_rate(&r)))
        .collect();
    let fixes = (1..=(DURATION as usize))
        .map(|k| {
            let noise = [(); 3].map(|()| normal(&mut rng, GNSS_SIGMA));
            GnssRow::of_antenna(&traj.truth(k as f64), &Vector3::zeros(), noise)
        })
        .collect();
    log.gnss = Some(fixes);
    log.truth = Some(
        (0..=(DURATION as usize * 10))
            .map(|k| TruthRow::from(&traj.truth(k as f64 * 0.1)))
            .collect(),
    );
    log
}

/// Over 100 drives (seeds 5800-5899) the smoothed horizontal error is below
/// the forward one. The NEES of both is printed, not asserted: the smoothed
/// one is above its expectation here (docs/ulog.md, "gnss-ins --smooth").
#[test]
fn smoothed_gnss_ins_is_closer_to_the_truth() {
    let seeds = 5800..5900u64;
    let options = ReplayOptions {
        smooth: true,
        ..ReplayOptions::default()
    };
    // The drives on both cores: the longest test of the suite.
    let rows: Vec<(f64, f64, f64, f64)> = seeds
        .clone()
        .into_par_iter()
        .map(|seed| {
            let out = GnssInsReplay
                .replay(&drive(seed), &options)
                .expect("replays");
            let m = &out.metrics;
            let number = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
            (
                number(&m["horizontal_error_rms_m"]),
                number(&m["smoothed"]["horizontal_error_rms_m"]),
                number(&m["nees_mean"]),
                number(&m["smoothed"]["nees_mean"]),
            )
        })
        .collect();
    let mut ratio: Vec<f64> = rows.iter().map(|r| r.1 / r.0).collect();
    ratio.sort_by(f64::total_cmp);
    let n = rows.len() as f64;
    let mean = |f: fn(&(f64, f64, f64, f64)) -> f64| rows.iter().map(f).sum::<f64>() / n;
    println!(
        "gnss-ins smoothing, seeds {seeds:?}: horizontal RMS mean {:.3} m forward, {:.3} m \
         smoothed; smoothed / forward median {:.3}, max {:.3}; NEES (9 states) mean {:.2} forward, \
         {:.2} smoothed",
        mean(|r| r.0),
        mean(|r| r.1),
        ratio[ratio.len() / 2],
        ratio[ratio.len() - 1],
        mean(|r| r.2),
        mean(|r| r.3),
    );
    let mut q: Vec<f64> = rows.iter().map(|r| r.3).collect();
    q.sort_by(f64::total_cmp);
    let mut f: Vec<f64> = rows.iter().map(|r| r.2).collect();
    f.sort_by(f64::total_cmp);
    println!(
        "NEES per run: smoothed median {:.2}, p90 {:.2}, max {:.2}; forward median {:.2}, max {:.2}",
        q[q.len() / 2],
        q[q.len() * 9 / 10],
        q[q.len() - 1],
        f[f.len() / 2],
        f[f.len() - 1]
    );
    assert!(
        ratio[ratio.len() / 2] < 1.0,
        "median ratio {}",
        ratio[ratio.len() / 2]
    );
}
