//! The backward pass: Rauch-Tung-Striebel over the recorded epochs.

use nalgebra::{SMatrix, SVector};

use super::epoch::Epoch;
use super::store::{EpochFile, SmootherError};

/// One epoch of the smoothed run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothedEpoch<const N: usize, const S: usize> {
    /// Time of the epoch, s.
    pub time: f64,
    /// The forward estimate's snapshot, as recorded.
    pub snapshot: SVector<f64, S>,
    /// Smoothed error of the forward estimate, `s_k` (forward minus true):
    /// the smoothed estimate is the forward one with `s_k` removed.
    pub error: SVector<f64, N>,
    /// Covariance of the smoothed estimate's error, `Ps_k`.
    pub covariance: SMatrix<f64, N, N>,
    /// Covariance of the forward estimate's error, `P_k+`.
    pub filtered: SMatrix<f64, N, N>,
}

/// Smooths the epochs of `file` and calls `visit` with each, latest first
/// (module docs; `docs/smoother.md`, eq. S1-S3). Memory: two epochs.
///
/// # Errors
/// [`SmootherError::NotPositiveDefinite`] if a predicted covariance has no
/// Cholesky factor, [`SmootherError::NonFinite`] for a non-finite result,
/// [`SmootherError::Io`] on a failed read, or the first error of `visit`.
pub fn smooth<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    mut visit: impl FnMut(&SmoothedEpoch<N, S>) -> Result<(), SmootherError>,
) -> Result<(), SmootherError> {
    // The later epoch k + 1 and its smoothed error and covariance.
    let mut later: Option<(Epoch<N, S>, SVector<f64, N>, SMatrix<f64, N, N>)> = None;
    file.read_back(|epoch| {
        let (error, covariance) = match &later {
            None => (SVector::zeros(), epoch.filtered),
            Some((next, next_error, next_cov)) => {
                let chol = next
                    .predicted
                    .cholesky()
                    .ok_or(SmootherError::NotPositiveDefinite { time: next.time })?;
                // C^T = (P_{k+1}-)^-1 Phi_k P_k+   (P_{k+1}- symmetric)
                let gain = chol.solve(&(next.transition * epoch.filtered)).transpose();
                let error = gain * (next_error + next.correction);
                let mut cov =
                    epoch.filtered + gain * (next_cov - next.predicted) * gain.transpose();
                cov = (cov + cov.transpose()) * 0.5;
                (error, cov)
            }
        };
        if error
            .iter()
            .chain(covariance.iter())
            .any(|v| !v.is_finite())
        {
            return Err(SmootherError::NonFinite { time: epoch.time });
        }
        visit(&SmoothedEpoch {
            time: epoch.time,
            snapshot: epoch.snapshot,
            error,
            covariance,
            filtered: epoch.filtered,
        })?;
        later = Some((*epoch, error, covariance));
        Ok(())
    })
}
