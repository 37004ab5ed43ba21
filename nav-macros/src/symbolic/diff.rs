//! Symbolic differentiation on the DAG, memoized per (node, variable) so shared
//! subexpressions are differentiated once and derivatives share nodes too.

use std::collections::HashMap;

use super::expr::{Func, Graph, Id, Node, Sym};

/// Differentiator with a memo table that lives as long as the graph is extended.
#[derive(Default)]
pub struct Diff {
    memo: HashMap<(Id, Sym), Id>,
}

impl Diff {
    pub fn new() -> Self {
        Diff::default()
    }

    /// `d id / d var`.
    pub fn diff(&mut self, g: &mut Graph, id: Id, var: Sym) -> Id {
        if let Some(&d) = self.memo.get(&(id, var)) {
            return d;
        }
        let node = g.node(id);
        let d = match node {
            Node::Const(_) => Graph::ZERO,
            Node::Sym(s) => {
                if s == var {
                    Graph::ONE
                } else {
                    Graph::ZERO
                }
            }
            Node::Add(a, b) => {
                let (da, db) = (self.diff(g, a, var), self.diff(g, b, var));
                g.add(da, db)
            }
            Node::Sub(a, b) => {
                let (da, db) = (self.diff(g, a, var), self.diff(g, b, var));
                g.sub(da, db)
            }
            Node::Mul(a, b) => {
                let (da, db) = (self.diff(g, a, var), self.diff(g, b, var));
                let l = g.mul(da, b);
                let r = g.mul(a, db);
                g.add(l, r)
            }
            Node::Div(a, b) => {
                // d(a/b) = (da - (a/b) db) / b, reusing the quotient node.
                let (da, db) = (self.diff(g, a, var), self.diff(g, b, var));
                let q = g.mul(id, db);
                let num = g.sub(da, q);
                g.div(num, b)
            }
            Node::Neg(a) => {
                let da = self.diff(g, a, var);
                g.neg(da)
            }
            Node::Call(f, a) => {
                let da = self.diff(g, a, var);
                if g.is_zero(da) {
                    Graph::ZERO
                } else {
                    let outer = self.outer(g, f, a, id);
                    g.mul(outer, da)
                }
            }
            Node::Atan2(y, x) => {
                // d atan2(y, x) = (x dy - y dx) / (x^2 + y^2)
                let (dy, dx) = (self.diff(g, y, var), self.diff(g, x, var));
                let l = g.mul(x, dy);
                let r = g.mul(y, dx);
                let num = g.sub(l, r);
                if g.is_zero(num) {
                    Graph::ZERO
                } else {
                    let xx = g.mul(x, x);
                    let yy = g.mul(y, y);
                    let den = g.add(xx, yy);
                    g.div(num, den)
                }
            }
            Node::Min(a, b) | Node::Max(a, b) => {
                // One-sided: the derivative of the selected argument, of the
                // first one at a tie (`a == b`):
                // d min(a, b) = da + step(a - b) (db - da),
                // d max(a, b) = da + step(b - a) (db - da).
                let (da, db) = (self.diff(g, a, var), self.diff(g, b, var));
                let change = g.sub(db, da);
                if g.is_zero(change) {
                    da
                } else {
                    let gap = match g.node(id) {
                        Node::Min(..) => g.sub(a, b),
                        _ => g.sub(b, a),
                    };
                    let step = g.call(Func::Step, gap);
                    let term = g.mul(step, change);
                    g.add(da, term)
                }
            }
            Node::Powi(a, n) => {
                let da = self.diff(g, a, var);
                if g.is_zero(da) {
                    Graph::ZERO
                } else {
                    let c = g.constant(n as f64);
                    let p = g.powi(a, n - 1);
                    let cp = g.mul(c, p);
                    g.mul(cp, da)
                }
            }
        };
        self.memo.insert((id, var), d);
        d
    }

