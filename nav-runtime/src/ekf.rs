//! The extended Kalman filter core: prediction, batch and sequential updates,
//! innovation gating and covariance repair for any [`Model`] and its [`Sensor`]s.
//!
//! Everything in this module is `core` only (no `std`, no heap): matrices are
//! `SMatrix` on the stack, factorizations are nalgebra's static Cholesky, and no
//! path in [`Ekf::predict`] or [`Ekf::update`] can panic (no `unwrap`, no
//! fallible indexing). Bad input is refused with a [`FilterError`] *before*
//! anything is mutated, so the filter state after an error is bit-identical to
//! the state before it.
//!
//! Equations (Bar-Shalom, Li & Kirubarajan 2001, ch. 5; Brown & Hwang,
//! *Introduction to Random Signals and Applied Kalman Filtering*, 4th ed., ch. 7):
//!
//! ```text
//! predict:  x <- f(x, u, p, dt)                        (model transition)
//!           P <- Phi P Phi^T + Qd                      (eq. P1)
//! update:   nu = z - h(x)       (angles wrapped)       (eq. U1)
//!           U  = P H^T,  S = H P H^T + R               (eq. U2)
//!           NIS = nu^T S^-1 nu  (gated against chi2(M)) (eq. U3)
//!           K  = U S^-1                                (eq. U4, by Cholesky solve)
//!           x <- x + K nu                              (eq. U5)
//!           P <- P - K U^T - U K^T + K S K^T           (eq. U6, Joseph form)
//! ```
//!
//! Eq. U6 is the Joseph form `(I - K H) P (I - K H)^T + K R K^T` expanded with
//! `U = P H^T`: it is valid for *any* gain (so rounding in `K` cannot make `P`
//! indefinite to first order) and costs O(N^2 M) instead of the O(N^3) of the
//! textbook product.

use core::any::TypeId;
use core::marker::PhantomData;

use nalgebra::{Cholesky, SMatrix, SVector};

use crate::gate::Gate;
use crate::lockout::Lockout;
use crate::math::wrap_angle;
use crate::model::{Model, Record, Sensor};

/// Why a filter operation was refused. After any of these the filter state
/// (`x`, `P`, last input) is unchanged; only the counters record the refusal.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
pub enum FilterError {
    /// The time step is zero, negative or not finite.
    #[error("time step {dt} s is not finite and positive")]
    InvalidTimeStep {
        /// The offending time step, in seconds.
        dt: f64,
    },
    /// An input scalar (IMU sample, nominal solution, ...) is NaN or infinite.
    #[error("input scalar {index} (`{name}`) is not finite")]
    NonFiniteInput {
        /// Index of the scalar in the input record.
        index: usize,
        /// Its declared name.
        name: &'static str,
    },
    /// A measurement component is NaN or infinite.
    #[error("measurement component {index} is not finite")]
    NonFiniteMeasurement {
        /// Index in the measurement vector.
        index: usize,
    },
    /// The measurement noise covariance is not finite, not symmetric or has a
    /// negative variance.
    #[error("measurement noise covariance is invalid: {reason}")]
    InvalidMeasurementNoise {
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A sensor auxiliary input is NaN or infinite.
    #[error("auxiliary input {index} (`{name}`) is not finite")]
    NonFiniteAux {
        /// Index of the scalar in the auxiliary record.
        index: usize,
        /// Its declared name.
        name: &'static str,
    },
    /// `S = H P H^T + R` has no Cholesky factor (singular or indefinite).
    #[error("innovation covariance of sensor `{sensor}` is not positive definite")]
    InnovationCovarianceNotPositiveDefinite {
        /// The sensor's declared name.
        sensor: &'static str,
    },
    /// The model or sensor functions produced NaN or infinity; nothing was stored.
    #[error("{stage} produced a non-finite value")]
    NonFiniteResult {
        /// Which computation: `"prediction"`, `"measurement model"`, `"update"`.
        stage: &'static str,
    },
    /// The initial state, covariance, parameters or noise densities are invalid.
    #[error("invalid filter setup: {reason}")]
    InvalidSetup {
        /// What is wrong.
        reason: &'static str,
    },
    /// A gate probability outside (0, 1).
    #[error("gate probability {probability} is not in (0, 1)")]
    InvalidProbability {
        /// The offending probability.
        probability: f64,
    },
    /// More per-sensor gate settings than [`MAX_SENSOR_GATES`].
    #[error("too many per-sensor gate settings (capacity {capacity})")]
    TooManySensorGates {
        /// The fixed capacity.
        capacity: usize,
    },
}

/// How a continuous model's transition matrix `Phi` and process noise `Qd` are
/// obtained over a step `dt`. Discrete models (`Model::DISCRETE`) always use the
/// model's own `Phi` and `Qd` and ignore this setting.
///
/// With `F` the continuous Jacobian and `Qc = G Q G^T` the continuous noise
/// covariance, the exact discretization is `Phi = exp(F dt)`,
/// `Qd = int_0^dt exp(F s) Qc exp(F s)^T ds` (Brown & Hwang, eqs. 3.9.20, 3.9.21).
/// The choice trades cost against the size of `||F dt||`:
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Discretization {
    /// `Phi = I + F dt`, `Qd = Qc dt`, through the generated sparse
    /// [`Model::propagate_covariance`] (structural zeros cost nothing). The
    /// truncation error is O((||F|| dt)^2) per step; right when `||F dt|| << 1`,
    /// e.g. an INS error model at 100 Hz (the Schuler frequency 1.24e-3 rad/s and
    /// Earth rate give `||F dt||` around 1e-5). The state uses the model's Euler
    /// transition. The default.
    #[default]
    FirstOrder,
    /// Dense `Phi = I + F dt + (F dt)^2 / 2` with the trapezoidal
    /// `Qd = (Phi Qc Phi^T + Qc) dt / 2`, and the state by Heun's method
    /// (second-order Runge-Kutta built from two model transitions). Error
    /// O((||F|| dt)^3) per step; for steps of about a second or where `F` has
    /// fast modes, at O(N^3) cost per step.
    SecondOrder,
    /// Exact (to rounding) `Phi` and `Qd` by Van Loan's method (C. F. Van Loan,
    /// "Computing integrals involving the matrix exponential", IEEE TAC 23(3),
    /// 1978): `exp([[-F, Qc], [0, F^T]] dt) = [[., E12], [0, E22]]`,
    /// `Phi = E22^T`, `Qd = Phi E12`. The exponential is a degree-16 Taylor
    /// series with scaling and squaring, evaluated on the three N x N blocks of
    /// the block-triangular 2N x 2N matrix, so it needs no `2N` const generic and
    /// allocates nothing. The state is integrated with classical Runge-Kutta 4.
    /// For long steps (1 s and more) or stiff dynamics; about 20 dense N x N
    /// products per block per step, so 10-100 times the cost of `SecondOrder`.
    VanLoan,
}

/// Totals kept by the filter. Per-sensor statistics are the caller's, from the
/// [`UpdateReport`]s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilterCounters {
    /// Predictions performed.
    pub predictions: u64,
    /// Predictions refused with an error.
    pub predictions_rejected: u64,
    /// Updates applied (passed the gate).
    pub updates_accepted: u64,
    /// Updates refused by the innovation gate (state unchanged, no error).
    pub updates_gated: u64,
    /// Updates refused with an error.
    pub updates_rejected: u64,
    /// Covariance diagonal entries repaired (non-positive or non-finite after a
    /// prediction or an update); each repaired entry counts once.
    pub covariance_repairs: u64,
    /// Gate lock-out releases: runs of refused measurements of one sensor
    /// that agreed within their noise, after which the covariance of the
    /// states they observe was inflated (see [`crate::lockout`]; no
    /// measurement is applied by a release).
    pub updates_released: u64,
}

/// The outcome of one measurement update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UpdateReport<const M: usize> {
    /// The sensor's declared name.
    pub sensor: &'static str,
    /// `true` if the update passed the gate and was applied.
    pub accepted: bool,
    /// Normalized innovation squared `nu^T S^-1 nu` (eq. U3), chi-square with M
    /// degrees of freedom for a consistent filter.
    pub nis: f64,
    /// The gate threshold that was applied, `None` if gating is disabled.
    pub threshold: Option<f64>,
    /// `nu = z - h(x)` with angle components wrapped to (-pi, pi] (eq. U1).
    pub innovation: SVector<f64, M>,
    /// `S = H P H^T + R` (eq. U2).
    pub innovation_covariance: SMatrix<f64, M, M>,
    /// Covariance diagonal entries repaired by this update.
    pub repairs: u32,
}

/// Number of sensors whose gate can be set individually on one filter.
pub const MAX_SENSOR_GATES: usize = 16;

/// The default lower bound a repaired variance is reset to when no positive
/// previous value exists (see [`Ekf::with_variance_floor`]).
pub const DEFAULT_VARIANCE_FLOOR: f64 = 1e-12;

/// A filter that can be propagated with an input sample: the interface the
/// multi-rate scheduler drives. Implemented by [`Ekf`] (input = the model input)
/// and by [`crate::error_state::ErrorStateFilter`] (input = an IMU sample that
/// also advances the nominal solution).
pub trait Propagate {
    /// One input sample, held constant over a propagation interval.
    type Input: Copy + core::fmt::Debug;
    /// Refuses a sample that could never be propagated (non-finite scalars).
    ///
    /// # Errors
    /// [`FilterError::NonFiniteInput`].
    fn check_input(input: &Self::Input) -> Result<(), FilterError>;
    /// Propagates over `dt` seconds with `input` held constant.
    ///
    /// # Errors
    /// As [`Ekf::predict`]; the filter is unchanged on error.
    fn propagate(&mut self, dt: f64, input: &Self::Input) -> Result<(), FilterError>;
}

/// A filter that can fuse measurements of the sensors of its model.
pub trait Estimator<const N: usize> {
    /// The process model.
    type Model: Model<N>;
    /// Batch update, as [`Ekf::update`].
    ///
    /// # Errors
    /// As [`Ekf::update`]; the filter is unchanged on error.
    fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Self::Model>;
    /// Sequential scalar update for diagonal `R`, as [`Ekf::update_sequential`].
    ///
    /// # Errors
    /// As [`Ekf::update_sequential`]; the filter is unchanged on error.
    fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Self::Model>;
}

/// An extended Kalman filter for model `Mo` with `N` states.
///
/// Holds the state `x`, its covariance `P` (kept exactly symmetric), the model
/// parameters and process-noise intensities, the last input (used by sensors
/// whose `h` depends on it), the discretization, the gates and the counters.
/// The whole filter is a plain value: cloning it is a checkpoint.
pub struct Ekf<Mo: Model<N>, const N: usize> {
    x: SVector<f64, N>,
    p: SMatrix<f64, N, N>,
    params: Mo::Params,
    noise: Mo::Noise,
    input: Mo::Input,
    discretization: Discretization,
    default_gate: Option<Gate>,
    gates: GateTable,
    /// Gate lock-out release state (see [`crate::lockout`]).
    pub(crate) lockout: Lockout,
    variance_floor: f64,
    counters: FilterCounters,
    _model: PhantomData<fn() -> Mo>,
}

