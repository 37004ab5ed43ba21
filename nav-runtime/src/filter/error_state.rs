//! Indirect-feedback (error-state) filtering, as in SDINS-25 (docs/models/sdins25.md).
//!
//! The navigation solution is carried outside the filter, in a *nominal state*
//! (the strapdown INS solution and the current sensor corrections). The
//! [`Ekf`] estimates the errors of that solution. After every accepted update the
//! estimated error is fed back into the nominal state and the error estimate is
//! reset to zero, so the linearization is always about a small error and the
//! nominal solution never drifts away from the estimate (Titterton & Weston,
//! *Strapdown Inertial Navigation Technology*, 2nd ed., sec. 12.3.3; Maybeck,
//! *Stochastic Models, Estimation and Control* vol. 1, sec. 6.5).
//!
//! **Sign convention.** Following docs/models/conventions.md (item 7), an error is *INS value minus true
//! value*: `dx = x_nominal - x_true`, and a measurement residual is *INS value
//! minus sensor value*. The best estimate of the truth is therefore
//! `x_nominal - dx_hat`, so [`NominalState::inject`] *subtracts* the estimated
//! error: `p <- p - dp`, `V <- V - dV`, and for the attitude error `phi` with the
//! computed `C^_b^n = (I - [phi x]) C_b^n`, the correction
//! `C_b^n <- (I + [phi x]) C^_b^n` (to first order, re-orthonormalized).
//! Sensor-error states (biases, scale factors, misalignments) are corrected the
//! same way: the nominal correction minus the estimated residual error.
//!
//! **Reset.** After injection the error state is set to zero and `P` is kept:
//! the reset Jacobian `d(dx+)/d(dx-)` is the identity to first order (for the
//! attitude error it is `I - [phi/2 x]`, whose effect on `P` is second order in
//! the small correction and is neglected, as in the paper).

use nalgebra::{SMatrix, SVector};

use crate::ekf::{Ekf, Estimator, FilterError, Propagate, UpdateReport};
use crate::model::{first_non_finite, name_of, Model, Record, Sensor};
#[cfg(feature = "std")]
use crate::smoother::Recorder;

/// The nominal solution that an error-state filter corrects.
pub trait NominalState<const N: usize> {
    /// Applies an estimated error `error` (INS minus true, in the error-state
    /// order of the model) to the nominal solution, so that the error of the
    /// corrected solution is zero: for additive states `x <- x - error[i]`, for
    /// attitude the small rotation that undoes `phi` (see the module docs).
    fn inject(&mut self, error: &SVector<f64, N>);
}

/// A nominal state that integrates its own IMU samples (the strapdown
/// mechanization), so that an [`ErrorStateFilter`] can be driven by the
/// multi-rate scheduler with raw IMU samples and re-propagated after a delayed
/// measurement.
pub trait Mechanization<Mo: Model<N>, const N: usize>: NominalState<N> + Clone {
    /// One IMU sample (specific force and angular rate, or their increments).
    type Imu: Record;
    /// Returns the error model's input for the interval `[t, t + dt]`
    /// (typically the nominal solution at `t` together with the IMU sample) and
    /// advances the nominal solution to `t + dt`. Called only with a finite,
    /// positive `dt` and a finite sample.
    fn mechanize(&mut self, dt: f64, imu: &Self::Imu) -> Mo::Input;
}

/// An [`Ekf`] on the error state of model `Mo`, with feedback into `Nom`.
///
/// The error model's input (nominal solution, IMU sample) is passed to
/// [`ErrorStateFilter::predict`] by the caller, who advances the nominal
/// solution, or produced by [`Mechanization::mechanize`] when the filter is
/// propagated through [`Propagate`] (the scheduler's path).
pub struct ErrorStateFilter<Mo: Model<N>, Nom, const N: usize> {
    ekf: Ekf<Mo, N>,
    nominal: Nom,
    resets: u64,
    /// Sum of the error estimates injected since [`ErrorStateFilter::take_fed_back`].
    fed_back: SVector<f64, N>,
    /// The run being recorded for the smoother, if any (boxed: a filter that
    /// records nothing stays small to copy).
    #[cfg(feature = "std")]
    recording: Option<Box<Recorder<N, 0>>>,
}

