// Expansion of `nav_runtime::model!` in models/src/sdins25/model.rs, formatted.
// Checked by `snapshots_are_current` (nav-macros/src/lib.rs); regenerate with
// `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`.
//
// Op counts:
//   Sdins25::OPS_TRANSITION = 251
//   Sdins25::OPS_JACOBIAN = 246
//   Sdins25::OPS_NOISE_JACOBIAN = 45
//   Sdins25::OPS_PROCESS_NOISE = 126
//   Sdins25::OPS_PROPAGATE_COVARIANCE = (368
//   Sdins25::OPS_DERIVATIVE = 234
//   Sdins25Depth::OPS_PREDICT = 1
//   Sdins25Depth::OPS_JACOBIAN = 0
//   Sdins25Depth::OPS_INNOVATION_TERMS = 28
//   Sdins25Dvl::OPS_PREDICT = 75
//   Sdins25Dvl::OPS_JACOBIAN = 174
//   Sdins25Dvl::OPS_INNOVATION_TERMS = 1569
//   Sdins25CompassSmallAngle::OPS_PREDICT = 2
//   Sdins25CompassSmallAngle::OPS_JACOBIAN = 0
//   Sdins25CompassSmallAngle::OPS_INNOVATION_TERMS = 53
//   Sdins25Compass::OPS_PREDICT = 12
//   Sdins25Compass::OPS_JACOBIAN = 21
//   Sdins25Compass::OPS_INNOVATION_TERMS = 181
//   Sdins25Usbl::OPS_PREDICT = 24
//   Sdins25Usbl::OPS_JACOBIAN = 14
//   Sdins25Usbl::OPS_INNOVATION_TERMS = 343