impl<Mo: Model<N>, const N: usize> Ekf<Mo, N> {
    /// A filter at state `x0` with covariance `p0`.
    ///
    /// `p0` must be finite, symmetric (to 1e-9 relative; the upper triangle is
    /// then kept) with non-negative diagonal; `params` finite; `noise` finite and
    /// non-negative. Positive definiteness is not required (a perfectly known
    /// state may have zero variance), but such a state's zero variance is
    /// reported as a repair if an update drives it non-positive.
    /// Gating starts at [`Gate::default`] for every sensor, discretization at
    /// [`Discretization::FirstOrder`], the last input at `Default`.
    ///
    /// # Errors
    /// [`FilterError::InvalidSetup`] naming the first problem found.
    pub fn new(
        x0: SVector<f64, N>,
        p0: SMatrix<f64, N, N>,
        params: Mo::Params,
        noise: Mo::Noise,
    ) -> Result<Self, FilterError> {
        if !all_finite(x0.as_slice()) {
            return Err(FilterError::InvalidSetup {
                reason: "initial state is not finite",
            });
        }
        let p = checked_covariance(&p0)?;
        if first_non_finite(&params).is_some() {
            return Err(FilterError::InvalidSetup {
                reason: "a parameter is not finite",
            });
        }
        check_noise_intensities(&noise)?;
        Ok(Self {
            x: x0,
            p,
            params,
            noise,
            input: Mo::Input::default(),
            discretization: Discretization::FirstOrder,
            default_gate: Some(Gate::default()),
            gates: GateTable::new(),
            lockout: Lockout::new(),
            variance_floor: DEFAULT_VARIANCE_FLOOR,
            counters: FilterCounters::default(),
            _model: PhantomData,
        })
    }

    /// Sets the discretization of continuous models (see [`Discretization`]).
    #[must_use]
    pub fn with_discretization(mut self, discretization: Discretization) -> Self {
        self.discretization = discretization;
        self
    }

    /// Sets the gate used by sensors without their own setting; `None` disables it.
    #[must_use]
    pub fn with_default_gate(mut self, gate: Option<Gate>) -> Self {
        self.default_gate = gate;
        self
    }

    /// Sets the value a repaired variance falls back to when its previous value
    /// is not positive. Must be positive and finite; other values are ignored.
    #[must_use]
    pub fn with_variance_floor(mut self, floor: f64) -> Self {
        if floor.is_finite() && floor > 0.0 {
            self.variance_floor = floor;
        }
        self
    }

    /// Changes the discretization.
    pub fn set_discretization(&mut self, discretization: Discretization) {
        self.discretization = discretization;
    }

    /// Changes the gate of sensors without their own setting; `None` disables it.
    pub fn set_default_gate(&mut self, gate: Option<Gate>) {
        self.default_gate = gate;
    }

