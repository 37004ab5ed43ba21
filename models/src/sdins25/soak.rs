//! Long-run (soak) check of the SDINS-25 filter: hours of a repeated
//! lawn-mower survey at 100 Hz with DVL, depth and compass aiding, streamed
//! sample by sample (no log is held in memory), with health checks of the
//! covariance every [`SoakConfig::check_every`] IMU steps.
//!
//! The pattern ([`pattern`]) repeats every [`PERIOD`] s: its manoeuvres start
//! and end inside the period, the heading returns to north and the depth to its
//! start, and the north legs cancel the south legs, so one period moves the
//! vehicle due east. Gravity and Earth rate depend on latitude and height only,
//! so the truth of period `k` is that of period 0 shifted in longitude
//! ([`PeriodicTruth`]): a 24 h truth costs one 240 s grid.

use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::imu::{ImuModel, ImuRate, ImuSpec};
use nav_runtime::log::{ImuNoise, ImuRow, LogDir};
use nav_runtime::nalgebra::{Cholesky, SVector};
use nav_runtime::scheduler::Scheduler;
use nav_runtime::sensors::{derive_seed, ErrorSpec, SensorErrorModel};
use nav_runtime::strapdown::NavState;
use nav_runtime::trajectory::{scenarios, Trajectory, TrajectorySpec, TruthSource, TruthState};

use super::filter::{
    depth_measurement, dvl_measurement, heading_measurement, initial_filter, Estimate, Filter,
    FilterOptions, ImuSample,
};
use super::score::NEES_DOF;
use super::simulation::{self, AIDING_RATE, IMU_RATE, SHALLOW_DEPTH};
use crate::harness::RunError;

/// Period of the repeated pattern (s).
pub const PERIOD: f64 = 240.0;

/// The lawn-mower manoeuvres of one period, as in the SDINS-25 survey (90 deg
/// turns in pairs, 5 m depth changes on the legs) but placed so that the
/// period starts and ends on a straight, level northbound leg.
pub fn pattern(start_depth: f64) -> TrajectorySpec {
    let mut s = TrajectorySpec::new(scenarios::sdins25_start(start_depth), 0.0, 1.5);
    let d = 90f64.to_radians();
    // Turns take 18 s, depth changes 28 s (default limits).
    s.turn(10.0, d);
    s.turn(30.0, d);
    s.change_depth(60.0, 5.0);
    s.turn(130.0, -d);
    s.turn(150.0, -d);
    s.change_depth(180.0, -5.0);
    s
}

/// The pattern of one period repeated: truth at `t` is the truth at
/// `t mod PERIOD` shifted east by whole periods.
#[derive(Clone, Debug)]
pub struct PeriodicTruth {
    base: Trajectory,
    dlon: f64,
    duration: f64,
    /// North (m), east (m) and down (m) gap between the end and the start of
    /// one period, east removed (the closure error of the pattern).
    pub closure_m: [f64; 3],
}

impl PeriodicTruth {
    /// The pattern at `start_depth`, repeated for `duration` s.
    pub fn new(start_depth: f64, duration: f64) -> Self {
        let base = pattern(start_depth).build(PERIOD + 1.0);
        let (a, b) = (base.truth(0.0), base.truth(PERIOD));
        let gap = LocalNed::new(a.position()).geodetic_to_ned(&b.position());
        Self {
            dlon: b.lon - a.lon,
            base,
            duration,
            closure_m: [gap.x, 0.0, gap.z],
        }
    }
}

impl TruthSource for PeriodicTruth {
    fn truth(&self, t: f64) -> TruthState {
        let k = (t / PERIOD).floor();
        let mut s = self.base.truth(t - k * PERIOD);
        s.t = t;
        s.lon += k * self.dlon;
        s
    }
    fn duration(&self) -> f64 {
        self.duration
    }
}

/// What to run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SoakConfig {
    /// Simulated duration (s).
    pub duration: f64,
    /// Seed of the sensor errors.
    pub seed: u64,
    /// Check the covariance every this many IMU steps.
    pub check_every: usize,
}

