//! Operating points, covariances and the dense / hand-written baselines shared by
//! the benches of this crate. Every baseline is checked against the generated
//! code (1e-12 relative) before anything is timed.
#![allow(dead_code)]

use std::time::{Duration, Instant};

use models::leveling::model::{Leveling6Input, Leveling6Noise, Leveling6Params};
use models::marker::model::{Marker9Input, Marker9Noise, Marker9Params};
use models::px4_ekf24::{Px4Ekf24Input, Px4Ekf24Noise, Px4Ekf24Params};
use models::sdins25::model::{Sdins25Input, Sdins25Noise, Sdins25Params};
use nav_runtime::attitude::Euler;
use nav_runtime::model::{Model, Sensor};
use nav_runtime::nalgebra::{SMatrix, SVector, Vector3};

/// IMU period of the SDINS-25 filter (100 Hz).
pub const DT_SDINS: f64 = 0.01;

/// A cruising vehicle at 37 deg N, 50 m deep, 1.5 m/s, pitched and heading NE.
pub fn sdins25_point() -> (SVector<f64, 25>, Sdins25Input, Sdins25Params, Sdins25Noise) {
    let c_bn = Euler::from_degrees(2.0, -3.0, 40.0).c_bn();
    let input = Sdins25Input {
        latitude: 37.0f64.to_radians(),
        height: -50.0,
        velocity: Vector3::new(1.15, 0.96, 0.05),
        c_bn,
        specific_force: Vector3::new(0.02, -0.01, -9.80),
    };
    let noise = Sdins25Noise {
        accel_noise: Vector3::repeat((1e-3f64).powi(2)),
        gyro_noise: Vector3::repeat((3e-6f64).powi(2)),
    };
    // Error states are zero after every feedback.
    (SVector::zeros(), input, Sdins25Params::default(), noise)
}

pub fn leveling6_point() -> (
    SVector<f64, 6>,
    Leveling6Input,
    Leveling6Params,
    Leveling6Noise,
) {
    let a = Vector3::new(0.05, 0.02, 1.0).normalize();
    let x = SVector::<f64, 6>::new(1.2, 0.05, -0.02, a[0], a[1], a[2]);
    let input = Leveling6Input {
        gyro: Vector3::new(0.01, -0.02, 0.05),
        specific_force: Vector3::new(0.1, -0.2, -9.79),
        earth_rate_body: Vector3::new(5.8e-5, 1e-6, -4.4e-5),
    };
    let params = Leveling6Params { gravity: 9.80 };
    let noise = Leveling6Noise {
        accel_noise: Vector3::repeat(1e-4),
        gyro_noise: Vector3::repeat(1e-8),
    };
    (x, input, params, noise)
}

pub fn marker9_point() -> (SVector<f64, 9>, Marker9Input, Marker9Params, Marker9Noise) {
    let x =
        SVector::<f64, 9>::from_column_slice(&[3.0, -2.0, 10.0, 0.4, 0.05, 0.01, 0.03, -0.02, 1.1]);
    let input = Marker9Input {
        gyro: Vector3::new(0.01, 0.02, -0.03),
        acceleration: Vector3::new(0.05, 0.0, -0.01),
    };
    let noise = Marker9Noise {
        velocity_noise: Vector3::repeat(1e-6),
        attitude_noise: Vector3::repeat(1e-8),
    };
    (x, input, Marker9Params::default(), noise)
}

/// A well-conditioned symmetric positive definite covariance with all entries
/// nonzero (no accidental zeros that the FPU could shortcut), scaled per state.
pub fn covariance<const N: usize>(sigmas: &[f64; N]) -> SMatrix<f64, N, N> {
    let mut seed = 0x9e37_79b9_7f4a_7c15u64;
    let mut next = || {
        seed = seed.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = seed;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0
    };
    let l = SMatrix::<f64, N, N>::from_fn(|_, _| next());
    let corr = l * l.transpose() / N as f64 + SMatrix::<f64, N, N>::identity();
    let d = SMatrix::<f64, N, N>::from_diagonal(&SVector::<f64, N>::from_column_slice(sigmas));
    d * corr * d
}

