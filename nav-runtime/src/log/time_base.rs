//! `[files.<sensor>] time`: where a file's times come from when its time
//! column cannot be taken as it is (docs/log-format.md, "Time of a mapped
//! file"). Real loggers write synthetic time columns (evenly spread over the
//! recording rather than at the true period), stamp a rate sample at the
//! start or the middle of its interval, or run a sensor on a clock offset
//! from the IMU's; the reader converts every time to the format's own
//! convention: seconds on the log's one clock, a rate sample stamped at the
//! end of its interval.

use super::error::Magnitude;
use super::meta::Cx;
use super::LogError;

/// Where in its interval a rate sample's time stands.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Stamp {
    /// At the start: the sample covers `[t, t + period]`.
    Start,
    /// In the middle: the sample covers `[t - period/2, t + period/2]`.
    Middle,
    /// At the end (the format's convention): the sample covers
    /// `[t - period, t]`.
    #[default]
    End,
}

impl Stamp {
    /// The fraction of a period added to a time stamped this way to stamp it
    /// at the end of its interval.
    pub fn shift(self) -> f64 {
        match self {
            Stamp::Start => 1.0,
            Stamp::Middle => 0.5,
            Stamp::End => 0.0,
        }
    }
}

/// How the times of one file are made: `t = base + offset_s + shift`, where
/// `base` is the time column (or `start_s + k period_s` for data row `k`
/// with `from_index`) and `shift` moves a start- or middle-stamped sample to
/// the end of its interval.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TimeBase {
    /// Times from the row index (`time.from_index`): row `k` (0-based, every
    /// data line counted, a rejected or skipped one too) is at
    /// `start_s + k period_s`; the file's time column is not read.
    pub from_index: bool,
    /// The sample period, s (`time.period_s`): the spacing of rows with
    /// `from_index`, and the interval a `stamp` shift is a fraction of.
    pub period_s: Option<f64>,
    /// Time of row 0 with `from_index`, s (`time.start_s`, default 0).
    pub start_s: f64,
    /// Added to every time of the file, s (`time.offset_s`, default 0): the
    /// file's clock minus the log's clock, negated.
    pub offset_s: f64,
    /// Where a sample's time stands in its interval (`time.stamp`, IMU only;
    /// default the end).
    pub stamp: Stamp,
}

/// Largest row period or offset accepted, s (ten years): beyond, a unit
/// mistake (milliseconds, microseconds since an epoch).
pub const MAX_TIME_S: f64 = 3.2e8;
/// The shortest sample period a file may declare, s: a sensor at more than
/// a megahertz is no navigation sensor, and a smaller value is a unit or
/// exponent mistake that would put the whole file at one instant.
pub const MIN_PERIOD_S: f64 = 1e-6;

impl TimeBase {
    /// Whether the times are the file's column as it is.
    pub fn is_identity(&self) -> bool {
        !self.from_index && self.offset_s == 0.0 && self.stamp == Stamp::End
    }

    /// The time of data row `index` whose time cell read `column` (already
    /// in seconds; ignored with `from_index`).
    pub fn time(&self, index: u64, column: f64) -> f64 {
        let period = self.period_s.unwrap_or(0.0);
        let base = if self.from_index {
            self.start_s + index as f64 * period
        } else {
            column
        };
        base + self.offset_s + self.stamp.shift() * period
    }

