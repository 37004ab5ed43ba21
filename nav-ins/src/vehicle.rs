//! Which vehicles the navigator (and the log replay built on it) can run:
//! the INS error-state core plus any subset of the sensor blocks it knows
//! (depth meter, DVL, compass, USBL, GNSS fix, barometer and magnetic
//! heading), declared in one piece or composed from `nav_blocks`.
//!
//! A vehicle is registered with a short [`InsVehicle`] impl that names, for
//! each sensor slot, the vehicle's generated sensor type (or [`Absent`]):
//!
//! ```
//! use nav_blocks::{Compass, Depth, Dvl, InsCore};
//! use nav_ins::{Absent, InsVehicle};
//!
//! nav_runtime::model! {
//!     /// The core with a depth meter, a DVL and a compass: 20 states.
//!     pub model Auv = InsCore + Depth + Dvl + Compass {
//!         allow_unused { position_error[1] }
//!     }
//! }
//!
//! impl InsVehicle<20> for Auv {
//!     const REPLAY_NAME: &'static str = "auv";
//!     const DESCRIPTION: &'static str = "INS + depth + DVL + compass";
//!     type Depth = AuvDepth;
//!     type Dvl = AuvDvl;
//!     type Compass = AuvCompass;
//!     type CompassSmallAngle = AuvCompassSmallAngle;
//!     type Usbl = Absent;
//!     type Gnss = Absent;
//!     type Baro = Absent;
//!     type Mag = Absent;
//! }
//!
//! assert!(nav_ins::vehicle::Layout::of::<Auv, 20>().is_ok());
//! ```
//!
//! Everything else is found from the generated declaration by name, once per
//! run ([`Layout::of`]): where each state lives in the vehicle's state
//! vector, and that its inputs, noise and the auxiliary inputs of the USBL
//! and GNSS sensors are those of the INS core and of those blocks (the
//! barometer's bias walk may follow the core's noise).
//! A sensor type of another dimension or another vehicle does not compile; a
//! sensor put in the wrong slot (e.g. the depth meter as the compass) or a
//! vehicle without the core is a [`NavigatorError::Setup`] naming what is wrong.

use nav_runtime::ekf::{FilterError, UpdateReport};
use nav_runtime::error_state::{ErrorStateFilter, NominalState};
use nav_runtime::model::{Model, Record, Sensor};
use nav_runtime::nalgebra::SVector;
use nav_runtime::recovery::Judgement;

use super::settings::InitialSigma;
use crate::navigator::NavigatorError;

