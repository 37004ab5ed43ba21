//! From the topic tables to the files of a log directory: which topic feeds
//! which file (see [`super::topics`]), unit conversions, time order, and the
//! initial estimate and sensor noise of `meta.toml`.

use std::collections::HashMap;
use std::fmt::Write as _;

use super::decode::Table;
use super::error::ImportError;
use super::topics::PARAMETERS;
use super::{CsvFile, ImportedLog};

/// Relative difference between an increment's own period and the row
/// spacing beyond which the increments are not over the row spacing.
const PERIOD_TOLERANCE: f64 = 0.05;

/// `int32` value PX4 writes in a `*_timestamp_relative` field with no sample.
const RELATIVE_TIMESTAMP_INVALID: f64 = 2_147_483_647.0;
/// GNSS fixes below this `fix_type` (3 = 3D fix) are not written.
const MIN_FIX_TYPE: f64 = 3.0;
/// PX4 EKF2's switch-on uncertainty of the gyro bias, rad/s.
const GYRO_BIAS_SIGMA_DEFAULT: f64 = 0.1;
/// PX4 EKF2's switch-on uncertainty of the accelerometer bias, m/s^2.
const ACCEL_BIAS_SIGMA_DEFAULT: f64 = 0.2;

/// The columns of `gnss.csv`: always all of them, a cell the receiver does
/// not give left empty (the log reader's fixed schema).
pub(crate) const GNSS_COLUMNS: [&str; 10] = [
    "t",
    "lat",
    "lon",
    "height",
    "eph",
    "epv",
    "vn",
    "ve",
    "vd",
    "speed_accuracy",
];

/// The columns of `reference.csv`: always all of them, the groups PX4's
/// log has no topic for left empty.
pub const REFERENCE_COLUMNS: [&str; 10] = [
    "t", "lat", "lon", "height", "vn", "ve", "vd", "roll", "pitch", "yaw",
];

/// `f` with the columns `full` (a superset of its header, in any order):
/// the columns it lacks are empty cells (NaN).
fn widen(f: CsvFile, full: &[&'static str]) -> CsvFile {
    let n = f.header.len();
    let map: Vec<Option<usize>> = full
        .iter()
        .map(|c| f.header.iter().position(|h| h == c))
        .collect();
    let mut values = Vec::with_capacity(f.rows() * full.len());
    for row in f.values.chunks_exact(n) {
        values.extend(map.iter().map(|m| m.map_or(f64::NAN, |i| row[i])));
    }
    CsvFile {
        name: f.name,
        header: full.to_vec(),
        values,
        dropped: f.dropped,
    }
}

/// Builds the log directory's content.
pub fn assemble(
    file: &str,
    origin_us: f64,
    tables: Vec<Table>,
    parameters: &HashMap<String, f64>,
    mut warnings: Vec<String>,
) -> Result<ImportedLog, ImportError> {
    let tables = &super::instances::splice(tables, origin_us, &mut warnings);
    let mut cx = Cx {
        file,
        origin_us,
        tables,
        warnings: &mut warnings,
    };
    let mut files = Vec::new();
    let (mut imu, imu_topic) = cx.imu()?;
    let reference = cx
        .estimate("", "reference.csv", "height")?
        .map(|f| widen(f, &REFERENCE_COLUMNS));
    let truth = cx.estimate("_groundtruth", "truth.csv", "depth")?;

    // The initial estimate: PX4's first estimate at or after the first IMU sample.
    let mut initial = None;
    if let Some(r) = &reference {
        if let Some(first) = r.row_at_or_after(imu.first_t().unwrap_or(f64::NEG_INFINITY)) {
            let t0 = r.values[first * r.header.len()];
            let dropped = imu.drop_before(t0);
            if dropped > 0 {
                cx.warn(format!(
                    "imu.csv: {dropped} samples before PX4's first estimate (t = {t0:.6} s) were not written"
                ));
            }
            initial = Some(r.row(first));
        }
    }
    if imu.rows() == 0 {
        return Err(ImportError::Unusable {
            file: file.to_string(),
            reason: format!("no IMU sample ({imu_topic}) at or after PX4's first estimate"),
        });
    }
    files.push(imu);
    for f in [
        cx.magnetometer()?,
        cx.barometer()?,
        cx.gnss()?.map(|f| widen(f, &GNSS_COLUMNS)),
    ]
    .into_iter()
    .flatten()
    {
        files.push(f);
    }
    let find = |name: &str| files.iter().find(|f| f.name == name);
    let (mut meta, position) = meta_toml(
        &mut cx,
        initial.as_deref(),
        reference.as_ref(),
        find("gnss.csv"),
        find("imu.csv"),
        find("mag.csv"),
        parameters,
    )?;
    let (imu_section, noise) = noise_toml(&mut cx, parameters);
    meta.push_str(&imu_section);
    let models = servable(position, find("gnss.csv").is_some_and(|g| g.rows() > 0));
    for (model, missing) in &models {
        if let Some(m) = missing {
            cx.warn(format!("model {model}: cannot replay this log: {m}"));
        }
    }
    files.extend(reference);
    files.extend(truth);
    Ok(ImportedLog {
        files,
        meta,
        noise,
        warnings,
        models,
    })
}

/// Which replay models (`navsim replay --model`) the log serves: `None`, or
/// what it lacks for that model.
fn servable(position: bool, gnss: bool) -> Vec<(&'static str, Option<String>)> {
    let gnss_ins = match (position, gnss) {
        (true, true) => None,
        (false, false) => Some("no GNSS fix (gnss.csv) and no initial position".to_string()),
        (true, false) => Some("no GNSS fix (gnss.csv)".to_string()),
        (false, true) => Some("no initial position".to_string()),
    };
    // The initial attitude is always written (or the import refused).
    vec![("ahrs", None), ("gnss-ins", gnss_ins)]
}

struct Cx<'a> {
    file: &'a str,
    /// The log's start (header timestamp), us: file times are seconds after it.
    origin_us: f64,
    tables: &'a [Table],
    warnings: &'a mut Vec<String>,
}

