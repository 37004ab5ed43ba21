//! The information each sensor's updates gave about the state at the start
//! of a recording (`docs/observability.md`, "Per sensor").
//!
//! An accepted update of sensor `s` with Jacobian `H` and noise `R` at a
//! time `t` tells `H^T R^-1 H` about the state at `t`, which is
//! `Phi(t, 0)^T H^T R^-1 H Phi(t, 0)` about the state at the start. Summed
//! per sensor this is that sensor's share of the observability Gramian:
//!
//! ```text
//! W_s = sum_{updates of s} (H Phi)^T R^-1 (H Phi)
//! ```
//!
//! kept forward beside the recording (the recorder knows `Phi(t, 0)`: the
//! product of the epochs' transitions and the steps since the last epoch),
//! so that nothing more is stored per epoch. Unlike the epochs' own
//! information `(P+)^-1 - (P-)^-1`, this is the linearized measurement's
//! information alone: a covariance repair or a lock-out recovery's
//! inflation is not in it.

use nalgebra::{SMatrix, SVector};

/// Most sensors tracked apart on one recording; the updates of further
/// sensors are counted in [`SensorInformation::untracked`] (the store is
/// reserved when tracking starts, so an update never allocates).
pub const MAX_TRACKED_SENSORS: usize = 16;

/// Per sensor, `W_s` ([`SensorInformation`] module docs), in the states'
/// units at the start of the recording.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorInformation<const N: usize> {
    /// `Phi(last opened epoch, start)`.
    pub(super) to_start: SMatrix<f64, N, N>,
    /// Sensor name and its `W_s`, in the order first seen.
    sensors: Vec<(&'static str, SMatrix<f64, N, N>)>,
    /// Accepted updates of sensors beyond [`MAX_TRACKED_SENSORS`].
    untracked: u64,
}

impl<const N: usize> Default for SensorInformation<N> {
    fn default() -> Self {
        Self::new()
    }
}

impl<const N: usize> SensorInformation<N> {
    /// Nothing learned yet, at the start of the recording.
    pub fn new() -> Self {
        Self {
            to_start: SMatrix::identity(),
            sensors: Vec::with_capacity(MAX_TRACKED_SENSORS),
            untracked: 0,
        }
    }

    /// Per sensor (in the order first seen), its `W_s`.
    pub fn sensors(&self) -> impl Iterator<Item = (&'static str, &SMatrix<f64, N, N>)> {
        self.sensors.iter().map(|(name, w)| (*name, w))
    }

    /// Accepted updates of sensors beyond [`MAX_TRACKED_SENSORS`], not in
    /// any `W_s`.
    pub fn untracked(&self) -> u64 {
        self.untracked
    }

    /// Adds one update of `sensor` with Jacobian `jacobian` (`H`, at the
    /// state the update was made at) and the inverse of its noise
    /// covariance, at a time whose transition to the start is
    /// `since_epoch * to_start` (`since_epoch`: `Phi` from the last epoch,
    /// `None` for the identity). A non-finite contribution is not added.
    pub(super) fn add<const M: usize>(
        &mut self,
        sensor: &'static str,
        jacobian: &SMatrix<f64, M, N>,
        noise_inverse: &SMatrix<f64, M, M>,
        since_epoch: Option<&SMatrix<f64, N, N>>,
    ) {
        let g = match since_epoch {
            Some(phi) => (jacobian * phi) * self.to_start,
            None => jacobian * self.to_start,
        };
        let w = g.transpose() * noise_inverse * g;
        if w.iter().any(|v| !v.is_finite()) {
            return;
        }
        if let Some((_, total)) = self.sensors.iter_mut().find(|(n, _)| *n == sensor) {
            *total += w;
        } else if self.sensors.len() < MAX_TRACKED_SENSORS {
            self.sensors.push((sensor, w));
        } else {
            self.untracked += 1;
        }
    }
}

/// `R^-1` of a diagonal noise given by its diagonal; a zero or invalid
/// variance gives a zero row (that component is left out).
pub fn diagonal_inverse<const M: usize>(r_diag: &SVector<f64, M>) -> SMatrix<f64, M, M> {
    SMatrix::from_diagonal(&r_diag.map(|v| {
        if v > 0.0 && v.is_finite() {
            1.0 / v
        } else {
            0.0
        }
    }))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn updates_are_summed_per_sensor_and_mapped_to_the_start() {
        let mut info = SensorInformation::<2>::new();
        // The state at the start is x0; now x = Phi x0 with Phi = [[1, 2], [0, 1]].
        let phi = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 0.0, 1.0);
        let h = SMatrix::<f64, 1, 2>::new(1.0, 0.0);
        let r_inv = SMatrix::<f64, 1, 1>::new(4.0);
        info.add("Pos", &h, &r_inv, None);
        info.add("Pos", &h, &r_inv, Some(&phi));
        info.add(
            "Vel",
            &SMatrix::<f64, 1, 2>::new(0.0, 1.0),
            &r_inv,
            Some(&phi),
        );
        let got: Vec<_> = info.sensors().collect();
        assert_eq!(got.len(), 2);
        // H Phi = [1, 2]: 4 [[1, 2], [2, 4]], plus 4 [[1, 0], [0, 0]].
        let pos = SMatrix::<f64, 2, 2>::new(8.0, 8.0, 8.0, 16.0);
        assert_eq!(got[0], ("Pos", &pos));
        assert_eq!(
            got[1],
            ("Vel", &SMatrix::<f64, 2, 2>::new(0.0, 0.0, 0.0, 4.0))
        );
    }

    #[test]
    fn sensors_past_the_limit_are_counted_not_stored() {
        const NAMES: [&str; MAX_TRACKED_SENSORS + 2] = [
            "a", "b", "c", "d", "e", "f", "g", "h", "i", "j", "k", "l", "m", "n", "o", "p", "q",
            "r",
        ];
        let mut info = SensorInformation::<1>::new();
        let capacity = info.sensors.capacity();
        let one = SMatrix::<f64, 1, 1>::new(1.0);
        for name in NAMES {
            info.add(name, &one, &one, None);
        }
        assert_eq!(info.sensors().count(), MAX_TRACKED_SENSORS);
        assert_eq!(info.untracked(), 2);
        assert_eq!(
            info.sensors.capacity(),
            capacity,
            "no allocation after the start"
        );
    }

    #[test]
    fn a_non_finite_update_and_an_invalid_variance_add_nothing() {
        let mut info = SensorInformation::<1>::new();
        let nan = SMatrix::<f64, 1, 1>::new(f64::NAN);
        info.add("a", &nan, &SMatrix::<f64, 1, 1>::new(1.0), None);
        assert_eq!(info.sensors().count(), 0);
        let r = diagonal_inverse(&SVector::<f64, 2>::new(0.25, 0.0));
        assert_eq!(r, SMatrix::<f64, 2, 2>::new(4.0, 0.0, 0.0, 0.0));
    }
}
