//! A file of a log directory opened for reading: confined to the directory
//! and, for a name ending in `.gz`, decompressed as it is read
//! (docs/log-format.md, "Files read through the log directory").
//!
//! Confinement: the real path of every file read through a log directory
//! (symbolic links and `..` resolved) must be inside the directory. A file
//! outside is refused before a byte of it is read, so no error can quote
//! its content (a header or a cell of `/etc/passwd`). Only regular files
//! are read: a FIFO or a device would block or never end.

use std::fs;
use std::io::{self, BufReader, Read};
use std::path::Path;

use super::{dangling_link, LogError};

/// A log file being read: plain, or gzip-compressed (several gzip members
/// in a row are read as one stream, as `gzip -d` does).
pub enum LogFile {
    /// A plain file.
    Plain(fs::File),
    /// A `.gz` file, decompressed as it is read.
    Gzip(Box<flate2::read::MultiGzDecoder<BufReader<fs::File>>>),
}

impl std::fmt::Debug for LogFile {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            LogFile::Plain(_) => "LogFile::Plain",
            LogFile::Gzip(_) => "LogFile::Gzip",
        })
    }
}

impl Read for LogFile {
    fn read(&mut self, buf: &mut [u8]) -> io::Result<usize> {
        match self {
            LogFile::Plain(f) => f.read(buf),
            LogFile::Gzip(g) => g.read(buf),
        }
    }
}

/// Whether `file` is read through gzip (its name ends in `.gz`).
pub fn is_gzip(file: &str) -> bool {
    file.len() > 3
        && file
            .get(file.len() - 3..)
            .is_some_and(|e| e.eq_ignore_ascii_case(".gz"))
}

/// Opens `file` (relative to `dir`) for reading, confined to `dir`; `key`
/// is what the user wrote to name it (`files.imu.file`, or the standard
/// file's own name). `Ok(None)` when nothing is there.
///
/// # Errors
/// A dangling symbolic link; a real path outside `dir`
/// ([`LogError::Outside`]); not a regular file; an unreadable file.
pub fn open_confined(dir: &Path, file: &str, key: &str) -> Result<Option<LogFile>, LogError> {
    let path = dir.join(file);
    let real = match fs::canonicalize(&path) {
        Ok(p) => p,
        Err(e) if e.kind() == io::ErrorKind::NotFound => {
            dangling_link(&path)?;
            return Ok(None);
        }
        Err(e) => return Err(LogError::io(&path, e)),
    };
    let real_dir = fs::canonicalize(dir).map_err(|e| LogError::io(dir, e))?;
    if !real.starts_with(&real_dir) {
        return Err(LogError::Outside {
            file: file.to_string(),
            key: key.to_string(),
            dir: dir.to_path_buf(),
        });
    }
    let meta = fs::metadata(&real).map_err(|e| LogError::io(&path, e))?;
    if !meta.is_file() {
        return Err(LogError::io(
            &path,
            io::Error::other("not a regular file (a log file is a plain or .gz file)"),
        ));
    }
    let f = fs::File::open(&real).map_err(|e| LogError::io(&path, e))?;
    Ok(Some(if is_gzip(file) {
        LogFile::Gzip(Box::new(flate2::read::MultiGzDecoder::new(BufReader::new(
            f,
        ))))
    } else {
        LogFile::Plain(f)
    }))
}
