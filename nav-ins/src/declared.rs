//! Sensors, states and process noise of a vehicle found by their declared
//! names, beyond what the navigator knows by kind (the seven reading types
//! of [`crate::Reading`] and the states of [`crate::vehicle::Layout`]).
//!
//! A block a user writes in their own crate (a speed log with a water-current
//! state, a range to a beacon) is part of the vehicle's generated model; the
//! navigator binds it by name, with no code per sensor:
//!
//! - a **declared sensor** that no reading kind feeds is fused in the model
//!   replay's convention: its `h` predicts the reading, so a reading `z`
//!   (one value per output) is applied as it is, with the auxiliary inputs
//!   the file gives ([`crate::Navigator::push_declared`]);
//! - a **state** of such a block has no place in the nominal solution: it
//!   stays in the filter as a total-state estimate (see
//!   `nav_runtime::error_state`, "States the nominal does not keep") and
//!   needs an initial sigma ([`crate::Builder::state_sigma`]);
//! - its **process noise** needs a value ([`crate::Builder::process_noise`]).
//!
//! Missing values are setup errors naming the state, noise or sensor, never
//! a silent default.

use std::marker::PhantomData;

use nav_runtime::ekf::FilterError;
use nav_runtime::model::{Model, Record, Sensor, SensorVisitor};
use nav_runtime::nalgebra::SVector;
use nav_runtime::scheduler::MeasurementOutcome;

use super::nominal::InsFilter;
use super::vehicle::{InsVehicle, Slot};

/// Fuses a reading: `(filter, z, noise variances, auxiliary inputs)`.
type UpdateFn<V, const N: usize> =
    fn(&mut InsFilter<V, N>, &[f64], &[f64], &[f64]) -> Result<MeasurementOutcome, FilterError>;

/// A declared sensor of vehicle `V`, bound by its name.
pub struct DeclaredSensor<V: InsVehicle<N>, const N: usize> {
    /// The declared name.
    pub name: &'static str,
    /// Number of outputs (values per reading).
    pub outputs: usize,
    /// Names of its auxiliary inputs, in order.
    pub aux: &'static [&'static str],
    update: UpdateFn<V, N>,
}

impl<V: InsVehicle<N>, const N: usize> Clone for DeclaredSensor<V, N> {
    fn clone(&self) -> Self {
        *self
    }
}

impl<V: InsVehicle<N>, const N: usize> Copy for DeclaredSensor<V, N> {}

impl<V: InsVehicle<N>, const N: usize> core::fmt::Debug for DeclaredSensor<V, N> {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("DeclaredSensor")
            .field("name", &self.name)
            .field("outputs", &self.outputs)
            .field("aux", &self.aux)
            .finish()
    }
}

struct Binder<V, const N: usize>(PhantomData<fn() -> V>);

impl<V: InsVehicle<N>, const N: usize> SensorVisitor<V, N> for Binder<V, N> {
    type Output = DeclaredSensor<V, N>;
    fn visit<S: Sensor<N, M, Model = V>, const M: usize>(self) -> DeclaredSensor<V, N> {
        DeclaredSensor {
            name: <S as Sensor<N, M>>::NAME,
            outputs: M,
            aux: <S::Aux as Record>::NAMES,
            update: update::<V, S, N, M>,
        }
    }
}

fn update<V: InsVehicle<N>, S: Sensor<N, M, Model = V>, const N: usize, const M: usize>(
    f: &mut InsFilter<V, N>,
    z: &[f64],
    r_diag: &[f64],
    aux: &[f64],
) -> Result<MeasurementOutcome, FilterError> {
    let at = |v: &[f64], i: usize| v.get(i).copied().unwrap_or(f64::NAN);
    let z = SVector::<f64, M>::from_fn(|i, _| at(z, i));
    let r = SVector::<f64, M>::from_fn(|i, _| at(r_diag, i));
    let aux = <S::Aux as Record>::from_fn(|i| at(aux, i));
    f.update_sequential::<S, M>(&z, &r, &aux)
        .map(|rep| MeasurementOutcome::from(&rep))
}

impl<V: InsVehicle<N>, const N: usize> DeclaredSensor<V, N> {
    /// The sensor of `V` declared as `name`, if any.
    pub fn named(name: &str) -> Option<Self> {
        V::visit_sensor(name, Binder(PhantomData))
    }

    /// Every declared sensor of `V` that no reading kind feeds (not in a
    /// slot of its [`InsVehicle`] impl), in declaration order.
    pub fn unslotted() -> Vec<Self> {
        let slotted = slotted_names::<V, N>();
        V::DECLARED_SENSORS
            .iter()
            .filter(|n| !slotted.contains(n))
            .filter_map(|n| Self::named(n))
            .collect()
    }

    /// Fuses one reading (`z`: one value per output; `r_diag`: the noise
    /// variance of each; `aux`: the auxiliary inputs in [`Self::aux`]
    /// order, NaN where missing, which the filter refuses).
    ///
    /// # Errors
    /// As `ErrorStateFilter::update_sequential`.
    pub fn update(
        &self,
        f: &mut InsFilter<V, N>,
        z: &[f64],
        r_diag: &[f64],
        aux: &[f64],
    ) -> Result<MeasurementOutcome, FilterError> {
        (self.update)(f, z, r_diag, aux)
    }
}

/// The declared names of the sensors in `V`'s slots (empty strings for
/// [`crate::Absent`]).
pub fn slotted_names<V: InsVehicle<N>, const N: usize>() -> [&'static str; 8] {
    [
        <V::Depth as Slot<V, N, 1>>::NAME,
        <V::Dvl as Slot<V, N, 3>>::NAME,
        <V::Compass as Slot<V, N, 1>>::NAME,
        <V::CompassSmallAngle as Slot<V, N, 1>>::NAME,
        <V::Usbl as Slot<V, N, 2>>::NAME,
        <V::Gnss as Slot<V, N, 3>>::NAME,
        <V::Baro as Slot<V, N, 1>>::NAME,
        <V::Mag as Slot<V, N, 1>>::NAME,
    ]
}

/// The slot (reading kind) that feeds sensor `name` of `V`, if it is in one:
/// the file it reads, for messages.
pub fn slot_file<V: InsVehicle<N>, const N: usize>(name: &str) -> Option<&'static str> {
    const FILES: [&str; 8] = [
        "depth.csv",
        "dvl.csv",
        "heading.csv",
        "heading.csv",
        "usbl.csv",
        "gnss.csv",
        "baro.csv",
        "mag.csv",
    ];
    slotted_names::<V, N>()
        .iter()
        .position(|n| !n.is_empty() && *n == name)
        .map(|i| FILES[i])
}

/// The state scalars of `V` the nominal solution does not keep (outside
/// its [`crate::vehicle::Layout`]), by index.
pub fn extra_states<V: InsVehicle<N>, const N: usize>(absorbed: &[bool; N]) -> Vec<usize> {
    (0..N).filter(|&i| !absorbed[i]).collect()
}

/// The process-noise scalars of `V` beyond the INS core's and the
/// barometer's bias walk, by index in `V::Noise`.
pub fn extra_noise<V: Model<N>, const N: usize>() -> Vec<usize> {
    let names = <V::Noise as Record>::NAMES;
    (0..names.len())
        .filter(|&i| {
            !super::vehicle::NOISE_NAMES.contains(&names[i])
                && !super::vehicle::SENSOR_NOISE_NAMES.contains(&names[i])
        })
        .collect()
}
