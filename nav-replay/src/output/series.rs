//! Time series of a replay that does not hold the log: rows written to a CSV
//! file as they come ([`TableWriter`], the same format as
//! [`RunTable::write_csv`]), and a bounded copy for plots ([`BoundedTable`]:
//! every k-th row, k doubling whenever the copy fills, so a 24-hour log keeps
//! as many points as a 1-hour one), and the choice between them and a whole
//! table in memory that a replay's options make ([`SeriesSink`]).

use std::io::Write;
use std::path::{Path, PathBuf};

use crate::{RunError, RunTable};

/// Rows written to a CSV file as they come.
#[derive(Debug)]
pub struct TableWriter {
    path: PathBuf,
    out: std::io::BufWriter<std::fs::File>,
    line: String,
}

impl TableWriter {
    /// Creates `path` and writes the header.
    ///
    /// # Errors
    /// The file cannot be created or written.
    pub fn create(path: &Path, columns: &[&str]) -> Result<Self, RunError> {
        let file = std::fs::File::create(path).map_err(|e| RunError::io(path, e))?;
        let mut w = TableWriter {
            path: path.to_path_buf(),
            out: std::io::BufWriter::new(file),
            line: String::new(),
        };
        writeln!(w.out, "{}", columns.join(",")).map_err(|e| RunError::io(path, e))?;
        Ok(w)
    }

    /// Appends one row.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn push(&mut self, row: &[f64]) -> Result<(), RunError> {
        self.line.clear();
        for (i, v) in row.iter().enumerate() {
            if i > 0 {
                self.line.push(',');
            }
            self.line.push_str(&nav_runtime::log::format_f64(*v));
        }
        self.line.push('\n');
        self.out
            .write_all(self.line.as_bytes())
            .map_err(|e| RunError::io(&self.path, e))
    }

    /// Flushes the file.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn finish(mut self) -> Result<(), RunError> {
        self.out.flush().map_err(|e| RunError::io(&self.path, e))
    }
}

/// A copy of a table of bounded size: at most `capacity` rows, evenly spaced
/// in row count over the whole series (the last row is always kept apart).
#[derive(Debug, Clone)]
pub struct BoundedTable {
    table: RunTable,
    capacity: usize,
    stride: usize,
    seen: usize,
    /// The last row offered, when it was not kept (compared by position,
    /// not by value: a row with a NaN is unequal to itself).
    last: Vec<f64>,
    last_kept: bool,
}

/// Rows a plot series keeps.
pub const PLOT_ROWS: usize = 20_000;

impl BoundedTable {
    /// An empty table keeping at most `capacity` (at least 2) rows.
    pub fn new(name: &str, columns: &[&str], capacity: usize) -> Self {
        BoundedTable {
            table: RunTable::new(name, columns),
            capacity: capacity.max(2),
            stride: 1,
            seen: 0,
            last: Vec::new(),
            last_kept: true,
        }
    }

    /// Offers one row.
    pub fn push(&mut self, row: &[f64]) {
        if self.seen.is_multiple_of(self.stride) && self.table.rows.len() == self.capacity {
            let kept: Vec<Vec<f64>> = self.table.rows.drain(..).step_by(2).collect();
            self.table.rows = kept;
            self.stride *= 2;
        }
        self.last_kept = self.seen.is_multiple_of(self.stride);
        if self.last_kept {
            self.table.push(row);
        } else {
            self.last.clear();
            self.last.extend_from_slice(row);
        }
        self.seen += 1;
    }

    /// Rows offered.
    pub fn seen(&self) -> usize {
        self.seen
    }

    /// The kept rows (and the last row offered, if it was not kept).
    pub fn into_table(mut self) -> RunTable {
        if !self.last_kept {
            self.table.rows.push(self.last);
        }
        self.table
    }
}

