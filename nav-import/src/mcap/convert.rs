//! From decoded messages to the rows of the log directory's files: sensor
//! per topic, ROS frames (REP-103: ENU world, FLU body) to the log format's
//! NED / FRD, clock, units, covariances to sigmas, and `meta.toml`.

use std::collections::{BTreeMap, HashMap};
use std::fmt::Write as _;

use nav_runtime::earth::{meridian_radius, transverse_radius};

use super::mapping::{Clock, Mapping, Sensor, TopicMap};
use super::messages::{self, Reading};
use super::mounting::{frame_name, Mount, Resolved, Transform, Tree, MAX_TRANSLATION_M};
use super::{ImportError, ImportSummary, ImportedBag};
use crate::ulog::assemble::{leveled, LEVELING_S};
use crate::ulog::CsvFile;

/// A time further than this from the first message's, s, is absurd (a
/// stamp in another unit or an unset clock).
const MAX_SPAN_S: f64 = 1e7;
/// Standard gravity, m/s^2 (depth from pressure).
const G0: f64 = 9.806_65;
/// Gauss per tesla.
const GAUSS_PER_TESLA: f64 = 1e4;

struct Channel {
    topic: String,
    ty: String,
    map: Option<TopicMap>,
    messages: u64,
}

/// Streams messages into files (see the module docs).
pub struct Converter<'m> {
    file: String,
    mapping: &'m Mapping,
    channels: HashMap<u16, Channel>,
    /// Sensor -> the topic feeding it.
    feeding: BTreeMap<Sensor, String>,
    files: BTreeMap<Sensor, CsvFile>,
    origin_ns: Option<i64>,
    /// First positive variance per sensor (converted to the file's unit).
    variance: BTreeMap<Sensor, f64>,
    /// The first positive accelerometer variance, (m/s^2)^2.
    accel_variance: Option<f64>,
    /// Sensors whose covariance was zero or absent in a message.
    no_covariance: BTreeMap<Sensor, u64>,
    /// The first IMU orientation (IMU FRD -> NED) and its time.
    first_attitude: Option<(f64, [[f64; 3]; 3])>,
    /// The static transforms of `/tf_static`.
    mounts: Tree,
    /// Frame id of each sensor's first message.
    sensor_frame: BTreeMap<Sensor, String>,
    skipped: BTreeMap<String, u64>,
    warnings: Vec<String>,
}

impl<'m> Converter<'m> {
    /// A converter for the bag `file` with `mapping`.
    pub fn new(file: &str, mapping: &'m Mapping) -> Self {
        Converter {
            file: file.to_string(),
            mapping,
            channels: HashMap::new(),
            feeding: BTreeMap::new(),
            files: BTreeMap::new(),
            origin_ns: None,
            variance: BTreeMap::new(),
            accel_variance: None,
            no_covariance: BTreeMap::new(),
            first_attitude: None,
            mounts: Tree::default(),
            sensor_frame: BTreeMap::new(),
            skipped: BTreeMap::new(),
            warnings: Vec::new(),
        }
    }

