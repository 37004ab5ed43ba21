//! A mapped CSV file read as a stream: its header checked against the
//! mapping (columns found by name, in any order), then one row at a time,
//! each cell converted to the declared scalar's SI unit. Nothing is held but
//! the current row.

use std::path::Path;

use nav_runtime::log::{
    closest_name, open_confined, plausible_limit, CsvProblem, LogError, LogFile, Rejected,
    SkippedRow, MAX_COLUMNS, REJECTED_FLOOR, REJECTED_ONE_IN,
};

use super::mapping::{Cell, Column, Source};
use super::row_checks::RowChecks;
use super::ModelReplayError;

/// Where a declared scalar is read from once the header is known.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Read {
    /// Column index and factor.
    Column(usize, f64),
    /// A constant.
    Constant(f64),
    /// Not in this file (a truth state the file does not have).
    Absent,
}

/// The rows of one mapped file.
pub struct MappedRows {
    file: String,
    reader: csv::Reader<LogFile>,
    record: csv::StringRecord,
    headers: Vec<String>,
    /// The time column, its unit factor and the offset added (s).
    time: (usize, f64, f64),
    cells: Vec<Read>,
    /// The current row's values, one per cell (NaN for an absent one).
    values: Vec<f64>,
    previous_t: Option<f64>,
    lenient: bool,
    /// Rows skipped (lenient reading): the first few with their reason.
    pub skipped: Vec<SkippedRow>,
    /// Number of rows skipped.
    pub skipped_rows: u64,
    /// Rows read.
    pub rows: u64,
    /// Whether a non-physical reading (non-finite, or beyond
    /// [`plausible_limit`] once in SI units) in a value column is a
    /// rejected row rather than a bad one: a sensor file's.
    rejects_readings: bool,
    /// The rows rejected as non-physical readings, with the first.
    pub rejected: Option<Rejected>,
    /// Data rows met (read, skipped or rejected).
    data_rows: u64,
    /// Per cell read from a column: its mapping key and header.
    column_names: Vec<Option<(String, String)>>,
    /// The checks of the rows ([`MappedRows::check`]).
    checks: RowChecks,
}

/// The skipped rows a reader keeps the reason of.
const KEPT_REASONS: usize = 5;

