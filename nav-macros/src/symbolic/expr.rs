//! The hash-consed scalar DAG. Every value of a model is scalarized into nodes of
//! one [`Graph`]; identical nodes are stored once, so common subexpressions are
//! shared by construction. The constructors simplify as they build: constant
//! folding, `x + 0`, `x * 1`, `x * 0`, `x - x`, `--x`, `0 / x`, `x / 1`, sign
//! normalization, and a canonical operand order for `+` and `*`.

use std::collections::HashMap;

/// Index of a node in its [`Graph`].
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct Id(pub u32);

/// A free symbol: a scalar read from the arguments of a generated function.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Sym {
    /// State scalar `x[k]`.
    State(u32),
    /// Model input scalar.
    Input(u32),
    /// Model parameter scalar.
    Param(u32),
    /// Process-noise sample `w[k]`.
    Noise(u32),
    /// Process-noise intensity `q[k]`.
    NoiseIntensity(u32),
    /// Sensor auxiliary input `(sensor, k)`.
    Aux(u32, u32),
    /// The time step.
    Dt,
    /// Covariance entry `P[(i, j)]`, always with `i <= j`.
    Cov(u32, u32),
}

impl Sym {
    /// The covariance symbol of entry (i, j), read from the upper triangle.
    pub fn cov(i: usize, j: usize) -> Sym {
        let (a, b) = if i <= j { (i, j) } else { (j, i) };
        Sym::Cov(a as u32, b as u32)
    }
}

/// Scalar functions of one argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Func {
    Sin,
    Cos,
    Tan,
    Asin,
    Acos,
    Atan,
    Sqrt,
    Exp,
    Ln,
    Abs,
    /// `sign(x)`: 1 for x > 0, -1 for x < 0, x itself for 0 and NaN.
    Sign,
    /// The unit step `1 if x > 0 else 0` (NaN gives 0): only built by
    /// differentiation (of `min` and `max`), never written by users.
    Step,
    /// `cos(sqrt(s) / 2)` of `s = |v|^2`: the scalar part of the exponential
    /// map (`rotvec_to_quat`), smooth in `s` (no square-root kink at 0).
    HalfCos,
    /// `sin(sqrt(s) / 2) / sqrt(s)` (1/2 at `s = 0`): the vector-part factor
    /// of the exponential map.
    HalfSinc,
    /// `d/ds HalfSinc(s) = (HalfCos(s) - 2 HalfSinc(s)) / (4 s)` (-1/48 at 0;
    /// a series below `s = 1e-3`, where the quotient would cancel).
    HalfSincSlope,
}

impl Func {
    /// All functions, for tables and tests.
    #[cfg(test)]
    pub const ALL: [Func; 15] = [
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
        Func::Step,
        Func::HalfCos,
        Func::HalfSinc,
        Func::HalfSincSlope,
    ];

    /// The name in the surface language and in `nav_runtime::math`.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Asin => "asin",
            Func::Acos => "acos",
            Func::Atan => "atan",
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Abs => "abs",
            Func::Sign => "sign",
            Func::Step => "step",
            Func::HalfCos => "half_cos",
            Func::HalfSinc => "half_sinc",
            Func::HalfSincSlope => "half_sinc_slope",
        }
    }

    /// Numeric value (std; used for constant folding and evaluation).
    pub fn apply(self, x: f64) -> f64 {
        match self {
            Func::Sin => x.sin(),
            Func::Cos => x.cos(),
            Func::Tan => x.tan(),
            Func::Asin => x.asin(),
            Func::Acos => x.acos(),
            Func::Atan => x.atan(),
            Func::Sqrt => x.sqrt(),
            Func::Exp => x.exp(),
            Func::Ln => x.ln(),
            Func::Abs => x.abs(),
            Func::Sign => {
                if x > 0.0 {
                    1.0
                } else if x < 0.0 {
                    -1.0
                } else {
                    x
                }
            }
            Func::Step => {
                if x > 0.0 {
                    1.0
                } else {
                    0.0
                }
            }
            Func::HalfCos => (0.5 * x.sqrt()).cos(),
            Func::HalfSinc => {
                if x < HALF_SINC_SERIES_BELOW {
                    0.5 - x / 48.0 + x * x / 3840.0 - x * x * x / 645_120.0
                } else {
                    let r = x.sqrt();
                    (0.5 * r).sin() / r
                }
            }
            Func::HalfSincSlope => {
                if x < HALF_SINC_SERIES_BELOW {
                    -1.0 / 48.0 + x / 1920.0 - x * x / 215_040.0
                } else {
                    let r = x.sqrt();
                    ((0.5 * r).cos() - 2.0 * (0.5 * r).sin() / r) / (4.0 * x)
                }
            }
        }
    }
}

