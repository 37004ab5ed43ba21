//! `[files.<sensor>]` of `meta.toml`: which CSV file feeds a sensor, under
//! which header names, in which units and frames. The reader converts every
//! row to the standard columns, units and frames, so nothing after it knows
//! a mapping was used. A sensor without a section is read in the standard
//! format (its standard file, names, SI units, FRD body, NED navigation).

use std::path::{Component, Path};

use super::axes::Axes;
use super::meta::Cx;
use super::rows::Row;
use super::time_base::TimeBase;
use super::LogError;

/// Body frame of a file's body-frame vectors (gyro, specific force,
/// increments, DVL velocity).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum BodyFrame {
    /// Forward-right-down (the standard).
    #[default]
    Frd,
    /// Forward-left-up: y and z are negated on reading.
    Flu,
}

/// Navigation frame of a file's navigation-frame velocity (`truth.csv`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum NavFrame {
    /// North-east-down (the standard).
    #[default]
    Ned,
    /// East-north-up: the column of `vd` holds the up velocity, negated on
    /// reading (`vn` and `ve` are named by meaning, so nothing is swapped).
    Enu,
}

/// What `imu.csv` carries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum ImuForm {
    /// Instantaneous rates `t,gx,gy,gz,ax,ay,az` (rad/s, m/s^2).
    #[default]
    Rates,
    /// Increments `t,dtheta_x,dtheta_y,dtheta_z,dv_x,dv_y,dv_z` (rad, m/s)
    /// over the interval ending at `t`; read as interval averages (increment
    /// divided by the interval) into the rate columns.
    Increments,
}

/// The quantity of a standard column, which sets the units it may be given in.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Time, s.
    Time,
    /// Angle, rad.
    Angle,
    /// Angular rate, rad/s.
    Rate,
    /// Specific force, m/s^2.
    SpecificForce,
    /// Depth, altitude, m.
    Length,
    /// Speed or velocity (and velocity increment), m/s.
    Speed,
    /// Revolutions per minute.
    Rpm,
    /// Magnetic field, gauss.
    MagneticField,
}

/// Units each quantity may be given in, with the factor to the standard unit.
const UNITS: &[(Quantity, &str, f64)] = &[
    (Quantity::Time, "s", 1.0),
    (Quantity::Angle, "rad", 1.0),
    (Quantity::Angle, "deg", core::f64::consts::PI / 180.0),
    (Quantity::Rate, "rad/s", 1.0),
    (Quantity::Rate, "deg/s", core::f64::consts::PI / 180.0),
    (Quantity::SpecificForce, "m/s^2", 1.0),
    (Quantity::SpecificForce, "g", STANDARD_GRAVITY),
    (Quantity::Length, "m", 1.0),
    (Quantity::Length, "ft", 0.3048),
    (Quantity::Speed, "m/s", 1.0),
    (Quantity::Speed, "kn", 1852.0 / 3600.0),
    (Quantity::Rpm, "rpm", 1.0),
    (Quantity::MagneticField, "gauss", 1.0),
    (Quantity::MagneticField, "T", 1e4),
    (Quantity::MagneticField, "uT", 1e-2),
    (Quantity::MagneticField, "nT", 1e-5),
];

/// Standard gravity (m/s^2), the value of the unit `g`.
pub const STANDARD_GRAVITY: f64 = 9.80665;

impl Quantity {
    /// The key of the quantity in a `units` table (`rate = "deg/s"`).
    pub fn key(self) -> &'static str {
        match self {
            Quantity::Time => "time",
            Quantity::Angle => "angle",
            Quantity::Rate => "rate",
            Quantity::SpecificForce => "specific_force",
            Quantity::Length => "length",
            Quantity::Speed => "speed",
            Quantity::Rpm => "rpm",
            Quantity::MagneticField => "magnetic_field",
        }
    }

    /// The units the quantity may be given in.
    pub fn units(self) -> Vec<&'static str> {
        UNITS
            .iter()
            .filter(|(q, _, _)| *q == self)
            .map(|(_, u, _)| *u)
            .collect()
    }

    /// Factor from `unit` to the standard unit, if `unit` is one of this
    /// quantity's units.
    pub fn factor(self, unit: &str) -> Option<f64> {
        UNITS
            .iter()
            .find(|(q, u, _)| *q == self && *u == unit)
            .map(|(_, _, f)| *f)
    }
}

