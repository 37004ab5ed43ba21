//! Checks of what enters the filter: measurements, auxiliary inputs, noise
//! covariances, initial covariances and noise intensities.

use nalgebra::{SMatrix, SVector};

use super::covariance::mirror_upper;
use super::{FilterError, SetupError};
use crate::model::{first_non_finite, name_of, Record, Sensor};
use crate::real::Real;

/// Refuses a non-finite measurement or auxiliary input.
pub(super) fn check_measurement<S, T: Real, const N: usize, const M: usize>(
    z: &SVector<T, M>,
    aux: &S::Aux,
) -> Result<(), FilterError>
where
    S: Sensor<N, M, T>,
{
    if let Some(index) = z.iter().position(|v| !v.is_finite()) {
        return Err(FilterError::NonFiniteMeasurement { index });
    }
    if let Some(index) = first_non_finite(aux) {
        return Err(FilterError::NonFiniteAux {
            index,
            name: name_of::<S::Aux>(index),
        });
    }
    Ok(())
}

/// `r` checked (finite, symmetric to 1e-9 relative, non-negative variances)
/// and made exactly symmetric from its upper triangle.
pub(super) fn checked_noise<T: Real, const M: usize>(
    r: &SMatrix<T, M, M>,
) -> Result<SMatrix<T, M, M>, FilterError> {
    if !all_finite(r.as_slice()) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "not finite",
        });
    }
    if (0..M).any(|i| r[(i, i)] < T::zero()) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "negative variance",
        });
    }
    if !is_symmetric(r) {
        return Err(FilterError::InvalidMeasurementNoise {
            reason: "not symmetric",
        });
    }
    let mut r = *r;
    mirror_upper(&mut r);
    Ok(r)
}

/// An initial covariance checked like [`checked_noise`].
pub(super) fn checked_covariance<T: Real, const N: usize>(
    p: &SMatrix<T, N, N>,
) -> Result<SMatrix<T, N, N>, SetupError> {
    if !all_finite(p.as_slice()) {
        return Err(SetupError::Invalid {
            reason: "covariance is not finite",
        });
    }
    if (0..N).any(|i| p[(i, i)] < T::zero()) {
        return Err(SetupError::Invalid {
            reason: "covariance has a negative variance",
        });
    }
    if !is_symmetric(p) {
        return Err(SetupError::Invalid {
            reason: "covariance is not symmetric",
        });
    }
    let mut p = *p;
    mirror_upper(&mut p);
    Ok(p)
}

/// Process-noise intensities must be finite and non-negative.
pub(super) fn check_noise_intensities<R: Record>(q: &R) -> Result<(), SetupError> {
    if (0..R::LEN).any(|i| !(q.get(i).is_finite() && q.get(i) >= 0.0)) {
        return Err(SetupError::Invalid {
            reason: "a noise intensity is negative or not finite",
        });
    }
    Ok(())
}

/// Symmetric to 1e-9 relative to the larger of the entry pair and the
/// geometric mean of the two variances.
/// Relative asymmetry accepted in a covariance given to the filter (`f64`;
/// an `f32` matrix may be off by its own rounding, 64 epsilon).
const SYMMETRY_TOLERANCE: f64 = 1e-9;

pub(super) fn is_symmetric<T: Real, const N: usize>(m: &SMatrix<T, N, N>) -> bool {
    (0..N).all(|c| {
        (0..c).all(|r| {
            let (a, b) = (m[(r, c)].to_f64(), m[(c, r)].to_f64());
            let scale = a
                .abs()
                .max(b.abs())
                .max(libm::sqrt((m[(r, r)].to_f64() * m[(c, c)].to_f64()).abs()));
            (a - b).abs() <= SYMMETRY_TOLERANCE.max(64.0 * T::EPSILON) * scale
        })
    })
}

/// `true` if every element is finite. Branch-free over chunks of four (`x * 0`
/// is zero for a finite `x` and NaN otherwise, and NaN survives the sums), so
/// the check vectorizes.
pub(super) fn all_finite<T: Real>(v: &[T]) -> bool {
    let zero = T::zero();
    let mut acc = [zero; 4];
    let mut chunks = v.chunks_exact(4);
    for chunk in &mut chunks {
        for (a, x) in acc.iter_mut().zip(chunk) {
            *a += *x * zero;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += *x * zero;
    }
    acc.iter().all(|a| *a == zero)
}