impl<Mo: Model<N>, Nom: NominalState<N>, const N: usize> ErrorStateFilter<Mo, Nom, N> {
    /// Wraps `ekf` and `nominal`. A non-zero initial error estimate in `ekf` is
    /// injected at once, so the error state starts at zero.
    pub fn new(ekf: Ekf<Mo, N>, nominal: Nom) -> Self {
        let mut filter = Self {
            ekf,
            nominal,
            resets: 0,
            fed_back: SVector::zeros(),
            #[cfg(feature = "std")]
            recording: None,
        };
        if filter.ekf.state().iter().any(|v| *v != 0.0) {
            filter.feedback();
        }
        filter
    }

    /// The error-state filter (its state is zero after every feedback).
    pub fn ekf(&self) -> &Ekf<Mo, N> {
        &self.ekf
    }

    /// Mutable access to the error-state filter (gates, noise, discretization).
    pub fn ekf_mut(&mut self) -> &mut Ekf<Mo, N> {
        &mut self.ekf
    }

    /// The corrected nominal solution: the filter's estimate of the truth.
    pub fn nominal(&self) -> &Nom {
        &self.nominal
    }

    /// Mutable access to the nominal solution (e.g. to advance it by hand).
    pub fn nominal_mut(&mut self) -> &mut Nom {
        &mut self.nominal
    }

    /// The error covariance: the covariance of the nominal solution's error.
    pub fn covariance(&self) -> &SMatrix<f64, N, N> {
        self.ekf.covariance()
    }

    /// Number of feedbacks (injections followed by a reset).
    pub fn resets(&self) -> u64 {
        self.resets
    }

    /// The sum of the error estimates fed back into the nominal solution since
    /// the last call (INS minus true, error-state order), and restarts the
    /// sum: what a smoother records as the correction of an epoch
    /// ([`crate::smoother::Recorder::updated`]).
    pub fn take_fed_back(&mut self) -> SVector<f64, N> {
        core::mem::replace(&mut self.fed_back, SVector::zeros())
    }

    /// Splits the filter into its parts.
    pub fn into_parts(self) -> (Ekf<Mo, N>, Nom) {
        (self.ekf, self.nominal)
    }

    /// Propagates the error covariance (and the error state) over `dt` with the
    /// error model's `input`; the caller advances the nominal solution.
    ///
    /// # Errors
    /// As [`Ekf::predict`]; nothing changes on error.
    pub fn predict(&mut self, dt: f64, input: &Mo::Input) -> Result<(), FilterError> {
        #[cfg(feature = "std")]
        if let Some(rec) = self.recording.as_deref_mut() {
            // The step's coefficients are staged as the propagation uses
            // them and recorded once the step has succeeded.
            let start = *self.ekf.state();
            let mut staged = false;
            let result = self.ekf.predict_observed(dt, input, |coefficients| {
                rec.stage(coefficients);
                staged = true;
            });
            if result.is_ok() && !(staged && rec.propagated_staged::<Mo>(dt)) {
                rec.propagated::<Mo>(&Mo::jacobian(&start, input, self.ekf.params(), dt), dt);
            }
            return result;
        }
        self.ekf.predict(dt, input)
    }

