//! One closed-loop inspection mission: the true vehicle in a current, its IMU,
//! DVL, depth meter and camera, MARKER-9 estimating the state, a current
//! observer, and guidance (planning once, then a path-following law at 10 Hz)
//! acting on the estimates. A time-ordered loop at the IMU rate (100 Hz).

use nav_runtime::attitude::{body_rate_from_euler_rates, Euler};
use nav_runtime::camera::Camera;
use nav_runtime::ekf::Ekf;
use nav_runtime::guidance::heading_qp::{CourseQp, QpConfig, QpInput};
use nav_runtime::guidance::los::{improved_los_course, los_course};
use nav_runtime::guidance::rrt::{plan_through, Plan, PlanError, RrtConfig};
use nav_runtime::guidance::structure::Structure;
use nav_runtime::guidance::{
    CourseLimiter, GuidanceCommand, GuidanceConfig, Law, Path, PathFollower,
};
use nav_runtime::nalgebra::{Matrix2, SMatrix, SVector, Vector2, Vector3};
use nav_runtime::sensors::{derive_seed, normal};
use nav_runtime::vehicle::{
    Autopilot, AutopilotCommand, AutopilotFeedback, VehicleParams, VehicleState,
};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use super::model::{
    Marker9, Marker9Depth, Marker9Dvl, Marker9Input, Marker9MarkerRelative,
    Marker9MarkerRelativeAux, Marker9Noise,
};

/// Gravity used to remove `g` from the specific force, m/s^2 (16 m depth, mid latitude).
pub const GRAVITY: f64 = 9.81;
/// IMU period, s (100 Hz).
pub const IMU_DT: f64 = 0.01;

/// Sensor error figures (1-sigma per sample at each sensor's rate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SensorErrors {
    /// Gyro white noise, rad/s.
    pub gyro_noise: f64,
    /// Gyro bias (drawn once per run), rad/s.
    pub gyro_bias: f64,
    /// Accelerometer white noise, m/s^2.
    pub accel_noise: f64,
    /// Accelerometer bias (drawn once per run), m/s^2.
    pub accel_bias: f64,
    /// DVL bottom-track noise per body axis, m/s (5 Hz).
    pub dvl_noise: f64,
    /// DVL water-track noise per body axis, m/s (5 Hz).
    pub water_track_noise: f64,
    /// Depth meter noise, m (10 Hz).
    pub depth_noise: f64,
}

impl Default for SensorErrors {
    /// A tactical-grade IMU (1 deg/h gyro bias, 0.5 mg accelerometer bias), a
    /// 1.2 MHz DVL close to the bottom, a 0.01 %-of-full-scale pressure sensor.
    fn default() -> Self {
        Self {
            gyro_noise: 5e-5,
            gyro_bias: 1f64.to_radians() / 3600.0,
            accel_noise: 3e-3,
            accel_bias: 5e-3,
            dvl_noise: 0.01,
            water_track_noise: 0.02,
            depth_noise: 0.02,
        }
    }
}

/// Everything that defines a mission apart from its seed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MissionConfig {
    /// Path-following law.
    pub law: Law,
    /// Guidance limits and speeds.
    pub guidance: GuidanceConfig,
    /// Convex program settings.
    pub qp: QpConfig,
    /// Planner settings.
    pub rrt: RrtConfig,
    /// Camera.
    pub camera: Camera,
    /// True vehicle.
    pub vehicle: VehicleParams,
    /// Sensors.
    pub sensors: SensorErrors,
    /// Current speed range, m/s (uniform), direction uniform.
    pub current_speed: (f64, f64),
    /// Mission time limit, s.
    pub max_time: f64,
    /// Initial horizontal position error 1-sigma, m.
    pub initial_position_sigma: f64,
    /// Initial heading error 1-sigma, rad.
    pub initial_heading_sigma: f64,
}

