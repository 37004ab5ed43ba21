//! One epoch of a forward run, as the backward pass reads it.

use nalgebra::{SMatrix, SVector};

/// What the backward pass needs of one epoch `k` of the forward run.
///
/// `N` is the filter's state (or error-state) dimension, `S` the length of
/// the caller's snapshot of the estimate (position, velocity, ... in any
/// units the caller chooses; the smoother only stores it).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Epoch<const N: usize, const S: usize> {
    /// Time of the epoch, s.
    pub time: f64,
    /// `Phi` from the previous epoch to this one (identity for the first).
    pub transition: SMatrix<f64, N, N>,
    /// Covariance before this epoch's updates, `P_k-`.
    pub predicted: SMatrix<f64, N, N>,
    /// Sum of the corrections applied at this epoch, `c_k` (forward solution
    /// before the updates minus after, in error-state coordinates).
    pub correction: SVector<f64, N>,
    /// Covariance after this epoch's updates, `P_k+`.
    pub filtered: SMatrix<f64, N, N>,
    /// The caller's snapshot of the forward estimate after the updates.
    pub snapshot: SVector<f64, S>,
}

impl<const N: usize, const S: usize> Epoch<N, S> {
    /// Number of `f64` scalars of one stored epoch: time, `Phi`, the upper
    /// triangles of the two covariances, the correction and the snapshot.
    pub const SCALARS: usize = 1 + N * N + N * (N + 1) + N + S;

    /// An epoch without updates (yet): `P+ = P-`, no correction.
    pub fn at(
        time: f64,
        transition: SMatrix<f64, N, N>,
        predicted: SMatrix<f64, N, N>,
        snapshot: SVector<f64, S>,
    ) -> Self {
        Self {
            time,
            transition,
            predicted,
            correction: SVector::zeros(),
            filtered: predicted,
            snapshot,
        }
    }

    /// Reads an epoch written by [`Epoch::encode`]; `bytes` holds exactly
    /// `8 * SCALARS` bytes (missing values read as NaN).
    pub(crate) fn decode(bytes: &[u8]) -> Self {
        let mut values = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]));
        let mut next = || values.next().unwrap_or(f64::NAN);
        let mut epoch = Self {
            time: next(),
            transition: SMatrix::zeros(),
            predicted: SMatrix::zeros(),
            correction: SVector::zeros(),
            filtered: SMatrix::zeros(),
            snapshot: SVector::zeros(),
        };
        epoch.transition.iter_mut().for_each(|v| *v = next());
        for m in [&mut epoch.predicted, &mut epoch.filtered] {
            let s = m.as_mut_slice();
            for c in 0..N {
                for r in 0..=c {
                    let v = next();
                    s[c * N + r] = v;
                    s[r * N + c] = v;
                }
            }
        }
        epoch.correction.iter_mut().for_each(|v| *v = next());
        epoch.snapshot.iter_mut().for_each(|v| *v = next());
        epoch
    }

    /// Writes the epoch as `SCALARS` little-endian `f64` into `out`.
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        out.reserve(8 * Self::SCALARS);
        let mut put = |v: f64| out.extend_from_slice(&v.to_le_bytes());
        put(self.time);
        self.transition.iter().for_each(|&v| put(v));
        for m in [&self.predicted, &self.filtered] {
            let s = m.as_slice();
            for c in 0..N {
                s[c * N..=c * N + c].iter().for_each(|&v| put(v));
            }
        }
        self.correction.iter().for_each(|&v| put(v));
        self.snapshot.iter().for_each(|&v| put(v));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn encoding_round_trips_bit_for_bit() {
        let sym = |s: f64| {
            let a = SMatrix::<f64, 3, 3>::from_fn(|r, c| s + (r * 3 + c) as f64 * 0.1);
            a * a.transpose()
        };
        let e = Epoch::<3, 2> {
            time: 12.5,
            transition: SMatrix::from_fn(|r, c| (r as f64 - c as f64) / 7.0),
            predicted: sym(1.0),
            correction: SVector::from_fn(|i, _| -(i as f64) * 1e-3),
            filtered: sym(0.5),
            snapshot: SVector::from_fn(|i, _| 1e6 + i as f64),
        };
        let mut bytes = Vec::new();
        e.encode(&mut bytes);
        assert_eq!(bytes.len(), 8 * Epoch::<3, 2>::SCALARS);
        assert_eq!(Epoch::<3, 2>::decode(&bytes), e);
    }
}
