//! The backward pass: Rauch-Tung-Striebel over the recorded epochs.
//!
//! Only the epochs with updates are links of the recursion. An epoch `j`
//! without an update (an output time: `P_j+ = P_j-`, `c_j = 0`) is derived
//! from the next epoch with updates `u` (or the last epoch) directly: with
//! `Phi = Phi(u, j)`, the product of the recorded transitions from `j` to `u`,
//! and `L L^T = P_u-`, the gain `C_j = P_j+ Phi^T (P_u-)^-1` gives (eq. S2, S3
//! across the interval, exact: the output epochs between them change nothing
//! in the chain)
//!
//! ```text
//! H_j  = L^-1 Phi(u, j) P_j+
//! s_j  = H_j^T y_u,                 y_u = L^-1 (s_u + c_u)
//! Ps_j = P_j+ + H_j^T X_u H_j,      X_u = L^-1 (Ps_u - P_u-) L^-T
//! ```
//!
//! `y_u` and `X_u` are computed once per epoch with updates; every epoch
//! (with updates or not) then costs one `Phi P`, one triangular solve of `N`
//! columns and one product (plus the upper triangle of `H^T (X H)`), on
//! well-scaled quantities: `X_u` has its eigenvalues in `[-1, 0]` (as
//! `0 <= Ps_u <= P_u-`) and `H_j^T H_j <= P_j+`.

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
    /// Covariance of the smoothed estimate's error, `Ps_k`: whole from
    /// [`smooth`]; from [`smooth_states`] the entries between two of the
    /// chosen states, and NaN elsewhere.
    pub covariance: SMatrix<f64, N, N>,
    /// Covariance of the forward estimate's error, `P_k+`.
    pub filtered: SMatrix<f64, N, N>,
}

/// A set of states (indices below `N`): those whose smoothed covariance
/// [`smooth_states`] reports.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct States<const N: usize> {
    /// The states, ascending (`list[..len]`).
    list: [usize; N],
    len: usize,
}

impl<const N: usize> States<N> {
    /// Every state.
    pub fn all() -> Self {
        Self {
            list: core::array::from_fn(|i| i),
            len: N,
        }
    }

    /// The states `i` with `chosen[i]`.
    pub fn from_mask(chosen: [bool; N]) -> Self {
        let mut out = Self {
            list: [0; N],
            len: 0,
        };
        for (i, _) in chosen.iter().enumerate().filter(|(_, &c)| c) {
            out.list[out.len] = i;
            out.len += 1;
        }
        out
    }

    /// The states, ascending.
    pub fn as_slice(&self) -> &[usize] {
        &self.list[..self.len]
    }

    /// `true` if state `i` is in the set.
    pub fn contains(&self, i: usize) -> bool {
        self.as_slice().binary_search(&i).is_ok()
    }
}

/// Smooths the epochs of `file` and calls `visit` with each, latest first
/// (module docs; `docs/smoother.md`, eq. S1-S3). Memory: two epochs and the
/// work space of one step (boxed, so nothing large is on the stack).
///
/// # Errors
/// [`SmootherError::NotPositiveDefinite`] if the predicted covariance of an
/// epoch with updates (or of the last epoch) has no Cholesky factor,
/// [`SmootherError::NonFinite`] for a non-finite result,
/// [`SmootherError::Io`] on a failed read, or the first error of `visit`.
pub fn smooth<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    visit: impl FnMut(&SmoothedEpoch<N, S>) -> Result<(), SmootherError>,
) -> Result<(), SmootherError> {
    smooth_with(file, &States::all(), false, visit)
}

/// [`smooth`], with the smoothed covariance reported between the `states`
/// only (NaN elsewhere): at the epochs without updates the backward pass
/// then computes only those entries, which is cheaper when they are few.
/// The smoothed errors, and the covariances at the epochs with updates that
/// the recursion carries, are computed whole; the reported entries are the
/// same bits as [`smooth`]'s.
///
/// # Errors
/// As [`smooth`] (a non-finite covariance entry counts among the states).
pub fn smooth_states<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    states: &States<N>,
    visit: impl FnMut(&SmoothedEpoch<N, S>) -> Result<(), SmootherError>,
) -> Result<(), SmootherError> {
    smooth_with(file, states, false, visit)
}