impl Default for MissionConfig {
    fn default() -> Self {
        Self {
            law: Law::ConvexCorrection,
            guidance: GuidanceConfig::default(),
            qp: QpConfig::default(),
            rrt: RrtConfig::default(),
            camera: Camera::default(),
            vehicle: VehicleParams::default(),
            sensors: SensorErrors::default(),
            current_speed: (0.05, 0.15),
            max_time: 900.0,
            initial_position_sigma: 0.2,
            initial_heading_sigma: 1f64.to_radians(),
        }
    }
}

/// Inspection waypoints: along the +y long face, round the +x leg into the +x
/// short face, through the inside at 16 m, round the -x leg to the -y face,
/// along it, round the +x leg again and back through the inside at 18.8 m. The
/// order avoids reversals (every turn at a waypoint is under about 120 deg).
pub fn inspection_waypoints() -> Vec<Vector3<f64>> {
    [
        [-3.4, 2.3, 13.5],
        [3.4, 2.3, 15.0],
        [3.85, 1.4, 15.4],
        [3.7, 0.0, 16.0],
        [-3.6, 0.0, 16.5],
        [-3.85, -1.4, 17.0],
        [-3.4, -2.3, 17.5],
        [3.4, -2.3, 18.5],
        [3.85, -1.4, 18.8],
        [3.7, 0.0, 18.8],
        [-3.7, 0.0, 18.8],
    ]
    .iter()
    .map(|p| Vector3::new(p[0], p[1], p[2]))
    .collect()
}

/// A harder planning query, timed but not flown: waypoints on opposite sides of
/// legs and braces (over the top, under the bottom frame), so RRT-Connect has to
/// find detours rather than straight edges.
pub fn detour_waypoints() -> Vec<Vector3<f64>> {
    [
        [-3.4, 2.3, 13.5],
        [3.4, 2.3, 15.0],
        [0.0, -2.4, 11.0],
        [3.7, 0.0, 16.0],
        [-3.6, 0.0, 16.5],
        [3.4, -2.3, 18.5],
        [0.0, 0.0, 21.3],
        [-3.4, 2.3, 18.0],
    ]
    .iter()
    .map(|p| Vector3::new(p[0], p[1], p[2]))
    .collect()
}

/// Plans the mission of run `seed` through [`inspection_waypoints`].
///
/// # Errors
/// The planner's error.
pub fn plan(structure: &Structure, cfg: &MissionConfig, seed: u64) -> Result<Plan, PlanError> {
    plan_through(
        structure,
        &inspection_waypoints(),
        &cfg.rrt,
        derive_seed(seed, "marker-rrt"),
    )
}

/// One 10 Hz sample of a run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrackSample {
    /// Time, s.
    pub t: f64,
    /// True position, m.
    pub truth: Vector3<f64>,
    /// Estimated position, m.
    pub estimate: Vector3<f64>,
    /// Filter 1-sigma of north, east, down, m.
    pub sigma: Vector3<f64>,
    /// 3-D distance of the true position to the path, m.
    pub path_error_true: f64,
    /// 3-D distance of the estimated position to the path, m.
    pub path_error_estimated: f64,
    /// Surface clearance of the vehicle sphere to the structure, m.
    pub clearance: f64,
}

/// What one mission produced.
#[derive(Clone, Debug, PartialEq)]
pub struct MissionResult {
    /// Path RMS of the true position, m.
    pub path_rms_true: f64,
    /// Path RMS of the estimated position, m.
    pub path_rms_estimated: f64,
    /// Contacts of the vehicle sphere with a capsule (entries, at 100 Hz).
    pub collisions: u32,
    /// Smallest clearance, m.
    pub min_clearance: f64,
    /// Whether the last waypoint was reached.
    pub finished: bool,
    /// Mission duration, s.
    pub duration: f64,
    /// Per-call times of the convex program, ms (empty for LOS laws).
    pub qp_times_ms: Vec<f64>,
    /// Solved convex programs.
    pub qp_solved: u64,
    /// Fallbacks to rate-limited LOS.
    pub qp_fallbacks: u64,
    /// Marker fixes applied.
    pub fixes_accepted: u64,
    /// Marker fixes rejected by the gate.
    pub fixes_gated: u64,
    /// Horizontal error of the current estimate at the end, m/s.
    pub current_error: f64,
    /// Mean normalized estimation error squared of the horizontal position
    /// (2 degrees of freedom), over the 10 Hz samples.
    pub position_nees: f64,
    /// 10 Hz samples.
    pub track: Vec<TrackSample>,
}

