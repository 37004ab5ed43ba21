//! Reading a log directory as a stream: [`LogFiles`] opens the directory
//! (`meta.toml` and the list of files, checked as [`LogDir::read`] checks
//! them) and each file row by row ([`RowReader`]); [`EventStream`] merges the
//! sensor files in time order. Memory does not grow with the log, so a
//! 24-hour log replays in the memory of a 1-hour one.
//!
//! The same merge runs over a log in memory ([`EventStream::of`]), so a
//! replay from files and a replay of the same rows in memory see the same
//! events in the same order.

use std::collections::BTreeMap;
use std::fs;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use super::log_file::{open_confined, LogFile};
use super::mapping::{ImuForm, LogMapping};
use super::reference_point::{AtImu, ReferencePoint};
use super::rejected::{NonPhysical, RejectedTally};
use super::rows::RowReader;
use super::{
    dangling_link, unknown_csv_files, AltitudeRow, DepthRow, DvlRow, Event, HeadingRow, ImuRow,
    LogDir, LogError, Meta, Row, RpmRow, SkippedRow, SpeedRow, Strictness, UsblRow, Warning,
    WarningKind, META_FILE,
};
use super::{BaroRow, GnssRow, MagRow};

/// A log directory opened for reading file by file: its `meta.toml`, what
/// the reader noticed about it, and a [`RowReader`] for any of its files.
#[derive(Debug, Clone)]
pub struct LogFiles {
    dir: PathBuf,
    meta: Meta,
    mapping: LogMapping,
    strictness: Strictness,
    unknown_files: Vec<String>,
    warnings: Vec<Warning>,
    /// Set by [`LogFiles::stop`]; shared by clones.
    stop: Arc<AtomicBool>,
    /// `imu.csv` shared with a check beside the replay
    /// ([`LogFiles::share_imu`]); shared by clones.
    pub(super) imu_share: super::shared::Slot,
    /// Rows rejected as non-physical readings by every reader this log
    /// opened; shared by clones.
    rejected: RejectedTally,
    /// How non-physical values of aiding files are treated.
    non_physical: NonPhysical,
    /// Values of the log's `replay.toml` in place of the file's
    /// ([`LogFiles::with_mapping_value`]).
    mapping_values: Vec<(String, f64)>,
}

/// One file of a log opened for reading (plain or gzip, confined to the
/// log directory).
pub type FileRows<R> = RowReader<R, LogFile>;