/// The quantity of standard column `column` (any file); `None` for an unknown
/// name.
pub fn quantity(column: &str) -> Option<Quantity> {
    Some(match column {
        "t" => Quantity::Time,
        "gx" | "gy" | "gz" => Quantity::Rate,
        "ax" | "ay" | "az" => Quantity::SpecificForce,
        "dtheta_x" | "dtheta_y" | "dtheta_z" | "heading" | "lat" | "lon" | "roll" | "pitch"
        | "yaw" => Quantity::Angle,
        "dv_x" | "dv_y" | "dv_z" | "vx" | "vy" | "vz" | "vn" | "ve" | "vd" | "speed" => {
            Quantity::Speed
        }
        "depth" | "altitude" => Quantity::Length,
        "rpm" => Quantity::Rpm,
        "mx" | "my" | "mz" => Quantity::MagneticField,
        _ => return None,
    })
}

/// Columns negated when the body frame is FLU.
const FLU_NEGATED: &[&str] = &[
    "gy", "gz", "ay", "az", "dtheta_y", "dtheta_z", "dv_y", "dv_z", "vy", "vz", "my", "mz",
];

/// The increment-form columns of `imu.csv`, in the order of the rate columns
/// they are read into.
pub const IMU_INCREMENT_COLUMNS: &[&str] = &[
    "t", "dtheta_x", "dtheta_y", "dtheta_z", "dv_x", "dv_y", "dv_z",
];

/// The sensor name of a standard file (`imu.csv` -> `imu`).
pub fn sensor_of(file: &str) -> &str {
    file.strip_suffix(".csv").unwrap_or(file)
}

/// Sensors that may have a `[files.<sensor>]` section, with their standard file.
pub const MAPPED_SENSORS: &[(&str, &str)] = &[
    ("imu", "imu.csv"),
    ("dvl", "dvl.csv"),
    ("depth", "depth.csv"),
    ("heading", "heading.csv"),
    ("usbl", "usbl.csv"),
    ("speed", "speed.csv"),
    ("rpm", "rpm.csv"),
    ("altitude", "altitude.csv"),
    ("truth", "truth.csv"),
    ("mag", "mag.csv"),
];

/// Standard columns of each mapped sensor (both forms for the IMU).
fn standard_columns(sensor: &str) -> &'static [&'static str] {
    use super::rows::*;
    match sensor {
        "imu" => &[
            "t", "gx", "gy", "gz", "ax", "ay", "az", "dtheta_x", "dtheta_y", "dtheta_z", "dv_x",
            "dv_y", "dv_z",
        ],
        "dvl" => DvlRow::COLUMNS,
        "depth" => DepthRow::COLUMNS,
        "heading" => HeadingRow::COLUMNS,
        "usbl" => UsblRow::COLUMNS,
        "speed" => SpeedRow::COLUMNS,
        "rpm" => RpmRow::COLUMNS,
        "altitude" => AltitudeRow::COLUMNS,
        "mag" => MagRow::COLUMNS,
        _ => TruthRow::COLUMNS,
    }
}

/// How one file is read: a `[files.<sensor>]` section, or the standard
/// format ([`FileMapping::standard`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FileMapping {
    /// The sensor (`imu`, `dvl`, ..., `truth`).
    pub sensor: String,
    /// The file, relative to the log directory.
    pub file: String,
    /// Whether `file` was given (`files.<sensor>.file`): a declared file
    /// must exist.
    pub declared_file: bool,
    /// Header names of standard columns that are not found under their own
    /// name: `(standard column, header name)`.
    pub columns: Vec<(String, String)>,
    /// Unit of each standard column not in its standard unit:
    /// `(standard column, unit)`.
    pub units: Vec<(String, String)>,
    /// Header names of columns that are read past.
    pub ignore: Vec<String>,
    /// Body frame of the body-frame vectors.
    pub body_frame: BodyFrame,
    /// Navigation frame of the navigation-frame velocity.
    pub nav_frame: NavFrame,
    /// The IMU form; `None`: found from the header.
    pub form: Option<ImuForm>,
    /// Whether the file has a `[files.<sensor>]` section (messages then point
    /// at its keys).
    pub declared: bool,
    /// Where the file's times come from (`time`): the time column as it
    /// is, unless the section says otherwise.
    pub time: TimeBase,
    /// Sign and permutation of the body-frame vector axes (`axes`).
    pub axes: Axes,
    /// `truth.csv` only: where on the vehicle the point the file describes
    /// sits, body axes (FRD) from the IMU, m (`lever_arm`); its rows are
    /// moved to the IMU before use ([`super::ReferencePoint`]). Zero: the
    /// truth is of the IMU.
    pub lever_arm: [f64; 3],
}

