//! The Joseph covariance update (eq. U6), in place, on one triangle.

use nalgebra::SMatrix;

use super::covariance::{mirror_lower, mirror_upper, off_diagonal_finite, repair_diagonal};
use super::FilterError;
use crate::real::Real;

/// The Joseph covariance update `P - K U^T - U K^T + K S K^T` (eq. U6) with
/// `U = P H^T` and `S = H P H^T + R`, which equals
/// `(I - K H) P (I - K H)^T + K R K^T` for any gain `K`. O(N^2 M) on one
/// triangle, then mirrored (see [`joseph_lower`]).
#[cfg(test)]
pub(crate) fn joseph_update<T: Real, const N: usize, const M: usize>(
    p: &SMatrix<T, N, N>,
    k: &SMatrix<T, N, M>,
    u: &SMatrix<T, N, M>,
    s: &SMatrix<T, M, M>,
) -> SMatrix<T, N, N> {
    let mut out = *p;
    let _ = joseph_lower::<T, N, M, false>(&mut out, k, u, s);
    mirror_lower(&mut out);
    out
}

/// The lower triangle (diagonal included) of the Joseph update (eq. U6),
/// computed in place; the strict upper triangle of `p` is left as it was.
/// Returns `true` if the result needs no repair (every entry finite, every
/// variance positive), checked in the same pass; `false` may also mean that a
/// checksum overflowed, so the caller then checks exactly.
///
/// With `W = K S - U`, eq. U6 is `P - K U^T + W K^T` (`K S K^T - U K^T =
/// W K^T`), so column `c` of the result is
/// `P[:, c] - sum_m K[:, m] U[c, m] + sum_m W[:, m] K[c, m]`: one loop over
/// the contiguous rows `c..N` of the column (`P`, `K`, `W` are column-major),
/// which the compiler vectorizes. Each entry reads only its own prior value,
/// so the prior's upper triangle (equal to its lower one, `P` being exactly
/// symmetric) stays available to undo the update.
#[inline(always)]
pub(super) fn joseph_lower<T: Real, const N: usize, const M: usize, const FUSED: bool>(
    p: &mut SMatrix<T, N, N>,
    k: &SMatrix<T, N, M>,
    u: &SMatrix<T, N, M>,
    s: &SMatrix<T, M, M>,
) -> bool {
    let w = k * s - u;
    let (kd, ud, wd) = (&k.data.0, &u.data.0, &w.data.0);
    // Row sums of the result: finite if every entry is (an overflowing sum
    // merely sends the caller to the exact slow path).
    let mut acc = [T::zero(); N];
    let mut diagonal_ok = true;
    // Coefficients of column `c`: `U[c, m]` and `K[c, m]`.
    let coefficients = |c: usize| {
        let mut a = [T::zero(); M];
        let mut b = [T::zero(); M];
        for m in 0..M {
            a[m] = ud[m][c];
            b[m] = kd[m][c];
        }
        (a, b)
    };
    let cols = &mut p.data.0;
    // Two columns per pass share the loads of the rows of `K` and `W`.
    let mut c = 0;
    while c + 1 < N {
        let (a0, b0) = coefficients(c);
        let (a1, b1) = coefficients(c + 1);
        let (left, right) = cols.split_at_mut(c + 1);
        let (Some(col0), Some(col1)) = (left.last_mut(), right.first_mut()) else {
            break;
        };
        let mut v = col0[c];
        for m in 0..M {
            v = term::<T, FUSED>(v, wd[m][c], b0[m], kd[m][c], a0[m]);
        }
        col0[c] = v;
        acc[c] += v;
        for r in c + 1..N {
            let (mut v0, mut v1) = (col0[r], col1[r]);
            for m in 0..M {
                let (k_r, w_r) = (kd[m][r], wd[m][r]);
                v0 = term::<T, FUSED>(v0, w_r, b0[m], k_r, a0[m]);
                v1 = term::<T, FUSED>(v1, w_r, b1[m], k_r, a1[m]);
            }
            col0[r] = v0;
            col1[r] = v1;
            acc[r] += v0 + v1;
        }
        diagonal_ok &= col0[c] > T::zero() && col0[c] <= T::MAX;
        diagonal_ok &= col1[c + 1] > T::zero() && col1[c + 1] <= T::MAX;
        c += 2;
    }
    if c + 1 == N {
        let (a, b) = coefficients(c);
        if let Some(col) = cols.last_mut() {
            let mut v = col[c];
            for m in 0..M {
                v = term::<T, FUSED>(v, wd[m][c], b[m], kd[m][c], a[m]);
            }
            col[c] = v;
            acc[c] += v;
            diagonal_ok &= v > T::zero() && v <= T::MAX;
        }
    }
    diagonal_ok && acc.iter().all(|x| x.is_finite())
}

/// One term of a column of eq. U6: `v + (w b - k a)`; `FUSED`: two fused
/// multiply-adds, `fma(-k, a, fma(w, b, v))`.
#[inline(always)]
fn term<T: Real, const FUSED: bool>(v: T, w: T, b: T, k: T, a: T) -> T {
    if FUSED {
        v.plus_product::<true>(w, b).plus_product::<true>(-k, a)
    } else {
        v + (w * b - k * a)
    }
}

crate::dispatch::avx_dispatch! {
    /// Eq. U6 stored in `p` in place, with the checks and repairs of
    /// [`Ekf::update`]; returns the number of repaired variances.
    ///
    /// The lower triangle is computed over the prior's (see [`joseph_lower`])
    /// and checked in one pass; only then is it mirrored. If an off-diagonal
    /// entry is not finite, the prior is restored exactly (its upper triangle
    /// and its saved diagonal) and the update is refused. Runs compiled for
    /// AVX where the CPU has it (bit-identical results).
    pub(super) fn joseph_in_place<T: Real, const N: usize, const M: usize>(
        p: &mut SMatrix<T, N, N>,
        k: &SMatrix<T, N, M>,
        u: &SMatrix<T, N, M>,
        s: &SMatrix<T, M, M>,
        floor: T,
    ) -> Result<u32, FilterError> => joseph_in_place_steps;
}

/// The body of [`joseph_in_place`].
#[inline(always)]
pub(super) fn joseph_in_place_steps<
    T: Real,
    const N: usize,
    const M: usize,
    const AVX: bool,
    const FUSED: bool,
>(
    p: &mut SMatrix<T, N, N>,
    k: &SMatrix<T, N, M>,
    u: &SMatrix<T, N, M>,
    s: &SMatrix<T, M, M>,
    floor: T,
) -> Result<u32, FilterError> {
    let prior_diagonal = p.diagonal();
    if joseph_lower::<T, N, M, FUSED>(p, k, u, s) {
        mirror_lower(p);
        return Ok(0);
    }
    if !off_diagonal_finite(p) {
        for (i, d) in prior_diagonal.iter().enumerate() {
            p[(i, i)] = *d;
        }
        mirror_upper(p);
        return Err(FilterError::NonFiniteResult { stage: "update" });
    }
    mirror_lower(p);
    Ok(repair_diagonal(p, &prior_diagonal, floor))
}
