//! The smoothed pass of a model replay (`--smooth`,
//! `docs/model-replay.md`, "Smoothing"): the forward run is recorded as an
//! INS replay's is, every estimate it hands on is an epoch of the recording,
//! and after the run the fixed-interval smoother (`docs/smoother.md`) gives
//! each of them its smoothed counterpart, `x_s = x_f + s_k` with `s_k` the
//! smoothed error of the forward estimate (the recorded corrections are
//! the filter's updates, after minus before, so the error is added, as a
//! vehicle's nominal absorbs it).
//!
//! Nothing of the run is held in memory: the forward estimates wait in a
//! temporary file ([`Forward`]) and come back latest first, as the smoother
//! meets the epochs.

use nav_runtime::model::Model;
use nav_runtime::nalgebra::{SMatrix, SVector};
use nav_runtime::smoother::{smooth_states, EpochFile, SmootherError, SpillFile, States};

/// Two times closer than this are the same epoch (s).
const SAME_EPOCH_S: f64 = 1e-9;

/// The forward estimates the smoother corrects, in the order handed on:
/// per estimate its time, whether it was written to `estimates.csv`, the
/// state and the truth values at its time (NaN for a state the truth file
/// lacks or a sample without a truth row).
pub(super) struct Forward<const N: usize> {
    file: SpillFile,
}

/// One smoothed estimate.
pub(super) struct Smoothed<const N: usize> {
    /// Time, s.
    pub t: f64,
    /// Whether its forward estimate was written (`--every`).
    pub written: bool,
    /// The smoothed state (angles wrapped, quaternions normalized).
    pub x: SVector<f64, N>,
    /// Its covariance.
    pub p: SMatrix<f64, N, N>,
    /// The truth at its time, when the forward estimate was scored.
    pub truth: Option<[f64; N]>,
}

impl<const N: usize> Forward<N> {
    const WIDTH: usize = 2 + 2 * N;

    /// An empty spill file.
    pub(super) fn create() -> Result<Self, SmootherError> {
        Ok(Forward {
            file: SpillFile::create(None, Self::WIDTH)?,
        })
    }

    /// Adds the forward estimate `x` at `t`.
    pub(super) fn push(
        &mut self,
        t: f64,
        written: bool,
        x: &SVector<f64, N>,
        truth: Option<&[f64]>,
        has: Option<&[bool; N]>,
    ) -> Result<(), SmootherError> {
        let mut record = vec![f64::NAN; Self::WIDTH];
        record[0] = t;
        record[1] = f64::from(u8::from(written));
        record[2..2 + N].copy_from_slice(x.as_slice());
        if let (Some(values), Some(has)) = (truth, has) {
            for i in (0..N).filter(|&i| has[i]) {
                record[2 + N + i] = values[i];
            }
        }
        self.file.push(&record)
    }

    /// The latest estimate not yet taken: time, written, state, truth.
    fn pop(&mut self) -> Result<Option<Smoothed<N>>, SmootherError> {
        let mut record = vec![0.0; Self::WIDTH];
        if !self.file.pop(&mut record)? {
            return Ok(None);
        }
        let truth: [f64; N] = std::array::from_fn(|i| record[2 + N + i]);
        Ok(Some(Smoothed {
            t: record[0],
            written: record[1] != 0.0,
            x: SVector::from_column_slice(&record[2..2 + N]),
            p: SMatrix::zeros(),
            truth: truth.iter().any(|v| !v.is_nan()).then_some(truth),
        }))
    }
}

/// Smooths the recorded run of `file` and hands each forward estimate of
/// `forward` its smoothed counterpart, latest first, to `visit`. Returns
/// the number of forward estimates without an epoch in the recording
/// (none in a run that marked every one; counted, never guessed).
///
/// # Errors
/// A read or write error of the temporary files, a non-finite smoothed
/// error, or the first error of `visit`.
pub(super) fn smooth<M: Model<N>, const N: usize>(
    file: &mut EpochFile<N, 0>,
    forward: &mut Forward<N>,
    mut visit: impl FnMut(&Smoothed<N>) -> Result<(), SmootherError>,
) -> Result<u64, SmootherError> {
    let mut pending = forward.pop()?;
    let mut unmatched = 0u64;
    smooth_states(file, &States::all(), |epoch| {
        while let Some(mut e) = pending.take() {
            if e.t < epoch.time - SAME_EPOCH_S {
                // An epoch of the recording that is no output (a
                // propagation step); the estimate waits for its own.
                pending = Some(e);
                break;
            }
            if (e.t - epoch.time).abs() <= SAME_EPOCH_S {
                e.x += epoch.error;
                M::normalize_state(&mut e.x);
                e.p = epoch.covariance;
                visit(&e)?;
            } else {
                unmatched += 1;
            }
            pending = forward.pop()?;
        }
        Ok(())
    })?;
    while pending.is_some() {
        unmatched += 1;
        pending = forward.pop()?;
    }
    Ok(unmatched)
}
