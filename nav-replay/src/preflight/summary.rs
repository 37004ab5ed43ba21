//! What a streaming preflight learns about a log that the replay needs
//! without holding the log: row counts, time spans, resolutions, the IMU's
//! first row and period, and the reader's warnings.

use std::collections::BTreeMap;

use nav_runtime::log::{
    skipped_row_warnings, DvlRow, FileRows, ImuRow, LogDir, LogFiles, ReadStats, Row, SkippedRow,
    Warning, MAX_SKIP_REASONS,
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

/// The smallest non-zero step between consecutive values of each column of
/// `rows` (empty cells passed over), 0 when no value changed: what
/// `RowReader::resolution` gives for the same rows.
fn resolutions<R: Row>(rows: &[R]) -> Vec<f64> {
    let n = R::COLUMNS.len();
    let mut step = vec![f64::INFINITY; n];
    let mut last: Vec<Option<f64>> = vec![None; n];
    for r in rows {
        for (i, cell) in r.to_cells().into_iter().enumerate().skip(1) {
            let Some(v) = cell else { continue };
            if let Some(l) = last[i] {
                let d = (v - l).abs();
                if d > 0.0 && d.is_finite() && d < step[i] {
                    step[i] = d;
                }
            }
            last[i] = Some(v);
        }
    }
    step.into_iter()
        .map(|q| if q.is_finite() { q } else { 0.0 })
        .collect()
}

impl LogSummary {
    /// The summary of a log in memory: what [`super::check_files`] gives
    /// for the same log on disk (skip reasons per file are those among
    /// `log.skip_reasons`).
    pub fn of(log: &LogDir) -> Self {
        fn file<R: Row>(log: &LogDir, rows: Option<&[R]>, out: &mut Vec<FileSummary>) {
            let Some(rows) = rows else { return };
            out.push(FileSummary {
                file: R::FILE,
                rows: rows.len(),
                skipped: log.skipped_rows.get(R::FILE).copied().unwrap_or(0),
                skip_reasons: log
                    .skip_reasons
                    .iter()
                    .filter(|r| r.file == R::FILE)
                    .cloned()
                    .collect(),
                first_t: rows.first().map(Row::t),
                last_t: rows.last().map(Row::t),
                resolution: resolutions(rows),
            });
        }
        let l = log;
        let mut files = Vec::new();
        file(l, Some(&l.imu[..]), &mut files);
        file(l, l.dvl.as_deref(), &mut files);
        file(l, l.depth.as_deref(), &mut files);
        file(l, l.heading.as_deref(), &mut files);
        file(l, l.usbl.as_deref(), &mut files);
        file(l, l.speed.as_deref(), &mut files);
        file(l, l.rpm.as_deref(), &mut files);
        file(l, l.altitude.as_deref(), &mut files);
        file(l, l.truth.as_deref(), &mut files);
        file(l, l.mag.as_deref(), &mut files);
        file(l, l.baro.as_deref(), &mut files);
        file(l, l.gnss.as_deref(), &mut files);
        file(l, l.reference.as_deref(), &mut files);
        let imu = l
            .imu
            .first()
            .zip(l.imu.last())
            .map(|(first, last)| ImuSummary {
                first: *first,
                last_t: last.t,
                rows: l.imu.len(),
                median_period: super::time_gaps::median(
                    l.imu
                        .windows(2)
                        .take(super::time_gaps::PERIOD_INTERVALS)
                        .map(|w| w[1].t - w[0].t)
                        .collect(),
                ),
            });
        let mut summary = LogSummary {
            files,
            imu,
            skipped_rows: l.skipped_rows.clone(),
            skip_reasons: l.skip_reasons.clone(),
            unknown_files: l.unknown_files.clone(),
            warnings: l.warnings.clone(),
        };
        let partial = l.dvl.as_deref().map_or(0, |rows| {
            rows.iter()
                .filter(|r| super::partial_rows::is_partial(r))
                .count()
        });
        summary.count_unused(DvlRow::FILE, partial);
        summary
    }

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
        let resolution = (0..R::COLUMNS.len()).map(|c| rows.resolution(c)).collect();
        self.add(
            R::FILE,
            rows.accepted(),
            rows.skip_reasons(),
            rows.skipped(),
            (first_t, rows.last().map(Row::t)),
            resolution,
        );
    }

    /// Adds `imu.csv` as another reader read it
    /// ([`SharedImu`](nav_runtime::log::SharedImu)).
    pub(super) fn add_shared_imu(&mut self, stats: &ReadStats, first_t: Option<f64>) {
        self.add(
            ImuRow::FILE,
            stats.accepted,
            &stats.skip_reasons,
            stats.skipped,
            (first_t, stats.last.as_ref().map(Row::t)),
            stats.resolution.clone(),
        );
    }

    fn add(
        &mut self,
        file: &'static str,
        accepted: usize,
        skip_reasons: &[SkippedRow],
        skipped: usize,
        (first_t, last_t): (Option<f64>, Option<f64>),
        resolution: Vec<f64>,
    ) {
        if skipped > 0 {
            self.skipped_rows.insert(file.to_string(), skipped);
            let room = MAX_SKIP_REASONS.saturating_sub(self.skip_reasons.len());
            self.skip_reasons
                .extend(skip_reasons.iter().take(room).cloned());
        }
        self.files.push(FileSummary {
            file,
            rows: accepted,
            skipped,
            skip_reasons: skip_reasons.to_vec(),
            first_t,
            last_t,
            resolution,
        });
    }

    pub(super) fn finish(&mut self, imu: Option<ImuSummary>) {
        self.imu = imu;
        self.warnings
            .extend(skipped_row_warnings(&self.skipped_rows, &self.skip_reasons));
    }

    /// Counts `rows` rows of `file` that the reader took but the replay
    /// does not use (a partly empty DVL row) as skipped, after the
    /// reader's own warnings (the preflight lists these rows itself).
    pub(super) fn count_unused(&mut self, file: &str, rows: usize) {
        if rows == 0 {
            return;
        }
        *self.skipped_rows.entry(file.to_string()).or_insert(0) += rows;
        if let Some(f) = self.files.iter_mut().find(|f| f.file == file) {
            f.skipped += rows;
        }
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
