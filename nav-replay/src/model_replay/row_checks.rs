//! The checks a mapped file's rows allow as they stream past (the model
//! replay's preflight, `docs/model-replay.md`, "Checks of the rows"): a
//! column of an input or of a sensor's reading that never changes (a
//! mapping that names the wrong column more often than a signal that holds
//! still), and a sensor that falls silent for many of its intervals. Both
//! are warnings, never refusals: a log can be right and still look so.
//! Nothing is kept but one value per column and the largest interval.

use nav_runtime::log::{Warning, WarningKind};

/// Rows a file needs before its columns or intervals are judged.
pub const MIN_ROWS: u64 = 20;

/// An interval longer than this many of the file's mean intervals is a
/// silence of the sensor.
pub const SILENT_INTERVALS: f64 = 10.0;

/// One checked column: its mapping key and header, the first value, and
/// whether a later row differed.
#[derive(Debug, Clone)]
struct Watched {
    cell: usize,
    key: String,
    header: String,
    first: Option<f64>,
    varies: bool,
}

/// The running checks of one file.
#[derive(Debug, Clone, Default)]
pub(super) struct RowChecks {
    columns: Vec<Watched>,
    /// Whether the file's intervals are judged (a sensor's; the inputs'
    /// gaps are the replay's own refusal or warning).
    intervals: bool,
    first_t: Option<f64>,
    last_t: f64,
    rows: u64,
    /// The largest interval: its length, the time and line of the row
    /// after it.
    largest: Option<(f64, f64, u64)>,
}

impl RowChecks {
    /// Checks of the columns `(cell, key, header)` and, with `intervals`,
    /// of the rows' spacing.
    pub(super) fn new(columns: Vec<(usize, String, String)>, intervals: bool) -> Self {
        RowChecks {
            columns: columns
                .into_iter()
                .map(|(cell, key, header)| Watched {
                    cell,
                    key,
                    header,
                    first: None,
                    varies: false,
                })
                .collect(),
            intervals,
            ..RowChecks::default()
        }
    }

    /// One row read: its line, time and values (one per cell).
    pub(super) fn row(&mut self, line: u64, t: f64, values: &[f64]) {
        for c in &mut self.columns {
            let Some(&v) = values.get(c.cell) else {
                continue;
            };
            match c.first {
                None => c.first = Some(v),
                Some(first) if first != v => c.varies = true,
                Some(_) => {}
            }
        }
        if self.rows > 0 {
            let gap = t - self.last_t;
            if !matches!(self.largest, Some((g, _, _)) if g >= gap) {
                self.largest = Some((gap, t, line));
            }
        } else {
            self.first_t = Some(t);
        }
        self.last_t = t;
        self.rows += 1;
    }

    /// The warnings of the rows read, about `file`.
    pub(super) fn warnings(&self, file: &str) -> Vec<Warning> {
        let mut out = Vec::new();
        if self.rows < MIN_ROWS {
            return out;
        }
        for c in self.columns.iter().filter(|c| !c.varies) {
            let Some(v) = c.first else { continue };
            out.push(
                Warning::about(
                    WarningKind::Suspicious,
                    file,
                    format!(
                        "`{}`: column `{}` of {file} holds {v} in all {} rows: a column that never \
                         changes is more often the wrong column than a signal (a constant is written \
                         as a number in the mapping)",
                        c.key, c.header, self.rows
                    ),
                )
                .with_key(&c.key),
            );
        }
        if let (true, Some(first), Some((gap, t, line))) =
            (self.intervals, self.first_t, self.largest)
        {
            let mean = (self.last_t - first) / (self.rows - 1) as f64;
            if mean > 0.0 && gap > SILENT_INTERVALS * mean {
                let mut w = Warning::about(
                    WarningKind::Suspicious,
                    file,
                    format!(
                        "{file}: no row for {gap} s before t = {t} s (line {line}), {:.0} times its \
                         mean interval of {mean:.6} s: the sensor was silent there",
                        gap / mean
                    ),
                );
                w.line = Some(line);
                out.push(w);
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (what the rows are, the warnings' keys, a silence warned)
    #[test]
    fn constant_columns_and_silences() {
        type Rows = fn(u64) -> (f64, [f64; 2]);
        let cases: [(&str, Rows, u64, &[&str], bool); 5] = [
            (
                "changing, evenly spaced",
                |k| (k as f64, [k as f64, -(k as f64)]),
                100,
                &[],
                false,
            ),
            (
                "second column constant",
                |k| (k as f64, [k as f64, 3.0]),
                100,
                &["z[1]"],
                false,
            ),
            (
                "both constant",
                |k| (k as f64, [1.0, 1.0]),
                100,
                &["z[0]", "z[1]"],
                false,
            ),
            (
                "a silence of 30 intervals",
                |k| {
                    (
                        if k < 50 { k as f64 } else { k as f64 + 30.0 },
                        [k as f64, k as f64],
                    )
                },
                100,
                &[],
                true,
            ),
            (
                "too few rows to judge",
                |k| (k as f64 * 100.0, [1.0, 1.0]),
                19,
                &[],
                false,
            ),
        ];
        for (name, rows, n, keys, silent) in cases {
            let mut c = RowChecks::new(
                vec![
                    (0, "z[0]".into(), "a".into()),
                    (1, "z[1]".into(), "b".into()),
                ],
                true,
            );
            for k in 0..n {
                let (t, v) = rows(k);
                c.row(k + 2, t, &v);
            }
            let w = c.warnings("f.csv");
            let got: Vec<&str> = w.iter().filter_map(|w| w.key.as_deref()).collect();
            assert_eq!(got, keys, "{name}");
            let silence = w.iter().find(|w| w.message.contains("silent"));
            assert_eq!(silence.is_some(), silent, "{name}: {w:?}");
            if let Some(s) = silence {
                assert_eq!(s.line, Some(52), "{name}");
            }
        }
    }
}
