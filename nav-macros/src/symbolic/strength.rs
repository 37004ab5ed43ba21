//! Strength reduction of one generated function before it is scheduled: the
//! slow scalar operations of its DAG are replaced by cheaper ones that the
//! compiler may not substitute itself (Rust never reassociates floating point):
//!
//! - `a / b` with a divisor `b` shared by two or more divisions of the function
//!   becomes `a * (1 / b)`: one division per divisor. Derivatives of
//!   `V / (R + h)` divide by the same radius a dozen times (SDINS-25's `F`
//!   had 35 divisions by 8 divisors);
//! - `a / c` with a constant `c` becomes `a * (1 / c)`;
//! - `tan(a)` becomes `sin(a) / cos(a)` when `sin(a)` or `cos(a)` is computed
//!   anyway; `sin` and `cos` of one argument are then one `sin_cos` call (see
//!   [`crate::symbolic::cse`]).
//!
//! Each rewrite changes a value by at most a rounding in the last place (the
//! tests below compare values before and after; every model's generated tests
//! check its Jacobians against finite differences and its covariance algebra
//! against dense products).
//!
//! The function is copied into a graph of its own (only the nodes its outputs
//! reach), so the model's graph, shared by all functions, stays as derived.

use std::collections::{HashMap, HashSet};

use super::expr::{Func, Graph, Id, Node};

/// The outputs `roots` of one function, reduced, in a new graph (same order).
pub fn reduce(source: &Graph, roots: &[Id]) -> (Graph, Vec<Id>) {
    // Pass 1: tangents of arguments whose sine or cosine is computed anyway.
    let trig_arguments: HashSet<Id> = source
        .reachable(roots)
        .into_iter()
        .filter_map(|id| match source.node(id) {
            Node::Call(Func::Sin | Func::Cos, a) => Some(a),
            _ => None,
        })
        .collect();
    let (first, roots) = copy(source, roots, |g, _, node, kids| match node {
        Node::Call(Func::Tan, a) if trig_arguments.contains(&a) => {
            let sin = g.call(Func::Sin, kids[0]);
            let cos = g.call(Func::Cos, kids[0]);
            g.div(sin, cos)
        }
        _ => g.rebuild(node, kids),
    });

    // Pass 2: divisions by constants and by shared divisors.
    let mut divisions: HashMap<Id, u32> = HashMap::new();
    for id in first.reachable(&roots) {
        if let Node::Div(_, b) = first.node(id) {
            *divisions.entry(b).or_default() += 1;
        }
    }
    let (second, roots) = copy(&first, &roots, |g, _, node, kids| match node {
        Node::Div(_, b) => {
            let reciprocal = match first.as_const(b) {
                Some(c) => Some(1.0 / c)
                    .filter(|r| r.is_normal())
                    .map(|r| g.constant(r)),
                None if divisions[&b] >= 2 => Some(g.div(Graph::ONE, kids[1])),
                None => None,
            };
            match reciprocal {
                Some(r) => g.mul(kids[0], r),
                None => g.rebuild(node, kids),
            }
        }
        _ => g.rebuild(node, kids),
    });
    signs_and_scales(&second, &roots)
}

