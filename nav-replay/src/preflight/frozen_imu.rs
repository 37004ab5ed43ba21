//! A frozen IMU: the gyro triple repeating one value for longer than noise
//! and resolution explain (the rule of `nav_runtime::stuck`).

use nav_runtime::log::{ImuRow, Meta, Row, Warning, WarningKind};
use nav_runtime::stuck::StuckDetector;

use super::{lines_text, PreflightOptions, Report};

/// Gyro noise sigma assumed when `[sensors.imu]` is absent, rad/s.
const DEFAULT_GYRO_SIGMA: f64 = 1e-6;

/// False-alarm probability per sample of the frozen-IMU test.
const FALSE_ALARM: f64 = 1e-9;

/// Runs reported; later ones are not listed.
const LISTED: usize = 3;

/// Runs kept while the resolution (and so the required repeats) may still
/// change: far more than any log has (each is at least `frozen_seconds`
/// long); beyond it later runs are not considered.
const MAX_CANDIDATES: usize = 1024;

/// One run of identical gyro triples.
#[derive(Debug, Clone, Copy)]
struct Run {
    first: ImuRow,
    first_line: Option<u64>,
    last_t: f64,
    last_line: Option<u64>,
    count: usize,
}

/// The runs of identical gyro triples as the rows go by, and the gyro's
/// output resolution: the smallest nonzero step between consecutive samples
/// of one axis (0 when every value repeats).
///
/// Whether a run is frozen depends on the resolution of the whole file, which
/// only gets finer as rows go by, so that the repeats it requires only
/// decrease once a step is seen. A run long enough for the current
/// resolution is certainly frozen; a shorter one (but at least
/// `frozen_seconds` long) is kept as a candidate unless [`LISTED`] earlier
/// kept runs are at least as long (those would be listed before it). The
/// choice is made at the end with the final resolution, as a check over the
/// whole file makes it.
#[derive(Debug)]
pub(super) struct Fold {
    sigma: f64,
    declared: bool,
    frozen_seconds: f64,
    resolution: f64,
    previous: Option<ImuRow>,
    run: Option<Run>,
    candidates: Vec<Run>,
    certain: usize,
    rows: usize,
}

impl Fold {
    pub(super) fn new(meta: &Meta, options: &PreflightOptions) -> Self {
        Fold {
            sigma: meta
                .sensors
                .imu
                .map_or(DEFAULT_GYRO_SIGMA, |n| n.gyro_noise_sigma),
            declared: meta.sensors.imu.is_some(),
            frozen_seconds: options.frozen_seconds,
            resolution: f64::INFINITY,
            previous: None,
            run: None,
            candidates: Vec::new(),
            certain: 0,
            rows: 0,
        }
    }

    fn resolution(&self) -> f64 {
        if self.resolution.is_finite() {
            self.resolution
        } else {
            0.0
        }
    }

    fn required(&self) -> usize {
        StuckDetector::required_repeats(self.sigma, self.resolution(), FALSE_ALARM) as usize
    }

    pub(super) fn imu(&mut self, line: Option<u64>, r: &ImuRow) {
        if let Some(p) = self.previous {
            for d in [r.gx - p.gx, r.gy - p.gy, r.gz - p.gz] {
                if d != 0.0 && d.abs() < self.resolution {
                    self.resolution = d.abs();
                }
            }
        }
        self.previous = Some(*r);
        self.rows += 1;
        match &mut self.run {
            Some(run) if run.first.gx == r.gx && run.first.gy == r.gy && run.first.gz == r.gz => {
                run.count += 1;
                run.last_t = r.t;
                run.last_line = line;
            }
            _ => {
                if let Some(run) = self.run.take() {
                    self.close(run);
                }
                self.run = Some(Run {
                    first: *r,
                    first_line: line,
                    last_t: r.t,
                    last_line: line,
                    count: 1,
                });
            }
        }
    }

    fn close(&mut self, run: Run) {
        if run.last_t - run.first.t < self.frozen_seconds || self.certain >= LISTED {
            return;
        }
        let longer = self
            .candidates
            .iter()
            .filter(|c| c.count >= run.count)
            .count();
        if longer >= LISTED || self.candidates.len() >= MAX_CANDIDATES {
            return;
        }
        // Once a step is seen, the final required repeats are at most the
        // current ones.
        if self.resolution.is_finite() && run.count >= self.required() {
            self.certain += 1;
        }
        self.candidates.push(run);
    }

    /// A run of identical gyro triples that is both longer than
    /// [`StuckDetector::required_repeats`] samples (for the logged gyro noise
    /// and the resolution of the whole file) and longer than
    /// `frozen_seconds` is an error naming its first and last lines (a
    /// warning with `--lenient`, and when `[sensors.imu]` is absent: a
    /// noise-free synthetic IMU repeats legitimately). The first
    /// [`LISTED`] are reported.
    pub(super) fn finish(mut self, options: &PreflightOptions, report: &mut Report) {
        if self.rows < 2 {
            return;
        }
        if let Some(run) = self.run.take() {
            self.close(run);
        }
        let required = self.required();
        let sigma = self.sigma;
        let frozen = self
            .candidates
            .iter()
            .filter(|r| r.count >= required && r.last_t - r.first.t >= self.frozen_seconds)
            .take(LISTED);
        for run in frozen {
            let span = run.last_t - run.first.t;
            let lines =
                lines_text(run.first_line, run.last_line, "-").unwrap_or_else(|| "rows".into());
            let mut w = Warning::about(
                WarningKind::FrozenImu,
                ImuRow::FILE,
                format!(
                    "gyro triple constant for {span:.1} s ({lines}, t = {:.3}..{:.3} s, \
                     {} samples; noise of {sigma:e} rad/s repeats at most {} times): \
                     frozen IMU",
                    run.first.t,
                    run.last_t,
                    run.count,
                    required.saturating_sub(1)
                ),
            )
            .with_key("gx,gy,gz");
            if let Some(line) = run.first_line {
                w = w.at_line(line);
            }
            if self.declared {
                report.error_unless(options.lenient, w);
            } else {
                w.message.push_str(
                    " (a warning: without [sensors.imu] the log does not say the gyro is noisy)",
                );
                report.warn(w);
            }
        }
    }
}
