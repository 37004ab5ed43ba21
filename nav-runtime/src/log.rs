//! The recorded-log directory format: reader, writer and a merged event stream.
//!
//! A log directory holds one CSV file per sensor (`imu.csv` required, aiding files
//! optional: a missing file means the sensor is absent), an optional `truth.csv` for
//! scoring and a required `meta.toml`:
//!
//! | file | columns |
//! |---|---|
//! | `imu.csv` | `t,gx,gy,gz,ax,ay,az` |
//! | `dvl.csv` | `t,vx,vy,vz` (empty cells = no bottom lock) |
//! | `depth.csv` | `t,depth` |
//! | `heading.csv` | `t,heading` |
//! | `usbl.csv` | `t,lat,lon,depth` |
//! | `speed.csv` | `t,speed` |
//! | `rpm.csv` | `t,rpm` |
//! | `altitude.csv` | `t,altitude` |
//! | `truth.csv` | `t,lat,lon,depth,vn,ve,vd,roll,pitch,yaw` |
//! | `mag.csv` | `t,mx,my,mz` |
//! | `baro.csv` | `t,altitude` |
//! | `gnss.csv` | `t,lat,lon,height,eph,epv,vn,ve,vd,speed_accuracy` (empty cells = not given) |
//! | `reference.csv` | `t,lat,lon,height,vn,ve,vd,roll,pitch,yaw` (another estimator's solution; empty cells = not given) |
//!
//! Columns are found by header name, in any order. `imu.csv` may carry
//! increments `t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z` instead of rates
//! ([`ImuForm`]). A `[files.<sensor>]` section of `meta.toml` may read a
//! sensor from another file, under other header names, in other units and
//! frames ([`LogMapping`]); the rows are converted on reading, so the rest of
//! the crate only sees the standard format.
//!
//! Reading validates everything: each error names the file, the 1-based line (the
//! header is line 1) and the column (or the dotted `meta.toml` key). With
//! [`Strictness::Lenient`] bad CSV rows are skipped and counted per file instead
//! (empty files, bad headers and `meta.toml` problems are always errors).
//!
//! A `.csv` file whose name is not in the table (e.g. `sonar.csv`, `IMU.CSV`) is
//! an error ([`LogError::UnknownFile`]) in strict mode, so a misnamed sensor file
//! is not silently dropped; the lenient reader ignores it and lists it in
//! [`LogDir::unknown_files`]. Files with other extensions are not looked at.
//!
//! Problems that do not stop reading are collected in [`LogDir::warnings`]:
//! unknown `meta.toml` sections, unknown files and skipped rows (lenient),
//! and, read with [`NonPhysical::Rejected`], rows of aiding files skipped as
//! non-physical readings. A symbolic link whose target is missing is an
//! error, never an absent sensor; every file read must be inside the log
//! directory once links and `..` are resolved ([`LogError::Outside`]). A
//! mapped file named `*.gz` is read through gzip. A section's `time` and
//! `axes` keys ([`TimeBase`], [`Axes`]) give times from the row index, a
//! per-file offset, the stamp of a rate sample, and a sign or permutation of
//! a sensor's axes (docs/log-format.md).
//!
//! Writing goes to a temporary sibling directory that is moved into place only once
//! every file is complete, so an error never leaves a partial log behind.

mod axes;
mod error;
#[cfg(feature = "fuzzing")]
pub mod fuzz;
mod log_file;
mod mapping;
mod meta;
mod read_ahead;
mod reference_point;
mod rejected;
mod rows;
mod shared;
mod stream;
mod time_base;
mod warning;

use std::collections::BTreeMap;
use std::fs;
use std::io::{BufWriter, Write};
use std::path::{Path, PathBuf};

