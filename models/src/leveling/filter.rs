//! Runs LEVELING-6 over a log: IMU rows drive `predict`, speed-log rows (or, at
//! rest, a 10 Hz zero-velocity pseudo-measurement) drive `update`.

use super::model::{
    Leveling6, Leveling6Input, Leveling6Moving, Leveling6Noise, Leveling6Params,
    Leveling6Stationary,
};
use nav_runtime::earth;
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::log::{Event, LogDir};
use nav_runtime::math::wrap_angle;
use nav_runtime::nalgebra::{Matrix2, Matrix4, SMatrix, Vector2, Vector3, Vector4, Vector6};

/// How the filter is set up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LevelingOptions {
    /// Use the stationary measurement model (eqs. 32-33).
    pub stationary: bool,
    /// Initial roll and pitch guess (rad); `None` starts level (`a = [0, 0, 1]`),
    /// i.e. with no attitude knowledge.
    pub initial_attitude: Option<(f64, f64)>,
    /// Noise tuning.
    pub tuning: Tuning,
}

/// Filter tuning (documented in the README, not fitted to a seed).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tuning {
    /// Accelerometer noise density, m/s^2/sqrt(Hz); covers the unmodelled 1 mg bias drift.
    pub accel_density: f64,
    /// Gyro noise density, rad/s/sqrt(Hz).
    pub gyro_density: f64,
    /// Speed-log 1-sigma per sample (noise and bias), m/s.
    pub speed_sigma: f64,
    /// Zero-velocity pseudo-measurement 1-sigma, m/s.
    pub zero_velocity_sigma: f64,
    /// Unit-norm pseudo-measurement 1-sigma per update. The constraint is exact,
    /// but applying it at every 10 Hz update as if its errors were independent
    /// overcounts it, and linearized at a wrong `a` (45-degree initial errors)
    /// a tight sigma makes the filter confident before it has converged: with
    /// 0.01 the S-type roll std is 0.04 deg against a filter sigma of 0.02 deg;
    /// with 1.0, 0.016 deg against 0.024 deg (README, LEVELING-6).
    pub norm_sigma: f64,
    /// Initial velocity 1-sigma, m/s.
    pub velocity_sigma: f64,
    /// The vehicle is known to be upright (`a3 = cos(roll) cos(pitch) > 0`): an
    /// estimate with `a3 < 0` is reflected to `-a3`. In the moving model `a3`
    /// enters only through the unit norm, so its sign is unobservable and an
    /// initial error beyond 90 degrees otherwise converges to the mirror
    /// solution (roll off by 180 degrees).
    pub upright: bool,
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning {
            accel_density: 2e-3,
            gyro_density: 1e-5,
            speed_sigma: 0.15,
            zero_velocity_sigma: 0.01,
            norm_sigma: 1.0,
            velocity_sigma: 0.5,
            upright: true,
        }
    }
}

/// One estimate: time (s), roll and pitch (rad), and their 1-sigma (rad) from the
/// covariance of `a` (eq. 28 linearized).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AttitudeEstimate {
    /// Time, s.
    pub t: f64,
    /// Roll, rad.
    pub roll: f64,
    /// Pitch, rad.
    pub pitch: f64,
    /// Roll 1-sigma, rad.
    pub roll_sigma: f64,
    /// Pitch 1-sigma, rad.
    pub pitch_sigma: f64,
}

/// What a run produced.
#[derive(Clone, Debug, Default)]
pub struct LevelingRun {
    /// One estimate per IMU sample.
    pub estimates: Vec<AttitudeEstimate>,
    /// Updates applied, gated.
    pub accepted: u64,
    /// Updates rejected by the gate.
    pub gated: u64,
    /// Measurements or inputs rejected as invalid.
    pub rejected: u64,
    /// Covariance repairs.
    pub repairs: u64,
    /// IMU samples processed.
    pub samples: usize,
}

