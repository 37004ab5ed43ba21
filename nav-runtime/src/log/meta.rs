//! `meta.toml`: initial estimate, initial uncertainty, sensor noise and USBL transducer.

use std::fmt::Write as _;

use super::error::{LogError, Magnitude};
use super::mapping::LogMapping;
use super::reference_point::ReferencePoint;
use super::warning::{Warning, WarningKind};
use crate::suggestion::closest_name;

/// `[initial]`: the initial estimate (not necessarily the truth). Angles in rad.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Initial {
    /// Epoch of the initial estimate, s in the log's time base (optional; when
    /// absent the estimate holds at the start of the first IMU interval).
    pub t: Option<f64>,
    /// Latitude, rad (required, but for an attitude-only `meta.toml`: none
    /// of `lat`, `lon`, `depth` given, all three NaN; see
    /// [`Initial::position`]).
    pub lat: f64,
    /// Longitude, rad (as `lat`).
    pub lon: f64,
    /// Depth, m (as `lat`).
    pub depth: f64,
    /// North velocity, m/s (default 0).
    pub vn: f64,
    /// East velocity, m/s (default 0).
    pub ve: f64,
    /// Down velocity, m/s (default 0).
    pub vd: f64,
    /// Roll, rad (optional: a leveling model takes none).
    pub roll: Option<f64>,
    /// Pitch, rad (optional: a leveling model takes none).
    pub pitch: Option<f64>,
    /// Yaw, rad (optional).
    pub yaw: Option<f64>,
}

impl Initial {
    /// Moves the position from the point `point` describes to the IMU
    /// (`[initial] lever_arm`: the initial position copied from a reference
    /// that describes another point of the vehicle, docs/log-format.md).
    /// The velocity is not moved: the body rate at the epoch, which the
    /// difference `C_b^n (omega x r)` needs, is not part of `[initial]`.
    ///
    /// # Errors
    /// The name of the first of `lat`, `roll`, `pitch`, `yaw` that is
    /// missing (the move needs a position and a full attitude).
    fn move_to_imu(&mut self, point: &ReferencePoint) -> Result<(), &'static str> {
        if !self.has_position() {
            return Err("lat");
        }
        let (Some(roll), Some(pitch), Some(yaw)) = (self.roll, self.pitch, self.yaw) else {
            return Err(["roll", "pitch", "yaw"][[self.roll, self.pitch, self.yaw]
                .iter()
                .position(Option::is_none)
                .unwrap_or(0)]);
        };
        let c_bn = crate::attitude::Euler { roll, pitch, yaw }.c_bn();
        [self.lat, self.lon, self.depth] =
            point.position_to_imu([self.lat, self.lon, self.depth], &c_bn);
        Ok(())
    }

    /// Whether `[initial]` has a position (an attitude-only `meta.toml`, as
    /// an importer writes for a log without any position or GNSS fix, has
    /// none: docs/log-format.md).
    pub fn has_position(&self) -> bool {
        self.lat.is_finite() && self.lon.is_finite() && self.depth.is_finite()
    }

    /// Latitude, longitude (rad) and depth (m), or an error naming
    /// `initial.lat` for an attitude-only `meta.toml` (for models that need
    /// a position).
    pub fn position(&self) -> Result<[f64; 3], LogError> {
        if self.has_position() {
            Ok([self.lat, self.lon, self.depth])
        } else {
            Err(LogError::meta(
                "initial.lat",
                "missing (an attitude-only meta.toml: the log has no position; this model needs one)",
            ))
        }
    }

    /// As [`Initial::position`], the error naming `model` (for a replay
    /// model that needs a position and is given an attitude-only log).
    pub fn position_for(&self, model: &str) -> Result<[f64; 3], LogError> {
        self.position().map_err(|_| {
            LogError::meta(
                "initial.lat",
                format!("model {model} needs an initial position: meta.toml [initial] has none (attitude-only log, e.g. an import without GNSS)"),
            )
        })
    }

    /// Roll, pitch and yaw, or an error naming the first missing key (for models that
    /// need a full initial attitude).
    pub fn attitude(&self) -> Result<[f64; 3], LogError> {
        let get = |v: Option<f64>, k: &str| {
            v.ok_or_else(|| {
                LogError::meta(format!("initial.{k}"), "missing (required by this model)")
            })
        };
        Ok([
            get(self.roll, "roll")?,
            get(self.pitch, "pitch")?,
            get(self.yaw, "yaw")?,
        ])
    }
}

/// `[initial_sigma]`: one-sigma uncertainty of the initial estimate; each key optional.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct InitialSigma {
    /// Position, m.
    pub position: Option<f64>,
    /// Velocity, m/s.
    pub velocity: Option<f64>,
    /// Roll and pitch, rad.
    pub level: Option<f64>,
    /// Heading, rad.
    pub heading: Option<f64>,
}

/// `[sensors.imu]`: per-sample noise sigmas at the IMU rate and bias sigmas.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImuNoise {
    /// Gyro bias sigma, rad/s (default 0).
    pub gyro_bias_sigma: f64,
    /// Gyro noise sigma per sample, rad/s (required).
    pub gyro_noise_sigma: f64,
    /// Accelerometer bias sigma, m/s^2 (default 0).
    pub accel_bias_sigma: f64,
    /// Accelerometer noise sigma per sample, m/s^2 (required).
    pub accel_noise_sigma: f64,
}

/// `[sensors.<name>]` for an aiding sensor, in the units of that sensor's CSV file.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SensorNoise {
    /// Bias sigma (default 0).
    pub bias_sigma: f64,
    /// Noise sigma per sample (required).
    pub noise_sigma: f64,
}

