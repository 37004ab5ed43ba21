//! IMU synthesis from a truth trajectory, and the IMU error model.
//!
//! Synthesis produces what an integrating IMU outputs: over each sample
//! interval `[t_{k-1}, t_k]` the body-frame integrals `dtheta = int w_ib^b dt`
//! (rad) and `dv = int f^b dt` (m/s), computed with 4-point Gauss-Legendre
//! quadrature on sub-intervals (exact for polynomials of degree 7: the result is
//! exact to round-off inside manoeuvres and within about 1e-13 rad, 1e-12 m/s on
//! the samples that straddle a ramp boundary of [`crate::trajectory`], where the
//! fourth derivative of the motion jumps). Because they
//! are plain integrals of body rates, the increments contain the genuine coning
//! and sculling effects that the strapdown's corrections must remove. Rates at
//! the sample instants are also available (the imu.csv convention).
//!
//! Error model (per axis, independent): a constant bias drawn once per run,
//! an optional constant scale-factor error drawn once per run, and white noise
//! drawn per sample, all from a seeded ChaCha generator, so a run is
//! reproducible. Noise figures follow docs/models/conventions.md, item 8: "1-sigma per sample at the
//! sensor's rate": a rate sample gets `N(0, sigma)` added, an increment gets
//! `N(0, sigma) dt` (so that increment / dt has the tabulated sigma).
//!
//! Units: SI in all fields (m/s^2, rad/s); [`ImuSpec::from_table`] takes the
//! datasheet units of docs/models/sdins25.md, Table 1 (mg, ug, deg/h).

use crate::sensors::normal;
use crate::trajectory::TruthSource;
use nalgebra::Vector3;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

/// 1 mg in m/s^2 (standard gravity g0 = 9.80665 m/s^2).
pub const MG: f64 = 1e-3 * crate::earth::G0;
/// 1 ug in m/s^2.
pub const UG: f64 = 1e-6 * crate::earth::G0;
/// 1 deg/h in rad/s.
pub const DEG_PER_HOUR: f64 = core::f64::consts::PI / 180.0 / 3600.0;
/// 1 ppm (scale factor) as a fraction.
pub const PPM: f64 = 1e-6;

/// One IMU output as increments over `[t - dt, t]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuIncrement {
    /// End of the interval (s).
    pub t: f64,
    /// Interval length (s).
    pub dt: f64,
    /// Angle increment `int w_ib^b dt` (rad).
    pub dtheta: Vector3<f64>,
    /// Velocity increment `int f^b dt` (m/s).
    pub dv: Vector3<f64>,
}

/// One IMU output as rates sampled at `t`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImuRate {
    /// Sample time (s).
    pub t: f64,
    /// Body rate `w_ib^b` (rad/s).
    pub w_ib_b: Vector3<f64>,
    /// Specific force `f^b` (m/s^2).
    pub f_b: Vector3<f64>,
}

/// The log row of a rate sample (`imu.csv`, rates form).
#[cfg(feature = "log")]
impl From<&ImuRate> for crate::log::ImuRow {
    fn from(r: &ImuRate) -> Self {
        let (w, f) = (r.w_ib_b, r.f_b);
        Self::new(r.t, w.x, w.y, w.z, f.x, f.y, f.z)
    }
}

