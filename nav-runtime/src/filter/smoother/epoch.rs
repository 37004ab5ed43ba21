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
    #[cfg(test)]
    pub(crate) fn decode(bytes: &[u8]) -> Self {
        let mut epoch = Self::at(
            f64::NAN,
            SMatrix::zeros(),
            SMatrix::zeros(),
            SVector::zeros(),
        );
        epoch.decode_into(bytes);
        epoch
    }

    /// [`Epoch::decode`] into `self`, without a temporary epoch.
    pub(crate) fn decode_into(&mut self, bytes: &[u8]) {
        let (words, _) = bytes.as_chunks::<8>();
        if let Some(words) = words.get(..Self::SCALARS) {
            self.decode_whole(words);
            return;
        }
        let mut at = 0;
        // The next `dst.len()` words into `dst` (NaN past the end).
        let mut fill = |dst: &mut [f64]| {
            let src = words.get(at..).unwrap_or(&[]);
            for (d, w) in dst.iter_mut().zip(src) {
                *d = f64::from_le_bytes(*w);
            }
            if let Some(rest) = dst.get_mut(src.len()..) {
                rest.fill(f64::NAN);
            }
            at += dst.len();
        };
        fill(core::slice::from_mut(&mut self.time));
        fill(self.transition.as_mut_slice());
        for m in [&mut self.predicted, &mut self.filtered] {
            // The upper triangle, column by column, then mirrored.
            let (columns, _) = m.as_mut_slice().as_chunks_mut::<N>();
            for (c, column) in columns.iter_mut().enumerate() {
                fill(&mut column[..=c]);
            }
            for c in 0..N {
                for r in c + 1..N {
                    m[(r, c)] = m[(c, r)];
                }
            }
        }
        fill(self.correction.as_mut_slice());
        fill(self.snapshot.as_mut_slice());
    }

    /// [`Epoch::decode_into`] of a whole record (`SCALARS` words): each
    /// entry of an upper triangle is written to both of its places.
    fn decode_whole(&mut self, words: &[[u8; 8]]) {
        let (time, rest) = words.split_at(1);
        self.time = f64::from_le_bytes(time[0]);
        let (transition, mut rest) = rest.split_at(N * N);
        for (d, w) in self.transition.as_mut_slice().iter_mut().zip(transition) {
            *d = f64::from_le_bytes(*w);
        }
        for m in [&mut self.predicted, &mut self.filtered] {
            let m = m.as_mut_slice();
            for c in 0..N {
                let (column, tail) = rest.split_at(c + 1);
                for (r, w) in column.iter().enumerate() {
                    let v = f64::from_le_bytes(*w);
                    m[c * N + r] = v;
                    m[r * N + c] = v;
                }
                rest = tail;
            }
        }
        let (correction, snapshot) = rest.split_at(N);
        for (d, w) in self.correction.iter_mut().zip(correction) {
            *d = f64::from_le_bytes(*w);
        }
        for (d, w) in self.snapshot.iter_mut().zip(snapshot) {
            *d = f64::from_le_bytes(*w);
        }
    }

    /// Writes the epoch as `SCALARS` little-endian `f64` into `out`
    /// (`8 * SCALARS` bytes; a shorter `out` gets the first values).
    pub(crate) fn encode(&self, out: &mut [u8]) {
        let (words, _) = out.as_chunks_mut::<8>();
        let mut words = words.iter_mut();
        let mut put = |values: &[f64]| {
            // `values` first: at its end no word is taken.
            for (v, w) in values.iter().zip(&mut words) {
                *w = v.to_le_bytes();
            }
        };
        put(&[self.time]);
        put(self.transition.as_slice());
        for m in [&self.predicted, &self.filtered] {
            let (columns, _) = m.as_slice().as_chunks::<N>();
            for (c, column) in columns.iter().enumerate() {
                put(&column[..=c]);
            }
        }
        put(self.correction.as_slice());
        put(self.snapshot.as_slice());
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
        let mut bytes = vec![0; 8 * Epoch::<3, 2>::SCALARS];
        e.encode(&mut bytes);
        assert_eq!(bytes.len(), 8 * Epoch::<3, 2>::SCALARS);
        assert_eq!(Epoch::<3, 2>::decode(&bytes), e);
        // A short record: what is there, NaN for the rest.
        let short = Epoch::<3, 2>::decode(&bytes[..8 * (Epoch::<3, 2>::SCALARS - 1)]);
        assert_eq!((short.time, short.filtered), (e.time, e.filtered));
        assert_eq!(short.correction, e.correction);
        assert_eq!(short.snapshot[0], e.snapshot[0]);
        assert!(short.snapshot[1].is_nan());
    }
}
