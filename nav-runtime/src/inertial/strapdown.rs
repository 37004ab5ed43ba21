//! Strapdown inertial navigation in the local-level NED frame: the nominal
//! mechanization of docs/models/sdins25.md, eqs. 1-3, integrated at the IMU rate from
//! increments (delta-theta, delta-v) or from rates, plus the feedback helpers of
//! an error-state filter.
//!
//! The discrete algorithm (Titterton & Weston ch. 11, Savage's two-speed
//! structure reduced to one speed with the previous-sample corrections):
//!
//! - attitude (T&W ch. 11, attitude computation): `C_b^n(k) = exp(-[zeta x]) C_b^n(k-1) exp([sigma x])`
//!   with the body rotation vector `sigma = dtheta_k + 1/12 dtheta_{k-1} x dtheta_k`
//!   (coning correction, exact for a rate linear in time over two samples) and the
//!   navigation-frame rotation `zeta = w_in^n dt` evaluated at mid-interval;
//! - velocity (T&W ch. 11, velocity computation; docs/models/sdins25.md, eq. 2): the specific-force increment
//!   `C_b^n(k-1) [dv + 1/2 dtheta x dv + 1/12 (dtheta_{k-1} x dv + dv_{k-1} x dtheta)
//!   + 1/6 dtheta x (dtheta x dv)]` (rotation compensation, sculling, second-order
//!   rotation term), corrected for the rotation of n during the interval to second
//!   order, plus `(g^n - (2 w_ie^n + w_en^n) x v^n) dt` at mid-interval;
//! - position (eq. 1): trapezoidal in velocity, radii at mid-interval.
//!
//! Mid-interval quantities come from a predictor (start-of-interval terms)
//! followed by one corrector, so the whole step is second order.
//!
//! Gravity is [`crate::earth::normal_gravity_ned`] (exact WGS-84 normal gravity,
//! with its north component); the truth generator uses the same field.
//!
//! How a step is evaluated (docs/performance-replay.md, second round): the
//! rate-form increments are constant weights on the raw samples; `sin L`
//! and `cos L` are evaluated once at a base latitude kept across steps and
//! carried to the latitudes of a step by a small-angle step (exact functions
//! beyond 1e-4 rad); gravity is the same exact field from those sines;
//! small rotations use their series; `C_b^n` is re-orthonormalized every
//! few steps. Each of these changes the result only at the rounding level,
//! which the tests check against the straightforward step kept beside it.
//!
//! `core` + libm only (via [`crate::math`]), so it builds `no_std`.

use crate::attitude::{
    attitude_error, correct_c_bn, euler_from_c_bn, orthonormalize, perturb_c_bn,
    rotation_from_rotvec, skew, Euler,
};
use crate::earth::{
    earth_rate_n, normal_gravity_ned, normal_gravity_ned_of, position_rates, transport_rate_n,
    AtLatitude, Geodetic,
};
#[cfg(test)]
use crate::earth::{meridian_radius, transverse_radius};
#[cfg(test)]
use crate::math::cos;
use crate::math::{abs, sin_cos, wrap_angle};
use nalgebra::{Matrix3, Vector3};

/// Steps between two re-orthonormalizations of `C_b^n` in
/// [`Strapdown::propagate`].
const ORTHONORMALIZE_EVERY: u8 = 8;

/// Largest latitude change (rad) that [`sin_cos_near`] carries by series.
const NEAR_LATITUDE: f64 = 1e-4;

/// `(sin L1, cos L1)` from `(sin L0, cos L0)` when `L1 - L0` is small, by the
/// angle-sum formulas with the series `sin d = d - d^3/6` (truncation
/// `d^5/120 < 1e-22`) and `1 - cos d = d^2/2 (1 - d^2/12)` (truncation
/// `d^6/720 < 2e-27`) for `|d| <= 1e-4` rad: the results are those of
/// `sin_cos(L1)` to an ulp or two. The difference `d = L1 - L0` is exact
/// (Sterbenz) for the nearby latitudes of one step. A larger change (a
/// pathological step) falls back to `sin_cos(L1)`.
#[inline]
fn sin_cos_near(sin0: f64, cos0: f64, lat0: f64, lat1: f64) -> (f64, f64) {
    let d = lat1 - lat0;
    if abs(d) <= NEAR_LATITUDE {
        let d2 = d * d;
        let sd = d * (1.0 - d2 / 6.0);
        let vd = 0.5 * d2 * (1.0 - d2 / 12.0);
        // sin(L0 + d) = sin L0 cos d + cos L0 sin d, the small parts summed first.
        (
            sin0 + (cos0 * sd - sin0 * vd),
            cos0 - (sin0 * sd + cos0 * vd),
        )
    } else {
        sin_cos(lat1)
    }
}

/// [`rotation_from_rotvec`] for the small rotation vectors of one step
/// (`|phi| < 1e-2` rad), without trigonometry or square root:
/// `I + a [phi x] + b [phi x]^2` with `[phi x]^2 = phi phi^T - |phi|^2 I` and
/// the series `a = sin t/t = 1 - t^2/6 (1 - t^2/20 (1 - t^2/42))`,
/// `b = (1 - cos t)/t^2 = 1/2 (1 - t^2/12 (1 - t^2/30 (1 - t^2/56)))`, whose
/// truncations `t^8/9!` and `t^8/10!` are below 3e-22 for `t^2 < 1e-4`, far
/// below rounding (T&W ch. 11, the rotation-vector attitude update). Larger
/// rotations take [`rotation_from_rotvec`].
#[inline]
fn small_rotation(phi: &Vector3<f64>) -> Matrix3<f64> {
    let t2 = phi.norm_squared();
    if t2 >= 1e-4 {
        return rotation_from_rotvec(phi);
    }
    let a = 1.0 - t2 / 6.0 * (1.0 - t2 / 20.0 * (1.0 - t2 / 42.0));
    let b = 0.5 * (1.0 - t2 / 12.0 * (1.0 - t2 / 30.0 * (1.0 - t2 / 56.0)));
    let (x, y, z) = (phi[0], phi[1], phi[2]);
    let (ax, ay, az) = (a * x, a * y, a * z);
    let (bx, by) = (b * x, b * y);
    let (bxy, bxz, byz) = (bx * y, bx * z, by * z);
    let (xx, yy, zz) = (x * x, y * y, z * z);
    Matrix3::new(
        1.0 - b * (yy + zz),
        bxy - az,
        bxz + ay,
        bxy + az,
        1.0 - b * (xx + zz),
        byz - ax,
        bxz - ay,
        byz + ax,
        1.0 - b * (xx + yy),
    )
}

/// [`wrap_angle`] with the common case first: a longitude already in
/// (-pi, pi] is returned as it is, which is what [`wrap_angle`] returns for it.
#[inline]
fn wrap_longitude(lon: f64) -> f64 {
    if lon > -core::f64::consts::PI && lon <= core::f64::consts::PI {
        lon
    } else {
        wrap_angle(lon)
    }
}

/// Nominal navigation state: geodetic position, NED velocity, attitude.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavState {
    /// Geodetic latitude L (rad).
    pub lat: f64,
    /// Longitude l (rad).
    pub lon: f64,
    /// Height h (m, positive up; depth = -h).
    pub h: f64,
    /// Velocity relative to the Earth in NED, `v^n = [V_N, V_E, V_D]` (m/s).
    pub v_n: Vector3<f64>,
    /// Attitude `C_b^n` (body to NED).
    pub c_bn: Matrix3<f64>,
}

impl Default for NavState {
    fn default() -> Self {
        Self {
            lat: 0.0,
            lon: 0.0,
            h: 0.0,
            v_n: Vector3::zeros(),
            c_bn: Matrix3::identity(),
        }
    }
}

