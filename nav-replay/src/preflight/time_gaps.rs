//! Time stamps: IMU gaps beyond a multiple of the IMU period (a hole or a
//! clock jump), too few IMU rows, and aiding rows far outside the IMU's span.

use nav_runtime::log::{ImuRow, Row, Warning, WarningKind};

use super::{lines_text, PreflightOptions, Report};

/// Aiding rows further than this outside the IMU span are a clock error, s.
const CLOCK_JUMP: f64 = 3600.0;

/// An interval of an increment file longer than this many periods lost
/// rows (each increment is the motion over its own interval only).
const LOST_INCREMENT_PERIODS: f64 = 1.5;

/// A median IMU period longer than this is not a strapdown IMU's, s (a
/// 100 Hz IMU stamped in milliseconds has a period of 10).
const MAX_IMU_PERIOD: f64 = 1.0;

/// Longest IMU gap propagated without `--lenient`, s: real loggers drop
/// data for a second or two (a bus hiccup, a full buffer), and holding the
/// sample before the gap for that long costs the navigation at most the
/// rate change over it, which the replay reports; a longer gap is missing
/// data or a clock jump and is refused.
pub const SHORT_GAP_SECONDS: f64 = 5.0;

/// Rows this close outside the IMU span are not reported, s.
const MARGIN: f64 = 1.0;

/// Findings listed per check before the rest are only counted.
const LISTED: usize = 3;

/// IMU intervals the period is the median of.
pub(super) const PERIOD_INTERVALS: usize = 10_000;

/// The median of `dt`.
pub(super) fn median(mut dt: Vec<f64>) -> Option<f64> {
    if dt.is_empty() {
        return None;
    }
    dt.sort_by(f64::total_cmp);
    Some(dt[dt.len() / 2])
}

/// The rows of one file outside the IMU span.
#[derive(Debug, Clone, Copy)]
struct Outside {
    file: &'static str,
    first: (Option<u64>, f64),
    last: (Option<u64>, f64),
    before: usize,
    after: usize,
    rows: usize,
}

/// The IMU time stamps as they go by: the first [`PERIOD_INTERVALS`]
/// intervals are held until the median period is known, later ones are
/// checked as they come; the first [`LISTED`] gaps are kept. For each other
/// file: its first and last rows and the counts before and after the IMU
/// span.
#[derive(Debug)]
pub(super) struct Fold {
    max_gap_periods: f64,
    /// The first IMU rows, until the period is known.
    start: Vec<(Option<u64>, f64)>,
    previous: Option<(Option<u64>, f64)>,
    period: Option<f64>,
    gaps: usize,
    /// Gaps longer than [`SHORT_GAP_SECONDS`].
    long_gaps: usize,
    /// The first gaps, with the line and time of the row after each and
    /// whether it is short enough to propagate.
    listed: Vec<(Warning, Option<u64>, f64, bool)>,
    outside: [Option<Outside>; 9],
    /// Whether `imu.csv` holds increments: then any interval longer than
    /// [`LOST_INCREMENT_PERIODS`] lost the motion of the rows missing.
    pub(super) increments: bool,
    /// Intervals of an increment file that lost rows, and the first.
    lost: usize,
    first_lost: Option<(Option<u64>, Option<u64>, f64)>,
}

impl Fold {
    pub(super) fn new(options: &PreflightOptions) -> Self {
        Fold {
            max_gap_periods: options.max_gap_periods,
            start: Vec::new(),
            previous: None,
            period: None,
            gaps: 0,
            long_gaps: 0,
            listed: Vec::new(),
            outside: [None; 9],
            increments: false,
            lost: 0,
            first_lost: None,
        }
    }

    /// The median IMU interval over the first 10 000 intervals, s.
    pub(super) fn period(&self) -> Option<f64> {
        self.period.or_else(|| self.start_period())
    }

    fn start_period(&self) -> Option<f64> {
        median(self.start.windows(2).map(|w| w[1].1 - w[0].1).collect())
    }

    pub(super) fn imu(&mut self, line: Option<u64>, r: &ImuRow) {
        let row = (line, r.t);
        if self.period.is_some() {
            if let Some(p) = self.previous {
                self.interval(p, row);
            }
        } else {
            self.start.push(row);
            if self.start.len() > PERIOD_INTERVALS {
                self.settle();
            }
        }
        self.previous = Some(row);
    }