    /// `f'(a)` for `node = f(a)`, reusing `node` where the derivative contains it.
    fn outer(&mut self, g: &mut Graph, f: Func, a: Id, node: Id) -> Id {
        match f {
            Func::Sin => g.call(Func::Cos, a),
            Func::Cos => {
                let s = g.call(Func::Sin, a);
                g.neg(s)
            }
            Func::Tan => {
                // 1 + tan^2
                let t2 = g.mul(node, node);
                g.add(Graph::ONE, t2)
            }
            Func::Asin | Func::Acos => {
                let aa = g.mul(a, a);
                let r = g.sub(Graph::ONE, aa);
                let s = g.call(Func::Sqrt, r);
                let inv = g.div(Graph::ONE, s);
                if f == Func::Asin {
                    inv
                } else {
                    g.neg(inv)
                }
            }
            Func::Atan => {
                let aa = g.mul(a, a);
                let den = g.add(Graph::ONE, aa);
                g.div(Graph::ONE, den)
            }
            Func::Sqrt => {
                let half = g.constant(0.5);
                g.div(half, node)
            }
            Func::Exp => node,
            Func::Ln => g.div(Graph::ONE, a),
            // One-sided derivatives: 0 at the kink of `abs` (sign(0) = 0) and
            // at the jump of `sign` and `step`.
            Func::Abs => g.call(Func::Sign, a),
            Func::Sign | Func::Step => Graph::ZERO,
            // d/ds cos(sqrt(s)/2) = -HalfSinc(s) / 4.
            Func::HalfCos => {
                let k = g.constant(-0.25);
                let sinc = g.call(Func::HalfSinc, a);
                g.mul(k, sinc)
            }
            Func::HalfSinc => g.call(Func::HalfSincSlope, a),
            // -(HalfSinc + 24 HalfSincSlope) / (16 s): only a second derivative
            // of the exponential map reaches it (first-order Jacobians never
            // do); ill-conditioned near s = 0.
            Func::HalfSincSlope => {
                let sinc = g.call(Func::HalfSinc, a);
                let c24 = g.constant(24.0);
                let t = g.mul(c24, node);
                let num = g.add(sinc, t);
                let c16 = g.constant(-1.0 / 16.0);
                let num = g.mul(c16, num);
                g.div(num, a)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// (name, f, f') over x, checked numerically at several points.
    #[allow(clippy::type_complexity)]
    const RULES: &[(&str, fn(&mut Graph, Id) -> Id, fn(f64) -> f64)] = &[
        ("x*x", |g, x| g.mul(x, x), |x| 2.0 * x),
        ("1/x", |g, x| g.div(Graph::ONE, x), |x| -1.0 / (x * x)),
        ("-x", |g, x| g.neg(x), |_| -1.0),
        (
            "x-3",
            |g, x| {
                let c = g.constant(3.0);
                g.sub(x, c)
            },
            |_| 1.0,
        ),
        ("sin", |g, x| g.call(Func::Sin, x), f64::cos),
        ("cos", |g, x| g.call(Func::Cos, x), |x| -x.sin()),
        (
            "tan",
            |g, x| g.call(Func::Tan, x),
            |x| 1.0 / (x.cos() * x.cos()),
        ),
        (
            "asin",
            |g, x| g.call(Func::Asin, x),
            |x| 1.0 / (1.0 - x * x).sqrt(),
        ),
        (
            "acos",
            |g, x| g.call(Func::Acos, x),
            |x| -1.0 / (1.0 - x * x).sqrt(),
        ),
        (
            "atan",
            |g, x| g.call(Func::Atan, x),
            |x| 1.0 / (1.0 + x * x),
        ),
        ("sqrt", |g, x| g.call(Func::Sqrt, x), |x| 0.5 / x.sqrt()),
        ("exp", |g, x| g.call(Func::Exp, x), f64::exp),
        ("ln", |g, x| g.call(Func::Ln, x), |x| 1.0 / x),
        ("abs", |g, x| g.call(Func::Abs, x), f64::signum),
        ("sign", |g, x| g.call(Func::Sign, x), |_| 0.0),
        (
            "half_cos",
            |g, x| g.call(Func::HalfCos, x),
            |x: f64| -(0.5 * x.sqrt()).sin() / (4.0 * x.sqrt()),
        ),
        (
            "half_sinc",
            |g, x| g.call(Func::HalfSinc, x),
            |x: f64| {
                let r = x.sqrt();
                ((0.5 * r).cos() / 4.0 - (0.5 * r).sin() / (2.0 * r)) / x
            },
        ),
        ("powi3", |g, x| g.powi(x, 3), |x| 3.0 * x * x),
        ("powi-2", |g, x| g.powi(x, -2), |x| -2.0 / (x * x * x)),
        (
            "atan2(x,2)",
            |g, x| {
                let c = g.constant(2.0);
                g.atan2(x, c)
            },
            |x| 2.0 / (4.0 + x * x),
        ),
        (
            "atan2(2,x)",
            |g, x| {
                let c = g.constant(2.0);
                g.atan2(c, x)
            },
            |x| -2.0 / (4.0 + x * x),
        ),
    ];

    #[test]
    fn derivative_rules() {
        for &(name, f, df) in RULES {
            let mut g = Graph::new();
            let x = g.sym(Sym::State(0));
            let e = f(&mut g, x);
            let d = Diff::new().diff(&mut g, e, Sym::State(0));
            // 0.5 is the tie of the `min`/`max` rules (one-sided derivatives).
            for &v in &[0.3, 0.7, 0.45, 0.55, 0.5] {
                let got = g.eval(d, &|_| v);
                let want = df(v);
                assert!(
                    (got - want).abs() <= 1e-12 * (1.0 + want.abs()),
                    "{name} at {v}: {got} vs {want}"
                );
            }
        }
    }

    /// The half-angle factors of the exponential map: limits at 0, the series
    /// and the quotient agree where they switch, and the slope of the slope
    /// against a central difference.
    #[test]
    fn exponential_map_factors() {
        let (c, s, d) = (Func::HalfCos, Func::HalfSinc, Func::HalfSincSlope);
        assert_eq!(c.apply(0.0), 1.0);
        assert_eq!(s.apply(0.0), 0.5);
        assert_eq!(d.apply(0.0), -1.0 / 48.0);
        let at = crate::symbolic::expr::HALF_SINC_SERIES_BELOW;
        for f in [s, d] {
            let (below, above) = (f.apply(at * (1.0 - 1e-12)), f.apply(at));
            assert!((below - above).abs() < 1e-13, "{f:?}: {below} vs {above}");
        }
        for x in [0.3f64, 1.2, 4.0] {
            // S(s) at theta = sqrt(s): sin(theta/2)/theta.
            let r: f64 = x.sqrt();
            assert!((s.apply(x) - (0.5 * r).sin() / r).abs() < 1e-15);
            let mut g = Graph::new();
            let v = g.sym(Sym::State(0));
            let e = g.call(d, v);
            let de = Diff::new().diff(&mut g, e, Sym::State(0));
            let got = g.eval(de, &|_| x);
            let h = 1e-5;
            let want = (d.apply(x + h) - d.apply(x - h)) / (2.0 * h);
            assert!((got - want).abs() < 1e-8, "at {x}: {got} vs {want}");
        }
    }

    #[test]
    fn independent_variable_gives_structural_zero() {
        let mut g = Graph::new();
        let x = g.sym(Sym::State(0));
        let y = g.sym(Sym::State(1));
        let s = g.call(Func::Sin, x);
        let e = g.mul(s, x);
        let mut d = Diff::new();
        assert_eq!(d.diff(&mut g, e, Sym::State(1)), Graph::ZERO);
        let e2 = g.add(e, y);
        assert_eq!(d.diff(&mut g, e2, Sym::State(1)), Graph::ONE);
    }
}

/// Property test: random expression trees over every operation, differentiated
/// symbolically and evaluated by the DAG interpreter, against forward-mode dual
/// numbers evaluated on the tree directly.
#[cfg(test)]
mod proptests {
    use super::*;
    use proptest::prelude::*;

    /// A tree whose every node is defined for all real inputs: partial
    /// functions are applied to arguments kept in their domain.
    #[derive(Clone, Debug)]
    enum T {
        Var(u32),
        Const(f64),
        Add(Box<T>, Box<T>),
        Sub(Box<T>, Box<T>),
        Mul(Box<T>, Box<T>),
        /// `a / (1 + b^2)`
        Div(Box<T>, Box<T>),
        Neg(Box<T>),
        Sin(Box<T>),
        Cos(Box<T>),
        /// `tan(sin(a))`
        Tan(Box<T>),
        /// `asin(sin(a) * 0.5)`
        Asin(Box<T>),
        /// `acos(sin(a) * 0.5)`
        Acos(Box<T>),
        Atan(Box<T>),
        /// `sqrt(1 + a^2)`
        Sqrt(Box<T>),
        /// `exp(sin(a))`
        Exp(Box<T>),
        /// `ln(1 + a^2)`
        Ln(Box<T>),
        /// `abs(2 + sin(a))` (kept away from the kink)
        Abs(Box<T>),
        /// `atan2(a, 2 + cos(b))`
        Atan2(Box<T>, Box<T>),
        /// `powi(1 + a^2, n)`
        Powi(Box<T>, i32),
        /// `sign(a) * a` (a piecewise-linear function; `sign` alone has derivative 0)
        Sign(Box<T>),
        Min(Box<T>, Box<T>),
        Max(Box<T>, Box<T>),
    }

    fn tree() -> impl Strategy<Value = T> {
        let leaf = prop_oneof![
            (0u32..3).prop_map(T::Var),
            (-2.0f64..2.0).prop_map(T::Const)
        ];
        leaf.prop_recursive(5, 48, 2, |inner| {
            let b = |t: T| Box::new(t);
            prop_oneof![
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Add(b(x), b(y))),
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Sub(b(x), b(y))),
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Mul(b(x), b(y))),
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Div(b(x), b(y))),
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Atan2(b(x), b(y))),
                (inner.clone(), -3i32..4).prop_map(move |(x, n)| T::Powi(b(x), n)),
                inner.clone().prop_map(move |x| T::Neg(b(x))),
                inner.clone().prop_map(move |x| T::Sin(b(x))),
                inner.clone().prop_map(move |x| T::Cos(b(x))),
                inner.clone().prop_map(move |x| T::Tan(b(x))),
                inner.clone().prop_map(move |x| T::Asin(b(x))),
                inner.clone().prop_map(move |x| T::Acos(b(x))),
                inner.clone().prop_map(move |x| T::Atan(b(x))),
                inner.clone().prop_map(move |x| T::Sqrt(b(x))),
                inner.clone().prop_map(move |x| T::Exp(b(x))),
                inner.clone().prop_map(move |x| T::Ln(b(x))),
                inner.clone().prop_map(move |x| T::Abs(b(x))),
                inner.clone().prop_map(move |x| T::Sign(b(x))),
                (inner.clone(), inner.clone()).prop_map(move |(x, y)| T::Min(b(x), b(y))),
                (inner.clone(), inner).prop_map(move |(x, y)| T::Max(b(x), b(y))),
            ]
        })
    }

    fn to_graph(t: &T, g: &mut Graph) -> Id {
        let one = Graph::ONE;
        let two = g.constant(2.0);
        let half = g.constant(0.5);
        match t {
            T::Var(k) => g.sym(Sym::State(*k)),
            T::Const(c) => g.constant(*c),
            T::Add(a, b) | T::Sub(a, b) | T::Mul(a, b) | T::Div(a, b) | T::Atan2(a, b) => {
                let (x, y) = (to_graph(a, g), to_graph(b, g));
                match t {
                    T::Add(..) => g.add(x, y),
                    T::Sub(..) => g.sub(x, y),
                    T::Mul(..) => g.mul(x, y),
                    T::Div(..) => {
                        let yy = g.mul(y, y);
                        let den = g.add(one, yy);
                        g.div(x, den)
                    }
                    _ => {
                        let c = g.call(Func::Cos, y);
                        let den = g.add(two, c);
                        g.atan2(x, den)
                    }
                }
            }
            T::Sign(a) => {
                let x = to_graph(a, g);
                let s = g.call(Func::Sign, x);
                g.mul(s, x)
            }
            T::Min(a, b) | T::Max(a, b) => {
                let (x, y) = (to_graph(a, g), to_graph(b, g));
                if matches!(t, T::Min(..)) {
                    g.min(x, y)
                } else {
                    g.max(x, y)
                }
            }
            T::Powi(a, n) => {
                let x = to_graph(a, g);
                let xx = g.mul(x, x);
                let base = g.add(one, xx);
                g.powi(base, *n)
            }
            T::Neg(a) => {
                let x = to_graph(a, g);
                g.neg(x)
            }
            T::Sin(a) | T::Cos(a) | T::Atan(a) => {
                let x = to_graph(a, g);
                let f = match t {
                    T::Sin(_) => Func::Sin,
                    T::Cos(_) => Func::Cos,
                    _ => Func::Atan,
                };
                g.call(f, x)
            }
            T::Tan(a) | T::Exp(a) | T::Abs(a) => {
                let x = to_graph(a, g);
                let s = g.call(Func::Sin, x);
                match t {
                    T::Tan(_) => g.call(Func::Tan, s),
                    T::Exp(_) => g.call(Func::Exp, s),
                    _ => {
                        let v = g.add(two, s);
                        g.call(Func::Abs, v)
                    }
                }
            }
            T::Asin(a) | T::Acos(a) => {
                let x = to_graph(a, g);
                let s = g.call(Func::Sin, x);
                let h = g.mul(s, half);
                g.call(
                    if matches!(t, T::Asin(_)) {
                        Func::Asin
                    } else {
                        Func::Acos
                    },
                    h,
                )
            }
            T::Sqrt(a) | T::Ln(a) => {
                let x = to_graph(a, g);
                let xx = g.mul(x, x);
                let v = g.add(one, xx);
                g.call(
                    if matches!(t, T::Sqrt(_)) {
                        Func::Sqrt
                    } else {
                        Func::Ln
                    },
                    v,
                )
            }
        }
    }

    /// Forward-mode dual number `v + d eps`.
    #[derive(Clone, Copy, Debug)]
    struct Dual {
        v: f64,
        d: f64,
    }

    impl Dual {
        fn c(v: f64) -> Dual {
            Dual { v, d: 0.0 }
        }
        fn add(self, o: Dual) -> Dual {
            Dual {
                v: self.v + o.v,
                d: self.d + o.d,
            }
        }
        fn sub(self, o: Dual) -> Dual {
            Dual {
                v: self.v - o.v,
                d: self.d - o.d,
            }
        }
        fn mul(self, o: Dual) -> Dual {
            Dual {
                v: self.v * o.v,
                d: self.d * o.v + self.v * o.d,
            }
        }
        fn div(self, o: Dual) -> Dual {
            Dual {
                v: self.v / o.v,
                d: (self.d * o.v - self.v * o.d) / (o.v * o.v),
            }
        }
        fn chain(self, v: f64, dv: f64) -> Dual {
            Dual { v, d: dv * self.d }
        }
        fn sin(self) -> Dual {
            self.chain(self.v.sin(), self.v.cos())
        }
        fn one_plus_sq(self) -> Dual {
            Dual::c(1.0).add(self.mul(self))
        }
    }

    fn to_dual(t: &T, xs: &[f64; 3], var: u32) -> Dual {
        let ev = |a: &T| to_dual(a, xs, var);
        match t {
            T::Var(k) => Dual {
                v: xs[*k as usize],
                d: if *k == var { 1.0 } else { 0.0 },
            },
            T::Const(c) => Dual::c(*c),
            T::Add(a, b) => ev(a).add(ev(b)),
            T::Sub(a, b) => ev(a).sub(ev(b)),
            T::Mul(a, b) => ev(a).mul(ev(b)),
            T::Div(a, b) => ev(a).div(ev(b).one_plus_sq()),
            T::Neg(a) => Dual::c(0.0).sub(ev(a)),
            T::Sin(a) => ev(a).sin(),
            T::Cos(a) => {
                let x = ev(a);
                x.chain(x.v.cos(), -x.v.sin())
            }
            T::Tan(a) => {
                let s = ev(a).sin();
                let t = s.v.tan();
                s.chain(t, 1.0 + t * t)
            }
            T::Asin(a) | T::Acos(a) => {
                let h = ev(a).sin().mul(Dual::c(0.5));
                let k = 1.0 / (1.0 - h.v * h.v).sqrt();
                if matches!(t, T::Asin(_)) {
                    h.chain(h.v.asin(), k)
                } else {
                    h.chain(h.v.acos(), -k)
                }
            }
            T::Atan(a) => {
                let x = ev(a);
                x.chain(x.v.atan(), 1.0 / (1.0 + x.v * x.v))
            }
            T::Sqrt(a) => {
                let x = ev(a).one_plus_sq();
                x.chain(x.v.sqrt(), 0.5 / x.v.sqrt())
            }
            T::Exp(a) => {
                let s = ev(a).sin();
                s.chain(s.v.exp(), s.v.exp())
            }
            T::Ln(a) => {
                let x = ev(a).one_plus_sq();
                x.chain(x.v.ln(), 1.0 / x.v)
            }
            T::Abs(a) => {
                let x = Dual::c(2.0).add(ev(a).sin());
                x.chain(x.v.abs(), x.v.signum())
            }
            T::Atan2(a, b) => {
                let (y, x) = (ev(a), ev(b));
                let den = Dual::c(2.0).add(x.chain(x.v.cos(), -x.v.sin()));
                let r2 = y.v * y.v + den.v * den.v;
                Dual {
                    v: y.v.atan2(den.v),
                    d: (den.v * y.d - y.v * den.d) / r2,
                }
            }
            T::Sign(a) => {
                let x = ev(a);
                let sign = Func::Sign.apply(x.v);
                Dual::c(sign).mul(x)
            }
            T::Min(a, b) | T::Max(a, b) => {
                let (x, y) = (ev(a), ev(b));
                let first = if matches!(t, T::Min(..)) {
                    x.v <= y.v
                } else {
                    x.v >= y.v
                };
                if first {
                    x
                } else {
                    y
                }
            }
            T::Powi(a, n) => {
                let x = ev(a).one_plus_sq();
                x.chain(x.v.powi(*n), *n as f64 * x.v.powi(n - 1))
            }
        }
    }

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * (1.0 + b.abs())
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(512))]
        #[test]
        fn symbolic_derivatives_match_dual_numbers(t in tree(), xs in [-1.0f64..1.0, -1.0f64..1.0, -1.0f64..1.0]) {
            let mut g = Graph::new();
            let e = to_graph(&t, &mut g);
            let env = |s: Sym| match s {
                Sym::State(k) => xs[k as usize],
                _ => f64::NAN,
            };
            let mut d = Diff::new();
            for var in 0..3 {
                let de = d.diff(&mut g, e, Sym::State(var));
                let want = to_dual(&t, &xs, var);
                prop_assume!(want.v.is_finite() && want.d.is_finite() && want.v.abs() < 1e8 && want.d.abs() < 1e8);
                let (v, dv) = (g.eval(e, &env), g.eval(de, &env));
                prop_assert!(close(v, want.v), "value {} vs {}", v, want.v);
                prop_assert!(close(dv, want.d), "d/dx{}: {} vs {}", var, dv, want.d);
            }
        }
    }

    #[test]
    fn every_function_is_generated() {
        // The tree language covers every scalar function of the graph.
        let covered = [
            Func::Sin,
            Func::Cos,
            Func::Tan,
            Func::Asin,
            Func::Acos,
            Func::Atan,
            Func::Sqrt,
            Func::Exp,
            Func::Ln,
            Func::Abs,
            Func::Sign,
            // In the derivatives of `Min` and `Max`.
            Func::Step,
            // Checked in `derivative_rules` and `exponential_map_factors`.
            Func::HalfCos,
            Func::HalfSinc,
            Func::HalfSincSlope,
        ];
        assert_eq!(covered, Func::ALL);
    }
}