/// All `[sensors.*]` sections; `None` = section absent.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Sensors {
    /// `[sensors.imu]`.
    pub imu: Option<ImuNoise>,
    /// `[sensors.dvl]`.
    pub dvl: Option<SensorNoise>,
    /// `[sensors.depth]`.
    pub depth: Option<SensorNoise>,
    /// `[sensors.heading]`.
    pub heading: Option<SensorNoise>,
    /// `[sensors.usbl]`.
    pub usbl: Option<SensorNoise>,
    /// `[sensors.speed]`.
    pub speed: Option<SensorNoise>,
    /// `[sensors.rpm]`.
    pub rpm: Option<SensorNoise>,
    /// `[sensors.altitude]`.
    pub altitude: Option<SensorNoise>,
    /// `[sensors.mag]` (gauss).
    pub mag: Option<SensorNoise>,
    /// `[sensors.baro]` (m).
    pub baro: Option<SensorNoise>,
    /// `[sensors.gnss]` (m, horizontal and vertical).
    pub gnss: Option<SensorNoise>,
    /// `[sensors.usbl] misalignment_sigma`: one-sigma prior of the USBL array
    /// misalignment about each axis, rad (optional; independent of the USBL
    /// bias sigma; `0` = no misalignment state; when absent the filter keeps
    /// its older rule: a prior only when the USBL has a bias sigma).
    pub usbl_misalignment_sigma: Option<f64>,
    /// `[sensors.<name>] lever_arm` / `misalignment` of each aiding sensor, in
    /// [`AIDING_SENSORS`] order (`None`: neither key given); see
    /// [`Sensors::mounting`].
    pub mountings: [Option<Mounting>; AIDING_SENSORS.len()],
    /// `[sensors.dvl] estimate`: which DVL mounting values the filter
    /// estimates, with their prior sigmas (docs/calibration.md).
    pub dvl_calibration: DvlCalibration,
    /// `[sensors.usbl] estimate`: whether the filter estimates the USBL
    /// transponder's lever arm and the lag of the fixes' clock, with their
    /// prior sigmas.
    pub usbl_calibration: DvlCalibration,
    /// `[sensors.gnss] estimate`: whether the filter estimates the GNSS
    /// antenna's lever arm and the lag of the fixes' clock, with their
    /// prior sigmas.
    pub gnss_calibration: DvlCalibration,
}

/// `[sensors.dvl] estimate = [..]` (any subset of [`ESTIMATE_NAMES`]) and
/// the prior sigmas: each field is the prior sigma of a value the filter
/// estimates (`None`: not listed, the given value is taken as exact). The
/// prior means are the section's `lever_arm` and `misalignment` (zero when
/// absent) and a scale of 1.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct DvlCalibration {
    /// Per lever-arm component, m (`lever_arm_sigma`, default
    /// [`LEVER_ARM_SIGMA_DEFAULT`]).
    pub lever_arm: Option<f64>,
    /// Per misalignment angle, rad (`misalignment_sigma`, default
    /// [`MISALIGNMENT_SIGMA_DEFAULT`]).
    pub misalignment: Option<f64>,
    /// Of the scale factor, dimensionless (`scale_sigma`, default
    /// [`SCALE_SIGMA_DEFAULT`]).
    pub scale: Option<f64>,
    /// Of the lag of the sensor's clock behind the log's times, s
    /// (`time_offset_sigma`, default [`TIME_OFFSET_SIGMA_DEFAULT`]).
    pub time_offset: Option<f64>,
}

impl DvlCalibration {
    /// Whether anything is estimated.
    pub fn any(&self) -> bool {
        self.sigmas().iter().any(Option::is_some)
    }

    /// The prior sigma of each name, in [`ESTIMATE_NAMES`] order.
    pub fn sigmas(&self) -> [Option<f64>; 4] {
        [
            self.lever_arm,
            self.misalignment,
            self.scale,
            self.time_offset,
        ]
    }

    /// The names listed, in [`ESTIMATE_NAMES`] order.
    pub fn names(&self) -> Vec<&'static str> {
        self.sigmas()
            .iter()
            .zip(ESTIMATE_NAMES)
            .filter(|(s, _)| s.is_some())
            .map(|(_, n)| n)
            .collect()
    }
}

/// The names of a position fix's `estimate` (`[sensors.usbl]`,
/// `[sensors.gnss]`).
const POSITION_FIX_ESTIMATE_NAMES: [&str; 2] = ["lever_arm", "time_offset"];

/// The names `[sensors.dvl] estimate` accepts.
pub const ESTIMATE_NAMES: [&str; 4] = ["lever_arm", "misalignment", "scale", "time_offset"];

/// The names of [`ESTIMATE_NAMES`] the `estimate` of `[sensors.<name>]`
/// accepts: all four for the DVL, the lever arm and the clock lag for the
/// USBL transponder and the GNSS antenna (the USBL's array misalignment is
/// already a state of its block, with its own `misalignment_sigma`), none
/// for the other sensors.
pub fn estimate_names_of(sensor: &str) -> &'static [&'static str] {
    match sensor {
        "dvl" => &ESTIMATE_NAMES,
        "usbl" | "gnss" => &POSITION_FIX_ESTIMATE_NAMES,
        _ => &[],
    }
}

impl Sensors {
    /// What `[sensors.<sensor>] estimate` lists (`dvl`, `usbl`, `gnss`;
    /// nothing for another sensor).
    pub fn calibration(&self, sensor: &str) -> DvlCalibration {
        match sensor {
            "dvl" => self.dvl_calibration,
            "usbl" => self.usbl_calibration,
            "gnss" => self.gnss_calibration,
            _ => DvlCalibration::default(),
        }
    }
}

/// Prior sigma of each DVL lever-arm component when `estimate` lists
/// `lever_arm` without `lever_arm_sigma`, m: an arm taken off a drawing.
pub const LEVER_ARM_SIGMA_DEFAULT: f64 = 0.5;
/// Prior sigma of each DVL misalignment angle without
/// `misalignment_sigma`, rad: 2 deg, a mounting not calibrated.
pub const MISALIGNMENT_SIGMA_DEFAULT: f64 = 0.034_906_585_039_886_59;
/// Prior sigma of the DVL scale factor without `scale_sigma`: 2 %, the
/// sound-speed error of an uncorrected DVL.
pub const SCALE_SIGMA_DEFAULT: f64 = 0.02;
/// Prior sigma of a sensor clock's lag (DVL, USBL, GNSS) without
/// `time_offset_sigma`, s: a file whose clock was aligned to the IMU's by
/// hand, to the second.
pub const TIME_OFFSET_SIGMA_DEFAULT: f64 = 0.5;

impl Sensors {
    /// The mounting of aiding sensor `name` (`dvl`, `usbl`, ...), if
    /// `meta.toml` gives one.
    pub fn mounting(&self, name: &str) -> Option<&Mounting> {
        let i = AIDING_SENSORS.iter().position(|s| *s == name)?;
        self.mountings.get(i)?.as_ref()
    }

    /// The `[sensors.<name>]` section of aiding sensor `name` (one of
    /// [`AIDING_SENSORS`]), if `meta.toml` has it.
    pub fn aiding(&self, name: &str) -> Option<SensorNoise> {
        let mut copy = *self;
        copy.aiding_mut(name).and_then(|s| *s)
    }

    /// The section of aiding sensor `name`, to change or add.
    pub fn aiding_mut(&mut self, name: &str) -> Option<&mut Option<SensorNoise>> {
        self.sections_mut()
            .into_iter()
            .find(|(n, _)| *n == name)
            .map(|(_, s)| s)
    }