/// The current observer: a random-walk Kalman filter on the horizontal current,
/// fed by `C_b^n (v_bottom - v_water)` from the DVL's bottom and water tracks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurrentObserver {
    /// Estimate `[v_N, v_E]`, m/s.
    pub estimate: Vector2<f64>,
    /// Variance per axis, (m/s)^2.
    pub variance: f64,
    /// Random-walk variance per update, (m/s)^2.
    pub q: f64,
    /// Measurement variance per axis, (m/s)^2.
    pub r: f64,
}

impl CurrentObserver {
    /// Starts at zero current with 1-sigma `sigma0`.
    pub fn new(sigma0: f64, measurement_sigma: f64) -> Self {
        Self {
            estimate: Vector2::zeros(),
            variance: sigma0 * sigma0,
            q: 1e-3 * 1e-3,
            r: measurement_sigma * measurement_sigma,
        }
    }

    /// One update with a horizontal current measurement.
    pub fn update(&mut self, z: &Vector2<f64>) {
        self.variance += self.q;
        let k = self.variance / (self.variance + self.r);
        self.estimate += (z - self.estimate) * k;
        self.variance *= 1.0 - k;
    }
}

/// Truth roll and pitch: small oscillations of a passively stable vehicle.
fn level_motion(t: f64, phase: f64) -> (f64, f64, f64, f64) {
    let (ar, wr) = (1.5f64.to_radians(), 2.0 * core::f64::consts::PI / 7.0);
    let (ap, wp) = (1.0f64.to_radians(), 2.0 * core::f64::consts::PI / 9.0);
    (
        ar * (wr * t + phase).sin(),
        ap * (wp * t + 2.0 * phase).sin(),
        ar * wr * (wr * t + phase).cos(),
        ap * wp * (wp * t + 2.0 * phase).cos(),
    )
}

