//! The preflight run beside the work it guards: a replay reads the log on
//! one thread while the preflight reads it on another, so a log on disk is
//! not read twice in a row, and the preflight's verdict still comes first.

use nav_runtime::log::LogFiles;

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
