//! What a streaming preflight learns about a log that the replay needs
//! without holding the log: row counts, time spans, resolutions, the IMU's
//! first row and period, and the reader's warnings.

use std::collections::BTreeMap;

use nav_runtime::log::{
    skipped_row_warnings, FileRows, ImuRow, LogFiles, Row, SkippedRow, Warning, MAX_SKIP_REASONS,
};

/// One CSV file of a log as read by [`super::check_files`].
#[derive(Debug, Clone, PartialEq)]
pub struct FileSummary {
    /// The file name (`imu.csv`, ...).
    pub file: &'static str,
    /// Rows accepted.
    pub rows: usize,
    /// Rows skipped by the lenient reader (0 when strict).
    pub skipped: usize,
    /// The first reasons rows of this file were skipped (at most
    /// [`MAX_SKIP_REASONS`]).
    pub skip_reasons: Vec<SkippedRow>,
    /// Time of the first accepted row, s.
    pub first_t: Option<f64>,
    /// Time of the last accepted row, s.
    pub last_t: Option<f64>,
    /// Per column (index in [`Row::COLUMNS`], `t` included): the smallest
    /// non-zero step between consecutive values
    /// ([`RowReader::resolution`](nav_runtime::log::RowReader::resolution)),
    /// 0 when no value changed.
    pub resolution: Vec<f64>,
}

/// The IMU as read by [`super::check_files`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuSummary {
    /// The first accepted row.
    pub first: ImuRow,
    /// Time of the last accepted row, s.
    pub last_t: f64,
    /// Rows accepted.
    pub rows: usize,
    /// The median IMU interval over the first 10 000 intervals, s (`None`
    /// with a single row); the period the preflight's gap check uses.
    pub median_period: Option<f64>,
}

/// What [`super::check_files`] learns about a log while it checks it: all a
/// replay needs to know before it streams the log (its plan: first IMU row,
/// period, resolutions; health row counts; `navsim check`'s output), in
/// memory of a size independent of the log's length.
///
/// `warnings` are those [`LogDir::read`](nav_runtime::log::LogDir::read)
/// gives in `LogDir::warnings` for the same directory (unknown `meta.toml`
/// sections, unknown files, skipped rows), in the same order.
#[derive(Debug, Clone, PartialEq)]
pub struct LogSummary {
    /// The present CSV files, in read order (imu, dvl, depth, heading, usbl,
    /// speed, rpm, altitude, truth).
    pub files: Vec<FileSummary>,
    /// The IMU's first row, last time and period; `None` without IMU rows.
    pub imu: Option<ImuSummary>,
    /// Rows skipped by the lenient reader, per file name (files with none are
    /// absent), as `LogDir::skipped_rows`.
    pub skipped_rows: BTreeMap<String, usize>,
    /// The first reasons rows were skipped over all files (at most
    /// [`MAX_SKIP_REASONS`]), as `LogDir::skip_reasons`.
    pub skip_reasons: Vec<SkippedRow>,
    /// `.csv` files that are not log files (lenient reading), as
    /// `LogDir::unknown_files`.
    pub unknown_files: Vec<String>,
    /// What the reader noticed, as `LogDir::warnings`.
    pub warnings: Vec<Warning>,
}

impl LogSummary {
    pub(super) fn new(files: &LogFiles) -> Self {
        LogSummary {
            files: Vec::new(),
            imu: None,
            skipped_rows: BTreeMap::new(),
            skip_reasons: Vec::new(),
            unknown_files: files.unknown_files().to_vec(),
            warnings: files.warnings().to_vec(),
        }
    }

    /// Adds a file read to its end whose first row is at `first_t`.
    pub(super) fn add_file<R: Row>(&mut self, rows: &FileRows<R>, first_t: Option<f64>) {
        if rows.skipped() > 0 {
            self.skipped_rows
                .insert(R::FILE.to_string(), rows.skipped());
            let room = MAX_SKIP_REASONS.saturating_sub(self.skip_reasons.len());
            self.skip_reasons
                .extend(rows.skip_reasons().iter().take(room).cloned());
        }
        self.files.push(FileSummary {
            file: R::FILE,
            rows: rows.accepted(),
            skipped: rows.skipped(),
            skip_reasons: rows.skip_reasons().to_vec(),
            first_t,
            last_t: rows.last().map(Row::t),
            resolution: (0..R::COLUMNS.len()).map(|c| rows.resolution(c)).collect(),
        });
    }

    pub(super) fn finish(&mut self, imu: Option<ImuSummary>) {
        self.imu = imu;
        self.warnings
            .extend(skipped_row_warnings(&self.skipped_rows, &self.skip_reasons));
    }

    /// The summary of file `name`, if present.
    pub fn file(&self, name: &str) -> Option<&FileSummary> {
        self.files.iter().find(|f| f.file == name)
    }

    /// IMU rows accepted.
    pub fn imu_rows(&self) -> usize {
        self.imu.map_or(0, |i| i.rows)
    }

    /// Time span `(first, last)` covered by the IMU, if it has rows (as
    /// `LogDir::imu_time_span`).
    pub fn imu_time_span(&self) -> Option<(f64, f64)> {
        self.imu.map(|i| (i.first.t, i.last_t))
    }

    /// Total number of rows the lenient reader skipped.
    pub fn total_skipped_rows(&self) -> usize {
        self.skipped_rows.values().sum()
    }
}