impl NavState {
    /// From a position, an NED velocity (m/s) and Euler angles.
    pub fn new(pos: Geodetic, v_n: Vector3<f64>, attitude: &Euler) -> Self {
        Self {
            lat: pos.lat,
            lon: pos.lon,
            h: pos.h,
            v_n,
            c_bn: attitude.c_bn(),
        }
    }
    /// Position as [`Geodetic`].
    pub fn position(&self) -> Geodetic {
        Geodetic::new(self.lat, self.lon, self.h)
    }
    /// Depth d = -h (m).
    pub fn depth(&self) -> f64 {
        -self.h
    }
    /// Euler angles of `C_b^n`.
    pub fn euler(&self) -> Euler {
        euler_from_c_bn(&self.c_bn)
    }
    /// Velocity in body axes, `v^b = C_n^b v^n` (m/s).
    pub fn v_body(&self) -> Vector3<f64> {
        self.c_bn.transpose() * self.v_n
    }
    /// The error of this (computed) state relative to `truth`, with the
    /// convention error = computed minus true and `C^_b^n = exp(-[phi x]) C_b^n`
    /// (`phi` exact, see [`attitude_error`]). Longitude difference wrapped to (-pi, pi].
    pub fn error_from(&self, truth: &NavState) -> NavError {
        NavError {
            dlat: self.lat - truth.lat,
            dlon: wrap_angle(self.lon - truth.lon),
            dh: self.h - truth.h,
            dv_n: self.v_n - truth.v_n,
            phi: attitude_error(&self.c_bn, &truth.c_bn),
        }
    }
    /// Applies an error to a true state (to build a computed state):
    /// `L^ = L + dL`, ..., `v^ = v + dV`, `C^ = (I - [phi x]) C` re-orthonormalized.
    pub fn perturbed(&self, e: &NavError) -> NavState {
        NavState {
            lat: self.lat + e.dlat,
            lon: self.lon + e.dlon,
            h: self.h + e.dh,
            v_n: self.v_n + e.dv_n,
            c_bn: perturb_c_bn(&self.c_bn, &e.phi),
        }
    }
    /// Removes an estimated error from a computed state (error-state feedback):
    /// `L <- L^ - dL`, ..., `v <- v^ - dV`, `C <- (I + [phi x]) C^` re-orthonormalized.
    pub fn corrected(&self, e: &NavError) -> NavState {
        NavState {
            lat: self.lat - e.dlat,
            lon: wrap_angle(self.lon - e.dlon),
            h: self.h - e.dh,
            v_n: self.v_n - e.dv_n,
            c_bn: correct_c_bn(&self.c_bn, &e.phi),
        }
    }
}

/// Navigation errors in the order of the first 9 SDINS-25 error states
/// (docs/models/sdins25.md error-state table: dL, dl, dh, dV_N, dV_E, dV_D, phi_N, phi_E, phi_D);
/// error = computed (INS) minus true.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct NavError {
    /// Latitude error dL (rad).
    pub dlat: f64,
    /// Longitude error dl (rad).
    pub dlon: f64,
    /// Height error dh (m).
    pub dh: f64,
    /// Velocity error dV^n (m/s).
    pub dv_n: Vector3<f64>,
    /// Attitude error phi (rad, in n): `C^_b^n = (I - [phi x]) C_b^n`.
    pub phi: Vector3<f64>,
}

impl NavError {
    /// From the first 9 entries of an error-state vector (SDINS-25 order).
    /// Panics if `x` has fewer than 9 entries.
    pub fn from_slice(x: &[f64]) -> Self {
        NavError {
            dlat: x[0],
            dlon: x[1],
            dh: x[2],
            dv_n: Vector3::new(x[3], x[4], x[5]),
            phi: Vector3::new(x[6], x[7], x[8]),
        }
    }
    /// The 9 entries in SDINS-25 order.
    pub fn to_array(&self) -> [f64; 9] {
        [
            self.dlat,
            self.dlon,
            self.dh,
            self.dv_n[0],
            self.dv_n[1],
            self.dv_n[2],
            self.phi[0],
            self.phi[1],
            self.phi[2],
        ]
    }
    /// Position error in metres, `[(R_m+h) dL, (R_n+h) cos L dl, -dh]` (N, E, D),
    /// at latitude `lat` (rad) and height `h` (m).
    pub fn position_ned(&self, lat: f64, h: f64) -> Vector3<f64> {
        crate::earth::geodetic_error_to_ned(lat, h, self.dlat, self.dlon, self.dh)
    }
}

/// Time derivatives of the nominal state, docs/models/sdins25.md, eqs. 1-3.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NavRates {
    /// `Ldot = V_N/(R_m+h)` (rad/s).
    pub lat: f64,
    /// `ldot = V_E/((R_n+h) cos L)` (rad/s).
    pub lon: f64,
    /// `hdot = -V_D` (m/s).
    pub h: f64,
    /// `Vdot^n = C_b^n f^b - (2 w_ie^n + w_en^n) x V^n + g^n` (m/s^2).
    pub v_n: Vector3<f64>,
    /// `Cdot_b^n = C_b^n [w_ib^b x] - [w_in^n x] C_b^n` (1/s).
    pub c_bn: Matrix3<f64>,
}

/// Continuous mechanization, docs/models/sdins25.md, eqs. 1-3, for body rate
/// `w_ib_b` (rad/s) and specific force `f_b` (m/s^2).
pub fn mechanization_rates(s: &NavState, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>) -> NavRates {
    let pr = position_rates(s.lat, s.h, &s.v_n);
    let w_ie = earth_rate_n(s.lat);
    let w_en = transport_rate_n(s.lat, s.h, &s.v_n);
    let v_dot = s.c_bn * f_b - (2.0 * w_ie + w_en).cross(&s.v_n) + normal_gravity_ned(s.lat, s.h);
    let c_dot = s.c_bn * skew(w_ib_b) - skew(&(w_ie + w_en)) * s.c_bn;
    NavRates {
        lat: pr[0],
        lon: pr[1],
        h: pr[2],
        v_n: v_dot,
        c_bn: c_dot,
    }
}

/// Body rotation vector over one interval with the previous-sample coning
/// correction, `sigma = dtheta + 1/12 dtheta_prev x dtheta` (rad) (T&W ch. 11, coning compensation;
/// exact to second order when the rate is linear in time over the two intervals).
pub fn coning_rotation_vector(dtheta_prev: &Vector3<f64>, dtheta: &Vector3<f64>) -> Vector3<f64> {
    dtheta + dtheta_prev.cross(dtheta) / 12.0
}

/// Velocity increment in the body frame at the start of the interval (m/s):
/// `dv + 1/2 dtheta x dv` (rotation compensation), plus previous-sample sculling
/// `1/12 (dtheta_prev x dv + dv_prev x dtheta)` (T&W ch. 11, sculling
/// compensation; exact for rates and forces linear in time over the two
/// intervals), plus the second-order rotation term `1/6 dtheta x (dtheta x dv)`.
pub fn sculling_velocity_increment(
    dtheta_prev: &Vector3<f64>,
    dv_prev: &Vector3<f64>,
    dtheta: &Vector3<f64>,
    dv: &Vector3<f64>,
) -> Vector3<f64> {
    let rot = dtheta.cross(dv);
    dv + 0.5 * rot
        + (dtheta_prev.cross(dv) + dv_prev.cross(dtheta)) / 12.0
        + dtheta.cross(&rot) / 6.0
}

/// Increments of one interval of length `T` for rates modelled as cubic
/// polynomials in the time `tau` from the start of the interval:
/// `w(tau) = sum_i w[i] tau^i`, `f(tau) = sum_i f[i] tau^i` (i = 0..3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PolyIncrements {
    /// `int w` (rad).
    pub dtheta: Vector3<f64>,
    /// `int f` (m/s).
    pub dv: Vector3<f64>,
    /// Rotation vector with the coning term `1/2 int alpha x w` (rad).
    pub sigma: Vector3<f64>,
    /// `dv + int alpha x f + 1/6 dtheta x (dtheta x dv)` (m/s): the velocity
    /// increment resolved in the body frame at the start of the interval, to
    /// second order (T&W ch. 11, velocity computation).
    pub dv_b: Vector3<f64>,
}

/// Closed-form [`PolyIncrements`]: with `alpha(tau) = int_0^tau w =
/// sum_i w[i] tau^(i+1)/(i+1)`, the Bortz first-order coning term and the
/// rotation-plus-sculling term are the exact double sums
/// `int_0^T alpha x g = sum_ij (w[i] x g[j]) T^(i+j+2) / ((i+1)(i+j+2))`.
pub fn polynomial_increments(
    w: &[Vector3<f64>; 4],
    f: &[Vector3<f64>; 4],
    t: f64,
) -> PolyIncrements {
    let mut tp = [1.0; 9];
    for i in 1..9 {
        tp[i] = tp[i - 1] * t;
    }
    let mut dtheta = Vector3::zeros();
    let mut dv = Vector3::zeros();
    let mut coning = Vector3::zeros();
    let mut axf = Vector3::zeros();
    for i in 0..4 {
        dtheta += w[i] * (tp[i + 1] / (i + 1) as f64);
        dv += f[i] * (tp[i + 1] / (i + 1) as f64);
        for j in 0..4 {
            let k = tp[i + j + 2] / (((i + 1) * (i + j + 2)) as f64);
            coning += w[i].cross(&w[j]) * k;
            axf += w[i].cross(&f[j]) * k;
        }
    }
    let sigma = dtheta + 0.5 * coning;
    let dv_b = dv + axf + dtheta.cross(&dtheta.cross(&dv)) / 6.0;
    PolyIncrements {
        dtheta,
        dv,
        sigma,
        dv_b,
    }
}