/// Runs one mission with `cfg.law` on `plan`; a pure function of `seed`.
pub fn run_mission(
    structure: &Structure,
    plan: &Plan,
    cfg: &MissionConfig,
    seed: u64,
) -> MissionResult {
    let path = Path::new(plan.path.clone());
    let g = &cfg.guidance;
    let se = &cfg.sensors;
    let mut rng_world = ChaCha8Rng::seed_from_u64(derive_seed(seed, "marker-world"));
    let mut rng_imu = ChaCha8Rng::seed_from_u64(derive_seed(seed, "marker-imu"));
    let mut rng_aid = ChaCha8Rng::seed_from_u64(derive_seed(seed, "marker-aiding"));
    let mut rng_cam = ChaCha8Rng::seed_from_u64(derive_seed(seed, "marker-camera"));

    // World: current and truth start.
    let speed = rng_world.random_range(cfg.current_speed.0..cfg.current_speed.1);
    let dir = rng_world.random_range(-core::f64::consts::PI..core::f64::consts::PI);
    let current = Vector3::new(speed * dir.cos(), speed * dir.sin(), 0.0);
    let phase = rng_world.random_range(0.0..core::f64::consts::TAU);
    let gyro_bias = Vector3::from_fn(|_, _| normal(&mut rng_world, se.gyro_bias));
    let accel_bias = Vector3::from_fn(|_, _| normal(&mut rng_world, se.accel_bias));
    let first = path.points[1] - path.points[0];
    let heading0 = first.y.atan2(first.x);
    let mut truth = VehicleState::at_rest(path.points[0], heading0);

    // Filter: initial errors drawn from the initial covariance.
    let ps = cfg.initial_position_sigma;
    let hs = cfg.initial_heading_sigma;
    let ls = 0.2f64.to_radians();
    let (roll0, pitch0, _, _) = level_motion(0.0, phase);
    let x0 = SVector::<f64, 9>::from_column_slice(&[
        truth.position.x + normal(&mut rng_world, ps),
        truth.position.y + normal(&mut rng_world, ps),
        truth.position.z + normal(&mut rng_world, 0.05),
        0.0,
        0.0,
        0.0,
        roll0 + normal(&mut rng_world, ls),
        pitch0 + normal(&mut rng_world, ls),
        heading0 + normal(&mut rng_world, hs),
    ]);
    let p0 = SMatrix::<f64, 9, 9>::from_diagonal(&SVector::<f64, 9>::from_column_slice(&[
        ps * ps,
        ps * ps,
        0.05 * 0.05,
        // At rest in the water, so moving with the unknown current.
        0.2 * 0.2,
        0.2 * 0.2,
        0.2 * 0.2,
        ls * ls,
        ls * ls,
        hs * hs,
    ]));
    // Per-step process noise. Velocity: the gravity leakage of the level errors,
    // which this model cannot observe (acceleration is an input; 3.5 mrad of
    // level error leaks 0.034 m/s^2), dominates the accelerometer noise; it is a
    // slowly varying bias, covered by a random walk that lets the 5 Hz DVL
    // absorb 0.034 m/s^2 over 0.2 s (1.5e-3 m/s per step, 6.7e-3 m/s per DVL
    // interval).
    let qv = (1.5e-3f64).powi(2);
    // Attitude: gyro noise and bias give about 1e-6 rad per step. (Fixes
    // resolved with the estimated heading needed 1e-4 to stay consistent; the
    // camera detections are now fused as seen, `Marker9MarkerRelative`, and
    // the update carries the attitude-position correlation itself.)
    let qa = (1e-6f64).powi(2);
    let noise = Marker9Noise {
        velocity_noise: Vector3::repeat(qv),
        attitude_noise: Vector3::repeat(qa),
    };
    let mut ekf =
        Ekf::<Marker9, 9>::new(x0, p0, Default::default(), noise).expect("valid filter setup");
    // The DVL has no outliers here and is what keeps the unobservable level
    // errors from running away: never gate it (a gated DVL lets the velocity
    // drift, and the next innovations are gated too).
    let _ = ekf.set_sensor_gate::<Marker9Dvl, 3>(None);
    let mut observer = CurrentObserver::new(
        0.2,
        (se.dvl_noise.powi(2) + se.water_track_noise.powi(2)).sqrt(),
    );

    // Guidance and control.
    let mut autopilot = Autopilot::new({
        // The autopilot's model is 20 % off in drag.
        let mut m = cfg.vehicle;
        m.quadratic_damping = m.quadratic_damping.map(|d| 0.8 * d);
        m.linear_damping = m.linear_damping.map(|d| 1.2 * d);
        m
    });
    let mut follower = PathFollower::new();
    let mut limiter = CourseLimiter::new(heading0);
    let mut qp = CourseQp::new(cfg.qp, heading0);
    let mut command = GuidanceCommand {
        course: heading0,
        course_rate: 0.0,
        speed: 0.0,
        depth: truth.position.z,
        vertical_speed: 0.0,
    };

    let g_n = Vector3::new(0.0, 0.0, GRAVITY);
    let mut last_gyro = Vector3::zeros();
    let mut track = Vec::new();
    let mut collisions = 0;
    let mut in_contact = false;
    let mut min_clearance = f64::INFINITY;
    let (mut fixes_accepted, mut fixes_gated) = (0u64, 0u64);
    let mut nees_sum = 0.0;
    let max_steps = (cfg.max_time / IMU_DT) as usize;
    let mut step = 0usize;
    while step < max_steps {
        let t = step as f64 * IMU_DT;
        let x = *ekf.state();
        let est_euler = Euler::new(x[6], x[7], x[8]);
        let est_c_bn = est_euler.c_bn();
        let est_pos = Vector3::new(x[0], x[1], x[2]);

        let v_ground_est = est_c_bn * Vector3::new(x[3], x[4], x[5]);
        // Guidance at 10 Hz on the estimate.
        if step.is_multiple_of(10) {
            let p2 = Vector2::new(est_pos.x, est_pos.y);
            let e = follower.update(&path, &p2, g);
            if follower.finished {
                break;
            }
            let u = command.speed;
            let (course, rate) = match cfg.law {
                Law::Los => {
                    let c = limiter.step(los_course(&path, &e, &p2, g.los_radius), g);
                    (c, limiter.rate)
                }
                Law::ImprovedLos => {
                    let target =
                        improved_los_course(&e, g.los_radius, g.turning_radius(u).max(0.05));
                    let c = limiter.step(target, g);
                    (c, limiter.rate)
                }
                Law::ConvexCorrection => {
                    let out = qp.step(&QpInput {
                        path: &path,
                        follower,
                        position: est_pos,
                        guidance: g,
                        structure,
                        vehicle_radius: cfg.vehicle.radius,
                        speed: command.speed,
                        ground_speed: v_ground_est.xy().norm(),
                        velocity_bandwidth: autopilot.velocity_gain,
                    });
                    (out.course, out.rate)
                }
            };
            let u = g.speed_command(&path, &e, course, command.speed, g.tick);
            let inside = e.along > 0.0 && e.along < e.length;
            command = GuidanceCommand {
                course,
                course_rate: rate,
                speed: u,
                depth: e.depth,
                vertical_speed: if inside { u * e.slope } else { 0.0 },
            };
        }

        // Autopilot on the estimate.
        let thrust = autopilot.thrust(
            &AutopilotCommand {
                ground_velocity: command.ground_velocity(),
                heading: command.course,
                heading_rate: command.course_rate,
                depth: command.depth,
                vertical_speed: command.vertical_speed,
            },
            &AutopilotFeedback {
                heading: x[8],
                yaw_rate: last_gyro.z,
                depth: x[2],
                ground_velocity: v_ground_est,
                current: Vector3::new(observer.estimate.x, observer.estimate.y, 0.0),
            },
            IMU_DT,
        );

        // Truth over [t, t + dt] and the IMU sample of that interval.
        let (roll, pitch, droll, dpitch) = level_motion(t, phase);
        let e_true = Euler::new(roll, pitch, truth.heading);
        let c_bn = e_true.c_bn();
        let v0 = truth.ground_velocity(&current);
        truth.step(&cfg.vehicle, &thrust, &current, IMU_DT);
        let v1 = truth.ground_velocity(&current);
        let a_n = (v1 - v0) / IMU_DT;
        let omega = body_rate_from_euler_rates(&e_true, &Euler::new(droll, dpitch, truth.yaw_rate));
        let gyro = omega + gyro_bias + Vector3::from_fn(|_, _| normal(&mut rng_imu, se.gyro_noise));
        let f_b = c_bn.transpose() * (a_n - g_n)
            + accel_bias
            + Vector3::from_fn(|_, _| normal(&mut rng_imu, se.accel_noise));
        last_gyro = gyro;
        let input = Marker9Input {
            gyro,
            acceleration: f_b + est_c_bn.transpose() * g_n,
        };
        let _ = ekf.predict(IMU_DT, &input);
        step += 1;
        let t1 = step as f64 * IMU_DT;
        let (roll1, pitch1, _, _) = level_motion(t1, phase);
        let c_bn1 = Euler::new(roll1, pitch1, truth.heading).c_bn();

        // Contact check at 100 Hz.
        let clearance = structure.nearest(&truth.position).0 - cfg.vehicle.radius;
        min_clearance = min_clearance.min(clearance);
        if clearance < 0.0 && !in_contact {
            collisions += 1;
        }
        in_contact = clearance < 0.0;

        // DVL bottom and water track at 5 Hz.
        if step.is_multiple_of(20) {
            let v_b = c_bn1.transpose() * v1;
            let z = v_b + Vector3::from_fn(|_, _| normal(&mut rng_aid, se.dvl_noise));
            let sd = 1.2 * se.dvl_noise;
            let _ = ekf.update::<Marker9Dvl, 3>(
                &z,
                &SMatrix::<f64, 3, 3>::identity().scale(sd * sd),
                &(),
            );
            let w_b = c_bn1.transpose() * (v1 - current)
                + Vector3::from_fn(|_, _| normal(&mut rng_aid, se.water_track_noise));
            let xe = *ekf.state();
            let rel = Euler::new(xe[6], xe[7], xe[8]).c_bn() * (z - w_b);
            observer.update(&Vector2::new(rel.x, rel.y));
        }
        // Depth at 10 Hz.
        if step % 10 == 5 {
            let z = SVector::<f64, 1>::new(truth.position.z + normal(&mut rng_aid, se.depth_noise));
            let r = SMatrix::<f64, 1, 1>::new(se.depth_noise * se.depth_noise);
            let _ = ekf.update::<Marker9Depth, 1>(&z, &r, &());
        }
        // Camera at 5 Hz.
        // Each detection is fused as seen (marker relative to the camera, body
        // axes), so the update correlates attitude and position errors.
        if step % 20 == 10 {
            for (i, _) in cfg.camera.visible(structure, &truth.position, &c_bn1) {
                let d = cfg
                    .camera
                    .detect(structure, i, &truth.position, &c_bn1, &mut rng_cam);
                let aux = Marker9MarkerRelativeAux {
                    marker: structure.markers[i].position,
                    lever_arm: cfg.camera.lever_arm,
                };
                match ekf.update::<Marker9MarkerRelative, 3>(&d.relative, &d.covariance, &aux) {
                    Ok(rep) if rep.accepted => fixes_accepted += 1,
                    _ => fixes_gated += 1,
                }
            }
        }

        // Scoring at 10 Hz.
        if step.is_multiple_of(10) {
            let xe = *ekf.state();
            let est = Vector3::new(xe[0], xe[1], xe[2]);
            let (from, to) = (follower.segment.saturating_sub(1), follower.segment + 1);
            let p = ekf.covariance();
            let err = Vector2::new(truth.position.x - est.x, truth.position.y - est.y);
            let ph = Matrix2::new(p[(0, 0)], p[(0, 1)], p[(1, 0)], p[(1, 1)]);
            if let Some(inv) = ph.try_inverse() {
                nees_sum += (err.transpose() * inv * err)[0];
            }
            track.push(TrackSample {
                t: t1,
                truth: truth.position,
                estimate: est,
                sigma: Vector3::new(p[(0, 0)].sqrt(), p[(1, 1)].sqrt(), p[(2, 2)].sqrt()),
                path_error_true: path.distance(&truth.position, from, to),
                path_error_estimated: path.distance(&est, from, to),
                clearance,
            });
        }
    }
    let rms = |f: fn(&TrackSample) -> f64| {
        let n = track.len().max(1) as f64;
        (track.iter().map(|s| f(s).powi(2)).sum::<f64>() / n).sqrt()
    };
    MissionResult {
        path_rms_true: rms(|s| s.path_error_true),
        path_rms_estimated: rms(|s| s.path_error_estimated),
        collisions,
        min_clearance,
        finished: follower.finished,
        duration: step as f64 * IMU_DT,
        qp_times_ms: qp.stats.times_ms.clone(),
        qp_solved: qp.stats.solved,
        qp_fallbacks: qp.stats.fallbacks,
        fixes_accepted,
        fixes_gated,
        current_error: (observer.estimate - Vector2::new(current.x, current.y)).norm(),
        position_nees: nees_sum / track.len().max(1) as f64,
        track,
    }
}
