//! The preflight run beside the work it guards: a replay reads the log on
//! one thread while the preflight reads it on another, so a log on disk is
//! not read twice in a row, and the preflight's verdict still comes first.

use nav_runtime::log::LogFiles;

use super::{check_files, LogSummary, PreflightOptions, Report};
use crate::harness::RunError;

/// Runs `work` (typically a replay of `files`) while [`check_files`] reads
/// the same log on a second thread, and answers as if the preflight had run
/// first: a log it refuses is refused with its read error, or with its first
/// error and the count of the others, whatever `work` returned. Refusing
/// also stops the log's streams ([`LogFiles::stop`]), so `work` ends early
/// instead of finishing a run that is discarded. With an accepted log: the
/// result of `work`, the preflight's report (its warnings) and the log's
/// summary.
///
/// # Errors
/// The preflight's refusal; otherwise the error of `work`.
pub fn check_alongside<T>(
    files: &LogFiles,
    options: &PreflightOptions,
    work: impl FnOnce() -> Result<T, RunError>,
) -> Result<(T, Report, LogSummary), RunError> {
    std::thread::scope(|scope| {
        let checking = scope.spawn(|| {
            let checked = check_files(files, options);
            if !matches!(&checked, Ok((report, _)) if report.errors().next().is_none()) {
                files.stop();
            }
            checked
        });
        let worked = work();
        let (report, summary) = checking
            .join()
            .map_err(|_| RunError::Invalid("the preflight stopped unexpectedly".into()))??;
        if let Some(refusal) = refusal(&report) {
            return Err(refusal);
        }
        Ok((worked?, report, summary))
    })
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