pub use crate::suggestion::{closest_name, did_you_mean, TWO_EDITS_FROM};
pub use axes::Axes;
pub use error::{CsvProblem, LogError, SkippedRow};
pub use log_file::{is_gzip, open_confined, LogFile};
pub use mapping::{
    quantity, relative_log_path, BodyFrame, FileMapping, ImuForm, LogMapping, NavFrame, Quantity,
    IMU_INCREMENT_COLUMNS, MAPPED_SENSORS, STANDARD_GRAVITY,
};
pub use meta::{
    DvlCalibration, ImuNoise, Initial, InitialSigma, Meta, Mounting, SensorNoise, Sensors,
    UsblTransducer, AIDING_SENSORS, ESTIMATE_NAMES, LEVER_ARM_SIGMA_DEFAULT,
    MISALIGNMENT_SIGMA_DEFAULT, SCALE_SIGMA_DEFAULT, TIME_OFFSET_SIGMA_DEFAULT,
};
pub use read_ahead::{reading_time, ReadAhead, READ_AHEAD_ROWS};
pub use reference_point::{AtImu, ReferencePoint};
pub use rejected::{
    plausible_limit, NonPhysical, Rejected, RejectedTally, REJECTED_FLOOR, REJECTED_ONE_IN,
};
pub use rows::{
    format_f64, parse_csv, write_csv, AltitudeRow, Cell, DepthRow, DvlRow, HeadingRow, ImuRow, Row,
    RowReader, RpmRow, SpeedRow, Table, TruthRow, UsblRow, MAX_COLUMNS, MAX_SKIP_REASONS,
};
pub use rows::{BaroRow, GnssRow, MagRow, ReferenceRow};
pub use shared::{ReadStats, SharedImu};
pub use stream::{
    skipped_row_warnings, EventStream, FileRows, Located, LogFiles, LogSource, LogTable,
    Prefetched, RowSource, SliceRows, StreamedRow,
};
pub use time_base::{Stamp, TimeBase};
pub use warning::{Warning, WarningKind};

/// How the reader treats bad CSV rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strictness {
    /// The first bad row is an error.
    #[default]
    Strict,
    /// Bad rows are skipped and counted (see [`LogDir::skipped_rows`]).
    Lenient,
}

/// Name of the metadata file.
pub const META_FILE: &str = "meta.toml";

/// Every file name a log directory may contain.
pub const LOG_FILES: &[&str] = &[
    "imu.csv",
    "dvl.csv",
    "depth.csv",
    "heading.csv",
    "usbl.csv",
    "speed.csv",
    "rpm.csv",
    "altitude.csv",
    "truth.csv",
    "mag.csv",
    "baro.csv",
    "gnss.csv",
    "reference.csv",
    META_FILE,
];

/// A whole log directory in memory. Aiding sensors and truth are `None` when their
/// file is absent (a present file with only a header gives `Some(vec![])`).
#[derive(Debug, Clone, PartialEq)]
pub struct LogDir {
    /// `meta.toml`.
    pub meta: Meta,
    /// `imu.csv` (required).
    pub imu: Vec<ImuRow>,
    /// `dvl.csv`.
    pub dvl: Option<Vec<DvlRow>>,
    /// `depth.csv`.
    pub depth: Option<Vec<DepthRow>>,
    /// `heading.csv`.
    pub heading: Option<Vec<HeadingRow>>,
    /// `usbl.csv`.
    pub usbl: Option<Vec<UsblRow>>,
    /// `speed.csv`.
    pub speed: Option<Vec<SpeedRow>>,
    /// `rpm.csv`.
    pub rpm: Option<Vec<RpmRow>>,
    /// `altitude.csv`.
    pub altitude: Option<Vec<AltitudeRow>>,
    /// `truth.csv`.
    pub truth: Option<Vec<TruthRow>>,
    /// `mag.csv`.
    pub mag: Option<Vec<MagRow>>,
    /// `baro.csv`.
    pub baro: Option<Vec<BaroRow>>,
    /// `gnss.csv`.
    pub gnss: Option<Vec<GnssRow>>,
    /// `reference.csv` (another estimator's solution; like truth, not a sensor).
    pub reference: Option<Vec<ReferenceRow>>,
    /// Rows skipped by the lenient reader, per file name (files with none are absent).
    pub skipped_rows: BTreeMap<String, usize>,
    /// The first few reasons rows were skipped, over all files.
    pub skip_reasons: Vec<SkippedRow>,
    /// `.csv` files of the directory that are not log files, sorted by name,
    /// ignored by the lenient reader (the strict reader refuses them).
    pub unknown_files: Vec<String>,
    /// What the reader noticed without refusing the log: unknown `meta.toml`
    /// sections, unknown files and skipped rows (lenient reading).
    pub warnings: Vec<Warning>,
    /// The form `imu.csv` was read in: with [`ImuForm::Increments`] the
    /// rows of [`LogDir::imu`] are interval averages (increment divided by
    /// the interval ending at `t`), not instantaneous samples. Not written by
    /// [`LogDir::write`], which writes the rate columns.
    pub imu_form: ImuForm,
}

