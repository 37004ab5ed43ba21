//! The navigator: an INS vehicle declared with `nav_runtime::model!` (the INS
//! core plus any of the depth, DVL, compass and USBL blocks), navigating from
//! pushed IMU samples and typed sensor readings (the blocks of the GNSS fix,
//! barometer and magnetic heading too). See `docs/pipeline.md` for
//! the user program and the list of concepts.
//!
//! - [`Navigator`], built with [`Navigator::builder`] from an
//!   [`InitialState`], [`ImuSettings`] and one [`SensorSettings`] per sensor;
//! - typed [`Handle`]s, one per reading type ([`DepthReading`],
//!   [`DvlReading`], [`HeadingReading`], [`UsblFix`], [`GnssFix`],
//!   [`BaroReading`], [`MagReading`]);
//! - [`Estimate`] and [`SensorReport`] to read;
//! - [`InsVehicle`] to register a vehicle.
//!
//! `use models::navigator::prelude::*;` brings all of it.

mod measurement;
#[allow(clippy::module_inception)]
mod navigator;
mod nominal;
mod sensor;
mod settings;
pub mod vehicle;

pub mod prelude;

pub use crate::harness::SensorHealth;
pub use measurement::{
    baro_measurement, depth_measurement, dvl_measurement, dvl_measurement_at, gnss_measurement,
    heading_measurement, mag_measurement, usbl_measurement, usbl_measurement_at, CompassForm,
};
pub use navigator::{
    Builder, Navigator, NavigatorError, SensorReport, Ticket, SENSORS, SENSOR_NAMES,
};
pub(crate) use nominal::ESTIMATE_SCALARS;
pub use nominal::{Estimate, ImuSample, InsFilter, InsNominal};
pub use sensor::{
    BaroReading, DepthReading, DvlReading, GnssFix, Handle, HeadingReading, MagReading, Reading,
    UsblFix,
};
pub use settings::{
    Bounds, ImuSettings, InitialSigma, InitialState, NavigatorOptions, SensorSettings,
};
pub use vehicle::{Absent, InsVehicle};
