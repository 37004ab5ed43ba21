//! A frozen IMU: one or more of its six channels (gyro `gx, gy, gz`,
//! accelerometer `ax, ay, az`) repeating one value for longer than noise and
//! resolution explain (the rule of `nav_runtime::stuck`).
//!
//! The rule is statistical: a channel with noise `sigma` and output
//! resolution `q` repeats a value `n` times in a row with probability
//! `p^(n-1)` ([`StuckDetector::repeat_probability`]); a run longer than the
//! repeats of false-alarm probability [`FALSE_ALARM`] is frozen. A 20-s
//! freeze at 100 Hz is 2000 identical values where a noisy gyro logged as
//! floating point repeats a value a handful of times at most.
//!
//! A floor of [`FROZEN_FLOOR_SECONDS`] (1 s) is added to the statistics:
//! loggers repeat the last sample when a new one is late (a few samples at
//! a time), which is a timing hiccup and not a frozen sensor; a freeze
//! shorter than a second costs the navigation at most the rate change over
//! that second; anything longer is reported.

use nav_runtime::log::{ImuRow, Meta, Row, Warning, WarningKind};
use nav_runtime::stuck::StuckDetector;

use super::{lines_text, PreflightOptions, Report};

/// Shortest frozen run reported, s (module docs): the default of
/// [`PreflightOptions::frozen_seconds`].
pub const FROZEN_FLOOR_SECONDS: f64 = 1.0;

/// Noise sigma assumed when `[sensors.imu]` is absent (rad/s, m/s^2).
const DEFAULT_SIGMA: f64 = 1e-6;

/// False-alarm probability per sample of the frozen-IMU test.
const FALSE_ALARM: f64 = 1e-9;

/// Runs reported; later ones are not listed.
const LISTED: usize = 3;

/// Runs kept per channel while the resolution (and so the required repeats)
/// may still change: far more than any log has (each is at least
/// `frozen_seconds` long); beyond it later runs are not considered.
const MAX_CANDIDATES: usize = 1024;

/// The channel names, in [`ImuRow`] column order.
const CHANNELS: [&str; 6] = ["gx", "gy", "gz", "ax", "ay", "az"];

/// One run of identical values of a channel.
#[derive(Debug, Clone, Copy)]
struct Run {
    value: f64,
    first_t: f64,
    first_line: Option<u64>,
    last_t: f64,
    last_line: Option<u64>,
    count: usize,
}

/// The runs of one channel as the rows go by, and its output resolution:
/// the smallest nonzero step between consecutive samples (0 when every value
/// repeats).
///
/// Whether a run is frozen depends on the resolution of the whole file, which
/// only gets finer as rows go by, so that the repeats it requires only
/// decrease once a step is seen. A run long enough for the current
/// resolution is certainly frozen; a shorter one (but at least
/// `frozen_seconds` long) is kept as a candidate unless [`LISTED`] earlier
/// kept runs are at least as long (those would be listed before it). The
/// choice is made at the end with the final resolution, as a check over the
/// whole file makes it.
#[derive(Debug, Clone)]
struct Channel {
    sigma: f64,
    resolution: f64,
    previous: Option<f64>,
    run: Option<Run>,
    candidates: Vec<Run>,
    certain: usize,
}