    /// Every aiding sensor's section by name, in [`AIDING_SENSORS`] order:
    /// the one table from names to fields.
    fn sections_mut(&mut self) -> [(&'static str, &mut Option<SensorNoise>); 10] {
        let Sensors {
            dvl,
            depth,
            heading,
            usbl,
            speed,
            rpm,
            altitude,
            mag,
            baro,
            gnss,
            ..
        } = self;
        [
            ("dvl", dvl),
            ("depth", depth),
            ("heading", heading),
            ("usbl", usbl),
            ("speed", speed),
            ("rpm", rpm),
            ("altitude", altitude),
            ("mag", mag),
            ("baro", baro),
            ("gnss", gnss),
        ]
    }
}

/// The sigmas of `[sensors.imu]` by key, in the order they are listed.
fn imu_sigmas(imu: &mut ImuNoise) -> [(&'static str, &mut f64); 4] {
    let ImuNoise {
        gyro_bias_sigma,
        gyro_noise_sigma,
        accel_bias_sigma,
        accel_noise_sigma,
    } = imu;
    [
        ("gyro_noise_sigma", gyro_noise_sigma),
        ("accel_noise_sigma", accel_noise_sigma),
        ("gyro_bias_sigma", gyro_bias_sigma),
        ("accel_bias_sigma", accel_bias_sigma),
    ]
}

/// The sigmas of an aiding sensor's section by key.
fn aiding_sigmas(s: &mut SensorNoise) -> [(&'static str, &mut f64); 2] {
    let SensorNoise {
        noise_sigma,
        bias_sigma,
    } = s;
    [("noise_sigma", noise_sigma), ("bias_sigma", bias_sigma)]
}

/// The noise parameters of `meta.toml` by their key (`sensors.dvl.noise_sigma`,
/// `sensors.imu.gyro_noise_sigma`, ...): what noise tuning reads and
/// changes.
impl Meta {
    /// Every noise parameter the file gives, with its value, in a fixed
    /// order (the IMU's, then the aiding sensors' in [`AIDING_SENSORS`]
    /// order; noise sigmas and bias sigmas).
    pub fn noise_parameters(&self) -> Vec<(String, f64)> {
        let mut copy = *self;
        let mut out = Vec::new();
        if let Some(imu) = copy.sensors.imu.as_mut() {
            for (k, v) in imu_sigmas(imu) {
                out.push((format!("sensors.imu.{k}"), *v));
            }
        }
        for (name, section) in copy.sensors.sections_mut() {
            if let Some(s) = section {
                for (k, v) in aiding_sigmas(s) {
                    out.push((format!("sensors.{name}.{k}"), *v));
                }
            }
        }
        out
    }

    /// The value of noise parameter `key` (see [`Meta::noise_parameters`]).
    pub fn noise_parameter(&self, key: &str) -> Option<f64> {
        let mut copy = *self;
        copy.noise_parameter_mut(key).map(|v| *v)
    }

    /// The place of noise parameter `key`, if the file gives it.
    fn noise_parameter_mut(&mut self, key: &str) -> Option<&mut f64> {
        let mut parts = key.split('.');
        let (Some("sensors"), Some(sensor), Some(field), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return None;
        };
        let slots: Vec<(&str, &mut f64)> = if sensor == "imu" {
            imu_sigmas(self.sensors.imu.as_mut()?).into()
        } else {
            aiding_sigmas(self.sensors.aiding_mut(sensor)?.as_mut()?).into()
        };
        slots.into_iter().find(|(k, _)| *k == field).map(|(_, v)| v)
    }

    /// The sensor of `key` when it names a field its section would have
    /// (`sensors.dvl.noise_sigma`) but the file has no such section.
    fn missing_section_of<'k>(&mut self, key: &'k str) -> Option<&'k str> {
        let mut parts = key.split('.');
        let (Some("sensors"), Some(sensor), Some(field), None) =
            (parts.next(), parts.next(), parts.next(), parts.next())
        else {
            return None;
        };
        // The keys a section would have, from the one list of each.
        let (missing, keys): (bool, Vec<&str>) = if sensor == "imu" {
            let mut blank = ImuNoise {
                gyro_bias_sigma: 0.0,
                gyro_noise_sigma: 0.0,
                accel_bias_sigma: 0.0,
                accel_noise_sigma: 0.0,
            };
            let keys = imu_sigmas(&mut blank).map(|(k, _)| k).to_vec();
            (self.sensors.imu.is_none(), keys)
        } else {
            let mut blank = SensorNoise {
                noise_sigma: 0.0,
                bias_sigma: 0.0,
            };
            let keys = aiding_sigmas(&mut blank).map(|(k, _)| k).to_vec();
            (matches!(self.sensors.aiding_mut(sensor), Some(None)), keys)
        };
        (missing && keys.contains(&field)).then_some(sensor)
    }

    /// Sets noise parameter `key` (which the file must give) to `value`.
    ///
    /// # Errors
    /// [`LogError::Meta`] naming the key when `meta.toml` has no such
    /// parameter (with the closest one) or `value` is not a finite sigma
    /// (not negative).
    pub fn set_noise_parameter(&mut self, key: &str, value: f64) -> Result<(), LogError> {
        if !(value.is_finite() && value >= 0.0) {
            return Err(LogError::meta(
                key,
                format!("{value} is not a sigma (finite, not negative)"),
            ));
        }
        let known: Vec<String> = self
            .noise_parameters()
            .into_iter()
            .map(|(k, _)| k)
            .collect();
        let missing = self.missing_section_of(key);
        let Some(slot) = self.noise_parameter_mut(key) else {
            if let Some(sensor) = missing {
                return Err(LogError::meta(
                    key,
                    format!(
                        "this meta.toml has no [sensors.{sensor}] section: the model's built-in \
                         sigmas are used; add the section (with the data sheet's values) to set \
                         or tune them"
                    ),
                ));
            }
            let known: Vec<&str> = known.iter().map(String::as_str).collect();
            return Err(LogError::meta(
                key,
                format!(
                    "not a noise parameter of this meta.toml{}",
                    crate::suggestion::did_you_mean(key, &known)
                ),
            ));
        };
        *slot = value;
        Ok(())
    }
}

/// Where an aiding sensor sits on the vehicle: `[sensors.<name>] lever_arm`
/// and `misalignment` (each optional, zero when absent).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Mounting {
    /// Position of the sensor relative to the IMU, body frame FRD, m.
    pub lever_arm: [f64; 3],
    /// Rotation of the sensor frame relative to the body frame as roll,
    /// pitch, yaw (rad, the Euler convention of `[initial]`).
    pub misalignment: [f64; 3],
}