/// [`smooth_states`]; with `chain_every_epoch` every epoch is a link of the
/// recursion, also those without updates (the plain chained RTS recursion,
/// which the tests compare with).
fn smooth_with<const N: usize, const S: usize>(
    file: &mut EpochFile<N, S>,
    states: &States<N>,
    chain_every_epoch: bool,
    mut visit: impl FnMut(&SmoothedEpoch<N, S>) -> Result<(), SmootherError>,
) -> Result<(), SmootherError> {
    let mut step = Box::new(Backward::<N>::new());
    let mut out = Box::new(SmoothedEpoch::<N, S> {
        time: f64::NAN,
        snapshot: SVector::zeros(),
        error: SVector::zeros(),
        covariance: SMatrix::zeros(),
        filtered: SMatrix::zeros(),
    });
    let all = States::<N>::all();
    let partial = states.len < N;
    let mut first = true;
    file.read_back(|epoch| {
        let updated = !all_zero(epoch.correction.as_slice())
            || differ(epoch.filtered.as_slice(), epoch.predicted.as_slice());
        let link = first || updated || chain_every_epoch;
        // A link's whole covariance is carried to the epochs before it.
        let computed = if link { &all } else { states };
        if first {
            out.error = SVector::zeros();
            out.covariance = epoch.filtered;
        } else {
            backward_step(&mut step, epoch, &mut out, computed.as_slice());
        }
        let finite = all_finite(out.error.as_slice())
            && if computed.len == N {
                all_finite(out.covariance.as_slice())
            } else {
                block_finite(&out.covariance, computed.as_slice())
            };
        if !finite {
            return Err(SmootherError::NonFinite { time: epoch.time });
        }
        if link && !backward_link(&mut step, epoch, &out) {
            return Err(SmootherError::NotPositiveDefinite { time: epoch.time });
        }
        // Entries outside the states: NaN after a link's whole covariance;
        // the other epochs write only those between the states.
        if partial && link {
            mask_outside(&mut out.covariance, states);
        }
        out.time = epoch.time;
        out.snapshot = epoch.snapshot;
        out.filtered = epoch.filtered;
        visit(&out)?;
        step.keep(epoch);
        first = false;
        Ok(())
    })
}

/// `true` if the entries of `m` between two of `states` are finite.
fn block_finite<const N: usize>(m: &SMatrix<f64, N, N>, states: &[usize]) -> bool {
    states
        .iter()
        .all(|&c| states.iter().all(|&r| m[(r, c)].is_finite()))
}

/// NaN into the entries of `m` that are not between two of `states`.
fn mask_outside<const N: usize>(m: &mut SMatrix<f64, N, N>, states: &States<N>) {
    let mut chosen = [false; N];
    for &i in states.as_slice() {
        chosen[i] = true;
    }
    for (column, &in_c) in m.as_mut_slice().chunks_exact_mut(N).zip(&chosen) {
        for (v, &in_r) in column.iter_mut().zip(&chosen) {
            if !(in_c && in_r) {
                *v = f64::NAN;
            }
        }
    }
}

/// The state of the backward pass between epochs, and its work space.
/// Matrices are column-major, so every inner loop runs over a contiguous
/// column (of a symmetric matrix, a column is also a row).
struct Backward<const N: usize> {
    /// Of the link `u` (the latest epoch with updates so far): the Cholesky
    /// factor `L` of `P_u-` (lower triangle).
    factor: SMatrix<f64, N, N>,
    /// Of the link: `X_u = L^-1 (Ps_u - P_u-) L^-T`.
    x: SMatrix<f64, N, N>,
    /// Of the link: `z_u = (P_u-)^-1 (s_u + c_u)`, so that
    /// `s_j = H_j^T y_u = (Phi(u, j) P_j+)^T z_u`.
    z: [f64; N],
    /// `Phi(u, j + 1)`, row-major, and which of its rows are not unit rows
    /// (`e_i`: states without dynamics keep those in every product).
    phi: [[f64; N]; N],
    phi_dynamic: [bool; N],
    /// The transition recorded with epoch `j + 1` (from `j` to `j + 1`),
    /// row-major, and its rows that are not unit rows.
    transition: [[f64; N]; N],
    transition_dynamic: [bool; N],
    /// `G = Phi(u, j) P_j+`, row by row; at a link `L^-1 (Ps - P-)` and
    /// `X_u`.
    rows: [[f64; N]; N],
    /// The columns of `G` of the chosen states (first `m` of each row),
    /// then of `H_j = L^-1 G`, in place.
    chosen: [[f64; N]; N],
    /// The columns of `H_j` of the chosen states (the first `m`).
    h: SMatrix<f64, N, N>,
    /// `X_u H_j`, the same columns.
    w: SMatrix<f64, N, N>,
}

