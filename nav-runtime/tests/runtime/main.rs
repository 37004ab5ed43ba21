//! The runtime through its public API: log reading (errors, mapping, round
//! trips, imported files, fuzz corpus and properties), the DVL estimate
//! keys of `meta.toml` and the strapdown against truth, one file each. One
//! test binary, each file a module of it, so that the suite links once.
//! (`no_alloc.rs` stays a binary of its own: it counts the allocations of
//! its whole process.)

mod common;

// Needs the fuzz entry points; the workspace test run enables `fuzzing`
// through the `tests` crate, `cargo test -p nav-runtime --features fuzzing`
// alone.
#[cfg(feature = "fuzzing")]
mod fuzz_harness;
mod log_errors;
mod log_fuzz;
mod log_imported_files;
mod log_mapping;
mod log_roundtrip;
mod meta_dvl_estimate;
mod strapdown_truth;
