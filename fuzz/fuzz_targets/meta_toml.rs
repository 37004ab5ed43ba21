//! Any bytes as `meta.toml`, the log's configuration file.
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    nav_runtime::log::fuzz::meta_toml(data);
});
