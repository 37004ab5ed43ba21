//! `imu.csv` parsed once for two readers on two threads: a replay reads the
//! file and hands each row on, in batches, to a check reading the same log
//! beside it ([`LogFiles::share_imu`]), which then does not parse the
//! largest file of the log a second time.
//!
//! The hand-over never changes what either reader sees: the check gets
//! every row with its line and, at the end, the reader's counts, skipped
//! rows and resolutions. If the replay stops before the end of the file (an
//! error, a refusal, a model that reads the log another way), the check
//! reads the rest of the file itself.

use std::sync::mpsc::{sync_channel, Receiver, SyncSender};
use std::sync::{Arc, Mutex};

use super::rows::{ImuRow, Row};
use super::stream::{FileRows, LogFiles, RowSource};
use super::{LogError, SkippedRow};

/// Rows handed on in one message.
const BATCH: usize = 1024;
/// Messages in flight: the replay waits when the check is this far behind,
/// so memory stays bounded (about 256 KB of rows).
const IN_FLIGHT: usize = 4;

/// What the reader knew at the end of the file.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct ReadStats {
    /// Rows accepted.
    pub accepted: usize,
    /// Rows skipped (lenient reading).
    pub skipped: usize,
    /// The first reasons rows were skipped.
    pub skip_reasons: Vec<SkippedRow>,
    /// The last accepted row.
    pub last: Option<ImuRow>,
    /// Smallest non-zero step of each column (0 when none changed).
    pub resolution: Vec<f64>,
}

impl ReadStats {
    /// The statistics of `reader` as it stands.
    pub fn of(reader: &FileRows<ImuRow>) -> Self {
        ReadStats {
            accepted: reader.accepted(),
            skipped: reader.skipped(),
            skip_reasons: reader.skip_reasons().to_vec(),
            last: reader.last().copied(),
            resolution: (0..ImuRow::COLUMNS.len())
                .map(|c| reader.resolution(c))
                .collect(),
        }
    }
}

/// What the replay hands on.
#[derive(Debug)]
pub(super) enum Message {
    Rows(Vec<(u64, ImuRow)>),
    End(ReadStats),
}

/// The sending side, held by the [`LogFiles`] until a replay opens
/// `imu.csv` through it.
pub(super) type Slot = Arc<Mutex<Option<SyncSender<Message>>>>;

/// `imu.csv` as the replay reads it, handing every row on.
pub(super) struct Teed {
    reader: FileRows<ImuRow>,
    sender: Option<SyncSender<Message>>,
    batch: Vec<(u64, ImuRow)>,
}

impl Teed {
    pub(super) fn new(reader: FileRows<ImuRow>, sender: SyncSender<Message>) -> Self {
        Teed {
            reader,
            sender: Some(sender),
            batch: Vec::with_capacity(BATCH),
        }
    }

    fn send(&mut self, message: Message) {
        if let Some(s) = &self.sender {
            // A check that has stopped listening is simply no longer fed.
            if s.send(message).is_err() {
                self.sender = None;
            }
        }
    }
}

impl RowSource<ImuRow> for Teed {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, ImuRow)>, LogError> {
        match self.reader.next_row() {
            Ok(Some((line, row))) => {
                if self.sender.is_some() {
                    self.batch.push((line, row));
                    if self.batch.len() == BATCH {
                        let full = std::mem::replace(&mut self.batch, Vec::with_capacity(BATCH));
                        self.send(Message::Rows(full));
                    }
                }
                Ok(Some((Some(line), row)))
            }
            Ok(None) => {
                let rest = std::mem::take(&mut self.batch);
                self.send(Message::Rows(rest));
                let stats = ReadStats::of(&self.reader);
                self.send(Message::End(stats));
                self.sender = None;
                Ok(None)
            }
            Err(e) => {
                // The check reads the file itself from here and meets the
                // same error.
                let rest = std::mem::take(&mut self.batch);
                self.send(Message::Rows(rest));
                self.sender = None;
                Err(e)
            }
        }
    }
}

