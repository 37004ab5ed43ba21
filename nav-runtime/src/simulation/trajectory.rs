//! Kinematic 6-DOF truth generator on the WGS-84 ellipsoid.
//!
//! A trajectory is described by smooth time functions ([`Channel`]s): speed V
//! along the velocity vector, heading rate, down velocity, roll, and an optional
//! pitch offset (angle of attack). Heading is the integral of the heading rate;
//! the velocity points along the heading with flight-path angle
//! `gamma = atan2(-V_D, U)`, `U = sqrt(V^2 - V_D^2)`, and the pitch is
//! `theta = gamma + pitch_offset` (so a diving vehicle points its nose down along
//! its path and, with no offset, `v^b = [V, 0, 0]`).
//!
//! Manoeuvres are built from a C3 "smooth step" (septic polynomial, its first
//! three derivatives vanish at both ends), so rates are C3, angular accelerations
//! C2, and the body rate and specific force seen by the IMU are C2: a 100 Hz
//! strapdown with second-order algorithms reproduces the truth to millimetres.
//!
//! Outputs ([`TruthState`]) at any time: position, `v^n` and its derivative,
//! Euler angles and `C_b^n`, and the IMU quantities consistent with WGS-84 and
//! docs/models/sdins25.md, eqs. 2-3:
//! `f^b = C_n^b (vdot^n + (2 w_ie^n + w_en^n) x v^n - g^n)`,
//! `w_ib^b = w_nb^b + C_n^b (w_ie^n + w_en^n)`.
//! Latitude and longitude are integrated (eq. 1) by RK4 on a grid and
//! interpolated with cubic Hermite polynomials (the grid stores the exact
//! derivatives); height is the closed-form integral of `-V_D`.

use crate::attitude::{body_rate_from_euler_rates, Euler};
use crate::earth::{
    earth_rate_n, meridian_radius, normal_gravity_ned, transport_rate_n, transverse_radius,
    Geodetic,
};
use crate::strapdown::NavState;
use nalgebra::{Matrix3, Vector3};

/// `S(s) = 35 s^4 - 84 s^5 + 70 s^6 - 20 s^7` on [0, 1] (0 before, 1 after):
/// value, derivative `S'(s) = 140 s^3 (1-s)^3`, and integral from 0 to s.
fn smooth_step(s: f64) -> (f64, f64, f64) {
    if s <= 0.0 {
        (0.0, 0.0, 0.0)
    } else if s >= 1.0 {
        (1.0, 0.0, 0.5 + (s - 1.0))
    } else {
        let s2 = s * s;
        let s3 = s2 * s;
        let s4 = s2 * s2;
        let v = s4 * (35.0 - 84.0 * s + 70.0 * s2 - 20.0 * s3);
        let d = 140.0 * s3 * (1.0 - s).powi(3);
        let i = s4 * s * (7.0 - 14.0 * s + 10.0 * s2 - 2.5 * s3);
        (v, d, i)
    }
}

/// One additive term of a [`Channel`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Term {
    /// A C3 smooth step of height `delta` from `t0` to `t0 + duration` (s).
    Step {
        /// Start time (s).
        t0: f64,
        /// Duration of the transition (s), > 0.
        duration: f64,
        /// Change of the channel value (channel units).
        delta: f64,
    },
    /// `amp sin(omega t + phase)` for all t (channel units; omega in rad/s).
    Sine {
        /// Amplitude (channel units).
        amp: f64,
        /// Angular frequency (rad/s), nonzero.
        omega: f64,
        /// Phase (rad).
        phase: f64,
    },
}

impl Term {
    /// (value, time derivative, antiderivative) at t; the antiderivative's
    /// constant is arbitrary (only differences are used).
    fn eval(&self, t: f64) -> (f64, f64, f64) {
        match *self {
            Term::Step {
                t0,
                duration,
                delta,
            } => {
                if t <= t0 {
                    // Not started (what `smooth_step` gives, without the division).
                    return (0.0, 0.0, 0.0);
                }
                let (v, d, i) = smooth_step((t - t0) / duration);
                (delta * v, delta * d / duration, delta * duration * i)
            }
            Term::Sine { amp, omega, phase } => {
                let a = omega * t + phase;
                (amp * a.sin(), amp * omega * a.cos(), -amp / omega * a.cos())
            }
        }
    }
}