    /// Fuses the residual `z` (INS value minus sensor value) of sensor `S`, as
    /// [`Ekf::update`]; if accepted, injects the estimated error into the
    /// nominal state and resets the error state to zero.
    ///
    /// # Errors
    /// As [`Ekf::update`]; nothing changes on error or when gated.
    pub fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        #[cfg(feature = "std")]
        let before = self.recording.is_some().then(|| *self.ekf.covariance());
        let report = self.ekf.update::<S, M>(z, r, aux)?;
        if report.accepted {
            let _error = self.feedback();
            #[cfg(feature = "std")]
            if let (Some(rec), Some(before)) = (self.recording.as_mut(), before) {
                rec.updating(&before, SVector::zeros());
                rec.updated(&_error, self.ekf.covariance(), SVector::zeros());
            }
        }
        Ok(report)
    }

    /// Sequential scalar update for diagonal `R`, as [`Ekf::update_sequential`],
    /// with the same feedback as [`ErrorStateFilter::update`].
    ///
    /// # Errors
    /// As [`Ekf::update_sequential`]; nothing changes on error or when gated.
    pub fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        #[cfg(feature = "std")]
        let before = self.recording.is_some().then(|| *self.ekf.covariance());
        let report = self.ekf.update_sequential::<S, M>(z, r_diag, aux)?;
        if report.accepted {
            let _error = self.feedback();
            #[cfg(feature = "std")]
            if let (Some(rec), Some(before)) = (self.recording.as_mut(), before) {
                rec.updating(&before, SVector::zeros());
                rec.updated(&_error, self.ekf.covariance(), SVector::zeros());
            }
        }
        Ok(report)
    }

    /// Injects the current error estimate into the nominal state and resets it.
    fn feedback(&mut self) -> SVector<f64, N> {
        let error = *self.ekf.state();
        self.nominal.inject(&error);
        self.ekf.reset_state();
        self.resets += 1;
        self.fed_back += error;
        error
    }
}

/// Recording for the fixed-interval smoother ([`crate::smoother`]).
#[cfg(feature = "std")]
impl<Mo: Model<N>, Nom: NominalState<N>, const N: usize> ErrorStateFilter<Mo, Nom, N> {
    /// Starts recording this filter's run into `file` for
    /// [`crate::smoother::smooth`], `time` (s) being the filter's time now:
    /// from now on every prediction step and every accepted update (with the
    /// error estimate it fed back) is recorded; [`ErrorStateFilter::mark_epoch`]
    /// adds output times. Checkpoint clones carry the recording, so a
    /// scheduler's re-propagation replaces what it supersedes.
    ///
    /// # Errors
    /// [`crate::setup_error::SetupError::Invalid`] for a continuous model with a
    /// discretization other than first order (the recorder's transition
    /// matrices are `I + F dt`, which would not match the filter's).
    pub fn start_recording(
        &mut self,
        file: crate::smoother::EpochFile<N, 0>,
        time: f64,
    ) -> Result<(), crate::setup_error::SetupError> {
        if !Mo::DISCRETE && self.ekf.discretization() != crate::ekf::Discretization::FirstOrder {
            return Err(crate::setup_error::SetupError::Invalid {
                reason: "smoothing needs the first-order discretization",
            });
        }
        let mut recorder = Recorder::new(file, time, self.ekf.covariance(), SVector::zeros());
        recorder.reserve_stage(Mo::PROPAGATION.map_or(0, |s| s.columns.len()));
        self.recording = Some(Box::new(recorder));
        Ok(())
    }

    /// An output epoch at `time` (s): the smoother reports the smoothed error
    /// here even if no measurement was fused. Does nothing when not recording.
    pub fn mark_epoch(&mut self, time: f64) {
        if let Some(rec) = self.recording.as_mut() {
            rec.mark(time, self.ekf.covariance(), SVector::zeros());
        }
    }

    /// `true` while recording.
    pub fn is_recording(&self) -> bool {
        self.recording.is_some()
    }

    /// Ends the recording and returns its epoch file, ready for
    /// [`crate::smoother::smooth`]; `None` when not recording.
    ///
    /// # Errors
    /// The first failure of the recording ([`crate::smoother::Recorder::finish`]).
    #[allow(clippy::type_complexity)]
    pub fn finish_recording(
        &mut self,
    ) -> Result<
        Option<std::rc::Rc<core::cell::RefCell<crate::smoother::EpochFile<N, 0>>>>,
        crate::smoother::SmootherError,
    > {
        let Some(mut rec) = self.recording.take() else {
            return Ok(None);
        };
        rec.finish()?;
        Ok(Some(rec.store()))
    }
}

