//! Any bytes as a PX4 ULog file: imported or refused with an error, never a panic.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nav_import::ulog::fuzz::import_bytes(data);
});