impl<const N: usize> Backward<N> {
    fn new() -> Self {
        Self {
            factor: SMatrix::zeros(),
            x: SMatrix::zeros(),
            z: [0.0; N],
            phi: [[0.0; N]; N],
            phi_dynamic: [false; N],
            transition: [[0.0; N]; N],
            transition_dynamic: [false; N],
            rows: [[0.0; N]; N],
            chosen: [[0.0; N]; N],
            h: SMatrix::zeros(),
            w: SMatrix::zeros(),
        }
    }

    /// Keeps the transition of `epoch` for the step to the epoch before it.
    fn keep<const S: usize>(&mut self, epoch: &Epoch<N, S>) {
        let (columns, _) = epoch.transition.as_slice().as_chunks::<N>();
        for (j, column) in columns.iter().enumerate() {
            for (row, &v) in self.transition.iter_mut().zip(column) {
                row[j] = v;
            }
        }
        // A unit row: its diagonal entry made 0 leaves a zero row.
        for (i, (row, dynamic)) in self
            .transition
            .iter()
            .zip(&mut self.transition_dynamic)
            .enumerate()
        {
            let mut unit = *row;
            unit[i] -= 1.0;
            *dynamic = !all_zero(&unit);
        }
    }
}

crate::dispatch::avx_dispatch! {
    /// Epoch `j` (not the last) from the link: overwrites `out`'s error and
    /// its covariance between two of `states` (ascending) with epoch `j`'s
    /// (module docs). Compiled for AVX where the
    /// CPU has it (the same operations in the same order: bit-identical
    /// results).
    fn backward_step<const N: usize, const S: usize>(
        step: &mut Backward<N>,
        epoch: &Epoch<N, S>,
        out: &mut SmoothedEpoch<N, S>,
        states: &[usize],
    ) => backward_step_portable;
}

crate::dispatch::avx_dispatch! {
    /// Makes `epoch`, smoothed in `out`, the link: its factor, `y` and `X`,
    /// and `Phi = I`. `false` if its predicted covariance has no Cholesky
    /// factor. Compiled for AVX where the CPU has it (bit-identical).
    fn backward_link<const N: usize, const S: usize>(
        step: &mut Backward<N>,
        epoch: &Epoch<N, S>,
        out: &SmoothedEpoch<N, S>,
    ) -> bool => backward_link_portable;
}

/// The body of [`backward_step`].
#[inline(always)]
fn backward_step_portable<const N: usize, const S: usize, const AVX: bool>(
    step: &mut Backward<N>,
    epoch: &Epoch<N, S>,
    out: &mut SmoothedEpoch<N, S>,
    states: &[usize],
) {
    step.extend_phi();
    step.phi_times(&epoch.filtered);
    // s_j = G^T z.
    let mut error = [0.0; N];
    for (row, &z) in step.rows.iter().zip(&step.z) {
        if z != 0.0 {
            axpy_n(z, row, &mut error);
        }
    }
    out.error = error.into();
    // H = L^-1 G over the chosen columns, row by row; its columns into `h`.
    let m = states.len();
    for (chosen, row) in step.chosen.iter_mut().zip(&step.rows) {
        for (v, &c) in chosen.iter_mut().zip(states) {
            *v = row[c];
        }
    }
    solve_rows(&step.factor, &mut step.chosen, m);
    for (k, column) in step
        .h
        .as_mut_slice()
        .chunks_exact_mut(N)
        .take(m)
        .enumerate()
    {
        for (v, row) in column.iter_mut().zip(&step.chosen) {
            *v = row[k];
        }
    }
    let (h, _) = step.h.as_slice().as_chunks::<N>();
    let h = &h[..m];
    // W = X H: column k is sum_i H_ik (column i of X).
    let (x, _) = step.x.as_slice().as_chunks::<N>();
    let (w, _) = step.w.as_mut_slice().as_chunks_mut::<N>();
    for (w_k, h_k) in w.iter_mut().zip(h) {
        w_k.fill(0.0);
        for (&a, x_i) in h_k.iter().zip(x) {
            if a != 0.0 {
                axpy_n(a, x_i, w_k);
            }
        }
    }
    // Ps_j = P_j+ + H^T W between the chosen states: the upper triangle,
    // mirrored (exactly symmetric).
    for (k, (w_k, &c)) in w.iter().zip(states).enumerate() {
        for (h_l, &r) in h[..=k].iter().zip(states) {
            let v = epoch.filtered[(r, c)] + dot_n(h_l, w_k);
            out.covariance[(r, c)] = v;
            out.covariance[(c, r)] = v;
        }
    }
}

