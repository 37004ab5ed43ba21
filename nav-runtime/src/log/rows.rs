//! Typed CSV rows and the CSV reader/writer shared by every log file.

use std::collections::{HashMap, HashSet};
use std::io::{BufRead, BufReader, Read, Write};

use super::error::{CsvProblem, LogError, SkippedRow};
use super::mapping::{FileMapping, ImuForm, IMU_INCREMENT_COLUMNS};
use super::rejected::{
    plausible_limit, NonPhysical, Rejected, RejectedTally, REJECTED_FLOOR, REJECTED_ONE_IN,
};
use super::time_base::TimeBase;
use super::Strictness;

/// The most columns a log file's header may have. A sensor file has at most
/// a few dozen (a mapped file of another tool with its ignored columns a few
/// hundred); a longer header is refused before any of it is looked at by
/// name, so its cost is one pass over its bytes.
pub const MAX_COLUMNS: usize = 4096;

/// Whether `R`'s file is an aiding sensor's, whose non-physical readings
/// are rejected rows rather than errors (not the IMU, truth or reference).
fn is_aiding<R: Row>() -> bool {
    !matches!(R::FILE, "imu.csv" | "truth.csv" | "reference.csv")
}

/// A value of one CSV cell: `f64` (a value is required) or `Option<f64>` (an empty
/// cell means "no value", e.g. DVL without bottom lock).
pub trait Cell: Copy {
    /// Builds the value from a parsed cell (`None` = empty cell); `None` if not allowed.
    fn from_cell(cell: Option<f64>) -> Option<Self>;
    /// The cell to write (`None` = empty cell).
    fn to_cell(self) -> Option<f64>;
}

impl Cell for f64 {
    fn from_cell(cell: Option<f64>) -> Option<Self> {
        cell
    }
    fn to_cell(self) -> Option<f64> {
        Some(self)
    }
}

impl Cell for Option<f64> {
    fn from_cell(cell: Option<f64>) -> Option<Self> {
        Some(cell)
    }
    fn to_cell(self) -> Option<f64> {
        self
    }
}

/// One row of a log CSV file.
pub trait Row: Copy + std::fmt::Debug + PartialEq {
    /// File name inside the log directory (e.g. `imu.csv`).
    const FILE: &'static str;
    /// Column names, in order; the first is always `t`.
    const COLUMNS: &'static [&'static str];
    /// Time of the row, seconds.
    fn t(&self) -> f64;
    /// Builds the row from parsed cells (one per column, `None` = empty); on failure the
    /// index of the offending column.
    fn from_cells(cells: &[Option<f64>]) -> Result<Self, usize>;
    /// The row's cells, one per column.
    fn to_cells(&self) -> Vec<Option<f64>>;
    /// Range checks beyond "finite": the offending column index and the allowed range.
    fn check(&self) -> Result<(), (usize, f64, &'static str)> {
        Ok(())
    }
}

