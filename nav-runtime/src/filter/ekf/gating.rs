//! Innovation gating: the per-sensor gate table, the gate totals and the
//! hand-over of each decision to the lock-out release ([`crate::lockout`]).

use core::any::TypeId;

use super::{Ekf, SetupError, UpdateReport};
use crate::gate::Gate;
use crate::model::{Model, Sensor};
use crate::real::Real;

/// Number of sensors whose gate can be set individually on one filter.
pub const MAX_SENSOR_GATES: usize = 16;

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
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
        S: Sensor<N, M, T, Model = Mo>,
    {
        self.gates.set(TypeId::of::<S>(), gate)
    }

    /// The gate that applies to sensor `S` (its own setting, else the default).
    pub fn sensor_gate<S, const M: usize>(&self) -> Option<Gate>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        self.gates
            .get(TypeId::of::<S>())
            .unwrap_or(self.default_gate)
    }

    /// Hands the gate's decision to the lock-out release, which may inflate
    /// `P` (see [`crate::lockout`]).
    pub(super) fn after_gate<S, const M: usize>(
        &mut self,
        report: &UpdateReport<M, T>,
        aux: &S::Aux,
    ) where
        S: Sensor<N, M, T, Model = Mo>,
    {
        let (p, x, u, par) = (&mut self.p, &self.x, &self.input, &self.params);
        if self
            .lockout
            .after_gate::<S, T, N, M>(report, p, x, u, par, aux)
        {
            self.counters.updates_released += 1;
            // The release acted on this sensor: its recovery horizon counts
            // again from here.
            self.lockout.recovery.restart_run(TypeId::of::<S>());
            // Inflated outside the update's checks.
            self.clean = false;
        }
    }

    /// Accepted/gated totals of one update that was not an error.
    pub(super) fn count_gate_outcome<const M: usize>(&mut self, report: &UpdateReport<M, T>) {
        if report.accepted {
            self.counters.updates_accepted += 1;
        } else {
            self.counters.updates_gated += 1;
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
