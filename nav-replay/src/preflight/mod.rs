//! Preflight: checks of a log's values before any filter runs, for the unit,
//! sign, frame and clock mistakes that the reader cannot see (every value is
//! finite and in its file's format, but the file means something else).
//!
//! Each check is one file; [`check`] runs them all over a log in memory and
//! [`check_files`] over a log on disk, read as a stream: each file is read
//! once, in the order of [`LogDir::read`], and memory does not grow with the
//! log. Both drive the same folds over the rows ([`SliceRows`] in memory, a
//! [`RowReader`](nav_runtime::log::RowReader) on disk), so they give the same
//! findings on the same rows.
//!
//! Most checks are folds over every row (IMU gaps, frozen IMU, gyro
//! magnitude, angle ranges, truth values, partial DVL rows, rows outside the
//! IMU span, the first depth sample, the first USBL fix, DVL speeds). The few
//! that compare one file with another over time (the gyro against the heading
//! reference, the compass changes against the gyro's turn) and the median DVL
//! speed over the first minute run on the *head* of the log: each file's rows
//! with `t` before the first IMU time plus
//! [`PreflightOptions::head_seconds`] (600 s by default).
//!
//! A clear mistake is an error naming the file, the line or column and the
//! likely cause; a doubtful one is a warning (listed in the JSON
//! `warnings`). `navsim replay` runs the preflight on every log before the
//! model and stops at its first error; `navsim check DIR` prints every
//! finding. Checks and thresholds are described in `docs/trust.md`.

mod aiding_plausibility;
mod alongside;
mod angle_range;
mod declared;
mod depth_consistency;
mod dvl_frame;
mod earth_rate;
mod finding;
pub(crate) mod frozen_imu;
mod gyro_rate;
mod heading_units;
mod initial_point;
mod initial_velocity;
mod partial_rows;
mod sensor_sections;
mod specific_force;
mod summary;
mod time_gaps;
mod truth_values;

pub use alongside::{check_alongside, explained, refusal, weigh_nees};
pub use finding::{Finding, Report, Severity};
pub use frozen_imu::FROZEN_FLOOR_SECONDS;
pub use summary::{FileSummary, ImuSummary, LogSummary};

use nav_runtime::log::{
    AltitudeRow, BaroRow, DepthRow, DvlRow, GnssRow, HeadingRow, ImuForm, ImuRow, LogDir, LogError,
    LogFiles, LogMapping, MagRow, Meta, ReferenceRow, Row, RowSource, RpmRow, SharedImu, SliceRows,
    SpeedRow, TruthRow, UsblRow,
};

/// What the preflight checks and how strictly.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PreflightOptions {
    /// `--lenient`: IMU gaps and a frozen IMU are warnings instead of errors.
    pub lenient: bool,
    /// An IMU interval longer than this many median IMU periods is a gap.
    pub max_gap_periods: f64,
    /// An IMU channel repeating one value for at least this long (s), and
    /// for more samples than noise and resolution explain, is a frozen IMU
    /// (default [`FROZEN_FLOOR_SECONDS`]).
    pub frozen_seconds: f64,
    /// Span of the log's start over which the vehicle is assumed near rest
    /// for the specific-force checks, s.
    pub settle_seconds: f64,
    /// Span over which aiding sensors are compared with the initial state, s
    /// (the median DVL speed uses at most `head_seconds` of it).
    pub aiding_seconds: f64,
    /// Span of the log's start kept in memory for the checks that compare
    /// files over time (gyro against heading, compass against gyro, median
    /// DVL speed), s from the first IMU time. Bounds the preflight's memory.
    pub head_seconds: f64,
    /// The files the model reads, when known: sections missing for other
    /// files are not reported (and the files are listed as unused).
    pub model_files: Option<&'static [&'static str]>,
}

/// Default [`PreflightOptions::head_seconds`]: ten minutes, long enough for
/// a turn, a minute of aiding and many compass samples; 3.4 MB of IMU rows
/// at 100 Hz.
pub const HEAD_SECONDS: f64 = 600.0;

impl Default for PreflightOptions {
    fn default() -> Self {
        PreflightOptions {
            lenient: false,
            max_gap_periods: 10.0,
            frozen_seconds: FROZEN_FLOOR_SECONDS,
            settle_seconds: 5.0,
            aiding_seconds: 60.0,
            head_seconds: HEAD_SECONDS,
            model_files: None,
        }
    }
}

