//! The extended Kalman filter core: prediction, batch and sequential updates,
//! innovation gating and covariance repair for any [`Model`] and its [`Sensor`](crate::model::Sensor)s.
//!
//! Everything in this module is `core` only (no `std`, no heap): matrices are
//! `SMatrix` on the stack, factorizations are nalgebra's static Cholesky, and no
//! path in [`Ekf::predict`] or [`Ekf::update`] can panic (no `unwrap`, no
//! fallible indexing). Bad input is refused with a [`FilterError`] *before*
//! anything is mutated, so the filter state after an error is bit-identical to
//! the state before it.
//!
//! Equations (Bar-Shalom, Li & Kirubarajan 2001, ch. 5; Brown & Hwang,
//! *Introduction to Random Signals and Applied Kalman Filtering*, 4th ed., ch. 7):
//!
//! ```text
//! predict:  x <- f(x, u, p, dt)                        (model transition)
//!           P <- Phi P Phi^T + Qd                      (eq. P1)
//! update:   nu = z - h(x)       (angles wrapped)       (eq. U1)
//!           U  = P H^T,  S = H P H^T + R               (eq. U2)
//!           NIS = nu^T S^-1 nu  (gated against chi2(M)) (eq. U3)
//!           K  = U S^-1                                (eq. U4, by Cholesky solve)
//!           x <- x + K nu                              (eq. U5)
//!           P <- P - K U^T - U K^T + K S K^T           (eq. U6, Joseph form)
//! ```
//!
//! Eq. U6 is the Joseph form `(I - K H) P (I - K H)^T + K R K^T` expanded with
//! `U = P H^T`: it is valid for *any* gain (so rounding in `K` cannot make `P`
//! indefinite to first order) and costs O(N^2 M) instead of the O(N^3) of the
//! textbook product.
//!
//! The module is split by facet, re-exported flat: [`Ekf`] and its setup
//! (`setup`), the covariance lifecycle (`covariance`: checks, repair,
//! symmetry), prediction (`predict`), updates (`update`) and the Joseph kernel
//! (`joseph`), gating and lock-out (`gating`), input validation
//! (`validation`), discretization of continuous models (`discretization`),
//! the errors (`error`) and the reports and totals (`report`).

use core::marker::PhantomData;

use nalgebra::{SMatrix, SVector};

use crate::gate::Gate;
use crate::model::Model;
use crate::real::Real;

mod changed;
mod covariance;
mod discretization;
mod error;
mod gating;
mod joseph;
mod predict;
mod recover;
mod report;
mod setup;
#[cfg(all(test, feature = "std"))]
mod tests;
mod update;
mod validation;

pub use crate::setup_error::SetupError;
pub use covariance::DEFAULT_VARIANCE_FLOOR;
pub use discretization::{second_order, van_loan, Discretization};
pub use error::FilterError;
pub use gating::MAX_SENSOR_GATES;
pub use predict::Propagate;
pub use report::{FilterCounters, UpdateReport};
pub use update::Estimator;

use gating::GateTable;

/// An extended Kalman filter for model `Mo` with `N` states, computed in
/// the model's scalar `T` (`f64` unless the model is declared `scalar f32;`).
///
/// Holds the state `x`, its covariance `P` (kept exactly symmetric), the model
/// parameters and process-noise intensities, the last input (used by sensors
/// whose `h` depends on it), the discretization, the gates and the counters.
/// The whole filter is a plain value: cloning it is a checkpoint.
pub struct Ekf<Mo: Model<N, T>, const N: usize, T: Real = f64> {
    x: SVector<T, N>,
    p: SMatrix<T, N, N>,
    params: Mo::Params,
    noise: Mo::Noise,
    input: Mo::Input,
    discretization: Discretization,
    default_gate: Option<Gate>,
    gates: GateTable,
    /// Gate lock-out release state (see [`crate::lockout`]).
    pub(crate) lockout: crate::lockout::Lockout,
    variance_floor: f64,
    counters: FilterCounters,
    /// `true` while `P` is known clean (every entry finite, every variance
    /// positive): set by the checks that end every prediction and update,
    /// cleared when `P` is set or inflated from outside them. A prediction
    /// over a known structure then checks only the entries it changes.
    clean: bool,
    /// Work space of a prediction over [`Model::PROPAGATION`]: the entries
    /// of `P` it changes, saved before the step to restore them if it fails
    /// (no meaning between calls; not copied by `clone_from`).
    saved: [[T; N]; N],
    _model: PhantomData<fn() -> Mo>,
}