macro_rules! rows {
    ($(
        $(#[$doc:meta])*
        $name:ident, $file:literal { $($(#[$fdoc:meta])* $field:ident : $ty:ty),+ $(,)? }
    )*) => {$(
        $(#[$doc])*
        #[derive(Debug, Clone, Copy, PartialEq)]
        pub struct $name {
            $($(#[$fdoc])* pub $field: $ty,)+
        }

        impl $name {
            #[allow(clippy::too_many_arguments)]
            #[doc = concat!("Builds a `", stringify!($name), "` from its fields, in column order.")]
            pub fn new($($field: $ty),+) -> Self {
                Self { $($field),+ }
            }
        }

        impl Row for $name {
            const FILE: &'static str = $file;
            const COLUMNS: &'static [&'static str] = &[$(stringify!($field)),+];
            fn t(&self) -> f64 {
                self.t
            }
            #[allow(unused_assignments)]
            fn from_cells(cells: &[Option<f64>]) -> Result<Self, usize> {
                let mut i = 0usize;
                Ok(Self {
                    $($field: {
                        let v = <$ty as Cell>::from_cell(cells[i]).ok_or(i)?;
                        i += 1;
                        v
                    },)+
                })
            }
            fn to_cells(&self) -> Vec<Option<f64>> {
                vec![$(Cell::to_cell(self.$field)),+]
            }
            fn check(&self) -> Result<(), (usize, f64, &'static str)> {
                RangeCheck::range_check(self)
            }
        }
    )*};
}

/// Per-row range checks (implemented for every row type; most have none).
trait RangeCheck {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        Ok(())
    }
}

rows! {
    /// `imu.csv`: gyro (rad/s) and specific force (m/s^2), body frame FRD.
    ImuRow, "imu.csv" {
        /// Time, s.
        t: f64,
        /// Angular rate about x, rad/s.
        gx: f64,
        /// Angular rate about y, rad/s.
        gy: f64,
        /// Angular rate about z, rad/s.
        gz: f64,
        /// Specific force along x, m/s^2.
        ax: f64,
        /// Specific force along y, m/s^2.
        ay: f64,
        /// Specific force along z, m/s^2.
        az: f64,
    }
    /// `dvl.csv`: body-frame velocity over ground, m/s; `None` = no bottom lock.
    DvlRow, "dvl.csv" {
        /// Time, s.
        t: f64,
        /// Forward velocity, m/s.
        vx: Option<f64>,
        /// Starboard velocity, m/s.
        vy: Option<f64>,
        /// Downward velocity, m/s.
        vz: Option<f64>,
    }
    /// `depth.csv`: depth, m, positive down.
    DepthRow, "depth.csv" {
        /// Time, s.
        t: f64,
        /// Depth, m.
        depth: f64,
    }
    /// `heading.csv`: magnetic compass heading, rad.
    HeadingRow, "heading.csv" {
        /// Time, s.
        t: f64,
        /// Heading, rad.
        heading: f64,
    }
    /// `usbl.csv`: position fix of the vehicle.
    UsblRow, "usbl.csv" {
        /// Time, s.
        t: f64,
        /// Latitude, rad.
        lat: f64,
        /// Longitude, rad.
        lon: f64,
        /// Depth, m.
        depth: f64,
    }
    /// `speed.csv`: forward speed log, m/s.
    SpeedRow, "speed.csv" {
        /// Time, s.
        t: f64,
        /// Forward speed, m/s.
        speed: f64,
    }
    /// `rpm.csv`: propeller revolutions per minute.
    RpmRow, "rpm.csv" {
        /// Time, s.
        t: f64,
        /// Revolutions per minute.
        rpm: f64,
    }
    /// `altitude.csv`: echo sounder, m above the sea floor.
    AltitudeRow, "altitude.csv" {
        /// Time, s.
        t: f64,
        /// Altitude, m.
        altitude: f64,
    }
    /// `truth.csv`: reference trajectory for scoring.
    TruthRow, "truth.csv" {
        /// Time, s.
        t: f64,
        /// Latitude, rad.
        lat: f64,
        /// Longitude, rad.
        lon: f64,
        /// Depth, m.
        depth: f64,
        /// North velocity, m/s.
        vn: f64,
        /// East velocity, m/s.
        ve: f64,
        /// Down velocity, m/s.
        vd: f64,
        /// Roll, rad.
        roll: f64,
        /// Pitch, rad.
        pitch: f64,
        /// Yaw, rad.
        yaw: f64,
    }
    /// `mag.csv`: magnetometer, gauss, body frame FRD.
    MagRow, "mag.csv" {
        /// Time, s.
        t: f64,
        /// Field along x (forward), gauss.
        mx: f64,
        /// Field along y (right), gauss.
        my: f64,
        /// Field along z (down), gauss.
        mz: f64,
    }
    /// `baro.csv`: barometric altitude, m above mean sea level, positive up.
    BaroRow, "baro.csv" {
        /// Time, s.
        t: f64,
        /// Barometric altitude, m.
        altitude: f64,
    }
    /// `gnss.csv`: GNSS receiver fix; the accuracy and velocity cells are
    /// empty when the receiver does not give them.
    GnssRow, "gnss.csv" {
        /// Time, s.
        t: f64,
        /// Latitude, rad.
        lat: f64,
        /// Longitude, rad.
        lon: f64,
        /// Height, m, positive up.
        height: f64,
        /// Horizontal position accuracy (1 sigma), m.
        eph: Option<f64>,
        /// Vertical position accuracy (1 sigma), m.
        epv: Option<f64>,
        /// North velocity, m/s.
        vn: Option<f64>,
        /// East velocity, m/s.
        ve: Option<f64>,
        /// Down velocity, m/s.
        vd: Option<f64>,
        /// Speed accuracy (1 sigma), m/s.
        speed_accuracy: Option<f64>,
    }
    /// `reference.csv`: another estimator's solution (e.g. PX4's own), for
    /// comparison only; a group of columns it does not have is left empty.
    ReferenceRow, "reference.csv" {
        /// Time, s.
        t: f64,
        /// Latitude, rad.
        lat: Option<f64>,
        /// Longitude, rad.
        lon: Option<f64>,
        /// Height, m, positive up.
        height: Option<f64>,
        /// North velocity, m/s.
        vn: Option<f64>,
        /// East velocity, m/s.
        ve: Option<f64>,
        /// Down velocity, m/s.
        vd: Option<f64>,
        /// Roll, rad.
        roll: Option<f64>,
        /// Pitch, rad.
        pitch: Option<f64>,
        /// Yaw, rad.
        yaw: Option<f64>,
    }
}

impl DvlRow {
    /// The velocity, if all three components are present (bottom lock).
    pub fn velocity(&self) -> Option<[f64; 3]> {
        Some([self.vx?, self.vy?, self.vz?])
    }
}

pub(crate) const LAT_RANGE: &str = "|lat| <= pi/2";
pub(crate) const LON_RANGE: &str = "|lon| <= 2 pi";

pub(crate) fn check_lat_lon(lat: f64, lon: f64) -> Result<(), (usize, f64, &'static str)> {
    if lat.abs() > core::f64::consts::FRAC_PI_2 {
        return Err((1, lat, LAT_RANGE));
    }
    if lon.abs() > 2.0 * core::f64::consts::PI {
        return Err((2, lon, LON_RANGE));
    }
    Ok(())
}

impl RangeCheck for ImuRow {}
impl RangeCheck for DvlRow {}
impl RangeCheck for DepthRow {}
impl RangeCheck for HeadingRow {}
impl RangeCheck for SpeedRow {}
impl RangeCheck for RpmRow {}
impl RangeCheck for UsblRow {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        check_lat_lon(self.lat, self.lon)
    }
}
impl From<&crate::trajectory::TruthState> for TruthRow {
    /// The `truth.csv` row of a simulated truth sample.
    fn from(s: &crate::trajectory::TruthState) -> Self {
        TruthRow::new(
            s.t,
            s.lat,
            s.lon,
            s.depth(),
            s.v_n.x,
            s.v_n.y,
            s.v_n.z,
            s.euler.roll,
            s.euler.pitch,
            s.euler.yaw,
        )
    }
}

impl GnssRow {
    /// The fix a receiver reports for an antenna at `antenna` (body axes
    /// from the IMU, m) of the simulated truth sample `s`, its north, east
    /// and height moved by `noise` (m); no receiver accuracy columns.
    pub fn of_antenna(
        s: &crate::trajectory::TruthState,
        antenna: &nalgebra::Vector3<f64>,
        noise: [f64; 3],
    ) -> Self {
        use crate::earth::{meridian_radius, transverse_radius};
        let arm = s.c_bn * antenna;
        let (rm, rn) = (meridian_radius(s.lat) + s.h, transverse_radius(s.lat) + s.h);
        let (north, east) = (arm.x + noise[0], arm.y + noise[1]);
        GnssRow::new(
            s.t,
            s.lat + north / rm,
            s.lon + east / (rn * s.lat.cos()),
            s.h - arm.z + noise[2],
            None,
            None,
            None,
            None,
            None,
            None,
        )
    }
}

impl RangeCheck for TruthRow {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        check_lat_lon(self.lat, self.lon)
    }
}
impl RangeCheck for MagRow {}
impl RangeCheck for BaroRow {}
impl RangeCheck for GnssRow {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        check_lat_lon(self.lat, self.lon)?;
        for (i, v) in [(4, self.eph), (5, self.epv), (9, self.speed_accuracy)] {
            if let Some(v) = v.filter(|v| *v < 0.0) {
                return Err((i, v, "accuracy >= 0"));
            }
        }
        Ok(())
    }
}
impl RangeCheck for ReferenceRow {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        check_lat_lon(self.lat.unwrap_or(0.0), self.lon.unwrap_or(0.0))
    }
}
impl ReferenceRow {
    /// Latitude, longitude (rad) and height (m), when all three are present.
    pub fn position(&self) -> Option<[f64; 3]> {
        Some([self.lat?, self.lon?, self.height?])
    }
    /// North, east, down velocity (m/s), when all three are present.
    pub fn velocity(&self) -> Option<[f64; 3]> {
        Some([self.vn?, self.ve?, self.vd?])
    }
    /// Roll, pitch, yaw (rad), when all three are present.
    pub fn attitude(&self) -> Option<[f64; 3]> {
        Some([self.roll?, self.pitch?, self.yaw?])
    }
}
impl RangeCheck for AltitudeRow {
    fn range_check(&self) -> Result<(), (usize, f64, &'static str)> {
        if self.altitude < 0.0 {
            return Err((1, self.altitude, "altitude >= 0"));
        }
        Ok(())
    }
}

/// The rows of one CSV file and what the lenient reader skipped.
#[derive(Debug, Clone, PartialEq)]
pub struct Table<R> {
    /// Accepted rows, strictly increasing in `t`.
    pub rows: Vec<R>,
    /// Number of rows skipped (lenient mode only; always 0 when strict).
    pub skipped: usize,
    /// The first few reasons rows were skipped (at most [`MAX_SKIP_REASONS`]).
    pub skip_reasons: Vec<SkippedRow>,
}

/// How many skip reasons a [`Table`] keeps.
pub const MAX_SKIP_REASONS: usize = 16;

fn cell_text(bytes: &[u8]) -> String {
    const MAX: usize = 40;
    let s = String::from_utf8_lossy(bytes);
    if s.chars().count() > MAX {
        let mut t: String = s.chars().take(MAX).collect();
        t.push_str("...");
        t
    } else {
        s.into_owned()
    }
}

/// Lines of a reader with their 1-based numbers; blank (whitespace-only) lines are
/// skipped, a trailing `\r` is removed.
struct Lines<R> {
    reader: R,
    line: u64,
    buf: Vec<u8>,
}

impl<R: BufRead> Lines<R> {
    fn next_line(&mut self) -> std::io::Result<Option<u64>> {
        loop {
            self.buf.clear();
            if self.reader.read_until(b'\n', &mut self.buf)? == 0 {
                return Ok(None);
            }
            self.line += 1;
            while matches!(self.buf.last(), Some(b'\n' | b'\r')) {
                self.buf.pop();
            }
            // A line that starts with a printable byte is not blank (the
            // common case, decided without scanning the line).
            let starts_printable = self.buf.first().is_some_and(|b| !b.is_ascii_whitespace());
            if starts_printable || !self.buf.iter().all(u8::is_ascii_whitespace) {
                return Ok(Some(self.line));
            }
        }
    }
}

/// Splits a line at commas and trims ASCII whitespace around each cell.
fn split_cells(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    let mut start = 0;
    let mut commas = memchr::memchr_iter(b',', line);
    let mut done = false;
    std::iter::from_fn(move || {
        if done {
            return None;
        }
        let end = commas.next().unwrap_or_else(|| {
            done = true;
            line.len()
        });
        let cell = line[start..end].trim_ascii();
        start = end + 1;
        Some(cell)
    })
}

/// Parses one CSV file of row type `R` from a reader: [`RowReader`] read to
/// the end, every accepted row kept.
///
/// The format is plain comma-separated text without quoting. The header names
/// the columns of [`Row::COLUMNS`], in any order, and no others (spaces around
/// names and a UTF-8 byte order mark are ignored); `imu.csv` may name the
/// increment columns instead ([`RowReader`]). Blank lines are ignored but counted, so line numbers are those of the
/// file. In [`Strictness::Strict`] the first bad row is an error; in
/// [`Strictness::Lenient`] bad rows are skipped and counted. An empty file or a bad
/// header is an error in both modes.
pub fn parse_csv<R: Row>(reader: impl Read, strictness: Strictness) -> Result<Table<R>, LogError> {
    let mut rows = RowReader::<R, _>::new(reader, strictness)?;
    let mut kept = Vec::new();
    while let Some((_, row)) = rows.next_row()? {
        kept.push(row);
    }
    Ok(Table {
        rows: kept,
        skipped: rows.skipped,
        skip_reasons: rows.skip_reasons,
    })
}

/// One CSV file of row type `R` read a row at a time (the streaming form of
/// [`parse_csv`], with the same checks and the same errors): memory does not
/// grow with the file.
///
/// Columns are found by header name, in any order ([`RowReader::new`]: the
/// standard names; [`RowReader::with_mapping`]: the names, units and frames
/// of a `[files.<sensor>]` section). Rows come out in the standard units and
/// frames. `imu.csv` may carry increments instead of rates (see
/// [`ImuForm::Increments`]): each row then comes out as the average rates
/// over its interval, the increments divided by the interval; the first
/// row's interval is taken to be as long as the second row's.
pub struct RowReader<R: Row, I: Read> {
    lines: Lines<BufReader<I>>,
    strictness: Strictness,
    file: String,
    /// Header text of each file column.
    header: Vec<String>,
    /// The standard column each file column is read into (`None`: ignored).
    slot: Vec<Option<usize>>,
    /// Header name of each standard column.
    names: Vec<String>,
    /// Factor to the standard unit and frame of each standard column.
    scale: Vec<f64>,
    form: ImuForm,
    /// Where the times come from.
    time: TimeBase,
    /// An aiding sensor's file: non-physical readings are rejected rows.
    aiding: bool,
    /// Data lines read so far (every non-blank line after the header).
    data_rows: u64,
    /// Rows rejected as non-physical readings.
    rejected: Option<Rejected>,
    /// Where rejected rows are reported too.
    tally: Option<RejectedTally>,
    /// Work of the header check ([`RowReader::header_work`]).
    header_work: usize,
    cells: Vec<Option<f64>>,
    previous_t: Option<f64>,
    previous: Option<R>,
    skipped: usize,
    skip_reasons: Vec<SkippedRow>,
    accepted: usize,
    min_step: Vec<f64>,
    last_value: Vec<Option<f64>>,
    increments: Increments,
}

/// Where the increment form is in its file.
#[derive(Debug, Default)]
struct Increments {
    /// The first row has been read.
    started: bool,
    /// A row read ahead (to know the first interval), with its line.
    held: Option<(u64, Vec<Option<f64>>)>,
    /// Time of the last row returned.
    last_t: f64,
    /// Interval of the last row returned.
    last_dt: f64,
    /// Rows skipped when the last row was returned.
    skipped_then: usize,
    /// A buffer of cells.
    spare: Vec<Option<f64>>,
}

impl<R: Row, I: Read> std::fmt::Debug for RowReader<R, I> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RowReader")
            .field("file", &self.file)
            .field("form", &self.form)
            .field("line", &self.lines.line)
            .field("accepted", &self.accepted)
            .field("skipped", &self.skipped)
            .finish()
    }
}