impl SoakConfig {
    /// `hours` of survey, checks every 10 s.
    pub fn hours(hours: f64, seed: u64) -> Self {
        Self {
            duration: hours * 3600.0,
            seed,
            check_every: 1000,
        }
    }
}

/// Resident and peak memory of this process (kB), from `/proc/self/status`
/// (`None` where that file does not exist).
pub fn memory_kb() -> Option<(u64, u64)> {
    let text = std::fs::read_to_string("/proc/self/status").ok()?;
    let field = |name: &str| {
        text.lines()
            .find(|l| l.starts_with(name))
            .and_then(|l| l.split_whitespace().nth(1))
            .and_then(|v| v.parse::<u64>().ok())
    };
    Some((field("VmRSS:")?, field("VmHWM:")?))
}

/// Statistics of one hour (or the last partial hour) of a soak run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SoakHour {
    /// End of the hour (s).
    pub t: f64,
    /// Mean NEES of the 9 navigation states over the hour's checks.
    pub nees_mean: f64,
    /// Largest horizontal error in the hour (m).
    pub horizontal_error_max_m: f64,
    /// Resident memory at the end of the hour (kB).
    pub rss_kb: u64,
}

/// The result of a soak run.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SoakReport {
    /// IMU steps.
    pub steps: u64,
    /// Covariance checks done.
    pub checks: u64,
    /// Checks where `P != P^T` (bitwise).
    pub asymmetric: u64,
    /// Checks where the Cholesky factorization of `P` failed.
    pub not_positive_definite: u64,
    /// Checks with a non-finite covariance or state.
    pub non_finite: u64,
    /// Smallest diagonal element of `P` relative to its largest.
    pub min_diagonal_ratio: f64,
    /// Mean NEES of the 9 navigation states over all checks.
    pub nees_mean: f64,
    /// Fraction of checks with the NEES inside the two-sided 95 % band of
    /// chi-square with 9 degrees of freedom.
    pub nees_in_band: f64,
    /// Horizontal error at the end (m).
    pub horizontal_error_final_m: f64,
    /// Largest horizontal error (m).
    pub horizontal_error_max_m: f64,
    /// Filter 1-sigma of the horizontal position at the end (m, rss of N and E).
    pub horizontal_sigma_final_m: f64,
    /// Aiding measurements applied / gated / refused.
    pub accepted: u64,
    /// Refused by the innovation gate.
    pub gated: u64,
    /// Refused by the scheduler or the filter.
    pub rejected: u64,
    /// Covariance repairs by the filter.
    pub covariance_repairs: u64,
    /// RSS (kB) after set-up, at the middle and at the end.
    pub rss_kb: [u64; 3],
    /// Peak RSS (kB) at the end.
    pub peak_rss_kb: u64,
    /// Filter-loop wall time (s).
    pub runtime_s: f64,
    /// Per-hour statistics.
    pub hours: Vec<SoakHour>,
    /// Closure error of the repeated pattern (m, N and D).
    pub closure_m: [f64; 3],
}

fn run_error(e: impl std::fmt::Display) -> RunError {
    RunError::Invalid(format!("soak: {e}"))
}

