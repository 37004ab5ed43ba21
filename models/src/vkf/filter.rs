//! The three navigators of the VKF comparison, run over one log in one pass:
//!
//! - pure INS: the strapdown (coning and sculling corrected) from the known
//!   initial state, no aiding;
//! - conventional INS-DVL: the 9-state filter ([`Nav9`]) aided by the DVL while
//!   the echo sounder says it is in range, inertial only during the outages;
//! - VKF-aided: the same 9-state filter aided by the switching box (eq. 12): the
//!   DVL in range, otherwise the RPM-derived velocity of the velocity filter
//!   ([`VelocityFilter`]) rotated to n with the Euler angles (eq. 11).
//!
//! Each aided navigator keeps a strapdown attitude computer whose position and
//! velocity are slaved to its filter: each IMU step it integrates the attitude
//! and returns the compensated nav-frame acceleration
//! `a^n = C_b^n f^b - (2 w_ie^n + w_en^n) x v^n + g^n` (coordinate transform,
//! Coriolis and gravity compensation, with coning and sculling) as
//! `delta v^n / dt`, the input of the 9-state filter.
//!
//! Aiding stamped `t` is fused after the IMU step ending at `t` (it is buffered
//! and applied before the next IMU step).

use super::attitude_computer::AttitudeComputer;
use super::coupled::{CoupledNav, MapTuning};
use super::model::{
    Nav9, Nav9Dvl, Nav9Input, Nav9Noise, Nav9Params, Nav9Rpm, VelocityFilter, VelocityFilterDvl,
    VelocityFilterInput, VelocityFilterNoise, VelocityFilterParams,
};
use nav_runtime::attitude::Euler;
use nav_runtime::earth::{geodetic_error_to_ned, Geodetic};
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::log::{Event, LogDir};
use nav_runtime::nalgebra::{Matrix1, Matrix3, SMatrix, SVector, Vector1, Vector3};
use nav_runtime::strapdown::{NavState, Strapdown};

/// Altitude (m) at or below which the switching box uses the DVL (paper: 100 m).
pub const SWITCH_ALTITUDE: f64 = 100.0;

/// Which velocity the switching box passes on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Source {
    /// The DVL (in range).
    Dvl,
    /// The RPM-derived velocity (DVL out of range).
    Rpm,
}

/// The switching box's decision (eq. 12): DVL when the echo-sounder altitude is
/// at most `threshold` (m), the RPM-derived velocity otherwise.
pub fn switch(altitude: f64, threshold: f64) -> Source {
    if altitude <= threshold {
        Source::Dvl
    } else {
        Source::Rpm
    }
}

/// Filter tuning (set from the sensor specifications, not fitted to seeds).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tuning {
    /// Switching altitude (m).
    pub switch_altitude: f64,
    /// Velocity filter: departure of the speed from the RPM map per step (m/s).
    pub map_noise: f64,
    /// Velocity filter: scale-factor random walk per step ((m/s)/rpm).
    pub scale_factor_walk: f64,
    /// Velocity filter: bias random walk per step (m/s).
    pub bias_walk: f64,
    /// Velocity filter: initial 1-sigma of the scale factor, fraction of the design value.
    pub scale_factor_sigma: f64,
    /// Velocity filter: initial 1-sigma of the bias (m/s).
    pub bias_sigma: f64,
    /// Design RPM map `(sf, b)` the velocity filter starts from.
    pub design_map: (f64, f64),
    /// RPM-derived velocity: 1-sigma of the unmeasured lateral and vertical body
    /// velocity (sideslip, heave), m/s.
    pub rpm_lateral_sigma: f64,
    /// 9-state filter: acceleration white noise, m/s^2/sqrt(Hz).
    pub accel_density: f64,
    /// 9-state filter: accelerometer-bias random walk, m/s^2/sqrt(s) (it also
    /// follows the tilt drift of the unaided attitude).
    pub bias_walk_density: f64,
    /// 9-state filter: initial bias 1-sigma, m/s^2.
    pub accel_bias_sigma: f64,
    /// Largest plausible velocity innovation (m/s): a larger one is an invalid
    /// ping (e.g. a misread altitude at the edge of the range) and is not fused.
    pub max_innovation: f64,
    /// DVL noise per axis per sample (m/s), used when the log has no `[sensors.dvl]`.
    pub dvl_noise: f64,
}