/// Typical SDINS-25 error sigmas (rad for latitude/longitude, m, m/s, rad, ...).
pub fn sdins25_covariance() -> SMatrix<f64, 25, 25> {
    let mut s = [0.0; 25];
    s[0] = 1.5e-6;
    s[1] = 2.0e-6;
    s[2] = 2.0;
    s[3..6].fill(0.1);
    s[6..8].fill(1e-3);
    s[8] = 1e-2;
    s[9..12].fill(5e-3);
    s[12..15].fill(5e-6);
    s[15..17].fill(3.0);
    s[17] = 0.2;
    s[18..21].fill(0.01);
    s[21] = 0.02;
    s[22..25].fill(8e-3);
    covariance(&s)
}

pub fn leveling6_covariance() -> SMatrix<f64, 6, 6> {
    covariance(&[0.5, 0.5, 0.5, 0.3, 0.3, 0.1])
}

/// PX4's 24-state model in forward flight at 100 Hz (summed IMU increments
/// over 10 ms): pitched and heading NE at 5 m/s, a little wind.
pub fn px4_ekf24_point() -> (
    SVector<f64, 24>,
    Px4Ekf24Input,
    Px4Ekf24Params,
    Px4Ekf24Noise,
) {
    let dt = 0.01;
    let q = nav_runtime::nalgebra::UnitQuaternion::from_euler_angles(
        2f64.to_radians(),
        -3f64.to_radians(),
        40f64.to_radians(),
    );
    let mut x = SVector::<f64, 24>::zeros();
    x.fixed_rows_mut::<4>(0)
        .copy_from_slice(&[q.w, q.i, q.j, q.k]);
    let rest = [
        3.8, 3.2, -0.4, // velocity
        120.0, -40.0, -30.0, // position
        1e-3, -2e-3, 5e-4, // gyro bias
        0.05, -0.03, 0.08, // accel bias
        0.21, 0.02, 0.42, // earth field
        0.01, -0.02, 0.015, // body field
        3.0, -2.0, // wind
    ];
    x.rows_mut(4, 20).copy_from_slice(&rest);
    let input = Px4Ekf24Input {
        delta_velocity: Vector3::new(0.2, -0.1, -9.78) * dt,
        delta_velocity_dt: dt,
        delta_angle: Vector3::new(0.01, -0.02, 0.05) * dt,
        delta_angle_dt: dt,
    };
    let noise = Px4Ekf24Noise {
        delta_velocity_noise: Vector3::repeat((0.35 * dt).powi(2)),
        delta_angle_noise: Vector3::repeat((0.015 * dt).powi(2)),
    };
    (x, input, Px4Ekf24Params { gravity: 9.80665 }, noise)
}

pub fn px4_ekf24_covariance() -> SMatrix<f64, 24, 24> {
    let mut s = [0.0; 24];
    s[..4].fill(0.02);
    s[4..7].fill(0.5);
    s[7..10].fill(2.0);
    s[10..13].fill(1e-3);
    s[13..16].fill(0.05);
    s[16..19].fill(0.02);
    s[19..22].fill(0.01);
    s[22..24].fill(1.0);
    covariance(&s)
}

pub fn marker9_covariance() -> SMatrix<f64, 9, 9> {
    covariance(&[1.0, 1.0, 0.5, 0.1, 0.1, 0.1, 0.02, 0.02, 0.1])
}

/// `Phi = I + F dt` (continuous models) or `Phi = df/dx` (discrete ones), dense.
pub fn dense_phi<Mo: Model<N>, const N: usize>(
    x: &SVector<f64, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    dt: f64,
) -> SMatrix<f64, N, N> {
    let j = Mo::jacobian(x, u, p, dt);
    if Mo::DISCRETE {
        j
    } else {
        SMatrix::<f64, N, N>::identity() + j * dt
    }
}

