//! The strapdown attitude computer of an aided navigator, slaved to its filter:
//! each IMU step its position and velocity are set from the filter, it
//! integrates the increments (coning and sculling corrected) and returns the
//! compensated nav-frame acceleration
//! `a^n = C_b^n f^b - (2 w_ie^n + w_en^n) x v^n + g^n` as `delta v^n / dt`.

use nav_runtime::earth::{meridian_radius, transverse_radius, Geodetic};
use nav_runtime::nalgebra::{Matrix3, Vector3};
use nav_runtime::strapdown::{NavState, Strapdown};

/// An attitude computer slaved to a local-NED position and velocity.
#[derive(Clone, Debug)]
pub struct AttitudeComputer {
    strapdown: Strapdown,
    origin: Geodetic,
    /// Metres per radian of latitude and of longitude at the origin.
    scale: (f64, f64),
}

impl AttitudeComputer {
    /// Starts at `state`, the origin of the local NED position.
    pub fn new(state: NavState) -> Self {
        let origin = state.position();
        let scale = (
            meridian_radius(origin.lat) + origin.h,
            (transverse_radius(origin.lat) + origin.h) * origin.lat.cos(),
        );
        AttitudeComputer {
            strapdown: Strapdown::new(state),
            origin,
            scale,
        }
    }

    /// Attitude `C_b^n`.
    pub fn c_bn(&self) -> Matrix3<f64> {
        self.strapdown.state.c_bn
    }

    /// One IMU step from the filter's NED position `p` (m from the origin) and
    /// velocity `v` (m/s): returns `a^n` (m/s^2) and the mid-step `C_b^n`.
    pub fn step(
        &mut self,
        p: &Vector3<f64>,
        v: &Vector3<f64>,
        dtheta: &Vector3<f64>,
        dv: &Vector3<f64>,
        dt: f64,
    ) -> (Vector3<f64>, Matrix3<f64>) {
        let s = &mut self.strapdown.state;
        s.lat = self.origin.lat + p.x / self.scale.0;
        s.lon = self.origin.lon + p.y / self.scale.1;
        s.h = self.origin.h - p.z;
        s.v_n = *v;
        let (v0, c0) = (s.v_n, s.c_bn);
        self.strapdown.update_increments(dtheta, dv, dt);
        let accel_n = (self.strapdown.state.v_n - v0) / dt;
        (accel_n, 0.5 * (c0 + self.strapdown.state.c_bn))
    }
}
