//! Scheduling: one pass over all outputs of a generated function decides which
//! nodes become shared temporaries (`let _tN = ..;`, nodes used more than once)
//! and in which order they are computed (children first). Single-use nodes are
//! written inline in their user. The order depends only on the outputs' order,
//! never on hash-map iteration, so generated code is deterministic.
//!
//! `sin(a)` and `cos(a)` of one argument both needed become one `sin_cos` call
//! (one argument reduction instead of two): both are temporaries, defined
//! together where the first of them is due.

use super::expr::{Func, Graph, Id, Node};
use super::ops;

/// The temporaries of one generated function.
pub struct Schedule {
    /// Nodes bound to temporaries, in evaluation order; `_tK` is `temps[K]`.
    pub temps: Vec<Id>,
    /// For each node of the graph, its temporary number if it has one.
    pub temp_of: Vec<Option<usize>>,
    /// `(sin(a), cos(a))` pairs computed by one `sin_cos` call.
    pub sin_cos: Vec<(Id, Id)>,
    /// Arithmetic operations of the function.
    pub ops: usize,
}

/// Schedules the computation of `roots`.
pub fn schedule(g: &Graph, roots: &[Id]) -> Schedule {
    let n = g.len();
    let mut uses = vec![0u32; n];
    let mut visited = vec![false; n];
    let mut post: Vec<Id> = Vec::new();
    for &root in roots {
        uses[root.0 as usize] += 1;
        // Iterative post-order DFS; a node is expanded once, when first popped.
        let mut stack: Vec<(Id, bool)> = vec![(root, false)];
        while let Some((id, expanded)) = stack.pop() {
            if expanded {
                post.push(id);
                continue;
            }
            if std::mem::replace(&mut visited[id.0 as usize], true) {
                continue;
            }
            stack.push((id, true));
            let kids: Vec<Id> = g.node(id).children().collect();
            for &c in kids.iter().rev() {
                uses[c.0 as usize] += 1;
                if !visited[c.0 as usize] {
                    stack.push((c, false));
                }
            }
        }
    }
    let mut sin_cos = Vec::new();
    for &id in &post {
        if let Node::Call(Func::Sin, a) = g.node(id) {
            if let Some(cos) = g
                .find(Node::Call(Func::Cos, a))
                .filter(|c| visited[c.0 as usize])
            {
                sin_cos.push((id, cos));
                // Defined by the pair's `let`, so never written inline.
                uses[id.0 as usize] += 1;
                uses[cos.0 as usize] += 1;
            }
        }
    }
    let mut temp_of = vec![None; n];
    let mut temps = Vec::new();
    for id in post {
        if g.node(id).is_op() && uses[id.0 as usize] > 1 {
            temp_of[id.0 as usize] = Some(temps.len());
            temps.push(id);
        }
    }
    Schedule {
        temps,
        temp_of,
        sin_cos,
        ops: ops::count(g, roots),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::expr::Sym;

    #[test]
    fn shared_subexpressions_become_temporaries_in_order() {
        let mut g = Graph::new();
        let x = g.sym(Sym::State(0));
        let y = g.sym(Sym::State(1));
        let s = g.add(x, y);
        let sin = g.call(Func::Sin, s);
        let cos = g.call(Func::Cos, s);
        let out1 = g.mul(sin, cos);
        let out2 = g.mul(sin, x);
        let sch = schedule(&g, &[out1, out2]);
        assert_eq!(sch.temps, vec![s, sin, cos], "sin and cos of s in one call");
        assert_eq!(sch.sin_cos, vec![(sin, cos)]);
        assert_eq!(sch.ops, 5);
        assert_eq!(sch.temp_of[x.0 as usize], None);
        // A root used twice is a temporary too.
        let sch = schedule(&g, &[cos, cos]);
        assert_eq!(sch.temps, vec![cos]);
        assert!(sch.sin_cos.is_empty(), "sin(s) is not needed here");
    }
}