    /// Gives sensor `S` its own gate (`None`: no gating for `S`), overriding the
    /// default gate, like robot_localization's per-sensor rejection thresholds.
    ///
    /// # Errors
    /// [`FilterError::TooManySensorGates`] if [`MAX_SENSOR_GATES`] other sensors
    /// already have a setting.
    pub fn set_sensor_gate<S, const M: usize>(
        &mut self,
        gate: Option<Gate>,
    ) -> Result<(), FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        self.gates.set(TypeId::of::<S>(), gate)
    }

    /// The gate that applies to sensor `S` (its own setting, else the default).
    pub fn sensor_gate<S, const M: usize>(&self) -> Option<Gate>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        self.gates
            .get(TypeId::of::<S>())
            .unwrap_or(self.default_gate)
    }

    /// The state estimate.
    pub fn state(&self) -> &SVector<f64, N> {
        &self.x
    }

    /// The state estimate as the model's named record.
    pub fn state_record(&self) -> Mo::State {
        <Mo::State as Record>::from_fn(|i| self.x.get(i).copied().unwrap_or(f64::NAN))
    }

    /// The state covariance (symmetric).
    pub fn covariance(&self) -> &SMatrix<f64, N, N> {
        &self.p
    }

    /// The model parameters.
    pub fn params(&self) -> &Mo::Params {
        &self.params
    }

    /// The process-noise intensities.
    pub fn noise(&self) -> &Mo::Noise {
        &self.noise
    }

    /// The input of the last prediction (`Default` before the first one).
    pub fn input(&self) -> &Mo::Input {
        &self.input
    }

    /// The discretization in use.
    pub fn discretization(&self) -> Discretization {
        self.discretization
    }

    /// Running totals.
    pub fn counters(&self) -> &FilterCounters {
        &self.counters
    }

    /// Replaces the state estimate (e.g. the reset of an error-state filter).
    ///
    /// # Errors
    /// [`FilterError::InvalidSetup`] if `x` is not finite (state unchanged).
    pub fn set_state(&mut self, x: SVector<f64, N>) -> Result<(), FilterError> {
        if !all_finite(x.as_slice()) {
            return Err(FilterError::InvalidSetup {
                reason: "state is not finite",
            });
        }
        self.x = x;
        Ok(())
    }

    /// Sets the state estimate to zero: the reset of an error-state filter
    /// after feedback (see [`crate::error_state`]).
    pub fn reset_state(&mut self) {
        self.x = SVector::zeros();
    }

    /// Replaces the covariance, with the checks of [`Ekf::new`].
    ///
    /// # Errors
    /// [`FilterError::InvalidSetup`] (covariance unchanged).
    pub fn set_covariance(&mut self, p: SMatrix<f64, N, N>) -> Result<(), FilterError> {
        self.p = checked_covariance(&p)?;
        Ok(())
    }

    /// Replaces the process-noise intensities (finite, non-negative).
    ///
    /// # Errors
    /// [`FilterError::InvalidSetup`] (noise unchanged).
    pub fn set_noise(&mut self, noise: Mo::Noise) -> Result<(), FilterError> {
        check_noise_intensities(&noise)?;
        self.noise = noise;
        Ok(())
    }

    /// Replaces the parameters, checked as at construction (every scalar
    /// finite), e.g. a beacon position or a sound speed that changes at run
    /// time.
    ///
    /// # Errors
    /// [`FilterError::InvalidSetup`] (parameters unchanged).
    pub fn set_params(&mut self, params: Mo::Params) -> Result<(), FilterError> {
        if first_non_finite(&params).is_some() {
            return Err(FilterError::InvalidSetup {
                reason: "a parameter is not finite",
            });
        }
        self.params = params;
        Ok(())
    }

    /// Propagates state and covariance over `dt` seconds with `input` held
    /// constant (eq. P1), using [`Model::transition`] and, by default, the
    /// generated sparse [`Model::propagate_covariance`]; see [`Discretization`].
    /// The Jacobian is taken at the state before the step.
    ///
    /// # Errors
    /// [`FilterError::InvalidTimeStep`] if `dt` is not finite and positive,
    /// [`FilterError::NonFiniteInput`] for a NaN/infinite input scalar,
    /// [`FilterError::NonFiniteResult`] if the model produced NaN/infinity.
    /// The filter is unchanged in every case.
    pub fn predict(&mut self, dt: f64, input: &Mo::Input) -> Result<(), FilterError> {
        match self.predict_in_place(dt, input) {
            Ok(repairs) => {
                Mo::normalize_state(&mut self.x);
                self.input = *input;
                self.counters.predictions += 1;
                self.counters.covariance_repairs += u64::from(repairs);
                Ok(())
            }
            Err(e) => {
                self.counters.predictions_rejected += 1;
                Err(e)
            }
        }
    }

    /// Fuses measurement `z` of sensor `S` with noise covariance `r`.
    ///
    /// Computes the innovation (eq. U1, angle components wrapped per
    /// `S::ANGLES`), `(h, U = P H^T, H P H^T)` from the generated sparse
    /// [`Sensor::innovation_terms`], `S = H P H^T + R` and its Cholesky factor
    /// (never an explicit inverse), the NIS (eq. U3) and gates it against the
    /// chi-square threshold of the sensor's gate. If accepted, `K = U S^-1` by
    /// two triangular solves, `x += K nu` and the Joseph update (eq. U6) on the
    /// upper triangle, mirrored; then any covariance diagonal that is not
    /// positive and finite is repaired (see [`FilterCounters::covariance_repairs`]):
    /// reset to its value before the update (a valid upper bound, since an
    /// update can only reduce variance) or to the variance floor, with its row
    /// and column decorrelated so `P` stays positive semidefinite.
    ///
    /// A gated measurement is not an error: the report says `accepted: false`
    /// and the state is unchanged.
    ///
    /// # Errors
    /// Non-finite `z` or aux, invalid `r` (non-finite, asymmetric beyond 1e-9
    /// relative, negative variance), `S` not positive definite, or non-finite
    /// model output. The filter state is unchanged in every case.
    pub fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        match self.batch_update::<S, M>(z, r, aux) {
            Ok(report) => {
                self.count_gate_outcome(&report);
                if report.accepted {
                    Mo::normalize_state(&mut self.x);
                    self.counters.covariance_repairs += u64::from(report.repairs);
                }
                self.after_gate::<S, M>(&report, aux);
                Ok(report)
            }
            Err(e) => {
                self.counters.updates_rejected += 1;
                Err(e)
            }
        }
    }

    /// Fuses measurement `z` of sensor `S` as `M` scalar updates, one per row of
    /// `H` (from the dense [`Sensor::jacobian`] at the prior state), with no
    /// matrix inverse or factorization: each step divides by the scalar
    /// `s_i = h_i P h_i^T + r_i` (the scalar fusion of PX4's EKF2).
    ///
    /// **Valid only for diagonal `R`**, which is why the noise is given as its
    /// diagonal `r_diag`: with correlated noise the scalar updates would ignore
    /// the correlation. Each scalar innovation is corrected for the state change
    /// of the earlier rows, `e_i = nu_i - h_i (x_i - x_0)`, with `h` and `H`
    /// evaluated once at the prior as in the batch update, so the result equals
    /// [`Ekf::update`] to rounding (tested to 1e-12, linear and nonlinear `h`), and
    /// `sum_i e_i^2 / s_i` equals the batch NIS (the scalar innovations are the
    /// decorrelated batch innovation), which is what the gate tests. The
    /// gate decision is made on the whole vector before anything is stored.
    ///
    /// # Errors
    /// As [`Ekf::update`]; a non-positive `s_i` gives
    /// [`FilterError::InnovationCovarianceNotPositiveDefinite`].
    pub fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        let result = self.sequential_update::<S, M>(z, r_diag, aux);
        let report = self.commit(result)?;
        self.after_gate::<S, M>(&report, aux);
        Ok(report)
    }

    // ---- gate lock-out (crate::lockout): the one call of both updates ----
    /// Hands the gate's decision to the lock-out release, which may inflate
    /// `P` (see [`crate::lockout`]).
    fn after_gate<S, const M: usize>(&mut self, report: &UpdateReport<M>, aux: &S::Aux)
    where
        S: Sensor<N, M, Model = Mo>,
    {
        let (p, x, u, par) = (&mut self.p, &self.x, &self.input, &self.params);
        if self
            .lockout
            .after_gate::<S, N, M>(report, p, x, u, par, aux)
        {
            self.counters.updates_released += 1;
        }
    }
    // ---- end of gate lock-out ----

    /// Accepted/gated totals of one update that was not an error.
    fn count_gate_outcome<const M: usize>(&mut self, report: &UpdateReport<M>) {
        if report.accepted {
            self.counters.updates_accepted += 1;
        } else {
            self.counters.updates_gated += 1;
        }
    }

    /// Stores an update's result and keeps the totals.
    fn commit<const M: usize>(
        &mut self,
        result: Result<Proposal<N, M>, FilterError>,
    ) -> Result<UpdateReport<M>, FilterError> {
        match result {
            Ok(Proposal { report, posterior }) => {
                if let Some((x, p)) = posterior {
                    self.x = x;
                    Mo::normalize_state(&mut self.x);
                    self.p = p;
                    self.counters.covariance_repairs += u64::from(report.repairs);
                }
                self.count_gate_outcome(&report);
                Ok(report)
            }
            Err(e) => {
                self.counters.updates_rejected += 1;
                Err(e)
            }
        }
    }

    /// Propagates `x` and `P` in place (eq. P1); on error both are unchanged.
    /// Returns the number of repaired variances.
    ///
    /// The state is propagated into a temporary and checked first; `P` is
    /// propagated in place with one backup copy, which is restored if the
    /// result has a non-finite covariance.
    fn predict_in_place(&mut self, dt: f64, u: &Mo::Input) -> Result<u32, FilterError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(FilterError::InvalidTimeStep { dt });
        }
        if let Some(index) = first_non_finite(u) {
            return Err(FilterError::NonFiniteInput {
                index,
                name: name_of::<Mo::Input>(index),
            });
        }
        let not_finite = FilterError::NonFiniteResult {
            stage: "prediction",
        };
        let (par, q) = (&self.params, &self.noise);
        let method = if Mo::DISCRETE {
            Discretization::FirstOrder
        } else {
            self.discretization
        };
        let prev = self.p;
        let x_new = match method {
            Discretization::FirstOrder => {
                let x_new = Mo::transition(&self.x, u, par, dt);
                if !all_finite(x_new.as_slice()) {
                    return Err(not_finite);
                }
                // The generated propagation writes an exactly symmetric `P`
                // (it computes the upper triangle and mirrors it), so there
                // is nothing to mirror here.
                Mo::propagate_covariance(&mut self.p, &self.x, u, par, q, dt);
                x_new
            }
            Discretization::SecondOrder => {
                let f = Mo::jacobian(&self.x, u, par, dt);
                let qc = Mo::process_noise(&self.x, u, par, q, dt) / dt;
                let (phi, qd) = second_order(&f, &qc, dt);
                let x_new = heun::<Mo, N>(&self.x, u, par, dt);
                if !all_finite(x_new.as_slice()) {
                    return Err(not_finite);
                }
                self.p = phi * prev * phi.transpose() + qd;
                mirror_upper(&mut self.p);
                x_new
            }
            Discretization::VanLoan => {
                let f = Mo::jacobian(&self.x, u, par, dt);
                let qc = Mo::process_noise(&self.x, u, par, q, dt) / dt;
                let (phi, qd) = van_loan(&f, &qc, dt);
                let x_new = runge_kutta4::<Mo, N>(&self.x, u, par, dt);
                if !all_finite(x_new.as_slice()) {
                    return Err(not_finite);
                }
                self.p = phi * prev * phi.transpose() + qd;
                mirror_upper(&mut self.p);
                x_new
            }
        };
        let mut repairs = 0;
        if !covariance_is_clean(&self.p) {
            if !off_diagonal_finite(&self.p) {
                self.p = prev;
                return Err(not_finite);
            }
            repairs = repair_diagonal(&mut self.p, &prev.diagonal(), self.variance_floor);
        }
        self.x = x_new;
        Ok(repairs)
    }

    /// Eqs. U1-U6 with the generated sparse innovation terms.
    ///
    /// Stores the posterior in place if the update is accepted and succeeds;
    /// on error `x` and `P` are unchanged.
    fn batch_update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        check_measurement::<S, N, M>(z, aux)?;
        let r = checked_noise(r)?;
        let (h, u, hph) = S::innovation_terms(&self.p, &self.x, &self.input, &self.params, aux);
        if !(all_finite(h.as_slice()) && all_finite(u.as_slice()) && all_finite(hph.as_slice())) {
            return Err(FilterError::NonFiniteResult {
                stage: "measurement model",
            });
        }
        let nu = innovation::<S, N, M>(z, &h);
        let mut s = hph + r;
        mirror_upper(&mut s);
        let not_pd = FilterError::InnovationCovarianceNotPositiveDefinite { sensor: S::NAME };
        // S^-1 once (M x M, from the Cholesky factor): the NIS and the gain
        // are then products, cheaper than M + N triangular solve pairs.
        let s_inverse = Cholesky::new(s).ok_or(not_pd)?.inverse();
        let nis = nu.dot(&(s_inverse * nu));
        if !nis.is_finite() {
            return Err(not_pd);
        }
        let threshold = self.sensor_gate::<S, M>().map(|g| g.threshold(M));
        let mut report = UpdateReport {
            sensor: S::NAME,
            accepted: passes(nis, threshold),
            nis,
            threshold,
            innovation: nu,
            innovation_covariance: s,
            repairs: 0,
        };
        if !report.accepted {
            return Ok(report);
        }
        // K = U S^-1, eq. U4.
        let k = u * s_inverse;
        let x_new = self.x + k * nu;
        if !all_finite(x_new.as_slice()) {
            return Err(FilterError::NonFiniteResult { stage: "update" });
        }
        report.repairs = joseph_in_place(&mut self.p, &k, &u, &s, self.variance_floor)?;
        self.x = x_new;
        Ok(report)
    }

    /// Scalar sequential fusion for diagonal `R` (see [`Ekf::update_sequential`]).
    fn sequential_update<S, const M: usize>(
        &self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<Proposal<N, M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        check_measurement::<S, N, M>(z, aux)?;
        if !all_finite(r_diag.as_slice()) {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "not finite",
            });
        }
        if r_diag.iter().any(|v| *v < 0.0) {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "negative variance",
            });
        }
        let h = S::predict(&self.x, &self.input, &self.params, aux);
        let hm = S::jacobian(&self.x, &self.input, &self.params, aux);
        if !(all_finite(h.as_slice()) && all_finite(hm.as_slice())) {
            return Err(FilterError::NonFiniteResult {
                stage: "measurement model",
            });
        }
        let nu = innovation::<S, N, M>(z, &h);
        let not_pd = FilterError::InnovationCovarianceNotPositiveDefinite { sensor: S::NAME };

        // The batch S = H P H^T + R, for the report only.
        let mut s_full = hm * (self.p * hm.transpose());
        for i in 0..M {
            s_full[(i, i)] += r_diag[i];
        }
        mirror_upper(&mut s_full);

        let mut dx = SVector::<f64, N>::zeros();
        let mut p = self.p;
        let mut nis = 0.0;
        for i in 0..M {
            let hi = hm.row(i).transpose();
            let ui = p * hi;
            let si = hi.dot(&ui) + r_diag[i];
            if !(si.is_finite() && si > 0.0) {
                return Err(not_pd);
            }
            let mut ei = nu[i] - hi.dot(&dx);
            if S::ANGLES[i] {
                ei = wrap_angle(ei);
            }
            nis += ei * ei / si;
            let ki = ui / si;
            dx += ki * ei;
            // Scalar Joseph form: P - k u^T - u k^T + k s k^T (eq. U6, M = 1).
            let _ = joseph_lower(&mut p, &ki, &ui, &SMatrix::<f64, 1, 1>::new(si));
            mirror_lower(&mut p);
        }
        if !nis.is_finite() {
            return Err(not_pd);
        }
        let threshold = self.sensor_gate::<S, M>().map(|g| g.threshold(M));
        let mut report = UpdateReport {
            sensor: S::NAME,
            accepted: passes(nis, threshold),
            nis,
            threshold,
            innovation: nu,
            innovation_covariance: s_full,
            repairs: 0,
        };
        if !report.accepted {
            return Ok(Proposal {
                report,
                posterior: None,
            });
        }
        let x_new = self.x + dx;
        if !all_finite(x_new.as_slice()) {
            return Err(FilterError::NonFiniteResult { stage: "update" });
        }
        if !covariance_is_clean(&p) {
            if !off_diagonal_finite(&p) {
                return Err(FilterError::NonFiniteResult { stage: "update" });
            }
            report.repairs = repair_diagonal(&mut p, &self.p.diagonal(), self.variance_floor);
        }
        Ok(Proposal {
            report,
            posterior: Some((x_new, p)),
        })
    }
}

impl<Mo: Model<N>, const N: usize> Clone for Ekf<Mo, N> {
    fn clone(&self) -> Self {
        Self {
            x: self.x,
            p: self.p,
            params: self.params,
            noise: self.noise,
            input: self.input,
            discretization: self.discretization,
            default_gate: self.default_gate,
            gates: self.gates,
            lockout: self.lockout,
            variance_floor: self.variance_floor,
            counters: self.counters,
            _model: PhantomData,
        }
    }
}

impl<Mo: Model<N>, const N: usize> core::fmt::Debug for Ekf<Mo, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Ekf")
            .field("model", &Mo::NAME)
            .field("x", &self.x)
            .field("p", &self.p)
            .field("input", &self.input)
            .field("discretization", &self.discretization)
            .field("counters", &self.counters)
            .finish_non_exhaustive()
    }
}

impl<Mo: Model<N>, const N: usize> Propagate for Ekf<Mo, N> {
    type Input = Mo::Input;

    fn check_input(input: &Mo::Input) -> Result<(), FilterError> {
        match first_non_finite(input) {
            Some(index) => Err(FilterError::NonFiniteInput {
                index,
                name: name_of::<Mo::Input>(index),
            }),
            None => Ok(()),
        }
    }

    fn propagate(&mut self, dt: f64, input: &Mo::Input) -> Result<(), FilterError> {
        self.predict(dt, input)
    }
}

impl<Mo: Model<N>, const N: usize> Estimator<N> for Ekf<Mo, N> {
    type Model = Mo;

    fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        Ekf::update::<S, M>(self, z, r, aux)
    }

    fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        Ekf::update_sequential::<S, M>(self, z, r_diag, aux)
    }
}