    /// A channel record: which sensor its topic feeds.
    ///
    /// # Errors
    /// [`ImportError::Mapping`] when two topics would feed one sensor and
    /// the mapping does not say which.
    pub fn channel(
        &mut self,
        id: u16,
        topic: &str,
        ty: &str,
        encoding: &str,
    ) -> Result<(), ImportError> {
        // The summary section at the end of the file repeats the channel
        // records: the channel keeps its message count.
        if self.channels.get(&id).is_some_and(|c| c.topic == topic) {
            return Ok(());
        }
        let declared = self.mapping.topics.get(topic).copied();
        let default = Sensor::of_type(ty).map(|sensor| TopicMap {
            sensor,
            body_flu: true,
            world_enu: true,
        });
        let mut map = declared.or(default);
        if ty == "tf2_msgs/msg/TFMessage" && topic == "/tf_static" {
            map = Some(TopicMap {
                sensor: Sensor::Ignore,
                body_flu: true,
                world_enu: true,
            });
        } else if encoding != "cdr" || !messages::TYPES.contains(&ty) {
            if declared.is_some_and(|m| m.sensor != Sensor::Ignore) {
                return Err(ImportError::Mapping {
                    file: self.file.clone(),
                    reason: format!(
                        "topic `{topic}`: type `{ty}` ({encoding}) is not one the import reads (CDR: {})",
                        messages::TYPES.join(", ")
                    ),
                });
            }
            map = None;
        }
        if let Some(m) = map.filter(|m| m.sensor != Sensor::Ignore) {
            if let Some(other) = self.feeding.get(&m.sensor) {
                if other != topic {
                    return Err(ImportError::Mapping {
                        file: self.file.clone(),
                        reason: format!(
                            "topics `{other}` and `{topic}` would both feed {}.csv: say which in a mapping file (`[topics.\"{topic}\"] sensor = \"ignore\"` or another sensor)",
                            m.sensor.name()
                        ),
                    });
                }
            }
            self.feeding.insert(m.sensor, topic.to_string());
        }
        self.channels.insert(
            id,
            Channel {
                topic: topic.to_string(),
                ty: ty.to_string(),
                map,
                messages: 0,
            },
        );
        Ok(())
    }

    fn err(&self, topic: &str, index: u64, reason: String) -> ImportError {
        ImportError::Message {
            file: self.file.clone(),
            topic: topic.to_string(),
            index,
            reason,
        }
    }