/// The body of [`backward_link`].
#[inline(always)]
fn backward_link_portable<const N: usize, const S: usize, const AVX: bool>(
    step: &mut Backward<N>,
    epoch: &Epoch<N, S>,
    out: &SmoothedEpoch<N, S>,
) -> bool {
    step.factor = epoch.predicted;
    if !cholesky_in_place(&mut step.factor) {
        return false;
    }
    // z = L^-T L^-1 (s + c).
    step.z = (out.error + epoch.correction).into();
    let (factor, _) = step.factor.as_slice().as_chunks::<N>();
    forward_in_place(factor, &mut step.z);
    backward_in_place(factor, &mut step.z);
    // Z = L^-1 D, D = Ps - P- (symmetric: its rows are its columns).
    let (ps, _) = out.covariance.as_slice().as_chunks::<N>();
    let (predicted, _) = epoch.predicted.as_slice().as_chunks::<N>();
    for ((row, ps), predicted) in step.rows.iter_mut().zip(ps).zip(predicted) {
        for ((v, a), b) in row.iter_mut().zip(ps).zip(predicted) {
            *v = a - b;
        }
    }
    solve_rows(&step.factor, &mut step.rows, N);
    // X = L^-1 Z^T = L^-1 D L^-T: the rows of Z^T are the columns of Z.
    let z = step.rows;
    for (c, row) in step.rows.iter_mut().enumerate() {
        for (v, z) in row.iter_mut().zip(&z) {
            *v = z[c];
        }
    }
    solve_rows(&step.factor, &mut step.rows, N);
    // Symmetric in exact arithmetic; made so to the bit.
    for (c, column) in step.x.as_mut_slice().chunks_exact_mut(N).enumerate() {
        for (r, v) in column.iter_mut().enumerate() {
            *v = 0.5 * (step.rows[r][c] + step.rows[c][r]);
        }
    }
    step.phi_dynamic = [false; N];
    true
}

impl<const N: usize> Backward<N> {
    /// `Phi(u, j) = Phi(u, j + 1) Phi_{j+1}` with the kept transition, over
    /// the rows that are not unit rows (a unit row `k` of the transition, as
    /// a factor, moves one entry).
    #[inline(always)]
    fn extend_phi(&mut self) {
        let mut row = [0.0; N];
        for (i, (phi_i, dynamic)) in self.phi.iter_mut().zip(&mut self.phi_dynamic).enumerate() {
            if *dynamic {
                row.fill(0.0);
                for (k, &a) in phi_i.iter().enumerate() {
                    if a == 0.0 {
                        continue;
                    }
                    if self.transition_dynamic[k] {
                        axpy_n(a, &self.transition[k], &mut row);
                    } else {
                        row[k] += a;
                    }
                }
                *phi_i = row;
            } else if self.transition_dynamic[i] {
                *phi_i = self.transition[i];
                *dynamic = true;
            }
        }
    }

