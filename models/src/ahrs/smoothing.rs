//! `ahrs --smooth`: the rows of the estimates table (the end of every
//! gravity window, each an epoch of the recording) smoothed after the run
//! by the fixed-interval smoother every replay uses
//! ([`nav_runtime::smoother::smooth_states`], `docs/smoother.md`). The
//! forward rows wait in a temporary file while the run goes, the smoothed
//! ones in another, so memory does not grow with the log.

use std::cell::RefCell;
use std::rc::Rc;

use nav_runtime::error_state::NominalState;
use nav_runtime::nalgebra::{Matrix3, SMatrix, SVector, Vector3};
use nav_runtime::smoother::{smooth_states, EpochFile, SmootherError, SpillFile, States};

use super::nominal::{AhrsFilter, AhrsNominal};
use crate::harness::RunError;

/// Scalars of one row: the time (s), `C_b^n` row by row, the gyro bias
/// correction (rad/s) and the attitude error's covariance (about north,
/// east and down, rad^2) row by row.
pub const RECORD: usize = 22;

/// One row of the estimates table, forward or smoothed.
#[derive(Debug, Clone, PartialEq)]
pub struct AhrsRow {
    /// Time, s.
    pub t: f64,
    /// The attitude and gyro bias correction.
    pub nominal: AhrsNominal,
    /// Covariance of the attitude error about north, east and down, rad^2.
    pub attitude_covariance: Matrix3<f64>,
}

impl AhrsRow {
    /// The filter's estimate at `t`.
    pub fn of(t: f64, filter: &AhrsFilter) -> Self {
        Self::from_parts(t, filter.nominal().clone(), filter.covariance())
    }

    fn from_parts(t: f64, nominal: AhrsNominal, p: &SMatrix<f64, 6, 6>) -> Self {
        AhrsRow {
            t,
            nominal,
            attitude_covariance: p.fixed_view::<3, 3>(0, 0).into_owned(),
        }
    }

    /// Sigmas of the attitude error about north, east and down, rad.
    pub fn attitude_sigma(&self) -> [f64; 3] {
        std::array::from_fn(|i| self.attitude_covariance[(i, i)].max(0.0).sqrt())
    }

    /// The row as [`RECORD`] scalars, bit for bit.
    pub fn to_record(&self) -> [f64; RECORD] {
        let mut r = [0.0; RECORD];
        r[0] = self.t;
        for i in 0..3 {
            for j in 0..3 {
                r[1 + 3 * i + j] = self.nominal.c_bn[(i, j)];
                r[13 + 3 * i + j] = self.attitude_covariance[(i, j)];
            }
            r[10 + i] = self.nominal.gyro_bias[i];
        }
        r
    }

    /// The row of [`AhrsRow::to_record`].
    pub fn from_record(r: &[f64; RECORD]) -> Self {
        AhrsRow {
            t: r[0],
            nominal: AhrsNominal {
                c_bn: Matrix3::from_fn(|i, j| r[1 + 3 * i + j]),
                gyro_bias: Vector3::new(r[10], r[11], r[12]),
            },
            attitude_covariance: Matrix3::from_fn(|i, j| r[13 + 3 * i + j]),
        }
    }
}

fn smoother_error(e: SmootherError) -> RunError {
    RunError::Invalid(format!("ahrs: smoothing: {e}"))
}

/// The forward rows of the run, in time order, kept for the smoother.
pub struct ForwardRows(SpillFile);

impl ForwardRows {
    /// An empty file of rows.
    ///
    /// # Errors
    /// The temporary file cannot be made.
    pub fn new() -> Result<Self, RunError> {
        SpillFile::create(None, RECORD)
            .map(ForwardRows)
            .map_err(smoother_error)
    }

    /// Keeps `row`.
    ///
    /// # Errors
    /// The row cannot be written.
    pub fn push(&mut self, row: &AhrsRow) -> Result<(), RunError> {
        self.0.push(&row.to_record()).map_err(smoother_error)
    }

    /// Each forward row with its smoothed counterpart (`None` where the
    /// recording has no epoch at its time), in time order, handed to
    /// `each`. The backward pass meets the epochs latest first and takes
    /// the rows off the end of the file to match; the smoothed rows wait in
    /// a second file and come back in time order.
    ///
    /// # Errors
    /// A recording or file error, or the first error of `each`.
    pub fn smooth(
        mut self,
        recording: &Rc<RefCell<EpochFile<6, 0>>>,
        mut each: impl FnMut(&AhrsRow, Option<&AhrsRow>) -> Result<(), RunError>,
    ) -> Result<(), RunError> {
        // Forward and smoothed side by side: a smoothed row of NaN time is
        // none.
        let mut out = SpillFile::create(None, 2 * RECORD).map_err(smoother_error)?;
        let mut record = [0.0; RECORD];
        let mut pair = [f64::NAN; 2 * RECORD];
        let mut pending = self
            .0
            .pop(&mut record)
            .map_err(smoother_error)?
            .then(|| AhrsRow::from_record(&record));
        let mut file = recording.borrow_mut();
        smooth_states(&mut file, &States::all(), |epoch| {
            while let Some(row) = &pending {
                if row.t < epoch.time - 1e-9 {
                    break;
                }
                pair[..RECORD].copy_from_slice(&row.to_record());
                if (row.t - epoch.time).abs() <= 1e-9 {
                    let s = smoothed(row, &epoch.error, &epoch.covariance);
                    pair[RECORD..].copy_from_slice(&s.to_record());
                } else {
                    pair[RECORD..].fill(f64::NAN);
                }
                out.push(&pair)?;
                pending = self
                    .0
                    .pop(&mut record)?
                    .then(|| AhrsRow::from_record(&record));
            }
            Ok(())
        })
        .map_err(smoother_error)?;
        while let Some(row) = pending {
            pair[..RECORD].copy_from_slice(&row.to_record());
            pair[RECORD..].fill(f64::NAN);
            out.push(&pair).map_err(smoother_error)?;
            pending = self
                .0
                .pop(&mut record)
                .map_err(smoother_error)?
                .then(|| AhrsRow::from_record(&record));
        }
        drop(file);
        let (mut forward, mut smoothed) = ([0.0; RECORD], [0.0; RECORD]);
        while out.pop(&mut pair).map_err(smoother_error)? {
            forward.copy_from_slice(&pair[..RECORD]);
            smoothed.copy_from_slice(&pair[RECORD..]);
            let s = (!smoothed[0].is_nan()).then(|| AhrsRow::from_record(&smoothed));
            each(&AhrsRow::from_record(&forward), s.as_ref())?;
        }
        Ok(())
    }
}

/// The forward row with the smoothed error `error` (forward minus true)
/// removed as the filter feeds an error back ([`AhrsNominal::inject`]), and
/// the smoothed covariance `p`.
fn smoothed(row: &AhrsRow, error: &SVector<f64, 6>, p: &SMatrix<f64, 6, 6>) -> AhrsRow {
    let mut nominal = row.nominal.clone();
    nominal.inject(error);
    AhrsRow::from_parts(row.t, nominal, p)
}
