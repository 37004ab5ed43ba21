//! Operation counting: the cost of a generated function is the number of
//! arithmetic nodes (`+ - * /`, negation, function calls) reachable from its
//! outputs, each computed once (shared temporaries count once).

use super::expr::{Graph, Id};

/// Arithmetic operations needed to compute all of `roots` with full sharing.
pub fn count(g: &Graph, roots: &[Id]) -> usize {
    g.reachable(roots)
        .into_iter()
        .filter(|&id| g.node(id).is_op())
        .count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::expr::{Func, Sym};

    #[test]
    fn shared_nodes_count_once() {
        let mut g = Graph::new();
        let x = g.sym(Sym::State(0));
        let y = g.sym(Sym::State(1));
        let s = g.add(x, y); // 1
        let a = g.call(Func::Sin, s); // 2
        let b = g.mul(s, a); // 3
        let c = g.neg(s); // 4
        assert_eq!(count(&g, &[b]), 3);
        assert_eq!(count(&g, &[b, c, a, x]), 4);
        assert_eq!(count(&g, &[x, Graph::ONE]), 0);
    }
}
