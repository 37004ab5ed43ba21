// Expansion of `nav_runtime::model!` in models/src/marker/model.rs, formatted.
// Checked by `snapshots_are_current` (nav-macros/src/lib.rs); regenerate with
// `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`.
//
// Op counts:
//   Marker9::OPS_TRANSITION = 80
//   Marker9::OPS_JACOBIAN = 112
//   Marker9::OPS_NOISE_JACOBIAN = 0
//   Marker9::OPS_PROCESS_NOISE = 0
//   Marker9::OPS_PROPAGATE_COVARIANCE = 683
//   Marker9Dvl::OPS_PREDICT = 0
//   Marker9Dvl::OPS_JACOBIAN = 0
//   Marker9Dvl::OPS_INNOVATION_TERMS = 0
//   Marker9Depth::OPS_PREDICT = 0
//   Marker9Depth::OPS_JACOBIAN = 0
//   Marker9Depth::OPS_INNOVATION_TERMS = 0
//   Marker9MarkerFix::OPS_PREDICT = 0
//   Marker9MarkerFix::OPS_JACOBIAN = 0
//   Marker9MarkerFix::OPS_INNOVATION_TERMS = 0
//   Marker9MarkerRelative::OPS_PREDICT = 45
//   Marker9MarkerRelative::OPS_JACOBIAN = 76
//   Marker9MarkerRelative::OPS_INNOVATION_TERMS = 419

