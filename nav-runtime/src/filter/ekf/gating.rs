//! Innovation gating and the gate lock-out release: the per-sensor gate
//! table, the run of refusals per sensor and the accept decision.

use core::any::TypeId;

use super::{Ekf, SetupError, UpdateReport};
use crate::gate::Gate;
use crate::model::{Model, Sensor};

/// Number of sensors whose gate can be set individually on one filter.
pub const MAX_SENSOR_GATES: usize = 16;

impl<Mo: Model<N>, const N: usize> Ekf<Mo, N> {
    /// Gate lock-out release: after `limit` consecutive gate refusals of one
    /// sensor, its next measurement is applied whatever its NIS (`None`, the
    /// default: never). See [`Ekf::set_lockout_release`].
    #[must_use]
    pub fn with_lockout_release(mut self, limit: Option<u32>) -> Self {
        self.lockout_release = limit;
        self
    }

    /// Changes the gate lock-out release (`None`: never).
    ///
    /// The gate assumes that the predicted innovation covariance `S` is right.
    /// It is not after the filter has accepted an outlier it could not
    /// recognise (while `H P H^T` was much larger than `R`, a 10-sigma outlier
    /// is a small fraction of `sqrt(S)`): the estimate is then off by the
    /// outlier while `S` has shrunk, and every later, correct measurement of
    /// that sensor fails the gate (lock-out). A consistent filter refuses
    /// `limit` good measurements in a row with probability `(1 - p)^limit`
    /// (1e-12 for `limit = 3` at the default `p`), and independent outliers
    /// at rate `e` come `limit` in a row with probability `e^limit`; a longer
    /// run of refusals means the filter, not the sensor, is wrong, so the
    /// next measurement is applied (counted in
    /// [`FilterCounters::updates_released`]) and the refusal count restarts.
    /// A sensor that is itself persistently wrong (a bias step, a drift) is
    /// then applied once every `limit + 1` samples instead of being refused.
    pub fn set_lockout_release(&mut self, limit: Option<u32>) {
        self.lockout_release = limit;
    }

    /// `true` if sensor `S` has been refused often enough in a row that its
    /// next measurement is released (see [`Ekf::set_lockout_release`]).
    pub(super) fn released<S: 'static>(&self) -> bool {
        self.lockout_release
            .is_some_and(|k| self.refusals.get(TypeId::of::<S>()) >= k)
    }

    /// Sets the gate used by sensors without their own setting; `None` disables it.
    #[must_use]
    pub fn with_default_gate(mut self, gate: Option<Gate>) -> Self {
        self.default_gate = gate;
        self
    }

    /// Changes the gate of sensors without their own setting; `None` disables it.
    pub fn set_default_gate(&mut self, gate: Option<Gate>) {
        self.default_gate = gate;
    }

    /// Gives sensor `S` its own gate (`None`: no gating for `S`), overriding the
    /// default gate, like robot_localization's per-sensor rejection thresholds.
    ///
    /// # Errors
    /// [`SetupError::TooManySensorGates`] if [`MAX_SENSOR_GATES`] other sensors
    /// already have a setting.
    pub fn set_sensor_gate<S, const M: usize>(
        &mut self,
        gate: Option<Gate>,
    ) -> Result<(), SetupError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        self.gates.set(TypeId::of::<S>(), gate)
    }

    /// The gate that applies to sensor `S` (its own setting, else the default).
    pub fn sensor_gate<S, const M: usize>(&self) -> Option<Gate>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        self.gates
            .get(TypeId::of::<S>())
            .unwrap_or(self.default_gate)
    }

    /// Accepted/gated totals and the per-sensor run of gate refusals of one
    /// update that was not an error (see [`Ekf::set_lockout_release`]).
    pub(super) fn count_gate_outcome<const M: usize>(
        &mut self,
        sensor: TypeId,
        report: &UpdateReport<M>,
    ) {
        if report.accepted {
            self.counters.updates_accepted += 1;
            if !passes(report.nis, report.threshold) {
                self.counters.updates_released += 1;
            }
            if self.lockout_release.is_some() {
                self.refusals.set(sensor, 0);
            }
        } else {
            self.counters.updates_gated += 1;
            if self.lockout_release.is_some() {
                let n = self.refusals.get(sensor);
                self.refusals.set(sensor, n.saturating_add(1));
            }
        }
    }
}

/// Consecutive gate refusals per sensor type, in a fixed array (sensors
/// beyond [`MAX_SENSOR_GATES`] are not counted, so never released).
#[derive(Clone, Copy, Debug)]
pub(super) struct RefusalTable {
    entries: [Option<(TypeId, u32)>; MAX_SENSOR_GATES],
}

impl RefusalTable {
    pub(super) fn new() -> Self {
        Self {
            entries: [None; MAX_SENSOR_GATES],
        }
    }

    pub(super) fn get(&self, id: TypeId) -> u32 {
        self.entries
            .iter()
            .flatten()
            .find(|(k, _)| *k == id)
            .map_or(0, |(_, n)| *n)
    }

    pub(super) fn set(&mut self, id: TypeId, n: u32) {
        if let Some(slot) = self.entries.iter_mut().flatten().find(|(k, _)| *k == id) {
            slot.1 = n;
        } else if let Some(slot) = self.entries.iter_mut().find(|e| e.is_none()) {
            *slot = Some((id, n));
        }
    }
}

/// Per-sensor gate settings keyed by the sensor type, in a fixed array.
#[derive(Clone, Copy, Debug)]
pub(super) struct GateTable {
    entries: [Option<(TypeId, Option<Gate>)>; MAX_SENSOR_GATES],
}

impl GateTable {
    pub(super) fn new() -> Self {
        Self {
            entries: [None; MAX_SENSOR_GATES],
        }
    }

    pub(super) fn get(&self, id: TypeId) -> Option<Option<Gate>> {
        self.entries
            .iter()
            .flatten()
            .find(|(k, _)| *k == id)
            .map(|(_, g)| *g)
    }

    pub(super) fn set(&mut self, id: TypeId, gate: Option<Gate>) -> Result<(), SetupError> {
        if let Some(slot) = self.entries.iter_mut().flatten().find(|(k, _)| *k == id) {
            slot.1 = gate;
            return Ok(());
        }
        match self.entries.iter_mut().find(|e| e.is_none()) {
            Some(slot) => {
                *slot = Some((id, gate));
                Ok(())
            }
            None => Err(SetupError::TooManySensorGates {
                capacity: MAX_SENSOR_GATES,
            }),
        }
    }
}

/// The gate decision: `nis <= threshold`, always true without a gate. A NaN
/// NIS never passes (it is refused as an error before this point anyway).
pub(super) fn passes(nis: f64, threshold: Option<f64>) -> bool {
    match threshold {
        Some(t) => nis <= t,
        None => true,
    }
}