/// Where the rows of one output table of a streamed replay go: written to
/// `<name>.csv` under the output directory with a bounded copy kept for the
/// plots, kept whole in memory (a replay asked for its series without an
/// output directory, e.g. a log in memory), or nowhere. Only the first
/// keeps memory bounded whatever the log's length, and only the second
/// returns every row.
#[derive(Debug)]
pub enum SeriesSink {
    /// Every row written to the file; a bounded copy for plots.
    Written(TableWriter, BoundedTable),
    /// Every row in memory.
    Kept(RunTable),
    /// Not asked for.
    Nothing,
}

impl SeriesSink {
    /// The sink of table `name` for a replay writing into `out` (when
    /// given), else keeping its series in memory when `keep_series`.
    ///
    /// # Errors
    /// The file cannot be created.
    pub fn new(
        name: &str,
        columns: &[&str],
        out: Option<&Path>,
        keep_series: bool,
    ) -> Result<Self, RunError> {
        Ok(match out {
            Some(dir) => SeriesSink::Written(
                TableWriter::create(&dir.join(format!("{name}.csv")), columns)?,
                BoundedTable::new(name, columns, PLOT_ROWS),
            ),
            None if keep_series => SeriesSink::Kept(RunTable::new(name, columns)),
            None => SeriesSink::Nothing,
        })
    }

    /// Whether rows go anywhere (a caller may skip forming them).
    pub fn wanted(&self) -> bool {
        !matches!(self, SeriesSink::Nothing)
    }

    /// Offers one row.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn push(&mut self, row: &[f64]) -> Result<(), RunError> {
        match self {
            SeriesSink::Written(writer, plot) => {
                plot.push(row);
                writer.push(row)
            }
            SeriesSink::Kept(table) => {
                table.push(row);
                Ok(())
            }
            SeriesSink::Nothing => Ok(()),
        }
    }

    /// Ends the table: the file flushed, and the rows in memory (every row,
    /// or the bounded copy of a written table); `None` when not asked for.
    ///
    /// # Errors
    /// The file cannot be written.
    pub fn finish(self) -> Result<Option<RunTable>, RunError> {
        match self {
            SeriesSink::Written(writer, plot) => {
                writer.finish()?;
                Ok(Some(plot.into_table()))
            }
            SeriesSink::Kept(table) => Ok(Some(table)),
            SeriesSink::Nothing => Ok(None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_bounded_table_keeps_evenly_spaced_rows_and_the_last() {
        for (n, capacity) in [(10usize, 100usize), (1000, 100), (12_345, 64)] {
            let mut b = BoundedTable::new("x", &["t"], capacity);
            for i in 0..n {
                b.push(&[i as f64]);
            }
            let t = b.into_table();
            assert!(t.rows.len() <= capacity + 1, "{n}: {}", t.rows.len());
            assert!(
                n <= capacity || t.rows.len() > capacity / 2,
                "{n}: {}",
                t.rows.len()
            );
            assert_eq!(t.rows[0][0], 0.0);
            assert_eq!(t.rows.last().unwrap()[0], (n - 1) as f64);
            let steps: Vec<f64> = t.rows.windows(2).map(|w| w[1][0] - w[0][0]).collect();
            let first = steps[0];
            assert!(
                steps[..steps.len() - 1].iter().all(|s| *s == first),
                "{n}: {steps:?}"
            );
        }
    }

    /// The last row is added once, whether kept or not, even when it holds
    /// a NaN (a column the row lacks) and so is unequal to itself.
    #[test]
    fn the_last_row_comes_once_even_with_a_nan() {
        for (n, capacity) in [(5usize, 100usize), (101, 100), (1000, 64)] {
            let mut b = BoundedTable::new("x", &["t", "v"], capacity);
            for i in 0..n {
                b.push(&[i as f64, f64::NAN]);
            }
            let t = b.into_table();
            let times: Vec<f64> = t.rows.iter().map(|r| r[0]).collect();
            assert_eq!(times.last(), Some(&((n - 1) as f64)), "{n}");
            assert!(times.windows(2).all(|w| w[0] < w[1]), "{n}: {times:?}");
        }
    }
}