/// The `.csv` files of `dir` (extension compared without case) whose names are
/// not in [`LOG_FILES`] and that `mapping` does not read, sorted. Directories
/// are not listed.
pub fn unknown_csv_files(dir: &Path, mapping: &LogMapping) -> Result<Vec<String>, LogError> {
    let claimed = claimed_by_replay_mapping(dir);
    let mut unknown = Vec::new();
    for entry in fs::read_dir(dir).map_err(|e| LogError::io(dir, e))? {
        let entry = entry.map_err(|e| LogError::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_csv = name.len() > 4
            && name
                .get(name.len() - 4..)
                .is_some_and(|ext| ext.eq_ignore_ascii_case(".csv"));
        if !is_csv
            || LOG_FILES.contains(&name.as_str())
            || mapping.reads(&name)
            || claimed.contains(&name)
        {
            continue;
        }
        if entry.file_type().is_ok_and(|t| t.is_dir()) {
            continue;
        }
        unknown.push(name);
    }
    unknown.sort();
    Ok(unknown)
}

/// The mapping file of a log directory that feeds declared sensors by name
/// (a model replay's, or an INS vehicle's own sensors).
pub const REPLAY_MAPPING_FILE: &str = "replay.toml";

/// The files `replay.toml` in `dir` names as `[sensors.<name>] file` (its
/// declared sensors' files, which are log files too). Empty when there is
/// no such file or it is not valid TOML: the replay that reads it reports
/// that, with its line.
fn claimed_by_replay_mapping(dir: &Path) -> Vec<String> {
    let Ok(Some(mut file)) = open_confined(dir, REPLAY_MAPPING_FILE, REPLAY_MAPPING_FILE) else {
        return Vec::new();
    };
    let mut text = String::new();
    if std::io::Read::read_to_string(&mut file, &mut text).is_err() {
        return Vec::new();
    }
    let Ok(table) = text.parse::<toml::Table>() else {
        return Vec::new();
    };
    let Some(toml::Value::Table(sensors)) = table.get("sensors") else {
        return Vec::new();
    };
    sensors
        .values()
        .filter_map(|s| match s.get("file") {
            Some(toml::Value::String(f)) => Some(f.trim_start_matches("./").to_string()),
            _ => None,
        })
        .collect()
}

fn read_table<R: Row>(
    files: &LogFiles,
    required: bool,
    skipped: &mut BTreeMap<String, usize>,
    reasons: &mut Vec<SkippedRow>,
    rejected: &mut Vec<Warning>,
) -> Result<Option<Vec<R>>, LogError> {
    let reader = if required {
        Some(files.imu_like::<R>()?)
    } else {
        files.rows::<R>()?
    };
    let Some(mut reader) = reader else {
        return Ok(None);
    };
    let mut rows = Vec::new();
    while let Some((_, row)) = reader.next_row()? {
        rows.push(row);
    }
    if let Some(r) = reader.rejected() {
        rejected.push(r.warning());
    }
    if reader.skipped() > 0 {
        // Keyed by the sensor's standard file name, even when a mapping reads
        // another file (the reasons name the file read).
        skipped.insert(R::FILE.to_string(), reader.skipped());
        let room = MAX_SKIP_REASONS.saturating_sub(reasons.len());
        reasons.extend(reader.skip_reasons().iter().take(room).cloned());
    }
    Ok(Some(rows))
}

impl LogDir {
    /// An empty log (no IMU rows, no aiding sensors) with the given metadata.
    pub fn new(meta: Meta) -> Self {
        LogDir {
            meta,
            imu: Vec::new(),
            dvl: None,
            depth: None,
            heading: None,
            usbl: None,
            speed: None,
            rpm: None,
            altitude: None,
            truth: None,
            mag: None,
            baro: None,
            gnss: None,
            reference: None,
            skipped_rows: BTreeMap::new(),
            skip_reasons: Vec::new(),
            unknown_files: Vec::new(),
            warnings: Vec::new(),
            imu_form: ImuForm::Rates,
        }
    }

    /// Reads and validates a log directory (every file read whole: for a
    /// log of any length, read it as a stream with [`LogFiles`]).
    pub fn read(path: impl AsRef<Path>, strictness: Strictness) -> Result<LogDir, LogError> {
        Self::read_with(path, strictness, NonPhysical::BadRow)
    }

    /// [`LogDir::read`] with non-physical values of aiding files read as
    /// `non_physical` says ([`NonPhysical::Rejected`]: skipped rows with a
    /// warning in [`LogDir::warnings`]).
    pub fn read_with(
        path: impl AsRef<Path>,
        strictness: Strictness,
        non_physical: NonPhysical,
    ) -> Result<LogDir, LogError> {
        let files = LogFiles::open(path, strictness)?.with_non_physical(non_physical);
        Self::from_files(&files)
    }

    /// Reads every file of the log directory of `files` whole, as `files`
    /// reads them: with its meta, mapping and time offsets, which may
    /// differ from those on disk ([`LogFiles::with_meta`], as noise tuning
    /// sets them).
    pub fn from_files(files: &LogFiles) -> Result<LogDir, LogError> {
        let mut sk = BTreeMap::new();
        let mut rs = Vec::new();
        let mut rj = Vec::new();
        let imu_form = files.imu_form()?;
        let imu = read_table::<ImuRow>(files, true, &mut sk, &mut rs, &mut rj)?.unwrap_or_default();
        let mut log = LogDir {
            meta: *files.meta(),
            imu,
            dvl: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            depth: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            heading: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            usbl: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            speed: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            rpm: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            altitude: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            truth: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            mag: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            baro: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            gnss: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            reference: read_table(files, false, &mut sk, &mut rs, &mut rj)?,
            skipped_rows: sk,
            skip_reasons: rs,
            unknown_files: files.unknown_files().to_vec(),
            warnings: files.warnings().to_vec(),
            imu_form,
        };
        // The truth as its users take it: moved to the IMU, as the
        // streamed rows are (`LogTable::as_used`).
        if let (Some(truth), Some(point)) = (
            log.truth.as_mut(),
            ReferencePoint::new(files.mapping().of::<TruthRow>().lever_arm),
        ) {
            point.move_all(truth);
        }
        log.warnings.extend(rj);
        log.warnings
            .extend(skipped_row_warnings(&log.skipped_rows, &log.skip_reasons));
        Ok(log)
    }

    /// Total number of rows the lenient reader skipped.
    pub fn total_skipped_rows(&self) -> usize {
        self.skipped_rows.values().sum()
    }

    /// Writes the log to `path`: every file is written into a temporary sibling
    /// directory first and moved into place at the end, so an error leaves nothing.
    ///
    /// If `path` exists it must be a directory; log files in it that this log does not
    /// have (e.g. a stale `dvl.csv`) are removed, other files are left alone.
    pub fn write(&self, path: impl AsRef<Path>) -> Result<(), LogError> {
        let target = path.as_ref();
        if let Ok(m) = fs::metadata(target) {
            if !m.is_dir() {
                return Err(LogError::Write {
                    path: target.to_path_buf(),
                    reason: "exists and is not a directory".into(),
                });
            }
        }
        // `meta.toml` gives a sensor's mounting and `estimate` in its
        // section, which needs the sensor's noise: without it they would be
        // left out of the file without a word.
        let sensors = &self.meta.sensors;
        if let Some(name) = AIDING_SENSORS.iter().find(|n| {
            sensors.aiding(n).is_none()
                && (sensors.mounting(n).is_some() || sensors.calibration(n).any())
        }) {
            return Err(LogError::Write {
                path: target.join(META_FILE),
                reason: format!(
                    "sensor `{name}` has a mounting or an `estimate` but no noise sigmas: \
                     [sensors.{name}] needs `noise_sigma` to say them (set `meta.sensors.{name}`)"
                ),
            });
        }
        let staging = Staging::new(target)?;
        let mut written: Vec<&'static str> = Vec::new();
        let res = (|| {
            self.write_files(&staging.dir, &mut written)?;
            staging.commit(target, &written)
        })();
        if res.is_err() {
            staging.discard();
        }
        res
    }

    fn write_files(&self, dir: &Path, written: &mut Vec<&'static str>) -> Result<(), LogError> {
        fn one<R: Row>(
            dir: &Path,
            rows: Option<&[R]>,
            written: &mut Vec<&'static str>,
        ) -> Result<(), LogError> {
            let Some(rows) = rows else { return Ok(()) };
            let path = dir.join(R::FILE);
            let f = fs::File::create(&path).map_err(|e| LogError::io(&path, e))?;
            let mut w = BufWriter::new(f);
            write_csv(&mut w, rows).map_err(|e| LogError::io(&path, e))?;
            w.flush().map_err(|e| LogError::io(&path, e))?;
            written.push(R::FILE);
            Ok(())
        }
        let meta_path = dir.join(META_FILE);
        fs::write(&meta_path, self.meta.to_toml()).map_err(|e| LogError::io(&meta_path, e))?;
        written.push(META_FILE);
        one(dir, Some(&self.imu[..]), written)?;
        one(dir, self.dvl.as_deref(), written)?;
        one(dir, self.depth.as_deref(), written)?;
        one(dir, self.heading.as_deref(), written)?;
        one(dir, self.usbl.as_deref(), written)?;
        one(dir, self.speed.as_deref(), written)?;
        one(dir, self.rpm.as_deref(), written)?;
        one(dir, self.altitude.as_deref(), written)?;
        one(dir, self.truth.as_deref(), written)?;
        one(dir, self.mag.as_deref(), written)?;
        one(dir, self.baro.as_deref(), written)?;
        one(dir, self.gnss.as_deref(), written)?;
        one(dir, self.reference.as_deref(), written)?;
        Ok(())
    }

    /// All aiding and IMU samples merged in time order (truth and the
    /// reference are not included).
    ///
    /// Samples with equal times come in the order IMU, DVL, depth, heading, USBL,
    /// speed, rpm, altitude, magnetometer, barometer, GNSS, so a filter
    /// propagates to `t` before it applies aiding measurements stamped `t`.
    pub fn events(&self) -> Events<'_> {
        Events {
            log: self,
            next: [0; EVENT_SOURCES],
        }
    }

    /// Time span `(first, last)` covered by the IMU, if it has samples.
    pub fn imu_time_span(&self) -> Option<(f64, f64)> {
        Some((self.imu.first()?.t, self.imu.last()?.t))
    }
}

