//! A registered sensor with its type erased: what the replay needs of a
//! generated [`Sensor`] to feed it from rows (its names, its gate, and the
//! update built from one row's values).

use std::marker::PhantomData;

use nav_runtime::ekf::{FilterError, Propagate};
use nav_runtime::gate::Gate;
use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::SVector;
use nav_runtime::scheduler::{Measurement, MeasurementOutcome, SensorUpdate};

use super::declared::DeclaredSensor;
use super::ModelFilter;

/// A sensor of model `M` fed from a log file (see the module docs).
pub trait Feed<M: Model<N>, const N: usize>: Send + Sync {
    /// Its declared names.
    fn declared(&self) -> DeclaredSensor;
    /// Gives it its gate (`None`: no gate).
    ///
    /// # Errors
    /// An invalid probability, or too many sensor gates on one filter.
    fn set_gate(
        &self,
        filter: &mut ModelFilter<M, N>,
        probability: Option<f64>,
    ) -> Result<(), String>;
    /// The update of one row: `values` holds the `K` outputs, then the
    /// auxiliary inputs; `sigma` the noise sigma per output.
    fn measurement(&self, values: &[f64], sigma: &[f64])
        -> Box<dyn Measurement<ModelFilter<M, N>>>;
    /// Applies one row to `filter` directly (a row at the initial epoch,
    /// before the scheduler starts).
    ///
    /// # Errors
    /// As [`nav_runtime::ekf::Ekf::update_sequential`].
    fn apply(
        &self,
        filter: &mut ModelFilter<M, N>,
        values: &[f64],
        sigma: &[f64],
    ) -> Result<MeasurementOutcome, FilterError>;
}

/// The [`Feed`] of generated sensor `S` with `K` outputs.
pub struct FeedOf<S, const K: usize>(PhantomData<fn() -> S>);

impl<S, const K: usize> Default for FeedOf<S, K> {
    fn default() -> Self {
        FeedOf(PhantomData)
    }
}

fn parts<S: Sensor<N, K>, const N: usize, const K: usize>(
    values: &[f64],
    sigma: &[f64],
) -> (SVector<f64, K>, SVector<f64, K>, S::Aux) {
    let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
    let z = SVector::<f64, K>::from_fn(|i, _| at(values, i));
    let r = SVector::<f64, K>::from_fn(|i, _| at(sigma, i) * at(sigma, i));
    let aux = <S::Aux as Record>::from_fn(|i| at(values, K + i));
    (z, r, aux)
}

impl<M, S, const N: usize, const K: usize> Feed<M, N> for FeedOf<S, K>
where
    M: Model<N>,
    S: Sensor<N, K, Model = M>,
    ModelFilter<M, N>: Propagate + Clone + 'static,
{
    fn declared(&self) -> DeclaredSensor {
        DeclaredSensor::of::<S, N, K>()
    }

    fn set_gate(
        &self,
        filter: &mut ModelFilter<M, N>,
        probability: Option<f64>,
    ) -> Result<(), String> {
        let gate = probability
            .map(Gate::new)
            .transpose()
            .map_err(|e| e.to_string())?;
        filter
            .ekf_mut()
            .set_sensor_gate::<S, K>(gate)
            .map_err(|e| e.to_string())
    }

    fn measurement(
        &self,
        values: &[f64],
        sigma: &[f64],
    ) -> Box<dyn Measurement<ModelFilter<M, N>>> {
        let (z, r, aux) = parts::<S, N, K>(values, sigma);
        Box::new(SensorUpdate::<S, N, K>::sequential(z, r, aux))
    }

    fn apply(
        &self,
        filter: &mut ModelFilter<M, N>,
        values: &[f64],
        sigma: &[f64],
    ) -> Result<MeasurementOutcome, FilterError> {
        let (z, r, aux) = parts::<S, N, K>(values, sigma);
        filter
            .update_sequential::<S, K>(&z, &r, &aux)
            .map(|report| MeasurementOutcome::from(&report))
    }
}