/// One node of the DAG. Constants are stored by their bit pattern (never -0.0).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Node {
    Const(u64),
    Sym(Sym),
    Add(Id, Id),
    Sub(Id, Id),
    Mul(Id, Id),
    Div(Id, Id),
    Neg(Id),
    Call(Func, Id),
    Atan2(Id, Id),
    Powi(Id, i32),
    /// `min(a, b)`: `a` when `a <= b`, `b` when `b < a`, NaN if either is NaN.
    Min(Id, Id),
    /// `max(a, b)`: `a` when `a >= b`, `b` when `b > a`, NaN if either is NaN.
    Max(Id, Id),
}

impl Node {
    /// Whether the node is an arithmetic operation (counted in op counts).
    pub fn is_op(&self) -> bool {
        !matches!(self, Node::Const(_) | Node::Sym(_))
    }

    /// The operands of the node, in order.
    pub fn children(&self) -> impl Iterator<Item = Id> {
        let (a, b) = match *self {
            Node::Const(_) | Node::Sym(_) => (None, None),
            Node::Add(a, b)
            | Node::Sub(a, b)
            | Node::Mul(a, b)
            | Node::Div(a, b)
            | Node::Atan2(a, b)
            | Node::Min(a, b)
            | Node::Max(a, b) => (Some(a), Some(b)),
            Node::Neg(a) | Node::Call(_, a) | Node::Powi(a, _) => (Some(a), None),
        };
        a.into_iter().chain(b)
    }
}

/// The DAG: nodes in creation order (children before parents) and the
/// hash-consing index.
#[derive(Default)]
pub struct Graph {
    nodes: Vec<Node>,
    index: HashMap<Node, Id>,
}

impl Graph {
    pub fn new() -> Self {
        let mut g = Graph::default();
        // Ids 0 and 1 are always the constants 0 and 1.
        g.intern(Node::Const(0f64.to_bits()));
        g.intern(Node::Const(1f64.to_bits()));
        g
    }

    pub const ZERO: Id = Id(0);
    pub const ONE: Id = Id(1);

    pub fn node(&self, id: Id) -> Node {
        self.nodes[id.0 as usize]
    }

    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// The nodes reachable from `roots`, each once (roots included).
    pub fn reachable(&self, roots: &[Id]) -> Vec<Id> {
        let mut seen = vec![false; self.len()];
        let mut stack = roots.to_vec();
        let mut out = Vec::new();
        while let Some(id) = stack.pop() {
            if std::mem::replace(&mut seen[id.0 as usize], true) {
                continue;
            }
            out.push(id);
            stack.extend(self.node(id).children());
        }
        out
    }

    /// The id of `node` if the graph holds it (never adds it).
    pub fn find(&self, node: Node) -> Option<Id> {
        self.index.get(&node).copied()
    }

    /// The constant value of a node, if it is a constant.
    pub fn as_const(&self, id: Id) -> Option<f64> {
        match self.node(id) {
            Node::Const(bits) => Some(f64::from_bits(bits)),
            _ => None,
        }
    }

    pub fn is_zero(&self, id: Id) -> bool {
        id == Graph::ZERO
    }

    pub fn constant(&mut self, v: f64) -> Id {
        let v = if v == 0.0 { 0.0 } else { v };
        self.intern(Node::Const(v.to_bits()))
    }

    pub fn sym(&mut self, s: Sym) -> Id {
        self.intern(Node::Sym(s))
    }

    pub fn add(&mut self, a: Id, b: Id) -> Id {
        if let Some(v) = self.fold2(a, b, |x, y| x + y) {
            return v;
        }
        if self.is_zero(a) {
            return b;
        }
        if self.is_zero(b) {
            return a;
        }
        if let Node::Neg(c) = self.node(b) {
            return self.sub(a, c);
        }
        if let Node::Neg(c) = self.node(a) {
            return self.sub(b, c);
        }
        if a == b {
            // `a + a = 2 a` exactly; as a product it meets other constant
            // factors (`2 (x + x)` from differentiating `x^2` becomes `4 x`).
            let two = self.constant(2.0);
            return self.mul(two, a);
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Add(a, b))
    }