    /// Fixes the period from the held rows and checks their intervals.
    fn settle(&mut self) {
        self.period = self.start_period();
        let start = std::mem::take(&mut self.start);
        if self.period.is_some() {
            for w in start.windows(2) {
                self.interval(w[0], w[1]);
            }
        }
    }

    fn interval(&mut self, (line_a, ta): (Option<u64>, f64), (line_b, tb): (Option<u64>, f64)) {
        let Some(period) = self.period else { return };
        let dt = tb - ta;
        if self.increments && dt > LOST_INCREMENT_PERIODS * period {
            self.lost += 1;
            self.first_lost.get_or_insert((line_a, line_b, dt));
        }
        if dt <= self.max_gap_periods * period {
            return;
        }
        self.gaps += 1;
        let short = dt <= SHORT_GAP_SECONDS;
        self.long_gaps += usize::from(!short);
        if self.gaps > LISTED {
            return;
        }
        let between = lines_text(line_a, line_b, " and ").unwrap_or_else(|| "two rows".into());
        let what = if short {
            format!("propagated holding the sample before it (at most {SHORT_GAP_SECONDS} s is)")
        } else {
            format!("missing data or a clock jump (more than {SHORT_GAP_SECONDS} s)")
        };
        let mut w = Warning::about(
            WarningKind::ImuGap,
            ImuRow::FILE,
            format!(
                "gap of {dt:.6} s between {between} (t = {ta} and t = {tb}; IMU period \
                 {period:.6} s, limit {} periods): {what}",
                self.max_gap_periods
            ),
        )
        .with_key("t");
        if let Some(a) = line_a {
            w = w.at_line(a);
        }
        self.listed.push((w, line_b, tb, short));
    }

    /// A row of file `index` (not the IMU) at `t`; `span` is the IMU span.
    pub(super) fn outside(
        &mut self,
        index: usize,
        file: &'static str,
        line: Option<u64>,
        t: f64,
        span: Option<(f64, f64)>,
    ) {
        let Some((t0, t1)) = span else { return };
        let o = self.outside[index].get_or_insert(Outside {
            file,
            first: (line, t),
            last: (line, t),
            before: 0,
            after: 0,
            rows: 0,
        });
        o.last = (line, t);
        o.rows += 1;
        if t < t0 - MARGIN {
            o.before += 1;
        }
        if t > t1 + MARGIN {
            o.after += 1;
        }
    }

    /// IMU gaps longer than `max_gap_periods` median periods are warnings
    /// naming both lines when at most [`SHORT_GAP_SECONDS`] long (the replay
    /// propagates them), errors beyond (warnings with `--lenient`), at the
    /// row before the gap, or at the row after it when that is the last row
    /// (a last stamp far in the future is that row's mistake); fewer than 2 IMU rows
    /// is an error; then the rows of each file outside the IMU span.
    pub(super) fn finish(
        mut self,
        imu_rows: usize,
        span: Option<(f64, f64)>,
        options: &PreflightOptions,
        report: &mut Report,
    ) {
        if imu_rows < 2 {
            report.error(Warning::about(
                WarningKind::ImuGap,
                ImuRow::FILE,
                format!("{imu_rows} IMU row(s): at least 2 are needed to propagate the state"),
            ));
            return;
        }
        if self.period.is_none() {
            self.settle();
        }
        if let Some(period) = self.period.filter(|p| *p > MAX_IMU_PERIOD) {
            let unit = if period >= 1000.0 * MAX_IMU_PERIOD {
                "microseconds"
            } else {
                "milliseconds"
            };
            report.error_unless(
                options.lenient,
                Warning::about(
                    WarningKind::Suspicious,
                    ImuRow::FILE,
                    format!(
                        "median IMU period {period} s (first {} intervals), slower than any \
                         strapdown IMU (limit {MAX_IMU_PERIOD} s): times in {unit}? the format \
                         is seconds (or declare [files.imu] time)",
                        PERIOD_INTERVALS.min(imu_rows - 1)
                    ),
                )
                .with_key("t"),
            );
        }
        if let (Some((a, b, dt)), Some(period)) = (self.first_lost, self.period) {
            let between = lines_text(a, b, " and ").unwrap_or_else(|| "two rows".into());
            let mut w = Warning::about(
                WarningKind::ImuGap,
                ImuRow::FILE,
                format!(
                    "{} interval(s) of the increment file are longer than {LOST_INCREMENT_PERIODS} \
                     IMU periods (first: {dt:.6} s between {between}, period {period:.6} s): \
                     increment rows dropped? their rotation and velocity change are lost",
                    self.lost
                ),
            )
            .with_key("t");
            if let Some(b) = b {
                w = w.at_line(b);
            }
            report.warn(w);
        }
        let last = self.previous;
        let mut long_listed = 0;
        for (mut w, line_b, tb, short) in std::mem::take(&mut self.listed) {
            // A gap before the last row: that row's stamp is the odd one.
            if let (Some(b), Some((Some(last_line), last_t))) = (line_b, last) {
                if b == last_line && tb == last_t {
                    w = w.at_line(b);
                }
            }
            long_listed += usize::from(!short);
            report.error_unless(options.lenient || short, w);
        }
        if self.gaps > LISTED {
            report.error_unless(
                options.lenient || self.long_gaps == long_listed,
                Warning::about(
                    WarningKind::ImuGap,
                    ImuRow::FILE,
                    format!(
                        "{} more IMU gaps, {} of them longer than {SHORT_GAP_SECONDS} s",
                        self.gaps - LISTED,
                        self.long_gaps - long_listed
                    ),
                ),
            );
        }
        let Some((t0, t1)) = span else { return };
        for o in self.outside.iter().flatten() {
            outside(o, t0, t1, options, report);
            if let Some(period) = self.period {
                packed(o, t1 - t0, period, report);
            }
        }
    }
}

