//! `nav-macros`: declarative estimator models with symbolic Jacobians, sparsity
//! and generated, allocation-free nalgebra code.
//!
//! Users write `nav_runtime::model! { .. }` (the macro is re-exported by
//! `nav-runtime`; generated code refers only to `::nav_runtime::..`, so a user
//! crate needs `nav-runtime` as its only dependency). This page is the language
//! reference.
//!
//! # A complete example
//!
//! ```ignore
//! nav_runtime::model! {
//!     /// Doc comments carry over to the generated type.
//!     pub model Leveling6 {
//!         states {
//!             /// body velocity, m/s
//!             velocity: 3,
//!             /// gravity direction in body axes
//!             a: 3,
//!         }
//!         inputs { gyro: 3, specific_force: 3, earth_rate_body: 3, c_bn: 3x3 }
//!         parameters { gravity }
//!         noise { accel_noise: 3, gyro_noise: 3 }
//!         continuous {
//!             let w_star = gyro + earth_rate_body;
//!             let w = gyro - earth_rate_body;
//!             d/dt velocity = -cross(w_star, velocity) + gravity * a + specific_force + accel_noise;
//!             d/dt a = -cross(w + gyro_noise, a);
//!         }
//!         sensor Moving: 2 {
//!             h = [velocity[0], norm_squared(a)];
//!         }
//!         sensor Compass: 1 {
//!             inputs { declination }
//!             angles = [0];
//!             let yaw = atan2(c_bn[(1, 0)], c_bn[(0, 0)]);
//!             h = [yaw + declination];
//!         }
//!     }
//! }
//! ```
//!
//! One invocation may hold several `model` declarations, and `block`s and
//! composed models (see "Blocks and composed models").
//!
//! # Sections
//!
//! A declaration is `[doc comments] [pub] model Name { sections }`. Sections
//! (and model-level `let`s, see below) may come in any order; each of `states`, `inputs`, `parameters`, `noise` appears
//! at most once, exactly one process section is required, `sensor` any number
//! of times.
//!
//! | section | meaning | becomes |
//! |---|---|---|
//! | `states { .. }` | the state `x` (at least one scalar) | `NameState`, `N` |
//! | `inputs { .. }` | inputs `u` known at each step (IMU, nominal solution, ..) | `NameInput` |
//! | `parameters { .. }` | constants `p` | `NameParams` |
//! | `noise { .. }` | process-noise inputs `w`; only in the process section | `NameNoise` (intensities `q`), `NW` |
//! | `continuous { .. }` | `dx/dt = f(x, u, p, w)` | `derivative`, `F`, `Phi = I + F dt` |
//! | `discrete { .. }` | `x_k = f(x_{k-1}, u, p, dt, w)` | `transition`, `Phi = df/dx` |
//! | `sensor Name: M { .. }` | a measurement `h(x, u, p, aux)` with `M` outputs | `NameSensorName` |
//! | `scalar f32;` | the scalar the code is generated for (`f64` when absent) | `Model<N, f32>`, `Ekf<Name, N, f32>` |
//! | `runs_with { [A, B], [A, B, C] }` | the sensor sets the model is meant to run with (all its sensors when absent) | `Name::RUNS_WITH` |
//! | `allow_unused { x, y[1] }` | state scalars meant to be seen by no sensor of some set (dead-reckoned) | checked at compile time |
//!
//! Entries of `states`, `inputs`, `parameters`, `noise` and sensor `inputs` are
//! comma-separated: `x` (scalar), `x: n` (vector), `x: RxC` (row-major matrix,
//! also `R x C`). Doc comments on entries become field docs. Every name is
//! unique across states, inputs, parameters, noise, model-level `let`s, the
//! process section's `let`s and each sensor's inputs and `let`s (different
//! sensors may reuse their own names); `dt` is reserved.
//!
//! ## Scalar type
//!
//! `scalar f32;` generates every record field, function and test of the
//! model in single precision (for flight computers without a double FPU);
//! the default is `f64`. The model then implements `Model<N, f32>` and its
//! sensors `Sensor<N, M, f32>`, and runs in `Ekf<Name, N, f32>` (the filter
//! core, gates and covariance kernels are generic; times stay `f32` in
//! `predict`, NIS values and thresholds are `f64`). Records keep their
//! `f64` `Record` interface (`from_fn`, `get`) for loggers and mappings.
//! The generated tests use a finite-difference step of `2e-3` and a
//! tolerance of `1e-3` in `f32` (`1e-6`, `1e-6` in `f64`), and `1e-4`
//! instead of `1e-12` for the sparse products. A composed model takes
//! `scalar f32;` among its options (`model X = A + B { scalar f32; }`); a
//! block has none. `f16` and other types are compile errors. See
//! `docs/language.md`, "Scalar type", for measured differences.
//!
//! ## States kept on a manifold
//!
//! Two state entries declare what the filter keeps a state on after every
//! predict and every accepted update (`Ekf::predict`, `Ekf::update`,
//! `Ekf::update_sequential`), through the generated
//! `Model::normalize_state` (a no-op for models without them):
//!
//! - `heading: angle`: a scalar angle (rad), wrapped to (-pi, pi]. (A sensor's
//!   `angles = [..]` wraps innovations; this wraps the state itself.)
//! - `q: quaternion`: a unit quaternion `[w, x, y, z]` (a 4-vector),
//!   renormalized to unit norm (left as it is if its norm is zero or not
//!   finite, which the filter's own checks then report).
//!
//! `angle` and `quaternion` mark states only; elsewhere they are an error.
//! Renormalizing fixes the norm drift of a first-order quaternion step, but a
//! full quaternion state keeps a covariance with a direction (along `q`) that
//! no measurement sees: for attitude, prefer the multiplicative error-state
//! pattern of `docs/language.md`.
//!
//! ## Model-level `let`
//!
//! `let name = expr;` beside the sections (not inside one) is evaluated once
//! and seen by the process section and by every sensor, e.g. a direction
//! cosine matrix used by several sensors:
//!
//! ```ignore
//! nav_runtime::model! {
//!     pub model Ahrs {
//!         states { q: quaternion }
//!         inputs { gyro: 3 }
//!         parameters { gravity, magnetic_field: 3 }
//!         noise { gyro_noise: 3 }
//!         let c_bn = quat_to_dcm(q);
//!         continuous { d/dt q = 0.5 * quat_mul(q, [0.0, gyro[0], gyro[1], gyro[2]]); }
//!         sensor Accel: 3 { h = transpose(c_bn) * [0.0, 0.0, -gravity]; }
//!         sensor Mag: 3 { h = transpose(c_bn) * magnetic_field; }
//!     }
//! }
//! ```
//!
//! A model-level `let` reads states, inputs, parameters and earlier
//! model-level `let`s; process noise is refused there (sensors would see it).
//! A `let` may stand at model level, in the process section or in a sensor;
//! anywhere else (inside `states { .. }`, at the top of the macro) is an error
//! that says so. A block may have block-level `let`s too: they join the
//! composed model's, visible to every section, and their names belong to
//! the block like its states (another block may not declare them, nor read
//! them through `needs`).
//!
//! ## Model functions
//!
//! `fn name(a, b) = expr;` beside the sections declares a small function,
//! inlined (scalarized and differentiated) wherever it is called, in the
//! process section, a sensor or a model-level `let`:
//!
//! ```ignore
//! fn body_axes(q, v) = transpose(quat_to_dcm(q)) * v;
//! sensor Accel: 3 { h = body_axes(q, [0.0, 0.0, -gravity]); }
//! ```
//!
//! Parameters take any shape (the body is checked for each call's shapes);
//! the body sees only its parameters and may call builtins and other model
//! functions, not itself. A function may not be named like a builtin. A
//! block may declare functions as well; they belong to the block like its
//! `let`s.
//!
//! ## Process sections
//!
//! - `continuous { .. }`: statements `let name = expr;` and `d/dt state = expr;`.
//!   A state without a `d/dt` line has zero derivative (a random constant).
//! - `discrete { .. }`: statements `let name = expr;` and `state = expr;`, where
//!   every right-hand side reads the previous values; `dt` is an implicit scalar.
//!   A state without a line keeps its value (identity row of `Phi`).
//!
//! Each state is assigned at most once, with an expression of its own shape.
//! Noise may appear anywhere in the process section; `f` is evaluated at
//! `w = 0` and `G = df/dw` is taken at `w = 0`, so noise may enter nonlinearly
//! (e.g. `-cross(w + gyro_noise, a)`).
//!
//! ## Sensors
//!
//! `sensor Name: M { .. }` contains, in any order:
//! - `inputs { .. }` (optional): auxiliary inputs of this sensor (lever arms, a
//!   transducer position); they form the type `ModelNameAux`, or `()` if absent;
//! - `angles = [i, ..];` (optional): components of `z - h` that are angles and
//!   are wrapped to (-pi, pi] by the filter (`Sensor::ANGLES`);
//! - `let name = expr;` (evaluated in order);
//! - `h = expr;` (required): a vector of length `M`, or a scalar if `M == 1`.
//!
//! Sensors see states, inputs, parameters, model-level `let`s and their own
//! inputs and `let`s; they do not see the process section's `let`s, and process noise in a sensor is an
//! error.
//!
//! # Blocks and composed models
//!
//! A vehicle is usually an INS core plus a sensor suite. Each part can be
//! declared once as a *block* and vehicles assembled from blocks in one line:
//!
//! ```ignore
//! nav_runtime::model! {
//!     /// The INS error-state core: states, the nominal solution as inputs, noise, dynamics.
//!     pub block InsCore {
//!         states { position_error: 3, velocity_error: 3, attitude_error: 3, accel_bias: 3, gyro_bias: 3 }
//!         inputs { latitude, height, velocity: 3, c_bn: 3x3, specific_force: 3 }
//!         noise { accel_noise: 3, gyro_noise: 3 }
//!         continuous { .. }
//!     }
//!     /// A sensor block: its own states and sensors, and what it reads from other blocks.
//!     pub block Depth {
//!         states { depth_bias }
//!         needs { position_error: 3 }
//!         sensor Depth: 1 { h = [position_error[2] - depth_bias]; }
//!     }
//! }
//!
//! nav_runtime::model! {
//!     pub model Auv = InsCore + Depth + Dvl + blocks::Compass;
//!     pub model Sdins25 = InsCore + Usbl + Depth + Dvl + Compass {
//!         order { position_error, velocity_error, .., usbl_misalignment }
//!     }
//!     pub model Submerged = InsCore + Depth + Dvl + Compass {
//!         allow_unused { position_error[1] }
//!     }
//! }
//! ```
//!
//! **Blocks.** `[doc comments] [pub] block Name { sections }` takes the sections
//! of a model, all optional (a block may have no states, e.g. a GNSS fix that
//! measures the core's position error), plus `needs { .. }`: the names the
//! block reads from other blocks (states, inputs or parameters), with their
//! shapes. A block is checked on its own when declared, its `needs` standing in
//! for the other blocks, so a mistake inside a block is reported once, at the
//! block; an unknown name hints at `needs`. A block without a process section
//! has random-constant states (zero rows of `F`); a block's `continuous` section
//! may give dynamics to the block's own states only (e.g. a Markov bias with its
//! own noise). A block generates nothing but a `macro_rules!` named after it
//! that re-emits its declaration (the standard way to let one macro invocation
//! see another's tokens); `pub` makes it visible in the whole crate
//! (`pub(crate) use`), other visibilities are kept. Blocks are therefore
//! imported and named like macros (`use blocks::{InsCore, Dvl};` or a path
//! `blocks::Dvl`). `#[macro_export] pub block ..` shares a block with other
//! crates (`use nav_blocks::{InsCore, Dvl};`, as the standard blocks of the
//! `nav-blocks` crate are used); in its own crate an exported block is not
//! nameable by path (a limit of macro-generated `macro_export` macros), so a
//! library of blocks lives in a crate of its own.
//!
//! **Composed models.** `[doc comments] [pub] model Name = A + B + ..;` or
//! `= A + B .. { order { .. } allow_unused { .. } }`. The blocks' macros are
//! called in turn and the last one hands every block's tokens back to `model!`,
//! which assembles one declaration and runs the ordinary pipeline on it, so a
//! composed model generates exactly what the same declaration written by hand
//! would (tested for SDINS-25 in `models/src/vehicles/sdins.rs`):
//! - states in block order, or in the order of `order { .. }`, which must list
//!   every state once; inputs, parameters and noise in block order; the process
//!   sections' statements concatenated; the sensors of all blocks;
//! - every name belongs to one block: two blocks declaring the same state (or
//!   input, ..) is an error at the second block of the composition; so is a
//!   block listed twice and two sensors of one name;
//! - every `needs` entry must be declared by another block of the model with the
//!   same shape, else an error at the entry ("block `Dvl` needs `c_bn`, which no
//!   block of `Auv` declares"): a block that needs an input the core does not
//!   provide, or reads a state of a block that is not included, does not compile;
//! - all process sections are `continuous` or all `discrete`;
//! - local `let`s of different blocks never clash (they are renamed if needed);
//! - **unused states are an error**, as in every model (see "Structural
//!   observability"); the error stands at the composed model's name and names
//!   the block of the state. `allow_unused { .. }` and `runs_with { .. }` are
//!   options of the composition (`model X = A + B { runs_with { [Dvl, Depth] } }`).
//!
//! # Structural observability
//!
//! A state scalar is *structurally observable* with a set of sensors if there
//! is a path from it to a measurement: some sensor of the set has a structural
//! nonzero of `H` in its column, or the derivative (a discrete model: the
//! step) of a state on such a path depends on it (`F[i][j] != 0`, `i != j`).
//! Only sparsity is used, so the test is necessary, not sufficient: a `false`
//! means no measurement of that set can ever correct the state (e.g. the
//! position of a DVL-only navigator, which is dead-reckoned), a `true` only
//! that sparsity does not exclude it (two biases that enter one measurement
//! only as their sum are both "observable" here and are not in fact; whether
//! a trajectory excites a state is a question for the data).
//!
//! Every model with at least one sensor is checked against the sensor sets it
//! declares it runs with, `runs_with { [Dvl, Depth], [Dvl, Depth, Usbl] }`
//! (one set of all its sensors when absent): a state scalar not observable
//! with some set is a compile error at the state's name, naming the sets,
//! unless `allow_unused { name, name[i], .. }` lists it (a whole state or one
//! component) as meant to be unobserved (dead-reckoned). A listed scalar that
//! every set observes is an error too, so the list stays true; a sensor name
//! in `runs_with` that the model does not declare is an error with a "did you
//! mean". A proc macro cannot emit a warning on stable Rust; an error with an
//! explicit, checked opt-out is what it can do honestly (a deprecation-lint
//! trick would give a warning that `-D warnings` turns into an error anyway,
//! and that is easy to scroll past). A model without sensors is not checked.
//!
//! The same data is generated for programs (see "What is generated"):
//! `Name::SENSORS`, `Name::SENSOR_DEPENDS`, `Name::RUNS_WITH`,
//! `Name::RUNS_WITH_OBSERVABLE`, the `const fn`
//! `Name::structurally_observable(&[bool; S]) -> [bool; N]` and per sensor
//! type `INDEX` and `OBSERVES`; `Name::UNUSED_STATES` names the scalars no
//! sensor at all observes. See `docs/language.md`, "Structural observability".
//!
//! # Expressions
//!
//! Straight-line arithmetic on scalars, vectors and matrices. Everything is
//! scalarized; no expression form allocates or loops at run time.
//!
//! | form | shapes |
//! |---|---|
//! | names, `1`, `2.5`, `1e-3` | as declared; literals are scalars |
//! | `a + b`, `a - b` | equal shapes, elementwise |
//! | `a * b` | scalar * any, any * scalar, matrix(r,c) * vector(c), matrix(r,c) * matrix(c,k) |
//! | `a / s` | any / scalar |
//! | `-a`, `(a)` | any |
//! | `[a, b, c]` | scalars -> vector; equal-length vectors -> matrix with those rows |
//! | `[[a, b], [c, d]]` | matrix literal (rows) |
//! | `v[i]`, `m[(i, j)]` | integer-literal indices, bounds-checked at expansion |
//! | `sin cos tan asin acos atan sqrt exp ln abs` `(x)` | scalar -> scalar |
//! | `atan2(y, x)` | scalars -> scalar (four-quadrant) |
//! | `powi(x, n)` | scalar, `n` an integer literal (may be negative) |
//! | `dot(a, b)` | equal-length vectors -> scalar |
//! | `cross(a, b)` | 3-vectors -> 3-vector |
//! | `skew(v)` | 3-vector -> 3x3 matrix with `skew(a) * b == cross(a, b)` |
//! | `norm_squared(v)`, `norm(v)` | vector -> scalar |
//! | `transpose(m)` | matrix(r,c) -> matrix(c,r) |
//! | `euler_dcm(roll, pitch, yaw)` | scalars -> `C_b^n`, the transpose of `C_n^b = C_x(roll) C_y(pitch) C_z(yaw)` (Z-Y-X Euler angles) |
//! | `dcm_to_euler(c)` | 3x3 `C_b^n` -> `[roll, pitch, yaw]`, the inverse of `euler_dcm` |
//! | `quat_mul(p, q)` | 4-vectors -> 4-vector, the Hamilton product `p ⊗ q` |
//! | `quat_to_dcm(q)` | unit 4-vector -> 3x3 `C_b^n` |
//! | `rotvec_to_quat(v)` | 3-vector (rad) -> unit 4-vector, the exponential map |
//! | `normalize(v)` | vector -> vector `v / norm(v)` |
//! | `min(a, b)`, `max(a, b)` | scalars -> scalar |
//! | `clamp(x, low, high)` | scalars -> scalar, `min(max(x, low), high)` |
//! | `sign(x)` | scalar -> 1, -1, or `x` itself for 0 (and NaN) |
//! | `meridian_radius(lat)`, `transverse_radius(lat)` | latitude (rad) -> the WGS-84 radii of curvature `R_M = a (1 - e²) / (1 - e² sin² lat)^1.5` and `R_N = a / sqrt(1 - e² sin² lat)`, m, as `nav_runtime::earth` computes them |
//!
//! **Rotations.** Quaternions are Hamilton, stored `[w, x, y, z]` (scalar
//! first), and rotate body to navigation axes like `C_b^n`:
//! `v_n = q ⊗ [0, v_b] ⊗ q^* = quat_to_dcm(q) * v_b`; `quat_to_dcm(p ⊗ q) =
//! quat_to_dcm(p) * quat_to_dcm(q)`, and the attitude kinematics are
//! `d/dt q = 0.5 * quat_mul(q, [0, w])` with `w` the body rate. `quat_to_dcm`
//! assumes a unit quaternion (`1 - 2(y² + z²)`, ..): apply `normalize` to one
//! that may not be. `dcm_to_euler(c)` is `[atan2(c21, c22), atan2(-c20,
//! sqrt(c21² + c22²)), atan2(c10, c00)]` (pitch in [-pi/2, pi/2]; singular at
//! ±pi/2). `rotvec_to_quat(v) = [cos(θ/2), sin(θ/2) v / θ]`, `θ = |v|`, is
//! built from `|v|²` so that it and its Jacobian are finite at `v = 0` (where
//! `dq/dv = [0; I/2]`): the error quaternion of the multiplicative
//! error-state pattern. All are scalarized and differentiated like every
//! other expression.
//!
//! **Non-smooth functions** have one-sided derivatives, so Jacobians never
//! hold NaN: `abs` differentiates to `sign(x)` (0 at the kink), `sign` to 0;
//! `min(a, b)` / `max(a, b)` to the derivative of the argument they select,
//! of the *first* argument at a tie (`min(x, 1)` at `x = 1` has derivative
//! 1); `clamp(x, low, high) = min(max(x, low), high)` therefore has
//! derivative 1 in `x` on `[low, high]` (boundaries included) and 0 outside.
//! `min` and `max` propagate NaN (unlike `f64::min`). The generated
//! finite-difference tests evaluate at random points, where a kink is met
//! with probability zero.
//!
//! `x^2` is Rust's exclusive or, and is refused with a hint towards
//! `powi(x, 2)`.
//!
//! Every function may also be written as a method of its first argument:
//! `x.sin()`, `y.atan2(x)`, `a.dot(b)`, `x.powi(2)`, `m.transpose()`. Generated
//! code calls `::nav_runtime::math::*` (std or libm), never `f64` methods.
//!
//! # Errors
//!
//! All mistakes of one declaration are reported together, each at its span:
//! unknown names (with "did you mean" by edit distance, ignoring case and
//! counting a swapped pair of letters as one edit), duplicated names, a
//! `d/dt` or assignment of a non-state, a state assigned twice, shape errors
//! ("cannot add 3-vector and scalar"), wrong argument counts, an `h` whose
//! length differs from `M`, noise used in a sensor, out-of-range indices and
//! angle components, and unsupported constructs (`if`, loops, closures,
//! `match`, blocks, macros, casts, field access, unknown functions, ..), each
//! named in its message.
//!
//! Generated type names are checked across the declarations of one
//! invocation: a sensor whose type (`ModelSensor`, `ModelSensorAux`) is also
//! generated by another declaration (`model Cart { sensor Fix .. }` beside
//! `model CartFix`) is one error at the sensor's name. Declarations in
//! different `model!` invocations are invisible to each other; there rustc
//! reports the duplicate type at the second invocation.
//!
//! # What is generated
//!
//! For `pub model Foo` with `N` state scalars and `NW` noise scalars:
//!
//! - `pub struct Foo;` implementing `nav_runtime::model::Model<N>` (`NAME`,
//!   `DISCRETE`, `STATE_NAMES`, `JACOBIAN_SPARSITY`, `OPS_*`,
//!   `ZERO_IS_FIXED`, `transition`, `jacobian`, `process_noise`,
//!   `propagate_covariance`, and for a model whose propagation runs the
//!   sparse row kernel (more than 12 states) `PROPAGATION`
//!   and `propagate_covariance_observed`, which hands the nonzeros of
//!   `C` (`Phi = I + C`) to a closure, for the smoother's recording;
//!   `Model<N, f32>` with `scalar f32;`, and `f32`
//!   wherever `f64` stands below), with inherent items:
//!   - `Foo::N`, `Foo::NW`, and one index constant per state block, the index
//!     of its first scalar in SCREAMING_CASE (`Foo::VELOCITY`);
//!   - `Foo::UNUSED_STATES`: the state scalars no sensor depends on (see
//!     "Structural observability");
//!   - `Foo::SENSORS: [&str; S]` (the sensor names in declaration order),
//!     `Foo::SENSOR_DEPENDS: [[bool; N]; S]` (the states each sensor's `h`
//!     depends on directly), `Foo::RUNS_WITH: [&[usize]; R]` (the declared
//!     sensor sets as indices into `SENSORS`), `Foo::RUNS_WITH_OBSERVABLE:
//!     [[bool; N]; R]`, `const fn Foo::structurally_observable(sensors:
//!     &[bool; S]) -> [bool; N]` and `Foo::sensor_index(name) -> Option<usize>`
//!     (see "Structural observability");
//!   - `Foo::derivative(x, u, p) -> SVector<f64, N>` and
//!     `Foo::derivative_with_noise(x, u, p, w)`: `dx/dt`, without and with an
//!     explicit noise sample `w: SVector<f64, NW>` (continuous models only; no
//!     `dt` argument: a derivative is not a step);
//!   - `Foo::step_with_noise(x, u, p, w, dt) -> SVector<f64, N>`: the state
//!     after `dt` seconds with the noise sample `w` (every model: the Euler
//!     step `x + f(x, u, p, w) dt` of a continuous model, `f(x, u, p, dt, w)`
//!     of a discrete one; `transition` at `w = 0`). Every generated function
//!     that takes `dt` and returns a state returns the state after the step;
//!   - `Foo::noise_jacobian(x, u, p, dt) -> SMatrix<f64, N, NW>` (`G = df/dw`
//!     of the derivative for a continuous model, where `dt` is unused, and of
//!     the step for a discrete one);
//!   - `normalize_state` in the `Model` impl if a state is declared `angle`
//!     or `quaternion` (see "States kept on a manifold");
//!   - `Foo::OPS_TRANSITION`, `OPS_DERIVATIVE`, `OPS_JACOBIAN`,
//!     `OPS_NOISE_JACOBIAN`, `OPS_PROCESS_NOISE`, `OPS_PROPAGATE_COVARIANCE`.
//!   - `ZERO_IS_FIXED` (in the `Model` impl) is `true` when every entry of
//!     the transition simplifies to zero at `x = 0` for any input and
//!     parameter, as in an error-state model; the filter then skips the
//!     transition of a zero state (exactly: it would return zero).
//! - `FooState`, `FooInput`, `FooParams`, `FooNoise`: structs with one public
//!   field per entry (`f64`, `SVector<f64, n>` or `SMatrix<f64, r, c>`),
//!   deriving `Clone, Copy, Debug, Default, PartialEq`, implementing
//!   `nav_runtime::model::Record` (empty structs if a section is absent);
//!   `FooState::from_vector(&SVector<f64, N>)` and `to_vector()`.
//! - For each `sensor Bar: M`: `pub struct FooBar;` implementing
//!   `nav_runtime::model::Sensor<N, M>` with `type Model = Foo` and `type Aux =
//!   FooBarAux` (or `()`), plus inherent `FooBar::M`, `NAME`, `OPS_PREDICT`,
//!   `OPS_JACOBIAN`, `OPS_INNOVATION_TERMS`.
//! - `#[cfg(test)] mod __foo_generated_tests`: tests of `jacobian`,
//!   `noise_jacobian` and every sensor's `jacobian` against central finite
//!   differences at seeded points uniform in [-1, 1] (splitmix64 inline; points
//!   with non-finite values are skipped; `|J - J_fd| <= 1e-6 (1 + |J|)` plus the
//!   rounding bound of the difference quotient), of `process_noise` and
//!   `propagate_covariance` against dense `G Q G^T` and `Phi P Phi^T + Qd`
//!   (and `propagate_covariance_observed` against it, with the coefficients
//!   it hands over rebuilding `Phi`), and
//!   of `innovation_terms` against dense `P H^T`, `H P H^T` (1e-12 relative,
//!   with a NaN lower triangle in `P` to prove only the upper one is read).
//!
//! Parameters may change at run time without rebuilding the filter:
//! `Ekf::set_params(params)` checks them as `Ekf::new` does (every scalar
//! finite) and leaves them unchanged on error.
//!
//! Generated items allow only the lints that misread generated code:
//! `clippy::possible_missing_comma` (every token of the expansion carries the
//! macro call's span, so multi-line array literals look like missing commas)
//! and `non_snake_case` where a name comes from the declaration.
//!
//! Conventions (see `nav_runtime::model`): continuous `Phi = I + F dt`,
//! `Qd = G Q G^T dt`; discrete `Phi = df/dx`, `Qd = G Q G^T`; `Q = diag(q)`.
//!
//! # How the code is derived
//!
//! Three stages, data flowing one way:
//!
//! - **Front end** (`src/front/`, syn): parse (`parse/`, including the grammar
//!   of compositions) -> check (`check.rs`, errors collected in `ctxt.rs`,
//!   spellings and suggestions in `names.rs`) -> lower to a hash-consed scalar
//!   DAG (`lower.rs`); blocks and compositions are assembled into one
//!   declaration first (`compose.rs`). After derivation, the structural
//!   observability of the declared sensor sets is checked against the
//!   sparsity of `H` and `F` (`observability.rs`).
//! - **Symbolic core** (`src/symbolic/`, no syn): the graph (`expr.rs`;
//!   constructors fold constants and drop `x + 0`, `x * 1`, `x * 0`, `x - x`,
//!   `--x`, ..) -> differentiate, memoized per (node, variable) (`diff.rs`) ->
//!   build `F`, `G`, `Qd`, `Phi P Phi^T + Qd` over symbols `P_ij` of the upper
//!   triangle, and per sensor `H`, `P H^T`, `H P H^T` (`derive.rs`) -> per
//!   generated function, strength reduction of its outputs in a graph of their
//!   own (`strength.rs`: a divisor shared by several divisions is inverted once,
//!   division by a constant becomes a multiplication, `tan` becomes `sin / cos`
//!   when those are computed anyway) -> one scheduling pass over all its
//!   outputs: nodes used twice become `let _tN` temporaries, `sin` and `cos` of
//!   one argument one `sin_cos` call (`cse.rs`); op counts (`ops.rs`).
//! - **Back end** (`src/back/`): emit the types, trait impls and inherent items
//!   (`emit.rs`) and the generated tests (`emit_tests.rs`).
//!
//! An entry of a Jacobian that simplifies to the literal 0 is a structural
//! zero: it is `false` in `JACOBIAN_SPARSITY` and never becomes code, and unit
//! entries of `Phi` cost nothing. The op count of a function (`OPS_*`, and
//! "Total ops: N" in its doc comment) is the number of arithmetic nodes
//! (`+ - * /`, negation, calls) it evaluates.
//!
//! The formatted expansions of the four paper models, with their op counts,
//! are committed under `nav-macros/snapshots/` and checked by the unit test
//! `snapshots_are_current`, so a change of the generator shows in review as a
//! diff of generated code (`UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib
//! snapshots` regenerates them).
#![warn(missing_docs)]