    pub fn sub(&mut self, a: Id, b: Id) -> Id {
        if let Some(v) = self.fold2(a, b, |x, y| x - y) {
            return v;
        }
        if a == b {
            return Graph::ZERO;
        }
        if self.is_zero(b) {
            return a;
        }
        if self.is_zero(a) {
            return self.neg(b);
        }
        if let Node::Neg(c) = self.node(b) {
            return self.add(a, c);
        }
        if let Node::Neg(c) = self.node(a) {
            // -c - b = -(c + b)
            let s = self.add(c, b);
            return self.neg(s);
        }
        self.intern(Node::Sub(a, b))
    }

    pub fn mul(&mut self, a: Id, b: Id) -> Id {
        if let Some(v) = self.fold2(a, b, |x, y| x * y) {
            return v;
        }
        if self.is_zero(a) || self.is_zero(b) {
            return Graph::ZERO;
        }
        if a == Graph::ONE {
            return b;
        }
        if b == Graph::ONE {
            return a;
        }
        if self.as_const(a) == Some(-1.0) {
            return self.neg(b);
        }
        if self.as_const(b) == Some(-1.0) {
            return self.neg(a);
        }
        match (self.node(a), self.node(b)) {
            (Node::Neg(x), Node::Neg(y)) => return self.mul(x, y),
            (Node::Neg(x), _) => {
                let m = self.mul(x, b);
                return self.neg(m);
            }
            (_, Node::Neg(y)) => {
                let m = self.mul(a, y);
                return self.neg(m);
            }
            _ => {}
        }
        // Negative constants are pulled out as a negation of the positive one.
        if let Some(c) = self.as_const(a).filter(|c| *c < 0.0) {
            let pos = self.constant(-c);
            let m = self.mul(pos, b);
            return self.neg(m);
        }
        if let Some(c) = self.as_const(b).filter(|c| *c < 0.0) {
            let pos = self.constant(-c);
            let m = self.mul(a, pos);
            return self.neg(m);
        }
        // Powers of two scale exactly: `c1 (c2 x) = (c1 c2) x` bit for bit.
        for (c, other) in [(a, b), (b, a)] {
            let (Some(c1), Node::Mul(p, q)) = (self.power_of_two(c), self.node(other)) else {
                continue;
            };
            for (k, x) in [(p, q), (q, p)] {
                if let Some(c2) = self.power_of_two(k) {
                    let c = self.constant(c1 * c2);
                    if self.power_of_two(c).is_some() {
                        return self.mul(c, x);
                    }
                }
            }
        }
        let (a, b) = if a <= b { (a, b) } else { (b, a) };
        self.intern(Node::Mul(a, b))
    }

    /// The value of a constant that is a positive power of two with a normal
    /// product range (multiplying by it never rounds).
    pub fn power_of_two(&self, id: Id) -> Option<f64> {
        self.as_const(id)
            .filter(|c| *c > 0.0 && c.is_normal() && c.to_bits() & ((1u64 << 52) - 1) == 0)
    }

    /// `a b` as given, without the sign normalization of [`Graph::mul`]
    /// (which pulls a negated operand out as `-(a b)`): for the last rewrite
    /// of a generated function, where `(-a) b` shares one negation among
    /// several products.
    pub fn product_as_is(&mut self, a: Id, b: Id) -> Id {
        self.intern(Node::Mul(a, b))
    }

    pub fn div(&mut self, a: Id, b: Id) -> Id {
        if let Some(v) = self.fold2(a, b, |x, y| x / y) {
            return v;
        }
        if self.is_zero(a) {
            return Graph::ZERO;
        }
        if b == Graph::ONE {
            return a;
        }
        if self.as_const(b) == Some(-1.0) {
            return self.neg(a);
        }
        if a == b {
            return Graph::ONE;
        }
        if let Node::Neg(x) = self.node(a) {
            let d = self.div(x, b);
            return self.neg(d);
        }
        if let Some(c) = self.as_const(a).filter(|c| *c < 0.0) {
            let pos = self.constant(-c);
            let d = self.div(pos, b);
            return self.neg(d);
        }
        if let Node::Neg(y) = self.node(b) {
            let d = self.div(a, y);
            return self.neg(d);
        }
        self.intern(Node::Div(a, b))
    }

