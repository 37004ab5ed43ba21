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
    /// `D = Ps_{k+1} - P_{k+1}-`.
    work: SMatrix<f64, N, N>,
    /// `U = L^T`.
    upper: SMatrix<f64, N, N>,
    /// `C_k`.
    gain: SMatrix<f64, N, N>,
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
            upper: SMatrix::zeros(),
            gain: SMatrix::zeros(),
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
        rts_step(self, epoch, out)
    }
}

crate::dispatch::avx_dispatch! {
    /// [`Step::smooth`], compiled for AVX where the CPU has it (the same
    /// operations in the same order: bit-identical results).
    fn rts_step<const N: usize, const S: usize>(
        step: &mut Step<N>,
        epoch: &Epoch<N, S>,
        out: &mut SmoothedEpoch<N, S>,
    ) -> Result<(), SmootherError> => rts_step_portable;
}

/// The body of [`rts_step`].
#[inline(always)]
fn rts_step_portable<const N: usize, const S: usize, const AVX: bool>(
    step: &mut Step<N>,
    epoch: &Epoch<N, S>,
    out: &mut SmoothedEpoch<N, S>,
) -> Result<(), SmootherError> {
    step.apply(epoch, out)
}

impl<const N: usize> Step<N> {
    #[inline(always)]
    fn apply<const S: usize>(
        &mut self,
        epoch: &Epoch<N, S>,
        out: &mut SmoothedEpoch<N, S>,
    ) -> Result<(), SmootherError> {
        // D = Ps_{k+1} - P_{k+1}- (before the factor overwrites P_{k+1}-).
        self.work = out.covariance - self.factor;
        if !cholesky_in_place(&mut self.factor) {
            return Err(SmootherError::NotPositiveDefinite { time: out.time });
        }
        // U = L^T, so that both triangular solves run over columns.
        self.upper = self.factor.transpose();
        self.phi_times(&epoch.filtered);
        // C^T = (P_{k+1}-)^-1 Phi_k P_k+   (P_{k+1}- symmetric)
        for column in self.gain_t.as_mut_slice().chunks_exact_mut(N) {
            solve_in_place(&self.factor, &self.upper, column);
        }
        // S2: s_k = C_k (s_{k+1} + c_{k+1}): entry i is column i of C^T dotted.
        let v: [f64; N] = (out.error + self.correction).into();
        let (gain_t, _) = self.gain_t.as_slice().as_chunks::<N>();
        for (e, column) in out.error.iter_mut().zip(gain_t) {
            *e = dot_n(column, &v);
        }
        // S3: Ps_k = P_k+ + C D C^T. With G = D C^T, column c of C G is
        // sum_j G_jc (column j of C); computed whole, its upper triangle is
        // kept and mirrored (exactly symmetric).
        self.gain = self.gain_t.transpose();
        let (work, _) = self.work.as_slice().as_chunks::<N>();
        let (gain, _) = self.gain.as_slice().as_chunks::<N>();
        let (filtered, _) = epoch.filtered.as_slice().as_chunks::<N>();
        let (cov, _) = out.covariance.as_mut_slice().as_chunks_mut::<N>();
        let mut g = [0.0; N];
        for ((gain_c, cov_c), filtered_c) in gain_t.iter().zip(cov.iter_mut()).zip(filtered) {
            g.fill(0.0);
            for (&a, d) in gain_c.iter().zip(work) {
                axpy_n(a, d, &mut g);
            }
            *cov_c = *filtered_c;
            for (&a, column) in g.iter().zip(gain) {
                axpy_n(a, column, cov_c);
            }
        }
        for c in 0..N {
            for r in c + 1..N {
                out.covariance[(r, c)] = out.covariance[(c, r)];
            }
        }
        Ok(())
    }

    /// `gain_t = Phi P`, copying the rows of `P` where `Phi` has a unit row
    /// (states without dynamics, e.g. random-constant biases, keep `e_i` rows
    /// in every product of their transition matrices); the other rows are
    /// `Phi`'s rows times `P`.
    #[inline(always)]
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
        // Row i of Phi P is sum_j Phi_ij (column j of P), P symmetric.
        let (p, _) = p.as_slice().as_chunks::<N>();
        let (out, _) = self.gain_t.as_mut_slice().as_chunks_mut::<N>();
        for (out, column) in out.iter_mut().zip(p) {
            *out = *column;
        }
        let mut row = [0.0; N];
        for (phi_row, &i) in self.phi_rows[..self.rows]
            .iter()
            .zip(&self.dynamic[..self.rows])
        {
            row.fill(0.0);
            for (&a, column) in phi_row.iter().zip(p) {
                if a != 0.0 {
                    axpy_n(a, column, &mut row);
                }
            }
            for (out, &v) in out.iter_mut().zip(&row) {
                out[i] = v;
            }
        }
    }
}

