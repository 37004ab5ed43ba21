//! The mapping file of the bag import (TOML, docs/mcap.md): which topic
//! feeds which sensor, the frames and clock where a bag departs from the ROS
//! conventions, the water for depth from pressure, and the origin of
//! positions given in a local frame.
//!
//! ```toml
//! time = "header"                 # or "receive" (the bag's log time)
//! vehicle_frame = "base_link"     # the body frame in /tf_static
//! origin = { lat = 47.4, lon = 8.5, height = 500.0 }   # deg, deg, m
//! [water]
//! density = 1025.0                # kg/m^3
//! surface_pressure = 101325.0     # Pa
//! [topics."/dvl/twist"]
//! sensor = "dvl"                  # imu mag depth gnss dvl usbl altitude truth ignore
//! body_frame = "FRD"              # default FLU (REP-103)
//! world_frame = "NED"             # default ENU (REP-103)
//! ```

use std::collections::BTreeMap;

use serde::Deserialize;

use super::ImportError;

/// Which clock dates the rows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Clock {
    /// The message's `header.stamp` (the sample time), the default.
    #[default]
    Header,
    /// The time the recorder received the message (the bag's log time).
    Receive,
}

/// The sensor files a topic can feed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sensor {
    /// `imu.csv`.
    Imu,
    /// `mag.csv`.
    Mag,
    /// `depth.csv`.
    Depth,
    /// `gnss.csv`.
    Gnss,
    /// `dvl.csv`.
    Dvl,
    /// `usbl.csv`.
    Usbl,
    /// `altitude.csv`.
    Altitude,
    /// `truth.csv`.
    Truth,
    /// Not read.
    Ignore,
}

impl Sensor {
    const NAMES: [(&'static str, Sensor); 9] = [
        ("imu", Sensor::Imu),
        ("mag", Sensor::Mag),
        ("depth", Sensor::Depth),
        ("gnss", Sensor::Gnss),
        ("dvl", Sensor::Dvl),
        ("usbl", Sensor::Usbl),
        ("altitude", Sensor::Altitude),
        ("truth", Sensor::Truth),
        ("ignore", Sensor::Ignore),
    ];

    /// The name in the mapping file.
    pub fn name(self) -> &'static str {
        Self::NAMES
            .iter()
            .find(|(_, s)| *s == self)
            .map_or("ignore", |(n, _)| n)
    }

    /// The sensor a standard type feeds without a mapping.
    pub fn of_type(ty: &str) -> Option<Sensor> {
        Some(match ty {
            "sensor_msgs/msg/Imu" => Sensor::Imu,
            "sensor_msgs/msg/MagneticField" => Sensor::Mag,
            "sensor_msgs/msg/FluidPressure" => Sensor::Depth,
            "sensor_msgs/msg/NavSatFix" => Sensor::Gnss,
            "geometry_msgs/msg/TwistStamped" | "geometry_msgs/msg/TwistWithCovarianceStamped" => {
                Sensor::Dvl
            }
            "geometry_msgs/msg/PoseWithCovarianceStamped" => Sensor::Usbl,
            "sensor_msgs/msg/Range" => Sensor::Altitude,
            "nav_msgs/msg/Odometry" => Sensor::Truth,
            _ => return None,
        })
    }
}

/// One topic's entry.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TopicMap {
    /// The sensor it feeds.
    pub sensor: Sensor,
    /// Body vectors in forward-left-up (REP-103, the default) rather than
    /// forward-right-down.
    pub body_flu: bool,
    /// World vectors in east-north-up (REP-103, the default) rather than
    /// north-east-down.
    pub world_enu: bool,
}

/// The mapping (defaults: ROS conventions, header stamps, sea water).
#[derive(Debug, Clone, PartialEq)]
pub struct Mapping {
    /// Declared topics.
    pub topics: BTreeMap<String, TopicMap>,
    /// The clock.
    pub clock: Clock,
    /// Water density, kg/m^3.
    pub density: f64,
    /// Pressure at the surface, Pa.
    pub surface_pressure: f64,
    /// Origin of local positions: lat, lon (rad), height (m).
    pub origin: Option<[f64; 3]>,
    /// The vehicle's body frame id in `/tf_static` (default: `base_link`
    /// when present, else the IMU's frame).
    pub vehicle_frame: Option<String>,
}

