//! The covariance lifecycle: the variance floor, the clean check after every
//! prediction and update, the repair of a broken diagonal, and the mirroring
//! that keeps `P` exactly symmetric.

use nalgebra::{SMatrix, SVector};

use super::validation::all_finite;
use crate::real::Real;

/// The default lower bound a repaired variance is reset to when no positive
/// previous value exists (see [`Ekf::with_variance_floor`](crate::ekf::Ekf::with_variance_floor)).
pub const DEFAULT_VARIANCE_FLOOR: f64 = 1e-12;

crate::dispatch::avx_dispatch! {
    /// `true` if every entry of `p` is finite and every diagonal entry positive:
    /// the common case, in which nothing needs repairing. One branch-free,
    /// vectorizable pass: the sum of all entries is finite if they all are (a sum
    /// that overflows merely sends the caller to the exact slow path,
    /// [`off_diagonal_finite`] and [`repair_diagonal`]).
    /// Runs compiled for AVX where the CPU has it.
    pub(super) fn covariance_is_clean<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> bool => covariance_is_clean_pass;
}

/// The pass of [`covariance_is_clean`].
#[inline(always)]
pub(super) fn covariance_is_clean_pass<
    T: Real,
    const N: usize,
    const AVX: bool,
    const FUSED: bool,
>(
    p: &SMatrix<T, N, N>,
) -> bool {
    let mut acc = [T::zero(); 8];
    let mut chunks = p.as_slice().chunks_exact(8);
    for chunk in &mut chunks {
        for (a, x) in acc.iter_mut().zip(chunk) {
            *a += *x;
        }
    }
    for (a, x) in acc.iter_mut().zip(chunks.remainder()) {
        *a += *x;
    }
    let mut diagonal_ok = true;
    for (i, col) in p.data.0.iter().enumerate() {
        let d = col[i];
        diagonal_ok &= d > T::zero() && d <= T::MAX;
    }
    diagonal_ok && acc.iter().fold(T::zero(), |s, a| s + *a).is_finite()
}

/// `true` if every entry below the diagonal of `p` is finite (for a symmetric
/// `p`, every off-diagonal entry). A non-finite off-diagonal entry cannot be
/// repaired meaningfully: the prediction or update is refused.
pub(super) fn off_diagonal_finite<T: Real, const N: usize>(p: &SMatrix<T, N, N>) -> bool {
    p.as_slice()
        .chunks_exact(N)
        .enumerate()
        .all(|(c, col)| col.get(c + 1..).is_none_or(all_finite))
}

/// Repairs the diagonal of a symmetric covariance after a prediction or
/// update (see [`Ekf::update`]): each variance that is not positive and
/// finite is reset to its previous value `prev[i]` (if above `floor`) or to
/// `floor`, with its row and column zeroed. Returns the number repaired.
pub(super) fn repair_diagonal<T: Real, const N: usize>(
    p: &mut SMatrix<T, N, N>,
    prev: &SVector<T, N>,
    floor: T,
) -> u32 {
    let mut repairs = 0;
    for i in 0..N {
        let d = p[(i, i)];
        if d.is_finite() && d > T::zero() {
            continue;
        }
        let before = prev[i];
        let value = if before.is_finite() && before > floor {
            before
        } else {
            floor
        };
        for j in 0..N {
            p[(i, j)] = T::zero();
            p[(j, i)] = T::zero();
        }
        p[(i, i)] = value;
        repairs += 1;
    }
    repairs
}

/// Copies the upper triangle onto the lower one.
pub(super) fn mirror_upper<T: Real, const N: usize>(m: &mut SMatrix<T, N, N>) {
    for c in 0..N {
        for r in 0..c {
            m[(c, r)] = m[(r, c)];
        }
    }
}

/// Copies the lower triangle onto the upper one.
pub(super) fn mirror_lower<T: Real, const N: usize>(m: &mut SMatrix<T, N, N>) {
    for c in 0..N {
        for r in 0..c {
            m[(r, c)] = m[(c, r)];
        }
    }
}
