//! Typed sensor handles: each log sensor of an INS vehicle has its own reading
//! type, and a [`Handle`] of that type is the only way to push a reading, so a
//! DVL reading pushed under the depth meter's handle does not compile.

use std::marker::PhantomData;

use nav_runtime::earth::LocalNed;
use nav_runtime::nalgebra::{Matrix3, Vector3};
use nav_runtime::scheduler::Measurement;

use super::measurement::{
    baro_measurement, depth_measurement_at, dvl_measurement_at, gnss_measurement,
    heading_measurement, mag_measurement, usbl_measurement_at, CompassForm,
};
use super::nominal::InsFilter;
use super::vehicle::{InsVehicle, Present};

/// A depth-meter reading: depth (m, positive down).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DepthReading(pub f64);

/// A DVL reading: velocity over the bottom in the sensor frame (m/s), which
/// the sensor's mounting turns into body axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvlReading(pub Vector3<f64>);

/// A compass reading: heading (rad, clockwise from north).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HeadingReading(pub f64);

/// A USBL fix: the vehicle's latitude and longitude (rad) as the surface array
/// measured them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UsblFix {
    /// Latitude (rad).
    pub lat: f64,
    /// Longitude (rad).
    pub lon: f64,
}

/// A GNSS position fix of the antenna: latitude, longitude (rad), height
/// (m, up), with the receiver's own horizontal and vertical accuracy (1
/// sigma, m) when it gives them; the noise used is the larger of those and
/// the sensor's noise sigma.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct GnssFix {
    /// Latitude (rad).
    pub lat: f64,
    /// Longitude (rad).
    pub lon: f64,
    /// Height (m, positive up).
    pub height: f64,
    /// Horizontal accuracy (m).
    pub eph: Option<f64>,
    /// Vertical accuracy (m).
    pub epv: Option<f64>,
}

/// A barometer reading: barometric altitude (m, positive up), biased.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BaroReading(pub f64);

/// A magnetometer reading: the magnetic field in body axes (any unit, the
/// unit of the sensor's noise sigma); it is used as a tilt-compensated
/// heading plus the declination.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MagReading(pub Vector3<f64>);

/// What a reading needs from the navigator to become a measurement.
#[derive(Clone, Copy, Debug)]
pub struct Context {
    /// Noise sigma of one reading (in the reading's units).
    pub noise_sigma: f64,
    /// Sensor-to-body rotation (`None`: the identity).
    pub mounting: Option<Matrix3<f64>>,
    /// Lever arm of the sensor from the IMU, body axes (m).
    pub lever_arm: Vector3<f64>,
    /// Compass residual form.
    pub compass: CompassForm,
    /// Local frame at the USBL transducer.
    pub usbl_frame: LocalNed,
    /// Magnetic declination (rad, east positive).
    pub declination: f64,
}

/// A reading of one of the log sensors (implemented by the seven reading types).
pub trait Reading: Copy + sealed::Sealed {
    /// Index of the sensor in the navigator (depth, DVL, compass, USBL,
    /// GNSS, barometer, magnetometer).
    #[doc(hidden)]
    const SLOT: usize;
    /// Sensor name (`depth`, `dvl`, `heading`, `usbl`, `gnss`, `baro`, `mag`).
    const NAME: &'static str;
    /// Whether vehicle `V` has this sensor.
    #[doc(hidden)]
    fn present(p: &Present, compass: CompassForm) -> bool;
    /// The reading as a measurement of `V`'s filter.
    #[doc(hidden)]
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>>;
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for super::DepthReading {}
    impl Sealed for super::DvlReading {}
    impl Sealed for super::HeadingReading {}
    impl Sealed for super::UsblFix {}
    impl Sealed for super::GnssFix {}
    impl Sealed for super::BaroReading {}
    impl Sealed for super::MagReading {}
}

impl Reading for DepthReading {
    const SLOT: usize = 0;
    const NAME: &'static str = "depth";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.depth
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        depth_measurement_at::<V, N>(self.0, ctx.noise_sigma, ctx.lever_arm)
    }
}

impl Reading for DvlReading {
    const SLOT: usize = 1;
    const NAME: &'static str = "dvl";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.dvl
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        let v = ctx.mounting.map_or(self.0, |m| m * self.0);
        dvl_measurement_at::<V, N>(v, ctx.noise_sigma, ctx.lever_arm)
    }
}

impl Reading for HeadingReading {
    const SLOT: usize = 2;
    const NAME: &'static str = "heading";
    fn present(p: &Present, compass: CompassForm) -> bool {
        match compass {
            CompassForm::Exact => p.compass,
            CompassForm::SmallAngle => p.compass_small_angle,
        }
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        heading_measurement::<V, N>(self.0, ctx.noise_sigma, ctx.compass)
    }
}

impl Reading for UsblFix {
    const SLOT: usize = 3;
    const NAME: &'static str = "usbl";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.usbl
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        usbl_measurement_at::<V, N>(
            self.lat,
            self.lon,
            ctx.noise_sigma,
            ctx.usbl_frame,
            ctx.lever_arm,
        )
    }
}

impl Reading for GnssFix {
    const SLOT: usize = 4;
    const NAME: &'static str = "gnss";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.gnss
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        gnss_measurement::<V, N>(self, ctx.noise_sigma, ctx.lever_arm)
    }
}

impl Reading for BaroReading {
    const SLOT: usize = 5;
    const NAME: &'static str = "baro";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.baro
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        baro_measurement::<V, N>(self.0, ctx.noise_sigma, ctx.lever_arm)
    }
}

impl Reading for MagReading {
    const SLOT: usize = 6;
    const NAME: &'static str = "mag";
    fn present(p: &Present, _: CompassForm) -> bool {
        p.mag
    }
    fn measurement<V: InsVehicle<N>, const N: usize>(
        &self,
        ctx: &Context,
    ) -> Box<dyn Measurement<InsFilter<V, N>>> {
        let m = ctx.mounting.map_or(self.0, |c| c * self.0);
        mag_measurement::<V, N>(m, ctx.noise_sigma, ctx.declination)
    }
}

/// The handle of a sensor added to a navigator: readings of type `R` only.
pub struct Handle<R> {
    reading: PhantomData<fn(R)>,
}

impl<R> Handle<R> {
    pub(crate) fn new() -> Self {
        Self {
            reading: PhantomData,
        }
    }
}

impl<R> Clone for Handle<R> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<R> Copy for Handle<R> {}

impl<R: Reading> std::fmt::Debug for Handle<R> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "Handle<{}>", R::NAME)
    }
}
