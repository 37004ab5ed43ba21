//! `nav-runtime`: the engine that runs models declared with [`model!`].
//!
//! Data flows one way: sensor events -> [`scheduler`] -> [`ekf`] -> estimates.
//! The model traits ([`model`]) are the only contract between generated code and
//! this crate; the EKF core and the generated code build without `std` (libm).
#![cfg_attr(not(feature = "std"), no_std)]

pub use nav_macros::model;
pub use nalgebra;

pub mod math;
pub mod model;
