//! Fixed-interval smoothing of a forward filter run (Rauch-Tung-Striebel).
//!
//! The forward filter is run as usual; a [`Recorder`] beside it writes, at
//! every *epoch* (a time at which the filter fused measurements, or at which
//! an output is wanted), what the backward pass needs: the transition matrix
//! from the previous epoch, the covariance before and after the epoch's
//! updates, the correction applied to the estimate at the epoch, and a
//! snapshot of the estimate. The records go to an [`EpochFile`], a temporary
//! file, so a run of any length is smoothed with bounded memory. [`smooth`]
//! then walks the file backwards and hands every epoch's smoothed error and
//! covariance to the caller, latest first.
//!
//! The same recursion serves a plain EKF and an indirect-feedback error-state
//! filter, because both are described by the *error of the forward solution*
//! `e = x_forward - x_true` (the project's sign convention, see
//! `docs/smoother.md`): after the updates at epoch `k` the forward error
//! estimate is zero with covariance `P_k+`; it propagates to zero with
//! `P_{k+1}- = Phi_k P_k+ Phi_k^T + Q_k`; the updates at `k + 1` move the
//! forward solution by `-c_{k+1}` (for an error-state filter `c` is the
//! error estimate fed back into the nominal solution, for a plain EKF
//! `c = x- - x+`). Hence the smoothed error of the solution *before* the
//! updates at `k + 1` is `s_{k+1} + c_{k+1}`, and (docs/smoother.md, eq. S1-S3)
//!
//! ```text
//! C_k   = P_k+ Phi_k^T (P_{k+1}-)^-1
//! s_k   = C_k (s_{k+1} + c_{k+1}),                    s_K = 0
//! Ps_k  = P_k+ + C_k (Ps_{k+1} - P_{k+1}-) C_k^T,     Ps_K = P_K+
//! ```
//!
//! and the smoothed estimate at epoch `k` is the forward estimate with the
//! error `s_k` removed (for an error-state filter: `NominalState::inject(s_k)`
//! on the recorded nominal solution).
//!
//! Only the epochs with updates are links of this recursion: an output epoch
//! `j` (no update, `P_j+ = P_j-`, `c_j = 0`) changes nothing in it, so it is
//! derived directly from the next epoch with updates `u`, with
//! `C_j = P_j+ Phi(u, j)^T (P_u-)^-1` over the product of the transitions
//! between them (exact; the backward pass's module docs give the form
//! computed). [`smooth_states`] reports the smoothed covariance between
//! chosen states only, which at the output epochs is all it computes.
//!
//! Late measurements: the scheduler restores a checkpoint (a clone of the
//! filter, recorder included) and re-propagates. Every recorder clone knows
//! how many records were valid on its own history, and truncates the file to
//! that length before it writes, so a re-propagated span replaces the records
//! it supersedes.

mod backward;
mod epoch;
mod observability;
mod recorder;
mod sensor_information;
mod spill;
mod store;

pub use backward::{smooth, smooth_states, SmoothedEpoch, States};
pub use epoch::Epoch;
pub use observability::{observability, Direction, Observability};
pub use recorder::Recorder;
pub use sensor_information::{diagonal_inverse, SensorInformation, MAX_TRACKED_SENSORS};
pub use spill::SpillFile;
pub use store::{EpochFile, SmootherError};

#[cfg(test)]
mod tests;