/// A smooth scalar function of time: an initial value plus [`Term`]s.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Channel {
    /// Value before any step (channel units).
    pub initial: f64,
    /// Additive terms.
    pub terms: Vec<Term>,
}

impl Channel {
    /// A constant channel.
    pub fn constant(value: f64) -> Self {
        Self {
            initial: value,
            terms: Vec::new(),
        }
    }
    /// Adds a smooth step of `delta` over `[t0, t0 + duration]`.
    pub fn add_step(&mut self, t0: f64, duration: f64, delta: f64) -> &mut Self {
        assert!(duration > 0.0, "step duration must be positive");
        self.terms.push(Term::Step {
            t0,
            duration,
            delta,
        });
        self
    }
    /// Adds a trapezoidal pulse with smooth corners: ramps from 0 to `peak` over
    /// `ramp` s starting at `t0`, holds for `hold` s, ramps back over `ramp` s.
    /// Its time integral is `peak (ramp + hold)`. Returns the end time (s).
    pub fn add_pulse(&mut self, t0: f64, ramp: f64, hold: f64, peak: f64) -> f64 {
        self.add_step(t0, ramp, peak);
        self.add_step(t0 + ramp + hold, ramp, -peak);
        t0 + 2.0 * ramp + hold
    }
    /// Adds `amp sin(omega t + phase)`.
    pub fn add_sine(&mut self, amp: f64, omega: f64, phase: f64) -> &mut Self {
        assert!(omega != 0.0, "sine frequency must be nonzero");
        self.terms.push(Term::Sine { amp, omega, phase });
        self
    }
    /// Value at `t` (s).
    pub fn value(&self, t: f64) -> f64 {
        self.initial + self.terms.iter().map(|x| x.eval(t).0).sum::<f64>()
    }
    /// Time derivative at `t` (channel units per s).
    pub fn rate(&self, t: f64) -> f64 {
        self.terms.iter().map(|x| x.eval(t).1).sum()
    }
    /// `(value, rate, integral)` at `t` in one pass over the terms: the same
    /// sums as [`Channel::value`], [`Channel::rate`], [`Channel::integral`]
    /// for a third of the work.
    pub fn evaluate(&self, t: f64) -> (f64, f64, f64) {
        let (mut value, mut rate, mut integral) = (0.0, 0.0, 0.0);
        for term in &self.terms {
            let (v, d, i) = term.eval(t);
            value += v;
            rate += d;
            integral += i - term.eval(0.0).2;
        }
        (self.initial + value, rate, self.initial * t + integral)
    }
    /// Integral from 0 to `t` (channel units times s).
    pub fn integral(&self, t: f64) -> f64 {
        self.initial * t
            + self
                .terms
                .iter()
                .map(|x| x.eval(t).2 - x.eval(0.0).2)
                .sum::<f64>()
    }
}

/// Limits used to turn heading and depth commands into smooth pulses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ManeuverLimits {
    /// Maximum heading rate (rad/s).
    pub max_turn_rate: f64,
    /// Time to ramp the heading rate up or down (s).
    pub turn_ramp: f64,
    /// Maximum down (or up) velocity (m/s); with speed V the flight-path angle is
    /// at most `asin(max_down_velocity / V)`.
    pub max_down_velocity: f64,
    /// Time to ramp the down velocity up or down (s).
    pub dive_ramp: f64,
}

impl Default for ManeuverLimits {
    /// 6 deg/s turns with 3 s ramps, 0.25 m/s dives with 4 s ramps (about 9.6 deg
    /// of pitch at 1.5 m/s): a 90 deg turn takes 18 s, a 5 m depth change 28 s.
    fn default() -> Self {
        Self {
            max_turn_rate: 6f64.to_radians(),
            turn_ramp: 3.0,
            max_down_velocity: 0.25,
            dive_ramp: 4.0,
        }
    }
}

