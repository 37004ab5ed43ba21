//! Any bytes as a `meta.toml` with a declared mapping, a NUL byte, and a CSV
//! file read through that mapping as each sensor's file.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nav_runtime::log::fuzz::mapped_log(data);
});