impl FileMapping {
    /// The standard format of `R`'s file.
    pub fn standard<R: Row>() -> FileMapping {
        Self::standard_named(sensor_of(R::FILE), R::FILE)
    }

    /// The standard format of `sensor`'s file `file`.
    fn standard_named(sensor: &str, file: &str) -> FileMapping {
        FileMapping {
            sensor: sensor.to_string(),
            file: file.to_string(),
            declared_file: false,
            columns: Vec::new(),
            units: Vec::new(),
            ignore: Vec::new(),
            body_frame: BodyFrame::Frd,
            nav_frame: NavFrame::Ned,
            form: None,
            declared: false,
            time: TimeBase::default(),
            axes: Axes::default(),
            lever_arm: [0.0; 3],
        }
    }

    /// The header name of standard column `column`.
    pub fn header_name<'a>(&'a self, column: &'a str) -> &'a str {
        self.columns
            .iter()
            .find(|(c, _)| c == column)
            .map_or(column, |(_, h)| h.as_str())
    }

    /// Whether `column` was renamed by the mapping.
    pub fn renamed(&self, column: &str) -> bool {
        self.columns.iter().any(|(c, _)| c == column)
    }

    /// The factor that takes a value of standard column `column` as written
    /// in the file to the standard unit and frame.
    pub fn scale(&self, column: &str) -> f64 {
        let unit = self
            .units
            .iter()
            .find(|(c, _)| c == column)
            .and_then(|(c, u)| quantity(c)?.factor(u))
            .unwrap_or(1.0);
        let body = if self.body_frame == BodyFrame::Flu && FLU_NEGATED.contains(&column) {
            -1.0
        } else {
            1.0
        };
        let nav = if self.nav_frame == NavFrame::Enu && column == "vd" {
            -1.0
        } else {
            1.0
        };
        unit * body * nav
    }

    /// For standard column `column`: the standard column of the file it is
    /// read from (another axis with `axes`) and the factor that takes the
    /// file's value to the standard unit, frame and axis.
    pub fn source(&self, column: &str) -> (String, f64) {
        match self.axes.source(column) {
            Some((from, sign)) if !self.axes.is_identity() => {
                let factor = sign * self.scale(&from);
                (from, factor)
            }
            _ => (column.to_string(), self.scale(column)),
        }
    }

    /// The dotted `meta.toml` key of `key` in this file's section.
    pub fn key(&self, key: &str) -> String {
        format!("files.{}.{key}", self.sensor)
    }
}

/// Every `[files.<sensor>]` section of `meta.toml`.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct LogMapping {
    /// The declared sections, in [`MAPPED_SENSORS`] order.
    pub files: Vec<FileMapping>,
}

impl LogMapping {
    /// How `R`'s file is read: its section, or the standard format.
    pub fn of<R: Row>(&self) -> FileMapping {
        self.get(sensor_of(R::FILE))
            .cloned()
            .unwrap_or_else(FileMapping::standard::<R>)
    }

    /// The section of `sensor`, if declared.
    pub fn get(&self, sensor: &str) -> Option<&FileMapping> {
        self.files.iter().find(|m| m.sensor == sensor)
    }

    /// `time.offset_s` of `sensor`'s file (0 without a section); `None`
    /// for a name that is not a mapped sensor.
    pub fn time_offset(&self, sensor: &str) -> Option<f64> {
        MAPPED_SENSORS
            .iter()
            .any(|(s, _)| *s == sensor)
            .then(|| self.get(sensor).map_or(0.0, |m| m.time.offset_s))
    }

    /// Sets `time.offset_s` of `sensor`'s file (s), giving a sensor read
    /// in the standard format a section of its own that changes nothing
    /// else (noise tuning replays a log with other clock offsets); `false`,
    /// and nothing changed, for a name that is not a mapped sensor.
    pub fn set_time_offset(&mut self, sensor: &str, offset_s: f64) -> bool {
        let Some(index) = MAPPED_SENSORS.iter().position(|(s, _)| *s == sensor) else {
            return false;
        };
        if let Some(m) = self.files.iter_mut().find(|m| m.sensor == sensor) {
            m.time.offset_s = offset_s;
            return true;
        }
        let (_, file) = MAPPED_SENSORS[index];
        let mut m = FileMapping::standard_named(sensor, file);
        m.time.offset_s = offset_s;
        // In [`MAPPED_SENSORS`] order, as parsed sections are.
        let at = self
            .files
            .iter()
            .position(|f| {
                MAPPED_SENSORS
                    .iter()
                    .position(|(s, _)| *s == f.sensor)
                    .is_some_and(|i| i > index)
            })
            .unwrap_or(self.files.len());
        self.files.insert(at, m);
        true
    }