/// A vehicle the SDINS replay loop can run (see the module docs).
///
/// Each associated type is the vehicle's generated sensor type of the block
/// named in its doc, or [`Absent`] when the vehicle does not have it; the
/// rows of a log sensor the vehicle lacks are ignored and counted as skipped.
pub trait InsVehicle<const N: usize>: Model<N> {
    /// `navsim replay --model <REPLAY_NAME>`.
    const REPLAY_NAME: &'static str;
    /// One line for `navsim list`.
    const DESCRIPTION: &'static str;
    /// Declared name of the sensor in the depth slot: the `Depth` block's,
    /// or another depth block's with the same residual (a pressure sensor at
    /// a lever arm, whose auxiliary input is `lever_arm: 3`).
    const DEPTH_SENSOR: &'static str = "Depth";
    /// The bias state of the depth slot's block.
    const DEPTH_BIAS: &'static str = "depth_bias";
    /// Declared name of the sensor in the DVL slot: the `Dvl` block's, or
    /// `DvlCalibrated` (mounting calibration states; its auxiliary input is
    /// [`DVL_CALIBRATED_AUX_NAMES`]).
    const DVL_SENSOR: &'static str = "Dvl";
    /// Declared name of the sensor in the USBL slot: the `Usbl` block's, or
    /// `UsblCalibrated` (the transponder's lever-arm error as states, same
    /// auxiliary input).
    const USBL_SENSOR: &'static str = "Usbl";
    /// Declared name of the sensor in the GNSS slot: the `GnssFix` block's,
    /// or `GnssFixCalibrated` (the antenna's lever-arm error as states, same
    /// auxiliary input).
    const GNSS_SENSOR: &'static str = "GnssFix";
    /// The depth sensor (block `Depth`, or the block of
    /// [`InsVehicle::DEPTH_SENSOR`]), fed by `depth.csv`.
    type Depth: Slot<Self, N, 1>;
    /// The DVL sensor (block `Dvl`, or the block of
    /// [`InsVehicle::DVL_SENSOR`]), fed by `dvl.csv`.
    type Dvl: Slot<Self, N, 3>;
    /// The exact `Compass` sensor (block `Compass`), fed by `heading.csv`.
    type Compass: Slot<Self, N, 1>;
    /// The small-angle `CompassSmallAngle` sensor (block `Compass`), used for
    /// `heading.csv` with `CompassForm::SmallAngle`.
    type CompassSmallAngle: Slot<Self, N, 1>;
    /// The USBL sensor (block `Usbl`, or the block of
    /// [`InsVehicle::USBL_SENSOR`]), fed by `usbl.csv`.
    type Usbl: Slot<Self, N, 2>;
    /// The GNSS sensor (block `GnssFix`: position of the antenna, whose
    /// auxiliary input is its lever arm; or the block of
    /// [`InsVehicle::GNSS_SENSOR`]), fed by `gnss.csv`.
    type Gnss: Slot<Self, N, 3>;
    /// The `Barometer` sensor (barometric altitude with a bias state
    /// `baro_bias`), fed by `baro.csv`.
    type Baro: Slot<Self, N, 1>;
    /// The `MagneticHeading` sensor (heading of a tilt-compensated
    /// magnetometer plus the declination), fed by `mag.csv`.
    type Mag: Slot<Self, N, 1>;
    /// The initial-state sigmas a log's `[initial_sigma]` does not give.
    const INITIAL_SIGMA: InitialSigma = InitialSigma::DEFAULT;
}

/// A place of [`InsVehicle`]: a generated sensor of model `Mo` with `M`
/// outputs (every [`Sensor`] is one), or [`Absent`].
pub trait Slot<Mo: Model<N>, const N: usize, const M: usize> {
    /// Whether the vehicle has the sensor.
    const PRESENT: bool;
    /// The sensor's declared name (empty for [`Absent`]).
    const NAME: &'static str;
    /// Names of the sensor's auxiliary inputs, in [`Record`] order.
    const AUX_NAMES: &'static [&'static str];
    /// Fuses the residual `z` with noise variances `r_diag`; `aux` holds the
    /// auxiliary inputs in [`Slot::AUX_NAMES`] order (missing ones are NaN,
    /// which the filter refuses).
    ///
    /// # Errors
    /// As [`ErrorStateFilter::update_sequential`]; [`Absent`] always fails.
    fn update<Nom: NominalState<N>>(
        f: &mut ErrorStateFilter<Mo, Nom, N>,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &[f64],
    ) -> Result<UpdateReport<M>, FilterError>;

    /// The recovery step after [`Slot::update`] returned `report` for the
    /// sensor's own `reading` (its values, 1-sigma noise `sigma` per
    /// component; [`nav_runtime::recovery`]): may inflate the covariance
    /// and set `report.recovered`, and returns how the reading was judged.
    /// Nothing for [`Absent`] ([`Judgement::NotFollowed`]).
    fn recover<Nom: NominalState<N>>(
        _f: &mut ErrorStateFilter<Mo, Nom, N>,
        _report: &mut UpdateReport<M>,
        _reading: &[f64],
        _sigma: &[f64],
        _aux: &[f64],
    ) -> Judgement {
        Judgement::NotFollowed
    }

    /// Makes the second refused reading of the sensor from now recover at
    /// once, reported as a run of `lasted` s
    /// ([`nav_runtime::ekf::Ekf::force_recovery`]: the navigator's
    /// rollback). Nothing for [`Absent`].
    fn force_recovery<Nom: NominalState<N>>(_f: &mut ErrorStateFilter<Mo, Nom, N>, _lasted: f64) {}
}