/// The dense baseline: `P <- Phi P Phi^T + Qd` with nalgebra's fixed-size products.
#[inline(never)]
pub fn dense_propagate<const N: usize>(
    p: &mut SMatrix<f64, N, N>,
    phi: &SMatrix<f64, N, N>,
    qd: &SMatrix<f64, N, N>,
) {
    *p = phi * *p * phi.transpose() + qd;
}

/// The dense baseline including the model evaluation a hand-coded dense filter
/// would do each step: `F` (or `Phi`) from `jacobian`, `Qd` from `process_noise`.
#[inline(never)]
pub fn dense_propagate_with_model<Mo: Model<N>, const N: usize>(
    cov: &mut SMatrix<f64, N, N>,
    x: &SVector<f64, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    q: &Mo::Noise,
    dt: f64,
) {
    let phi = dense_phi::<Mo, N>(x, u, p, dt);
    let qd = Mo::process_noise(x, u, p, q, dt);
    *cov = phi * *cov * phi.transpose() + qd;
}

/// The generated propagation, behind the same call boundary as the baselines.
#[inline(never)]
pub fn generated_propagate<Mo: Model<N>, const N: usize>(
    cov: &mut SMatrix<f64, N, N>,
    x: &SVector<f64, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    q: &Mo::Noise,
    dt: f64,
) {
    Mo::propagate_covariance(cov, x, u, p, q, dt);
}

/// The SDINS-25 structure a careful engineer exploits by hand: `F` is nonzero
/// only in rows 0..9 and columns 0..15 (navigation errors driven by navigation
/// errors and IMU biases), so `Phi` has unit rows 9..25, and `Qd` lives in the
/// velocity/attitude block 3..9. Precomputed per step: `F[0..9, 0..15] dt`
/// and `qd = Qd[3..9, 3..9]`.
pub struct HandWrittenSdins25 {
    /// `(F dt)[0..9, 0..15]` transposed: `fdt_t[k][i] = F[i][k] dt`.
    pub fdt_t: [[f64; 9]; 15],
    /// `Qd[3..9, 3..9]`.
    pub qd: [[f64; 6]; 6],
}

impl HandWrittenSdins25 {
    /// Extracts the blocks from the model's dense `F` and `Qd`, asserting that
    /// everything outside them is zero (the premise of the hand-written code).
    pub fn new(f: &SMatrix<f64, 25, 25>, qd: &SMatrix<f64, 25, 25>, dt: f64) -> Self {
        for i in 0..25 {
            for j in 0..25 {
                if i >= 9 || j >= 15 {
                    assert_eq!(f[(i, j)], 0.0, "F({i},{j}) outside the assumed block");
                }
                if !(3..9).contains(&i) || !(3..9).contains(&j) {
                    assert_eq!(qd[(i, j)], 0.0, "Qd({i},{j}) outside the assumed block");
                }
            }
        }
        Self {
            fdt_t: core::array::from_fn(|k| core::array::from_fn(|i| f[(i, k)] * dt)),
            qd: core::array::from_fn(|i| core::array::from_fn(|j| qd[(i + 3, j + 3)])),
        }
    }