impl LogFiles {
    /// Opens the log at `dir`: reads and validates `meta.toml` and lists the
    /// directory (an unknown `.csv` file is an error when strict). No CSV
    /// file is read yet.
    ///
    /// # Errors
    /// As [`LogDir::read`] for the directory and `meta.toml`.
    pub fn open(dir: impl AsRef<Path>, strictness: Strictness) -> Result<LogFiles, LogError> {
        let dir = dir.as_ref();
        match fs::metadata(dir) {
            Ok(m) if m.is_dir() => {}
            Ok(_) => return Err(LogError::io(dir, std::io::Error::other("not a directory"))),
            Err(e) => return Err(LogError::io(dir, e)),
        }
        let meta_path = dir.join(META_FILE);
        let Some(mut meta_file) = open_confined(dir, META_FILE, META_FILE)? else {
            dangling_link(&meta_path)?;
            return Err(LogError::MissingFile {
                file: META_FILE.to_string(),
                dir: dir.to_path_buf(),
                key: None,
            });
        };
        let mut bytes = Vec::new();
        std::io::Read::read_to_end(&mut meta_file, &mut bytes)
            .map_err(|e| LogError::io(&meta_path, e))?;
        let meta_text = String::from_utf8(bytes).map_err(|e| LogError::Meta {
            key: String::new(),
            line: None,
            problem: format!("not valid UTF-8 ({e})"),
        })?;
        let (meta, mapping, mut warnings) = Meta::parse_log(&meta_text)?;
        let unknown_files = unknown_csv_files(dir, &mapping)?;
        if let (Strictness::Strict, Some(file)) = (strictness, unknown_files.first()) {
            // A file a section names that is missing is the error to give
            // first: the stray file is often the one it was meant to name.
            for m in mapping.files.iter().filter(|m| m.declared_file) {
                if open_confined(dir, &m.file, &m.key("file"))?.is_none() {
                    return Err(LogError::MissingFile {
                        file: m.file.clone(),
                        dir: dir.to_path_buf(),
                        key: Some(m.key("file")),
                    });
                }
            }
            return Err(LogError::UnknownFile {
                file: file.clone(),
                dir: dir.to_path_buf(),
            });
        }
        for file in &unknown_files {
            warnings.push(Warning::about(
                WarningKind::UnknownFile,
                file,
                "not a log file: ignored",
            ));
        }
        for (_, standard) in super::mapping::MAPPED_SENSORS {
            if let Some(m) = mapping.replaced(standard) {
                if fs::symlink_metadata(dir.join(standard)).is_ok() {
                    warnings.push(
                        Warning::about(
                            WarningKind::UnknownFile,
                            standard,
                            format!("not read: `files.{}.file` reads `{}`", m.sensor, m.file),
                        )
                        .with_key(&m.key("file")),
                    );
                }
            }
        }
        Ok(LogFiles {
            dir: dir.to_path_buf(),
            meta,
            mapping,
            strictness,
            unknown_files,
            warnings,
            stop: Arc::default(),
            imu_share: Arc::default(),
            rejected: RejectedTally::default(),
            non_physical: NonPhysical::default(),
            mapping_values: Vec::new(),
        })
    }

    /// The log with non-physical values of aiding files (`1e300`, `inf`)
    /// read as `how` says: [`NonPhysical::Rejected`] skips their rows with a
    /// warning ([`LogFiles::rejected_warnings`]) instead of refusing the log.
    pub fn with_non_physical(mut self, how: NonPhysical) -> Self {
        self.non_physical = how;
        self
    }

    /// How non-physical values of aiding files are read.
    pub fn non_physical(&self) -> NonPhysical {
        self.non_physical
    }

    /// One warning per file of which rows were rejected as non-physical
    /// readings (skipped, never returned) by the readers this log (or a
    /// clone) opened so far: after a replay or a check has read the log,
    /// what it rejected ([`WarningKind::RejectedReading`]).
    pub fn rejected_warnings(&self) -> Vec<Warning> {
        self.rejected.warnings()
    }

    /// Stops every [`EventStream`] of this log (and of its clones): their
    /// next [`EventStream::next_event`] is [`LogError::Stopped`]. A check
    /// reading the log on another thread calls it when it refuses the log,
    /// so a replay running meanwhile ends at once instead of finishing a
    /// run whose result is discarded.
    pub fn stop(&self) {
        self.stop.store(true, Ordering::Relaxed);
    }

    /// Whether [`LogFiles::stop`] was called.
    pub fn stopped(&self) -> bool {
        self.stop.load(Ordering::Relaxed)
    }

    /// The directory.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// `meta.toml`.
    pub fn meta(&self) -> &Meta {
        &self.meta
    }

    /// The same log read with `meta` in place of its `meta.toml` (noise
    /// tuning replays a log with other sigmas). Shares the stop flag and
    /// the tally of rejected rows with `self`, as a clone does, but not a
    /// check's share of `imu.csv` ([`LogFiles::share_imu`]): each such log
    /// reads its own rows, so several can replay at once.
    pub fn with_meta(&self, meta: Meta) -> LogFiles {
        LogFiles {
            meta,
            imu_share: Arc::default(),
            ..self.clone()
        }
    }