impl Drop for Teed {
    fn drop(&mut self) {
        // Rows handed to the replay but not yet on: the check needs them to
        // know where to go on reading by itself.
        if !self.batch.is_empty() {
            let rest = std::mem::take(&mut self.batch);
            self.send(Message::Rows(rest));
        }
    }
}

/// The check's side of a shared `imu.csv` ([`LogFiles::share_imu`]): every
/// row the replay read, then the rest of the file read here if the replay
/// stopped early.
pub struct SharedImu {
    files: LogFiles,
    receiver: Option<Receiver<Message>>,
    batch: std::vec::IntoIter<(u64, ImuRow)>,
    /// Rows received so far.
    received: usize,
    /// Reading the file itself (the replay stopped early).
    own: Option<FileRows<ImuRow>>,
    stats: Option<ReadStats>,
}

impl SharedImu {
    pub(super) fn new(files: LogFiles, receiver: Receiver<Message>) -> Self {
        SharedImu {
            files,
            receiver: Some(receiver),
            batch: Vec::new().into_iter(),
            received: 0,
            own: None,
            stats: None,
        }
    }

    /// The reader's statistics once every row was read.
    pub fn stats(&self) -> ReadStats {
        match (&self.stats, &self.own) {
            (Some(s), _) => s.clone(),
            (None, Some(own)) => ReadStats::of(own),
            (None, None) => ReadStats::default(),
        }
    }

    /// Opens the file here and passes the rows already received.
    fn read_on_from_here(&mut self) -> Result<(), LogError> {
        let mut own = self.files.imu()?;
        for _ in 0..self.received {
            if own.next_row()?.is_none() {
                break;
            }
        }
        self.own = Some(own);
        Ok(())
    }
}

impl RowSource<ImuRow> for SharedImu {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, ImuRow)>, LogError> {
        loop {
            if let Some(own) = self.own.as_mut() {
                return Ok(own.next_row()?.map(|(line, r)| (Some(line), r)));
            }
            if let Some((line, row)) = self.batch.next() {
                self.received += 1;
                return Ok(Some((Some(line), row)));
            }
            if self.stats.is_some() {
                return Ok(None);
            }
            let message = self.receiver.as_ref().and_then(|r| r.recv().ok());
            match message {
                Some(Message::Rows(rows)) => self.batch = rows.into_iter(),
                Some(Message::End(stats)) => {
                    self.stats = Some(stats);
                    self.receiver = None;
                }
                None => {
                    self.receiver = None;
                    self.read_on_from_here()?;
                }
            }
        }
    }
}

impl LogFiles {
    /// Shares `imu.csv` between this log's next replay and the caller: the
    /// next [`LogSource::imu_rows`](super::LogSource::imu_rows) of the log
    /// (on any clone) hands every row it reads to the returned reader, which
    /// reads the rest of the file itself if the replay stops early, or
    /// everything once [`LogFiles::stop_sharing`] is called without a replay
    /// having opened the file.
    pub fn share_imu(&self) -> SharedImu {
        let (sender, receiver) = sync_channel(IN_FLIGHT);
        if let Ok(mut slot) = self.imu_share.lock() {
            *slot = Some(sender);
        }
        SharedImu::new(self.clone(), receiver)
    }

    /// Withdraws a share no replay took (the reader then reads the file
    /// itself); nothing happens to one already taken.
    pub fn stop_sharing(&self) {
        if let Ok(mut slot) = self.imu_share.lock() {
            *slot = None;
        }
    }

    /// `imu.csv`, handing its rows on if it is shared.
    pub(super) fn imu_for_replay(&self) -> Result<Box<dyn RowSource<ImuRow>>, LogError> {
        let reader = self.imu()?;
        let sender = self.imu_share.lock().ok().and_then(|mut s| s.take());
        Ok(match sender {
            Some(s) => Box::new(Teed::new(reader, s)),
            None => Box::new(reader),
        })
    }
}