/// Runs every check over `log` in memory. Lines in findings are known when
/// the reader skipped no row of the file.
pub fn check(log: &LogDir, options: &PreflightOptions) -> Report {
    fn slice<'a, R: Row>(log: &LogDir, rows: Option<&'a [R]>) -> Option<SliceRows<'a, R>> {
        rows.map(|r| SliceRows::of(log, Some(r)))
    }
    let l = log;
    let mut scan = Scan::new(&l.meta, LogMapping::default(), options);
    scan.time_gaps.increments = l.imu_form == ImuForm::Increments;
    let read = (|| {
        scan.file(Some(&mut SliceRows::of(l, Some(&l.imu[..]))))?;
        scan.file(slice(l, l.dvl.as_deref()).as_mut())?;
        scan.file(slice(l, l.depth.as_deref()).as_mut())?;
        scan.file(slice(l, l.heading.as_deref()).as_mut())?;
        scan.file(slice(l, l.usbl.as_deref()).as_mut())?;
        scan.file(slice(l, l.speed.as_deref()).as_mut())?;
        scan.file(slice(l, l.rpm.as_deref()).as_mut())?;
        scan.file(slice(l, l.altitude.as_deref()).as_mut())?;
        scan.file(slice(l, l.truth.as_deref()).as_mut())?;
        scan.file(slice(l, l.mag.as_deref()).as_mut())?;
        scan.file(slice(l, l.baro.as_deref()).as_mut())?;
        scan.file(slice(l, l.gnss.as_deref()).as_mut())?;
        scan.file(slice(l, l.reference.as_deref()).as_mut())
    })();
    // Rows in memory are read without error (`SliceRows` never fails).
    debug_assert!(read.is_ok());
    scan.finish()
}

/// Runs every check over the log opened as `files`, reading each CSV file
/// once in the order of [`LogDir::read`] (so a bad file or row gives the
/// error `LogDir::read` gives) and keeping only the head of the log
/// ([`PreflightOptions::head_seconds`]) and bounded state in memory. Returns
/// the findings and what the replay needs to know about the log without
/// holding it ([`LogSummary`]). Lines in findings are those of the files,
/// lenient reading or not.
///
/// # Errors
/// As [`LogDir::read`] for the CSV files.
pub fn check_files(
    files: &LogFiles,
    options: &PreflightOptions,
) -> Result<(Report, LogSummary), LogError> {
    check_files_with(files, options, None)
}

/// [`check_files`] with `imu.csv` taken from `imu` (the rows a replay
/// beside the check reads, [`LogFiles::share_imu`]) instead of parsed here.
///
/// # Errors
/// As [`check_files`].
pub fn check_files_with(
    files: &LogFiles,
    options: &PreflightOptions,
    imu: Option<SharedImu>,
) -> Result<(Report, LogSummary), LogError> {
    let mut scan = Scan::new(files.meta(), files.mapping().clone(), options);
    scan.time_gaps.increments = files.imu_form()? == ImuForm::Increments;
    let mut summary = LogSummary::new(files);
    match imu {
        Some(mut shared) => {
            scan.file(Some(&mut shared))?;
            summary.add_shared_imu(&shared.stats(), scan.first_t[ImuRow::INDEX]);
        }
        None => {
            let mut imu = files.imu()?;
            scan.file(Some(&mut imu))?;
            summary.add_file(&imu, scan.first_t[ImuRow::INDEX]);
        }
    }
    summary_file::<DvlRow>(files, &mut scan, &mut summary)?;
    summary_file::<DepthRow>(files, &mut scan, &mut summary)?;
    summary_file::<HeadingRow>(files, &mut scan, &mut summary)?;
    summary_file::<UsblRow>(files, &mut scan, &mut summary)?;
    summary_file::<SpeedRow>(files, &mut scan, &mut summary)?;
    summary_file::<RpmRow>(files, &mut scan, &mut summary)?;
    summary_file::<AltitudeRow>(files, &mut scan, &mut summary)?;
    summary_file::<TruthRow>(files, &mut scan, &mut summary)?;
    // Read like every other file (the replay's reader refuses what it
    // refuses), though no check judges their values yet.
    summary_file::<MagRow>(files, &mut scan, &mut summary)?;
    summary_file::<BaroRow>(files, &mut scan, &mut summary)?;
    summary_file::<GnssRow>(files, &mut scan, &mut summary)?;
    summary_file::<ReferenceRow>(files, &mut scan, &mut summary)?;
    summary.finish(scan.imu_summary());
    summary.count_unused(DvlRow::FILE, scan.partial_rows.found());
    Ok((scan.finish(), summary))
}

