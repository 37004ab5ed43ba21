//! Small models implementing the traits of [`crate::model`] by hand, for the
//! engine's tests. They do not depend on the code generator, so they are an
//! independent check of the engine (and the generator can be checked against
//! them).
//!
//! - [`Cvb`]: 1-D inertial toy, states (p, v, b): `p' = v`, `v' = a - b`,
//!   `b' = w_b`, input the measured acceleration `a`, white acceleration noise
//!   and a bias random walk. `F` is nilpotent (`F^3 = 0`), so `exp(F dt)` and
//!   `Qd` have closed forms.
//! - [`Osc`]: harmonic oscillator (theta, omega) with `omega' = -w^2 theta`, whose
//!   transition matrix is a rotation; its sensor [`Angle`] measures an angle.
//! - [`Dcv`]: a discrete constant-velocity model.
//! - [`Rows`]: a 4-state model whose covariance propagation runs the row
//!   kernel over a [`Model::PROPAGATION`] structure (two changed rows, `Qd`
//!   inside and outside them), with `F` taken from the input, so a test can
//!   make any step (a zeroed row, an overflow).
//! - [`Tilt`]: a planar error-state AHRS, states (attitude error `phi`, gyro
//!   bias error `db`), input the nominal angle; its two sensors [`TiltCos`]
//!   and [`TiltSin`] read the two components of gravity (an accelerometer
//!   seen as two scalar sensors, fused at the same epoch) through the
//!   nominal angle of the input, as the AHRS of docs/ulog.md does with
//!   `C^_b^n`. [`TiltNominal`] is its nominal solution.

use nalgebra::{SMatrix, SVector};

use crate::error_state::{Mechanization, NominalState};
use crate::model::{Model, Record, Sensor};

/// Declares a record of named `f64` fields.
macro_rules! record {
    ($name:ident { $($field:ident),+ $(,)? }) => {
        #[derive(Clone, Copy, Debug, Default, PartialEq)]
        pub struct $name {
            $(pub $field: f64),+
        }
        impl Record for $name {
            const LEN: usize = [$(stringify!($field)),+].len();
            const NAMES: &'static [&'static str] = &[$(stringify!($field)),+];
            fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
                let mut i = 0;
                $(let $field = f(i); i += 1;)+
                let _ = i;
                Self { $($field),+ }
            }
            fn get(&self, i: usize) -> f64 {
                [$(self.$field),+].get(i).copied().unwrap_or(f64::NAN)
            }
        }
    };
}

record!(CvbState { p, v, b });
record!(CvbInput { a });
record!(CvbNoise { q_a, q_b });
record!(Offset { offset });
record!(OscParams { w });
record!(OscNoise { q });
record!(DcvNoise { var_v });
record!(RowsInput { f00, f01, f22, f23 });
record!(RowsNoise { q1, q2 });
record!(TiltInput { theta });
record!(TiltState { phi, db });
record!(TiltNoise { q_gyro, q_bias });

/// Dense `(h, P H^T, H P H^T)` for hand-written sensors.
pub fn dense_terms<const N: usize, const M: usize>(
    cov: &SMatrix<f64, N, N>,
    h: SVector<f64, M>,
    hm: &SMatrix<f64, N, M>,
) -> (SVector<f64, M>, SMatrix<f64, N, M>, SMatrix<f64, M, M>) {
    let u = cov * hm;
    (h, u, hm.transpose() * u)
}

/// `P <- Phi P Phi^T + Qd` reading only the upper triangle of `P`, as the
/// contract requires of generated code.
fn propagate_dense<const N: usize>(
    cov: &mut SMatrix<f64, N, N>,
    phi: &SMatrix<f64, N, N>,
    qd: &SMatrix<f64, N, N>,
) {
    let mut sym = *cov;
    for c in 0..N {
        for r in 0..c {
            sym[(c, r)] = sym[(r, c)];
        }
    }
    let mut out = phi * sym * phi.transpose() + qd;
    for c in 0..N {
        for r in 0..c {
            out[(c, r)] = out[(r, c)];
        }
    }
    *cov = out;
}