/// Coefficients (in `tau`, from the start of the last interval) of the
/// polynomial through equally spaced samples `y` (oldest first, the last one at
/// `tau = T`): linear for 2 samples, quadratic for 3, cubic for 4. The
/// reference of [`sample_increments`], which applies it folded into weights.
#[cfg(test)]
fn fit_samples(y: &[Vector3<f64>], t: f64) -> [Vector3<f64>; 4] {
    let z = Vector3::zeros();
    match y.len() {
        0 => [z; 4],
        1 => [y[0], z, z, z],
        2 => [y[0], (y[1] - y[0]) / t, z, z],
        3 => {
            // Nodes at u = -1, 0, 1 (u = tau/T).
            let c1 = (y[2] - y[0]) / 2.0;
            let c2 = (y[2] + y[0]) / 2.0 - y[1];
            [y[1], c1 / t, c2 / (t * t), z]
        }
        _ => {
            // Nodes at u = -2, -1, 0, 1.
            let (ym2, ym1, y0, y1) = (
                y[y.len() - 4],
                y[y.len() - 3],
                y[y.len() - 2],
                y[y.len() - 1],
            );
            let c2 = (y1 + ym1) / 2.0 - y0;
            let s = (y1 - ym1) / 2.0;
            let c3 = (y0 - ym2 + c2 * 4.0 - s * 2.0) / 6.0;
            let c1 = s - c3;
            [y0, c1 / t, c2 / (t * t), c3 / (t * t * t)]
        }
    }
}

/// [`fit_samples`] as matrices in units of the interval: with `u = tau/T`,
/// coefficient `i` times `T^i` is `sum_s FIT[n-1][i][s] y_s` for `n` samples
/// (oldest first, the last at `u = 1`): nodes `u = 1` (constant), `0, 1`,
/// `-1, 0, 1` and `-2, -1, 0, 1`.
const FIT: [[[f64; 4]; 4]; 4] = [
    [[1.0, 0.0, 0.0, 0.0], [0.0; 4], [0.0; 4], [0.0; 4]],
    [
        [1.0, 0.0, 0.0, 0.0],
        [-1.0, 1.0, 0.0, 0.0],
        [0.0; 4],
        [0.0; 4],
    ],
    [
        [0.0, 1.0, 0.0, 0.0],
        [-0.5, 0.0, 0.5, 0.0],
        [0.5, -1.0, 0.5, 0.0],
        [0.0; 4],
    ],
    [
        [0.0, 0.0, 1.0, 0.0],
        [1.0 / 6.0, -1.0, 0.5, 1.0 / 3.0],
        [0.0, 0.5, -1.0, 0.5],
        [-1.0 / 6.0, 0.5, -0.5, 1.0 / 6.0],
    ],
];

/// [`polynomial_increments`] of [`fit_samples`] as weights on the samples.
///
/// The fit is linear in the samples, `c_i T^i = sum_s A_is y_s`, so the
/// increments are linear (`dtheta`, `dv`) and bilinear (coning, rotation plus
/// sculling) in them: with `K_ij = 1/((i+1)(i+j+2))`,
/// `dtheta = T sum_s a_s w_s`, `a_s = sum_i A_is/(i+1)`, and
/// `int alpha x g = T^2 sum_sr M_sr w_s x g_r`, `M = A^T K A`. By
/// antisymmetry the coning term needs only `s < r`:
/// `1/2 int alpha x w = T^2 sum_{s<r} G_sr w_s x w_r`, `G_sr = (M_sr - M_rs)/2`.
/// The weights depend on the number of samples only (the powers of `T` are
/// applied per step), so they are constants.
#[derive(Clone, Copy, Debug)]
struct SampleWeights {
    a: [f64; 4],
    m: [[f64; 4]; 4],
    g: [[f64; 4]; 4],
}

const fn sample_weights(n: usize) -> SampleWeights {
    let fit = &FIT[n - 1];
    let mut w = SampleWeights {
        a: [0.0; 4],
        m: [[0.0; 4]; 4],
        g: [[0.0; 4]; 4],
    };
    let mut s = 0;
    while s < n {
        let mut i = 0;
        while i < 4 {
            w.a[s] += fit[i][s] / (i + 1) as f64;
            i += 1;
        }
        let mut r = 0;
        while r < n {
            let mut i = 0;
            while i < 4 {
                let mut j = 0;
                while j < 4 {
                    w.m[s][r] += fit[i][s] * fit[j][r] / ((i + 1) * (i + j + 2)) as f64;
                    j += 1;
                }
                i += 1;
            }
            r += 1;
        }
        s += 1;
    }
    let mut s = 0;
    while s < n {
        let mut r = s + 1;
        while r < n {
            w.g[s][r] = 0.5 * (w.m[s][r] - w.m[r][s]);
            r += 1;
        }
        s += 1;
    }
    w
}

/// [`SampleWeights`] for 1 to 4 samples.
const SAMPLE_WEIGHTS: [SampleWeights; 4] = [
    sample_weights(1),
    sample_weights(2),
    sample_weights(3),
    sample_weights(4),
];

/// `polynomial_increments(&fit_samples(w), &fit_samples(f), t)` from the
/// `N` samples directly (see [`SampleWeights`]): 3 cross products for the
/// coning term and `N` for rotation plus sculling instead of 32, no fit.
/// Equal to the two-stage form to rounding (tested).
#[inline(always)]
#[allow(clippy::needless_range_loop)] // s and r index weights and samples alike
fn sample_increments<const N: usize>(
    w: &[Vector3<f64>; 4],
    f: &[Vector3<f64>; 4],
    t: f64,
) -> PolyIncrements {
    let k = &SAMPLE_WEIGHTS[N - 1];
    // Sample s's terms; called with constant s so that the whole sum is
    // straight-line code with the weights as constants.
    #[inline(always)]
    fn sample<const N: usize>(
        s: usize,
        k: &SampleWeights,
        w: &[Vector3<f64>; 4],
        f: &[Vector3<f64>; 4],
        acc: &mut [Vector3<f64>; 4],
    ) {
        if s >= N {
            return;
        }
        acc[0] += w[s] * k.a[s];
        acc[1] += f[s] * k.a[s];
        let mut u = f[0] * k.m[s][0];
        for r in 1..N {
            u += f[r] * k.m[s][r];
        }
        acc[3] += w[s].cross(&u);
        if s + 1 < N {
            let mut z = w[s + 1] * k.g[s][s + 1];
            for r in s + 2..N {
                z += w[r] * k.g[s][r];
            }
            acc[2] += w[s].cross(&z);
        }
    }
    let mut acc = [Vector3::zeros(); 4];
    sample::<N>(0, k, w, f, &mut acc);
    sample::<N>(1, k, w, f, &mut acc);
    sample::<N>(2, k, w, f, &mut acc);
    sample::<N>(3, k, w, f, &mut acc);
    let [dtheta, dv, coning, axf] = acc;
    let t2 = t * t;
    let dtheta = dtheta * t;
    let dv = dv * t;
    let sigma = dtheta + coning * t2;
    let dv_b = dv + axf * t2 + dtheta.cross(&dtheta.cross(&dv)) / 6.0;
    PolyIncrements {
        dtheta,
        dv,
        sigma,
        dv_b,
    }
}

/// [`sample_increments`] for `n` (1 to 4) samples; zero increments for none.
fn increments_of_samples(
    n: usize,
    w: &[Vector3<f64>; 4],
    f: &[Vector3<f64>; 4],
    t: f64,
) -> PolyIncrements {
    match n {
        0 => PolyIncrements {
            dtheta: Vector3::zeros(),
            dv: Vector3::zeros(),
            sigma: Vector3::zeros(),
            dv_b: Vector3::zeros(),
        },
        1 => sample_increments::<1>(w, f, t),
        2 => sample_increments::<2>(w, f, t),
        3 => sample_increments::<3>(w, f, t),
        _ => sample_increments::<4>(w, f, t),
    }
}

/// The last (up to) four rate samples, oldest first; fixed capacity, no
/// allocation. Rates and forces in separate arrays, which
/// [`increments_of_samples`] reads in place (entries from `len` on are stale
/// and unused).
#[derive(Clone, Copy, Debug)]
struct RateHistory {
    w: [Vector3<f64>; 4],
    f: [Vector3<f64>; 4],
    len: usize,
}

impl RateHistory {
    fn new() -> Self {
        Self {
            w: [Vector3::zeros(); 4],
            f: [Vector3::zeros(); 4],
            len: 0,
        }
    }
    fn len(&self) -> usize {
        self.len
    }
    fn clear(&mut self) {
        self.len = 0;
    }
    /// The newest sample; call with `len() > 0`.
    fn last(&self) -> (Vector3<f64>, Vector3<f64>) {
        let i = self.len.saturating_sub(1);
        (self.w[i], self.f[i])
    }
    /// Appends a sample, dropping the oldest when full.
    fn push(&mut self, w: &Vector3<f64>, f: &Vector3<f64>) {
        if self.len == 4 {
            self.w.copy_within(1..4, 0);
            self.f.copy_within(1..4, 0);
            self.len = 3;
        }
        self.w[self.len] = *w;
        self.f[self.len] = *f;
        self.len += 1;
    }
}

/// What the rates given to [`Strapdown::update_rates`] are.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum RateSamples {
    /// Instantaneous samples at the end of each interval (the `imu.csv` rate
    /// form): integrated through a cubic rate model.
    #[default]
    Instantaneous,
    /// Averages over the interval ending at the sample, i.e. increments
    /// divided by the interval (the `imu.csv` increment form as the log reader
    /// returns it): `w dt`, `f dt` are the increments and go through
    /// [`Strapdown::update_increments`] with its coning and sculling terms.
    IntervalAverage,
}