    /// The same log with `sensor`'s file read `offset_s` seconds later than
    /// its mapping says (`time.offset_s` replaced; noise tuning replays a
    /// log with other clock offsets), sharing what [`LogFiles::with_meta`]
    /// shares; `None` for a name that is not a mapped sensor.
    pub fn with_time_offset(&self, sensor: &str, offset_s: f64) -> Option<LogFiles> {
        let mut mapping = self.mapping.clone();
        mapping.set_time_offset(sensor, offset_s).then(|| LogFiles {
            mapping,
            imu_share: Arc::default(),
            ..self.clone()
        })
    }

    /// The same log with value `key` of its `replay.toml` (the mapping of
    /// a vehicle's own sensors and noise) set to `value`: noise tuning
    /// replays a log with other values. Keys: `sensors.<name>.sigma` (the
    /// sigma of its first output; every output scaled by the same ratio)
    /// and `noise.<name>` (a process noise, every scalar of a vector scaled
    /// together). Shares what [`LogFiles::with_meta`] shares.
    pub fn with_mapping_value(&self, key: &str, value: f64) -> LogFiles {
        let mut mapping_values = self.mapping_values.clone();
        mapping_values.retain(|(k, _)| k != key);
        mapping_values.push((key.to_string(), value));
        LogFiles {
            mapping_values,
            imu_share: Arc::default(),
            ..self.clone()
        }
    }

    /// The value [`LogFiles::with_mapping_value`] set for `key`, if any.
    pub fn mapping_value(&self, key: &str) -> Option<f64> {
        self.mapping_values
            .iter()
            .find(|(k, _)| k == key)
            .map(|(_, v)| *v)
    }

    /// The `[files.<sensor>]` sections of `meta.toml` (empty: every file in
    /// the standard format).
    pub fn mapping(&self) -> &LogMapping {
        &self.mapping
    }

    /// The form of `imu.csv` (read from its header, or declared by
    /// `[files.imu] form`).
    ///
    /// # Errors
    /// As [`LogFiles::imu`].
    pub fn imu_form(&self) -> Result<ImuForm, LogError> {
        Ok(self.imu()?.form())
    }

    /// How bad rows are treated.
    pub fn strictness(&self) -> Strictness {
        self.strictness
    }

    /// `.csv` files that are not log files (lenient reading only; sorted).
    pub fn unknown_files(&self) -> &[String] {
        &self.unknown_files
    }

    /// What opening noticed: unknown `meta.toml` sections and unknown files.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Opens `R`'s file (the one its `[files.<sensor>]` section names, or
    /// the standard one), its header checked; `None` when the file is absent
    /// (the sensor is absent).
    ///
    /// # Errors
    /// A dangling symbolic link, an unreadable file, an empty file or a bad
    /// header; a file a section names that is missing or resolves outside the
    /// log directory.
    pub fn rows<R: Row>(&self) -> Result<Option<FileRows<R>>, LogError> {
        let mapping = self.mapping.of::<R>();
        let key = if mapping.declared_file {
            mapping.key("file")
        } else {
            mapping.file.clone()
        };
        match open_confined(&self.dir, &mapping.file, &key)? {
            Some(f) => RowReader::with_mapping(f, self.strictness, &mapping).map(|r| {
                Some(
                    r.non_physical(self.non_physical)
                        .reporting_to(self.rejected.clone()),
                )
            }),
            None if mapping.declared_file => Err(LogError::MissingFile {
                file: mapping.file,
                dir: self.dir.clone(),
                key: Some(key),
            }),
            None => Ok(None),
        }
    }

    /// Opens `imu.csv`, which every log has.
    ///
    /// # Errors
    /// As [`LogFiles::rows`], and a missing file.
    pub fn imu(&self) -> Result<FileRows<ImuRow>, LogError> {
        self.imu_like::<ImuRow>()
    }

