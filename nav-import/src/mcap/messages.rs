//! The standard ROS 2 message types the bag import understands, decoded
//! from CDR ([`super::cdr`]) into what the log directory needs. Vectors are
//! as in the message (ROS frames: REP-103); `frames` converts.

use super::cdr::{Cdr, CdrError};

/// A decoded message: its header stamp (ns), frame id and content.
#[derive(Debug, Clone, PartialEq)]
pub struct Decoded {
    /// Header stamp, ns since the epoch.
    pub stamp_ns: i64,
    /// `header.frame_id`.
    pub frame: String,
    /// The content.
    pub reading: Reading,
}

/// The content of a standard message.
#[derive(Debug, Clone, PartialEq)]
pub enum Reading {
    /// `sensor_msgs/Imu`: orientation (x, y, z, w; `None` when its
    /// covariance says "no estimate"), rate (rad/s), acceleration (m/s^2),
    /// and the first diagonal element of each covariance.
    Imu {
        orientation: Option<[f64; 4]>,
        rate: [f64; 3],
        accel: [f64; 3],
        rate_variance: f64,
        accel_variance: f64,
    },
    /// `sensor_msgs/MagneticField`, tesla.
    Mag { field: [f64; 3], variance: f64 },
    /// `sensor_msgs/FluidPressure`, Pa.
    Pressure { pa: f64, variance: f64 },
    /// `sensor_msgs/NavSatFix`: fix status, lat/lon (deg), altitude (m),
    /// position covariance diagonal (east, north, up), its type.
    Fix {
        status: i8,
        lat: f64,
        lon: f64,
        alt: f64,
        variance: [f64; 3],
        covariance_type: u8,
    },
    /// `geometry_msgs/TwistStamped` / `TwistWithCovarianceStamped`: linear
    /// velocity (m/s), its variance (x) when given.
    Twist {
        linear: [f64; 3],
        variance: Option<f64>,
    },
    /// `geometry_msgs/PoseWithCovarianceStamped`: position (m), orientation,
    /// position variance (x).
    Pose {
        position: [f64; 3],
        orientation: [f64; 4],
        variance: f64,
    },
    /// `sensor_msgs/Range`, m.
    Range { range: f64, min: f64, max: f64 },
    /// `nav_msgs/Odometry`: pose in `header.frame_id`, twist in the child frame.
    Odometry {
        position: [f64; 3],
        orientation: [f64; 4],
        linear: [f64; 3],
    },
    /// `tf2_msgs/TFMessage`: (parent, child, translation, rotation x y z w).
    Transforms(Vec<(String, String, [f64; 3], [f64; 4])>),
}

/// The types understood, by their ROS 2 names (`sensor_msgs/msg/Imu`; the
/// form without `msg/` is accepted too).
pub const TYPES: &[&str] = &[
    "sensor_msgs/msg/Imu",
    "sensor_msgs/msg/MagneticField",
    "sensor_msgs/msg/FluidPressure",
    "sensor_msgs/msg/NavSatFix",
    "geometry_msgs/msg/TwistStamped",
    "geometry_msgs/msg/TwistWithCovarianceStamped",
    "geometry_msgs/msg/PoseWithCovarianceStamped",
    "sensor_msgs/msg/Range",
    "nav_msgs/msg/Odometry",
    "tf2_msgs/msg/TFMessage",
];

/// `name` in the `pkg/msg/Type` form.
pub fn canonical(name: &str) -> String {
    match name.split('/').collect::<Vec<_>>().as_slice() {
        [pkg, ty] => format!("{pkg}/msg/{ty}"),
        _ => name.to_string(),
    }
}

/// At most this many transforms in one `TFMessage` are read.
const MAX_TRANSFORMS: usize = 1024;

/// Decodes a message of type `ty` (canonical); `None` for a type not in [`TYPES`].
///
/// # Errors
/// The field that could not be read.
pub fn decode(ty: &str, data: &[u8]) -> Option<Result<Decoded, CdrError>> {
    if !TYPES.contains(&ty) {
        return None;
    }
    Some(decode_known(ty, data))
}