/// Roll and pitch from `a` (eq. 28).
pub fn roll_pitch(a: &Vector3<f64>) -> (f64, f64) {
    let pitch = (-a.x / a.norm()).clamp(-1.0, 1.0).asin();
    (a.y.atan2(a.z), pitch)
}

/// `a = C_n^b [0, 0, 1]` for roll and pitch (eq. 5).
pub fn gravity_direction(roll: f64, pitch: f64) -> Vector3<f64> {
    Vector3::new(
        -pitch.sin(),
        roll.sin() * pitch.cos(),
        roll.cos() * pitch.cos(),
    )
}

fn estimate(t: f64, x: &Vector6<f64>, p: &SMatrix<f64, 6, 6>) -> AttitudeEstimate {
    let a = Vector3::new(x[3], x[4], x[5]);
    let (roll, pitch) = roll_pitch(&a);
    let n2 = a.y * a.y + a.z * a.z;
    let j_roll = Vector3::new(0.0, a.z / n2, -a.y / n2);
    let j_pitch = Vector3::new(-1.0 / (1.0 - (a.x * a.x).min(0.999_999)).sqrt(), 0.0, 0.0);
    let pa = p.fixed_view::<3, 3>(3, 3);
    AttitudeEstimate {
        t,
        roll,
        pitch,
        roll_sigma: (j_roll.transpose() * pa * j_roll)[0].max(0.0).sqrt(),
        pitch_sigma: (j_pitch.transpose() * pa * j_pitch)[0].max(0.0).sqrt(),
    }
}

/// Runs the filter over `log`.
pub fn run(log: &LogDir, options: &LevelingOptions) -> Result<LevelingRun, FilterError> {
    let init = &log.meta.initial;
    let lat = init.lat;
    let height = -init.depth;
    let t = options.tuning;
    let (roll0, pitch0) = options.initial_attitude.unwrap_or((0.0, 0.0));
    let a0 = gravity_direction(roll0, pitch0);
    let speed0 = if options.stationary {
        0.0
    } else {
        (init.vn * init.vn + init.ve * init.ve).sqrt()
    };
    let x0 = Vector6::new(speed0, 0.0, 0.0, a0.x, a0.y, a0.z);
    let v2 = t.velocity_sigma * t.velocity_sigma;
    let p0 = SMatrix::<f64, 6, 6>::from_diagonal(&Vector6::new(v2, v2, v2, 1.0, 1.0, 1.0));
    let params = Leveling6Params {
        gravity: earth::normal_gravity(lat, height),
    };
    let noise = Leveling6Noise {
        accel_noise: Vector3::repeat(t.accel_density * t.accel_density),
        gyro_noise: Vector3::repeat(t.gyro_density * t.gyro_density),
    };
    // No innovation gate: during convergence from a 45-degree error the linearized
    // S understates the innovation and a gate would reject the very measurements
    // that make the attitude observable (the paper uses none).
    let mut ekf = Ekf::<Leveling6, 6>::new(x0, p0, params, noise)?.with_default_gate(None);
    if t.upright {
        keep_upright(&mut ekf)?;
    }
    let w_ie_n = earth::earth_rate_n(lat);
    // Yaw is not estimated; it is carried by integrating the Euler yaw rate from
    // [initial].yaw so that the Earth-rate input W^b (eq. 16) follows the turns.
    let mut yaw = init.yaw.unwrap_or(0.0);

    let mut out = LevelingRun::default();
    let mut last_imu: Option<(f64, Leveling6Input)> = None;
    let mut next_zero_velocity = 0.1;
    let r_moving =
        Matrix2::from_diagonal(&Vector2::new(t.speed_sigma.powi(2), t.norm_sigma.powi(2)));
    let zv = t.zero_velocity_sigma.powi(2);
    let r_stationary = Matrix4::from_diagonal(&Vector4::new(zv, zv, zv, t.norm_sigma.powi(2)));

    for event in log.events() {
        match event {
            Event::Imu(row) => {
                let gyro = Vector3::new(row.gx, row.gy, row.gz);
                let x = *ekf.state();
                let (roll, pitch) = roll_pitch(&Vector3::new(x[3], x[4], x[5]));
                let c_nb = nav_runtime::attitude::Euler::new(roll, pitch, yaw).c_nb();
                let input = Leveling6Input {
                    gyro,
                    specific_force: Vector3::new(row.ax, row.ay, row.az),
                    earth_rate_body: c_nb * w_ie_n,
                };
                if let Some((t_prev, prev)) = last_imu {
                    let dt = row.t - t_prev;
                    match ekf.predict(dt, &prev) {
                        Ok(()) => {}
                        Err(_) => {
                            out.rejected += 1;
                            continue;
                        }
                    }
                    let w = gyro - input.earth_rate_body;
                    yaw =
                        wrap_angle(yaw + dt * (w.y * roll.sin() + w.z * roll.cos()) / pitch.cos());
                }
                last_imu = Some((row.t, input));
                out.samples += 1;
                if options.stationary && log.speed.is_none() && row.t + 1e-9 >= next_zero_velocity {
                    next_zero_velocity += 0.1;
                    let z = Vector4::new(0.0, 0.0, 0.0, 1.0);
                    count(
                        &mut out,
                        ekf.update::<Leveling6Stationary, 4>(&z, &r_stationary, &()),
                    );
                }
                out.estimates
                    .push(estimate(row.t, ekf.state(), ekf.covariance()));
            }
            Event::Speed(row) if last_imu.is_some() => {
                if options.stationary {
                    let z = Vector4::new(0.0, 0.0, 0.0, 1.0);
                    count(
                        &mut out,
                        ekf.update::<Leveling6Stationary, 4>(&z, &r_stationary, &()),
                    );
                } else {
                    let z = Vector2::new(row.speed, 1.0);
                    count(
                        &mut out,
                        ekf.update::<Leveling6Moving, 2>(&z, &r_moving, &()),
                    );
                }
                if t.upright {
                    keep_upright(&mut ekf)?;
                }
                if let Some(last) = out.estimates.last_mut() {
                    *last = estimate(last.t, ekf.state(), ekf.covariance());
                }
            }
            _ => {}
        }
    }
    out.repairs = ekf.counters().covariance_repairs;
    Ok(out)
}

