//! Sensor faults injected into a simulated SDINS-25 log (`--faults` of the
//! `lawnmower-*` scenarios and of `navsim simulate`).
//!
//! Data faults change the log in memory after the simulation ([`apply`]); the
//! delivery faults (`delayed`, `reordered`) change when the filter receives
//! the 2 Hz aiding measurements ([`delivery`]). Every fault is drawn from its
//! own generator seeded by the run's seed, so a faulted run is reproducible and
//! the unfaulted part of the log is identical to the run without faults.
//!
//! | name | what happens |
//! |---|---|
//! | `dvl-dropout` | 3 windows of 30 s without any DVL row (no data) |
//! | `dvl-bottom-lock` | 2 windows of 60 s where the DVL reports no bottom lock |
//! | `spikes` | 5 % of the DVL, depth and compass samples get a 10 sigma outlier |
//! | `stuck-compass` | the compass repeats one value for 60 s |
//! | `stuck-depth` | the depth meter repeats one value for 60 s |
//! | `nan-burst` | 3 bursts of 5 s of NaN on DVL, depth and compass; 2 NaN USBL fixes |
//! | `usbl-multipath` | 5 % of the USBL fixes are off by 100-300 m horizontally |
//! | `delayed` | DVL, depth and compass reach the filter 0.5 s late |
//! | `reordered` | ... 0 to 1 s late, so deliveries overtake each other |
//!
//! NaN values are injected in memory only: a log file with NaN is a parse error
//! (or a skipped row with `--lenient`). In memory they reach the scheduler,
//! which refuses them with a typed error counted as `rejected`.

use std::collections::BTreeMap;

use nav_runtime::earth::LocalNed;
use nav_runtime::log::{LogDir, UsblRow};
use nav_runtime::sensors::derive_seed;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::filter::Delivery;
use super::simulation::{Usbl, DURATION};
use crate::harness::RunError;

/// Every fault name.
pub const ALL: [&str; 9] = [
    DVL_DROPOUT,
    DVL_BOTTOM_LOCK,
    SPIKES,
    STUCK_COMPASS,
    STUCK_DEPTH,
    NAN_BURST,
    USBL_MULTIPATH,
    DELAYED,
    REORDERED,
];
/// Faults of the scenarios without a USBL.
pub const WITHOUT_USBL: [&str; 8] = [
    DVL_DROPOUT,
    DVL_BOTTOM_LOCK,
    SPIKES,
    STUCK_COMPASS,
    STUCK_DEPTH,
    NAN_BURST,
    DELAYED,
    REORDERED,
];

/// DVL rows missing for 3 windows of [`DROPOUT_WINDOW`].
pub const DVL_DROPOUT: &str = "dvl-dropout";
/// DVL reports no bottom lock for 2 windows of [`BOTTOM_LOCK_WINDOW`].
pub const DVL_BOTTOM_LOCK: &str = "dvl-bottom-lock";
/// Outliers of [`SPIKE_SIGMAS`] sigma at [`SPIKE_FRACTION`] of the samples.
pub const SPIKES: &str = "spikes";
/// Compass frozen for [`STUCK_WINDOW`].
pub const STUCK_COMPASS: &str = "stuck-compass";
/// Depth meter frozen for [`STUCK_WINDOW`].
pub const STUCK_DEPTH: &str = "stuck-depth";
/// Bursts of NaN.
pub const NAN_BURST: &str = "nan-burst";
/// USBL multipath outliers.
pub const USBL_MULTIPATH: &str = "usbl-multipath";
/// Constant late delivery of the 2 Hz aiding.
pub const DELAYED: &str = "delayed";
/// Random late delivery that reorders the 2 Hz aiding.
pub const REORDERED: &str = "reordered";