    /// A message record.
    ///
    /// # Errors
    /// [`ImportError::Message`] naming the topic, the message index and the field.
    pub fn message(&mut self, channel: u16, log_time: u64, data: &[u8]) -> Result<(), ImportError> {
        let Some(ch) = self.channels.get_mut(&channel) else {
            return Err(ImportError::Container {
                file: self.file.clone(),
                reason: format!("a message of channel {channel}, which no channel record declares"),
            });
        };
        let index = ch.messages;
        ch.messages += 1;
        let topic = ch.topic.clone();
        let Some(map) = ch.map else {
            *self
                .skipped
                .entry(format!("{topic} ({})", ch.ty))
                .or_default() += 1;
            return Ok(());
        };
        let ty = ch.ty.clone();
        if map.sensor == Sensor::Ignore && ty != "tf2_msgs/msg/TFMessage" {
            return Ok(());
        }
        let decoded = match messages::decode(&ty, data) {
            Some(Ok(d)) => d,
            Some(Err(e)) => return Err(self.err(&topic, index, format!("{ty}: {e}"))),
            None => return Ok(()),
        };
        if let Reading::Transforms(list) = &decoded.reading {
            for (parent, child, translation, rotation) in list {
                self.mounts.insert(
                    child,
                    Transform {
                        parent: parent.clone(),
                        translation: *translation,
                        rotation: *rotation,
                        topic: topic.clone(),
                        index,
                    },
                );
            }
            return Ok(());
        }
        let ns = match self.mapping.clock {
            Clock::Header => decoded.stamp_ns,
            Clock::Receive => i64::try_from(log_time).unwrap_or(i64::MAX),
        };
        if ns == 0 && self.mapping.clock == Clock::Header {
            return Err(self.err(
                &topic,
                index,
                "header.stamp is zero (not set by the driver): declare `time = \"receive\"` in a mapping file".into(),
            ));
        }
        let origin = *self.origin_ns.get_or_insert(ns);
        let t = (ns.saturating_sub(origin)) as f64 * 1e-9;
        if t.abs() > MAX_SPAN_S {
            return Err(self.err(
                &topic,
                index,
                format!("time {t:.3e} s from the bag's first message: beyond {MAX_SPAN_S:e} s (a stamp in another unit?)"),
            ));
        }
        self.sensor_frame
            .entry(map.sensor)
            .or_insert_with(|| decoded.frame.clone());
        let body = |v: [f64; 3]| {
            if map.body_flu {
                [v[0], -v[1], -v[2]]
            } else {
                v
            }
        };
        let world = |v: [f64; 3]| {
            if map.world_enu {
                [v[1], v[0], -v[2]]
            } else {
                v
            }
        };
        let row: Option<Vec<f64>> = match (map.sensor, &decoded.reading) {
            (
                Sensor::Imu,
                Reading::Imu {
                    orientation,
                    rate,
                    accel,
                    rate_variance,
                    accel_variance,
                },
            ) => {
                if self.first_attitude.is_none() {
                    if let Some(q) = orientation {
                        let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
                        if n.is_finite() && n > 1e-6 {
                            self.first_attitude = Some((t, dcm_ned_frd(*q, map)));
                        }
                    }
                }
                self.covariance(Sensor::Imu, *rate_variance);
                if *accel_variance > 0.0 && accel_variance.is_finite() {
                    self.accel_variance.get_or_insert(*accel_variance);
                }
                let mut v = vec![t];
                v.extend(body(*rate));
                v.extend(body(*accel));
                Some(v)
            }
            (Sensor::Mag, Reading::Mag { field, variance }) => {
                self.covariance(Sensor::Mag, variance * GAUSS_PER_TESLA * GAUSS_PER_TESLA);
                let mut v = vec![t];
                v.extend(body(*field).map(|x| x * GAUSS_PER_TESLA));
                Some(v)
            }
            (Sensor::Depth, Reading::Pressure { pa, variance }) => {
                let scale = 1.0 / (self.mapping.density * G0);
                self.covariance(Sensor::Depth, variance * scale * scale);
                Some(vec![t, (pa - self.mapping.surface_pressure) * scale])
            }
            (
                Sensor::Gnss,
                Reading::Fix {
                    status,
                    lat,
                    lon,
                    alt,
                    variance,
                    covariance_type,
                },
            ) => {
                if *status < 0 {
                    None
                } else {
                    let (eph, epv) = if *covariance_type > 0 {
                        (variance[0].max(variance[1]).sqrt(), variance[2].sqrt())
                    } else {
                        (f64::NAN, f64::NAN)
                    };
                    self.covariance(Sensor::Gnss, if eph.is_finite() { eph * eph } else { 0.0 });
                    let mut v = vec![t, lat.to_radians(), lon.to_radians(), *alt, eph, epv];
                    v.extend([f64::NAN; 4]);
                    Some(v)
                }
            }
            (Sensor::Dvl, Reading::Twist { linear, variance }) => {
                self.covariance(Sensor::Dvl, variance.unwrap_or(0.0));
                let mut v = vec![t];
                v.extend(body(*linear));
                Some(v)
            }
            (Sensor::Altitude, Reading::Range { range, min, max }) => {
                (range >= min && range <= max).then(|| vec![t, *range])
            }
            (
                Sensor::Usbl,
                Reading::Pose {
                    position, variance, ..
                },
            ) => {
                self.covariance(Sensor::Usbl, *variance);
                let o = self.origin(&topic, index)?;
                let [lat, lon, depth] = geodetic(o, world(*position));
                Some(vec![t, lat, lon, depth])
            }
            (
                Sensor::Truth,
                Reading::Odometry {
                    position,
                    orientation,
                    linear,
                },
            ) => {
                let o = self.origin(&topic, index)?;
                let [lat, lon, depth] = geodetic(o, world(*position));
                let c = dcm_ned_frd(*orientation, map);
                let vb = body(*linear);
                let vn: Vec<f64> = (0..3)
                    .map(|i| (0..3).map(|j| c[i][j] * vb[j]).sum())
                    .collect();
                let e = euler(c);
                let mut v = vec![t, lat, lon, depth];
                v.extend(vn);
                v.extend(e);
                Some(v)
            }
            (sensor, reading) => {
                return Err(self.err(
                    &topic,
                    index,
                    format!(
                        "{ty} cannot feed {}.csv (mapping) ({})",
                        sensor.name(),
                        kind(reading)
                    ),
                ))
            }
        };
        if let Some(row) = row {
            let f = self
                .files
                .entry(map.sensor)
                .or_insert_with(|| new_file(map.sensor));
            let last = f
                .values
                .len()
                .checked_sub(f.header.len())
                .map(|i| f.values[i]);
            if row.len() != f.header.len()
                || !row[1..]
                    .iter()
                    .enumerate()
                    .all(|(i, x)| x.is_finite() || (map.sensor == Sensor::Gnss && i >= 3))
                || last.is_some_and(|l| row[0] <= l)
            {
                f.dropped += 1;
            } else {
                f.values.extend(row);
            }
        }
        Ok(())
    }