impl MappedRows {
    /// Opens `source` in `dir`: `Ok(None)` for an absent file the mapping
    /// does not require.
    ///
    /// # Errors
    /// A required file absent or unreadable, an empty file, a column the
    /// mapping names that the header lacks, a header naming a column twice.
    pub fn open(
        dir: &Path,
        source: &Source,
        mapping_file: &str,
        lenient: bool,
    ) -> Result<Option<MappedRows>, ModelReplayError> {
        // Confined to the log directory: a symbolic link or `..` that leads
        // out of it is refused before a byte is read (and never quoted).
        let key = format!("{mapping_file}: file {}", source.file);
        let Some(file) = open_confined(dir, &source.file, &key)? else {
            if !source.required {
                return Ok(None);
            }
            return Err(LogError::MissingFile {
                file: source.file.clone(),
                dir: dir.to_path_buf(),
                key: Some(format!("{mapping_file}: {}.file", source.section)),
            }
            .into());
        };
        let mut reader = csv::ReaderBuilder::new()
            .has_headers(true)
            .flexible(true)
            .trim(csv::Trim::All)
            .from_reader(file);
        let headers: Vec<String> = match reader.headers() {
            Ok(h) => h.iter().map(str::to_string).collect(),
            Err(e) => return Err(csv_error(&source.file, 1, e).into()),
        };
        if headers.iter().all(|h| h.is_empty()) {
            return Err(LogError::EmptyFile {
                file: source.file.clone(),
                expected: expected_header(source),
            }
            .into());
        }
        if headers.len() > MAX_COLUMNS {
            return Err(LogError::Csv {
                file: source.file.clone(),
                line: 1,
                column: String::new(),
                problem: CsvProblem::TooManyColumns {
                    found: headers.len(),
                    limit: MAX_COLUMNS,
                },
            }
            .into());
        }
        // One pass: the cost stays linear in the header's width.
        let mut seen = std::collections::HashSet::with_capacity(headers.len());
        for h in &headers {
            if !seen.insert(h.as_str()) {
                return Err(LogError::Csv {
                    file: source.file.clone(),
                    line: 1,
                    column: h.clone(),
                    problem: CsvProblem::DuplicateColumn { name: h.clone() },
                }
                .into());
            }
        }
        let find = |c: &Column| headers.iter().position(|h| *h == c.header);
        let missing = |c: &Column| {
            let names: Vec<&str> = headers.iter().map(String::as_str).collect();
            // A few names say what the file is; a wide header is not echoed whole.
            const LISTED: usize = 8;
            let mut listed = names[..names.len().min(LISTED)].join(", ");
            if names.len() > LISTED {
                listed.push_str(&format!(" and {} more", names.len() - LISTED));
            }
            let mut problem = format!(
                "{} has no column `{}` (its columns: {listed})",
                source.file, c.header
            );
            if let Some(close) = closest_name(&c.header, &names) {
                problem.push_str(&format!("; did you mean `{close}`?"));
            }
            ModelReplayError::Mapping {
                file: mapping_file.to_string(),
                key: c.key.clone(),
                line: None,
                problem,
            }
        };
        let time = (
            find(&source.time).ok_or_else(|| missing(&source.time))?,
            source.time.factor,
            source.time_offset_s,
        );
        let mut cells = Vec::with_capacity(source.cells.len());
        for c in &source.cells {
            cells.push(match c {
                Cell::Constant(v) => Read::Constant(*v),
                Cell::Column(col) => match find(col) {
                    Some(i) => Read::Column(i, col.factor),
                    None if !col.required => Read::Absent,
                    None => return Err(missing(col)),
                },
            });
        }
        Ok(Some(MappedRows {
            file: source.file.clone(),
            reader,
            record: csv::StringRecord::new(),
            headers,
            time,
            values: vec![f64::NAN; cells.len()],
            cells,
            previous_t: None,
            lenient,
            skipped: Vec::new(),
            skipped_rows: 0,
            rows: 0,
            rejects_readings: source.section.starts_with("sensors."),
            rejected: None,
            data_rows: 0,
            column_names: source
                .cells
                .iter()
                .map(|c| match c {
                    Cell::Column(col) => Some((col.key.clone(), col.header.clone())),
                    Cell::Constant(_) => None,
                })
                .collect(),
            checks: RowChecks::default(),
        }))
    }

    /// The file's name.
    pub fn file(&self) -> &str {
        &self.file
    }

    /// Checks the rows as they are read (`row_checks`): the columns of the
    /// first `cells` cells for a value that never changes, and with
    /// `intervals` the rows' spacing for a silence.
    pub fn check(&mut self, cells: usize, intervals: bool) {
        let columns = (0..cells.min(self.cells.len()))
            .filter(|&i| matches!(self.cells[i], Read::Column(..)))
            .filter_map(|i| {
                let (key, header) = self.column_names.get(i)?.clone()?;
                Some((i, key, header))
            })
            .collect();
        self.checks = RowChecks::new(columns, intervals);
    }

    /// The warnings of the checks of the rows read so far.
    pub fn row_warnings(&self) -> Vec<nav_runtime::log::Warning> {
        self.checks.warnings(&self.file)
    }

    /// Whether cell `i` is read (not [`Read::Absent`]).
    pub fn has(&self, i: usize) -> bool {
        !matches!(self.cells.get(i), Some(Read::Absent) | None)
    }

    /// A warning for each column of the header no cell reads (nor the
    /// time) within two edits of a column the mapping looks for by name
    /// and the header lacks: a misspelt truth column, which would leave its
    /// state unscored without a word.
    pub fn near_miss_warnings(&self) -> Vec<nav_runtime::log::Warning> {
        let file = &self.file;
        self.near_misses()
            .into_iter()
            .map(|(column, state)| {
                nav_runtime::log::Warning::about(
                    nav_runtime::log::WarningKind::PartialScoring,
                    file,
                    format!(
                        "{file}: column `{column}` matches no state, and state {state} has no column: it is not scored (did you mean `{state}`?)"
                    ),
                )
                .with_key(&column)
            })
            .collect()
    }

