//! Why a model replay could not start or stopped.

use nav_runtime::log::LogError;

/// A set-up or reading error of a model replay. Each names the file and the
/// key (of the mapping) or the line and column (of a CSV file).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ModelReplayError {
    /// The mapping file is malformed, misses a key, names something the
    /// declaration does not have, or gives a value out of its range.
    #[error("{file}{}: {}{problem}", line.map(|l| format!(":{l}")).unwrap_or_default(), if key.is_empty() { String::new() } else { format!("`{key}`: ") })]
    Mapping {
        /// The mapping file's name (`replay.toml`).
        file: String,
        /// The dotted key (`sensors.Fix.z`); empty for a syntax error.
        key: String,
        /// 1-based line, when known.
        line: Option<u64>,
        /// What is wrong.
        problem: String,
    },
    /// A log file could not be read, or a header, row or cell was rejected.
    #[error(transparent)]
    Log(#[from] LogError),
    /// The filter refused a row (a non-finite model output, a propagation
    /// the model cannot take).
    #[error("{file}:{line}: t = {t} s: {problem}")]
    Filter {
        /// The file of the row.
        file: String,
        /// Its 1-based line.
        line: u64,
        /// Its time, s.
        t: f64,
        /// What the filter said.
        problem: String,
    },
    /// The filter could not be built from the mapping's values.
    #[error("{0}")]
    Setup(String),
}
