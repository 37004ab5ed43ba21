//! The error of scenarios, replay models and the driver.

use std::path::PathBuf;

use nav_runtime::log::LogError;

/// Errors of scenarios, replay models and the driver. The `Display` text is one line
/// and names what is wrong (the command line prints it after `error: `).
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum RunError {
    /// A bad value (option, argument, missing sensor, ...).
    #[error("{0}")]
    Invalid(String),
    /// The filter's estimate left its physical bounds or stopped being
    /// finite (the message names the input line that led to it, and the
    /// doubtful inputs when the preflight saw any).
    #[error("{0}")]
    Diverged(String),
    /// One run failed.
    #[error("run with seed {seed} failed: {message}")]
    Failed {
        /// The run's seed.
        seed: u64,
        /// Why.
        message: String,
    },
    /// A file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// A log directory could not be read or written.
    #[error(transparent)]
    Log(#[from] LogError),
    /// A plot could not be drawn.
    #[error("plot {}: {message}", path.display())]
    Plot {
        /// The plot file.
        path: PathBuf,
        /// Why.
        message: String,
    },
    /// A shard file is unreadable or shard files do not fit together.
    #[error("{}: {message}", path.display())]
    Shard {
        /// The shard file (or directory).
        path: PathBuf,
        /// Why.
        message: String,
    },
}

impl RunError {
    /// An I/O error on `path`.
    pub fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        RunError::Io {
            path: path.into(),
            source,
        }
    }
}

/// A navigator that cannot be set up (a vehicle that does not fit, bad
/// settings) is an invalid replay, with the navigator's message.
impl From<nav_ins::NavigatorError> for RunError {
    fn from(e: nav_ins::NavigatorError) -> Self {
        match e {
            nav_ins::NavigatorError::Setup(message) => RunError::Invalid(message),
            other => RunError::Invalid(other.to_string()),
        }
    }
}
