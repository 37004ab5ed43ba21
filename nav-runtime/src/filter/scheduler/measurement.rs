//! Type-erased measurements: what the scheduler queues and applies.

use std::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use super::MAX_RAW_VALUES;
use crate::ekf::{Estimator, FilterError, UpdateReport};
use crate::innovations::InnovationStatistics;
use crate::model::{Record, Sensor};
#[cfg(doc)]
use crate::stuck::StuckDetector;

/// A measurement that can be applied to a filter of type `F`, type-erased so a
/// scenario can mix the sensors of one model in one queue.
pub trait Measurement<F> {
    /// Refuses a measurement that can never be applied (non-finite values).
    ///
    /// # Errors
    /// The [`FilterError`] the filter would return.
    fn check(&self) -> Result<(), FilterError>;
    /// Applies the measurement to `filter` at its current time.
    ///
    /// # Errors
    /// As the filter's update; the filter is unchanged on error.
    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError>;
    /// The raw values the sensor reported (at most [`MAX_RAW_VALUES`]), for the
    /// frozen-value check of [`StuckDetector`]; empty (the default) disables
    /// the check for this measurement.
    fn raw_values(&self) -> &[f64] {
        &[]
    }
}

/// The dimension-free part of an [`UpdateReport`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MeasurementOutcome {
    /// Passed the gate and applied.
    pub accepted: bool,
    /// Normalized innovation squared.
    pub nis: f64,
    /// Gate threshold, `None` if gating is disabled.
    pub threshold: Option<f64>,
    /// Measurement dimension (degrees of freedom of the NIS).
    pub dof: usize,
    /// The innovation weighed against its covariance and noise (for the
    /// per-sensor NIS and noise tuning); default when not an update.
    pub statistics: InnovationStatistics,
    /// `Some(s)`: the filter recovered after this refused reading, which
    /// ended a run of refusals `s` seconds long ([`crate::recovery`]).
    pub recovered: Option<f64>,
}

impl MeasurementOutcome {
    /// The outcome of a measurement that only marks a time (an estimate
    /// asked for, an epoch of a recording): applied, no innovation.
    pub fn marker() -> Self {
        Self {
            accepted: true,
            nis: 0.0,
            threshold: None,
            dof: 0,
            statistics: InnovationStatistics::default(),
            recovered: None,
        }
    }
}

impl<const M: usize> From<&UpdateReport<M>> for MeasurementOutcome {
    fn from(r: &UpdateReport<M>) -> Self {
        Self {
            accepted: r.accepted,
            nis: r.nis,
            threshold: r.threshold,
            dof: M,
            statistics: r.statistics(),
            recovered: r.recovered,
        }
    }
}

/// How the noise of a [`SensorUpdate`] is given, which selects the update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum MeasurementNoise<const M: usize> {
    /// Full covariance: batch update ([`crate::ekf::Ekf::update`]).
    Full(SMatrix<f64, M, M>),
    /// Diagonal variances: sequential scalar update
    /// ([`crate::ekf::Ekf::update_sequential`]).
    Diagonal(SVector<f64, M>),
}

/// A measurement `z` of sensor `S` with its noise and auxiliary input; the
/// [`Measurement`] implementation for any [`Estimator`] of `S`'s model.
///
/// `z` is fixed when the measurement is pushed. For an error-state filter the
/// update takes a residual (INS value minus sensor value) that depends on the
/// nominal solution at the measurement time, which a delayed measurement only
/// meets during the replay: use [`FnMeasurement`] to form it there.
pub struct SensorUpdate<S: Sensor<N, M>, const N: usize, const M: usize> {
    /// The measurement (for an error-state filter: INS value minus sensor value).
    pub z: SVector<f64, M>,
    /// Its noise.
    pub noise: MeasurementNoise<M>,
    /// The sensor's auxiliary input.
    pub aux: S::Aux,
    _sensor: PhantomData<fn() -> S>,
}

impl<S: Sensor<N, M>, const N: usize, const M: usize> SensorUpdate<S, N, M> {
    /// A measurement fused with the batch update and full covariance `r`.
    pub fn new(z: SVector<f64, M>, r: SMatrix<f64, M, M>, aux: S::Aux) -> Self {
        Self {
            z,
            noise: MeasurementNoise::Full(r),
            aux,
            _sensor: PhantomData,
        }
    }