/// The increment-form columns of `R`'s file, if it has that form.
fn increment_columns<R: Row>() -> Option<&'static [&'static str]> {
    (R::FILE == ImuRow::FILE).then_some(IMU_INCREMENT_COLUMNS)
}

impl<R: Row, I: Read> RowReader<R, I> {
    /// Reads and checks the header of `R`'s file in the standard format
    /// (standard names in any order, SI units, FRD and NED frames).
    ///
    /// # Errors
    /// An empty file, a missing column, a column that is not `R`'s.
    pub fn new(reader: I, strictness: Strictness) -> Result<Self, LogError> {
        Self::with_mapping(reader, strictness, &FileMapping::standard::<R>())
    }

    /// Reads and checks the header of a file read as `mapping` says (its
    /// header names, units, frames, ignored columns and IMU form); errors
    /// name `mapping.file`.
    ///
    /// # Errors
    /// An empty file, a missing column (naming the `meta.toml` key that named
    /// it, if any), a column neither read nor ignored.
    pub fn with_mapping(
        reader: I,
        strictness: Strictness,
        mapping: &FileMapping,
    ) -> Result<Self, LogError> {
        let file = mapping.file.clone();
        let mut lines = Lines {
            reader: BufReader::new(reader),
            line: 0,
            buf: Vec::new(),
        };
        let from_index = mapping.time.from_index;
        // Header name and factor of each standard column (another axis of
        // the file with `axes`).
        let sources = |columns: &[&str]| -> Vec<(String, f64)> {
            columns
                .iter()
                .map(|c| {
                    let (from, factor) = mapping.source(c);
                    (mapping.header_name(&from).to_string(), factor)
                })
                .collect()
        };
        let names_of = |columns: &[&str]| -> Vec<String> {
            sources(columns).into_iter().map(|s| s.0).collect()
        };
        // The header a file should have, for messages (no time column when
        // times come from the row index).
        let expected_of = |names: &[String]| -> String {
            let skip = usize::from(from_index);
            names[skip..].join(",")
        };
        let rate_names = names_of(R::COLUMNS);
        let Some(header_line) = lines.next_line().map_err(|e| LogError::io(&file, e))? else {
            let expected = match (mapping.form, increment_columns::<R>()) {
                (Some(ImuForm::Increments), Some(c)) => expected_of(&names_of(c)),
                _ => expected_of(&rate_names),
            };
            return Err(LogError::EmptyFile { file, expected });
        };
        let header_bytes = lines
            .buf
            .strip_prefix(b"\xEF\xBB\xBF")
            .unwrap_or(&lines.buf);
        // Counted before anything is built from the header: the cost of a
        // refused header is one pass over its bytes.
        let ncols = memchr::memchr_iter(b',', header_bytes).count() + 1;
        if ncols > MAX_COLUMNS {
            return Err(LogError::Csv {
                file,
                line: header_line,
                column: format!("<column {}>", MAX_COLUMNS + 1),
                problem: CsvProblem::TooManyColumns {
                    found: ncols,
                    limit: MAX_COLUMNS,
                },
            });
        }
        let header: Vec<String> = split_cells(header_bytes)
            .map(|c| String::from_utf8_lossy(c).into_owned())
            .collect();
        // Each header name to its first column: one pass, then lookups, so
        // the header costs time linear in its length.
        let mut work = header.len();
        let mut index: HashMap<&str, usize> = HashMap::with_capacity(header.len());
        for (j, h) in header.iter().enumerate().rev() {
            index.insert(h.as_str(), j);
        }
        let has = |name: &String| index.contains_key(name.as_str());
        let form = match (mapping.form, increment_columns::<R>()) {
            (_, None) => ImuForm::Rates,
            (Some(form), _) => form,
            (None, Some(inc)) => {
                let inc = names_of(inc);
                work += rate_names.len() + inc.len();
                if !rate_names[1..].iter().any(has) && inc[1..].iter().any(has) {
                    ImuForm::Increments
                } else {
                    ImuForm::Rates
                }
            }
        };
        let standard: &[&str] = match (form, increment_columns::<R>()) {
            (ImuForm::Increments, Some(c)) => c,
            _ => R::COLUMNS,
        };
        let sourced = sources(standard);
        let names: Vec<String> = sourced.iter().map(|s| s.0.clone()).collect();
        let expected = expected_of(&names);
        let mut slot = vec![None; header.len()];
        for (i, name) in names.iter().enumerate() {
            if i == 0 && from_index {
                continue;
            }
            work += 1;
            match index.get(name.as_str()) {
                Some(&j) => {
                    if slot[j].is_some() {
                        // Two standard columns read from one file column
                        // (cannot happen with a valid mapping).
                        return Err(LogError::Csv {
                            file,
                            line: header_line,
                            column: name.clone(),
                            problem: CsvProblem::DuplicateColumn { name: name.clone() },
                        });
                    }
                    slot[j] = Some(i);
                }
                None => {
                    let problem = if mapping.renamed(standard[i]) {
                        CsvProblem::MissingColumn {
                            key: mapping.key(&format!("columns.{}", standard[i])),
                            expected,
                        }
                    } else {
                        CsvProblem::WrongHeader {
                            expected,
                            found: header.get(i).map(|h| short(h)).unwrap_or_default(),
                        }
                    };
                    return Err(LogError::Csv {
                        file,
                        line: header_line,
                        column: name.clone(),
                        problem,
                    });
                }
            }
        }
        // A column read twice by name: which of the two is meant?
        for (j, h) in header.iter().enumerate() {
            work += 1;
            if slot[j].is_none()
                && index
                    .get(h.as_str())
                    .is_some_and(|&first| slot[first].is_some())
            {
                return Err(LogError::Csv {
                    file,
                    line: header_line,
                    column: short(h),
                    problem: CsvProblem::DuplicateColumn { name: short(h) },
                });
            }
        }
        // A column both read and listed to be read past: which is meant?
        let read: HashSet<&str> = (0..header.len())
            .filter(|&j| slot[j].is_some())
            .map(|j| header[j].as_str())
            .collect();
        work += header.len();
        if let Some(name) = mapping.ignore.iter().find(|n| read.contains(n.as_str())) {
            return Err(LogError::Meta {
                key: mapping.key("ignore"),
                line: None,
                problem: format!(
                    "`{}` is a column the file's mapping reads: a column is read or ignored, \
                     not both",
                    short(name)
                ),
            });
        }
        let ignore: HashSet<&str> = mapping.ignore.iter().map(String::as_str).collect();
        work += mapping.ignore.len();
        let mut unknown = (0..header.len())
            .filter(|&j| slot[j].is_none() && !ignore.contains(header[j].as_str()));
        work += header.len();
        if let Some(j) = unknown.next() {
            let (column, problem) = if mapping.declared {
                const LISTED: usize = 8;
                let mut names = vec![short(&header[j])];
                names.extend(unknown.by_ref().take(LISTED - 1).map(|j| short(&header[j])));
                let more = unknown.count();
                (
                    short(&header[j]),
                    CsvProblem::UnknownColumns {
                        names,
                        key: mapping.key("ignore"),
                        more,
                    },
                )
            } else {
                (
                    format!("<column {}>", j + 1),
                    CsvProblem::WrongHeader {
                        expected,
                        found: short(&header[j]),
                    },
                )
            };
            return Err(LogError::Csv {
                file,
                line: header_line,
                column,
                problem,
            });
        }
        let n = standard.len();
        Ok(RowReader {
            lines,
            strictness,
            file,
            header,
            slot,
            names,
            scale: sourced.iter().map(|s| s.1).collect(),
            form,
            time: mapping.time,
            aiding: false,
            data_rows: 0,
            rejected: None,
            tally: None,
            header_work: work,
            cells: vec![None; n],
            previous_t: None,
            previous: None,
            skipped: 0,
            skip_reasons: Vec::new(),
            accepted: 0,
            min_step: vec![f64::INFINITY; n],
            last_value: vec![None; n],
            increments: Increments::default(),
        })
    }