/// One sample of the merged event stream ([`LogDir::events`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Event {
    /// An IMU sample.
    Imu(ImuRow),
    /// A DVL sample.
    Dvl(DvlRow),
    /// A depth sample.
    Depth(DepthRow),
    /// A compass sample.
    Heading(HeadingRow),
    /// A USBL fix.
    Usbl(UsblRow),
    /// A speed-log sample.
    Speed(SpeedRow),
    /// A propeller rpm sample.
    Rpm(RpmRow),
    /// An echo-sounder sample.
    Altitude(AltitudeRow),
    /// A magnetometer sample.
    Mag(MagRow),
    /// A barometer sample.
    Baro(BaroRow),
    /// A GNSS fix.
    Gnss(GnssRow),
}

/// Number of sensor files merged by [`LogDir::events`].
const EVENT_SOURCES: usize = 11;

impl Event {
    /// Time of the event, s.
    pub fn t(&self) -> f64 {
        match self {
            Event::Imu(r) => r.t,
            Event::Dvl(r) => r.t,
            Event::Depth(r) => r.t,
            Event::Heading(r) => r.t,
            Event::Usbl(r) => r.t,
            Event::Speed(r) => r.t,
            Event::Rpm(r) => r.t,
            Event::Altitude(r) => r.t,
            Event::Mag(r) => r.t,
            Event::Baro(r) => r.t,
            Event::Gnss(r) => r.t,
        }
    }
}