impl<S, Mo, const N: usize, const M: usize> Slot<Mo, N, M> for S
where
    S: Sensor<N, M, Model = Mo>,
    Mo: Model<N>,
{
    const PRESENT: bool = true;
    const NAME: &'static str = <S as Sensor<N, M>>::NAME;
    const AUX_NAMES: &'static [&'static str] = <S::Aux as Record>::NAMES;
    fn update<Nom: NominalState<N>>(
        f: &mut ErrorStateFilter<Mo, Nom, N>,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &[f64],
    ) -> Result<UpdateReport<M>, FilterError> {
        let aux = <S::Aux as Record>::from_fn(|i| aux.get(i).copied().unwrap_or(f64::NAN));
        f.update_sequential::<S, M>(z, r_diag, &aux)
    }

    fn recover<Nom: NominalState<N>>(
        f: &mut ErrorStateFilter<Mo, Nom, N>,
        report: &mut UpdateReport<M>,
        reading: &[f64],
        sigma: &[f64],
        aux: &[f64],
    ) -> Judgement {
        let aux = <S::Aux as Record>::from_fn(|i| aux.get(i).copied().unwrap_or(f64::NAN));
        f.ekf_mut()
            .recover_after_refusal::<S, M>(report, reading, sigma, &aux)
    }

    fn force_recovery<Nom: NominalState<N>>(f: &mut ErrorStateFilter<Mo, Nom, N>, lasted: f64) {
        f.ekf_mut().force_recovery::<S, M>(lasted);
    }
}

/// The vehicle has no such sensor.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Absent;

impl<Mo: Model<N>, const N: usize, const M: usize> Slot<Mo, N, M> for Absent {
    const PRESENT: bool = false;
    const NAME: &'static str = "";
    const AUX_NAMES: &'static [&'static str] = &[];
    fn update<Nom: NominalState<N>>(
        _: &mut ErrorStateFilter<Mo, Nom, N>,
        _: &SVector<f64, M>,
        _: &SVector<f64, M>,
        _: &[f64],
    ) -> Result<UpdateReport<M>, FilterError> {
        Err(FilterError::Setup(nav_runtime::ekf::SetupError::Invalid {
            reason: "the vehicle has no such sensor",
        }))
    }
}

/// The inputs of the INS core block, in [`Record`] order: the nominal solution
/// and the specific force.
pub const INPUT_NAMES: [&str; 17] = [
    "latitude",
    "height",
    "velocity[0]",
    "velocity[1]",
    "velocity[2]",
    "c_bn[0][0]",
    "c_bn[0][1]",
    "c_bn[0][2]",
    "c_bn[1][0]",
    "c_bn[1][1]",
    "c_bn[1][2]",
    "c_bn[2][0]",
    "c_bn[2][1]",
    "c_bn[2][2]",
    "specific_force[0]",
    "specific_force[1]",
    "specific_force[2]",
];

/// The process noise of the INS core block, in [`Record`] order.
pub const NOISE_NAMES: [&str; 6] = [
    "accel_noise[0]",
    "accel_noise[1]",
    "accel_noise[2]",
    "gyro_noise[0]",
    "gyro_noise[1]",
    "gyro_noise[2]",
];

/// Process noise of the blocks of the log sensors beyond the INS core's,
/// set from the sensor's [`super::SensorSettings::bias_walk`]: the
/// barometer bias random walk.
pub const SENSOR_NOISE_NAMES: [&str; 1] = ["baro_bias_noise"];

/// The auxiliary input of the GNSS block's sensor: the antenna lever arm
/// (body axes, m).
pub const ANTENNA_AUX_NAMES: [&str; 3] = [
    "antenna_lever_arm[0]",
    "antenna_lever_arm[1]",
    "antenna_lever_arm[2]",
];

/// The auxiliary input of a depth sensor at a lever arm (body axes, m).
pub const LEVER_ARM_AUX_NAMES: [&str; 3] = ["lever_arm[0]", "lever_arm[1]", "lever_arm[2]"];

