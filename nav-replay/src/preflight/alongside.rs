//! The preflight run beside the work it guards: a replay reads the log on
//! one thread while the preflight reads it on another, so a log on disk is
//! not read twice in a row, and the preflight's verdict still comes first.

use nav_runtime::log::{LogFiles, Warning};

use super::{check_files_with, LogSummary, PreflightOptions, Report};
use crate::RunError;

/// Runs `work` (typically a replay of `files`) while
/// [`check_files`](super::check_files) reads the same log on a second
/// thread, and answers as if the preflight had run first: a log it refuses is refused with its read error, or with its first
/// error and the count of the others, whatever `work` returned. Refusing
/// also stops the log's streams ([`LogFiles::stop`]), so `work` ends early
/// instead of finishing a run that is discarded. With an accepted log: the
/// result of `work`, the preflight's report (its warnings) and the log's
/// summary.
///
/// With `share_imu`, `work` reads `imu.csv` through
/// [`LogSource::imu_rows`](nav_runtime::log::LogSource::imu_rows) and the
/// preflight takes the rows it reads ([`LogFiles::share_imu`]) instead of
/// parsing the file a second time; if `work` does not open it, or stops
/// early, the preflight reads the rest itself.
///
/// # Errors
/// The preflight's refusal; otherwise the error of `work`.
pub fn check_alongside<T>(
    files: &LogFiles,
    options: &PreflightOptions,
    share_imu: bool,
    work: impl FnOnce() -> Result<T, RunError>,
) -> Result<(T, Report, LogSummary), RunError> {
    let shared = share_imu.then(|| files.share_imu());
    std::thread::scope(|scope| {
        let checking = scope.spawn(|| {
            let checked = check_files_with(files, options, shared);
            if !matches!(&checked, Ok((report, _)) if report.errors().next().is_none()) {
                files.stop();
            }
            checked
        });
        let worked = work();
        // A share `work` did not take: the preflight reads the file itself.
        files.stop_sharing();
        let (report, summary) = checking
            .join()
            .map_err(|_| RunError::Invalid("the preflight stopped unexpectedly".into()))??;
        if let Some(refusal) = refusal(&report) {
            return Err(refusal);
        }
        let worked = worked.map_err(|e| explained(e, &report));
        Ok((worked?, report, summary))
    })
}

/// A replay's error as the replay gives it beside the preflight's `report`:
/// a divergence with what the preflight doubted in the inputs (`check
/// --model` words it as `replay` does), any other error as it is.
pub fn explained(e: RunError, report: &Report) -> RunError {
    match e {
        RunError::Diverged {
            message,
            file,
            line,
        } => RunError::Diverged {
            message: with_evidence(message, report),
            file,
            line,
        },
        e => e,
    }
}

/// Findings listed after a divergence before the rest are only counted.
const EVIDENCE_LISTED: usize = 2;

/// A divergence's message with what the preflight doubted in the inputs
/// (units, frames, clock, lost rows): the likely cause, with its file and
/// line, rather than the estimate that left its bounds.
fn with_evidence(message: String, report: &Report) -> String {
    let doubts = input_doubts(report);
    if doubts.is_empty() {
        return format!(
            "{message} (the preflight found no unit, frame or clock doubt in the inputs: \
             check the model's noise settings)"
        );
    }
    let more = doubts.len().saturating_sub(EVIDENCE_LISTED);
    let listed = doubts[..doubts.len().min(EVIDENCE_LISTED)].join("; ");
    let tail = if more > 0 {
        format!(" ({more} more: see `navsim check`)")
    } else {
        String::new()
    };
    format!("{message}; likely cause, from the inputs: {listed}{tail}")
}

/// The error refusing a log whose report has errors: the first, and how
/// many more there are.
pub fn refusal(report: &Report) -> Option<RunError> {
    let first = report.errors().next()?;
    let more = report.errors().count() - 1;
    let tail = if more > 0 {
        format!(" ({more} more problems: see `navsim check`)")
    } else {
        String::new()
    };
    Some(RunError::Invalid(format!("{first}{tail}")))
}

/// The preflight's warnings about the inputs' units, frames, clock and
/// lost or frozen rows (not about the truth), as text.
fn input_doubts(report: &Report) -> Vec<String> {
    use nav_runtime::log::WarningKind::{FrozenImu, ImuGap, Suspicious};
    report
        .warnings()
        .filter(|w| matches!(w.kind, Suspicious | ImuGap | FrozenImu))
        .filter(|w| w.file.as_deref() != Some("truth.csv"))
        .map(ToString::to_string)
        .collect()
}

/// The NEES warning of a run (key `nees`) weighed against the preflight's
/// doubts about the inputs: with any, they, not `truth.csv`, are named as
/// the likelier cause of errors beyond the filter's sigmas.
pub fn weigh_nees(warnings: &mut [Warning], report: &Report) {
    let doubts = input_doubts(report);
    let Some(first) = doubts.first() else { return };
    for w in warnings
        .iter_mut()
        .filter(|w| w.key.as_deref() == Some(crate::ins::output::NEES_KEY))
    {
        let base = w
            .message
            .split("; the aiding innovations")
            .next()
            .unwrap_or("");
        w.message = format!(
            "{base}; the preflight doubted the inputs, a likelier cause than truth.csv: {first}"
        );
        w.file = None;
    }
}
