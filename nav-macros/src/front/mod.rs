//! The front end: the declaration as written (syn tokens) becomes checked,
//! scalarized graphs. `parse` (grammar, including compositions) -> `check`
//! (names, sections, errors collected in `ctxt`) -> `lower` (shapes, the
//! scalar graph of the symbolic core); `compose` assembles blocks into one
//! declaration before the same pipeline runs on it.

pub mod check;
pub mod compose;
pub mod ctxt;
pub mod lower;
pub mod names;
pub mod observability;
pub mod parse;