fn summary_file<R: Scanned>(
    files: &LogFiles,
    scan: &mut Scan,
    summary: &mut LogSummary,
) -> Result<(), LogError> {
    let mut rows = files.rows::<R>()?;
    scan.file(rows.as_mut())?;
    if let Some(rows) = &rows {
        summary.add_file(rows, scan.first_t[R::INDEX]);
    }
    Ok(())
}

/// Whether the model reads `file` (any file when the model's are not known).
fn reads(model_files: Option<&[&str]>, file: &str) -> bool {
    model_files.is_none_or(|m| m.contains(&file))
}

/// Rows of `rows` with `t` before `t_end`.
fn rows_until<R: Row>(rows: &[R], t_end: f64) -> &[R] {
    let n = rows.partition_point(|r| r.t() < t_end);
    &rows[..n]
}

/// `lines a<sep>b`; `None` when a line is not known.
fn lines_text(a: Option<u64>, b: Option<u64>, sep: &str) -> Option<String> {
    Some(format!("lines {}{sep}{}", a?, b?))
}

/// Number of files the preflight reads (the files of [`LogDir`]).
const FILES: usize = 13;

/// The state of one preflight run as the rows go by: every check's fold, the
/// head of the log and what is known about each file. Files are fed in the
/// order of [`LogDir::read`], `imu.csv` first.
struct Scan<'m> {
    meta: &'m Meta,
    /// The `[files.<sensor>]` sections: findings on mapped values name them.
    mapping: LogMapping,
    options: PreflightOptions,
    /// Rows before `head_end` of each file.
    head: LogDir,
    head_end: f64,
    /// Per file (index [`Scanned::INDEX`]): present, rows.
    present: [bool; FILES],
    rows: [usize; FILES],
    first_t: [Option<f64>; FILES],
    imu_first: Option<ImuRow>,
    imu_last_t: Option<f64>,
    specific_force: specific_force::Fold,
    earth_rate: earth_rate::Fold,
    gyro_rate: gyro_rate::Fold,
    frozen_imu: frozen_imu::Fold,
    time_gaps: time_gaps::Fold,
    partial_rows: partial_rows::Fold,
    angle_range: angle_range::Fold,
    depth: depth_consistency::Fold,
    aiding: aiding_plausibility::Fold,
    truth: truth_values::Fold,
    initial_point: initial_point::Fold,
    initial_velocity: initial_velocity::Fold,
}

/// A row type the preflight reads: its place in the read order, its head in
/// a [`LogDir`] and the folds it feeds.
trait Scanned: Row {
    /// Position in the order of [`LogDir::read`].
    const INDEX: usize;
    /// The rows of this file in `log` (created empty when absent).
    fn head(log: &mut LogDir) -> &mut Vec<Self>;
    /// Feeds one row, on `line` when known, to the folds it concerns.
    fn feed(scan: &mut Scan, line: Option<u64>, row: &Self);
}

impl Scanned for ImuRow {
    const INDEX: usize = 0;
    fn head(log: &mut LogDir) -> &mut Vec<Self> {
        &mut log.imu
    }
    fn feed(scan: &mut Scan, line: Option<u64>, r: &Self) {
        if scan.imu_first.is_none() {
            scan.imu_first = Some(*r);
            scan.head_end = r.t + scan.options.head_seconds;
        }
        scan.imu_last_t = Some(r.t);
        scan.specific_force
            .imu(scan.options.settle_seconds, line, r);
        scan.earth_rate.imu(scan.options.settle_seconds, line, r);
        scan.gyro_rate.imu(line, r);
        scan.frozen_imu.imu(line, r);
        scan.time_gaps.imu(line, r);
    }
}