/// Rows this many or more in a file whose span is a small part of the
/// IMU's are weighed by [`packed`].
const PACKED_ROWS: usize = 20;
/// The part of the IMU span below which a file's rows are packed.
const PACKED_SPAN: f64 = 0.05;

/// A file of at least [`PACKED_ROWS`] rows, coming faster than the IMU and
/// spanning less than [`PACKED_SPAN`] of its span: a time base that squeezes
/// the file into its start (`period_s` too small, times in another unit).
/// A warning: every row is then applied, at the wrong time.
fn packed(o: &Outside, imu_span: f64, imu_period: f64, report: &mut Report) {
    let span = o.last.1 - o.first.1;
    if o.rows < PACKED_ROWS || span >= PACKED_SPAN * imu_span {
        return;
    }
    let every = span / (o.rows - 1) as f64;
    if every >= imu_period {
        return;
    }
    report.warn(
        Warning::about(
            WarningKind::Suspicious,
            o.file,
            format!(
                "its {} rows span {span:.3} s of the IMU's {imu_span:.1} s, one every {every:.2e} s \
                 where the IMU samples every {imu_period:.2e} s: a time base that packs them into \
                 the start (`period_s` of `[files.<sensor>] time` too small, or times in another \
                 unit?)",
                o.rows
            ),
        )
        .with_key("t"),
    );
}

/// Rows of a file before the first or after the last IMU sample: a warning
/// (they are not used), an error when more than [`CLOCK_JUMP`] away (a clock
/// jump; a warning with `--lenient`).
fn outside(o: &Outside, t0: f64, t1: f64, options: &PreflightOptions, report: &mut Report) {
    let far = |(line, t): (Option<u64>, f64), d: f64| {
        let mut w = Warning::about(
            WarningKind::OutsideImuSpan,
            o.file,
            format!("t = {t} is {d:.1} s outside the IMU span {t0}..{t1} s: a clock jump?"),
        )
        .with_key("t");
        if let Some(line) = line {
            w = w.at_line(line);
        }
        w
    };
    let (before, after) = (o.before, o.after);
    if before > 0 && t0 - o.first.1 > CLOCK_JUMP {
        report.error_unless(options.lenient, far(o.first, t0 - o.first.1));
    } else if after > 0 && o.last.1 - t1 > CLOCK_JUMP {
        report.error_unless(options.lenient, far(o.last, o.last.1 - t1));
    } else if before + after > 0 && o.file != "truth.csv" {
        report.warn(Warning::about(
            WarningKind::OutsideImuSpan,
            o.file,
            format!(
                "{before} row(s) before and {after} row(s) after the IMU span {t0}..{t1} s are not used"
            ),
        ));
    }
}