/// Iterator over the merged, time-ordered samples of a [`LogDir`].
#[derive(Debug, Clone)]
pub struct Events<'a> {
    log: &'a LogDir,
    next: [usize; EVENT_SOURCES],
}

impl Events<'_> {
    fn head(&self, k: usize) -> Option<Event> {
        let l = self.log;
        let i = self.next[k];
        fn at<R: Copy>(v: Option<&Vec<R>>, i: usize) -> Option<R> {
            v.and_then(|v| v.get(i).copied())
        }
        match k {
            0 => l.imu.get(i).copied().map(Event::Imu),
            1 => at(l.dvl.as_ref(), i).map(Event::Dvl),
            2 => at(l.depth.as_ref(), i).map(Event::Depth),
            3 => at(l.heading.as_ref(), i).map(Event::Heading),
            4 => at(l.usbl.as_ref(), i).map(Event::Usbl),
            5 => at(l.speed.as_ref(), i).map(Event::Speed),
            6 => at(l.rpm.as_ref(), i).map(Event::Rpm),
            7 => at(l.altitude.as_ref(), i).map(Event::Altitude),
            8 => at(l.mag.as_ref(), i).map(Event::Mag),
            9 => at(l.baro.as_ref(), i).map(Event::Baro),
            _ => at(l.gnss.as_ref(), i).map(Event::Gnss),
        }
    }
}

