// Expansion of `nav_runtime::model!` in models/src/leveling/model.rs, formatted.
// Checked by `snapshots_are_current` (nav-macros/src/lib.rs); regenerate with
// `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`.
//
// Op counts:
//   Leveling6::OPS_TRANSITION = 45
//   Leveling6::OPS_JACOBIAN = 12
//   Leveling6::OPS_NOISE_JACOBIAN = 3
//   Leveling6::OPS_PROCESS_NOISE = 28
//   Leveling6::OPS_PROPAGATE_COVARIANCE = 289
//   Leveling6::OPS_DERIVATIVE = 33
//   Leveling6Moving::OPS_PREDICT = 5
//   Leveling6Moving::OPS_JACOBIAN = 3
//   Leveling6Moving::OPS_INNOVATION_TERMS = 43
//   Leveling6Stationary::OPS_PREDICT = 5
//   Leveling6Stationary::OPS_JACOBIAN = 3
//   Leveling6Stationary::OPS_INNOVATION_TERMS = 43

///The state of [`Leveling6`] (6 scalars), with named fields.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Leveling6State {
    /// Body-frame velocity over ground `V^b`, m/s.
    pub velocity: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Gravity direction in body axes `a = [-sin theta, sin phi cos theta, cos phi cos theta]`.
    pub gravity_direction: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Leveling6State {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "gravity_direction[0]",
        "gravity_direction[1]",
        "gravity_direction[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 6] = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            velocity: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            gravity_direction: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.gravity_direction[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.gravity_direction[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.gravity_direction[2]),
            _ => f64::NAN,
        }
    }
}
#[allow(clippy::possible_missing_comma)]
impl Leveling6State {
    /// The state from its vector (declaration order).
    pub fn from_vector(v: &::nav_runtime::nalgebra::SVector<f64, 6>) -> Self {
        <Self as ::nav_runtime::model::Record>::from_fn(|i| <f64 as ::nav_runtime::Real>::to_f64(
            v[i],
        ))
    }
    /// The state as a vector (declaration order).
    pub fn to_vector(&self) -> ::nav_runtime::nalgebra::SVector<f64, 6> {
        ::nav_runtime::nalgebra::SVector::<
            f64,
            6,
        >::from_column_slice(
            &[
                self.velocity[0],
                self.velocity[1],
                self.velocity[2],
                self.gravity_direction[0],
                self.gravity_direction[1],
                self.gravity_direction[2],
            ],
        )
    }
}
///The inputs `u` of [`Leveling6`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Leveling6Input {
    /// Gyro output `w_ib^b`, rad/s.
    pub gyro: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Accelerometer output `f^b`, m/s^2.
    pub specific_force: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Earth rate in body axes from the current estimate `W^b` (eq. 16), rad/s.
    pub earth_rate_body: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Leveling6Input {
    const LEN: usize = 9;
    const NAMES: &'static [&'static str] = &[
        "gyro[0]",
        "gyro[1]",
        "gyro[2]",
        "specific_force[0]",
        "specific_force[1]",
        "specific_force[2]",
        "earth_rate_body[0]",
        "earth_rate_body[1]",
        "earth_rate_body[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 9] = [0.0; 9];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            gyro: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            specific_force: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
            earth_rate_body: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[6..9]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[2]),
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.earth_rate_body[0]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.earth_rate_body[1]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.earth_rate_body[2]),
            _ => f64::NAN,
        }
    }
}
///The parameters `p` of [`Leveling6`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Leveling6Params {
    /// Local gravity magnitude `g`, m/s^2.
    pub gravity: f64,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Leveling6Params {
    const LEN: usize = 1;
    const NAMES: &'static [&'static str] = &["gravity"];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 1] = [0.0; 1];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self { gravity: v[0] }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.gravity),
            _ => f64::NAN,
        }
    }
}
///The process-noise power spectral densities `q` of [`Leveling6`], one per noise scalar (units^2 / s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Leveling6Noise {
    /// Accelerometer white noise, (m/s^2)^2/Hz.
    pub accel_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Gyro white noise, (rad/s)^2/Hz.
    pub gyro_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Leveling6Noise {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "accel_noise[0]",
        "accel_noise[1]",
        "accel_noise[2]",
        "gyro_noise[0]",
        "gyro_noise[1]",
        "gyro_noise[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 6] = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            accel_noise: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            gyro_noise: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_noise[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_noise[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_noise[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_noise[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_noise[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_noise[2]),
            _ => f64::NAN,
        }
    }
}
/// Roll/pitch leveling filter, eqs. 15, 17 and 26 of the leveling paper.
///
///Generated by `model!`: continuous model with 6 states, 6 noise inputs and 2 sensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Leveling6;
#[allow(clippy::possible_missing_comma)]
impl Leveling6 {
    /// Number of scalar states.
    pub const N: usize = 6;
    /// Number of scalar process-noise inputs.
    pub const NW: usize = 6;
    ///Index of the first scalar of `velocity` in the state vector.
    pub const VELOCITY: usize = 0;
    ///Index of the first scalar of `gravity_direction` in the state vector.
    pub const GRAVITY_DIRECTION: usize = 3;
    /// State scalars no sensor depends on, directly or through the dynamics
    /// (no measurement can correct them). The model lists them in
    /// `allow_unused { .. }` (checked at compile time).
    pub const UNUSED_STATES: &'static [&'static str] = &[];
    /// Operations in `transition`.
    pub const OPS_TRANSITION: usize = 45;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 12;
    /// Operations in [`Self::noise_jacobian`].
    pub const OPS_NOISE_JACOBIAN: usize = 3;
    /// Operations in `process_noise`.
    pub const OPS_PROCESS_NOISE: usize = 28;
    /// Operations in `propagate_covariance`.
    pub const OPS_PROPAGATE_COVARIANCE: usize = 289;
    ///Structure of `Phi` (`I + F dt`) and `Qd` for the covariance propagation: rows [0, 1, 2, 3, 4, 5] change, the others are unit rows.
    pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> = ::nav_runtime::propagation::Structure {
        identity: true,
        rows: &[0, 1, 2, 3, 4, 5],
        start: &[0, 3, 6, 9, 11, 13, 15],
        columns: &[1, 2, 3, 0, 2, 4, 0, 1, 5, 4, 5, 3, 5, 3, 4],
        noise: &[(0, 0), (1, 1), (2, 2), (3, 3), (3, 4), (3, 5), (4, 4), (4, 5), (5, 5)],
    };
    /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
    pub const SENSORS: [&'static str; 2] = ["Moving", "Stationary"];
    /// Per sensor, per state scalar: the sensor's `h` depends on the state
    /// directly (a structural nonzero of its `H`).
    pub const SENSOR_DEPENDS: [[bool; 6]; 2] = [
        [true, false, false, true, true, true],
        [true, true, true, true, true, true],
    ];
    /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
    /// indices into `SENSORS`); the set of all sensors when it declares none.
    pub const RUNS_WITH: [&'static [usize]; 1] = [&[0, 1]];
    /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
    /// that set (checked at compile time against `allow_unused`).
    pub const RUNS_WITH_OBSERVABLE: [[bool; 6]; 1] = [
        [true, true, true, true, true, true],
    ];
    /// Per state scalar: is it structurally observable with the sensors marked
    /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
    /// a measurement of one of them, through a sensor's `H` or the dynamics
    /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
    /// only: `false` means no measurement of that set can ever correct the
    /// state; `true` means only that sparsity does not exclude it (see
    /// `docs/language.md`, "Structural observability").
    pub const fn structurally_observable(sensors: &[bool; 2]) -> [bool; 6] {
        let deps = Self::SENSOR_DEPENDS;
        let f = <Self as ::nav_runtime::model::Model<6, f64>>::JACOBIAN_SPARSITY;
        let mut seen = [false; 6];
        let mut s = 0;
        while s < 2 {
            if sensors[s] {
                let mut j = 0;
                while j < 6 {
                    if deps[s][j] {
                        seen[j] = true;
                    }
                    j += 1;
                }
            }
            s += 1;
        }
        let mut changed = true;
        while changed {
            changed = false;
            let mut i = 0;
            while i < 6 {
                if seen[i] {
                    let mut j = 0;
                    while j < 6 {
                        if j != i && !seen[j] && f[i][j] {
                            seen[j] = true;
                            changed = true;
                        }
                        j += 1;
                    }
                }
                i += 1;
            }
        }
        seen
    }
    /// The index in `SENSORS` of the sensor declared as `name`, if any.
    pub fn sensor_index(name: &str) -> ::core::option::Option<usize> {
        Self::SENSORS.iter().position(|s| *s == name)
    }
    /// Operations in [`Self::derivative`].
    pub const OPS_DERIVATIVE: usize = 33;
    /**The state derivative `f(x, u, p)` at `w = 0`.

Total ops: 33*/
    pub fn derivative(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 6> {
        let _t0 = u.earth_rate_body[2] + u.gyro[2];
        let _t1 = u.earth_rate_body[1] + u.gyro[1];
        let _t2 = u.earth_rate_body[0] + u.gyro[0];
        let _t3 = u.gyro[2] - u.earth_rate_body[2];
        let _t4 = u.gyro[1] - u.earth_rate_body[1];
        let _t5 = u.gyro[0] - u.earth_rate_body[0];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 6>::zeros();
        out[0] = p.gravity * x[3] + (_t0 * x[1] - _t1 * x[2]) + u.specific_force[0];
        out[1] = p.gravity * x[4] + (x[2] * _t2 - _t0 * x[0]) + u.specific_force[1];
        out[2] = p.gravity * x[5] + (_t1 * x[0] - x[1] * _t2) + u.specific_force[2];
        out[3] = x[4] * _t3 - x[5] * _t4;
        out[4] = x[5] * _t5 - x[3] * _t3;
        out[5] = x[3] * _t4 - x[4] * _t5;
        out
    }
    /**The state derivative `dx/dt = f(x, u, p, w)` with an explicit noise sample `w` (units of the state per second; not a step: [`Self::step_with_noise`] advances the state by `dt`).

Total ops: 39*/
    pub fn derivative_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 6> {
        let _t0 = u.earth_rate_body[2] + u.gyro[2];
        let _t1 = u.earth_rate_body[1] + u.gyro[1];
        let _t2 = u.earth_rate_body[0] + u.gyro[0];
        let _t3 = u.gyro[2] - u.earth_rate_body[2] + w[5];
        let _t4 = u.gyro[1] - u.earth_rate_body[1] + w[4];
        let _t5 = u.gyro[0] - u.earth_rate_body[0] + w[3];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 6>::zeros();
        out[0] = p.gravity * x[3] + (_t0 * x[1] - _t1 * x[2]) + u.specific_force[0]
            + w[0];
        out[1] = p.gravity * x[4] + (x[2] * _t2 - _t0 * x[0]) + u.specific_force[1]
            + w[1];
        out[2] = p.gravity * x[5] + (_t1 * x[0] - x[1] * _t2) + u.specific_force[2]
            + w[2];
        out[3] = x[4] * _t3 - x[5] * _t4;
        out[4] = x[5] * _t5 - x[3] * _t3;
        out[5] = x[3] * _t4 - x[4] * _t5;
        out
    }
    /**The state after one step of `dt` seconds with an explicit noise sample `w`: the Euler step `x + f(x, u, p, w) dt` (`transition` at `w = 0`; the derivative itself is [`Self::derivative_with_noise`]).

Total ops: 51*/
    pub fn step_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 6> {
        let _t0 = u.earth_rate_body[2] + u.gyro[2];
        let _t1 = u.earth_rate_body[1] + u.gyro[1];
        let _t2 = u.earth_rate_body[0] + u.gyro[0];
        let _t3 = u.gyro[2] - u.earth_rate_body[2] + w[5];
        let _t4 = u.gyro[1] - u.earth_rate_body[1] + w[4];
        let _t5 = u.gyro[0] - u.earth_rate_body[0] + w[3];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 6>::zeros();
        out[0] = dt
            * (p.gravity * x[3] + (_t0 * x[1] - _t1 * x[2]) + u.specific_force[0] + w[0])
            + x[0];
        out[1] = x[1]
            + dt
                * (p.gravity * x[4] + (x[2] * _t2 - _t0 * x[0]) + u.specific_force[1]
                    + w[1]);
        out[2] = x[2]
            + dt
                * (p.gravity * x[5] + (_t1 * x[0] - x[1] * _t2) + u.specific_force[2]
                    + w[2]);
        out[3] = x[3] + dt * (x[4] * _t3 - x[5] * _t4);
        out[4] = x[4] + dt * (x[5] * _t5 - x[3] * _t3);
        out[5] = x[5] + dt * (x[3] * _t4 - x[4] * _t5);
        out
    }
    /**The noise Jacobian `G = df/dw` of the derivative at `w = 0` (N x NW, noise scalars in declaration order; `dt` is unused: the step's own is `G dt`).

Total ops: 3*/
    pub fn noise_jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 6, 6> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 6, 6>::zeros();
        out[(0, 0)] = 1.0;
        out[(1, 1)] = 1.0;
        out[(2, 2)] = 1.0;
        out[(3, 4)] = -x[5];
        out[(3, 5)] = x[4];
        out[(4, 3)] = x[5];
        out[(4, 5)] = -x[3];
        out[(5, 3)] = -x[4];
        out[(5, 4)] = x[3];
        out
    }
}
impl ::nav_runtime::propagation::StaticStructure for Leveling6 {
    const STRUCTURE: ::nav_runtime::propagation::Structure<'static> = Self::PROPAGATION_STRUCTURE;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Model<6, f64> for Leveling6 {
    type Input = Leveling6Input;
    type Params = Leveling6Params;
    type Noise = Leveling6Noise;
    type State = Leveling6State;
    const NAME: &'static str = "Leveling6";
    const DISCRETE: bool = !true;
    const STATE_NAMES: [&'static str; 6] = [
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "gravity_direction[0]",
        "gravity_direction[1]",
        "gravity_direction[2]",
    ];
    const JACOBIAN_SPARSITY: [[bool; 6]; 6] = [
        [false, true, true, true, false, false],
        [true, false, true, false, true, false],
        [true, true, false, false, false, true],
        [false, false, false, false, true, true],
        [false, false, false, true, false, true],
        [false, false, false, true, true, false],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 289;
    const OPS_JACOBIAN: usize = 12;
    const ZERO_IS_FIXED: bool = false;
    /**One Euler step `x + f(x, u, p) dt`.

Total ops: 45*/
    fn transition(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 6> {
        let _t0 = u.earth_rate_body[2] + u.gyro[2];
        let _t1 = u.earth_rate_body[1] + u.gyro[1];
        let _t2 = u.earth_rate_body[0] + u.gyro[0];
        let _t3 = u.gyro[2] - u.earth_rate_body[2];
        let _t4 = u.gyro[1] - u.earth_rate_body[1];
        let _t5 = u.gyro[0] - u.earth_rate_body[0];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 6>::zeros();
        out[0] = dt
            * (p.gravity * x[3] + (_t0 * x[1] - _t1 * x[2]) + u.specific_force[0])
            + x[0];
        out[1] = x[1]
            + dt * (p.gravity * x[4] + (x[2] * _t2 - _t0 * x[0]) + u.specific_force[1]);
        out[2] = x[2]
            + dt * (p.gravity * x[5] + (_t1 * x[0] - x[1] * _t2) + u.specific_force[2]);
        out[3] = x[3] + dt * (x[4] * _t3 - x[5] * _t4);
        out[4] = x[4] + dt * (x[5] * _t5 - x[3] * _t3);
        out[5] = x[5] + dt * (x[3] * _t4 - x[4] * _t5);
        out
    }
    /**`F = df/dx` at `w = 0` (`dt` is unused).

Total ops: 12*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 6, 6> {
        let _t0 = u.earth_rate_body[2] + u.gyro[2];
        let _t1 = u.earth_rate_body[1] + u.gyro[1];
        let _t2 = u.earth_rate_body[0] + u.gyro[0];
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 6, 6>::zeros();
        out[(0, 1)] = _t0;
        out[(0, 2)] = -_t1;
        out[(0, 3)] = p.gravity;
        out[(1, 0)] = -_t0;
        out[(1, 2)] = _t2;
        out[(1, 4)] = p.gravity;
        out[(2, 0)] = _t1;
        out[(2, 1)] = -_t2;
        out[(2, 5)] = p.gravity;
        out[(3, 4)] = u.gyro[2] - u.earth_rate_body[2];
        out[(3, 5)] = u.earth_rate_body[1] - u.gyro[1];
        out[(4, 3)] = u.earth_rate_body[2] - u.gyro[2];
        out[(4, 5)] = u.gyro[0] - u.earth_rate_body[0];
        out[(5, 3)] = u.gyro[1] - u.earth_rate_body[1];
        out[(5, 4)] = u.earth_rate_body[0] - u.gyro[0];
        out
    }
    /**`Qd = G Q G^T dt`, `Q = diag(q)`.

Total ops: 28*/
    fn process_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        q: &Leveling6Noise,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 6, 6> {
        let _t0 = q.gyro_noise[2] * x[4];
        let _t1 = q.gyro_noise[1] * x[5];
        let _t2 = -dt;
        let _t3 = x[5] * q.gyro_noise[0];
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 6, 6>::zeros();
        out[(0, 0)] = q.accel_noise[0] * dt;
        out[(1, 1)] = dt * q.accel_noise[1];
        out[(2, 2)] = dt * q.accel_noise[2];
        out[(3, 3)] = dt * (x[4] * _t0 + x[5] * _t1);
        out[(3, 4)] = _t2 * (_t0 * x[3]);
        out[(3, 5)] = _t2 * (_t1 * x[3]);
        out[(4, 4)] = dt * (x[3] * (q.gyro_noise[2] * x[3]) + x[5] * _t3);
        out[(4, 5)] = _t2 * (x[4] * _t3);
        out[(5, 5)] = dt
            * (x[3] * (q.gyro_noise[1] * x[3]) + x[4] * (x[4] * q.gyro_noise[0]));
        for i in 0..6 {
            for j in 0..i {
                out[(i, j)] = out[(j, i)];
            }
        }
        out
    }
    /**`P <- Phi P Phi^T + Qd` unrolled entry by entry from the upper triangle of `P` (a small model: straight-line code fits the caches), generated from the sparsity of `Phi` and `G`; the result is mirrored.

Total ops: 289*/
    fn propagate_covariance(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 6, 6>,
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        q: &Leveling6Noise,
        dt: f64,
    ) {
        let _p = *cov;
        let _t0 = dt * (u.earth_rate_body[2] + u.gyro[2]);
        let _t1 = (u.earth_rate_body[1] + u.gyro[1]) * dt;
        let _t2 = dt * p.gravity;
        let _t3 = _t0 * _p[(1, 1)] + _p[(0, 1)] - _t1 * _p[(1, 2)] + _t2 * _p[(1, 3)];
        let _t4 = _t0 * _p[(0, 1)];
        let _t5 = _t1 * _p[(0, 2)];
        let _t6 = _t4 + _p[(0, 0)] - _t5 + _t2 * _p[(0, 3)];
        let _t7 = _p[(1, 2)] * _t0 + _p[(0, 2)] - _p[(2, 2)] * _t1 + _p[(2, 3)] * _t2;
        let _t8 = _p[(0, 3)] + _t0 * _p[(1, 3)] - _t1 * _p[(2, 3)] + _t2 * _p[(3, 3)];
        let _t9 = dt * (u.earth_rate_body[0] + u.gyro[0]);
        let _t10 = _t2 * _p[(3, 4)];
        let _t11 = _t0 * _p[(1, 4)] + _p[(0, 4)] - _t1 * _p[(2, 4)] + _t10;
        let _t12 = _t2 * _p[(3, 5)];
        let _t13 = _t0 * _p[(1, 5)] + _p[(0, 5)] - _t1 * _p[(2, 5)] + _t12;
        let _t14 = dt * (u.gyro[2] - u.earth_rate_body[2]);
        let _t15 = dt * (u.earth_rate_body[1] - u.gyro[1]);
        let _t16 = dt * (u.earth_rate_body[2] - u.gyro[2]);
        let _t17 = dt * (u.gyro[0] - u.earth_rate_body[0]);
        let _t18 = dt * (u.earth_rate_body[0] - u.gyro[0]);
        let _t19 = dt * (u.gyro[1] - u.earth_rate_body[1]);
        let _t20 = _p[(1, 2)] * _t9;
        let _t21 = _p[(1, 1)] - _t4 + _t20 + _t2 * _p[(1, 4)];
        let _t22 = _p[(0, 1)] - _t0 * _p[(0, 0)] + _p[(0, 2)] * _t9 + _t2 * _p[(0, 4)];
        let _t23 = _p[(1, 2)] - _t0 * _p[(0, 2)] + _p[(2, 2)] * _t9 + _t2 * _p[(2, 4)];
        let _t24 = _p[(1, 4)] - _t0 * _p[(0, 4)] + _t9 * _p[(2, 4)] + _t2 * _p[(4, 4)];
        let _t25 = _t2 * _p[(4, 5)];
        let _t26 = _p[(1, 5)] - _t0 * _p[(0, 5)] + _t9 * _p[(2, 5)] + _t25;
        let _t27 = _t10 + (_p[(1, 3)] - _t0 * _p[(0, 3)] + _p[(2, 3)] * _t9);
        let _t28 = _p[(2, 5)] + (_t1 * _p[(0, 5)] - _t9 * _p[(1, 5)]) + _t2 * _p[(5, 5)];
        let _t29 = _t25 + (_p[(2, 4)] + (_t1 * _p[(0, 4)] - _t9 * _p[(1, 4)]));
        let _t30 = _t12 + (_p[(2, 3)] + (_t1 * _p[(0, 3)] - _p[(1, 3)] * _t9));
        let _t31 = _p[(3, 4)] + _t14 * _p[(4, 4)] + _t15 * _p[(4, 5)];
        let _t32 = _p[(3, 3)] + _p[(3, 4)] * _t14 + _p[(3, 5)] * _t15;
        let _t33 = _p[(3, 5)] + _t14 * _p[(4, 5)] + _t15 * _p[(5, 5)];
        let _t34 = q.gyro_noise[2] * x[4];
        let _t35 = q.gyro_noise[1] * x[5];
        let _t36 = _p[(3, 4)] + _p[(3, 3)] * _t16 + _p[(3, 5)] * _t17;
        let _t37 = _p[(4, 4)] + _p[(3, 4)] * _t16 + _t17 * _p[(4, 5)];
        let _t38 = _p[(4, 5)] + _p[(3, 5)] * _t16 + _t17 * _p[(5, 5)];
        let _t39 = x[5] * q.gyro_noise[0];
        cov[(0, 0)] = _t0 * _t3 + _t6 - _t1 * _t7 + _t2 * _t8 + dt * q.accel_noise[0];
        cov[(0, 1)] = _t3 - _t0 * _t6 + _t7 * _t9 + _t2 * _t11;
        cov[(0, 2)] = _t7 + (_t1 * _t6 - _t3 * _t9) + _t2 * _t13;
        cov[(0, 3)] = _t8 + _t11 * _t14 + _t13 * _t15;
        cov[(0, 4)] = _t11 + _t8 * _t16 + _t13 * _t17;
        cov[(0, 5)] = _t13 + (_t11 * _t18 + _t8 * _t19);
        cov[(1, 1)] = _t21 - _t0 * _t22 + _t9 * _t23 + _t2 * _t24
            + dt * q.accel_noise[1];
        cov[(1, 2)] = _t23 + (_t1 * _t22 - _t9 * _t21) + _t2 * _t26;
        cov[(1, 3)] = _t14 * _t24 + _t27 + _t15 * _t26;
        cov[(1, 4)] = _t24 + _t16 * _t27 + _t17 * _t26;
        cov[(1, 5)] = _t26 + (_t18 * _t24 + _t19 * _t27);
        cov[(2, 2)] = _t1
            * (_p[(0, 2)] + (_t1 * _p[(0, 0)] - _p[(0, 1)] * _t9) + _t2 * _p[(0, 5)])
            - _t9
                * (_p[(1, 2)] + (_t1 * _p[(0, 1)] - _p[(1, 1)] * _t9) + _t2 * _p[(1, 5)])
            + (_p[(2, 2)] + (_t5 - _t20) + _t2 * _p[(2, 5)]) + _t2 * _t28
            + dt * q.accel_noise[2];
        cov[(2, 3)] = _t14 * _t29 + _t30 + _t15 * _t28;
        cov[(2, 4)] = _t29 + _t16 * _t30 + _t17 * _t28;
        cov[(2, 5)] = _t28 + (_t18 * _t29 + _t19 * _t30);
        cov[(3, 3)] = _t14 * _t31 + _t32 + _t15 * _t33
            + dt * (x[4] * _t34 + x[5] * _t35);
        cov[(3, 4)] = _t31 + _t16 * _t32 + _t17 * _t33 - dt * (_t34 * x[3]);
        cov[(3, 5)] = _t33 + (_t18 * _t31 + _t19 * _t32) - dt * (_t35 * x[3]);
        cov[(4, 4)] = _t16 * _t36 + _t37 + _t17 * _t38
            + dt * (x[3] * (q.gyro_noise[2] * x[3]) + x[5] * _t39);
        cov[(4, 5)] = _t38 + (_t18 * _t37 + _t19 * _t36) - dt * (x[4] * _t39);
        cov[(5, 5)] = _t18 * (_p[(4, 5)] + (_t18 * _p[(4, 4)] + _p[(3, 4)] * _t19))
            + _t19 * (_p[(3, 5)] + (_p[(3, 4)] * _t18 + _p[(3, 3)] * _t19))
            + (_p[(5, 5)] + (_t18 * _p[(4, 5)] + _p[(3, 5)] * _t19))
            + dt * (x[3] * (q.gyro_noise[1] * x[3]) + x[4] * (x[4] * q.gyro_noise[0]));
        for i in 0..6 {
            for j in 0..i {
                cov[(i, j)] = cov[(j, i)];
            }
        }
    }
    const DECLARED_SENSORS: &'static [&'static str] = &["Moving", "Stationary"];
    fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, 6, f64>>(
        name: &str,
        visitor: V,
    ) -> ::core::option::Option<V::Output> {
        match name {
            "Moving" => {
                ::core::option::Option::Some(visitor.visit::<Leveling6Moving, 2>())
            }
            "Stationary" => {
                ::core::option::Option::Some(visitor.visit::<Leveling6Stationary, 4>())
            }
            _ => {
                let _ = visitor;
                ::core::option::Option::None
            }
        }
    }
}
/// Moving: forward speed log and the unit-norm constraint (eqs. 29-30).
///
///Sensor `Moving` of [`Leveling6`]: 2 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Leveling6Moving;
#[allow(clippy::possible_missing_comma)]
impl Leveling6Moving {
    /// Number of measurement components.
    pub const M: usize = 2;
    /// The declared sensor name.
    pub const NAME: &'static str = "Moving";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 0;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 6] = [true, true, true, true, true, true];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 5;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 3;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 43;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<6, 2, f64> for Leveling6Moving {
    type Model = Leveling6;
    type Aux = ();
    const NAME: &'static str = "Moving";
    const ANGLES: [bool; 2] = [false, false];
    const JACOBIAN_SPARSITY: [[bool; 6]; 2] = [
        [true, false, false, false, false, false],
        [false, false, false, true, true, true],
    ];
    const OPS_INNOVATION_TERMS: usize = 43;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 5*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 2> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        out[0] = x[0];
        out[1] = x[4] * x[4] + x[3] * x[3] + x[5] * x[5];
        out
    }
    /**`H = dh/dx`.

Total ops: 3*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 2, 6> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 6>::zeros();
        out[(0, 0)] = 1.0;
        out[(1, 3)] = 2.0 * x[3];
        out[(1, 4)] = 2.0 * x[4];
        out[(1, 5)] = 2.0 * x[5];
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 43*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 6, 6>,
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 6, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 2, 2>,
    ) {
        let _t0 = x[4] * 2.0;
        let _t1 = x[3] * 2.0;
        let _t2 = x[5] * 2.0;
        let _t3 = _t0 * cov[(0, 4)] + _t1 * cov[(0, 3)] + _t2 * cov[(0, 5)];
        let _t4 = _t0 * cov[(3, 4)] + _t1 * cov[(3, 3)] + _t2 * cov[(3, 5)];
        let _t5 = _t0 * cov[(4, 4)] + _t1 * cov[(3, 4)] + _t2 * cov[(4, 5)];
        let _t6 = _t0 * cov[(4, 5)] + _t1 * cov[(3, 5)] + _t2 * cov[(5, 5)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 6, 2>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 2>::zeros();
        h[0] = x[0];
        h[1] = x[4] * x[4] + x[3] * x[3] + x[5] * x[5];
        pht[(0, 0)] = cov[(0, 0)];
        pht[(0, 1)] = _t3;
        pht[(1, 0)] = cov[(0, 1)];
        pht[(1, 1)] = _t0 * cov[(1, 4)] + _t1 * cov[(1, 3)] + _t2 * cov[(1, 5)];
        pht[(2, 0)] = cov[(0, 2)];
        pht[(2, 1)] = _t0 * cov[(2, 4)] + _t1 * cov[(2, 3)] + _t2 * cov[(2, 5)];
        pht[(3, 0)] = cov[(0, 3)];
        pht[(3, 1)] = _t4;
        pht[(4, 0)] = cov[(0, 4)];
        pht[(4, 1)] = _t5;
        pht[(5, 0)] = cov[(0, 5)];
        pht[(5, 1)] = _t6;
        s[(0, 0)] = cov[(0, 0)];
        s[(0, 1)] = _t3;
        s[(1, 1)] = _t0 * _t5 + _t1 * _t4 + _t2 * _t6;
        for i in 0..2 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// Stationary: zero velocity on three axes and the unit norm (eqs. 32-33).
///
///Sensor `Stationary` of [`Leveling6`]: 4 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Leveling6Stationary;
#[allow(clippy::possible_missing_comma)]
impl Leveling6Stationary {
    /// Number of measurement components.
    pub const M: usize = 4;
    /// The declared sensor name.
    pub const NAME: &'static str = "Stationary";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 1;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 6] = [true, true, true, true, true, true];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 5;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 3;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 43;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<6, 4, f64> for Leveling6Stationary {
    type Model = Leveling6;
    type Aux = ();
    const NAME: &'static str = "Stationary";
    const ANGLES: [bool; 4] = [false, false, false, false];
    const JACOBIAN_SPARSITY: [[bool; 6]; 4] = [
        [true, false, false, false, false, false],
        [false, true, false, false, false, false],
        [false, false, true, false, false, false],
        [false, false, false, true, true, true],
    ];
    const OPS_INNOVATION_TERMS: usize = 43;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 5*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 4> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 4>::zeros();
        out[0] = x[0];
        out[1] = x[1];
        out[2] = x[2];
        out[3] = x[4] * x[4] + x[3] * x[3] + x[5] * x[5];
        out
    }
    /**`H = dh/dx`.

Total ops: 3*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 4, 6> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 4, 6>::zeros();
        out[(0, 0)] = 1.0;
        out[(1, 1)] = 1.0;
        out[(2, 2)] = 1.0;
        out[(3, 3)] = 2.0 * x[3];
        out[(3, 4)] = 2.0 * x[4];
        out[(3, 5)] = 2.0 * x[5];
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 43*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 6, 6>,
        x: &::nav_runtime::nalgebra::SVector<f64, 6>,
        u: &Leveling6Input,
        p: &Leveling6Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 4>,
        ::nav_runtime::nalgebra::SMatrix<f64, 6, 4>,
        ::nav_runtime::nalgebra::SMatrix<f64, 4, 4>,
    ) {
        let _t0 = x[4] * 2.0;
        let _t1 = x[3] * 2.0;
        let _t2 = x[5] * 2.0;
        let _t3 = _t0 * cov[(0, 4)] + _t1 * cov[(0, 3)] + _t2 * cov[(0, 5)];
        let _t4 = _t0 * cov[(1, 4)] + _t1 * cov[(1, 3)] + _t2 * cov[(1, 5)];
        let _t5 = _t0 * cov[(2, 4)] + _t1 * cov[(2, 3)] + _t2 * cov[(2, 5)];
        let _t6 = _t0 * cov[(3, 4)] + _t1 * cov[(3, 3)] + _t2 * cov[(3, 5)];
        let _t7 = _t0 * cov[(4, 4)] + _t1 * cov[(3, 4)] + _t2 * cov[(4, 5)];
        let _t8 = _t0 * cov[(4, 5)] + _t1 * cov[(3, 5)] + _t2 * cov[(5, 5)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 4>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 6, 4>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 4, 4>::zeros();
        h[0] = x[0];
        h[1] = x[1];
        h[2] = x[2];
        h[3] = x[4] * x[4] + x[3] * x[3] + x[5] * x[5];
        pht[(0, 0)] = cov[(0, 0)];
        pht[(0, 1)] = cov[(0, 1)];
        pht[(0, 2)] = cov[(0, 2)];
        pht[(0, 3)] = _t3;
        pht[(1, 0)] = cov[(0, 1)];
        pht[(1, 1)] = cov[(1, 1)];
        pht[(1, 2)] = cov[(1, 2)];
        pht[(1, 3)] = _t4;
        pht[(2, 0)] = cov[(0, 2)];
        pht[(2, 1)] = cov[(1, 2)];
        pht[(2, 2)] = cov[(2, 2)];
        pht[(2, 3)] = _t5;
        pht[(3, 0)] = cov[(0, 3)];
        pht[(3, 1)] = cov[(1, 3)];
        pht[(3, 2)] = cov[(2, 3)];
        pht[(3, 3)] = _t6;
        pht[(4, 0)] = cov[(0, 4)];
        pht[(4, 1)] = cov[(1, 4)];
        pht[(4, 2)] = cov[(2, 4)];
        pht[(4, 3)] = _t7;
        pht[(5, 0)] = cov[(0, 5)];
        pht[(5, 1)] = cov[(1, 5)];
        pht[(5, 2)] = cov[(2, 5)];
        pht[(5, 3)] = _t8;
        s[(0, 0)] = cov[(0, 0)];
        s[(0, 1)] = cov[(0, 1)];
        s[(0, 2)] = cov[(0, 2)];
        s[(0, 3)] = _t3;
        s[(1, 1)] = cov[(1, 1)];
        s[(1, 2)] = cov[(1, 2)];
        s[(1, 3)] = _t4;
        s[(2, 2)] = cov[(2, 2)];
        s[(2, 3)] = _t5;
        s[(3, 3)] = _t0 * _t7 + _t1 * _t6 + _t2 * _t8;
        for i in 0..4 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
#[cfg(test)]
#[allow(clippy::possible_missing_comma, non_snake_case)]
mod __leveling6_generated_tests {
    use super::*;
    use ::nav_runtime::model::{Model, Record, Sensor};
    use ::nav_runtime::nalgebra::{SMatrix, SVector};
    /// The model's scalar.
    type S = f64;
    /// Finite-difference step (relative), tolerance of a Jacobian entry
    /// against it, and tolerance of the sparse covariance algebra
    /// against dense products, for this scalar's precision.
    const FD_STEP: S = 1e-6;
    const FD_TOLERANCE: S = 1e-6;
    const RELATIVE: S = 1e-12;
    const N: usize = 6;
    const NW: usize = 6;
    /// Points checked per test.
    const POINTS: usize = 6;
    /// Random draws tried to find them (points with non-finite values, or a kink within a step, are skipped).
    const ATTEMPTS: usize = 400;
    /// Calls `check` at random `(x, u, p, dt)` (it draws anything else from
    /// `rng`) until `POINTS` points were usable (`check` returns true
    /// for those); fails if none had.
    fn at_random_points(
        seed: u64,
        mut check: impl FnMut(
            &mut SplitMix64,
            SVector<S, N>,
            Leveling6Input,
            Leveling6Params,
            S,
        ) -> bool,
    ) {
        let mut rng = SplitMix64(seed);
        let mut checked = 0;
        for _ in 0..ATTEMPTS {
            if checked == POINTS {
                break;
            }
            let x = random_vector::<N>(&mut rng);
            let u: Leveling6Input = random_record(&mut rng);
            let p: Leveling6Params = random_record(&mut rng);
            let dt = random_dt(&mut rng);
            if check(&mut rng, x, u, p, dt) {
                checked += 1;
            }
        }
        assert!(checked > 0, "no point with finite values found");
    }
    /// splitmix64: a tiny deterministic generator.
    struct SplitMix64(u64);
    impl SplitMix64 {
        fn next_u64(&mut self) -> u64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            z ^ (z >> 31)
        }
        /// Uniform in [-1, 1].
        fn uniform(&mut self) -> f64 {
            ((self.next_u64() >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
        }
    }
    fn abs(v: S) -> S {
        ::nav_runtime::math::abs(v)
    }
    /// A uniform draw in [-1, 1] in the model's scalar.
    fn draw(rng: &mut SplitMix64) -> S {
        <S as ::nav_runtime::Real>::of(rng.uniform())
    }
    fn random_record<R: Record>(rng: &mut SplitMix64) -> R {
        R::from_fn(|_| rng.uniform())
    }
    fn random_vector<const K: usize>(rng: &mut SplitMix64) -> SVector<S, K> {
        SVector::<S, K>::from_fn(|_, _| draw(rng))
    }
    fn random_dt(rng: &mut SplitMix64) -> S {
        0.01 + 0.1 * abs(draw(rng))
    }
    /// A random symmetric positive definite matrix `L L^T + I`.
    fn random_covariance(rng: &mut SplitMix64) -> SMatrix<S, N, N> {
        let l = SMatrix::<S, N, N>::from_fn(|_, _| draw(rng));
        l * l.transpose() + SMatrix::<S, N, N>::identity()
    }
    /// The upper triangle of `m`, NaN below (generated code must not read it).
    fn upper_only(m: &SMatrix<S, N, N>) -> SMatrix<S, N, N> {
        SMatrix::<S, N, N>::from_fn(|i, j| if i <= j { m[(i, j)] } else { S::NAN })
    }
    fn finite<const R: usize, const C: usize>(m: &SMatrix<S, R, C>) -> bool {
        m.iter().all(|v| v.is_finite())
    }
    /// Central differences with step `FD_STEP (1 + |x_j|)`, and for each entry
    /// the rounding bound `4 eps |f| / step` of the difference quotient
    /// (it matters only for outputs of order 1e6, such as Earth radii, or
    /// in `f32`). `None` where the step straddles a kink of a non-smooth
    /// function (`min`, `max`, `clamp`, `abs`, `sign`): the one-sided
    /// quotients then disagree by far more than curvature explains, and
    /// the central one is no derivative.
    fn fd_jacobian<const R: usize, const C: usize>(
        x: &SVector<S, C>,
        f: impl Fn(&SVector<S, C>) -> SVector<S, R>,
    ) -> Option<(SMatrix<S, R, C>, SMatrix<S, R, C>)> {
        let mut out = SMatrix::<S, R, C>::zeros();
        let mut rounding = SMatrix::<S, R, C>::zeros();
        let f0 = f(x);
        for j in 0..C {
            let h = FD_STEP * (1.0 + abs(x[j]));
            let (mut xp, mut xm) = (*x, *x);
            xp[j] += h;
            xm[j] -= h;
            let (fp, fm) = (f(&xp), f(&xm));
            let col = (fp - fm) / (xp[j] - xm[j]);
            for r in 0..R {
                let big = if abs(fp[r]) > abs(fm[r]) { abs(fp[r]) } else { abs(fm[r]) };
                rounding[(r, j)] = 4.0 * S::EPSILON * big / h;
                let forward = (fp[r] - f0[r]) / (xp[j] - x[j]);
                let backward = (f0[r] - fm[r]) / (x[j] - xm[j]);
                if abs(forward - backward)
                    > 0.25 * (1.0 + abs(col[r])) + 4.0 * rounding[(r, j)]
                {
                    return None;
                }
            }
            out.set_column(j, &col);
        }
        Some((out, rounding))
    }
    /// `|J - J_fd| <= FD_TOLERANCE (1 + |J|)` entrywise (plus the rounding bound).
    fn assert_close_fd<const R: usize, const C: usize>(
        what: &str,
        j: &SMatrix<S, R, C>,
        (fd, rounding): &(SMatrix<S, R, C>, SMatrix<S, R, C>),
    ) {
        for r in 0..R {
            for c in 0..C {
                let (a, b) = (j[(r, c)], fd[(r, c)]);
                assert!(
                    abs(a - b) <= FD_TOLERANCE * (1.0 + abs(a)) + rounding[(r, c)],
                    "{what}[({r}, {c})]: generated {a} vs finite differences {b}"
                );
            }
        }
    }
    /// Equal to `RELATIVE` relative to the largest entry of `want`.
    fn assert_close_rel<const R: usize, const C: usize>(
        what: &str,
        got: &SMatrix<S, R, C>,
        want: &SMatrix<S, R, C>,
    ) {
        let scale = want
            .iter()
            .fold(1.0 as S, |m, v| if abs(*v) > m { abs(*v) } else { m });
        for r in 0..R {
            for c in 0..C {
                let (a, b) = (got[(r, c)], want[(r, c)]);
                assert!(
                    abs(a - b) <= RELATIVE * scale,
                    "{what}[({r}, {c})]: generated {a} vs dense {b}"
                );
            }
        }
    }
    fn assert_sparsity<const R: usize, const C: usize>(
        what: &str,
        j: &SMatrix<S, R, C>,
        sparsity: &[[bool; C]; R],
    ) {
        for r in 0..R {
            for c in 0..C {
                assert!(
                    sparsity[r] [c] || j[(r, c)] == 0.0,
                    "{what}[({r}, {c})] is a structural zero but is {}", j[(r, c)]
                );
            }
        }
    }
    #[test]
    fn jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0000,
            |rng, x, u, p, dt| {
                let jac = <Leveling6 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let f = |x: &SVector<S, N>| Leveling6::derivative(x, &u, &p);
                let Some(fd) = fd_jacobian(&x, f) else { return false };
                if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd("jacobian", &jac, &fd);
                assert_sparsity(
                    "jacobian",
                    &jac,
                    &<Leveling6 as Model<N, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn noise_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0001,
            |rng, x, u, p, dt| {
                let g = Leveling6::noise_jacobian(&x, &u, &p, dt);
                let f = |w: &SVector<S, NW>| Leveling6::derivative_with_noise(
                    &x,
                    &u,
                    &p,
                    w,
                );
                let w0 = SVector::<S, NW>::zeros();
                let Some(fd) = fd_jacobian(&w0, f) else { return false };
                if !finite(&f(&w0)) || !finite(&g) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd("noise_jacobian", &g, &fd);
                true
            },
        );
    }
    #[test]
    fn propagate_covariance_matches_dense_products() {
        at_random_points(
            0x5eed_0004,
            |rng, x, u, p, dt| {
                let q: Leveling6Noise = <Leveling6Noise as Record>::from_fn(|_| ::nav_runtime::math::abs(
                    rng.uniform(),
                ));
                let cov = random_covariance(rng);
                let jac = <Leveling6 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let g = Leveling6::noise_jacobian(&x, &u, &p, dt);
                if !finite(&jac) || !finite(&g) {
                    return false;
                }
                let qdiag = SMatrix::<
                    S,
                    NW,
                    NW,
                >::from_fn(|i, j| {
                    if i == j { <S as ::nav_runtime::Real>::of(q.get(i)) } else { 0.0 }
                });
                let qd_dense = g * qdiag * g.transpose() * dt;
                let qd = <Leveling6 as Model<N, S>>::process_noise(&x, &u, &p, &q, dt);
                assert_close_rel("process_noise", &qd, &qd_dense);
                let phi = SMatrix::<S, N, N>::identity() + jac * dt;
                let dense = phi * cov * phi.transpose() + qd_dense;
                let mut got = cov;
                <Leveling6 as Model<
                    N,
                    S,
                >>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                assert_close_rel("propagate_covariance", &got, &dense);
                assert_eq!(
                    got, got.transpose(), "the propagated covariance must be symmetric"
                );
                let mut observed = cov;
                let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                <Leveling6 as Model<
                    N,
                    S,
                >>::propagate_covariance_observed(
                    &mut observed,
                    &x,
                    &u,
                    &p,
                    &q,
                    dt,
                    |c| {
                        let s = <Leveling6 as Model<N, S>>::PROPAGATION
                            .expect("observed only over a structure");
                        let mut m = SMatrix::<S, N, N>::identity();
                        for (r, &i) in s.rows.iter().enumerate() {
                            if !s.identity {
                                m[(i, i)] = 0.0;
                            }
                            for k in s.start[r]..s.start[r + 1] {
                                m[(i, s.columns[k])] += c[k];
                            }
                        }
                        rebuilt = Some(m);
                    },
                );
                assert_eq!(
                    observed, got,
                    "propagate_covariance_observed equals propagate_covariance"
                );
                assert_eq!(
                    rebuilt.is_some(), < Leveling6 as Model < N, S >> ::PROPAGATION
                    .is_some(), "observed once over a structure"
                );
                if let Some(m) = rebuilt {
                    assert_close_rel("observed transition", &m, &phi);
                }
                true
            },
        );
    }
    #[test]
    fn state_record_round_trips() {
        let mut rng = SplitMix64(0x5eed_0005);
        let x = random_vector::<N>(&mut rng);
        let s = Leveling6State::from_vector(&x);
        assert_eq!(s.to_vector(), x);
        for i in 0..N {
            assert_eq!(s.get(i), < S as ::nav_runtime::Real > ::to_f64(x[i]));
        }
        assert_eq!(<< Leveling6 as Model < N, S >> ::State as Record > ::NAMES.len(), N);
        assert_eq!(< Leveling6 as Model < N, S >> ::STATE_NAMES.len(), N);
    }
    #[test]
    fn sensor_moving_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Leveling6Moving as Sensor<N, 2, S>>::Aux = random_record(rng);
                let jac = <Leveling6Moving as Sensor<
                    N,
                    2,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Leveling6Moving as Sensor<
                    N,
                    2,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Leveling6Moving), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Leveling6Moving), "::jacobian"),
                    &jac,
                    &<Leveling6Moving as Sensor<N, 2, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_moving_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Leveling6Moving as Sensor<N, 2, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Leveling6Moving as Sensor<
                    N,
                    2,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Leveling6Moving as Sensor<
                    N,
                    2,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Leveling6Moving as Sensor<
                    N,
                    2,
                    S,
                >>::innovation_terms(&upper_only(&cov), &x, &u, &p, &aux);
                assert_close_rel("h", &h, &pred);
                assert_close_rel("P H^T", &pht, &(cov * hjac.transpose()));
                assert_close_rel("H P H^T", &s, &(hjac * cov * hjac.transpose()));
                assert_eq!(s, s.transpose(), "H P H^T must be symmetric");
                true
            },
        );
    }
    #[test]
    fn sensor_stationary_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Leveling6Stationary as Sensor<N, 4, S>>::Aux = random_record(
                    rng,
                );
                let jac = <Leveling6Stationary as Sensor<
                    N,
                    4,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Leveling6Stationary as Sensor<
                    N,
                    4,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Leveling6Stationary), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Leveling6Stationary), "::jacobian"),
                    &jac,
                    &<Leveling6Stationary as Sensor<N, 4, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_stationary_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Leveling6Stationary as Sensor<N, 4, S>>::Aux = random_record(
                    rng,
                );
                let cov = random_covariance(rng);
                let hjac = <Leveling6Stationary as Sensor<
                    N,
                    4,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Leveling6Stationary as Sensor<
                    N,
                    4,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Leveling6Stationary as Sensor<
                    N,
                    4,
                    S,
                >>::innovation_terms(&upper_only(&cov), &x, &u, &p, &aux);
                assert_close_rel("h", &h, &pred);
                assert_close_rel("P H^T", &pht, &(cov * hjac.transpose()));
                assert_close_rel("H P H^T", &s, &(hjac * cov * hjac.transpose()));
                assert_eq!(s, s.transpose(), "H P H^T must be symmetric");
                true
            },
        );
    }
}