    /// Sets how non-physical values of an aiding sensor's file are treated
    /// (the IMU, truth and reference files are never aiding files).
    pub fn non_physical(mut self, how: NonPhysical) -> Self {
        self.aiding = how == NonPhysical::Rejected && is_aiding::<R>();
        self
    }

    /// Reports the rows this reader rejects as non-physical readings to
    /// `tally` too (see [`RejectedTally`]).
    pub fn reporting_to(mut self, tally: RejectedTally) -> Self {
        self.tally = Some(tally);
        self
    }

    /// The header cells and name lookups the header check took: linear in
    /// the header's length (a measure of work for the tests, which must not
    /// time it).
    pub fn header_work(&self) -> usize {
        self.header_work
    }

    /// The next accepted row with its 1-based line number; `None` at the end
    /// of the file. Lenient reading skips (and counts) bad rows.
    ///
    /// # Errors
    /// A read error, or (strict) the first bad row, naming file, line and column.
    pub fn next_row(&mut self) -> Result<Option<(u64, R)>, LogError> {
        if self.form == ImuForm::Increments {
            return self.next_increment_row();
        }
        match self.next_checked()? {
            Some(line) => {
                let cells = std::mem::take(&mut self.cells);
                let row = self.emit(line, &cells);
                self.cells = cells;
                Ok(Some(row))
            }
            None => Ok(None),
        }
    }