/// The 1-D inertial toy (see module docs).
pub struct Cvb;

impl Cvb {
    /// `F = df/dx`.
    pub fn f() -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::new(0.0, 1.0, 0.0, 0.0, 0.0, -1.0, 0.0, 0.0, 0.0)
    }
}

impl Model<3> for Cvb {
    type Input = CvbInput;
    type Params = ();
    type Noise = CvbNoise;
    type State = CvbState;
    const NAME: &'static str = "Cvb";
    const DISCRETE: bool = false;
    const STATE_NAMES: [&'static str; 3] = ["p", "v", "b"];
    const JACOBIAN_SPARSITY: [[bool; 3]; 3] = [
        [false, true, false],
        [false, false, true],
        [false, false, false],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;

    fn transition(x: &SVector<f64, 3>, u: &CvbInput, _: &(), dt: f64) -> SVector<f64, 3> {
        SVector::<f64, 3>::new(x[0] + x[1] * dt, x[1] + (u.a - x[2]) * dt, x[2])
    }

    fn jacobian(_: &SVector<f64, 3>, _: &CvbInput, _: &(), _: f64) -> SMatrix<f64, 3, 3> {
        Self::f()
    }

    fn process_noise(
        _: &SVector<f64, 3>,
        _: &CvbInput,
        _: &(),
        q: &CvbNoise,
        dt: f64,
    ) -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::from_diagonal(&SVector::<f64, 3>::new(0.0, q.q_a * dt, q.q_b * dt))
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 3, 3>,
        x: &SVector<f64, 3>,
        u: &CvbInput,
        p: &(),
        q: &CvbNoise,
        dt: f64,
    ) {
        let phi = SMatrix::<f64, 3, 3>::identity() + Self::f() * dt;
        propagate_dense(cov, &phi, &Self::process_noise(x, u, p, q, dt));
    }
}

/// Position of [`Cvb`] plus a known offset carried as auxiliary input.
pub struct Pos;

impl Sensor<3, 1> for Pos {
    type Model = Cvb;
    type Aux = Offset;
    const NAME: &'static str = "pos";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 3]; 1] = [[true, false, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 3>, _: &CvbInput, _: &(), aux: &Offset) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(x[0] + aux.offset)
    }

