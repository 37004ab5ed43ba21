//! Aiding sensors against what the initial state predicts, as far as that is
//! cheap without a filter: DVL speed against a plausible vehicle speed, the
//! first USBL fix against the initial position moved by the initial velocity.

use nav_runtime::earth::{Geodetic, LocalNed};
use nav_runtime::log::{DvlRow, LogDir, Meta, Row, UsblRow, Warning, WarningKind};
use nav_runtime::nalgebra::Vector3;

use super::{rows_until, PreflightOptions, Report};

/// Fastest plausible vehicle carrying a DVL, m/s (about 20 kn).
pub(super) const MAX_DVL_SPEED: f64 = 10.0;

/// A DVL speed beyond this is not a measurement of any vehicle, m/s.
const MAX_PHYSICAL_SPEED: f64 = 1e4;

/// A USBL fix this far from the predicted position is an error, m.
const USBL_FAR: f64 = 10_000.0;

/// Position uncertainty assumed without `[initial_sigma] position`, m.
const DEFAULT_POSITION_SIGMA: f64 = 10.0;

fn speed(r: &DvlRow) -> Option<f64> {
    r.velocity()
        .map(|v| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt())
}

/// The first DVL rows faster than [`MAX_PHYSICAL_SPEED`] and than twice
/// [`MAX_DVL_SPEED`], and the first USBL fix within `aiding_seconds` of the
/// first IMU time.
#[derive(Debug, Default)]
pub(super) struct Fold {
    unphysical: Option<(Option<u64>, f64)>,
    fast: Option<(Option<u64>, f64)>,
    fix: Option<(Option<u64>, UsblRow)>,
}

impl Fold {
    pub(super) fn dvl(&mut self, line: Option<u64>, r: &DvlRow) {
        let Some(s) = speed(r) else { return };
        if self.unphysical.is_none() && s > MAX_PHYSICAL_SPEED {
            self.unphysical = Some((line, s));
        }
        if self.fast.is_none() && s > 2.0 * MAX_DVL_SPEED {
            self.fast = Some((line, s));
        }
    }

    pub(super) fn usbl(&mut self, line: Option<u64>, r: &UsblRow, t_start: f64, seconds: f64) {
        if self.fix.is_none() && r.t >= t_start && r.t <= t_start + seconds {
            self.fix = Some((line, *r));
        }
    }

    /// Error if a DVL speed exceeds [`MAX_PHYSICAL_SPEED`], or if the median
    /// DVL speed over the first `aiding_seconds` (of the head) exceeds
    /// [`MAX_DVL_SPEED`] (cm/s or mm/s?); a warning naming the first row
    /// faster than twice that anywhere in the file. The first USBL fix within
    /// `aiding_seconds`: an error beyond [`USBL_FAR`] from the initial
    /// position advanced by the initial velocity, a warning beyond a 5-sigma
    /// band.
    pub(super) fn finish(
        &self,
        head: &LogDir,
        t_start: f64,
        has_dvl: bool,
        options: &PreflightOptions,
        report: &mut Report,
    ) {
        if has_dvl {
            let early = head.dvl.as_deref().unwrap_or_default();
            self.dvl_speed(rows_until(early, t_start + options.aiding_seconds), report);
        }
        if let Some((line, fix)) = self.fix {
            usbl_position(&head.meta, line, &fix, t_start, report);
        }
    }

    fn dvl_speed(&self, early: &[DvlRow], report: &mut Report) {
        if let Some((line, s)) = self.unphysical {
            let mut w = Warning::about(
                WarningKind::Suspicious,
                DvlRow::FILE,
                format!("speed {s:e} m/s: not a physical speed"),
            )
            .with_key("vx,vy,vz");
            if let Some(line) = line {
                w = w.at_line(line);
            }
            report.error(w);
            return;
        }
        let mut early: Vec<f64> = early.iter().filter_map(speed).collect();
        if !early.is_empty() {
            early.sort_by(f64::total_cmp);
            let median = early[early.len() / 2];
            if median > MAX_DVL_SPEED {
                let cause = if median > 1000.0 {
                    "mm/s? the format is m/s"
                } else if median > 100.0 {
                    "cm/s? the format is m/s"
                } else {
                    "wrong unit or scale? the format is m/s"
                };
                report.error(
                    Warning::about(
                        WarningKind::Suspicious,
                        DvlRow::FILE,
                        format!(
                            "median speed {median:.1} m/s over the first {} rows with bottom \
                             lock, beyond a plausible vehicle speed ({MAX_DVL_SPEED} m/s): {cause}",
                            early.len()
                        ),
                    )
                    .with_key("vx,vy,vz"),
                );
                return;
            }
        }
        if let Some((line, s)) = self.fast {
            let mut w = Warning::about(
                WarningKind::Suspicious,
                DvlRow::FILE,
                format!("speed {s:.1} m/s beyond a plausible vehicle speed ({MAX_DVL_SPEED} m/s)"),
            )
            .with_key("vx,vy,vz");
            if let Some(line) = line {
                w = w.at_line(line);
            }
            report.warn(w);
        }
    }
}

fn usbl_position(meta: &Meta, line: Option<u64>, fix: &UsblRow, t_start: f64, report: &mut Report) {
    let init = &meta.initial;
    // An attitude-only meta.toml has no position to compare the fix with.
    let Ok([lat, lon, depth]) = init.position() else {
        return;
    };
    let frame = LocalNed::new(Geodetic::new(lat, lon, -depth));
    let dt = fix.t - init.t.unwrap_or(t_start);
    let predicted = Vector3::new(init.vn, init.ve, init.vd) * dt;
    let measured = frame.geodetic_to_ned(&Geodetic::new(fix.lat, fix.lon, -fix.depth));
    let d = (measured - predicted).xy().norm();
    let sigma0 = meta
        .initial_sigma
        .and_then(|s| s.position)
        .unwrap_or(DEFAULT_POSITION_SIGMA);
    let usbl_sigma = meta.sensors.usbl.map_or(0.0, |n| n.noise_sigma);
    // 5 sigma of the initial position and the fix, plus 1 m/s of unmodelled
    // motion over the elapsed time.
    let band = 5.0 * (sigma0 * sigma0 + usbl_sigma * usbl_sigma).sqrt() + dt.abs();
    if d <= band {
        return;
    }
    let mut w = Warning::about(
        WarningKind::Suspicious,
        UsblRow::FILE,
        format!(
            "fix at t = {} is {d:.0} m from the initial position advanced by the initial \
             velocity (band {band:.0} m){}",
            fix.t,
            if d > USBL_FAR {
                ": lat/lon in degrees or swapped, or a wrong [initial] position?"
            } else {
                ""
            }
        ),
    )
    .with_key("lat,lon");
    if let Some(line) = line {
        w = w.at_line(line);
    }
    if d > USBL_FAR {
        report.error(w);
    } else {
        report.warn(w);
    }
}