mod back;
mod front;
mod symbolic;

use proc_macro::TokenStream;

use front::{check, compose, ctxt, lower, names, parse};
use symbolic::derive;

/// Declares estimator models; see the crate documentation for the language.
#[proc_macro]
pub fn model(input: TokenStream) -> TokenStream {
    expand(input.into()).into()
}

/// Parse -> check -> lower -> derive -> emit, for every declaration of the input.
fn expand(input: proc_macro2::TokenStream) -> proc_macro2::TokenStream {
    let items = match syn::parse2::<parse::Declarations>(input) {
        Ok(parse::Declarations::Items(items)) => items,
        Ok(parse::Declarations::Step(step)) => {
            return compose::step(*step).unwrap_or_else(|e| e.to_compile_error())
        }
        Err(e) => return e.to_compile_error(),
    };
    let collisions = names::collisions(&items);
    let mut out = proc_macro2::TokenStream::new();
    for item in &items {
        match item {
            parse::Item::Model(decl) if collisions.contains_key(&decl.name.to_string()) => {
                out.extend(collisions[&decl.name.to_string()].to_compile_error());
            }
            parse::Item::Model(decl) => match expand_model(decl) {
                Ok(tokens) => out.extend(tokens),
                Err(e) => out.extend(e.to_compile_error()),
            },
            parse::Item::Block(block) => out.extend(compose::block(block)),
            parse::Item::Compose(c) => out.extend(compose::start(c)),
        }
    }
    out
}

