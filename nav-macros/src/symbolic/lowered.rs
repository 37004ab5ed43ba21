//! The input of the symbolic core: a model as scalar nodes of one graph, as
//! the front end lowers it.

use super::expr::{Graph, Id};

/// Continuous (`d/dt x = ..`) or discrete (`x = ..` from the previous values).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProcessKind {
    Continuous,
    Discrete,
}

/// The scalarized model.
pub struct Lowered {
    pub graph: Graph,
    pub kind: ProcessKind,
    /// `f(x, u, p, w)` (continuous) or `f(x, u, p, dt, w)` (discrete), per state scalar.
    pub f: Vec<Id>,
    /// Each sensor's `h`, in declaration order.
    pub sensors: Vec<Vec<Id>>,
}
