//! A hover-capable thruster AUV in four degrees of freedom (surge, sway, heave,
//! yaw) in a constant current, and its velocity/heading/depth autopilot.
//!
//! Dynamics (Fossen, *Handbook of Marine Craft Hydrodynamics and Motion
//! Control*, 2011, ch. 6-7, decoupled low-speed form), with water-relative body
//! velocities `nu_r = [u, v, w]`, yaw rate `r`, and masses including added mass:
//!
//! ```text
//! m_u du/dt = tau_x + m_v v r - (X_u + X_uu |u|) u
//! m_v dv/dt = tau_y - m_u u r - (Y_v + Y_vv |v|) v
//! m_w dw/dt = tau_z           - (Z_w + Z_ww |w|) w
//! I_z dr/dt = tau_n           - (N_r + N_rr |r|) r
//! d/dt [x, y] = R(psi) [u, v] + v_c,  d/dt z = w,  d/dt psi = r
//! ```
//!
//! Thrust is saturated per axis. Roll and pitch are passively stable and left to
//! the caller (they stay within a few degrees on such a vehicle).

use nalgebra::{Matrix2, Vector2, Vector3};

use crate::math::wrap_angle;

/// Physical parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleParams {
    /// Surge, sway, heave masses including added mass, kg.
    pub mass: [f64; 3],
    /// Yaw inertia including added inertia, kg m^2.
    pub inertia: f64,
    /// Linear damping per axis `[X_u, Y_v, Z_w, N_r]`.
    pub linear_damping: [f64; 4],
    /// Quadratic damping per axis `[X_uu, Y_vv, Z_ww, N_rr]`.
    pub quadratic_damping: [f64; 4],
    /// Thrust limits `[X, Y, Z]` (N) and yaw moment limit (N m).
    pub max_thrust: [f64; 4],
    /// Radius of the sphere enclosing the vehicle, m (collision checks).
    pub radius: f64,
}

impl Default for VehicleParams {
    /// A compact hover-capable inspection AUV of about 120 kg: top speed about
    /// 0.55 m/s in surge, 0.3 m/s in sway and heave, 0.4 rad/s in yaw.
    fn default() -> Self {
        Self {
            mass: [180.0, 250.0, 250.0],
            inertia: 40.0,
            linear_damping: [20.0, 30.0, 30.0, 20.0],
            quadratic_damping: [150.0, 300.0, 300.0, 40.0],
            max_thrust: [60.0, 40.0, 40.0, 15.0],
            radius: 0.3,
        }
    }
}

impl VehicleParams {
    /// Damping force or moment on axis `i` at velocity `v`.
    pub fn damping(&self, i: usize, v: f64) -> f64 {
        (self.linear_damping[i] + self.quadratic_damping[i] * v.abs()) * v
    }
}

/// Generalized thrust `[tau_x, tau_y, tau_z, tau_n]`.
pub type Thrust = [f64; 4];

/// The true vehicle state.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VehicleState {
    /// NED position, m.
    pub position: Vector3<f64>,
    /// Heading, rad (unwrapped).
    pub heading: f64,
    /// Water-relative body velocity `[u, v, w]`, m/s.
    pub velocity: Vector3<f64>,
    /// Yaw rate, rad/s.
    pub yaw_rate: f64,
}

impl VehicleState {
    /// At rest at `position` with `heading`.
    pub fn at_rest(position: Vector3<f64>, heading: f64) -> Self {
        Self {
            position,
            heading,
            velocity: Vector3::zeros(),
            yaw_rate: 0.0,
        }
    }

    /// Ground velocity in NED, m/s, in `current` (NED, m/s).
    pub fn ground_velocity(&self, current: &Vector3<f64>) -> Vector3<f64> {
        let r = rot(self.heading);
        let h = r * Vector2::new(self.velocity.x, self.velocity.y);
        Vector3::new(h.x, h.y, self.velocity.z) + current
    }

    /// One explicit step of `dt` with thrust `tau` (saturated here) in `current`.
    pub fn step(&mut self, p: &VehicleParams, tau: &Thrust, current: &Vector3<f64>, dt: f64) {
        let t: [f64; 4] = core::array::from_fn(|i| tau[i].clamp(-p.max_thrust[i], p.max_thrust[i]));
        let (u, v, w, r) = (
            self.velocity.x,
            self.velocity.y,
            self.velocity.z,
            self.yaw_rate,
        );
        let du = (t[0] + p.mass[1] * v * r - p.damping(0, u)) / p.mass[0];
        let dv = (t[1] - p.mass[0] * u * r - p.damping(1, v)) / p.mass[1];
        let dw = (t[2] - p.damping(2, w)) / p.mass[2];
        let dr = (t[3] - p.damping(3, r)) / p.inertia;
        // Semi-implicit: velocities first, then positions with the new velocities.
        self.velocity += Vector3::new(du, dv, dw) * dt;
        self.yaw_rate += dr * dt;
        self.heading += self.yaw_rate * dt;
        self.position += self.ground_velocity(current) * dt;
    }
}

/// `R(psi)`: horizontal body to NED.
pub fn rot(psi: f64) -> Matrix2<f64> {
    let (s, c) = psi.sin_cos();
    Matrix2::new(c, -s, s, c)
}

/// What the autopilot tracks.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutopilotCommand {
    /// Desired horizontal ground velocity `[v_N, v_E]`, m/s.
    pub ground_velocity: Vector2<f64>,
    /// Desired heading, rad.
    pub heading: f64,
    /// Heading rate feed-forward, rad/s.
    pub heading_rate: f64,
    /// Depth reference, m.
    pub depth: f64,
    /// Vertical speed feed-forward, m/s (positive down).
    pub vertical_speed: f64,
}