impl<Mo: Model<N>, Nom: Clone, const N: usize> Clone for ErrorStateFilter<Mo, Nom, N> {
    fn clone(&self) -> Self {
        Self {
            ekf: self.ekf.clone(),
            nominal: self.nominal.clone(),
            resets: self.resets,
            fed_back: self.fed_back,
            #[cfg(feature = "std")]
            recording: self.recording.clone(),
        }
    }

    /// Part by part into `self` (see `Ekf`'s `clone_from`): no temporary copy.
    fn clone_from(&mut self, source: &Self) {
        self.ekf.clone_from(&source.ekf);
        self.nominal.clone_from(&source.nominal);
        self.resets = source.resets;
        self.fed_back = source.fed_back;
        #[cfg(feature = "std")]
        self.recording.clone_from(&source.recording);
    }
}

impl<Mo: Model<N>, Nom: core::fmt::Debug, const N: usize> core::fmt::Debug
    for ErrorStateFilter<Mo, Nom, N>
{
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("ErrorStateFilter")
            .field("ekf", &self.ekf)
            .field("nominal", &self.nominal)
            .field("resets", &self.resets)
            .finish()
    }
}

impl<Mo: Model<N>, Nom: NominalState<N>, const N: usize> Estimator<N>
    for ErrorStateFilter<Mo, Nom, N>
{
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
        ErrorStateFilter::update::<S, M>(self, z, r, aux)
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
        ErrorStateFilter::update_sequential::<S, M>(self, z, r_diag, aux)
    }
}

/// Driven by raw IMU samples: the nominal solution is mechanized, the error
/// model is propagated with the input it returns, and the nominal solution
/// goes back to where it was if the prediction fails.
impl<Mo: Model<N>, Nom: Mechanization<Mo, N>, const N: usize> Propagate
    for ErrorStateFilter<Mo, Nom, N>
{
    type Input = Nom::Imu;

    fn check_input(imu: &Nom::Imu) -> Result<(), FilterError> {
        match first_non_finite(imu) {
            Some(index) => Err(FilterError::NonFiniteInput {
                index,
                name: name_of::<Nom::Imu>(index),
            }),
            None => Ok(()),
        }
    }

    fn propagate(&mut self, dt: f64, imu: &Nom::Imu) -> Result<(), FilterError> {
        if !(dt.is_finite() && dt > 0.0) {
            return Err(FilterError::InvalidTimeStep { dt });
        }
        Self::check_input(imu)?;
        // Mechanized in place; the copy before the step is put back only if
        // the prediction fails.
        let before = self.nominal.clone();
        let input = self.nominal.mechanize(dt, imu);
        if let Err(e) = self.predict(dt, &input) {
            self.nominal = before;
            return Err(e);
        }
        Ok(())
    }
}

#[cfg(all(test, feature = "std"))]
mod tests {
    use super::*;
    use crate::testmodels::{Cvb, CvbInput, CvbNoise, Gauss, Offset, Pos, Toy};

    fn p0() -> SMatrix<f64, 3, 3> {
        SMatrix::<f64, 3, 3>::from_diagonal(&SVector::<f64, 3>::new(4.0, 0.25, 0.01))
    }

    const NOISE: CvbNoise = CvbNoise {
        q_a: 1e-3,
        q_b: 1e-6,
    };

