//! Prediction (eq. P1) and the [`Propagate`] interface the scheduler drives.

use nalgebra::{SMatrix, SVector};

use super::changed::{
    changed_are_clean, changed_entries, restore_changed, save_changed, saved_diagonal,
    ChangedEntries,
};
use super::covariance::{covariance_is_clean, mirror_upper, off_diagonal_finite, repair_diagonal};
use super::discretization::{second_order, van_loan, Discretization};
use super::validation::all_finite;
use super::{Ekf, FilterError};
use crate::model::{first_non_finite, name_of, Model};
use crate::propagation::Structure;
use crate::real::Real;

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

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
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
    pub fn predict(&mut self, dt: T, input: &Mo::Input) -> Result<(), FilterError> {
        self.predict_observed(dt, input, |_| ())
    }

    /// [`Ekf::predict`], handing the step's transition to `observe` as
    /// [`Model::propagate_covariance_observed`] does (only with the
    /// first-order step of a model whose [`Model::PROPAGATION`] is set; the
    /// step may still fail after the call).
    ///
    /// # Errors
    /// As [`Ekf::predict`].
    pub(crate) fn predict_observed<F: FnOnce(&[T])>(
        &mut self,
        dt: T,
        input: &Mo::Input,
        observe: F,
    ) -> Result<(), FilterError> {
        match self.predict_in_place(dt, input, observe) {
            Ok(repairs) => {
                Mo::normalize_state(&mut self.x);
                self.input = *input;
                self.counters.predictions += 1;
                self.lockout.recovery.advance(dt.to_f64());
                self.counters.covariance_repairs += u64::from(repairs);
                Ok(())
            }
            Err(e) => {
                self.counters.predictions_rejected += 1;
                Err(e)
            }
        }
    }

    /// Propagates `x` and `P` in place (eq. P1); on error both are unchanged.
    /// Returns the number of repaired variances.
    ///
    /// The state is propagated into a temporary and checked first. `P` is
    /// propagated in place: over a model's [`Model::PROPAGATION`] structure,
    /// from a `P` known clean, only the entries the step changes are saved
    /// before it and checked after it ([`super::changed`]: nothing else can
    /// change, so this is the whole check); otherwise the whole `P`. A
    /// result with a non-finite off-diagonal entry is refused and the saved
    /// entries are restored; non-positive variances are repaired.
    pub(super) fn predict_in_place<F: FnOnce(&[T])>(
        &mut self,
        dt: T,
        u: &Mo::Input,
        observe: F,
    ) -> Result<u32, FilterError> {
        if !(dt.is_finite() && dt > T::zero()) {
            return Err(FilterError::InvalidTimeStep { dt: dt.to_f64() });
        }
        if let Some(index) = first_non_finite(u) {
            return Err(FilterError::NonFiniteInput {
                index,
                name: name_of::<Mo::Input>(index),
            });
        }
        let (par, q) = (&self.params, &self.noise);
        let method = if Mo::DISCRETE {
            Discretization::FirstOrder
        } else {
            self.discretization
        };
        if method == Discretization::FirstOrder {
            // An error-state filter's state is zero after every feedback,
            // and its transition keeps it there: nothing to evaluate (the
            // inputs were checked finite above).
            let x_new = if Mo::ZERO_IS_FIXED && self.x.iter().all(|v| *v == T::zero()) {
                self.x
            } else {
                Mo::transition(&self.x, u, par, dt)
            };
            if !all_finite(x_new.as_slice()) {
                return Err(NOT_FINITE);
            }
            // Fixed at compile time from the model's constant structure.
            let changed = const { changed_entries::<N>(Mo::PROPAGATION) };
            let repairs = match Mo::PROPAGATION.filter(|_| changed.valid && self.clean) {
                Some(structure) => self.propagate_changed(&structure, &changed, dt, u, observe)?,
                None => {
                    let prev = self.p;
                    // The generated propagation writes an exactly symmetric
                    // `P` (it computes the upper triangle and mirrors it).
                    Mo::propagate_covariance_observed(&mut self.p, &self.x, u, par, q, dt, observe);
                    self.checked_or_restored(&prev)?
                }
            };
            self.x = x_new;
            return Ok(repairs);
        }
        let prev = self.p;
        let f = Mo::jacobian(&self.x, u, par, dt);
        let qc = Mo::process_noise(&self.x, u, par, q, dt) / dt;
        let (phi, qd, x_new) = if method == Discretization::SecondOrder {
            let (phi, qd) = second_order(&f, &qc, dt);
            (phi, qd, heun::<Mo, N, T>(&self.x, u, par, dt))
        } else {
            let (phi, qd) = van_loan(&f, &qc, dt);
            (phi, qd, runge_kutta4::<Mo, N, T>(&self.x, u, par, dt))
        };
        if !all_finite(x_new.as_slice()) {
            return Err(NOT_FINITE);
        }
        self.p = phi * prev * phi.transpose() + qd;
        mirror_upper(&mut self.p);
        let repairs = self.checked_or_restored(&prev)?;
        self.x = x_new;
        Ok(repairs)
    }

    /// After a prediction from `prev`: `P` checked whole and its variances
    /// repaired, or `prev` restored if an off-diagonal entry is not finite.
    fn checked_or_restored(&mut self, prev: &SMatrix<T, N, N>) -> Result<u32, FilterError> {
        let mut repairs = 0;
        if !covariance_is_clean(&self.p) {
            if !off_diagonal_finite(&self.p) {
                self.p = *prev;
                return Err(NOT_FINITE);
            }
            repairs = repair_diagonal(&mut self.p, &prev.diagonal(), T::of(self.variance_floor));
        }
        self.clean = true;
        Ok(repairs)
    }

    /// The first-order covariance step over `structure` from a `P` known
    /// clean, saving, checking and restoring only the entries it changes
    /// ([`super::changed`]). Its outcome is that of the whole check: the
    /// entries it skips are those of the clean `P` before the step.
    fn propagate_changed<F: FnOnce(&[T])>(
        &mut self,
        structure: &Structure<'_>,
        changed: &ChangedEntries<N>,
        dt: T,
        u: &Mo::Input,
        observe: F,
    ) -> Result<u32, FilterError> {
        save_changed(&mut self.saved, &self.p, structure, changed);
        let (par, q) = (&self.params, &self.noise);
        Mo::propagate_covariance_observed(&mut self.p, &self.x, u, par, q, dt, observe);
        if changed_are_clean(&self.p, structure, changed) {
            return Ok(0);
        }
        if !off_diagonal_finite(&self.p) {
            restore_changed(&mut self.p, &self.saved, structure, changed);
            return Err(NOT_FINITE);
        }
        let prev_diagonal = saved_diagonal(&self.p, &self.saved, structure, changed);
        Ok(repair_diagonal(
            &mut self.p,
            &prev_diagonal,
            T::of(self.variance_floor),
        ))
    }
}