/// Dense second-order discretization: `Phi = I + F dt + (F dt)^2 / 2` and the
/// trapezoidal `Qd = (Phi Qc Phi^T + Qc) dt / 2` (Brown & Hwang, sec. 7.2), with
/// `Qc = G Q G^T` the continuous noise covariance. Returns `(Phi, Qd)`.
pub fn second_order<const N: usize>(
    f: &SMatrix<f64, N, N>,
    qc: &SMatrix<f64, N, N>,
    dt: f64,
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let fdt = f * dt;
    let phi = SMatrix::<f64, N, N>::identity() + fdt + fdt * fdt * 0.5;
    let mut qd = (phi * qc * phi.transpose() + qc) * (0.5 * dt);
    mirror_upper(&mut qd);
    (phi, qd)
}

/// Van Loan's exact discretization (IEEE TAC 23(3), 1978): with
/// `A = [[-F, Qc], [0, F^T]] dt` and `exp(A) = [[E11, E12], [0, E22]]`,
/// `Phi = E22^T = exp(F dt)` and `Qd = Phi E12 = int_0^dt exp(F s) Qc exp(F s)^T ds`.
/// Returns `(Phi, Qd)`; `Qd` is symmetrized from its upper triangle.
///
/// The 2N x 2N exponential is computed on its three N x N blocks (block upper
/// triangular matrices are closed under products), by scaling `A` by `2^-s`
/// until its infinity norm is at most 1/2, a degree-16 Taylor polynomial
/// (truncation below 1e-19 relative) and `s` squarings. No allocation.
pub fn van_loan<const N: usize>(
    f: &SMatrix<f64, N, N>,
    qc: &SMatrix<f64, N, N>,
    dt: f64,
) -> (SMatrix<f64, N, N>, SMatrix<f64, N, N>) {
    let a = BlockUpper {
        a: -(f * dt),
        b: qc * dt,
        c: f.transpose() * dt,
    };
    let e = a.exp();
    let phi = e.c.transpose();
    let mut qd = phi * e.b;
    mirror_upper(&mut qd);
    (phi, qd)
}

/// The Joseph covariance update `P - K U^T - U K^T + K S K^T` (eq. U6) with
/// `U = P H^T` and `S = H P H^T + R`, which equals
/// `(I - K H) P (I - K H)^T + K R K^T` for any gain `K`. O(N^2 M) on one
/// triangle, then mirrored (see [`joseph_lower`]).
#[cfg(test)]
pub(crate) fn joseph_update<const N: usize, const M: usize>(
    p: &SMatrix<f64, N, N>,
    k: &SMatrix<f64, N, M>,
    u: &SMatrix<f64, N, M>,
    s: &SMatrix<f64, M, M>,
) -> SMatrix<f64, N, N> {
    let mut out = *p;
    let _ = joseph_lower(&mut out, k, u, s);
    mirror_lower(&mut out);
    out
}

/// The lower triangle (diagonal included) of the Joseph update (eq. U6),
/// computed in place; the strict upper triangle of `p` is left as it was.
/// Returns `true` if the result needs no repair (every entry finite, every
/// variance positive), checked in the same pass; `false` may also mean that a
/// checksum overflowed, so the caller then checks exactly.
///
/// With `W = K S - U`, eq. U6 is `P - K U^T + W K^T` (`K S K^T - U K^T =
/// W K^T`), so column `c` of the result is
/// `P[:, c] - sum_m K[:, m] U[c, m] + sum_m W[:, m] K[c, m]`: one loop over
/// the contiguous rows `c..N` of the column (`P`, `K`, `W` are column-major),
/// which the compiler vectorizes. Each entry reads only its own prior value,
/// so the prior's upper triangle (equal to its lower one, `P` being exactly
/// symmetric) stays available to undo the update.
#[inline(always)]
fn joseph_lower<const N: usize, const M: usize>(
    p: &mut SMatrix<f64, N, N>,
    k: &SMatrix<f64, N, M>,
    u: &SMatrix<f64, N, M>,
    s: &SMatrix<f64, M, M>,
) -> bool {
    let w = k * s - u;
    let (kd, ud, wd) = (&k.data.0, &u.data.0, &w.data.0);
    // Row sums of the result: finite if every entry is (an overflowing sum
    // merely sends the caller to the exact slow path).
    let mut acc = [0.0f64; N];
    let mut diagonal_ok = true;
    // Coefficients of column `c`: `U[c, m]` and `K[c, m]`.
    let coefficients = |c: usize| {
        let mut a = [0.0f64; M];
        let mut b = [0.0f64; M];
        for m in 0..M {
            a[m] = ud[m][c];
            b[m] = kd[m][c];
        }
        (a, b)
    };
    let cols = &mut p.data.0;
    // Two columns per pass share the loads of the rows of `K` and `W`.
    let mut c = 0;
    while c + 1 < N {
        let (a0, b0) = coefficients(c);
        let (a1, b1) = coefficients(c + 1);
        let (left, right) = cols.split_at_mut(c + 1);
        let (Some(col0), Some(col1)) = (left.last_mut(), right.first_mut()) else {
            break;
        };
        let mut v = col0[c];
        for m in 0..M {
            v += wd[m][c] * b0[m] - kd[m][c] * a0[m];
        }
        col0[c] = v;
        acc[c] += v;
        for r in c + 1..N {
            let (mut v0, mut v1) = (col0[r], col1[r]);
            for m in 0..M {
                let (k_r, w_r) = (kd[m][r], wd[m][r]);
                v0 += w_r * b0[m] - k_r * a0[m];
                v1 += w_r * b1[m] - k_r * a1[m];
            }
            col0[r] = v0;
            col1[r] = v1;
            acc[r] += v0 + v1;
        }
        diagonal_ok &= col0[c] > 0.0 && col0[c] <= f64::MAX;
        diagonal_ok &= col1[c + 1] > 0.0 && col1[c + 1] <= f64::MAX;
        c += 2;
    }
    if c + 1 == N {
        let (a, b) = coefficients(c);
        if let Some(col) = cols.last_mut() {
            let mut v = col[c];
            for m in 0..M {
                v += wd[m][c] * b[m] - kd[m][c] * a[m];
            }
            col[c] = v;
            acc[c] += v;
            diagonal_ok &= v > 0.0 && v <= f64::MAX;
        }
    }
    diagonal_ok && acc.iter().all(|x| x.is_finite())
}

crate::dispatch::avx_dispatch! {
    /// Eq. U6 stored in `p` in place, with the checks and repairs of
    /// [`Ekf::update`]; returns the number of repaired variances.
    ///
    /// The lower triangle is computed over the prior's (see [`joseph_lower`])
    /// and checked in one pass; only then is it mirrored. If an off-diagonal
    /// entry is not finite, the prior is restored exactly (its upper triangle
    /// and its saved diagonal) and the update is refused. Runs compiled for
    /// AVX where the CPU has it (bit-identical results).
    fn joseph_in_place<const N: usize, const M: usize>(
        p: &mut SMatrix<f64, N, N>,
        k: &SMatrix<f64, N, M>,
        u: &SMatrix<f64, N, M>,
        s: &SMatrix<f64, M, M>,
        floor: f64,
    ) -> Result<u32, FilterError> => joseph_in_place_steps;
}

/// The body of [`joseph_in_place`].
#[inline(always)]
fn joseph_in_place_steps<const N: usize, const M: usize, const AVX: bool>(
    p: &mut SMatrix<f64, N, N>,
    k: &SMatrix<f64, N, M>,
    u: &SMatrix<f64, N, M>,
    s: &SMatrix<f64, M, M>,
    floor: f64,
) -> Result<u32, FilterError> {
    let prior_diagonal = p.diagonal();
    if joseph_lower(p, k, u, s) {
        mirror_lower(p);
        return Ok(0);
    }
    if !off_diagonal_finite(p) {
        for (i, d) in prior_diagonal.iter().enumerate() {
            p[(i, i)] = *d;
        }
        mirror_upper(p);
        return Err(FilterError::NonFiniteResult { stage: "update" });
    }
    mirror_lower(p);
    Ok(repair_diagonal(p, &prior_diagonal, floor))
}

/// A computed update not yet stored: the report and, if accepted, `(x, P)`.
struct Proposal<const N: usize, const M: usize> {
    report: UpdateReport<M>,
    posterior: Option<(SVector<f64, N>, SMatrix<f64, N, N>)>,
}

/// Per-sensor gate settings keyed by the sensor type, in a fixed array.
#[derive(Clone, Copy, Debug)]
struct GateTable {
    entries: [Option<(TypeId, Option<Gate>)>; MAX_SENSOR_GATES],
}

impl GateTable {
    fn new() -> Self {
        Self {
            entries: [None; MAX_SENSOR_GATES],
        }
    }

    fn get(&self, id: TypeId) -> Option<Option<Gate>> {
        self.entries
            .iter()
            .flatten()
            .find(|(k, _)| *k == id)
            .map(|(_, g)| *g)
    }

    fn set(&mut self, id: TypeId, gate: Option<Gate>) -> Result<(), FilterError> {
        if let Some(slot) = self.entries.iter_mut().flatten().find(|(k, _)| *k == id) {
            slot.1 = gate;
            return Ok(());
        }
        match self.entries.iter_mut().find(|e| e.is_none()) {
            Some(slot) => {
                *slot = Some((id, gate));
                Ok(())
            }
            None => Err(FilterError::TooManySensorGates {
                capacity: MAX_SENSOR_GATES,
            }),
        }
    }
}

/// A 2N x 2N block upper-triangular matrix `[[a, b], [0, c]]`.
#[derive(Clone, Copy)]
struct BlockUpper<const N: usize> {
    a: SMatrix<f64, N, N>,
    b: SMatrix<f64, N, N>,
    c: SMatrix<f64, N, N>,
}

impl<const N: usize> BlockUpper<N> {
    fn identity() -> Self {
        Self {
            a: SMatrix::identity(),
            b: SMatrix::zeros(),
            c: SMatrix::identity(),
        }
    }

    /// `[[a1, b1], [0, c1]] [[a2, b2], [0, c2]] = [[a1 a2, a1 b2 + b1 c2], [0, c1 c2]]`.
    fn mul(&self, o: &Self) -> Self {
        Self {
            a: self.a * o.a,
            b: self.a * o.b + self.b * o.c,
            c: self.c * o.c,
        }
    }

    fn scale(&self, k: f64) -> Self {
        Self {
            a: self.a * k,
            b: self.b * k,
            c: self.c * k,
        }
    }

    /// Infinity norm (maximum absolute row sum) of the full 2N x 2N matrix.
    fn norm_inf(&self) -> f64 {
        let mut n: f64 = 0.0;
        for r in 0..N {
            let top: f64 = (0..N)
                .map(|c| self.a[(r, c)].abs() + self.b[(r, c)].abs())
                .sum();
            let bottom: f64 = (0..N).map(|c| self.c[(r, c)].abs()).sum();
            n = n.max(top).max(bottom);
        }
        n
    }