    /// The next row of the increment form, divided by its interval.
    fn next_increment_row(&mut self) -> Result<Option<(u64, R)>, LogError> {
        let mut cells = std::mem::take(&mut self.increments.spare);
        loop {
            let (line, dt) = if !self.increments.started {
                self.increments.started = true;
                let Some(first) = self.next_checked()? else {
                    return Ok(None);
                };
                cells.clone_from(&self.cells);
                let Some(second) = self.next_checked()? else {
                    self.reject(first, self.names[0].clone(), CsvProblem::NoInterval)?;
                    return Ok(None);
                };
                // The first row's interval is taken as long as the second's.
                let dt = self.cells[0].unwrap_or_default() - cells[0].unwrap_or_default();
                self.increments.held = Some((second, self.cells.clone()));
                self.increments.last_dt = dt;
                (first, dt)
            } else {
                let line = match self.increments.held.take() {
                    Some((line, held)) => {
                        cells = held;
                        line
                    }
                    None => match self.next_checked()? {
                        Some(line) => {
                            cells.clone_from(&self.cells);
                            line
                        }
                        None => return Ok(None),
                    },
                };
                // After a skipped row this row's interval is not known: it is
                // taken as long as the previous one (the rate is held over
                // the gap).
                let dt = if self.skipped > self.increments.skipped_then {
                    self.increments.last_dt
                } else {
                    cells[0].unwrap_or_default() - self.increments.last_t
                };
                (line, dt)
            };
            let t = cells[0].unwrap_or_default();
            let too_large =
                (1..cells.len()).find(|&i| cells[i].is_some_and(|v| !(v / dt).is_finite()));
            if let Some(i) = too_large {
                let value = cells[i].unwrap_or_default();
                self.increments.last_t = t;
                self.reject(
                    line,
                    self.names[i].clone(),
                    CsvProblem::OutOfRange {
                        value,
                        allowed: "increment / interval finite",
                    },
                )?;
                continue;
            }
            for c in cells.iter_mut().skip(1) {
                *c = c.map(|v| v / dt);
            }
            self.increments.last_t = t;
            self.increments.last_dt = dt;
            self.increments.skipped_then = self.skipped;
            let row = self.emit(line, &cells);
            self.increments.spare = cells;
            return Ok(Some(row));
        }
    }

