//! Why a filter or one of its gates could not be built or configured.
//!
//! Shared by the gate ([`crate::gate::Gate::new`]) and the filter
//! constructors and setters, so that neither imports the other.

/// Why a filter could not be built or configured (constructors and setters).
/// Unlike a [`crate::ekf::FilterError`], which refuses one step of a running filter, a
/// setup error means the filter, its gate or its settings are wrong before it
/// runs. The filter is unchanged after any of these.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum SetupError {
    /// The initial state, covariance, parameters or noise densities are invalid.
    #[error("invalid filter setup: {reason}")]
    Invalid {
        /// What is wrong.
        reason: &'static str,
    },
    /// A gate probability outside (0, 1).
    #[error("gate probability {probability} is not in (0, 1)")]
    InvalidProbability {
        /// The offending probability.
        probability: f64,
    },
    /// More per-sensor gate settings than [`crate::ekf::MAX_SENSOR_GATES`].
    #[error("too many per-sensor gate settings (capacity {capacity})")]
    TooManySensorGates {
        /// The fixed capacity.
        capacity: usize,
    },
}
