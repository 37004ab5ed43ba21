//! Workspace-level integration tests live in `tests/tests/`. The crate's docs are
//! the README, so its Rust examples are compiled and run as doctests.
// The README is prose for GitHub-flavoured Markdown, not rustdoc-formatted docs.
#![allow(clippy::doc_lazy_continuation, clippy::doc_overindented_list_items)]
#![doc = include_str!("../../README.md")]