/// Length of a DVL dropout (s).
pub const DROPOUT_WINDOW: f64 = 30.0;
/// Length of a loss of bottom lock (s).
pub const BOTTOM_LOCK_WINDOW: f64 = 60.0;
/// Size of a spike in measurement-noise sigmas.
pub const SPIKE_SIGMAS: f64 = 10.0;
/// Fraction of samples with a spike.
pub const SPIKE_FRACTION: f64 = 0.05;
/// Length of a stuck-sensor window (s).
pub const STUCK_WINDOW: f64 = 60.0;
/// Length of a NaN burst (s).
pub const NAN_WINDOW: f64 = 5.0;
/// Fraction of USBL fixes with a multipath error.
pub const MULTIPATH_FRACTION: f64 = 0.05;
/// Range of the multipath error (m, horizontal).
pub const MULTIPATH_RANGE: (f64, f64) = (100.0, 300.0);
/// Delay of `delayed` (s).
pub const DELAY: f64 = 0.5;
/// Largest delay of `reordered` (s); the aiding comes every 0.5 s.
pub const JITTER: f64 = 1.0;

/// The fault names a scenario with this USBL accepts.
pub fn accepted(usbl: Usbl, aided: bool) -> &'static [&'static str] {
    match (aided, usbl) {
        (false, _) => &[],
        (true, Usbl::None) => &WITHOUT_USBL,
        (true, _) => &ALL,
    }
}

/// How many samples each fault touched (key: fault name).
pub type Injected = BTreeMap<String, u64>;

/// Windows `[t, t + len)` of `count` starts drawn uniformly in
/// `[0.1, 0.9] * duration - len`, sorted.
fn windows(rng: &mut ChaCha8Rng, count: usize, len: f64, duration: f64) -> Vec<(f64, f64)> {
    let (lo, hi) = (0.1 * duration, (0.9 * duration - len).max(0.1 * duration));
    let mut w: Vec<(f64, f64)> = (0..count)
        .map(|_| {
            let t = rng.random_range(lo..=hi);
            (t, t + len)
        })
        .collect();
    w.sort_by(|a, b| a.0.total_cmp(&b.0));
    w
}

fn inside(w: &[(f64, f64)], t: f64) -> bool {
    w.iter().any(|&(a, b)| t >= a && t < b)
}

fn rng(seed: u64, fault: &str) -> ChaCha8Rng {
    ChaCha8Rng::seed_from_u64(derive_seed(seed, &format!("sdins25-fault-{fault}")))
}

/// Applies the data faults of `faults` to `log` (simulated with `seed`).
/// Returns the number of samples each fault changed. Delivery faults are
/// left to [`delivery`].
///
/// # Errors
/// An unknown fault name.
pub fn apply(log: &mut LogDir, faults: &[String], seed: u64) -> Result<Injected, RunError> {
    let mut injected = Injected::new();
    let duration = log.imu.last().map_or(DURATION, |r| r.t);
    for f in faults {
        let mut g = rng(seed, f);
        let n: u64 = match f.as_str() {
            DVL_DROPOUT => {
                let w = windows(&mut g, 3, DROPOUT_WINDOW, duration);
                log.dvl.as_mut().map_or(0, |rows| {
                    let before = rows.len();
                    rows.retain(|r| !inside(&w, r.t));
                    (before - rows.len()) as u64
                })
            }
            DVL_BOTTOM_LOCK => {
                let w = windows(&mut g, 2, BOTTOM_LOCK_WINDOW, duration);
                let mut n = 0;
                for r in log.dvl.iter_mut().flatten() {
                    if inside(&w, r.t) {
                        r.vx = None;
                        r.vy = None;
                        r.vz = None;
                        n += 1;
                    }
                }
                n
            }
            SPIKES => spikes(log, &mut g),
            STUCK_COMPASS => {
                let w = windows(&mut g, 1, STUCK_WINDOW, duration);
                let rows = log.heading.iter_mut().flatten();
                freeze(rows.map(|r| (r.t, &mut r.heading)), &w)
            }
            STUCK_DEPTH => {
                let w = windows(&mut g, 1, STUCK_WINDOW, duration);
                let rows = log.depth.iter_mut().flatten();
                freeze(rows.map(|r| (r.t, &mut r.depth)), &w)
            }
            NAN_BURST => nan_bursts(log, &mut g, duration),
            USBL_MULTIPATH => multipath(log, &mut g),
            DELAYED | REORDERED => 0,
            other => {
                return Err(RunError::Invalid(format!(
                    "unknown fault `{other}`; valid faults: {}{}",
                    ALL.join(", "),
                    nav_runtime::log::did_you_mean(other, &ALL)
                )))
            }
        };
        injected.insert(f.clone(), n);
    }
    Ok(injected)
}