impl Default for Mapping {
    fn default() -> Self {
        Mapping {
            topics: BTreeMap::new(),
            clock: Clock::Header,
            density: 1025.0,
            surface_pressure: 101_325.0,
            origin: None,
            vehicle_frame: None,
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct File {
    time: Option<String>,
    origin: Option<Origin>,
    vehicle_frame: Option<String>,
    water: Option<Water>,
    #[serde(default)]
    topics: BTreeMap<String, Topic>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Origin {
    lat: f64,
    lon: f64,
    height: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Water {
    density: Option<f64>,
    surface_pressure: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct Topic {
    sensor: String,
    body_frame: Option<String>,
    world_frame: Option<String>,
}

impl Mapping {
    /// Parses the mapping file `text` (`file` names it in errors).
    ///
    /// # Errors
    /// [`ImportError::Mapping`] naming the key (and the line for TOML errors).
    pub fn parse(file: &str, text: &str) -> Result<Mapping, ImportError> {
        let err = |reason: String| ImportError::Mapping {
            file: file.to_string(),
            reason,
        };
        let f: File = toml::from_str(text).map_err(|e| err(e.to_string().trim().to_string()))?;
        let clock = match f.time.as_deref() {
            None | Some("header") => Clock::Header,
            Some("receive") => Clock::Receive,
            Some(other) => {
                return Err(err(format!(
                    "`time`: `{other}`, `header` or `receive` expected"
                )))
            }
        };
        let mut m = Mapping {
            clock,
            ..Mapping::default()
        };
        if let Some(f) = f.vehicle_frame {
            if f.trim().is_empty() {
                return Err(err(
                    "`vehicle_frame`: empty, a frame id of /tf_static expected".into(),
                ));
            }
            m.vehicle_frame = Some(f);
        }
        if let Some(o) = f.origin {
            if !(o.lat.abs() <= 90.0 && o.lon.abs() <= 360.0 && o.height.abs() < 1e5) {
                return Err(err(format!(
                    "`origin`: lat {} lon {} height {}: degrees within +-90 / +-360 and metres expected",
                    o.lat, o.lon, o.height
                )));
            }
            m.origin = Some([o.lat.to_radians(), o.lon.to_radians(), o.height]);
        }
        if let Some(w) = f.water {
            if let Some(d) = w.density {
                if !(500.0..=2000.0).contains(&d) {
                    return Err(err(format!(
                        "`water.density`: {d}, kg/m^3 (500..2000) expected"
                    )));
                }
                m.density = d;
            }
            if let Some(p) = w.surface_pressure {
                if !(50_000.0..=150_000.0).contains(&p) {
                    return Err(err(format!(
                        "`water.surface_pressure`: {p}, Pa (50000..150000) expected"
                    )));
                }
                m.surface_pressure = p;
            }
        }
        for (topic, t) in f.topics {
            let sensor = Sensor::NAMES
                .iter()
                .find(|(n, _)| *n == t.sensor)
                .map(|(_, s)| *s)
                .ok_or_else(|| {
                    let names: Vec<&str> = Sensor::NAMES.iter().map(|(n, _)| *n).collect();
                    err(format!(
                        "`topics.\"{topic}\".sensor`: `{}`, one of {} expected{}",
                        t.sensor,
                        names.join(", "),
                        nav_runtime::log::did_you_mean(&t.sensor, &names)
                    ))
                })?;
            let body_flu = match t.body_frame.as_deref() {
                None | Some("FLU") => true,
                Some("FRD") => false,
                Some(o) => {
                    return Err(err(format!(
                        "`topics.\"{topic}\".body_frame`: `{o}`, `FLU` or `FRD` expected"
                    )))
                }
            };
            let world_enu = match t.world_frame.as_deref() {
                None | Some("ENU") => true,
                Some("NED") => false,
                Some(o) => {
                    return Err(err(format!(
                        "`topics.\"{topic}\".world_frame`: `{o}`, `ENU` or `NED` expected"
                    )))
                }
            };
            m.topics.insert(
                topic,
                TopicMap {
                    sensor,
                    body_flu,
                    world_enu,
                },
            );
        }
        Ok(m)
    }
}