/// Aiding sensors that may carry a mounting (not `rpm`).
const MOUNTED: &[&str] = &[
    "dvl", "depth", "heading", "usbl", "speed", "altitude", "mag", "baro", "gnss",
];

/// Aiding sensor names accepted under `[sensors.<name>]` (besides `imu`).
pub const AIDING_SENSORS: &[&str] = &[
    "dvl", "depth", "heading", "usbl", "speed", "rpm", "altitude", "mag", "baro", "gnss",
];

/// `[usbl]`: the USBL transducer position.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UsblTransducer {
    /// Latitude, rad.
    pub lat: f64,
    /// Longitude, rad.
    pub lon: f64,
    /// Depth, m.
    pub depth: f64,
}

/// The content of `meta.toml`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Meta {
    /// `[initial]`.
    pub initial: Initial,
    /// `[initial_sigma]`, if present.
    pub initial_sigma: Option<InitialSigma>,
    /// `[sensors.*]`.
    pub sensors: Sensors,
    /// `[usbl]`, if present.
    pub usbl: Option<UsblTransducer>,
}

impl Meta {
    /// A meta with only the required `[initial]` position; everything else absent/zero.
    pub fn at(lat: f64, lon: f64, depth: f64) -> Self {
        Meta {
            initial: Initial {
                t: None,
                lat,
                lon,
                depth,
                vn: 0.0,
                ve: 0.0,
                vd: 0.0,
                roll: None,
                pitch: None,
                yaw: None,
            },
            initial_sigma: None,
            sensors: Sensors::default(),
            usbl: None,
        }
    }

    /// Parses and validates `meta.toml` text; [`Meta::parse_with_warnings`]
    /// without the warnings.
    pub fn parse(text: &str) -> Result<Meta, LogError> {
        Self::parse_with_warnings(text).map(|(meta, _)| meta)
    }

    /// Parses and validates `meta.toml` text.
    ///
    /// Unknown keys inside a known section and unknown sensor names are errors
    /// (with the closest valid name suggested); so are non-numbers, non-finite
    /// numbers, negative sigmas, zero or negative noise sigmas, `|lat| > pi/2`,
    /// `|lon| > 2 pi`, `|roll| > pi`, `|pitch| > pi/2` and `|yaw| > 2 pi` (named as
    /// degrees, the likely cause). An unknown top-level section (another tool's
    /// `[vehicle]` or `[generator]`) is accepted and returned as a warning.
    pub fn parse_with_warnings(text: &str) -> Result<(Meta, Vec<Warning>), LogError> {
        Self::parse_log(text).map(|(meta, _, warnings)| (meta, warnings))
    }