    /// The columns of the header no cell reads (nor the time) within two
    /// edits of a column looked for by name and absent: `(column, the name
    /// looked for)`.
    fn near_misses(&self) -> Vec<(String, String)> {
        let read: Vec<usize> = self
            .cells
            .iter()
            .filter_map(|c| match c {
                Read::Column(i, _) => Some(*i),
                _ => None,
            })
            .chain(std::iter::once(self.time.0))
            .collect();
        let absent: Vec<&str> = self
            .cells
            .iter()
            .zip(&self.column_names)
            .filter(|(c, _)| matches!(c, Read::Absent))
            .filter_map(|(_, name)| name.as_ref().map(|(_, header)| header.as_str()))
            .collect();
        if absent.is_empty() {
            return Vec::new();
        }
        self.headers
            .iter()
            .enumerate()
            .filter(|(i, _)| !read.contains(i))
            .filter_map(|(_, h)| Some((h.clone(), closest_name(h, &absent)?.to_string())))
            .collect()
    }

    /// The next row: `(line, t)`, its values in [`MappedRows::values`].
    ///
    /// # Errors
    /// A cell that is not a finite number (as read or once converted), a
    /// row with fewer or more cells than the header, a time not after the
    /// previous row's (strict reading; lenient reading skips
    /// and counts the row).
    pub fn next_row(&mut self) -> Result<Option<(u64, f64)>, LogError> {
        loop {
            let line = self.reader.position().line() + 1;
            match self.reader.read_record(&mut self.record) {
                Ok(false) => return Ok(None),
                Ok(true) => {}
                Err(e) => {
                    let e = csv_error(&self.file, line, e);
                    self.skip_or(e)?;
                    continue;
                }
            }
            let line = self.record.position().map_or(line, |p| p.line());
            if self.record.iter().all(str::is_empty) {
                continue;
            }
            self.data_rows += 1;
            match self.parse(line) {
                Ok(t) => {
                    self.previous_t = Some(t);
                    self.rows += 1;
                    self.checks.row(line, t, &self.values);
                    return Ok(Some((line, t)));
                }
                Err((e, true)) if self.rejects_readings => self.reject_reading(e)?,
                Err((e, _)) => self.skip_or(e)?,
            }
        }
    }

    /// Skips a row of a non-physical reading (a sensor glitch), counted and
    /// reported; a strict reader refuses the file once more than
    /// [`REJECTED_FLOOR`] rows and more than one in [`REJECTED_ONE_IN`] are
    /// rejected (a unit or column mistake, not glitches), as the log
    /// reader does.
    fn reject_reading(&mut self, e: LogError) -> Result<(), LogError> {
        let LogError::Csv {
            file,
            line,
            column,
            problem,
        } = e
        else {
            return Err(e);
        };
        let r = self.rejected.get_or_insert(Rejected {
            count: 0,
            first: SkippedRow {
                file,
                line,
                column,
                problem,
            },
        });
        r.count += 1;
        let rows = usize::try_from(self.data_rows).unwrap_or(usize::MAX);
        if !self.lenient
            && r.count > REJECTED_FLOOR
            && r.count.saturating_mul(REJECTED_ONE_IN) > rows
        {
            return Err(LogError::Csv {
                file: r.first.file.clone(),
                line: r.first.line,
                column: r.first.column.clone(),
                problem: CsvProblem::TooManyRejected {
                    count: r.count,
                    rows,
                    first: Box::new(r.first.problem.clone()),
                },
            });
        }
        Ok(())
    }

    /// The values of the row [`MappedRows::next_row`] returned last.
    pub fn values(&self) -> &[f64] {
        &self.values
    }

    fn skip_or(&mut self, e: LogError) -> Result<(), LogError> {
        if !self.lenient {
            return Err(e);
        }
        self.skipped_rows += 1;
        if let LogError::Csv {
            file,
            line,
            column,
            problem,
        } = e
        {
            if self.skipped.len() < KEPT_REASONS {
                self.skipped.push(SkippedRow {
                    file,
                    line,
                    column,
                    problem,
                });
            }
        }
        Ok(())
    }

