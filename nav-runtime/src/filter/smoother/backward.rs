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
                let gain = chol
                    .solve(&phi_times(&next.transition, &epoch.filtered))
                    .transpose();
                let error = gain * (next_error + next.correction);
                let d = next_cov - next.predicted;
                (error, rts_covariance(&epoch.filtered, &gain, &d))
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

/// `Phi P`, copying the rows of `P` where `Phi` has a unit row (states
/// without dynamics, e.g. random-constant biases, keep `e_i` rows in every
/// product of their transition matrices) and skipping zeros elsewhere.
fn phi_times<const N: usize>(
    phi: &SMatrix<f64, N, N>,
    p: &SMatrix<f64, N, N>,
) -> SMatrix<f64, N, N> {
    let mut out = SMatrix::<f64, N, N>::zeros();
    for i in 0..N {
        let unit = (0..N).all(|j| phi[(i, j)] == if i == j { 1.0 } else { 0.0 });
        if unit {
            out.set_row(i, &p.row(i));
            continue;
        }
        for j in (0..N).filter(|&j| phi[(i, j)] != 0.0) {
            let a = phi[(i, j)];
            for c in 0..N {
                out[(i, c)] += a * p[(j, c)];
            }
        }
    }
    out
}

/// `P+ + C D C^T` for symmetric `D`, on the upper triangle and mirrored, so
/// the result is exactly symmetric (eq. S3).
fn rts_covariance<const N: usize>(
    filtered: &SMatrix<f64, N, N>,
    gain: &SMatrix<f64, N, N>,
    d: &SMatrix<f64, N, N>,
) -> SMatrix<f64, N, N> {
    let cd_t = (gain * d).transpose();
    let gain_t = gain.transpose();
    let mut out = *filtered;
    for c in 0..N {
        for r in 0..=c {
            // (C D C^T)[r][c] = row r of C D . row c of C: columns of the transposes.
            let v = cd_t.column(r).dot(&gain_t.column(c));
            out[(r, c)] += v;
            out[(c, r)] = out[(r, c)];
        }
    }
    out
}