    /// Whether `name` (a file directly in the log directory) is read by some
    /// sensor through a section.
    pub fn reads(&self, name: &str) -> bool {
        self.files
            .iter()
            .any(|m| Path::new(&m.file) == Path::new(name))
    }

    /// Whether the standard file `name` is replaced by a section naming
    /// another file (it is then not read).
    pub fn replaced(&self, name: &str) -> Option<&FileMapping> {
        self.get(sensor_of(name))
            .filter(|m| m.file != name && !self.reads(name))
    }

    /// Reads `[files]` (already known to be a table).
    pub(super) fn parse(cx: &Cx<'_>, files: &toml::Table) -> Result<LogMapping, LogError> {
        let names: Vec<&str> = MAPPED_SENSORS.iter().map(|(s, _)| *s).collect();
        cx.check_keys(files, "files", &names)?;
        let mut out = LogMapping::default();
        for (sensor, standard) in MAPPED_SENSORS {
            let Some(t) = cx.section(files, "files", sensor)? else {
                continue;
            };
            out.files.push(parse_section(cx, sensor, standard, t)?);
        }
        // Each file feeds one sensor; a standard file feeds its own sensor
        // unless that sensor reads another file.
        for (i, m) in out.files.iter().enumerate() {
            let key = m.key("file");
            if let Some(other) = out.files[..i].iter().find(|o| o.file == m.file) {
                return Err(cx.err(
                    &key,
                    format!("`{}` is already read by `files.{}`", m.file, other.sensor),
                ));
            }
            if let Some((owner, _)) = MAPPED_SENSORS
                .iter()
                .find(|(s, f)| *f == m.file && *s != m.sensor)
            {
                let moved = out.get(owner).is_some_and(|o| o.file != m.file);
                if !moved {
                    return Err(cx.err(
                        &key,
                        format!(
                            "`{}` is the standard file of `{owner}`; give `files.{owner}.file` another file first",
                            m.file
                        ),
                    ));
                }
            }
        }
        Ok(out)
    }
}