    /// A measurement with diagonal noise, fused by sequential scalar updates.
    pub fn sequential(z: SVector<f64, M>, r_diag: SVector<f64, M>, aux: S::Aux) -> Self {
        Self {
            z,
            noise: MeasurementNoise::Diagonal(r_diag),
            aux,
            _sensor: PhantomData,
        }
    }
}

impl<F, S, const N: usize, const M: usize> Measurement<F> for SensorUpdate<S, N, M>
where
    S: Sensor<N, M>,
    F: Estimator<N, Model = S::Model>,
{
    fn check(&self) -> Result<(), FilterError> {
        if let Some(index) = self.z.iter().position(|v| !v.is_finite()) {
            return Err(FilterError::NonFiniteMeasurement { index });
        }
        let finite = match &self.noise {
            MeasurementNoise::Full(r) => r.iter().all(|v| v.is_finite()),
            MeasurementNoise::Diagonal(r) => r.iter().all(|v| v.is_finite()),
        };
        if !finite {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "not finite",
            });
        }
        if let Some(index) = (0..<S::Aux as Record>::LEN).find(|&i| !self.aux.get(i).is_finite()) {
            let name = <S::Aux as Record>::NAMES.get(index).copied().unwrap_or("?");
            return Err(FilterError::NonFiniteAux { index, name });
        }
        Ok(())
    }

    fn raw_values(&self) -> &[f64] {
        let z = self.z.as_slice();
        z.get(..MAX_RAW_VALUES).unwrap_or(z)
    }

    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError> {
        let report = match &self.noise {
            MeasurementNoise::Full(r) => filter.update::<S, M>(&self.z, r, &self.aux)?,
            MeasurementNoise::Diagonal(r) => {
                filter.update_sequential::<S, M>(&self.z, r, &self.aux)?
            }
        };
        Ok(MeasurementOutcome::from(&report))
    }
}

/// A measurement given as a closure that updates the filter, for what a fixed
/// `z` cannot express: an error-state residual formed from the nominal solution
/// at the measurement time (which, for a delayed measurement, is known only
/// during the replay), or a sensor-specific preprocessing step.
///
/// ```ignore
/// let m = FnMeasurement::new(&[z_depth, r_depth], move |f: &mut Esf| {
///     let residual = SVector::from([f.nominal().height() - z_depth]);
///     f.update::<Depth, 1>(&residual, &r, &()).map(|r| MeasurementOutcome::from(&r))
/// });
/// ```
pub struct FnMeasurement<C> {
    finite: bool,
    raw: [f64; MAX_RAW_VALUES],
    raw_len: usize,
    apply: C,
}

impl<C> FnMeasurement<C> {
    /// Wraps `apply`; `values` are the raw sensor values it captured, checked
    /// for finiteness so a non-finite measurement is refused before
    /// scheduling, and (the first [`MAX_RAW_VALUES`]) compared with the
    /// previous ones of the sensor by a [`StuckDetector`].
    pub fn new(values: &[f64], apply: C) -> Self {
        let mut raw = [0.0; MAX_RAW_VALUES];
        let raw_len = values.len().min(MAX_RAW_VALUES);
        raw[..raw_len].copy_from_slice(&values[..raw_len]);
        Self {
            finite: values.iter().all(|v| v.is_finite()),
            raw,
            raw_len,
            apply,
        }
    }
}

impl<F, C> Measurement<F> for FnMeasurement<C>
where
    C: Fn(&mut F) -> Result<MeasurementOutcome, FilterError>,
{
    fn check(&self) -> Result<(), FilterError> {
        if self.finite {
            Ok(())
        } else {
            Err(FilterError::NonFiniteMeasurement { index: 0 })
        }
    }

    fn apply(&self, filter: &mut F) -> Result<MeasurementOutcome, FilterError> {
        (self.apply)(filter)
    }

    fn raw_values(&self) -> &[f64] {
        self.raw.get(..self.raw_len).unwrap_or(&[])
    }
}