/// The auxiliary input of the calibrated DVL block's sensor: the given
/// lever arm (body axes, m), the bias-corrected body rate (rad/s) and the
/// rate of change of the body-axes velocity (m/s^2).
pub const DVL_CALIBRATED_AUX_NAMES: [&str; 9] = [
    "lever_arm[0]",
    "lever_arm[1]",
    "lever_arm[2]",
    "body_rate[0]",
    "body_rate[1]",
    "body_rate[2]",
    "body_acceleration[0]",
    "body_acceleration[1]",
    "body_acceleration[2]",
];

/// The auxiliary input of the USBL block's sensor.
pub const USBL_AUX_NAMES: [&str; 3] = [
    "relative_position[0]",
    "relative_position[1]",
    "relative_position[2]",
];

/// Where the states the replay loop knows live in a vehicle's state vector
/// (index of the first scalar of each), found by name from
/// [`Model::STATE_NAMES`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Layout {
    /// `position_error` (3).
    pub position: usize,
    /// `velocity_error` (3).
    pub velocity: usize,
    /// `attitude_error` (3).
    pub attitude: usize,
    /// `accel_bias` (3).
    pub accel_bias: usize,
    /// `gyro_bias` (3).
    pub gyro_bias: usize,
    /// `usbl_bias` (2), with the USBL block.
    pub usbl_bias: Option<usize>,
    /// `depth_bias` (1), with the depth block.
    pub depth_bias: Option<usize>,
    /// `dvl_bias` (3), with the DVL block.
    pub dvl_bias: Option<usize>,
    /// `compass_bias` (1), with the compass block.
    pub compass_bias: Option<usize>,
    /// `usbl_misalignment` (3), with the USBL block.
    pub usbl_misalignment: Option<usize>,
    /// `baro_bias` (1), with the barometer block.
    pub baro_bias: Option<usize>,
}

/// Which log sensors a vehicle has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Present {
    /// `depth.csv`.
    pub depth: bool,
    /// `dvl.csv`.
    pub dvl: bool,
    /// `heading.csv`, exact form.
    pub compass: bool,
    /// `heading.csv`, small-angle form.
    pub compass_small_angle: bool,
    /// `usbl.csv`.
    pub usbl: bool,
    /// `gnss.csv`.
    pub gnss: bool,
    /// `baro.csv`.
    pub baro: bool,
    /// `mag.csv`.
    pub mag: bool,
}

impl Present {
    /// The sensors of vehicle `V`.
    pub fn of<V: InsVehicle<N>, const N: usize>() -> Self {
        Self {
            depth: <V::Depth as Slot<V, N, 1>>::PRESENT,
            dvl: <V::Dvl as Slot<V, N, 3>>::PRESENT,
            compass: <V::Compass as Slot<V, N, 1>>::PRESENT,
            compass_small_angle: <V::CompassSmallAngle as Slot<V, N, 1>>::PRESENT,
            usbl: <V::Usbl as Slot<V, N, 2>>::PRESENT,
            gnss: <V::Gnss as Slot<V, N, 3>>::PRESENT,
            baro: <V::Baro as Slot<V, N, 1>>::PRESENT,
            mag: <V::Mag as Slot<V, N, 1>>::PRESENT,
        }
    }
}

/// Index of the state group `name` of `len` scalars, if declared (its scalars
/// contiguous and in order).
fn group(names: &[&str], name: &str, len: usize) -> Result<Option<usize>, String> {
    let first = if len == 1 {
        name.to_string()
    } else {
        format!("{name}[0]")
    };
    let Some(i) = names.iter().position(|n| *n == first) else {
        if names.iter().any(|n| n.starts_with(&format!("{name}["))) {
            return Err(format!("state `{name}` does not have {len} scalars"));
        }
        return Ok(None);
    };
    for k in 1..len {
        if names.get(i + k) != Some(&format!("{name}[{k}]").as_str()) {
            return Err(format!("state `{name}` does not have {len} scalars"));
        }
    }
    if len == 1
        && names
            .get(i + 1)
            .is_some_and(|n| n.starts_with(&format!("{name}[")))
    {
        return Err(format!("state `{name}` is not a scalar"));
    }
    Ok(Some(i))
}