    /// Counts a returned row: resolution and last row.
    fn emit(&mut self, line: u64, cells: &[Option<f64>]) -> (u64, R) {
        // The cells were accepted by `parse_row`, so the row builds.
        let row = match R::from_cells(cells) {
            Ok(row) => row,
            Err(_) => unreachable!("accepted cells build a row"),
        };
        self.accepted += 1;
        self.previous = Some(row);
        for (i, cell) in cells.iter().enumerate().skip(1) {
            let Some(v) = *cell else { continue };
            if let Some(last) = self.last_value[i] {
                let d = (v - last).abs();
                if d > 0.0 && d.is_finite() && d < self.min_step[i] {
                    self.min_step[i] = d;
                }
            }
            self.last_value[i] = Some(v);
        }
        (line, row)
    }

    /// Skips (lenient) or refuses (strict) a row.
    fn reject(&mut self, line: u64, column: String, problem: CsvProblem) -> Result<(), LogError> {
        let skipped = SkippedRow {
            file: self.file.clone(),
            line,
            column,
            problem,
        };
        match self.strictness {
            Strictness::Strict => Err(LogError::Csv {
                file: skipped.file,
                line: skipped.line,
                column: skipped.column,
                problem: skipped.problem,
            }),
            Strictness::Lenient => {
                self.skipped += 1;
                if self.skip_reasons.len() < MAX_SKIP_REASONS {
                    self.skip_reasons.push(skipped);
                }
                Ok(())
            }
        }
    }

