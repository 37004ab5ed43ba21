//! Why a filter step was refused.

use crate::setup_error::SetupError;

/// Why a filter operation was refused. After any of these the filter state
/// (`x`, `P`, last input) is unchanged; only the counters record the refusal.
#[derive(Clone, Copy, Debug, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum FilterError {
    /// The time step is zero, negative or not finite.
    #[error("time step {dt} s is not finite and positive")]
    InvalidTimeStep {
        /// The offending time step, in seconds.
        dt: f64,
    },
    /// An input scalar (IMU sample, nominal solution, ...) is NaN or infinite.
    #[error("input scalar {index} (`{name}`) is not finite")]
    NonFiniteInput {
        /// Index of the scalar in the input record.
        index: usize,
        /// Its declared name.
        name: &'static str,
    },
    /// A measurement component is NaN or infinite.
    #[error("measurement component {index} is not finite")]
    NonFiniteMeasurement {
        /// Index in the measurement vector.
        index: usize,
    },
    /// The measurement noise covariance is not finite, not symmetric or has a
    /// negative variance.
    #[error("measurement noise covariance is invalid: {reason}")]
    InvalidMeasurementNoise {
        /// What is wrong with it.
        reason: &'static str,
    },
    /// A sensor auxiliary input is NaN or infinite.
    #[error("auxiliary input {index} (`{name}`) is not finite")]
    NonFiniteAux {
        /// Index of the scalar in the auxiliary record.
        index: usize,
        /// Its declared name.
        name: &'static str,
    },
    /// `S = H P H^T + R` has no Cholesky factor (singular or indefinite).
    #[error("innovation covariance of sensor `{sensor}` is not positive definite")]
    InnovationCovarianceNotPositiveDefinite {
        /// The sensor's declared name.
        sensor: &'static str,
    },
    /// The model or sensor functions produced NaN or infinity; nothing was stored.
    #[error("{stage} produced a non-finite value")]
    NonFiniteResult {
        /// Which computation: `"prediction"`, `"measurement model"`, `"update"`.
        stage: &'static str,
    },
    /// A setup error met during a step (e.g. a sensor the filter was not
    /// built with); the setters and constructors return [`SetupError`] itself.
    #[error(transparent)]
    Setup(#[from] SetupError),
}
