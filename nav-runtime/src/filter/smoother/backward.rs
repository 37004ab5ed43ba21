//! The backward pass: Rauch-Tung-Striebel over the recorded epochs.

use nalgebra::{SMatrix, SVector};

use super::epoch::Epoch;
use super::store::{EpochFile, SmootherError};

/// One epoch of the smoothed run.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SmoothedEpoch<const N: usize, const S: usize> {
    /// Time of the epoch, s.
    pub time: f64,
    /// The forward estimate's snapshot, as recorded.
    pub snapshot: SVector<f64, S>,
    /// Smoothed error of the forward estimate, `s_k` (forward minus true):
    /// the smoothed estimate is the forward one with `s_k` removed.
    pub error: SVector<f64, N>,
    /// Covariance of the smoothed estimate's error, `Ps_k`.
    pub covariance: SMatrix<f64, N, N>,
    /// Covariance of the forward estimate's error, `P_k+`.
    pub filtered: SMatrix<f64, N, N>,
}

/// Smooths the epochs of `file` and calls `visit` with each, latest first
/// (module docs; `docs/smoother.md`, eq. S1-S3). Memory: two epochs and the
/// work space of one step (boxed, so nothing large is on the stack).
///
/// # Errors
/// [`SmootherError::NotPositiveDefinite`] if a predicted covariance has no
/// Cholesky factor, [`SmootherError::NonFinite`] for a non-finite result,
/// [`SmootherError::Io`] on a failed read, or the first error of `visit`.
pub fn smooth<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    mut visit: impl FnMut(&SmoothedEpoch<N, S>) -> Result<(), SmootherError>,
) -> Result<(), SmootherError> {
    let mut step = Box::new(Step::<N>::new());
    // The smoothed epoch handed to `visit`, then kept as epoch k + 1.
    let mut out = Box::new(SmoothedEpoch::<N, S> {
        time: f64::NAN,
        snapshot: SVector::zeros(),
        error: SVector::zeros(),
        covariance: SMatrix::zeros(),
        filtered: SMatrix::zeros(),
    });
    let mut first = true;
    file.read_back(|epoch| {
        if first {
            out.error = SVector::zeros();
            out.covariance = epoch.filtered;
            first = false;
        } else {
            step.smooth(epoch, &mut out)?;
        }
        if out
            .error
            .iter()
            .chain(out.covariance.iter())
            .any(|v| !v.is_finite())
        {
            return Err(SmootherError::NonFinite { time: epoch.time });
        }
        out.time = epoch.time;
        out.snapshot = epoch.snapshot;
        out.filtered = epoch.filtered;
        visit(&out)?;
        // What epoch k - 1 needs of this one.
        step.keep(epoch);
        Ok(())
    })
}

/// One RTS step (eq. S1-S3) with its work space. Matrices are column-major,
/// so every inner loop runs over a contiguous column.
struct Step<const N: usize> {
    /// Of the later epoch k + 1: `P_{k+1}-`, then its Cholesky factor `L`
    /// (lower triangle).
    factor: SMatrix<f64, N, N>,
    /// Of the later epoch: `Phi_k` (from k to k + 1).
    transition: SMatrix<f64, N, N>,
    /// Of the later epoch: `c_{k+1}`.
    correction: SVector<f64, N>,
    /// `Phi_k P_k+`, then `C_k^T = (P_{k+1}-)^-1 Phi_k P_k+`.
    gain_t: SMatrix<f64, N, N>,
    /// `D = Ps_{k+1} - P_{k+1}-`, then `D C_k^T`.
    work: SMatrix<f64, N, N>,
    /// The rows of `Phi_k` that are not unit rows, row-major, and their
    /// indices (`dynamic[..rows]`).
    phi_rows: [[f64; N]; N],
    dynamic: [usize; N],
    rows: usize,
}