/// 4-point Gauss-Legendre nodes on [-1, 1] and weights.
const GL4: [(f64, f64); 4] = [
    (-0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
    (-0.339_981_043_584_856_26, 0.652_145_154_862_546_2),
    (0.339_981_043_584_856_26, 0.652_145_154_862_546_2),
    (0.861_136_311_594_052_6, 0.347_854_845_137_453_85),
];

/// Exact increments over `[t0, t1]` (s): `(int w_ib^b dt, int f^b dt)` (rad, m/s),
/// by 4-point Gauss-Legendre on `n_sub` equal sub-intervals.
pub fn exact_increment<T: TruthSource + ?Sized>(
    truth: &T,
    t0: f64,
    t1: f64,
    n_sub: usize,
) -> (Vector3<f64>, Vector3<f64>) {
    let n = n_sub.max(1);
    let h = (t1 - t0) / n as f64;
    let mut dth = Vector3::zeros();
    let mut dv = Vector3::zeros();
    for j in 0..n {
        let mid = t0 + (j as f64 + 0.5) * h;
        for (x, w) in GL4 {
            let s = truth.truth(mid + 0.5 * h * x);
            dth += s.w_ib_b * (0.5 * h * w);
            dv += s.f_b * (0.5 * h * w);
        }
    }
    (dth, dv)
}

/// Error-free increments at `rate_hz` from `t = 0` to `t_end` (s): samples
/// `k = 1..=floor(t_end rate_hz)`, each over `[(k-1)/rate, k/rate]`, two
/// Gauss-Legendre sub-intervals each.
pub fn increments<T: TruthSource + ?Sized>(
    truth: &T,
    rate_hz: f64,
    t_end: f64,
) -> impl Iterator<Item = ImuIncrement> + '_ {
    let dt = 1.0 / rate_hz;
    let n = (t_end * rate_hz + 1e-9).floor() as usize;
    (1..=n).map(move |k| {
        let (t0, t1) = ((k - 1) as f64 * dt, k as f64 * dt);
        let (dtheta, dv) = exact_increment(truth, t0, t1, 2);
        ImuIncrement {
            t: t1,
            dt,
            dtheta,
            dv,
        }
    })
}

/// Error-free rate samples at `t = k / rate_hz`, `k = 0..=floor(t_end rate_hz)`.
pub fn rates<T: TruthSource + ?Sized>(
    truth: &T,
    rate_hz: f64,
    t_end: f64,
) -> impl Iterator<Item = ImuRate> + '_ {
    let n = (t_end * rate_hz + 1e-9).floor() as usize;
    (0..=n).map(move |k| {
        let t = k as f64 / rate_hz;
        let s = truth.truth(t);
        ImuRate {
            t,
            w_ib_b: s.w_ib_b,
            f_b: s.f_b,
        }
    })
}

/// IMU error specification, 1-sigma per axis, SI units.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuSpec {
    /// Accelerometer bias, drawn once per run (m/s^2).
    pub accel_bias: f64,
    /// Accelerometer white noise per sample (m/s^2).
    pub accel_noise: f64,
    /// Gyro bias, drawn once per run (rad/s).
    pub gyro_bias: f64,
    /// Gyro white noise per sample (rad/s).
    pub gyro_noise: f64,
    /// Accelerometer scale-factor error, drawn once per run (fraction).
    pub accel_scale: f64,
    /// Gyro scale-factor error, drawn once per run (fraction).
    pub gyro_scale: f64,
}

impl ImuSpec {
    /// No errors.
    pub const IDEAL: ImuSpec = ImuSpec {
        accel_bias: 0.0,
        accel_noise: 0.0,
        gyro_bias: 0.0,
        gyro_noise: 0.0,
        accel_scale: 0.0,
        gyro_scale: 0.0,
    };

    /// From datasheet units (docs/models/sdins25.md, Table 1 style): accelerometer bias (mg) and
    /// noise (ug), gyro bias and noise (deg/h); no scale-factor error.
    pub fn from_table(
        accel_bias_mg: f64,
        accel_noise_ug: f64,
        gyro_bias_deg_h: f64,
        gyro_noise_deg_h: f64,
    ) -> Self {
        ImuSpec {
            accel_bias: accel_bias_mg * MG,
            accel_noise: accel_noise_ug * UG,
            gyro_bias: gyro_bias_deg_h * DEG_PER_HOUR,
            gyro_noise: gyro_noise_deg_h * DEG_PER_HOUR,
            accel_scale: 0.0,
            gyro_scale: 0.0,
        }
    }

    /// SDINS-25 Table 1: 1 mg / 100 ug, 1 deg/h / 0.3 deg/h.
    pub fn sdins25() -> Self {
        Self::from_table(1.0, 100.0, 1.0, 0.3)
    }

    /// LEVELING-6 Table 1: 1 mg / 50 ug, 1 deg/h / 0.3 deg/h.
    pub fn leveling6() -> Self {
        Self::from_table(1.0, 50.0, 1.0, 0.3)
    }

    /// With scale-factor errors (ppm, 1-sigma).
    pub fn with_scale_ppm(mut self, accel_ppm: f64, gyro_ppm: f64) -> Self {
        self.accel_scale = accel_ppm * PPM;
        self.gyro_scale = gyro_ppm * PPM;
        self
    }
}