/// The Cholesky factor of the symmetric `a` in place (lower triangle; the
/// strict upper triangle is left as it was); `false` if `a` is not
/// positive definite (or not finite).
#[inline(always)]
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

/// `x <- (L L^T)^-1 x` with the lower-triangular `l` and `u = l^T`
/// (column-major).
#[inline(always)]
fn solve_in_place<const N: usize>(l: &SMatrix<f64, N, N>, u: &SMatrix<f64, N, N>, x: &mut [f64]) {
    let (l, u) = (l.as_slice(), u.as_slice());
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
    // U z = y, column by column from the last.
    for j in (0..N).rev() {
        let col = &u[j * N..(j + 1) * N];
        x[j] /= col[j];
        let xj = x[j];
        if xj != 0.0 {
            axpy(-xj, &col[..j], &mut x[..j]);
        }
    }
}

/// `y <- y + a x` (over the shorter of the two).
#[inline(always)]
fn axpy(a: f64, x: &[f64], y: &mut [f64]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

/// `x . y` (over the shorter of the two), in four interleaved partial sums
/// (so the loop runs in vector lanes), added pairwise at the end.
#[inline(always)]
fn dot(x: &[f64], y: &[f64]) -> f64 {
    let n = x.len().min(y.len());
    let (x, y) = (&x[..n], &y[..n]);
    let mut acc = [0.0; 4];
    let (xs, x_tail) = x.as_chunks::<4>();
    let (ys, y_tail) = y.as_chunks::<4>();
    for (a, b) in xs.iter().zip(ys) {
        for k in 0..4 {
            acc[k] += a[k] * b[k];
        }
    }
    let mut tail = 0.0;
    for (a, b) in x_tail.iter().zip(y_tail) {
        tail += a * b;
    }
    ((acc[0] + acc[2]) + (acc[1] + acc[3])) + tail
}

/// [`axpy`] of length `N`.
#[inline(always)]
fn axpy_n<const N: usize>(a: f64, x: &[f64; N], y: &mut [f64; N]) {
    for (y, x) in y.iter_mut().zip(x) {
        *y += a * x;
    }
}

/// [`dot`] of length `N`.
#[inline(always)]
fn dot_n<const N: usize>(x: &[f64; N], y: &[f64; N]) -> f64 {
    dot(x, y)
}

#[cfg(test)]
impl<const N: usize> Step<N> {
    /// A copy of the kept later epoch (tests).
    fn clone_parts(&self) -> Self {
        let mut s = Self::new();
        s.factor = self.factor;
        s.transition = self.transition;
        s.correction = self.correction;
        s
    }
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
        solve_in_place(&l, &l.transpose(), x.as_mut_slice());
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

    /// The dispatched step (AVX where the CPU has it) and the portable build
    /// give the same bits.
    #[test]
    fn dispatched_step_equals_the_portable_one_bit_for_bit() {
        let p = spd();
        let mut later = Step::<5>::new();
        let mut phi = SMatrix::<f64, 5, 5>::identity();
        phi[(0, 1)] = 0.1;
        phi[(2, 4)] = -0.3;
        let predicted = phi * p * phi.transpose() + SMatrix::identity() * 0.1;
        later.keep(&Epoch::<5, 0>::at(1.0, phi, predicted, SVector::zeros()));
        later.correction = SVector::from_fn(|i, _| 0.01 * i as f64);
        let epoch = Epoch::<5, 0>::at(0.0, SMatrix::identity(), p, SVector::zeros());
        let smoothed = SmoothedEpoch::<5, 0> {
            time: 1.0,
            snapshot: SVector::zeros(),
            error: SVector::from_fn(|i, _| 0.2 - 0.1 * i as f64),
            covariance: predicted * 0.5,
            filtered: predicted,
        };
        let (mut a, mut b) = (later.clone_parts(), later.clone_parts());
        let (mut out_a, mut out_b) = (smoothed, smoothed);
        rts_step(&mut a, &epoch, &mut out_a).unwrap();
        rts_step_portable::<5, 0, false>(&mut b, &epoch, &mut out_b).unwrap();
        assert_eq!(out_a.error.map(f64::to_bits), out_b.error.map(f64::to_bits));
        assert_eq!(
            out_a.covariance.map(f64::to_bits),
            out_b.covariance.map(f64::to_bits)
        );
        assert_ne!(out_a.covariance, smoothed.covariance, "the step ran");
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