/// The delivery of the aiding measurements under `faults`.
pub fn delivery(faults: &[String], seed: u64) -> Delivery {
    let mut d = Delivery {
        seed: derive_seed(seed, "sdins25-fault-delivery"),
        ..Delivery::default()
    };
    if faults.iter().any(|f| f == DELAYED) {
        d.delay_s = DELAY;
    }
    if faults.iter().any(|f| f == REORDERED) {
        d.jitter_s = JITTER;
    }
    d
}

/// Random sign times `SPIKE_SIGMAS` sigma.
fn spike(g: &mut ChaCha8Rng, sigma: f64) -> f64 {
    let sign = if g.random_bool(0.5) { 1.0 } else { -1.0 };
    sign * SPIKE_SIGMAS * sigma
}

fn spikes(log: &mut LogDir, g: &mut ChaCha8Rng) -> u64 {
    let s = &log.meta.sensors;
    let sig_dvl = s.dvl.map_or(0.0, |n| n.noise_sigma);
    let sig_depth = s.depth.map_or(0.0, |n| n.noise_sigma);
    let sig_heading = s.heading.map_or(0.0, |n| n.noise_sigma);
    let mut n = 0;
    for r in log.dvl.iter_mut().flatten() {
        if g.random_bool(SPIKE_FRACTION) {
            let axis = g.random_range(0..3usize);
            let d = spike(g, sig_dvl);
            let v = [&mut r.vx, &mut r.vy, &mut r.vz];
            if let Some(x) = v.into_iter().nth(axis).and_then(|x| x.as_mut()) {
                *x += d;
                n += 1;
            }
        }
    }
    for r in log.depth.iter_mut().flatten() {
        if g.random_bool(SPIKE_FRACTION) {
            r.depth += spike(g, sig_depth);
            n += 1;
        }
    }
    for r in log.heading.iter_mut().flatten() {
        if g.random_bool(SPIKE_FRACTION) {
            r.heading = nav_runtime::math::wrap_angle(r.heading + spike(g, sig_heading));
            n += 1;
        }
    }
    n
}

/// Holds each value at the first value inside each window.
fn freeze<'a>(rows: impl Iterator<Item = (f64, &'a mut f64)>, w: &[(f64, f64)]) -> u64 {
    let mut held: Option<(usize, f64)> = None;
    let mut n = 0;
    for (t, v) in rows {
        let Some(k) = w.iter().position(|&(a, b)| t >= a && t < b) else {
            held = None;
            continue;
        };
        match held {
            Some((hk, x)) if hk == k => {
                *v = x;
                n += 1;
            }
            _ => held = Some((k, *v)),
        }
    }
    n
}

fn nan_bursts(log: &mut LogDir, g: &mut ChaCha8Rng, duration: f64) -> u64 {
    let mut n = 0;
    let w = windows(g, 3, NAN_WINDOW, duration);
    for r in log.dvl.iter_mut().flatten() {
        if inside(&w, r.t) && r.vx.is_some() {
            r.vx = Some(f64::NAN);
            n += 1;
        }
    }
    let w = windows(g, 3, NAN_WINDOW, duration);
    for r in log.depth.iter_mut().flatten() {
        if inside(&w, r.t) {
            r.depth = f64::NAN;
            n += 1;
        }
    }
    let w = windows(g, 3, NAN_WINDOW, duration);
    for r in log.heading.iter_mut().flatten() {
        if inside(&w, r.t) {
            r.heading = f64::NAN;
            n += 1;
        }
    }
    if let Some(rows) = log.usbl.as_mut().filter(|r| !r.is_empty()) {
        for _ in 0..2 {
            let k = g.random_range(0..rows.len());
            if rows[k].lat.is_finite() {
                rows[k].lat = f64::NAN;
                n += 1;
            }
        }
    }
    n
}