///The state of [`Marker9`] (9 scalars), with named fields.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Marker9State {
    /// NED position in the local structure frame, m.
    pub position: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Body-frame velocity `[u, v, w]`, m/s.
    pub velocity: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Euler angles `[roll, pitch, yaw]`, rad.
    pub euler: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Marker9State {
    const LEN: usize = 9;
    const NAMES: &'static [&'static str] = &[
        "position[0]",
        "position[1]",
        "position[2]",
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "euler[0]",
        "euler[1]",
        "euler[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 9] = [0.0; 9];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            position: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            velocity: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
            euler: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[6..9]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.position[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.position[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.position[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[2]),
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.euler[0]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.euler[1]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.euler[2]),
            _ => f64::NAN,
        }
    }
}
#[allow(clippy::possible_missing_comma)]
impl Marker9State {
    /// The state from its vector (declaration order).
    pub fn from_vector(v: &::nav_runtime::nalgebra::SVector<f64, 9>) -> Self {
        <Self as ::nav_runtime::model::Record>::from_fn(|i| <f64 as ::nav_runtime::Real>::to_f64(
            v[i],
        ))
    }
    /// The state as a vector (declaration order).
    pub fn to_vector(&self) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        ::nav_runtime::nalgebra::SVector::<
            f64,
            9,
        >::from_column_slice(
            &[
                self.position[0],
                self.position[1],
                self.position[2],
                self.velocity[0],
                self.velocity[1],
                self.velocity[2],
                self.euler[0],
                self.euler[1],
                self.euler[2],
            ],
        )
    }
}
///The inputs `u` of [`Marker9`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Marker9Input {
    /// Gyro output `[p, q, r]`, rad/s.
    pub gyro: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Body-frame acceleration with gravity removed, m/s^2.
    pub acceleration: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Marker9Input {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "gyro[0]",
        "gyro[1]",
        "gyro[2]",
        "acceleration[0]",
        "acceleration[1]",
        "acceleration[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 6] = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            gyro: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            acceleration: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.acceleration[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.acceleration[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.acceleration[2]),
            _ => f64::NAN,
        }
    }
}
///The parameters `p` of [`Marker9`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Marker9Params {}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Marker9Params {
    const LEN: usize = 0;
    const NAMES: &'static [&'static str] = &[];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 0] = [0.0; 0];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {}
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            _ => f64::NAN,
        }
    }
}
///The per-step process-noise variances `q` of [`Marker9`], one per noise scalar.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Marker9Noise {
    /// Per-step velocity variance from accelerometer noise, (m/s)^2.
    pub velocity_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Per-step attitude variance from gyro noise, rad^2.
    pub attitude_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Marker9Noise {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "velocity_noise[0]",
        "velocity_noise[1]",
        "velocity_noise[2]",
        "attitude_noise[0]",
        "attitude_noise[1]",
        "attitude_noise[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 6] = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            velocity_noise: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            attitude_noise: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_noise[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_noise[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_noise[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_noise[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_noise[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_noise[2]),
            _ => f64::NAN,
        }
    }
}
///The auxiliary inputs of sensor [`Marker9MarkerRelative`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Marker9MarkerRelativeAux {
    /// Marker position in the local (structure) frame, m.
    pub marker: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Camera position in body axes, m.
    pub lever_arm: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Marker9MarkerRelativeAux {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "marker[0]",
        "marker[1]",
        "marker[2]",
        "lever_arm[0]",
        "lever_arm[1]",
        "lever_arm[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 6] = [0.0; 6];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            marker: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            lever_arm: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.marker[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.marker[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.marker[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.lever_arm[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.lever_arm[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.lever_arm[2]),
            _ => f64::NAN,
        }
    }
}
/// Marker-fusion filter, eq. 2 of the marker paper, with the body-frame
/// velocity equation completed by the transport term `-w x v` (the paper's
/// `v_k = v_{k-1} + a dt` holds only without rotation).
///
///Generated by `model!`: discrete model with 9 states, 6 noise inputs and 4 sensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Marker9;
#[allow(clippy::possible_missing_comma)]
impl Marker9 {
    /// Number of scalar states.
    pub const N: usize = 9;
    /// Number of scalar process-noise inputs.
    pub const NW: usize = 6;
    ///Index of the first scalar of `position` in the state vector.
    pub const POSITION: usize = 0;
    ///Index of the first scalar of `velocity` in the state vector.
    pub const VELOCITY: usize = 3;
    ///Index of the first scalar of `euler` in the state vector.
    pub const EULER: usize = 6;
    /// State scalars no sensor depends on, directly or through the dynamics
    /// (no measurement can correct them). The model lists them in
    /// `allow_unused { .. }` (checked at compile time).
    pub const UNUSED_STATES: &'static [&'static str] = &[];
    /// Operations in `transition`.
    pub const OPS_TRANSITION: usize = 80;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 112;
    /// Operations in [`Self::noise_jacobian`].
    pub const OPS_NOISE_JACOBIAN: usize = 0;
    /// Operations in `process_noise`.
    pub const OPS_PROCESS_NOISE: usize = 0;
    /// Operations in `propagate_covariance`.
    pub const OPS_PROPAGATE_COVARIANCE: usize = 683;
    ///Structure of `Phi` (`df/dx`) and `Qd` for the covariance propagation: rows [0, 1, 2, 3, 4, 5, 6, 7, 8] change, the others are unit rows.
    pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> = ::nav_runtime::propagation::Structure {
        identity: false,
        rows: &[0, 1, 2, 3, 4, 5, 6, 7, 8],
        start: &[0, 7, 14, 20, 23, 26, 29, 31, 33, 36],
        columns: &[
            0, 3, 4, 5, 6, 7, 8, 1, 3, 4, 5, 6, 7, 8, 2, 3, 4, 5, 6, 7, 3, 4, 5, 3, 4, 5,
            3, 4, 5, 6, 7, 6, 7, 6, 7, 8,
        ],
        noise: &[(3, 3), (4, 4), (5, 5), (6, 6), (7, 7), (8, 8)],
    };
    /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
    pub const SENSORS: [&'static str; 4] = [
        "Dvl",
        "Depth",
        "MarkerFix",
        "MarkerRelative",
    ];
    /// Per sensor, per state scalar: the sensor's `h` depends on the state
    /// directly (a structural nonzero of its `H`).
    pub const SENSOR_DEPENDS: [[bool; 9]; 4] = [
        [false, false, false, true, true, true, false, false, false],
        [false, false, true, false, false, false, false, false, false],
        [true, true, false, false, false, false, false, false, false],
        [true, true, true, false, false, false, true, true, true],
    ];
    /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
    /// indices into `SENSORS`); the set of all sensors when it declares none.
    pub const RUNS_WITH: [&'static [usize]; 1] = [&[0, 1, 2, 3]];
    /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
    /// that set (checked at compile time against `allow_unused`).
    pub const RUNS_WITH_OBSERVABLE: [[bool; 9]; 1] = [
        [true, true, true, true, true, true, true, true, true],
    ];
    /// Per state scalar: is it structurally observable with the sensors marked
    /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
    /// a measurement of one of them, through a sensor's `H` or the dynamics
    /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
    /// only: `false` means no measurement of that set can ever correct the
    /// state; `true` means only that sparsity does not exclude it (see
    /// `docs/language.md`, "Structural observability").
    pub const fn structurally_observable(sensors: &[bool; 4]) -> [bool; 9] {
        let deps = Self::SENSOR_DEPENDS;
        let f = <Self as ::nav_runtime::model::Model<9, f64>>::JACOBIAN_SPARSITY;
        let mut seen = [false; 9];
        let mut s = 0;
        while s < 4 {
            if sensors[s] {
                let mut j = 0;
                while j < 9 {
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
            while i < 9 {
                if seen[i] {
                    let mut j = 0;
                    while j < 9 {
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
    /**The state after one step of `dt` seconds with an explicit noise sample `w`: `f(x, u, p, dt, w)` (`transition` at `w = 0`).

Total ops: 86*/
    pub fn step_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let (_t0, _t5) = ::nav_runtime::math::sin_cos(x[6]);
        let (_t1, _t6) = ::nav_runtime::math::sin_cos(x[7]);
        let _t2 = _t0 * _t1;
        let (_t4, _t3) = ::nav_runtime::math::sin_cos(x[8]);
        let _t7 = _t5 * _t1;
        let _t8 = 1.0 / _t6;
        let _t9 = _t5 * u.gyro[2] + _t0 * u.gyro[1];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = ((_t2 * _t3 - _t4 * _t5) * x[4] + _t3 * _t6 * x[3]
            + (_t4 * _t0 + _t3 * _t7) * x[5]) * dt + x[0];
        out[1] = dt
            * (x[4] * (_t5 * _t3 + _t4 * _t2) + x[3] * (_t4 * _t6)
                + x[5] * (_t4 * _t7 - _t0 * _t3)) + x[1];
        out[2] = dt * (x[4] * (_t0 * _t6) - _t1 * x[3] + x[5] * (_t5 * _t6)) + x[2];
        out[3] = x[3] + dt * (u.acceleration[0] - (x[5] * u.gyro[1] - x[4] * u.gyro[2]))
            + w[0];
        out[4] = x[4] + dt * (u.acceleration[1] - (x[3] * u.gyro[2] - x[5] * u.gyro[0]))
            + w[1];
        out[5] = x[5] + dt * (u.acceleration[2] - (x[4] * u.gyro[0] - x[3] * u.gyro[1]))
            + w[2];
        out[6] = x[6] + dt * (u.gyro[0] + _t1 * _t8 * _t9) + w[3];
        out[7] = x[7] + dt * (_t5 * u.gyro[1] - _t0 * u.gyro[2]) + w[4];
        out[8] = x[8] + dt * (_t8 * _t9) + w[5];
        out
    }
    /**The noise Jacobian `G = df/dw` of the step at `w = 0` (N x NW, noise scalars in declaration order).

Total ops: 0*/
    pub fn noise_jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 9, 6> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 6>::zeros();
        out[(3, 0)] = 1.0;
        out[(4, 1)] = 1.0;
        out[(5, 2)] = 1.0;
        out[(6, 3)] = 1.0;
        out[(7, 4)] = 1.0;
        out[(8, 5)] = 1.0;
        out
    }
}
impl ::nav_runtime::propagation::StaticStructure for Marker9 {
    const STRUCTURE: ::nav_runtime::propagation::Structure<'static> = Self::PROPAGATION_STRUCTURE;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Model<9, f64> for Marker9 {
    type Input = Marker9Input;
    type Params = Marker9Params;
    type Noise = Marker9Noise;
    type State = Marker9State;
    const NAME: &'static str = "Marker9";
    const DISCRETE: bool = !false;
    const STATE_NAMES: [&'static str; 9] = [
        "position[0]",
        "position[1]",
        "position[2]",
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "euler[0]",
        "euler[1]",
        "euler[2]",
    ];
    const JACOBIAN_SPARSITY: [[bool; 9]; 9] = [
        [true, false, false, true, true, true, true, true, true],
        [false, true, false, true, true, true, true, true, true],
        [false, false, true, true, true, true, true, true, false],
        [false, false, false, true, true, true, false, false, false],
        [false, false, false, true, true, true, false, false, false],
        [false, false, false, true, true, true, false, false, false],
        [false, false, false, false, false, false, true, true, false],
        [false, false, false, false, false, false, true, true, false],
        [false, false, false, false, false, false, true, true, true],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 683;
    const OPS_JACOBIAN: usize = 112;
    const ZERO_IS_FIXED: bool = false;
    /**The next state `f(x, u, p, dt)` (noise-free).

Total ops: 80*/
    fn transition(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let (_t0, _t5) = ::nav_runtime::math::sin_cos(x[6]);
        let (_t1, _t6) = ::nav_runtime::math::sin_cos(x[7]);
        let _t2 = _t0 * _t1;
        let (_t4, _t3) = ::nav_runtime::math::sin_cos(x[8]);
        let _t7 = _t5 * _t1;
        let _t8 = 1.0 / _t6;
        let _t9 = _t5 * u.gyro[2] + _t0 * u.gyro[1];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = ((_t2 * _t3 - _t4 * _t5) * x[4] + _t3 * _t6 * x[3]
            + (_t4 * _t0 + _t3 * _t7) * x[5]) * dt + x[0];
        out[1] = dt
            * (x[4] * (_t5 * _t3 + _t4 * _t2) + x[3] * (_t4 * _t6)
                + x[5] * (_t4 * _t7 - _t0 * _t3)) + x[1];
        out[2] = dt * (x[4] * (_t0 * _t6) - _t1 * x[3] + x[5] * (_t5 * _t6)) + x[2];
        out[3] = x[3] + dt * (u.acceleration[0] - (x[5] * u.gyro[1] - x[4] * u.gyro[2]));
        out[4] = x[4] + dt * (u.acceleration[1] - (x[3] * u.gyro[2] - x[5] * u.gyro[0]));
        out[5] = x[5] + dt * (u.acceleration[2] - (x[4] * u.gyro[0] - x[3] * u.gyro[1]));
        out[6] = x[6] + dt * (u.gyro[0] + _t1 * _t8 * _t9);
        out[7] = x[7] + dt * (_t5 * u.gyro[1] - _t0 * u.gyro[2]);
        out[8] = x[8] + dt * (_t8 * _t9);
        out
    }
    /**`Phi = df/dx` at `w = 0`.

Total ops: 112*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 9, 9> {
        let (_t7, _t0) = ::nav_runtime::math::sin_cos(x[8]);
        let (_t3, _t1) = ::nav_runtime::math::sin_cos(x[7]);
        let _t2 = _t0 * _t1;
        let (_t4, _t8) = ::nav_runtime::math::sin_cos(x[6]);
        let _t5 = _t3 * _t4;
        let _t6 = _t0 * _t5;
        let _t9 = _t7 * _t8;
        let _t10 = _t6 - _t9;
        let _t11 = _t8 * _t3;
        let _t12 = _t7 * _t4 + _t0 * _t11;
        let _t13 = _t1 * _t4;
        let _t14 = _t1 * _t8;
        let _t15 = _t0 * _t4;
        let _t16 = _t7 * _t11;
        let _t17 = _t0 * _t8 + _t7 * _t5;
        let _t18 = _t1 * _t7;
        let _t19 = _t16 - _t15;
        let _t20 = -dt;
        let _t21 = dt * u.gyro[2];
        let _t22 = dt * u.gyro[1];
        let _t23 = dt * u.gyro[0];
        let _t24 = _t8 * u.gyro[1] - _t4 * u.gyro[2];
        let _t25 = 1.0 / _t1;
        let _t26 = _t3 * _t25;
        let _t27 = _t8 * u.gyro[2] + _t4 * u.gyro[1];
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 9>::zeros();
        out[(0, 0)] = 1.0;
        out[(0, 3)] = _t2 * dt;
        out[(0, 4)] = dt * _t10;
        out[(0, 5)] = dt * _t12;
        out[(0, 6)] = dt * (_t12 * x[4] + (_t9 - _t6) * x[5]);
        out[(0, 7)] = dt
            * (x[4] * (_t0 * _t13) - _t0 * _t3 * x[3] + x[5] * (_t0 * _t14));
        out[(0, 8)] = dt * (x[5] * (_t15 - _t16) - (x[4] * _t17 + x[3] * _t18));
        out[(1, 1)] = 1.0;
        out[(1, 3)] = dt * _t18;
        out[(1, 4)] = dt * _t17;
        out[(1, 5)] = dt * _t19;
        out[(1, 6)] = dt * (x[4] * _t19 - x[5] * _t17);
        out[(1, 7)] = dt
            * (x[4] * (_t7 * _t13) - x[3] * (_t7 * _t3) + x[5] * (_t7 * _t14));
        out[(1, 8)] = dt * (_t10 * x[4] + _t2 * x[3] + _t12 * x[5]);
        out[(2, 2)] = 1.0;
        out[(2, 3)] = _t20 * _t3;
        out[(2, 4)] = dt * _t13;
        out[(2, 5)] = dt * _t14;
        out[(2, 6)] = dt * (x[4] * _t14 - x[5] * _t13);
        out[(2, 7)] = _t20 * (_t1 * x[3] + _t5 * x[4] + _t11 * x[5]);
        out[(3, 3)] = 1.0;
        out[(3, 4)] = _t21;
        out[(3, 5)] = -_t22;
        out[(4, 3)] = -_t21;
        out[(4, 4)] = 1.0;
        out[(4, 5)] = _t23;
        out[(5, 3)] = _t22;
        out[(5, 4)] = -_t23;
        out[(5, 5)] = 1.0;
        out[(6, 6)] = 1.0 + dt * (_t24 * _t26);
        out[(6, 7)] = dt * ((1.0 + _t26 * _t26) * _t27);
        out[(7, 6)] = _t20 * _t27;
        out[(7, 7)] = 1.0;
        out[(8, 6)] = dt * (_t24 * _t25);
        out[(8, 7)] = dt * (_t25 * (_t3 * (_t25 * _t27)));
        out[(8, 8)] = 1.0;
        out
    }
    /**`Qd = G Q G^T`, `Q = diag(q)`.

Total ops: 0*/
    fn process_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        q: &Marker9Noise,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 9, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 9>::zeros();
        out[(3, 3)] = q.velocity_noise[0];
        out[(4, 4)] = q.velocity_noise[1];
        out[(5, 5)] = q.velocity_noise[2];
        out[(6, 6)] = q.attitude_noise[0];
        out[(7, 7)] = q.attitude_noise[1];
        out[(8, 8)] = q.attitude_noise[2];
        for i in 0..9 {
            for j in 0..i {
                out[(i, j)] = out[(j, i)];
            }
        }
        out
    }
    /**`P <- Phi P Phi^T + Qd` unrolled entry by entry from the upper triangle of `P` (a small model: straight-line code fits the caches), generated from the sparsity of `Phi` and `G`; the result is mirrored.

Total ops: 683*/
    fn propagate_covariance(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        q: &Marker9Noise,
        dt: f64,
    ) {
        let _p = *cov;
        let (_t9, _t0) = ::nav_runtime::math::sin_cos(x[8]);
        let (_t4, _t1) = ::nav_runtime::math::sin_cos(x[7]);
        let _t2 = _t0 * _t1;
        let _t3 = _t2 * dt;
        let (_t5, _t8) = ::nav_runtime::math::sin_cos(x[6]);
        let _t6 = _t4 * _t5;
        let _t7 = _t0 * _t6;
        let _t10 = _t8 * _t9;
        let _t11 = _t7 - _t10;
        let _t12 = dt * _t11;
        let _t13 = _t8 * _t4;
        let _t14 = _t9 * _t5 + _t0 * _t13;
        let _t15 = dt * _t14;
        let _t16 = dt * (_t14 * x[4] + (_t10 - _t7) * x[5]);
        let _t17 = _t1 * _t5;
        let _t18 = _t1 * _t8;
        let _t19 = dt * (x[4] * (_t0 * _t17) - _t0 * _t4 * x[3] + x[5] * (_t0 * _t18));
        let _t20 = _t0 * _t5;
        let _t21 = _t9 * _t13;
        let _t22 = _t0 * _t8 + _t9 * _t6;
        let _t23 = _t1 * _t9;
        let _t24 = dt * (x[5] * (_t20 - _t21) - (x[4] * _t22 + x[3] * _t23));
        let _t25 = _p[(3, 3)] * _t3 + _p[(0, 3)] + _p[(3, 4)] * _t12 + _p[(3, 5)] * _t15
            + _p[(3, 6)] * _t16 + _p[(3, 7)] * _t19 + _p[(3, 8)] * _t24;
        let _t26 = _p[(0, 4)] + _t3 * _p[(3, 4)] + _t12 * _p[(4, 4)] + _t15 * _p[(4, 5)]
            + _t16 * _p[(4, 6)] + _t19 * _p[(4, 7)] + _t24 * _p[(4, 8)];
        let _t27 = _p[(0, 5)] + _t3 * _p[(3, 5)] + _t12 * _p[(4, 5)] + _t15 * _p[(5, 5)]
            + _t16 * _p[(5, 6)] + _t19 * _p[(5, 7)] + _t24 * _p[(5, 8)];
        let _t28 = _p[(0, 6)] + _t3 * _p[(3, 6)] + _t12 * _p[(4, 6)] + _t15 * _p[(5, 6)]
            + _t16 * _p[(6, 6)] + _t19 * _p[(6, 7)] + _t24 * _p[(6, 8)];
        let _t29 = _p[(0, 7)] + _t3 * _p[(3, 7)] + _t12 * _p[(4, 7)] + _t15 * _p[(5, 7)]
            + _t16 * _p[(6, 7)] + _t19 * _p[(7, 7)] + _t24 * _p[(7, 8)];
        let _t30 = _p[(0, 8)] + _t3 * _p[(3, 8)] + _t12 * _p[(4, 8)] + _t15 * _p[(5, 8)]
            + _t16 * _p[(6, 8)] + _t19 * _p[(7, 8)] + _t24 * _p[(8, 8)];
        let _t31 = dt * _t23;
        let _t32 = dt * _t22;
        let _t33 = _t21 - _t20;
        let _t34 = dt * _t33;
        let _t35 = dt * (x[4] * _t33 - x[5] * _t22);
        let _t36 = dt * (x[4] * (_t9 * _t17) - x[3] * (_t9 * _t4) + x[5] * (_t9 * _t18));
        let _t37 = dt * (_t11 * x[4] + _t2 * x[3] + _t14 * x[5]);
        let _t38 = dt * _t4;
        let _t39 = dt * _t17;
        let _t40 = dt * _t18;
        let _t41 = dt * (x[4] * _t18 - x[5] * _t17);
        let _t42 = dt * (_t1 * x[3] + _t6 * x[4] + _t13 * x[5]);
        let _t43 = dt * u.gyro[2];
        let _t44 = dt * u.gyro[1];
        let _t45 = dt * u.gyro[0];
        let _t46 = 1.0 / _t1;
        let _t47 = _t4 * _t46;
        let _t48 = _t8 * u.gyro[2] + _t5 * u.gyro[1];
        let _t49 = dt * ((1.0 + _t47 * _t47) * _t48);
        let _t50 = _t8 * u.gyro[1] - _t5 * u.gyro[2];
        let _t51 = 1.0 + dt * (_t47 * _t50);
        let _t52 = dt * _t48;
        let _t53 = dt * (_t46 * (_t4 * (_t46 * _t48)));
        let _t54 = dt * (_t46 * _t50);
        let _t55 = _p[(1, 3)] + _p[(3, 3)] * _t31 + _p[(3, 4)] * _t32 + _p[(3, 5)] * _t34
            + _p[(3, 6)] * _t35 + _p[(3, 7)] * _t36 + _p[(3, 8)] * _t37;
        let _t56 = _p[(1, 4)] + _p[(3, 4)] * _t31 + _p[(4, 4)] * _t32 + _p[(4, 5)] * _t34
            + _p[(4, 6)] * _t35 + _p[(4, 7)] * _t36 + _p[(4, 8)] * _t37;
        let _t57 = _p[(1, 5)] + _p[(3, 5)] * _t31 + _p[(4, 5)] * _t32 + _p[(5, 5)] * _t34
            + _p[(5, 6)] * _t35 + _p[(5, 7)] * _t36 + _p[(5, 8)] * _t37;
        let _t58 = _p[(1, 6)] + _p[(3, 6)] * _t31 + _p[(4, 6)] * _t32 + _p[(5, 6)] * _t34
            + _p[(6, 6)] * _t35 + _p[(6, 7)] * _t36 + _p[(6, 8)] * _t37;
        let _t59 = _p[(1, 7)] + _p[(3, 7)] * _t31 + _p[(4, 7)] * _t32 + _p[(5, 7)] * _t34
            + _p[(6, 7)] * _t35 + _p[(7, 7)] * _t36 + _p[(7, 8)] * _t37;
        let _t60 = _p[(1, 8)] + _p[(3, 8)] * _t31 + _p[(4, 8)] * _t32 + _p[(5, 8)] * _t34
            + _p[(6, 8)] * _t35 + _p[(7, 8)] * _t36 + _p[(8, 8)] * _t37;
        let _t61 = _p[(2, 3)] - _p[(3, 3)] * _t38 + _p[(3, 4)] * _t39 + _p[(3, 5)] * _t40
            + _p[(3, 6)] * _t41 - _p[(3, 7)] * _t42;
        let _t62 = _p[(2, 4)] - _p[(3, 4)] * _t38 + _p[(4, 4)] * _t39 + _p[(4, 5)] * _t40
            + _p[(4, 6)] * _t41 - _p[(4, 7)] * _t42;
        let _t63 = _p[(2, 5)] - _p[(3, 5)] * _t38 + _p[(4, 5)] * _t39 + _p[(5, 5)] * _t40
            + _p[(5, 6)] * _t41 - _p[(5, 7)] * _t42;
        let _t64 = _p[(2, 6)] - _p[(3, 6)] * _t38 + _p[(4, 6)] * _t39 + _p[(5, 6)] * _t40
            + _p[(6, 6)] * _t41 - _p[(6, 7)] * _t42;
        let _t65 = _p[(2, 7)] - _p[(3, 7)] * _t38 + _p[(4, 7)] * _t39 + _p[(5, 7)] * _t40
            + _p[(6, 7)] * _t41 - _p[(7, 7)] * _t42;
        let _t66 = _p[(3, 4)] + _p[(4, 4)] * _t43 - _p[(4, 5)] * _t44;
        let _t67 = _p[(3, 4)] * _t43;
        let _t68 = _p[(3, 5)] * _t44;
        let _t69 = _p[(3, 3)] + _t67 - _t68;
        let _t70 = _p[(3, 5)] + _p[(4, 5)] * _t43 - _p[(5, 5)] * _t44;
        let _t71 = _p[(3, 7)] + _p[(4, 7)] * _t43 - _p[(5, 7)] * _t44;
        let _t72 = _p[(3, 6)] + _p[(4, 6)] * _t43 - _p[(5, 6)] * _t44;
        let _t73 = _p[(4, 5)] * _t45;
        let _t74 = _p[(4, 4)] - _t67 + _t73;
        let _t75 = _p[(3, 4)] - _p[(3, 3)] * _t43 + _p[(3, 5)] * _t45;
        let _t76 = _p[(4, 5)] - _p[(3, 5)] * _t43 + _p[(5, 5)] * _t45;
        let _t77 = _p[(4, 7)] - _p[(3, 7)] * _t43 + _p[(5, 7)] * _t45;
        let _t78 = _p[(4, 6)] - _p[(3, 6)] * _t43 + _p[(5, 6)] * _t45;
        let _t79 = _p[(5, 7)] + (_p[(3, 7)] * _t44 - _p[(4, 7)] * _t45);
        let _t80 = _p[(5, 6)] + (_p[(3, 6)] * _t44 - _p[(4, 6)] * _t45);
        let _t81 = _p[(7, 7)] * _t49 + _p[(6, 7)] * _t51;
        let _t82 = _p[(6, 7)] * _t49 + _p[(6, 6)] * _t51;
        let _t83 = _p[(7, 7)] - _p[(6, 7)] * _t52;
        let _t84 = _p[(6, 7)] - _p[(6, 6)] * _t52;
        cov[(0, 0)] = _t3 * _t25
            + (_t3 * _p[(0, 3)] + _p[(0, 0)] + _t12 * _p[(0, 4)] + _t15 * _p[(0, 5)]
                + _t16 * _p[(0, 6)] + _t19 * _p[(0, 7)] + _t24 * _p[(0, 8)])
            + _t12 * _t26 + _t15 * _t27 + _t16 * _t28 + _t19 * _t29 + _t24 * _t30;
        cov[(0, 1)] = _t25 * _t31
            + (_t3 * _p[(1, 3)] + _p[(0, 1)] + _t12 * _p[(1, 4)] + _t15 * _p[(1, 5)]
                + _t16 * _p[(1, 6)] + _t19 * _p[(1, 7)] + _t24 * _p[(1, 8)])
            + _t26 * _t32 + _t27 * _t34 + _t28 * _t35 + _t29 * _t36 + _t30 * _t37;
        cov[(0, 2)] = _t3 * _p[(2, 3)] + _p[(0, 2)] + _t12 * _p[(2, 4)]
            + _t15 * _p[(2, 5)] + _t16 * _p[(2, 6)] + _t19 * _p[(2, 7)]
            + _t24 * _p[(2, 8)] - _t25 * _t38 + _t26 * _t39 + _t27 * _t40 + _t28 * _t41
            - _t29 * _t42;
        cov[(0, 3)] = _t25 + _t26 * _t43 - _t27 * _t44;
        cov[(0, 4)] = _t26 - _t25 * _t43 + _t27 * _t45;
        cov[(0, 5)] = _t27 + (_t25 * _t44 - _t26 * _t45);
        cov[(0, 6)] = _t29 * _t49 + _t28 * _t51;
        cov[(0, 7)] = _t29 - _t28 * _t52;
        cov[(0, 8)] = _t30 + (_t29 * _t53 + _t28 * _t54);
        cov[(1, 1)] = _t31 * _t55
            + (_t31 * _p[(1, 3)] + _p[(1, 1)] + _p[(1, 4)] * _t32 + _p[(1, 5)] * _t34
                + _p[(1, 6)] * _t35 + _p[(1, 7)] * _t36 + _p[(1, 8)] * _t37)
            + _t32 * _t56 + _t34 * _t57 + _t35 * _t58 + _t36 * _t59 + _t37 * _t60;
        cov[(1, 2)] = _t31 * _p[(2, 3)] + _p[(1, 2)] + _t32 * _p[(2, 4)]
            + _t34 * _p[(2, 5)] + _t35 * _p[(2, 6)] + _t36 * _p[(2, 7)]
            + _t37 * _p[(2, 8)] - _t38 * _t55 + _t39 * _t56 + _t40 * _t57 + _t41 * _t58
            - _t42 * _t59;
        cov[(1, 3)] = _t55 + _t43 * _t56 - _t44 * _t57;
        cov[(1, 4)] = _t56 - _t43 * _t55 + _t45 * _t57;
        cov[(1, 5)] = _t57 + (_t44 * _t55 - _t45 * _t56);
        cov[(1, 6)] = _t49 * _t59 + _t51 * _t58;
        cov[(1, 7)] = _t59 - _t52 * _t58;
        cov[(1, 8)] = _t60 + (_t53 * _t59 + _t54 * _t58);
        cov[(2, 2)] = _p[(2, 2)] - _t38 * _p[(2, 3)] + _p[(2, 4)] * _t39
            + _p[(2, 5)] * _t40 + _p[(2, 6)] * _t41 - _t42 * _p[(2, 7)] - _t38 * _t61
            + _t39 * _t62 + _t40 * _t63 + _t41 * _t64 - _t42 * _t65;
        cov[(2, 3)] = _t61 + _t43 * _t62 - _t44 * _t63;
        cov[(2, 4)] = _t62 - _t43 * _t61 + _t45 * _t63;
        cov[(2, 5)] = _t63 + (_t44 * _t61 - _t45 * _t62);
        cov[(2, 6)] = _t49 * _t65 + _t51 * _t64;
        cov[(2, 7)] = _t65 - _t52 * _t64;
        cov[(2, 8)] = _t53 * _t65 + _t54 * _t64
            + (_p[(2, 8)] - _p[(3, 8)] * _t38 + _p[(4, 8)] * _t39 + _p[(5, 8)] * _t40
                + _p[(6, 8)] * _t41 - _p[(7, 8)] * _t42);
        cov[(3, 3)] = _t43 * _t66 + _t69 - _t44 * _t70 + q.velocity_noise[0];
        cov[(3, 4)] = _t66 - _t43 * _t69 + _t45 * _t70;
        cov[(3, 5)] = _t70 + (_t44 * _t69 - _t45 * _t66);
        cov[(3, 6)] = _t49 * _t71 + _t51 * _t72;
        cov[(3, 7)] = _t71 - _t52 * _t72;
        cov[(3, 8)] = _t53 * _t71 + _t54 * _t72
            + (_p[(3, 8)] + _p[(4, 8)] * _t43 - _p[(5, 8)] * _t44);
        cov[(4, 4)] = _t74 - _t43 * _t75 + _t45 * _t76 + q.velocity_noise[1];
        cov[(4, 5)] = _t76 + (_t44 * _t75 - _t45 * _t74);
        cov[(4, 6)] = _t49 * _t77 + _t51 * _t78;
        cov[(4, 7)] = _t77 - _t52 * _t78;
        cov[(4, 8)] = _t53 * _t77 + _t54 * _t78
            + (_p[(4, 8)] - _p[(3, 8)] * _t43 + _p[(5, 8)] * _t45);
        cov[(5, 5)] = _t44 * (_p[(3, 5)] + (_p[(3, 3)] * _t44 - _p[(3, 4)] * _t45))
            - _t45 * (_p[(4, 5)] + (_p[(3, 4)] * _t44 - _p[(4, 4)] * _t45))
            + (_p[(5, 5)] + (_t68 - _t73)) + q.velocity_noise[2];
        cov[(5, 6)] = _t49 * _t79 + _t51 * _t80;
        cov[(5, 7)] = _t79 - _t52 * _t80;
        cov[(5, 8)] = _t53 * _t79 + _t54 * _t80
            + (_p[(5, 8)] + (_p[(3, 8)] * _t44 - _p[(4, 8)] * _t45));
        cov[(6, 6)] = _t49 * _t81 + _t51 * _t82 + q.attitude_noise[0];
        cov[(6, 7)] = _t81 - _t52 * _t82;
        cov[(6, 8)] = _t53 * _t81 + _t54 * _t82
            + (_p[(7, 8)] * _t49 + _p[(6, 8)] * _t51);
        cov[(7, 7)] = _t83 - _t52 * _t84 + q.attitude_noise[1];
        cov[(7, 8)] = _t53 * _t83 + _t54 * _t84 + (_p[(7, 8)] - _p[(6, 8)] * _t52);
        cov[(8, 8)] = _t53 * (_p[(7, 8)] + (_p[(7, 7)] * _t53 + _p[(6, 7)] * _t54))
            + _t54 * (_p[(6, 8)] + (_p[(6, 7)] * _t53 + _p[(6, 6)] * _t54))
            + (_p[(8, 8)] + (_p[(7, 8)] * _t53 + _p[(6, 8)] * _t54))
            + q.attitude_noise[2];
        for i in 0..9 {
            for j in 0..i {
                cov[(i, j)] = cov[(j, i)];
            }
        }
    }
    const DECLARED_SENSORS: &'static [&'static str] = &[
        "Dvl",
        "Depth",
        "MarkerFix",
        "MarkerRelative",
    ];
    fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, 9, f64>>(
        name: &str,
        visitor: V,
    ) -> ::core::option::Option<V::Output> {
        match name {
            "Dvl" => ::core::option::Option::Some(visitor.visit::<Marker9Dvl, 3>()),
            "Depth" => ::core::option::Option::Some(visitor.visit::<Marker9Depth, 1>()),
            "MarkerFix" => {
                ::core::option::Option::Some(visitor.visit::<Marker9MarkerFix, 2>())
            }
            "MarkerRelative" => {
                ::core::option::Option::Some(visitor.visit::<Marker9MarkerRelative, 3>())
            }
            _ => {
                let _ = visitor;
                ::core::option::Option::None
            }
        }
    }
}
/// DVL body-frame velocity, m/s.
///
///Sensor `Dvl` of [`Marker9`]: 3 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Marker9Dvl;
#[allow(clippy::possible_missing_comma)]
impl Marker9Dvl {
    /// Number of measurement components.
    pub const M: usize = 3;
    /// The declared sensor name.
    pub const NAME: &'static str = "Dvl";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 0;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 9] = [
        false, false, false, true, true, true, false, false, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 3, f64> for Marker9Dvl {
    type Model = Marker9;
    type Aux = ();
    const NAME: &'static str = "Dvl";
    const ANGLES: [bool; 3] = [false, false, false];
    const JACOBIAN_SPARSITY: [[bool; 9]; 3] = [
        [false, false, false, true, false, false, false, false, false],
        [false, false, false, false, true, false, false, false, false],
        [false, false, false, false, false, true, false, false, false],
    ];
    const OPS_INNOVATION_TERMS: usize = 0;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 0*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        out[0] = x[3];
        out[1] = x[4];
        out[2] = x[5];
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 9>::zeros();
        out[(0, 3)] = 1.0;
        out[(1, 4)] = 1.0;
        out[(2, 5)] = 1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 0*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 9, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
    ) {
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 3>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        h[0] = x[3];
        h[1] = x[4];
        h[2] = x[5];
        pht[(0, 0)] = cov[(0, 3)];
        pht[(0, 1)] = cov[(0, 4)];
        pht[(0, 2)] = cov[(0, 5)];
        pht[(1, 0)] = cov[(1, 3)];
        pht[(1, 1)] = cov[(1, 4)];
        pht[(1, 2)] = cov[(1, 5)];
        pht[(2, 0)] = cov[(2, 3)];
        pht[(2, 1)] = cov[(2, 4)];
        pht[(2, 2)] = cov[(2, 5)];
        pht[(3, 0)] = cov[(3, 3)];
        pht[(3, 1)] = cov[(3, 4)];
        pht[(3, 2)] = cov[(3, 5)];
        pht[(4, 0)] = cov[(3, 4)];
        pht[(4, 1)] = cov[(4, 4)];
        pht[(4, 2)] = cov[(4, 5)];
        pht[(5, 0)] = cov[(3, 5)];
        pht[(5, 1)] = cov[(4, 5)];
        pht[(5, 2)] = cov[(5, 5)];
        pht[(6, 0)] = cov[(3, 6)];
        pht[(6, 1)] = cov[(4, 6)];
        pht[(6, 2)] = cov[(5, 6)];
        pht[(7, 0)] = cov[(3, 7)];
        pht[(7, 1)] = cov[(4, 7)];
        pht[(7, 2)] = cov[(5, 7)];
        pht[(8, 0)] = cov[(3, 8)];
        pht[(8, 1)] = cov[(4, 8)];
        pht[(8, 2)] = cov[(5, 8)];
        s[(0, 0)] = cov[(3, 3)];
        s[(0, 1)] = cov[(3, 4)];
        s[(0, 2)] = cov[(3, 5)];
        s[(1, 1)] = cov[(4, 4)];
        s[(1, 2)] = cov[(4, 5)];
        s[(2, 2)] = cov[(5, 5)];
        for i in 0..3 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// Depth meter, m (positive down).
///
///Sensor `Depth` of [`Marker9`]: 1 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Marker9Depth;
#[allow(clippy::possible_missing_comma)]
impl Marker9Depth {
    /// Number of measurement components.
    pub const M: usize = 1;
    /// The declared sensor name.
    pub const NAME: &'static str = "Depth";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 1;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 9] = [
        false, false, true, true, true, true, true, true, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 1, f64> for Marker9Depth {
    type Model = Marker9;
    type Aux = ();
    const NAME: &'static str = "Depth";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 9]; 1] = [
        [false, false, true, false, false, false, false, false, false],
    ];
    const OPS_INNOVATION_TERMS: usize = 0;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 0*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 1> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        out[0] = x[2];
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 1, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 9>::zeros();
        out[(0, 2)] = 1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 0*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 9, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 1, 1>,
    ) {
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 1>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::zeros();
        h[0] = x[2];
        pht[(0, 0)] = cov[(0, 2)];
        pht[(1, 0)] = cov[(1, 2)];
        pht[(2, 0)] = cov[(2, 2)];
        pht[(3, 0)] = cov[(2, 3)];
        pht[(4, 0)] = cov[(2, 4)];
        pht[(5, 0)] = cov[(2, 5)];
        pht[(6, 0)] = cov[(2, 6)];
        pht[(7, 0)] = cov[(2, 7)];
        pht[(8, 0)] = cov[(2, 8)];
        s[(0, 0)] = cov[(2, 2)];
        for i in 0..1 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// Horizontal position fix from a visible marker of known position (eq. 3,
/// already in the local frame), m. The fix is resolved with the estimated
/// attitude, so its error is correlated with the attitude error, which
/// this form cannot express; [`Marker9MarkerRelative`] can.
///
///Sensor `MarkerFix` of [`Marker9`]: 2 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Marker9MarkerFix;
#[allow(clippy::possible_missing_comma)]
impl Marker9MarkerFix {
    /// Number of measurement components.
    pub const M: usize = 2;
    /// The declared sensor name.
    pub const NAME: &'static str = "MarkerFix";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 2;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 9] = [
        true, true, false, true, true, true, true, true, true,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 2, f64> for Marker9MarkerFix {
    type Model = Marker9;
    type Aux = ();
    const NAME: &'static str = "MarkerFix";
    const ANGLES: [bool; 2] = [false, false];
    const JACOBIAN_SPARSITY: [[bool; 9]; 2] = [
        [true, false, false, false, false, false, false, false, false],
        [false, true, false, false, false, false, false, false, false],
    ];
    const OPS_INNOVATION_TERMS: usize = 0;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 0*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 2> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        out[0] = x[0];
        out[1] = x[1];
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 2, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 9>::zeros();
        out[(0, 0)] = 1.0;
        out[(1, 1)] = 1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 0*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 9, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 2, 2>,
    ) {
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 2>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 2>::zeros();
        h[0] = x[0];
        h[1] = x[1];
        pht[(0, 0)] = cov[(0, 0)];
        pht[(0, 1)] = cov[(0, 1)];
        pht[(1, 0)] = cov[(0, 1)];
        pht[(1, 1)] = cov[(1, 1)];
        pht[(2, 0)] = cov[(0, 2)];
        pht[(2, 1)] = cov[(1, 2)];
        pht[(3, 0)] = cov[(0, 3)];
        pht[(3, 1)] = cov[(1, 3)];
        pht[(4, 0)] = cov[(0, 4)];
        pht[(4, 1)] = cov[(1, 4)];
        pht[(5, 0)] = cov[(0, 5)];
        pht[(5, 1)] = cov[(1, 5)];
        pht[(6, 0)] = cov[(0, 6)];
        pht[(6, 1)] = cov[(1, 6)];
        pht[(7, 0)] = cov[(0, 7)];
        pht[(7, 1)] = cov[(1, 7)];
        pht[(8, 0)] = cov[(0, 8)];
        pht[(8, 1)] = cov[(1, 8)];
        s[(0, 0)] = cov[(0, 0)];
        s[(0, 1)] = cov[(0, 1)];
        s[(1, 1)] = cov[(1, 1)];
        for i in 0..2 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// The raw camera detection of a marker of known position: the marker
/// relative to the camera in body axes, m. The attitude enters `h`, so an
/// update correlates position and attitude errors instead of treating a
/// fix resolved with the estimated heading as independent of it.
///
///Sensor `MarkerRelative` of [`Marker9`]: 3 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Marker9MarkerRelative;
#[allow(clippy::possible_missing_comma)]
impl Marker9MarkerRelative {
    /// Number of measurement components.
    pub const M: usize = 3;
    /// The declared sensor name.
    pub const NAME: &'static str = "MarkerRelative";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 3;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 9] = [
        true, true, true, true, true, true, true, true, true,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 45;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 76;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 419;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 3, f64> for Marker9MarkerRelative {
    type Model = Marker9;
    type Aux = Marker9MarkerRelativeAux;
    const NAME: &'static str = "MarkerRelative";
    const ANGLES: [bool; 3] = [false, false, false];
    const JACOBIAN_SPARSITY: [[bool; 9]; 3] = [
        [true, true, true, false, false, false, false, true, true],
        [true, true, true, false, false, false, true, true, true],
        [true, true, true, false, false, false, true, true, true],
    ];
    const OPS_INNOVATION_TERMS: usize = 419;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 45*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &Marker9MarkerRelativeAux,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        let _t0 = aux.marker[1] - x[1];
        let (_t1, _t4) = ::nav_runtime::math::sin_cos(x[8]);
        let (_t6, _t2) = ::nav_runtime::math::sin_cos(x[7]);
        let _t3 = aux.marker[0] - x[0];
        let _t5 = aux.marker[2] - x[2];
        let (_t8, _t7) = ::nav_runtime::math::sin_cos(x[6]);
        let _t9 = _t6 * _t8;
        let _t10 = _t6 * _t7;
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        out[0] = _t0 * (_t1 * _t2) + _t3 * (_t2 * _t4) - _t5 * _t6 - aux.lever_arm[0];
        out[1] = _t0 * (_t4 * _t7 + _t1 * _t9) + _t3 * (_t4 * _t9 - _t1 * _t7)
            + _t5 * (_t2 * _t8) - aux.lever_arm[1];
        out[2] = _t0 * (_t1 * _t10 - _t4 * _t8) + _t3 * (_t1 * _t8 + _t4 * _t10)
            + _t5 * (_t2 * _t7) - aux.lever_arm[2];
        out
    }
    /**`H = dh/dx`.

Total ops: 76*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &Marker9MarkerRelativeAux,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 9> {
        let (_t3, _t0) = ::nav_runtime::math::sin_cos(x[8]);
        let (_t5, _t1) = ::nav_runtime::math::sin_cos(x[7]);
        let _t2 = _t0 * _t1;
        let _t4 = _t1 * _t3;
        let _t6 = aux.marker[2] - x[2];
        let _t7 = aux.marker[1] - x[1];
        let _t8 = aux.marker[0] - x[0];
        let (_t11, _t9) = ::nav_runtime::math::sin_cos(x[6]);
        let _t10 = _t3 * _t9;
        let _t12 = _t5 * _t11;
        let _t13 = _t0 * _t12;
        let _t14 = _t10 - _t13;
        let _t15 = _t0 * _t9 + _t3 * _t12;
        let _t16 = _t1 * _t11;
        let _t17 = _t5 * _t9;
        let _t18 = _t3 * _t17;
        let _t19 = _t0 * _t11;
        let _t20 = _t3 * _t11 + _t0 * _t17;
        let _t21 = _t1 * _t9;
        let _t22 = _t19 - _t18;
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 9>::zeros();
        out[(0, 0)] = -_t2;
        out[(0, 1)] = -_t4;
        out[(0, 2)] = _t5;
        out[(0, 7)] = -(_t1 * _t6 + (_t3 * _t5 * _t7 + _t0 * _t5 * _t8));
        out[(0, 8)] = _t2 * _t7 - _t4 * _t8;
        out[(1, 0)] = _t14;
        out[(1, 1)] = -_t15;
        out[(1, 2)] = -_t16;
        out[(1, 6)] = _t7 * (_t18 - _t19) + _t8 * _t20 + _t6 * _t21;
        out[(1, 7)] = _t7 * (_t3 * _t16) + _t8 * (_t0 * _t16) - _t6 * _t12;
        out[(1, 8)] = _t7 * (_t13 - _t10) - _t8 * _t15;
        out[(2, 0)] = -_t20;
        out[(2, 1)] = _t22;
        out[(2, 2)] = -_t21;
        out[(2, 6)] = _t8 * _t14 - _t7 * _t15 - _t6 * _t16;
        out[(2, 7)] = _t7 * (_t3 * _t21) + _t8 * (_t0 * _t21) - _t6 * _t17;
        out[(2, 8)] = _t7 * _t20 + _t8 * _t22;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 419*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Marker9Input,
        p: &Marker9Params,
        aux: &Marker9MarkerRelativeAux,
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 9, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
    ) {
        let _t0 = aux.marker[1] - x[1];
        let (_t1, _t5) = ::nav_runtime::math::sin_cos(x[8]);
        let (_t8, _t2) = ::nav_runtime::math::sin_cos(x[7]);
        let _t3 = _t1 * _t2;
        let _t4 = aux.marker[0] - x[0];
        let _t6 = _t2 * _t5;
        let _t7 = aux.marker[2] - x[2];
        let (_t10, _t9) = ::nav_runtime::math::sin_cos(x[6]);
        let _t11 = _t8 * _t10;
        let _t12 = _t5 * _t9 + _t1 * _t11;
        let _t13 = _t0 * _t12;
        let _t14 = _t5 * _t11;
        let _t15 = _t1 * _t9;
        let _t16 = _t14 - _t15;
        let _t17 = _t2 * _t10;
        let _t18 = _t7 * _t17;
        let _t19 = _t8 * _t9;
        let _t20 = _t1 * _t19;
        let _t21 = _t5 * _t10;
        let _t22 = _t1 * _t10 + _t5 * _t19;
        let _t23 = _t2 * _t9;
        let _t24 = _t0 * (_t20 - _t21) + _t4 * _t22 + _t7 * _t23;
        let _t25 = _t7 * _t2 + (_t0 * (_t8 * _t1) + _t4 * (_t8 * _t5));
        let _t26 = _t0 * _t6 - _t3 * _t4;
        let _t27 = _t8 * cov[(0, 2)] - (_t3 * cov[(0, 1)] + _t6 * cov[(0, 0)])
            - _t25 * cov[(0, 7)] + _t26 * cov[(0, 8)];
        let _t28 = _t15 - _t14;
        let _t29 = _t0 * (_t1 * _t17) + _t4 * (_t5 * _t17) - _t7 * _t11;
        let _t30 = _t0 * _t16 - _t4 * _t12;
        let _t31 = cov[(0, 0)] * _t28 - _t12 * cov[(0, 1)] - _t17 * cov[(0, 2)]
            + _t24 * cov[(0, 6)] + cov[(0, 7)] * _t29 + cov[(0, 8)] * _t30;
        let _t32 = _t21 - _t20;
        let _t33 = _t4 * _t28 - _t13 - _t18;
        let _t34 = _t0 * (_t1 * _t23) + _t4 * (_t5 * _t23) - _t7 * _t19;
        let _t35 = _t0 * _t22 + _t4 * _t32;
        let _t36 = cov[(0, 1)] * _t32 - _t22 * cov[(0, 0)] - _t23 * cov[(0, 2)]
            + cov[(0, 6)] * _t33 + cov[(0, 7)] * _t34 + cov[(0, 8)] * _t35;
        let _t37 = _t8 * cov[(1, 2)] - (_t3 * cov[(1, 1)] + _t6 * cov[(0, 1)])
            - _t25 * cov[(1, 7)] + _t26 * cov[(1, 8)];
        let _t38 = cov[(0, 1)] * _t28 - _t12 * cov[(1, 1)] - _t17 * cov[(1, 2)]
            + _t24 * cov[(1, 6)] + _t29 * cov[(1, 7)] + _t30 * cov[(1, 8)];
        let _t39 = _t32 * cov[(1, 1)] - _t22 * cov[(0, 1)] - _t23 * cov[(1, 2)]
            + _t33 * cov[(1, 6)] + _t34 * cov[(1, 7)] + _t35 * cov[(1, 8)];
        let _t40 = _t8 * cov[(2, 2)] - (_t3 * cov[(1, 2)] + _t6 * cov[(0, 2)])
            - _t25 * cov[(2, 7)] + _t26 * cov[(2, 8)];
        let _t41 = cov[(0, 2)] * _t28 - _t12 * cov[(1, 2)] - _t17 * cov[(2, 2)]
            + _t24 * cov[(2, 6)] + _t29 * cov[(2, 7)] + _t30 * cov[(2, 8)];
        let _t42 = _t32 * cov[(1, 2)] - _t22 * cov[(0, 2)] - _t23 * cov[(2, 2)]
            + _t33 * cov[(2, 6)] + _t34 * cov[(2, 7)] + _t35 * cov[(2, 8)];
        let _t43 = _t28 * cov[(0, 6)] - _t12 * cov[(1, 6)] - _t17 * cov[(2, 6)]
            + _t24 * cov[(6, 6)] + _t29 * cov[(6, 7)] + _t30 * cov[(6, 8)];
        let _t44 = _t32 * cov[(1, 6)] - _t22 * cov[(0, 6)] - _t23 * cov[(2, 6)]
            + _t33 * cov[(6, 6)] + _t34 * cov[(6, 7)] + _t35 * cov[(6, 8)];
        let _t45 = _t8 * cov[(2, 7)] - (_t3 * cov[(1, 7)] + _t6 * cov[(0, 7)])
            - _t25 * cov[(7, 7)] + _t26 * cov[(7, 8)];
        let _t46 = cov[(0, 7)] * _t28 - _t12 * cov[(1, 7)] - _t17 * cov[(2, 7)]
            + _t24 * cov[(6, 7)] + _t29 * cov[(7, 7)] + _t30 * cov[(7, 8)];
        let _t47 = _t32 * cov[(1, 7)] - _t22 * cov[(0, 7)] - _t23 * cov[(2, 7)]
            + _t33 * cov[(6, 7)] + _t34 * cov[(7, 7)] + _t35 * cov[(7, 8)];
        let _t48 = _t8 * cov[(2, 8)] - (_t3 * cov[(1, 8)] + _t6 * cov[(0, 8)])
            - _t25 * cov[(7, 8)] + _t26 * cov[(8, 8)];
        let _t49 = cov[(0, 8)] * _t28 - _t12 * cov[(1, 8)] - _t17 * cov[(2, 8)]
            + _t24 * cov[(6, 8)] + _t29 * cov[(7, 8)] + _t30 * cov[(8, 8)];
        let _t50 = _t32 * cov[(1, 8)] - _t22 * cov[(0, 8)] - _t23 * cov[(2, 8)]
            + _t33 * cov[(6, 8)] + _t34 * cov[(7, 8)] + _t35 * cov[(8, 8)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 3>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        h[0] = _t0 * _t3 + _t4 * _t6 - _t7 * _t8 - aux.lever_arm[0];
        h[1] = _t13 + _t4 * _t16 + _t18 - aux.lever_arm[1];
        h[2] = _t24 - aux.lever_arm[2];
        pht[(0, 0)] = _t27;
        pht[(0, 1)] = _t31;
        pht[(0, 2)] = _t36;
        pht[(1, 0)] = _t37;
        pht[(1, 1)] = _t38;
        pht[(1, 2)] = _t39;
        pht[(2, 0)] = _t40;
        pht[(2, 1)] = _t41;
        pht[(2, 2)] = _t42;
        pht[(3, 0)] = _t8 * cov[(2, 3)] - (_t3 * cov[(1, 3)] + _t6 * cov[(0, 3)])
            - _t25 * cov[(3, 7)] + _t26 * cov[(3, 8)];
        pht[(3, 1)] = _t28 * cov[(0, 3)] - _t12 * cov[(1, 3)] - _t17 * cov[(2, 3)]
            + _t24 * cov[(3, 6)] + _t29 * cov[(3, 7)] + _t30 * cov[(3, 8)];
        pht[(3, 2)] = _t32 * cov[(1, 3)] - _t22 * cov[(0, 3)] - _t23 * cov[(2, 3)]
            + _t33 * cov[(3, 6)] + _t34 * cov[(3, 7)] + _t35 * cov[(3, 8)];
        pht[(4, 0)] = _t8 * cov[(2, 4)] - (_t3 * cov[(1, 4)] + _t6 * cov[(0, 4)])
            - _t25 * cov[(4, 7)] + _t26 * cov[(4, 8)];
        pht[(4, 1)] = _t28 * cov[(0, 4)] - _t12 * cov[(1, 4)] - _t17 * cov[(2, 4)]
            + _t24 * cov[(4, 6)] + _t29 * cov[(4, 7)] + _t30 * cov[(4, 8)];
        pht[(4, 2)] = _t32 * cov[(1, 4)] - _t22 * cov[(0, 4)] - _t23 * cov[(2, 4)]
            + _t33 * cov[(4, 6)] + _t34 * cov[(4, 7)] + _t35 * cov[(4, 8)];
        pht[(5, 0)] = _t8 * cov[(2, 5)] - (_t3 * cov[(1, 5)] + _t6 * cov[(0, 5)])
            - _t25 * cov[(5, 7)] + _t26 * cov[(5, 8)];
        pht[(5, 1)] = _t28 * cov[(0, 5)] - _t12 * cov[(1, 5)] - _t17 * cov[(2, 5)]
            + _t24 * cov[(5, 6)] + _t29 * cov[(5, 7)] + _t30 * cov[(5, 8)];
        pht[(5, 2)] = _t32 * cov[(1, 5)] - _t22 * cov[(0, 5)] - _t23 * cov[(2, 5)]
            + _t33 * cov[(5, 6)] + _t34 * cov[(5, 7)] + _t35 * cov[(5, 8)];
        pht[(6, 0)] = _t8 * cov[(2, 6)] - (_t3 * cov[(1, 6)] + _t6 * cov[(0, 6)])
            - _t25 * cov[(6, 7)] + _t26 * cov[(6, 8)];
        pht[(6, 1)] = _t43;
        pht[(6, 2)] = _t44;
        pht[(7, 0)] = _t45;
        pht[(7, 1)] = _t46;
        pht[(7, 2)] = _t47;
        pht[(8, 0)] = _t48;
        pht[(8, 1)] = _t49;
        pht[(8, 2)] = _t50;
        s[(0, 0)] = _t8 * _t40 - (_t3 * _t37 + _t6 * _t27) - _t25 * _t45 + _t26 * _t48;
        s[(0, 1)] = _t8 * _t41 - (_t3 * _t38 + _t6 * _t31) - _t25 * _t46 + _t26 * _t49;
        s[(0, 2)] = _t8 * _t42 - (_t3 * _t39 + _t6 * _t36) - _t25 * _t47 + _t26 * _t50;
        s[(1, 1)] = _t28 * _t31 - _t12 * _t38 - _t17 * _t41 + _t24 * _t43 + _t29 * _t46
            + _t30 * _t49;
        s[(1, 2)] = _t28 * _t36 - _t12 * _t39 - _t17 * _t42 + _t24 * _t44 + _t29 * _t47
            + _t30 * _t50;
        s[(2, 2)] = _t32 * _t39 - _t22 * _t36 - _t23 * _t42 + _t33 * _t44 + _t34 * _t47
            + _t35 * _t50;
        for i in 0..3 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
#[cfg(test)]
#[allow(clippy::possible_missing_comma, non_snake_case)]
mod __marker9_generated_tests {
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
    const N: usize = 9;
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
            Marker9Input,
            Marker9Params,
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
            let u: Marker9Input = random_record(&mut rng);
            let p: Marker9Params = random_record(&mut rng);
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
                let jac = <Marker9 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let f = |x: &SVector<S, N>| <Marker9 as Model<
                    N,
                    S,
                >>::transition(x, &u, &p, dt);
                let Some(fd) = fd_jacobian(&x, f) else { return false };
                if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd("jacobian", &jac, &fd);
                assert_sparsity(
                    "jacobian",
                    &jac,
                    &<Marker9 as Model<N, S>>::JACOBIAN_SPARSITY,
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
                let g = Marker9::noise_jacobian(&x, &u, &p, dt);
                let f = |w: &SVector<S, NW>| Marker9::step_with_noise(&x, &u, &p, w, dt);
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
                let q: Marker9Noise = <Marker9Noise as Record>::from_fn(|_| ::nav_runtime::math::abs(
                    rng.uniform(),
                ));
                let cov = random_covariance(rng);
                let jac = <Marker9 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let g = Marker9::noise_jacobian(&x, &u, &p, dt);
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
                let qd_dense = g * qdiag * g.transpose() * 1.0;
                let qd = <Marker9 as Model<N, S>>::process_noise(&x, &u, &p, &q, dt);
                assert_close_rel("process_noise", &qd, &qd_dense);
                let phi = jac;
                let dense = phi * cov * phi.transpose() + qd_dense;
                let mut got = cov;
                <Marker9 as Model<
                    N,
                    S,
                >>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                assert_close_rel("propagate_covariance", &got, &dense);
                assert_eq!(
                    got, got.transpose(), "the propagated covariance must be symmetric"
                );
                let mut observed = cov;
                let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                <Marker9 as Model<
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
                        let s = <Marker9 as Model<N, S>>::PROPAGATION
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
                    rebuilt.is_some(), < Marker9 as Model < N, S >> ::PROPAGATION
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
        let s = Marker9State::from_vector(&x);
        assert_eq!(s.to_vector(), x);
        for i in 0..N {
            assert_eq!(s.get(i), < S as ::nav_runtime::Real > ::to_f64(x[i]));
        }
        assert_eq!(<< Marker9 as Model < N, S >> ::State as Record > ::NAMES.len(), N);
        assert_eq!(< Marker9 as Model < N, S >> ::STATE_NAMES.len(), N);
    }
    #[test]
    fn sensor_dvl_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Marker9Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let jac = <Marker9Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Marker9Dvl as Sensor<
                    N,
                    3,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Marker9Dvl), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Marker9Dvl), "::jacobian"),
                    &jac,
                    &<Marker9Dvl as Sensor<N, 3, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_dvl_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Marker9Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Marker9Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Marker9Dvl as Sensor<N, 3, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Marker9Dvl as Sensor<
                    N,
                    3,
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
    fn sensor_depth_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Marker9Depth as Sensor<N, 1, S>>::Aux = random_record(rng);
                let jac = <Marker9Depth as Sensor<N, 1, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Marker9Depth as Sensor<
                    N,
                    1,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Marker9Depth), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Marker9Depth), "::jacobian"),
                    &jac,
                    &<Marker9Depth as Sensor<N, 1, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_depth_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Marker9Depth as Sensor<N, 1, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Marker9Depth as Sensor<N, 1, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Marker9Depth as Sensor<N, 1, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Marker9Depth as Sensor<
                    N,
                    1,
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
    fn sensor_marker_fix_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Marker9MarkerFix as Sensor<N, 2, S>>::Aux = random_record(rng);
                let jac = <Marker9MarkerFix as Sensor<
                    N,
                    2,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Marker9MarkerFix as Sensor<
                    N,
                    2,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Marker9MarkerFix), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Marker9MarkerFix), "::jacobian"),
                    &jac,
                    &<Marker9MarkerFix as Sensor<N, 2, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_marker_fix_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Marker9MarkerFix as Sensor<N, 2, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Marker9MarkerFix as Sensor<
                    N,
                    2,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Marker9MarkerFix as Sensor<
                    N,
                    2,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Marker9MarkerFix as Sensor<
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
    fn sensor_marker_relative_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Marker9MarkerRelative as Sensor<N, 3, S>>::Aux = random_record(
                    rng,
                );
                let jac = <Marker9MarkerRelative as Sensor<
                    N,
                    3,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Marker9MarkerRelative as Sensor<
                    N,
                    3,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Marker9MarkerRelative), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Marker9MarkerRelative), "::jacobian"),
                    &jac,
                    &<Marker9MarkerRelative as Sensor<N, 3, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_marker_relative_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Marker9MarkerRelative as Sensor<N, 3, S>>::Aux = random_record(
                    rng,
                );
                let cov = random_covariance(rng);
                let hjac = <Marker9MarkerRelative as Sensor<
                    N,
                    3,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Marker9MarkerRelative as Sensor<
                    N,
                    3,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Marker9MarkerRelative as Sensor<
                    N,
                    3,
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
