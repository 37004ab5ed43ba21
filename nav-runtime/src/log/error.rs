//! Errors of the log reader and writer.

use std::fmt;
use std::path::PathBuf;

/// Why one CSV cell, row or header was rejected.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub enum CsvProblem {
    /// The header row does not match the expected column names.
    WrongHeader {
        /// The full expected header, comma-separated.
        expected: String,
        /// The text found in the offending header cell (empty if missing).
        found: String,
    },
    /// The row has the wrong number of cells.
    ColumnCount {
        /// Expected number of cells.
        expected: usize,
        /// Number of cells found.
        found: usize,
    },
    /// The cell is empty in a column that requires a value.
    EmptyCell,
    /// The cell text is not a number.
    NotANumber {
        /// The offending text (lossily decoded as UTF-8, truncated).
        text: String,
    },
    /// The cell parsed to NaN or an infinity.
    NonFinite {
        /// The offending text.
        text: String,
    },
    /// The value is outside of its physical range.
    OutOfRange {
        /// The value found.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// `t` is smaller than the previous row's `t`.
    TimeBackwards {
        /// The previous accepted row's time.
        previous: f64,
        /// This row's time.
        t: f64,
    },
    /// The header names a column twice (which of the two is meant?).
    DuplicateColumn {
        /// The name given twice.
        name: String,
    },
    /// `t` equals the previous row's `t`.
    DuplicateTime {
        /// The repeated time.
        t: f64,
    },
    /// A column named by a `[files.<sensor>] columns` key is not in the header.
    MissingColumn {
        /// The dotted `meta.toml` key that names it.
        key: String,
        /// The header expected (in any order).
        expected: String,
    },
    /// Header columns a `[files.<sensor>]` section neither reads nor ignores.
    UnknownColumns {
        /// Their header names.
        names: Vec<String>,
        /// The `meta.toml` key that would ignore them.
        key: String,
        /// How many more there are beyond `names` (which lists the first
        /// few, so that a header of a million columns gives a short message).
        more: usize,
    },
    /// An increment file with a single row: its interval is not known.
    NoInterval,
    /// A header with more columns than a log file may have.
    TooManyColumns {
        /// The columns found (counted up to the first line end).
        found: usize,
        /// The largest number accepted ([`MAX_COLUMNS`](super::MAX_COLUMNS)).
        limit: usize,
    },
    /// Too many rows of an aiding file rejected as non-physical readings
    /// for them to be glitches (see [`REJECTED_FLOOR`](super::REJECTED_FLOOR)).
    TooManyRejected {
        /// Rows rejected.
        count: usize,
        /// Rows read.
        rows: usize,
        /// Why the first of them was rejected.
        first: Box<CsvProblem>,
    },
}

impl fmt::Display for CsvProblem {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CsvProblem::WrongHeader { expected, found } => {
                write!(
                    f,
                    "wrong header: found `{found}`, expected header `{expected}`"
                )
            }
            CsvProblem::ColumnCount { expected, found } => {
                let columns = if *expected == 1 { "column" } else { "columns" };
                write!(f, "expected {expected} {columns}, found {found}")
            }
            CsvProblem::EmptyCell => write!(f, "empty cell"),
            CsvProblem::NotANumber { text } => write!(f, "`{text}` is not a number"),
            CsvProblem::NonFinite { text } => write!(f, "non-finite value `{text}`"),
            CsvProblem::OutOfRange { value, allowed } => {
                write!(f, "value {} out of range ({allowed})", Magnitude(*value))
            }
            CsvProblem::TimeBackwards { previous, t } => {
                write!(f, "time goes backwards (t = {t} after t = {previous})")
            }
            CsvProblem::DuplicateTime { t } => write!(f, "duplicate timestamp t = {t}"),
            CsvProblem::DuplicateColumn { name } => {
                write!(f, "the header names column `{name}` twice")
            }
            CsvProblem::MissingColumn { key, expected } => write!(
                f,
                "missing column (named by `{key}` in meta.toml), expected header `{expected}` in any order"
            ),
            CsvProblem::UnknownColumns { names, key, more } => {
                let names: Vec<String> = names.iter().map(|n| format!("`{n}`")).collect();
                let more = if *more > 0 {
                    format!(" and {more} more")
                } else {
                    String::new()
                };
                write!(
                    f,
                    "unknown columns {}{more}: not read by this file's mapping (list them in `{key}` to skip them)",
                    names.join(", ")
                )
            }
            CsvProblem::TooManyColumns { found, limit } => write!(
                f,
                "the header has {found} columns, more than the {limit} a log file may have"
            ),
            // Every row: the rule that fired is that nothing is left.
            CsvProblem::TooManyRejected { count, rows, first } if count == rows => write!(
                f,
                "all {rows} rows rejected as non-physical readings (first: {first}): a unit, column or sign mistake rather than sensor glitches?"
            ),
            CsvProblem::TooManyRejected { count, rows, first } => write!(
                f,
                "{count} of {rows} rows rejected as non-physical readings (first: {first}): more than {} and one in {}, a unit, column or sign mistake rather than sensor glitches?",
                super::REJECTED_FLOOR,
                super::REJECTED_ONE_IN
            ),
            CsvProblem::NoInterval => write!(
                f,
                "a single increment row has no interval (the first row's interval is taken from the second row)"
            ),
        }
    }
}

/// A CSV row the lenient reader skipped, and why.
#[derive(Debug, Clone, PartialEq)]
pub struct SkippedRow {
    /// The file name.
    pub file: String,
    /// 1-based line number.
    pub line: u64,
    /// The column name.
    pub column: String,
    /// What was wrong.
    pub problem: CsvProblem,
}

