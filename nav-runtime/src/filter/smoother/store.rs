//! The temporary file that holds a forward run's epochs.

use std::fs::{File, OpenOptions};
use std::io::{Read, Seek, SeekFrom, Write};
use std::marker::PhantomData;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicU64, Ordering};

use nalgebra::{SMatrix, SVector};

use super::epoch::Epoch;

/// A new, empty temporary file `nav-smoother-<process>-<n>.<extension>`
/// in `dir` (the system's temporary directory when `None`), opened for
/// reading and writing; never an existing file.
///
/// # Errors
/// [`SmootherError::Io`] if the file cannot be created.
pub(super) fn create_temporary(
    dir: Option<&Path>,
    extension: &str,
) -> Result<(PathBuf, File), SmootherError> {
    static COUNTER: AtomicU64 = AtomicU64::new(0);
    let dir = dir.map_or_else(std::env::temp_dir, Path::to_path_buf);
    let name = format!(
        "nav-smoother-{}-{}.{extension}",
        std::process::id(),
        COUNTER.fetch_add(1, Ordering::Relaxed)
    );
    let path = dir.join(name);
    let file = OpenOptions::new()
        .read(true)
        .write(true)
        .create_new(true)
        .open(&path)
        .map_err(|source| SmootherError::Io {
            path: path.clone(),
            source,
        })?;
    Ok((path, file))
}

/// Why smoothing failed.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum SmootherError {
    /// The epoch file could not be created, written or read.
    #[error("smoother epoch file {path}: {source}")]
    Io {
        /// The temporary file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A predicted covariance of the forward run is not positive definite, so
    /// the smoother gain does not exist.
    #[error("predicted covariance at t = {time} s is not positive definite")]
    NotPositiveDefinite {
        /// Time of the epoch, s.
        time: f64,
    },
    /// Recording the forward run failed (the first failure, kept until
    /// [`super::Recorder::finish`]).
    #[error("recording for the smoother failed: {reason}")]
    Recording {
        /// What failed.
        reason: String,
    },
    /// A smoothed value is not finite.
    #[error("smoothed estimate at t = {time} s is not finite")]
    NonFinite {
        /// Time of the epoch, s.
        time: f64,
    },
}

/// Epochs written in this many records per buffered write or read.
const CHUNK: usize = 64;

/// Epochs of one forward run in a temporary file (deleted when dropped).
///
/// Records have a fixed size, so truncating to `n` epochs and reading epoch
/// `i` are plain offsets; writes are buffered `CHUNK` (64) epochs at a time and
/// [`EpochFile::read_back`] reads the same amount, so memory stays bounded
/// whatever the length of the run.
#[derive(Debug)]
pub struct EpochFile<const N: usize, const S: usize> {
    path: PathBuf,
    file: File,
    /// Epochs in the file, including the `filled / RECORD` ones still in
    /// `buffer`.
    len: usize,
    /// Bytes of `buffer` holding encoded epochs not yet written.
    filled: usize,
    /// Encoded epochs not yet written.
    buffer: Vec<u8>,
    _epoch: PhantomData<Epoch<N, S>>,
}

impl<const N: usize, const S: usize> EpochFile<N, S> {
    const RECORD: usize = 8 * Epoch::<N, S>::SCALARS;

    /// Creates an empty epoch file in `dir` (the system's temporary directory
    /// when `None`).
    ///
    /// # Errors
    /// [`SmootherError::Io`] if the file cannot be created.
    pub fn create(dir: Option<&Path>) -> Result<Self, SmootherError> {
        let (path, file) = create_temporary(dir, "epochs")?;
        Ok(Self {
            path,
            file,
            len: 0,
            // Sized once: epochs are encoded into it in place.
            buffer: vec![0; CHUNK * Self::RECORD],
            filled: 0,
            _epoch: PhantomData,
        })
    }