    /// Reads `[files.<sensor>] time` (a table) of section `sec`; `stamp`
    /// is allowed for the IMU only.
    pub(super) fn parse(
        cx: &Cx<'_>,
        sec: &str,
        t: &toml::Table,
        stamp_allowed: bool,
        time_column_named: bool,
    ) -> Result<TimeBase, LogError> {
        let tsec = format!("{sec}.time");
        let mut keys = vec!["from_index", "period_s", "start_s", "offset_s"];
        if stamp_allowed {
            keys.push("stamp");
        }
        cx.check_keys(t, &tsec, &keys)?;
        let key = |k: &str| format!("{tsec}.{k}");
        let number = |k: &str, positive: bool| -> Result<Option<f64>, LogError> {
            let v = match t.get(k) {
                None => return Ok(None),
                Some(toml::Value::Float(f)) => *f,
                Some(toml::Value::Integer(i)) => *i as f64,
                Some(other) => {
                    return Err(cx.err(
                        &key(k),
                        format!("expected a number of seconds, found {}", other.type_str()),
                    ))
                }
            };
            if !v.is_finite() || v.abs() > MAX_TIME_S || (positive && v < MIN_PERIOD_S) {
                return Err(cx.err(
                    &key(k),
                    format!(
                        "value {} out of range (expected {}at most {MAX_TIME_S:e} in magnitude; milliseconds?)",
                        Magnitude(v),
                        if positive {
                            format!("positive seconds, at least {MIN_PERIOD_S:e} and ")
                        } else {
                            "finite seconds, ".to_string()
                        }
                    ),
                ));
            }
            Ok(Some(v))
        };
        let from_index = match t.get("from_index") {
            None => false,
            Some(toml::Value::Boolean(b)) => *b,
            Some(other) => {
                return Err(cx.err(
                    &key("from_index"),
                    format!("expected true or false, found {}", other.type_str()),
                ))
            }
        };
        let period_s = number("period_s", true)?;
        let start_s = number("start_s", false)?;
        let offset_s = number("offset_s", false)?.unwrap_or(0.0);
        let stamp = match t.get("stamp") {
            None => Stamp::End,
            Some(toml::Value::String(s)) => match s.as_str() {
                "start" => Stamp::Start,
                "middle" => Stamp::Middle,
                "end" => Stamp::End,
                other => {
                    return Err(cx.err(
                        &key("stamp"),
                        format!(
                            "unknown stamp `{other}`; expected one of: start, middle, end{}",
                            super::did_you_mean(other, &["start", "middle", "end"])
                        ),
                    ))
                }
            },
            Some(other) => {
                return Err(cx.err(
                    &key("stamp"),
                    format!(
                        "expected one of \"start\", \"middle\", \"end\", found {}",
                        other.type_str()
                    ),
                ))
            }
        };
        if from_index && time_column_named {
            return Err(cx.err(
                &format!("{sec}.columns.t"),
                format!(
                    "contradicts `{}`: times come from the row index, not from a column (list the time column in `{sec}.ignore` to read past it)",
                    key("from_index")
                ),
            ));
        }
        if from_index && period_s.is_none() {
            return Err(cx.err(
                &key("from_index"),
                format!("needs `{}`, the spacing of rows (s)", key("period_s")),
            ));
        }
        if !from_index && start_s.is_some() {
            return Err(cx.err(
                &key("start_s"),
                format!("is the time of row 0 with `{} = true`", key("from_index")),
            ));
        }
        if stamp != Stamp::End && period_s.is_none() {
            return Err(cx.err(
                &key("stamp"),
                format!(
                    "a sample stamped at the {} of its interval needs `{}`, the interval (s)",
                    if stamp == Stamp::Start {
                        "start"
                    } else {
                        "middle"
                    },
                    key("period_s")
                ),
            ));
        }
        if !from_index && stamp == Stamp::End && period_s.is_some() {
            return Err(cx.err(
                &key("period_s"),
                format!(
                    "is used with `{} = true` or a `{}` other than \"end\"; neither is given",
                    key("from_index"),
                    key("stamp")
                ),
            ));
        }
        Ok(TimeBase {
            from_index,
            period_s,
            start_s: start_s.unwrap_or(0.0),
            offset_s,
            stamp,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_from_index_offset_and_stamp() {
        // (time base, row index, time column, expected time)
        let cases = [
            (TimeBase::default(), 7, 1.25, 1.25),
            (
                TimeBase {
                    offset_s: -0.3,
                    ..TimeBase::default()
                },
                0,
                2.0,
                1.7,
            ),
            (
                TimeBase {
                    from_index: true,
                    period_s: Some(0.01),
                    start_s: 5.0,
                    ..TimeBase::default()
                },
                200,
                99.0,
                7.0,
            ),
            (
                TimeBase {
                    from_index: true,
                    period_s: Some(0.01),
                    stamp: Stamp::Start,
                    ..TimeBase::default()
                },
                0,
                0.0,
                0.01,
            ),
            (
                TimeBase {
                    period_s: Some(0.02),
                    stamp: Stamp::Middle,
                    offset_s: 1.0,
                    ..TimeBase::default()
                },
                3,
                10.0,
                11.01,
            ),
        ];
        for (i, (base, k, column, want)) in cases.into_iter().enumerate() {
            let got = base.time(k, column);
            assert!((got - want).abs() < 1e-12, "case {i}: {got} != {want}");
        }
        assert!(TimeBase::default().is_identity());
    }
}
