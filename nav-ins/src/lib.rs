//! `nav-ins`: the navigator, an INS error-state filter for a vehicle declared
//! with `nav_runtime::model!` (the INS core of `nav_blocks` plus any of its
//! depth, DVL, compass, USBL, GNSS fix, barometer and magnetic heading
//! blocks), navigating from pushed IMU samples and typed sensor readings.
//! See `docs/pipeline.md` for the user program and the list of concepts.
//!
//! - [`Navigator`], built with [`Navigator::builder`] from an
//!   [`InitialState`], [`ImuSettings`] and one [`SensorSettings`] per sensor;
//! - typed [`Handle`]s, one per reading type ([`DepthReading`],
//!   [`DvlReading`], [`HeadingReading`], [`UsblFix`], [`GnssFix`],
//!   [`BaroReading`], [`MagReading`]);
//! - [`Estimate`] and [`SensorReport`] to read;
//! - [`InsVehicle`] to register a vehicle.
//!
//! `use nav_ins::prelude::*;` brings all of it. The crate knows nothing of
//! log files: the replay library (`nav-replay`) feeds it from a log
//! directory.
#![warn(missing_docs)]

pub mod declared;
pub mod heading;
pub mod health;
pub mod lockout;
mod measurement;
#[allow(clippy::module_inception)]
mod navigator;
mod nominal;
mod recovery;
mod sensor;
mod settings;
pub mod vehicle;

pub mod prelude;

pub use declared::DeclaredSensor;
pub use health::{RunHealth, SensorHealth};
pub use measurement::{
    baro_measurement, depth_measurement, dvl_measurement, dvl_measurement_at, gnss_measurement,
    heading_measurement, mag_measurement, usbl_measurement, usbl_measurement_at, CompassForm,
};
pub use navigator::{
    Builder, DeclaredHandle, Navigator, NavigatorError, SensorReport, Ticket, SENSORS,
    SENSOR_NAMES, SIGMA_FLOOR,
};
pub use nominal::{Estimate, ImuSample, InsFilter, InsNominal, ESTIMATE_SCALARS};
pub use recovery::Recovery;
pub use sensor::{
    BaroReading, DepthReading, DvlReading, GnssFix, Handle, HeadingReading, MagReading, Reading,
    UsblFix,
};
pub use settings::{
    Bounds, ImuSettings, InitialSigma, InitialState, NavigatorOptions, SensorSettings,
};
pub use vehicle::{Absent, InsVehicle};
