//! Typed sensor handles and slots: a reading of the wrong type under a
//! sensor's handle, and a sensor of the wrong dimension in a slot of an
//! `InsVehicle` impl, are compile errors (the cases in `tests/ui/`).

#[test]
fn a_reading_under_another_sensors_handle_does_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/wrong_handle.rs");
}

#[test]
fn a_sensor_of_the_wrong_dimension_in_a_slot_does_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/wrong_slot_dimension.rs");
}
