//! The recovery step of the filter after an update ([`crate::recovery`]):
//! the reading judged, and `P` inflated when the sensor's refused readings
//! show that the filter, not the sensor, is wrong.

use core::any::TypeId;

use super::{Ekf, UpdateReport};
use crate::model::{Model, Sensor};
use crate::real::Real;
use crate::recovery::{Judgement, INFLATION_FACTOR};

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// The recovery step after an update of sensor `S` that returned
    /// `report` for the reading `reading` (the sensor's own values, each
    /// component with its 1-sigma noise in `sigma`; `S::ANGLES` says which
    /// are angles): the reading is judged ([`Judgement`]); on
    /// [`Judgement::Recover`] `P` is inflated along the states the sensor
    /// observes, `P <- P + d d^T` with `d = U C^-1 (c nu)` (`U = P H^T`, `C =
    /// H P H^T`, `c` = [`INFLATION_FACTOR`]; eq. L4 of docs/lockout.md with
    /// the refused innovation itself), so that the next reading passes the
    /// gate. The run of the lock-out release is
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
        let (_, u, hph) = S::innovation_terms(&self.p, &self.x, &self.input, &self.params, aux);
        let b = report.innovation * T::of(INFLATION_FACTOR);
        match crate::lockout::inflation(&self.p, &u, &hph, &b) {
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
