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

    /// Writes the epoch as `SCALARS` little-endian `f64` into `out`.
    pub(crate) fn encode(&self, out: &mut Vec<u8>) {
        let mut put = |v: f64| out.extend_from_slice(&v.to_le_bytes());
        put(self.time);
        self.transition.iter().for_each(|&v| put(v));
        for m in [&self.predicted, &self.filtered] {
            for c in 0..N {
                for r in 0..=c {
                    put(m[(r, c)]);
                }
            }
        }
        self.correction.iter().for_each(|&v| put(v));
        self.snapshot.iter().for_each(|&v| put(v));
    }

    /// Reads an epoch written by [`Epoch::encode`]; `bytes` holds exactly
    /// `8 * SCALARS` bytes.
    pub(crate) fn decode(bytes: &[u8]) -> Self {
        let mut values = bytes
            .chunks_exact(8)
            .map(|c| f64::from_le_bytes(c.try_into().unwrap_or([0; 8])));
        let mut next = || values.next().unwrap_or(f64::NAN);
        let time = next();
        let transition = SMatrix::<f64, N, N>::from_iterator((0..N * N).map(|_| next()));
        let mut symmetric = || {
            let mut m = SMatrix::<f64, N, N>::zeros();
            for c in 0..N {
                for r in 0..=c {
                    let v = next();
                    m[(r, c)] = v;
                    m[(c, r)] = v;
                }
            }
            m
        };
        let predicted = symmetric();
        let filtered = symmetric();
        let correction = SVector::<f64, N>::from_fn(|_, _| next());
        let snapshot = SVector::<f64, S>::from_fn(|_, _| next());
        Self {
            time,
            transition,
            predicted,
            correction,
            filtered,
            snapshot,
        }
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