impl Layout {
    /// The layout of `V`, after checking that `V` is the INS core plus the
    /// blocks of its sensors: every sensor in its slot (by declared name), the
    /// states of each present sensor's block, and the core's inputs and noise.
    ///
    /// # Errors
    /// [`NavigatorError::Setup`] naming the vehicle and what does not fit.
    pub fn of<V: InsVehicle<N>, const N: usize>() -> Result<Self, NavigatorError> {
        Self::check::<V, N>().map_err(|e| {
            NavigatorError::Setup(format!(
                "vehicle {} ({}) cannot be replayed: {e}",
                V::REPLAY_NAME,
                V::NAME
            ))
        })
    }

    fn check<V: InsVehicle<N>, const N: usize>() -> Result<Self, String> {
        let names = &V::STATE_NAMES[..];
        let need = |name: &str, len: usize| -> Result<usize, String> {
            group(names, name, len)?
                .ok_or_else(|| format!("no state `{name}` (the INS core block's)"))
        };
        check_slot::<V, V::Depth, N, 1>(V::DEPTH_SENSOR)?;
        check_slot::<V, V::Dvl, N, 3>(V::DVL_SENSOR)?;
        check_slot::<V, V::Compass, N, 1>("Compass")?;
        check_slot::<V, V::CompassSmallAngle, N, 1>("CompassSmallAngle")?;
        check_slot::<V, V::Usbl, N, 2>(V::USBL_SENSOR)?;
        check_slot::<V, V::Gnss, N, 3>(V::GNSS_SENSOR)?;
        check_slot::<V, V::Baro, N, 1>("Barometer")?;
        check_slot::<V, V::Mag, N, 1>("MagneticHeading")?;
        if <V::Input as Record>::NAMES != INPUT_NAMES {
            return Err(format!(
                "its inputs {:?} are not the INS core's {INPUT_NAMES:?}",
                <V::Input as Record>::NAMES
            ));
        }
        // The core's noise first; any other declared noise (a block's own,
        // e.g. a water current's random walk) is given by name to the
        // builder (`Builder::process_noise`).
        let noise = <V::Noise as Record>::NAMES;
        if noise.get(..NOISE_NAMES.len()) != Some(&NOISE_NAMES[..]) {
            return Err(format!(
                "its process noise {noise:?} does not start with the INS core's {NOISE_NAMES:?}"
            ));
        }
        let present = Present::of::<V, N>();
        let depth_aux = <V::Depth as Slot<V, N, 1>>::AUX_NAMES;
        if present.depth && !depth_aux.is_empty() && depth_aux != LEVER_ARM_AUX_NAMES {
            return Err(format!(
                "its depth sensor's auxiliary input {depth_aux:?} is not {LEVER_ARM_AUX_NAMES:?}"
            ));
        }
        let dvl_aux = <V::Dvl as Slot<V, N, 3>>::AUX_NAMES;
        if present.dvl && !dvl_aux.is_empty() && dvl_aux != DVL_CALIBRATED_AUX_NAMES {
            return Err(format!(
                "its DVL sensor's auxiliary input {dvl_aux:?} is not {DVL_CALIBRATED_AUX_NAMES:?}"
            ));
        }
        if present.usbl && <V::Usbl as Slot<V, N, 2>>::AUX_NAMES != USBL_AUX_NAMES {
            return Err(format!(
                "its USBL auxiliary input is not {USBL_AUX_NAMES:?}"
            ));
        }
        let gnss_aux = <V::Gnss as Slot<V, N, 3>>::AUX_NAMES;
        if present.gnss && gnss_aux != ANTENNA_AUX_NAMES {
            return Err(format!(
                "its GNSS auxiliary input {gnss_aux:?} is not {ANTENNA_AUX_NAMES:?}"
            ));
        }
        for (slot, aux) in [
            ("Barometer", <V::Baro as Slot<V, N, 1>>::AUX_NAMES),
            ("MagneticHeading", <V::Mag as Slot<V, N, 1>>::AUX_NAMES),
        ] {
            if !aux.is_empty() {
                return Err(format!(
                    "its {slot} sensor has auxiliary inputs {aux:?}; the slot gives none"
                ));
            }
        }
        let layout = Layout {
            position: need("position_error", 3)?,
            velocity: need("velocity_error", 3)?,
            attitude: need("attitude_error", 3)?,
            accel_bias: need("accel_bias", 3)?,
            gyro_bias: need("gyro_bias", 3)?,
            usbl_bias: group(names, "usbl_bias", 2)?,
            depth_bias: group(names, V::DEPTH_BIAS, 1)?,
            dvl_bias: group(names, "dvl_bias", 3)?,
            compass_bias: group(names, "compass_bias", 1)?,
            usbl_misalignment: group(names, "usbl_misalignment", 3)?,
            baro_bias: group(names, "baro_bias", 1)?,
        };
        let block = |present: bool, state: Option<usize>, name: &str| -> Result<(), String> {
            if present && state.is_none() {
                return Err(format!("it has the sensor but no state `{name}`"));
            }
            Ok(())
        };
        block(present.depth, layout.depth_bias, V::DEPTH_BIAS)?;
        block(present.dvl, layout.dvl_bias, "dvl_bias")?;
        block(present.compass, layout.compass_bias, "compass_bias")?;
        block(
            present.compass_small_angle,
            layout.compass_bias,
            "compass_bias",
        )?;
        block(present.usbl, layout.usbl_bias, "usbl_bias")?;
        block(present.usbl, layout.usbl_misalignment, "usbl_misalignment")?;
        block(present.baro, layout.baro_bias, "baro_bias")?;
        if noise.contains(&"baro_bias_noise") && layout.baro_bias.is_none() {
            return Err("it has `baro_bias_noise` but no state `baro_bias`".into());
        }
        Ok(layout)
    }