fn multipath(log: &mut LogDir, g: &mut ChaCha8Rng) -> u64 {
    let Some(rows) = log.usbl.as_mut() else {
        return 0;
    };
    let mut n = 0;
    for r in rows.iter_mut() {
        if !g.random_bool(MULTIPATH_FRACTION) {
            continue;
        }
        let range = g.random_range(MULTIPATH_RANGE.0..=MULTIPATH_RANGE.1);
        let dir = g.random_range(0.0..std::f64::consts::TAU);
        *r = offset(r, range * dir.cos(), range * dir.sin());
        n += 1;
    }
    n
}

/// The fix moved by (north, east) metres.
fn offset(r: &UsblRow, north: f64, east: f64) -> UsblRow {
    let p = nav_runtime::earth::Geodetic::new(r.lat, r.lon, -r.depth);
    let frame = LocalNed::new(p);
    let q = frame.ned_to_geodetic(&nav_runtime::nalgebra::Vector3::new(north, east, 0.0));
    UsblRow::new(r.t, q.lat, q.lon, r.depth)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sdins25::simulation::{simulate, SimConfig};

    fn names(v: &[&str]) -> Vec<String> {
        v.iter().map(|s| s.to_string()).collect()
    }

    #[test]
    fn every_fault_changes_the_log_reproducibly() {
        let base = simulate(&SimConfig::usbl(), 3).log;
        for f in ALL {
            let mut a = base.clone();
            let mut b = base.clone();
            let na = apply(&mut a, &names(&[f]), 3).unwrap();
            let nb = apply(&mut b, &names(&[f]), 3).unwrap();
            assert_eq!(na, nb, "{f}");
            if f == DELAYED || f == REORDERED {
                assert_eq!(na[f], 0);
                continue;
            }
            assert!(na[f] > 0, "{f} injected nothing");
            assert_eq!(a.imu, base.imu, "{f} must not touch the IMU");
        }
    }

    #[test]
    fn spikes_hit_about_five_percent() {
        let mut log = simulate(&SimConfig::dvl(), 5).log;
        let samples = 3.0 * log.depth.as_ref().map_or(0, |r| r.len()) as f64;
        let n = apply(&mut log, &names(&[SPIKES]), 5).unwrap()[SPIKES] as f64;
        assert!(
            (n / samples - SPIKE_FRACTION).abs() < 0.015,
            "{n} of {samples}"
        );
    }

    #[test]
    fn stuck_compass_repeats_one_value() {
        let base = simulate(&SimConfig::dvl(), 2).log;
        let mut log = base.clone();
        let n = apply(&mut log, &names(&[STUCK_COMPASS]), 2).unwrap()[STUCK_COMPASS];
        let rows = log.heading.unwrap();
        let changed: Vec<_> = rows
            .iter()
            .zip(base.heading.unwrap())
            .filter(|(a, b)| a.heading != b.heading)
            .map(|(a, _)| a.heading)
            .collect();
        assert_eq!(changed.len() as u64, n);
        assert!(changed.windows(2).all(|w| w[0] == w[1]));
        assert!(n as f64 >= STUCK_WINDOW * 2.0 - 2.0);
    }

    #[test]
    fn delivery_delays_are_bounded_and_seeded() {
        let d = delivery(&names(&[DELAYED, REORDERED]), 9);
        for i in 0..1000 {
            let x = d.delay(1, i);
            assert!((DELAY..DELAY + JITTER).contains(&x));
            assert_eq!(x, d.delay(1, i));
        }
        assert!(!delivery(&[], 9).is_late());
    }
}
