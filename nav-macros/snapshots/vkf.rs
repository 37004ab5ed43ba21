// Expansion of `nav_runtime::model!` in models/src/vkf/model.rs, formatted.
// Checked by `snapshots_are_current` (nav-macros/src/lib.rs); regenerate with
// `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`.
//
// Op counts:
//   VelocityFilter::OPS_TRANSITION = 2
//   VelocityFilter::OPS_JACOBIAN = 0
//   VelocityFilter::OPS_NOISE_JACOBIAN = 0
//   VelocityFilter::OPS_PROCESS_NOISE = 0
//   VelocityFilter::OPS_PROPAGATE_COVARIANCE = 9
//   VelocityFilterDvl::OPS_PREDICT = 0
//   VelocityFilterDvl::OPS_JACOBIAN = 0
//   VelocityFilterDvl::OPS_INNOVATION_TERMS = 0
//   Nav9::OPS_TRANSITION = 30
//   Nav9::OPS_JACOBIAN = 9
//   Nav9::OPS_NOISE_JACOBIAN = 0
//   Nav9::OPS_PROCESS_NOISE = 6
//   Nav9::OPS_PROPAGATE_COVARIANCE = 258
//   Nav9::OPS_DERIVATIVE = 18
//   Nav9Dvl::OPS_PREDICT = 0
//   Nav9Dvl::OPS_JACOBIAN = 0
//   Nav9Dvl::OPS_INNOVATION_TERMS = 0
//   Nav9Rpm::OPS_PREDICT = 0
//   Nav9Rpm::OPS_JACOBIAN = 0
//   Nav9Rpm::OPS_INNOVATION_TERMS = 0