    /// Path of the temporary file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// Number of epochs stored.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` if no epoch is stored.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    fn io(&self, source: std::io::Error) -> SmootherError {
        SmootherError::Io {
            path: self.path.clone(),
            source,
        }
    }

    fn flush(&mut self) -> Result<(), SmootherError> {
        if self.filled == 0 {
            return Ok(());
        }
        let written = self.len - self.filled / Self::RECORD;
        let offset = (written * Self::RECORD) as u64;
        let result = self
            .file
            .seek(SeekFrom::Start(offset))
            .and_then(|_| self.file.write_all(&self.buffer[..self.filled]));
        self.filled = 0;
        result.map_err(|e| self.io(e))
    }

    /// Appends an epoch.
    ///
    /// # Errors
    /// [`SmootherError::Io`] if a buffered write fails.
    pub fn push(&mut self, epoch: &Epoch<N, S>) -> Result<(), SmootherError> {
        let end = self.filled + Self::RECORD;
        if let Some(out) = self.buffer.get_mut(self.filled..end) {
            epoch.encode(out);
        }
        self.filled = end;
        self.len += 1;
        if self.filled >= CHUNK * Self::RECORD {
            self.flush()?;
        }
        Ok(())
    }

    /// Keeps the first `len` epochs and drops the rest (a re-propagated span
    /// replaces what it supersedes). Longer `len` than stored changes nothing.
    ///
    /// # Errors
    /// [`SmootherError::Io`] if the file cannot be shortened.
    pub fn truncate(&mut self, len: usize) -> Result<(), SmootherError> {
        if len >= self.len {
            return Ok(());
        }
        self.flush()?;
        self.file
            .set_len((len * Self::RECORD) as u64)
            .map_err(|e| self.io(e))?;
        self.len = len;
        Ok(())
    }

    /// Reads the `count` epochs from `start` into `out`, through `bytes`.
    fn read_into(
        &mut self,
        start: usize,
        count: usize,
        bytes: &mut Vec<u8>,
        out: &mut Vec<Epoch<N, S>>,
    ) -> Result<(), SmootherError> {
        self.flush()?;
        bytes.resize(count * Self::RECORD, 0);
        self.file
            .seek(SeekFrom::Start((start * Self::RECORD) as u64))
            .and_then(|_| self.file.read_exact(bytes))
            .map_err(|e| self.io(e))?;
        // Decoded in place into the reused epochs (no temporary copies).
        while out.len() < count {
            out.push(Epoch::at(
                f64::NAN,
                SMatrix::zeros(),
                SMatrix::zeros(),
                SVector::zeros(),
            ));
        }
        for (epoch, b) in out.iter_mut().zip(bytes.chunks_exact(Self::RECORD)) {
            epoch.decode_into(b);
        }
        Ok(())
    }

    /// Calls `visit` with every epoch, latest first, reading `CHUNK` (64) epochs
    /// at a time.
    ///
    /// # Errors
    /// [`SmootherError::Io`] on a failed read, or the first error of `visit`.
    pub fn read_back(
        &mut self,
        mut visit: impl FnMut(&Epoch<N, S>) -> Result<(), SmootherError>,
    ) -> Result<(), SmootherError> {
        let mut chunk = Vec::with_capacity(CHUNK);
        let mut bytes = Vec::with_capacity(CHUNK * Self::RECORD);
        let mut end = self.len;
        while end > 0 {
            let start = end.saturating_sub(CHUNK);
            self.read_into(start, end - start, &mut bytes, &mut chunk)?;
            for epoch in chunk[..end - start].iter().rev() {
                visit(epoch)?;
            }
            end = start;
        }
        Ok(())
    }
}

impl<const N: usize, const S: usize> Drop for EpochFile<N, S> {
    fn drop(&mut self) {
        // A temporary file: failing to remove it loses nothing but disk space.
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn epoch(t: f64) -> Epoch<2, 1> {
        Epoch::at(
            t,
            SMatrix::identity(),
            SMatrix::identity() * t,
            SVector::from_element(-t),
        )
    }

    fn times(file: &mut EpochFile<2, 1>) -> Vec<f64> {
        let mut t = Vec::new();
        file.read_back(|e| {
            t.push(e.time);
            Ok(())
        })
        .unwrap();
        t.reverse();
        t
    }

    #[test]
    fn push_truncate_and_read_back_across_chunks() {
        let mut file = EpochFile::<2, 1>::create(None).unwrap();
        let path = file.path().to_path_buf();
        // Cases: (epochs pushed, truncated to, pushed after): every split of
        // the write buffer and of the read chunks.
        for &(first, keep, second) in &[(0, 0, 3), (5, 2, 1), (150, 70, 90), (64, 64, 64)] {
            file.truncate(0).unwrap();
            (0..first).for_each(|i| file.push(&epoch(i as f64)).unwrap());
            file.truncate(keep).unwrap();
            (0..second).for_each(|i| file.push(&epoch(1000.0 + i as f64)).unwrap());
            let expected: Vec<f64> = (0..keep.min(first))
                .map(|i| i as f64)
                .chain((0..second).map(|i| 1000.0 + i as f64))
                .collect();
            assert_eq!(times(&mut file), expected, "case {first}/{keep}/{second}");
            assert_eq!(file.len(), expected.len());
        }
        drop(file);
        assert!(!path.exists(), "the temporary file is removed");
    }
}
