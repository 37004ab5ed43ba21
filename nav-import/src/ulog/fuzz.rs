//! The body of the `ulog_import` fuzz target (`fuzz/fuzz_targets/ulog_import.rs`):
//! any bytes are either imported or refused with an error, never a panic.

/// Imports `bytes` without the panic guard, so that a panic reaches the fuzzer.
pub fn import_bytes(bytes: &[u8]) {
    if let Ok(log) = super::read_unguarded("fuzz.ulg", bytes) {
        // Writing is not fuzzed (it touches the disk); producing the text is.
        for f in &log.files {
            let _ = f.text();
        }
    }
}