impl Iterator for Events<'_> {
    type Item = Event;

    fn next(&mut self) -> Option<Event> {
        let mut best: Option<(usize, Event)> = None;
        for k in 0..EVENT_SOURCES {
            if let Some(e) = self.head(k) {
                let earlier = match &best {
                    None => true,
                    Some((_, b)) => e.t() < b.t(),
                };
                if earlier {
                    best = Some((k, e));
                }
            }
        }
        let (k, e) = best?;
        self.next[k] += 1;
        Some(e)
    }
}

/// An error if `path` is a symbolic link whose target does not exist (the
/// sensor must not silently vanish); `Ok` when there is nothing at `path`.
fn dangling_link(path: &Path) -> Result<(), LogError> {
    match fs::symlink_metadata(path) {
        Ok(m) if m.file_type().is_symlink() => {
            let target = fs::read_link(path)
                .map(|t| t.display().to_string())
                .unwrap_or_else(|_| "?".into());
            Err(LogError::io(
                path,
                std::io::Error::new(
                    std::io::ErrorKind::NotFound,
                    format!("symbolic link to `{target}`, which does not exist"),
                ),
            ))
        }
        _ => Ok(()),
    }
}

/// A temporary sibling directory that becomes the target on commit.
struct Staging {
    dir: PathBuf,
}

impl Staging {
    fn new(target: &Path) -> Result<Staging, LogError> {
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "log".into());
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        if !parent.is_dir() {
            fs::create_dir_all(&parent).map_err(|e| LogError::io(&parent, e))?;
        }
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.subsec_nanos())
            .unwrap_or(0);
        let dir = parent.join(format!(".{name}.partial-{}-{nanos}", std::process::id()));
        fs::create_dir(&dir).map_err(|e| LogError::io(&dir, e))?;
        Ok(Staging { dir })
    }

    fn commit(&self, target: &Path, written: &[&str]) -> Result<(), LogError> {
        if !target.exists() {
            return fs::rename(&self.dir, target).map_err(|e| LogError::io(target, e));
        }
        for name in LOG_FILES {
            let old = target.join(name);
            if !written.contains(name) && old.exists() {
                fs::remove_file(&old).map_err(|e| LogError::io(&old, e))?;
            }
        }
        for name in written {
            let to = target.join(name);
            fs::rename(self.dir.join(name), &to).map_err(|e| LogError::io(&to, e))?;
        }
        fs::remove_dir(&self.dir).map_err(|e| LogError::io(&self.dir, e))
    }

    fn discard(&self) {
        let _ = fs::remove_dir_all(&self.dir);
    }
}
