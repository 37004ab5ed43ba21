//! The PX4 topics the importer reads, and the fields of each (every layout
//! seen over the years; a table keeps the ones its log has).
//!
//! | output | topics, in order of preference |
//! |---|---|
//! | `imu.csv` (rates) | `sensor_combined`: `gyro_rad[3]`, `accelerometer_m_s2[3]` |
//! | `imu.csv` (increments) | `vehicle_imu`: `delta_angle[3]`, `delta_velocity[3]`; as rates (divided by `delta_angle_dt`, `delta_velocity_dt`) when those periods are not the row spacing |
//! | `mag.csv` | `vehicle_magnetometer.magnetometer_ga[3]`; older logs `sensor_combined.magnetometer_ga[3]` |
//! | `baro.csv` | `vehicle_air_data.baro_alt_meter`; `sensor_baro.pressure` (standard atmosphere); older logs `sensor_combined.baro_alt_meter` |
//! | `gnss.csv` | `vehicle_gps_position`, then `sensor_gps`: `latitude_deg`/`longitude_deg`/`altitude_ellipsoid_m` (newer) or `lat`/`lon` (1e-7 deg) and `alt_ellipsoid` (mm) (older) |
//! | `reference.csv` | `vehicle_attitude.q`, `vehicle_global_position`, `vehicle_local_position.vx/vy/vz` |
//! | `truth.csv` | the same three topics with the suffix `_groundtruth` (simulated flights) |

const QUATERNION: &[&str] = &[
    "timestamp",
    "timestamp_sample",
    "q[0]",
    "q[1]",
    "q[2]",
    "q[3]",
];
const GLOBAL: &[&str] = &[
    "timestamp",
    "timestamp_sample",
    "lat",
    "lon",
    "alt",
    "alt_ellipsoid",
];
const LOCAL: &[&str] = &["timestamp", "timestamp_sample", "vx", "vy", "vz"];
const GNSS: &[&str] = &[
    "timestamp",
    "timestamp_sample",
    "latitude_deg",
    "longitude_deg",
    "altitude_msl_m",
    "altitude_ellipsoid_m",
    "lat",
    "lon",
    "alt",
    "alt_ellipsoid",
    "eph",
    "epv",
    "vel_n_m_s",
    "vel_e_m_s",
    "vel_d_m_s",
    "s_variance_m_s",
    "fix_type",
];

/// Every topic read, with the fields read from it where present.
pub const WANTED: &[(&str, &[&str])] = &[
    (
        "sensor_combined",
        &[
            "timestamp",
            "gyro_rad[0]",
            "gyro_rad[1]",
            "gyro_rad[2]",
            "accelerometer_m_s2[0]",
            "accelerometer_m_s2[1]",
            "accelerometer_m_s2[2]",
            "accelerometer_timestamp_relative",
            "magnetometer_ga[0]",
            "magnetometer_ga[1]",
            "magnetometer_ga[2]",
            "magnetometer_timestamp_relative",
            "baro_alt_meter",
            "baro_timestamp_relative",
        ],
    ),
    (
        "vehicle_imu",
        &[
            "timestamp",
            "timestamp_sample",
            "delta_angle[0]",
            "delta_angle[1]",
            "delta_angle[2]",
            "delta_velocity[0]",
            "delta_velocity[1]",
            "delta_velocity[2]",
            "delta_angle_dt",
            "delta_velocity_dt",
        ],
    ),
    (
        "vehicle_magnetometer",
        &[
            "timestamp",
            "timestamp_sample",
            "magnetometer_ga[0]",
            "magnetometer_ga[1]",
            "magnetometer_ga[2]",
        ],
    ),
    (
        "vehicle_air_data",
        &["timestamp", "timestamp_sample", "baro_alt_meter"],
    ),
    (
        "sensor_baro",
        &["timestamp", "timestamp_sample", "pressure"],
    ),
    ("vehicle_gps_position", GNSS),
    ("sensor_gps", GNSS),
    ("vehicle_attitude", QUATERNION),
    ("vehicle_global_position", GLOBAL),
    ("vehicle_local_position", LOCAL),
    ("vehicle_attitude_groundtruth", QUATERNION),
    ("vehicle_global_position_groundtruth", GLOBAL),
    ("vehicle_local_position_groundtruth", LOCAL),
];

/// Parameters read from the log's initial parameters, with the default used
/// when a log lacks one (PX4 EKF2's defaults) and its unit.
pub const PARAMETERS: &[(&str, f64, &str)] = &[
    ("EKF2_GYR_NOISE", 1.5e-2, "rad/s"),
    ("EKF2_ACC_NOISE", 3.5e-1, "m/s^2"),
    ("EKF2_MAG_NOISE", 5.0e-2, "gauss"),
    ("EKF2_BARO_NOISE", 3.5, "m"),
    ("EKF2_GPS_P_NOISE", 0.5, "m"),
    ("EKF2_GPS_V_NOISE", 0.3, "m/s"),
];

// `EKF2_MAG_DECL` (deg) is read too, for the declination of an attitude
// leveled from the magnetometer; it has no default (0 is said).