    fn covariance(&mut self, sensor: Sensor, variance: f64) {
        if variance > 0.0 && variance.is_finite() {
            self.variance.entry(sensor).or_insert(variance);
        } else {
            *self.no_covariance.entry(sensor).or_default() += 1;
        }
    }

    fn origin(&self, topic: &str, index: u64) -> Result<[f64; 3], ImportError> {
        self.mapping.origin.ok_or_else(|| {
            self.err(
                topic,
                index,
                "a position in a local frame: declare its `origin = { lat, lon, height }` in a mapping file".into(),
            )
        })
    }

    /// The files, `meta.toml` and the summary.
    ///
    /// # Errors
    /// [`ImportError::Unusable`] without IMU rows or an initial attitude.
    pub fn finish(mut self) -> Result<ImportedBag, ImportError> {
        let file = self.file.clone();
        let unusable = move |reason: String| ImportError::Unusable {
            file: file.clone(),
            reason,
        };
        if self
            .files
            .get(&Sensor::Imu)
            .filter(|f| f.rows() > 1)
            .is_none()
        {
            return Err(unusable("no IMU data: no sensor_msgs/Imu topic with two or more messages (every model needs imu.csv)".into()));
        }
        let mut w = Vec::new();
        let mounts = self.mount(&mut w)?;
        let imu = self
            .files
            .get(&Sensor::Imu)
            .ok_or_else(|| unusable("no IMU data".into()))?;
        let t0 = imu.first_t().unwrap_or(0.0);
        if let Some(origin) = self.origin_ns {
            w.push(format!(
                "times are seconds after the bag's first message ({} clock, {origin} ns since the epoch)",
                match self.mapping.clock {
                    Clock::Header => "header.stamp",
                    Clock::Receive => "receive",
                }
            ));
        }
        let mut meta = String::from("# Written by `navsim import mcap`.\n[initial]\n");
        let _ = writeln!(meta, "t = {t0:e}");
        let gnss = self.files.get(&Sensor::Gnss).filter(|g| g.rows() > 0);
        if let Some(g) = gnss {
            let _ = writeln!(
                meta,
                "lat = {:e}\nlon = {:e}\ndepth = {:e}",
                g.values[1], g.values[2], -g.values[3]
            );
            w.push("meta.toml: [initial] position from the first NavSatFix".into());
        } else if let Some([lat, lon, h]) = self.mapping.origin {
            let _ = writeln!(meta, "lat = {lat:e}\nlon = {lon:e}\ndepth = {:e}", -h);
            w.push("meta.toml: [initial] position is the mapping's origin".into());
        } else {
            w.push(
                "meta.toml: attitude only (no NavSatFix and no origin): no initial position".into(),
            );
        }
        let attitude = match self.first_attitude {
            Some((_, c_ned_imu)) => {
                w.push("meta.toml: [initial] attitude from the first IMU orientation".into());
                // C_ned_body = C_ned_imu C_body_imu^T.
                let m = mounts
                    .get(&Sensor::Imu)
                    .map_or_else(Mount::identity, |m| *m)
                    .rotation;
                let mut c = [[0.0; 3]; 3];
                for (i, ci) in c.iter_mut().enumerate() {
                    for (j, cij) in ci.iter_mut().enumerate() {
                        *cij = (0..3).map(|k| c_ned_imu[i][k] * m[(j, k)]).sum();
                    }
                }
                Some(euler(c))
            }
            None => {
                let l = leveled(Some(imu), self.files.get(&Sensor::Mag), t0);
                if l.is_some() {
                    w.push(format!("meta.toml: [initial] attitude leveled from the first {LEVELING_S} s of accelerometer and magnetometer; declination 0 (the bag has none): the yaw is the magnetic heading"));
                }
                l
            }
        };
        let [roll, pitch, yaw] = attitude.ok_or_else(|| {
            unusable("no initial attitude: no IMU orientation, and no magnetometer in the first second to level from (model ahrs needs one)".into())
        })?;
        let _ = writeln!(meta, "roll = {roll:e}\npitch = {pitch:e}\nyaw = {yaw:e}");
        // Sigmas from the covariances.
        if let Some(v) = self.variance.get(&Sensor::Imu) {
            if let Some(accel) = self.accel_variance {
                let _ = writeln!(
                    meta,
                    "\n[sensors.imu]\ngyro_noise_sigma = {:e}\naccel_noise_sigma = {:e}",
                    v.sqrt(),
                    accel.sqrt()
                );
            }
        }
        for (sensor, section) in [
            (Sensor::Mag, "mag"),
            (Sensor::Depth, "depth"),
            (Sensor::Gnss, "gnss"),
            (Sensor::Dvl, "dvl"),
            (Sensor::Usbl, "usbl"),
        ] {
            if !self.files.contains_key(&sensor) {
                continue;
            }
            // A direction is the same anywhere on the vehicle: no lever
            // arm for the magnetometer.
            let arm = lever_arm(&mounts, sensor).filter(|_| sensor != Sensor::Mag);
            match self.variance.get(&sensor).filter(|v| v.is_finite()) {
                Some(v) => {
                    let _ = writeln!(meta, "\n[sensors.{section}]\nnoise_sigma = {:e}", v.sqrt());
                    if let Some(arm) = arm {
                        let _ = writeln!(meta, "lever_arm = [{:e}, {:e}, {:e}]", arm[0], arm[1], arm[2]);
                        w.push(format!("meta.toml: [sensors.{section}] lever_arm from /tf_static (from the IMU, body frame FRD)"));
                    }
                }
                None => w.push(format!(
                    "{section}.csv: the messages' covariance is zero or absent: no [sensors.{section}] noise written (the model's default applies){}",
                    if arm.is_some() { "; its lever arm from /tf_static is not written either" } else { "" }
                )),
            }
        }
        if !self.variance.contains_key(&Sensor::Imu) {
            w.push("imu.csv: the messages' covariance is zero or absent: no [sensors.imu] noise written".into());
        }
        for (what, n) in &self.skipped {
            w.push(format!(
                "topic {what}: {n} messages not read (type not understood)"
            ));
        }
        let mut files = Vec::new();
        let mut summary_files = Vec::new();
        for (sensor, f) in std::mem::take(&mut self.files) {
            if sensor == Sensor::Imu || f.rows() > 0 {
                if f.dropped > 0 {
                    w.push(format!(
                        "{}: {} rows dropped (time not increasing, value not finite, no fix)",
                        f.name, f.dropped
                    ));
                }
                summary_files.push((f.name.to_string(), f.rows()));
                files.push(f);
            }
        }
        let mut topics: Vec<(String, String, String, u64)> = self
            .channels
            .values()
            .map(|c| {
                (
                    c.topic.clone(),
                    c.ty.clone(),
                    c.map.map_or("ignored", |m| m.sensor.name()).to_string(),
                    c.messages,
                )
            })
            .collect();
        topics.sort();
        // A mapped topic the bag lacks is most often a misspelt one: the
        // automatic mapping took its place without a word.
        let names: Vec<&str> = self.channels.values().map(|c| c.topic.as_str()).collect();
        for topic in self.mapping.topics.keys() {
            if !names.contains(&topic.as_str()) {
                let hint = nav_runtime::log::closest_name(topic, &names)
                    .map(|n| format!(" (did you mean `{n}`?)"))
                    .unwrap_or_default();
                w.push(format!(
                    "mapping: topic `{topic}` is not in the bag{hint}: its entry is not used"
                ));
            }
        }
        self.warnings.extend(w);
        Ok(ImportedBag {
            files,
            meta,
            summary: ImportSummary {
                files: summary_files,
                topics,
                warnings: self.warnings,
            },
        })
    }