/// Commanded motion: start point and the time functions of the trajectory.
#[derive(Clone, Debug, PartialEq)]
pub struct TrajectorySpec {
    /// Start position.
    pub start: Geodetic,
    /// Heading at t = 0 (rad).
    pub heading0: f64,
    /// Speed V along the velocity vector (m/s), >= |V_D|.
    pub speed: Channel,
    /// Heading rate psidot (rad/s); heading = heading0 + its integral.
    pub heading_rate: Channel,
    /// Down velocity V_D (m/s); height = h0 - its integral.
    pub down_velocity: Channel,
    /// Roll phi (rad).
    pub roll: Channel,
    /// Pitch minus flight-path angle (rad), e.g. trim or angle of attack.
    pub pitch_offset: Channel,
    /// Limits used by [`TrajectorySpec::turn`] and [`TrajectorySpec::change_depth`].
    pub limits: ManeuverLimits,
}

impl TrajectorySpec {
    /// Constant speed (m/s), constant heading (rad), level, from `start`.
    pub fn new(start: Geodetic, heading0: f64, speed: f64) -> Self {
        Self {
            start,
            heading0,
            speed: Channel::constant(speed),
            heading_rate: Channel::default(),
            down_velocity: Channel::default(),
            roll: Channel::default(),
            pitch_offset: Channel::default(),
            limits: ManeuverLimits::default(),
        }
    }

    /// Commands a heading change of `delta` (rad, positive clockwise seen from
    /// above) starting at `t0` (s): a heading-rate pulse at most
    /// `limits.max_turn_rate`, with smooth ramps. Returns the end time (s).
    pub fn turn(&mut self, t0: f64, delta: f64) -> f64 {
        let l = self.limits;
        pulse_for(
            &mut self.heading_rate,
            t0,
            delta,
            l.max_turn_rate,
            l.turn_ramp,
        )
    }

    /// Commands a depth change of `delta` (m, positive deeper) starting at `t0`
    /// (s): a down-velocity pulse at most `limits.max_down_velocity`. Returns the
    /// end time (s).
    pub fn change_depth(&mut self, t0: f64, delta: f64) -> f64 {
        let l = self.limits;
        pulse_for(
            &mut self.down_velocity,
            t0,
            delta,
            l.max_down_velocity,
            l.dive_ramp,
        )
    }

    /// Commands a speed change of `delta` (m/s) over `[t0, t0 + duration]`.
    pub fn change_speed(&mut self, t0: f64, duration: f64, delta: f64) {
        self.speed.add_step(t0, duration, delta);
    }

    /// Builds the trajectory for `[0, duration]` s (position grid 0.05 s).
    pub fn build(self, duration: f64) -> Trajectory {
        Trajectory::new(self, duration, 0.05)
    }
}

/// A pulse whose integral is `delta` with peak at most `max_rate`.
fn pulse_for(ch: &mut Channel, t0: f64, delta: f64, max_rate: f64, ramp: f64) -> f64 {
    if delta == 0.0 {
        return t0;
    }
    let mag = delta.abs();
    let (peak, hold) = if mag >= max_rate * ramp {
        (max_rate, mag / max_rate - ramp)
    } else {
        (mag / ramp, 0.0)
    };
    ch.add_pulse(t0, ramp, hold, peak * delta.signum())
}

/// Truth at one instant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TruthState {
    /// Time (s).
    pub t: f64,
    /// Latitude (rad).
    pub lat: f64,
    /// Longitude (rad).
    pub lon: f64,
    /// Height (m, positive up).
    pub h: f64,
    /// NED velocity (m/s).
    pub v_n: Vector3<f64>,
    /// NED acceleration relative to the Earth, `dv^n/dt` (m/s^2).
    pub a_n: Vector3<f64>,
    /// Euler angles (rad).
    pub euler: Euler,
    /// Euler angle rates (rad/s).
    pub euler_rates: Euler,
    /// `C_b^n`.
    pub c_bn: Matrix3<f64>,
    /// Body rate relative to n, `w_nb^b` (rad/s).
    pub w_nb_b: Vector3<f64>,
    /// Body rate relative to inertial space, `w_ib^b` (rad/s): what gyros measure.
    pub w_ib_b: Vector3<f64>,
    /// Specific force `f^b` (m/s^2): what accelerometers measure.
    pub f_b: Vector3<f64>,
}