    /// Parses and validates `meta.toml` text with its `[files.<sensor>]`
    /// sections (how the log's files are read; see [`LogMapping`]).
    pub fn parse_log(text: &str) -> Result<(Meta, LogMapping, Vec<Warning>), LogError> {
        let table: toml::Table = text.parse().map_err(|e: toml::de::Error| {
            let line = e.span().map(|s| {
                text.as_bytes()[..s.start.min(text.len())]
                    .iter()
                    .filter(|&&b| b == b'\n')
                    .count() as u64
                    + 1
            });
            LogError::Meta {
                key: String::new(),
                line,
                problem: e.message().trim().replace('\n', " "),
            }
        })?;
        let cx = Cx { text };
        let mut warnings = Vec::new();
        for (name, value) in &table {
            if !TOP_LEVEL.contains(&name.as_str()) {
                // A value outside any section (`foo = 3` above the first
                // header) is a key, not a section.
                let what = if value.is_table() { "section" } else { "key" };
                let line = cx
                    .locate(name, "")
                    .or_else(|| cx.locate("", name))
                    .or_else(|| {
                        let prefix = format!("[{name}.");
                        text.lines()
                            .position(|l| l.trim_start().starts_with(&prefix))
                            .map(|n| n as u64 + 1)
                    });
                let mut message = format!(
                    "unknown {what} `{name}` ignored (sections read: {})",
                    TOP_LEVEL.join(", ")
                );
                if let Some(close) = closest_name(name, TOP_LEVEL) {
                    message.push_str(&format!("; did you mean `{close}`?"));
                    // A misspelling of a section the file lacks would leave
                    // its values to defaults without a word: refused.
                    if !table.contains_key(close) {
                        return Err(cx.err(
                            name,
                            format!(
                                "unknown section; expected one of: {}; did you mean `{close}`?",
                                TOP_LEVEL.join(", ")
                            ),
                        ));
                    }
                }
                warnings.push(Warning {
                    kind: WarningKind::UnknownSection,
                    file: Some(super::META_FILE.to_string()),
                    line,
                    key: Some(name.clone()),
                    message,
                });
            }
        }

        let initial = cx
            .section(&table, "", "initial")?
            .ok_or_else(|| cx.err("initial", "missing section [initial]"))?;
        cx.check_keys(
            initial,
            "initial",
            &[
                "t",
                "lat",
                "lon",
                "depth",
                "vn",
                "ve",
                "vd",
                "roll",
                "pitch",
                "yaw",
                "lever_arm",
            ],
        )?;
        // None of lat, lon, depth: an attitude-only meta.toml (NaN); some of
        // them: the others are missing keys.
        let attitude_only = ["lat", "lon", "depth"]
            .iter()
            .all(|k| !initial.contains_key(*k));
        let position = |key: &str, range: Range| {
            if attitude_only {
                Ok(f64::NAN)
            } else {
                cx.req(initial, "initial", key, range)
            }
        };
        let arm = cx.vec3(initial, "initial", "lever_arm", Range::LeverArm)?;
        let mut initial = Initial {
            t: cx.opt(initial, "initial", "t", Range::Any)?,
            lat: position("lat", Range::Lat)?,
            lon: position("lon", Range::Lon)?,
            depth: position("depth", Range::Any)?,
            vn: cx
                .opt(initial, "initial", "vn", Range::Speed)?
                .unwrap_or(0.0),
            ve: cx
                .opt(initial, "initial", "ve", Range::Speed)?
                .unwrap_or(0.0),
            vd: cx
                .opt(initial, "initial", "vd", Range::Speed)?
                .unwrap_or(0.0),
            roll: cx.opt(initial, "initial", "roll", Range::Roll)?,
            pitch: cx.opt(initial, "initial", "pitch", Range::Lat)?,
            yaw: cx.opt(initial, "initial", "yaw", Range::Yaw)?,
        };
        if let Some(point) = arm.and_then(ReferencePoint::new) {
            initial.move_to_imu(&point).map_err(|missing| {
                cx.err(
                    "initial.lever_arm",
                    format!(
                        "moving the initial position to the IMU needs `initial.{missing}`, \
                         which is not given"
                    ),
                )
            })?;
        }

        let initial_sigma = match cx.section(&table, "", "initial_sigma")? {
            None => None,
            Some(s) => {
                let sec = "initial_sigma";
                cx.check_keys(s, sec, &["position", "velocity", "level", "heading"])?;
                Some(InitialSigma {
                    position: cx.opt(s, sec, "position", Range::Prior)?,
                    velocity: cx.opt(s, sec, "velocity", Range::Prior)?,
                    level: cx.opt(s, sec, "level", Range::AnglePrior)?,
                    heading: cx.opt(s, sec, "heading", Range::AnglePrior)?,
                })
            }
        };

        let mut sensors = Sensors::default();
        if let Some(s) = cx.section(&table, "", "sensors")? {
            let mut allowed = vec!["imu"];
            allowed.extend_from_slice(AIDING_SENSORS);
            cx.check_keys(s, "sensors", &allowed)?;
            if let Some(imu) = cx.section(s, "sensors", "imu")? {
                let sec = "sensors.imu";
                cx.check_keys(
                    imu,
                    sec,
                    &[
                        "gyro_bias_sigma",
                        "gyro_noise_sigma",
                        "accel_bias_sigma",
                        "accel_noise_sigma",
                    ],
                )?;
                sensors.imu = Some(ImuNoise {
                    gyro_bias_sigma: cx
                        .opt(imu, sec, "gyro_bias_sigma", Range::Sigma)?
                        .unwrap_or(0.0),
                    gyro_noise_sigma: cx.req(imu, sec, "gyro_noise_sigma", Range::Noise)?,
                    accel_bias_sigma: cx
                        .opt(imu, sec, "accel_bias_sigma", Range::Sigma)?
                        .unwrap_or(0.0),
                    accel_noise_sigma: cx.req(imu, sec, "accel_noise_sigma", Range::Noise)?,
                });
            }
            for name in AIDING_SENSORS {
                let sec = format!("sensors.{name}");
                let Some(t) = cx.section(s, "sensors", name)? else {
                    continue;
                };
                let mut keys = vec!["bias_sigma", "noise_sigma"];
                if MOUNTED.contains(name) {
                    keys.extend(["lever_arm", "misalignment"]);
                }
                if *name == "usbl" {
                    keys.push("misalignment_sigma");
                }
                let accepted = estimate_names_of(name);
                if !accepted.is_empty() {
                    keys.push(CALIBRATION_KEYS[0]);
                    keys.extend(
                        ESTIMATE_NAMES
                            .iter()
                            .zip(&CALIBRATION_KEYS[1..])
                            .filter(|(n, _)| accepted.contains(n))
                            .map(|(_, k)| *k),
                    );
                }
                cx.check_keys(t, &sec, &keys)?;
                match *name {
                    "dvl" => sensors.dvl_calibration = cx.dvl_calibration(t, &sec, accepted)?,
                    "usbl" => sensors.usbl_calibration = cx.dvl_calibration(t, &sec, accepted)?,
                    "gnss" => sensors.gnss_calibration = cx.dvl_calibration(t, &sec, accepted)?,
                    _ => {}
                }
                if *name == "usbl" {
                    sensors.usbl_misalignment_sigma =
                        cx.opt(t, &sec, "misalignment_sigma", Range::AngleSigma)?;
                }
                // The compass's sigmas are angles (rad), as its file.
                let (sigma, noise) = if *name == "heading" {
                    (Range::AngleSigma, Range::AngleNoise)
                } else {
                    (Range::Sigma, Range::Noise)
                };
                let lever_arm = cx.vec3(t, &sec, "lever_arm", Range::LeverArm)?;
                let misalignment = cx.vec3(t, &sec, "misalignment", Range::Roll)?;
                if lever_arm.is_some() || misalignment.is_some() {
                    let i = AIDING_SENSORS.iter().position(|s| s == name).unwrap_or(0);
                    sensors.mountings[i] = Some(Mounting {
                        lever_arm: lever_arm.unwrap_or_default(),
                        misalignment: misalignment.unwrap_or_default(),
                    });
                }
                let noise = SensorNoise {
                    bias_sigma: cx.opt(t, &sec, "bias_sigma", sigma)?.unwrap_or(0.0),
                    noise_sigma: cx.req(t, &sec, "noise_sigma", noise)?,
                };
                let slot = match *name {
                    "dvl" => &mut sensors.dvl,
                    "depth" => &mut sensors.depth,
                    "heading" => &mut sensors.heading,
                    "usbl" => &mut sensors.usbl,
                    "speed" => &mut sensors.speed,
                    "rpm" => &mut sensors.rpm,
                    "mag" => &mut sensors.mag,
                    "baro" => &mut sensors.baro,
                    "gnss" => &mut sensors.gnss,
                    _ => &mut sensors.altitude,
                };
                *slot = Some(noise);
            }
        }

        let usbl = match cx.section(&table, "", "usbl")? {
            None => None,
            Some(u) => {
                cx.check_keys(u, "usbl", &["lat", "lon", "depth"])?;
                Some(UsblTransducer {
                    lat: cx.req(u, "usbl", "lat", Range::Lat)?,
                    lon: cx.req(u, "usbl", "lon", Range::Lon)?,
                    depth: cx.req(u, "usbl", "depth", Range::Any)?,
                })
            }
        };

        let mapping = match cx.section(&table, "", "files")? {
            None => LogMapping::default(),
            Some(files) => LogMapping::parse(&cx, files)?,
        };

        Ok((
            Meta {
                initial,
                initial_sigma,
                sensors,
                usbl,
            },
            mapping,
            warnings,
        ))
    }