/// Runs the soak test. `progress` is called at the end of every simulated hour.
pub fn run(
    config: &SoakConfig,
    mut progress: impl FnMut(&SoakHour),
) -> Result<SoakReport, RunError> {
    let Survey {
        truth,
        mut imu_model,
        mut dvl,
        mut depth,
        mut compass,
        meta,
    } = Survey::new(config);
    let floor_depth = SHALLOW_DEPTH + simulation::FLOOR_BELOW_START;
    assert!(floor_depth - (SHALLOW_DEPTH + 5.0) < simulation::DVL_MAX_ALTITUDE);

    let sample = |m: &mut ImuModel, t: f64| {
        let s = truth.truth(t);
        m.corrupt_rate(&ImuRate {
            t,
            w_ib_b: s.w_ib_b,
            f_b: s.f_b,
        })
    };
    let dt = 1.0 / IMU_RATE;
    let first = sample(&mut imu_model, 0.0);
    // A log holding only the set-up: meta.toml and the first IMU samples.
    let mut setup = LogDir::new(meta);
    let row = |r: &ImuRate| {
        ImuRow::new(
            r.t, r.w_ib_b.x, r.w_ib_b.y, r.w_ib_b.z, r.f_b.x, r.f_b.y, r.f_b.z,
        )
    };
    setup.imu = vec![
        row(&first),
        ImuRow {
            t: dt,
            ..row(&first)
        },
    ];
    let options = FilterOptions::default();
    let filter = initial_filter(&setup, &options)?;
    let noise = |n: Option<nav_runtime::log::SensorNoise>| n.map_or(0.0, |n| n.noise_sigma);
    let (sig_dvl, sig_depth, sig_heading) = (
        noise(setup.meta.sensors.dvl),
        noise(setup.meta.sensors.depth),
        noise(setup.meta.sensors.heading),
    );

    let mut sched = Scheduler::new(filter, 0.0).map_err(run_error)?;
    let ids = [
        sched
            .add_sensor("depth", AIDING_RATE, 0.0)
            .map_err(run_error)?,
        sched
            .add_sensor("dvl", AIDING_RATE, 0.0)
            .map_err(run_error)?,
        sched
            .add_sensor("heading", AIDING_RATE, 0.0)
            .map_err(run_error)?,
    ];

    let steps = (config.duration * IMU_RATE + 1e-9).floor() as u64;
    let aiding_every = (IMU_RATE / AIDING_RATE).round() as u64;
    let (lo, hi) = (
        nav_runtime::gate::chi_square_quantile(0.025, NEES_DOF).unwrap_or(f64::NAN),
        nav_runtime::gate::chi_square_quantile(0.975, NEES_DOF).unwrap_or(f64::NAN),
    );
    let mut rep = SoakReport {
        closure_m: truth.closure_m,
        min_diagonal_ratio: f64::INFINITY,
        ..SoakReport::default()
    };
    let (mut nees_sum, mut in_band) = (0.0, 0u64);
    let mut hour = (0.0, 0u64, 0.0f64);
    rep.rss_kb[0] = memory_kb().map_or(0, |m| m.0);
    let start = std::time::Instant::now();
    for k in 1..=steps {
        let t = k as f64 * dt;
        if k % aiding_every == 0 {
            let s = truth.truth(t);
            let v = dvl.measure(&s.v_body());
            let z_depth = depth.measure_scalar(s.depth());
            let psi = compass.measure_angle(s.euler.yaw);
            // Refusals are counted per sensor by the scheduler.
            let _ = sched.push_measurement(ids[0], t, depth_measurement(z_depth, sig_depth));
            let _ = sched.push_measurement(ids[1], t, dvl_measurement(v, sig_dvl));
            let _ = sched.push_measurement(
                ids[2],
                t,
                heading_measurement(psi, sig_heading, options.compass),
            );
        }
        let m = sample(&mut imu_model, t);
        sched
            .push_imu(
                t,
                ImuSample {
                    gyro: m.w_ib_b,
                    accel: m.f_b,
                },
            )
            .map_err(|e| run_error(format!("IMU at t = {t} s: {e}")))?;
        rep.steps += 1;

        if k % config.check_every as u64 == 0 || k == steps {
            let f: &Filter = sched.filter();
            let p = f.covariance();
            rep.checks += 1;
            if p != &p.transpose() {
                rep.asymmetric += 1;
            }
            let finite = p.iter().all(|x| x.is_finite())
                && f.nominal().ins.state.c_bn.iter().all(|x| x.is_finite())
                && f.nominal().ins.state.v_n.iter().all(|x| x.is_finite());
            if !finite {
                rep.non_finite += 1;
            }
            if Cholesky::new(*p).is_none() {
                rep.not_positive_definite += 1;
            }
            let d = p.diagonal();
            let (dmin, dmax) = (d.min(), d.max());
            rep.min_diagonal_ratio = rep.min_diagonal_ratio.min(dmin / dmax);

            let e = Estimate::of(t, f);
            let tr = truth.truth(t);
            let tn = NavState {
                lat: tr.lat,
                lon: tr.lon,
                h: tr.h,
                v_n: tr.v_n,
                c_bn: tr.c_bn,
            };
            let err = e.nav.error_from(&tn);
            let pn = err.position_ned(tn.lat, tn.h);
            let x = SVector::<f64, 9>::from([
                pn.x, pn.y, pn.z, err.dv_n.x, err.dv_n.y, err.dv_n.z, err.phi.x, err.phi.y,
                err.phi.z,
            ]);
            let nees = Cholesky::new(e.cov).map_or(f64::NAN, |c| x.dot(&c.solve(&x)));
            let horizontal = pn.x.hypot(pn.y);
            nees_sum += nees;
            if (lo..=hi).contains(&nees) {
                in_band += 1;
            }
            rep.horizontal_error_final_m = horizontal;
            rep.horizontal_error_max_m = rep.horizontal_error_max_m.max(horizontal);
            rep.horizontal_sigma_final_m = (e.cov[(0, 0)] + e.cov[(1, 1)]).sqrt();
            hour.0 += nees;
            hour.1 += 1;
            hour.2 = hour.2.max(horizontal);
        }
        if k == steps / 2 {
            rep.rss_kb[1] = memory_kb().map_or(0, |m| m.0);
        }
        let hour_end = k % (3600 * IMU_RATE as u64) == 0;
        if (hour_end || k == steps) && hour.1 > 0 {
            let h = SoakHour {
                t,
                nees_mean: hour.0 / hour.1 as f64,
                horizontal_error_max_m: hour.2,
                rss_kb: memory_kb().map_or(0, |m| m.0),
            };
            progress(&h);
            rep.hours.push(h);
            hour = (0.0, 0, 0.0);
        }
    }
    rep.runtime_s = start.elapsed().as_secs_f64();
    let mem = memory_kb().unwrap_or((0, 0));
    rep.rss_kb[2] = mem.0;
    rep.peak_rss_kb = mem.1;
    rep.nees_mean = nees_sum / rep.checks.max(1) as f64;
    rep.nees_in_band = in_band as f64 / rep.checks.max(1) as f64;
    for id in ids {
        if let Some(s) = sched.sensor_stats(id) {
            rep.accepted += s.accepted;
            rep.gated += s.gated;
            rep.rejected += s.failed + s.too_old + s.duplicate + s.invalid + s.queue_full;
        }
    }
    rep.covariance_repairs = sched.filter().ekf().counters().covariance_repairs;
    Ok(rep)
}

