//! Tests of the navigator (vehicle.rs) with the estimators of this crate.
use models::sdins25::model::Sdins25;
use models::vehicles::sdins::{Sdins20, Sdins25Composed};
use nav_blocks::{Compass, Depth, InsCore};
use nav_ins::vehicle::*;

#[test]
fn registered_vehicles_fit_the_loop() {
    let mono = Layout::of::<Sdins25, 25>().unwrap();
    assert_eq!(mono.navigation(), [0, 1, 2, 3, 4, 5, 6, 7, 8]);
    assert_eq!(mono.usbl_bias, Some(Sdins25::USBL_BIAS));
    assert_eq!(mono.usbl_misalignment, Some(Sdins25::USBL_MISALIGNMENT));
    assert_eq!(Layout::of::<Sdins25Composed, 25>().unwrap(), mono);
    let l20 = Layout::of::<Sdins20, 20>().unwrap();
    assert_eq!(l20.usbl_bias, None);
    assert_eq!(l20.usbl_misalignment, None);
    assert_eq!(l20.depth_bias, Some(Sdins20::DEPTH_BIAS));
    assert_eq!(l20.dvl_bias, Some(Sdins20::DVL_BIAS));
    assert_eq!(l20.compass_bias, Some(Sdins20::COMPASS_BIAS));
    let p = Present::of::<Sdins20, 20>();
    assert!(p.depth && p.dvl && p.compass && p.compass_small_angle && !p.usbl);
}

nav_runtime::model! {
    /// Core + depth + compass, registered below with two sensors swapped.
    model Swapped = InsCore + Depth + Compass {
        allow_unused { position_error[1] }
    }
}

impl InsVehicle<17> for Swapped {
    const REPLAY_NAME: &'static str = "swapped";
    const DESCRIPTION: &'static str = "";
    type Depth = SwappedCompass;
    type Dvl = Absent;
    type Compass = SwappedDepth;
    type CompassSmallAngle = SwappedCompassSmallAngle;
    type Usbl = Absent;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

#[test]
fn a_sensor_in_the_wrong_slot_is_an_error() {
    let e = Layout::of::<Swapped, 17>().unwrap_err().to_string();
    assert!(
        e.contains("swapped") && e.contains("sensor `Compass` is in the `Depth` slot"),
        "{e}"
    );
}

nav_runtime::model! {
    /// Not an INS: a constant-velocity cart.
    pub model Cart {
        states { position, velocity }
        noise { accel_noise }
        continuous {
            d/dt position = velocity;
            d/dt velocity = accel_noise;
        }
        sensor Fix: 1 { h = [position]; }
    }
}

impl InsVehicle<2> for Cart {
    const REPLAY_NAME: &'static str = "cart-as-ins";
    const DESCRIPTION: &'static str = "";
    type Depth = Absent;
    type Dvl = Absent;
    type Compass = Absent;
    type CompassSmallAngle = Absent;
    type Usbl = Absent;
    type Gnss = Absent;
    type Baro = Absent;
    type Mag = Absent;
}

#[test]
fn a_model_without_the_ins_core_is_an_error() {
    let e = Layout::of::<Cart, 2>().unwrap_err().to_string();
    assert!(e.contains("cart-as-ins") && e.contains("inputs"), "{e}");
}