    /// `P <- Phi P Phi^T + Qd`. Rows 9..25 of `Phi` are unit rows, so only rows
    /// (and, mirrored, columns) 0..9 change: first `A = (Phi P)[0..9, ..]`
    /// (25 columns of 9 entries, 15 terms each), then `R = A Phi^T` for the
    /// 9 x 9 block (columns 9.. of `R` are those of `A`), plus `Qd`. The inner
    /// loops run over the 9 rows with independent accumulators, so they
    /// vectorize. 3,375 + 1,215 multiply-adds (the 9 x 9 block is computed
    /// whole, then its upper triangle is stored and mirrored).
    #[inline(never)]
    pub fn propagate(&self, p: &mut SMatrix<f64, 25, 25>) {
        let s = p.as_mut_slice(); // column-major; P symmetric, so column j == row j
                                  // at[j][i] = A[i][j]
        let mut at = [[0.0f64; 9]; 25];
        for (j, a) in at.iter_mut().enumerate() {
            let col: &[f64; 25] = s[25 * j..25 * j + 25].try_into().unwrap();
            let mut acc: [f64; 9] = col[..9].try_into().unwrap();
            for (fk, &pkj) in self.fdt_t.iter().zip(&col[..15]) {
                for (x, &f) in acc.iter_mut().zip(fk) {
                    *x += f * pkj;
                }
            }
            *a = acc;
        }
        for j in 0..9 {
            // R[i][j] = A[i][j] + sum_k A[i][k] F[j][k] dt, for all i < 9 at once.
            let mut acc = at[j];
            for (ak, fk) in at[..15].iter().zip(&self.fdt_t) {
                let fjk = fk[j];
                for (x, &a) in acc.iter_mut().zip(ak) {
                    *x += a * fjk;
                }
            }
            for (i, &v) in acc.iter().enumerate().take(j + 1) {
                let v = if i >= 3 { v + self.qd[i - 3][j - 3] } else { v };
                s[i + 25 * j] = v;
                s[j + 25 * i] = v;
            }
        }
        for (j, a) in at.iter().enumerate().skip(9) {
            for (i, &v) in a.iter().enumerate() {
                s[i + 25 * j] = v;
                s[j + 25 * i] = v;
            }
        }
    }
}

/// `max |a - b| / max |b|`.
pub fn rel_diff<const R: usize, const C: usize>(
    a: &SMatrix<f64, R, C>,
    b: &SMatrix<f64, R, C>,
) -> f64 {
    (a - b).amax() / b.amax().max(f64::MIN_POSITIVE)
}

/// Dense Joseph update of a sensor, what one writes without the generator:
/// `h`, dense `H` from `Sensor::jacobian`, `S = H P H^T + R` (Cholesky),
/// `K = P H^T S^-1`, `x += K nu`, `P <- (I - K H) P (I - K H)^T + K R K^T`.
#[inline(never)]
#[allow(clippy::too_many_arguments)]
pub fn dense_joseph_update<S, const N: usize, const M: usize>(
    x: &mut SVector<f64, N>,
    cov: &mut SMatrix<f64, N, N>,
    z: &SVector<f64, M>,
    r: &SMatrix<f64, M, M>,
    u: &<S::Model as Model<N>>::Input,
    p: &<S::Model as Model<N>>::Params,
    aux: &S::Aux,
) where
    S: Sensor<N, M>,
{
    let h = S::predict(x, u, p, aux);
    let hm = S::jacobian(x, u, p, aux);
    let mut nu = z - h;
    for i in 0..M {
        if S::ANGLES[i] {
            nu[i] = nav_runtime::math::wrap_angle(nu[i]);
        }
    }
    let pht = *cov * hm.transpose();
    let s = hm * pht + r;
    let chol = s.cholesky().expect("S positive definite");
    let k = chol.solve(&pht.transpose()).transpose();
    *x += k * nu;
    let ikh = SMatrix::<f64, N, N>::identity() - k * hm;
    *cov = ikh * *cov * ikh.transpose() + k * r * k.transpose();
}

/// Times `iters` calls of `step` on a state that starts from `init` and is
/// restored every `reset_every` calls (amortized; the state stays hot in cache,
/// as a filter's covariance is). The restore is inside the timed loop and costs
/// every variant the same.
pub fn time_in_place<T: Clone>(
    iters: u64,
    init: &T,
    reset_every: u64,
    mut step: impl FnMut(&mut T),
) -> Duration {
    let mut state = init.clone();
    let start = Instant::now();
    for i in 0..iters {
        if i % reset_every == 0 && i > 0 {
            state.clone_from(init);
        }
        step(std::hint::black_box(&mut state));
    }
    let elapsed = start.elapsed();
    std::hint::black_box(&state);
    elapsed
}
