//! A row source parsed in runs: rows are taken from the file
//! [`READ_AHEAD_ROWS`] at a time and handed out one by one, so that a replay
//! alternates between parsing many rows and filtering them rather than
//! between the two on every row (which keeps each one's code and data in
//! the caches: the same work, in less time).

use std::cell::Cell;
use std::collections::VecDeque;
use std::time::{Duration, Instant};

use super::rows::Row;
use super::stream::RowSource;
use super::LogError;

/// Rows parsed per run.
pub const READ_AHEAD_ROWS: usize = 256;

thread_local! {
    /// This thread's time in [`ReadAhead`] runs.
    static READING: Cell<Duration> = const { Cell::new(Duration::ZERO) };
}

/// The time this thread has spent reading and parsing log rows in
/// [`ReadAhead`] runs (two clock reads per run of [`READ_AHEAD_ROWS`]
/// rows). A replay takes the difference over its loop to leave the reading
/// out of the time it reports as the filter's, without a clock read per
/// sample.
pub fn reading_time() -> Duration {
    READING.with(Cell::get)
}

/// `source` read [`READ_AHEAD_ROWS`] rows at a time. A read error is
/// returned where it occurred, after the rows before it.
pub struct ReadAhead<S, R> {
    source: S,
    rows: VecDeque<(Option<u64>, R)>,
    /// The error met while reading ahead, returned once the rows before it
    /// are taken.
    error: Option<LogError>,
    ended: bool,
}

impl<S: RowSource<R>, R: Row> ReadAhead<S, R> {
    /// `source`, nothing read yet.
    pub fn new(source: S) -> Self {
        ReadAhead {
            source,
            rows: VecDeque::with_capacity(READ_AHEAD_ROWS),
            error: None,
            ended: false,
        }
    }

    fn fill(&mut self) {
        let start = Instant::now();
        self.read_run();
        READING.with(|r| r.set(r.get() + start.elapsed()));
    }

    fn read_run(&mut self) {
        while self.rows.len() < READ_AHEAD_ROWS {
            match self.source.next_row() {
                Ok(Some(row)) => self.rows.push_back(row),
                Ok(None) => {
                    self.ended = true;
                    return;
                }
                Err(e) => {
                    self.error = Some(e);
                    return;
                }
            }
        }
    }
}

impl<S: RowSource<R>, R: Row> RowSource<R> for ReadAhead<S, R> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
        if self.rows.is_empty() && self.error.is_none() && !self.ended {
            self.fill();
        }
        if let Some(row) = self.rows.pop_front() {
            return Ok(Some(row));
        }
        match self.error.take() {
            Some(e) => Err(e),
            None => Ok(None),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{ReadAhead, READ_AHEAD_ROWS};
    use crate::log::{DepthRow, LogError, RowSource};

    /// Rows `0..n` then an error, as a source.
    struct Counting {
        next: usize,
        n: usize,
    }

    impl RowSource<DepthRow> for Counting {
        fn next_row(&mut self) -> Result<Option<(Option<u64>, DepthRow)>, LogError> {
            if self.next == self.n {
                self.next += 1;
                return Err(LogError::Meta {
                    key: "k".into(),
                    line: None,
                    problem: "end".into(),
                });
            }
            let i = self.next;
            self.next += 1;
            Ok(Some((Some(i as u64 + 2), DepthRow::new(i as f64, 0.0))))
        }
    }

    #[test]
    fn rows_come_in_order_and_the_error_where_it_was() {
        let n = 2 * READ_AHEAD_ROWS + 7;
        let mut r = ReadAhead::new(Counting { next: 0, n });
        for i in 0..n {
            let (line, row) = r.next_row().unwrap().unwrap();
            assert_eq!((line, row.t), (Some(i as u64 + 2), i as f64));
        }
        assert!(r.next_row().is_err());
    }
}