    /// The body frame: the mapping's `vehicle_frame`, else `base_link` when
    /// `/tf_static` has it, else the IMU's frame.
    fn body_frame(&self) -> (String, &'static str) {
        if let Some(f) = &self.mapping.vehicle_frame {
            return (f.clone(), "the mapping's vehicle_frame");
        }
        if self.mounts.contains("base_link") {
            return ("base_link".into(), "base_link, in /tf_static");
        }
        (
            self.sensor_frame
                .get(&Sensor::Imu)
                .cloned()
                .unwrap_or_default(),
            "the IMU's frame (no base_link in /tf_static)",
        )
    }

    /// Resolves each sensor's frame in the body frame and rotates the
    /// vectors of its rows (IMU rates and forces, magnetic field, DVL
    /// velocity) into it.
    ///
    /// # Errors
    /// [`ImportError::Message`] naming the `/tf_static` message of a cycle,
    /// a rotation that is not one, or an absurd translation.
    fn mount(&mut self, w: &mut Vec<String>) -> Result<BTreeMap<Sensor, Mount>, ImportError> {
        let (body, why) = self.body_frame();
        let mut mounts = BTreeMap::new();
        let sensors: Vec<(Sensor, String)> = self
            .sensor_frame
            .iter()
            .filter(|(s, _)| self.files.contains_key(s) && **s != Sensor::Truth)
            .map(|(s, f)| (*s, f.clone()))
            .collect();
        let mut mounted = false;
        for (sensor, frame) in sensors {
            let resolved = self
                .mounts
                .resolve(&frame, &body)
                .map_err(|e| self.err(&e.topic, e.index, e.reason))?;
            match resolved {
                Resolved::Mounted(m) => {
                    mounted |= frame_name(&frame) != frame_name(&body);
                    mounts.insert(sensor, m);
                }
                Resolved::Unconnected { root } => {
                    if !self.mounts.is_empty() {
                        w.push(format!(
                            "{}.csv: frame `{frame}` is not connected to the body frame `{body}` in /tf_static (its chain ends at `{root}`): taken as the body frame, no lever arm",
                            sensor.name()
                        ));
                    }
                }
            }
        }
        for (topic, index, norm) in std::mem::take(&mut self.mounts.normalised) {
            w.push(format!(
                "topic `{topic}`, message {index}: a rotation of norm {norm:.9} normalised"
            ));
        }
        if mounted {
            w.push(format!(
                "sensors mounted from /tf_static in the body frame `{body}` ({why}): vectors rotated into it, lever arms from the IMU"
            ));
        }
        for sensor in mounts.keys() {
            if let Some(arm) = lever_arm(&mounts, *sensor) {
                if arm.iter().any(|v| v.abs() > MAX_TRANSLATION_M) {
                    let frame = self.sensor_frame.get(sensor).cloned().unwrap_or_default();
                    let (topic, index) = self.mounts.source(&frame).unwrap_or(("/tf_static", 0));
                    return Err(self.err(topic, index, format!(
                        "{}.csv: frame `{frame}` is {:.3e} m from the IMU in the body frame: within {MAX_TRANSLATION_M} m expected for a lever arm",
                        sensor.name(),
                        arm.iter().fold(0.0f64, |a, v| a.max(v.abs()))
                    )));
                }
            }
        }
        for (sensor, m) in &mounts {
            let columns: &[usize] = match sensor {
                Sensor::Imu => &[1, 4],
                Sensor::Mag | Sensor::Dvl => &[1],
                _ => &[],
            };
            if m.is_unrotated() || columns.is_empty() {
                continue;
            }
            if let Some(f) = self.files.get_mut(sensor) {
                let width = f.header.len();
                for row in f.values.chunks_exact_mut(width) {
                    for &c in columns {
                        let v = m.rotate([row[c], row[c + 1], row[c + 2]]);
                        row[c..c + 3].copy_from_slice(&v);
                    }
                }
            }
        }
        Ok(mounts)
    }
}