fn parse_section(
    cx: &Cx<'_>,
    sensor: &str,
    standard: &str,
    t: &toml::Table,
) -> Result<FileMapping, LogError> {
    let sec = format!("files.{sensor}");
    let mut keys = vec!["file", "columns", "units", "ignore", "time"];
    let body = matches!(sensor, "imu" | "dvl" | "mag");
    if body {
        keys.extend(["body_frame", "axes"]);
    }
    if sensor == "truth" {
        keys.extend(["nav_frame", "lever_arm"]);
    }
    if sensor == "imu" {
        keys.push("form");
    }
    cx.check_keys(t, &sec, &keys)?;
    let string = |key: &str| -> Result<Option<&str>, LogError> {
        match t.get(key) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.as_str())),
            Some(other) => Err(cx.err(
                &format!("{sec}.{key}"),
                format!("expected a string, found {}", other.type_str()),
            )),
        }
    };
    let mut m = FileMapping {
        sensor: sensor.to_string(),
        file: standard.to_string(),
        declared_file: false,
        columns: Vec::new(),
        units: Vec::new(),
        ignore: Vec::new(),
        body_frame: BodyFrame::Frd,
        nav_frame: NavFrame::Ned,
        form: None,
        declared: true,
        time: TimeBase::default(),
        axes: Axes::default(),
        lever_arm: [0.0; 3],
    };
    if let Some(file) = string("file")? {
        m.file = relative_log_path(file).map_err(|p| cx.err(&m.key("file"), p))?;
        m.declared_file = true;
    }
    let allowed = standard_columns(sensor);
    if let Some(c) = cx.section(t, &sec, "columns")? {
        let csec = format!("{sec}.columns");
        cx.check_keys(c, &csec, allowed)?;
        for (column, header) in c {
            let key = format!("{csec}.{column}");
            let header = match header {
                toml::Value::String(s) => s.trim(),
                other => {
                    return Err(cx.err(
                        &key,
                        format!(
                            "expected a header name (string), found {}",
                            other.type_str()
                        ),
                    ))
                }
            };
            if header.is_empty() || header.contains(',') {
                return Err(cx.err(&key, "a header name is not empty and has no comma"));
            }
            if let Some((other, _)) = m.columns.iter().find(|(_, h)| h == header) {
                return Err(cx.err(&key, format!("header `{header}` already names `{other}`")));
            }
            m.columns.push((column.clone(), header.to_string()));
        }
    }
    if let Some(u) = cx.section(t, &sec, "units")? {
        let usec = format!("{sec}.units");
        let mut quantities: Vec<Quantity> = Vec::new();
        for q in allowed.iter().filter_map(|c| quantity(c)) {
            if !quantities.contains(&q) {
                quantities.push(q);
            }
        }
        let mut unit_keys: Vec<&str> = allowed.to_vec();
        unit_keys.extend(quantities.iter().map(|q| q.key()));
        cx.check_keys(u, &usec, &unit_keys)?;
        let mut by_quantity = Vec::new();
        for (k, v) in u {
            let key = format!("{usec}.{k}");
            let unit = match v {
                toml::Value::String(s) => s.trim(),
                other => {
                    return Err(cx.err(
                        &key,
                        format!("expected a unit (string), found {}", other.type_str()),
                    ))
                }
            };
            let is_column = allowed.contains(&k.as_str());
            let q = is_column
                .then(|| quantity(k))
                .flatten()
                .or_else(|| quantities.iter().copied().find(|q| q.key() == k))
                .unwrap_or(Quantity::Time);
            if q.factor(unit).is_none() {
                return Err(cx.err(
                    &key,
                    format!(
                        "unknown unit `{unit}` for {} ({}); expected one of: {}{}",
                        if is_column {
                            format!("column `{k}`")
                        } else {
                            format!("every `{k}` column")
                        },
                        q.key().replace('_', " "),
                        q.units().join(", "),
                        super::did_you_mean(unit, &q.units())
                    ),
                ));
            }
            if is_column {
                m.units.push((k.clone(), unit.to_string()));
            } else {
                by_quantity.push((q, unit.to_string()));
            }
        }
        // A quantity's unit applies to its columns not given one of their own.
        for column in allowed {
            let Some(q) = quantity(column) else { continue };
            if m.units.iter().any(|(c, _)| c == column) {
                continue;
            }
            if let Some((_, unit)) = by_quantity.iter().find(|(bq, _)| *bq == q) {
                m.units.push((column.to_string(), unit.clone()));
            }
        }
    }
    if let Some(v) = t.get("ignore") {
        let key = m.key("ignore");
        let toml::Value::Array(items) = v else {
            return Err(cx.err(
                &key,
                format!("expected an array of header names, found {}", v.type_str()),
            ));
        };
        for item in items {
            match item {
                toml::Value::String(s) => m.ignore.push(s.trim().to_string()),
                other => {
                    return Err(cx.err(
                        &key,
                        format!(
                            "expected header names (strings), found {}",
                            other.type_str()
                        ),
                    ))
                }
            }
        }
    }
    if body {
        if let Some(f) = string("body_frame")? {
            m.body_frame = match f {
                "FRD" => BodyFrame::Frd,
                "FLU" => BodyFrame::Flu,
                _ => {
                    return Err(cx.err(
                        &m.key("body_frame"),
                        format!(
                            "unknown body frame `{f}`; expected one of: FRD, FLU{}",
                            super::did_you_mean(f, &["FRD", "FLU"])
                        ),
                    ))
                }
            };
        }
    }
    if body {
        if let Some(v) = t.get("axes") {
            let key = m.key("axes");
            if t.contains_key("body_frame") {
                return Err(cx.err(
                    &key,
                    format!(
                        "contradicts `{}`: give the axes in one of the two (`body_frame = \"FLU\"` is `axes = [\"x\", \"-y\", \"-z\"]`)",
                        m.key("body_frame")
                    ),
                ));
            }
            m.axes = Axes::parse(cx, &key, v)?;
        }
    }
    if let Some(time) = cx.section(t, &sec, "time")? {
        let column_named = m.columns.iter().any(|(c, _)| c == "t");
        m.time = TimeBase::parse(cx, &sec, time, sensor == "imu", column_named)?;
    }
    if sensor == "truth" {
        if let Some(arm) = cx.lever_arm(t, &sec, "lever_arm")? {
            m.lever_arm = arm;
        }
        if let Some(f) = string("nav_frame")? {
            m.nav_frame = match f {
                "NED" => NavFrame::Ned,
                "ENU" => NavFrame::Enu,
                _ => {
                    return Err(cx.err(
                        &m.key("nav_frame"),
                        format!(
                            "unknown navigation frame `{f}`; expected one of: NED, ENU{}",
                            super::did_you_mean(f, &["NED", "ENU"])
                        ),
                    ))
                }
            };
        }
    }
    if sensor == "imu" {
        let rate_keys = m.columns.iter().any(|(c, _)| is_rate_column(c));
        let increment_keys = m.columns.iter().any(|(c, _)| is_increment_column(c));
        m.form = match string("form")? {
            Some("rates") => Some(ImuForm::Rates),
            Some("increments") => Some(ImuForm::Increments),
            Some(f) => {
                return Err(cx.err(
                    &m.key("form"),
                    format!(
                        "unknown IMU form `{f}`; expected one of: rates, increments{}",
                        super::did_you_mean(f, &["rates", "increments"])
                    ),
                ))
            }
            None if increment_keys => Some(ImuForm::Increments),
            None if rate_keys => Some(ImuForm::Rates),
            None => None,
        };
        let wrong = match m.form {
            Some(ImuForm::Rates) => m.columns.iter().find(|(c, _)| is_increment_column(c)),
            Some(ImuForm::Increments) => m.columns.iter().find(|(c, _)| is_rate_column(c)),
            None => None,
        };
        if let Some((c, _)) = wrong {
            return Err(cx.err(
                &format!("{sec}.columns.{c}"),
                "rate and increment columns cannot be mixed: `form` is one or the other",
            ));
        }
    }
    Ok(m)
}