    /// Renders `meta.toml` text that [`Meta::parse`] reads back to the same value.
    pub fn to_toml(&self) -> String {
        let mut s = String::new();
        let f = |v: f64| {
            // Debug always has a `.` or an exponent: a TOML float, and round-trip exact.
            format!("{v:?}")
        };
        let i = &self.initial;
        let _ = writeln!(s, "[initial]");
        for (k, v) in [
            ("t", i.t),
            ("lat", Some(i.lat)),
            ("lon", Some(i.lon)),
            ("depth", Some(i.depth)),
            ("vn", Some(i.vn)),
            ("ve", Some(i.ve)),
            ("vd", Some(i.vd)),
            ("roll", i.roll),
            ("pitch", i.pitch),
            ("yaw", i.yaw),
        ] {
            if let Some(v) = v.filter(|v| v.is_finite()) {
                let _ = writeln!(s, "{k} = {}", f(v));
            }
        }
        if let Some(sig) = &self.initial_sigma {
            let _ = writeln!(s, "\n[initial_sigma]");
            for (k, v) in [
                ("position", sig.position),
                ("velocity", sig.velocity),
                ("level", sig.level),
                ("heading", sig.heading),
            ] {
                if let Some(v) = v {
                    let _ = writeln!(s, "{k} = {}", f(v));
                }
            }
        }
        if let Some(imu) = &self.sensors.imu {
            let _ = writeln!(s, "\n[sensors.imu]");
            let _ = writeln!(s, "gyro_bias_sigma = {}", f(imu.gyro_bias_sigma));
            let _ = writeln!(s, "gyro_noise_sigma = {}", f(imu.gyro_noise_sigma));
            let _ = writeln!(s, "accel_bias_sigma = {}", f(imu.accel_bias_sigma));
            let _ = writeln!(s, "accel_noise_sigma = {}", f(imu.accel_noise_sigma));
        }
        let sn = &self.sensors;
        for (name, v) in [
            ("dvl", sn.dvl),
            ("depth", sn.depth),
            ("heading", sn.heading),
            ("usbl", sn.usbl),
            ("speed", sn.speed),
            ("rpm", sn.rpm),
            ("altitude", sn.altitude),
            ("mag", sn.mag),
            ("baro", sn.baro),
            ("gnss", sn.gnss),
        ] {
            if let Some(n) = v {
                let _ = writeln!(s, "\n[sensors.{name}]");
                let _ = writeln!(s, "bias_sigma = {}", f(n.bias_sigma));
                let _ = writeln!(s, "noise_sigma = {}", f(n.noise_sigma));
                if let ("usbl", Some(m)) = (name, sn.usbl_misalignment_sigma) {
                    let _ = writeln!(s, "misalignment_sigma = {}", f(m));
                }
                if let Some(m) = sn.mounting(name) {
                    let v = |a: [f64; 3]| format!("[{}, {}, {}]", f(a[0]), f(a[1]), f(a[2]));
                    let _ = writeln!(s, "lever_arm = {}", v(m.lever_arm));
                    let _ = writeln!(s, "misalignment = {}", v(m.misalignment));
                }
                let cal = sn.calibration(name);
                if cal.any() {
                    let names: Vec<String> =
                        cal.names().iter().map(|n| format!("\"{n}\"")).collect();
                    let _ = writeln!(s, "estimate = [{}]", names.join(", "));
                    for (key, sigma) in CALIBRATION_KEYS[1..].iter().zip(cal.sigmas()) {
                        if let Some(sigma) = sigma {
                            let _ = writeln!(s, "{key} = {}", f(sigma));
                        }
                    }
                }
            }
        }
        if let Some(u) = &self.usbl {
            let _ = writeln!(s, "\n[usbl]");
            let _ = writeln!(s, "lat = {}", f(u.lat));
            let _ = writeln!(s, "lon = {}", f(u.lon));
            let _ = writeln!(s, "depth = {}", f(u.depth));
        }
        s
    }
}

/// The keys of `[sensors.dvl]` for its mounting calibration: the list,
/// then the prior sigma of each name of [`ESTIMATE_NAMES`] in its order.
const CALIBRATION_KEYS: [&str; 5] = [
    "estimate",
    "lever_arm_sigma",
    "misalignment_sigma",
    "scale_sigma",
    "time_offset_sigma",
];

/// The top-level sections `meta.toml` is read from.
const TOP_LEVEL: &[&str] = &["initial", "initial_sigma", "sensors", "usbl", "files"];

#[derive(Clone, Copy)]
enum Range {
    Any,
    Lat,
    Lon,
    Roll,
    Yaw,
    Sigma,
    Noise,
    /// The sigma of an angle, rad: at most pi (beyond, degrees).
    AngleSigma,
    /// The noise sigma of an angle, rad: above 0, at most pi.
    AngleNoise,
    LeverArm,
    /// A velocity component, m/s.
    Speed,
    /// The 1-sigma of an initial estimate: above 0 (a zero claims the
    /// state exactly known: the filter's covariance starts singular and
    /// the NEES against a truth divides by it), its square finite.
    Prior,
    /// The 1-sigma of an initial angle, rad: above 0, at most pi.
    AnglePrior,
    /// The prior sigma of a clock lag, s: above 0, at most
    /// [`MAX_LAG_SIGMA`] (the lag enters to first order).
    LagSigma,
}

impl Range {
    fn check(self, v: f64) -> Result<(), &'static str> {
        use core::f64::consts::{FRAC_PI_2, PI};
        let ok = match self {
            Range::Any => true,
            Range::Lat => v.abs() <= FRAC_PI_2,
            Range::Lon => v.abs() <= 2.0 * PI,
            Range::Roll => v.abs() <= PI,
            Range::Yaw => v.abs() <= 2.0 * PI,
            // A sigma is squared into a variance: the square must be finite.
            Range::Sigma => v >= 0.0 && (v * v).is_finite(),
            // A noise sigma whose square underflows to 0 (1e-300) is a zero
            // noise as well.
            Range::Noise => v > 0.0 && v * v > 0.0 && (v * v).is_finite(),
            Range::AngleSigma => (0.0..=PI).contains(&v),
            Range::AngleNoise => v > 0.0 && v * v > 0.0 && v <= PI,
            Range::LeverArm => v.abs() <= MAX_LEVER_ARM,
            Range::Speed => v.abs() <= MAX_SPEED,
            Range::Prior => v > 0.0 && v * v > 0.0 && (v * v).is_finite(),
            Range::AnglePrior => v > 0.0 && v * v > 0.0 && v <= PI,
            Range::LagSigma => v > 0.0 && v * v > 0.0 && v <= MAX_LAG_SIGMA,
        };
        if ok {
            Ok(())
        } else {
            Err(match self {
                Range::Any => "",
                Range::Lat => "allowed: |value| <= pi/2",
                Range::Lon => "allowed: |value| <= 2 pi",
                Range::Roll => "allowed: |value| <= pi",
                Range::Yaw => "allowed: |value| <= 2 pi; degrees? the format is radians",
                Range::Sigma => "a sigma must be >= 0, its square finite",
                Range::Noise => {
                    "a noise sigma must be > 0 (zero noise makes the filter trust the sensor exactly), its square finite and above 0"
                }
                Range::AngleSigma => {
                    "an angle's sigma must be in 0..=pi rad; degrees? the format is radians"
                }
                Range::AngleNoise => {
                    "an angle's noise sigma must be > 0 and <= pi rad; degrees? the format is radians"
                }
                Range::LeverArm => "allowed: |value| <= 1000 m; millimetres? the format is metres",
                Range::Speed => "allowed: |value| <= 10000 m/s (faster than any vehicle)",
                Range::Prior => {
                    "an initial sigma must be > 0 (zero claims the state exactly known; give the uncertainty of the initial value), its square finite and above 0"
                }
                Range::AnglePrior => {
                    "an initial angle's sigma must be > 0 (zero claims the angle exactly known) and <= pi rad; degrees? the format is radians"
                }
                Range::LagSigma => {
                    "a clock lag's sigma must be > 0 and <= 10 s (the filter models the lag to first order; a larger misalignment of clocks is set with `files.<file>.time.offset_s`); milliseconds? the format is seconds"
                }
            })
        }
    }
}