///The state of [`VelocityFilter`] (3 scalars), with named fields.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct VelocityFilterState {
    /// Forward (body x) speed over ground `V`, m/s.
    pub speed: f64,
    /// RPM-to-speed scale factor `sf`, (m/s)/rpm.
    pub scale_factor: f64,
    /// RPM-to-speed bias `b`, m/s.
    pub bias: f64,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for VelocityFilterState {
    const LEN: usize = 3;
    const NAMES: &'static [&'static str] = &["speed", "scale_factor", "bias"];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 3] = [0.0; 3];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            speed: v[0],
            scale_factor: v[1],
            bias: v[2],
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.speed),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.scale_factor),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.bias),
            _ => f64::NAN,
        }
    }
}
#[allow(clippy::possible_missing_comma)]
impl VelocityFilterState {
    /// The state from its vector (declaration order).
    pub fn from_vector(v: &::nav_runtime::nalgebra::SVector<f64, 3>) -> Self {
        <Self as ::nav_runtime::model::Record>::from_fn(|i| <f64 as ::nav_runtime::Real>::to_f64(
            v[i],
        ))
    }
    /// The state as a vector (declaration order).
    pub fn to_vector(&self) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        ::nav_runtime::nalgebra::SVector::<
            f64,
            3,
        >::from_column_slice(&[self.speed, self.scale_factor, self.bias])
    }
}
///The inputs `u` of [`VelocityFilter`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct VelocityFilterInput {
    /// Measured propeller revolutions per minute.
    pub rpm: f64,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for VelocityFilterInput {
    const LEN: usize = 1;
    const NAMES: &'static [&'static str] = &["rpm"];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 1] = [0.0; 1];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self { rpm: v[0] }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.rpm),
            _ => f64::NAN,
        }
    }
}
///The parameters `p` of [`VelocityFilter`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct VelocityFilterParams {}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for VelocityFilterParams {
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
///The per-step process-noise variances `q` of [`VelocityFilter`], one per noise scalar.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct VelocityFilterNoise {
    /// Departure of the speed from the map in one step (map curvature,
    /// RPM noise, sea state), m/s.
    pub speed_noise: f64,
    /// Scale-factor random-walk step, (m/s)/rpm.
    pub scale_factor_walk: f64,
    /// Bias random-walk step, m/s.
    pub bias_walk: f64,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for VelocityFilterNoise {
    const LEN: usize = 3;
    const NAMES: &'static [&'static str] = &[
        "speed_noise",
        "scale_factor_walk",
        "bias_walk",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 3] = [0.0; 3];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            speed_noise: v[0],
            scale_factor_walk: v[1],
            bias_walk: v[2],
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.speed_noise),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.scale_factor_walk),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.bias_walk),
            _ => f64::NAN,
        }
    }
}
/// Velocity Kalman filter, `X = [V, sf, b]` (paper eqs. 6-10): the forward
/// speed is the RPM map `V_{k+1} = sf_k rpm_k + b_k`; the scale factor and the
/// bias are random walks; the DVL forward speed measures `V`.
/// Discrete, one step per RPM sample; noise intensities are per-step variances.
///
///Generated by `model!`: discrete model with 3 states, 3 noise inputs and 1 sensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VelocityFilter;
#[allow(clippy::possible_missing_comma)]
impl VelocityFilter {
    /// Number of scalar states.
    pub const N: usize = 3;
    /// Number of scalar process-noise inputs.
    pub const NW: usize = 3;
    ///Index of the first scalar of `speed` in the state vector.
    pub const SPEED: usize = 0;
    ///Index of the first scalar of `scale_factor` in the state vector.
    pub const SCALE_FACTOR: usize = 1;
    ///Index of the first scalar of `bias` in the state vector.
    pub const BIAS: usize = 2;
    /// State scalars no sensor depends on, directly or through the dynamics
    /// (no measurement can correct them). The model lists them in
    /// `allow_unused { .. }` (checked at compile time).
    pub const UNUSED_STATES: &'static [&'static str] = &[];
    /// Operations in `transition`.
    pub const OPS_TRANSITION: usize = 2;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in [`Self::noise_jacobian`].
    pub const OPS_NOISE_JACOBIAN: usize = 0;
    /// Operations in `process_noise`.
    pub const OPS_PROCESS_NOISE: usize = 0;
    /// Operations in `propagate_covariance`.
    pub const OPS_PROPAGATE_COVARIANCE: usize = 9;
    ///Structure of `Phi` (`df/dx`) and `Qd` for the covariance propagation: rows [0] change, the others are unit rows.
    pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> = ::nav_runtime::propagation::Structure {
        identity: false,
        rows: &[0],
        start: &[0, 2],
        columns: &[1, 2],
        noise: &[(0, 0), (1, 1), (2, 2)],
    };
    /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
    pub const SENSORS: [&'static str; 1] = ["Dvl"];
    /// Per sensor, per state scalar: the sensor's `h` depends on the state
    /// directly (a structural nonzero of its `H`).
    pub const SENSOR_DEPENDS: [[bool; 3]; 1] = [[true, false, false]];
    /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
    /// indices into `SENSORS`); the set of all sensors when it declares none.
    pub const RUNS_WITH: [&'static [usize]; 1] = [&[0]];
    /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
    /// that set (checked at compile time against `allow_unused`).
    pub const RUNS_WITH_OBSERVABLE: [[bool; 3]; 1] = [[true, true, true]];
    /// Per state scalar: is it structurally observable with the sensors marked
    /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
    /// a measurement of one of them, through a sensor's `H` or the dynamics
    /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
    /// only: `false` means no measurement of that set can ever correct the
    /// state; `true` means only that sparsity does not exclude it (see
    /// `docs/language.md`, "Structural observability").
    pub const fn structurally_observable(sensors: &[bool; 1]) -> [bool; 3] {
        let deps = Self::SENSOR_DEPENDS;
        let f = <Self as ::nav_runtime::model::Model<3, f64>>::JACOBIAN_SPARSITY;
        let mut seen = [false; 3];
        let mut s = 0;
        while s < 1 {
            if sensors[s] {
                let mut j = 0;
                while j < 3 {
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
            while i < 3 {
                if seen[i] {
                    let mut j = 0;
                    while j < 3 {
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

Total ops: 5*/
    pub fn step_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        w: &::nav_runtime::nalgebra::SVector<f64, 3>,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        out[0] = u.rpm * x[1] + x[2] + w[0];
        out[1] = x[1] + w[1];
        out[2] = x[2] + w[2];
        out
    }
    /**The noise Jacobian `G = df/dw` of the step at `w = 0` (N x NW, noise scalars in declaration order).

Total ops: 0*/
    pub fn noise_jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 3> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        out[(0, 0)] = 1.0;
        out[(1, 1)] = 1.0;
        out[(2, 2)] = 1.0;
        out
    }
}
impl ::nav_runtime::propagation::StaticStructure for VelocityFilter {
    const STRUCTURE: ::nav_runtime::propagation::Structure<'static> = Self::PROPAGATION_STRUCTURE;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Model<3, f64> for VelocityFilter {
    type Input = VelocityFilterInput;
    type Params = VelocityFilterParams;
    type Noise = VelocityFilterNoise;
    type State = VelocityFilterState;
    const NAME: &'static str = "VelocityFilter";
    const DISCRETE: bool = !false;
    const STATE_NAMES: [&'static str; 3] = ["speed", "scale_factor", "bias"];
    const JACOBIAN_SPARSITY: [[bool; 3]; 3] = [
        [false, true, true],
        [false, true, false],
        [false, false, true],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 9;
    const OPS_JACOBIAN: usize = 0;
    const ZERO_IS_FIXED: bool = true;
    /**The next state `f(x, u, p, dt)` (noise-free).

Total ops: 2*/
    fn transition(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 3> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 3>::zeros();
        out[0] = u.rpm * x[1] + x[2];
        out[1] = x[1];
        out[2] = x[2];
        out
    }
    /**`Phi = df/dx` at `w = 0`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 3> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        out[(0, 1)] = u.rpm;
        out[(0, 2)] = 1.0;
        out[(1, 1)] = 1.0;
        out[(2, 2)] = 1.0;
        out
    }
    /**`Qd = G Q G^T`, `Q = diag(q)`.

Total ops: 0*/
    fn process_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        q: &VelocityFilterNoise,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 3, 3> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 3>::zeros();
        out[(0, 0)] = q.speed_noise;
        out[(1, 1)] = q.scale_factor_walk;
        out[(2, 2)] = q.bias_walk;
        for i in 0..3 {
            for j in 0..i {
                out[(i, j)] = out[(j, i)];
            }
        }
        out
    }
    /**`P <- Phi P Phi^T + Qd` unrolled entry by entry from the upper triangle of `P` (a small model: straight-line code fits the caches), generated from the sparsity of `Phi` and `G`; the result is mirrored.

Total ops: 9*/
    fn propagate_covariance(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        q: &VelocityFilterNoise,
        dt: f64,
    ) {
        let _p = *cov;
        let _t0 = _p[(1, 1)] * u.rpm + _p[(1, 2)];
        let _t1 = _p[(2, 2)] + u.rpm * _p[(1, 2)];
        cov[(0, 0)] = u.rpm * _t0 + _t1 + q.speed_noise;
        cov[(0, 1)] = _t0;
        cov[(0, 2)] = _t1;
        cov[(1, 1)] = _p[(1, 1)] + q.scale_factor_walk;
        cov[(2, 2)] = _p[(2, 2)] + q.bias_walk;
        for i in 0..3 {
            for j in 0..i {
                cov[(i, j)] = cov[(j, i)];
            }
        }
    }
    const DECLARED_SENSORS: &'static [&'static str] = &["Dvl"];
    fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, 3, f64>>(
        name: &str,
        visitor: V,
    ) -> ::core::option::Option<V::Output> {
        match name {
            "Dvl" => {
                ::core::option::Option::Some(visitor.visit::<VelocityFilterDvl, 1>())
            }
            _ => {
                let _ = visitor;
                ::core::option::Option::None
            }
        }
    }
}
/// DVL forward speed, eq. 9: `z = V + v` (the DVL velocity rotated to the
/// body forward axis with the Euler angles, eq. 5).
///
///Sensor `Dvl` of [`VelocityFilter`]: 1 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct VelocityFilterDvl;
#[allow(clippy::possible_missing_comma)]
impl VelocityFilterDvl {
    /// Number of measurement components.
    pub const M: usize = 1;
    /// The declared sensor name.
    pub const NAME: &'static str = "Dvl";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 0;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 3] = [true, true, true];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<3, 1, f64> for VelocityFilterDvl {
    type Model = VelocityFilter;
    type Aux = ();
    const NAME: &'static str = "Dvl";
    const ANGLES: [bool; 1] = [false];
    const JACOBIAN_SPARSITY: [[bool; 3]; 1] = [[true, false, false]];
    const OPS_INNOVATION_TERMS: usize = 0;
    /**The predicted measurement `h(x, u, p, aux)`.

Total ops: 0*/
    fn predict(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SVector<f64, 1> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        out[0] = x[0];
        out
    }
    /**`H = dh/dx`.

Total ops: 0*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        aux: &(),
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 1, 3> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 3>::zeros();
        out[(0, 0)] = 1.0;
        out
    }
    /**`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.

Total ops: 0*/
    fn innovation_terms(
        cov: &::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
        x: &::nav_runtime::nalgebra::SVector<f64, 3>,
        u: &VelocityFilterInput,
        p: &VelocityFilterParams,
        aux: &(),
    ) -> (
        ::nav_runtime::nalgebra::SVector<f64, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 3, 1>,
        ::nav_runtime::nalgebra::SMatrix<f64, 1, 1>,
    ) {
        let mut h = ::nav_runtime::nalgebra::SVector::<f64, 1>::zeros();
        let mut pht = ::nav_runtime::nalgebra::SMatrix::<f64, 3, 1>::zeros();
        let mut s = ::nav_runtime::nalgebra::SMatrix::<f64, 1, 1>::zeros();
        h[0] = x[0];
        pht[(0, 0)] = cov[(0, 0)];
        pht[(1, 0)] = cov[(0, 1)];
        pht[(2, 0)] = cov[(0, 2)];
        s[(0, 0)] = cov[(0, 0)];
        for i in 0..1 {
            for j in 0..i {
                s[(i, j)] = s[(j, i)];
            }
        }
        (h, pht, s)
    }
}
#[cfg(test)]
#[allow(clippy::possible_missing_comma, non_snake_case)]
mod __velocity_filter_generated_tests {
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
    const N: usize = 3;
    const NW: usize = 3;
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
            VelocityFilterInput,
            VelocityFilterParams,
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
            let u: VelocityFilterInput = random_record(&mut rng);
            let p: VelocityFilterParams = random_record(&mut rng);
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
                let jac = <VelocityFilter as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let f = |x: &SVector<S, N>| <VelocityFilter as Model<
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
                    &<VelocityFilter as Model<N, S>>::JACOBIAN_SPARSITY,
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
                let g = VelocityFilter::noise_jacobian(&x, &u, &p, dt);
                let f = |w: &SVector<S, NW>| VelocityFilter::step_with_noise(
                    &x,
                    &u,
                    &p,
                    w,
                    dt,
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
                let q: VelocityFilterNoise = <VelocityFilterNoise as Record>::from_fn(|
                    _|
                ::nav_runtime::math::abs(rng.uniform()));
                let cov = random_covariance(rng);
                let jac = <VelocityFilter as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let g = VelocityFilter::noise_jacobian(&x, &u, &p, dt);
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
                let qd = <VelocityFilter as Model<
                    N,
                    S,
                >>::process_noise(&x, &u, &p, &q, dt);
                assert_close_rel("process_noise", &qd, &qd_dense);
                let phi = jac;
                let dense = phi * cov * phi.transpose() + qd_dense;
                let mut got = cov;
                <VelocityFilter as Model<
                    N,
                    S,
                >>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                assert_close_rel("propagate_covariance", &got, &dense);
                assert_eq!(
                    got, got.transpose(), "the propagated covariance must be symmetric"
                );
                let mut observed = cov;
                let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                <VelocityFilter as Model<
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
                        let s = <VelocityFilter as Model<N, S>>::PROPAGATION
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
                    rebuilt.is_some(), < VelocityFilter as Model < N, S >> ::PROPAGATION
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
        let s = VelocityFilterState::from_vector(&x);
        assert_eq!(s.to_vector(), x);
        for i in 0..N {
            assert_eq!(s.get(i), < S as ::nav_runtime::Real > ::to_f64(x[i]));
        }
        assert_eq!(
            << VelocityFilter as Model < N, S >> ::State as Record > ::NAMES.len(), N
        );
        assert_eq!(< VelocityFilter as Model < N, S >> ::STATE_NAMES.len(), N);
    }
    #[test]
    fn sensor_dvl_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <VelocityFilterDvl as Sensor<N, 1, S>>::Aux = random_record(
                    rng,
                );
                let jac = <VelocityFilterDvl as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <VelocityFilterDvl as Sensor<
                    N,
                    1,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(
                    concat!(stringify!(VelocityFilterDvl), "::jacobian"),
                    &jac,
                    &fd,
                );
                assert_sparsity(
                    concat!(stringify!(VelocityFilterDvl), "::jacobian"),
                    &jac,
                    &<VelocityFilterDvl as Sensor<N, 1, S>>::JACOBIAN_SPARSITY,
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
                let aux: <VelocityFilterDvl as Sensor<N, 1, S>>::Aux = random_record(
                    rng,
                );
                let cov = random_covariance(rng);
                let hjac = <VelocityFilterDvl as Sensor<
                    N,
                    1,
                    S,
                >>::jacobian(&x, &u, &p, &aux);
                let pred = <VelocityFilterDvl as Sensor<
                    N,
                    1,
                    S,
                >>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <VelocityFilterDvl as Sensor<
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
}
///The state of [`Nav9`] (9 scalars), with named fields.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Nav9State {
    /// Position north, east, down of the start point, m.
    pub position: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// NED velocity over ground, m/s.
    pub velocity: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Accelerometer bias in body axes, m/s^2.
    pub accel_bias: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Nav9State {
    const LEN: usize = 9;
    const NAMES: &'static [&'static str] = &[
        "position[0]",
        "position[1]",
        "position[2]",
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "accel_bias[0]",
        "accel_bias[1]",
        "accel_bias[2]",
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
            accel_bias: ::nav_runtime::nalgebra::SVector::<
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
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[0]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[1]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_bias[2]),
            _ => f64::NAN,
        }
    }
}
#[allow(clippy::possible_missing_comma)]
impl Nav9State {
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
                self.accel_bias[0],
                self.accel_bias[1],
                self.accel_bias[2],
            ],
        )
    }
}
///The inputs `u` of [`Nav9`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Nav9Input {
    /// Compensated nav-frame acceleration `a^n`, m/s^2.
    pub accel_n: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Attitude `C_b^n` of the strapdown attitude computer.
    pub c_bn: ::nav_runtime::nalgebra::SMatrix<f64, 3, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Nav9Input {
    const LEN: usize = 12;
    const NAMES: &'static [&'static str] = &[
        "accel_n[0]",
        "accel_n[1]",
        "accel_n[2]",
        "c_bn[0][0]",
        "c_bn[0][1]",
        "c_bn[0][2]",
        "c_bn[1][0]",
        "c_bn[1][1]",
        "c_bn[1][2]",
        "c_bn[2][0]",
        "c_bn[2][1]",
        "c_bn[2][2]",
    ];
    fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
        let mut v: [f64; 12] = [0.0; 12];
        for (i, slot) in v.iter_mut().enumerate() {
            *slot = <f64 as ::nav_runtime::Real>::of(f(i));
        }
        Self {
            accel_n: ::nav_runtime::nalgebra::SVector::<
                f64,
                3,
            >::from_column_slice(&v[0..3]),
            c_bn: ::nav_runtime::nalgebra::SMatrix::<
                f64,
                3,
                3,
            >::from_row_slice(&v[3..12]),
        }
    }
    fn get(&self, i: usize) -> f64 {
        match i {
            0 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_n[0]),
            1 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_n[1]),
            2 => <f64 as ::nav_runtime::Real>::to_f64(self.accel_n[2]),
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 0)]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 1)]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(0, 2)]),
            6 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 0)]),
            7 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 1)]),
            8 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(1, 2)]),
            9 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 0)]),
            10 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 1)]),
            11 => <f64 as ::nav_runtime::Real>::to_f64(self.c_bn[(2, 2)]),
            _ => f64::NAN,
        }
    }
}
///The parameters `p` of [`Nav9`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Nav9Params {}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Nav9Params {
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
///The process-noise power spectral densities `q` of [`Nav9`], one per noise scalar (units^2 / s).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[allow(non_snake_case)]
pub struct Nav9Noise {
    /// Acceleration white noise (accelerometer noise, unmodelled tilt), (m/s^2)^2/Hz.
    pub accel_noise: ::nav_runtime::nalgebra::SVector<f64, 3>,
    /// Bias random walk, (m/s^2)^2/s.
    pub bias_walk: ::nav_runtime::nalgebra::SVector<f64, 3>,
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Record for Nav9Noise {
    const LEN: usize = 6;
    const NAMES: &'static [&'static str] = &[
        "accel_noise[0]",
        "accel_noise[1]",
        "accel_noise[2]",
        "bias_walk[0]",
        "bias_walk[1]",
        "bias_walk[2]",
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
            bias_walk: ::nav_runtime::nalgebra::SVector::<
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
            3 => <f64 as ::nav_runtime::Real>::to_f64(self.bias_walk[0]),
            4 => <f64 as ::nav_runtime::Real>::to_f64(self.bias_walk[1]),
            5 => <f64 as ::nav_runtime::Real>::to_f64(self.bias_walk[2]),
            _ => f64::NAN,
        }
    }
}
/// 9-state integrated navigation filter (paper eqs. 13-18): local-level NED
/// position and velocity relative to the start point and the accelerometer
/// bias. The input is the nav-frame acceleration after the coordinate
/// transform, Coriolis and gravity compensation,
/// `a^n = C_b^n f^b - (2 w_ie^n + w_en^n) x v^n + g^n`; the bias is carried in
/// body axes and rotated with `C_b^n`, so a turn does not invalidate it (it
/// also absorbs the slowly growing tilt error, which this filter does not
/// estimate).
///
///Generated by `model!`: continuous model with 9 states, 6 noise inputs and 2 sensors.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Nav9;
#[allow(clippy::possible_missing_comma)]
impl Nav9 {
    /// Number of scalar states.
    pub const N: usize = 9;
    /// Number of scalar process-noise inputs.
    pub const NW: usize = 6;
    ///Index of the first scalar of `position` in the state vector.
    pub const POSITION: usize = 0;
    ///Index of the first scalar of `velocity` in the state vector.
    pub const VELOCITY: usize = 3;
    ///Index of the first scalar of `accel_bias` in the state vector.
    pub const ACCEL_BIAS: usize = 6;
    /// State scalars no sensor depends on, directly or through the dynamics
    /// (no measurement can correct them). The model lists them in
    /// `allow_unused { .. }` (checked at compile time).
    pub const UNUSED_STATES: &'static [&'static str] = &[
        "position[0]",
        "position[1]",
        "position[2]",
    ];
    /// Operations in `transition`.
    pub const OPS_TRANSITION: usize = 30;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 9;
    /// Operations in [`Self::noise_jacobian`].
    pub const OPS_NOISE_JACOBIAN: usize = 0;
    /// Operations in `process_noise`.
    pub const OPS_PROCESS_NOISE: usize = 6;
    /// Operations in `propagate_covariance`.
    pub const OPS_PROPAGATE_COVARIANCE: usize = 258;
    ///Structure of `Phi` (`I + F dt`) and `Qd` for the covariance propagation: rows [0, 1, 2, 3, 4, 5] change, the others are unit rows.
    pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> = ::nav_runtime::propagation::Structure {
        identity: true,
        rows: &[0, 1, 2, 3, 4, 5],
        start: &[0, 1, 2, 3, 6, 9, 12],
        columns: &[3, 4, 5, 6, 7, 8, 6, 7, 8, 6, 7, 8],
        noise: &[(3, 3), (4, 4), (5, 5), (6, 6), (7, 7), (8, 8)],
    };
    /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
    pub const SENSORS: [&'static str; 2] = ["Dvl", "Rpm"];
    /// Per sensor, per state scalar: the sensor's `h` depends on the state
    /// directly (a structural nonzero of its `H`).
    pub const SENSOR_DEPENDS: [[bool; 9]; 2] = [
        [false, false, false, true, true, true, false, false, false],
        [false, false, false, true, true, true, false, false, false],
    ];
    /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
    /// indices into `SENSORS`); the set of all sensors when it declares none.
    pub const RUNS_WITH: [&'static [usize]; 1] = [&[0, 1]];
    /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
    /// that set (checked at compile time against `allow_unused`).
    pub const RUNS_WITH_OBSERVABLE: [[bool; 9]; 1] = [
        [false, false, false, true, true, true, true, true, true],
    ];
    /// Per state scalar: is it structurally observable with the sensors marked
    /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
    /// a measurement of one of them, through a sensor's `H` or the dynamics
    /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
    /// only: `false` means no measurement of that set can ever correct the
    /// state; `true` means only that sparsity does not exclude it (see
    /// `docs/language.md`, "Structural observability").
    pub const fn structurally_observable(sensors: &[bool; 2]) -> [bool; 9] {
        let deps = Self::SENSOR_DEPENDS;
        let f = <Self as ::nav_runtime::model::Model<9, f64>>::JACOBIAN_SPARSITY;
        let mut seen = [false; 9];
        let mut s = 0;
        while s < 2 {
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
    /// Operations in [`Self::derivative`].
    pub const OPS_DERIVATIVE: usize = 18;
    /**The state derivative `f(x, u, p)` at `w = 0`.

Total ops: 18*/
    pub fn derivative(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = x[3];
        out[1] = x[4];
        out[2] = x[5];
        out[3] = u.accel_n[0]
            - (u.c_bn[(0, 1)] * x[7] + u.c_bn[(0, 0)] * x[6] + u.c_bn[(0, 2)] * x[8]);
        out[4] = u.accel_n[1]
            - (x[7] * u.c_bn[(1, 1)] + x[6] * u.c_bn[(1, 0)] + x[8] * u.c_bn[(1, 2)]);
        out[5] = u.accel_n[2]
            - (x[7] * u.c_bn[(2, 1)] + x[6] * u.c_bn[(2, 0)] + x[8] * u.c_bn[(2, 2)]);
        out
    }
    /**The state derivative `dx/dt = f(x, u, p, w)` with an explicit noise sample `w` (units of the state per second; not a step: [`Self::step_with_noise`] advances the state by `dt`).

Total ops: 21*/
    pub fn derivative_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = x[3];
        out[1] = x[4];
        out[2] = x[5];
        out[3] = u.accel_n[0]
            - (u.c_bn[(0, 1)] * x[7] + u.c_bn[(0, 0)] * x[6] + u.c_bn[(0, 2)] * x[8])
            + w[0];
        out[4] = u.accel_n[1]
            - (x[7] * u.c_bn[(1, 1)] + x[6] * u.c_bn[(1, 0)] + x[8] * u.c_bn[(1, 2)])
            + w[1];
        out[5] = u.accel_n[2]
            - (x[7] * u.c_bn[(2, 1)] + x[6] * u.c_bn[(2, 0)] + x[8] * u.c_bn[(2, 2)])
            + w[2];
        out[6] = w[3];
        out[7] = w[4];
        out[8] = w[5];
        out
    }
    /**The state after one step of `dt` seconds with an explicit noise sample `w`: the Euler step `x + f(x, u, p, w) dt` (`transition` at `w = 0`; the derivative itself is [`Self::derivative_with_noise`]).

Total ops: 39*/
    pub fn step_with_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        w: &::nav_runtime::nalgebra::SVector<f64, 6>,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = dt * x[3] + x[0];
        out[1] = dt * x[4] + x[1];
        out[2] = dt * x[5] + x[2];
        out[3] = x[3]
            + dt
                * (u.accel_n[0]
                    - (u.c_bn[(0, 1)] * x[7] + u.c_bn[(0, 0)] * x[6]
                        + u.c_bn[(0, 2)] * x[8]) + w[0]);
        out[4] = x[4]
            + dt
                * (u.accel_n[1]
                    - (x[7] * u.c_bn[(1, 1)] + x[6] * u.c_bn[(1, 0)]
                        + x[8] * u.c_bn[(1, 2)]) + w[1]);
        out[5] = x[5]
            + dt
                * (u.accel_n[2]
                    - (x[7] * u.c_bn[(2, 1)] + x[6] * u.c_bn[(2, 0)]
                        + x[8] * u.c_bn[(2, 2)]) + w[2]);
        out[6] = x[6] + dt * w[3];
        out[7] = x[7] + dt * w[4];
        out[8] = x[8] + dt * w[5];
        out
    }
    /**The noise Jacobian `G = df/dw` of the derivative at `w = 0` (N x NW, noise scalars in declaration order; `dt` is unused: the step's own is `G dt`).

Total ops: 0*/
    pub fn noise_jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
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
impl ::nav_runtime::propagation::StaticStructure for Nav9 {
    const STRUCTURE: ::nav_runtime::propagation::Structure<'static> = Self::PROPAGATION_STRUCTURE;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Model<9, f64> for Nav9 {
    type Input = Nav9Input;
    type Params = Nav9Params;
    type Noise = Nav9Noise;
    type State = Nav9State;
    const NAME: &'static str = "Nav9";
    const DISCRETE: bool = !true;
    const STATE_NAMES: [&'static str; 9] = [
        "position[0]",
        "position[1]",
        "position[2]",
        "velocity[0]",
        "velocity[1]",
        "velocity[2]",
        "accel_bias[0]",
        "accel_bias[1]",
        "accel_bias[2]",
    ];
    const JACOBIAN_SPARSITY: [[bool; 9]; 9] = [
        [false, false, false, true, false, false, false, false, false],
        [false, false, false, false, true, false, false, false, false],
        [false, false, false, false, false, true, false, false, false],
        [false, false, false, false, false, false, true, true, true],
        [false, false, false, false, false, false, true, true, true],
        [false, false, false, false, false, false, true, true, true],
        [false, false, false, false, false, false, false, false, false],
        [false, false, false, false, false, false, false, false, false],
        [false, false, false, false, false, false, false, false, false],
    ];
    const OPS_PROPAGATE_COVARIANCE: usize = 258;
    const OPS_JACOBIAN: usize = 9;
    const ZERO_IS_FIXED: bool = false;
    /**One Euler step `x + f(x, u, p) dt`.

Total ops: 30*/
    fn transition(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SVector<f64, 9> {
        let mut out = ::nav_runtime::nalgebra::SVector::<f64, 9>::zeros();
        out[0] = dt * x[3] + x[0];
        out[1] = dt * x[4] + x[1];
        out[2] = dt * x[5] + x[2];
        out[3] = x[3]
            + dt
                * (u.accel_n[0]
                    - (u.c_bn[(0, 1)] * x[7] + u.c_bn[(0, 0)] * x[6]
                        + u.c_bn[(0, 2)] * x[8]));
        out[4] = x[4]
            + dt
                * (u.accel_n[1]
                    - (x[7] * u.c_bn[(1, 1)] + x[6] * u.c_bn[(1, 0)]
                        + x[8] * u.c_bn[(1, 2)]));
        out[5] = x[5]
            + dt
                * (u.accel_n[2]
                    - (x[7] * u.c_bn[(2, 1)] + x[6] * u.c_bn[(2, 0)]
                        + x[8] * u.c_bn[(2, 2)]));
        out[6] = x[6];
        out[7] = x[7];
        out[8] = x[8];
        out
    }
    /**`F = df/dx` at `w = 0` (`dt` is unused).

Total ops: 9*/
    fn jacobian(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 9, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 9>::zeros();
        out[(0, 3)] = 1.0;
        out[(1, 4)] = 1.0;
        out[(2, 5)] = 1.0;
        out[(3, 6)] = -u.c_bn[(0, 0)];
        out[(3, 7)] = -u.c_bn[(0, 1)];
        out[(3, 8)] = -u.c_bn[(0, 2)];
        out[(4, 6)] = -u.c_bn[(1, 0)];
        out[(4, 7)] = -u.c_bn[(1, 1)];
        out[(4, 8)] = -u.c_bn[(1, 2)];
        out[(5, 6)] = -u.c_bn[(2, 0)];
        out[(5, 7)] = -u.c_bn[(2, 1)];
        out[(5, 8)] = -u.c_bn[(2, 2)];
        out
    }
    /**`Qd = G Q G^T dt`, `Q = diag(q)`.

Total ops: 6*/
    fn process_noise(
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        q: &Nav9Noise,
        dt: f64,
    ) -> ::nav_runtime::nalgebra::SMatrix<f64, 9, 9> {
        let mut out = ::nav_runtime::nalgebra::SMatrix::<f64, 9, 9>::zeros();
        out[(3, 3)] = q.accel_noise[0] * dt;
        out[(4, 4)] = dt * q.accel_noise[1];
        out[(5, 5)] = dt * q.accel_noise[2];
        out[(6, 6)] = dt * q.bias_walk[0];
        out[(7, 7)] = dt * q.bias_walk[1];
        out[(8, 8)] = dt * q.bias_walk[2];
        for i in 0..9 {
            for j in 0..i {
                out[(i, j)] = out[(j, i)];
            }
        }
        out
    }
    /**`P <- Phi P Phi^T + Qd` unrolled entry by entry from the upper triangle of `P` (a small model: straight-line code fits the caches), generated from the sparsity of `Phi` and `G`; the result is mirrored.

Total ops: 258*/
    fn propagate_covariance(
        cov: &mut ::nav_runtime::nalgebra::SMatrix<f64, 9, 9>,
        x: &::nav_runtime::nalgebra::SVector<f64, 9>,
        u: &Nav9Input,
        p: &Nav9Params,
        q: &Nav9Noise,
        dt: f64,
    ) {
        let _p = *cov;
        let _t0 = _p[(3, 3)] * dt + _p[(0, 3)];
        let _t1 = dt * _p[(3, 4)];
        let _t2 = _t1 + _p[(0, 4)];
        let _t3 = dt * _p[(3, 5)];
        let _t4 = _t3 + _p[(0, 5)];
        let _t5 = dt * _p[(3, 6)] + _p[(0, 6)];
        let _t6 = dt * u.c_bn[(0, 0)];
        let _t7 = dt * _p[(3, 7)] + _p[(0, 7)];
        let _t8 = dt * u.c_bn[(0, 1)];
        let _t9 = dt * _p[(3, 8)] + _p[(0, 8)];
        let _t10 = dt * u.c_bn[(0, 2)];
        let _t11 = dt * u.c_bn[(1, 0)];
        let _t12 = dt * u.c_bn[(1, 1)];
        let _t13 = dt * u.c_bn[(1, 2)];
        let _t14 = dt * u.c_bn[(2, 0)];
        let _t15 = dt * u.c_bn[(2, 1)];
        let _t16 = dt * u.c_bn[(2, 2)];
        let _t17 = dt * _p[(4, 4)] + _p[(1, 4)];
        let _t18 = dt * _p[(4, 5)];
        let _t19 = _t18 + _p[(1, 5)];
        let _t20 = dt * _p[(4, 6)] + _p[(1, 6)];
        let _t21 = dt * _p[(4, 7)] + _p[(1, 7)];
        let _t22 = dt * _p[(4, 8)] + _p[(1, 8)];
        let _t23 = dt * _p[(5, 5)] + _p[(2, 5)];
        let _t24 = dt * _p[(5, 6)] + _p[(2, 6)];
        let _t25 = dt * _p[(5, 7)] + _p[(2, 7)];
        let _t26 = dt * _p[(5, 8)] + _p[(2, 8)];
        let _t27 = _p[(3, 6)] - _t6 * _p[(6, 6)] - _t8 * _p[(6, 7)] - _t10 * _p[(6, 8)];
        let _t28 = _p[(3, 7)] - _t6 * _p[(6, 7)] - _t8 * _p[(7, 7)] - _t10 * _p[(7, 8)];
        let _t29 = _p[(3, 8)] - _t6 * _p[(6, 8)] - _t8 * _p[(7, 8)] - _t10 * _p[(8, 8)];
        let _t30 = _p[(4, 6)] - _t11 * _p[(6, 6)] - _t12 * _p[(6, 7)]
            - _t13 * _p[(6, 8)];
        let _t31 = _p[(4, 7)] - _t11 * _p[(6, 7)] - _t12 * _p[(7, 7)]
            - _t13 * _p[(7, 8)];
        let _t32 = _p[(4, 8)] - _t11 * _p[(6, 8)] - _t12 * _p[(7, 8)]
            - _t13 * _p[(8, 8)];
        let _t33 = _p[(5, 6)] - _t14 * _p[(6, 6)] - _t15 * _p[(6, 7)]
            - _t16 * _p[(6, 8)];
        let _t34 = _p[(5, 7)] - _t14 * _p[(6, 7)] - _t15 * _p[(7, 7)]
            - _t16 * _p[(7, 8)];
        let _t35 = _p[(5, 8)] - _t14 * _p[(6, 8)] - _t15 * _p[(7, 8)]
            - _t16 * _p[(8, 8)];
        cov[(0, 0)] = dt * _t0 + (dt * _p[(0, 3)] + _p[(0, 0)]);
        cov[(0, 1)] = dt * _t2 + (dt * _p[(1, 3)] + _p[(0, 1)]);
        cov[(0, 2)] = dt * _t4 + (dt * _p[(2, 3)] + _p[(0, 2)]);
        cov[(0, 3)] = _t0 - _t5 * _t6 - _t7 * _t8 - _t9 * _t10;
        cov[(0, 4)] = _t2 - _t5 * _t11 - _t7 * _t12 - _t9 * _t13;
        cov[(0, 5)] = _t4 - _t5 * _t14 - _t7 * _t15 - _t9 * _t16;
        cov[(0, 6)] = _t5;
        cov[(0, 7)] = _t7;
        cov[(0, 8)] = _t9;
        cov[(1, 1)] = dt * _t17 + (dt * _p[(1, 4)] + _p[(1, 1)]);
        cov[(1, 2)] = dt * _t19 + (dt * _p[(2, 4)] + _p[(1, 2)]);
        cov[(1, 3)] = _t1 + _p[(1, 3)] - _t6 * _t20 - _t8 * _t21 - _t10 * _t22;
        cov[(1, 4)] = _t17 - _t11 * _t20 - _t12 * _t21 - _t13 * _t22;
        cov[(1, 5)] = _t19 - _t14 * _t20 - _t15 * _t21 - _t16 * _t22;
        cov[(1, 6)] = _t20;
        cov[(1, 7)] = _t21;
        cov[(1, 8)] = _t22;
        cov[(2, 2)] = dt * _t23 + (dt * _p[(2, 5)] + _p[(2, 2)]);
        cov[(2, 3)] = _t3 + _p[(2, 3)] - _t6 * _t24 - _t8 * _t25 - _t10 * _t26;
        cov[(2, 4)] = _t18 + _p[(2, 4)] - _t11 * _t24 - _t12 * _t25 - _t13 * _t26;
        cov[(2, 5)] = _t23 - _t14 * _t24 - _t15 * _t25 - _t16 * _t26;
        cov[(2, 6)] = _t24;
        cov[(2, 7)] = _t25;
        cov[(2, 8)] = _t26;
        cov[(3, 3)] = _p[(3, 3)] - _p[(3, 6)] * _t6 - _p[(3, 7)] * _t8
            - _p[(3, 8)] * _t10 - _t6 * _t27 - _t8 * _t28 - _t10 * _t29
            + dt * q.accel_noise[0];
        cov[(3, 4)] = _p[(3, 4)] - _t6 * _p[(4, 6)] - _t8 * _p[(4, 7)]
            - _t10 * _p[(4, 8)] - _t11 * _t27 - _t12 * _t28 - _t13 * _t29;
        cov[(3, 5)] = _p[(3, 5)] - _t6 * _p[(5, 6)] - _t8 * _p[(5, 7)]
            - _t10 * _p[(5, 8)] - _t14 * _t27 - _t15 * _t28 - _t16 * _t29;
        cov[(3, 6)] = _t27;
        cov[(3, 7)] = _t28;
        cov[(3, 8)] = _t29;
        cov[(4, 4)] = _p[(4, 4)] - _t11 * _p[(4, 6)] - _t12 * _p[(4, 7)]
            - _t13 * _p[(4, 8)] - _t11 * _t30 - _t12 * _t31 - _t13 * _t32
            + dt * q.accel_noise[1];
        cov[(4, 5)] = _p[(4, 5)] - _t11 * _p[(5, 6)] - _t12 * _p[(5, 7)]
            - _t13 * _p[(5, 8)] - _t14 * _t30 - _t15 * _t31 - _t16 * _t32;
        cov[(4, 6)] = _t30;
        cov[(4, 7)] = _t31;
        cov[(4, 8)] = _t32;
        cov[(5, 5)] = _p[(5, 5)] - _t14 * _p[(5, 6)] - _t15 * _p[(5, 7)]
            - _t16 * _p[(5, 8)] - _t14 * _t33 - _t15 * _t34 - _t16 * _t35
            + dt * q.accel_noise[2];
        cov[(5, 6)] = _t33;
        cov[(5, 7)] = _t34;
        cov[(5, 8)] = _t35;
        cov[(6, 6)] = _p[(6, 6)] + dt * q.bias_walk[0];
        cov[(7, 7)] = _p[(7, 7)] + dt * q.bias_walk[1];
        cov[(8, 8)] = _p[(8, 8)] + dt * q.bias_walk[2];
        for i in 0..9 {
            for j in 0..i {
                cov[(i, j)] = cov[(j, i)];
            }
        }
    }
    const DECLARED_SENSORS: &'static [&'static str] = &["Dvl", "Rpm"];
    fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, 9, f64>>(
        name: &str,
        visitor: V,
    ) -> ::core::option::Option<V::Output> {
        match name {
            "Dvl" => ::core::option::Option::Some(visitor.visit::<Nav9Dvl, 3>()),
            "Rpm" => ::core::option::Option::Some(visitor.visit::<Nav9Rpm, 3>()),
            _ => {
                let _ = visitor;
                ::core::option::Option::None
            }
        }
    }
}
/// The DVL's NED velocity (valid below the DVL's range), eq. 12 upper branch.
///
///Sensor `Dvl` of [`Nav9`]: 3 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Nav9Dvl;
#[allow(clippy::possible_missing_comma)]
impl Nav9Dvl {
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
        false, false, false, true, true, true, true, true, true,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 3, f64> for Nav9Dvl {
    type Model = Nav9;
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
        u: &Nav9Input,
        p: &Nav9Params,
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
        u: &Nav9Input,
        p: &Nav9Params,
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
        u: &Nav9Input,
        p: &Nav9Params,
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
/// The RPM-derived NED velocity `C_b^n [sf rpm + b, 0, 0]`, eqs. 11-12.
///
///Sensor `Rpm` of [`Nav9`]: 3 outputs.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Nav9Rpm;
#[allow(clippy::possible_missing_comma)]
impl Nav9Rpm {
    /// Number of measurement components.
    pub const M: usize = 3;
    /// The declared sensor name.
    pub const NAME: &'static str = "Rpm";
    /// The index of this sensor in the model's `SENSORS` (declaration order).
    pub const INDEX: usize = 1;
    /// Per state scalar: structurally observable with this sensor alone (its `h`
    /// depends on the state, directly or through the dynamics); see
    /// `docs/language.md`, "Structural observability".
    pub const OBSERVES: [bool; 9] = [
        false, false, false, true, true, true, true, true, true,
    ];
    /// Operations in `predict`.
    pub const OPS_PREDICT: usize = 0;
    /// Operations in `jacobian`.
    pub const OPS_JACOBIAN: usize = 0;
    /// Operations in `innovation_terms`.
    pub const OPS_INNOVATION_TERMS: usize = 0;
}
#[allow(clippy::possible_missing_comma)]
impl ::nav_runtime::model::Sensor<9, 3, f64> for Nav9Rpm {
    type Model = Nav9;
    type Aux = ();
    const NAME: &'static str = "Rpm";
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
        u: &Nav9Input,
        p: &Nav9Params,
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
        u: &Nav9Input,
        p: &Nav9Params,
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
        u: &Nav9Input,
        p: &Nav9Params,
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
#[cfg(test)]
#[allow(clippy::possible_missing_comma, non_snake_case)]
mod __nav9_generated_tests {
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
            Nav9Input,
            Nav9Params,
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
            let u: Nav9Input = random_record(&mut rng);
            let p: Nav9Params = random_record(&mut rng);
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
                let jac = <Nav9 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let f = |x: &SVector<S, N>| Nav9::derivative(x, &u, &p);
                let Some(fd) = fd_jacobian(&x, f) else { return false };
                if !finite(&f(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd("jacobian", &jac, &fd);
                assert_sparsity(
                    "jacobian",
                    &jac,
                    &<Nav9 as Model<N, S>>::JACOBIAN_SPARSITY,
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
                let g = Nav9::noise_jacobian(&x, &u, &p, dt);
                let f = |w: &SVector<S, NW>| Nav9::derivative_with_noise(&x, &u, &p, w);
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
                let q: Nav9Noise = <Nav9Noise as Record>::from_fn(|_| ::nav_runtime::math::abs(
                    rng.uniform(),
                ));
                let cov = random_covariance(rng);
                let jac = <Nav9 as Model<N, S>>::jacobian(&x, &u, &p, dt);
                let g = Nav9::noise_jacobian(&x, &u, &p, dt);
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
                let qd = <Nav9 as Model<N, S>>::process_noise(&x, &u, &p, &q, dt);
                assert_close_rel("process_noise", &qd, &qd_dense);
                let phi = SMatrix::<S, N, N>::identity() + jac * dt;
                let dense = phi * cov * phi.transpose() + qd_dense;
                let mut got = cov;
                <Nav9 as Model<
                    N,
                    S,
                >>::propagate_covariance(&mut got, &x, &u, &p, &q, dt);
                assert_close_rel("propagate_covariance", &got, &dense);
                assert_eq!(
                    got, got.transpose(), "the propagated covariance must be symmetric"
                );
                let mut observed = cov;
                let mut rebuilt: Option<SMatrix<S, N, N>> = None;
                <Nav9 as Model<
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
                        let s = <Nav9 as Model<N, S>>::PROPAGATION
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
                    rebuilt.is_some(), < Nav9 as Model < N, S >> ::PROPAGATION.is_some(),
                    "observed once over a structure"
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
        let s = Nav9State::from_vector(&x);
        assert_eq!(s.to_vector(), x);
        for i in 0..N {
            assert_eq!(s.get(i), < S as ::nav_runtime::Real > ::to_f64(x[i]));
        }
        assert_eq!(<< Nav9 as Model < N, S >> ::State as Record > ::NAMES.len(), N);
        assert_eq!(< Nav9 as Model < N, S >> ::STATE_NAMES.len(), N);
    }
    #[test]
    fn sensor_dvl_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Nav9Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let jac = <Nav9Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Nav9Dvl as Sensor<
                    N,
                    3,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(concat!(stringify!(Nav9Dvl), "::jacobian"), &jac, &fd);
                assert_sparsity(
                    concat!(stringify!(Nav9Dvl), "::jacobian"),
                    &jac,
                    &<Nav9Dvl as Sensor<N, 3, S>>::JACOBIAN_SPARSITY,
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
                let aux: <Nav9Dvl as Sensor<N, 3, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Nav9Dvl as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Nav9Dvl as Sensor<N, 3, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Nav9Dvl as Sensor<
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
    fn sensor_rpm_jacobian_matches_finite_differences() {
        at_random_points(
            0x5eed_0002,
            |rng, x, u, p, dt| {
                let aux: <Nav9Rpm as Sensor<N, 3, S>>::Aux = random_record(rng);
                let jac = <Nav9Rpm as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let h = |x: &SVector<S, N>| <Nav9Rpm as Sensor<
                    N,
                    3,
                    S,
                >>::predict(x, &u, &p, &aux);
                let Some(fd) = fd_jacobian(&x, h) else { return false };
                if !finite(&h(&x)) || !finite(&jac) || !finite(&fd.0) {
                    return false;
                }
                assert_close_fd(concat!(stringify!(Nav9Rpm), "::jacobian"), &jac, &fd);
                assert_sparsity(
                    concat!(stringify!(Nav9Rpm), "::jacobian"),
                    &jac,
                    &<Nav9Rpm as Sensor<N, 3, S>>::JACOBIAN_SPARSITY,
                );
                true
            },
        );
    }
    #[test]
    fn sensor_rpm_innovation_terms_match_dense_products() {
        at_random_points(
            0x5eed_0003,
            |rng, x, u, p, dt| {
                let aux: <Nav9Rpm as Sensor<N, 3, S>>::Aux = random_record(rng);
                let cov = random_covariance(rng);
                let hjac = <Nav9Rpm as Sensor<N, 3, S>>::jacobian(&x, &u, &p, &aux);
                let pred = <Nav9Rpm as Sensor<N, 3, S>>::predict(&x, &u, &p, &aux);
                if !finite(&hjac) || !finite(&pred) {
                    return false;
                }
                let (h, pht, s) = <Nav9Rpm as Sensor<
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