    /// For a linear model, the feedback error-state filter and the full-state
    /// filter are the same estimator: the corrected nominal equals the
    /// full-state estimate and the covariances agree.
    #[test]
    fn feedback_filter_equals_full_state_filter() {
        let x0 = SVector::<f64, 3>::new(1.0, 0.5, 0.02);
        let mut full = Ekf::<Cvb, 3>::new(x0, p0(), (), NOISE)
            .unwrap()
            .with_default_gate(None);
        let err = Ekf::<Cvb, 3>::new(SVector::zeros(), p0(), (), NOISE)
            .unwrap()
            .with_default_gate(None);
        let mut esf = ErrorStateFilter::new(
            err,
            Toy {
                p: 1.0,
                v: 0.5,
                b: 0.02,
            },
        );
        let mut g = Gauss::new(7);
        let r = SMatrix::<f64, 1, 1>::new(0.5);
        let dt = 0.01;
        let (mut p_true, mut v_true, b_true) = (0.0, 0.0, 0.05);
        for k in 0..20_000 {
            let a_true = (k as f64 * 0.003).sin();
            let a_meas = a_true + b_true + 0.03 * g.normal();
            p_true += v_true * dt;
            v_true += a_true * dt;
            full.predict(dt, &CvbInput { a: a_meas }).unwrap();
            Propagate::propagate(&mut esf, dt, &CvbInput { a: a_meas }).unwrap();
            if k % 50 == 49 {
                let z = p_true + 0.7 * g.normal();
                let rf = full
                    .update::<Pos, 1>(&SVector::<f64, 1>::new(z), &r, &Offset::default())
                    .unwrap();
                let residual = esf.nominal().p - z;
                let re = esf
                    .update::<Pos, 1>(&SVector::<f64, 1>::new(residual), &r, &Offset::default())
                    .unwrap();
                assert!((rf.nis - re.nis).abs() < 1e-9 * (1.0 + rf.nis));
                assert_eq!(
                    esf.ekf().state(),
                    &SVector::<f64, 3>::zeros(),
                    "reset after feedback"
                );
            }
        }
        let n = esf.nominal();
        let got = SVector::<f64, 3>::new(n.p, n.v, n.b);
        assert!(
            (got - full.state()).norm() < 1e-9 * (1.0 + full.state().norm()),
            "{got} vs {}",
            full.state()
        );
        assert!((esf.covariance() - full.covariance()).norm() < 1e-12);
        assert_eq!(esf.resets(), 400);
        // The bias is observable through position: estimated within 3 sigma.
        assert!((n.b - b_true).abs() < 3.0 * full.covariance()[(2, 2)].sqrt());
    }

    #[test]
    fn gated_and_failed_updates_do_not_touch_the_nominal() {
        let err = Ekf::<Cvb, 3>::new(SVector::zeros(), p0(), (), NOISE).unwrap();
        let mut esf = ErrorStateFilter::new(
            err,
            Toy {
                p: 1.0,
                v: 0.5,
                b: 0.0,
            },
        );
        let before = *esf.nominal();
        let r = SMatrix::<f64, 1, 1>::new(0.01);
        // 100 sigma residual: gated.
        let rep = esf
            .update::<Pos, 1>(&SVector::<f64, 1>::new(200.0), &r, &Offset::default())
            .unwrap();
        assert!(!rep.accepted);
        assert!(esf
            .update::<Pos, 1>(&SVector::<f64, 1>::new(f64::NAN), &r, &Offset::default())
            .is_err());
        assert!(Propagate::propagate(&mut esf, -1.0, &CvbInput { a: 0.0 }).is_err());
        assert!(Propagate::propagate(&mut esf, 0.1, &CvbInput { a: f64::INFINITY }).is_err());
        assert_eq!(*esf.nominal(), before);
        assert_eq!(esf.resets(), 0);
    }

    #[test]
    fn initial_error_estimate_is_injected() {
        let err =
            Ekf::<Cvb, 3>::new(SVector::<f64, 3>::new(0.5, -0.25, 0.0), p0(), (), NOISE).unwrap();
        let esf = ErrorStateFilter::new(
            err,
            Toy {
                p: 1.0,
                v: 0.5,
                b: 0.0,
            },
        );
        assert_eq!(
            *esf.nominal(),
            Toy {
                p: 0.5,
                v: 0.75,
                b: 0.0
            }
        );
        assert_eq!(esf.ekf().state(), &SVector::<f64, 3>::zeros());
    }
}
