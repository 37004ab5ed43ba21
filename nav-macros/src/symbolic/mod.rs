//! The symbolic core, free of syn: a hash-consed scalar graph (`expr`),
//! differentiation (`diff`), the derived outputs of every generated function
//! (`derive`), strength reduction (`strength`), scheduling into temporaries
//! (`cse`) and op counts (`ops`). Its input is [`Lowered`], built by the front
//! end; its output, [`derive::Derived`], is read by the back end.

pub mod cse;
pub mod derive;
pub mod diff;
pub mod expr;
mod lowered;
pub mod ops;
pub mod rotation;
pub mod strength;

pub use expr::{Func, Graph, Id, Node, Sym};
pub use lowered::{Lowered, ProcessKind};
