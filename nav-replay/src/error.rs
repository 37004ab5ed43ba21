//! The error of scenarios, replay models and the driver.

use std::path::PathBuf;

use nav_runtime::log::{LogError, Warning, WarningKind};

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
    #[error("{message}")]
    Diverged {
        /// What happened, where, and what the preflight doubted.
        message: String,
        /// The log file of the input at which it happened, when known.
        file: Option<String>,
        /// That input's 1-based line in its file, when it is known (a
        /// reader that skipped rows knows only the data row).
        line: Option<u64>,
    },
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
    /// A divergence whose place is not known.
    pub fn diverged(message: impl Into<String>) -> Self {
        RunError::Diverged {
            message: message.into(),
            file: None,
            line: None,
        }
    }

    /// The error as a finding of kind `kind` (`navsim check --model` lists
    /// a replay's error among its errors): with the file, line and column
    /// or key it names, so that the JSON says where without parsing the
    /// message.
    pub fn finding(&self, kind: WarningKind) -> Warning {
        let (file, line, key) = match self {
            RunError::Diverged { file, line, .. } => (file.clone(), *line, None),
            RunError::Log(e) => (
                e.file().map(str::to_string),
                e.line(),
                e.column().map(str::to_string),
            ),
            _ => (None, None, None),
        };
        // The place is in the fields: the message of a reading error is
        // its problem (a warning's text puts the place before it).
        let message = match self {
            RunError::Log(LogError::Meta { problem, .. }) => problem.clone(),
            RunError::Log(LogError::Csv { problem, .. }) => problem.to_string(),
            e => e.to_string(),
        };
        Warning {
            kind,
            file,
            line,
            key,
            message: crate::program::one_line(&message),
        }
    }

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