/// The start of the survey as a geodetic point (for reports).
pub fn start() -> Geodetic {
    scenarios::sdins25_start(SHALLOW_DEPTH)
}

/// The soak survey's truth, sensor error models and `meta.toml`.
struct Survey {
    truth: PeriodicTruth,
    imu_model: ImuModel,
    dvl: SensorErrorModel<3>,
    depth: SensorErrorModel<1>,
    compass: SensorErrorModel<1>,
    meta: nav_runtime::log::Meta,
}

impl Survey {
    fn new(config: &SoakConfig) -> Self {
        let seed = config.seed;
        let truth = PeriodicTruth::new(SHALLOW_DEPTH, config.duration);
        let s0 = truth.truth(0.0);
        let spec = ImuSpec::sdins25();
        let (dvl_spec, depth_spec, compass_spec) = (
            ErrorSpec::sdins25_dvl(),
            ErrorSpec::sdins25_depth(),
            ErrorSpec::sdins25_compass(),
        );
        let mut meta = simulation::initial_meta(&s0, seed);
        meta.sensors.imu = Some(ImuNoise {
            gyro_bias_sigma: spec.gyro_bias,
            gyro_noise_sigma: spec.gyro_noise,
            accel_bias_sigma: spec.accel_bias,
            accel_noise_sigma: spec.accel_noise,
        });
        meta.sensors.dvl = Some(simulation::sensor_noise(&dvl_spec));
        meta.sensors.depth = Some(simulation::sensor_noise(&depth_spec));
        meta.sensors.heading = Some(simulation::sensor_noise(&compass_spec));
        Survey {
            truth,
            imu_model: ImuModel::new(spec, derive_seed(seed, "sdins25-imu")),
            dvl: SensorErrorModel::new(dvl_spec, derive_seed(seed, "sdins25-dvl")),
            depth: SensorErrorModel::new(depth_spec, derive_seed(seed, "sdins25-depth")),
            compass: SensorErrorModel::new(compass_spec, derive_seed(seed, "sdins25-compass")),
            meta,
        }
    }
}