impl TruthState {
    /// As a navigation state (for initializing or comparing a strapdown).
    pub fn nav_state(&self) -> NavState {
        NavState {
            lat: self.lat,
            lon: self.lon,
            h: self.h,
            v_n: self.v_n,
            c_bn: self.c_bn,
        }
    }
    /// Position.
    pub fn position(&self) -> Geodetic {
        Geodetic::new(self.lat, self.lon, self.h)
    }
    /// Depth (m, positive down).
    pub fn depth(&self) -> f64 {
        -self.h
    }
    /// Velocity in body axes `v^b = C_n^b v^n` (m/s), what a DVL measures.
    pub fn v_body(&self) -> Vector3<f64> {
        self.c_bn.transpose() * self.v_n
    }
}

/// Anything that gives the truth at a time: IMU and sensor synthesis take it.
pub trait TruthSource {
    /// Truth at `t` (s).
    fn truth(&self, t: f64) -> TruthState;
    /// Last valid time (s); valid times are `[0, duration]`.
    fn duration(&self) -> f64;
}

/// Velocity, attitude and height part of the kinematics at time t.
struct Kin {
    v_n: Vector3<f64>,
    a_n: Vector3<f64>,
    euler: Euler,
    euler_rates: Euler,
    h: f64,
}

/// A built trajectory: the spec plus the integrated latitude/longitude grid.
#[derive(Clone, Debug)]
pub struct Trajectory {
    spec: TrajectorySpec,
    duration: f64,
    node_dt: f64,
    /// (lat, lon, latdot, londot) at `k node_dt`.
    nodes: Vec<[f64; 4]>,
}

impl Trajectory {
    /// Integrates the position over `[0, duration]` (s) with RK4 at `node_dt` (s).
    pub fn new(spec: TrajectorySpec, duration: f64, node_dt: f64) -> Self {
        assert!(duration > 0.0 && node_dt > 0.0);
        let n = (duration / node_dt).ceil() as usize + 1;
        let mut me = Self {
            spec,
            duration,
            node_dt,
            nodes: Vec::with_capacity(n + 1),
        };
        let mut y = [me.spec.start.lat, me.spec.start.lon];
        // Latitude and longitude rates from the kinematics at a time (which
        // do not depend on the position) and a position.
        let f = |k: &Kin, y: &[f64; 2]| -> [f64; 2] {
            let rm = meridian_radius(y[0]) + k.h;
            let rn = transverse_radius(y[0]) + k.h;
            [k.v_n[0] / rm, k.v_n[1] / (rn * y[0].cos())]
        };
        for i in 0..=n {
            let t = i as f64 * node_dt;
            let d = f(&me.kinematics(t), &y);
            me.nodes.push([y[0], y[1], d[0], d[1]]);
            let h = node_dt;
            // RK4's two midpoint stages share the kinematics at t + h/2.
            let mid = me.kinematics(t + h / 2.0);
            let k1 = d;
            let k2 = f(&mid, &[y[0] + h / 2.0 * k1[0], y[1] + h / 2.0 * k1[1]]);
            let k3 = f(&mid, &[y[0] + h / 2.0 * k2[0], y[1] + h / 2.0 * k2[1]]);
            let k4 = f(&me.kinematics(t + h), &[y[0] + h * k3[0], y[1] + h * k3[1]]);
            for j in 0..2 {
                y[j] += h / 6.0 * (k1[j] + 2.0 * k2[j] + 2.0 * k3[j] + k4[j]);
            }
        }
        me
    }

    /// The spec this trajectory was built from.
    pub fn spec(&self) -> &TrajectorySpec {
        &self.spec
    }

