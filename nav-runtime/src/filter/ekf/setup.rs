//! Building and configuring a filter, its accessors and setters.

use core::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use super::covariance::DEFAULT_VARIANCE_FLOOR;
use super::discretization::Discretization;
use super::gating::GateTable;
use super::validation::{all_finite, check_noise_intensities, checked_covariance};
use super::{Ekf, FilterCounters, SetupError};
use crate::gate::Gate;
use crate::model::{first_non_finite, Model, Record};
use crate::real::Real;

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// A filter at state `x0` with covariance `p0`.
    ///
    /// `p0` must be finite, symmetric (to 1e-9 relative; the upper triangle is
    /// then kept) with non-negative diagonal; `params` finite; `noise` finite and
    /// non-negative. Positive definiteness is not required (a perfectly known
    /// state may have zero variance), but such a state's zero variance is
    /// reported as a repair if an update drives it non-positive.
    /// Gating starts at [`Gate::default`] for every sensor, discretization at
    /// [`Discretization::FirstOrder`], the last input at `Default`. `x0` is
    /// returned to its manifold ([`Model::normalize_state`]: angles wrapped,
    /// quaternions renormalized) as after every step.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] naming the first problem found.
    pub fn new(
        x0: SVector<T, N>,
        p0: SMatrix<T, N, N>,
        params: Mo::Params,
        noise: Mo::Noise,
    ) -> Result<Self, SetupError> {
        if !all_finite(x0.as_slice()) {
            return Err(SetupError::Invalid {
                reason: "initial state is not finite",
            });
        }
        let p = checked_covariance(&p0)?;
        if first_non_finite(&params).is_some() {
            return Err(SetupError::Invalid {
                reason: "a parameter is not finite",
            });
        }
        check_noise_intensities(&noise)?;
        // On its manifold from the start, as after every step: a heading of
        // 350 degrees is reported as -10 from the first estimate on.
        let mut x0 = x0;
        Mo::normalize_state(&mut x0);
        Ok(Self {
            x: x0,
            p,
            params,
            noise,
            input: Mo::Input::default(),
            discretization: Discretization::FirstOrder,
            default_gate: Some(Gate::default()),
            gates: GateTable::new(),
            lockout: crate::lockout::Lockout::new(),
            variance_floor: DEFAULT_VARIANCE_FLOOR,
            counters: FilterCounters::default(),
            clean: false,
            saved: [[T::zero(); N]; N],
            _model: PhantomData,
        })
    }

    /// Sets the discretization of continuous models (see [`Discretization`]).
    #[must_use]
    pub fn with_discretization(mut self, discretization: Discretization) -> Self {
        self.discretization = discretization;
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

    /// The state estimate.
    pub fn state(&self) -> &SVector<T, N> {
        &self.x
    }

    /// The state estimate as the model's named record.
    pub fn state_record(&self) -> Mo::State {
        <Mo::State as Record>::from_fn(|i| self.x.get(i).map_or(f64::NAN, |v| v.to_f64()))
    }

    /// The state covariance (symmetric).
    pub fn covariance(&self) -> &SMatrix<T, N, N> {
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

    /// Replaces the input that sensors read (`h(x, u, p, aux)` and `H`)
    /// until the next prediction: an error-state filter sets it from its
    /// nominal solution after a feedback ([`crate::error_state`]). The
    /// caller passes a finite input (a non-finite one makes the next update
    /// fail on its non-finite innovation, not panic).
    pub(crate) fn set_input(&mut self, input: Mo::Input) {
        self.input = input;
    }

    /// The discretization in use.
    pub fn discretization(&self) -> Discretization {
        self.discretization
    }

    /// Running totals.
    pub fn counters(&self) -> &FilterCounters {
        &self.counters
    }

    /// Replaces the state estimate (e.g. the reset of an error-state filter),
    /// returned to its manifold ([`Model::normalize_state`]) as after a step.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] if `x` is not finite (state unchanged).
    pub fn set_state(&mut self, x: SVector<T, N>) -> Result<(), SetupError> {
        if !all_finite(x.as_slice()) {
            return Err(SetupError::Invalid {
                reason: "state is not finite",
            });
        }
        self.x = x;
        Mo::normalize_state(&mut self.x);
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
    /// [`SetupError::Invalid`] (covariance unchanged).
    pub fn set_covariance(&mut self, p: SMatrix<T, N, N>) -> Result<(), SetupError> {
        self.p = checked_covariance(&p)?;
        self.clean = false;
        Ok(())
    }

    /// Replaces the process-noise intensities (finite, non-negative).
    ///
    /// # Errors
    /// [`SetupError::Invalid`] (noise unchanged).
    pub fn set_noise(&mut self, noise: Mo::Noise) -> Result<(), SetupError> {
        check_noise_intensities(&noise)?;
        self.noise = noise;
        Ok(())
    }

    /// Replaces the parameters, checked as at construction (every scalar
    /// finite), e.g. a beacon position or a sound speed that changes at run
    /// time.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] (parameters unchanged).
    pub fn set_params(&mut self, params: Mo::Params) -> Result<(), SetupError> {
        if first_non_finite(&params).is_some() {
            return Err(SetupError::Invalid {
                reason: "a parameter is not finite",
            });
        }
        self.params = params;
        Ok(())
    }
}

impl<Mo: Model<N, T>, const N: usize, T: Real> Clone for Ekf<Mo, N, T> {
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
            clean: self.clean,
            saved: [[T::zero(); N]; N],
            _model: PhantomData,
        }
    }

    /// Field by field into `self`: one copy of the covariance, no temporary.
    fn clone_from(&mut self, source: &Self) {
        self.x = source.x;
        self.p = source.p;
        self.params = source.params;
        self.noise = source.noise;
        self.input = source.input;
        self.discretization = source.discretization;
        self.default_gate = source.default_gate;
        self.gates = source.gates;
        self.lockout = source.lockout;
        self.variance_floor = source.variance_floor;
        self.counters = source.counters;
        self.clean = source.clean;
    }
}

impl<Mo: Model<N, T>, const N: usize, T: Real> core::fmt::Debug for Ekf<Mo, N, T> {
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