/// One run's constant IMU errors (per body axis, SI units).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ImuErrors {
    /// Accelerometer bias (m/s^2).
    pub accel_bias: Vector3<f64>,
    /// Gyro bias (rad/s).
    pub gyro_bias: Vector3<f64>,
    /// Accelerometer scale-factor error (fraction): output `(1 + s) f`.
    pub accel_scale: Vector3<f64>,
    /// Gyro scale-factor error (fraction).
    pub gyro_scale: Vector3<f64>,
}

/// A seeded IMU error source: constant errors of one run plus per-sample noise.
#[derive(Clone, Debug)]
pub struct ImuModel {
    /// The specification.
    pub spec: ImuSpec,
    /// This run's constant errors.
    pub errors: ImuErrors,
    rng: ChaCha8Rng,
}

impl ImuModel {
    /// Draws the constant errors from `spec` with a generator seeded by `seed`
    /// (order: accelerometer bias, gyro bias, accelerometer scale, gyro scale,
    /// x-y-z each), then the same generator supplies the noise.
    pub fn new(spec: ImuSpec, seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut v = |s: f64| {
            Vector3::new(
                normal(&mut rng, s),
                normal(&mut rng, s),
                normal(&mut rng, s),
            )
        };
        let errors = ImuErrors {
            accel_bias: v(spec.accel_bias),
            gyro_bias: v(spec.gyro_bias),
            accel_scale: v(spec.accel_scale),
            gyro_scale: v(spec.gyro_scale),
        };
        Self { spec, errors, rng }
    }

    /// Given constant errors (e.g. a fixed 1 mg bias for an analytic test); the
    /// noise comes from `spec` and `seed`.
    pub fn with_errors(spec: ImuSpec, errors: ImuErrors, seed: u64) -> Self {
        Self {
            spec,
            errors,
            rng: ChaCha8Rng::seed_from_u64(seed),
        }
    }

    fn noise(&mut self, sigma: f64) -> Vector3<f64> {
        Vector3::new(
            normal(&mut self.rng, sigma),
            normal(&mut self.rng, sigma),
            normal(&mut self.rng, sigma),
        )
    }

    /// Measured increments: `dtheta (1 + s_g) + (b_g + n_g) dt`, `dv (1 + s_a) + (b_a + n_a) dt`,
    /// `n ~ N(0, sigma)` per axis per sample.
    pub fn corrupt_increment(&mut self, x: &ImuIncrement) -> ImuIncrement {
        let e = self.errors;
        let (sg, sa) = (self.spec.gyro_noise, self.spec.accel_noise);
        let ng = self.noise(sg);
        let na = self.noise(sa);
        ImuIncrement {
            t: x.t,
            dt: x.dt,
            dtheta: x.dtheta + x.dtheta.component_mul(&e.gyro_scale) + (e.gyro_bias + ng) * x.dt,
            dv: x.dv + x.dv.component_mul(&e.accel_scale) + (e.accel_bias + na) * x.dt,
        }
    }

