//! The VKF navigator with the speed map inside the integrated filter
//! ([`NavSpeedMap`], docs/results/vkf.md "Speed-map states").
//!
//! The paper's VKF learns the RPM map in a separate velocity filter and hands
//! the integrated filter a velocity whose error it treats as white: whatever
//! the map gets wrong during an outage goes straight into the position and
//! nothing in the covariance remembers it. Here the map's scale, offset and the
//! correlated speed disturbance are states of the integrated filter; the RPM
//! is fused at every epoch (with the DVL when it is in range, alone during the
//! outages), so the filter learns the map from the DVL itself, keeps the
//! correlation between the map errors and the position it integrates, and the
//! returning DVL corrects the position drift of the outage as it does for
//! the conventional filter.

use super::attitude_computer::AttitudeComputer;
use super::model::{
    NavSpeedMap, NavSpeedMapDvl, NavSpeedMapInput, NavSpeedMapNoise, NavSpeedMapParams,
    NavSpeedMapRpm, NavSpeedMapRpmAux,
};
use super::simulation::SPEED_DISTURBANCE;
use nav_runtime::ekf::{Ekf, FilterError};
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use nav_runtime::strapdown::NavState;

/// Tuning of the speed-map states (from the sensor and map specifications).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapTuning {
    /// Design RPM map `(slope sf0 in (m/s)/rpm, offset in m/s)` the filter starts from.
    pub design_map: (f64, f64),
    /// Initial 1-sigma of the relative scale error.
    pub scale_sigma: f64,
    /// Initial 1-sigma of the offset, m/s.
    pub offset_sigma: f64,
    /// Scale random walk, 1/sqrt(s).
    pub scale_walk: f64,
    /// Offset random walk, (m/s)/sqrt(s) (follows the map's curvature as the
    /// operating point moves).
    pub offset_walk: f64,
    /// Speed disturbance: 1-sigma (m/s) and correlation time (s).
    pub disturbance: (f64, f64),
    /// White noise of the RPM-derived forward speed per sample (RPM read-out), m/s.
    pub rpm_speed_noise: f64,
    /// 1-sigma of the unmeasured lateral and vertical body velocity, m/s.
    pub lateral_sigma: f64,
    /// 1-sigma of the DVL's scale-factor error per axis (its specification;
    /// the bias sigma comes from the log's `[sensors.dvl] bias_sigma`).
    pub dvl_scale_sigma: f64,
}

impl Default for MapTuning {
    fn default() -> Self {
        let design = super::simulation::RpmMap::NOMINAL;
        MapTuning {
            design_map: (design.slope, design.offset),
            scale_sigma: 0.05,
            offset_sigma: 0.3,
            scale_walk: 2e-6,
            offset_walk: 2e-4,
            disturbance: SPEED_DISTURBANCE,
            rpm_speed_noise: 0.012,
            lateral_sigma: 0.05,
            // +-0.2 % uniform.
            dvl_scale_sigma: super::simulation::DVL_SCALE / 3f64.sqrt(),
        }
    }
}

/// The speed-map navigator: [`NavSpeedMap`] and its slaved attitude computer.
#[derive(Clone, Debug)]
pub struct CoupledNav {
    ekf: Ekf<NavSpeedMap, 16>,
    attitude: AttitudeComputer,
    r_rpm: Matrix3<f64>,
    max_innovation: f64,
    /// Updates refused (implausible or by the filter).
    pub refused: u64,
}