impl<const N: usize> Step<N> {
    fn new() -> Self {
        Self {
            factor: SMatrix::zeros(),
            transition: SMatrix::zeros(),
            correction: SVector::zeros(),
            gain_t: SMatrix::zeros(),
            work: SMatrix::zeros(),
            phi_rows: [[0.0; N]; N],
            dynamic: [0; N],
            rows: 0,
        }
    }

    /// Keeps what the step to the epoch before `epoch` needs.
    fn keep<const S: usize>(&mut self, epoch: &Epoch<N, S>) {
        self.factor = epoch.predicted;
        self.transition = epoch.transition;
        self.correction = epoch.correction;
    }

    /// Epoch k from epoch k + 1 (kept, smoothed in `out`): overwrites `out`'s
    /// error and covariance with epoch k's.
    fn smooth<const S: usize>(
        &mut self,
        epoch: &Epoch<N, S>,
        out: &mut SmoothedEpoch<N, S>,
    ) -> Result<(), SmootherError> {
        // D = Ps_{k+1} - P_{k+1}- (before the factor overwrites P_{k+1}-).
        self.work = out.covariance - self.factor;
        if !cholesky_in_place(&mut self.factor) {
            return Err(SmootherError::NotPositiveDefinite { time: out.time });
        }
        self.phi_times(&epoch.filtered);
        // C^T = (P_{k+1}-)^-1 Phi_k P_k+   (P_{k+1}- symmetric)
        for column in self.gain_t.as_mut_slice().chunks_exact_mut(N) {
            solve_in_place(&self.factor, column);
        }
        // S2: s_k = C_k (s_{k+1} + c_{k+1}): entry i is column i of C^T dotted.
        let v = out.error + self.correction;
        let gain_t = self.gain_t.as_slice();
        for (e, column) in out.error.iter_mut().zip(gain_t.chunks_exact(N)) {
            *e = dot(column, v.as_slice());
        }
        // S3: Ps_k = P_k+ + C D C^T, with G = D C^T:
        // (C D C^T)[r][c] = column r of C^T . column c of G.
        let work = self.work.as_slice();
        let mut g = [0.0; N];
        for c in 0..N {
            g.fill(0.0);
            for (&a, d) in gain_t[c * N..(c + 1) * N].iter().zip(work.chunks_exact(N)) {
                axpy(a, d, &mut g);
            }
            for r in 0..=c {
                let v = epoch.filtered[(r, c)] + dot(&gain_t[r * N..(r + 1) * N], &g);
                out.covariance[(r, c)] = v;
                out.covariance[(c, r)] = v;
            }
        }
        Ok(())
    }

    /// `gain_t = Phi P`, copying the rows of `P` where `Phi` has a unit row
    /// (states without dynamics, e.g. random-constant biases, keep `e_i` rows
    /// in every product of their transition matrices); the other rows are
    /// `Phi`'s rows (zeros skipped) times `P`.
    fn phi_times(&mut self, p: &SMatrix<f64, N, N>) {
        let phi = &self.transition;
        self.rows = 0;
        for i in 0..N {
            let unit = (0..N).all(|j| phi[(i, j)] == if i == j { 1.0 } else { 0.0 });
            if !unit {
                let r = self.rows;
                self.dynamic[r] = i;
                for j in 0..N {
                    self.phi_rows[r][j] = phi[(i, j)];
                }
                self.rows += 1;
            }
        }
        for c in 0..N {
            let column = &p.as_slice()[c * N..(c + 1) * N];
            let out = &mut self.gain_t.as_mut_slice()[c * N..(c + 1) * N];
            out.copy_from_slice(column);
            for (row, &i) in self.phi_rows[..self.rows]
                .iter()
                .zip(&self.dynamic[..self.rows])
            {
                out[i] = dot(row, column);
            }
        }
    }
}