/// A strapdown navigator: the nominal state plus the IMU history the coning and
/// sculling corrections need.
///
/// IMU inputs must already be corrected for estimated sensor errors (biases);
/// that is the error-state filter's job.
///
/// `Copy` (a few hundred bytes, no heap): an error-state filter keeps the
/// nominal solution before each step to put back if the step fails, and a
/// copy is the cheapest way to keep it.
#[derive(Clone, Copy, Debug)]
pub struct Strapdown {
    /// The current nominal state.
    pub state: NavState,
    /// Time of the state (s), advanced by each update's `dt`.
    pub time: f64,
    /// Apply the coning and sculling corrections (default `true`); with `false`
    /// only the first-order rotation compensation remains (for comparisons).
    pub compensate: bool,
    /// What [`Strapdown::update_rates`] receives (default: instantaneous
    /// samples). Set it before [`Strapdown::set_previous_rates`] or
    /// [`Strapdown::prime_rates`], which keep the history of that form.
    pub samples: RateSamples,
    prev_increments: Option<(Vector3<f64>, Vector3<f64>)>,
    /// Interval-average rates of the interval ending at the initial state
    /// ([`RateSamples::IntervalAverage`]), scaled by the first update's `dt`.
    prev_average: Option<(Vector3<f64>, Vector3<f64>)>,
    rate_history: RateHistory,
    rate_dt: f64,
    /// Gravity at the previous step's mid-interval: the predictor's gravity
    /// (see [`Strapdown::propagate`]).
    gravity: Option<Vector3<f64>>,
    /// Steps since `C_b^n` was last re-orthonormalized.
    since_orthonormalize: u8,
    /// Base latitude and its sine and cosine (see [`Strapdown::latitude_base`]).
    latitude_trig: Option<(f64, f64, f64)>,
}

impl Strapdown {
    /// A navigator starting at `state` at time 0.
    pub fn new(state: NavState) -> Self {
        Self {
            state,
            time: 0.0,
            compensate: true,
            samples: RateSamples::Instantaneous,
            prev_increments: None,
            prev_average: None,
            rate_history: RateHistory::new(),
            rate_dt: 0.0,
            gravity: None,
            since_orthonormalize: 0,
            latitude_trig: None,
        }
    }

    /// A navigator starting at `state` at time `time` (s).
    pub fn with_time(state: NavState, time: f64) -> Self {
        Self {
            time,
            ..Self::new(state)
        }
    }

    /// Forgets the IMU history (after a data gap): the next update uses no
    /// coning/sculling correction, or treats its rates as constant.
    pub fn reset_history(&mut self) {
        self.prev_increments = None;
        self.prev_average = None;
        self.rate_history.clear();
    }

    /// Sets the rate sample preceding the next [`Strapdown::update_rates`] call
    /// (e.g. the first row of a log, at the time of the initial state), without
    /// propagating; earlier samples are forgotten.
    ///
    /// With [`RateSamples::IntervalAverage`] the sample is the average over the
    /// interval ending at the initial state: times the first update's `dt`
    /// (that interval's length is taken as the next one's), it is the
    /// previous increment of the coning and sculling terms.
    pub fn set_previous_rates(&mut self, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>) {
        if self.samples == RateSamples::IntervalAverage {
            self.prev_increments = None;
            self.prev_average = Some((*w_ib_b, *f_b));
        }
        self.rate_history.clear();
        self.rate_history.push(w_ib_b, f_b);
    }

    /// Records the increments of the interval ending at the time of the initial
    /// state without propagating, so that the first [`Strapdown::update_increments`]
    /// has its coning and sculling history.
    pub fn prime_increments(&mut self, dtheta: &Vector3<f64>, dv: &Vector3<f64>) {
        self.prev_increments = Some((*dtheta, *dv));
    }

    /// Records a rate sample taken `dt` s after the previous one without
    /// propagating, so that the rate model of the first updates has its full
    /// order. Feed the samples up to the time of the initial state this way: the
    /// first interval otherwise uses a linear model, whose one-off attitude error
    /// `dt^3/12 wddot(0)` (2e-7 rad for a 5 deg, 0.5 Hz roll at 100 Hz) then
    /// biases the velocity for the rest of the run.
    /// With [`RateSamples::IntervalAverage`] the last primed sample times `dt`
    /// is the previous increment of the first update.
    pub fn prime_rates(&mut self, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>, dt: f64) {
        if self.samples == RateSamples::IntervalAverage {
            self.prev_increments = Some((w_ib_b * dt, f_b * dt));
            self.prev_average = None;
        }
        self.push_rate(w_ib_b, f_b, dt);
    }

    fn push_rate(&mut self, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>, dt: f64) {
        if self.rate_history.len() > 1 && crate::math::abs(self.rate_dt - dt) > 1e-9 * dt {
            // Keep only the last sample when the step changes.
            let (w, f) = self.rate_history.last();
            self.rate_history.clear();
            self.rate_history.push(&w, &f);
        }
        self.rate_dt = dt;
        self.rate_history.push(w_ib_b, f_b);
    }

    /// One update from IMU increments over an interval of `dt` s:
    /// `dtheta = int w_ib^b dt` (rad) and `dv = int f^b dt` (m/s), both in the
    /// body frame as an integrating IMU outputs them.
    pub fn update_increments(&mut self, dtheta: &Vector3<f64>, dv: &Vector3<f64>, dt: f64) {
        let (sigma, dv_b) = if self.compensate {
            let (pth, pdv) = self.prev_increments.unwrap_or((*dtheta, *dv));
            (
                coning_rotation_vector(&pth, dtheta),
                sculling_velocity_increment(&pth, &pdv, dtheta, dv),
            )
        } else {
            (*dtheta, sculling_velocity_increment(dtheta, dv, dtheta, dv))
        };
        self.prev_increments = Some((*dtheta, *dv));
        self.propagate(&sigma, &dv_b, dtheta, dv, dt);
    }

    /// One update from rate samples: body rate `w_ib_b` (rad/s) and specific
    /// force `f_b` (m/s^2) sampled at the end of an interval of `dt` s (the
    /// imu.csv convention of instantaneous samples).
    ///
    /// Within the interval the rates are modelled by the cubic through the last
    /// four samples (fewer at the start or after `dt` changes), and the body
    /// rotation vector and velocity increment are the closed-form integrals of
    /// that model ([`polynomial_increments`]). A linear model would leave a
    /// specific-force error of order `dt^2/12 <w^2> g` (a rectified curvature
    /// term: 3e-6 m/s^2 for a 5 deg, 0.5 Hz roll at 100 Hz) and a quadratic one a
    /// tilt offset of order `dt^3/24 wddot(0)`; the cubic pushes both below the
    /// millimetre level on the test tracks. Samples that are interval averages
    /// (delta/dt of an integrating IMU) should go through
    /// [`Strapdown::update_increments`] as `w dt`, `f dt` instead.
    ///
    /// With [`RateSamples::IntervalAverage`] the samples are interval
    /// averages instead and the update is [`Strapdown::update_increments`] of
    /// `w dt`, `f dt`.
    pub fn update_rates(&mut self, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>, dt: f64) {
        if self.samples == RateSamples::IntervalAverage {
            if let Some((w0, f0)) = self.prev_average.take() {
                self.prev_increments = Some((w0 * dt, f0 * dt));
            }
            self.update_increments(&(w_ib_b * dt), &(f_b * dt), dt);
            return;
        }
        self.push_rate(w_ib_b, f_b, dt);
        // With a single sample the rate is held constant over the interval.
        let h = &self.rate_history;
        let p = increments_of_samples(h.len(), &h.w, &h.f, dt);
        let (sigma, dv_b) = if self.compensate {
            (p.sigma, p.dv_b)
        } else {
            (
                p.dtheta,
                sculling_velocity_increment(&p.dtheta, &p.dv, &p.dtheta, &p.dv),
            )
        };
        self.propagate(&sigma, &dv_b, &p.dtheta, &p.dv, dt);
    }

    /// Feeds an estimated error back into the state (error = INS minus true):
    /// see [`NavState::corrected`]. The IMU history is kept (it is body-frame data).
    pub fn inject(&mut self, e: &NavError) {
        self.state = self.state.corrected(e);
    }