/// Largest prior sigma of a clock lag accepted, s.
const MAX_LAG_SIGMA: f64 = 10.0;
/// Largest lever-arm component accepted (m).
const MAX_LEVER_ARM: f64 = 1000.0;
/// Largest initial velocity component accepted, m/s (above any vehicle's
/// speed; the DVL's physical bound of the preflight is the same).
const MAX_SPEED: f64 = 1e4;

/// Validation context: the source text, to find line numbers of keys.
pub(super) struct Cx<'a> {
    text: &'a str,
}

fn join(section: &str, key: &str) -> String {
    if section.is_empty() {
        key.to_string()
    } else {
        format!("{section}.{key}")
    }
}

impl Cx<'_> {
    /// Best-effort 1-based line of `key` in `[section]` (or of the section header when
    /// `key` is empty). Handles the plain `[a.b]` / `key = value` layout.
    fn locate(&self, section: &str, key: &str) -> Option<u64> {
        let mut current = String::new();
        for (n, raw) in self.text.lines().enumerate() {
            let line = raw.trim();
            if let Some(h) = line.strip_prefix('[') {
                let name = h.split(']').next().unwrap_or("");
                current = name
                    .split('.')
                    .map(|p| p.trim().trim_matches('"'))
                    .collect::<Vec<_>>()
                    .join(".");
                if key.is_empty() && current == section {
                    return Some(n as u64 + 1);
                }
                continue;
            }
            if current == section && !key.is_empty() {
                if let Some((k, _)) = line.split_once('=') {
                    if k.trim().trim_matches('"') == key {
                        return Some(n as u64 + 1);
                    }
                }
            }
        }
        None
    }

    pub(super) fn err(&self, dotted: &str, problem: impl Into<String>) -> LogError {
        let (section, key) = match dotted.rsplit_once('.') {
            Some((s, k)) => (s, k),
            None => ("", dotted),
        };
        let line = self
            .locate(section, key)
            .or_else(|| self.locate(dotted, ""))
            .or_else(|| self.locate(section, ""));
        LogError::Meta {
            key: dotted.to_string(),
            line,
            problem: problem.into(),
        }
    }

    pub(super) fn check_keys(
        &self,
        t: &toml::Table,
        section: &str,
        allowed: &[&str],
    ) -> Result<(), LogError> {
        for k in t.keys() {
            if !allowed.contains(&k.as_str()) {
                let what = if section == "sensors" {
                    "unknown sensor name"
                } else if section.is_empty() {
                    "unknown section"
                } else {
                    "unknown key"
                };
                let mut problem = format!("{what}; expected one of: {}", allowed.join(", "));
                if let Some(close) = closest_name(k, allowed) {
                    problem.push_str(&format!("; did you mean `{close}`?"));
                }
                return Err(self.err(&join(section, k), problem));
            }
        }
        Ok(())
    }

    pub(super) fn section<'t>(
        &self,
        t: &'t toml::Table,
        parent: &str,
        key: &str,
    ) -> Result<Option<&'t toml::Table>, LogError> {
        match t.get(key) {
            None => Ok(None),
            Some(toml::Value::Table(s)) => Ok(Some(s)),
            Some(other) => Err(self.err(
                &join(parent, key),
                format!("expected a table, found {}", other.type_str()),
            )),
        }
    }

    fn opt(
        &self,
        t: &toml::Table,
        section: &str,
        key: &str,
        range: Range,
    ) -> Result<Option<f64>, LogError> {
        let dotted = join(section, key);
        let v = match t.get(key) {
            None => return Ok(None),
            Some(toml::Value::Float(f)) => *f,
            Some(toml::Value::Integer(i)) => *i as f64,
            Some(other) => {
                return Err(self.err(
                    &dotted,
                    format!("expected a number, found {}", other.type_str()),
                ))
            }
        };
        if !v.is_finite() {
            return Err(self.err(&dotted, format!("non-finite value {v}")));
        }
        range.check(v).map_err(|allowed| {
            self.err(
                &dotted,
                format!("value {} out of range ({allowed})", Magnitude(v)),
            )
        })?;
        Ok(Some(v))
    }

    /// `[sensors.dvl] estimate` and the prior sigmas of the names it lists:
    /// an unknown, repeated or non-string name, and a sigma for a name not
    /// listed, are errors naming the key.
    fn dvl_calibration(
        &self,
        t: &toml::Table,
        sec: &str,
        names: &[&str],
    ) -> Result<DvlCalibration, LogError> {
        let key = join(sec, "estimate");
        let accepted = names.join(", ");
        let mut listed = [false; ESTIMATE_NAMES.len()];
        match t.get("estimate") {
            None => {}
            Some(toml::Value::Array(items)) => {
                for item in items {
                    let toml::Value::String(name) = item else {
                        return Err(self.err(
                            &key,
                            format!(
                                "expected an array of names (strings) out of {accepted}, found an item of type {}",
                                item.type_str()
                            ),
                        ));
                    };
                    let i = ESTIMATE_NAMES.iter().position(|n| n == name);
                    let Some(i) = i.filter(|_| names.contains(&name.as_str())) else {
                        let file = sec.trim_start_matches("sensors.");
                        let problem = if ESTIMATE_NAMES.contains(&name.as_str()) {
                            format!(
                                "`{name}` is not estimated for the {file}; accepted: {accepted}{}",
                                if file == "usbl" && name == "misalignment" {
                                    " (the USBL's array misalignment is already a state of its block: give its prior as `misalignment_sigma`)"
                                } else {
                                    ""
                                }
                            )
                        } else {
                            format!(
                                "unknown name `{name}`; accepted: {accepted}{}",
                                crate::suggestion::did_you_mean(name, names)
                            )
                        };
                        return Err(self.err(&key, problem));
                    };
                    if listed[i] {
                        return Err(self.err(&key, format!("`{name}` is listed twice")));
                    }
                    listed[i] = true;
                }
            }
            Some(other) => {
                return Err(self.err(
                    &key,
                    format!(
                        "expected an array of names out of {accepted} (e.g. estimate = [\"lever_arm\"]), found {}",
                        other.type_str()
                    ),
                ))
            }
        }
        let ranges = [
            Range::Noise,
            Range::AngleNoise,
            Range::Noise,
            Range::LagSigma,
        ];
        let defaults = [
            LEVER_ARM_SIGMA_DEFAULT,
            MISALIGNMENT_SIGMA_DEFAULT,
            SCALE_SIGMA_DEFAULT,
            TIME_OFFSET_SIGMA_DEFAULT,
        ];
        let mut sigma = [None; ESTIMATE_NAMES.len()];
        for i in (0..ESTIMATE_NAMES.len()).filter(|&i| names.contains(&ESTIMATE_NAMES[i])) {
            let sigma_key = CALIBRATION_KEYS[i + 1];
            let given = self.opt(t, sec, sigma_key, ranges[i])?;
            if given.is_some() && !listed[i] {
                return Err(self.err(
                    &join(sec, sigma_key),
                    format!(
                        "a prior sigma for `{}`, which `estimate` does not list (add it there, or drop this key)",
                        ESTIMATE_NAMES[i]
                    ),
                ));
            }
            sigma[i] = listed[i].then(|| given.unwrap_or(defaults[i]));
        }
        Ok(DvlCalibration {
            lever_arm: sigma[0],
            misalignment: sigma[1],
            scale: sigma[2],
            time_offset: sigma[3],
        })
    }

    /// An optional lever arm `key` of `section`: three numbers, m, each
    /// within the bounds of a lever arm on a vehicle.
    pub(super) fn lever_arm(
        &self,
        t: &toml::Table,
        section: &str,
        key: &str,
    ) -> Result<Option<[f64; 3]>, LogError> {
        self.vec3(t, section, key, Range::LeverArm)
    }

    /// An optional array of three numbers, each in `range`.
    fn vec3(
        &self,
        t: &toml::Table,
        section: &str,
        key: &str,
        range: Range,
    ) -> Result<Option<[f64; 3]>, LogError> {
        let dotted = join(section, key);
        let Some(v) = t.get(key) else {
            return Ok(None);
        };
        let items = match v {
            toml::Value::Array(a) if a.len() == 3 => a,
            other => {
                return Err(self.err(
                    &dotted,
                    format!(
                        "expected an array of 3 numbers [x, y, z], found {}",
                        match other {
                            toml::Value::Array(a) => format!("an array of {}", a.len()),
                            o => o.type_str().to_string(),
                        }
                    ),
                ))
            }
        };
        let mut out = [0.0; 3];
        for (i, item) in items.iter().enumerate() {
            let x = match item {
                toml::Value::Float(f) => *f,
                toml::Value::Integer(i) => *i as f64,
                other => {
                    return Err(self.err(
                        &dotted,
                        format!("expected numbers, found {}", other.type_str()),
                    ))
                }
            };
            if !x.is_finite() {
                return Err(self.err(&dotted, format!("non-finite value {x}")));
            }
            range.check(x).map_err(|allowed| {
                self.err(
                    &dotted,
                    format!("value {} out of range ({allowed})", Magnitude(x)),
                )
            })?;
            out[i] = x;
        }
        Ok(Some(out))
    }

    fn req(
        &self,
        t: &toml::Table,
        section: &str,
        key: &str,
        range: Range,
    ) -> Result<f64, LogError> {
        self.opt(t, section, key, range)?
            .ok_or_else(|| self.err(&join(section, key), "missing key"))
    }
}