    /// `rows = Phi(u, j) P` (row by row), copying the rows of `P` where
    /// `Phi` has a unit row; the other rows are `Phi`'s rows times `P`
    /// (skipping its zeros).
    #[inline(always)]
    fn phi_times(&mut self, p: &SMatrix<f64, N, N>) {
        // Row k of P is column k (P symmetric).
        let (p, _) = p.as_slice().as_chunks::<N>();
        for (((out, phi_i), &dynamic), p_i) in self
            .rows
            .iter_mut()
            .zip(&self.phi)
            .zip(&self.phi_dynamic)
            .zip(p)
        {
            if dynamic {
                out.fill(0.0);
                for (&a, p_k) in phi_i.iter().zip(p) {
                    if a != 0.0 {
                        axpy_n(a, p_k, out);
                    }
                }
            } else {
                *out = *p_i;
            }
        }
    }
}

/// `B <- L^-1 B` in place over the first `m` columns, `B` given by its rows
/// and `L` by its columns (lower triangle; the strict upper triangle is not
/// read): row `j` of the result is row `j` of `B` less `L_jk` times the rows
/// `k < j` before it, over `L_jj`. Every operation is on a whole row, each
/// entry the same operations whatever `m`.
#[inline(always)]
fn solve_rows<const N: usize>(l: &SMatrix<f64, N, N>, b: &mut [[f64; N]; N], m: usize) {
    for j in 0..N {
        // Accumulated in a local row, which the compiler knows aliases
        // nothing (so the row operations run in vector lanes).
        let mut row = b[j];
        for (k, done_k) in b[..j].iter().enumerate() {
            let a = l[(j, k)];
            if a != 0.0 {
                if m == N {
                    axpy_n(-a, done_k, &mut row);
                } else {
                    axpy(-a, &done_k[..m], &mut row[..m]);
                }
            }
        }
        let d = l[(j, j)];
        for v in row.iter_mut().take(m) {
            *v /= d;
        }
        b[j] = row;
    }
}

/// `x <- L^-T x` with the lower-triangular `l` given by its columns:
/// `x_j = (x_j - L[j+1.., j] . x[j+1..]) / L_jj` from the last.
#[inline(always)]
fn backward_in_place<const N: usize>(l: &[[f64; N]], x: &mut [f64; N]) {
    for (j, col) in l.iter().enumerate().take(N).rev() {
        let s = dot(&col[j + 1..], &x[j + 1..]);
        x[j] = (x[j] - s) / col[j];
    }
}

/// `true` if every value is finite: a product with zero is NaN exactly for
/// the others. In four partial sums, so the loop runs in vector lanes.
#[inline(always)]
fn all_finite(values: &[f64]) -> bool {
    let mut acc = [0.0; 4];
    let (chunks, tail) = values.as_chunks::<4>();
    for chunk in chunks {
        for (a, v) in acc.iter_mut().zip(chunk) {
            *a += v * 0.0;
        }
    }
    for (a, v) in acc.iter_mut().zip(tail) {
        *a += v * 0.0;
    }
    (acc[0] + acc[1]) + (acc[2] + acc[3]) == 0.0
}

/// `true` if every value is zero (of either sign); NaN is not.
#[inline(always)]
fn all_zero(values: &[f64]) -> bool {
    // Without the sign bit, zero is the only value with all bits clear.
    let mut acc = [0u64; 4];
    let (chunks, tail) = values.as_chunks::<4>();
    for chunk in chunks {
        for (a, v) in acc.iter_mut().zip(chunk) {
            *a |= v.to_bits() << 1;
        }
    }
    for (a, v) in acc.iter_mut().zip(tail) {
        *a |= v.to_bits() << 1;
    }
    (acc[0] | acc[1] | acc[2] | acc[3]) == 0
}

