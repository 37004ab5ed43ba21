//! The back end: Rust tokens from the declaration and its derived graphs.
//! `emit` writes the model's types and trait impls, `emit_tests` the
//! generated finite-difference and covariance tests.

pub mod emit;
pub mod emit_tests;