/// A prediction whose state or covariance is not finite.
const NOT_FINITE: FilterError = FilterError::NonFiniteResult {
    stage: "prediction",
};

impl<Mo: Model<N, T>, const N: usize, T: Real> Propagate for Ekf<Mo, N, T> {
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
        self.predict(T::of(dt), input)
    }
}

/// Heun's method from model transitions: with `x1 = T(x)` (Euler),
/// `x + dt (f(x) + f(x1)) / 2 = (x + T(x1)) / 2`.
pub(super) fn heun<Mo: Model<N, T>, const N: usize, T: Real>(
    x: &SVector<T, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    dt: T,
) -> SVector<T, N> {
    let x1 = Mo::transition(x, u, p, dt);
    (x + Mo::transition(&x1, u, p, dt)) * T::of(0.5)
}

/// Classical Runge-Kutta 4 from model transitions: `f(y) dt = T(y) - y`.
pub(super) fn runge_kutta4<Mo: Model<N, T>, const N: usize, T: Real>(
    x: &SVector<T, N>,
    u: &Mo::Input,
    p: &Mo::Params,
    dt: T,
) -> SVector<T, N> {
    let step = |y: &SVector<T, N>| Mo::transition(y, u, p, dt) - y;
    let d1 = step(x);
    let half = T::of(0.5);
    let d2 = step(&(x + d1 * half));
    let d3 = step(&(x + d2 * half));
    let d4 = step(&(x + d3));
    x + (d1 + (d2 + d3) * T::of(2.0) + d4) / T::of(6.0)
}