/// The Cholesky factor of the symmetric `a` in place (lower triangle; the
/// strict upper triangle is left as it was); `false` if `a` is not
/// positive definite (or not finite).
fn cholesky_in_place<const N: usize>(a: &mut SMatrix<f64, N, N>) -> bool {
    let s = a.as_mut_slice();
    for j in 0..N {
        let (left, right) = s.split_at_mut((j + 1) * N);
        let col = &mut left[j * N..];
        let d = col[j];
        if !(d > 0.0 && d.is_finite()) {
            return false;
        }
        let d = d.sqrt();
        col[j] = d;
        for x in &mut col[j + 1..] {
            *x /= d;
        }
        // The trailing columns: a[c.., c] -= l[c] l[c..].
        for (k, later) in right.chunks_exact_mut(N).enumerate() {
            let c = j + 1 + k;
            let l = col[c];
            if l != 0.0 {
                axpy(-l, &col[c..], &mut later[c..]);
            }
        }
    }
    true
}

/// `x <- (L L^T)^-1 x` with the lower-triangular `l` (column-major).
fn solve_in_place<const N: usize>(l: &SMatrix<f64, N, N>, x: &mut [f64]) {
    let l = l.as_slice();
    // L y = x, column by column.
    for j in 0..N {
        let col = &l[j * N..(j + 1) * N];
        x[j] /= col[j];
        let xj = x[j];
        if xj != 0.0 {
            let (_, tail) = x.split_at_mut(j + 1);
            axpy(-xj, &col[j + 1..], tail);
        }
    }
    // L^T z = y, from the last row: row j of L^T is column j of L.
    for j in (0..N).rev() {
        let col = &l[j * N..(j + 1) * N];
        let v = x[j] - dot(&col[j + 1..], &x[j + 1..]);
        x[j] = v / col[j];
    }
}

/// `y <- y + a x`.
fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

/// `x . y` (over the shorter of the two).
fn dot(x: &[f64], y: &[f64]) -> f64 {
    x.iter().zip(y).map(|(a, b)| a * b).sum()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn spd() -> SMatrix<f64, 5, 5> {
        let a = SMatrix::<f64, 5, 5>::from_fn(|r, c| ((r * 5 + c) as f64 * 0.7).sin());
        a * a.transpose() + SMatrix::identity() * 0.5
    }

    /// The in-place Cholesky factor and solve agree with nalgebra's.
    #[test]
    fn cholesky_and_solve_match_nalgebra() {
        let a = spd();
        let mut l = a;
        assert!(cholesky_in_place(&mut l));
        let reference = a.cholesky().unwrap();
        let l_ref = reference.l();
        for r in 0..5 {
            for c in 0..=r {
                assert!((l[(r, c)] - l_ref[(r, c)]).abs() < 1e-12, "L[{r}][{c}]");
            }
        }
        let b = SVector::<f64, 5>::from_fn(|i, _| i as f64 - 1.5);
        let mut x = b;
        solve_in_place(&l, x.as_mut_slice());
        let x_ref = reference.solve(&b);
        assert!((x - x_ref).norm() < 1e-12 * x_ref.norm());
    }

    /// Not positive definite, or not finite: no factor.
    #[test]
    fn cholesky_refuses_indefinite_and_non_finite_matrices() {
        let mut a = spd();
        a[(3, 3)] = -1.0;
        assert!(!cholesky_in_place(&mut a));
        let mut a = spd();
        a[(0, 0)] = f64::NAN;
        assert!(!cholesky_in_place(&mut a));
        let mut a = SMatrix::<f64, 2, 2>::new(1.0, 2.0, 2.0, 1.0);
        assert!(!cholesky_in_place(&mut a));
    }

    /// `Phi P` with unit rows copied equals the dense product.
    #[test]
    fn phi_times_equals_the_dense_product() {
        let p = spd();
        let mut step = Step::<5>::new();
        step.transition = SMatrix::identity();
        step.transition[(1, 0)] = 0.3;
        step.transition[(1, 4)] = -2.0;
        step.transition[(3, 3)] = 0.9;
        step.phi_times(&p);
        let dense = step.transition * p;
        assert!((step.gain_t - dense).norm() < 1e-14);
        assert_eq!(step.rows, 2);
        assert_eq!(step.dynamic[..2], [1, 3]);
    }
}
