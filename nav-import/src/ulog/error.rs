//! What can go wrong importing a ULog file: every message names the file and,
//! where there is one, the byte offset, the topic and the field.

use std::path::PathBuf;

/// An import failure. Nothing is written when an import fails.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The file (or the output directory) could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// The output directory is something the import must not replace (a
    /// file, a symbolic link, a non-empty directory that is not an earlier
    /// import).
    #[error("{}: {reason}", path.display())]
    Refused {
        /// The output directory as given.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The bytes are not a well-formed ULog file.
    #[error("{file}: byte {offset}: {reason}")]
    Malformed {
        /// The file name as given.
        file: String,
        /// Byte offset of the message (or header) at fault.
        offset: usize,
        /// What is wrong, naming the message type and field.
        reason: String,
    },
    /// A topic is present with a layout this importer does not know.
    #[error("{file}: topic `{topic}`: field `{field}`: {reason}")]
    Layout {
        /// The file name as given.
        file: String,
        /// The topic.
        topic: String,
        /// The field that is missing or of the wrong kind.
        field: String,
        /// What was expected.
        reason: String,
    },
    /// A row of a CSV file written by the import (read back for scoring) is bad.
    #[error("{file}: line {line}: {reason}")]
    Csv {
        /// The file.
        file: String,
        /// 1-based line.
        line: usize,
        /// What is wrong, naming the column.
        reason: String,
    },
    /// The file is well formed but lacks what a log directory needs.
    #[error("{file}: {reason}")]
    Unusable {
        /// The file name as given.
        file: String,
        /// What is missing.
        reason: String,
    },
}