impl<'a> Cx<'a> {
    fn warn(&mut self, w: String) {
        self.warnings.push(w);
    }

    /// The instance of `topic` used: the lowest `multi_id` with rows; says so
    /// when there are several.
    fn pick(&mut self, topic: &str) -> Option<&'a Table> {
        let tables = self.tables;
        let mut found: Vec<&Table> = tables
            .iter()
            .filter(|t| t.topic == topic && t.rows() > 0)
            .collect();
        found.sort_by_key(|t| (t.instance, std::cmp::Reverse(t.rows())));
        let first = *found.first()?;
        if found.len() > 1 {
            let ids: Vec<String> = found.iter().map(|t| t.instance.to_string()).collect();
            self.warn(format!(
                "{topic}: {} instances (multi_id {}); multi_id {} used",
                found.len(),
                ids.join(", "),
                first.instance
            ));
        }
        Some(first)
    }

    fn layout(&self, topic: &str, field: &str, reason: &str) -> ImportError {
        ImportError::Layout {
            file: self.file.to_string(),
            topic: topic.to_string(),
            field: field.to_string(),
            reason: reason.to_string(),
        }
    }

    /// Index of every one of `fields` in `t`, or a layout error naming the first missing one.
    fn require(&self, t: &Table, fields: &[&str]) -> Result<Vec<usize>, ImportError> {
        fields
            .iter()
            .map(|f| {
                t.column(f)
                    .ok_or_else(|| self.layout(&t.topic, f, "missing (unknown topic layout)"))
            })
            .collect()
    }

    fn imu(&mut self) -> Result<(CsvFile, &'static str), ImportError> {
        if let Some(t) = self.pick("sensor_combined") {
            let cols = self.require(
                t,
                &[
                    "timestamp",
                    "gyro_rad[0]",
                    "gyro_rad[1]",
                    "gyro_rad[2]",
                    "accelerometer_m_s2[0]",
                    "accelerometer_m_s2[1]",
                    "accelerometer_m_s2[2]",
                ],
            )?;
            let what = format!(
                "imu.csv: sensor_combined multi_id {} (gyro_rad, accelerometer_m_s2)",
                t.instance
            );
            let f = series(
                t,
                self.origin_us,
                "imu.csv",
                &["t", "gx", "gy", "gz", "ax", "ay", "az"],
                |r| Some(cols.iter().map(|&c| t.at(r, c)).collect()),
            );
            self.used(what, &f);
            return Ok((f, "sensor_combined"));
        }
        if let Some(t) = self.pick("vehicle_imu") {
            let time =
                time_column(t).ok_or_else(|| self.layout("vehicle_imu", "timestamp", "missing"))?;
            let cols = self.require(
                t,
                &[
                    "delta_angle[0]",
                    "delta_angle[1]",
                    "delta_angle[2]",
                    "delta_velocity[0]",
                    "delta_velocity[1]",
                    "delta_velocity[2]",
                ],
            )?;
            let periods = [t.column("delta_angle_dt"), t.column("delta_velocity_dt")];
            if let Some(mismatch) = increment_periods(t, time, periods) {
                // The increments cover less (or more) than the time since the
                // previous row (a topic logged below its rate): as increments
                // over the row spacing they would be wrong by that ratio, so
                // each becomes the average rate over its own period, dated at
                // the middle of that period.
                let what = format!(
                    "imu.csv: vehicle_imu multi_id {} (delta_angle / delta_angle_dt, delta_velocity / delta_velocity_dt as rates: {mismatch})",
                    t.instance
                );
                let [pa, pv] = periods;
                let f = series(
                    t,
                    self.origin_us,
                    "imu.csv",
                    &["t", "gx", "gy", "gz", "ax", "ay", "az"],
                    |r| {
                        let da = pa.map(|c| t.at(r, c) * 1e-6)?;
                        let dv = pv.map_or(da, |c| t.at(r, c) * 1e-6);
                        let mut v = vec![time.at(t, r) - 0.5e6 * da];
                        v.extend(cols[..3].iter().map(|&c| t.at(r, c) / da));
                        v.extend(cols[3..].iter().map(|&c| t.at(r, c) / dv));
                        Some(v)
                    },
                );
                self.used(what, &f);
                return Ok((f, "vehicle_imu"));
            }
            let what = format!(
                "imu.csv: vehicle_imu multi_id {} (increments delta_angle, delta_velocity)",
                t.instance
            );
            let f = series(
                t,
                self.origin_us,
                "imu.csv",
                &[
                    "t", "dtheta_x", "dtheta_y", "dtheta_z", "dv_x", "dv_y", "dv_z",
                ],
                |r| {
                    let mut v = vec![time.at(t, r)];
                    v.extend(cols.iter().map(|&c| t.at(r, c)));
                    Some(v)
                },
            );
            self.used(what, &f);
            return Ok((f, "vehicle_imu"));
        }
        Err(ImportError::Unusable {
            file: self.file.to_string(),
            reason: "no IMU data: neither `sensor_combined` nor `vehicle_imu` has samples".into(),
        })
    }

    /// Records which topic fed a file, and rows dropped for time order or non-finite values.
    fn used(&mut self, what: String, f: &CsvFile) {
        self.warn(format!("{what}: {} rows", f.rows()));
        if f.dropped > 0 {
            self.warn(format!(
                "{}: {} rows dropped (time not increasing or value not finite)",
                f.name, f.dropped
            ));
        }
    }

    fn magnetometer(&mut self) -> Result<Option<CsvFile>, ImportError> {
        const MAG: [&str; 3] = [
            "magnetometer_ga[0]",
            "magnetometer_ga[1]",
            "magnetometer_ga[2]",
        ];
        let header = &["t", "mx", "my", "mz"];
        if let Some(t) = self.pick("vehicle_magnetometer") {
            let time =
                time_column(t).ok_or_else(|| self.layout(&t.topic, "timestamp", "missing"))?;
            let cols = self.require(t, &MAG)?;
            let what = format!("mag.csv: vehicle_magnetometer multi_id {}", t.instance);
            let f = series(t, self.origin_us, "mag.csv", header, |r| {
                let mut v = vec![time.at(t, r)];
                v.extend(cols.iter().map(|&c| t.at(r, c)));
                Some(v)
            });
            self.used(what, &f);
            return Ok(Some(f));
        }
        if let Some(t) = self.pick("sensor_combined") {
            if t.has_all(&MAG) {
                let cols = self.require(
                    t,
                    &[
                        "timestamp",
                        "magnetometer_timestamp_relative",
                        MAG[0],
                        MAG[1],
                        MAG[2],
                    ],
                )?;
                let what = format!(
                    "mag.csv: sensor_combined multi_id {} (magnetometer_ga, older layout)",
                    t.instance
                );
                let f = series(t, self.origin_us, "mag.csv", header, |r| {
                    relative_row(t, r, &cols)
                });
                self.used(what, &f);
                return Ok(Some(f));
            }
        }
        self.warn(
            "mag.csv: not written (no vehicle_magnetometer, no magnetometer in sensor_combined)"
                .into(),
        );
        Ok(None)
    }

    fn barometer(&mut self) -> Result<Option<CsvFile>, ImportError> {
        let header = &["t", "altitude"];
        if let Some(t) = self.pick("vehicle_air_data") {
            let time =
                time_column(t).ok_or_else(|| self.layout(&t.topic, "timestamp", "missing"))?;
            let alt = self.require(t, &["baro_alt_meter"])?[0];
            let what = format!(
                "baro.csv: vehicle_air_data multi_id {} (baro_alt_meter)",
                t.instance
            );
            let f = series(t, self.origin_us, "baro.csv", header, |r| {
                Some(vec![time.at(t, r), t.at(r, alt)])
            });
            self.used(what, &f);
            return Ok(Some(f));
        }
        if let Some(t) = self.pick("sensor_baro") {
            let time =
                time_column(t).ok_or_else(|| self.layout(&t.topic, "timestamp", "missing"))?;
            let p = self.require(t, &["pressure"])?[0];
            let what = format!(
                "baro.csv: sensor_baro multi_id {} (pressure, converted with the standard atmosphere)",
                t.instance
            );
            let f = series(t, self.origin_us, "baro.csv", header, |r| {
                Some(vec![time.at(t, r), pressure_altitude(t.at(r, p))])
            });
            self.used(what, &f);
            return Ok(Some(f));
        }
        if let Some(t) = self.pick("sensor_combined") {
            if t.has_all(&["baro_alt_meter"]) {
                let cols = self.require(
                    t,
                    &["timestamp", "baro_timestamp_relative", "baro_alt_meter"],
                )?;
                let what = format!(
                    "baro.csv: sensor_combined multi_id {} (baro_alt_meter, older layout)",
                    t.instance
                );
                let f = series(t, self.origin_us, "baro.csv", header, |r| {
                    relative_row(t, r, &cols)
                });
                self.used(what, &f);
                return Ok(Some(f));
            }
        }
        self.warn("baro.csv: not written (no vehicle_air_data, sensor_baro or barometer in sensor_combined)".into());
        Ok(None)
    }

    fn gnss(&mut self) -> Result<Option<CsvFile>, ImportError> {
        let has = |name: &str| self.tables.iter().any(|t| t.topic == name && t.rows() > 0);
        let topic = if has("vehicle_gps_position") {
            "vehicle_gps_position"
        } else {
            "sensor_gps"
        };
        let Some(t) = self.pick(topic) else {
            self.warn("gnss.csv: not written (no vehicle_gps_position or sensor_gps)".into());
            return Ok(None);
        };
        let time = time_column(t).ok_or_else(|| self.layout(topic, "timestamp", "missing"))?;
        // (column, scale to degrees or metres)
        let one =
            |names: &[(&str, f64)]| names.iter().find_map(|(n, s)| t.column(n).map(|c| (c, *s)));
        let lat = one(&[("latitude_deg", 1.0), ("lat", 1e-7)])
            .ok_or_else(|| self.layout(topic, "latitude_deg", "missing (nor the older `lat`)"))?;
        let lon = one(&[("longitude_deg", 1.0), ("lon", 1e-7)])
            .ok_or_else(|| self.layout(topic, "longitude_deg", "missing (nor the older `lon`)"))?;
        let ellipsoid = one(&[("altitude_ellipsoid_m", 1.0), ("alt_ellipsoid", 1e-3)]);
        let height = match ellipsoid {
            Some(h) => h,
            None => {
                let h = one(&[("altitude_msl_m", 1.0), ("alt", 1e-3)]).ok_or_else(|| {
                    self.layout(
                        topic,
                        "altitude_ellipsoid_m",
                        "missing (nor altitude_msl_m, alt_ellipsoid, alt)",
                    )
                })?;
                self.warn(format!(
                    "gnss.csv: {topic} has no ellipsoidal height; height is above mean sea level"
                ));
                h
            }
        };
        let fix = t.column("fix_type");
        let optional: Vec<(&'static str, usize)> = [
            ("eph", "eph"),
            ("epv", "epv"),
            ("vn", "vel_n_m_s"),
            ("ve", "vel_e_m_s"),
            ("vd", "vel_d_m_s"),
            ("speed_accuracy", "s_variance_m_s"),
        ]
        .into_iter()
        .filter_map(|(name, field)| t.column(field).map(|c| (name, c)))
        .collect();
        let mut header = vec!["t", "lat", "lon", "height"];
        header.extend(optional.iter().map(|(n, _)| *n));
        let mut no_fix = 0usize;
        let f = series(t, self.origin_us, "gnss.csv", &header, |r| {
            if fix.is_some_and(|c| t.at(r, c) < MIN_FIX_TYPE || t.at(r, c).is_nan()) {
                no_fix += 1;
                return None;
            }
            let mut v = vec![
                time.at(t, r),
                (t.at(r, lat.0) * lat.1).to_radians(),
                (t.at(r, lon.0) * lon.1).to_radians(),
                t.at(r, height.0) * height.1,
            ];
            v.extend(optional.iter().map(|(_, c)| t.at(r, *c)));
            Some(v)
        });
        let what = format!("gnss.csv: {topic} multi_id {}", t.instance);
        self.used(what, &f);
        if no_fix > 0 {
            self.warn(format!(
                "gnss.csv: {no_fix} rows without a 3D fix (fix_type < 3) not written"
            ));
        }
        Ok(Some(f))
    }

    /// PX4's estimate (`suffix` "") or the simulator's truth (`suffix`
    /// "_groundtruth"): attitude, global position, local velocity, on the
    /// attitude's timestamps (position and velocity interpolated linearly).
    fn estimate(
        &mut self,
        suffix: &str,
        name: &'static str,
        vertical: &'static str,
    ) -> Result<Option<CsvFile>, ImportError> {
        let att_topic = format!("vehicle_attitude{suffix}");
        let pos_topic = format!("vehicle_global_position{suffix}");
        let vel_topic = format!("vehicle_local_position{suffix}");
        let att = self.pick(&att_topic);
        let pos = self.pick(&pos_topic);
        let vel = self.pick(&vel_topic);
        let truth = !suffix.is_empty();
        if truth && (att.is_none() || pos.is_none() || vel.is_none()) {
            if att.is_some() || pos.is_some() || vel.is_some() {
                self.warn(format!(
                    "{name}: not written (needs {att_topic}, {pos_topic} and {vel_topic})"
                ));
            }
            return Ok(None);
        }
        let Some(base) = att.or(pos) else {
            if vel.is_some() {
                self.warn(format!("{name}: not written ({vel_topic} alone)"));
            }
            return Ok(None);
        };
        let q = match att {
            Some(a) => Some(self.require(a, &["q[0]", "q[1]", "q[2]", "q[3]"])?),
            None => None,
        };
        let p = match pos {
            Some(g) => {
                let mut c = self.require(g, &["lat", "lon"])?;
                let h = g
                    .column("alt_ellipsoid")
                    .or_else(|| g.column("alt"))
                    .ok_or_else(|| self.layout(&g.topic, "alt_ellipsoid", "missing (nor alt)"))?;
                c.push(h);
                Some((
                    g,
                    time_column(g).ok_or_else(|| self.layout(&g.topic, "timestamp", "missing"))?,
                    c,
                ))
            }
            None => None,
        };
        let v = match vel {
            Some(l) => Some((
                l,
                time_column(l).ok_or_else(|| self.layout(&l.topic, "timestamp", "missing"))?,
                self.require(l, &["vx", "vy", "vz"])?,
            )),
            None => None,
        };
        let base_time =
            time_column(base).ok_or_else(|| self.layout(&base.topic, "timestamp", "missing"))?;
        let mut header = vec!["t"];
        if p.is_some() {
            header.extend(["lat", "lon", vertical]);
        }
        if v.is_some() {
            header.extend(["vn", "ve", "vd"]);
        }
        if q.is_some() {
            header.extend(["roll", "pitch", "yaw"]);
        }
        let f = series(base, self.origin_us, name, &header, |r| {
            let t = base_time.at(base, r);
            let mut row = vec![t];
            if let Some((g, gt, c)) = &p {
                let w = interpolate(g, *gt, c, t)?;
                let height = w[2];
                row.extend([
                    w[0].to_radians(),
                    w[1].to_radians(),
                    if truth { -height } else { height },
                ]);
            }
            if let Some((l, lt, c)) = &v {
                row.extend(interpolate(l, *lt, c, t)?);
            }
            if let Some(c) = &q {
                let quat = [
                    base.at(r, c[0]),
                    base.at(r, c[1]),
                    base.at(r, c[2]),
                    base.at(r, c[3]),
                ];
                row.extend(euler(quat)?);
            }
            Some(row)
        });
        let mut parts = Vec::new();
        if let Some(a) = att {
            parts.push(format!("{} multi_id {}", a.topic, a.instance));
        }
        if let Some((g, _, _)) = &p {
            parts.push(format!("{} multi_id {}", g.topic, g.instance));
        }
        if let Some((l, _, _)) = &v {
            parts.push(format!("{} multi_id {}", l.topic, l.instance));
        }
        self.used(format!("{name}: {}", parts.join(", ")), &f);
        Ok(Some(f))
    }
}

