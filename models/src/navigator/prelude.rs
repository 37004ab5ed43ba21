//! Everything a navigator program needs: `use models::navigator::prelude::*;`.

pub use super::{
    Absent, Bounds, DepthReading, DvlReading, Estimate, Handle, HeadingReading, ImuSample,
    ImuSettings, InitialSigma, InitialState, InsVehicle, Navigator, NavigatorError,
    NavigatorOptions, SensorReport, SensorSettings, UsblFix,
};
pub use nav_runtime::attitude::Euler;
pub use nav_runtime::earth::Geodetic;
pub use nav_runtime::nalgebra::Vector3;