/// `true` if `a` and `b` differ in a bit.
#[inline(always)]
fn differ(a: &[f64], b: &[f64]) -> bool {
    let mut acc = [0u64; 4];
    let (a, a_tail) = a.as_chunks::<4>();
    let (b, b_tail) = b.as_chunks::<4>();
    for (x, y) in a.iter().zip(b) {
        for k in 0..4 {
            acc[k] |= x[k].to_bits() ^ y[k].to_bits();
        }
    }
    for (k, (x, y)) in a_tail.iter().zip(b_tail).enumerate() {
        acc[k] |= x.to_bits() ^ y.to_bits();
    }
    (acc[0] | acc[1] | acc[2] | acc[3]) != 0
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

/// `x <- L^-1 x` with the lower-triangular `l` given by its columns (the
/// strict upper triangle is not read), column by column.
#[inline(always)]
fn forward_in_place<const N: usize>(l: &[[f64; N]], x: &mut [f64; N]) {
    for (j, col) in l.iter().enumerate().take(N) {
        x[j] /= col[j];
        let xj = x[j];
        if xj != 0.0 {
            let (_, tail) = x.split_at_mut(j + 1);
            axpy(-xj, &col[j + 1..], tail);
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
mod tests {
    use super::*;

    fn spd() -> SMatrix<f64, 5, 5> {
        let a = SMatrix::<f64, 5, 5>::from_fn(|r, c| ((r * 5 + c) as f64 * 0.7).sin());
        a * a.transpose() + SMatrix::identity() * 0.5
    }

    /// A transition with unit rows 1 and 4 (states without dynamics).
    fn transition(s: f64) -> SMatrix<f64, 5, 5> {
        let mut phi = SMatrix::<f64, 5, 5>::identity();
        for (i, j, v) in [
            (0, 1, 0.1),
            (0, 4, -0.3),
            (2, 0, 0.2),
            (2, 2, 0.05),
            (3, 1, 0.4),
        ] {
            phi[(i, j)] += v * s;
        }
        phi
    }

    /// The in-place Cholesky factor and forward solve agree with nalgebra's.
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
        let mut x: [f64; 5] = b.into();
        let (columns, _) = l.as_slice().as_chunks::<5>();
        forward_in_place(columns, &mut x);
        let x_ref = l_ref.solve_lower_triangular(&b).unwrap();
        assert!((SVector::from(x) - x_ref).norm() < 1e-12 * x_ref.norm());
    }

    /// The row-wise solve of a matrix equals nalgebra's triangular solve.
    #[test]
    fn row_solve_matches_nalgebra() {
        let a = spd();
        let mut l = a;
        assert!(cholesky_in_place(&mut l));
        let b = SMatrix::<f64, 5, 5>::from_fn(|r, c| (r as f64 - 2.0 * c as f64).cos());
        let mut rows: [[f64; 5]; 5] = core::array::from_fn(|r| core::array::from_fn(|c| b[(r, c)]));
        let mut first_three = rows;
        solve_rows(&l, &mut rows, 5);
        solve_rows(&l, &mut first_three, 3);
        let got = SMatrix::<f64, 5, 5>::from_fn(|r, c| rows[r][c]);
        let l_ref = a.cholesky().unwrap().l();
        let reference = l_ref.solve_lower_triangular(&b).unwrap();
        assert!((got - reference).norm() < 1e-12 * reference.norm());
        // Over the first columns only: the same bits there, the rest untouched.
        for (r, (part, whole)) in first_three.iter().zip(&rows).enumerate() {
            assert_eq!(part[..3], whole[..3]);
            assert_eq!(part[3..], [b[(r, 3)], b[(r, 4)]]);
        }
        // L^-T, from the last entry.
        let mut x: [f64; 5] = core::array::from_fn(|i| 0.3 * i as f64 - 0.4);
        let (columns, _) = l.as_slice().as_chunks::<5>();
        let expected = l_ref
            .transpose()
            .solve_upper_triangular(&SVector::from(x))
            .unwrap();
        backward_in_place(columns, &mut x);
        assert!((SVector::from(x) - expected).norm() < 1e-12 * expected.norm());
    }

    /// The vectorized checks: non-finite values, zeros, bit differences.
    #[test]
    fn checks_find_every_value() {
        let mut v = [1.5; 7];
        assert!(all_finite(&v) && !all_zero(&v) && !differ(&v, &v));
        for i in 0..7 {
            for bad in [f64::NAN, f64::INFINITY, f64::NEG_INFINITY] {
                let mut w = v;
                w[i] = bad;
                assert!(!all_finite(&w), "{i} {bad}");
                assert!(differ(&v, &w));
            }
        }
        v = [0.0; 7];
        v[3] = -0.0;
        assert!(all_zero(&v));
        for i in 0..7 {
            let mut w = v;
            w[i] = f64::MIN_POSITIVE;
            assert!(!all_zero(&w));
            w[i] = f64::NAN;
            assert!(!all_zero(&w));
        }
        assert!(differ(&[0.0], &[-0.0]));
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

    /// `Phi P` with unit rows copied, and `Phi` extended by a transition
    /// with unit rows, equal the dense products.
    #[test]
    fn phi_products_equal_the_dense_ones() {
        let p = spd();
        let mut step = Backward::<5>::new();
        let mut dense = SMatrix::<f64, 5, 5>::identity();
        for s in [1.0, -0.5, 2.0] {
            let t = transition(s);
            step.keep(&Epoch::<5, 0>::at(0.0, t, p, SVector::zeros()));
            assert_eq!(step.transition_dynamic, [true, false, true, true, false]);
            step.extend_phi();
            dense *= t;
            let phi = SMatrix::<f64, 5, 5>::from_fn(|r, c| match step.phi_dynamic[r] {
                true => step.phi[r][c],
                false => f64::from(u8::from(r == c)),
            });
            assert!((phi - dense).norm() < 1e-14, "{phi} != {dense}");
            step.phi_times(&p);
            let rows = SMatrix::<f64, 5, 5>::from_fn(|r, c| step.rows[r][c]);
            assert!((rows - dense * p).norm() < 1e-14);
        }
        assert_eq!(step.phi_dynamic, [true, false, true, true, false]);
    }

    /// A forward run of a 5-state linear system (states 1 and 4 without
    /// dynamics) into an epoch file: epochs at every step, an update of
    /// states 0 and 2 at every `every`-th.
    fn run(every: usize) -> EpochFile<5, 0> {
        let mut file = EpochFile::<5, 0>::create(None).unwrap();
        let q = SMatrix::<f64, 5, 5>::from_diagonal(&SVector::from([0.02, 0.0, 0.05, 0.01, 0.0]));
        let h = SMatrix::<f64, 2, 5>::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 1.0, 0.0, 0.0);
        let r = SMatrix::<f64, 2, 2>::new(0.3, 0.05, 0.05, 0.2);
        let mut p = spd();
        let mut phi = SMatrix::identity();
        for k in 0..40 {
            let mut epoch = Epoch::<5, 0>::at(k as f64, phi, p, SVector::zeros());
            if k % every == 0 {
                let s = h * p * h.transpose() + r;
                let gain = p * h.transpose() * s.try_inverse().unwrap();
                let i_kh = SMatrix::<f64, 5, 5>::identity() - gain * h;
                p = i_kh * p * i_kh.transpose() + gain * r * gain.transpose();
                p = (p + p.transpose()) * 0.5;
                epoch.filtered = p;
                let z = SVector::<f64, 2>::new((k as f64 * 0.9).sin(), (k as f64 * 0.4).cos());
                epoch.correction = -gain * z;
            }
            file.push(&epoch).unwrap();
            phi = transition(1.0 + 0.01 * k as f64);
            p = phi * p * phi.transpose() + q;
        }
        file
    }

    fn smoothed(file: &mut EpochFile<5, 0>, chain: bool) -> Vec<SmoothedEpoch<5, 0>> {
        let mut out = Vec::new();
        smooth_with(file, &States::all(), chain, |e| {
            out.push(*e);
            Ok(())
        })
        .unwrap();
        out
    }

    /// The epochs without updates, derived from the next epoch with updates,
    /// equal the recursion chained through every epoch to 1e-9.
    #[test]
    fn output_epochs_from_the_next_update_equal_the_chained_recursion() {
        for every in [1, 3, 7, 50] {
            let mut file = run(every);
            let (direct, chained) = (smoothed(&mut file, false), smoothed(&mut file, true));
            assert_eq!(direct.len(), 40);
            for (d, c) in direct.iter().zip(&chained) {
                let scale = c.covariance.norm();
                assert!(
                    (d.covariance - c.covariance).norm() <= 1e-9 * scale,
                    "every {every}, t = {}",
                    d.time
                );
                assert!((d.error - c.error).norm() <= 1e-9 * c.error.norm().max(1e-3));
                assert_eq!(d.filtered, c.filtered);
            }
            // The smoother ran: the first epoch learnt from later updates.
            let first = direct.last().unwrap();
            if every < 40 {
                assert!(first.covariance[(0, 0)] < first.filtered[(0, 0)]);
                assert_ne!(first.error, SVector::<f64, 5>::zeros());
            }
        }
    }

    /// With a set of states, the reported covariance entries between them
    /// are the same bits as the whole computation's, the others NaN; the
    /// errors are the same.
    #[test]
    fn chosen_states_give_the_same_bits_as_the_whole_covariance() {
        let states = States::from_mask([true, false, true, true, false]);
        assert_eq!(states.as_slice(), [0, 2, 3]);
        assert!(states.contains(2) && !states.contains(1));
        assert_eq!(States::<3>::all().as_slice(), [0, 1, 2]);
        for every in [1, 3, 7] {
            let mut file = run(every);
            let whole = smoothed(&mut file, false);
            let mut block = Vec::new();
            smooth_states(&mut file, &states, |e| {
                block.push(*e);
                Ok(())
            })
            .unwrap();
            for (w, b) in whole.iter().zip(&block) {
                assert_eq!(w.error, b.error);
                for r in 0..5 {
                    for c in 0..5 {
                        let (got, whole) = (b.covariance[(r, c)], w.covariance[(r, c)]);
                        if states.contains(r) && states.contains(c) {
                            assert_eq!(got.to_bits(), whole.to_bits());
                        } else {
                            assert!(got.is_nan());
                        }
                    }
                }
            }
        }
    }

    /// An epoch with updates whose predicted covariance has no factor is an
    /// error naming its time.
    #[test]
    fn a_predicted_covariance_without_factor_is_an_error() {
        let mut file = EpochFile::<5, 0>::create(None).unwrap();
        let p = spd();
        file.push(&Epoch::at(0.0, SMatrix::identity(), p, SVector::zeros()))
            .unwrap();
        let mut bad = Epoch::at(1.0, transition(1.0), -p, SVector::zeros());
        bad.filtered = p;
        file.push(&bad).unwrap();
        file.push(&Epoch::at(2.0, transition(1.0), p * 3.0, SVector::zeros()))
            .unwrap();
        let e = smooth(&mut file, |_| Ok(())).unwrap_err();
        assert!(
            matches!(e, SmootherError::NotPositiveDefinite { time } if time == 1.0),
            "{e}"
        );
    }

    /// The dispatched kernels (AVX where the CPU has it) and the portable
    /// build give the same bits.
    #[test]
    fn dispatched_kernels_equal_the_portable_ones_bit_for_bit() {
        let p = spd();
        let t = transition(1.0);
        let predicted = t * p * t.transpose() + SMatrix::identity() * 0.1;
        let mut later = Epoch::<5, 0>::at(1.0, t, predicted, SVector::zeros());
        later.correction = SVector::from_fn(|i, _| 0.01 * i as f64);
        later.filtered = predicted * 0.7;
        let smoothed_later = SmoothedEpoch::<5, 0> {
            time: 1.0,
            snapshot: SVector::zeros(),
            error: SVector::from_fn(|i, _| 0.2 - 0.1 * i as f64),
            covariance: predicted * 0.5,
            filtered: later.filtered,
        };
        let epoch = Epoch::<5, 0>::at(0.0, SMatrix::identity(), p, SVector::zeros());
        let (mut a, mut b) = (
            Box::new(Backward::<5>::new()),
            Box::new(Backward::<5>::new()),
        );
        assert!(backward_link(&mut a, &later, &smoothed_later));
        assert!(backward_link_portable::<5, 0, false>(
            &mut b,
            &later,
            &smoothed_later
        ));
        assert_eq!(a.x.map(f64::to_bits), b.x.map(f64::to_bits));
        assert_eq!(a.z.map(f64::to_bits), b.z.map(f64::to_bits));
        a.keep(&later);
        b.keep(&later);
        let (mut out_a, mut out_b) = (smoothed_later, smoothed_later);
        let all = States::<5>::all();
        backward_step(&mut a, &epoch, &mut out_a, all.as_slice());
        backward_step_portable::<5, 0, false>(&mut b, &epoch, &mut out_b, all.as_slice());
        assert_eq!(out_a.error.map(f64::to_bits), out_b.error.map(f64::to_bits));
        assert_eq!(
            out_a.covariance.map(f64::to_bits),
            out_b.covariance.map(f64::to_bits)
        );
        assert_ne!(out_a.covariance, smoothed_later.covariance, "the step ran");
    }
}
