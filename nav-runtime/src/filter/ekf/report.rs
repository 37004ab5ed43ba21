//! What the filter reports: one update's outcome and the running totals.

use nalgebra::{SMatrix, SVector};

use crate::innovations::InnovationStatistics;
use crate::real::Real;

/// Totals kept by the filter. Per-sensor statistics are the caller's, from the
/// [`UpdateReport`]s.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FilterCounters {
    /// Predictions performed.
    pub predictions: u64,
    /// Predictions refused with an error.
    pub predictions_rejected: u64,
    /// Updates applied (passed the gate).
    pub updates_accepted: u64,
    /// Updates refused by the innovation gate (state unchanged, no error).
    pub updates_gated: u64,
    /// Updates refused with an error.
    pub updates_rejected: u64,
    /// Covariance diagonal entries repaired (non-positive or non-finite after a
    /// prediction or an update); each repaired entry counts once.
    pub covariance_repairs: u64,
    /// Gate lock-out releases: runs of refused measurements of one sensor
    /// that agreed within their noise, after which the covariance of the
    /// states they observe was inflated (see [`crate::lockout`]; no
    /// measurement is applied by a release).
    pub updates_released: u64,
    /// Recoveries from a lock-out into divergence: runs of refused readings
    /// of one sensor that were plausible and agreed with one another for
    /// longer than the sensor's horizon, after which the covariance of the
    /// states it observes was inflated (see [`crate::recovery`]).
    pub recoveries: u64,
}

/// The outcome of one measurement update.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UpdateReport<const M: usize, T: Real = f64> {
    /// The sensor's declared name.
    pub sensor: &'static str,
    /// `true` if the update passed the gate and was applied.
    pub accepted: bool,
    /// Normalized innovation squared `nu^T S^-1 nu` (eq. U3), chi-square with M
    /// degrees of freedom for a consistent filter.
    pub nis: f64,
    /// The gate threshold that was applied, `None` if gating is disabled.
    pub threshold: Option<f64>,
    /// `nu = z - h(x)` with angle components wrapped to (-pi, pi] (eq. U1).
    pub innovation: SVector<T, M>,
    /// `S = H P H^T + R` (eq. U2).
    pub innovation_covariance: SMatrix<T, M, M>,
    /// `R`, the measurement noise covariance of this update (diagonal for
    /// the sequential update): with `S` it gives the noise's share of the
    /// innovation that noise tuning and the NIS check weigh
    /// ([`crate::innovations`]).
    pub noise: SMatrix<T, M, M>,
    /// Covariance diagonal entries repaired by this update.
    pub repairs: u32,
    /// `Some(s)`: this refused reading ended a run of refusals `s` seconds
    /// long after which the filter recovered ([`crate::recovery`]); set by
    /// [`crate::ekf::Ekf::recover_after_refusal`], `None` otherwise.
    pub recovered: Option<f64>,
}

impl<const M: usize, T: Real> UpdateReport<M, T> {
    /// What this update says about the noise of its sensor (for the
    /// innovation likelihood and the tuning of `R`, docs/tuning.md).
    pub fn statistics(&self) -> InnovationStatistics {
        InnovationStatistics::of(&self.innovation, &self.innovation_covariance, &self.noise)
    }
}
