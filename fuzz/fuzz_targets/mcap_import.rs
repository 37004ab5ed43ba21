//! Any bytes as a ROS 2 bag (MCAP): imported or refused with an error, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nav_import::mcap::fuzz::import_bytes(data);
});