    pub fn neg(&mut self, a: Id) -> Id {
        if let Some(x) = self.as_const(a) {
            return self.constant(-x);
        }
        match self.node(a) {
            Node::Neg(x) => x,
            Node::Sub(x, y) => self.sub(y, x),
            _ => self.intern(Node::Neg(a)),
        }
    }

    pub fn call(&mut self, f: Func, a: Id) -> Id {
        if let Some(v) = self
            .as_const(a)
            .map(|x| f.apply(x))
            .filter(|v| v.is_finite())
        {
            return self.constant(v);
        }
        match (f, self.node(a)) {
            (Func::Abs, Node::Neg(x)) => self.call(f, x),
            _ => self.intern(Node::Call(f, a)),
        }
    }

    pub fn atan2(&mut self, y: Id, x: Id) -> Id {
        if let Some(v) = self.fold2(y, x, f64::atan2) {
            return v;
        }
        self.intern(Node::Atan2(y, x))
    }

    pub fn min(&mut self, a: Id, b: Id) -> Id {
        if a == b {
            return a;
        }
        if let Some(v) = self.fold2(a, b, min) {
            return v;
        }
        self.intern(Node::Min(a, b))
    }

    pub fn max(&mut self, a: Id, b: Id) -> Id {
        if a == b {
            return a;
        }
        if let Some(v) = self.fold2(a, b, max) {
            return v;
        }
        self.intern(Node::Max(a, b))
    }

    pub fn powi(&mut self, a: Id, n: i32) -> Id {
        match n {
            0 => return Graph::ONE,
            1 => return a,
            _ => {}
        }
        if let Some(v) = self
            .as_const(a)
            .map(|x| x.powi(n))
            .filter(|v| v.is_finite())
        {
            return self.constant(v);
        }
        self.intern(Node::Powi(a, n))
    }

    /// Sum of a list of terms, left to right.
    pub fn sum(&mut self, terms: impl IntoIterator<Item = Id>) -> Id {
        terms
            .into_iter()
            .fold(Graph::ZERO, |acc, t| self.add(acc, t))
    }

    /// Whether `id` depends on any symbol accepted by `pred`.
    #[cfg(test)]
    pub fn depends_on(&self, id: Id, pred: impl Fn(Sym) -> bool) -> bool {
        let mut seen = vec![false; self.nodes.len()];
        let mut stack = vec![id];
        while let Some(n) = stack.pop() {
            if std::mem::replace(&mut seen[n.0 as usize], true) {
                continue;
            }
            match self.node(n) {
                Node::Sym(s) if pred(s) => return true,
                node => stack.extend(node.children()),
            }
        }
        false
    }

    /// `id` with every symbol accepted by `zero` replaced by 0, re-simplified.
    pub fn substitute_zero(
        &mut self,
        id: Id,
        zero: &dyn Fn(Sym) -> bool,
        memo: &mut HashMap<Id, Id>,
    ) -> Id {
        if let Some(&r) = memo.get(&id) {
            return r;
        }
        let node = self.node(id);
        let r = match node {
            Node::Const(_) => id,
            Node::Sym(s) => {
                if zero(s) {
                    Graph::ZERO
                } else {
                    id
                }
            }
            _ => {
                let kids: Vec<Id> = node
                    .children()
                    .map(|c| self.substitute_zero(c, zero, memo))
                    .collect();
                self.rebuild(node, &kids)
            }
        };
        memo.insert(id, r);
        r
    }

    /// Builds `node` again through the simplifying constructors with new operands.
    pub fn rebuild(&mut self, node: Node, kids: &[Id]) -> Id {
        match node {
            Node::Const(_) | Node::Sym(_) => unreachable!("leaves have no operands"),
            Node::Add(..) => self.add(kids[0], kids[1]),
            Node::Sub(..) => self.sub(kids[0], kids[1]),
            Node::Mul(..) => self.mul(kids[0], kids[1]),
            Node::Div(..) => self.div(kids[0], kids[1]),
            Node::Neg(_) => self.neg(kids[0]),
            Node::Call(f, _) => self.call(f, kids[0]),
            Node::Atan2(..) => self.atan2(kids[0], kids[1]),
            Node::Powi(_, n) => self.powi(kids[0], n),
            Node::Min(..) => self.min(kids[0], kids[1]),
            Node::Max(..) => self.max(kids[0], kids[1]),
        }
    }