    /// Opens `R`'s file, which must exist.
    pub(super) fn imu_like<R: Row>(&self) -> Result<FileRows<R>, LogError> {
        self.rows::<R>()?.ok_or_else(|| LogError::MissingFile {
            file: self.mapping.of::<R>().file,
            dir: self.dir.clone(),
            key: None,
        })
    }
}

/// The warnings of the rows a lenient reader skipped: the first reasons,
/// each naming file, line and column, and the count of the rest.
pub fn skipped_row_warnings(
    skipped: &BTreeMap<String, usize>,
    reasons: &[SkippedRow],
) -> Vec<Warning> {
    let mut warnings: Vec<Warning> = reasons
        .iter()
        .map(|r| {
            Warning::about(
                WarningKind::SkippedRow,
                &r.file,
                format!("row skipped: {}", r.problem),
            )
            .at_line(r.line)
            .with_key(&r.column)
        })
        .collect();
    let listed = reasons.len();
    let total: usize = skipped.values().sum();
    if total > listed {
        warnings.push(Warning {
            kind: WarningKind::SkippedRow,
            file: None,
            line: None,
            key: None,
            message: format!(
                "{} more rows skipped (first {listed} listed)",
                total - listed
            ),
        });
    }
    warnings
}

/// Rows of one file, one at a time, each with its 1-based line when known.
pub trait RowSource<R: Row> {
    /// The next row; `None` at the end.
    ///
    /// # Errors
    /// A read error or (strict reading) a bad row.
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError>;
}

impl<R: Row, S: RowSource<R> + ?Sized> RowSource<R> for Box<S> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
        (**self).next_row()
    }
}

impl<R: Row, I: std::io::Read> RowSource<R> for RowReader<R, I> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
        Ok(RowReader::next_row(self)?.map(|(line, r)| (Some(line), r)))
    }
}

/// The rows of a file in memory; lines are known when the reader skipped
/// none of the file's rows (row `i` is then on line `i + 2`).
#[derive(Debug, Clone)]
pub struct SliceRows<'a, R> {
    rows: &'a [R],
    next: usize,
    lines_known: bool,
}

impl<'a, R: Row> SliceRows<'a, R> {
    /// The rows of `R`'s file of `log` (none when the file is absent).
    pub fn of(log: &LogDir, rows: Option<&'a [R]>) -> Self {
        SliceRows {
            rows: rows.unwrap_or_default(),
            next: 0,
            lines_known: !log.skipped_rows.contains_key(R::FILE),
        }
    }
}

impl<R: Row> RowSource<R> for SliceRows<'_, R> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
        let Some(r) = self.rows.get(self.next) else {
            return Ok(None);
        };
        let line = self.lines_known.then_some(self.next as u64 + 2);
        self.next += 1;
        Ok(Some((line, *r)))
    }
}

/// A row source read ahead: the rows [`Prefetched::read_ahead`] took are
/// given again, in order, before the rest of the source. A replay plans from
/// the first rows of `imu.csv` and then streams the file from its start
/// without parsing those rows twice.
pub struct Prefetched<'a, R> {
    head: std::collections::VecDeque<(Option<u64>, R)>,
    rest: Box<dyn RowSource<R> + 'a>,
}

impl<'a, R: Row> Prefetched<'a, R> {
    /// `rest` with nothing read ahead yet.
    pub fn new(rest: Box<dyn RowSource<R> + 'a>) -> Self {
        Prefetched {
            head: std::collections::VecDeque::new(),
            rest,
        }
    }

    /// Reads the next row of the source and keeps it to be given again.
    ///
    /// # Errors
    /// As the source's [`RowSource::next_row`].
    pub fn read_ahead(&mut self) -> Result<Option<R>, LogError> {
        let Some(next) = self.rest.next_row()? else {
            return Ok(None);
        };
        self.head.push_back(next);
        Ok(Some(next.1))
    }

    /// The rows read ahead so far, in order.
    pub fn read(&self) -> impl Iterator<Item = &R> {
        self.head.iter().map(|(_, r)| r)
    }
}

