//! The smoothed estimates of a leveling run (`leveling6 --smooth`), kept
//! on disk between the backward pass, which meets them latest first, and
//! their scoring in time order (docs/results/leveling6.md, "Replay").

use nav_runtime::smoother::{SmootherError, SpillFile};

use super::filter::AttitudeEstimate;
use crate::harness::RunError;

/// Scalars of one estimate in a [`SmoothedEstimates`] file.
const RECORD: usize = 6;

/// The smoothed estimates of a run: the backward pass meets them latest
/// first, and they wait in a temporary file until taken in time order, so
/// memory does not grow with the log.
#[derive(Debug)]
pub struct SmoothedEstimates {
    file: SpillFile,
    /// The times of the earliest and the latest, s.
    span: Option<(f64, f64)>,
}

impl SmoothedEstimates {
    pub(super) fn new() -> Result<Self, SmootherError> {
        Ok(SmoothedEstimates {
            file: SpillFile::create(None, RECORD)?,
            span: None,
        })
    }

    /// Keeps `e`, which comes before every estimate kept so far.
    pub(super) fn push_earlier(&mut self, e: &AttitudeEstimate) -> Result<(), SmootherError> {
        self.span = Some(self.span.map_or((e.t, e.t), |(_, last)| (e.t, last)));
        self.file.push(&[
            e.t,
            e.roll,
            e.pitch,
            e.roll_sigma,
            e.pitch_sigma,
            e.roll_pitch_covariance,
        ])
    }

    /// How many there are.
    pub fn len(&self) -> usize {
        self.file.len()
    }

    /// Whether there are none.
    pub fn is_empty(&self) -> bool {
        self.file.is_empty()
    }

    /// Their mean spacing in time, s (0 for fewer than two).
    pub fn mean_period(&self) -> f64 {
        match self.span {
            Some((first, last)) if self.len() > 1 => (last - first) / (self.len() - 1) as f64,
            _ => 0.0,
        }
    }

    /// Hands each to `each`, in time order.
    ///
    /// # Errors
    /// The file cannot be read, or the first error of `each`.
    pub fn for_each(
        mut self,
        mut each: impl FnMut(&AttitudeEstimate) -> Result<(), RunError>,
    ) -> Result<(), RunError> {
        let mut r = [0.0; RECORD];
        let read = |e: SmootherError| RunError::Invalid(format!("leveling6: smoothing: {e}"));
        while self.file.pop(&mut r).map_err(read)? {
            each(&AttitudeEstimate {
                t: r[0],
                roll: r[1],
                pitch: r[2],
                roll_sigma: r[3],
                pitch_sigma: r[4],
                roll_pitch_covariance: r[5],
            })?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Kept latest first, as the backward pass meets them, and given back
    /// in time order, bit for bit, with their mean spacing.
    #[test]
    fn kept_latest_first_and_given_back_in_time_order() {
        let at = |t: f64| AttitudeEstimate {
            t,
            roll: 0.1 * t,
            pitch: -0.2 * t,
            roll_sigma: 1e-3 * t,
            pitch_sigma: 2e-3 * t,
            roll_pitch_covariance: -1e-7 * t,
        };
        let times = [0.5, 0.75, 1.0, 1.25, 1.5];
        let mut kept = SmoothedEstimates::new().unwrap();
        for &t in times.iter().rev() {
            kept.push_earlier(&at(t)).unwrap();
        }
        assert_eq!(kept.len(), times.len());
        assert_eq!(kept.mean_period(), 0.25);
        let mut back = Vec::new();
        kept.for_each(|e| {
            back.push(*e);
            Ok(())
        })
        .unwrap();
        let expected: Vec<AttitudeEstimate> = times.iter().map(|&t| at(t)).collect();
        assert_eq!(back, expected);
    }
}