/// Pass 3, the last (its products are built as they are, not normalized):
///
/// - `-(a b)`, the product used only there, becomes `(-c) b` for a constant
///   factor `c` (the negation is free), and `(-a) b` when `a` is a factor
///   of two or more such products (one negation for all: `-(dt R_ij)` over
///   nine `R_ij` is nine products and one negation, not eighteen operations);
/// - `c (a b)` with `c` a power of two, the product used only there, becomes
///   `(c a) b` when `c a` is computed anyway (`2 (x y)` next to `2 x`).
///
/// Both are exact: negation never rounds and scaling by a power of two
/// commutes with rounding (outside the subnormal range).
fn signs_and_scales(source: &Graph, roots: &[Id]) -> (Graph, Vec<Id>) {
    let reach = source.reachable(roots);
    let mut uses = vec![0u32; source.len()];
    for id in roots
        .iter()
        .copied()
        .chain(reach.iter().flat_map(|&id| source.node(id).children()))
    {
        uses[id.0 as usize] += 1;
    }
    let reached: HashSet<Id> = reach.iter().copied().collect();
    // The operands of a product used once, by its only user.
    let single_product = |m: Id| match source.node(m) {
        Node::Mul(a, b) if uses[m.0 as usize] == 1 => Some((a, b)),
        _ => None,
    };
    let mut negated: HashMap<Id, u32> = HashMap::new();
    for &id in &reach {
        if let Some((a, b)) = match source.node(id) {
            Node::Neg(m) => single_product(m),
            _ => None,
        } {
            *negated.entry(a).or_default() += 1;
            if b != a {
                *negated.entry(b).or_default() += 1;
            }
        }
    }
    let product = |x: Id, y: Id| {
        source
            .find(Node::Mul(x, y))
            .or_else(|| source.find(Node::Mul(y, x)))
            .filter(|m| reached.contains(m))
    };
    // New ids of the copied operation nodes (leaves are interned again).
    let mut made: HashMap<Id, Id> = HashMap::new();
    let new = |g: &mut Graph, made: &HashMap<Id, Id>, old: Id| match source.node(old) {
        Node::Const(bits) => g.constant(f64::from_bits(bits)),
        Node::Sym(s) => g.sym(s),
        _ => made[&old],
    };
    copy(source, roots, |g, id, node, kids| {
        let out = match node {
            Node::Neg(m) if single_product(m).is_some() => {
                let (a, b) = single_product(m).expect("checked");
                let count = |f: Id| negated.get(&f).copied().unwrap_or(0);
                if let Some(c) = source.as_const(a) {
                    let (c, b) = (g.constant(-c), new(g, &made, b));
                    g.product_as_is(c, b)
                } else if let Some(c) = source.as_const(b) {
                    let (c, a) = (g.constant(-c), new(g, &made, a));
                    g.product_as_is(c, a)
                } else if count(a).max(count(b)) >= 2 {
                    let (f, other) = if count(a) >= count(b) { (a, b) } else { (b, a) };
                    let f = new(g, &made, f);
                    let negated = g.neg(f);
                    let other = new(g, &made, other);
                    g.product_as_is(negated, other)
                } else {
                    g.rebuild(node, kids)
                }
            }
            Node::Mul(x, y) => {
                let scaled = [(x, y), (y, x)].into_iter().find_map(|(c, m)| {
                    source.power_of_two(c)?;
                    let (a, b) = single_product(m)?;
                    [(a, b), (b, a)]
                        .into_iter()
                        .find(|&(a, _)| product(c, a).is_some())
                        .map(|(a, b)| (c, a, b))
                });
                match scaled {
                    // `c a` may not be copied yet: built from its operands
                    // (the same node as its own copy will be).
                    Some((c, a, b)) => {
                        let (c, a, b) = (new(g, &made, c), new(g, &made, a), new(g, &made, b));
                        let ca = g.mul(c, a);
                        g.mul(ca, b)
                    }
                    None => g.rebuild(node, kids),
                }
            }
            _ => g.rebuild(node, kids),
        };
        made.insert(id, out);
        out
    })
}