    /// The line of the next row that passes every check, its cells (standard
    /// units and frames) in `self.cells`.
    fn next_checked(&mut self) -> Result<Option<u64>, LogError> {
        if self.cells.len() != self.names.len() {
            self.cells = vec![None; self.names.len()];
        }
        while let Some(line) = self
            .lines
            .next_line()
            .map_err(|e| LogError::io(&self.file, e))?
        {
            self.data_rows += 1;
            match self.parse_row() {
                Ok(t) => {
                    self.previous_t = Some(t);
                    return Ok(Some(line));
                }
                Err((column, problem, true)) => self.reject_reading(line, column, problem)?,
                Err((column, problem, false)) => self.reject(line, column, problem)?,
            }
        }
        // A file of which every row was rejected gives nothing: a mistake,
        // not glitches.
        if let (Strictness::Strict, None, Some(r)) =
            (self.strictness, self.previous_t, &self.rejected)
        {
            return Err(self.too_many_rejected(r));
        }
        Ok(None)
    }

    /// Skips a row of a non-physical reading (counted, reported); a strict
    /// reader refuses the file once there are too many.
    fn reject_reading(
        &mut self,
        line: u64,
        column: String,
        problem: CsvProblem,
    ) -> Result<(), LogError> {
        let file = &self.file;
        let r = self.rejected.get_or_insert_with(|| Rejected {
            count: 0,
            first: SkippedRow {
                file: file.clone(),
                line,
                column,
                problem,
            },
        });
        r.count += 1;
        let r = r.clone();
        if let Some(tally) = &self.tally {
            tally.record(&r);
        }
        let rows = usize::try_from(self.data_rows).unwrap_or(usize::MAX);
        if self.strictness == Strictness::Strict
            && r.count > REJECTED_FLOOR
            && r.count.saturating_mul(REJECTED_ONE_IN) > rows
        {
            return Err(self.too_many_rejected(&r));
        }
        Ok(())
    }

    fn too_many_rejected(&self, r: &Rejected) -> LogError {
        LogError::Csv {
            file: r.first.file.clone(),
            line: r.first.line,
            column: r.first.column.clone(),
            problem: CsvProblem::TooManyRejected {
                count: r.count,
                rows: usize::try_from(self.data_rows).unwrap_or(usize::MAX),
                first: Box::new(r.first.problem.clone()),
            },
        }
    }

    /// The rows rejected so far as non-physical readings (aiding files),
    /// with the first of them: skipped, never returned.
    pub fn rejected(&self) -> Option<&Rejected> {
        self.rejected.as_ref()
    }

    /// The header name of file column `j` (`<column N>` beyond the header).
    fn file_column(&self, j: usize) -> String {
        match self.header.get(j) {
            Some(h) => short(h),
            None => format!("<column {}>", j + 1),
        }
    }

    /// Parses the current line into `self.cells`; its time, or the offending
    /// column, the problem and whether it is a non-physical reading of an
    /// aiding file (a rejected row rather than a bad one).
    fn parse_row(&mut self) -> Result<f64, (String, CsvProblem, bool)> {
        let line = &self.lines.buf;
        let ncols = self.header.len();
        // Commas are found with a vectorised search; the cells are parsed from
        // one UTF-8 check of the whole line.
        let count = memchr::memchr_iter(b',', line).count() + 1;
        if count != ncols {
            // First missing column, or the first extra one.
            return Err((
                self.file_column(count.min(ncols)),
                CsvProblem::ColumnCount {
                    expected: ncols,
                    found: count,
                },
                false,
            ));
        }
        let text = std::str::from_utf8(line).ok();
        for (j, raw) in split_cells(line).enumerate() {
            let Some(i) = self.slot[j] else { continue };
            self.cells[i] = if raw.is_empty() {
                None
            } else {
                // A cell of a valid UTF-8 line is a valid `str` (the trimmed
                // comma-separated pieces end on ASCII bytes); a line that is
                // not UTF-8 is checked cell by cell, to name the bad cell.
                let cell = match text {
                    Some(t) => {
                        let start = raw.as_ptr() as usize - line.as_ptr() as usize;
                        t.get(start..start + raw.len())
                    }
                    None => std::str::from_utf8(raw).ok(),
                };
                let reading = self.aiding && i > 0;
                match cell.and_then(|s| s.parse::<f64>().ok()) {
                    Some(v) if v.is_finite() && (v * self.scale[i]).is_finite() => {
                        let v = v * self.scale[i];
                        if reading {
                            let (limit, allowed) = plausible_limit(R::COLUMNS[i]);
                            if v.abs() > limit {
                                return Err((
                                    self.names[i].clone(),
                                    CsvProblem::OutOfRange { value: v, allowed },
                                    true,
                                ));
                            }
                        }
                        Some(v)
                    }
                    Some(_) => {
                        return Err((
                            self.names[i].clone(),
                            CsvProblem::NonFinite {
                                text: cell_text(raw),
                            },
                            reading,
                        ))
                    }
                    None => {
                        return Err((
                            self.names[i].clone(),
                            CsvProblem::NotANumber {
                                text: cell_text(raw),
                            },
                            false,
                        ))
                    }
                }
            };
        }
        if !self.time.is_identity() {
            let index = self.data_rows.saturating_sub(1);
            self.cells[0] = if self.time.from_index {
                Some(self.time.time(index, 0.0))
            } else {
                self.cells[0].map(|t| self.time.time(index, t))
            };
        }
        let row = R::from_cells(&self.cells)
            .map_err(|i| (self.names[i].clone(), CsvProblem::EmptyCell, false))?;
        if let Err((i, value, allowed)) = row.check() {
            return Err((
                self.names[i].clone(),
                CsvProblem::OutOfRange { value, allowed },
                self.aiding && i > 0,
            ));
        }
        let t = row.t();
        if !t.is_finite() {
            return Err((
                self.names[0].clone(),
                CsvProblem::NonFinite {
                    text: format_f64(t),
                },
                false,
            ));
        }
        if let Some(prev) = self.previous_t {
            if t < prev {
                return Err((
                    self.names[0].clone(),
                    CsvProblem::TimeBackwards { previous: prev, t },
                    false,
                ));
            }
            if t == prev {
                return Err((
                    self.names[0].clone(),
                    CsvProblem::DuplicateTime { t },
                    false,
                ));
            }
        }
        Ok(t)
    }