/// Where a table's time is: `timestamp_sample` (the sample time) where
/// present and set, else `timestamp` (PX4 leaves `timestamp_sample` at 0 in
/// some topics, e.g. a simulated GNSS receiver).
#[derive(Debug, Clone, Copy)]
struct Time {
    sample: Option<usize>,
    stamp: Option<usize>,
}

impl Time {
    /// Microseconds.
    fn at(self, t: &Table, r: usize) -> f64 {
        match (self.sample.map(|c| t.at(r, c)), self.stamp) {
            (Some(s), _) if s > 0.0 => s,
            (_, Some(c)) => t.at(r, c),
            (Some(s), None) => s,
            (None, None) => f64::NAN,
        }
    }
}

fn time_column(t: &Table) -> Option<Time> {
    let time = Time {
        sample: t.column("timestamp_sample"),
        stamp: t.column("timestamp"),
    };
    (time.sample.is_some() || time.stamp.is_some()).then_some(time)
}

/// When `vehicle_imu`'s increments are not over the time since the previous
/// row (their `delta_angle_dt` / `delta_velocity_dt`, us, differ from the
/// row spacing by more than [`PERIOD_TOLERANCE`], plus 50 us of clock
/// jitter): a description with the median period and spacing. `None` when
/// they agree or the log has no period fields (older layouts).
fn increment_periods(t: &Table, time: Time, periods: [Option<usize>; 2]) -> Option<String> {
    let angle = periods[0]?;
    let mut off = 0usize;
    let mut spacing = Vec::new();
    let mut period = Vec::new();
    for r in 1..t.rows() {
        let gap = time.at(t, r) - time.at(t, r - 1);
        for c in periods.iter().flatten() {
            let dt = t.at(r, *c);
            if (gap - dt).abs() > PERIOD_TOLERANCE * gap.abs().max(dt.abs()) + 50.0 {
                off += 1;
                break;
            }
        }
        spacing.push(gap);
        period.push(t.at(r, angle));
    }
    if off == 0 {
        return None;
    }
    let median = |v: &mut Vec<f64>| {
        v.sort_by(f64::total_cmp);
        v.get(v.len() / 2).copied().unwrap_or(f64::NAN) * 1e-3
    };
    Some(format!(
        "the increments cover {:.3} ms (median delta_angle_dt) but the rows are {:.3} ms apart (median) in {off} of {} intervals",
        median(&mut period),
        median(&mut spacing),
        t.rows().saturating_sub(1)
    ))
}