    /// Per state: whether the nominal solution keeps it (the navigation
    /// errors and the groups above); the others stay in the filter as
    /// total-state estimates (`NominalState::absorbs`).
    pub fn absorbed<const N: usize>(&self) -> [bool; N] {
        let mut kept = [false; N];
        let mut mark = |at: Option<usize>, len: usize| {
            if let Some(i) = at {
                for k in kept.iter_mut().skip(i).take(len) {
                    *k = true;
                }
            }
        };
        mark(Some(self.position), 3);
        mark(Some(self.velocity), 3);
        mark(Some(self.attitude), 3);
        mark(Some(self.accel_bias), 3);
        mark(Some(self.gyro_bias), 3);
        mark(self.usbl_bias, 2);
        mark(self.depth_bias, 1);
        mark(self.dvl_bias, 3);
        mark(self.compass_bias, 1);
        mark(self.usbl_misalignment, 3);
        mark(self.baro_bias, 1);
        kept
    }

    /// Indices of the 9 navigation errors (position, velocity, attitude).
    pub fn navigation(&self) -> [usize; 9] {
        let (p, v, a) = (self.position, self.velocity, self.attitude);
        [p, p + 1, p + 2, v, v + 1, v + 2, a, a + 1, a + 2]
    }
}

/// A present sensor in slot `expected` of an [`InsVehicle`] impl must be the
/// one declared with that name.
fn check_slot<V: Model<N>, S: Slot<V, N, M>, const N: usize, const M: usize>(
    expected: &str,
) -> Result<(), String> {
    if S::PRESENT && S::NAME != expected {
        return Err(format!(
            "sensor `{}` is in the `{expected}` slot of the InsVehicle impl",
            S::NAME
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::group;

    #[test]
    fn state_groups_are_found_by_name() {
        let names = ["a", "b[0]", "b[1]", "c[0]", "c[2]"];
        assert_eq!(group(&names, "a", 1), Ok(Some(0)));
        assert_eq!(group(&names, "b", 2), Ok(Some(1)));
        assert_eq!(group(&names, "d", 3), Ok(None));
        assert!(group(&names, "b", 3).is_err());
        assert!(group(&names, "c", 2).is_err());
        assert!(group(&names, "b", 1).is_err());
    }
}