fn decode_known(ty: &str, data: &[u8]) -> Result<Decoded, CdrError> {
    let mut c = Cdr::new(data)?;
    if ty == "tf2_msgs/msg/TFMessage" {
        let n = c.sequence("transforms", 8 + 4 + 4 + 56)?;
        let mut out = Vec::with_capacity(n.min(MAX_TRANSFORMS));
        for _ in 0..n {
            let (_, parent) = c.header()?;
            let child = c.string("child_frame_id")?;
            let t = c.f64s::<3>("transform.translation")?;
            let q = c.f64s::<4>("transform.rotation")?;
            if out.len() < MAX_TRANSFORMS {
                out.push((parent, child, t, q));
            }
        }
        return Ok(Decoded {
            stamp_ns: 0,
            frame: String::new(),
            reading: Reading::Transforms(out),
        });
    }
    let (stamp_ns, frame) = c.header()?;
    let reading = match ty {
        "sensor_msgs/msg/Imu" => {
            let q = c.f64s::<4>("orientation")?;
            let qc = c.f64s::<9>("orientation_covariance")?;
            let rate = c.f64s::<3>("angular_velocity")?;
            let rc = c.f64s::<9>("angular_velocity_covariance")?;
            let accel = c.f64s::<3>("linear_acceleration")?;
            let ac = c.f64s::<9>("linear_acceleration_covariance")?;
            Reading::Imu {
                orientation: (qc[0] != -1.0).then_some(q),
                rate,
                accel,
                rate_variance: rc[0],
                accel_variance: ac[0],
            }
        }
        "sensor_msgs/msg/MagneticField" => {
            let field = c.f64s::<3>("magnetic_field")?;
            let cov = c.f64s::<9>("magnetic_field_covariance")?;
            Reading::Mag {
                field,
                variance: cov[0],
            }
        }
        "sensor_msgs/msg/FluidPressure" => Reading::Pressure {
            pa: c.f64("fluid_pressure")?,
            variance: c.f64("variance")?,
        },
        "sensor_msgs/msg/NavSatFix" => {
            let status = c.u8("status.status")? as i8;
            c.u16("status.service")?;
            let lat = c.f64("latitude")?;
            let lon = c.f64("longitude")?;
            let alt = c.f64("altitude")?;
            let cov = c.f64s::<9>("position_covariance")?;
            let covariance_type = c.u8("position_covariance_type")?;
            Reading::Fix {
                status,
                lat,
                lon,
                alt,
                variance: [cov[0], cov[4], cov[8]],
                covariance_type,
            }
        }
        "geometry_msgs/msg/TwistStamped" => {
            let linear = c.f64s::<3>("twist.linear")?;
            c.f64s::<3>("twist.angular")?;
            Reading::Twist {
                linear,
                variance: None,
            }
        }
        "geometry_msgs/msg/TwistWithCovarianceStamped" => {
            let linear = c.f64s::<3>("twist.twist.linear")?;
            c.f64s::<3>("twist.twist.angular")?;
            let cov = c.f64s::<36>("twist.covariance")?;
            Reading::Twist {
                linear,
                variance: Some(cov[0]),
            }
        }
        "geometry_msgs/msg/PoseWithCovarianceStamped" => {
            let position = c.f64s::<3>("pose.pose.position")?;
            let orientation = c.f64s::<4>("pose.pose.orientation")?;
            let cov = c.f64s::<36>("pose.covariance")?;
            Reading::Pose {
                position,
                orientation,
                variance: cov[0],
            }
        }
        "sensor_msgs/msg/Range" => {
            c.u8("radiation_type")?;
            c.f32("field_of_view")?;
            let min = c.f32("min_range")?;
            let max = c.f32("max_range")?;
            let range = c.f32("range")?;
            Reading::Range { range, min, max }
        }
        _ => {
            // nav_msgs/msg/Odometry
            c.string("child_frame_id")?;
            let position = c.f64s::<3>("pose.pose.position")?;
            let orientation = c.f64s::<4>("pose.pose.orientation")?;
            c.f64s::<36>("pose.covariance")?;
            let linear = c.f64s::<3>("twist.twist.linear")?;
            Reading::Odometry {
                position,
                orientation,
                linear,
            }
        }
    };
    Ok(Decoded {
        stamp_ns,
        frame,
        reading,
    })
}