macro_rules! scanned {
    ($row:ty, $index:literal, $field:ident, |$scan:ident, $line:ident, $r:ident| $feed:block) => {
        impl Scanned for $row {
            const INDEX: usize = $index;
            fn head(log: &mut LogDir) -> &mut Vec<Self> {
                log.$field.get_or_insert_with(Vec::new)
            }
            fn feed($scan: &mut Scan, $line: Option<u64>, $r: &Self) {
                let span = $scan.imu_span();
                $scan
                    .time_gaps
                    .outside(Self::INDEX, <$row>::FILE, $line, $r.t, span);
                $feed
            }
        }
    };
}

scanned!(DvlRow, 1, dvl, |scan, line, r| {
    scan.partial_rows.dvl(line, r);
    scan.aiding.dvl(line, r);
    let epoch = scan.epoch();
    scan.initial_velocity.dvl(epoch, line, r);
});
scanned!(DepthRow, 2, depth, |scan, line, r| {
    scan.depth.depth(line, r);
});
scanned!(HeadingRow, 3, heading, |scan, line, r| {
    scan.angle_range.heading(line, r);
});
scanned!(UsblRow, 4, usbl, |scan, line, r| {
    scan.depth.usbl(line, r);
    let t_start = scan.t_start();
    scan.aiding
        .usbl(line, r, t_start, scan.options.aiding_seconds);
});
scanned!(SpeedRow, 5, speed, |_scan, _line, _r| {});
scanned!(RpmRow, 6, rpm, |_scan, _line, _r| {});
scanned!(AltitudeRow, 7, altitude, |_scan, _line, _r| {});
scanned!(TruthRow, 8, truth, |scan, line, r| {
    scan.angle_range.truth(line, r);
    scan.truth.row(line, r);
    let epoch = scan.epoch();
    scan.initial_point.row(epoch, r);
});

/// A file read through (so that its reader refuses what the replay's
/// refuses) whose values no check judges yet.
macro_rules! read_through {
    ($row:ty, $index:literal, $field:ident) => {
        impl Scanned for $row {
            const INDEX: usize = $index;
            fn head(log: &mut LogDir) -> &mut Vec<Self> {
                log.$field.get_or_insert_with(Vec::new)
            }
            fn feed(_scan: &mut Scan, _line: Option<u64>, _r: &Self) {}
        }
    };
}

read_through!(MagRow, 9, mag);
read_through!(BaroRow, 10, baro);
read_through!(GnssRow, 11, gnss);
read_through!(ReferenceRow, 12, reference);

impl<'m> Scan<'m> {
    fn new(meta: &'m Meta, mapping: LogMapping, options: &PreflightOptions) -> Self {
        Scan {
            meta,
            mapping,
            options: *options,
            head: LogDir::new(*meta),
            head_end: options.head_seconds,
            present: [false; FILES],
            rows: [0; FILES],
            first_t: [None; FILES],
            imu_first: None,
            imu_last_t: None,
            specific_force: specific_force::Fold::default(),
            earth_rate: earth_rate::Fold::default(),
            gyro_rate: gyro_rate::Fold::default(),
            frozen_imu: frozen_imu::Fold::new(meta, options),
            time_gaps: time_gaps::Fold::new(options),
            partial_rows: partial_rows::Fold::default(),
            angle_range: angle_range::Fold::new(meta),
            depth: depth_consistency::Fold::default(),
            aiding: aiding_plausibility::Fold::default(),
            truth: truth_values::Fold::default(),
            initial_point: initial_point::Fold::default(),
            initial_velocity: initial_velocity::Fold::default(),
        }
    }

    /// Reads one file (`None`: absent) to its end.
    fn file<R: Scanned>(&mut self, rows: Option<&mut impl RowSource<R>>) -> Result<(), LogError> {
        let Some(rows) = rows else { return Ok(()) };
        self.present[R::INDEX] = true;
        R::head(&mut self.head);
        while let Some((line, row)) = rows.next_row()? {
            self.rows[R::INDEX] += 1;
            self.first_t[R::INDEX].get_or_insert(row.t());
            R::feed(self, line, &row);
            if row.t() < self.head_end {
                R::head(&mut self.head).push(row);
            }
        }
        Ok(())
    }

    /// The first IMU time (0 without IMU rows): where the log starts.
    fn t_start(&self) -> f64 {
        self.imu_first.map_or(0.0, |r| r.t)
    }