    fn kinematics(&self, t: f64) -> Kin {
        let s = &self.spec;
        let (v, vdot, _) = s.speed.evaluate(t);
        let (vd, vddot, dive) = s.down_velocity.evaluate(t);
        let (psidot, _, turned) = s.heading_rate.evaluate(t);
        let psi = s.heading0 + turned;
        assert!(v >= vd.abs(), "speed {v} below |V_D| {vd} at t = {t}");
        let u = (v * v - vd * vd).max(0.0).sqrt();
        let udot = if u > 0.0 {
            (v * vdot - vd * vddot) / u
        } else {
            0.0
        };
        // gamma = atan2(-V_D, U); d gamma/dt = (-U Vdot_D + V_D Udot) / V^2.
        let (gamma, gammadot) = if v > 0.0 {
            ((-vd).atan2(u), (-u * vddot + vd * udot) / (v * v))
        } else {
            (0.0, 0.0)
        };
        let (roll, roll_rate, _) = s.roll.evaluate(t);
        let (pitch_offset, pitch_offset_rate, _) = s.pitch_offset.evaluate(t);
        let euler = Euler::new(roll, gamma + pitch_offset, psi);
        let euler_rates = Euler::new(roll_rate, gammadot + pitch_offset_rate, psidot);
        let (sp, cp) = psi.sin_cos();
        let v_n = Vector3::new(u * cp, u * sp, vd);
        let a_n = Vector3::new(
            udot * cp - u * sp * psidot,
            udot * sp + u * cp * psidot,
            vddot,
        );
        let h = s.start.h - dive;
        Kin {
            v_n,
            a_n,
            euler,
            euler_rates,
            h,
        }
    }

    /// Latitude and longitude at `t` by cubic Hermite interpolation of the grid.
    fn lat_lon(&self, t: f64) -> (f64, f64) {
        let x = (t / self.node_dt).max(0.0);
        let i = (x.floor() as usize).min(self.nodes.len() - 2);
        let s = x - i as f64;
        let (a, b) = (&self.nodes[i], &self.nodes[i + 1]);
        let h = self.node_dt;
        let (s2, s3) = (s * s, s * s * s);
        let h00 = 2.0 * s3 - 3.0 * s2 + 1.0;
        let h10 = s3 - 2.0 * s2 + s;
        let h01 = -2.0 * s3 + 3.0 * s2;
        let h11 = s3 - s2;
        let lat = h00 * a[0] + h10 * h * a[2] + h01 * b[0] + h11 * h * b[2];
        let lon = h00 * a[1] + h10 * h * a[3] + h01 * b[1] + h11 * h * b[3];
        (lat, lon)
    }
}

impl TruthSource for Trajectory {
    fn truth(&self, t: f64) -> TruthState {
        assert!(
            t >= -1e-9 && t <= self.duration + 1e-9,
            "t = {t} outside [0, {}]",
            self.duration
        );
        let k = self.kinematics(t);
        let (lat, lon) = self.lat_lon(t);
        let c_bn = k.euler.c_bn();
        let c_nb = c_bn.transpose();
        let w_ie = earth_rate_n(lat);
        let w_en = transport_rate_n(lat, k.h, &k.v_n);
        let w_nb_b = body_rate_from_euler_rates(&k.euler, &k.euler_rates);
        let w_ib_b = w_nb_b + c_nb * (w_ie + w_en);
        let g = normal_gravity_ned(lat, k.h);
        let f_b = c_nb * (k.a_n + (2.0 * w_ie + w_en).cross(&k.v_n) - g);
        TruthState {
            t,
            lat,
            lon,
            h: k.h,
            v_n: k.v_n,
            a_n: k.a_n,
            euler: k.euler,
            euler_rates: k.euler_rates,
            c_bn,
            w_nb_b,
            w_ib_b,
            f_b,
        }
    }
    fn duration(&self) -> f64 {
        self.duration
    }
}

/// Scenario presets.
pub mod scenarios {
    use super::*;