fn is_rate_column(c: &str) -> bool {
    matches!(c, "gx" | "gy" | "gz" | "ax" | "ay" | "az")
}

fn is_increment_column(c: &str) -> bool {
    IMU_INCREMENT_COLUMNS[1..].contains(&c)
}

/// The path `file` as `a/b.csv` (no `.` components), or why it is refused:
/// anything but a plain relative path below the log directory.
pub fn relative_log_path(file: &str) -> Result<String, String> {
    if file.trim().is_empty() {
        return Err("empty file name".into());
    }
    if file.contains('\\') {
        return Err(format!("`{file}`: write paths with `/`"));
    }
    let path = Path::new(file);
    for c in path.components() {
        match c {
            Component::Normal(_) | Component::CurDir => {}
            Component::ParentDir => {
                return Err(format!("`{file}`: `..` would leave the log directory"))
            }
            Component::RootDir | Component::Prefix(_) => {
                return Err(format!(
                    "`{file}`: an absolute path; a log file is named relative to the log directory"
                ))
            }
        }
    }
    let parts: Vec<String> = path
        .components()
        .filter_map(|c| match c {
            Component::Normal(p) => Some(p.to_string_lossy().into_owned()),
            _ => None,
        })
        .collect();
    if parts.is_empty() || path.file_name().is_none() {
        return Err(format!("`{file}` names no file"));
    }
    let normal = parts.join("/");
    if normal == super::META_FILE {
        return Err(format!("`{file}` is the metadata file"));
    }
    Ok(normal)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_clock_offset_is_set_on_a_section_or_one_made_for_it() {
        let mut mapping = LogMapping::default();
        assert_eq!(mapping.time_offset("dvl"), Some(0.0));
        assert_eq!(mapping.time_offset("sonar"), None);
        assert!(!mapping.set_time_offset("sonar", 1.0));
        assert!(mapping.set_time_offset("usbl", -0.5));
        assert!(mapping.set_time_offset("dvl", 1.25));
        // A section made for it reads the standard file, in sensor order.
        let sensors: Vec<&str> = mapping.files.iter().map(|m| m.sensor.as_str()).collect();
        assert_eq!(sensors, ["dvl", "usbl"]);
        let dvl = mapping.get("dvl").unwrap();
        assert_eq!((dvl.file.as_str(), dvl.declared), ("dvl.csv", false));
        assert_eq!(dvl.time.time(3, 10.0), 11.25);
        // An existing section keeps everything but its offset.
        let mut declared = FileMapping::standard_named("dvl", "raw.csv");
        declared.time.from_index = true;
        declared.time.period_s = Some(1.0);
        let mut mapping = LogMapping {
            files: vec![declared.clone()],
        };
        assert!(mapping.set_time_offset("dvl", -0.45));
        declared.time.offset_s = -0.45;
        assert_eq!(mapping.files, vec![declared]);
        assert_eq!(mapping.time_offset("dvl"), Some(-0.45));
    }
}