/// A row `[t, values..]` of an older `sensor_combined` field whose sample time
/// is `timestamp + *_timestamp_relative`; `cols` = [timestamp, relative, values..].
fn relative_row(t: &Table, r: usize, cols: &[usize]) -> Option<Vec<f64>> {
    let relative = t.at(r, cols[1]);
    if relative == RELATIVE_TIMESTAMP_INVALID {
        return None;
    }
    let mut v = vec![t.at(r, cols[0]) + relative];
    v.extend(cols[2..].iter().map(|&c| t.at(r, c)));
    Some(v)
}

/// Pressure altitude of the standard atmosphere (sea level 101325 Pa,
/// 288.15 K, lapse 0.0065 K/m), m.
fn pressure_altitude(pa: f64) -> f64 {
    44_330.769_2 * (1.0 - (pa / 101_325.0).powf(0.190_263_2))
}

/// Roll, pitch, yaw (rad, z-y-x) of a Hamilton quaternion `[w, x, y, z]`
/// rotating body to NED; `None` for a zero or non-finite quaternion.
pub fn euler(q: [f64; 4]) -> Option<[f64; 3]> {
    let n = q.iter().map(|v| v * v).sum::<f64>().sqrt();
    if !(n.is_finite() && n > 1e-6) {
        return None;
    }
    let [w, x, y, z] = q.map(|v| v / n);
    let roll = (2.0 * (w * x + y * z)).atan2(1.0 - 2.0 * (x * x + y * y));
    let pitch = (2.0 * (w * y - z * x)).clamp(-1.0, 1.0).asin();
    let yaw = (2.0 * (w * z + x * y)).atan2(1.0 - 2.0 * (y * y + z * z));
    Some([roll, pitch, yaw])
}

