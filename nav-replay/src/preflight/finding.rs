//! The result of the preflight: findings with a severity and a location.

use nav_runtime::log::{Warning, WarningKind};

/// How serious a finding is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Severity {
    /// A clear mistake: the replay does not run.
    Error,
    /// Doubtful: the replay runs and lists it in `warnings`.
    Warning,
}

/// One finding: its severity and the located message (a [`Warning`] value
/// carries kind, file, line and key for errors as well).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Finding {
    /// Error or warning.
    pub severity: Severity,
    /// What, where, and the likely cause.
    pub what: Warning,
}

/// Every finding of one preflight run, in check order.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct Report {
    /// The findings.
    pub findings: Vec<Finding>,
}

impl Report {
    /// Adds an error.
    pub fn error(&mut self, what: Warning) {
        self.findings.push(Finding {
            severity: Severity::Error,
            what,
        });
    }

    /// Adds a warning.
    pub fn warn(&mut self, what: Warning) {
        self.findings.push(Finding {
            severity: Severity::Warning,
            what,
        });
    }

    /// Adds an error, or a warning when `lenient`.
    pub fn error_unless(&mut self, lenient: bool, what: Warning) {
        if lenient {
            self.warn(what);
        } else {
            self.error(what);
        }
    }

    /// The errors.
    pub fn errors(&self) -> impl Iterator<Item = &Warning> {
        self.of(Severity::Error)
    }

    /// The warnings.
    pub fn warnings(&self) -> impl Iterator<Item = &Warning> {
        self.of(Severity::Warning)
    }

    fn of(&self, s: Severity) -> impl Iterator<Item = &Warning> {
        self.findings
            .iter()
            .filter(move |f| f.severity == s)
            .map(|f| &f.what)
    }

    /// `true` when some finding is an error.
    pub fn has_errors(&self) -> bool {
        self.errors().next().is_some()
    }

    /// Whether some finding has `kind`.
    pub fn has(&self, kind: WarningKind) -> bool {
        self.findings.iter().any(|f| f.what.kind == kind)
    }
}
