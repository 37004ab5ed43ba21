//! The filter core: the EKF, its gates, the error-state wrapper, the sparse
//! covariance propagation kernels, the frozen-value detector and the scalar
//! math they share. Always compiled and `no_std` (`core` + libm); only the
//! multi-rate [`scheduler`] needs the `std` feature (it keeps a heap history).
//!
//! Every module is also re-exported at the crate root (`nav_runtime::ekf`,
//! `nav_runtime::gate`, ...), the paths the generated code uses.

pub(crate) mod dispatch;
pub mod ekf;
pub mod error_state;
pub mod gate;
pub mod innovations;
pub mod lockout;
pub mod math;
pub mod propagation;
pub mod real;
pub mod recovery;
#[cfg(feature = "std")]
pub mod scheduler;
pub mod setup_error;
#[cfg(feature = "std")]
pub mod smoother;
pub mod stuck;