impl Default for Tuning {
    fn default() -> Self {
        let design = super::simulation::RpmMap::NOMINAL;
        Tuning {
            switch_altitude: SWITCH_ALTITUDE,
            map_noise: 0.015,
            scale_factor_walk: 2e-7,
            bias_walk: 5e-4,
            scale_factor_sigma: 0.05,
            bias_sigma: 0.3,
            design_map: (design.slope, design.offset),
            rpm_lateral_sigma: 0.05,
            accel_density: 3e-4,
            bias_walk_density: 3e-5,
            accel_bias_sigma: 2e-3,
            max_innovation: 1.5,
            dvl_noise: 0.02,
        }
    }
}

/// The velocity filter with its fixed noise settings.
#[derive(Clone, Debug)]
pub struct SpeedLearner {
    ekf: Ekf<VelocityFilter, 3>,
    r: Matrix1<f64>,
    max_innovation: f64,
}

impl SpeedLearner {
    /// Starts from the design map at `rpm0`, with DVL noise `dvl_noise` (m/s).
    pub fn new(t: &Tuning, rpm0: f64, dvl_noise: f64) -> Result<Self, FilterError> {
        let (sf, b) = t.design_map;
        let x0 = Vector3::new(sf * rpm0 + b, sf, b);
        let p0 = Matrix3::from_diagonal(&Vector3::new(
            0.5f64.powi(2),
            (t.scale_factor_sigma * sf).powi(2),
            t.bias_sigma.powi(2),
        ));
        let noise = VelocityFilterNoise {
            speed_noise: t.map_noise.powi(2),
            scale_factor_walk: t.scale_factor_walk.powi(2),
            bias_walk: t.bias_walk.powi(2),
        };
        let ekf = Ekf::new(x0, p0, VelocityFilterParams::default(), noise)?.with_default_gate(None);
        Ok(SpeedLearner {
            ekf,
            r: Matrix1::new(dvl_noise * dvl_noise),
            max_innovation: t.max_innovation,
        })
    }

    /// One step with the RPM sample `rpm` (eq. 8).
    pub fn predict(&mut self, rpm: f64, dt: f64) -> Result<(), FilterError> {
        self.ekf.predict(dt, &VelocityFilterInput { rpm })
    }

    /// Fuses a DVL forward speed (eq. 10); `false` if implausible or refused.
    pub fn update(&mut self, forward_speed: f64) -> bool {
        if (forward_speed - self.ekf.state()[0]).abs() > self.max_innovation {
            return false;
        }
        matches!(self.ekf.update::<VelocityFilterDvl, 1>(&Vector1::new(forward_speed), &self.r, &()), Ok(r) if r.accepted)
    }

    /// Estimated scale factor and bias.
    pub fn map(&self) -> (f64, f64) {
        (self.ekf.state()[1], self.ekf.state()[2])
    }

    /// 1-sigma of the scale factor and the bias.
    pub fn map_sigma(&self) -> (f64, f64) {
        let p = self.ekf.covariance();
        (p[(1, 1)].max(0.0).sqrt(), p[(2, 2)].max(0.0).sqrt())
    }

    /// RPM-derived forward speed `sf rpm + b` (eq. 6) and its 1-sigma (map
    /// uncertainty at this rpm plus the per-step map noise).
    pub fn speed_from_rpm(&self, rpm: f64) -> (f64, f64) {
        let (sf, b) = self.map();
        let p = self.ekf.covariance();
        let var = rpm * rpm * p[(1, 1)]
            + 2.0 * rpm * p[(1, 2)]
            + p[(2, 2)]
            + self.ekf.noise().speed_noise;
        (sf * rpm + b, var.max(0.0).sqrt())
    }
}

/// The switching box's output for the 9-state filter: an NED velocity and its
/// noise covariance (eqs. 11-12).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SwitchOutput {
    /// Which velocity was chosen.
    pub source: Source,
    /// NED velocity (m/s).
    pub v_n: Vector3<f64>,
    /// Its noise covariance ((m/s)^2).
    pub r_n: Matrix3<f64>,
}

/// DVL body velocity rotated to n: `C_b^n v_dvl` with per-axis noise `sigma`.
pub fn dvl_nav(c_bn: &Matrix3<f64>, v_b: &Vector3<f64>, sigma: f64) -> SwitchOutput {
    SwitchOutput {
        source: Source::Dvl,
        v_n: c_bn * v_b,
        r_n: Matrix3::identity() * sigma * sigma,
    }
}