    /// The common step: body rotation vector `sigma`, compensated body velocity
    /// increment `dv_b`, raw increments (for the second-order cross term).
    ///
    /// The latitude terms are needed at two nearby latitudes (the start and
    /// the predicted mid-interval point), which differ by the latitude change
    /// of half a step (about 1e-9 rad). `sin L` and `cos L` are evaluated
    /// exactly only at a base latitude kept from step to step
    /// ([`Strapdown::latitude_base`], renewed when the latitude has moved
    /// 5e-5 rad, 300 m, from it) and carried to each of the two by one
    /// [`sin_cos_near`] from the base (no accumulation from step to step);
    /// `tan L`, the radii (from `1 - e^2 sin^2 L`) and normal gravity take
    /// them as they are.
    fn propagate(
        &mut self,
        sigma: &Vector3<f64>,
        dv_b: &Vector3<f64>,
        dtheta: &Vector3<f64>,
        dv: &Vector3<f64>,
        dt: f64,
    ) {
        let s = self.state;
        let (lat, h, v) = (s.lat, s.h, s.v_n);
        let c0 = s.c_bn;
        let f_n = c0 * dv_b;

        // Predictor: slow terms at the start of the interval.
        let (lat_b, sin_b, cos_b) = self.latitude_base(lat);
        let (sin0, cos0) = sin_cos_near(sin_b, cos_b, lat_b, lat);
        let start = AtLatitude::from_sin_cos(sin0, cos0);
        let w_ie0 = start.earth_rate();
        let w_en0 = start.transport_rate(h, &v);
        // The predictor's gravity is the previous step's mid-interval value
        // (exact on the first step): the point is a few centimetres away,
        // which changes gravity by about 1e-7 m/s^2 and the step by far less
        // than its own truncation error; one exact field evaluation per step
        // instead of two.
        let g0 = match self.gravity {
            Some(g) => g,
            None => normal_gravity_ned_of(sin0, cos0, h),
        };
        let v_pred = v + f_n + (g0 - (2.0 * w_ie0 + w_en0).cross(&v)) * dt;
        let h_mid = h - 0.25 * (v[2] + v_pred[2]) * dt;
        let lat_mid = lat + 0.25 * (v[0] + v_pred[0]) * dt / (start.rm + h_mid);
        let v_mid = 0.5 * (v + v_pred);

        // Corrector: Earth rate, transport rate, gravity and Coriolis at mid-interval.
        let (sin_mid, cos_mid) = sin_cos_near(sin_b, cos_b, lat_b, lat_mid);
        let mid = AtLatitude::from_sin_cos(sin_mid, cos_mid);
        let w_ie = mid.earth_rate();
        let w_en = mid.transport_rate(h_mid, &v_mid);
        let zeta = (w_ie + w_en) * dt;
        // Rotation of n during the interval, to second order in zeta:
        // int B(t) C0 A(t) f dt with B = exp(-[zeta t/T x]), A = exp([dtheta t/T x]),
        // i.e. -zeta x (1/2 C0 dv + 1/3 C0 (dtheta x dv)) + 1/6 zeta x (zeta x C0 dv)
        // (the two first-order terms under one cross product).
        let cdv = c0 * dv;
        let f_n = f_n - zeta.cross(&(0.5 * cdv + c0 * dtheta.cross(dv) / 3.0))
            + zeta.cross(&zeta.cross(&cdv)) / 6.0;
        let g = normal_gravity_ned_of(sin_mid, cos_mid, h_mid);
        self.gravity = Some(g);
        let v_new = v + f_n + (g - (2.0 * w_ie + w_en).cross(&v_mid)) * dt;

        // Position: trapezoidal velocity, radii at mid-interval (eq. 1). The
        // radii and cos L are those of the predicted mid-interval latitude:
        // it differs from the corrected one, (L + L_new)/2, by the
        // predictor's latitude error (about 1e-15 rad at 100 Hz), which
        // changes the radii and cos L by some 1e-15 relative and the latitude
        // and longitude steps (1e-8 rad) by some 1e-23 rad, far below their
        // rounding (1e-16 rad).
        let h_new = h - 0.5 * (v[2] + v_new[2]) * dt;
        let h_m = 0.5 * (h + h_new);
        let lat_new = lat + 0.5 * (v[0] + v_new[0]) * dt / (mid.rm + h_m);
        let lon_new = s.lon + 0.5 * (v[1] + v_new[1]) * dt / ((mid.rn + h_m) * cos_mid);

        // Attitude (eq. 3): body rotation then navigation-frame rotation.
        let c_new = small_rotation(&(-zeta)) * c0 * small_rotation(sigma);
        // Each factor is orthonormal to rounding, so the product drifts from
        // orthonormality by a few 1e-16 per step; a full re-orthonormalization
        // every ORTHONORMALIZE_EVERY steps keeps |C^T C - I| below 1e-14
        // (tested over an hour) at a fraction of the cost of one per step.
        self.since_orthonormalize += 1;
        let c_new = if self.since_orthonormalize >= ORTHONORMALIZE_EVERY {
            self.since_orthonormalize = 0;
            orthonormalize(&c_new)
        } else {
            c_new
        };

        self.state = NavState {
            lat: lat_new,
            lon: wrap_longitude(lon_new),
            h: h_new,
            v_n: v_new,
            c_bn: c_new,
        };
        self.time += dt;
    }

    /// [`Strapdown::update_rates`] as it was before the sample weights and the
    /// shared trigonometry: the reference of the equivalence tests.
    #[cfg(test)]
    fn update_rates_reference(&mut self, w_ib_b: &Vector3<f64>, f_b: &Vector3<f64>, dt: f64) {
        if self.samples == RateSamples::IntervalAverage {
            if let Some((w0, f0)) = self.prev_average.take() {
                self.prev_increments = Some((w0 * dt, f0 * dt));
            }
            self.update_increments_reference(&(w_ib_b * dt), &(f_b * dt), dt);
            return;
        }
        self.push_rate(w_ib_b, f_b, dt);
        let n = self.rate_history.len();
        let (ws, fs) = (self.rate_history.w, self.rate_history.f);
        let p = polynomial_increments(&fit_samples(&ws[..n], dt), &fit_samples(&fs[..n], dt), dt);
        let (sigma, dv_b) = if self.compensate {
            (p.sigma, p.dv_b)
        } else {
            (
                p.dtheta,
                sculling_velocity_increment(&p.dtheta, &p.dv, &p.dtheta, &p.dv),
            )
        };
        self.propagate_reference(&sigma, &dv_b, &p.dtheta, &p.dv, dt);
    }

    /// [`Strapdown::update_increments`] through the reference step.
    #[cfg(test)]
    fn update_increments_reference(&mut self, dtheta: &Vector3<f64>, dv: &Vector3<f64>, dt: f64) {
        let (sigma, dv_b) = if self.compensate {
            let (pth, pdv) = self.prev_increments.unwrap_or((*dtheta, *dv));
            (
                coning_rotation_vector(&pth, dtheta),
                sculling_velocity_increment(&pth, &pdv, dtheta, dv),
            )
        } else {
            (*dtheta, sculling_velocity_increment(dtheta, dv, dtheta, dv))
        };
        self.prev_increments = Some((*dtheta, *dv));
        self.propagate_reference(&sigma, &dv_b, dtheta, dv, dt);
    }

    /// The base latitude of [`Strapdown::propagate`]'s trigonometry and its
    /// exact sine and cosine: kept while `lat` is within half of
    /// [`NEAR_LATITUDE`] of it (so that the step's other latitudes, within
    /// 1e-8 rad of `lat`, are within the series' range), renewed otherwise.
    /// Any change of the state (a correction, a new state) is covered: only
    /// the distance to `lat` counts.
    fn latitude_base(&mut self, lat: f64) -> (f64, f64, f64) {
        match self.latitude_trig {
            Some(b) if abs(lat - b.0) <= 0.5 * NEAR_LATITUDE => b,
            _ => {
                let (s, c) = sin_cos(lat);
                self.latitude_trig = Some((lat, s, c));
                (lat, s, c)
            }
        }
    }