    /// SDINS-25 start point (Table 2): 36 deg 23' 38.52" N, 127 deg 21' 43.56" E,
    /// at `depth` m.
    pub fn sdins25_start(depth: f64) -> Geodetic {
        Geodetic::from_degrees(
            36.0 + 23.0 / 60.0 + 38.52 / 3600.0,
            127.0 + 21.0 / 60.0 + 43.56 / 3600.0,
            -depth,
        )
    }

    /// SDINS-25 lawn-mowing survey (docs/models/sdins25.md, Table 2): heading north, level, at
    /// 1.5 m/s (the project's canonical speed; the paper gives none), starting at
    /// 10 m depth (the paper gives none), with the commanded depth and heading
    /// increments at 30, 100, 120, 150, 220, 240, 270, 340, 360, 390, 460, 480 s.
    /// Default [`ManeuverLimits`]: every 90 deg turn ends within 18 s, before the
    /// next command. Build for 500 s.
    pub fn sdins25_lawn_mower() -> TrajectorySpec {
        let mut s = TrajectorySpec::new(sdins25_start(10.0), 0.0, 1.5);
        let d = 90f64.to_radians();
        for (t, dd) in [(30.0, 5.0), (150.0, -5.0), (270.0, 5.0), (390.0, -5.0)] {
            s.change_depth(t, dd);
        }
        for (t, dpsi) in [
            (100.0, d),
            (120.0, d),
            (220.0, -d),
            (240.0, -d),
            (340.0, d),
            (360.0, d),
            (460.0, -d),
            (480.0, -d),
        ] {
            s.turn(t, dpsi);
        }
        s
    }

    /// A straight, level track at `speed` m/s and `heading` rad (leveling,
    /// straight case).
    pub fn straight(start: Geodetic, heading: f64, speed: f64) -> TrajectorySpec {
        TrajectorySpec::new(start, heading, speed)
    }

    /// An S-type (weaving) track: heading rate `amp sin(2 pi t / period)` (rad/s),
    /// so the heading swings by +-amp period / pi about `heading`, at `speed` m/s.
    pub fn s_type(
        start: Geodetic,
        heading: f64,
        speed: f64,
        amp: f64,
        period: f64,
    ) -> TrajectorySpec {
        let mut s = TrajectorySpec::new(start, heading, speed);
        s.heading_rate
            .add_sine(amp, 2.0 * core::f64::consts::PI / period, 0.0);
        s
    }