/// RPM-derived velocity `C_b^n [V_rpm, 0, 0]` (eq. 11) with forward 1-sigma
/// `sigma_forward` and lateral/vertical 1-sigma `sigma_lateral`.
pub fn rpm_nav(
    c_bn: &Matrix3<f64>,
    speed: f64,
    sigma_forward: f64,
    sigma_lateral: f64,
) -> SwitchOutput {
    let r_b = Matrix3::from_diagonal(&Vector3::new(
        sigma_forward.powi(2),
        sigma_lateral.powi(2),
        sigma_lateral.powi(2),
    ));
    SwitchOutput {
        source: Source::Rpm,
        v_n: c_bn * Vector3::new(speed, 0.0, 0.0),
        r_n: c_bn * r_b * c_bn.transpose(),
    }
}

/// An aided navigator: the 9-state filter and its slaved attitude computer.
#[derive(Clone, Debug)]
pub struct AidedNav {
    ekf: Ekf<Nav9, 9>,
    attitude: AttitudeComputer,
    max_innovation: f64,
    /// Updates refused (implausible or by the filter).
    pub refused: u64,
}

impl AidedNav {
    /// Starts at `state` (the origin of the local NED position).
    pub fn new(state: NavState, t: &Tuning) -> Result<Self, FilterError> {
        let mut x0 = SVector::<f64, 9>::zeros();
        x0.fixed_rows_mut::<3>(3).copy_from(&state.v_n);
        let mut d = SVector::<f64, 9>::zeros();
        d.fixed_rows_mut::<3>(0).fill(0.1f64.powi(2));
        d.fixed_rows_mut::<3>(3).fill(0.05f64.powi(2));
        d.fixed_rows_mut::<3>(6).fill(t.accel_bias_sigma.powi(2));
        let noise = Nav9Noise {
            accel_noise: Vector3::repeat(t.accel_density.powi(2)),
            bias_walk: Vector3::repeat(t.bias_walk_density.powi(2)),
        };
        let ekf = Ekf::new(x0, SMatrix::from_diagonal(&d), Nav9Params::default(), noise)?
            .with_default_gate(None);
        Ok(AidedNav {
            ekf,
            attitude: AttitudeComputer::new(state),
            max_innovation: t.max_innovation,
            refused: 0,
        })
    }

    /// NED position relative to the start (m).
    pub fn position(&self) -> Vector3<f64> {
        self.ekf.state().fixed_rows::<3>(0).into_owned()
    }

    /// NED velocity (m/s).
    pub fn velocity(&self) -> Vector3<f64> {
        self.ekf.state().fixed_rows::<3>(3).into_owned()
    }

    /// Estimated accelerometer bias, body axes (m/s^2).
    pub fn accel_bias(&self) -> Vector3<f64> {
        self.ekf.state().fixed_rows::<3>(6).into_owned()
    }

    /// Attitude `C_b^n` of the attitude computer.
    pub fn c_bn(&self) -> Matrix3<f64> {
        self.attitude.c_bn()
    }

    /// One IMU step: slave the attitude computer to the filter, integrate the
    /// increments, predict the filter with the compensated acceleration.
    pub fn propagate(
        &mut self,
        dtheta: &Vector3<f64>,
        dv: &Vector3<f64>,
        dt: f64,
    ) -> Result<(), FilterError> {
        let (p, v) = (self.position(), self.velocity());
        let (accel_n, c_bn) = self.attitude.step(&p, &v, dtheta, dv, dt);
        self.ekf.predict(dt, &Nav9Input { accel_n, c_bn })
    }

    /// Fuses a switching-box output.
    pub fn update(&mut self, z: &SwitchOutput) -> bool {
        if (z.v_n - self.velocity()).amax() > self.max_innovation {
            self.refused += 1;
            return false;
        }
        let r = match z.source {
            Source::Dvl => self.ekf.update::<Nav9Dvl, 3>(&z.v_n, &z.r_n, &()),
            Source::Rpm => self.ekf.update::<Nav9Rpm, 3>(&z.v_n, &z.r_n, &()),
        };
        let ok = matches!(r, Ok(rep) if rep.accepted);
        if !ok {
            self.refused += 1;
        }
        ok
    }
}

