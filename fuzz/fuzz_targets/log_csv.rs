//! Any bytes as a CSV file of the log format: the first byte selects the
//! sensor file (imu, dvl, depth, heading, usbl, speed, rpm, altitude, truth).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nav_runtime::log::fuzz::csv_file(data);
});
