//! A temporary file of fixed-width records of `f64`, read back latest first:
//! what a caller of the smoother keeps per output time (the forward
//! estimates the smoothed errors are applied to, the smoothed estimates
//! while the backward pass produces them latest first), so that memory does
//! not grow with the length of the run.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use super::store::{create_temporary, SmootherError};

/// Records written and read this many at a time.
const CHUNK: usize = 256;

/// Records of `width` scalars in a temporary file (deleted when dropped).
///
/// [`SpillFile::push`] appends (buffered, `CHUNK` records per write);
/// [`SpillFile::pop`] takes the latest record off the end, reading `CHUNK`
/// records at a time, so a file written in one order is read in the
/// reverse one with memory for two chunks.
#[derive(Debug)]
pub struct SpillFile {
    path: PathBuf,
    file: File,
    width: usize,
    /// Records in the file, including the ones still in `buffer`.
    len: usize,
    /// Records not yet written (push), or read and not yet popped (pop).
    buffer: Vec<u8>,
    /// `true` while `buffer` holds read records (the records `len -
    /// buffer_records .. len`).
    reading: bool,
}

impl SpillFile {
    /// Creates an empty file of records of `width` scalars in `dir` (the
    /// system's temporary directory when `None`).
    ///
    /// # Errors
    /// [`SmootherError::Io`] if the file cannot be created.
    pub fn create(dir: Option<&Path>, width: usize) -> Result<Self, SmootherError> {
        let (path, file) = create_temporary(dir, "spill")?;
        Ok(Self {
            path,
            file,
            width,
            len: 0,
            buffer: Vec::with_capacity(CHUNK * 8 * width),
            reading: false,
        })
    }

    /// Number of records stored.
    pub fn len(&self) -> usize {
        self.len
    }

    /// `true` if no record is stored.
    pub fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// Path of the temporary file.
    pub fn path(&self) -> &Path {
        &self.path
    }

    fn record(&self) -> usize {
        8 * self.width
    }

    fn io(&self, source: std::io::Error) -> SmootherError {
        SmootherError::Io {
            path: self.path.clone(),
            source,
        }
    }

    /// Writes the pushed records, or forgets the read ones (they stay in the
    /// file below `len`).
    fn settle(&mut self) -> Result<(), SmootherError> {
        if self.reading || self.buffer.is_empty() {
            self.reading = false;
            self.buffer.clear();
            return Ok(());
        }
        let written = self.len - self.buffer.len() / self.record();
        let offset = (written * self.record()) as u64;
        let result = self
            .file
            .seek(SeekFrom::Start(offset))
            .and_then(|_| self.file.write_all(&self.buffer));
        self.buffer.clear();
        result.map_err(|e| self.io(e))
    }

    /// Appends a record; `values` has `width` scalars (shorter is padded
    /// with NaN, longer is cut).
    ///
    /// # Errors
    /// [`SmootherError::Io`] if a buffered write fails.
    pub fn push(&mut self, values: &[f64]) -> Result<(), SmootherError> {
        if self.reading {
            self.settle()?;
        }
        // The record's bytes in place (one resize, not one extend a scalar).
        let start = self.buffer.len();
        self.buffer.resize(start + self.record(), 0);
        let (words, _) = self.buffer[start..].as_chunks_mut::<8>();
        for (i, w) in words.iter_mut().enumerate() {
            *w = values.get(i).copied().unwrap_or(f64::NAN).to_le_bytes();
        }
        self.len += 1;
        if self.buffer.len() >= CHUNK * self.record() {
            self.settle()?;
        }
        Ok(())
    }

    /// Removes the latest record and writes it into `out` (`width` scalars;
    /// a longer `out` keeps its tail). `false` when the file is empty.
    ///
    /// # Errors
    /// [`SmootherError::Io`] on a failed read or a failed write of pushed
    /// records.
    pub fn pop(&mut self, out: &mut [f64]) -> Result<bool, SmootherError> {
        if self.len == 0 {
            return Ok(false);
        }
        if !self.reading || self.buffer.is_empty() {
            self.settle()?;
            let count = self.len.min(CHUNK);
            let start = self.len - count;
            self.buffer.resize(count * self.record(), 0);
            let (file, buffer) = (&mut self.file, &mut self.buffer);
            let result = file
                .seek(SeekFrom::Start((start * self.width * 8) as u64))
                .and_then(|_| file.read_exact(buffer));
            if let Err(e) = result {
                self.buffer.clear();
                return Err(self.io(e));
            }
            self.reading = true;
        }
        let at = self.buffer.len() - self.record();
        for (o, b) in out.iter_mut().zip(self.buffer[at..].chunks_exact(8)) {
            *o = f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]);
        }
        self.buffer.truncate(at);
        self.len -= 1;
        if self.buffer.is_empty() {
            self.reading = false;
            self.file
                .set_len((self.len * self.record()) as u64)
                .map_err(|e| self.io(e))?;
        }
        Ok(true)
    }
}

impl Drop for SpillFile {
    fn drop(&mut self) {
        // A temporary file: failing to remove it loses nothing but disk space.
        let _ = std::fs::remove_file(&self.path);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn record(i: usize) -> [f64; 3] {
        [i as f64, -(i as f64) * 0.5, f64::from_bits(i as u64 + 7)]
    }

    /// Records come back latest first, bit for bit, across chunk boundaries
    /// and with pushes between pops.
    #[test]
    fn pops_return_the_pushed_records_latest_first() {
        let mut file = SpillFile::create(None, 3).unwrap();
        let path = file.path().to_path_buf();
        let mut model: Vec<[f64; 3]> = Vec::new();
        let mut next = 0usize;
        let mut out = [0.0; 3];
        // (pushes, pops) rounds: inside one chunk, across several, emptying.
        for &(pushes, pops) in &[(5, 2), (600, 300), (1, 257), (256, 600), (0, 1)] {
            for _ in 0..pushes {
                file.push(&record(next)).unwrap();
                model.push(record(next));
                next += 1;
            }
            for _ in 0..pops {
                let got = file.pop(&mut out).unwrap();
                match model.pop() {
                    Some(want) => {
                        assert!(got);
                        assert_eq!(out.map(f64::to_bits), want.map(f64::to_bits));
                    }
                    None => assert!(!got),
                }
            }
            assert_eq!(file.len(), model.len());
        }
        assert!(file.is_empty());
        drop(file);
        assert!(!path.exists(), "the temporary file is removed");
    }
}