    /// Rows accepted so far.
    pub fn accepted(&self) -> usize {
        self.accepted
    }

    /// Rows skipped so far (lenient reading).
    pub fn skipped(&self) -> usize {
        self.skipped
    }

    /// The first few reasons rows were skipped (at most [`MAX_SKIP_REASONS`]).
    pub fn skip_reasons(&self) -> &[SkippedRow] {
        &self.skip_reasons
    }

    /// The last accepted row.
    pub fn last(&self) -> Option<&R> {
        self.previous.as_ref()
    }

    /// The file read (as named in messages).
    pub fn file(&self) -> &str {
        &self.file
    }

    /// What the file carries: [`ImuForm::Increments`] for an `imu.csv` of
    /// increments (read as interval averages), otherwise [`ImuForm::Rates`].
    pub fn form(&self) -> ImuForm {
        self.form
    }

    /// The smallest non-zero change between consecutive values of column
    /// `column` (index in [`Row::COLUMNS`]) over the rows read so far (an
    /// empty cell is passed over); 0 when no value changed. A multiple of the
    /// column's quantization step, so never finer than it.
    pub fn resolution(&self, column: usize) -> f64 {
        match self.min_step.get(column) {
            Some(q) if q.is_finite() => *q,
            _ => 0.0,
        }
    }
}

/// A header cell for messages (truncated).
fn short(text: &str) -> String {
    cell_text(text.as_bytes())
}

/// Formats a float so that parsing it gives back the same bits (shortest round-trip
/// form; exponent notation for very small or very large magnitudes).
pub fn format_f64(v: f64) -> String {
    let a = v.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// Writes rows as CSV (header + one line per row) to a writer.
pub fn write_csv<R: Row>(mut w: impl Write, rows: &[R]) -> std::io::Result<()> {
    writeln!(w, "{}", R::COLUMNS.join(","))?;
    let mut line = String::new();
    for row in rows {
        line.clear();
        for (i, cell) in row.to_cells().into_iter().enumerate() {
            if i > 0 {
                line.push(',');
            }
            if let Some(v) = cell {
                line.push_str(&format_f64(v));
            }
        }
        line.push('\n');
        w.write_all(line.as_bytes())?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::GnssRow;
    use crate::earth::{meridian_radius, transverse_radius, Geodetic};
    use crate::trajectory::{Trajectory, TrajectorySpec, TruthSource};
    use nalgebra::Vector3;

    /// An antenna 10 m above the IMU of a level vehicle heading east, and
    /// noise of 1 m north, 2 m east and 3 m up: each moves the fix by its
    /// metres in its own direction.
    #[test]
    fn a_fix_is_the_antenna_moved_by_its_noise() {
        let start = Geodetic::new(0.6, 2.2, 50.0);
        let traj = Trajectory::new(
            TrajectorySpec::new(start, std::f64::consts::FRAC_PI_2, 3.0),
            10.0,
            0.1,
        );
        let s = traj.truth(5.0);
        let rm = meridian_radius(s.lat) + s.h;
        let rn = transverse_radius(s.lat) + s.h;
        // (antenna in body axes, noise, expected north, east, up in m)
        let cases = [
            ([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0]),
            ([0.0, 0.0, -10.0], [0.0, 0.0, 0.0], [0.0, 0.0, 10.0]),
            ([0.0, 0.0, 0.0], [1.0, 2.0, 3.0], [1.0, 2.0, 3.0]),
            // Forward is east when heading east.
            ([4.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 4.0, 0.0]),
        ];
        for (antenna, noise, [n, e, u]) in cases {
            let f = GnssRow::of_antenna(&s, &Vector3::from(antenna), noise);
            let got = [
                (f.lat - s.lat) * rm,
                (f.lon - s.lon) * rn * s.lat.cos(),
                f.height - s.h,
            ];
            for (g, w) in got.iter().zip([n, e, u]) {
                assert!((g - w).abs() < 1e-3, "{antenna:?} {noise:?}: {got:?}");
            }
        }
    }
}
