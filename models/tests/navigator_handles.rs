//! Typed sensor handles: a reading of the wrong type under a sensor's handle
//! is a compile error (the case in `tests/ui/`).

#[test]
fn a_reading_under_another_sensors_handle_does_not_compile() {
    let t = trybuild::TestCases::new();
    t.compile_fail("tests/ui/wrong_handle.rs");
}
