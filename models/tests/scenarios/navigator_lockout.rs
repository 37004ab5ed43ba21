//! Tests of the navigator (lockout.rs) with the estimators of this crate.
use models::sdins25::Sdins25;
use nav_ins::lockout::{configure, LockoutOptions};
use nav_ins::vehicle::{InsVehicle, Slot};
use nav_runtime::ekf::Ekf;

#[test]
fn every_sdins25_aiding_sensor_gets_its_bound() {
    let ekf = Ekf::<Sdins25, 25>::new(
        Default::default(),
        Default::default(),
        Default::default(),
        Default::default(),
    )
    .unwrap();
    let ekf = configure::<Sdins25, 25>(ekf, Some(LockoutOptions::default())).unwrap();
    let o = LockoutOptions::default();
    for (name, bound) in [
        (
            <<Sdins25 as InsVehicle<25>>::Depth as Slot<Sdins25, 25, 1>>::NAME,
            o.depth_m,
        ),
        (
            <<Sdins25 as InsVehicle<25>>::Dvl as Slot<Sdins25, 25, 3>>::NAME,
            o.dvl_m_s,
        ),
        (
            <<Sdins25 as InsVehicle<25>>::Compass as Slot<Sdins25, 25, 1>>::NAME,
            o.heading_rad,
        ),
        (
            <<Sdins25 as InsVehicle<25>>::Usbl as Slot<Sdins25, 25, 2>>::NAME,
            o.usbl_m,
        ),
    ] {
        assert!(!name.is_empty());
        assert_eq!(ekf.lockout_bound(name), bound, "{name}");
    }
    assert_eq!(ekf.lockout_release(), Some(o.rule));
    let bad = LockoutOptions { dvl_m_s: 0.0, ..o };
    let ekf = Ekf::<Sdins25, 25>::new(
        Default::default(),
        Default::default(),
        Default::default(),
        Default::default(),
    )
    .unwrap();
    assert!(configure::<Sdins25, 25>(ekf, Some(bad)).is_err());
}