impl fmt::Display for SkippedRow {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}:{}: column `{}`: {}",
            self.file, self.line, self.column, self.problem
        )
    }
}

/// An error reading or writing a log directory.
///
/// Every variant names the file; CSV errors also carry the 1-based line (the header is
/// line 1) and the column name, `meta.toml` errors the dotted key (`initial.lat`).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum LogError {
    /// The operating system refused to read or write a path.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path that failed.
        path: PathBuf,
        /// The underlying error.
        #[source]
        source: std::io::Error,
    },
    /// A file the log cannot do without (`imu.csv`, `meta.toml`, a file a
    /// mapping declares) is absent.
    #[error("{file}: required file is missing from {}{}", dir.display(), key.as_ref().map(|k| format!(" (named by `{k}`)")).unwrap_or_default())]
    MissingFile {
        /// The missing file's name.
        file: String,
        /// The log directory.
        dir: PathBuf,
        /// The key that names it, for a declared file (`files.imu.file`
        /// of `meta.toml`).
        key: Option<String>,
    },
    /// A `.csv` file that is not one of the log files (strict reading only).
    #[error("{file}: unknown log file in {} (log files: {}; the file of a sensor fed by its declared name is named in replay.toml, [sensors.<name>] file)", dir.display(), super::LOG_FILES.join(", "))]
    UnknownFile {
        /// The file's name.
        file: String,
        /// The log directory.
        dir: PathBuf,
    },
    /// The CSV file has no header row.
    #[error("{file}: empty file (expected header `{expected}`)")]
    EmptyFile {
        /// The file name.
        file: String,
        /// The expected header.
        expected: String,
    },
    /// A header, row or cell of a CSV file was rejected.
    #[error("{file}:{line}: column `{column}`: {problem}")]
    Csv {
        /// The file name (e.g. `dvl.csv`).
        file: String,
        /// 1-based line number; the header is line 1.
        line: u64,
        /// The column name (`<column N>` for a cell beyond the expected columns).
        column: String,
        /// What is wrong.
        problem: CsvProblem,
    },
    /// `meta.toml` is malformed, misses a key, has an unknown key or an out-of-range value.
    #[error("meta.toml{}: {}{problem}", line.map(|l| format!(":{l}")).unwrap_or_default(), if key.is_empty() { String::new() } else { format!("`{key}`: ") })]
    Meta {
        /// The dotted key (e.g. `sensors.dvl.noise_sigma`); empty for syntax errors.
        key: String,
        /// 1-based line, when known.
        line: Option<u64>,
        /// What is wrong.
        problem: String,
    },
    /// The writer refused to replace an existing path.
    #[error("{}: {reason}", path.display())]
    Write {
        /// The target path.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// A file read through the log directory whose real path (symbolic
    /// links and `..` resolved) is outside it: refused before any of it is
    /// read, so nothing of its content is quoted.
    #[error("{file}: `{key}` resolves outside the log directory {} (a symbolic link or `..`); refused", dir.display())]
    Outside {
        /// The file as named in the log (relative to the log directory).
        file: String,
        /// What named it: the `meta.toml` key (`files.imu.file`) or the
        /// standard file's own name (`imu.csv`).
        key: String,
        /// The log directory.
        dir: PathBuf,
    },
    /// Reading was stopped through [`LogFiles::stop`](super::LogFiles::stop)
    /// (another reader of the same log, such as the preflight, refused it).
    #[error("{}: reading stopped", dir.display())]
    Stopped {
        /// The log directory.
        dir: PathBuf,
    },
}

impl LogError {
    /// The file the error is about (`meta.toml` for meta errors).
    pub fn file(&self) -> Option<&str> {
        match self {
            LogError::Io { .. } | LogError::Write { .. } | LogError::Stopped { .. } => None,
            LogError::MissingFile { file, .. }
            | LogError::UnknownFile { file, .. }
            | LogError::EmptyFile { file, .. }
            | LogError::Csv { file, .. }
            | LogError::Outside { file, .. } => Some(file),
            LogError::Meta { .. } => Some("meta.toml"),
        }
    }

    /// The 1-based line, when known.
    pub fn line(&self) -> Option<u64> {
        match self {
            LogError::Csv { line, .. } => Some(*line),
            LogError::Meta { line, .. } => *line,
            _ => None,
        }
    }

    /// The column name of a CSV error, or the dotted key of a meta error
    /// (or of the mapping key that names a missing file).
    pub fn column(&self) -> Option<&str> {
        match self {
            LogError::Csv { column, .. } => Some(column),
            LogError::Meta { key, .. } | LogError::Outside { key, .. } => {
                (!key.is_empty()).then_some(key.as_str())
            }
            LogError::MissingFile { key, .. } => key.as_deref(),
            _ => None,
        }
    }

    /// The CSV problem, for CSV errors.
    pub fn csv_problem(&self) -> Option<&CsvProblem> {
        match self {
            LogError::Csv { problem, .. } => Some(problem),
            _ => None,
        }
    }

    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        LogError::Io {
            path: path.into(),
            source,
        }
    }

    pub(crate) fn meta(key: impl Into<String>, problem: impl Into<String>) -> Self {
        LogError::Meta {
            key: key.into(),
            line: None,
            problem: problem.into(),
        }
    }
}

/// A number in a message: an absurd magnitude in scientific notation
/// (`1e200`), not as 201 digits; others as they are.
pub(crate) struct Magnitude(pub f64);

impl std::fmt::Display for Magnitude {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let a = self.0.abs();
        if a >= 1e15 || (a > 0.0 && a < 1e-6) {
            write!(f, "{:e}", self.0)
        } else {
            write!(f, "{}", self.0)
        }
    }
}