    fn jacobian(_: &SVector<f64, 3>, _: &CvbInput, _: &(), _: &Offset) -> SMatrix<f64, 1, 3> {
        SMatrix::<f64, 1, 3>::new(1.0, 0.0, 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 3, 3>,
        x: &SVector<f64, 3>,
        u: &CvbInput,
        p: &(),
        aux: &Offset,
    ) -> (SVector<f64, 1>, SMatrix<f64, 3, 1>, SMatrix<f64, 1, 1>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// Position and velocity of [`Cvb`].
pub struct PosVel;

impl Sensor<3, 2> for PosVel {
    type Model = Cvb;
    type Aux = ();
    const NAME: &'static str = "posvel";
    const ANGLES: [bool; 2] = [false, false];
    const JACOBIAN_SPARSITY: [[bool; 3]; 2] = [[true, false, false], [false, true, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 3>, _: &CvbInput, _: &(), _: &()) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(x[0], x[1])
    }

    fn jacobian(_: &SVector<f64, 3>, _: &CvbInput, _: &(), _: &()) -> SMatrix<f64, 2, 3> {
        SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 3, 3>,
        x: &SVector<f64, 3>,
        u: &CvbInput,
        p: &(),
        aux: &(),
    ) -> (SVector<f64, 2>, SMatrix<f64, 3, 2>, SMatrix<f64, 2, 2>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// A nonlinear sensor of [`Cvb`]: `(p^2 / 2, p + v)`, to exercise the
/// relinearization in sequential updates and mixed sensors.
pub struct Quad;

impl Sensor<3, 2> for Quad {
    type Model = Cvb;
    type Aux = ();
    const NAME: &'static str = "quad";
    const ANGLES: [bool; 2] = [false, false];
    const JACOBIAN_SPARSITY: [[bool; 3]; 2] = [[true, false, false], [true, true, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 3>, _: &CvbInput, _: &(), _: &()) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(0.5 * x[0] * x[0], x[0] + x[1])
    }

    fn jacobian(x: &SVector<f64, 3>, _: &CvbInput, _: &(), _: &()) -> SMatrix<f64, 2, 3> {
        SMatrix::<f64, 2, 3>::new(x[0], 0.0, 0.0, 1.0, 1.0, 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 3, 3>,
        x: &SVector<f64, 3>,
        u: &CvbInput,
        p: &(),
        aux: &(),
    ) -> (SVector<f64, 2>, SMatrix<f64, 3, 2>, SMatrix<f64, 2, 2>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// Harmonic oscillator (see module docs).
pub struct Osc;

impl Osc {
    /// `F = [[0, 1], [-w^2, 0]]`.
    pub fn f(w: f64) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 1.0, -w * w, 0.0)
    }
}

impl Model<2> for Osc {
    type Input = ();
    type Params = OscParams;
    type Noise = OscNoise;
    type State = ();
    const NAME: &'static str = "Osc";
    const DISCRETE: bool = false;
    const STATE_NAMES: [&'static str; 2] = ["theta", "omega"];
    const JACOBIAN_SPARSITY: [[bool; 2]; 2] = [[false, true], [true, false]];
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;

    fn transition(x: &SVector<f64, 2>, _: &(), p: &OscParams, dt: f64) -> SVector<f64, 2> {
        x + Self::f(p.w) * x * dt
    }

    fn jacobian(_: &SVector<f64, 2>, _: &(), p: &OscParams, _: f64) -> SMatrix<f64, 2, 2> {
        Self::f(p.w)
    }

    fn process_noise(
        _: &SVector<f64, 2>,
        _: &(),
        _: &OscParams,
        q: &OscNoise,
        dt: f64,
    ) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, q.q * dt)
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &(),
        p: &OscParams,
        q: &OscNoise,
        dt: f64,
    ) {
        let phi = SMatrix::<f64, 2, 2>::identity() + Self::f(p.w) * dt;
        propagate_dense(cov, &phi, &Self::process_noise(x, u, p, q, dt));
    }
}

/// The angle `theta` of [`Osc`], wrapped.
pub struct Angle;

impl Sensor<2, 1> for Angle {
    type Model = Osc;
    type Aux = ();
    const NAME: &'static str = "angle";
    const ANGLES: [bool; 1] = [true];
    const JACOBIAN_SPARSITY: [[bool; 2]; 1] = [[true, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 2>, _: &(), _: &OscParams, _: &()) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(x[0])
    }

    fn jacobian(_: &SVector<f64, 2>, _: &(), _: &OscParams, _: &()) -> SMatrix<f64, 1, 2> {
        SMatrix::<f64, 1, 2>::new(1.0, 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &(),
        p: &OscParams,
        aux: &(),
    ) -> (SVector<f64, 1>, SMatrix<f64, 2, 1>, SMatrix<f64, 1, 1>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// Discrete constant velocity: `p_k = p + v dt`, `v_k = v + w`, `Var(w) = var_v`.
pub struct Dcv;

impl Model<2> for Dcv {
    type Input = ();
    type Params = ();
    type Noise = DcvNoise;
    type State = ();
    const NAME: &'static str = "Dcv";
    const DISCRETE: bool = true;
    const STATE_NAMES: [&'static str; 2] = ["p", "v"];
    const JACOBIAN_SPARSITY: [[bool; 2]; 2] = [[true, true], [false, true]];
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;

    fn transition(x: &SVector<f64, 2>, _: &(), _: &(), dt: f64) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(x[0] + x[1] * dt, x[1])
    }

    fn jacobian(_: &SVector<f64, 2>, _: &(), _: &(), dt: f64) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(1.0, dt, 0.0, 1.0)
    }

    fn process_noise(
        _: &SVector<f64, 2>,
        _: &(),
        _: &(),
        q: &DcvNoise,
        _: f64,
    ) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, q.var_v)
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &(),
        p: &(),
        q: &DcvNoise,
        dt: f64,
    ) {
        propagate_dense(
            cov,
            &Self::jacobian(x, u, p, dt),
            &Self::process_noise(x, u, p, q, dt),
        );
    }
}

/// States (a, b, c, d): `a' = f00 a + f01 b`, `c' = f22 c + f23 d`,
/// `b' = d' = w1`, `c` also driven by `w2`. Changed rows 0 and 2; `Qd` at
/// `(1, 1)`, `(1, 3)`, `(3, 3)` (outside them, one off the diagonal) and
/// `(2, 2)`.
pub struct Rows;

impl Rows {
    /// `F` of the input.
    fn f(u: &RowsInput) -> SMatrix<f64, 4, 4> {
        let mut f = SMatrix::<f64, 4, 4>::zeros();
        f[(0, 0)] = u.f00;
        f[(0, 1)] = u.f01;
        f[(2, 2)] = u.f22;
        f[(2, 3)] = u.f23;
        f
    }
}

impl Model<4> for Rows {
    type Input = RowsInput;
    type Params = ();
    type Noise = RowsNoise;
    type State = ();
    const NAME: &'static str = "Rows";
    const DISCRETE: bool = false;
    const STATE_NAMES: [&'static str; 4] = ["a", "b", "c", "d"];
    const JACOBIAN_SPARSITY: [[bool; 4]; 4] = [
        [true, true, false, false],
        [false; 4],
        [false, false, true, true],
        [false; 4],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;
    const PROPAGATION: Option<crate::propagation::Structure<'static>> =
        Some(crate::propagation::Structure {
            identity: true,
            rows: &[0, 2],
            start: &[0, 2, 4],
            columns: &[0, 1, 2, 3],
            noise: &[(1, 1), (1, 3), (2, 2), (3, 3)],
        });

    fn transition(x: &SVector<f64, 4>, u: &RowsInput, _: &(), dt: f64) -> SVector<f64, 4> {
        x + Self::f(u) * x * dt
    }

    fn jacobian(_: &SVector<f64, 4>, u: &RowsInput, _: &(), _: f64) -> SMatrix<f64, 4, 4> {
        Self::f(u)
    }

    fn process_noise(
        _: &SVector<f64, 4>,
        _: &RowsInput,
        _: &(),
        q: &RowsNoise,
        dt: f64,
    ) -> SMatrix<f64, 4, 4> {
        let (q1, q2) = (q.q1 * dt, q.q2 * dt);
        SMatrix::<f64, 4, 4>::from_row_slice(&[
            0.0, 0.0, 0.0, 0.0, //
            0.0, q1, 0.0, q1, //
            0.0, 0.0, q2, 0.0, //
            0.0, q1, 0.0, q1,
        ])
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 4, 4>,
        x: &SVector<f64, 4>,
        u: &RowsInput,
        p: &(),
        q: &RowsNoise,
        dt: f64,
    ) {
        Self::propagate_covariance_observed(cov, x, u, p, q, dt, |_| ());
    }

    fn propagate_covariance_observed<F: FnOnce(&[f64])>(
        cov: &mut SMatrix<f64, 4, 4>,
        _: &SVector<f64, 4>,
        u: &RowsInput,
        _: &(),
        q: &RowsNoise,
        dt: f64,
        observe: F,
    ) {
        let coefficients = [u.f00 * dt, u.f01 * dt, u.f22 * dt, u.f23 * dt];
        observe(&coefficients);
        let structure = Self::PROPAGATION.expect("declared above");
        crate::propagation::propagate::<f64, 4, 2>(
            cov,
            &structure,
            &coefficients,
            &[q.q1 * dt, q.q1 * dt, q.q2 * dt, q.q1 * dt],
        );
    }
}

/// Toy nominal solution of [`Cvb`] for error-state tests: position, velocity
/// and the accelerometer-bias correction, mechanized as `v' = a_meas - b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Toy {
    pub p: f64,
    pub v: f64,
    pub b: f64,
}

impl NominalState<3> for Toy {
    fn inject(&mut self, e: &SVector<f64, 3>) {
        // error = INS minus true, so the correction subtracts.
        self.p -= e[0];
        self.v -= e[1];
        self.b -= e[2];
    }
}

impl Mechanization<Cvb, 3> for Toy {
    type Imu = CvbInput;
    fn mechanize(&mut self, dt: f64, imu: &CvbInput) -> CvbInput {
        self.p += self.v * dt;
        self.v += (imu.a - self.b) * dt;
        // The error dynamics dp' = dv, dv' = -db (+ noise) are Cvb with zero input.
        CvbInput { a: 0.0 }
    }
}

/// The planar error-state AHRS (see module docs). Errors are INS minus true
/// (docs/models/conventions.md, item 7): `phi = theta^ - theta`,
/// `db = b^ - b`; the nominal angle integrates `w_meas - b^`, so
/// `phi' = -db + n_gyro` and `db' = n_bias`.
pub struct Tilt;

impl Tilt {
    /// `F = df/dx`.
    pub fn f() -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::new(0.0, -1.0, 0.0, 0.0)
    }
}

impl Model<2> for Tilt {
    type Input = TiltInput;
    type Params = ();
    type Noise = TiltNoise;
    type State = TiltState;
    const NAME: &'static str = "Tilt";
    const DISCRETE: bool = false;
    const STATE_NAMES: [&'static str; 2] = ["phi", "db"];
    const JACOBIAN_SPARSITY: [[bool; 2]; 2] = [[false, true], [false, false]];
    const OPS_PROPAGATE_COVARIANCE: usize = 0;
    const OPS_JACOBIAN: usize = 0;

    fn transition(x: &SVector<f64, 2>, _: &TiltInput, _: &(), dt: f64) -> SVector<f64, 2> {
        SVector::<f64, 2>::new(x[0] - x[1] * dt, x[1])
    }

    fn jacobian(_: &SVector<f64, 2>, _: &TiltInput, _: &(), _: f64) -> SMatrix<f64, 2, 2> {
        Self::f()
    }

    fn process_noise(
        _: &SVector<f64, 2>,
        _: &TiltInput,
        _: &(),
        q: &TiltNoise,
        dt: f64,
    ) -> SMatrix<f64, 2, 2> {
        SMatrix::<f64, 2, 2>::from_diagonal(&SVector::<f64, 2>::new(q.q_gyro * dt, q.q_bias * dt))
    }

    fn propagate_covariance(
        cov: &mut SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &TiltInput,
        p: &(),
        q: &TiltNoise,
        dt: f64,
    ) {
        let phi = SMatrix::<f64, 2, 2>::identity() + Self::f() * dt;
        propagate_dense(cov, &phi, &Self::process_noise(x, u, p, q, dt));
    }
}

/// Gravity along the first axis, `cos(theta)` (in g): the residual is INS
/// minus sensor, `h = cos(theta^) - cos(theta^ - phi)`, read through the
/// nominal angle of the input.
pub struct TiltCos;

impl Sensor<2, 1> for TiltCos {
    type Model = Tilt;
    type Aux = ();
    const NAME: &'static str = "tilt_cos";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 2]; 1] = [[true, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 2>, u: &TiltInput, _: &(), _: &()) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(u.theta.cos() - (u.theta - x[0]).cos())
    }

    fn jacobian(x: &SVector<f64, 2>, u: &TiltInput, _: &(), _: &()) -> SMatrix<f64, 1, 2> {
        SMatrix::<f64, 1, 2>::new(-(u.theta - x[0]).sin(), 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &TiltInput,
        p: &(),
        aux: &(),
    ) -> (SVector<f64, 1>, SMatrix<f64, 2, 1>, SMatrix<f64, 1, 1>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// Gravity along the second axis, `sin(theta)` (in g):
/// `h = sin(theta^) - sin(theta^ - phi)`.
pub struct TiltSin;

impl Sensor<2, 1> for TiltSin {
    type Model = Tilt;
    type Aux = ();
    const NAME: &'static str = "tilt_sin";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 2]; 1] = [[true, false]];
    const OPS_INNOVATION_TERMS: usize = 0;

    fn predict(x: &SVector<f64, 2>, u: &TiltInput, _: &(), _: &()) -> SVector<f64, 1> {
        SVector::<f64, 1>::new(u.theta.sin() - (u.theta - x[0]).sin())
    }

    fn jacobian(x: &SVector<f64, 2>, u: &TiltInput, _: &(), _: &()) -> SMatrix<f64, 1, 2> {
        SMatrix::<f64, 1, 2>::new((u.theta - x[0]).cos(), 0.0)
    }

    fn innovation_terms(
        cov: &SMatrix<f64, 2, 2>,
        x: &SVector<f64, 2>,
        u: &TiltInput,
        p: &(),
        aux: &(),
    ) -> (SVector<f64, 1>, SMatrix<f64, 2, 1>, SMatrix<f64, 1, 1>) {
        dense_terms(
            cov,
            Self::predict(x, u, p, aux),
            &Self::jacobian(x, u, p, aux).transpose(),
        )
    }
}

/// The nominal solution of [`Tilt`]: the angle integrated from the gyro and
/// the gyro-bias correction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TiltNominal {
    /// rad.
    pub theta: f64,
    /// rad/s.
    pub bias: f64,
}

impl TiltNominal {
    /// The error model's input at this nominal solution (what the sensors
    /// read), for [`crate::error_state::ErrorStateFilter::with_sensor_input`].
    pub fn input(&self) -> TiltInput {
        TiltInput { theta: self.theta }
    }
}

impl NominalState<2> for TiltNominal {
    fn inject(&mut self, e: &SVector<f64, 2>) {
        self.theta -= e[0];
        self.bias -= e[1];
    }
}

/// The gyro sample is the measured rate, rad/s.
impl Mechanization<Tilt, 2> for TiltNominal {
    type Imu = TiltInput;
    fn mechanize(&mut self, dt: f64, gyro: &TiltInput) -> TiltInput {
        // As the AHRS of the models: the input is the nominal at the start
        // of the interval.
        let input = self.input();
        self.theta += (gyro.theta - self.bias) * dt;
        input
    }
}

/// Seeded standard normal draws for the statistical tests.
pub struct Gauss(rand_chacha::ChaCha8Rng);

impl Gauss {
    /// A reproducible generator.
    pub fn new(seed: u64) -> Self {
        use rand::SeedableRng;
        Self(rand_chacha::ChaCha8Rng::seed_from_u64(seed))
    }

    /// One N(0, 1) draw.
    pub fn normal(&mut self) -> f64 {
        use rand::Rng;
        self.0.sample(rand_distr::StandardNormal)
    }

    /// A uniform draw from `0..n`.
    pub fn index(&mut self, n: usize) -> usize {
        use rand::Rng;
        self.0.random_range(0..n)
    }

    /// A random symmetric positive definite matrix `A A^T + eps I`.
    pub fn spd<const N: usize>(&mut self, eps: f64) -> SMatrix<f64, N, N> {
        let a = SMatrix::<f64, N, N>::from_fn(|_, _| self.normal());
        a * a.transpose() + SMatrix::<f64, N, N>::identity() * eps
    }

    /// A draw from N(0, cov).
    pub fn multivariate<const N: usize>(&mut self, cov: &SMatrix<f64, N, N>) -> SVector<f64, N> {
        let l = nalgebra::Cholesky::new(*cov)
            .map(|c| c.l())
            .unwrap_or_else(SMatrix::zeros);
        l * SVector::<f64, N>::from_fn(|_, _| self.normal())
    }
}