///The state of [`Sdins25`] (25 scalars), with named fields.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Sdins25State {
    /// `[dL, dl, dh]`: latitude, longitude errors (rad) and height error (m).
    pub position_error: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// `[dV_N, dV_E, dV_D]`, m/s.
    pub velocity_error: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// `phi = [phi_N, phi_E, phi_D]` with `C^_b^n = (I - [phi x]) C_b^n`, rad.
    pub attitude_error: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Accelerometer biases `nabla` (body), m/s^2.
    pub accel_bias: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Gyro biases `eps` (body), rad/s.
    pub gyro_bias: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// USBL horizontal position bias (N, E), m.
    pub usbl_bias: ::nav_runtime::nalgebra::SVector<f64, 2>,
    /// Depth-meter bias, m.
    pub depth_bias: f64,
    /// DVL body-frame velocity error `a_v`, m/s.
    pub dvl_bias: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Magnetic compass bias, rad.
    pub compass_bias: f64,
    /// USBL array misalignment (small angles), rad.
    pub usbl_misalignment: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Sdins25State {
    const LEN: usize = 25;
    const NAMES: &'static [&'static str] = &[
        "position_error[0]",
        "position_error[1]",
        "position_error[2]",
        "velocity_error[0]",
        "velocity_error[1]",
        "velocity_error[2]",
        "attitude_error[0]",
        "attitude_error[1]",
        "attitude_error[2]",
        "accel_bias[0]",
        "accel_bias[1]",
        "accel_bias[2]",
        "gyro_bias[0]",
        "gyro_bias[1]",
        "gyro_bias[2]",
        "usbl_bias[0]",
        "usbl_bias[1]",
        "depth_bias",
        "dvl_bias[0]",
        "dvl_bias[1]",
        "dvl_bias[2]",
        "compass_bias",
        "usbl_misalignment[0]",
        "usbl_misalignment[1]",
        "usbl_misalignment[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 25] = [0.0; 25];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            position_error: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            velocity_error: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[3..6]),
            attitude_error: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[6..9]),
            accel_bias: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[9..12]),
            gyro_bias: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[12..15]),
            usbl_bias: ::nav_runtime::nalgebra::SVector::<
                f64,
                2,
            >::from_column_slice(&v[15..17]),
            depth_bias: v[17],
            dvl_bias: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[18..21]),
            compass_bias: v[21],
            usbl_misalignment: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[22..25]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.position_error[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.position_error[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.position_error[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_error[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_error[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity_error[2]),
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_error[0]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_error[1]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.attitude_error[2]),
            9 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[0]),
            10 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[1]),
            11 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[2]),
            12 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_bias[0]),
            13 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_bias[1]),
            14 => <f64 as ::nav_runtime::Real>::to_f64(self.gyro_bias[2]),
            15 => <f64 as ::nav_runtime::Real>::to_f64(self.usbl_bias[0]),
            16 => <f64 as ::nav_runtime::Real>::to_f64(self.usbl_bias[1]),
            17 => <f64 as ::nav_runtime::Real>::to_f64(self.depth_bias),
            18 => <f64 as ::nav_runtime::Real>::to_f64(self.dvl_bias[0]),
            19 => <f64 as ::nav_runtime::Real>::to_f64(self.dvl_bias[1]),
            20 => <f64 as ::nav_runtime::Real>::to_f64(self.dvl_bias[2]),
            21 => <f64 as ::nav_runtime::Real>::to_f64(self.compass_bias),
            22 => <f64 as ::nav_runtime::Real>::to_f64(self.usbl_misalignment[0]),
            23 => <f64 as ::nav_runtime::Real>::to_f64(self.usbl_misalignment[1]),
            24 => <f64 as ::nav_runtime::Real>::to_f64(self.usbl_misalignment[2]),
            _ => f64::NAN,
        }
    }
}
#[allow(clippy::possible_missing_comma)]
impl Sdins25State {
    /// The state from its vector (declaration order).
    pub fn from_vector(v: &::nav_runtime::nalgebra::SVector<f64, 25>) -> Self {
        <Self as ::nav_runtime::model::Record>::from_fn(|i| <f64 as ::nav_runtime::Real>::to_f64(
            v[i],
        ))
    }
    /// The state as a vector (declaration order).
    pub fn to_vector(&self) -> ::nav_runtime::nalgebra::SVector<f64, 25> {
        ::nav_runtime::nalgebra::SVector::<
            f64,
            25,
        >::from_column_slice(
            &[
                self.position_error[0],
                self.position_error[1],
                self.position_error[2],
                self.velocity_error[0],
                self.velocity_error[1],
                self.velocity_error[2],
                self.attitude_error[0],
                self.attitude_error[1],
                self.attitude_error[2],
                self.accel_bias[0],
                self.accel_bias[1],
                self.accel_bias[2],
                self.gyro_bias[0],
                self.gyro_bias[1],
                self.gyro_bias[2],
                self.usbl_bias[0],
                self.usbl_bias[1],
                self.depth_bias,
                self.dvl_bias[0],
                self.dvl_bias[1],
                self.dvl_bias[2],
                self.compass_bias,
                self.usbl_misalignment[0],
                self.usbl_misalignment[1],
                self.usbl_misalignment[2],
            ],
        )
    }
}
///The inputs `u` of [`Sdins25`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Sdins25Input {
    /// Nominal (INS) latitude `L^`, rad.
    pub latitude: f64,
    /// Nominal (INS) height `h^` (positive up), m.
    pub height: f64,
    /// Nominal (INS) NED velocity `V^n`, m/s.
    pub velocity: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Nominal (INS) attitude `C^_b^n`.
    pub c_bn: ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
    /// Measured specific force `f~^b` (after the current bias correction), m/s^2.
    pub specific_force: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Sdins25Input {
    const LEN: usize = 17;
    const NAMES: &'static [&'static str] = &[
        "latitude",
        "height",
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "c_bn[0][0]",
        "c_bn[0][1]",
        "c_bn[0][2]",
        "c_bn[1][0]",
        "c_bn[1][1]",
        "c_bn[1][2]",
        "c_bn[2][0]",
        "c_bn[2][1]",
        "c_bn[2][2]",
        "specific_force[0]",
        "specific_force[1]",
        "specific_force[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 17] = [0.0; 17];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            latitude: v[0],
            height: v[1],
            velocity: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[2..5]),
            c_bn: ::nav_runtime::nalgebra::SMatrix::<
                f64,
                3,
                3,
            >::from_row_slice(&v[5..14]),
            specific_force: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[14..17]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.latitude),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.height),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[0]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[1]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.velocity[2]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 0)]),
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 1)]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 2)]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 0)]),
            9 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 1)]),
            10 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 2)]),
            11 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 0)]),
            12 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 1)]),
            13 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 2)]),
            14 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[0]),
            15 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[1]),
            16 => <f64 as ::nav_runtime::Real>::to_f64(self.specific_force[2]),
            _ => f64::NAN,
        }
    }
}
///The parameters `p` of [`Sdins25`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Sdins25Params {}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Sdins25Params {
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
///The process-noise power spectral densities `q` of [`Sdins25`], one per noise scalar (units^2 / s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Sdins25Noise {
    /// Accelerometer white noise, (m/s^2)^2/Hz.
    pub accel_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Gyro white noise, (rad/s)^2/Hz.
    pub gyro_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Sdins25Noise {
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
///The auxiliary inputs of sensor [`Sdins25Usbl`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Sdins25UsblAux {
    /// Vector from the USBL transducer to the vehicle, NED, m.
    pub relative_position: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Sdins25UsblAux {
    const LEN: usize = 3;
    const NAMES: &'static [&'static str] = &[
        "relative_position[0]",
        "relative_position[1]",
        "relative_position[2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 3] = [0.0; 3];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            relative_position: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.relative_position[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.relative_position[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.relative_position[2]),
            _ => f64::NAN,
        }
    }
}
/// 25-state indirect-feedback INS error model, docs/models/sdins25.md, eqs. 4-17.
///
///Generated by `model!`: continuous model with 25 states, 6 noise inputs and 5 sensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25;
#[allow(clippy::possible_missing_comma)]
impl Sdins25 {
    /// Number of scalar states.
    pub const N: usize = 25;
    /// Number of scalar process-noise inputs.
    pub const NW: usize = 6;
    ///Index of the first scalar of `position_error` in the state vector.
    pub const POSITION_ERROR: usize = 0;
    ///Index of the first scalar of `velocity_error` in the state vector.
    pub const VELOCITY_ERROR: usize = 3;
    ///Index of the first scalar of `attitude_error` in the state vector.
    pub const ATTITUDE_ERROR: usize = 6;
    ///Index of the first scalar of `accel_bias` in the state vector.
    pub const ACCEL_BIAS: usize = 9;
    ///Index of the first scalar of `gyro_bias` in the state vector.
    pub const GYRO_BIAS: usize = 12;
    ///Index of the first scalar of `usbl_bias` in the state vector.
    pub const USBL_BIAS: usize = 15;
    ///Index of the first scalar of `depth_bias` in the state vector.
    pub const DEPTH_BIAS: usize = 17;
    ///Index of the first scalar of `dvl_bias` in the state vector.
    pub const DVL_BIAS: usize = 18;
    ///Index of the first scalar of `compass_bias` in the state vector.
    pub const COMPASS_BIAS: usize = 21;
    ///Index of the first scalar of `usbl_misalignment` in the state vector.
    pub const USBL_MISALIGNMENT: usize = 22;
    /// State scalars no sensor depends on, directly or through the dynamics
    /// (no measurement can correct them). The model lists them in
    /// `allow_unused { .. }` (checked at compile time).
    pub const UNUSED_STATES: &'static [&'static str] = &[];
    /// Operations in `transition`.
    pub const OPS_TRANSITION: usize = 251;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 246;
    /// Operations in [`Self::noise_jacobian`].
    pub const OPS_NOISE_JACOBIAN: usize = 45;
    /// Operations in `process_noise`.
    pub const OPS_PROCESS_NOISE: usize = 126;
    /// Operations in `propagate_covariance`.
    pub const OPS_PROPAGATE_COVARIANCE: usize = (368
        + Self::PROPAGATION_STRUCTURE.ops(25));
    ///Structure of `Phi` (`I + F dt`) and `Qd` for the covariance propagation: rows [0, 1, 2, 3, 4, 5, 6, 7, 8] change, the others are unit rows.
    pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> = ::nav_runtime::propagation::Structure {
        identity: true,
        rows: &[0, 1, 2, 3, 4, 5, 6, 7, 8],
        start: &[0, 3, 6, 7, 17, 27, 36, 44, 52, 60],
        columns: &[
            0, 2, 3, 0, 2, 4, 5, 0, 2, 3, 4, 5, 7, 8, 9, 10, 11, 0, 2, 3, 4, 5, 6, 8, 9,
            10, 11, 0, 2, 3, 4, 6, 7, 9, 10, 11, 0, 2, 4, 7, 8, 12, 13, 14, 0, 2, 3, 6,
            8, 12, 13, 14, 0, 2, 4, 6, 7, 12, 13, 14,
        ],
        noise: &[
            (3, 3),
            (3, 4),
            (3, 5),
            (4, 4),
            (4, 5),
            (5, 5),
            (6, 6),
            (6, 7),
            (6, 8),
            (7, 7),
            (7, 8),
            (8, 8),
        ],
    };
    /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
    pub const SENSORS: [&'static str; 5] = [
        "Depth",
        "Dvl",
        "CompassSmallAngle",
        "Compass",
        "Usbl",
    ];
    /// Per sensor, per state scalar: the sensor's `h` depends on the state
    /// directly (a structural nonzero of its `H`).
    pub const SENSOR_DEPENDS: [[bool; 25]; 5] = [
        [
            false, false, true, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, true, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, true, true, true, true, true, true, false, false, false,
            false, false, false, false, false, false, true, true, true, false, false,
            false, false,
        ],
        [
            false, false, false, false, false, false, false, false, true, false, false,
            false, false, false, false, false, false, false, false, false, false, true,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, true, true, true, false, false,
            false, false, false, false, false, false, false, false, false, false, true,
            false, false, false,
        ],
        [
            true, true, false, false, false, false, false, false, false, false, false,
            false, false, false, false, true, true, false, false, false, false, false,
            true, true, true,
        ],
    ];
    /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
    /// indices into `SENSORS`); the set of all sensors when it declares none.
    pub const RUNS_WITH: [&'static [usize]; 1] = [&[0, 1, 2, 3, 4]];
    /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
    /// that set (checked at compile time against `allow_unused`).
    pub const RUNS_WITH_OBSERVABLE: [[bool; 25]; 1] = [
        [
            true, true, true, true, true, true, true, true, true, true, true, true, true,
            true, true, true, true, true, true, true, true, true, true, true, true,
        ],
    ];
    /// Per state scalar: is it structurally observable with the sensors marked
    /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
    /// a measurement of one of them, through a sensor's `H` or the dynamics
    /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
    /// only: `false` means no measurement of that set can ever correct the
    /// state; `true` means only that sparsity does not exclude it (see
    /// `docs/language.md`, "Structural observability").
    pub const fn structurally_observable(sensors: &[bool; 5]) -> [bool; 25] {
        let deps = Self::SENSOR_DEPENDS;
        let f = <Self as ::nav_runtime::model::Model<25, f64>>::JACOBIAN_SPARSITY;
        let mut seen = [false; 25];
        let mut s = 0;
        while s < 5 {
            if sensors[s] {
                let mut j = 0;
                while j < 25 {
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
            while i < 25 {
                if seen[i] {
                    let mut j = 0;
                    while j < 25 {
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
    pub const OPS_DERIVATIVE: usize = 234;
    /**The state derivative `f(x, u, p)` at `w = 0`.

Total ops: 234*/
    pub fn derivative(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 25> {
        let (_t0, _t13) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (0.0066943799901413165 * _t0);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let _t3 = u.velocity[0] / (u.height + 6335439.3272928195 / (_t1 * _t2));
        let _t4 = u.latitude - x[0];
        let (_t5, _t17) = ::nav_runtime::math::sin_cos(_t4);
        let _t6 = 1.0 - _t5 * (_t5 * 0.0066943799901413165);
        let _t7 = ::nav_runtime::math::sqrt(_t6);
        let _t8 = u.height - x[2];
        let _t9 = 1.0 / (6335439.3272928195 / (_t6 * _t7) + _t8);
        let _t10 = u.velocity[0] - x[3];
        let _t11 = 1.0 / _t2;
        let _t12 = u.height + 6378137.0 * _t11;
        let _t14 = u.velocity[1] - x[4];
        let _t15 = 1.0 / _t7;
        let _t16 = _t8 + _t15 * 6378137.0;
        let _t18 = u.velocity[2] - x[5];
        let _t19 = _t0 * 7.292115e-5;
        let _t20 = 1.0 / _t12;
        let _t21 = _t20 * (u.velocity[1] * (_t0 / _t13));
        let _t22 = 2.0 * _t19 + _t21;
        let _t23 = u.specific_force[1] - x[10];
        let _t24 = u.specific_force[0] - x[9];
        let _t25 = u.specific_force[2] - x[11];
        let _t26 = _t9 * (x[3] - u.velocity[0]);
        let _t27 = 1.0 / _t16;
        let _t28 = _t27 * (_t5 / _t17 * (x[4] - u.velocity[1]));
        let _t29 = _t5 * 7.292115e-5;
        let _t30 = _t28 - _t29 * 2.0;
        let _t31 = _t13 * 7.292115e-5;
        let _t32 = u.velocity[1] * _t20;
        let _t33 = 2.0 * _t31 + _t32;
        let _t34 = _t17 * 7.292115e-5;
        let _t35 = _t14 * _t27;
        let _t36 = 2.0 * _t34 + _t35;
        let _t37 = _t19 + _t21;
        let _t38 = _t31 + _t32;
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 25>::zeros();
        out[0] = _t3 - _t9 * _t10;
        out[1] = u.velocity[1] / (_t12 * _t13) - _t14 / (_t16 * _t17);
        out[2] = _t18 - u.velocity[2];
        out[3] = u.specific_force[1] * u.c_bn[(0, 1)]
            + u.specific_force[0] * u.c_bn[(0, 0)] + u.specific_force[2] * u.c_bn[(0, 2)]
            - (u.velocity[1] * _t22 - _t3 * u.velocity[2])
            - (_t23 * (u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)])
                + _t24 * (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)] + u.c_bn[(0, 0)])
                + _t25 * (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)] + u.c_bn[(0, 2)])
                - (_t18 * _t26 - _t14 * _t30));
        out[4] = u.velocity[2] * _t33 + u.velocity[0] * _t22
            + (u.specific_force[1] * u.c_bn[(1, 1)]
                + u.specific_force[0] * u.c_bn[(1, 0)]
                + u.specific_force[2] * u.c_bn[(1, 2)])
            - (_t23 * (u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]))
                + _t24
                    * (u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]))
                + _t25
                    * (u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]))
                - (_t10 * _t30 - _t18 * _t36));
        out[5] = u.specific_force[1] * u.c_bn[(2, 1)]
            + u.specific_force[0] * u.c_bn[(2, 0)] + u.specific_force[2] * u.c_bn[(2, 2)]
            - (u.velocity[0] * _t3 + u.velocity[1] * _t33)
            + (2.458172257647332e-14 * (u.height * (u.height * 3.0))
                + (1.0
                    - (1.00680259666783 - _t0 * (_t0 * 0.0067056213295))
                        * (1.567855942887398e-7 * (u.height * 2.0))))
                * (_t11 * (9.7803253359 * (1.0 + _t0 * (_t0 * 0.00193185265241))))
            - (_t23 * (u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]))
                + _t24
                    * (u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]))
                + _t25
                    * (u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]))
                - (_t14 * _t36 - _t10 * _t26)
                + (2.458172257647332e-14 * (_t8 * (_t8 * 3.0))
                    + (1.0
                        - (1.00680259666783 - _t5 * (_t5 * 0.0067056213295))
                            * (1.567855942887398e-7 * (_t8 * 2.0))))
                    * (_t15 * ((1.0 + _t5 * (_t5 * 0.00193185265241)) * 9.7803253359)));
        out[6] = _t3 * x[8] - x[7] * _t37
            - (u.c_bn[(0, 1)] * x[13] + u.c_bn[(0, 0)] * x[12] + u.c_bn[(0, 2)] * x[14])
            + _t38 - (_t34 + _t35);
        out[7] = x[8] * _t38 + x[6] * _t37
            - (u.c_bn[(1, 1)] * x[13] + u.c_bn[(1, 0)] * x[12] + u.c_bn[(1, 2)] * x[14])
            - _t3 - _t26;
        out[8] = -(_t37
            + (u.c_bn[(2, 1)] * x[13] + u.c_bn[(2, 0)] * x[12] + u.c_bn[(2, 2)] * x[14]
                + (_t3 * x[6] + x[7] * _t38)) + (_t28 - _t29));
        out
    }
    /**The state derivative `dx/dt = f(x, u, p, w)` with an explicit noise sample `w` (units of the state per second; not a step: [`Self::step_with_noise`] advances the state by `dt`).

Total ops: 240*/
    pub fn derivative_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 25> {
        let (_t0, _t13) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (0.0066943799901413165 * _t0);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let _t3 = u.velocity[0] / (u.height + 6335439.3272928195 / (_t1 * _t2));
        let _t4 = u.latitude - x[0];
        let (_t5, _t17) = ::nav_runtime::math::sin_cos(_t4);
        let _t6 = 1.0 - _t5 * (_t5 * 0.0066943799901413165);
        let _t7 = ::nav_runtime::math::sqrt(_t6);
        let _t8 = u.height - x[2];
        let _t9 = 1.0 / (6335439.3272928195 / (_t6 * _t7) + _t8);
        let _t10 = u.velocity[0] - x[3];
        let _t11 = 1.0 / _t2;
        let _t12 = u.height + 6378137.0 * _t11;
        let _t14 = u.velocity[1] - x[4];
        let _t15 = 1.0 / _t7;
        let _t16 = _t8 + _t15 * 6378137.0;
        let _t18 = u.velocity[2] - x[5];
        let _t19 = _t0 * 7.292115e-5;
        let _t20 = 1.0 / _t12;
        let _t21 = _t20 * (u.velocity[1] * (_t0 / _t13));
        let _t22 = 2.0 * _t19 + _t21;
        let _t23 = u.specific_force[1] - x[10] - w[1];
        let _t24 = u.specific_force[0] - x[9] - w[0];
        let _t25 = u.specific_force[2] - x[11] - w[2];
        let _t26 = _t9 * (x[3] - u.velocity[0]);
        let _t27 = 1.0 / _t16;
        let _t28 = _t27 * (_t5 / _t17 * (x[4] - u.velocity[1]));
        let _t29 = _t5 * 7.292115e-5;
        let _t30 = _t28 - _t29 * 2.0;
        let _t31 = _t13 * 7.292115e-5;
        let _t32 = u.velocity[1] * _t20;
        let _t33 = 2.0 * _t31 + _t32;
        let _t34 = _t17 * 7.292115e-5;
        let _t35 = _t14 * _t27;
        let _t36 = 2.0 * _t34 + _t35;
        let _t37 = _t19 + _t21;
        let _t38 = w[4] + x[13];
        let _t39 = w[3] + x[12];
        let _t40 = w[5] + x[14];
        let _t41 = _t31 + _t32;
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 25>::zeros();
        out[0] = _t3 - _t9 * _t10;
        out[1] = u.velocity[1] / (_t12 * _t13) - _t14 / (_t16 * _t17);
        out[2] = _t18 - u.velocity[2];
        out[3] = u.specific_force[1] * u.c_bn[(0, 1)]
            + u.specific_force[0] * u.c_bn[(0, 0)] + u.specific_force[2] * u.c_bn[(0, 2)]
            - (u.velocity[1] * _t22 - _t3 * u.velocity[2])
            - (_t23 * (u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)])
                + _t24 * (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)] + u.c_bn[(0, 0)])
                + _t25 * (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)] + u.c_bn[(0, 2)])
                - (_t18 * _t26 - _t14 * _t30));
        out[4] = u.velocity[2] * _t33 + u.velocity[0] * _t22
            + (u.specific_force[1] * u.c_bn[(1, 1)]
                + u.specific_force[0] * u.c_bn[(1, 0)]
                + u.specific_force[2] * u.c_bn[(1, 2)])
            - (_t23 * (u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]))
                + _t24
                    * (u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]))
                + _t25
                    * (u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]))
                - (_t10 * _t30 - _t18 * _t36));
        out[5] = u.specific_force[1] * u.c_bn[(2, 1)]
            + u.specific_force[0] * u.c_bn[(2, 0)] + u.specific_force[2] * u.c_bn[(2, 2)]
            - (u.velocity[0] * _t3 + u.velocity[1] * _t33)
            + (2.458172257647332e-14 * (u.height * (u.height * 3.0))
                + (1.0
                    - (1.00680259666783 - _t0 * (_t0 * 0.0067056213295))
                        * (1.567855942887398e-7 * (u.height * 2.0))))
                * (_t11 * (9.7803253359 * (1.0 + _t0 * (_t0 * 0.00193185265241))))
            - (_t23 * (u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]))
                + _t24
                    * (u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]))
                + _t25
                    * (u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]))
                - (_t14 * _t36 - _t10 * _t26)
                + (2.458172257647332e-14 * (_t8 * (_t8 * 3.0))
                    + (1.0
                        - (1.00680259666783 - _t5 * (_t5 * 0.0067056213295))
                            * (1.567855942887398e-7 * (_t8 * 2.0))))
                    * (_t15 * ((1.0 + _t5 * (_t5 * 0.00193185265241)) * 9.7803253359)));
        out[6] = _t3 * x[8] - x[7] * _t37
            - (u.c_bn[(0, 1)] * _t38 + u.c_bn[(0, 0)] * _t39 + u.c_bn[(0, 2)] * _t40)
            + _t41 - (_t34 + _t35);
        out[7] = x[8] * _t41 + x[6] * _t37
            - (u.c_bn[(1, 1)] * _t38 + u.c_bn[(1, 0)] * _t39 + u.c_bn[(1, 2)] * _t40)
            - _t3 - _t26;
        out[8] = -(_t28 - _t29
            + (_t37
                + (u.c_bn[(2, 1)] * _t38 + u.c_bn[(2, 0)] * _t39 + u.c_bn[(2, 2)] * _t40
                    + (_t3 * x[6] + x[7] * _t41))));
        out
    }
    /**The state after one step of `dt` seconds with an explicit noise sample `w`: the Euler step `x + f(x, u, p, w) dt` (`transition` at `w = 0`; the derivative itself is [`Self::derivative_with_noise`]).

Total ops: 257*/
    pub fn step_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 25> {
        let (_t0, _t13) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (0.0066943799901413165 * _t0);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let _t3 = u.velocity[0] / (u.height + 6335439.3272928195 / (_t1 * _t2));
        let _t4 = u.latitude - x[0];
        let (_t5, _t17) = ::nav_runtime::math::sin_cos(_t4);
        let _t6 = 1.0 - _t5 * (_t5 * 0.0066943799901413165);
        let _t7 = ::nav_runtime::math::sqrt(_t6);
        let _t8 = u.height - x[2];
        let _t9 = 1.0 / (6335439.3272928195 / (_t6 * _t7) + _t8);
        let _t10 = u.velocity[0] - x[3];
        let _t11 = 1.0 / _t2;
        let _t12 = u.height + 6378137.0 * _t11;
        let _t14 = u.velocity[1] - x[4];
        let _t15 = 1.0 / _t7;
        let _t16 = _t8 + _t15 * 6378137.0;
        let _t18 = u.velocity[2] - x[5];
        let _t19 = _t0 * 7.292115e-5;
        let _t20 = 1.0 / _t12;
        let _t21 = _t20 * (u.velocity[1] * (_t0 / _t13));
        let _t22 = 2.0 * _t19 + _t21;
        let _t23 = u.specific_force[1] - x[10] - w[1];
        let _t24 = u.specific_force[0] - x[9] - w[0];
        let _t25 = u.specific_force[2] - x[11] - w[2];
        let _t26 = _t9 * (x[3] - u.velocity[0]);
        let _t27 = 1.0 / _t16;
        let _t28 = _t27 * (_t5 / _t17 * (x[4] - u.velocity[1]));
        let _t29 = _t5 * 7.292115e-5;
        let _t30 = _t28 - _t29 * 2.0;
        let _t31 = _t13 * 7.292115e-5;
        let _t32 = u.velocity[1] * _t20;
        let _t33 = 2.0 * _t31 + _t32;
        let _t34 = _t17 * 7.292115e-5;
        let _t35 = _t14 * _t27;
        let _t36 = 2.0 * _t34 + _t35;
        let _t37 = _t19 + _t21;
        let _t38 = w[4] + x[13];
        let _t39 = w[3] + x[12];
        let _t40 = w[5] + x[14];
        let _t41 = _t31 + _t32;
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 25>::zeros();
        out[0] = x[0] + dt * (_t3 - _t9 * _t10);
        out[1] = dt * (u.velocity[1] / (_t12 * _t13) - _t14 / (_t16 * _t17)) + x[1];
        out[2] = x[2] + dt * (_t18 - u.velocity[2]);
        out[3] = x[3]
            + dt
                * (u.specific_force[1] * u.c_bn[(0, 1)]
                    + u.specific_force[0] * u.c_bn[(0, 0)]
                    + u.specific_force[2] * u.c_bn[(0, 2)]
                    - (u.velocity[1] * _t22 - _t3 * u.velocity[2])
                    - (_t23
                        * (u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8]
                            + u.c_bn[(0, 1)])
                        + _t24
                            * (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)]
                                + u.c_bn[(0, 0)])
                        + _t25
                            * (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)]
                                + u.c_bn[(0, 2)]) - (_t18 * _t26 - _t14 * _t30)));
        out[4] = x[4]
            + dt
                * (u.velocity[2] * _t33 + u.velocity[0] * _t22
                    + (u.specific_force[1] * u.c_bn[(1, 1)]
                        + u.specific_force[0] * u.c_bn[(1, 0)]
                        + u.specific_force[2] * u.c_bn[(1, 2)])
                    - (_t23
                        * (u.c_bn[(1, 1)]
                            + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]))
                        + _t24
                            * (u.c_bn[(1, 0)]
                                + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]))
                        + _t25
                            * (u.c_bn[(1, 2)]
                                + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]))
                        - (_t10 * _t30 - _t18 * _t36)));
        out[5] = x[5]
            + dt
                * (u.specific_force[1] * u.c_bn[(2, 1)]
                    + u.specific_force[0] * u.c_bn[(2, 0)]
                    + u.specific_force[2] * u.c_bn[(2, 2)]
                    - (u.velocity[0] * _t3 + u.velocity[1] * _t33)
                    + (2.458172257647332e-14 * (u.height * (u.height * 3.0))
                        + (1.0
                            - (1.00680259666783 - _t0 * (_t0 * 0.0067056213295))
                                * (1.567855942887398e-7 * (u.height * 2.0))))
                        * (_t11
                            * (9.7803253359 * (1.0 + _t0 * (_t0 * 0.00193185265241))))
                    - (_t23
                        * (u.c_bn[(2, 1)]
                            + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]))
                        + _t24
                            * (u.c_bn[(2, 0)]
                                + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]))
                        + _t25
                            * (u.c_bn[(2, 2)]
                                + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]))
                        - (_t14 * _t36 - _t10 * _t26)
                        + (2.458172257647332e-14 * (_t8 * (_t8 * 3.0))
                            + (1.0
                                - (1.00680259666783 - _t5 * (_t5 * 0.0067056213295))
                                    * (1.567855942887398e-7 * (_t8 * 2.0))))
                            * (_t15
                                * ((1.0 + _t5 * (_t5 * 0.00193185265241))
                                    * 9.7803253359))));
        out[6] = x[6]
            + dt
                * (_t3 * x[8] - x[7] * _t37
                    - (u.c_bn[(0, 1)] * _t38 + u.c_bn[(0, 0)] * _t39
                        + u.c_bn[(0, 2)] * _t40) + _t41 - (_t34 + _t35));
        out[7] = x[7]
            + dt
                * (x[8] * _t41 + x[6] * _t37
                    - (u.c_bn[(1, 1)] * _t38 + u.c_bn[(1, 0)] * _t39
                        + u.c_bn[(1, 2)] * _t40) - _t3 - _t26);
        out[8] = x[8]
            - dt
                * (_t28 - _t29
                    + (_t37
                        + (u.c_bn[(2, 1)] * _t38 + u.c_bn[(2, 0)] * _t39
                            + u.c_bn[(2, 2)] * _t40 + (_t3 * x[6] + x[7] * _t41))));
        out[9] = x[9];
        out[10] = x[10];
        out[11] = x[11];
        out[12] = x[12];
        out[13] = x[13];
        out[14] = x[14];
        out[15] = x[15];
        out[16] = x[16];
        out[17] = x[17];
        out[18] = x[18];
        out[19] = x[19];
        out[20] = x[20];
        out[21] = x[21];
        out[22] = x[22];
        out[23] = x[23];
        out[24] = x[24];
        out
    }
    /**The noise Jacobian `G = df/dw` of the derivative at `w = 0` (N x NW, noise scalars in declaration order; `dt` is unused: the step's own is `G dt`).

Total ops: 45*/
    pub fn noise_jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 25, 6> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 6>::zeros();
        out[(3, 0)] = u.c_bn[(2, 0)] * x[7] - u.c_bn[(1, 0)] * x[8] + u.c_bn[(0, 0)];
        out[(3, 1)] = x[7] * u.c_bn[(2, 1)] - x[8] * u.c_bn[(1, 1)] + u.c_bn[(0, 1)];
        out[(3, 2)] = x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)] + u.c_bn[(0, 2)];
        out[(4, 0)] = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        out[(4, 1)] = u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]);
        out[(4, 2)] = u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]);
        out[(5, 0)] = u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]);
        out[(5, 1)] = u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]);
        out[(5, 2)] = u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]);
        out[(6, 3)] = -u.c_bn[(0, 0)];
        out[(6, 4)] = -u.c_bn[(0, 1)];
        out[(6, 5)] = -u.c_bn[(0, 2)];
        out[(7, 3)] = -u.c_bn[(1, 0)];
        out[(7, 4)] = -u.c_bn[(1, 1)];
        out[(7, 5)] = -u.c_bn[(1, 2)];
        out[(8, 3)] = -u.c_bn[(2, 0)];
        out[(8, 4)] = -u.c_bn[(2, 1)];
        out[(8, 5)] = -u.c_bn[(2, 2)];
        out
    }
}
impl ::nav_runtime::propagation::StaticStructure for Sdins25 {
    const STRUCTURE: ::nav_runtime::propagation::Structure<'static> = Self::PROPAGATION_STRUCTURE;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Model<25, f64> for Sdins25 {
    type Input = Sdins25Input;
    type Params = Sdins25Params;
    type Noise = Sdins25Noise;
    type State = Sdins25State;
    const NAME: &'static str = "Sdins25";
    const DISCRETE: bool = !true;
    const STATE_NAMES: [&'static str; 25] = [
        "position_error[0]",
        "position_error[1]",
        "position_error[2]",
        "velocity_error[0]",
        "velocity_error[1]",
        "velocity_error[2]",
        "attitude_error[0]",
        "attitude_error[1]",
        "attitude_error[2]",
        "accel_bias[0]",
        "accel_bias[1]",
        "accel_bias[2]",
        "gyro_bias[0]",
        "gyro_bias[1]",
        "gyro_bias[2]",
        "usbl_bias[0]",
        "usbl_bias[1]",
        "depth_bias",
        "dvl_bias[0]",
        "dvl_bias[1]",
        "dvl_bias[2]",
        "compass_bias",
        "usbl_misalignment[0]",
        "usbl_misalignment[1]",
        "usbl_misalignment[2]",
    ];
    const JACOBIAN_SPARSITY: [[bool; 25]; 25] = [
        [
            true, false, true, true, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            true, false, true, false, true, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, true, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            true, false, true, true, true, true, false, true, true, true, true, true,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false,
        ],
        [
            true, false, true, true, true, true, true, false, true, true, true, true,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false,
        ],
        [
            true, false, true, true, true, false, true, true, false, true, true, true,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false,
        ],
        [
            true, false, true, false, true, false, false, true, true, false, false,
            false, true, true, true, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            true, false, true, true, false, false, true, false, true, false, false,
            false, true, true, true, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            true, false, true, false, true, false, true, true, false, false, false,
            false, true, true, true, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
        [
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, false, false, false, false, false,
            false, false, false,
        ],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = (368 + Self::PROPAGATION_STRUCTURE.ops(25));
    const OPS_JACOBIAN: usize = 246;
    const ZERO_IS_FIXED: bool = true;
    /**One Euler step `x + f(x, u, p) dt`.

Total ops: 251*/
    fn transition(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 25> {
        let (_t0, _t13) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (0.0066943799901413165 * _t0);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let _t3 = u.velocity[0] / (u.height + 6335439.3272928195 / (_t1 * _t2));
        let _t4 = u.latitude - x[0];
        let (_t5, _t17) = ::nav_runtime::math::sin_cos(_t4);
        let _t6 = 1.0 - _t5 * (_t5 * 0.0066943799901413165);
        let _t7 = ::nav_runtime::math::sqrt(_t6);
        let _t8 = u.height - x[2];
        let _t9 = 1.0 / (6335439.3272928195 / (_t6 * _t7) + _t8);
        let _t10 = u.velocity[0] - x[3];
        let _t11 = 1.0 / _t2;
        let _t12 = u.height + 6378137.0 * _t11;
        let _t14 = u.velocity[1] - x[4];
        let _t15 = 1.0 / _t7;
        let _t16 = _t8 + _t15 * 6378137.0;
        let _t18 = u.velocity[2] - x[5];
        let _t19 = _t0 * 7.292115e-5;
        let _t20 = 1.0 / _t12;
        let _t21 = _t20 * (u.velocity[1] * (_t0 / _t13));
        let _t22 = 2.0 * _t19 + _t21;
        let _t23 = u.specific_force[1] - x[10];
        let _t24 = u.specific_force[0] - x[9];
        let _t25 = u.specific_force[2] - x[11];
        let _t26 = _t9 * (x[3] - u.velocity[0]);
        let _t27 = 1.0 / _t16;
        let _t28 = _t27 * (_t5 / _t17 * (x[4] - u.velocity[1]));
        let _t29 = _t5 * 7.292115e-5;
        let _t30 = _t28 - _t29 * 2.0;
        let _t31 = _t13 * 7.292115e-5;
        let _t32 = u.velocity[1] * _t20;
        let _t33 = 2.0 * _t31 + _t32;
        let _t34 = _t17 * 7.292115e-5;
        let _t35 = _t14 * _t27;
        let _t36 = 2.0 * _t34 + _t35;
        let _t37 = _t19 + _t21;
        let _t38 = _t31 + _t32;
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 25>::zeros();
        out[0] = x[0] + dt * (_t3 - _t9 * _t10);
        out[1] = dt * (u.velocity[1] / (_t12 * _t13) - _t14 / (_t16 * _t17)) + x[1];
        out[2] = x[2] + dt * (_t18 - u.velocity[2]);
        out[3] = x[3]
            + dt
                * (u.specific_force[1] * u.c_bn[(0, 1)]
                    + u.specific_force[0] * u.c_bn[(0, 0)]
                    + u.specific_force[2] * u.c_bn[(0, 2)]
                    - (u.velocity[1] * _t22 - _t3 * u.velocity[2])
                    - (_t23
                        * (u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8]
                            + u.c_bn[(0, 1)])
                        + _t24
                            * (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)]
                                + u.c_bn[(0, 0)])
                        + _t25
                            * (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)]
                                + u.c_bn[(0, 2)]) - (_t18 * _t26 - _t14 * _t30)));
        out[4] = x[4]
            + dt
                * (u.velocity[2] * _t33 + u.velocity[0] * _t22
                    + (u.specific_force[1] * u.c_bn[(1, 1)]
                        + u.specific_force[0] * u.c_bn[(1, 0)]
                        + u.specific_force[2] * u.c_bn[(1, 2)])
                    - (_t23
                        * (u.c_bn[(1, 1)]
                            + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]))
                        + _t24
                            * (u.c_bn[(1, 0)]
                                + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]))
                        + _t25
                            * (u.c_bn[(1, 2)]
                                + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]))
                        - (_t10 * _t30 - _t18 * _t36)));
        out[5] = x[5]
            + dt
                * (u.specific_force[1] * u.c_bn[(2, 1)]
                    + u.specific_force[0] * u.c_bn[(2, 0)]
                    + u.specific_force[2] * u.c_bn[(2, 2)]
                    - (u.velocity[0] * _t3 + u.velocity[1] * _t33)
                    + (2.458172257647332e-14 * (u.height * (u.height * 3.0))
                        + (1.0
                            - (1.00680259666783 - _t0 * (_t0 * 0.0067056213295))
                                * (1.567855942887398e-7 * (u.height * 2.0))))
                        * (_t11
                            * (9.7803253359 * (1.0 + _t0 * (_t0 * 0.00193185265241))))
                    - (_t23
                        * (u.c_bn[(2, 1)]
                            + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]))
                        + _t24
                            * (u.c_bn[(2, 0)]
                                + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]))
                        + _t25
                            * (u.c_bn[(2, 2)]
                                + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]))
                        - (_t14 * _t36 - _t10 * _t26)
                        + (2.458172257647332e-14 * (_t8 * (_t8 * 3.0))
                            + (1.0
                                - (1.00680259666783 - _t5 * (_t5 * 0.0067056213295))
                                    * (1.567855942887398e-7 * (_t8 * 2.0))))
                            * (_t15
                                * ((1.0 + _t5 * (_t5 * 0.00193185265241))
                                    * 9.7803253359))));
        out[6] = x[6]
            + dt
                * (_t3 * x[8] - x[7] * _t37
                    - (u.c_bn[(0, 1)] * x[13] + u.c_bn[(0, 0)] * x[12]
                        + u.c_bn[(0, 2)] * x[14]) + _t38 - (_t34 + _t35));
        out[7] = x[7]
            + dt
                * (x[8] * _t38 + x[6] * _t37
                    - (u.c_bn[(1, 1)] * x[13] + u.c_bn[(1, 0)] * x[12]
                        + u.c_bn[(1, 2)] * x[14]) - _t3 - _t26);
        out[8] = x[8]
            - dt
                * (_t37
                    + (u.c_bn[(2, 1)] * x[13] + u.c_bn[(2, 0)] * x[12]
                        + u.c_bn[(2, 2)] * x[14] + (_t3 * x[6] + x[7] * _t38))
                    + (_t28 - _t29));
        out[9] = x[9];
        out[10] = x[10];
        out[11] = x[11];
        out[12] = x[12];
        out[13] = x[13];
        out[14] = x[14];
        out[15] = x[15];
        out[16] = x[16];
        out[17] = x[17];
        out[18] = x[18];
        out[19] = x[19];
        out[20] = x[20];
        out[21] = x[21];
        out[22] = x[22];
        out[23] = x[23];
        out[24] = x[24];
        out
    }
    /**`F = df/dx` at `w = 0` (`dt` is unused).

Total ops: 246*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 25, 25> {
        let _t0 = u.latitude - x[0];
        let (_t1, _t11) = ::nav_runtime::math::sin_cos(_t0);
        let _t2 = _t1 * 0.0066943799901413165;
        let _t3 = 1.0 - _t1 * _t2;
        let _t4 = ::nav_runtime::math::sqrt(_t3);
        let _t5 = 1.0 / (_t3 * _t4);
        let _t6 = _t5 * 6335439.3272928195;
        let _t7 = u.height - x[2];
        let _t8 = 1.0 / (_t6 + _t7);
        let _t9 = -_t8;
        let _t10 = 1.0 / _t4;
        let _t12 = _t1 * (0.0066943799901413165 * _t11) + _t2 * _t11;
        let _t13 = _t10 * 0.5 * _t12;
        let _t14 = _t5 * ((_t3 * _t13 + _t4 * _t12) * _t6);
        let _t15 = u.velocity[0] - x[3];
        let _t16 = _t8 * _t15;
        let _t17 = _t10 * 6378137.0;
        let _t18 = _t7 + _t17;
        let _t19 = 1.0 / (_t11 * _t18);
        let _t20 = _t10 * (_t13 * _t17);
        let _t21 = u.velocity[1] - x[4];
        let _t22 = _t19 * _t21;
        let _t23 = _t8 * (x[3] - u.velocity[0]);
        let _t24 = _t8 * (_t14 * _t23);
        let _t25 = u.velocity[2] - x[5];
        let _t26 = 1.0 / _t18;
        let _t27 = _t1 / _t11;
        let _t28 = x[4] - u.velocity[1];
        let _t29 = _t26 * (_t27 * _t28);
        let _t30 = _t26 * (_t20 * _t29 - (1.0 + _t27 * _t27) * _t28);
        let _t31 = _t11 * 7.292115e-5;
        let _t32 = _t31 * 2.0;
        let _t33 = _t30 + _t32;
        let _t34 = _t8 * _t23;
        let _t35 = _t26 * _t29;
        let _t36 = _t27 * _t26;
        let _t37 = _t1 * 7.292115e-5;
        let _t38 = 2.0 * _t37;
        let _t39 = _t38 - _t29;
        let _t40 = u.specific_force[1] - x[10];
        let _t41 = u.specific_force[0] - x[9];
        let _t42 = u.specific_force[2] - x[11];
        let _t43 = _t40 * u.c_bn[(2, 1)] + _t41 * u.c_bn[(2, 0)] + _t42 * u.c_bn[(2, 2)];
        let _t44 = _t40 * u.c_bn[(1, 1)] + _t41 * u.c_bn[(1, 0)] + _t42 * u.c_bn[(1, 2)];
        let _t45 = _t21 * _t26;
        let _t46 = _t26 * (_t20 * _t45);
        let _t47 = _t38 + _t46;
        let _t48 = _t26 * _t45;
        let _t49 = _t32 + _t45;
        let _t50 = _t40 * u.c_bn[(0, 1)] + _t41 * u.c_bn[(0, 0)] + _t42 * u.c_bn[(0, 2)];
        let _t51 = _t1 * 0.0067056213295;
        let _t52 = 1.567855942887398e-7 * (_t7 * 2.0);
        let _t53 = _t1 * 0.00193185265241;
        let _t54 = _t10 * ((1.0 + _t1 * _t53) * 9.7803253359);
        let _t55 = _t7 * 3.0;
        let _t56 = 1.00680259666783 - _t1 * _t51;
        let (_t57, _t61) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t58 = 1.0 - _t57 * (0.0066943799901413165 * _t57);
        let _t59 = ::nav_runtime::math::sqrt(_t58);
        let _t60 = 1.0 / (u.height + 6378137.0 / _t59);
        let _t62 = _t60 * (u.velocity[1] * (_t57 / _t61)) + 7.292115e-5 * _t57;
        let _t63 = u.velocity[0] / (u.height + 6335439.3272928195 / (_t58 * _t59));
        let _t64 = u.velocity[1] * _t60 + 7.292115e-5 * _t61;
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 25>::zeros();
        out[(0, 0)] = _t9 * (_t14 * _t16);
        out[(0, 2)] = _t9 * _t16;
        out[(0, 3)] = _t8;
        out[(1, 0)] = _t19 * ((_t1 * _t18 - _t11 * _t20) * _t22);
        out[(1, 2)] = -(_t19 * (_t11 * _t22));
        out[(1, 4)] = _t19;
        out[(2, 5)] = -1.0;
        out[(3, 0)] = _t24 * _t25 - _t21 * _t33;
        out[(3, 2)] = _t25 * _t34 - _t21 * _t35;
        out[(3, 3)] = _t8 * _t25;
        out[(3, 4)] = -(_t21 * _t36 + _t39);
        out[(3, 5)] = -_t23;
        out[(3, 7)] = -_t43;
        out[(3, 8)] = _t44;
        out[(3, 9)] = u.c_bn[(2, 0)] * x[7] - u.c_bn[(1, 0)] * x[8] + u.c_bn[(0, 0)];
        out[(3, 10)] = u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)];
        out[(3, 11)] = u.c_bn[(2, 2)] * x[7] - u.c_bn[(1, 2)] * x[8] + u.c_bn[(0, 2)];
        out[(4, 0)] = _t15 * _t33 - _t25 * _t47;
        out[(4, 2)] = _t15 * _t35 - _t25 * _t48;
        out[(4, 3)] = _t39;
        out[(4, 4)] = _t26 * _t25 + _t15 * _t36;
        out[(4, 5)] = _t49;
        out[(4, 6)] = _t43;
        out[(4, 8)] = -_t50;
        out[(4, 9)] = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        out[(4, 10)] = u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]);
        out[(4, 11)] = u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]);
        out[(5, 0)] = (_t1 * (_t11 * 0.0067056213295) + _t11 * _t51) * _t52 * _t54
            + _t10
                * (_t13 * _t54
                    + 9.7803253359 * (_t1 * (_t11 * 0.00193185265241) + _t11 * _t53))
                * (2.458172257647332e-14 * (_t7 * _t55) + (1.0 - _t52 * _t56))
            - (_t15 * _t24 - _t21 * _t47);
        out[(5, 2)] = -(_t15 * _t34 - _t21 * _t48
            + _t54
                * (_t56 * 3.135711885774796e-7 - 2.458172257647332e-14 * (2.0 * _t55)));
        out[(5, 3)] = _t23 - _t16;
        out[(5, 4)] = -(_t45 + _t49);
        out[(5, 6)] = -_t44;
        out[(5, 7)] = _t50;
        out[(5, 9)] = u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]);
        out[(5, 10)] = u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]);
        out[(5, 11)] = u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]);
        out[(6, 0)] = -(_t37 + _t46);
        out[(6, 2)] = -_t48;
        out[(6, 4)] = _t26;
        out[(6, 7)] = -_t62;
        out[(6, 8)] = _t63;
        out[(6, 12)] = -u.c_bn[(0, 0)];
        out[(6, 13)] = -u.c_bn[(0, 1)];
        out[(6, 14)] = -u.c_bn[(0, 2)];
        out[(7, 0)] = -_t24;
        out[(7, 2)] = -_t34;
        out[(7, 3)] = _t9;
        out[(7, 6)] = _t62;
        out[(7, 8)] = _t64;
        out[(7, 12)] = -u.c_bn[(1, 0)];
        out[(7, 13)] = -u.c_bn[(1, 1)];
        out[(7, 14)] = -u.c_bn[(1, 2)];
        out[(8, 0)] = -(_t30 + _t31);
        out[(8, 2)] = -_t35;
        out[(8, 4)] = -_t36;
        out[(8, 6)] = -_t63;
        out[(8, 7)] = -_t64;
        out[(8, 12)] = -u.c_bn[(2, 0)];
        out[(8, 13)] = -u.c_bn[(2, 1)];
        out[(8, 14)] = -u.c_bn[(2, 2)];
        out
    }
    /**`Qd = G Q G^T dt`, `Q = diag(q)`.

Total ops: 126*/
    fn process_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        q: &Sdins25Noise,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 25, 25> {
        let _t0 = u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)];
        let _t1 = q.accel_noise[1] * _t0;
        let _t2 = x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)] + u.c_bn[(0, 0)];
        let _t3 = q.accel_noise[0] * _t2;
        let _t4 = x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)] + u.c_bn[(0, 2)];
        let _t5 = q.accel_noise[2] * _t4;
        let _t6 = u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]);
        let _t7 = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        let _t8 = u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]);
        let _t9 = u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]);
        let _t10 = u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]);
        let _t11 = u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]);
        let _t12 = q.accel_noise[1] * _t6;
        let _t13 = q.accel_noise[0] * _t7;
        let _t14 = q.accel_noise[2] * _t8;
        let _t15 = u.c_bn[(0, 1)] * q.gyro_noise[1];
        let _t16 = u.c_bn[(0, 0)] * q.gyro_noise[0];
        let _t17 = u.c_bn[(0, 2)] * q.gyro_noise[2];
        let _t18 = u.c_bn[(1, 1)] * q.gyro_noise[1];
        let _t19 = u.c_bn[(1, 0)] * q.gyro_noise[0];
        let _t20 = u.c_bn[(1, 2)] * q.gyro_noise[2];
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 25>::zeros();
        out[(3, 3)] = (_t0 * _t1 + _t2 * _t3 + _t4 * _t5) * dt;
        out[(3, 4)] = dt * (_t1 * _t6 + _t3 * _t7 + _t5 * _t8);
        out[(3, 5)] = dt * (_t1 * _t9 + _t3 * _t10 + _t5 * _t11);
        out[(4, 4)] = dt * (_t6 * _t12 + _t7 * _t13 + _t8 * _t14);
        out[(4, 5)] = dt * (_t9 * _t12 + _t10 * _t13 + _t11 * _t14);
        out[(5, 5)] = dt
            * (_t9 * (q.accel_noise[1] * _t9) + _t10 * (q.accel_noise[0] * _t10)
                + _t11 * (q.accel_noise[2] * _t11));
        out[(6, 6)] = dt
            * (u.c_bn[(0, 1)] * _t15 + u.c_bn[(0, 0)] * _t16 + u.c_bn[(0, 2)] * _t17);
        out[(6, 7)] = dt
            * (u.c_bn[(1, 1)] * _t15 + u.c_bn[(1, 0)] * _t16 + u.c_bn[(1, 2)] * _t17);
        out[(6, 8)] = dt
            * (u.c_bn[(2, 1)] * _t15 + u.c_bn[(2, 0)] * _t16 + u.c_bn[(2, 2)] * _t17);
        out[(7, 7)] = dt
            * (u.c_bn[(1, 1)] * _t18 + u.c_bn[(1, 0)] * _t19 + u.c_bn[(1, 2)] * _t20);
        out[(7, 8)] = dt
            * (u.c_bn[(2, 1)] * _t18 + u.c_bn[(2, 0)] * _t19 + u.c_bn[(2, 2)] * _t20);
        out[(8, 8)] = dt
            * (u.c_bn[(2, 1)] * (u.c_bn[(2, 1)] * q.gyro_noise[1])
                + u.c_bn[(2, 0)] * (u.c_bn[(2, 0)] * q.gyro_noise[0])
                + u.c_bn[(2, 2)] * (u.c_bn[(2, 2)] * q.gyro_noise[2]));
        for i in 0..25 {
            for j in 0..i {
                out[(i, j)] = out[(j, i)];
            }
        }
        out
    }
    ///`P <- Phi P Phi^T + Qd`: the 60 nonzero coefficients of `Phi` in its 9 changed rows and the 12 nonzeros of `Qd` (368 ops), then `nav_runtime::propagation::propagate_static` over [`Self::PROPAGATION_STRUCTURE`]. `P` must be symmetric; the result is exactly symmetric.
    fn propagate_covariance(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        q: &Sdins25Noise,
        dt: f64,
    ) {
        Self::propagate_covariance_observed(cov, x, u, p, q, dt, |_| ());
    }
    const PROPAGATION: ::core::option::Option<
        ::nav_runtime::propagation::Structure<'static>,
    > = ::core::option::Option::Some(Self::PROPAGATION_STRUCTURE);
    /// The coefficients of `C` go to `observe`, then `nav_runtime::propagation::propagate_static`
    /// runs over [`Self::PROPAGATION_STRUCTURE`].
    #[inline]
    fn propagate_covariance_observed<F: FnOnce(&[f64])>(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        q: &Sdins25Noise,
        dt: f64,
        observe: F,
    ) {
        let _t0 = -dt;
        let _t1 = u.latitude - x[0];
        let (_t2, _t11) = ::nav_runtime::math::sin_cos(_t1);
        let _t3 = _t2 * 0.0066943799901413165;
        let _t4 = 1.0 - _t2 * _t3;
        let _t5 = ::nav_runtime::math::sqrt(_t4);
        let _t6 = 1.0 / (_t4 * _t5);
        let _t7 = _t6 * 6335439.3272928195;
        let _t8 = u.height - x[2];
        let _t9 = 1.0 / (_t7 + _t8);
        let _t10 = 1.0 / _t5;
        let _t12 = _t2 * (0.0066943799901413165 * _t11) + _t3 * _t11;
        let _t13 = _t10 * 0.5 * _t12;
        let _t14 = _t6 * ((_t4 * _t13 + _t5 * _t12) * _t7);
        let _t15 = u.velocity[0] - x[3];
        let _t16 = _t9 * _t15;
        let _t17 = _t9 * dt;
        let _t18 = _t10 * 6378137.0;
        let _t19 = _t8 + _t18;
        let _t20 = 1.0 / (_t11 * _t19);
        let _t21 = _t10 * (_t13 * _t18);
        let _t22 = u.velocity[1] - x[4];
        let _t23 = _t20 * _t22;
        let _t24 = _t9 * (x[3] - u.velocity[0]);
        let _t25 = _t9 * (_t14 * _t24);
        let _t26 = u.velocity[2] - x[5];
        let _t27 = 1.0 / _t19;
        let _t28 = _t2 / _t11;
        let _t29 = x[4] - u.velocity[1];
        let _t30 = _t27 * (_t28 * _t29);
        let _t31 = _t27 * (_t21 * _t30 - (1.0 + _t28 * _t28) * _t29);
        let _t32 = _t11 * 7.292115e-5;
        let _t33 = _t32 * 2.0;
        let _t34 = _t31 + _t33;
        let _t35 = _t9 * _t24;
        let _t36 = _t27 * _t30;
        let _t37 = _t28 * _t27;
        let _t38 = _t2 * 7.292115e-5;
        let _t39 = 2.0 * _t38;
        let _t40 = _t39 - _t30;
        let _t41 = u.specific_force[1] - x[10];
        let _t42 = u.specific_force[0] - x[9];
        let _t43 = u.specific_force[2] - x[11];
        let _t44 = dt
            * (_t41 * u.c_bn[(2, 1)] + _t42 * u.c_bn[(2, 0)] + _t43 * u.c_bn[(2, 2)]);
        let _t45 = dt
            * (_t41 * u.c_bn[(1, 1)] + _t42 * u.c_bn[(1, 0)] + _t43 * u.c_bn[(1, 2)]);
        let _t46 = u.c_bn[(2, 0)] * x[7] - u.c_bn[(1, 0)] * x[8] + u.c_bn[(0, 0)];
        let _t47 = u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)];
        let _t48 = u.c_bn[(2, 2)] * x[7] - u.c_bn[(1, 2)] * x[8] + u.c_bn[(0, 2)];
        let _t49 = _t22 * _t27;
        let _t50 = _t27 * (_t21 * _t49);
        let _t51 = _t39 + _t50;
        let _t52 = _t27 * _t49;
        let _t53 = _t33 + _t49;
        let _t54 = dt
            * (_t41 * u.c_bn[(0, 1)] + _t42 * u.c_bn[(0, 0)] + _t43 * u.c_bn[(0, 2)]);
        let _t55 = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        let _t56 = u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]);
        let _t57 = u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]);
        let _t58 = _t2 * 0.0067056213295;
        let _t59 = 1.567855942887398e-7 * (_t8 * 2.0);
        let _t60 = _t2 * 0.00193185265241;
        let _t61 = _t10 * ((1.0 + _t2 * _t60) * 9.7803253359);
        let _t62 = _t8 * 3.0;
        let _t63 = 1.00680259666783 - _t2 * _t58;
        let _t64 = u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]);
        let _t65 = u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]);
        let _t66 = u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]);
        let (_t67, _t71) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t68 = 1.0 - _t67 * (0.0066943799901413165 * _t67);
        let _t69 = ::nav_runtime::math::sqrt(_t68);
        let _t70 = 1.0 / (u.height + 6378137.0 / _t69);
        let _t72 = dt * (_t70 * (u.velocity[1] * (_t67 / _t71)) + 7.292115e-5 * _t67);
        let _t73 = dt
            * (u.velocity[0] / (u.height + 6335439.3272928195 / (_t68 * _t69)));
        let _t74 = dt * (u.velocity[1] * _t70 + 7.292115e-5 * _t71);
        let _t75 = _t47 * q.accel_noise[1];
        let _t76 = _t46 * q.accel_noise[0];
        let _t77 = _t48 * q.accel_noise[2];
        let _t78 = _t56 * q.accel_noise[1];
        let _t79 = _t55 * q.accel_noise[0];
        let _t80 = _t57 * q.accel_noise[2];
        let _t81 = u.c_bn[(0, 1)] * q.gyro_noise[1];
        let _t82 = u.c_bn[(0, 0)] * q.gyro_noise[0];
        let _t83 = u.c_bn[(0, 2)] * q.gyro_noise[2];
        let _t84 = u.c_bn[(1, 1)] * q.gyro_noise[1];
        let _t85 = u.c_bn[(1, 0)] * q.gyro_noise[0];
        let _t86 = u.c_bn[(1, 2)] * q.gyro_noise[2];
        let coefficients = [
            _t0 * (_t9 * (_t14 * _t16)),
            _t0 * (_t9 * _t16),
            _t17,
            dt * (_t20 * ((_t2 * _t19 - _t11 * _t21) * _t23)),
            _t0 * (_t20 * (_t11 * _t23)),
            dt * _t20,
            _t0,
            dt * (_t25 * _t26 - _t22 * _t34),
            dt * (_t26 * _t35 - _t22 * _t36),
            dt * (_t9 * _t26),
            _t0 * (_t22 * _t37 + _t40),
            _t0 * _t24,
            -_t44,
            _t45,
            dt * _t46,
            dt * _t47,
            dt * _t48,
            dt * (_t15 * _t34 - _t26 * _t51),
            dt * (_t15 * _t36 - _t26 * _t52),
            dt * _t40,
            dt * (_t27 * _t26 + _t15 * _t37),
            dt * _t53,
            _t44,
            -_t54,
            dt * _t55,
            dt * _t56,
            dt * _t57,
            dt
                * ((_t2 * (_t11 * 0.0067056213295) + _t11 * _t58) * _t59 * _t61
                    + _t10
                        * (_t13 * _t61
                            + 9.7803253359
                                * (_t2 * (_t11 * 0.00193185265241) + _t11 * _t60))
                        * (2.458172257647332e-14 * (_t8 * _t62) + (1.0 - _t59 * _t63))
                    - (_t15 * _t25 - _t22 * _t51)),
            _t0
                * (_t15 * _t35 - _t22 * _t52
                    + _t61
                        * (_t63 * 3.135711885774796e-7
                            - 2.458172257647332e-14 * (2.0 * _t62))),
            dt * (_t24 - _t16),
            _t0 * (_t49 + _t53),
            -_t45,
            _t54,
            dt * _t64,
            dt * _t65,
            dt * _t66,
            _t0 * (_t38 + _t50),
            _t0 * _t52,
            dt * _t27,
            -_t72,
            _t73,
            _t0 * u.c_bn[(0, 0)],
            _t0 * u.c_bn[(0, 1)],
            _t0 * u.c_bn[(0, 2)],
            _t0 * _t25,
            _t0 * _t35,
            -_t17,
            _t72,
            _t74,
            _t0 * u.c_bn[(1, 0)],
            _t0 * u.c_bn[(1, 1)],
            _t0 * u.c_bn[(1, 2)],
            _t0 * (_t31 + _t32),
            _t0 * _t36,
            _t0 * _t37,
            -_t73,
            -_t74,
            _t0 * u.c_bn[(2, 0)],
            _t0 * u.c_bn[(2, 1)],
            _t0 * u.c_bn[(2, 2)],
        ];
        observe(&coefficients);
        ::nav_runtime::propagation::propagate_static::<
            f64,
            25,
            9,
            60,
            12,
            Self,
        >(
            cov,
            &coefficients,
            &[
                dt * (_t47 * _t75 + _t46 * _t76 + _t48 * _t77),
                dt * (_t56 * _t75 + _t55 * _t76 + _t57 * _t77),
                dt * (_t65 * _t75 + _t64 * _t76 + _t66 * _t77),
                dt * (_t56 * _t78 + _t55 * _t79 + _t57 * _t80),
                dt * (_t65 * _t78 + _t64 * _t79 + _t66 * _t80),
                dt
                    * (_t65 * (_t65 * q.accel_noise[1])
                        + _t64 * (_t64 * q.accel_noise[0])
                        + _t66 * (_t66 * q.accel_noise[2])),
                dt
                    * (u.c_bn[(0, 1)] * _t81 + u.c_bn[(0, 0)] * _t82
                        + u.c_bn[(0, 2)] * _t83),
                dt
                    * (u.c_bn[(1, 1)] * _t81 + u.c_bn[(1, 0)] * _t82
                        + u.c_bn[(1, 2)] * _t83),
                dt
                    * (u.c_bn[(2, 1)] * _t81 + u.c_bn[(2, 0)] * _t82
                        + u.c_bn[(2, 2)] * _t83),
                dt
                    * (u.c_bn[(1, 1)] * _t84 + u.c_bn[(1, 0)] * _t85
                        + u.c_bn[(1, 2)] * _t86),
                dt
                    * (u.c_bn[(2, 1)] * _t84 + u.c_bn[(2, 0)] * _t85
                        + u.c_bn[(2, 2)] * _t86),
                dt
                    * (u.c_bn[(2, 1)] * (u.c_bn[(2, 1)] * q.gyro_noise[1])
                        + u.c_bn[(2, 0)] * (u.c_bn[(2, 0)] * q.gyro_noise[0])
                        + u.c_bn[(2, 2)] * (u.c_bn[(2, 2)] * q.gyro_noise[2])),
            ],
        );
    }
    const DECLARED_SENSORS: &'static [&'static str] = &[
        "Depth",
        "Dvl",
        "CompassSmallAngle",
        "Compass",
        "Usbl",
    ];
    fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, 25, f64>>(
        name: &str,
        visitor: V,
    ) -> ::core::option::Option<V::Output> {
        match name {
            "Depth" => ::core::option::Option::Some(visitor.visit::<Sdins25Depth, 1>()),
            "Dvl" => ::core::option::Option::Some(visitor.visit::<Sdins25Dvl, 3>()),
            "CompassSmallAngle" => {
                ::core::option::Option::Some(
                    visitor.visit::<Sdins25CompassSmallAngle, 1>(),
                )
            }
            "Compass" => {
                ::core::option::Option::Some(visitor.visit::<Sdins25Compass, 1>())
            }
            "Usbl" => ::core::option::Option::Some(visitor.visit::<Sdins25Usbl, 2>()),
            _ => {
                let _ = visitor;
                ::core::option::Option::None
            }
        }
    }
}
/// Depth meter, height convention: `h^ - h_meas = dh - b_depth` (eq. 10).
///
///Sensor `Depth` of [`Sdins25`]: 1 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25Depth;
#[allow(clippy::possible_missing_comma)]
impl Sdins25Depth {
    /// Number of measurement components.
    pub const M: usize = 1;
    /// The declared sensor name.
    pub const NAME: &'static str = "Depth";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 0;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 25] = [
        true, false, true, true, true, true, true, true, true, true, true, true, true,
        true, true, false, false, true, false, false, false, false, false, false, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 1;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 28;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<25, 1, f64> for Sdins25Depth {
    type Model = Sdins25;
    type Aux = ();
    const NAME: &'static str = "Depth";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 25]; 1] = [
        [
            false, false, true, false, false, false, false, false, false, false, false,
            false, false, false, false, false, false, true, false, false, false, false,
            false, false, false,
        ],
    ];
    const OPS_INNOVATION_TERMS: usize = 28;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 1*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 1> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        out[0] = x[2] - x[17];
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 1, 25> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 25>::zeros();
        out[(0, 2)] = 1.0;
        out[(0, 17)] = -1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 28*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 25, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 1, 1>,
    ) {
        let _t0 = cov[(2, 2)] - cov[(2, 17)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 1>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::zeros();
        h[0] = x[2] - x[17];
        pht[(0, 0)] = cov[(0, 2)] - cov[(0, 17)];
        pht[(1, 0)] = cov[(1, 2)] - cov[(1, 17)];
        pht[(2, 0)] = _t0;
        pht[(3, 0)] = cov[(2, 3)] - cov[(3, 17)];
        pht[(4, 0)] = cov[(2, 4)] - cov[(4, 17)];
        pht[(5, 0)] = cov[(2, 5)] - cov[(5, 17)];
        pht[(6, 0)] = cov[(2, 6)] - cov[(6, 17)];
        pht[(7, 0)] = cov[(2, 7)] - cov[(7, 17)];
        pht[(8, 0)] = cov[(2, 8)] - cov[(8, 17)];
        pht[(9, 0)] = cov[(2, 9)] - cov[(9, 17)];
        pht[(10, 0)] = cov[(2, 10)] - cov[(10, 17)];
        pht[(11, 0)] = cov[(2, 11)] - cov[(11, 17)];
        pht[(12, 0)] = cov[(2, 12)] - cov[(12, 17)];
        pht[(13, 0)] = cov[(2, 13)] - cov[(13, 17)];
        pht[(14, 0)] = cov[(2, 14)] - cov[(14, 17)];
        pht[(15, 0)] = cov[(2, 15)] - cov[(15, 17)];
        pht[(16, 0)] = cov[(2, 16)] - cov[(16, 17)];
        pht[(17, 0)] = cov[(2, 17)] - cov[(17, 17)];
        pht[(18, 0)] = cov[(2, 18)] - cov[(17, 18)];
        pht[(19, 0)] = cov[(2, 19)] - cov[(17, 19)];
        pht[(20, 0)] = cov[(2, 20)] - cov[(17, 20)];
        pht[(21, 0)] = cov[(2, 21)] - cov[(17, 21)];
        pht[(22, 0)] = cov[(2, 22)] - cov[(17, 22)];
        pht[(23, 0)] = cov[(2, 23)] - cov[(17, 23)];
        pht[(24, 0)] = cov[(2, 24)] - cov[(17, 24)];
        s[(0, 0)] = _t0 + (cov[(17, 17)] - cov[(2, 17)]);
        for i in 0..1 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// DVL, body 3-axis: `V^n - C^_b^n v_meas = dV - V^n x phi - C_b^n b_dvl` (eq. 11),
/// derived from the true velocity and attitude.
///
///Sensor `Dvl` of [`Sdins25`]: 3 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25Dvl;
#[allow(clippy::possible_missing_comma)]
impl Sdins25Dvl {
    /// Number of measurement components.
    pub const M: usize = 3;
    /// The declared sensor name.
    pub const NAME: &'static str = "Dvl";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 1;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 25] = [
        true, false, true, true, true, true, true, true, true, true, true, true, true,
        true, true, false, false, false, true, true, true, false, false, false, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 75;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 174;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 1569;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<25, 3, f64> for Sdins25Dvl {
    type Model = Sdins25;
    type Aux = ();
    const NAME: &'static str = "Dvl";
    const ANGLES: [bool; 3] = [false, false, false];
    const JACOBIAN_SPARSITY: [[bool; 25]; 3] = [
        [
            false, false, false, true, true, true, true, true, true, false, false, false,
            false, false, false, false, false, false, true, true, true, false, false,
            false, false,
        ],
        [
            false, false, false, true, true, true, true, true, true, false, false, false,
            false, false, false, false, false, false, true, true, true, false, false,
            false, false,
        ],
        [
            false, false, false, true, true, true, true, true, true, false, false, false,
            false, false, false, false, false, false, true, true, true, false, false,
            false, false,
        ],
    ];
    const OPS_INNOVATION_TERMS: usize = 1569;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 75*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        let _t0 = u.velocity[1] - x[4];
        let _t1 = u.velocity[0] - x[3];
        let _t2 = u.velocity[2] - x[5];
        let _t3 = (u.c_bn[(0, 1)] * x[8] - u.c_bn[(2, 1)] * x[6] + u.c_bn[(1, 1)]) * _t0
            + (u.c_bn[(0, 1)] + (u.c_bn[(2, 1)] * x[7] - x[8] * u.c_bn[(1, 1)])) * _t1
            + (u.c_bn[(2, 1)] + (x[6] * u.c_bn[(1, 1)] - u.c_bn[(0, 1)] * x[7])) * _t2
            + x[19];
        let _t4 = _t0 * (x[8] * u.c_bn[(0, 0)] - x[6] * u.c_bn[(2, 0)] + u.c_bn[(1, 0)])
            + _t1 * (u.c_bn[(0, 0)] + (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)]))
            + _t2 * (u.c_bn[(2, 0)] + (x[6] * u.c_bn[(1, 0)] - x[7] * u.c_bn[(0, 0)]))
            + x[18];
        let _t5 = _t0 * (x[8] * u.c_bn[(0, 2)] - x[6] * u.c_bn[(2, 2)] + u.c_bn[(1, 2)])
            + _t1 * (u.c_bn[(0, 2)] + (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)]))
            + _t2 * (u.c_bn[(2, 2)] + (x[6] * u.c_bn[(1, 2)] - x[7] * u.c_bn[(0, 2)]))
            + x[20];
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        out[0] = u.velocity[0]
            - (u.c_bn[(0, 1)] * _t3 + u.c_bn[(0, 0)] * _t4 + u.c_bn[(0, 2)] * _t5);
        out[1] = u.velocity[1]
            - (u.c_bn[(1, 1)] * _t3 + u.c_bn[(1, 0)] * _t4 + u.c_bn[(1, 2)] * _t5);
        out[2] = u.velocity[2]
            - (u.c_bn[(2, 1)] * _t3 + u.c_bn[(2, 0)] * _t4 + u.c_bn[(2, 2)] * _t5);
        out
    }
    /**`H = dh/dx`.

Total ops: 174*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 25> {
        let _t0 = u.c_bn[(2, 1)] * x[7] - u.c_bn[(1, 1)] * x[8] + u.c_bn[(0, 1)];
        let _t1 = x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)] + u.c_bn[(0, 0)];
        let _t2 = x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)] + u.c_bn[(0, 2)];
        let _t3 = u.c_bn[(1, 1)] + (x[8] * u.c_bn[(0, 1)] - u.c_bn[(2, 1)] * x[6]);
        let _t4 = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        let _t5 = u.c_bn[(1, 2)] + (x[8] * u.c_bn[(0, 2)] - u.c_bn[(2, 2)] * x[6]);
        let _t6 = u.c_bn[(2, 1)] + (u.c_bn[(1, 1)] * x[6] - x[7] * u.c_bn[(0, 1)]);
        let _t7 = u.c_bn[(2, 0)] + (u.c_bn[(1, 0)] * x[6] - x[7] * u.c_bn[(0, 0)]);
        let _t8 = u.c_bn[(2, 2)] + (u.c_bn[(1, 2)] * x[6] - x[7] * u.c_bn[(0, 2)]);
        let _t9 = u.velocity[2] - x[5];
        let _t10 = u.velocity[1] - x[4];
        let _t11 = u.c_bn[(1, 1)] * _t9 - u.c_bn[(2, 1)] * _t10;
        let _t12 = u.c_bn[(1, 0)] * _t9 - u.c_bn[(2, 0)] * _t10;
        let _t13 = u.c_bn[(1, 2)] * _t9 - u.c_bn[(2, 2)] * _t10;
        let _t14 = u.velocity[0] - x[3];
        let _t15 = u.c_bn[(2, 1)] * _t14 - u.c_bn[(0, 1)] * _t9;
        let _t16 = u.c_bn[(2, 0)] * _t14 - u.c_bn[(0, 0)] * _t9;
        let _t17 = u.c_bn[(2, 2)] * _t14 - u.c_bn[(0, 2)] * _t9;
        let _t18 = u.c_bn[(0, 1)] * _t10 - u.c_bn[(1, 1)] * _t14;
        let _t19 = u.c_bn[(0, 0)] * _t10 - u.c_bn[(1, 0)] * _t14;
        let _t20 = u.c_bn[(0, 2)] * _t10 - u.c_bn[(1, 2)] * _t14;
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 25>::zeros();
        out[(0, 3)] = u.c_bn[(0, 1)] * _t0 + u.c_bn[(0, 0)] * _t1 + u.c_bn[(0, 2)] * _t2;
        out[(0, 4)] = u.c_bn[(0, 1)] * _t3 + u.c_bn[(0, 0)] * _t4 + u.c_bn[(0, 2)] * _t5;
        out[(0, 5)] = u.c_bn[(0, 1)] * _t6 + u.c_bn[(0, 0)] * _t7 + u.c_bn[(0, 2)] * _t8;
        out[(0, 6)] = -(u.c_bn[(0, 1)] * _t11 + u.c_bn[(0, 0)] * _t12
            + u.c_bn[(0, 2)] * _t13);
        out[(0, 7)] = -(u.c_bn[(0, 1)] * _t15 + u.c_bn[(0, 0)] * _t16
            + u.c_bn[(0, 2)] * _t17);
        out[(0, 8)] = -(u.c_bn[(0, 1)] * _t18 + u.c_bn[(0, 0)] * _t19
            + u.c_bn[(0, 2)] * _t20);
        out[(0, 18)] = -u.c_bn[(0, 0)];
        out[(0, 19)] = -u.c_bn[(0, 1)];
        out[(0, 20)] = -u.c_bn[(0, 2)];
        out[(1, 3)] = u.c_bn[(1, 1)] * _t0 + u.c_bn[(1, 0)] * _t1 + u.c_bn[(1, 2)] * _t2;
        out[(1, 4)] = u.c_bn[(1, 1)] * _t3 + u.c_bn[(1, 0)] * _t4 + u.c_bn[(1, 2)] * _t5;
        out[(1, 5)] = u.c_bn[(1, 1)] * _t6 + u.c_bn[(1, 0)] * _t7 + u.c_bn[(1, 2)] * _t8;
        out[(1, 6)] = -(u.c_bn[(1, 1)] * _t11 + u.c_bn[(1, 0)] * _t12
            + u.c_bn[(1, 2)] * _t13);
        out[(1, 7)] = -(u.c_bn[(1, 1)] * _t15 + u.c_bn[(1, 0)] * _t16
            + u.c_bn[(1, 2)] * _t17);
        out[(1, 8)] = -(u.c_bn[(1, 1)] * _t18 + u.c_bn[(1, 0)] * _t19
            + u.c_bn[(1, 2)] * _t20);
        out[(1, 18)] = -u.c_bn[(1, 0)];
        out[(1, 19)] = -u.c_bn[(1, 1)];
        out[(1, 20)] = -u.c_bn[(1, 2)];
        out[(2, 3)] = u.c_bn[(2, 1)] * _t0 + u.c_bn[(2, 0)] * _t1 + u.c_bn[(2, 2)] * _t2;
        out[(2, 4)] = u.c_bn[(2, 1)] * _t3 + u.c_bn[(2, 0)] * _t4 + u.c_bn[(2, 2)] * _t5;
        out[(2, 5)] = u.c_bn[(2, 1)] * _t6 + u.c_bn[(2, 0)] * _t7 + u.c_bn[(2, 2)] * _t8;
        out[(2, 6)] = -(u.c_bn[(2, 1)] * _t11 + u.c_bn[(2, 0)] * _t12
            + u.c_bn[(2, 2)] * _t13);
        out[(2, 7)] = -(u.c_bn[(2, 1)] * _t15 + u.c_bn[(2, 0)] * _t16
            + u.c_bn[(2, 2)] * _t17);
        out[(2, 8)] = -(u.c_bn[(2, 1)] * _t18 + u.c_bn[(2, 0)] * _t19
            + u.c_bn[(2, 2)] * _t20);
        out[(2, 18)] = -u.c_bn[(2, 0)];
        out[(2, 19)] = -u.c_bn[(2, 1)];
        out[(2, 20)] = -u.c_bn[(2, 2)];
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 1569*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 25, 3>,
        ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
    ) {
        let _t0 = u.c_bn[(0, 1)] * x[8] - u.c_bn[(2, 1)] * x[6] + u.c_bn[(1, 1)];
        let _t1 = u.velocity[1] - x[4];
        let _t2 = u.c_bn[(0, 1)] + (u.c_bn[(2, 1)] * x[7] - x[8] * u.c_bn[(1, 1)]);
        let _t3 = u.velocity[0] - x[3];
        let _t4 = u.c_bn[(2, 1)] + (x[6] * u.c_bn[(1, 1)] - u.c_bn[(0, 1)] * x[7]);
        let _t5 = u.velocity[2] - x[5];
        let _t6 = _t0 * _t1 + _t2 * _t3 + _t4 * _t5 + x[19];
        let _t7 = x[8] * u.c_bn[(0, 0)] - x[6] * u.c_bn[(2, 0)] + u.c_bn[(1, 0)];
        let _t8 = u.c_bn[(0, 0)] + (x[7] * u.c_bn[(2, 0)] - x[8] * u.c_bn[(1, 0)]);
        let _t9 = u.c_bn[(2, 0)] + (x[6] * u.c_bn[(1, 0)] - x[7] * u.c_bn[(0, 0)]);
        let _t10 = _t1 * _t7 + _t3 * _t8 + _t5 * _t9 + x[18];
        let _t11 = x[8] * u.c_bn[(0, 2)] - x[6] * u.c_bn[(2, 2)] + u.c_bn[(1, 2)];
        let _t12 = u.c_bn[(0, 2)] + (x[7] * u.c_bn[(2, 2)] - x[8] * u.c_bn[(1, 2)]);
        let _t13 = u.c_bn[(2, 2)] + (x[6] * u.c_bn[(1, 2)] - x[7] * u.c_bn[(0, 2)]);
        let _t14 = _t1 * _t11 + _t3 * _t12 + _t5 * _t13 + x[20];
        let _t15 = u.c_bn[(0, 1)] * _t0 + u.c_bn[(0, 0)] * _t7 + u.c_bn[(0, 2)] * _t11;
        let _t16 = u.c_bn[(0, 1)] * _t2 + u.c_bn[(0, 0)] * _t8 + u.c_bn[(0, 2)] * _t12;
        let _t17 = u.c_bn[(0, 1)] * _t4 + u.c_bn[(0, 0)] * _t9 + u.c_bn[(0, 2)] * _t13;
        let _t18 = u.c_bn[(1, 1)] * _t5 - u.c_bn[(2, 1)] * _t1;
        let _t19 = _t5 * u.c_bn[(1, 0)] - _t1 * u.c_bn[(2, 0)];
        let _t20 = _t5 * u.c_bn[(1, 2)] - _t1 * u.c_bn[(2, 2)];
        let _t21 = u.c_bn[(0, 1)] * _t18 + u.c_bn[(0, 0)] * _t19 + u.c_bn[(0, 2)] * _t20;
        let _t22 = u.c_bn[(2, 1)] * _t3 - u.c_bn[(0, 1)] * _t5;
        let _t23 = _t3 * u.c_bn[(2, 0)] - _t5 * u.c_bn[(0, 0)];
        let _t24 = _t3 * u.c_bn[(2, 2)] - _t5 * u.c_bn[(0, 2)];
        let _t25 = u.c_bn[(0, 1)] * _t22 + u.c_bn[(0, 0)] * _t23 + u.c_bn[(0, 2)] * _t24;
        let _t26 = u.c_bn[(0, 1)] * _t1 - u.c_bn[(1, 1)] * _t3;
        let _t27 = _t1 * u.c_bn[(0, 0)] - _t3 * u.c_bn[(1, 0)];
        let _t28 = _t1 * u.c_bn[(0, 2)] - _t3 * u.c_bn[(1, 2)];
        let _t29 = u.c_bn[(0, 1)] * _t26 + u.c_bn[(0, 0)] * _t27 + u.c_bn[(0, 2)] * _t28;
        let _t30 = u.c_bn[(1, 1)] * _t0 + u.c_bn[(1, 0)] * _t7 + u.c_bn[(1, 2)] * _t11;
        let _t31 = u.c_bn[(1, 1)] * _t2 + u.c_bn[(1, 0)] * _t8 + u.c_bn[(1, 2)] * _t12;
        let _t32 = u.c_bn[(1, 1)] * _t4 + u.c_bn[(1, 0)] * _t9 + u.c_bn[(1, 2)] * _t13;
        let _t33 = u.c_bn[(1, 1)] * _t18 + u.c_bn[(1, 0)] * _t19 + u.c_bn[(1, 2)] * _t20;
        let _t34 = u.c_bn[(1, 1)] * _t22 + u.c_bn[(1, 0)] * _t23 + u.c_bn[(1, 2)] * _t24;
        let _t35 = u.c_bn[(1, 1)] * _t26 + u.c_bn[(1, 0)] * _t27 + u.c_bn[(1, 2)] * _t28;
        let _t36 = u.c_bn[(2, 1)] * _t0 + u.c_bn[(2, 0)] * _t7 + u.c_bn[(2, 2)] * _t11;
        let _t37 = u.c_bn[(2, 1)] * _t2 + u.c_bn[(2, 0)] * _t8 + u.c_bn[(2, 2)] * _t12;
        let _t38 = u.c_bn[(2, 1)] * _t4 + u.c_bn[(2, 0)] * _t9 + u.c_bn[(2, 2)] * _t13;
        let _t39 = u.c_bn[(2, 1)] * _t18 + u.c_bn[(2, 0)] * _t19 + u.c_bn[(2, 2)] * _t20;
        let _t40 = u.c_bn[(2, 1)] * _t22 + u.c_bn[(2, 0)] * _t23 + u.c_bn[(2, 2)] * _t24;
        let _t41 = u.c_bn[(2, 1)] * _t26 + u.c_bn[(2, 0)] * _t27 + u.c_bn[(2, 2)] * _t28;
        let _t42 = _t15 * cov[(3, 4)] + _t16 * cov[(3, 3)] + _t17 * cov[(3, 5)]
            - _t21 * cov[(3, 6)] - _t25 * cov[(3, 7)] - _t29 * cov[(3, 8)]
            - u.c_bn[(0, 0)] * cov[(3, 18)] - u.c_bn[(0, 1)] * cov[(3, 19)]
            - u.c_bn[(0, 2)] * cov[(3, 20)];
        let _t43 = _t30 * cov[(3, 4)] + _t31 * cov[(3, 3)] + _t32 * cov[(3, 5)]
            - _t33 * cov[(3, 6)] - _t34 * cov[(3, 7)] - _t35 * cov[(3, 8)]
            - u.c_bn[(1, 0)] * cov[(3, 18)] - u.c_bn[(1, 1)] * cov[(3, 19)]
            - u.c_bn[(1, 2)] * cov[(3, 20)];
        let _t44 = _t36 * cov[(3, 4)] + _t37 * cov[(3, 3)] + _t38 * cov[(3, 5)]
            - _t39 * cov[(3, 6)] - _t40 * cov[(3, 7)] - _t41 * cov[(3, 8)]
            - u.c_bn[(2, 0)] * cov[(3, 18)] - u.c_bn[(2, 1)] * cov[(3, 19)]
            - u.c_bn[(2, 2)] * cov[(3, 20)];
        let _t45 = _t15 * cov[(4, 4)] + _t16 * cov[(3, 4)] + _t17 * cov[(4, 5)]
            - _t21 * cov[(4, 6)] - _t25 * cov[(4, 7)] - _t29 * cov[(4, 8)]
            - u.c_bn[(0, 0)] * cov[(4, 18)] - u.c_bn[(0, 1)] * cov[(4, 19)]
            - u.c_bn[(0, 2)] * cov[(4, 20)];
        let _t46 = _t30 * cov[(4, 4)] + _t31 * cov[(3, 4)] + _t32 * cov[(4, 5)]
            - _t33 * cov[(4, 6)] - _t34 * cov[(4, 7)] - _t35 * cov[(4, 8)]
            - u.c_bn[(1, 0)] * cov[(4, 18)] - u.c_bn[(1, 1)] * cov[(4, 19)]
            - u.c_bn[(1, 2)] * cov[(4, 20)];
        let _t47 = _t36 * cov[(4, 4)] + _t37 * cov[(3, 4)] + _t38 * cov[(4, 5)]
            - _t39 * cov[(4, 6)] - _t40 * cov[(4, 7)] - _t41 * cov[(4, 8)]
            - u.c_bn[(2, 0)] * cov[(4, 18)] - u.c_bn[(2, 1)] * cov[(4, 19)]
            - u.c_bn[(2, 2)] * cov[(4, 20)];
        let _t48 = _t15 * cov[(4, 5)] + _t16 * cov[(3, 5)] + _t17 * cov[(5, 5)]
            - _t21 * cov[(5, 6)] - _t25 * cov[(5, 7)] - _t29 * cov[(5, 8)]
            - u.c_bn[(0, 0)] * cov[(5, 18)] - u.c_bn[(0, 1)] * cov[(5, 19)]
            - u.c_bn[(0, 2)] * cov[(5, 20)];
        let _t49 = _t30 * cov[(4, 5)] + _t31 * cov[(3, 5)] + _t32 * cov[(5, 5)]
            - _t33 * cov[(5, 6)] - _t34 * cov[(5, 7)] - _t35 * cov[(5, 8)]
            - u.c_bn[(1, 0)] * cov[(5, 18)] - u.c_bn[(1, 1)] * cov[(5, 19)]
            - u.c_bn[(1, 2)] * cov[(5, 20)];
        let _t50 = _t36 * cov[(4, 5)] + _t37 * cov[(3, 5)] + _t38 * cov[(5, 5)]
            - _t39 * cov[(5, 6)] - _t40 * cov[(5, 7)] - _t41 * cov[(5, 8)]
            - u.c_bn[(2, 0)] * cov[(5, 18)] - u.c_bn[(2, 1)] * cov[(5, 19)]
            - u.c_bn[(2, 2)] * cov[(5, 20)];
        let _t51 = _t15 * cov[(4, 6)] + _t16 * cov[(3, 6)] + _t17 * cov[(5, 6)]
            - _t21 * cov[(6, 6)] - _t25 * cov[(6, 7)] - _t29 * cov[(6, 8)]
            - u.c_bn[(0, 0)] * cov[(6, 18)] - u.c_bn[(0, 1)] * cov[(6, 19)]
            - u.c_bn[(0, 2)] * cov[(6, 20)];
        let _t52 = _t30 * cov[(4, 6)] + _t31 * cov[(3, 6)] + _t32 * cov[(5, 6)]
            - _t33 * cov[(6, 6)] - _t34 * cov[(6, 7)] - _t35 * cov[(6, 8)]
            - u.c_bn[(1, 0)] * cov[(6, 18)] - u.c_bn[(1, 1)] * cov[(6, 19)]
            - u.c_bn[(1, 2)] * cov[(6, 20)];
        let _t53 = _t36 * cov[(4, 6)] + _t37 * cov[(3, 6)] + _t38 * cov[(5, 6)]
            - _t39 * cov[(6, 6)] - _t40 * cov[(6, 7)] - _t41 * cov[(6, 8)]
            - u.c_bn[(2, 0)] * cov[(6, 18)] - u.c_bn[(2, 1)] * cov[(6, 19)]
            - u.c_bn[(2, 2)] * cov[(6, 20)];
        let _t54 = _t15 * cov[(4, 7)] + _t16 * cov[(3, 7)] + _t17 * cov[(5, 7)]
            - _t21 * cov[(6, 7)] - _t25 * cov[(7, 7)] - _t29 * cov[(7, 8)]
            - u.c_bn[(0, 0)] * cov[(7, 18)] - u.c_bn[(0, 1)] * cov[(7, 19)]
            - u.c_bn[(0, 2)] * cov[(7, 20)];
        let _t55 = _t30 * cov[(4, 7)] + _t31 * cov[(3, 7)] + _t32 * cov[(5, 7)]
            - _t33 * cov[(6, 7)] - _t34 * cov[(7, 7)] - _t35 * cov[(7, 8)]
            - u.c_bn[(1, 0)] * cov[(7, 18)] - u.c_bn[(1, 1)] * cov[(7, 19)]
            - u.c_bn[(1, 2)] * cov[(7, 20)];
        let _t56 = _t36 * cov[(4, 7)] + _t37 * cov[(3, 7)] + _t38 * cov[(5, 7)]
            - _t39 * cov[(6, 7)] - _t40 * cov[(7, 7)] - _t41 * cov[(7, 8)]
            - u.c_bn[(2, 0)] * cov[(7, 18)] - u.c_bn[(2, 1)] * cov[(7, 19)]
            - u.c_bn[(2, 2)] * cov[(7, 20)];
        let _t57 = _t15 * cov[(4, 8)] + _t16 * cov[(3, 8)] + _t17 * cov[(5, 8)]
            - _t21 * cov[(6, 8)] - _t25 * cov[(7, 8)] - _t29 * cov[(8, 8)]
            - u.c_bn[(0, 0)] * cov[(8, 18)] - u.c_bn[(0, 1)] * cov[(8, 19)]
            - u.c_bn[(0, 2)] * cov[(8, 20)];
        let _t58 = _t30 * cov[(4, 8)] + _t31 * cov[(3, 8)] + _t32 * cov[(5, 8)]
            - _t33 * cov[(6, 8)] - _t34 * cov[(7, 8)] - _t35 * cov[(8, 8)]
            - u.c_bn[(1, 0)] * cov[(8, 18)] - u.c_bn[(1, 1)] * cov[(8, 19)]
            - u.c_bn[(1, 2)] * cov[(8, 20)];
        let _t59 = _t36 * cov[(4, 8)] + _t37 * cov[(3, 8)] + _t38 * cov[(5, 8)]
            - _t39 * cov[(6, 8)] - _t40 * cov[(7, 8)] - _t41 * cov[(8, 8)]
            - u.c_bn[(2, 0)] * cov[(8, 18)] - u.c_bn[(2, 1)] * cov[(8, 19)]
            - u.c_bn[(2, 2)] * cov[(8, 20)];
        let _t60 = _t15 * cov[(4, 18)] + _t16 * cov[(3, 18)] + _t17 * cov[(5, 18)]
            - _t21 * cov[(6, 18)] - _t25 * cov[(7, 18)] - _t29 * cov[(8, 18)]
            - u.c_bn[(0, 0)] * cov[(18, 18)] - u.c_bn[(0, 1)] * cov[(18, 19)]
            - u.c_bn[(0, 2)] * cov[(18, 20)];
        let _t61 = _t30 * cov[(4, 18)] + _t31 * cov[(3, 18)] + _t32 * cov[(5, 18)]
            - _t33 * cov[(6, 18)] - _t34 * cov[(7, 18)] - _t35 * cov[(8, 18)]
            - u.c_bn[(1, 0)] * cov[(18, 18)] - u.c_bn[(1, 1)] * cov[(18, 19)]
            - u.c_bn[(1, 2)] * cov[(18, 20)];
        let _t62 = _t36 * cov[(4, 18)] + _t37 * cov[(3, 18)] + _t38 * cov[(5, 18)]
            - _t39 * cov[(6, 18)] - _t40 * cov[(7, 18)] - _t41 * cov[(8, 18)]
            - u.c_bn[(2, 0)] * cov[(18, 18)] - u.c_bn[(2, 1)] * cov[(18, 19)]
            - u.c_bn[(2, 2)] * cov[(18, 20)];
        let _t63 = _t15 * cov[(4, 19)] + _t16 * cov[(3, 19)] + _t17 * cov[(5, 19)]
            - _t21 * cov[(6, 19)] - _t25 * cov[(7, 19)] - _t29 * cov[(8, 19)]
            - u.c_bn[(0, 0)] * cov[(18, 19)] - u.c_bn[(0, 1)] * cov[(19, 19)]
            - u.c_bn[(0, 2)] * cov[(19, 20)];
        let _t64 = _t30 * cov[(4, 19)] + _t31 * cov[(3, 19)] + _t32 * cov[(5, 19)]
            - _t33 * cov[(6, 19)] - _t34 * cov[(7, 19)] - _t35 * cov[(8, 19)]
            - u.c_bn[(1, 0)] * cov[(18, 19)] - u.c_bn[(1, 1)] * cov[(19, 19)]
            - u.c_bn[(1, 2)] * cov[(19, 20)];
        let _t65 = _t36 * cov[(4, 19)] + _t37 * cov[(3, 19)] + _t38 * cov[(5, 19)]
            - _t39 * cov[(6, 19)] - _t40 * cov[(7, 19)] - _t41 * cov[(8, 19)]
            - u.c_bn[(2, 0)] * cov[(18, 19)] - u.c_bn[(2, 1)] * cov[(19, 19)]
            - u.c_bn[(2, 2)] * cov[(19, 20)];
        let _t66 = _t15 * cov[(4, 20)] + _t16 * cov[(3, 20)] + _t17 * cov[(5, 20)]
            - _t21 * cov[(6, 20)] - _t25 * cov[(7, 20)] - _t29 * cov[(8, 20)]
            - u.c_bn[(0, 0)] * cov[(18, 20)] - u.c_bn[(0, 1)] * cov[(19, 20)]
            - u.c_bn[(0, 2)] * cov[(20, 20)];
        let _t67 = _t30 * cov[(4, 20)] + _t31 * cov[(3, 20)] + _t32 * cov[(5, 20)]
            - _t33 * cov[(6, 20)] - _t34 * cov[(7, 20)] - _t35 * cov[(8, 20)]
            - u.c_bn[(1, 0)] * cov[(18, 20)] - u.c_bn[(1, 1)] * cov[(19, 20)]
            - u.c_bn[(1, 2)] * cov[(20, 20)];
        let _t68 = _t36 * cov[(4, 20)] + _t37 * cov[(3, 20)] + _t38 * cov[(5, 20)]
            - _t39 * cov[(6, 20)] - _t40 * cov[(7, 20)] - _t41 * cov[(8, 20)]
            - u.c_bn[(2, 0)] * cov[(18, 20)] - u.c_bn[(2, 1)] * cov[(19, 20)]
            - u.c_bn[(2, 2)] * cov[(20, 20)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 3>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        h[0] = u.velocity[0]
            - (u.c_bn[(0, 1)] * _t6 + u.c_bn[(0, 0)] * _t10 + u.c_bn[(0, 2)] * _t14);
        h[1] = u.velocity[1]
            - (u.c_bn[(1, 1)] * _t6 + u.c_bn[(1, 0)] * _t10 + u.c_bn[(1, 2)] * _t14);
        h[2] = u.velocity[2]
            - (u.c_bn[(2, 1)] * _t6 + u.c_bn[(2, 0)] * _t10 + u.c_bn[(2, 2)] * _t14);
        pht[(0, 0)] = cov[(0, 4)] * _t15 + cov[(0, 3)] * _t16 + cov[(0, 5)] * _t17
            - cov[(0, 6)] * _t21 - cov[(0, 7)] * _t25 - cov[(0, 8)] * _t29
            - u.c_bn[(0, 0)] * cov[(0, 18)] - u.c_bn[(0, 1)] * cov[(0, 19)]
            - u.c_bn[(0, 2)] * cov[(0, 20)];
        pht[(0, 1)] = cov[(0, 4)] * _t30 + cov[(0, 3)] * _t31 + cov[(0, 5)] * _t32
            - cov[(0, 6)] * _t33 - cov[(0, 7)] * _t34 - cov[(0, 8)] * _t35
            - u.c_bn[(1, 0)] * cov[(0, 18)] - u.c_bn[(1, 1)] * cov[(0, 19)]
            - u.c_bn[(1, 2)] * cov[(0, 20)];
        pht[(0, 2)] = cov[(0, 4)] * _t36 + cov[(0, 3)] * _t37 + cov[(0, 5)] * _t38
            - cov[(0, 6)] * _t39 - cov[(0, 7)] * _t40 - cov[(0, 8)] * _t41
            - u.c_bn[(2, 0)] * cov[(0, 18)] - u.c_bn[(2, 1)] * cov[(0, 19)]
            - u.c_bn[(2, 2)] * cov[(0, 20)];
        pht[(1, 0)] = _t15 * cov[(1, 4)] + _t16 * cov[(1, 3)] + _t17 * cov[(1, 5)]
            - _t21 * cov[(1, 6)] - _t25 * cov[(1, 7)] - _t29 * cov[(1, 8)]
            - u.c_bn[(0, 0)] * cov[(1, 18)] - u.c_bn[(0, 1)] * cov[(1, 19)]
            - u.c_bn[(0, 2)] * cov[(1, 20)];
        pht[(1, 1)] = _t30 * cov[(1, 4)] + _t31 * cov[(1, 3)] + _t32 * cov[(1, 5)]
            - _t33 * cov[(1, 6)] - _t34 * cov[(1, 7)] - _t35 * cov[(1, 8)]
            - u.c_bn[(1, 0)] * cov[(1, 18)] - u.c_bn[(1, 1)] * cov[(1, 19)]
            - u.c_bn[(1, 2)] * cov[(1, 20)];
        pht[(1, 2)] = _t36 * cov[(1, 4)] + _t37 * cov[(1, 3)] + _t38 * cov[(1, 5)]
            - _t39 * cov[(1, 6)] - _t40 * cov[(1, 7)] - _t41 * cov[(1, 8)]
            - u.c_bn[(2, 0)] * cov[(1, 18)] - u.c_bn[(2, 1)] * cov[(1, 19)]
            - u.c_bn[(2, 2)] * cov[(1, 20)];
        pht[(2, 0)] = _t15 * cov[(2, 4)] + _t16 * cov[(2, 3)] + _t17 * cov[(2, 5)]
            - _t21 * cov[(2, 6)] - _t25 * cov[(2, 7)] - _t29 * cov[(2, 8)]
            - u.c_bn[(0, 0)] * cov[(2, 18)] - u.c_bn[(0, 1)] * cov[(2, 19)]
            - u.c_bn[(0, 2)] * cov[(2, 20)];
        pht[(2, 1)] = _t30 * cov[(2, 4)] + _t31 * cov[(2, 3)] + _t32 * cov[(2, 5)]
            - _t33 * cov[(2, 6)] - _t34 * cov[(2, 7)] - _t35 * cov[(2, 8)]
            - u.c_bn[(1, 0)] * cov[(2, 18)] - u.c_bn[(1, 1)] * cov[(2, 19)]
            - u.c_bn[(1, 2)] * cov[(2, 20)];
        pht[(2, 2)] = _t36 * cov[(2, 4)] + _t37 * cov[(2, 3)] + _t38 * cov[(2, 5)]
            - _t39 * cov[(2, 6)] - _t40 * cov[(2, 7)] - _t41 * cov[(2, 8)]
            - u.c_bn[(2, 0)] * cov[(2, 18)] - u.c_bn[(2, 1)] * cov[(2, 19)]
            - u.c_bn[(2, 2)] * cov[(2, 20)];
        pht[(3, 0)] = _t42;
        pht[(3, 1)] = _t43;
        pht[(3, 2)] = _t44;
        pht[(4, 0)] = _t45;
        pht[(4, 1)] = _t46;
        pht[(4, 2)] = _t47;
        pht[(5, 0)] = _t48;
        pht[(5, 1)] = _t49;
        pht[(5, 2)] = _t50;
        pht[(6, 0)] = _t51;
        pht[(6, 1)] = _t52;
        pht[(6, 2)] = _t53;
        pht[(7, 0)] = _t54;
        pht[(7, 1)] = _t55;
        pht[(7, 2)] = _t56;
        pht[(8, 0)] = _t57;
        pht[(8, 1)] = _t58;
        pht[(8, 2)] = _t59;
        pht[(9, 0)] = _t15 * cov[(4, 9)] + _t16 * cov[(3, 9)] + _t17 * cov[(5, 9)]
            - _t21 * cov[(6, 9)] - _t25 * cov[(7, 9)] - _t29 * cov[(8, 9)]
            - u.c_bn[(0, 0)] * cov[(9, 18)] - u.c_bn[(0, 1)] * cov[(9, 19)]
            - u.c_bn[(0, 2)] * cov[(9, 20)];
        pht[(9, 1)] = _t30 * cov[(4, 9)] + _t31 * cov[(3, 9)] + _t32 * cov[(5, 9)]
            - _t33 * cov[(6, 9)] - _t34 * cov[(7, 9)] - _t35 * cov[(8, 9)]
            - u.c_bn[(1, 0)] * cov[(9, 18)] - u.c_bn[(1, 1)] * cov[(9, 19)]
            - u.c_bn[(1, 2)] * cov[(9, 20)];
        pht[(9, 2)] = _t36 * cov[(4, 9)] + _t37 * cov[(3, 9)] + _t38 * cov[(5, 9)]
            - _t39 * cov[(6, 9)] - _t40 * cov[(7, 9)] - _t41 * cov[(8, 9)]
            - u.c_bn[(2, 0)] * cov[(9, 18)] - u.c_bn[(2, 1)] * cov[(9, 19)]
            - u.c_bn[(2, 2)] * cov[(9, 20)];
        pht[(10, 0)] = _t15 * cov[(4, 10)] + _t16 * cov[(3, 10)] + _t17 * cov[(5, 10)]
            - _t21 * cov[(6, 10)] - _t25 * cov[(7, 10)] - _t29 * cov[(8, 10)]
            - u.c_bn[(0, 0)] * cov[(10, 18)] - u.c_bn[(0, 1)] * cov[(10, 19)]
            - u.c_bn[(0, 2)] * cov[(10, 20)];
        pht[(10, 1)] = _t30 * cov[(4, 10)] + _t31 * cov[(3, 10)] + _t32 * cov[(5, 10)]
            - _t33 * cov[(6, 10)] - _t34 * cov[(7, 10)] - _t35 * cov[(8, 10)]
            - u.c_bn[(1, 0)] * cov[(10, 18)] - u.c_bn[(1, 1)] * cov[(10, 19)]
            - u.c_bn[(1, 2)] * cov[(10, 20)];
        pht[(10, 2)] = _t36 * cov[(4, 10)] + _t37 * cov[(3, 10)] + _t38 * cov[(5, 10)]
            - _t39 * cov[(6, 10)] - _t40 * cov[(7, 10)] - _t41 * cov[(8, 10)]
            - u.c_bn[(2, 0)] * cov[(10, 18)] - u.c_bn[(2, 1)] * cov[(10, 19)]
            - u.c_bn[(2, 2)] * cov[(10, 20)];
        pht[(11, 0)] = _t15 * cov[(4, 11)] + _t16 * cov[(3, 11)] + _t17 * cov[(5, 11)]
            - _t21 * cov[(6, 11)] - _t25 * cov[(7, 11)] - _t29 * cov[(8, 11)]
            - u.c_bn[(0, 0)] * cov[(11, 18)] - u.c_bn[(0, 1)] * cov[(11, 19)]
            - u.c_bn[(0, 2)] * cov[(11, 20)];
        pht[(11, 1)] = _t30 * cov[(4, 11)] + _t31 * cov[(3, 11)] + _t32 * cov[(5, 11)]
            - _t33 * cov[(6, 11)] - _t34 * cov[(7, 11)] - _t35 * cov[(8, 11)]
            - u.c_bn[(1, 0)] * cov[(11, 18)] - u.c_bn[(1, 1)] * cov[(11, 19)]
            - u.c_bn[(1, 2)] * cov[(11, 20)];
        pht[(11, 2)] = _t36 * cov[(4, 11)] + _t37 * cov[(3, 11)] + _t38 * cov[(5, 11)]
            - _t39 * cov[(6, 11)] - _t40 * cov[(7, 11)] - _t41 * cov[(8, 11)]
            - u.c_bn[(2, 0)] * cov[(11, 18)] - u.c_bn[(2, 1)] * cov[(11, 19)]
            - u.c_bn[(2, 2)] * cov[(11, 20)];
        pht[(12, 0)] = _t15 * cov[(4, 12)] + _t16 * cov[(3, 12)] + _t17 * cov[(5, 12)]
            - _t21 * cov[(6, 12)] - _t25 * cov[(7, 12)] - _t29 * cov[(8, 12)]
            - u.c_bn[(0, 0)] * cov[(12, 18)] - u.c_bn[(0, 1)] * cov[(12, 19)]
            - u.c_bn[(0, 2)] * cov[(12, 20)];
        pht[(12, 1)] = _t30 * cov[(4, 12)] + _t31 * cov[(3, 12)] + _t32 * cov[(5, 12)]
            - _t33 * cov[(6, 12)] - _t34 * cov[(7, 12)] - _t35 * cov[(8, 12)]
            - u.c_bn[(1, 0)] * cov[(12, 18)] - u.c_bn[(1, 1)] * cov[(12, 19)]
            - u.c_bn[(1, 2)] * cov[(12, 20)];
        pht[(12, 2)] = _t36 * cov[(4, 12)] + _t37 * cov[(3, 12)] + _t38 * cov[(5, 12)]
            - _t39 * cov[(6, 12)] - _t40 * cov[(7, 12)] - _t41 * cov[(8, 12)]
            - u.c_bn[(2, 0)] * cov[(12, 18)] - u.c_bn[(2, 1)] * cov[(12, 19)]
            - u.c_bn[(2, 2)] * cov[(12, 20)];
        pht[(13, 0)] = _t15 * cov[(4, 13)] + _t16 * cov[(3, 13)] + _t17 * cov[(5, 13)]
            - _t21 * cov[(6, 13)] - _t25 * cov[(7, 13)] - _t29 * cov[(8, 13)]
            - u.c_bn[(0, 0)] * cov[(13, 18)] - u.c_bn[(0, 1)] * cov[(13, 19)]
            - u.c_bn[(0, 2)] * cov[(13, 20)];
        pht[(13, 1)] = _t30 * cov[(4, 13)] + _t31 * cov[(3, 13)] + _t32 * cov[(5, 13)]
            - _t33 * cov[(6, 13)] - _t34 * cov[(7, 13)] - _t35 * cov[(8, 13)]
            - u.c_bn[(1, 0)] * cov[(13, 18)] - u.c_bn[(1, 1)] * cov[(13, 19)]
            - u.c_bn[(1, 2)] * cov[(13, 20)];
        pht[(13, 2)] = _t36 * cov[(4, 13)] + _t37 * cov[(3, 13)] + _t38 * cov[(5, 13)]
            - _t39 * cov[(6, 13)] - _t40 * cov[(7, 13)] - _t41 * cov[(8, 13)]
            - u.c_bn[(2, 0)] * cov[(13, 18)] - u.c_bn[(2, 1)] * cov[(13, 19)]
            - u.c_bn[(2, 2)] * cov[(13, 20)];
        pht[(14, 0)] = _t15 * cov[(4, 14)] + _t16 * cov[(3, 14)] + _t17 * cov[(5, 14)]
            - _t21 * cov[(6, 14)] - _t25 * cov[(7, 14)] - _t29 * cov[(8, 14)]
            - u.c_bn[(0, 0)] * cov[(14, 18)] - u.c_bn[(0, 1)] * cov[(14, 19)]
            - u.c_bn[(0, 2)] * cov[(14, 20)];
        pht[(14, 1)] = _t30 * cov[(4, 14)] + _t31 * cov[(3, 14)] + _t32 * cov[(5, 14)]
            - _t33 * cov[(6, 14)] - _t34 * cov[(7, 14)] - _t35 * cov[(8, 14)]
            - u.c_bn[(1, 0)] * cov[(14, 18)] - u.c_bn[(1, 1)] * cov[(14, 19)]
            - u.c_bn[(1, 2)] * cov[(14, 20)];
        pht[(14, 2)] = _t36 * cov[(4, 14)] + _t37 * cov[(3, 14)] + _t38 * cov[(5, 14)]
            - _t39 * cov[(6, 14)] - _t40 * cov[(7, 14)] - _t41 * cov[(8, 14)]
            - u.c_bn[(2, 0)] * cov[(14, 18)] - u.c_bn[(2, 1)] * cov[(14, 19)]
            - u.c_bn[(2, 2)] * cov[(14, 20)];
        pht[(15, 0)] = _t15 * cov[(4, 15)] + _t16 * cov[(3, 15)] + _t17 * cov[(5, 15)]
            - _t21 * cov[(6, 15)] - _t25 * cov[(7, 15)] - _t29 * cov[(8, 15)]
            - u.c_bn[(0, 0)] * cov[(15, 18)] - u.c_bn[(0, 1)] * cov[(15, 19)]
            - u.c_bn[(0, 2)] * cov[(15, 20)];
        pht[(15, 1)] = _t30 * cov[(4, 15)] + _t31 * cov[(3, 15)] + _t32 * cov[(5, 15)]
            - _t33 * cov[(6, 15)] - _t34 * cov[(7, 15)] - _t35 * cov[(8, 15)]
            - u.c_bn[(1, 0)] * cov[(15, 18)] - u.c_bn[(1, 1)] * cov[(15, 19)]
            - u.c_bn[(1, 2)] * cov[(15, 20)];
        pht[(15, 2)] = _t36 * cov[(4, 15)] + _t37 * cov[(3, 15)] + _t38 * cov[(5, 15)]
            - _t39 * cov[(6, 15)] - _t40 * cov[(7, 15)] - _t41 * cov[(8, 15)]
            - u.c_bn[(2, 0)] * cov[(15, 18)] - u.c_bn[(2, 1)] * cov[(15, 19)]
            - u.c_bn[(2, 2)] * cov[(15, 20)];
        pht[(16, 0)] = _t15 * cov[(4, 16)] + _t16 * cov[(3, 16)] + _t17 * cov[(5, 16)]
            - _t21 * cov[(6, 16)] - _t25 * cov[(7, 16)] - _t29 * cov[(8, 16)]
            - u.c_bn[(0, 0)] * cov[(16, 18)] - u.c_bn[(0, 1)] * cov[(16, 19)]
            - u.c_bn[(0, 2)] * cov[(16, 20)];
        pht[(16, 1)] = _t30 * cov[(4, 16)] + _t31 * cov[(3, 16)] + _t32 * cov[(5, 16)]
            - _t33 * cov[(6, 16)] - _t34 * cov[(7, 16)] - _t35 * cov[(8, 16)]
            - u.c_bn[(1, 0)] * cov[(16, 18)] - u.c_bn[(1, 1)] * cov[(16, 19)]
            - u.c_bn[(1, 2)] * cov[(16, 20)];
        pht[(16, 2)] = _t36 * cov[(4, 16)] + _t37 * cov[(3, 16)] + _t38 * cov[(5, 16)]
            - _t39 * cov[(6, 16)] - _t40 * cov[(7, 16)] - _t41 * cov[(8, 16)]
            - u.c_bn[(2, 0)] * cov[(16, 18)] - u.c_bn[(2, 1)] * cov[(16, 19)]
            - u.c_bn[(2, 2)] * cov[(16, 20)];
        pht[(17, 0)] = _t15 * cov[(4, 17)] + _t16 * cov[(3, 17)] + _t17 * cov[(5, 17)]
            - _t21 * cov[(6, 17)] - _t25 * cov[(7, 17)] - _t29 * cov[(8, 17)]
            - u.c_bn[(0, 0)] * cov[(17, 18)] - u.c_bn[(0, 1)] * cov[(17, 19)]
            - u.c_bn[(0, 2)] * cov[(17, 20)];
        pht[(17, 1)] = _t30 * cov[(4, 17)] + _t31 * cov[(3, 17)] + _t32 * cov[(5, 17)]
            - _t33 * cov[(6, 17)] - _t34 * cov[(7, 17)] - _t35 * cov[(8, 17)]
            - u.c_bn[(1, 0)] * cov[(17, 18)] - u.c_bn[(1, 1)] * cov[(17, 19)]
            - u.c_bn[(1, 2)] * cov[(17, 20)];
        pht[(17, 2)] = _t36 * cov[(4, 17)] + _t37 * cov[(3, 17)] + _t38 * cov[(5, 17)]
            - _t39 * cov[(6, 17)] - _t40 * cov[(7, 17)] - _t41 * cov[(8, 17)]
            - u.c_bn[(2, 0)] * cov[(17, 18)] - u.c_bn[(2, 1)] * cov[(17, 19)]
            - u.c_bn[(2, 2)] * cov[(17, 20)];
        pht[(18, 0)] = _t60;
        pht[(18, 1)] = _t61;
        pht[(18, 2)] = _t62;
        pht[(19, 0)] = _t63;
        pht[(19, 1)] = _t64;
        pht[(19, 2)] = _t65;
        pht[(20, 0)] = _t66;
        pht[(20, 1)] = _t67;
        pht[(20, 2)] = _t68;
        pht[(21, 0)] = _t15 * cov[(4, 21)] + _t16 * cov[(3, 21)] + _t17 * cov[(5, 21)]
            - _t21 * cov[(6, 21)] - _t25 * cov[(7, 21)] - _t29 * cov[(8, 21)]
            - u.c_bn[(0, 0)] * cov[(18, 21)] - u.c_bn[(0, 1)] * cov[(19, 21)]
            - u.c_bn[(0, 2)] * cov[(20, 21)];
        pht[(21, 1)] = _t30 * cov[(4, 21)] + _t31 * cov[(3, 21)] + _t32 * cov[(5, 21)]
            - _t33 * cov[(6, 21)] - _t34 * cov[(7, 21)] - _t35 * cov[(8, 21)]
            - u.c_bn[(1, 0)] * cov[(18, 21)] - u.c_bn[(1, 1)] * cov[(19, 21)]
            - u.c_bn[(1, 2)] * cov[(20, 21)];
        pht[(21, 2)] = _t36 * cov[(4, 21)] + _t37 * cov[(3, 21)] + _t38 * cov[(5, 21)]
            - _t39 * cov[(6, 21)] - _t40 * cov[(7, 21)] - _t41 * cov[(8, 21)]
            - u.c_bn[(2, 0)] * cov[(18, 21)] - u.c_bn[(2, 1)] * cov[(19, 21)]
            - u.c_bn[(2, 2)] * cov[(20, 21)];
        pht[(22, 0)] = _t15 * cov[(4, 22)] + _t16 * cov[(3, 22)] + _t17 * cov[(5, 22)]
            - _t21 * cov[(6, 22)] - _t25 * cov[(7, 22)] - _t29 * cov[(8, 22)]
            - u.c_bn[(0, 0)] * cov[(18, 22)] - u.c_bn[(0, 1)] * cov[(19, 22)]
            - u.c_bn[(0, 2)] * cov[(20, 22)];
        pht[(22, 1)] = _t30 * cov[(4, 22)] + _t31 * cov[(3, 22)] + _t32 * cov[(5, 22)]
            - _t33 * cov[(6, 22)] - _t34 * cov[(7, 22)] - _t35 * cov[(8, 22)]
            - u.c_bn[(1, 0)] * cov[(18, 22)] - u.c_bn[(1, 1)] * cov[(19, 22)]
            - u.c_bn[(1, 2)] * cov[(20, 22)];
        pht[(22, 2)] = _t36 * cov[(4, 22)] + _t37 * cov[(3, 22)] + _t38 * cov[(5, 22)]
            - _t39 * cov[(6, 22)] - _t40 * cov[(7, 22)] - _t41 * cov[(8, 22)]
            - u.c_bn[(2, 0)] * cov[(18, 22)] - u.c_bn[(2, 1)] * cov[(19, 22)]
            - u.c_bn[(2, 2)] * cov[(20, 22)];
        pht[(23, 0)] = _t15 * cov[(4, 23)] + _t16 * cov[(3, 23)] + _t17 * cov[(5, 23)]
            - _t21 * cov[(6, 23)] - _t25 * cov[(7, 23)] - _t29 * cov[(8, 23)]
            - u.c_bn[(0, 0)] * cov[(18, 23)] - u.c_bn[(0, 1)] * cov[(19, 23)]
            - u.c_bn[(0, 2)] * cov[(20, 23)];
        pht[(23, 1)] = _t30 * cov[(4, 23)] + _t31 * cov[(3, 23)] + _t32 * cov[(5, 23)]
            - _t33 * cov[(6, 23)] - _t34 * cov[(7, 23)] - _t35 * cov[(8, 23)]
            - u.c_bn[(1, 0)] * cov[(18, 23)] - u.c_bn[(1, 1)] * cov[(19, 23)]
            - u.c_bn[(1, 2)] * cov[(20, 23)];
        pht[(23, 2)] = _t36 * cov[(4, 23)] + _t37 * cov[(3, 23)] + _t38 * cov[(5, 23)]
            - _t39 * cov[(6, 23)] - _t40 * cov[(7, 23)] - _t41 * cov[(8, 23)]
            - u.c_bn[(2, 0)] * cov[(18, 23)] - u.c_bn[(2, 1)] * cov[(19, 23)]
            - u.c_bn[(2, 2)] * cov[(20, 23)];
        pht[(24, 0)] = _t15 * cov[(4, 24)] + _t16 * cov[(3, 24)] + _t17 * cov[(5, 24)]
            - _t21 * cov[(6, 24)] - _t25 * cov[(7, 24)] - _t29 * cov[(8, 24)]
            - u.c_bn[(0, 0)] * cov[(18, 24)] - u.c_bn[(0, 1)] * cov[(19, 24)]
            - u.c_bn[(0, 2)] * cov[(20, 24)];
        pht[(24, 1)] = _t30 * cov[(4, 24)] + _t31 * cov[(3, 24)] + _t32 * cov[(5, 24)]
            - _t33 * cov[(6, 24)] - _t34 * cov[(7, 24)] - _t35 * cov[(8, 24)]
            - u.c_bn[(1, 0)] * cov[(18, 24)] - u.c_bn[(1, 1)] * cov[(19, 24)]
            - u.c_bn[(1, 2)] * cov[(20, 24)];
        pht[(24, 2)] = _t36 * cov[(4, 24)] + _t37 * cov[(3, 24)] + _t38 * cov[(5, 24)]
            - _t39 * cov[(6, 24)] - _t40 * cov[(7, 24)] - _t41 * cov[(8, 24)]
            - u.c_bn[(2, 0)] * cov[(18, 24)] - u.c_bn[(2, 1)] * cov[(19, 24)]
            - u.c_bn[(2, 2)] * cov[(20, 24)];
        s[(0, 0)] = _t15 * _t45 + _t16 * _t42 + _t17 * _t48 - _t21 * _t51 - _t25 * _t54
            - _t29 * _t57 - u.c_bn[(0, 0)] * _t60 - u.c_bn[(0, 1)] * _t63
            - u.c_bn[(0, 2)] * _t66;
        s[(0, 1)] = _t15 * _t46 + _t16 * _t43 + _t17 * _t49 - _t21 * _t52 - _t25 * _t55
            - _t29 * _t58 - u.c_bn[(0, 0)] * _t61 - u.c_bn[(0, 1)] * _t64
            - u.c_bn[(0, 2)] * _t67;
        s[(0, 2)] = _t15 * _t47 + _t16 * _t44 + _t17 * _t50 - _t21 * _t53 - _t25 * _t56
            - _t29 * _t59 - u.c_bn[(0, 0)] * _t62 - u.c_bn[(0, 1)] * _t65
            - u.c_bn[(0, 2)] * _t68;
        s[(1, 1)] = _t30 * _t46 + _t31 * _t43 + _t32 * _t49 - _t33 * _t52 - _t34 * _t55
            - _t35 * _t58 - u.c_bn[(1, 0)] * _t61 - u.c_bn[(1, 1)] * _t64
            - u.c_bn[(1, 2)] * _t67;
        s[(1, 2)] = _t30 * _t47 + _t31 * _t44 + _t32 * _t50 - _t33 * _t53 - _t34 * _t56
            - _t35 * _t59 - u.c_bn[(1, 0)] * _t62 - u.c_bn[(1, 1)] * _t65
            - u.c_bn[(1, 2)] * _t68;
        s[(2, 2)] = _t36 * _t47 + _t37 * _t44 + _t38 * _t50 - _t39 * _t53 - _t40 * _t56
            - _t41 * _t59 - u.c_bn[(2, 0)] * _t62 - u.c_bn[(2, 1)] * _t65
            - u.c_bn[(2, 2)] * _t68;
        for i in 0..3 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// Magnetic compass, the paper's small-angle form `-phi_D - b_psi` (eq. 12).
///
///Sensor `CompassSmallAngle` of [`Sdins25`]: 1 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25CompassSmallAngle;
#[allow(clippy::possible_missing_comma)]
impl Sdins25CompassSmallAngle {
    /// Number of measurement components.
    pub const M: usize = 1;
    /// The declared sensor name.
    pub const NAME: &'static str = "CompassSmallAngle";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 2;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 25] = [
        true, false, true, true, true, true, true, true, true, true, true, true, true,
        true, true, false, false, false, false, false, false, true, false, false, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 2;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 53;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<25, 1, f64> for Sdins25CompassSmallAngle {
    type Model = Sdins25;
    type Aux = ();
    const NAME: &'static str = "CompassSmallAngle";
    const ANGLES: [bool; 1] = [true];
    const JACOBIAN_SPARSITY: [[bool; 25]; 1] = [
        [
            false, false, false, false, false, false, false, false, true, false, false,
            false, false, false, false, false, false, false, false, false, false, true,
            false, false, false,
        ],
    ];
    const OPS_INNOVATION_TERMS: usize = 53;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 2*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 1> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        out[0] = -(x[21] + x[8]);
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 1, 25> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 25>::zeros();
        out[(0, 8)] = -1.0;
        out[(0, 21)] = -1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 53*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 25, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 1, 1>,
    ) {
        let _t0 = cov[(8, 21)] + cov[(8, 8)];
        let _t1 = cov[(8, 21)] + cov[(21, 21)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 1>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::zeros();
        h[0] = -(x[21] + x[8]);
        pht[(0, 0)] = -(cov[(0, 21)] + cov[(0, 8)]);
        pht[(1, 0)] = -(cov[(1, 21)] + cov[(1, 8)]);
        pht[(2, 0)] = -(cov[(2, 21)] + cov[(2, 8)]);
        pht[(3, 0)] = -(cov[(3, 21)] + cov[(3, 8)]);
        pht[(4, 0)] = -(cov[(4, 21)] + cov[(4, 8)]);
        pht[(5, 0)] = -(cov[(5, 21)] + cov[(5, 8)]);
        pht[(6, 0)] = -(cov[(6, 21)] + cov[(6, 8)]);
        pht[(7, 0)] = -(cov[(7, 21)] + cov[(7, 8)]);
        pht[(8, 0)] = -_t0;
        pht[(9, 0)] = -(cov[(9, 21)] + cov[(8, 9)]);
        pht[(10, 0)] = -(cov[(10, 21)] + cov[(8, 10)]);
        pht[(11, 0)] = -(cov[(11, 21)] + cov[(8, 11)]);
        pht[(12, 0)] = -(cov[(12, 21)] + cov[(8, 12)]);
        pht[(13, 0)] = -(cov[(13, 21)] + cov[(8, 13)]);
        pht[(14, 0)] = -(cov[(14, 21)] + cov[(8, 14)]);
        pht[(15, 0)] = -(cov[(15, 21)] + cov[(8, 15)]);
        pht[(16, 0)] = -(cov[(16, 21)] + cov[(8, 16)]);
        pht[(17, 0)] = -(cov[(17, 21)] + cov[(8, 17)]);
        pht[(18, 0)] = -(cov[(18, 21)] + cov[(8, 18)]);
        pht[(19, 0)] = -(cov[(19, 21)] + cov[(8, 19)]);
        pht[(20, 0)] = -(cov[(20, 21)] + cov[(8, 20)]);
        pht[(21, 0)] = -_t1;
        pht[(22, 0)] = -(cov[(21, 22)] + cov[(8, 22)]);
        pht[(23, 0)] = -(cov[(21, 23)] + cov[(8, 23)]);
        pht[(24, 0)] = -(cov[(21, 24)] + cov[(8, 24)]);
        s[(0, 0)] = _t0 + _t1;
        for i in 0..1 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// Magnetic compass, exact yaw of the perturbed attitude: `psi(C^) - psi(C) - b_psi`.
/// Equals the small-angle form when level; differs when the vehicle pitches.
///
///Sensor `Compass` of [`Sdins25`]: 1 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25Compass;
#[allow(clippy::possible_missing_comma)]
impl Sdins25Compass {
    /// Number of measurement components.
    pub const M: usize = 1;
    /// The declared sensor name.
    pub const NAME: &'static str = "Compass";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 3;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 25] = [
        true, false, true, true, true, true, true, true, true, true, true, true, true,
        true, true, false, false, false, false, false, false, true, false, false, false,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 12;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 21;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 181;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<25, 1, f64> for Sdins25Compass {
    type Model = Sdins25;
    type Aux = ();
    const NAME: &'static str = "Compass";
    const ANGLES: [bool; 1] = [true];
    const JACOBIAN_SPARSITY: [[bool; 25]; 1] = [
        [
            false, false, false, false, false, false, true, true, true, false, false,
            false, false, false, false, false, false, false, false, false, false, true,
            false, false, false,
        ],
    ];
    const OPS_INNOVATION_TERMS: usize = 181;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 12*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 1> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        out[0] = ::nav_runtime::math::atan2(u.c_bn[(1, 0)], u.c_bn[(0, 0)])
            - ::nav_runtime::math::atan2(
                u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]),
                u.c_bn[(2, 0)] * x[7] - u.c_bn[(1, 0)] * x[8] + u.c_bn[(0, 0)],
            ) - x[21];
        out
    }
    /**`H = dh/dx`.

Total ops: 21*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 1, 25> {
        let _t0 = u.c_bn[(0, 0)] * x[8] - x[6] * u.c_bn[(2, 0)] + u.c_bn[(1, 0)];
        let _t1 = u.c_bn[(0, 0)] + (u.c_bn[(2, 0)] * x[7] - x[8] * u.c_bn[(1, 0)]);
        let _t2 = 1.0 / (_t0 * _t0 + _t1 * _t1);
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 25>::zeros();
        out[(0, 6)] = _t2 * (u.c_bn[(2, 0)] * _t1);
        out[(0, 7)] = _t2 * (u.c_bn[(2, 0)] * _t0);
        out[(0, 8)] = -(_t2 * (u.c_bn[(1, 0)] * _t0 + u.c_bn[(0, 0)] * _t1));
        out[(0, 21)] = -1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 181*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 25, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 1, 1>,
    ) {
        let _t0 = u.c_bn[(1, 0)] + (x[8] * u.c_bn[(0, 0)] - u.c_bn[(2, 0)] * x[6]);
        let _t1 = u.c_bn[(2, 0)] * x[7] - u.c_bn[(1, 0)] * x[8] + u.c_bn[(0, 0)];
        let _t2 = 1.0 / (_t0 * _t0 + _t1 * _t1);
        let _t3 = _t2 * (u.c_bn[(2, 0)] * _t0);
        let _t4 = _t2 * (u.c_bn[(2, 0)] * _t1);
        let _t5 = _t2 * (u.c_bn[(1, 0)] * _t0 + u.c_bn[(0, 0)] * _t1);
        let _t6 = _t3 * cov[(6, 7)] + _t4 * cov[(6, 6)] - _t5 * cov[(6, 8)]
            - cov[(6, 21)];
        let _t7 = _t3 * cov[(7, 7)] + _t4 * cov[(6, 7)] - _t5 * cov[(7, 8)]
            - cov[(7, 21)];
        let _t8 = _t3 * cov[(7, 8)] + _t4 * cov[(6, 8)] - _t5 * cov[(8, 8)]
            - cov[(8, 21)];
        let _t9 = _t3 * cov[(7, 21)] + _t4 * cov[(6, 21)] - _t5 * cov[(8, 21)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 1>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::zeros();
        h[0] = ::nav_runtime::math::atan2(u.c_bn[(1, 0)], u.c_bn[(0, 0)])
            - ::nav_runtime::math::atan2(_t0, _t1) - x[21];
        pht[(0, 0)] = _t3 * cov[(0, 7)] + _t4 * cov[(0, 6)] - _t5 * cov[(0, 8)]
            - cov[(0, 21)];
        pht[(1, 0)] = _t3 * cov[(1, 7)] + _t4 * cov[(1, 6)] - _t5 * cov[(1, 8)]
            - cov[(1, 21)];
        pht[(2, 0)] = _t3 * cov[(2, 7)] + _t4 * cov[(2, 6)] - _t5 * cov[(2, 8)]
            - cov[(2, 21)];
        pht[(3, 0)] = _t3 * cov[(3, 7)] + _t4 * cov[(3, 6)] - _t5 * cov[(3, 8)]
            - cov[(3, 21)];
        pht[(4, 0)] = _t3 * cov[(4, 7)] + _t4 * cov[(4, 6)] - _t5 * cov[(4, 8)]
            - cov[(4, 21)];
        pht[(5, 0)] = _t3 * cov[(5, 7)] + _t4 * cov[(5, 6)] - _t5 * cov[(5, 8)]
            - cov[(5, 21)];
        pht[(6, 0)] = _t6;
        pht[(7, 0)] = _t7;
        pht[(8, 0)] = _t8;
        pht[(9, 0)] = _t3 * cov[(7, 9)] + _t4 * cov[(6, 9)] - _t5 * cov[(8, 9)]
            - cov[(9, 21)];
        pht[(10, 0)] = _t3 * cov[(7, 10)] + _t4 * cov[(6, 10)] - _t5 * cov[(8, 10)]
            - cov[(10, 21)];
        pht[(11, 0)] = _t3 * cov[(7, 11)] + _t4 * cov[(6, 11)] - _t5 * cov[(8, 11)]
            - cov[(11, 21)];
        pht[(12, 0)] = _t3 * cov[(7, 12)] + _t4 * cov[(6, 12)] - _t5 * cov[(8, 12)]
            - cov[(12, 21)];
        pht[(13, 0)] = _t3 * cov[(7, 13)] + _t4 * cov[(6, 13)] - _t5 * cov[(8, 13)]
            - cov[(13, 21)];
        pht[(14, 0)] = _t3 * cov[(7, 14)] + _t4 * cov[(6, 14)] - _t5 * cov[(8, 14)]
            - cov[(14, 21)];
        pht[(15, 0)] = _t3 * cov[(7, 15)] + _t4 * cov[(6, 15)] - _t5 * cov[(8, 15)]
            - cov[(15, 21)];
        pht[(16, 0)] = _t3 * cov[(7, 16)] + _t4 * cov[(6, 16)] - _t5 * cov[(8, 16)]
            - cov[(16, 21)];
        pht[(17, 0)] = _t3 * cov[(7, 17)] + _t4 * cov[(6, 17)] - _t5 * cov[(8, 17)]
            - cov[(17, 21)];
        pht[(18, 0)] = _t3 * cov[(7, 18)] + _t4 * cov[(6, 18)] - _t5 * cov[(8, 18)]
            - cov[(18, 21)];
        pht[(19, 0)] = _t3 * cov[(7, 19)] + _t4 * cov[(6, 19)] - _t5 * cov[(8, 19)]
            - cov[(19, 21)];
        pht[(20, 0)] = _t3 * cov[(7, 20)] + _t4 * cov[(6, 20)] - _t5 * cov[(8, 20)]
            - cov[(20, 21)];
        pht[(21, 0)] = _t9 - cov[(21, 21)];
        pht[(22, 0)] = _t3 * cov[(7, 22)] + _t4 * cov[(6, 22)] - _t5 * cov[(8, 22)]
            - cov[(21, 22)];
        pht[(23, 0)] = _t3 * cov[(7, 23)] + _t4 * cov[(6, 23)] - _t5 * cov[(8, 23)]
            - cov[(21, 23)];
        pht[(24, 0)] = _t3 * cov[(7, 24)] + _t4 * cov[(6, 24)] - _t5 * cov[(8, 24)]
            - cov[(21, 24)];
        s[(0, 0)] = _t3 * _t7 + _t4 * _t6 - _t5 * _t8 + (cov[(21, 21)] - _t9);
        for i in 0..1 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
/// USBL horizontal fix, INS minus fix in metres N/E (eq. 17):
/// `[(R_m+h) dL, (R_n+h) cos L dl] - b_usbl - ([theta x] r)_NE`.
///
///Sensor `Usbl` of [`Sdins25`]: 2 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Sdins25Usbl;
#[allow(clippy::possible_missing_comma)]
impl Sdins25Usbl {
    /// Number of measurement components.
    pub const M: usize = 2;
    /// The declared sensor name.
    pub const NAME: &'static str = "Usbl";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 4;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 25] = [
        true, true, true, true, true, true, true, true, true, true, true, true, true,
        true, true, true, true, false, false, false, false, false, true, true, true,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 24;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 14;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 343;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<25, 2, f64> for Sdins25Usbl {
    type Model = Sdins25;
    type Aux = Sdins25UsblAux;
    const NAME: &'static str = "Usbl";
    const ANGLES: [bool; 2] = [false, false];
    const JACOBIAN_SPARSITY: [[bool; 25]; 2] = [
        [
            true, false, false, false, false, false, false, false, false, false, false,
            false, false, false, false, true, false, false, false, false, false, false,
            false, true, true,
        ],
        [
            false, true, false, false, false, false, false, false, false, false, false,
            false, false, false, false, false, true, false, false, false, false, false,
            true, false, true,
        ],
    ];
    const OPS_INNOVATION_TERMS: usize = 343;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 24*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &Sdins25UsblAux,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 2> {
        let (_t0, _t3) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (_t0 * 0.0066943799901413165);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        out[0] = (6335439.3272928195 / (_t1 * _t2) + u.height) * x[0] - x[15]
            - (aux.relative_position[2] * x[23] - aux.relative_position[1] * x[24]);
        out[1] = (u.height + 6378137.0 / _t2) * _t3 * x[1] - x[16]
            - (x[24] * aux.relative_position[0] - aux.relative_position[2] * x[22]);
        out
    }
    /**`H = dh/dx`.

Total ops: 14*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &Sdins25UsblAux,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 2, 25> {
        let (_t0, _t3) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (_t0 * 0.0066943799901413165);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 25>::zeros();
        out[(0, 0)] = 6335439.3272928195 / (_t1 * _t2) + u.height;
        out[(0, 15)] = -1.0;
        out[(0, 23)] = -aux.relative_position[2];
        out[(0, 24)] = aux.relative_position[1];
        out[(1, 1)] = (u.height + 6378137.0 / _t2) * _t3;
        out[(1, 16)] = -1.0;
        out[(1, 22)] = aux.relative_position[2];
        out[(1, 24)] = -aux.relative_position[0];
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 343*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 25, 25>,
        x: &::nav_runtime::nalgebra::SVector<f64, 25>,
        u: &Sdins25Input,
        p: &Sdins25Params,
        aux: &Sdins25UsblAux,
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 25, 2>,
        ::nav_runtime::nalgebra::SMatrix<f64, 2, 2>,
    ) {
        let (_t0, _t4) = ::nav_runtime::math::sin_cos(u.latitude);
        let _t1 = 1.0 - _t0 * (_t0 * 0.0066943799901413165);
        let _t2 = ::nav_runtime::math::sqrt(_t1);
        let _t3 = 6335439.3272928195 / (_t1 * _t2) + u.height;
        let _t5 = (u.height + 6378137.0 / _t2) * _t4;
        let _t6 = _t3 * cov[(0, 0)] - cov[(0, 15)]
            - aux.relative_position[2] * cov[(0, 23)]
            + aux.relative_position[1] * cov[(0, 24)];
        let _t7 = _t5 * cov[(0, 1)] - cov[(0, 16)]
            + aux.relative_position[2] * cov[(0, 22)]
            - aux.relative_position[0] * cov[(0, 24)];
        let _t8 = _t5 * cov[(1, 1)] - cov[(1, 16)]
            + aux.relative_position[2] * cov[(1, 22)]
            - aux.relative_position[0] * cov[(1, 24)];
        let _t9 = _t3 * cov[(0, 15)] - cov[(15, 15)]
            - aux.relative_position[2] * cov[(15, 23)]
            + aux.relative_position[1] * cov[(15, 24)];
        let _t10 = _t5 * cov[(1, 15)] - cov[(15, 16)]
            + aux.relative_position[2] * cov[(15, 22)];
        let _t11 = aux.relative_position[0] * cov[(15, 24)];
        let _t12 = _t5 * cov[(1, 16)] - cov[(16, 16)]
            + aux.relative_position[2] * cov[(16, 22)];
        let _t13 = aux.relative_position[0] * cov[(16, 24)];
        let _t14 = aux.relative_position[2] * cov[(22, 23)];
        let _t15 = _t5 * cov[(1, 22)] - cov[(16, 22)]
            + aux.relative_position[2] * cov[(22, 22)]
            - aux.relative_position[0] * cov[(22, 24)];
        let _t16 = _t3 * cov[(0, 23)] - cov[(15, 23)]
            - aux.relative_position[2] * cov[(23, 23)]
            + aux.relative_position[1] * cov[(23, 24)];
        let _t17 = _t14 + (_t5 * cov[(1, 23)] - cov[(16, 23)])
            - aux.relative_position[0] * cov[(23, 24)];
        let _t18 = _t3 * cov[(0, 24)] - cov[(15, 24)]
            - aux.relative_position[2] * cov[(23, 24)]
            + aux.relative_position[1] * cov[(24, 24)];
        let _t19 = _t5 * cov[(1, 24)] - cov[(16, 24)]
            + aux.relative_position[2] * cov[(22, 24)]
            - aux.relative_position[0] * cov[(24, 24)];
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 2>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 25, 2>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 2, 2>::zeros();
        h[0] = _t3 * x[0] - x[15]
            - (aux.relative_position[2] * x[23] - aux.relative_position[1] * x[24]);
        h[1] = _t5 * x[1] - x[16]
            - (x[24] * aux.relative_position[0] - aux.relative_position[2] * x[22]);
        pht[(0, 0)] = _t6;
        pht[(0, 1)] = _t7;
        pht[(1, 0)] = _t3 * cov[(0, 1)] - cov[(1, 15)]
            - aux.relative_position[2] * cov[(1, 23)]
            + aux.relative_position[1] * cov[(1, 24)];
        pht[(1, 1)] = _t8;
        pht[(2, 0)] = _t3 * cov[(0, 2)] - cov[(2, 15)]
            - aux.relative_position[2] * cov[(2, 23)]
            + aux.relative_position[1] * cov[(2, 24)];
        pht[(2, 1)] = _t5 * cov[(1, 2)] - cov[(2, 16)]
            + aux.relative_position[2] * cov[(2, 22)]
            - aux.relative_position[0] * cov[(2, 24)];
        pht[(3, 0)] = _t3 * cov[(0, 3)] - cov[(3, 15)]
            - aux.relative_position[2] * cov[(3, 23)]
            + aux.relative_position[1] * cov[(3, 24)];
        pht[(3, 1)] = _t5 * cov[(1, 3)] - cov[(3, 16)]
            + aux.relative_position[2] * cov[(3, 22)]
            - aux.relative_position[0] * cov[(3, 24)];
        pht[(4, 0)] = _t3 * cov[(0, 4)] - cov[(4, 15)]
            - aux.relative_position[2] * cov[(4, 23)]
            + aux.relative_position[1] * cov[(4, 24)];
        pht[(4, 1)] = _t5 * cov[(1, 4)] - cov[(4, 16)]
            + aux.relative_position[2] * cov[(4, 22)]
            - aux.relative_position[0] * cov[(4, 24)];
        pht[(5, 0)] = _t3 * cov[(0, 5)] - cov[(5, 15)]
            - aux.relative_position[2] * cov[(5, 23)]
            + aux.relative_position[1] * cov[(5, 24)];
        pht[(5, 1)] = _t5 * cov[(1, 5)] - cov[(5, 16)]
            + aux.relative_position[2] * cov[(5, 22)]
            - aux.relative_position[0] * cov[(5, 24)];
        pht[(6, 0)] = _t3 * cov[(0, 6)] - cov[(6, 15)]
            - aux.relative_position[2] * cov[(6, 23)]
            + aux.relative_position[1] * cov[(6, 24)];
        pht[(6, 1)] = _t5 * cov[(1, 6)] - cov[(6, 16)]
            + aux.relative_position[2] * cov[(6, 22)]
            - aux.relative_position[0] * cov[(6, 24)];
        pht[(7, 0)] = _t3 * cov[(0, 7)] - cov[(7, 15)]
            - aux.relative_position[2] * cov[(7, 23)]
            + aux.relative_position[1] * cov[(7, 24)];
        pht[(7, 1)] = _t5 * cov[(1, 7)] - cov[(7, 16)]
            + aux.relative_position[2] * cov[(7, 22)]
            - aux.relative_position[0] * cov[(7, 24)];
        pht[(8, 0)] = _t3 * cov[(0, 8)] - cov[(8, 15)]
            - aux.relative_position[2] * cov[(8, 23)]
            + aux.relative_position[1] * cov[(8, 24)];
        pht[(8, 1)] = _t5 * cov[(1, 8)] - cov[(8, 16)]
            + aux.relative_position[2] * cov[(8, 22)]
            - aux.relative_position[0] * cov[(8, 24)];
        pht[(9, 0)] = _t3 * cov[(0, 9)] - cov[(9, 15)]
            - aux.relative_position[2] * cov[(9, 23)]
            + aux.relative_position[1] * cov[(9, 24)];
        pht[(9, 1)] = _t5 * cov[(1, 9)] - cov[(9, 16)]
            + aux.relative_position[2] * cov[(9, 22)]
            - aux.relative_position[0] * cov[(9, 24)];
        pht[(10, 0)] = _t3 * cov[(0, 10)] - cov[(10, 15)]
            - aux.relative_position[2] * cov[(10, 23)]
            + aux.relative_position[1] * cov[(10, 24)];
        pht[(10, 1)] = _t5 * cov[(1, 10)] - cov[(10, 16)]
            + aux.relative_position[2] * cov[(10, 22)]
            - aux.relative_position[0] * cov[(10, 24)];
        pht[(11, 0)] = _t3 * cov[(0, 11)] - cov[(11, 15)]
            - aux.relative_position[2] * cov[(11, 23)]
            + aux.relative_position[1] * cov[(11, 24)];
        pht[(11, 1)] = _t5 * cov[(1, 11)] - cov[(11, 16)]
            + aux.relative_position[2] * cov[(11, 22)]
            - aux.relative_position[0] * cov[(11, 24)];
        pht[(12, 0)] = _t3 * cov[(0, 12)] - cov[(12, 15)]
            - aux.relative_position[2] * cov[(12, 23)]
            + aux.relative_position[1] * cov[(12, 24)];
        pht[(12, 1)] = _t5 * cov[(1, 12)] - cov[(12, 16)]
            + aux.relative_position[2] * cov[(12, 22)]
            - aux.relative_position[0] * cov[(12, 24)];
        pht[(13, 0)] = _t3 * cov[(0, 13)] - cov[(13, 15)]
            - aux.relative_position[2] * cov[(13, 23)]
            + aux.relative_position[1] * cov[(13, 24)];
        pht[(13, 1)] = _t5 * cov[(1, 13)] - cov[(13, 16)]
            + aux.relative_position[2] * cov[(13, 22)]
            - aux.relative_position[0] * cov[(13, 24)];
        pht[(14, 0)] = _t3 * cov[(0, 14)] - cov[(14, 15)]
            - aux.relative_position[2] * cov[(14, 23)]
            + aux.relative_position[1] * cov[(14, 24)];
        pht[(14, 1)] = _t5 * cov[(1, 14)] - cov[(14, 16)]
            + aux.relative_position[2] * cov[(14, 22)]
            - aux.relative_position[0] * cov[(14, 24)];
        pht[(15, 0)] = _t9;
        pht[(15, 1)] = _t10 - _t11;
        pht[(16, 0)] = _t3 * cov[(0, 16)] - cov[(15, 16)]
            - aux.relative_position[2] * cov[(16, 23)]
            + aux.relative_position[1] * cov[(16, 24)];
        pht[(16, 1)] = _t12 - _t13;
        pht[(17, 0)] = _t3 * cov[(0, 17)] - cov[(15, 17)]
            - aux.relative_position[2] * cov[(17, 23)]
            + aux.relative_position[1] * cov[(17, 24)];
        pht[(17, 1)] = _t5 * cov[(1, 17)] - cov[(16, 17)]
            + aux.relative_position[2] * cov[(17, 22)]
            - aux.relative_position[0] * cov[(17, 24)];
        pht[(18, 0)] = _t3 * cov[(0, 18)] - cov[(15, 18)]
            - aux.relative_position[2] * cov[(18, 23)]
            + aux.relative_position[1] * cov[(18, 24)];
        pht[(18, 1)] = _t5 * cov[(1, 18)] - cov[(16, 18)]
            + aux.relative_position[2] * cov[(18, 22)]
            - aux.relative_position[0] * cov[(18, 24)];
        pht[(19, 0)] = _t3 * cov[(0, 19)] - cov[(15, 19)]
            - aux.relative_position[2] * cov[(19, 23)]
            + aux.relative_position[1] * cov[(19, 24)];
        pht[(19, 1)] = _t5 * cov[(1, 19)] - cov[(16, 19)]
            + aux.relative_position[2] * cov[(19, 22)]
            - aux.relative_position[0] * cov[(19, 24)];
        pht[(20, 0)] = _t3 * cov[(0, 20)] - cov[(15, 20)]
            - aux.relative_position[2] * cov[(20, 23)]
            + aux.relative_position[1] * cov[(20, 24)];
        pht[(20, 1)] = _t5 * cov[(1, 20)] - cov[(16, 20)]
            + aux.relative_position[2] * cov[(20, 22)]
            - aux.relative_position[0] * cov[(20, 24)];
        pht[(21, 0)] = _t3 * cov[(0, 21)] - cov[(15, 21)]
            - aux.relative_position[2] * cov[(21, 23)]
            + aux.relative_position[1] * cov[(21, 24)];
        pht[(21, 1)] = _t5 * cov[(1, 21)] - cov[(16, 21)]
            + aux.relative_position[2] * cov[(21, 22)]
            - aux.relative_position[0] * cov[(21, 24)];
        pht[(22, 0)] = _t3 * cov[(0, 22)] - cov[(15, 22)] - _t14
            + aux.relative_position[1] * cov[(22, 24)];
        pht[(22, 1)] = _t15;
        pht[(23, 0)] = _t16;
        pht[(23, 1)] = _t17;
        pht[(24, 0)] = _t18;
        pht[(24, 1)] = _t19;
        s[(0, 0)] = _t3 * _t6 - _t9 - aux.relative_position[2] * _t16
            + aux.relative_position[1] * _t18;
        s[(0, 1)] = _t11 - _t10 + _t3 * _t7 - aux.relative_position[2] * _t17
            + aux.relative_position[1] * _t19;
        s[(1, 1)] = _t13 - _t12 + _t5 * _t8 + aux.relative_position[2] * _t15
            - aux.relative_position[0] * _t19;
        for i in 0..2 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
#[cfg(test)]
#[allow(clippy::possible_missing_comma, non_snake_case)]
mod __sdins25_generated_tests {
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
    const N: usize = 25;
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
            Sdins25Input,
            Sdins25Params,
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
            let u: Sdins25Input = random_record(&mut rng);
            let p: Sdins25Params = random_record(&mut rng);
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
                let jac = <Sdins25 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let f = |x: &SVector<S, N>| Sdins25::derivative(x, &u, &p);
                let Some(fd) = fd_jacobian(&x, f) else { return false };
                if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd("jacobian", &jac, &fd);
                assert_sparsity(
                    "jacobian",
                    &jac,
                    &<Sdins25 as Model<N, S>>::JACOBIAN_SPARSITY,
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
                let g = Sdins25::noise_jacobian(&x, &u, &p, dt);
                let f = |w: &SVector<S, NW>| Sdins25::derivative_with_noise(
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
                let q: Sdins25Noise = <Sdins25Noise as Record>::from_fn(|_| ::nav_runtime::math::abs(
                    rng.uniform(),
                ));
                let cov = random_covariance(rng);
                let jac = <Sdins25 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let g = Sdins25::noise_jacobian(&x, &u, &p, dt);
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
                let qd = <Sdins25 as Model<N, S>>::process_noise(&x, &u, &p, &q, dt);
                assert_close_rel("process_noise", &qd, &qd_dense);
                let phi = SMatrix::<S, N, N>::identity() + jac * dt;
                let dense = phi * cov * phi.transpose() + qd_dense;
                let mut got = cov;
                <Sdins25 as Model<
                    N,
                    S,
                >>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                assert_close_rel("propagate_covariance", &got, &dense);
                assert_eq!(
                    got, got.transpose(), "the propagated covariance must be symmetric"
                );
                let mut observed = cov;
                let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                <Sdins25 as Model<
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
                        let s = <Sdins25 as Model<N, S>>::PROPAGATION
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
                    rebuilt.is_some(), < Sdins25 as Model < N, S >> ::PROPAGATION
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
        let s = Sdins25State::from_vector(&x);
        assert_eq!(s.to_vector(), x);
        for i in 0..N {
            assert_eq!(s.get(i), < S as ::nav_runtime::Real > ::to_f64(x[i]));
        }
        assert_eq!(<< Sdins25 as Model < N, S >> ::State as Record > ::NAMES.len(), N);
        assert_eq!(< Sdins25 as Model < N, S >> ::STATE_NAMES.len(), N);
    }
    #[test]
    fn sensor_depth_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Depth as Sensor<N, 1, S>>::Aux = random_record(rng);
                let jac = <Sdins25Depth as Sensor<N, 1, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Sdins25Depth as Sensor<
                    N,
                    1,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Sdins25Depth), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Sdins25Depth), "::jacobian"),
                    &jac,
                    &<Sdins25Depth as Sensor<N, 1, S>>::JACOBIAN_SPARSITY,
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
                let aux: <Sdins25Depth as Sensor<N, 1, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Sdins25Depth as Sensor<N, 1, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Sdins25Depth as Sensor<N, 1, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Sdins25Depth as Sensor<
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
    fn sensor_dvl_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let jac = <Sdins25Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Sdins25Dvl as Sensor<
                    N,
                    3,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Sdins25Dvl), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Sdins25Dvl), "::jacobian"),
                    &jac,
                    &<Sdins25Dvl as Sensor<N, 3, S>>::JACOBIAN_SPARSITY,
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
                let aux: <Sdins25Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Sdins25Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Sdins25Dvl as Sensor<N, 3, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Sdins25Dvl as Sensor<
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
    fn sensor_compass_small_angle_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Sdins25CompassSmallAngle as Sensor<N, 1, S>>::Aux = random_record(
                    rng,
                );
                let jac = <Sdins25CompassSmallAngle as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Sdins25CompassSmallAngle as Sensor<
                    N,
                    1,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Sdins25CompassSmallAngle), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Sdins25CompassSmallAngle), "::jacobian"),
                    &jac,
                    &<Sdins25CompassSmallAngle as Sensor<N, 1, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_compass_small_angle_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Sdins25CompassSmallAngle as Sensor<N, 1, S>>::Aux = random_record(
                    rng,
                );
                let cov = random_covariance(rng);
                let hjac = <Sdins25CompassSmallAngle as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Sdins25CompassSmallAngle as Sensor<
                    N,
                    1,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Sdins25CompassSmallAngle as Sensor<
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
    fn sensor_compass_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Compass as Sensor<N, 1, S>>::Aux = random_record(rng);
                let jac = <Sdins25Compass as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Sdins25Compass as Sensor<
                    N,
                    1,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Sdins25Compass), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Sdins25Compass), "::jacobian"),
                    &jac,
                    &<Sdins25Compass as Sensor<N, 1, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_compass_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Compass as Sensor<N, 1, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Sdins25Compass as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <Sdins25Compass as Sensor<
                    N,
                    1,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Sdins25Compass as Sensor<
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
    fn sensor_usbl_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Usbl as Sensor<N, 2, S>>::Aux = random_record(rng);
                let jac = <Sdins25Usbl as Sensor<N, 2, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Sdins25Usbl as Sensor<
                    N,
                    2,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(Sdins25Usbl), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(Sdins25Usbl), "::jacobian"),
                    &jac,
                    &<Sdins25Usbl as Sensor<N, 2, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_usbl_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Sdins25Usbl as Sensor<N, 2, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Sdins25Usbl as Sensor<N, 2, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Sdins25Usbl as Sensor<N, 2, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Sdins25Usbl as Sensor<
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
}