    /// The step as it was before [`Strapdown::propagate`] shared its
    /// trigonometry: the reference of the equivalence tests.
    #[cfg(test)]
    fn propagate_reference(
        &mut self,
        sigma: &Vector3<f64>,
        dv_b: &Vector3<f64>,
        dtheta: &Vector3<f64>,
        dv: &Vector3<f64>,
        dt: f64,
    ) {
        let s = self.state;
        let (lat, h, v) = (s.lat, s.h, s.v_n);
        let c0 = s.c_bn;
        let f_n = c0 * dv_b;

        // Predictor: slow terms at the start of the interval.
        let start = AtLatitude::new(lat);
        let w_ie0 = start.earth_rate();
        let w_en0 = start.transport_rate(h, &v);
        // The predictor's gravity is the previous step's mid-interval value
        // (exact on the first step): the point is a few centimetres away,
        // which changes gravity by about 1e-7 m/s^2 and the step by far less
        // than its own truncation error; one exact field evaluation per step
        // instead of two.
        let g0 = match self.gravity {
            Some(g) => g,
            None => normal_gravity_ned(lat, h),
        };
        let v_pred = v + f_n + (g0 - (2.0 * w_ie0 + w_en0).cross(&v)) * dt;
        let h_mid = h - 0.25 * (v[2] + v_pred[2]) * dt;
        let lat_mid = lat + 0.25 * (v[0] + v_pred[0]) * dt / (start.rm + h_mid);
        let v_mid = 0.5 * (v + v_pred);

        // Corrector: Earth rate, transport rate, gravity and Coriolis at mid-interval.
        let mid = AtLatitude::new(lat_mid);
        let w_ie = mid.earth_rate();
        let w_en = mid.transport_rate(h_mid, &v_mid);
        let zeta = (w_ie + w_en) * dt;
        // Rotation of n during the interval, to second order in zeta:
        // int B(t) C0 A(t) f dt with B = exp(-[zeta t/T x]), A = exp([dtheta t/T x]).
        let cdv = c0 * dv;
        let f_n = f_n - 0.5 * zeta.cross(&cdv) + zeta.cross(&zeta.cross(&cdv)) / 6.0
            - zeta.cross(&(c0 * dtheta.cross(dv))) / 3.0;
        let g = normal_gravity_ned(lat_mid, h_mid);
        self.gravity = Some(g);
        let v_new = v + f_n + (g - (2.0 * w_ie + w_en).cross(&v_mid)) * dt;

        // Position: trapezoidal velocity, radii at mid-interval (eq. 1).
        let h_new = h - 0.5 * (v[2] + v_new[2]) * dt;
        let h_m = 0.5 * (h + h_new);
        let vn_avg = 0.5 * (v[0] + v_new[0]);
        let lat_m = lat + 0.5 * vn_avg * dt / (start.rm + h_m);
        let lat_new = lat + vn_avg * dt / (meridian_radius(lat_m) + h_m);
        let lat_m = 0.5 * (lat + lat_new);
        let lon_new =
            s.lon + 0.5 * (v[1] + v_new[1]) * dt / ((transverse_radius(lat_m) + h_m) * cos(lat_m));

        // Attitude (eq. 3): body rotation then navigation-frame rotation.
        let c_new = rotation_from_rotvec(&(-zeta)) * c0 * rotation_from_rotvec(sigma);

        self.state = NavState {
            lat: lat_new,
            lon: wrap_angle(lon_new),
            h: h_new,
            v_n: v_new,
            c_bn: orthonormalize(&c_new),
        };
        self.time += dt;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::attitude::{dcm_from_quat, Euler};
    use crate::earth::{normal_gravity, G0};
    use nalgebra::{Quaternion, UnitQuaternion};

    fn start(lat_deg: f64) -> NavState {
        NavState::new(
            Geodetic::from_degrees(lat_deg, 127.36, -20.0),
            Vector3::zeros(),
            &Euler::from_degrees(0.0, 0.0, 0.0),
        )
    }

    /// Error-free IMU at rest: `w_ib^b = C_n^b w_ie^n`, `f^b = -C_n^b g^n`.
    fn stationary_imu(s: &NavState) -> (Vector3<f64>, Vector3<f64>) {
        let c_nb = s.c_bn.transpose();
        (
            c_nb * earth_rate_n(s.lat),
            -(c_nb * normal_gravity_ned(s.lat, s.h)),
        )
    }

    fn horizontal_error(a: &NavState, b: &NavState) -> f64 {
        let e = a.error_from(b).position_ned(b.lat, b.h);
        (e[0] * e[0] + e[1] * e[1]).sqrt()
    }

    #[test]
    fn stationary_error_free_stays_put_for_one_hour() {
        for attitude in [Euler::default(), Euler::from_degrees(3.0, -4.0, 130.0)] {
            let truth = NavState {
                c_bn: attitude.c_bn(),
                ..start(36.4)
            };
            let (w, f) = stationary_imu(&truth);
            let dt = 0.01;
            let mut inc = Strapdown::new(truth);
            let mut rat = Strapdown::new(truth);
            for _ in 0..360_000 {
                inc.update_increments(&(w * dt), &(f * dt), dt);
                rat.update_rates(&w, &f, dt);
            }
            for nav in [&inc, &rat] {
                let e = nav.state.error_from(&truth);
                let p = e.position_ned(truth.lat, truth.h).norm();
                println!(
                    "stationary 1 h: position {p:.2e} m, velocity {:.2e} m/s",
                    e.dv_n.norm()
                );
                assert!(p < 1e-3, "position error {p:e} m");
                assert!(e.dv_n.norm() < 1e-6, "velocity error {:e}", e.dv_n.norm());
                assert!(e.phi.norm() < 1e-9, "attitude error {:e}", e.phi.norm());
            }
        }
    }

    #[test]
    fn accelerometer_bias_gives_bounded_schuler_error() {
        // 1 mg on the north-pointing accelerometer of a level, north-facing IMU:
        // dN(t) = b/ws^2 (1 - cos ws t), ws^2 = g/(R_m+h) (T&W ch. 12, Schuler oscillation),
        // modulated by the Foucault rotation Omega sin L (slow over one hour).
        let truth = start(36.4);
        let (w, f) = stationary_imu(&truth);
        let b = 1e-3 * G0;
        let fb = f + Vector3::new(b, 0.0, 0.0);
        let dt = 0.01;
        let mut nav = Strapdown::new(truth);
        let g = normal_gravity(truth.lat, truth.h);
        let ws2 = g / (meridian_radius(truth.lat) + truth.h);
        let ws = ws2.sqrt();
        let bound = 2.0 * b / ws2;
        let mut worst: f64 = 0.0;
        let mut worst_model: f64 = 0.0;
        for k in 1..=360_000 {
            nav.update_increments(&(w * dt), &(fb * dt), dt);
            if k % 1000 == 0 {
                let t = k as f64 * dt;
                let e = nav
                    .state
                    .error_from(&truth)
                    .position_ned(truth.lat, truth.h);
                let hor = (e[0] * e[0] + e[1] * e[1]).sqrt();
                worst = worst.max(hor);
                let model = b / ws2 * (1.0 - (ws * t).cos());
                worst_model = worst_model.max((e[0] - model).abs());
            }
        }
        println!("1 mg bias, 1 h: worst horizontal {worst:.1} m, bound {bound:.1} m, north vs model {worst_model:.1} m");
        // Analytic bound 2 b / ws^2 = 12.7 km, reached at half a Schuler period (42 min).
        assert!(worst <= bound * 1.005, "worst {worst} bound {bound}");
        assert!(worst > 0.97 * bound, "worst {worst} bound {bound}");
        // The north error follows the Schuler curve within the Foucault modulation
        // (1 - cos(Omega sin L t) <= 1.3 % after 1 h, plus coupling; allow 3 % of the bound).
        assert!(
            worst_model < 0.03 * bound,
            "north error vs model {worst_model}"
        );
    }

    /// Classical coning: `q(t) = [cos a/2, 0, sin a/2 cos Wt, sin a/2 sin Wt]`,
    /// `w = [-2W sin^2 a/2, -W sin a sin Wt, W sin a cos Wt]` (body rate,
    /// `qdot = 1/2 q (x) w`). Integrates attitude alone from exact increments.
    fn coning_run(compensate: bool, alpha: f64, big_w: f64, dt: f64, n: usize) -> (f64, f64) {
        let q = |t: f64| {
            UnitQuaternion::new_normalize(Quaternion::new(
                (alpha / 2.0).cos(),
                0.0,
                (alpha / 2.0).sin() * (big_w * t).cos(),
                (alpha / 2.0).sin() * (big_w * t).sin(),
            ))
        };
        let inc = |t0: f64, t1: f64| {
            Vector3::new(
                -2.0 * big_w * (alpha / 2.0).sin().powi(2) * (t1 - t0),
                alpha.sin() * ((big_w * t1).cos() - (big_w * t0).cos()),
                alpha.sin() * ((big_w * t1).sin() - (big_w * t0).sin()),
            )
        };
        let mut c = dcm_from_quat(&q(0.0));
        let mut prev = inc(-dt, 0.0);
        for k in 0..n {
            let d = inc(k as f64 * dt, (k + 1) as f64 * dt);
            let sigma = if compensate {
                coning_rotation_vector(&prev, &d)
            } else {
                d
            };
            c = orthonormalize(&(c * rotation_from_rotvec(&sigma)));
            prev = d;
        }
        let t = n as f64 * dt;
        let err = attitude_error(&c, &dcm_from_quat(&q(t))).norm();
        // Analytic drift of the uncorrected algorithm: the coning term
        // 1/2 int alpha x w per interval, A^2/(2W) (1 - sin(W dt)/(W dt)) per second
        // with A = W sin a (T&W ch. 11, coning).
        let a = big_w * alpha.sin();
        let drift = a * a / (2.0 * big_w) * (1.0 - (big_w * dt).sin() / (big_w * dt)) * t;
        (err, drift)
    }

    #[test]
    fn coning_correction_reduces_error() {
        // Check the closed-form body rate against the quaternion derivative first.
        let (alpha, big_w) = (0.05_f64, 2.0 * core::f64::consts::PI);
        let (e0, drift) = coning_run(false, alpha, big_w, 0.01, 1000);
        let (e1, _) = coning_run(true, alpha, big_w, 0.01, 1000);
        assert!(
            (e0 - drift).abs() < 0.02 * drift,
            "uncorrected {e0:e} vs analytic drift {drift:e}"
        );
        println!(
            "coning 10 s: uncorrected {e0:.2e} rad (analytic {drift:.2e}), corrected {e1:.2e} rad"
        );
        assert!(e1 < 0.01 * e0, "corrected {e1:e} uncorrected {e0:e}");
    }

    #[test]
    fn coning_rate_is_consistent_with_quaternion() {
        let (alpha, big_w) = (0.3_f64, 1.7_f64);
        let q = |t: f64| {
            Quaternion::new(
                (alpha / 2.0).cos(),
                0.0,
                (alpha / 2.0).sin() * (big_w * t).cos(),
                (alpha / 2.0).sin() * (big_w * t).sin(),
            )
        };
        let t = 0.4;
        let d = 1e-6;
        let qdot = (q(t + d) - q(t - d)) / (2.0 * d);
        let w = 2.0 * q(t).conjugate() * qdot;
        let want = Vector3::new(
            -2.0 * big_w * (alpha / 2.0).sin().powi(2),
            -big_w * alpha.sin() * (big_w * t).sin(),
            big_w * alpha.sin() * (big_w * t).cos(),
        );
        assert!((w.imag() - want).norm() < 1e-8 && w.w.abs() < 1e-8);
    }

    #[test]
    fn small_step_agrees_with_continuous_equations() {
        let s = NavState::new(
            Geodetic::from_degrees(36.4, 127.0, -30.0),
            Vector3::new(1.2, -0.8, 0.1),
            &Euler::from_degrees(2.0, -5.0, 60.0),
        );
        let w = Vector3::new(0.01, -0.02, 0.03);
        let f = Vector3::new(0.1, 0.2, -9.7);
        let dt = 1e-3;
        let mut nav = Strapdown::new(s);
        nav.update_rates(&w, &f, dt);
        let r = mechanization_rates(&s, &w, &f);
        let n = nav.state;
        // Rates of 2e-7 rad/s; the step uses the mean velocity over dt, which
        // differs from the initial one by Vdot dt/2 (0.1 %).
        assert!(((n.lat - s.lat) / dt - r.lat).abs() < 2e-3 * r.lat.abs());
        assert!(((n.lon - s.lon) / dt - r.lon).abs() < 2e-3 * r.lon.abs());
        assert!(((n.h - s.h) / dt - r.h).abs() < 1e-2);
        assert!(((n.v_n - s.v_n) / dt - r.v_n).norm() < 1e-3);
        assert!(((n.c_bn - s.c_bn) / dt - r.c_bn).norm() < 1e-4);
    }

    #[test]
    fn rate_fits_are_exact_for_polynomials() {
        let t = 0.01;
        let c = [
            Vector3::new(1.0, -2.0, 0.5),
            Vector3::new(3.0, 0.1, -1.0),
            Vector3::new(-20.0, 5.0, 2.0),
            Vector3::new(100.0, -50.0, 7.0),
        ];
        let p = |tau: f64| c[0] + c[1] * tau + c[2] * tau * tau + c[3] * tau * tau * tau;
        let ys: Vec<_> = [-2.0, -1.0, 0.0, 1.0].iter().map(|u| p(u * t)).collect();
        let fit = fit_samples(&ys, t);
        for i in 0..4 {
            assert!(
                (fit[i] - c[i]).norm() < 1e-9 * c[i].norm().max(1.0),
                "cubic coefficient {i}"
            );
        }
        let quad = |tau: f64| c[0] + c[1] * tau + c[2] * tau * tau;
        let fit = fit_samples(&[quad(-t), quad(0.0), quad(t)], t);
        assert!(
            (fit[1] - c[1]).norm() < 1e-9 && (fit[2] - c[2]).norm() < 1e-7 && fit[3].norm() == 0.0
        );
        // Constant rates: the rotation vector is w T and the velocity increment in
        // the start frame is int exp([w tau x]) f, to second order.
        let w = [
            Vector3::new(0.3, -0.2, 0.1),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let f = [
            Vector3::new(0.5, 0.2, -9.8),
            Vector3::zeros(),
            Vector3::zeros(),
            Vector3::zeros(),
        ];
        let r = polynomial_increments(&w, &f, t);
        assert!((r.sigma - w[0] * t).norm() < 1e-18);
        let th = w[0] * t;
        let exact = f[0] * t + th.cross(&f[0]) * (t / 2.0) + th.cross(&th.cross(&f[0])) * (t / 6.0);
        assert!((r.dv_b - exact).norm() < 1e-15);
    }

    #[test]
    fn inject_inverts_perturbation() {
        let truth = NavState::new(
            Geodetic::from_degrees(36.4, 127.36, -5.0),
            Vector3::new(1.5, 0.1, 0.0),
            &Euler::from_degrees(1.0, 2.0, 91.0),
        );
        let e = NavError::from_slice(&[1e-6, -2e-6, 3.0, 0.1, -0.2, 0.05, 1e-3, -2e-3, 4e-3]);
        assert_eq!(NavError::from_slice(&e.to_array()), e);
        let ins = truth.perturbed(&e);
        let measured = ins.error_from(&truth);
        assert!((measured.dlat - e.dlat).abs() < 1e-15 && (measured.dh - e.dh).abs() < 1e-12);
        assert!((measured.phi - e.phi).norm() < 1e-7);
        let mut nav = Strapdown::new(ins);
        nav.inject(&e);
        let back = nav.state.error_from(&truth);
        assert!(back.dlat.abs() < 1e-15 && back.dh.abs() < 1e-12 && back.dv_n.norm() < 1e-15);
        assert!(back.phi.norm() < 1e-7, "{:e}", back.phi.norm());
        assert!(horizontal_error(&nav.state, &truth) < 1e-9);
    }

    /// A deterministic uniform generator in [-1, 1) (xorshift64*).
    struct Uniform(u64);
    impl Uniform {
        fn next(&mut self) -> f64 {
            self.0 ^= self.0 >> 12;
            self.0 ^= self.0 << 25;
            self.0 ^= self.0 >> 27;
            let x = self.0.wrapping_mul(0x2545_f491_4f6c_dd1d) >> 11;
            x as f64 / (1u64 << 52) as f64 - 1.0
        }
        fn vector(&mut self, scale: f64) -> Vector3<f64> {
            Vector3::new(self.next(), self.next(), self.next()) * scale
        }
    }

    #[test]
    fn sample_weights_equal_the_fit_then_the_closed_form() {
        let mut u = Uniform(0x9e37_79b9_7f4a_7c15);
        let mut worst = [0.0_f64; 4];
        for _ in 0..2000 {
            let t = [0.01, 0.005, 0.1, 1.0 / 256.0][(u.next().abs() * 4.0) as usize % 4];
            // Random cubic rates (rad/s, m/s^2) sampled at the nodes, and
            // independent random samples.
            let cw = [
                u.vector(2.0),
                u.vector(5.0),
                u.vector(20.0),
                u.vector(100.0),
            ];
            let cf = [
                u.vector(10.0),
                u.vector(5.0),
                u.vector(50.0),
                u.vector(200.0),
            ];
            let poly = |c: &[Vector3<f64>; 4], tau: f64| {
                c[0] + c[1] * tau + c[2] * tau * tau + c[3] * tau * tau * tau
            };
            for random_samples in [false, true] {
                for n in 1..=4 {
                    let mut ws = [Vector3::zeros(); 4];
                    let mut fs = [Vector3::zeros(); 4];
                    for s in 0..n {
                        // Node of sample s (the last one at tau = T).
                        let tau = (s as f64 + 2.0 - n as f64) * t;
                        let tau = if n == 1 { t } else { tau };
                        (ws[s], fs[s]) = if random_samples {
                            (u.vector(2.0), u.vector(15.0))
                        } else {
                            (poly(&cw, tau), poly(&cf, tau))
                        };
                    }
                    let want = polynomial_increments(
                        &fit_samples(&ws[..n], t),
                        &fit_samples(&fs[..n], t),
                        t,
                    );
                    let got = increments_of_samples(n, &ws, &fs, t);
                    // Relative to the size of the inputs' integrals, T max |y_s|:
                    // random samples can integrate to almost nothing, and a
                    // relative error of the cancelled result measures the
                    // conditioning, not the algorithm.
                    let scale = |y: &[Vector3<f64>; 4]| {
                        t * y[..n].iter().map(|v| v.norm()).fold(0.0, f64::max)
                    };
                    let (sw, sf) = (scale(&ws), scale(&fs));
                    let e = ((got.dtheta - want.dtheta).norm() / sw)
                        .max((got.dv - want.dv).norm() / sf)
                        .max((got.sigma - want.sigma).norm() / sw)
                        .max((got.dv_b - want.dv_b).norm() / sf);
                    worst[n - 1] = worst[n - 1].max(e);
                }
            }
        }
        // Measured: 0, 3.0e-16, 4.2e-16 and 5.4e-16 for 1 to 4 samples.
        println!("sample weights vs fit + closed form, worst relative by samples: {worst:?}");
        for (n, e) in worst.iter().enumerate() {
            assert!(*e < 1e-15, "{} samples: {e:e}", n + 1);
        }
        let none = increments_of_samples(0, &[Vector3::zeros(); 4], &[Vector3::zeros(); 4], 0.01);
        assert_eq!(none.sigma, Vector3::zeros());
        assert_eq!(none.dv_b, Vector3::zeros());
    }

    #[test]
    fn sin_cos_near_matches_libm() {
        let mut u = Uniform(12345);
        let mut worst: f64 = 0.0;
        for _ in 0..100_000 {
            let lat = u.next() * 1.58;
            let d =
                u.next() * NEAR_LATITUDE * [1.0, 1e-3, 1e-6][(u.next().abs() * 3.0) as usize % 3];
            let lat1 = lat + d;
            let (s0, c0) = sin_cos(lat);
            let (s, c) = sin_cos_near(s0, c0, lat, lat1);
            let (se, ce) = sin_cos(lat1);
            worst = worst.max((s - se).abs()).max((c - ce).abs());
        }
        // Measured: 1.1e-16 (an ulp of values near 1).
        println!("sin_cos_near vs sin_cos: worst {worst:.1e}");
        assert!(worst < 4.5e-16, "{worst:e}");
        // Beyond the series' range: the exact functions.
        let (s0, c0) = sin_cos(0.3);
        assert_eq!(sin_cos_near(s0, c0, 0.3, 0.31), sin_cos(0.31));
    }

    #[test]
    fn small_rotation_matches_rotation_from_rotvec() {
        let mut u = Uniform(777);
        let mut worst: f64 = 0.0;
        for k in 0..100_000 {
            let scale = [1e-2, 1e-3, 1e-5, 1e-8][k % 4];
            let phi = u.vector(scale / 3f64.sqrt());
            worst = worst.max((small_rotation(&phi) - rotation_from_rotvec(&phi)).amax());
        }
        // Measured: 1.1e-16.
        println!("small_rotation vs rotation_from_rotvec: worst {worst:.1e}");
        assert!(worst < 4.5e-16, "{worst:e}");
        let big = Vector3::new(0.3, -0.2, 0.1);
        assert_eq!(small_rotation(&big), rotation_from_rotvec(&big));
    }

    /// A varied body motion: turning at up to `scale` x 0.5 rad/s and
    /// accelerating at up to a few m/s^2 on top of the support force.
    fn varied_imu(t: f64, scale: f64) -> (Vector3<f64>, Vector3<f64>) {
        let w = Vector3::new(
            0.3 * (1.3 * t).sin() + 0.05 * (7.0 * t).cos(),
            0.2 * (0.7 * t).cos() - 0.1 * (3.1 * t).sin(),
            0.1 + 0.4 * (0.2 * t).sin(),
        ) * scale;
        let f = Vector3::new(
            2.0 * (0.4 * t).sin() + 0.3 * (5.0 * t).cos(),
            1.5 * (0.9 * t).cos(),
            -9.8 + 0.5 * (2.0 * t).sin(),
        );
        (w, f)
    }

    /// Position (m), velocity (m/s) and attitude (rad) differences of two states.
    fn state_difference(a: &NavState, b: &NavState) -> (f64, f64, f64) {
        let e = a.error_from(b);
        (
            e.position_ned(b.lat, b.h).norm(),
            e.dv_n.norm(),
            e.phi.norm(),
        )
    }

    #[test]
    fn fast_step_matches_the_reference_step() {
        // (latitude deg, dt s, rate scale, samples, compensate, speed m/s)
        let cases = [
            (0.0, 0.01, 1.0, RateSamples::Instantaneous, true, 3.0),
            (36.4, 0.01, 1.0, RateSamples::Instantaneous, true, 3.0),
            (70.0, 0.01, 1.0, RateSamples::Instantaneous, true, 3.0),
            (-70.0, 0.01, 4.0, RateSamples::Instantaneous, true, 3.0),
            // Fast: 250 m/s north-east.
            (70.0, 0.01, 1.0, RateSamples::Instantaneous, true, 250.0),
            // Large steps: rotation vectors beyond the series' range.
            (36.4, 0.1, 4.0, RateSamples::Instantaneous, true, 3.0),
            (36.4, 0.1, 1.0, RateSamples::Instantaneous, true, 250.0),
            (70.0, 0.01, 1.0, RateSamples::IntervalAverage, true, 3.0),
            (36.4, 0.01, 1.0, RateSamples::Instantaneous, false, 3.0),
        ];
        for (lat, dt, scale, samples, compensate, speed) in cases {
            let s0 = NavState::new(
                Geodetic::from_degrees(lat, 127.36, -20.0),
                Vector3::new(0.8 * speed, -0.6 * speed, 0.2),
                &Euler::from_degrees(2.0, -3.0, 40.0),
            );
            let mut fast = Strapdown::new(s0);
            let mut reference = Strapdown::new(s0);
            // The reference from an initial attitude one rounding away: how far
            // rounding alone carries the runs apart.
            let mut nudged = Strapdown::new(NavState {
                c_bn: s0.c_bn * rotation_from_rotvec(&Vector3::new(0.0, 0.0, 2e-16)),
                ..s0
            });
            for nav in [&mut fast, &mut reference, &mut nudged] {
                nav.samples = samples;
                nav.compensate = compensate;
            }
            let mut run = (0.0_f64, 0.0_f64, 0.0_f64);
            let mut rounding = (0.0_f64, 0.0_f64, 0.0_f64);
            for k in 1..=10_000 {
                let (w, f) = varied_imu(k as f64 * dt, scale);
                // Support against gravity plus the varied acceleration, from the
                // reference's state (the same inputs for both).
                let r = reference.state;
                let f = r.c_bn.transpose() * -normal_gravity_ned(r.lat, r.h)
                    + (f - Vector3::new(0.0, 0.0, -9.8))
                    - r.c_bn.transpose() * (r.v_n - s0.v_n) * 0.05;
                fast.update_rates(&w, &f, dt);
                reference.update_rates_reference(&w, &f, dt);
                nudged.update_rates_reference(&w, &f, dt);
                let (p, v, a) = state_difference(&fast.state, &reference.state);
                run = (run.0.max(p), run.1.max(v), run.2.max(a));
                let (p, v, a) = state_difference(&nudged.state, &reference.state);
                rounding = (rounding.0.max(p), rounding.1.max(v), rounding.2.max(a));
            }
            println!(
                "  reference nudged by 2e-16 rad: position {:.1e} m, velocity {:.1e} m/s, attitude {:.1e} rad",
                rounding.0, rounding.1, rounding.2
            );
            println!(
                "lat {lat} dt {dt} x{scale} {samples:?} compensate {compensate} {speed} m/s: \
                 position {:.1e} m, velocity {:.1e} m/s, attitude {:.1e} rad \
                 (speed {:.0} m/s)",
                run.0,
                run.1,
                run.2,
                fast.state.v_n.norm()
            );
            // Bounds a small factor above the measured differences: at 100 Hz
            // (100 s, 3 and 250 m/s) at most 5.1e-12 m, 1.8e-12 m/s and
            // 5.9e-15 rad; with dt = 0.1 s (1000 s, rotation vectors up to
            // 0.25 rad) 1.2e-8 m, 3.1e-11 m/s and 1.1e-14 rad. The reference
            // nudged by one rounding of its attitude drifts from itself by as
            // much (up to 1.2e-11 m, 1.1e-12 m/s, 4.9e-15 rad at 100 Hz;
            // 9.1e-9 m, 1.5e-11 m/s at dt = 0.1 s): the attitudes differ by
            // some ulps, g times that over the run is the velocity difference,
            // and a latitude ulp is 4e-10 m.
            let (bp, bv, ba) = if dt > 0.05 {
                (1e-7, 2e-10, 1e-13)
            } else {
                (5e-11, 6e-12, 2e-14)
            };
            assert!(run.0 < bp, "position {:e}", run.0);
            assert!(run.1 < bv, "velocity {:e}", run.1);
            assert!(run.2 < ba, "attitude {:e}", run.2);
        }
    }

    #[test]
    fn attitude_stays_orthonormal_for_one_hour() {
        let s0 = start(36.4);
        let mut nav = Strapdown::new(s0);
        let dt = 0.01;
        let mut worst: f64 = 0.0;
        for k in 1..=360_000 {
            let t = k as f64 * dt;
            // Keep the speed bounded: the varied motion's forces, level on average.
            let (w, mut f) = varied_imu(t, 1.0);
            f = nav.state.c_bn.transpose() * -normal_gravity_ned(nav.state.lat, nav.state.h)
                + (f - Vector3::new(0.0, 0.0, -9.8)) * 0.01;
            nav.update_rates(&w, &f, dt);
            let c = nav.state.c_bn;
            worst = worst.max((c.transpose() * c - Matrix3::identity()).amax());
        }
        println!("1 h rotating: worst |C^T C - I| {worst:.1e}");
        assert!(worst < 1e-14, "{worst:e}");
    }
}