impl<R: Row> RowSource<R> for Prefetched<'_, R> {
    fn next_row(&mut self) -> Result<Option<(Option<u64>, R)>, LogError> {
        match self.head.pop_front() {
            Some(row) => Ok(Some(row)),
            None => self.rest.next_row(),
        }
    }
}

impl<R> std::fmt::Debug for Prefetched<'_, R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Prefetched")
            .field("read_ahead", &self.head.len())
            .finish()
    }
}

/// An event of [`EventStream`] with the line of its row when known.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Located {
    /// The sample.
    pub event: Event,
    /// 1-based line in the event's file (`None` when not known).
    pub line: Option<u64>,
}

type Pull<'a> = Box<dyn FnMut() -> Result<Option<Located>, LogError> + 'a>;

/// Number of sources of [`EventStream`]. At equal times the echo sounder
/// comes first (so a DVL sample sees the altitude of its own time), then the
/// DVL, depth, compass, USBL, speed, rpm, and the magnetometer, barometer and
/// GNSS of an imported flight log, and the IMU last: a replay that has an
/// IMU sample in hand has every measurement stamped up to its time.
const ORDER: usize = 11;

/// Index of the IMU among the sources of [`EventStream`].
const IMU: usize = ORDER - 1;

/// The samples of a log's sensor files (not truth) merged in time order, from
/// files or from memory. Holds one row of each file.
pub struct EventStream<'a> {
    pulls: Vec<Pull<'a>>,
    heads: [Option<Located>; ORDER],
    /// The time of each head, read once when it is pulled: the merge
    /// compares times only, never copying an event to get at its time.
    times: [Option<f64>; ORDER],
    /// The earliest head of the sources before the IMU (at equal times the
    /// first) and its time: most events are IMU samples, and taking one
    /// leaves it as it is.
    aiding: Option<(usize, f64)>,
    started: bool,
    /// The log's stop flag and directory (file-backed streams only).
    stop: Option<(Arc<AtomicBool>, PathBuf)>,
}

impl std::fmt::Debug for EventStream<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("EventStream")
            .field("heads", &self.heads)
            .finish()
    }
}

