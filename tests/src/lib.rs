//! Workspace-level integration tests live in `tests/tests/`.
//!
//! The README and the chapters of `docs/` that hold Rust examples are included below as
//! documentation of empty modules, so every example in them is compiled and run
//! as a doctest of this crate (a crate that is neither `nav-blocks` nor
//! `models`, as a user's crate would be).
#![warn(missing_docs)]

/// `docs/guide/declaring-a-model.md`.
// The chapters are GitHub-flavoured Markdown, not rustdoc-formatted docs.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../docs/guide/declaring-a-model.md")]
pub mod guide_declaring_a_model {}

/// `docs/guide/building-a-vehicle.md`.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../docs/guide/building-a-vehicle.md")]
pub mod guide_building_a_vehicle {}

/// `docs/pipeline.md`.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../docs/pipeline.md")]
pub mod pipeline {}

/// `docs/model-replay.md`.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../docs/model-replay.md")]
pub mod model_replay {}

/// `docs/language.md`.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../docs/language.md")]
pub mod language {}

/// `README.md`.
#[allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#[doc = include_str!("../../README.md")]
pub mod readme {}