    /// `exp(self)` by scaling and squaring of a degree-16 Taylor polynomial
    /// (Moler & Van Loan, "Nineteen dubious ways...", SIAM Review 45(1), 2003,
    /// method 3): with `||A / 2^s|| <= 1/2` the remainder is below
    /// `0.5^17 / 17!`, about 2e-20.
    fn exp(&self) -> Self {
        const DEGREE: u32 = 16;
        const MAX_SQUARINGS: i32 = 64;
        let norm = self.norm_inf();
        let mut squarings = 0;
        if norm.is_finite() && norm > 0.5 {
            squarings = (libm::ceil(libm::log2(norm / 0.5)) as i32).clamp(0, MAX_SQUARINGS);
        }
        let scaled = self.scale(libm::pow(2.0, -f64::from(squarings)));
        // Horner: I + A (I + A/2 (I + A/3 (...))).
        let mut r = Self::identity();
        for k in (1..=DEGREE).rev() {
            let t = scaled.mul(&r).scale(1.0 / f64::from(k));
            r = Self {
                a: t.a + SMatrix::identity(),
                b: t.b,
                c: t.c + SMatrix::identity(),
            };
        }
        for _ in 0..squarings {
            r = r.mul(&r);
        }
        r
    }
}

/// Heun's method from model transitions: with `x1 = T(x)` (Euler),
/// `x + dt (f(x) + f(x1)) / 2 = (x + T(x1)) / 2`.
fn heun<Mo: Model<N>, const N: usize>(
    x: &SVector<f64, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    dt: f64,
) -> SVector<f64, N> {
    let x1 = Mo::transition(x, u, p, dt);
    (x + Mo::transition(&x1, u, p, dt)) * 0.5
}

/// Classical Runge-Kutta 4 from model transitions: `f(y) dt = T(y) - y`.
fn runge_kutta4<Mo: Model<N>, const N: usize>(
    x: &SVector<f64, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    dt: f64,
) -> SVector<f64, N> {
    let step = |y: &SVector<f64, N>| Mo::transition(y, u, p, dt) - y;
    let d1 = step(x);
    let d2 = step(&(x + d1 * 0.5));
    let d3 = step(&(x + d2 * 0.5));
    let d4 = step(&(x + d3));
    x + (d1 + (d2 + d3) * 2.0 + d4) / 6.0
}

/// `nu = z - h`, angle components wrapped to (-pi, pi] (eq. U1).
fn innovation<S, const N: usize, const M: usize>(
    z: &SVector<f64, M>,
    h: &SVector<f64, M>,
) -> SVector<f64, M>
where
    S: Sensor<N, M>,
{
    let mut nu = z - h;
    for (v, angle) in nu.iter_mut().zip(S::ANGLES.iter()) {
        if *angle {
            *v = wrap_angle(*v);
        }
    }
    nu
}

/// Refuses a non-finite measurement or auxiliary input.
fn check_measurement<S, const N: usize, const M: usize>(
    z: &SVector<f64, M>,
    aux: &S::Aux,
) -> Result<(), FilterError>
where
    S: Sensor<N, M>,
{
    if let Some(index) = z.iter().position(|v| !v.is_finite()) {
        return Err(FilterError::NonFiniteMeasurement { index });
    }
    if let Some(index) = first_non_finite(aux) {
        return Err(FilterError::NonFiniteAux {
            index,
            name: name_of::<S::Aux>(index),
        });
    }
    Ok(())
}

/// `r` checked (finite, symmetric to 1e-9 relative, non-negative variances)
/// and made exactly symmetric from its upper triangle.
fn checked_noise<const M: usize>(
    r: &SMatrix<f64, M, M>,
) -> Result<SMatrix<f64, M, M>, FilterError> {
    if !all_finite(r.as_slice()) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "not finite",
        });
    }
    if (0..M).any(|i| r[(i, i)] < 0.0) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "negative variance",
        });
    }
    if !is_symmetric(r) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "not symmetric",
        });
    }
    let mut r = *r;
    mirror_upper(&mut r);
    Ok(r)
}

/// An initial covariance checked like [`checked_noise`].
fn checked_covariance<const N: usize>(
    p: &SMatrix<f64, N, N>,
) -> Result<SMatrix<f64, N, N>, FilterError> {
    if !all_finite(p.as_slice()) {
        return Err(FilterError::InvalidSetup {
            reason: "covariance is not finite",
        });
    }
    if (0..N).any(|i| p[(i, i)] < 0.0) {
        return Err(FilterError::InvalidSetup {
            reason: "covariance has a negative variance",
        });
    }
    if !is_symmetric(p) {
        return Err(FilterError::InvalidSetup {
            reason: "covariance is not symmetric",
        });
    }
    let mut p = *p;
    mirror_upper(&mut p);
    Ok(p)
}

/// Process-noise intensities must be finite and non-negative.
fn check_noise_intensities<R: Record>(q: &R) -> Result<(), FilterError> {
    if (0..R::LEN).any(|i| !(q.get(i).is_finite() && q.get(i) >= 0.0)) {
        return Err(FilterError::InvalidSetup {
            reason: "a noise intensity is negative or not finite",
        });
    }
    Ok(())
}

/// Symmetric to 1e-9 relative to the larger of the entry pair and the
/// geometric mean of the two variances.
fn is_symmetric<const N: usize>(m: &SMatrix<f64, N, N>) -> bool {
    (0..N).all(|c| {
        (0..c).all(|r| {
            let (a, b) = (m[(r, c)], m[(c, r)]);
            let scale = a
                .abs()
                .max(b.abs())
                .max(libm::sqrt((m[(r, r)] * m[(c, c)]).abs()));
            (a - b).abs() <= 1e-9 * scale
        })
    })
}

crate::dispatch::avx_dispatch! {
    /// `true` if every entry of `p` is finite and every diagonal entry positive:
    /// the common case, in which nothing needs repairing. One branch-free,
    /// vectorizable pass: the sum of all entries is finite if they all are (a sum
    /// that overflows merely sends the caller to the exact slow path,
    /// [`off_diagonal_finite`] and [`repair_diagonal`]).
    /// Runs compiled for AVX where the CPU has it.
    fn covariance_is_clean<const N: usize>(p: &SMatrix<f64, N, N>) -> bool => covariance_is_clean_pass;
}