/// Writes the soak survey of `config` as a log directory at `dir` (which
/// must not exist), one row at a time: IMU at 100 Hz, DVL, depth and compass
/// at 2 Hz, truth at 1 Hz. A log of any length is written in the memory of a
/// short one (the long-log replay measurements of `docs/trust.md` use it).
///
/// # Errors
/// The directory or a file cannot be written.
pub fn write_log(config: &SoakConfig, dir: &std::path::Path) -> Result<(), RunError> {
    use nav_runtime::log::{DepthRow, DvlRow, HeadingRow, Row, TruthRow};
    use std::io::Write;

    struct Out {
        path: std::path::PathBuf,
        w: std::io::BufWriter<std::fs::File>,
    }
    impl Out {
        fn create<R: Row>(dir: &std::path::Path) -> Result<Self, RunError> {
            let path = dir.join(R::FILE);
            let f = std::fs::File::create(&path).map_err(|e| RunError::io(&path, e))?;
            let mut o = Out {
                path,
                w: std::io::BufWriter::new(f),
            };
            writeln!(o.w, "{}", R::COLUMNS.join(",")).map_err(|e| RunError::io(&o.path, e))?;
            Ok(o)
        }
        fn row<R: Row>(&mut self, r: &R) -> Result<(), RunError> {
            let cells: Vec<String> = r
                .to_cells()
                .into_iter()
                .map(|c| c.map_or(String::new(), nav_runtime::log::format_f64))
                .collect();
            writeln!(self.w, "{}", cells.join(",")).map_err(|e| RunError::io(&self.path, e))
        }
        fn finish(mut self) -> Result<(), RunError> {
            self.w.flush().map_err(|e| RunError::io(&self.path, e))
        }
    }

    let Survey {
        truth,
        mut imu_model,
        mut dvl,
        mut depth,
        mut compass,
        meta,
    } = Survey::new(config);
    std::fs::create_dir(dir).map_err(|e| RunError::io(dir, e))?;
    let meta_path = dir.join("meta.toml");
    std::fs::write(&meta_path, meta.to_toml()).map_err(|e| RunError::io(&meta_path, e))?;
    let mut imu = Out::create::<ImuRow>(dir)?;
    let mut dvl_out = Out::create::<DvlRow>(dir)?;
    let mut depth_out = Out::create::<DepthRow>(dir)?;
    let mut heading_out = Out::create::<HeadingRow>(dir)?;
    let mut truth_out = Out::create::<TruthRow>(dir)?;
    let steps = (config.duration * IMU_RATE + 1e-9).floor() as u64;
    let aiding_every = (IMU_RATE / AIDING_RATE).round() as u64;
    for k in 0..=steps {
        let t = k as f64 / IMU_RATE;
        let s = truth.truth(t);
        let m = imu_model.corrupt_rate(&ImuRate {
            t,
            w_ib_b: s.w_ib_b,
            f_b: s.f_b,
        });
        imu.row(&ImuRow::new(
            t, m.w_ib_b.x, m.w_ib_b.y, m.w_ib_b.z, m.f_b.x, m.f_b.y, m.f_b.z,
        ))?;
        if k > 0 && k % aiding_every == 0 {
            let v = dvl.measure(&s.v_body());
            dvl_out.row(&DvlRow::new(t, Some(v.x), Some(v.y), Some(v.z)))?;
            depth_out.row(&DepthRow::new(t, depth.measure_scalar(s.depth())))?;
            heading_out.row(&HeadingRow::new(t, compass.measure_angle(s.euler.yaw)))?;
        }
        if k % (IMU_RATE as u64) == 0 {
            truth_out.row(&TruthRow::from(&s))?;
        }
    }
    for o in [imu, dvl_out, depth_out, heading_out, truth_out] {
        o.finish()?;
    }
    Ok(())
}