/// Copies the nodes reachable from `roots` into a new graph, children first;
/// `build(graph, node, new operands)` makes each operation node there.
fn copy(
    source: &Graph,
    roots: &[Id],
    mut build: impl FnMut(&mut Graph, Id, Node, &[Id]) -> Id,
) -> (Graph, Vec<Id>) {
    let mut g = Graph::new();
    let mut new_id: Vec<Option<Id>> = vec![None; source.len()];
    for &root in roots {
        let mut stack = vec![(root, false)];
        while let Some((id, expanded)) = stack.pop() {
            if new_id[id.0 as usize].is_some() {
                continue;
            }
            let node = source.node(id);
            let id_in = |new_id: &[Option<Id>], c: Id| new_id[c.0 as usize];
            let made = match node {
                Node::Const(bits) => g.constant(f64::from_bits(bits)),
                Node::Sym(s) => g.sym(s),
                _ if expanded => {
                    let kids: Vec<Id> = node
                        .children()
                        .map(|c| id_in(&new_id, c).expect("children are copied first"))
                        .collect();
                    build(&mut g, id, node, &kids)
                }
                _ => {
                    stack.push((id, true));
                    stack.extend(
                        node.children()
                            .filter(|&c| id_in(&new_id, c).is_none())
                            .map(|c| (c, false)),
                    );
                    continue;
                }
            };
            new_id[id.0 as usize] = Some(made);
        }
    }
    let roots = roots
        .iter()
        .map(|r| new_id[r.0 as usize].expect("roots are copied"))
        .collect();
    (g, roots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::symbolic::expr::Sym;

    fn symbols(g: &mut Graph) -> (Id, Id, Id) {
        (
            g.sym(Sym::State(0)),
            g.sym(Sym::State(1)),
            g.sym(Sym::State(2)),
        )
    }

    fn count(g: &Graph, roots: &[Id], pred: impl Fn(Node) -> bool) -> usize {
        g.reachable(roots)
            .into_iter()
            .filter(|&id| pred(g.node(id)))
            .count()
    }

    fn env(s: Sym) -> f64 {
        match s {
            Sym::State(k) => [0.7, -1.3, 2.9][k as usize],
            Sym::Dt => 0.01,
            _ => 0.0,
        }
    }

    /// Values before and after are the same bits (an exact rewrite).
    fn assert_same_bits(before: (&Graph, &[Id]), after: (&Graph, &[Id])) {
        for (&a, &b) in before.1.iter().zip(after.1) {
            assert_eq!(
                before.0.eval(a, &env).to_bits(),
                after.0.eval(b, &env).to_bits()
            );
        }
    }

    /// Values before and after agree to rounding.
    fn assert_same_values(before: (&Graph, &[Id]), after: (&Graph, &[Id])) {
        for (&a, &b) in before.1.iter().zip(after.1) {
            let (va, vb) = (before.0.eval(a, &env), after.0.eval(b, &env));
            assert!(
                (va - vb).abs() <= 4.0 * f64::EPSILON * va.abs(),
                "{va} vs {vb}"
            );
        }
    }

    #[test]
    fn shared_divisors_are_inverted_once() {
        let mut g = Graph::new();
        let (x, y, z) = symbols(&mut g);
        let r = g.add(y, z);
        let a = g.div(x, r);
        let b = g.div(y, r);
        let r2 = g.mul(r, r);
        let c = g.div(z, r2); // a divisor used once stays a division
        let roots = [a, b, c];
        let (h, reduced) = reduce(&g, &roots);
        let is_div = |n: Node| matches!(n, Node::Div(..));
        assert_eq!(count(&g, &roots, is_div), 3);
        assert_eq!(count(&h, &reduced, is_div), 2, "1 / r and z / r^2");
        assert_same_values((&g, &roots), (&h, &reduced));
    }

    #[test]
    fn constant_divisors_become_multiplications() {
        let mut g = Graph::new();
        let (x, ..) = symbols(&mut g);
        let c = g.constant(6378137.0);
        let a = g.div(x, c);
        let zero = g.constant(0.0);
        let by_zero = g.div(x, zero); // 1 / 0 is not finite: kept
        let roots = [a, by_zero];
        let (h, reduced) = reduce(&g, &roots);
        assert!(matches!(h.node(reduced[0]), Node::Mul(..)));
        assert!(matches!(h.node(reduced[1]), Node::Div(..)));
        assert_same_values((&g, &roots[..1]), (&h, &reduced[..1]));
    }

    #[test]
    fn tangent_shares_sine_and_cosine() {
        let mut g = Graph::new();
        let (x, y, _) = symbols(&mut g);
        let s = g.call(Func::Sin, x);
        let t = g.call(Func::Tan, x);
        let ty = g.call(Func::Tan, y); // no sin(y) or cos(y): stays a call
        let roots = [s, t, ty];
        let (h, reduced) = reduce(&g, &roots);
        let is_tan = |n: Node| matches!(n, Node::Call(Func::Tan, _));
        assert_eq!(count(&h, &reduced, is_tan), 1);
        assert!(matches!(h.node(reduced[1]), Node::Div(..)));
        assert_same_values((&g, &roots), (&h, &reduced));
    }

    /// Operations reachable from `roots`.
    fn ops(g: &Graph, roots: &[Id]) -> usize {
        crate::symbolic::ops::count(g, roots)
    }

    #[test]
    fn negated_products_share_one_negation() {
        let mut g = Graph::new();
        let (x, y, z) = symbols(&mut g);
        let dt = g.sym(Sym::Dt);
        let products = [x, y, z].map(|v| {
            let m = g.mul(dt, v);
            g.neg(m)
        });
        // -(x y): no factor shared with another negated product, kept.
        let xy = g.mul(x, y);
        let alone = g.neg(xy);
        // -(2 z): the constant takes the sign.
        let two = g.constant(2.0);
        let two_z = g.mul(two, z);
        let constant = g.neg(two_z);
        let roots = [products[0], products[1], products[2], alone, constant];
        let (h, reduced) = reduce(&g, &roots);
        assert_eq!(ops(&g, &roots), 10);
        // 3 products and -dt, -(x y) as before, (-2) z.
        assert_eq!(ops(&h, &reduced), 7);
        let is_neg = |n: Node| matches!(n, Node::Neg(_));
        assert_eq!(count(&h, &reduced, is_neg), 2, "-dt and -(x y)");
        assert_same_values((&g, &roots), (&h, &reduced));
        assert_same_bits((&g, &roots), (&h, &reduced));
    }

    #[test]
    fn a_doubled_factor_computed_anyway_is_reused() {
        let mut g = Graph::new();
        let (x, y, z) = symbols(&mut g);
        let two = g.constant(2.0);
        let two_x = g.mul(two, x);
        let a = g.mul(two_x, z); // 2x is needed anyway
        let xy = g.mul(x, y);
        let b = g.mul(two, xy); // 2 (x y) becomes (2 x) y
        let yz = g.mul(y, z);
        let c = g.mul(two, yz); // neither 2 y nor 2 z is computed: kept
        let roots = [a, b, c];
        let (h, reduced) = reduce(&g, &roots);
        assert_eq!(ops(&g, &roots), 6);
        assert_eq!(ops(&h, &reduced), 5);
        assert_same_bits((&g, &roots), (&h, &reduced));
    }

    #[test]
    fn only_reachable_nodes_are_copied() {
        let mut g = Graph::new();
        let (x, y, z) = symbols(&mut g);
        let _unused = g.mul(y, z);
        let a = g.add(x, y);
        let (h, reduced) = reduce(&g, &[a]);
        // 0, 1, x, y and x + y.
        assert_eq!(h.len(), 5);
        assert_same_values((&g, &[a]), (&h, &reduced));
    }
}