/// Columns `cols` of `t` linearly interpolated at time `at` (same unit as the
/// time column `time`); `None` outside the table's time span.
fn interpolate(t: &Table, time: Time, cols: &[usize], at: f64) -> Option<Vec<f64>> {
    let n = t.rows();
    if n == 0 {
        return None;
    }
    // First row with time >= at (rows are in file order, which PX4 writes in time order).
    let (mut lo, mut hi) = (0usize, n);
    while lo < hi {
        let mid = (lo + hi) / 2;
        if time.at(t, mid) < at {
            lo = mid + 1;
        } else {
            hi = mid;
        }
    }
    if lo == n {
        return None;
    }
    let t1 = time.at(t, lo);
    if t1 == at {
        return Some(cols.iter().map(|&c| t.at(lo, c)).collect());
    }
    if lo == 0 {
        return None;
    }
    let t0 = time.at(t, lo - 1);
    let s = (at - t0) / (t1 - t0);
    if !(0.0..=1.0).contains(&s) {
        return None;
    }
    Some(
        cols.iter()
            .map(|&c| t.at(lo - 1, c) + s * (t.at(lo, c) - t.at(lo - 1, c)))
            .collect(),
    )
}

/// The rows of a file from a table: `row` gives each row (or `None` to skip
/// it); rows with a non-finite value or a time not after the previous row's
/// are dropped and counted.
fn series(
    t: &Table,
    origin_us: f64,
    name: &'static str,
    header: &[&'static str],
    mut row: impl FnMut(usize) -> Option<Vec<f64>>,
) -> CsvFile {
    let mut f = CsvFile {
        name,
        header: header.to_vec(),
        values: Vec::new(),
        dropped: 0,
    };
    let mut last = f64::NEG_INFINITY;
    for r in 0..t.rows() {
        let Some(mut v) = row(r) else { continue };
        if let Some(t) = v.first_mut() {
            *t = (*t - origin_us) * 1e-6;
        }
        if v.len() != header.len() || !v.iter().all(|x| x.is_finite()) || v[0] <= last {
            f.dropped += 1;
            continue;
        }
        last = v[0];
        f.values.extend(v);
    }
    f
}

/// `meta.toml`'s `[initial]` and whether it has a position. Without PX4's
/// position estimate the position is the first GNSS fix; without either the
/// file is attitude-only (docs/log-format.md): the attitude is PX4's, or
/// leveled from the mean specific force and magnetic field of the first
/// [`LEVELING_S`] (declination `EKF2_MAG_DECL`, or 0 with a warning).
#[allow(clippy::too_many_arguments)]
fn meta_toml(
    cx: &mut Cx,
    initial: Option<&[f64]>,
    reference: Option<&CsvFile>,
    gnss: Option<&CsvFile>,
    imu: Option<&CsvFile>,
    mag: Option<&CsvFile>,
    parameters: &HashMap<String, f64>,
) -> Result<(String, bool), ImportError> {
    let mut out = String::from("# Written by `navsim import ulog`.\n[initial]\n");
    let mut keys: Vec<(&str, f64)> = Vec::new();
    if let (Some(row), Some(r)) = (initial, reference) {
        for (name, value) in r.header.iter().zip(row) {
            if !value.is_finite() {
                continue; // an empty cell: the log has no such estimate
            }
            match *name {
                "t" => {}
                "height" => keys.push(("depth", -value)),
                n => keys.push((n, *value)),
            }
        }
        cx.warn(format!(
            "meta.toml: [initial] is PX4's estimate at t = {:.6} s",
            row[0]
        ));
    }
    let mut position = keys.iter().any(|(k, _)| *k == "lat");
    if !position {
        keys.retain(|(k, _)| !matches!(*k, "lat" | "lon" | "depth" | "vn" | "ve" | "vd"));
        if let Some(g) = gnss.filter(|g| g.rows() > 0) {
            // No PX4 position estimate: the first GNSS fix.
            keys.extend([
                ("lat", g.values[1]),
                ("lon", g.values[2]),
                ("depth", -g.values[3]),
            ]);
            cx.warn("meta.toml: [initial] position from the first GNSS fix".into());
            position = true;
        } else {
            cx.warn("meta.toml: attitude only (no vehicle_global_position, no GNSS fix): no initial position or velocity".into());
        }
    }
    if !keys.iter().any(|(k, _)| *k == "yaw") {
        let t0 = imu.and_then(CsvFile::first_t).unwrap_or(0.0);
        match leveled(imu, mag, t0) {
            Some([roll, pitch, heading]) => {
                let declination = match parameters.get("EKF2_MAG_DECL") {
                    Some(d) if d.is_finite() => {
                        cx.warn(format!("meta.toml: declination {d} deg (EKF2_MAG_DECL)"));
                        d.to_radians()
                    }
                    _ => {
                        cx.warn("meta.toml: declination 0 (EKF2_MAG_DECL not in the log): the initial yaw is the magnetic heading".into());
                        0.0
                    }
                };
                let yaw = heading + declination;
                keys.retain(|(k, _)| !matches!(*k, "roll" | "pitch" | "yaw"));
                keys.push(("t", t0));
                keys.extend([
                    ("roll", roll),
                    ("pitch", pitch),
                    ("yaw", yaw.sin().atan2(yaw.cos())),
                ]);
                cx.warn(format!(
                    "meta.toml: [initial] attitude leveled from the mean specific force and magnetic field of the first {LEVELING_S} s (no vehicle_attitude)"
                ));
            }
            None => {
                return Err(ImportError::Unusable {
                    file: cx.file.to_string(),
                    reason: "no initial attitude: no vehicle_attitude, and no magnetometer and accelerometer samples in the first second to level from (model ahrs needs one; gnss-ins too)".into(),
                });
            }
        }
    }
    for (k, v) in keys {
        let _ = writeln!(out, "{k} = {v:e}");
    }
    Ok((out, position))
}

/// Seconds of IMU and magnetometer samples averaged to level an initial attitude.
pub const LEVELING_S: f64 = 1.0;

/// Roll, pitch (from the mean specific force) and magnetic heading (from
/// the mean magnetic field, tilt-compensated) over [`LEVELING_S`] from `t0`,
/// rad, body frame forward-right-down. Works on rates and on increments
/// alike (only the directions of the sums count). `None` without samples.
pub(crate) fn leveled(imu: Option<&CsvFile>, mag: Option<&CsvFile>, t0: f64) -> Option<[f64; 3]> {
    let mean = |f: &CsvFile, cols: [usize; 3]| -> Option<[f64; 3]> {
        let n = f.header.len();
        let mut sum = [0.0; 3];
        let mut count = 0usize;
        for row in f.values.chunks_exact(n) {
            if row[0] < t0 || row[0] > t0 + LEVELING_S {
                continue;
            }
            for i in 0..3 {
                sum[i] += row[cols[i]];
            }
            count += 1;
        }
        (count > 0).then_some(sum)
    };
    let [fx, fy, fz] = mean(imu?, [4, 5, 6])?;
    let [mx, my, mz] = mean(mag?, [1, 2, 3])?;
    let roll = (-fy).atan2(-fz);
    let pitch = fx.atan2(fy.hypot(fz));
    let (sr, cr) = roll.sin_cos();
    let (sp, cp) = pitch.sin_cos();
    let hx = mx * cp + my * sr * sp + mz * cr * sp;
    let hy = my * cr - mz * sr;
    let heading = (-hy).atan2(hx);
    [roll, pitch, heading]
        .iter()
        .all(|v| v.is_finite())
        .then_some([roll, pitch, heading])
}

fn parameter(cx: &mut Cx, parameters: &HashMap<String, f64>, name: &str) -> f64 {
    let (_, default, unit) = PARAMETERS
        .iter()
        .find(|(n, _, _)| *n == name)
        .copied()
        .unwrap_or((name, f64::NAN, ""));
    match parameters.get(name) {
        Some(v) if v.is_finite() && *v >= 0.0 => *v,
        _ => {
            cx.warn(format!(
                "parameter {name} not in the log; PX4's default {default} {unit} used"
            ));
            default
        }
    }
}

/// `[sensors.imu]`, `[sensors.mag]`, `[sensors.baro]` and `[sensors.gnss]`
/// go into `meta.toml` (what the replay models read); `noise.toml` repeats
/// the aiding sensors' noise with the GNSS velocity noise, which `meta.toml`
/// has no key for.
fn noise_toml(cx: &mut Cx, parameters: &HashMap<String, f64>) -> (String, String) {
    let gyro = parameter(cx, parameters, "EKF2_GYR_NOISE");
    let accel = parameter(cx, parameters, "EKF2_ACC_NOISE");
    let mag = parameter(cx, parameters, "EKF2_MAG_NOISE");
    let baro = parameter(cx, parameters, "EKF2_BARO_NOISE");
    let gps_p = parameter(cx, parameters, "EKF2_GPS_P_NOISE");
    let gps_v = parameter(cx, parameters, "EKF2_GPS_V_NOISE");
    cx.warn(format!(
        "meta.toml: bias sigmas are PX4 EKF2's switch-on values (gyro {GYRO_BIAS_SIGMA_DEFAULT} rad/s, accelerometer {ACCEL_BIAS_SIGMA_DEFAULT} m/s^2)"
    ));
    let mut imu = String::new();
    let _ = writeln!(
        imu,
        "\n[sensors.imu]\ngyro_noise_sigma = {gyro:e}\naccel_noise_sigma = {accel:e}"
    );
    let _ = writeln!(
        imu,
        "gyro_bias_sigma = {GYRO_BIAS_SIGMA_DEFAULT:e}\naccel_bias_sigma = {ACCEL_BIAS_SIGMA_DEFAULT:e}"
    );
    let _ = writeln!(
        imu,
        "\n[sensors.mag]\nnoise_sigma = {mag:e}\n\n[sensors.baro]\nnoise_sigma = {baro:e}\n\n[sensors.gnss]\nnoise_sigma = {gps_p:e}"
    );
    let mut noise =
        String::from("# Aiding-sensor noise, per sample (written by `navsim import ulog`).\n");
    let _ = writeln!(
        noise,
        "[mag]\nnoise_sigma = {mag:e}\n\n[baro]\nnoise_sigma = {baro:e}"
    );
    let _ = writeln!(
        noise,
        "\n[gnss]\nnoise_sigma = {gps_p:e}\nvelocity_noise_sigma = {gps_v:e}"
    );
    (imu, noise)
}