/// The lever arm of `sensor` from the IMU, body frame FRD (m), when
/// `/tf_static` places both and they differ.
fn lever_arm(mounts: &BTreeMap<Sensor, Mount>, sensor: Sensor) -> Option<[f64; 3]> {
    let s = mounts.get(&sensor)?.translation;
    let imu = mounts
        .get(&Sensor::Imu)
        .map_or_else(nalgebra::Vector3::zeros, |m| m.translation);
    let arm = s - imu;
    (arm.amax() > 0.0).then(|| [arm[0], arm[1], arm[2]])
}

fn kind(r: &Reading) -> &'static str {
    match r {
        Reading::Imu { .. } => "an IMU message",
        Reading::Mag { .. } => "a magnetic field",
        Reading::Pressure { .. } => "a pressure",
        Reading::Fix { .. } => "a GNSS fix",
        Reading::Twist { .. } => "a velocity",
        Reading::Pose { .. } => "a pose",
        Reading::Range { .. } => "a range",
        Reading::Odometry { .. } => "an odometry",
        Reading::Transforms(_) => "transforms",
    }
}

fn new_file(sensor: Sensor) -> CsvFile {
    let (name, header): (&'static str, Vec<&'static str>) = match sensor {
        Sensor::Imu => ("imu.csv", vec!["t", "gx", "gy", "gz", "ax", "ay", "az"]),
        Sensor::Mag => ("mag.csv", vec!["t", "mx", "my", "mz"]),
        Sensor::Depth => ("depth.csv", vec!["t", "depth"]),
        Sensor::Gnss => ("gnss.csv", crate::ulog::assemble::GNSS_COLUMNS.to_vec()),
        Sensor::Dvl => ("dvl.csv", vec!["t", "vx", "vy", "vz"]),
        Sensor::Usbl => ("usbl.csv", vec!["t", "lat", "lon", "depth"]),
        Sensor::Altitude => ("altitude.csv", vec!["t", "altitude"]),
        Sensor::Truth | Sensor::Ignore => (
            "truth.csv",
            vec![
                "t", "lat", "lon", "depth", "vn", "ve", "vd", "roll", "pitch", "yaw",
            ],
        ),
    };
    CsvFile {
        name,
        header,
        values: Vec::new(),
        dropped: 0,
    }
}

