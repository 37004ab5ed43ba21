//! Everything a navigator program needs: `use nav_ins::prelude::*;`.

pub use super::{
    Absent, BaroReading, Bounds, DepthReading, DvlReading, Estimate, GnssFix, Handle,
    HeadingReading, ImuSample, ImuSettings, InitialSigma, InitialState, InsVehicle, MagReading,
    Navigator, NavigatorError, NavigatorOptions, SensorReport, SensorSettings, UsblFix,
};
pub use nav_runtime::attitude::Euler;
pub use nav_runtime::earth::Geodetic;
pub use nav_runtime::nalgebra::Vector3;