fn pull<'a, R: Row + 'a>(mut source: impl RowSource<R> + 'a, wrap: fn(R) -> Event) -> Pull<'a> {
    Box::new(move || {
        Ok(source.next_row()?.map(|(line, r)| Located {
            event: wrap(r),
            line,
        }))
    })
}

fn none<'a>() -> Pull<'a> {
    Box::new(|| Ok(None))
}

impl<'a> EventStream<'a> {
    /// The events of a log in memory.
    pub fn of(log: &'a LogDir) -> EventStream<'a> {
        let l = log;
        EventStream::new(vec![
            pull(SliceRows::of(l, l.altitude.as_deref()), Event::Altitude),
            pull(SliceRows::of(l, l.dvl.as_deref()), Event::Dvl),
            pull(SliceRows::of(l, l.depth.as_deref()), Event::Depth),
            pull(SliceRows::of(l, l.heading.as_deref()), Event::Heading),
            pull(SliceRows::of(l, l.usbl.as_deref()), Event::Usbl),
            pull(SliceRows::of(l, l.speed.as_deref()), Event::Speed),
            pull(SliceRows::of(l, l.rpm.as_deref()), Event::Rpm),
            pull(SliceRows::of(l, l.mag.as_deref()), Event::Mag),
            pull(SliceRows::of(l, l.baro.as_deref()), Event::Baro),
            pull(SliceRows::of(l, l.gnss.as_deref()), Event::Gnss),
            pull(SliceRows::of(l, Some(&l.imu[..])), Event::Imu),
        ])
    }

    /// The events of a log on disk, each file read as the stream goes.
    ///
    /// # Errors
    /// As [`LogFiles::rows`] for any sensor file.
    pub fn open(files: &LogFiles) -> Result<EventStream<'static>, LogError> {
        fn opt<R: Row + 'static>(
            files: &LogFiles,
            wrap: fn(R) -> Event,
        ) -> Result<Pull<'static>, LogError> {
            Ok(match files.rows::<R>()? {
                Some(r) => pull(r, wrap),
                None => none(),
            })
        }
        Ok(EventStream::new(vec![
            opt::<AltitudeRow>(files, Event::Altitude)?,
            opt::<DvlRow>(files, Event::Dvl)?,
            opt::<DepthRow>(files, Event::Depth)?,
            opt::<HeadingRow>(files, Event::Heading)?,
            opt::<UsblRow>(files, Event::Usbl)?,
            opt::<SpeedRow>(files, Event::Speed)?,
            opt::<RpmRow>(files, Event::Rpm)?,
            opt::<MagRow>(files, Event::Mag)?,
            opt::<BaroRow>(files, Event::Baro)?,
            opt::<GnssRow>(files, Event::Gnss)?,
            pull(files.imu()?, Event::Imu),
        ])
        .stopped_by(files))
    }

    /// The stream ends with [`LogError::Stopped`] once `files` is stopped.
    fn stopped_by(mut self, files: &LogFiles) -> Self {
        self.stop = Some((Arc::clone(&files.stop), files.dir.clone()));
        self
    }

    fn new(pulls: Vec<Pull<'a>>) -> Self {
        EventStream {
            pulls,
            heads: [None; ORDER],
            times: [None; ORDER],
            aiding: None,
            started: false,
            stop: None,
        }
    }

    /// Reads the first row of every source, once.
    #[inline]
    fn fill(&mut self) -> Result<(), LogError> {
        if self.started {
            return Ok(());
        }
        self.start()
    }

    #[cold]
    fn start(&mut self) -> Result<(), LogError> {
        for k in 0..ORDER {
            self.pull(k)?;
        }
        self.started = true;
        Ok(())
    }

    /// Replaces the head of source `k` with its next row; returns the old
    /// head. On error the head stays.
    fn pull(&mut self, k: usize) -> Result<Option<Located>, LogError> {
        let next = (self.pulls[k])()?;
        self.times[k] = next.map(|h| h.event.t());
        if k != IMU {
            self.aiding = earliest(&self.times[..IMU]);
        }
        Ok(std::mem::replace(&mut self.heads[k], next))
    }

    /// The next event in time order (ties: the echo sounder, the aiding
    /// sensors, the IMU last).
    ///
    /// # Errors
    /// A read error or (strict reading) a bad row of any file.
    pub fn next_event(&mut self) -> Result<Option<Located>, LogError> {
        if let Some((stop, dir)) = &self.stop {
            if stop.load(Ordering::Relaxed) {
                return Err(LogError::Stopped { dir: dir.clone() });
            }
        }
        self.fill()?;
        // The earliest head; at equal times the IMU comes last.
        let k = match (self.aiding, self.times[IMU]) {
            (Some((k, t)), Some(imu)) => {
                if imu < t {
                    IMU
                } else {
                    k
                }
            }
            (Some((k, _)), None) => k,
            (None, Some(_)) => IMU,
            (None, None) => return Ok(None),
        };
        self.pull(k)
    }

    /// The next IMU sample (its line when known, and its row), each event
    /// before it handed to `other` first, in order; `None` when no IMU row
    /// is left, every other event having been handed over.
    ///
    /// # Errors
    /// As [`EventStream::next_event`].
    pub fn next_imu(
        &mut self,
        mut other: impl FnMut(&Located),
    ) -> Result<Option<(Option<u64>, ImuRow)>, LogError> {
        while let Some(ev) = self.next_event()? {
            match ev.event {
                Event::Imu(r) => return Ok(Some((ev.line, r))),
                _ => other(&ev),
            }
        }
        Ok(None)
    }

    /// The time of the next IMU sample, if any.
    ///
    /// # Errors
    /// As [`EventStream::next_event`].
    #[inline]
    pub fn next_imu_t(&mut self) -> Result<Option<f64>, LogError> {
        self.fill()?;
        Ok(self.times[IMU])
    }

    /// The stream with the rows of `R`'s file taken from `rows` (e.g. a
    /// [`Prefetched`] file) instead of the log's own reader. Meant for a
    /// stream not yet begun; on a begun one, the row already read stays next.
    pub fn with_rows<R: StreamedRow>(mut self, rows: impl RowSource<R> + 'a) -> Self {
        self.pulls[R::SOURCE] = pull(rows, R::event);
        self
    }
}