/// Reflects `a3 -> -a3` (and its covariance row and column) when `a3 < 0`.
fn keep_upright(ekf: &mut Ekf<Leveling6, 6>) -> Result<(), FilterError> {
    let mut x = *ekf.state();
    if x[5] >= 0.0 {
        return Ok(());
    }
    x[5] = -x[5];
    let mut p = *ekf.covariance();
    for i in 0..6 {
        if i != 5 {
            p[(i, 5)] = -p[(i, 5)];
            p[(5, i)] = -p[(5, i)];
        }
    }
    ekf.set_state(x)?;
    Ok(ekf.set_covariance(p)?)
}

fn count<const M: usize>(
    out: &mut LevelingRun,
    r: Result<nav_runtime::ekf::UpdateReport<M>, FilterError>,
) {
    match r {
        Ok(rep) if rep.accepted => out.accepted += 1,
        Ok(_) => out.gated += 1,
        Err(_) => out.rejected += 1,
    }
}

/// Roll and pitch errors (rad) of the estimate in force at each truth time.
pub fn errors_at_truth(run: &LevelingRun, log: &LogDir) -> Vec<(f64, f64, f64)> {
    let Some(truth) = &log.truth else {
        return Vec::new();
    };
    truth
        .iter()
        .filter_map(|row| {
            let i = run.estimates.partition_point(|e| e.t <= row.t + 1e-9);
            let e = run.estimates.get(i.checked_sub(1)?)?;
            Some((
                row.t,
                wrap_angle(e.roll - row.roll),
                wrap_angle(e.pitch - row.pitch),
            ))
        })
        .collect()
}
