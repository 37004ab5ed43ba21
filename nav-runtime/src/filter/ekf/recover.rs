//! The recovery step of the filter after an update ([`crate::recovery`]):
//! the reading judged, and `P` inflated when the sensor's refused readings
//! show that the filter, not the sensor, is wrong.

use core::any::TypeId;

use super::{Ekf, UpdateReport};
use crate::model::{Model, Sensor};
use crate::real::Real;
use crate::recovery::{Judgement, INFLATION_FACTOR};

/// Largest factor on a state's sigma in step R1 of a recovery: sigmas grow
/// at most a hundredfold, however large the refused readings' NIS (docs/lockout.md).
const MAX_RECOVERY_SCALE: f64 = 100.0;

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// The recovery step after an update of sensor `S` that returned
    /// `report` for the reading `reading` (the sensor's own values, each
    /// component with its 1-sigma noise in `sigma`; `S::ANGLES` says which
    /// are angles): the reading is judged ([`Judgement`]); on
    /// [`Judgement::Recover`] `P` is inflated in two steps (eqs. R1, R2 of
    /// docs/lockout.md). R1: the rows and columns of the states in the
    /// rule's [`crate::recovery::RecoveryRule::scaled_states`] that the
    /// sensor observes (a non-zero column of `H`) are scaled by `k =
    /// sqrt(max(1, NIS / M))`, `P <- D P D` (the filter was too sure of them
    /// by about that much; their correlations are kept). R2: `P <- P + d
    /// d^T` with `d = U C^-1 (c nu)` (`U = P H^T`, `C = H P H^T` of the
    /// scaled `P`, `c` = [`INFLATION_FACTOR`]; eq. L4 with the refused
    /// innovation itself), so that the next reading passes the gate. The
    /// run of the lock-out release is
    /// forgotten, [`crate::ekf::FilterCounters::recoveries`] counts it and
    /// `report.recovered` gets the run's duration. No reading is applied.
    /// If `C` has no Cholesky factor or the result is not finite, nothing
    /// changes and [`Judgement::Following`] is returned.
    pub fn recover_after_refusal<S, const M: usize>(
        &mut self,
        report: &mut UpdateReport<M, T>,
        reading: &[f64],
        sigma: &[f64],
        aux: &S::Aux,
    ) -> Judgement
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        let sensor = TypeId::of::<S>();
        let judgement = self.lockout.recovery.judge(
            sensor,
            S::NAME,
            report.accepted,
            reading,
            sigma,
            &S::ANGLES,
        );
        let Judgement::Recover(lasted) = judgement else {
            return judgement;
        };
        // R1: the states of the rule's mask that the sensor observes (a
        // non-zero column of `H`) scaled by `k = sqrt(max(1, NIS / M))`.
        let mask = self
            .lockout
            .recovery
            .rule(S::NAME)
            .map_or(0, |r| r.scaled_states);
        let mut scaled = self.p;
        if mask != 0 {
            let h = S::jacobian(&self.x, &self.input, &self.params, aux);
            // Held below MAX_RECOVERY_SCALE: a NIS of 1e12 (a filter fed
            // garbage) would scale the covariance past any meaning.
            let k = T::of(libm::sqrt((report.nis / M as f64).max(1.0)).min(MAX_RECOVERY_SCALE));
            let mut scale = [T::one(); N];
            for (j, s) in scale.iter_mut().enumerate() {
                let in_mask = j < 64 && mask & (1u64 << j) != 0;
                if in_mask && (0..M).any(|i| h[(i, j)] != T::zero()) {
                    *s = k;
                }
            }
            for i in 0..N {
                for j in 0..N {
                    // `k_i k_j == k_j k_i` exactly: `P` stays symmetric.
                    scaled[(i, j)] *= scale[i] * scale[j];
                }
            }
        }
        // R2 (eq. L4 with the refused innovation) on the scaled `P`.
        let (_, u, hph) = S::innovation_terms(&scaled, &self.x, &self.input, &self.params, aux);
        let b = report.innovation * T::of(INFLATION_FACTOR);
        match crate::lockout::inflation(&scaled, &u, &hph, &b)
            .filter(|p| p.iter().all(|v| v.is_finite()))
        {
            Some(inflated) => {
                self.p = inflated;
                self.clean = false;
                self.lockout.clear(sensor);
                self.counters.recoveries += 1;
                report.recovered = Some(lasted);
                judgement
            }
            None => Judgement::Following,
        }
    }
}
