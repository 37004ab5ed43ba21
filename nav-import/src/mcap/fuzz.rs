//! The body of the `mcap_import` fuzz target (`fuzz/fuzz_targets/mcap_import.rs`):
//! any bytes as a bag are either imported or refused with an error, never a
//! panic.

/// Imports `bytes` as a bag with the default mapping.
pub fn import_bytes(bytes: &[u8]) {
    if let Ok(bag) = super::read("fuzz.mcap", bytes, &super::Mapping::default()) {
        for f in &bag.files {
            let _ = f.text();
        }
    }
}