    /// The VKF run: 10 knots (5.144 m/s) from rest-free cruise for 27 min
    /// (1620 s), level, heading `heading` rad, with two gentle 30 deg course
    /// changes at 600 s and 1100 s.
    pub fn vkf_run(start: Geodetic, heading: f64) -> TrajectorySpec {
        let mut s = TrajectorySpec::new(start, heading, 10.0 * 1852.0 / 3600.0);
        s.limits.max_turn_rate = 1f64.to_radians();
        s.limits.turn_ramp = 5.0;
        s.turn(600.0, 30f64.to_radians());
        s.turn(1100.0, -30f64.to_radians());
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::skew;

    #[test]
    fn smooth_step_derivative_and_integral() {
        for i in 0..=40 {
            let s = i as f64 / 40.0 * 1.2 - 0.1;
            let d = 1e-6;
            let (v, dv, iv) = smooth_step(s);
            let fd = (smooth_step(s + d).0 - smooth_step(s - d).0) / (2.0 * d);
            assert!((dv - fd).abs() < 1e-8, "{s}");
            let fi = (smooth_step(s + d).2 - smooth_step(s - d).2) / (2.0 * d);
            assert!((v - fi).abs() < 1e-8, "{s}");
            let _ = iv;
        }
        assert_eq!(smooth_step(1.0).2, 0.5);
    }

    #[test]
    fn channel_pulse_integral() {
        let mut c = Channel::default();
        let end = c.add_pulse(10.0, 3.0, 12.0, 0.1);
        assert_eq!(end, 28.0);
        assert!((c.integral(end) - 1.5).abs() < 1e-12);
        assert!((c.integral(40.0) - 1.5).abs() < 1e-12);
        c.add_sine(0.2, 0.5, 0.3);
        let t = 17.3;
        let d = 1e-5;
        assert!(((c.integral(t + d) - c.integral(t - d)) / (2.0 * d) - c.value(t)).abs() < 1e-8);
        assert!(((c.value(t + d) - c.value(t - d)) / (2.0 * d) - c.rate(t)).abs() < 1e-8);
        // One pass gives the three sums bit for bit.
        for t in [0.0, 5.0, 11.5, 17.3, 27.9, 40.0] {
            assert_eq!(
                c.evaluate(t),
                (c.value(t), c.rate(t), c.integral(t)),
                "at {t}"
            );
        }
    }

    #[test]
    fn lawn_mower_reaches_commanded_headings_and_depths() {
        let tr = scenarios::sdins25_lawn_mower().build(500.0);
        let deg = |t: f64| crate::math::wrap_angle(tr.truth(t).euler.yaw).to_degrees();
        assert!(deg(99.0).abs() < 1e-9);
        assert!((deg(119.0) - 90.0).abs() < 1e-9);
        assert!((deg(140.0).abs() - 180.0).abs() < 1e-9);
        assert!(deg(260.0).abs() < 1e-9);
        assert!((tr.truth(99.0).depth() - 15.0).abs() < 1e-9);
        assert!((tr.truth(200.0).depth() - 10.0).abs() < 1e-9);
        let t = tr.truth(40.0);
        assert!((t.v_n.norm() - 1.5).abs() < 1e-12);
        assert!(t.euler.pitch < -0.1, "diving nose down: {}", t.euler.pitch);
        // DVL would see [V, 0, 0].
        assert!((t.v_body() - Vector3::new(1.5, 0.0, 0.0)).norm() < 1e-12);
    }

    #[test]
    fn truth_is_self_consistent() {
        // Derivatives of the truth match its own rates (finite differences), and
        // the specific force / body rate satisfy docs/models/sdins25.md, eqs. 2-3.
        let mut spec = scenarios::sdins25_lawn_mower();
        spec.roll.add_sine(0.05, 0.7, 0.0);
        let tr = spec.build(200.0);
        for t in [5.0, 33.0, 41.7, 104.0, 127.3, 152.2] {
            let d = 1e-3;
            let (a, b, x) = (tr.truth(t - d), tr.truth(t + d), tr.truth(t));
            let latdot = (b.lat - a.lat) / (2.0 * d);
            let londot = (b.lon - a.lon) / (2.0 * d);
            let pr = crate::earth::position_rates(x.lat, x.h, &x.v_n);
            assert!(
                (latdot - pr[0]).abs() < 1e-12 && (londot - pr[1]).abs() < 1e-12,
                "{t}"
            );
            assert!(((b.h - a.h) / (2.0 * d) - pr[2]).abs() < 1e-6);
            assert!(((b.v_n - a.v_n) / (2.0 * d) - x.a_n).norm() < 1e-7, "{t}");
            // Cdot_b^n = C_b^n [w_ib^b x] - [w_in^n x] C_b^n (eq. 3).
            let w_in = earth_rate_n(x.lat) + transport_rate_n(x.lat, x.h, &x.v_n);
            let cdot = (b.c_bn - a.c_bn) / (2.0 * d);
            assert!(
                (cdot - (x.c_bn * skew(&x.w_ib_b) - skew(&w_in) * x.c_bn)).norm() < 1e-7,
                "{t}"
            );
            // vdot = C_b^n f^b - (2 w_ie + w_en) x v + g (eq. 2).
            let w_ie = earth_rate_n(x.lat);
            let w_en = transport_rate_n(x.lat, x.h, &x.v_n);
            let vdot =
                x.c_bn * x.f_b - (2.0 * w_ie + w_en).cross(&x.v_n) + normal_gravity_ned(x.lat, x.h);
            assert!((vdot - x.a_n).norm() < 1e-12);
        }
    }
}