impl CoupledNav {
    /// Starts at `state` with the 9-state part tuned as the other navigators
    /// (`nav`), the map states from `map` and the DVL bias states from
    /// `dvl_bias_sigma` (m/s).
    pub fn new(
        state: NavState,
        nav: &super::filter::Tuning,
        map: &MapTuning,
        dvl_bias_sigma: f64,
    ) -> Result<Self, FilterError> {
        let mut x0 = SVector::<f64, 16>::zeros();
        x0.fixed_rows_mut::<3>(3).copy_from(&state.v_n);
        x0[NavSpeedMap::SPEED_OFFSET] = map.design_map.1;
        let mut d = SVector::<f64, 16>::zeros();
        d.fixed_rows_mut::<3>(0).fill(0.1f64.powi(2));
        d.fixed_rows_mut::<3>(3).fill(0.05f64.powi(2));
        d.fixed_rows_mut::<3>(6).fill(nav.accel_bias_sigma.powi(2));
        d[NavSpeedMap::SPEED_SCALE] = map.scale_sigma.powi(2);
        d[NavSpeedMap::SPEED_OFFSET] = map.offset_sigma.powi(2);
        let (sigma_d, tau) = map.disturbance;
        d[NavSpeedMap::SPEED_DISTURBANCE] = sigma_d.powi(2);
        d[NavSpeedMap::DVL_SCALE] = map.dvl_scale_sigma.powi(2);
        d.fixed_rows_mut::<3>(NavSpeedMap::DVL_BIAS)
            .fill(dvl_bias_sigma.powi(2));
        let noise = NavSpeedMapNoise {
            accel_noise: Vector3::repeat(nav.accel_density.powi(2)),
            bias_walk: Vector3::repeat(nav.bias_walk_density.powi(2)),
            scale_walk: map.scale_walk.powi(2),
            offset_walk: map.offset_walk.powi(2),
            disturbance_drive: 2.0 * sigma_d * sigma_d / tau,
        };
        let params = NavSpeedMapParams {
            design_slope: map.design_map.0,
            tau,
        };
        let ekf = Ekf::new(x0, SMatrix::from_diagonal(&d), params, noise)?.with_default_gate(None);
        Ok(CoupledNav {
            ekf,
            attitude: AttitudeComputer::new(state),
            r_rpm: Matrix3::from_diagonal(&Vector3::new(
                map.rpm_speed_noise.powi(2),
                map.lateral_sigma.powi(2),
                map.lateral_sigma.powi(2),
            )),
            max_innovation: nav.max_innovation,
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

    /// Attitude `C_b^n` of the attitude computer.
    pub fn c_bn(&self) -> Matrix3<f64> {
        self.attitude.c_bn()
    }

    /// Horizontal position covariance `[P_NN, P_NE, P_EE]` (m^2).
    pub fn horizontal_covariance(&self) -> [f64; 3] {
        let p = self.ekf.covariance();
        [p[(0, 0)], p[(0, 1)], p[(1, 1)]]
    }

    /// The map's speed at `rpm` (m/s, without the disturbance).
    pub fn map_speed(&self, rpm: f64) -> f64 {
        let x = self.ekf.state();
        (1.0 + x[NavSpeedMap::SPEED_SCALE]) * self.ekf.params().design_slope * rpm
            + x[NavSpeedMap::SPEED_OFFSET]
    }

    /// One IMU step (as [`super::filter::AidedNav::propagate`]).
    pub fn propagate(
        &mut self,
        dtheta: &Vector3<f64>,
        dv: &Vector3<f64>,
        dt: f64,
    ) -> Result<(), FilterError> {
        let (p, v) = (self.position(), self.velocity());
        let (accel_n, c_bn) = self.attitude.step(&p, &v, dtheta, dv, dt);
        self.ekf.predict(dt, &NavSpeedMapInput { accel_n, c_bn })
    }

    /// Fuses a DVL NED velocity `v_n` with per-axis noise `sigma` (m/s).
    pub fn update_dvl(&mut self, v_n: &Vector3<f64>, sigma: f64) -> bool {
        if (v_n - self.velocity()).amax() > self.max_innovation {
            self.refused += 1;
            return false;
        }
        let r = Matrix3::identity() * sigma * sigma;
        let r = self.considering_dvl_scale(|ekf| {
            ekf.update::<NavSpeedMapDvl, 3>(v_n, &r, &())
                .map(|r| r.accepted)
        });
        self.accepted(r)
    }

    /// Fuses the RPM sample `rpm` as the body-velocity constraint.
    pub fn update_rpm(&mut self, rpm: f64) -> bool {
        let aux = NavSpeedMapRpmAux { rpm };
        let z = Vector3::zeros();
        let h = <NavSpeedMapRpm as nav_runtime::model::Sensor<16, 3>>::predict(
            self.ekf.state(),
            self.ekf.input(),
            self.ekf.params(),
            &aux,
        );
        if h.amax() > self.max_innovation {
            self.refused += 1;
            return false;
        }
        let r_rpm = self.r_rpm;
        let r = self.considering_dvl_scale(|ekf| {
            ekf.update::<NavSpeedMapRpm, 3>(&z, &r_rpm, &aux)
                .map(|r| r.accepted)
        });
        self.accepted(r)
    }

    /// Runs `update` with the DVL's forward scale error as a consider state
    /// (Schmidt): the gains of the other states account for its
    /// uncertainty, but its estimate and variance are not updated.
    fn considering_dvl_scale(
        &mut self,
        update: impl FnOnce(&mut Ekf<NavSpeedMap, 16>) -> Result<bool, FilterError>,
    ) -> Result<bool, FilterError> {
        let i = NavSpeedMap::DVL_SCALE;
        let (x_c, p_c) = (self.ekf.state()[i], self.ekf.covariance()[(i, i)]);
        let r = update(&mut self.ekf)?;
        let mut x = *self.ekf.state();
        x[i] = x_c;
        let mut p = *self.ekf.covariance();
        p[(i, i)] = p_c;
        // Restoring a larger variance keeps P positive semidefinite.
        let _ = self.ekf.set_state(x);
        let _ = self.ekf.set_covariance(p);
        Ok(r)
    }

    fn accepted(&mut self, r: Result<bool, FilterError>) -> bool {
        let ok = matches!(r, Ok(true));
        if !ok {
            self.refused += 1;
        }
        ok
    }
}