    /// The initial epoch: `[initial] t`, else (near enough for the checks)
    /// the first IMU time.
    fn epoch(&self) -> f64 {
        self.meta.initial.t.unwrap_or_else(|| self.t_start())
    }

    /// The IMU span `(first, last)`, if the IMU has rows.
    fn imu_span(&self) -> Option<(f64, f64)> {
        Some((self.imu_first?.t, self.imu_last_t?))
    }

    fn imu_summary(&self) -> Option<ImuSummary> {
        Some(ImuSummary {
            first: self.imu_first?,
            last_t: self.imu_last_t?,
            rows: self.rows[0],
            median_period: self.time_gaps.period(),
        })
    }

    /// Every finding, in check order.
    fn finish(self) -> Report {
        let mut report = Report::default();
        let o = self.options;
        let imu_rows = self.rows[0];
        let span = self.imu_span();
        let t_start = self.t_start();
        let epoch = self.epoch();
        let epoch_ok = initial_epoch(self.meta, span, self.time_gaps.period(), &mut report);
        self.specific_force.finish(self.meta, &mut report);
        let reference_beyond = self.angle_range.reference_beyond();
        let gyro_bias = self.meta.sensors.imu.map(|s| s.gyro_bias_sigma);
        self.earth_rate
            .finish(&self.mapping, gyro_bias, &mut report);
        self.gyro_rate
            .finish(&self.head, reference_beyond, &self.mapping, &mut report);
        self.frozen_imu.finish(&o, &mut report);
        self.time_gaps.finish(imu_rows, span, &o, &mut report);
        self.partial_rows.finish(&o, &mut report);
        self.angle_range.finish(&mut report);
        if !report.has_errors() {
            heading_units::check(&self.head, &self.mapping, &mut report);
        }
        self.depth.finish(self.meta, &mut report);
        if !report.has_errors() {
            dvl_frame::check(&self.head, &self.mapping, &mut report);
        }
        if epoch_ok {
            // The aiding checks measure time from the epoch.
            self.aiding.finish(
                &self.head,
                t_start,
                self.present[DvlRow::INDEX],
                &o,
                &mut report,
            );
            if !report.has_errors() && reads(o.model_files, DvlRow::FILE) {
                self.initial_velocity
                    .finish(&self.head, self.meta, epoch, &mut report);
            }
        }
        self.truth.finish(
            self.present[TruthRow::INDEX] && self.rows[TruthRow::INDEX] == 0,
            &mut report,
        );
        let truth_arm = self.mapping.of::<TruthRow>().lever_arm;
        self.initial_point
            .finish(self.meta, epoch, truth_arm, &mut report);
        let mut has_rows = [false; 8];
        for (has, rows) in has_rows.iter_mut().zip(self.rows) {
            *has = rows > 0;
        }
        let mut present = [false; 8];
        present.copy_from_slice(&self.present[..8]);
        sensor_sections::check(self.meta, present, has_rows, o.model_files, &mut report);
        report
    }
}

/// `[initial] t` more IMU periods before the first IMU row than the replay
/// carries the initial state over, or after the last row: an error naming
/// the key (a log moved to epoch time stamps without its epoch, say). False
/// when it is one.
fn initial_epoch(
    meta: &nav_runtime::log::Meta,
    span: Option<(f64, f64)>,
    period: Option<f64>,
    report: &mut Report,
) -> bool {
    use crate::ins::setup::MAX_EPOCH_LEAD_PERIODS;
    use nav_runtime::log::{Warning, WarningKind, META_FILE};
    let (Some(t), Some((t0, t1))) = (meta.initial.t, span) else {
        return true;
    };
    let period = period.unwrap_or(0.01);
    let problem = if t0 - t > MAX_EPOCH_LEAD_PERIODS * period {
        format!(
            "initial.t = {t} s is {} s before the first IMU row (t = {t0} s), more than \
             {MAX_EPOCH_LEAD_PERIODS} IMU periods: a clock offset? (time stamps moved without \
             initial.t)",
            t0 - t
        )
    } else if t > t1 {
        format!("initial.t = {t} s is after the last IMU row (t = {t1} s): nothing to replay")
    } else {
        return true;
    };
    report.error(Warning::about(WarningKind::Suspicious, META_FILE, problem).with_key("initial.t"));
    false
}