    /// Measured rates: `w (1 + s_g) + b_g + n_g`, `f (1 + s_a) + b_a + n_a`.
    pub fn corrupt_rate(&mut self, x: &ImuRate) -> ImuRate {
        let e = self.errors;
        let (sg, sa) = (self.spec.gyro_noise, self.spec.accel_noise);
        let ng = self.noise(sg);
        let na = self.noise(sa);
        ImuRate {
            t: x.t,
            w_ib_b: x.w_ib_b + x.w_ib_b.component_mul(&e.gyro_scale) + e.gyro_bias + ng,
            f_b: x.f_b + x.f_b.component_mul(&e.accel_scale) + e.accel_bias + na,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::earth::Geodetic;
    use crate::trajectory::{scenarios, TrajectorySpec, TruthSource};

    #[test]
    fn units() {
        assert!((MG - 9.80665e-3).abs() < 1e-18);
        assert!((DEG_PER_HOUR - 4.84813681109536e-6).abs() < 1e-18);
        let s = ImuSpec::sdins25();
        assert!(
            (s.accel_noise - 100.0 * UG).abs() < 1e-18
                && (s.gyro_noise - 0.3 * DEG_PER_HOUR).abs() < 1e-20
        );
    }

    #[test]
    fn stationary_increments_are_rate_times_dt() {
        let tr =
            TrajectorySpec::new(Geodetic::from_degrees(36.4, 127.0, -10.0), 0.3, 0.0).build(2.0);
        let s = tr.truth(0.0);
        for inc in increments(&tr, 100.0, 1.0) {
            assert!((inc.dtheta - s.w_ib_b * 0.01).norm() < 1e-20);
            assert!((inc.dv - s.f_b * 0.01).norm() < 1e-15);
        }
        assert_eq!(increments(&tr, 100.0, 1.0).count(), 100);
        assert_eq!(rates(&tr, 100.0, 1.0).count(), 101);
    }

    #[test]
    fn quadrature_is_converged() {
        let mut spec = scenarios::sdins25_lawn_mower();
        spec.roll.add_sine(0.1, 2.0, 0.0);
        let tr = spec.build(150.0);
        for t0 in [29.995, 33.0, 100.0, 101.234, 117.0] {
            let a = exact_increment(&tr, t0, t0 + 0.01, 1);
            let b = exact_increment(&tr, t0, t0 + 0.01, 8);
            // Exact to round-off inside a manoeuvre; across a ramp boundary
            // (29.995..30.005, where the fourth derivative of the motion jumps)
            // about 1e-13 rad.
            assert!((a.0 - b.0).norm() < 3e-13, "{t0}: {:e}", (a.0 - b.0).norm());
            assert!((a.1 - b.1).norm() < 1e-12, "{t0}: {:e}", (a.1 - b.1).norm());
        }
    }

    #[test]
    fn error_model_is_seeded_and_has_the_specified_statistics() {
        let spec = ImuSpec::sdins25().with_scale_ppm(100.0, 50.0);
        let a = ImuModel::new(spec, 7);
        let b = ImuModel::new(spec, 7);
        let c = ImuModel::new(spec, 8);
        assert_eq!(a.errors, b.errors);
        assert_ne!(a.errors, c.errors);
        // Bias spread over many runs.
        let n = 4000;
        let mut s2 = 0.0;
        for seed in 0..n {
            let m = ImuModel::new(spec, seed);
            s2 += m.errors.gyro_bias.norm_squared();
        }
        let sigma = (s2 / (3.0 * n as f64)).sqrt();
        assert!(
            (sigma / spec.gyro_bias - 1.0).abs() < 0.03,
            "{}",
            sigma / spec.gyro_bias
        );
        // Per-sample noise on rates; increment noise is rate noise times dt.
        let mut m = ImuModel::with_errors(spec, ImuErrors::default(), 3);
        let zero = ImuRate {
            t: 0.0,
            w_ib_b: Vector3::zeros(),
            f_b: Vector3::zeros(),
        };
        let (mut sa, mut sg) = (0.0, 0.0);
        for _ in 0..n {
            let r = m.corrupt_rate(&zero);
            sa += r.f_b.norm_squared();
            sg += r.w_ib_b.norm_squared();
        }
        let ea = (sa / (3.0 * n as f64)).sqrt() / spec.accel_noise;
        let eg = (sg / (3.0 * n as f64)).sqrt() / spec.gyro_noise;
        assert!(
            (ea - 1.0).abs() < 0.03 && (eg - 1.0).abs() < 0.03,
            "{ea} {eg}"
        );
        let mut m1 = ImuModel::new(spec, 11);
        let mut m2 = ImuModel::new(spec, 11);
        let inc = ImuIncrement {
            t: 0.01,
            dt: 0.01,
            dtheta: Vector3::new(1e-3, 0.0, 0.0),
            dv: Vector3::new(0.0, 0.0, -0.098),
        };
        let r = ImuRate {
            t: 0.01,
            w_ib_b: inc.dtheta / 0.01,
            f_b: inc.dv / 0.01,
        };
        let (x, y) = (m1.corrupt_increment(&inc), m2.corrupt_rate(&r));
        assert!(
            (x.dtheta / 0.01 - y.w_ib_b).norm() < 1e-15 && (x.dv / 0.01 - y.f_b).norm() < 1e-12
        );
    }
}
