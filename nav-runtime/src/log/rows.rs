//! Typed CSV rows and the CSV reader/writer shared by every log file.

use std::io::{BufRead, BufReader, Read, Write};

use super::error::{CsvProblem, LogError, SkippedRow};
use super::Strictness;

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

fn column_name<R: Row>(index: usize) -> String {
    match R::COLUMNS.get(index) {
        Some(name) => (*name).to_string(),
        None => format!("<column {}>", index + 1),
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
            if !self.buf.iter().all(u8::is_ascii_whitespace) {
                return Ok(Some(self.line));
            }
        }
    }
}

/// Splits a line at commas and trims ASCII whitespace around each cell.
fn split_cells(line: &[u8]) -> impl Iterator<Item = &[u8]> {
    line.split(|&b| b == b',').map(|c| c.trim_ascii())
}

/// Parses one CSV file of row type `R` from a reader: [`RowReader`] read to
/// the end, every accepted row kept.
///
/// The format is plain comma-separated text without quoting. The header must match
/// [`Row::COLUMNS`] exactly (spaces around names and a UTF-8 byte order mark are
/// ignored). Blank lines are ignored but counted, so line numbers are those of the
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
pub struct RowReader<R: Row, I: Read> {
    lines: Lines<BufReader<I>>,
    strictness: Strictness,
    cells: Vec<Option<f64>>,
    previous_t: Option<f64>,
    previous: Option<R>,
    skipped: usize,
    skip_reasons: Vec<SkippedRow>,
    accepted: usize,
    min_step: Vec<f64>,
    last_value: Vec<Option<f64>>,
}

impl<R: Row, I: Read> std::fmt::Debug for RowReader<R, I> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("RowReader")
            .field("file", &R::FILE)
            .field("line", &self.lines.line)
            .field("accepted", &self.accepted)
            .field("skipped", &self.skipped)
            .finish()
    }
}

impl<R: Row, I: Read> RowReader<R, I> {
    /// Reads and checks the header.
    ///
    /// # Errors
    /// An empty file or a header other than [`Row::COLUMNS`].
    pub fn new(reader: I, strictness: Strictness) -> Result<Self, LogError> {
        let file = R::FILE;
        let mut lines = Lines {
            reader: BufReader::new(reader),
            line: 0,
            buf: Vec::new(),
        };
        let expected_header = R::COLUMNS.join(",");
        let Some(header_line) = lines.next_line().map_err(|e| LogError::io(file, e))? else {
            return Err(LogError::EmptyFile {
                file: file.to_string(),
                expected: expected_header,
            });
        };
        let header = lines
            .buf
            .strip_prefix(b"\xEF\xBB\xBF")
            .unwrap_or(&lines.buf);
        let found: Vec<&[u8]> = split_cells(header).collect();
        let ncols = R::COLUMNS.len();
        for i in 0..ncols.max(found.len()) {
            let cell = found.get(i).map(|c| cell_text(c));
            let ok = matches!((R::COLUMNS.get(i), &cell), (Some(exp), Some(f)) if f == exp);
            if !ok {
                return Err(LogError::Csv {
                    file: file.to_string(),
                    line: header_line,
                    column: column_name::<R>(i),
                    problem: CsvProblem::WrongHeader {
                        expected: expected_header,
                        found: cell.unwrap_or_default(),
                    },
                });
            }
        }
        Ok(RowReader {
            lines,
            strictness,
            cells: vec![None; ncols],
            previous_t: None,
            previous: None,
            skipped: 0,
            skip_reasons: Vec::new(),
            accepted: 0,
            min_step: vec![f64::INFINITY; ncols],
            last_value: vec![None; ncols],
        })
    }

    /// The next accepted row with its 1-based line number; `None` at the end
    /// of the file. Lenient reading skips (and counts) bad rows.
    ///
    /// # Errors
    /// A read error, or (strict) the first bad row, naming file, line and column.
    pub fn next_row(&mut self) -> Result<Option<(u64, R)>, LogError> {
        while let Some(line) = self
            .lines
            .next_line()
            .map_err(|e| LogError::io(R::FILE, e))?
        {
            match parse_row::<R>(&self.lines.buf, &mut self.cells, self.previous_t) {
                Ok(row) => {
                    self.previous_t = Some(row.t());
                    self.previous = Some(row);
                    self.accepted += 1;
                    for (i, cell) in self.cells.iter().enumerate().skip(1) {
                        let Some(v) = *cell else { continue };
                        if let Some(last) = self.last_value[i] {
                            let d = (v - last).abs();
                            if d > 0.0 && d.is_finite() && d < self.min_step[i] {
                                self.min_step[i] = d;
                            }
                        }
                        self.last_value[i] = Some(v);
                    }
                    return Ok(Some((line, row)));
                }
                Err((column, problem)) => {
                    let skipped = SkippedRow {
                        file: R::FILE.to_string(),
                        line,
                        column,
                        problem,
                    };
                    match self.strictness {
                        Strictness::Strict => {
                            return Err(LogError::Csv {
                                file: skipped.file,
                                line: skipped.line,
                                column: skipped.column,
                                problem: skipped.problem,
                            })
                        }
                        Strictness::Lenient => {
                            self.skipped += 1;
                            if self.skip_reasons.len() < MAX_SKIP_REASONS {
                                self.skip_reasons.push(skipped);
                            }
                        }
                    }
                }
            }
        }
        Ok(None)
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

fn parse_row<R: Row>(
    line: &[u8],
    cells: &mut [Option<f64>],
    previous_t: Option<f64>,
) -> Result<R, (String, CsvProblem)> {
    let ncols = R::COLUMNS.len();
    let count = split_cells(line).count();
    if count != ncols {
        // First missing column, or the first extra one.
        return Err((
            column_name::<R>(count.min(ncols)),
            CsvProblem::ColumnCount {
                expected: ncols,
                found: count,
            },
        ));
    }
    for (i, raw) in split_cells(line).enumerate() {
        cells[i] = if raw.is_empty() {
            None
        } else {
            let text = std::str::from_utf8(raw).ok();
            match text.and_then(|s| s.parse::<f64>().ok()) {
                Some(v) if v.is_finite() => Some(v),
                Some(_) => {
                    return Err((
                        column_name::<R>(i),
                        CsvProblem::NonFinite {
                            text: cell_text(raw),
                        },
                    ))
                }
                None => {
                    return Err((
                        column_name::<R>(i),
                        CsvProblem::NotANumber {
                            text: cell_text(raw),
                        },
                    ))
                }
            }
        };
    }
    let row = R::from_cells(cells).map_err(|i| (column_name::<R>(i), CsvProblem::EmptyCell))?;
    if let Err((i, value, allowed)) = row.check() {
        return Err((
            column_name::<R>(i),
            CsvProblem::OutOfRange { value, allowed },
        ));
    }
    if let Some(prev) = previous_t {
        let t = row.t();
        if t < prev {
            return Err((
                "t".to_string(),
                CsvProblem::TimeBackwards { previous: prev, t },
            ));
        }
        if t == prev {
            return Err(("t".to_string(), CsvProblem::DuplicateTime { t }));
        }
    }
    Ok(row)
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
