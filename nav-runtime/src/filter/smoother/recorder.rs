//! The forward-pass side of the smoother: epochs into the epoch file.

use std::cell::RefCell;
use std::rc::Rc;

use nalgebra::{SMatrix, SVector};

use super::epoch::Epoch;
use super::store::{EpochFile, SmootherError};
use crate::model::Model;

/// Records a forward run for [`super::smooth`].
///
/// Drive it beside the filter: [`Recorder::propagated`] for every prediction
/// step (with the step's Jacobian), [`Recorder::updating`] before the first
/// update at a time and [`Recorder::updated`] after each update,
/// [`Recorder::mark`] at a time an output is wanted without an update, and
/// [`Recorder::finish`] at the end. An epoch is written when the first
/// prediction after it starts (or at `finish`), so every update of one time
/// lands in one epoch. The recorder keeps the time itself (the start plus
/// every step) and [`Recorder::mark`] re-synchronizes it.
///
/// Recording never fails in the forward pass (so a filter's predict and
/// update keep their error contract): the first failure is kept and returned
/// by [`Recorder::finish`].
///
/// A clone shares the file but keeps its own history: cloned with a filter
/// checkpoint and resumed after a rollback, it truncates the file to the
/// epochs of its own history before writing, so the re-propagated span
/// replaces the old one.
#[derive(Clone, Debug)]
pub struct Recorder<const N: usize, const S: usize> {
    store: Rc<RefCell<EpochFile<N, S>>>,
    /// Epochs of this history already in the file.
    written: usize,
    /// Time now, s.
    time: f64,
    /// `Phi` from the last epoch to now.
    transition: SMatrix<f64, N, N>,
    /// The epoch reached and not yet written.
    open: Option<Epoch<N, S>>,
    /// The first failure.
    failure: Option<Rc<str>>,
}

impl<const N: usize, const S: usize> Recorder<N, S> {
    /// Starts a recording at the filter's initial `time` (s), `covariance` and
    /// `snapshot`: the first epoch.
    pub fn new(
        store: EpochFile<N, S>,
        time: f64,
        covariance: &SMatrix<f64, N, N>,
        snapshot: SVector<f64, S>,
    ) -> Self {
        Self {
            store: Rc::new(RefCell::new(store)),
            written: 0,
            time,
            transition: SMatrix::identity(),
            open: Some(Epoch::at(time, SMatrix::identity(), *covariance, snapshot)),
            failure: None,
        }
    }

    /// The epoch file (shared by every clone).
    pub fn store(&self) -> Rc<RefCell<EpochFile<N, S>>> {
        Rc::clone(&self.store)
    }

    /// Time of the recording now (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    fn fail(&mut self, reason: String) {
        if self.failure.is_none() {
            self.failure = Some(Rc::from(reason));
        }
    }

    fn close(&mut self) {
        let Some(epoch) = self.open.take() else {
            return;
        };
        let result = match self.store.try_borrow_mut() {
            Ok(mut store) => store
                .truncate(self.written)
                .and_then(|()| store.push(&epoch))
                .map_err(|e| e.to_string()),
            Err(_) => Err("the epoch file was borrowed while recording".to_string()),
        };
        match result {
            Ok(()) => self.written += 1,
            Err(reason) => self.fail(reason),
        }
    }

    /// One prediction step of model `Mo` over `dt` seconds with the step's
    /// `jacobian` (`F` of a continuous model, so `Phi = I + F dt` as the
    /// filter's first-order step; `Phi` itself for a discrete model).
    /// Structural zeros of `Mo::JACOBIAN_SPARSITY` cost nothing.
    pub fn propagated<Mo: Model<N>>(&mut self, jacobian: &SMatrix<f64, N, N>, dt: f64) {
        self.close();
        self.time += dt;
        if Mo::DISCRETE {
            self.transition = jacobian * self.transition;
            return;
        }
        // T <- T + dt F T over the structural nonzeros of F (rows of F that
        // are zero leave their rows of T as they are). T is column-major:
        // entry (i, c) at c N + i.
        let t = self.transition.as_slice();
        let mut delta = [[0.0f64; N]; N]; // delta[c][i]
        for (i, row) in Mo::JACOBIAN_SPARSITY.iter().enumerate() {
            for (j, _) in row.iter().enumerate().filter(|(_, &nonzero)| nonzero) {
                let a = dt * jacobian[(i, j)];
                for (c, d) in delta.iter_mut().enumerate() {
                    d[i] += a * t[c * N + j];
                }
            }
        }
        for (column, d) in self
            .transition
            .as_mut_slice()
            .chunks_exact_mut(N)
            .zip(&delta)
        {
            for (x, dx) in column.iter_mut().zip(d) {
                *x += dx;
            }
        }
    }

    /// Opens the epoch at the current time before its first update, with the
    /// filter's covariance before the update; further calls at the same
    /// epoch change nothing.
    pub fn updating(&mut self, covariance: &SMatrix<f64, N, N>, snapshot: SVector<f64, S>) {
        if self.open.is_none() {
            self.open = Some(Epoch::at(self.time, self.transition, *covariance, snapshot));
            self.transition = SMatrix::identity();
        }
    }

    /// After an update of the open epoch: the `correction` it made (forward
    /// solution before minus after, in error-state coordinates: for an
    /// error-state filter the error estimate it fed back), the covariance
    /// after it and the snapshot of the corrected estimate.
    pub fn updated(
        &mut self,
        correction: &SVector<f64, N>,
        covariance: &SMatrix<f64, N, N>,
        snapshot: SVector<f64, S>,
    ) {
        if let Some(epoch) = self.open.as_mut() {
            epoch.correction += correction;
            epoch.filtered = *covariance;
            epoch.snapshot = snapshot;
        }
    }

    /// An epoch at `time` (s; an output time, re-synchronizing the
    /// recorder's clock), without update unless one follows.
    pub fn mark(&mut self, time: f64, covariance: &SMatrix<f64, N, N>, snapshot: SVector<f64, S>) {
        match self.open.as_mut() {
            Some(epoch) => epoch.time = time,
            None => {
                self.time = time;
                self.updating(covariance, snapshot);
            }
        }
        self.time = time;
    }

    /// Writes the open epoch and drops epochs of superseded histories; call
    /// at the end of the run (after a final [`Recorder::mark`] if the last
    /// prediction steps should be smoothed).
    ///
    /// # Errors
    /// [`SmootherError::Recording`] with the first failure of the run, or
    /// [`SmootherError::Io`] if the final write fails.
    pub fn finish(&mut self) -> Result<(), SmootherError> {
        self.close();
        if let Some(reason) = &self.failure {
            return Err(SmootherError::Recording {
                reason: reason.to_string(),
            });
        }
        self.store.borrow_mut().truncate(self.written)
    }
}