/// One 5 Hz record of a run (positions NED from the start, m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Record {
    /// Time (s).
    pub t: f64,
    /// Pure INS position error, NED (m), against the log's truth at `t`.
    pub pure_error: Vector3<f64>,
    /// INS-DVL position.
    pub ins_dvl: Vector3<f64>,
    /// VKF-aided position.
    pub vkf: Vector3<f64>,
    /// Position of the VKF with the speed map inside the integrated filter.
    pub vkf_coupled: Vector3<f64>,
    /// Its map's forward speed at this epoch's RPM (m/s).
    pub coupled_map_speed: f64,
    /// Its horizontal position covariance `[P_NN, P_NE, P_EE]` (m^2).
    pub coupled_covariance: [f64; 3],
    /// Position of INS-DVL with the DVL error states of the map-state VKF
    /// (the same filter with the RPM never fused): the baseline that tells
    /// what the DVL states do from what the RPM map does.
    pub ins_dvl_calibrated: Vector3<f64>,
    /// Its horizontal position covariance (m^2).
    pub calibrated_covariance: [f64; 3],
    /// Switch decision.
    pub source: Source,
    /// Measured altitude (m).
    pub altitude: f64,
    /// RPM.
    pub rpm: f64,
    /// DVL NED velocity (VKF attitude), m/s.
    pub dvl_n: Vector3<f64>,
    /// DVL forward speed, m/s.
    pub dvl_forward: f64,
    /// RPM-derived forward speed, m/s.
    pub rpm_speed: f64,
    /// RPM-derived NED velocity, m/s.
    pub rpm_n: Vector3<f64>,
    /// Scale factor, bias and their 1-sigma.
    pub sf: f64,
    /// Bias (m/s).
    pub b: f64,
    /// Scale factor 1-sigma.
    pub sf_sigma: f64,
    /// Bias 1-sigma.
    pub b_sigma: f64,
}

/// Everything a run over a log produced.
#[derive(Clone, Debug, Default)]
pub struct VkfRun {
    /// One record per aiding epoch (5 Hz).
    pub records: Vec<Record>,
    /// IMU samples processed.
    pub samples: usize,
    /// Updates refused by the INS-DVL and VKF navigators.
    pub refused: (u64, u64),
    /// Updates refused by the speed-map VKF navigator.
    pub refused_coupled: u64,
    /// Updates refused by the calibrated INS-DVL navigator.
    pub refused_calibrated: u64,
    /// Velocity-filter updates applied.
    pub speed_updates: u64,
}

/// Options of [`run`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RunSettings {
    /// Tuning.
    pub tuning: Tuning,
    /// Tuning of the speed-map states of the coupled VKF navigator.
    pub map: MapTuning,
}

#[derive(Clone, Copy, Debug, Default)]
struct Pending {
    t: f64,
    dvl: Option<Vector3<f64>>,
    rpm: Option<f64>,
    altitude: Option<f64>,
}