impl Channel {
    fn new(sigma: f64) -> Self {
        Channel {
            sigma,
            resolution: f64::INFINITY,
            previous: None,
            run: None,
            candidates: Vec::new(),
            certain: 0,
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

    fn value(&mut self, line: Option<u64>, t: f64, v: f64, frozen_seconds: f64) {
        if let Some(p) = self.previous {
            let d = (v - p).abs();
            if d != 0.0 && d < self.resolution {
                self.resolution = d;
            }
        }
        self.previous = Some(v);
        let fresh = Run {
            value: v,
            first_t: t,
            first_line: line,
            last_t: t,
            last_line: line,
            count: 1,
        };
        match &mut self.run {
            Some(run) if run.value == v => {
                run.count += 1;
                run.last_t = t;
                run.last_line = line;
            }
            // The common case of a live sensor: a one-sample run is never
            // frozen; it is replaced in place.
            Some(run) if run.count == 1 => *run = fresh,
            _ => {
                if let Some(run) = self.run.replace(fresh) {
                    self.close(run, frozen_seconds);
                }
            }
        }
    }

    fn close(&mut self, run: Run, frozen_seconds: f64) {
        if run.last_t - run.first_t < frozen_seconds || self.certain >= LISTED {
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

    /// The frozen runs, with the repeats noise explains at most, for the
    /// output resolution `resolution` (its triad's: see [`Fold::finish`]).
    fn frozen(mut self, frozen_seconds: f64, resolution: f64) -> (Vec<Run>, usize) {
        if let Some(run) = self.run.take() {
            self.close(run, frozen_seconds);
        }
        self.resolution = resolution;
        let required = self.required();
        let runs = self
            .candidates
            .into_iter()
            .filter(|r| r.count >= required && r.last_t - r.first_t >= frozen_seconds)
            .take(LISTED)
            .collect();
        (runs, required)
    }
}

/// The six channels' runs as the rows go by.
#[derive(Debug, Clone)]
pub(crate) struct Fold {
    channels: [Channel; 6],
    declared: bool,
    frozen_seconds: f64,
    rows: usize,
}

impl Fold {
    pub(crate) fn new(meta: &Meta, options: &PreflightOptions) -> Self {
        let (gyro, accel) = meta
            .sensors
            .imu
            .map_or((DEFAULT_SIGMA, DEFAULT_SIGMA), |n| {
                (n.gyro_noise_sigma, n.accel_noise_sigma)
            });
        Fold {
            channels: std::array::from_fn(|i| Channel::new(if i < 3 { gyro } else { accel })),
            declared: meta.sensors.imu.is_some(),
            frozen_seconds: options.frozen_seconds,
            rows: 0,
        }
    }

    pub(crate) fn imu(&mut self, line: Option<u64>, r: &ImuRow) {
        self.rows += 1;
        let values = [r.gx, r.gy, r.gz, r.ax, r.ay, r.az];
        for (c, v) in self.channels.iter_mut().zip(values) {
            c.value(line, r.t, v, self.frozen_seconds);
        }
    }

    /// Every channel run that is both longer than
    /// [`StuckDetector::required_repeats`] samples (for the logged noise of
    /// the channel and its resolution over the whole file) and at least
    /// `frozen_seconds` long is an error naming its first and last lines (a
    /// warning with `--lenient`, and when `[sensors.imu]` is absent: a
    /// noise-free synthetic IMU repeats legitimately). Channels frozen over
    /// the same span are one finding; the first [`LISTED`] are reported.
    pub(crate) fn finish(self, options: &PreflightOptions, report: &mut Report) {
        if self.rows < 2 {
            return;
        }
        let frozen_seconds = self.frozen_seconds;
        // (run, channel names, repeats noise explains at most, sigma)
        let mut found: Vec<(Run, Vec<&str>, usize, f64)> = Vec::new();
        // The three axes of a triad share one converter: the resolution of
        // each is the finest step seen on any of them (an axis that never
        // steps, held at one value by a coarse quantization, is judged by
        // its neighbours' steps, not as a continuous output).
        let triad = |k: usize| {
            self.channels[3 * k..3 * k + 3]
                .iter()
                .map(|c| c.resolution)
                .fold(f64::INFINITY, f64::min)
        };
        let resolutions = [triad(0), triad(1)];
        for (i, (name, channel)) in CHANNELS.into_iter().zip(self.channels).enumerate() {
            let sigma = channel.sigma;
            let (runs, required) = channel.frozen(frozen_seconds, resolutions[i / 3]);
            for run in runs {
                match found
                    .iter_mut()
                    .find(|(r, ..)| r.first_t == run.first_t && r.last_t == run.last_t)
                {
                    Some((_, names, ..)) => names.push(name),
                    None => found.push((run, vec![name], required, sigma)),
                }
            }
        }
        found.sort_by(|a, b| a.0.first_t.total_cmp(&b.0.first_t));
        for (run, names, required, sigma) in found.into_iter().take(LISTED) {
            let span = run.last_t - run.first_t;
            let lines =
                lines_text(run.first_line, run.last_line, "-").unwrap_or_else(|| "rows".into());
            let what = if names.iter().any(|n| n.starts_with('g')) {
                "gyro"
            } else {
                "accelerometer"
            };
            let columns = names.join(",");
            let mut w = Warning::about(
                WarningKind::FrozenImu,
                ImuRow::FILE,
                format!(
                    "{what} {columns} constant for {span:.1} s ({lines}, t = {:.3}..{:.3} s, \
                     {} samples; noise of {sigma:e} repeats at most {} times): \
                     frozen IMU",
                    run.first_t,
                    run.last_t,
                    run.count,
                    required.saturating_sub(1)
                ),
            )
            .with_key(&columns);
            if let Some(line) = run.first_line {
                w = w.at_line(line);
            }
            if self.declared {
                report.error_unless(options.lenient, w);
            } else {
                w.message.push_str(
                    " (a warning: without [sensors.imu] the log does not say the IMU is noisy)",
                );
                report.warn(w);
            }
        }
    }
}
