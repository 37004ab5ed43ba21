//! An evaluation of the PX4 24-state prediction that shares nothing with the
//! generator: the transition written out by hand in plain Rust and
//! differentiated numerically exactly, by forward-mode dual numbers (one
//! tangent per column of `Phi` or `G`).

use core::ops::{Add, Mul, Neg, Sub};

use nav_runtime::nalgebra::{SMatrix, SVector};

/// A number with one tangent: `value + tangent * epsilon`, `epsilon^2 = 0`.
#[derive(Clone, Copy, Debug)]
pub struct Dual {
    pub value: f64,
    pub tangent: f64,
}

impl Dual {
    fn constant(value: f64) -> Self {
        Dual {
            value,
            tangent: 0.0,
        }
    }
}

impl Add for Dual {
    type Output = Dual;
    fn add(self, b: Dual) -> Dual {
        Dual {
            value: self.value + b.value,
            tangent: self.tangent + b.tangent,
        }
    }
}

impl Sub for Dual {
    type Output = Dual;
    fn sub(self, b: Dual) -> Dual {
        Dual {
            value: self.value - b.value,
            tangent: self.tangent - b.tangent,
        }
    }
}

impl Mul for Dual {
    type Output = Dual;
    fn mul(self, b: Dual) -> Dual {
        Dual {
            value: self.value * b.value,
            tangent: self.tangent * b.value + self.value * b.tangent,
        }
    }
}

impl Neg for Dual {
    type Output = Dual;
    fn neg(self) -> Dual {
        Dual {
            value: -self.value,
            tangent: -self.tangent,
        }
    }
}

/// The inputs of one prediction step, as PX4 passes them.
#[derive(Clone, Copy, Debug)]
pub struct Step {
    pub delta_velocity: [f64; 3],
    pub delta_velocity_dt: f64,
    pub delta_angle: [f64; 3],
    pub delta_angle_dt: f64,
    pub gravity: f64,
}

/// The next state from the state `x` (24) and the noise `w` (velocity then
/// angle increment, 6), written directly from the published equations:
/// `q+ = q ⊗ [1, a/2]` with `a = delta_angle + w_a - gyro_bias dt_a`;
/// `v+ = v + R(q) (delta_velocity + w_v - accel_bias dt_v) + [0, 0, g dt_v]`;
/// `p+ = p + v dt_v`; every other state constant.
pub fn transition(x: &[Dual; 24], w: &[Dual; 6], s: &Step) -> [Dual; 24] {
    let c = Dual::constant;
    let half = c(0.5);
    let two = c(2.0);
    let one = c(1.0);
    let (q0, q1, q2, q3) = (x[0], x[1], x[2], x[3]);
    let a: [Dual; 3] =
        core::array::from_fn(|i| c(s.delta_angle[i]) + w[3 + i] - x[10 + i] * c(s.delta_angle_dt));
    let (r0, r1, r2, r3) = (one, half * a[0], half * a[1], half * a[2]);
    // Hamilton product q ⊗ r.
    let q_next = [
        q0 * r0 - q1 * r1 - q2 * r2 - q3 * r3,
        q0 * r1 + q1 * r0 + q2 * r3 - q3 * r2,
        q0 * r2 - q1 * r3 + q2 * r0 + q3 * r1,
        q0 * r3 + q1 * r2 - q2 * r1 + q3 * r0,
    ];
    // Body-to-NED rotation of the unit quaternion, in the unit-norm form.
    let rotation = [
        [
            one - two * (q2 * q2 + q3 * q3),
            two * (q1 * q2 - q0 * q3),
            two * (q1 * q3 + q0 * q2),
        ],
        [
            two * (q1 * q2 + q0 * q3),
            one - two * (q1 * q1 + q3 * q3),
            two * (q2 * q3 - q0 * q1),
        ],
        [
            two * (q1 * q3 - q0 * q2),
            two * (q2 * q3 + q0 * q1),
            one - two * (q1 * q1 + q2 * q2),
        ],
    ];
    let dv: [Dual; 3] = core::array::from_fn(|i| {
        c(s.delta_velocity[i]) + w[i] - x[13 + i] * c(s.delta_velocity_dt)
    });
    let mut next = *x;
    next[..4].copy_from_slice(&q_next);
    for i in 0..3 {
        let rotated = rotation[i][0] * dv[0] + rotation[i][1] * dv[1] + rotation[i][2] * dv[2];
        next[4 + i] = x[4 + i] + rotated;
        next[7 + i] = x[7 + i] + x[4 + i] * c(s.delta_velocity_dt);
    }
    next[6] = next[6] + c(s.gravity * s.delta_velocity_dt);
    next
}

fn seeded(
    x: &SVector<f64, 24>,
    w: &[f64; 6],
    state_seed: Option<usize>,
    noise_seed: Option<usize>,
) -> ([Dual; 24], [Dual; 6]) {
    let xs = core::array::from_fn(|i| Dual {
        value: x[i],
        tangent: f64::from(state_seed == Some(i)),
    });
    let ws = core::array::from_fn(|i| Dual {
        value: w[i],
        tangent: f64::from(noise_seed == Some(i)),
    });
    (xs, ws)
}

/// The next state (no noise).
pub fn next_state(x: &SVector<f64, 24>, s: &Step) -> SVector<f64, 24> {
    let (xs, ws) = seeded(x, &[0.0; 6], None, None);
    let next = transition(&xs, &ws, s);
    SVector::from_fn(|i, _| next[i].value)
}

/// `Phi = d next / d x`, one column per dual evaluation.
pub fn transition_matrix(x: &SVector<f64, 24>, s: &Step) -> SMatrix<f64, 24, 24> {
    let mut phi = SMatrix::zeros();
    for j in 0..24 {
        let (xs, ws) = seeded(x, &[0.0; 6], Some(j), None);
        let next = transition(&xs, &ws, s);
        for i in 0..24 {
            phi[(i, j)] = next[i].tangent;
        }
    }
    phi
}

/// `G = d next / d w` at `w = 0`.
pub fn noise_matrix(x: &SVector<f64, 24>, s: &Step) -> SMatrix<f64, 24, 6> {
    let mut g = SMatrix::zeros();
    for j in 0..6 {
        let (xs, ws) = seeded(x, &[0.0; 6], None, Some(j));
        let next = transition(&xs, &ws, s);
        for i in 0..24 {
            g[(i, j)] = next[i].tangent;
        }
    }
    g
}

/// `Qd = G diag(variances) G^T`.
pub fn process_noise(x: &SVector<f64, 24>, s: &Step, variances: &[f64; 6]) -> SMatrix<f64, 24, 24> {
    let g = noise_matrix(x, s);
    let v = SMatrix::<f64, 6, 6>::from_diagonal(&SVector::from_column_slice(variances));
    g * v * g.transpose()
}