/// What the autopilot knows: the navigation estimate and the current estimate.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AutopilotFeedback {
    /// Estimated heading, rad.
    pub heading: f64,
    /// Measured yaw rate (gyro), rad/s.
    pub yaw_rate: f64,
    /// Estimated depth, m.
    pub depth: f64,
    /// Estimated ground velocity in NED, m/s.
    pub ground_velocity: Vector3<f64>,
    /// Estimated water current in NED, m/s.
    pub current: Vector3<f64>,
}

/// Velocity, heading and depth loops with model feed-forward.
#[derive(Clone, Debug, PartialEq)]
pub struct Autopilot {
    /// The autopilot's model of the vehicle (may differ from the truth).
    pub model: VehicleParams,
    /// Velocity loop bandwidth, 1/s.
    pub velocity_gain: f64,
    /// Velocity integral gain, 1/s^2.
    pub integral_gain: f64,
    /// Heading loop natural frequency, rad/s (critically damped).
    pub heading_bandwidth: f64,
    /// Depth-to-vertical-speed gain, 1/s.
    pub depth_gain: f64,
    /// Largest vertical speed command, m/s.
    pub max_vertical_speed: f64,
    integral: Vector3<f64>,
}

impl Autopilot {
    /// An autopilot using `model` for feed-forward.
    pub fn new(model: VehicleParams) -> Self {
        Self {
            model,
            velocity_gain: 1.2,
            integral_gain: 0.3,
            heading_bandwidth: 1.2,
            depth_gain: 0.6,
            max_vertical_speed: 0.25,
            integral: Vector3::zeros(),
        }
    }

    /// Thrust for one control step of `dt`.
    pub fn thrust(&mut self, cmd: &AutopilotCommand, fb: &AutopilotFeedback, dt: f64) -> Thrust {
        let m = &self.model;
        let w_cmd = (cmd.vertical_speed + self.depth_gain * (cmd.depth - fb.depth))
            .clamp(-self.max_vertical_speed, self.max_vertical_speed);
        let want_ground = Vector3::new(cmd.ground_velocity.x, cmd.ground_velocity.y, w_cmd);
        // Water-relative velocity wanted, in body axes (the current feed-forward).
        let rt = rot(fb.heading).transpose();
        let water_n = want_ground - Vector3::new(fb.current.x, fb.current.y, 0.0);
        let water_h = rt * Vector2::new(water_n.x, water_n.y);
        let water_b = Vector3::new(water_h.x, water_h.y, water_n.z);
        // Ground-velocity error in body axes.
        let err_n = want_ground - fb.ground_velocity;
        let err_h = rt * Vector2::new(err_n.x, err_n.y);
        let err_b = Vector3::new(err_h.x, err_h.y, err_n.z);
        let mut tau = [0.0; 4];
        for i in 0..3 {
            let ff = m.damping(i, water_b[i]);
            let fb_term = m.mass[i] * (self.velocity_gain * err_b[i] + self.integral[i]);
            let raw = ff + fb_term;
            let limit = m.max_thrust[i];
            // Conditional integration (anti-windup).
            if raw.abs() < limit || raw.signum() != err_b[i].signum() {
                self.integral[i] += self.integral_gain * err_b[i] * dt;
            }
            tau[i] = raw.clamp(-limit, limit);
        }
        let wn = self.heading_bandwidth;
        let e_psi = wrap_angle(cmd.heading - fb.heading);
        let r_ref = cmd.heading_rate;
        let accel = wn * wn * e_psi + 2.0 * wn * (r_ref - fb.yaw_rate);
        tau[3] = (m.inertia * accel + m.damping(3, r_ref)).clamp(-m.max_thrust[3], m.max_thrust[3]);
        tau
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn top_speeds_match_thrust_and_drag() {
        let p = VehicleParams::default();
        for (axis, want) in [(0usize, 0.55), (1, 0.32), (2, 0.32)] {
            let mut s = VehicleState::at_rest(Vector3::zeros(), 0.0);
            let mut tau = [0.0; 4];
            tau[axis] = 1e3; // saturates
            for _ in 0..20_000 {
                s.step(&p, &tau, &Vector3::zeros(), 0.01);
            }
            assert!(
                (s.velocity[axis] - want).abs() < 0.03,
                "axis {axis}: {}",
                s.velocity[axis]
            );
        }
    }

    #[test]
    fn autopilot_holds_ground_velocity_in_a_current() {
        let p = VehicleParams::default();
        let mut model = p;
        model.quadratic_damping = model.quadratic_damping.map(|d| 0.8 * d);
        let mut ap = Autopilot::new(model);
        let current = Vector3::new(0.1, -0.08, 0.0);
        let mut s = VehicleState::at_rest(Vector3::new(0.0, 0.0, 15.0), 0.0);
        let cmd = AutopilotCommand {
            ground_velocity: Vector2::new(0.0, 0.3),
            heading: 1.2,
            heading_rate: 0.0,
            depth: 16.0,
            vertical_speed: 0.0,
        };
        for _ in 0..6000 {
            let fb = AutopilotFeedback {
                heading: s.heading,
                yaw_rate: s.yaw_rate,
                depth: s.position.z,
                ground_velocity: s.ground_velocity(&current),
                current,
            };
            let tau = ap.thrust(&cmd, &fb, 0.01);
            s.step(&p, &tau, &current, 0.01);
        }
        let v = s.ground_velocity(&current);
        assert!((v.x - 0.0).abs() < 0.01 && (v.y - 0.3).abs() < 0.01, "{v}");
        assert!((s.heading - 1.2).abs() < 0.01);
        assert!((s.position.z - 16.0).abs() < 0.02);
    }
}