/// The earliest of `times` (at equal times the first) and its index; a
/// source without a head (`None`) is passed over.
fn earliest(times: &[Option<f64>]) -> Option<(usize, f64)> {
    let mut best: Option<(usize, f64)> = None;
    for (k, t) in times.iter().enumerate() {
        if let Some(t) = *t {
            if best.is_none_or(|(_, b)| t < b) {
                best = Some((k, t));
            }
        }
    }
    best
}

/// A row type [`EventStream`] merges: its place among the stream's sources
/// (ties in time go in this order) and its [`Event`].
pub trait StreamedRow: Row + 'static {
    /// Index of the file among the stream's sources.
    const SOURCE: usize;
    /// The row as an event.
    fn event(self) -> Event;
}

macro_rules! streamed_rows {
    ($($row:ty => $source:literal, $event:ident),* $(,)?) => {$(
        impl StreamedRow for $row {
            const SOURCE: usize = $source;
            fn event(self) -> Event {
                Event::$event(self)
            }
        }
    )*};
}

// The order of `EventStream::of` and `EventStream::open`.
streamed_rows! {
    AltitudeRow => 0, Altitude,
    DvlRow => 1, Dvl,
    DepthRow => 2, Depth,
    HeadingRow => 3, Heading,
    UsblRow => 4, Usbl,
    SpeedRow => 5, Speed,
    RpmRow => 6, Rpm,
    MagRow => 7, Mag,
    BaroRow => 8, Baro,
    GnssRow => 9, Gnss,
    ImuRow => 10, Imu,
}

/// A row type with its table in a [`LogDir`].
pub trait LogTable: Row + 'static {
    /// The rows of this file in `log` (`None` when the file is absent).
    fn table(log: &LogDir) -> Option<&[Self]>;
    /// The rows of this file as the log's users take them, from the rows
    /// as read with the mapping of `files`: as read, except the truth,
    /// moved to the IMU by `[files.truth] lever_arm` ([`ReferencePoint`]).
    fn as_used<'a>(
        rows: Box<dyn RowSource<Self> + 'a>,
        files: &LogFiles,
    ) -> Box<dyn RowSource<Self> + 'a> {
        let _ = files;
        rows
    }
}

impl LogTable for super::TruthRow {
    fn table(log: &LogDir) -> Option<&[Self]> {
        log.truth.as_deref()
    }
    fn as_used<'a>(
        rows: Box<dyn RowSource<Self> + 'a>,
        files: &LogFiles,
    ) -> Box<dyn RowSource<Self> + 'a> {
        match ReferencePoint::new(files.mapping().of::<Self>().lever_arm) {
            Some(point) => Box::new(AtImu::new(rows, point)),
            None => rows,
        }
    }
}

macro_rules! log_tables {
    ($($row:ty => $field:ident),* $(,)?) => {$(
        impl LogTable for $row {
            fn table(log: &LogDir) -> Option<&[Self]> {
                log.$field.as_deref()
            }
        }
    )*};
}