/// Latitude, longitude (rad) and depth (m) of the NED offset `ned` (m) from
/// `origin` (lat, lon rad, height m), on the local tangent plane (the
/// offsets of a survey: metres to kilometres).
fn geodetic(origin: [f64; 3], ned: [f64; 3]) -> [f64; 3] {
    let [lat0, lon0, h0] = origin;
    let lat = lat0 + ned[0] / (meridian_radius(lat0) + h0);
    let lon = lon0 + ned[1] / ((transverse_radius(lat0) + h0) * lat0.cos());
    [lat, lon, -(h0 - ned[2])]
}

/// The rotation body -> world of quaternion `q` (x, y, z, w), as NED / FRD
/// (converted from ENU / FLU as `map` says).
fn dcm_ned_frd(q: [f64; 4], map: TopicMap) -> [[f64; 3]; 3] {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let [x, y, z, w] = if n > 1e-9 {
        q.map(|v| v / n)
    } else {
        [0.0, 0.0, 0.0, 1.0]
    };
    let r = [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ];
    // C_ned_frd = A C_enu_flu B, A swapping x/y and negating z, B = diag(1, -1, -1).
    let a = |i: usize| -> ([f64; 3], f64) {
        if !map.world_enu {
            return (r[i], 1.0);
        }
        match i {
            0 => (r[1], 1.0),
            1 => (r[0], 1.0),
            _ => (r[2], -1.0),
        }
    };
    let b = if map.body_flu {
        [1.0, -1.0, -1.0]
    } else {
        [1.0, 1.0, 1.0]
    };
    let mut c = [[0.0; 3]; 3];
    for (i, ci) in c.iter_mut().enumerate() {
        let (row, s) = a(i);
        for j in 0..3 {
            ci[j] = s * row[j] * b[j];
        }
    }
    c
}

/// Roll, pitch, yaw (z-y-x) of a body -> NED rotation.
fn euler(c: [[f64; 3]; 3]) -> [f64; 3] {
    [
        c[2][1].atan2(c[2][2]),
        (-c[2][0]).clamp(-1.0, 1.0).asin(),
        c[1][0].atan2(c[0][0]),
    ]
}