    /// Parses the current record: its time, or the error and whether it is
    /// a non-physical reading in a value column (a glitch).
    fn parse(&mut self, line: u64) -> Result<f64, (LogError, bool)> {
        let err = |column: usize, problem: CsvProblem| LogError::Csv {
            file: self.file.clone(),
            line,
            column: self
                .headers
                .get(column)
                .cloned()
                .unwrap_or_else(|| format!("<column {}>", column + 1)),
            problem,
        };
        let cell = |i: usize| -> Result<f64, LogError> {
            let Some(text) = self.record.get(i) else {
                return Err(err(
                    i,
                    CsvProblem::ColumnCount {
                        expected: self.headers.len(),
                        found: self.record.len(),
                    },
                ));
            };
            if text.is_empty() {
                return Err(err(i, CsvProblem::EmptyCell));
            }
            let v: f64 = text.parse().map_err(|_| {
                err(
                    i,
                    CsvProblem::NotANumber {
                        text: text.chars().take(40).collect(),
                    },
                )
            })?;
            if !v.is_finite() {
                return Err(err(
                    i,
                    CsvProblem::NonFinite {
                        text: text.chars().take(40).collect(),
                    },
                ));
            }
            Ok(v)
        };
        // A row with more cells than the header is not read by position: a
        // decimal comma (`1,5`) or a shifted column would move every value.
        if self.record.len() != self.headers.len() {
            return Err((
                err(
                    self.record.len().min(self.headers.len()),
                    CsvProblem::ColumnCount {
                        expected: self.headers.len(),
                        found: self.record.len(),
                    },
                ),
                false,
            ));
        }
        // A finite cell can overflow once converted (`1e306` km).
        let converted = |i: usize, factor: f64| -> Result<f64, LogError> {
            let v = cell(i)?;
            let x = v * factor;
            if x.is_finite() {
                Ok(x)
            } else {
                Err(err(
                    i,
                    CsvProblem::OutOfRange {
                        value: v,
                        allowed: "finite once converted to the declared unit",
                    },
                ))
            }
        };
        let t = converted(self.time.0, self.time.1).map_err(|e| (e, false))? + self.time.2;
        if let Some(previous) = self.previous_t {
            if t < previous {
                return Err((
                    err(self.time.0, CsvProblem::TimeBackwards { previous, t }),
                    false,
                ));
            }
            if t == previous {
                return Err((err(self.time.0, CsvProblem::DuplicateTime { t }), false));
            }
        }
        let mut values = std::mem::take(&mut self.values);
        for (k, value) in values.iter_mut().enumerate() {
            *value = match self.cells[k] {
                Read::Column(i, f) => {
                    // Non-finite as read or once converted: a glitch; so is
                    // a magnitude beyond any sensor's.
                    let x = converted(i, f).map_err(|e| {
                        let glitch = matches!(
                            &e,
                            LogError::Csv {
                                problem: CsvProblem::NonFinite { .. }
                                    | CsvProblem::OutOfRange { .. },
                                ..
                            }
                        );
                        (e, glitch)
                    });
                    let x = match x {
                        Ok(x) => x,
                        Err(e) => {
                            self.values = values;
                            return Err(e);
                        }
                    };
                    let (limit, allowed) = plausible_limit(&self.headers[i]);
                    if x.abs() > limit {
                        self.values = values;
                        return Err((err(i, CsvProblem::OutOfRange { value: x, allowed }), true));
                    }
                    x
                }
                Read::Constant(v) => v,
                Read::Absent => f64::NAN,
            };
        }
        self.values = values;
        Ok(t)
    }
}

fn expected_header(source: &Source) -> String {
    let mut names = vec![source.time.header.clone()];
    for c in &source.cells {
        if let Cell::Column(c) = c {
            if !names.contains(&c.header) {
                names.push(c.header.clone());
            }
        }
    }
    names.join(",")
}

fn csv_error(file: &str, line: u64, e: csv::Error) -> LogError {
    let problem = match e.kind() {
        csv::ErrorKind::Utf8 { .. } => CsvProblem::NotANumber {
            text: "<not UTF-8>".into(),
        },
        _ => CsvProblem::NotANumber {
            text: e.to_string().chars().take(60).collect(),
        },
    };
    LogError::Csv {
        file: file.to_string(),
        line,
        column: "<row>".into(),
        problem,
    }
}