#[cfg(test)]
mod noise_parameter_tests {
    use super::*;

    const META: &str = "[initial]\nlat = 0.6\nlon = 2.2\ndepth = 10.0\n\n[sensors.imu]\ngyro_noise_sigma = 1e-6\naccel_noise_sigma = 1e-3\n\n[sensors.dvl]\nnoise_sigma = 0.02\nbias_sigma = 0.01\n";

    #[test]
    fn noise_parameters_are_listed_read_and_set_by_key() {
        let mut m = Meta::parse(META).unwrap();
        let keys: Vec<String> = m.noise_parameters().into_iter().map(|(k, _)| k).collect();
        assert_eq!(
            keys,
            [
                "sensors.imu.gyro_noise_sigma",
                "sensors.imu.accel_noise_sigma",
                "sensors.imu.gyro_bias_sigma",
                "sensors.imu.accel_bias_sigma",
                "sensors.dvl.noise_sigma",
                "sensors.dvl.bias_sigma",
            ]
        );
        m.set_noise_parameter("sensors.dvl.noise_sigma", 0.05)
            .unwrap();
        m.set_noise_parameter("sensors.imu.accel_noise_sigma", 2e-3)
            .unwrap();
        assert_eq!(m.sensors.dvl.unwrap().noise_sigma, 0.05);
        assert_eq!(
            m.noise_parameter("sensors.imu.accel_noise_sigma"),
            Some(2e-3)
        );
        assert_eq!(m.sensors.aiding("dvl").map(|s| s.bias_sigma), Some(0.01));
        assert!(m.sensors.aiding("depth").is_none());
    }

    #[test]
    fn a_key_the_file_lacks_or_a_value_that_is_no_sigma_is_an_error_naming_the_key() {
        // (key, value, what the message says)
        let cases = [
            (
                "sensors.dvl.noise_sigmaa",
                1.0,
                "did you mean `sensors.dvl.noise_sigma`",
            ),
            // A sensor whose section the file lacks: the section is named.
            (
                "sensors.depth.noise_sigma",
                1.0,
                "no [sensors.depth] section",
            ),
            (
                "sensors.depth.bias_sigma",
                1.0,
                "no [sensors.depth] section",
            ),
            ("sensors.depth.noise", 1.0, "not a noise parameter"),
            ("sensors.dvl", 1.0, "not a noise parameter"),
            ("initial.lat", 1.0, "not a noise parameter"),
            ("sensors.dvl.noise_sigma", -1.0, "not a sigma"),
            ("sensors.dvl.noise_sigma", f64::NAN, "not a sigma"),
        ];
        for (key, value, says) in cases {
            let mut m = Meta::parse(META).unwrap();
            let before = m;
            let e = m.set_noise_parameter(key, value).unwrap_err().to_string();
            assert!(e.contains(key) && e.contains(says), "{key}: {e}");
            assert_eq!(m, before, "{key}: changed on error");
        }
    }
}