    /// Evaluates `id` with symbol values from `env` (the reference interpreter).
    #[cfg(test)]
    pub fn eval(&self, id: Id, env: &dyn Fn(Sym) -> f64) -> f64 {
        let mut memo: HashMap<Id, f64> = HashMap::new();
        self.eval_memo(id, env, &mut memo)
    }

    #[cfg(test)]
    fn eval_memo(&self, id: Id, env: &dyn Fn(Sym) -> f64, memo: &mut HashMap<Id, f64>) -> f64 {
        if let Some(&v) = memo.get(&id) {
            return v;
        }
        let mut ev = |c: Id| self.eval_memo(c, env, memo);
        let v = match self.node(id) {
            Node::Const(bits) => f64::from_bits(bits),
            Node::Sym(s) => env(s),
            Node::Add(a, b) => ev(a) + ev(b),
            Node::Sub(a, b) => ev(a) - ev(b),
            Node::Mul(a, b) => ev(a) * ev(b),
            Node::Div(a, b) => ev(a) / ev(b),
            Node::Neg(a) => -ev(a),
            Node::Call(f, a) => f.apply(ev(a)),
            Node::Atan2(y, x) => ev(y).atan2(ev(x)),
            Node::Powi(a, n) => ev(a).powi(n),
            Node::Min(a, b) => min(ev(a), ev(b)),
            Node::Max(a, b) => max(ev(a), ev(b)),
        };
        memo.insert(id, v);
        v
    }

    fn fold2(&mut self, a: Id, b: Id, op: impl Fn(f64, f64) -> f64) -> Option<Id> {
        let v = op(self.as_const(a)?, self.as_const(b)?);
        v.is_finite().then(|| self.constant(v))
    }

    fn intern(&mut self, node: Node) -> Id {
        if let Some(&id) = self.index.get(&node) {
            return id;
        }
        let id = Id(self.nodes.len() as u32);
        self.nodes.push(node);
        self.index.insert(node, id);
        id
    }
}

/// Below this `s`, [`Func::HalfSinc`] and [`Func::HalfSincSlope`] are
/// evaluated by their Taylor series (truncation error below 1e-16 there).
pub const HALF_SINC_SERIES_BELOW: f64 = 1e-3;

/// The value of [`Node::Min`] (NaN-propagating, unlike `f64::min`).
pub fn min(a: f64, b: f64) -> f64 {
    if a <= b {
        a
    } else if b < a {
        b
    } else {
        a + b
    }
}

