//! Warnings: problems of a log that do not stop a replay but must not pass
//! silently. Each names what it is about (file, line, key) and is listed in
//! the replay and check JSON under `warnings`.

use std::fmt;

/// What a [`Warning`] is about.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[non_exhaustive]
pub enum WarningKind {
    /// A top-level section of `meta.toml` that is not read (another tool's metadata).
    UnknownSection,
    /// A `.csv` file that is not a log file (lenient reading).
    UnknownFile,
    /// A log file the model does not use.
    UnusedFile,
    /// A sensor file without its `[sensors.*]` section: built-in noise used.
    MissingSensorSection,
    /// A CSV row the lenient reader skipped.
    SkippedRow,
    /// A value that looks like a unit, sign or frame mistake, not certain enough
    /// for an error.
    Suspicious,
    /// A gap in the IMU time stamps (an error without `--lenient`).
    ImuGap,
    /// A frozen IMU (an error without `--lenient`).
    FrozenImu,
    /// Aiding or truth samples outside the IMU's time span.
    OutsideImuSpan,
    /// Scoring covers only part of the truth.
    PartialScoring,
    /// A note of the replay model.
    Model,
    /// Rows of an aiding file skipped as non-physical readings (sensor
    /// glitches: `1e300`, `inf`); the warning gives their count and the
    /// first one's line.
    RejectedReading,
    /// A sensor whose innovations say its noise sigma is off by more than a
    /// factor of two; the warning gives the sigma they support.
    NoiseSigma,
    /// The filter recovered from a lock-out into divergence: a sensor's
    /// readings were refused for longer than its horizon while plausible and
    /// agreeing with one another (`nav_runtime::recovery`).
    LockoutRecovery,
    /// A random-constant state (a sensor or IMU bias, a mounting
    /// calibration) whose final estimate is beyond the spread its prior
    /// allows a consistent filter: the state took up an error the model
    /// does not carry, or its prior is too tight.
    StateBeyondPrior,
}

impl WarningKind {
    /// The snake_case name used in the JSON (`unknown_section`, ...).
    pub fn as_str(self) -> &'static str {
        match self {
            WarningKind::UnknownSection => "unknown_section",
            WarningKind::UnknownFile => "unknown_file",
            WarningKind::UnusedFile => "unused_file",
            WarningKind::MissingSensorSection => "missing_sensor_section",
            WarningKind::SkippedRow => "skipped_row",
            WarningKind::Suspicious => "suspicious",
            WarningKind::ImuGap => "imu_gap",
            WarningKind::FrozenImu => "frozen_imu",
            WarningKind::OutsideImuSpan => "outside_imu_span",
            WarningKind::PartialScoring => "partial_scoring",
            WarningKind::Model => "model",
            WarningKind::RejectedReading => "rejected_reading",
            WarningKind::NoiseSigma => "noise_sigma",
            WarningKind::LockoutRecovery => "lockout_recovery",
            WarningKind::StateBeyondPrior => "state_beyond_prior",
        }
    }
}

/// One warning: its kind, where (file, 1-based line, column or dotted key,
/// each when known) and a message for the user.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Warning {
    /// What it is about.
    pub kind: WarningKind,
    /// The file (e.g. `dvl.csv`, `meta.toml`).
    pub file: Option<String>,
    /// 1-based line; the CSV header is line 1.
    pub line: Option<u64>,
    /// The column or dotted `meta.toml` key.
    pub key: Option<String>,
    /// What was found and what it means.
    pub message: String,
}

impl Warning {
    /// A warning about `file` (no line, no key).
    pub fn about(kind: WarningKind, file: &str, message: impl Into<String>) -> Self {
        Warning {
            kind,
            file: Some(file.to_string()),
            line: None,
            key: None,
            message: message.into(),
        }
    }

    /// The same warning at `line`.
    pub fn at_line(mut self, line: u64) -> Self {
        self.line = Some(line);
        self
    }

    /// The same warning about column or key `key`.
    pub fn with_key(mut self, key: &str) -> Self {
        self.key = Some(key.to_string());
        self
    }
}

impl fmt::Display for Warning {
    /// `file:line: column `key`: message` with the parts that are known.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        if let Some(file) = &self.file {
            write!(f, "{file}")?;
            if let Some(line) = self.line {
                write!(f, ":{line}")?;
            }
            write!(f, ": ")?;
        }
        if let Some(key) = &self.key {
            write!(f, "`{key}`: ")?;
        }
        write!(f, "{}", self.message)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn display_names_the_known_parts() {
        let w = Warning::about(WarningKind::ImuGap, "imu.csv", "gap of 30 s")
            .at_line(12)
            .with_key("t");
        assert_eq!(w.to_string(), "imu.csv:12: `t`: gap of 30 s");
        let bare = Warning {
            kind: WarningKind::Model,
            file: None,
            line: None,
            key: None,
            message: "note".into(),
        };
        assert_eq!(bare.to_string(), "note");
        assert_eq!(WarningKind::UnknownSection.as_str(), "unknown_section");
    }
}