log_tables! {
    DvlRow => dvl,
    DepthRow => depth,
    HeadingRow => heading,
    UsblRow => usbl,
    SpeedRow => speed,
    RpmRow => rpm,
    AltitudeRow => altitude,
    super::MagRow => mag,
    super::BaroRow => baro,
    super::GnssRow => gnss,
    super::ReferenceRow => reference,
}

impl LogTable for ImuRow {
    fn table(log: &LogDir) -> Option<&[Self]> {
        Some(&log.imu)
    }
}

/// A log to replay: in memory (a simulated log, a test) or on disk (read
/// as the replay goes). Both give the same rows in the same order.
#[derive(Debug, Clone, Copy)]
pub enum LogSource<'a> {
    /// A log in memory.
    Memory(&'a LogDir),
    /// A log directory read file by file.
    Files(&'a LogFiles),
}

impl<'a> LogSource<'a> {
    /// `meta.toml`.
    pub fn meta(&self) -> &'a Meta {
        match self {
            LogSource::Memory(log) => &log.meta,
            LogSource::Files(files) => files.meta(),
        }
    }

    /// The rows of `R`'s file from the start; `None` when the file is absent.
    ///
    /// # Errors
    /// As [`LogFiles::rows`].
    pub fn rows<R: LogTable>(&self) -> Result<Option<Box<dyn RowSource<R> + 'a>>, LogError> {
        Ok(match self {
            LogSource::Memory(log) => {
                let log: &'a LogDir = log;
                R::table(log).map(|rows| Box::new(SliceRows::of(log, Some(rows))) as Box<_>)
            }
            LogSource::Files(files) => files
                .rows::<R>()?
                .map(|r| R::as_used(Box::new(super::ReadAhead::new(r)), files)),
        })
    }

    /// `imu.csv` for a replay: from a log on disk shared with a check
    /// beside the replay when the log shares it ([`LogFiles::share_imu`]).
    ///
    /// # Errors
    /// As [`LogFiles::imu`].
    pub fn imu_rows(&self) -> Result<Box<dyn RowSource<ImuRow> + 'a>, LogError> {
        Ok(match self {
            LogSource::Memory(log) => {
                let log: &'a LogDir = log;
                Box::new(SliceRows::of(log, Some(&log.imu[..])))
            }
            LogSource::Files(files) => Box::new(super::ReadAhead::new(files.imu_for_replay()?)),
        })
    }

    /// Whether the log has `R`'s file.
    ///
    /// # Errors
    /// As [`LogFiles::rows`].
    pub fn has<R: LogTable>(&self) -> Result<bool, LogError> {
        Ok(match self {
            LogSource::Memory(log) => R::table(log).is_some(),
            LogSource::Files(files) => files.rows::<R>()?.is_some(),
        })
    }

    /// The form of `imu.csv` (rates, or increments read as interval
    /// averages).
    ///
    /// # Errors
    /// As [`LogFiles::imu_form`].
    pub fn imu_form(&self) -> Result<ImuForm, LogError> {
        match self {
            LogSource::Memory(log) => Ok(log.imu_form),
            LogSource::Files(files) => files.imu_form(),
        }
    }

    /// The whole log in memory: the log itself, or every file of the log
    /// directory read as it reads them ([`LogDir::from_files`]).
    ///
    /// # Errors
    /// As [`LogDir::from_files`].
    pub fn whole(&self) -> Result<std::borrow::Cow<'a, LogDir>, LogError> {
        Ok(match self {
            LogSource::Memory(log) => std::borrow::Cow::Borrowed(*log),
            LogSource::Files(files) => std::borrow::Cow::Owned(LogDir::from_files(files)?),
        })
    }

    /// The merged sensor events from the start.
    ///
    /// # Errors
    /// As [`EventStream::open`].
    pub fn events(&self) -> Result<EventStream<'a>, LogError> {
        match self {
            LogSource::Memory(log) => Ok(EventStream::of(log)),
            LogSource::Files(files) => EventStream::open(files),
        }
    }
}