/// The pass of [`covariance_is_clean`].
#[inline(always)]
fn covariance_is_clean_pass<const N: usize, const AVX: bool>(p: &SMatrix<f64, N, N>) -> bool {
    let mut acc = [0.0f64; 8];
    let mut chunks = p.as_slice().chunks_exact(8);
    for chunk in &mut chunks {
        for (a, x) in acc.iter_mut().zip(chunk) {
            *a += x;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += x;
    }
    let mut diagonal_ok = true;
    for (i, col) in p.data.0.iter().enumerate() {
        let d = col[i];
        diagonal_ok &= d > 0.0 && d <= f64::MAX;
    }
    diagonal_ok && acc.iter().sum::<f64>().is_finite()
}

/// `true` if every entry below the diagonal of `p` is finite (for a symmetric
/// `p`, every off-diagonal entry). A non-finite off-diagonal entry cannot be
/// repaired meaningfully: the prediction or update is refused.
fn off_diagonal_finite<const N: usize>(p: &SMatrix<f64, N, N>) -> bool {
    p.as_slice()
        .chunks_exact(N)
        .enumerate()
        .all(|(c, col)| col.get(c + 1..).is_none_or(all_finite))
}

/// Repairs the diagonal of a symmetric covariance after a prediction or
/// update (see [`Ekf::update`]): each variance that is not positive and
/// finite is reset to its previous value `prev[i]` (if above `floor`) or to
/// `floor`, with its row and column zeroed. Returns the number repaired.
fn repair_diagonal<const N: usize>(
    p: &mut SMatrix<f64, N, N>,
    prev: &SVector<f64, N>,
    floor: f64,
) -> u32 {
    let mut repairs = 0;
    for i in 0..N {
        let d = p[(i, i)];
        if d.is_finite() && d > 0.0 {
            continue;
        }
        let before = prev[i];
        let value = if before.is_finite() && before > floor {
            before
        } else {
            floor
        };
        for j in 0..N {
            p[(i, j)] = 0.0;
            p[(j, i)] = 0.0;
        }
        p[(i, i)] = value;
        repairs += 1;
    }
    repairs
}

/// The gate decision: `nis <= threshold`, always true without a gate. A NaN
/// NIS never passes (it is refused as an error before this point anyway).
fn passes(nis: f64, threshold: Option<f64>) -> bool {
    match threshold {
        Some(t) => nis <= t,
        None => true,
    }
}

/// Copies the upper triangle onto the lower one.
fn mirror_upper<const N: usize>(m: &mut SMatrix<f64, N, N>) {
    for c in 0..N {
        for r in 0..c {
            m[(c, r)] = m[(r, c)];
        }
    }
}

/// Copies the lower triangle onto the upper one.
fn mirror_lower<const N: usize>(m: &mut SMatrix<f64, N, N>) {
    for c in 0..N {
        for r in 0..c {
            m[(r, c)] = m[(c, r)];
        }
    }
}

/// `true` if every element is finite. Branch-free over chunks of four (`x * 0`
/// is zero for a finite `x` and NaN otherwise, and NaN survives the sums), so
/// the check vectorizes.
fn all_finite(v: &[f64]) -> bool {
    let mut acc = [0.0f64; 4];
    let mut chunks = v.chunks_exact(4);
    for chunk in &mut chunks {
        for (a, x) in acc.iter_mut().zip(chunk) {
            *a += x * 0.0;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += x * 0.0;
    }
    acc.iter().all(|a| *a == 0.0)
}

/// Index of the first non-finite scalar of a record.
pub(crate) fn first_non_finite<R: Record>(r: &R) -> Option<usize> {
    (0..R::LEN).find(|&i| !r.get(i).is_finite())
}

/// Declared name of scalar `index` of a record.
pub(crate) fn name_of<R: Record>(index: usize) -> &'static str {
    R::NAMES.get(index).copied().unwrap_or("?")
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::testmodels::{
        Angle, Cvb, CvbInput, CvbNoise, Dcv, DcvNoise, Gauss, Offset, Osc, OscNoise, OscParams,
        Pos, PosVel, Quad,
    };

    type M3 = SMatrix<f64, 3, 3>;
    type V3 = SVector<f64, 3>;

    const NOISE: CvbNoise = CvbNoise {
        q_a: 1e-2,
        q_b: 1e-5,
    };

    fn p0() -> M3 {
        M3::new(4.0, 0.3, 0.01, 0.3, 0.5, -0.02, 0.01, -0.02, 0.01)
    }

    fn filter() -> Ekf<Cvb, 3> {
        Ekf::new(V3::new(1.0, -0.5, 0.1), p0(), (), NOISE).unwrap()
    }

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / (1.0 + a.abs().max(b.abs()))
    }

    fn max_rel<const R: usize, const C: usize>(
        a: &SMatrix<f64, R, C>,
        b: &SMatrix<f64, R, C>,
    ) -> f64 {
        (a - b).amax() / (1.0 + a.amax().max(b.amax()))
    }

    /// Bitwise identity of state, covariance and last input.
    fn same_bits(a: &Ekf<Cvb, 3>, b: &Ekf<Cvb, 3>) -> bool {
        let bits = |e: &Ekf<Cvb, 3>| {
            let mut v: Vec<u64> = e
                .state()
                .iter()
                .chain(e.covariance().iter())
                .map(|x| x.to_bits())
                .collect();
            v.push(e.input().a.to_bits());
            v
        };
        bits(a) == bits(b)
    }

    /// A random SPD prior `P`, `H`, SPD `R`, and `U = P H^T`, `S = H U + R`.
    #[allow(clippy::type_complexity)]
    fn random_update<const N: usize, const M: usize>(
        g: &mut Gauss,
    ) -> (
        SMatrix<f64, N, N>,
        SMatrix<f64, M, N>,
        SMatrix<f64, M, M>,
        SMatrix<f64, N, M>,
        SMatrix<f64, M, M>,
    ) {
        let p: SMatrix<f64, N, N> = g.spd(0.1);
        let h = SMatrix::<f64, M, N>::from_fn(|_, _| g.normal());
        let r: SMatrix<f64, M, M> = g.spd(0.05);
        let u = p * h.transpose();
        let s = h * u + r;
        (p, h, r, u, s)
    }

    #[test]
    fn joseph_equals_textbook_for_any_gain_and_standard_form_for_optimal_gain() {
        let mut g = Gauss::new(1);
        for _ in 0..50 {
            let (p, h, r, u, s) = random_update::<5, 2>(&mut g);
            let i5 = SMatrix::<f64, 5, 5>::identity();
            // Random suboptimal gain.
            let k = SMatrix::<f64, 5, 2>::from_fn(|_, _| g.normal());
            let textbook = (i5 - k * h) * p * (i5 - k * h).transpose() + k * r * k.transpose();
            let got = joseph_update(&p, &k, &u, &s);
            assert!(
                max_rel(&got, &textbook) < 1e-12,
                "{}",
                max_rel(&got, &textbook)
            );
            // Optimal gain: equals (I - K H) P.
            let k_opt = u * s.try_inverse().unwrap();
            let standard = (i5 - k_opt * h) * p;
            let got = joseph_update(&p, &k_opt, &u, &s);
            assert!(
                max_rel(&got, &standard) < 1e-12,
                "{}",
                max_rel(&got, &standard)
            );
            assert_eq!(got, got.transpose());
        }
    }

    #[test]
    fn joseph_vector_width_never_changes_a_bit() {
        let mut g = Gauss::new(7);
        for _ in 0..20 {
            let (p, _, _, u, s) = random_update::<25, 3>(&mut g);
            let k = u * s.try_inverse().unwrap();
            let (mut dispatched, mut portable) = (p, p);
            let a = joseph_in_place(&mut dispatched, &k, &u, &s, 0.0);
            let b = joseph_in_place_steps::<25, 3, false>(&mut portable, &k, &u, &s, 0.0);
            assert_eq!(a, b);
            assert!(dispatched
                .iter()
                .zip(&portable)
                .all(|(x, y)| x.to_bits() == y.to_bits()));
        }
    }

    #[test]
    fn update_matches_textbook_kalman_update() {
        let mut f = filter().with_default_gate(None);
        let z = SVector::<f64, 2>::new(1.7, -0.2);
        let r = SMatrix::<f64, 2, 2>::new(0.3, 0.05, 0.05, 0.2);
        let (x, p) = (*f.state(), *f.covariance());
        let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
        let s = h * p * h.transpose() + r;
        let k = p * h.transpose() * s.try_inverse().unwrap();
        let nu = z - h * x;
        let rep = f.update::<PosVel, 2>(&z, &r, &()).unwrap();
        assert!(rep.accepted && rep.threshold.is_none());
        assert!(max_rel(&rep.innovation, &nu) < 1e-15);
        assert!(max_rel(&rep.innovation_covariance, &s) < 1e-15);
        assert!(rel(rep.nis, (nu.transpose() * s.try_inverse().unwrap() * nu)[0]) < 1e-13);
        assert!(max_rel(f.state(), &(x + k * nu)) < 1e-14);
        assert!(max_rel(f.covariance(), &((M3::identity() - k * h) * p)) < 1e-13);
        assert_eq!(f.counters().updates_accepted, 1);
    }

    #[test]
    fn sequential_update_equals_batch_for_diagonal_noise() {
        fn check<S: Sensor<3, 2, Model = Cvb, Aux = ()>>(z: SVector<f64, 2>) {
            let r = SVector::<f64, 2>::new(0.3, 0.2);
            let mut batch = filter().with_default_gate(None);
            let mut seq = batch.clone();
            let rb = batch
                .update::<S, 2>(&z, &SMatrix::from_diagonal(&r), &())
                .unwrap();
            let rs = seq.update_sequential::<S, 2>(&z, &r, &()).unwrap();
            assert!(rel(rb.nis, rs.nis) < 1e-12, "{} {}", rb.nis, rs.nis);
            assert!(max_rel(&rb.innovation_covariance, &rs.innovation_covariance) < 1e-14);
            assert!(max_rel(batch.state(), seq.state()) < 1e-12);
            assert!(max_rel(batch.covariance(), seq.covariance()) < 1e-12);
        }
        check::<PosVel>(SVector::<f64, 2>::new(1.7, -0.2));
        check::<Quad>(SVector::<f64, 2>::new(0.9, 0.3));
    }

    /// Table-driven: one long run per discretization, with two sensors.
    #[test]
    fn covariance_stays_symmetric_positive_definite_over_long_runs() {
        for method in [
            Discretization::FirstOrder,
            Discretization::SecondOrder,
            Discretization::VanLoan,
        ] {
            let mut f = filter().with_discretization(method);
            let mut g = Gauss::new(3);
            let r2 = SMatrix::<f64, 2, 2>::new(0.04, 0.0, 0.0, 1e-4);
            let r1 = SMatrix::<f64, 1, 1>::new(1e-6);
            for k in 0..100_000u32 {
                f.predict(
                    0.01,
                    &CvbInput {
                        a: (f64::from(k) * 1e-3).sin(),
                    },
                )
                .unwrap();
                if k % 10 == 0 {
                    let z = SVector::<f64, 2>::new(
                        f.state()[0] + 0.2 * g.normal(),
                        f.state()[1] + 0.01 * g.normal(),
                    );
                    f.update::<PosVel, 2>(&z, &r2, &()).unwrap();
                }
                if k % 97 == 0 {
                    // A very precise position fix stresses the update.
                    let z = SVector::<f64, 1>::new(f.state()[0] + 1e-3 * g.normal());
                    f.update::<Pos, 1>(&z, &r1, &Offset::default()).unwrap();
                }
                let p = f.covariance();
                assert_eq!(p, &p.transpose(), "{method:?} step {k}");
                assert!(Cholesky::new(*p).is_some(), "{method:?} step {k}: {p}");
            }
            assert_eq!(f.counters().covariance_repairs, 0, "{method:?}");
            assert_eq!(f.counters().predictions, 100_000);
        }
    }

    #[test]
    fn gate_rejects_ten_sigma_outlier_and_leaves_state_unchanged() {
        let mut f = filter().with_default_gate(Some(Gate::new(0.9973).unwrap()));
        let before = f.clone();
        let r = SMatrix::<f64, 1, 1>::new(0.25);
        let sigma = (f.covariance()[(0, 0)] + 0.25).sqrt();
        let z = SVector::<f64, 1>::new(f.state()[0] + 10.0 * sigma);
        let rep = f.update::<Pos, 1>(&z, &r, &Offset::default()).unwrap();
        assert!(!rep.accepted);
        assert!((rep.nis - 100.0).abs() < 1e-9);
        assert!(same_bits(&f, &before));
        assert_eq!(f.counters().updates_gated, 1);
        assert_eq!(f.counters().updates_accepted, 0);
        // A 1-sigma measurement passes.
        let z = SVector::<f64, 1>::new(f.state()[0] + sigma);
        assert!(
            f.update::<Pos, 1>(&z, &r, &Offset::default())
                .unwrap()
                .accepted
        );
    }

    /// A filter 10 sigma off its sensor (as after an accepted outlier) with
    /// measurements that agree with each other: the third refusal in a row
    /// releases the lock-out by inflating `P`, and the fourth sample passes
    /// the gate on its own and is applied through the Kalman gain. Refusals
    /// that disagree, or lie beyond the plausibility bound, never release.
    #[test]
    fn lockout_release_applies_the_measurement_after_consecutive_refusals() {
        use crate::lockout::LockoutRelease;
        let r = SMatrix::<f64, 1, 1>::new(0.25);
        let gate = Some(Gate::new(0.9999).unwrap());
        let rule = Some(LockoutRelease::default());
        let none = Offset::default();
        // The sensor's constant reading, 10 innovation sigmas off the estimate.
        let f0 = filter().with_default_gate(gate);
        let sigma = (f0.covariance()[(0, 0)] + 0.25).sqrt();
        let reading = SVector::<f64, 1>::new(f0.state()[0] + 10.0 * sigma);
        let fuse = |f: &mut Ekf<Cvb, 3>, z: SVector<f64, 1>| {
            let rep = f.update::<Pos, 1>(&z, &r, &none).unwrap();
            (rep.accepted, rep.nis)
        };
        let mut locked = f0.clone();
        let mut released = f0.clone().with_lockout_release(rule);
        for k in 0..3 {
            let before = released.clone();
            assert!(!fuse(&mut released, reading).0, "refusal {k}");
            assert!(!fuse(&mut locked, reading).0);
            // A refusal never moves the state; only the third inflates `P`.
            assert_eq!(released.state(), before.state());
            assert_eq!(released.covariance() == before.covariance(), k < 2);
        }
        assert_eq!(released.counters().updates_released, 1);
        assert_eq!(released.counters().updates_gated, 3);
        // Inflated along the position: `S` grew by about the offset squared.
        let s_after = released.covariance()[(0, 0)] + 0.25;
        assert!(s_after > 99.0 * sigma * sigma, "{s_after}");
        // The fourth passes the gate (no forcing) and is applied: the estimate
        // moves onto the reading, within the sensor noise.
        let (accepted, nis) = fuse(&mut released, reading);
        assert!(accepted && nis < 1.0, "NIS {nis}");
        assert_eq!(released.counters().updates_accepted, 1);
        assert!((released.state()[0] - reading[0]).abs() < 0.5);
        // A repeat is consistent now.
        assert!(fuse(&mut released, reading).0);
        // Without the rule the sensor stays locked out.
        assert!(!fuse(&mut locked, reading).0);
        assert_eq!(locked.counters().updates_released, 0);

        // Refusals that disagree (+10, -10, +10 sigma ...) never release.
        let mut f = f0.clone().with_lockout_release(rule);
        for k in 0..12 {
            let sign = if k % 2 == 0 { 10.0 } else { -10.0 };
            let z = SVector::<f64, 1>::new(f0.state()[0] + sign * sigma);
            assert!(!fuse(&mut f, z).0);
        }
        assert_eq!(f.counters().updates_released, 0);
        assert_eq!(f.covariance(), f0.covariance());

        // Agreeing refusals beyond the plausibility bound never release.
        let mut f = f0.clone().with_lockout_release(rule);
        f.set_lockout_bound(Pos::NAME, 5.0 * sigma).unwrap();
        for _ in 0..12 {
            assert!(!fuse(&mut f, reading).0);
        }
        assert_eq!(f.counters().updates_released, 0);
        assert_eq!(f.covariance(), f0.covariance());

        // Isolated outliers between good samples never release.
        let mut f = f0
            .clone()
            .with_lockout_release(Some(LockoutRelease::new(2, 0.999).unwrap()));
        for _ in 0..5 {
            let good = SVector::<f64, 1>::new(f.state()[0]);
            assert!(fuse(&mut f, good).0);
            let s = (f.covariance()[(0, 0)] + 0.25).sqrt();
            let z = SVector::<f64, 1>::new(f.state()[0] + 10.0 * s);
            assert!(!fuse(&mut f, z).0);
        }
        assert_eq!(f.counters().updates_released, 0);
    }

    /// Over 10,000 consistent draws the acceptance rate is the gate probability
    /// within 4.5 binomial standard deviations.
    #[test]
    fn gate_acceptance_rate_matches_probability() {
        const DRAWS: u32 = 10_000;
        let mut g = Gauss::new(11);
        for prob in [0.9, 0.95, 0.99] {
            let gate = Some(Gate::new(prob).unwrap());
            let base = filter().with_default_gate(gate);
            let bound = 4.5 * (prob * (1.0 - prob) / f64::from(DRAWS)).sqrt();
            // M = 1.
            let r1 = SMatrix::<f64, 1, 1>::new(0.5);
            let s1 = base.covariance()[(0, 0)] + 0.5;
            let mut accepted = 0;
            for _ in 0..DRAWS {
                let z = SVector::<f64, 1>::new(base.state()[0] + s1.sqrt() * g.normal());
                accepted += u32::from(
                    base.clone()
                        .update::<Pos, 1>(&z, &r1, &Offset::default())
                        .unwrap()
                        .accepted,
                );
            }
            let rate = f64::from(accepted) / f64::from(DRAWS);
            assert!((rate - prob).abs() < bound, "M=1 p={prob}: rate {rate}");
            // M = 2.
            let r2 = SMatrix::<f64, 2, 2>::new(0.3, 0.1, 0.1, 0.2);
            let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0);
            let s2 = h * base.covariance() * h.transpose() + r2;
            let mut accepted = 0;
            for _ in 0..DRAWS {
                let z = h * base.state() + g.multivariate(&s2);
                accepted += u32::from(
                    base.clone()
                        .update::<PosVel, 2>(&z, &r2, &())
                        .unwrap()
                        .accepted,
                );
            }
            let rate = f64::from(accepted) / f64::from(DRAWS);
            assert!((rate - prob).abs() < bound, "M=2 p={prob}: rate {rate}");
        }
    }

    /// A filter whose model is the truth's: mean NIS -> M, mean NEES -> N.
    #[test]
    fn nis_and_nees_of_a_consistent_filter_average_to_their_dimensions() {
        const UPDATES: u32 = 5_000;
        let dt = 0.01;
        let mut g = Gauss::new(2024);
        let mut f = filter().with_default_gate(None);
        let mut truth = f.state() + g.multivariate(&p0());
        let r = SMatrix::<f64, 2, 2>::new(0.25, 0.0, 0.0, 0.01);
        let (mut nis_sum, mut nees_sum) = (0.0, 0.0);
        let mut seq_nis_sum = 0.0;
        for k in 0..UPDATES * 10 {
            let u = CvbInput {
                a: (f64::from(k) * 2e-3).cos(),
            };
            let w = V3::new(
                0.0,
                (NOISE.q_a * dt).sqrt() * g.normal(),
                (NOISE.q_b * dt).sqrt() * g.normal(),
            );
            truth = Cvb::transition(&truth, &u, &(), dt) + w;
            f.predict(dt, &u).unwrap();
            if k % 10 == 9 {
                let z = SVector::<f64, 2>::new(
                    truth[0] + 0.5 * g.normal(),
                    truth[1] + 0.1 * g.normal(),
                );
                // The sequential NIS of a clone, for the same draw.
                let rs = f
                    .clone()
                    .update_sequential::<PosVel, 2>(&z, &SVector::<f64, 2>::new(0.25, 0.01), &())
                    .unwrap();
                seq_nis_sum += rs.nis;
                nis_sum += f.update::<PosVel, 2>(&z, &r, &()).unwrap().nis;
                let e = f.state() - truth;
                nees_sum += (e.transpose() * f.covariance().try_inverse().unwrap() * e)[0];
            }
        }
        let n = f64::from(UPDATES);
        let nis = nis_sum / n;
        // chi2(2): mean 2, variance 4; innovations of a consistent filter are white.
        assert!((nis - 2.0).abs() < 4.5 * (4.0 / n).sqrt(), "mean NIS {nis}");
        assert!(rel(seq_nis_sum / n, nis) < 1e-9);
        // NEES samples are correlated in time: a looser bound.
        let nees = nees_sum / n;
        assert!((nees - 3.0).abs() < 0.3, "mean NEES {nees}");
    }

    #[test]
    fn invalid_inputs_are_refused_and_leave_state_unchanged() {
        let mut f = filter();
        f.predict(0.01, &CvbInput { a: 0.3 }).unwrap();
        let before = f.clone();
        let r1 = SMatrix::<f64, 1, 1>::new(0.1);
        let z1 = SVector::<f64, 1>::new(1.0);
        let ok_aux = Offset::default();
        type Case = (
            &'static str,
            Box<dyn Fn(&mut Ekf<Cvb, 3>) -> Result<(), FilterError>>,
        );
        let cases: Vec<Case> = vec![
            (
                "dt NaN",
                Box::new(|f| f.predict(f64::NAN, &CvbInput { a: 0.0 })),
            ),
            (
                "dt inf",
                Box::new(|f| f.predict(f64::INFINITY, &CvbInput { a: 0.0 })),
            ),
            (
                "dt zero",
                Box::new(|f| f.predict(0.0, &CvbInput { a: 0.0 })),
            ),
            (
                "dt negative (time backwards)",
                Box::new(|f| f.predict(-0.01, &CvbInput { a: 0.0 })),
            ),
            (
                "input NaN",
                Box::new(|f| f.predict(0.01, &CvbInput { a: f64::NAN })),
            ),
            (
                "input -inf",
                Box::new(|f| {
                    f.predict(
                        0.01,
                        &CvbInput {
                            a: f64::NEG_INFINITY,
                        },
                    )
                }),
            ),
            (
                "z NaN",
                Box::new(move |f| {
                    f.update::<Pos, 1>(&SVector::<f64, 1>::new(f64::NAN), &r1, &ok_aux)
                        .map(drop)
                }),
            ),
            (
                "R NaN",
                Box::new(move |f| {
                    f.update::<Pos, 1>(&z1, &SMatrix::<f64, 1, 1>::new(f64::NAN), &ok_aux)
                        .map(drop)
                }),
            ),
            (
                "R negative",
                Box::new(move |f| {
                    f.update::<Pos, 1>(&z1, &SMatrix::<f64, 1, 1>::new(-1.0), &ok_aux)
                        .map(drop)
                }),
            ),
            (
                "R asymmetric",
                Box::new(|f| {
                    let r = SMatrix::<f64, 2, 2>::new(1.0, 0.5, 0.0, 1.0);
                    f.update::<PosVel, 2>(&SVector::<f64, 2>::new(1.0, 0.0), &r, &())
                        .map(drop)
                }),
            ),
            (
                "aux NaN",
                Box::new(move |f| {
                    f.update::<Pos, 1>(&z1, &r1, &Offset { offset: f64::NAN })
                        .map(drop)
                }),
            ),
            (
                "sequential R negative",
                Box::new(move |f| {
                    f.update_sequential::<Pos, 1>(&z1, &SVector::<f64, 1>::new(-0.1), &ok_aux)
                        .map(drop)
                }),
            ),
            (
                "sequential z inf",
                Box::new(move |f| {
                    f.update_sequential::<Pos, 1>(
                        &SVector::<f64, 1>::new(f64::INFINITY),
                        &SVector::<f64, 1>::new(0.1),
                        &ok_aux,
                    )
                    .map(drop)
                }),
            ),
        ];
        for (name, case) in &cases {
            assert!(case(&mut f).is_err(), "{name} accepted");
            assert!(same_bits(&f, &before), "{name} changed the state");
        }
        assert_eq!(f.counters().predictions_rejected, 6);
        assert_eq!(f.counters().updates_rejected, 7);
        assert_eq!(
            f.counters().updates_accepted + f.counters().updates_gated,
            0
        );
    }

    /// Results that overflow are refused after `P` was (partly) overwritten in
    /// place: the prior must come back bit for bit, for every discretization
    /// and for both updates.
    #[test]
    fn overflowing_results_are_refused_and_leave_state_unchanged() {
        // Valid setup (symmetric, finite, non-negative variances) whose
        // propagation and update overflow in off-diagonal entries.
        let p = M3::new(1.0, 1e200, 1e200, 1e200, 1e300, 0.0, 1e200, 0.0, 1e300);
        let x = V3::new(0.1, 0.2, 0.3);
        for method in [
            Discretization::FirstOrder,
            Discretization::SecondOrder,
            Discretization::VanLoan,
        ] {
            let mut f = Ekf::<Cvb, 3>::new(x, p, (), NOISE)
                .unwrap()
                .with_discretization(method)
                .with_default_gate(None);
            let before = f.clone();
            let err = f.predict(1e10, &CvbInput { a: 0.0 }).unwrap_err();
            assert_eq!(
                err,
                FilterError::NonFiniteResult {
                    stage: "prediction"
                },
                "{method:?}"
            );
            assert!(same_bits(&f, &before), "{method:?}");
            assert_eq!(f.counters().predictions_rejected, 1);
        }
        let mut f = Ekf::<Cvb, 3>::new(x, p, (), NOISE)
            .unwrap()
            .with_default_gate(None);
        let before = f.clone();
        let z = SVector::<f64, 1>::new(0.5);
        let err = f
            .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::new(0.1), &Offset::default())
            .unwrap_err();
        assert_eq!(err, FilterError::NonFiniteResult { stage: "update" });
        assert!(same_bits(&f, &before));
        let err = f
            .update_sequential::<Pos, 1>(&z, &SVector::<f64, 1>::new(0.1), &Offset::default())
            .unwrap_err();
        assert_eq!(err, FilterError::NonFiniteResult { stage: "update" });
        assert!(same_bits(&f, &before));
        assert_eq!(f.counters().updates_rejected, 2);
    }

    #[test]
    fn singular_innovation_covariance_is_an_error() {
        let mut p = p0();
        for i in 0..3 {
            p[(0, i)] = 0.0;
            p[(i, 0)] = 0.0;
        }
        let mut f = Ekf::<Cvb, 3>::new(V3::zeros(), p, (), NOISE).unwrap();
        let before = f.clone();
        let z = SVector::<f64, 1>::new(0.1);
        let err = f
            .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::zeros(), &Offset::default())
            .unwrap_err();
        assert_eq!(
            err,
            FilterError::InnovationCovarianceNotPositiveDefinite { sensor: "pos" }
        );
        assert!(same_bits(&f, &before));
        let err = f
            .update_sequential::<Pos, 1>(&z, &SVector::<f64, 1>::zeros(), &Offset::default())
            .unwrap_err();
        assert_eq!(
            err,
            FilterError::InnovationCovarianceNotPositiveDefinite { sensor: "pos" }
        );
    }

    #[test]
    fn non_positive_variance_after_update_is_repaired_and_counted() {
        // A noise-free position fix drives the position variance to exactly 0.
        let mut f = filter().with_default_gate(None);
        let prior = f.covariance()[(0, 0)];
        let rep = f
            .update::<Pos, 1>(
                &SVector::<f64, 1>::new(1.2),
                &SMatrix::<f64, 1, 1>::zeros(),
                &Offset::default(),
            )
            .unwrap();
        assert_eq!(rep.repairs, 1);
        assert_eq!(f.counters().covariance_repairs, 1);
        assert_eq!(f.covariance()[(0, 0)], prior);
        assert_eq!(f.covariance()[(0, 1)], 0.0);
        assert!(Cholesky::new(*f.covariance()).is_some());
    }

    #[test]
    fn setup_is_validated() {
        let bad: [(V3, M3, CvbNoise); 5] = [
            (V3::new(f64::NAN, 0.0, 0.0), p0(), NOISE),
            (
                V3::zeros(),
                M3::new(1.0, 0.5, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0),
                NOISE,
            ),
            (V3::zeros(), -p0(), NOISE),
            (V3::zeros(), p0() * f64::INFINITY, NOISE),
            (
                V3::zeros(),
                p0(),
                CvbNoise {
                    q_a: -1.0,
                    q_b: 0.0,
                },
            ),
        ];
        for (x, p, q) in bad {
            assert!(matches!(
                Ekf::<Cvb, 3>::new(x, p, (), q),
                Err(FilterError::InvalidSetup { .. })
            ));
        }
    }

    /// `F` of the toy is nilpotent, so `exp(F dt) = I + F dt + (F dt)^2 / 2` and
    /// `Qd` has the closed form of the module docs of `testmodels`.
    #[test]
    fn van_loan_matches_closed_forms() {
        let (qa, qb) = (0.3, 0.07);
        let qc = M3::from_diagonal(&V3::new(0.0, qa, qb));
        for dt in [1e-3, 0.1, 1.0, 5.0] {
            let (phi, qd) = van_loan(&Cvb::f(), &qc, dt);
            let fdt = Cvb::f() * dt;
            let exact_phi = M3::identity() + fdt + fdt * fdt * 0.5;
            assert!(max_rel(&phi, &exact_phi) < 1e-13, "dt {dt}");
            let (d2, d3, d4, d5) = (dt * dt, dt.powi(3), dt.powi(4), dt.powi(5));
            let exact_qd = M3::new(d3 / 3.0, d2 / 2.0, 0.0, d2 / 2.0, dt, 0.0, 0.0, 0.0, 0.0) * qa
                + M3::new(
                    d5 / 20.0,
                    d4 / 8.0,
                    -d3 / 6.0,
                    d4 / 8.0,
                    d3 / 3.0,
                    -d2 / 2.0,
                    -d3 / 6.0,
                    -d2 / 2.0,
                    dt,
                ) * qb;
            let err = (qd - exact_qd).amax() / exact_qd.amax();
            assert!(err < 1e-13, "dt {dt}: {err}");
            // The same Phi from the second-order series (exact here, F^3 = 0).
            let (phi2, _) = second_order(&Cvb::f(), &qc, dt);
            assert!(max_rel(&phi2, &exact_phi) < 1e-15);
        }
        // Oscillator: Phi is a rotation-like matrix, Qd matches fine steps.
        let w = 2.0;
        let qc2 = SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 0.5);
        for dt in [0.01, 0.7, 3.0, 40.0] {
            let (phi, qd) = van_loan(&Osc::f(w), &qc2, dt);
            let (c, s) = ((w * dt).cos(), (w * dt).sin());
            let exact = SMatrix::<f64, 2, 2>::new(c, s / w, -w * s, c);
            assert!(max_rel(&phi, &exact) < 1e-11, "dt {dt}: {phi} vs {exact}");
            // Qd = int_0^dt e^{Fs} Qc e^{Fs}^T ds, closed form for the oscillator.
            let q = 0.5;
            let t = dt;
            let q11 = q / (w * w) * (t / 2.0 - (2.0 * w * t).sin() / (4.0 * w));
            let q12 = q / (2.0 * w * w) * (w * t).sin().powi(2);
            let q22 = q * (t / 2.0 + (2.0 * w * t).sin() / (4.0 * w));
            let exact_qd = SMatrix::<f64, 2, 2>::new(q11, q12, q12, q22);
            assert!(
                (qd - exact_qd).amax() < 1e-11 * (1.0 + exact_qd.amax()),
                "dt {dt}: {qd} vs {exact_qd}"
            );
        }
    }

    #[test]
    fn discretizations_propagate_state_consistently() {
        // Linear dynamics: Heun gives exactly the second-order Phi times x; RK4
        // is within O((w dt)^5) of the exact rotation.
        let w = 1.5;
        let dt = 0.2;
        let x0 = SVector::<f64, 2>::new(0.4, -0.3);
        let p0 = SMatrix::<f64, 2, 2>::identity() * 0.1;
        let params = OscParams { w };
        let mk = |d| {
            Ekf::<Osc, 2>::new(x0, p0, params, OscNoise { q: 0.01 })
                .unwrap()
                .with_discretization(d)
        };
        let mut second = mk(Discretization::SecondOrder);
        second.predict(dt, &()).unwrap();
        let (phi2, qd2) = second_order(
            &Osc::f(w),
            &SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 0.01),
            dt,
        );
        assert!(max_rel(second.state(), &(phi2 * x0)) < 1e-15);
        assert!(max_rel(second.covariance(), &(phi2 * p0 * phi2.transpose() + qd2)) < 1e-15);
        let mut vl = mk(Discretization::VanLoan);
        vl.predict(dt, &()).unwrap();
        let (c, s) = ((w * dt).cos(), (w * dt).sin());
        let exact = SMatrix::<f64, 2, 2>::new(c, s / w, -w * s, c) * x0;
        assert!((vl.state() - exact).amax() < (w * dt).powi(5) / 60.0 * x0.norm());
        assert!((vl.state() - exact).amax() > 1e-12, "RK4 is not exact");
        // First order equals the model's own sparse path.
        let mut first = mk(Discretization::FirstOrder);
        first.predict(dt, &()).unwrap();
        let mut p = p0;
        Osc::propagate_covariance(&mut p, &x0, &(), &params, &OscNoise { q: 0.01 }, dt);
        assert_eq!(first.covariance(), &p);
        assert_eq!(first.state(), &Osc::transition(&x0, &(), &params, dt));
    }

    #[test]
    fn discrete_models_use_their_own_transition_matrix() {
        let x0 = SVector::<f64, 2>::new(1.0, 2.0);
        let p0 = SMatrix::<f64, 2, 2>::new(1.0, 0.1, 0.1, 0.5);
        let mk = |d| {
            Ekf::<Dcv, 2>::new(x0, p0, (), DcvNoise { var_v: 0.2 })
                .unwrap()
                .with_discretization(d)
        };
        let mut a = mk(Discretization::FirstOrder);
        a.predict(2.0, &()).unwrap();
        for d in [Discretization::SecondOrder, Discretization::VanLoan] {
            let mut b = mk(d);
            b.predict(2.0, &()).unwrap();
            assert_eq!(a.state(), b.state());
            assert_eq!(a.covariance(), b.covariance());
        }
        assert_eq!(a.state(), &SVector::<f64, 2>::new(5.0, 2.0));
        assert!((a.covariance()[(1, 1)] - 0.7).abs() < 1e-15);
    }

    #[test]
    fn angle_innovations_are_wrapped() {
        let x0 = SVector::<f64, 2>::new(3.1, 0.0);
        let mut f = Ekf::<Osc, 2>::new(
            x0,
            SMatrix::identity() * 0.01,
            OscParams { w: 1.0 },
            OscNoise { q: 0.0 },
        )
        .unwrap();
        let z = SVector::<f64, 1>::new(-3.1);
        let r = SMatrix::<f64, 1, 1>::new(0.01);
        let rep = f.update::<Angle, 1>(&z, &r, &()).unwrap();
        let want = 2.0 * core::f64::consts::PI - 6.2;
        assert!(
            (rep.innovation[0] - want).abs() < 1e-12,
            "{}",
            rep.innovation[0]
        );
        assert!(rep.accepted);
        assert!((f.state()[0] - (3.1 + want / 2.0)).abs() < 1e-12);
        let mut f2 = Ekf::<Osc, 2>::new(
            x0,
            SMatrix::identity() * 0.01,
            OscParams { w: 1.0 },
            OscNoise { q: 0.0 },
        )
        .unwrap();
        let rs = f2
            .update_sequential::<Angle, 1>(&z, &SVector::<f64, 1>::new(0.01), &())
            .unwrap();
        assert!((rs.innovation[0] - want).abs() < 1e-12);
        assert!(max_rel(f.state(), f2.state()) < 1e-14);
    }

    #[test]
    fn per_sensor_gates_override_the_default() {
        let mut f = filter();
        assert_eq!(f.sensor_gate::<Pos, 1>(), Some(Gate::default()));
        f.set_sensor_gate::<Pos, 1>(None).unwrap();
        let tight = Gate::new(0.5).unwrap();
        f.set_sensor_gate::<PosVel, 2>(Some(tight)).unwrap();
        assert_eq!(f.sensor_gate::<Pos, 1>(), None);
        assert_eq!(f.sensor_gate::<PosVel, 2>(), Some(tight));
        assert_eq!(f.sensor_gate::<Quad, 2>(), Some(Gate::default()));
        // Ungated: a 100-sigma fix is applied.
        let z = SVector::<f64, 1>::new(f.state()[0] + 200.0);
        let rep = f
            .update::<Pos, 1>(&z, &SMatrix::<f64, 1, 1>::new(1.0), &Offset::default())
            .unwrap();
        assert!(rep.accepted && rep.threshold.is_none());
        // Re-setting an existing entry does not use capacity.
        for _ in 0..100 {
            f.set_sensor_gate::<Pos, 1>(Some(tight)).unwrap();
        }
        assert_eq!(f.sensor_gate::<Pos, 1>(), Some(tight));
    }
}