/// The value of [`Node::Max`] (NaN-propagating, unlike `f64::max`).
pub fn max(a: f64, b: f64) -> f64 {
    if a >= b {
        a
    } else if b > a {
        b
    } else {
        a + b
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn xy(g: &mut Graph) -> (Id, Id) {
        (g.sym(Sym::State(0)), g.sym(Sym::State(1)))
    }

    #[test]
    fn simplifier_identities() {
        let mut g = Graph::new();
        let (x, y) = xy(&mut g);
        let zero = Graph::ZERO;
        let one = Graph::ONE;
        let two = g.constant(2.0);
        let m1 = g.constant(-1.0);
        let nx = g.neg(x);
        let ny = g.neg(y);
        let x_minus_y = g.sub(x, y);
        let cases: Vec<(&str, Id, Id)> = vec![
            ("x + 0", g.add(x, zero), x),
            ("0 + x", g.add(zero, x), x),
            ("x - 0", g.sub(x, zero), x),
            ("0 - x", g.sub(zero, x), nx),
            ("x - x", g.sub(x, x), zero),
            ("x * 1", g.mul(x, one), x),
            ("1 * x", g.mul(one, x), x),
            ("x * 0", g.mul(x, zero), zero),
            ("0 * x", g.mul(zero, x), zero),
            ("x * -1", g.mul(x, m1), nx),
            ("--x", g.neg(nx), x),
            ("0 / x", g.div(zero, x), zero),
            ("x / 1", g.div(x, one), x),
            ("x / x", g.div(x, x), one),
            ("2 + 2", g.add(two, two), g.constant(4.0)),
            ("2 * -1", g.mul(two, m1), g.constant(-2.0)),
            ("-(0)", g.neg(zero), zero),
            ("x + y == y + x", g.add(x, y), g.add(y, x)),
            ("x * y == y * x", g.mul(x, y), g.mul(y, x)),
            ("x + -y == x - y", g.add(x, ny), x_minus_y),
            ("x - -y == x + y", g.sub(x, ny), g.add(x, y)),
            ("-x * -y == x * y", g.mul(nx, ny), g.mul(x, y)),
            ("-(x - y) == y - x", g.neg(x_minus_y), g.sub(y, x)),
            ("powi(x, 1)", g.powi(x, 1), x),
            ("powi(x, 0)", g.powi(x, 0), one),
            ("sin(0)", g.call(Func::Sin, zero), zero),
            ("cos(0)", g.call(Func::Cos, zero), one),
            ("abs(-x)", g.call(Func::Abs, nx), g.call(Func::Abs, x)),
            ("x + x == 2 x", g.add(x, x), g.mul(two, x)),
            (
                "2 (x + x) == 4 x",
                {
                    let s = g.add(x, x);
                    g.mul(two, s)
                },
                {
                    let four = g.constant(4.0);
                    g.mul(x, four)
                },
            ),
            (
                "(x 0.5) 2 == x",
                {
                    let half = g.constant(0.5);
                    let h = g.mul(x, half);
                    g.mul(h, two)
                },
                x,
            ),
        ];
        for (name, got, want) in cases {
            assert_eq!(got, want, "{name}");
        }
    }

    #[test]
    fn only_powers_of_two_are_folded_across_products() {
        // `3 (2 x)` would round differently from `6 x`: kept as two products.
        let mut g = Graph::new();
        let (x, _) = xy(&mut g);
        let (two, three) = (g.constant(2.0), g.constant(3.0));
        let two_x = g.mul(two, x);
        let product = g.mul(three, two_x);
        assert_eq!(
            g.node(product),
            Node::Mul(three.min(two_x), three.max(two_x))
        );
        for (c, power) in [
            (2.0, true),
            (0.25, true),
            (1.0, true),
            (3.0, false),
            (-2.0, false),
            (f64::MIN_POSITIVE / 2.0, false),
        ] {
            let id = g.constant(c);
            assert_eq!(g.power_of_two(id).is_some(), power, "{c}");
        }
    }

    #[test]
    fn nonfinite_constants_are_not_folded() {
        let mut g = Graph::new();
        let one = Graph::ONE;
        let d = g.div(one, Graph::ZERO);
        assert!(matches!(g.node(d), Node::Div(..)));
        let m1 = g.constant(-1.0);
        let l = g.call(Func::Ln, m1);
        assert!(matches!(g.node(l), Node::Call(Func::Ln, _)));
    }

    #[test]
    fn hash_consing_shares_nodes() {
        let mut g = Graph::new();
        let (x, y) = xy(&mut g);
        let a = g.mul(x, y);
        let s1 = g.call(Func::Sin, a);
        let before = g.len();
        let b = g.mul(y, x);
        let s2 = g.call(Func::Sin, b);
        assert_eq!(s1, s2);
        assert_eq!(g.len(), before);
    }

    #[test]
    fn eval_and_substitution() {
        let mut g = Graph::new();
        let (x, y) = xy(&mut g);
        let w = g.sym(Sym::Noise(0));
        let xw = g.add(x, w);
        let e = g.mul(xw, y);
        let env = |s: Sym| match s {
            Sym::State(0) => 2.0,
            Sym::State(1) => 3.0,
            Sym::Noise(0) => 5.0,
            _ => f64::NAN,
        };
        assert_eq!(g.eval(e, &env), 21.0);
        assert!(g.depends_on(e, |s| matches!(s, Sym::Noise(_))));
        let mut memo = HashMap::new();
        let e0 = g.substitute_zero(e, &|s| matches!(s, Sym::Noise(_)), &mut memo);
        assert_eq!(e0, g.mul(x, y));
        assert!(!g.depends_on(e0, |s| matches!(s, Sym::Noise(_))));
    }
}