/// Check, lower and derive one declaration.
fn derive_model(decl: &parse::ModelDecl) -> syn::Result<derive::Derived> {
    let cx = ctxt::Ctxt::new();
    check::check(&cx, decl);
    let lowered = lower::lower(&cx, decl);
    cx.check()?;
    let lowered = lowered.expect("a checked model has a process section");
    let nw = decl.noise.iter().map(|v| v.shape.len()).sum();
    Ok(derive::derive(lowered, nw))
}

fn expand_model(decl: &parse::ModelDecl) -> syn::Result<proc_macro2::TokenStream> {
    let derived = derive_model(decl)?;
    front::observability::check(decl, &derived, None)?;
    Ok(back::emit::model(decl, &derived))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The body of the first `nav_runtime::model! { .. }` in `source`.
    fn macro_body(source: &str) -> proc_macro2::TokenStream {
        let start = source
            .find("nav_runtime::model! {")
            .expect("a model! invocation");
        let file: syn::File = syn::parse_str(&source[start..]).expect("parses");
        match &file.items[0] {
            syn::Item::Macro(m) => m.mac.tokens.clone(),
            _ => panic!("expected a macro invocation"),
        }
    }

    /// Expands the workspace's SDINS-25 declaration (the largest model) in process.
    #[test]
    fn ins25_expansion_is_fast() {
        let body = macro_body(include_str!("../../models/src/sdins25/model.rs"));
        let start = std::time::Instant::now();
        let out = expand(body);
        let elapsed = start.elapsed();
        let text = out.to_string();
        assert!(!text.contains("compile_error"), "{text}");
        if std::env::var_os("NAV_MACROS_DUMP").is_some() {
            std::fs::write(std::env::temp_dir().join("ins25_expanded.rs"), &text).unwrap();
        }
        eprintln!("INS-25 expansion: {elapsed:?}, {} bytes", text.len());
        assert!(elapsed.as_secs_f64() < 5.0, "expansion took {elapsed:?}");
    }

    /// The paper models whose expansions are committed under `snapshots/`.
    const SNAPSHOTS: [(&str, &str); 4] = [
        ("sdins25", include_str!("../../models/src/sdins25/model.rs")),
        (
            "leveling",
            include_str!("../../models/src/leveling/model.rs"),
        ),
        ("vkf", include_str!("../../models/src/vkf/model.rs")),
        ("marker", include_str!("../../models/src/marker/model.rs")),
    ];

    /// The expansion of `source`'s model, formatted, after a header listing its
    /// op counts.
    fn snapshot(name: &str, source: &str) -> String {
        let out = expand(macro_body(source));
        let file: syn::File = syn::parse2(out).expect("the expansion parses as a file");
        let code = prettyplease::unparse(&file);
        let mut header = format!(
            "// Expansion of `nav_runtime::model!` in models/src/{name}/model.rs, formatted.\n\
             // Checked by `snapshots_are_current` (nav-macros/src/lib.rs); regenerate with\n\
             // `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`.\n//\n// Op counts:\n"
        );
        // The inherent `OPS_*` constants, under the type of their `impl` block.
        let mut owner = "";
        for line in code.lines() {
            if let Some(rest) = line.strip_prefix("impl ") {
                owner = rest.trim_end_matches(" {");
            }
            if let Some(rest) = line.trim().strip_prefix("pub const OPS_") {
                let rest = rest.trim_end_matches(';').replace(": usize", "");
                header.push_str(&format!("//   {owner}::OPS_{rest}\n"));
            }
        }
        header.push('\n');
        header + &code
    }

    /// The committed expansions match the generator: a change of the generated
    /// code shows in review as a diff of `snapshots/*.rs`.
    #[test]
    fn snapshots_are_current() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("snapshots");
        let update = std::env::var_os("UPDATE_SNAPSHOTS").is_some();
        let mut stale = Vec::new();
        for (name, source) in SNAPSHOTS {
            let text = snapshot(name, source);
            let path = dir.join(format!("{name}.rs"));
            if update {
                std::fs::create_dir_all(&dir).unwrap();
                std::fs::write(&path, &text).unwrap();
            } else if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
                stale.push(path.display().to_string());
            }
        }
        assert!(
            stale.is_empty(),
            "generated code changed: {stale:?}; review it and run `UPDATE_SNAPSHOTS=1 cargo test -p nav-macros --lib snapshots`"
        );
    }
}