/// Runs the three navigators over `log` (imu.csv as interval averages;
/// dvl.csv, rpm.csv and altitude.csv at a common rate; `[initial]` with the full
/// attitude).
pub fn run(log: &LogDir, settings: &RunSettings) -> Result<VkfRun, FilterError> {
    let tn = settings.tuning;
    let init = &log.meta.initial;
    let att = Euler::new(
        init.roll.unwrap_or(0.0),
        init.pitch.unwrap_or(0.0),
        init.yaw.unwrap_or(0.0),
    );
    let start = NavState::new(
        Geodetic::new(init.lat, init.lon, -init.depth),
        Vector3::new(init.vn, init.ve, init.vd),
        &att,
    );
    let dvl_noise = log.meta.sensors.dvl.map_or(tn.dvl_noise, |d| d.noise_sigma);
    let rpm0 = log
        .rpm
        .as_ref()
        .and_then(|r| r.first())
        .map_or(300.0, |r| r.rpm);
    let truth = log.truth.as_deref().unwrap_or(&[]);

    let mut pure = Strapdown::new(start);
    let mut ins_dvl = AidedNav::new(start, &tn)?;
    let mut vkf = AidedNav::new(start, &tn)?;
    let dvl_bias_sigma = log.meta.sensors.dvl.map_or(0.0, |d| d.bias_sigma);
    let mut coupled = CoupledNav::new(start, &tn, &settings.map, dvl_bias_sigma)?;
    let mut calibrated = coupled.clone();
    let mut learner = SpeedLearner::new(&tn, rpm0, dvl_noise)?;
    let mut out = VkfRun::default();
    let mut t_prev = log.imu.first().map_or(0.0, |r| r.t - 0.01).min(0.0);
    let mut last_rpm_t: Option<f64> = None;
    let mut pending = Pending::default();
    let mut truth_i = 0usize;

    let mut flush = |pending: &mut Pending,
                     pure: &Strapdown,
                     ins_dvl: &mut AidedNav,
                     vkf: &mut AidedNav,
                     [coupled, calibrated]: [&mut CoupledNav; 2],
                     learner: &mut SpeedLearner,
                     out: &mut VkfRun|
     -> Result<(), FilterError> {
        let p = std::mem::take(pending);
        let Some(rpm) = p.rpm else {
            return Ok(());
        };
        // Velocity filter: one step per RPM sample.
        let dt = last_rpm_t.map_or(0.2, |t0| (p.t - t0).max(1e-3));
        last_rpm_t = Some(p.t);
        learner.predict(rpm, dt)?;
        let altitude = p.altitude.unwrap_or(f64::INFINITY);
        let source = switch(altitude, tn.switch_altitude);
        let dvl_forward = p.dvl.map_or(f64::NAN, |v| v.x);
        if source == Source::Dvl && dvl_forward.is_finite() && learner.update(dvl_forward) {
            out.speed_updates += 1;
        }
        // Switching box (eq. 12) for VKF; DVL-only for the conventional filter.
        let (rpm_speed, rpm_sigma) = learner.speed_from_rpm(rpm);
        let rpm_out = rpm_nav(&vkf.c_bn(), rpm_speed, rpm_sigma, tn.rpm_lateral_sigma);
        let dvl_vkf = p.dvl.map(|v| dvl_nav(&vkf.c_bn(), &v, dvl_noise));
        if source == Source::Dvl {
            if let Some(v) = p.dvl {
                ins_dvl.update(&dvl_nav(&ins_dvl.c_bn(), &v, dvl_noise));
            }
            if let Some(z) = &dvl_vkf {
                vkf.update(z);
            }
        } else {
            vkf.update(&rpm_out);
        }
        // The speed-map navigator: the DVL in range, the RPM constraint always.
        if source == Source::Dvl {
            if let Some(v) = p.dvl {
                coupled.update_dvl(&(coupled.c_bn() * v), dvl_noise);
                calibrated.update_dvl(&(calibrated.c_bn() * v), dvl_noise);
            }
        }
        coupled.update_rpm(rpm);
        // Record at this epoch, pure INS scored against the truth row at p.t.
        while truth_i + 1 < truth.len() && truth[truth_i].t < p.t - 1e-6 {
            truth_i += 1;
        }
        let pure_error = match truth.get(truth_i) {
            Some(tr) if (tr.t - p.t).abs() < 1e-6 => {
                let s = &pure.state;
                geodetic_error_to_ned(
                    tr.lat,
                    -tr.depth,
                    s.lat - tr.lat,
                    s.lon - tr.lon,
                    s.h + tr.depth,
                )
            }
            _ => Vector3::repeat(f64::NAN),
        };
        let (sf, b) = learner.map();
        let (sf_sigma, b_sigma) = learner.map_sigma();
        out.records.push(Record {
            t: p.t,
            pure_error,
            ins_dvl: ins_dvl.position(),
            vkf: vkf.position(),
            vkf_coupled: coupled.position(),
            coupled_map_speed: coupled.map_speed(rpm),
            coupled_covariance: coupled.horizontal_covariance(),
            ins_dvl_calibrated: calibrated.position(),
            calibrated_covariance: calibrated.horizontal_covariance(),
            source,
            altitude,
            rpm,
            dvl_n: dvl_vkf.map_or(Vector3::repeat(f64::NAN), |z| z.v_n),
            dvl_forward,
            rpm_speed,
            rpm_n: rpm_out.v_n,
            sf,
            b,
            sf_sigma,
            b_sigma,
        });
        Ok(())
    };

    for event in log.events() {
        match event {
            Event::Imu(row) => {
                flush(
                    &mut pending,
                    &pure,
                    &mut ins_dvl,
                    &mut vkf,
                    [&mut coupled, &mut calibrated],
                    &mut learner,
                    &mut out,
                )?;
                let dt = row.t - t_prev;
                t_prev = row.t;
                if !(dt > 0.0 && dt < 1.0) {
                    continue;
                }
                let dtheta = Vector3::new(row.gx, row.gy, row.gz) * dt;
                let dv = Vector3::new(row.ax, row.ay, row.az) * dt;
                pure.update_increments(&dtheta, &dv, dt);
                ins_dvl.propagate(&dtheta, &dv, dt)?;
                vkf.propagate(&dtheta, &dv, dt)?;
                coupled.propagate(&dtheta, &dv, dt)?;
                calibrated.propagate(&dtheta, &dv, dt)?;
                out.samples += 1;
            }
            Event::Dvl(row) => {
                pending.t = row.t;
                pending.dvl = row.velocity().map(|v| Vector3::new(v[0], v[1], v[2]));
            }
            Event::Rpm(row) => {
                pending.t = row.t;
                pending.rpm = Some(row.rpm);
            }
            Event::Altitude(row) => {
                pending.t = row.t;
                pending.altitude = Some(row.altitude);
            }
            _ => {}
        }
    }
    flush(
        &mut pending,
        &pure,
        &mut ins_dvl,
        &mut vkf,
        [&mut coupled, &mut calibrated],
        &mut learner,
        &mut out,
    )?;
    out.refused = (ins_dvl.refused, vkf.refused);
    out.refused_coupled = coupled.refused;
    out.refused_calibrated = calibrated.refused;
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::sensors::normal;
    use rand::SeedableRng;
    use rand_chacha::ChaCha8Rng;

    #[test]
    fn switch_picks_dvl_in_range_and_rpm_beyond() {
        let cases = [
            (0.0, Source::Dvl),
            (55.0, Source::Dvl),
            (100.0, Source::Dvl),
            (100.01, Source::Rpm),
            (230.0, Source::Rpm),
            (f64::INFINITY, Source::Rpm),
        ];
        for (alt, want) in cases {
            assert_eq!(switch(alt, SWITCH_ALTITUDE), want, "{alt}");
        }
        // The RPM branch rotates the forward speed with the attitude (eq. 11).
        let c = Euler::from_degrees(0.0, 0.0, 90.0).c_bn();
        let z = rpm_nav(&c, 5.0, 0.01, 0.05);
        assert!((z.v_n - Vector3::new(0.0, 5.0, 0.0)).norm() < 1e-12);
        assert!((z.r_n[(1, 1)] - 1e-4).abs() < 1e-12 && (z.r_n[(0, 0)] - 25e-4).abs() < 1e-12);
    }

    /// Velocity filter on a synthetic linear map (constant sf and b, so the bias
    /// walk is set small), speed swept over +-1 kn for 10 min: sf and b end within
    /// 3 sigma of the truth and within 0.5 % of sf and 0.03 m/s of b (the DVL
    /// noise averaged over the sweep allows about 0.1 %).
    #[test]
    fn velocity_filter_learns_a_synthetic_map() {
        for seed in 1..=4u64 {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let (sf_true, b_true) = (
                0.0175 * (1.0 + normal(&mut rng, 0.03)),
                -0.2 + normal(&mut rng, 0.1),
            );
            let t = Tuning {
                bias_walk: 1e-5,
                ..Tuning::default()
            };
            let mut vf = SpeedLearner::new(&t, 300.0, 0.02).unwrap();
            for k in 0..3000 {
                let rpm = 300.0 + 30.0 * (k as f64 * 0.2 / 40.0).sin();
                let v = sf_true * rpm + b_true;
                vf.predict(rpm + normal(&mut rng, 0.5), 0.2).unwrap();
                assert!(vf.update(v + normal(&mut rng, 0.02)));
            }
            let ((sf, b), (ssf, sb)) = (vf.map(), vf.map_sigma());
            assert!(
                (sf - sf_true).abs() < 3.0 * ssf && (sf / sf_true - 1.0).abs() < 5e-3,
                "seed {seed}: sf {sf} vs {sf_true} (sigma {ssf})"
            );
            assert!(
                (b - b_true).abs() < 3.0 * sb && (b - b_true).abs() < 0.03,
                "seed {seed}: b {b} vs {b_true} (sigma {sb})"
            );
            let (v, _) = vf.speed_from_rpm(300.0);
            assert!((v - (sf_true * 300.0 + b_true)).abs() < 0.01, "seed {seed}");
        }
    }
}
