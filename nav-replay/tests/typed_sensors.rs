//! Typed sensors: a reading of the wrong type under a sensor's handle, a
//! sensor of the wrong dimension in a slot of an `InsVehicle` impl, and a
//! sensor of another model registered with a model replay are compile
//! errors (the cases in `tests/ui/`, compiled in one batch).

#[test]
fn sensors_of_the_wrong_type_dimension_or_model_do_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/wrong_handle.rs");
    t.compile_fail("tests/ui/wrong_slot_dimension.rs");
    t.compile_fail("tests/ui/foreign_sensor_in_model_replay.rs");
}
