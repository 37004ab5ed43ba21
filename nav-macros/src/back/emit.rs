//! Code generation: quotes the generated items from the checked declaration and
//! the derived outputs. Nothing is validated here.

use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote};
use syn::Ident;

use crate::front::names::screaming_case;
use crate::front::parse::{Manifold, ModelDecl, Scalar, Shape, Var};
use crate::symbolic::cse::{schedule, Schedule};
use crate::symbolic::derive::Derived;
use crate::symbolic::strength;
use crate::symbolic::{Func, Graph, Id, Node, ProcessKind, Sym};

/// All items generated for one model.
pub fn model(decl: &ModelDecl, d: &Derived) -> TokenStream {
    let em = Emitter::new(decl, d);
    let records = em.records();
    let model = em.model_items();
    let sensors: Vec<TokenStream> = (0..decl.sensors.len())
        .map(|s| em.sensor_items(s))
        .collect();
    let tests = em.tests();
    quote! {
        #records
        #model
        #(#sensors)*
        #tests
    }
}

struct Emitter<'a> {
    decl: &'a ModelDecl,
    d: &'a Derived,
    g: &'a Graph,
    name: &'a Ident,
    state_ty: Ident,
    input_ty: Ident,
    params_ty: Ident,
    noise_ty: Ident,
    n: Literal,
    nw: Literal,
    inputs: Vec<TokenStream>,
    params: Vec<TokenStream>,
    noise: Vec<TokenStream>,
    aux: Vec<Vec<TokenStream>>,
    /// The scalar type (`f64` or `f32`) and the module of its functions.
    scalar: TokenStream,
    math: TokenStream,
}

fn lit(v: usize) -> Literal {
    Literal::usize_unsuffixed(v)
}

/// `T`, `SVector<T, n>` or `SMatrix<T, r, c>` for the scalar `T`.
fn field_type(shape: Shape, scalar: &TokenStream) -> TokenStream {
    match shape {
        Shape::Scalar => quote!(#scalar),
        Shape::Vector(n) => {
            let n = lit(n);
            quote!(::nav_runtime::nalgebra::SVector<#scalar, #n>)
        }
        Shape::Matrix(r, c) => {
            let (r, c) = (lit(r), lit(c));
            quote!(::nav_runtime::nalgebra::SMatrix<#scalar, #r, #c>)
        }
    }
}

/// Per scalar of a record: its access path suffix (`.gyro[1]`) and its name.
fn scalar_paths(vars: &[Var]) -> Vec<(TokenStream, String)> {
    let mut out = Vec::new();
    for v in vars {
        let f = &v.name;
        match v.shape {
            Shape::Scalar => out.push((quote!(.#f), f.to_string())),
            Shape::Vector(n) => {
                for i in 0..n {
                    let li = lit(i);
                    out.push((quote!(.#f[#li]), format!("{f}[{i}]")));
                }
            }
            Shape::Matrix(r, c) => {
                for i in 0..r {
                    for j in 0..c {
                        let (li, lj) = (lit(i), lit(j));
                        out.push((quote!(.#f[(#li, #lj)]), format!("{f}[{i}][{j}]")));
                    }
                }
            }
        }
    }
    out
}

fn doc(text: &str) -> TokenStream {
    quote!(#[doc = #text])
}

/// A function being emitted: its own graph and schedule.
struct Function<'g> {
    graph: &'g Graph,
    sch: &'g Schedule,
}

/// One function body: shared temporaries, then the output expressions.
struct Body {
    lets: TokenStream,
    exprs: Vec<TokenStream>,
    ops: usize,
}

impl<'a> Emitter<'a> {
    fn new(decl: &'a ModelDecl, d: &'a Derived) -> Self {
        let name = &decl.name;
        let paths = |vars: &[Var]| scalar_paths(vars).into_iter().map(|(p, _)| p).collect();
        Emitter {
            decl,
            d,
            g: &d.graph,
            name,
            state_ty: format_ident!("{}State", name),
            input_ty: format_ident!("{}Input", name),
            params_ty: format_ident!("{}Params", name),
            noise_ty: format_ident!("{}Noise", name),
            n: lit(d.n),
            nw: lit(d.nw),
            inputs: paths(&decl.inputs),
            params: paths(&decl.params),
            noise: paths(&decl.noise),
            aux: decl.sensors.iter().map(|s| paths(&s.inputs)).collect(),
            scalar: decl.scalar.tokens(),
            math: decl.scalar.math(),
        }
    }

    /// Reads a symbol in a generated function; `cov` names the covariance.
    fn read(&self, s: Sym, cov: &TokenStream) -> TokenStream {
        match s {
            Sym::State(k) => {
                let k = lit(k as usize);
                quote!(x[#k])
            }
            Sym::Input(k) => {
                let p = &self.inputs[k as usize];
                quote!(u #p)
            }
            Sym::Param(k) => {
                let p = &self.params[k as usize];
                quote!(p #p)
            }
            Sym::NoiseIntensity(k) => {
                let p = &self.noise[k as usize];
                quote!(q #p)
            }
            Sym::Noise(k) => {
                let k = lit(k as usize);
                quote!(w[#k])
            }
            Sym::Aux(s, k) => {
                let p = &self.aux[s as usize][k as usize];
                quote!(aux #p)
            }
            Sym::Dt => quote!(dt),
            Sym::Cov(i, j) => {
                let (i, j) = (lit(i as usize), lit(j as usize));
                quote!(#cov[(#i, #j)])
            }
        }
    }

    /// One function's code: its outputs strength-reduced in a graph of their
    /// own ([`strength::reduce`]), shared nodes as `let` temporaries.
    fn body(&self, roots: &[Id], cov: TokenStream) -> Body {
        let (graph, roots) = strength::reduce(self.g, roots);
        let sch = schedule(&graph, &roots);
        let f = Function {
            graph: &graph,
            sch: &sch,
        };
        let math = &self.math;
        let temp = |id: Id| sch.temp_of[id.0 as usize].map(|k| format_ident!("_t{}", k));
        let mut lets = TokenStream::new();
        let mut paired = vec![false; sch.temps.len()];
        for (k, &id) in sch.temps.iter().enumerate() {
            if paired[k] {
                continue;
            }
            let t = format_ident!("_t{}", k);
            if let Some(&(sin, cos)) = sch.sin_cos.iter().find(|p| p.0 == id || p.1 == id) {
                let Node::Call(_, a) = graph.node(sin) else {
                    unreachable!("a sin_cos pair is two calls");
                };
                let a = self.expr(&f, a, &cov, 0);
                let (ts, tc) = (temp(sin), temp(cos));
                lets.extend(quote!(let (#ts, #tc) = #math::sin_cos(#a);));
                for p in [sin, cos] {
                    if let Some(j) = sch.temp_of[p.0 as usize] {
                        paired[j] = true;
                    }
                }
                continue;
            }
            let e = self.node_expr(&f, id, &cov, 0);
            lets.extend(quote!(let #t = #e;));
        }
        let exprs = roots.iter().map(|&r| self.expr(&f, r, &cov, 0)).collect();
        Body {
            lets,
            exprs,
            ops: sch.ops,
        }
    }

    /// The expression of `id` in a context of precedence `min` (0: none,
    /// 1: `+ -`, 2: `* /`, 3: unary).
    fn expr(&self, f: &Function<'_>, id: Id, cov: &TokenStream, min: u8) -> TokenStream {
        if let Some(t) = f.sch.temp_of[id.0 as usize] {
            let t = format_ident!("_t{}", t);
            return quote!(#t);
        }
        self.node_expr(f, id, cov, min)
    }

    fn node_expr(&self, f: &Function<'_>, id: Id, cov: &TokenStream, min: u8) -> TokenStream {
        let math = &self.math;
        let (prec, tokens) = match f.graph.node(id) {
            Node::Const(bits) => {
                let v = f64::from_bits(bits);
                let l = float_literal(v.abs(), self.decl.scalar);
                if v < 0.0 {
                    (3, quote!(-#l))
                } else {
                    (4, quote!(#l))
                }
            }
            Node::Sym(s) => (4, self.read(s, cov)),
            Node::Add(a, b) => {
                let (a, b) = (self.expr(f, a, cov, 1), self.expr(f, b, cov, 2));
                (1, quote!(#a + #b))
            }
            Node::Sub(a, b) => {
                let (a, b) = (self.expr(f, a, cov, 1), self.expr(f, b, cov, 2));
                (1, quote!(#a - #b))
            }
            Node::Mul(a, b) => {
                let (a, b) = (self.expr(f, a, cov, 2), self.expr(f, b, cov, 3));
                (2, quote!(#a * #b))
            }
            Node::Div(a, b) => {
                let (a, b) = (self.expr(f, a, cov, 2), self.expr(f, b, cov, 3));
                (2, quote!(#a / #b))
            }
            Node::Neg(a) => {
                let a = self.expr(f, a, cov, 4);
                (3, quote!(-#a))
            }
            Node::Call(Func::Sign, a) => {
                let a = self.expr(f, a, cov, 0);
                (
                    4,
                    quote!({ let a = #a; if a > 0.0 { 1.0 } else if a < 0.0 { -1.0 } else { a } }),
                )
            }
            Node::Call(Func::Step, a) => {
                let a = self.expr(f, a, cov, 0);
                (4, quote!({ if #a > 0.0 { 1.0 } else { 0.0 } }))
            }
            Node::Call(Func::HalfCos, a) => {
                let a = self.expr(f, a, cov, 0);
                (4, quote!(#math::cos(0.5 * #math::sqrt(#a))))
            }
            Node::Call(Func::HalfSinc, a) => {
                let a = self.expr(f, a, cov, 0);
                let below = Literal::f64_unsuffixed(crate::symbolic::expr::HALF_SINC_SERIES_BELOW);
                (
                    4,
                    quote!({
                        let s = #a;
                        if s < #below {
                            0.5 - s / 48.0 + s * s / 3840.0 - s * s * s / 645120.0
                        } else {
                            let r = #math::sqrt(s);
                            #math::sin(0.5 * r) / r
                        }
                    }),
                )
            }
            Node::Call(Func::HalfSincSlope, a) => {
                let a = self.expr(f, a, cov, 0);
                let below = Literal::f64_unsuffixed(crate::symbolic::expr::HALF_SINC_SERIES_BELOW);
                (
                    4,
                    quote!({
                        let s = #a;
                        if s < #below {
                            -1.0 / 48.0 + s / 1920.0 - s * s / 215040.0
                        } else {
                            let r = #math::sqrt(s);
                            (#math::cos(0.5 * r) - 2.0 * #math::sin(0.5 * r) / r) / (4.0 * s)
                        }
                    }),
                )
            }
            Node::Call(func, a) => {
                let fname = format_ident!("{}", func.name());
                let a = self.expr(f, a, cov, 0);
                (4, quote!(#math::#fname(#a)))
            }
            Node::Min(a, b) | Node::Max(a, b) => {
                let (a, b) = (self.expr(f, a, cov, 0), self.expr(f, b, cov, 0));
                let (first, second) = if matches!(f.graph.node(id), Node::Min(..)) {
                    (quote!(<=), quote!(<))
                } else {
                    (quote!(>=), quote!(>))
                };
                // NaN-propagating: a NaN operand fails both comparisons.
                (
                    4,
                    quote!({ let (a, b) = (#a, #b); if a #first b { a } else if b #second a { b } else { a + b } }),
                )
            }
            Node::Atan2(y, x) => {
                let (y, x) = (self.expr(f, y, cov, 0), self.expr(f, x, cov, 0));
                (4, quote!(#math::atan2(#y, #x)))
            }
            Node::Powi(a, n) => {
                let a = self.expr(f, a, cov, 0);
                let n = Literal::i32_unsuffixed(n);
                (4, quote!(#math::powi(#a, #n)))
            }
        };
        if prec < min {
            quote!((#tokens))
        } else {
            tokens
        }
    }

    fn records(&self) -> TokenStream {
        let name = self.name;
        let n = self.d.n;
        let state = self.record(
            &self.state_ty,
            &format!("The state of [`{name}`] ({n} scalars), with named fields."),
            &self.decl.states,
        );
        let state_ty = &self.state_ty;
        let nl = &self.n;
        let scalar = &self.scalar;
        let to_vec: Vec<TokenStream> = scalar_paths(&self.decl.states)
            .into_iter()
            .map(|(p, _)| quote!(self #p))
            .collect();
        let input = self.record(
            &self.input_ty,
            &format!("The inputs `u` of [`{name}`]."),
            &self.decl.inputs,
        );
        let params = self.record(
            &self.params_ty,
            &format!("The parameters `p` of [`{name}`]."),
            &self.decl.params,
        );
        let noise_doc = match self.d.kind {
            ProcessKind::Continuous => format!(
                "The process-noise power spectral densities `q` of [`{name}`], one per noise scalar (units^2 / s)."
            ),
            ProcessKind::Discrete => {
                format!("The per-step process-noise variances `q` of [`{name}`], one per noise scalar.")
            }
        };
        let noise = self.record(&self.noise_ty, &noise_doc, &self.decl.noise);
        let sensor_aux: Vec<TokenStream> = self
            .decl
            .sensors
            .iter()
            .filter(|s| !s.inputs.is_empty())
            .map(|s| {
                let ty = format_ident!("{}{}Aux", name, s.name);
                self.record(
                    &ty,
                    &format!("The auxiliary inputs of sensor [`{}{}`].", name, s.name),
                    &s.inputs,
                )
            })
            .collect();
        quote! {
            #state
            #[allow(clippy::possible_missing_comma)]
            impl #state_ty {
                /// The state from its vector (declaration order).
                pub fn from_vector(v: &::nav_runtime::nalgebra::SVector<#scalar, #nl>) -> Self {
                    <Self as ::nav_runtime::model::Record>::from_fn(|i| <#scalar as ::nav_runtime::Real>::to_f64(v[i]))
                }
                /// The state as a vector (declaration order).
                pub fn to_vector(&self) -> ::nav_runtime::nalgebra::SVector<#scalar, #nl> {
                    ::nav_runtime::nalgebra::SVector::<#scalar, #nl>::from_column_slice(&[#(#to_vec),*])
                }
            }
            #input
            #params
            #noise
            #(#sensor_aux)*
        }
    }

    fn record(&self, ty: &Ident, text: &str, vars: &[Var]) -> TokenStream {
        let vis = &self.decl.vis;
        let doc = doc(text);
        let scalar = &self.scalar;
        let fields = vars.iter().map(|v| {
            let (attrs, f, t) = (&v.attrs, &v.name, field_type(v.shape, scalar));
            quote!(#(#attrs)* pub #f: #t,)
        });
        let paths = scalar_paths(vars);
        let len = lit(paths.len());
        let names = paths.iter().map(|(_, s)| s);
        let arms = paths.iter().enumerate().map(|(i, (p, _))| {
            let i = lit(i);
            quote!(#i => <#scalar as ::nav_runtime::Real>::to_f64(self #p),)
        });
        let mut offset = 0;
        let inits = vars.iter().map(|v| {
            let f = &v.name;
            let (a, b) = (lit(offset), lit(offset + v.shape.len()));
            offset += v.shape.len();
            match v.shape {
                Shape::Scalar => quote!(#f: v[#a],),
                Shape::Vector(n) => {
                    let n = lit(n);
                    quote!(#f: ::nav_runtime::nalgebra::SVector::<#scalar, #n>::from_column_slice(&v[#a..#b]),)
                }
                Shape::Matrix(r, c) => {
                    let (r, c) = (lit(r), lit(c));
                    quote!(#f: ::nav_runtime::nalgebra::SMatrix::<#scalar, #r, #c>::from_row_slice(&v[#a..#b]),)
                }
            }
        });
        quote! {
            #doc
            #[derive(Clone, Copy, Debug, Default, PartialEq)]
            #[allow(non_snake_case)]
            #vis struct #ty {
                #(#fields)*
            }
            #[allow(clippy::possible_missing_comma)]
            impl ::nav_runtime::model::Record for #ty {
                const LEN: usize = #len;
                const NAMES: &'static [&'static str] = &[#(#names),*];
                fn from_fn(mut f: impl FnMut(usize) -> f64) -> Self {
                    let mut v: [#scalar; #len] = [0.0; #len];
                    for (i, slot) in v.iter_mut().enumerate() {
                        *slot = <#scalar as ::nav_runtime::Real>::of(f(i));
                    }
                    Self { #(#inits)* }
                }
                fn get(&self, i: usize) -> f64 {
                    match i {
                        #(#arms)*
                        _ => f64::NAN,
                    }
                }
            }
        }
    }

    fn model_items(&self) -> TokenStream {
        let d = self.d;
        let (name, vis, n, nw) = (self.name, &self.decl.vis, &self.n, &self.nw);
        let (state_ty, input_ty, params_ty, noise_ty) = (
            &self.state_ty,
            &self.input_ty,
            &self.params_ty,
            &self.noise_ty,
        );
        let attrs = &self.decl.attrs;
        let svec = quote!(::nav_runtime::nalgebra::SVector);
        let smat = quote!(::nav_runtime::nalgebra::SMatrix);
        let scalar = &self.scalar;
        let nocov = quote!(_p);

        // Index constants.
        let mut offset = 0;
        let index_consts: Vec<TokenStream> = self
            .decl
            .states
            .iter()
            .map(|v| {
                let c = format_ident!("{}", screaming_case(&v.name.to_string()));
                let o = lit(offset);
                let text = format!(
                    "Index of the first scalar of `{}` in the state vector.",
                    v.name
                );
                offset += v.shape.len();
                quote!(#[doc = #text] pub const #c: usize = #o;)
            })
            .collect();

        let state_names: Vec<String> = scalar_paths(&self.decl.states)
            .into_iter()
            .map(|(_, s)| s)
            .collect();
        let sparsity = self.sparsity(&d.jacobian, d.n, d.n);
        let used = d.used_states();
        let unused_states = state_names
            .iter()
            .zip(&used)
            .filter(|(_, &u)| !u)
            .map(|(s, _)| s);

        // transition
        let tr = self.body(&d.transition, nocov.clone());
        let tr_fill = self.nonzero_vector(&tr, &d.transition);
        let (tr_lets, tr_ops) = (&tr.lets, tr.ops);
        let tr_doc = doc(&match d.kind {
            ProcessKind::Continuous => {
                format!("One Euler step `x + f(x, u, p) dt`.\n\nTotal ops: {tr_ops}")
            }
            ProcessKind::Discrete => {
                format!("The next state `f(x, u, p, dt)` (noise-free).\n\nTotal ops: {tr_ops}")
            }
        });

        // jacobian
        let jb = self.body(&d.jacobian, nocov.clone());
        let jb_fill = self.nonzero_matrix(&jb, &d.jacobian, d.n, d.n);
        let (jb_lets, jb_ops) = (&jb.lets, jb.ops);
        let jb_doc = doc(&match d.kind {
            ProcessKind::Continuous => {
                format!("`F = df/dx` at `w = 0` (`dt` is unused).\n\nTotal ops: {jb_ops}")
            }
            ProcessKind::Discrete => format!("`Phi = df/dx` at `w = 0`.\n\nTotal ops: {jb_ops}"),
        });

        // noise jacobian
        let gb = self.body(&d.noise_jacobian, nocov.clone());
        let gb_fill = self.nonzero_matrix(&gb, &d.noise_jacobian, d.n, d.nw);
        let (gb_lets, gb_ops) = (&gb.lets, gb.ops);
        let gb_doc = doc(&match d.kind {
            ProcessKind::Continuous => format!(
                "The noise Jacobian `G = df/dw` of the derivative at `w = 0` (N x NW, noise scalars in \
                 declaration order; `dt` is unused: the step's own is `G dt`).\n\nTotal ops: {gb_ops}"
            ),
            ProcessKind::Discrete => format!(
                "The noise Jacobian `G = df/dw` of the step at `w = 0` (N x NW, noise scalars in declaration \
                 order).\n\nTotal ops: {gb_ops}"
            ),
        });

        // process noise
        let upper: Vec<(usize, usize, Id)> = (0..d.n)
            .flat_map(|i| (i..d.n).map(move |j| (i, j)))
            .map(|(i, j)| (i, j, d.process_noise[i * d.n + j]))
            .collect();
        let qb = self.body(
            &upper.iter().map(|e| e.2).collect::<Vec<_>>(),
            nocov.clone(),
        );
        let qb_fill = self.symmetric(&qb, &upper, d.n);
        let (qb_lets, qb_ops) = (&qb.lets, qb.ops);
        let qb_doc = doc(&match d.kind {
            ProcessKind::Continuous => {
                format!("`Qd = G Q G^T dt`, `Q = diag(q)`.\n\nTotal ops: {qb_ops}")
            }
            ProcessKind::Discrete => {
                format!("`Qd = G Q G^T`, `Q = diag(q)`.\n\nTotal ops: {qb_ops}")
            }
        });

        // propagate covariance: small models unrolled entry by entry; larger
        // ones evaluate the coefficients and Qd entries here and run the
        // product in the runtime's row kernel.
        let pr = &d.propagation;
        let identity = pr.identity;
        let structure_doc = doc(&format!(
            "Structure of `Phi` ({}) and `Qd` for the covariance propagation: rows {:?} change, the others are unit rows.",
            match (identity, d.kind) {
                (true, ProcessKind::Continuous) => "`I + F dt`",
                (true, ProcessKind::Discrete) => "`I + C`: `df/dx` with a unit diagonal in its changed rows",
                (false, _) => "`df/dx`",
            },
            pr.rows
        ));
        let rows = pr.rows.iter().map(|&i| lit(i));
        let mut start = vec![0];
        for e in &pr.entries {
            start.push(start.last().copied().unwrap_or(0) + e.len());
        }
        let start = start.into_iter().map(lit);
        let columns = pr.entries.iter().flatten().map(|e| lit(e.0));
        let noise_at = pr.noise.iter().map(|&(i, j, _)| {
            let (i, j) = (lit(i), lit(j));
            quote!((#i, #j))
        });
        let structure = quote! {
            #structure_doc
            pub const PROPAGATION_STRUCTURE: ::nav_runtime::propagation::Structure<'static> =
                ::nav_runtime::propagation::Structure {
                    identity: #identity,
                    rows: &[#(#rows),*],
                    start: &[#(#start),*],
                    columns: &[#(#columns),*],
                    noise: &[#(#noise_at),*],
                };
        };
        let visit_sensor = {
            let arms = self.decl.sensors.iter().zip(&d.sensors).map(|(sd, ds)| {
                let ty = format_ident!("{}{}", self.name, sd.name);
                let name = sd.name.to_string();
                let m = lit(ds.m);
                quote!(#name => ::core::option::Option::Some(visitor.visit::<#ty, #m>()),)
            });
            let scalar = &self.scalar;
            let n = &self.n;
            let names = self.decl.sensors.iter().map(|sd| sd.name.to_string());
            quote! {
                const DECLARED_SENSORS: &'static [&'static str] = &[#(#names),*];
                fn visit_sensor<V: ::nav_runtime::model::SensorVisitor<Self, #n, #scalar>>(
                    name: &str,
                    visitor: V,
                ) -> ::core::option::Option<V::Output> {
                    match name {
                        #(#arms)*
                        _ => {
                            let _ = visitor;
                            ::core::option::Option::None
                        }
                    }
                }
            }
        };
        let (pb_body, pb_ops, pb_doc, pb_observed) = match &pr.unrolled {
            Some(entries) => {
                let pb = self.body(&entries.iter().map(|e| e.2).collect::<Vec<_>>(), quote!(_p));
                let sets = entries
                    .iter()
                    .zip(&pb.exprs)
                    .filter_map(|(&(i, j, id), e)| {
                        // An entry equal to the old value of the same entry needs no store.
                        if self.g.node(id) == Node::Sym(Sym::cov(i, j)) {
                            return None;
                        }
                        let (i, j) = (lit(i), lit(j));
                        Some(quote!(cov[(#i, #j)] = #e;))
                    });
                let lets = &pb.lets;
                let n = &self.n;
                let body = quote! {
                    let _p = *cov;
                    #lets
                    #(#sets)*
                    for i in 0..#n {
                        for j in 0..i {
                            cov[(i, j)] = cov[(j, i)];
                        }
                    }
                };
                let ops = lit(pb.ops);
                let text = format!(
                    "`P <- Phi P Phi^T + Qd` unrolled entry by entry from the upper triangle of `P` (a small \
                     model: straight-line code fits the caches), generated from the sparsity of `Phi` and `G`; \
                     the result is mirrored.\n\nTotal ops: {}",
                    pb.ops
                );
                (body, quote!(#ops), doc(&text), quote!())
            }
            None => {
                let mut roots: Vec<Id> = pr.entries.iter().flatten().map(|e| e.1).collect();
                let nc = roots.len();
                roots.extend(pr.noise.iter().map(|e| e.2));
                let pb = self.body(&roots, nocov.clone());
                let (lets, coefficients, noise_values) =
                    (&pb.lets, &pb.exprs[..nc], &pb.exprs[nc..]);
                let (n, changed) = (&self.n, lit(pr.rows.len()));
                let (nc_lit, nq_lit) = (lit(nc), lit(pr.noise.len()));
                let body = quote! {
                    Self::propagate_covariance_observed(cov, x, u, p, q, dt, |_| ());
                };
                let observed = quote! {
                    const PROPAGATION: ::core::option::Option<::nav_runtime::propagation::Structure<'static>> =
                        ::core::option::Option::Some(Self::PROPAGATION_STRUCTURE);
                    /// The coefficients of `C` go to `observe`, then `nav_runtime::propagation::propagate_static`
                    /// runs over [`Self::PROPAGATION_STRUCTURE`].
                    #[inline]
                    fn propagate_covariance_observed<F: FnOnce(&[#scalar])>(
                        cov: &mut #smat<#scalar, #n, #n>, x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty,
                        q: &#noise_ty, dt: #scalar, observe: F,
                    ) {
                        #lets
                        let coefficients = [#(#coefficients),*];
                        observe(&coefficients);
                        ::nav_runtime::propagation::propagate_static::<#scalar, #n, #changed, #nc_lit, #nq_lit, Self>(
                            cov,
                            &coefficients,
                            &[#(#noise_values),*],
                        );
                    }
                };
                let body_ops = lit(pb.ops);
                let text = format!(
                    "`P <- Phi P Phi^T + Qd`: the {nc} nonzero coefficients of `Phi` in its {} changed rows and \
                     the {} nonzeros of `Qd` ({} ops), then `nav_runtime::propagation::propagate_static` over \
                     [`Self::PROPAGATION_STRUCTURE`]. `P` must be symmetric; the result is exactly symmetric.",
                    pr.rows.len(),
                    pr.noise.len(),
                    pb.ops
                );
                (
                    body,
                    quote!((#body_ops + Self::PROPAGATION_STRUCTURE.ops(#n))),
                    doc(&text),
                    observed,
                )
            }
        };

        let normalize = normalize_state(&self.decl.states, &self.n, self.decl.scalar);
        // derivative and process with noise
        let continuous = d.kind == ProcessKind::Continuous;
        let derivative = if continuous {
            let fb = self.body(&d.f, nocov.clone());
            let fill = self.nonzero_vector(&fb, &d.f);
            let (lets, ops) = (&fb.lets, fb.ops);
            let dd = doc(&format!(
                "The state derivative `f(x, u, p)` at `w = 0`.\n\nTotal ops: {ops}"
            ));
            let ops = lit(ops);
            quote! {
                /// Operations in [`Self::derivative`].
                pub const OPS_DERIVATIVE: usize = #ops;
                #dd
                pub fn derivative(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty) -> #svec<#scalar, #n> {
                    #lets
                    #fill
                    out
                }
            }
        } else {
            quote!()
        };
        // With an explicit noise sample: the derivative (continuous models,
        // no `dt`) and the step (every model; the only one taking `dt`).
        let derivative_with_noise = if continuous {
            let wb = self.body(&d.f_noisy, nocov.clone());
            let w_fill = self.nonzero_vector(&wb, &d.f_noisy);
            let w_lets = &wb.lets;
            let w_doc = doc(&format!(
                "The state derivative `dx/dt = f(x, u, p, w)` with an explicit noise sample `w` (units of the \
                 state per second; not a step: [`Self::step_with_noise`] advances the state by `dt`).\n\n\
                 Total ops: {}",
                wb.ops
            ));
            quote! {
                #w_doc
                pub fn derivative_with_noise(
                    x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, w: &#svec<#scalar, #nw>,
                ) -> #svec<#scalar, #n> {
                    #w_lets
                    #w_fill
                    out
                }
            }
        } else {
            quote!()
        };
        let sb = self.body(&d.step_noisy, nocov.clone());
        let s_fill = self.nonzero_vector(&sb, &d.step_noisy);
        let s_lets = &sb.lets;
        let s_doc = doc(&match d.kind {
            ProcessKind::Continuous => format!(
                "The state after one step of `dt` seconds with an explicit noise sample `w`: the Euler step \
                 `x + f(x, u, p, w) dt` (`transition` at `w = 0`; the derivative itself is \
                 [`Self::derivative_with_noise`]).\n\nTotal ops: {}",
                sb.ops
            ),
            ProcessKind::Discrete => format!(
                "The state after one step of `dt` seconds with an explicit noise sample `w`: \
                 `f(x, u, p, dt, w)` (`transition` at `w = 0`).\n\nTotal ops: {}",
                sb.ops
            ),
        });
        let step_with_noise = quote! {
            #s_doc
            pub fn step_with_noise(
                x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, w: &#svec<#scalar, #nw>, dt: #scalar,
            ) -> #svec<#scalar, #n> {
                #s_lets
                #s_fill
                out
            }
        };

        let observability = self.observability_items();

        let name_str = name.to_string();
        let zero_is_fixed = d.zero_is_fixed;
        let (tr_ops, jb_ops, gb_ops, qb_ops) = (lit(tr_ops), lit(jb_ops), lit(gb_ops), lit(qb_ops));
        let type_doc = doc(&format!(
            "Generated by `model!`: {} model with {} states, {} noise inputs and {} sensors.",
            if continuous { "continuous" } else { "discrete" },
            d.n,
            d.nw,
            self.decl.sensors.len()
        ));
        quote! {
            #(#attrs)*
            #[doc = ""]
            #type_doc
            #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
            #vis struct #name;

            #[allow(clippy::possible_missing_comma)]
            impl #name {
                /// Number of scalar states.
                pub const N: usize = #n;
                /// Number of scalar process-noise inputs.
                pub const NW: usize = #nw;
                #(#index_consts)*
                /// State scalars no sensor depends on, directly or through the dynamics
                /// (no measurement can correct them). The model lists them in
                /// `allow_unused { .. }` (checked at compile time).
                pub const UNUSED_STATES: &'static [&'static str] = &[#(#unused_states),*];
                /// Operations in `transition`.
                pub const OPS_TRANSITION: usize = #tr_ops;
                /// Operations in `jacobian`.
                pub const OPS_JACOBIAN: usize = #jb_ops;
                /// Operations in [`Self::noise_jacobian`].
                pub const OPS_NOISE_JACOBIAN: usize = #gb_ops;
                /// Operations in `process_noise`.
                pub const OPS_PROCESS_NOISE: usize = #qb_ops;
                /// Operations in `propagate_covariance`.
                pub const OPS_PROPAGATE_COVARIANCE: usize = #pb_ops;
                #structure
                #observability
                #derivative
                #derivative_with_noise
                #step_with_noise
                #gb_doc
                pub fn noise_jacobian(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, dt: #scalar) -> #smat<#scalar, #n, #nw> {
                    #gb_lets
                    #gb_fill
                    out
                }
            }

            impl ::nav_runtime::propagation::StaticStructure for #name {
                const STRUCTURE: ::nav_runtime::propagation::Structure<'static> =
                    Self::PROPAGATION_STRUCTURE;
            }

            #[allow(clippy::possible_missing_comma)]
            impl ::nav_runtime::model::Model<#n, #scalar> for #name {
                type Input = #input_ty;
                type Params = #params_ty;
                type Noise = #noise_ty;
                type State = #state_ty;
                const NAME: &'static str = #name_str;
                const DISCRETE: bool = !#continuous;
                const STATE_NAMES: [&'static str; #n] = [#(#state_names),*];
                const JACOBIAN_SPARSITY: [[bool; #n]; #n] = #sparsity;
                const OPS_PROPAGATE_COVARIANCE: usize = #pb_ops;
                const OPS_JACOBIAN: usize = #jb_ops;
                const ZERO_IS_FIXED: bool = #zero_is_fixed;

                #tr_doc
                fn transition(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, dt: #scalar) -> #svec<#scalar, #n> {
                    #tr_lets
                    #tr_fill
                    out
                }
                #jb_doc
                fn jacobian(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, dt: #scalar) -> #smat<#scalar, #n, #n> {
                    #jb_lets
                    #jb_fill
                    out
                }
                #qb_doc
                fn process_noise(
                    x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, q: &#noise_ty, dt: #scalar,
                ) -> #smat<#scalar, #n, #n> {
                    #qb_lets
                    #qb_fill
                    out
                }
                #normalize
                #pb_doc
                fn propagate_covariance(
                    cov: &mut #smat<#scalar, #n, #n>, x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, q: &#noise_ty, dt: #scalar,
                ) {
                    #pb_body
                }
                #pb_observed
                #visit_sensor
            }
        }
    }

    fn sensor_items(&self, s: usize) -> TokenStream {
        let d = self.d;
        let sd = &self.decl.sensors[s];
        let ds = &d.sensors[s];
        let (name, vis, n) = (self.name, &self.decl.vis, &self.n);
        let (input_ty, params_ty) = (&self.input_ty, &self.params_ty);
        let ty = format_ident!("{}{}", name, sd.name);
        let aux_ty = if sd.inputs.is_empty() {
            quote!(())
        } else {
            let a = format_ident!("{}{}Aux", name, sd.name);
            quote!(#a)
        };
        let m = lit(ds.m);
        let svec = quote!(::nav_runtime::nalgebra::SVector);
        let smat = quote!(::nav_runtime::nalgebra::SMatrix);
        let scalar = &self.scalar;
        let attrs = &sd.attrs;
        let sensor_name = sd.name.to_string();
        let angles: Vec<bool> = (0..ds.m)
            .map(|i| {
                sd.angles.as_ref().is_some_and(|(_, l)| {
                    l.iter().any(|x| x.base10_parse::<usize>().ok() == Some(i))
                })
            })
            .collect();
        let sparsity = self.sparsity(&ds.jacobian, ds.m, d.n);

        let hb = self.body(&ds.h, quote!(cov));
        let h_fill = self.nonzero_vector(&hb, &ds.h);
        let (h_lets, h_ops) = (&hb.lets, hb.ops);
        let jb = self.body(&ds.jacobian, quote!(cov));
        let j_fill = self.nonzero_matrix(&jb, &ds.jacobian, ds.m, d.n);
        let (j_lets, j_ops) = (&jb.lets, jb.ops);

        // innovation terms: h, P H^T and the upper triangle of H P H^T share temporaries.
        let mut roots = ds.h.clone();
        roots.extend(&ds.pht);
        roots.extend(ds.hpht.iter().map(|e| e.2));
        let ib = self.body(&roots, quote!(cov));
        let (i_lets, i_ops) = (&ib.lets, ib.ops);
        let mm = ds.m;
        let h_sets = ib.exprs[..mm]
            .iter()
            .enumerate()
            .filter(|(i, _)| !self.g.is_zero(ds.h[*i]))
            .map(|(i, e)| {
                let i = lit(i);
                quote!(h[#i] = #e;)
            });
        let u_sets = ib.exprs[mm..mm + d.n * mm]
            .iter()
            .enumerate()
            .filter(|(k, _)| !self.g.is_zero(ds.pht[*k]))
            .map(|(k, e)| {
                let (i, j) = (lit(k / mm), lit(k % mm));
                quote!(pht[(#i, #j)] = #e;)
            });
        let s_sets = ib.exprs[mm + d.n * mm..]
            .iter()
            .zip(&ds.hpht)
            .filter(|(_, e)| !self.g.is_zero(e.2))
            .map(|(expr, &(i, j, _))| {
                let (i, j) = (lit(i), lit(j));
                quote!(s[(#i, #j)] = #expr;)
            });

        let text = format!("Sensor `{sensor_name}` of [`{name}`]: {} outputs.", ds.m);
        let p_doc = doc(&format!(
            "The predicted measurement `h(x, u, p, aux)`.\n\nTotal ops: {h_ops}"
        ));
        let j_doc = doc(&format!("`H = dh/dx`.\n\nTotal ops: {j_ops}"));
        let i_doc = doc(&format!(
            "`(h, P H^T, H P H^T)` from the upper triangle of `P` and the sparsity of `H`.\n\nTotal ops: {i_ops}"
        ));
        let (h_ops, j_ops, i_ops) = (lit(h_ops), lit(j_ops), lit(i_ops));
        let index = lit(s);
        let mut alone = vec![false; d.sensors.len()];
        alone[s] = true;
        let observes = d.observable_with(&alone);
        quote! {
            #(#attrs)*
            #[doc = ""]
            #[doc = #text]
            #[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
            #vis struct #ty;

            #[allow(clippy::possible_missing_comma)]
            impl #ty {
                /// Number of measurement components.
                pub const M: usize = #m;
                /// The declared sensor name.
                pub const NAME: &'static str = #sensor_name;
                /// The index of this sensor in the model's `SENSORS` (declaration order).
                pub const INDEX: usize = #index;
                /// Per state scalar: structurally observable with this sensor alone (its `h`
                /// depends on the state, directly or through the dynamics); see
                /// `docs/language.md`, "Structural observability".
                pub const OBSERVES: [bool; #n] = [#(#observes),*];
                /// Operations in `predict`.
                pub const OPS_PREDICT: usize = #h_ops;
                /// Operations in `jacobian`.
                pub const OPS_JACOBIAN: usize = #j_ops;
                /// Operations in `innovation_terms`.
                pub const OPS_INNOVATION_TERMS: usize = #i_ops;
            }

            #[allow(clippy::possible_missing_comma)]
            impl ::nav_runtime::model::Sensor<#n, #m, #scalar> for #ty {
                type Model = #name;
                type Aux = #aux_ty;
                const NAME: &'static str = #sensor_name;
                const ANGLES: [bool; #m] = [#(#angles),*];
                const JACOBIAN_SPARSITY: [[bool; #n]; #m] = #sparsity;
                const OPS_INNOVATION_TERMS: usize = #i_ops;

                #p_doc
                fn predict(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, aux: &#aux_ty) -> #svec<#scalar, #m> {
                    #h_lets
                    #h_fill
                    out
                }
                #j_doc
                fn jacobian(x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, aux: &#aux_ty) -> #smat<#scalar, #m, #n> {
                    #j_lets
                    #j_fill
                    out
                }
                #i_doc
                fn innovation_terms(
                    cov: &#smat<#scalar, #n, #n>, x: &#svec<#scalar, #n>, u: &#input_ty, p: &#params_ty, aux: &#aux_ty,
                ) -> (#svec<#scalar, #m>, #smat<#scalar, #n, #m>, #smat<#scalar, #m, #m>) {
                    #i_lets
                    let mut h = #svec::<#scalar, #m>::zeros();
                    let mut pht = #smat::<#scalar, #n, #m>::zeros();
                    let mut s = #smat::<#scalar, #m, #m>::zeros();
                    #(#h_sets)*
                    #(#u_sets)*
                    #(#s_sets)*
                    for i in 0..#m {
                        for j in 0..i {
                            s[(i, j)] = s[(j, i)];
                        }
                    }
                    (h, pht, s)
                }
            }
        }
    }

    fn nonzero_vector(&self, body: &Body, ids: &[Id]) -> TokenStream {
        let l = lit(ids.len());
        let scalar = &self.scalar;
        let sets = body
            .exprs
            .iter()
            .zip(ids)
            .enumerate()
            .filter(|(_, (_, &id))| !self.g.is_zero(id))
            .map(|(i, (e, _))| {
                let i = lit(i);
                quote!(out[#i] = #e;)
            });
        quote!(let mut out = ::nav_runtime::nalgebra::SVector::<#scalar, #l>::zeros(); #(#sets)*)
    }

    fn nonzero_matrix(&self, body: &Body, ids: &[Id], rows: usize, cols: usize) -> TokenStream {
        let (r, c) = (lit(rows), lit(cols));
        let scalar = &self.scalar;
        let sets = body
            .exprs
            .iter()
            .zip(ids)
            .enumerate()
            .filter(|(_, (_, &id))| !self.g.is_zero(id))
            .map(|(k, (e, _))| {
                let (i, j) = (lit(k / cols), lit(k % cols));
                quote!(out[(#i, #j)] = #e;)
            });
        quote!(let mut out = ::nav_runtime::nalgebra::SMatrix::<#scalar, #r, #c>::zeros(); #(#sets)*)
    }

    fn symmetric(&self, body: &Body, upper: &[(usize, usize, Id)], n: usize) -> TokenStream {
        let nl = lit(n);
        let scalar = &self.scalar;
        let sets = body
            .exprs
            .iter()
            .zip(upper)
            .filter(|(_, e)| !self.g.is_zero(e.2))
            .map(|(expr, &(i, j, _))| {
                let (i, j) = (lit(i), lit(j));
                quote!(out[(#i, #j)] = #expr;)
            });
        quote! {
            let mut out = ::nav_runtime::nalgebra::SMatrix::<#scalar, #nl, #nl>::zeros();
            #(#sets)*
            for i in 0..#nl {
                for j in 0..i {
                    out[(i, j)] = out[(j, i)];
                }
            }
        }
    }

    /// The structural observability data of the model type: its sensors, what
    /// each one's `h` depends on, the declared sensor sets, and the closure
    /// through the dynamics as a `const fn` (see `front/observability.rs`).
    fn observability_items(&self) -> TokenStream {
        let d = self.d;
        let (n, scalar) = (&self.n, &self.scalar);
        let ns = lit(d.sensors.len());
        let names = self.decl.sensors.iter().map(|s| s.name.to_string());
        let depends = d
            .sensor_depends()
            .into_iter()
            .map(|row| quote!([#(#row),*]));
        let sets = crate::front::observability::run_sets(self.decl);
        let sets_t = sets.iter().map(|set| {
            let set = set.iter().map(|&k| lit(k));
            quote!(&[#(#set),*])
        });
        let per_set = sets.iter().map(|set| {
            let mut on = vec![false; d.sensors.len()];
            for &k in set {
                on[k] = true;
            }
            let row = d.observable_with(&on);
            quote!([#(#row),*])
        });
        let nsets = lit(sets.len());
        // A model without sensors observes nothing (and a loop `while s < 0`
        // would be a lint).
        let observable_body = if d.sensors.is_empty() {
            quote! {
                let _ = sensors;
                [false; #n]
            }
        } else {
            quote! {
                let deps = Self::SENSOR_DEPENDS;
                let f = <Self as ::nav_runtime::model::Model<#n, #scalar>>::JACOBIAN_SPARSITY;
                let mut seen = [false; #n];
                let mut s = 0;
                while s < #ns {
                    if sensors[s] {
                        let mut j = 0;
                        while j < #n {
                            if deps[s][j] {
                                seen[j] = true;
                            }
                            j += 1;
                        }
                    }
                    s += 1;
                }
                let mut changed = true;
                while changed {
                    changed = false;
                    let mut i = 0;
                    while i < #n {
                        if seen[i] {
                            let mut j = 0;
                            while j < #n {
                                if j != i && !seen[j] && f[i][j] {
                                    seen[j] = true;
                                    changed = true;
                                }
                                j += 1;
                            }
                        }
                        i += 1;
                    }
                }
                seen
            }
        };
        quote! {
            /// The sensors, in declaration order (`Sensor::INDEX` of each sensor type).
            pub const SENSORS: [&'static str; #ns] = [#(#names),*];
            /// Per sensor, per state scalar: the sensor's `h` depends on the state
            /// directly (a structural nonzero of its `H`).
            pub const SENSOR_DEPENDS: [[bool; #n]; #ns] = [#(#depends),*];
            /// The sensor sets the model is declared to run with (`runs_with { .. }`, as
            /// indices into `SENSORS`); the set of all sensors when it declares none.
            pub const RUNS_WITH: [&'static [usize]; #nsets] = [#(#sets_t),*];
            /// Per set of `RUNS_WITH`, per state scalar: structurally observable with
            /// that set (checked at compile time against `allow_unused`).
            pub const RUNS_WITH_OBSERVABLE: [[bool; #n]; #nsets] = [#(#per_set),*];
            /// Per state scalar: is it structurally observable with the sensors marked
            /// `true` (indexed like `SENSORS`), i.e. is there a path from the state to
            /// a measurement of one of them, through a sensor's `H` or the dynamics
            /// (`F[i][j] != 0`, `i != j`, of a state `i` on such a path)? Sparsity
            /// only: `false` means no measurement of that set can ever correct the
            /// state; `true` means only that sparsity does not exclude it (see
            /// `docs/language.md`, "Structural observability").
            pub const fn structurally_observable(sensors: &[bool; #ns]) -> [bool; #n] {
                #observable_body
            }
            /// The index in `SENSORS` of the sensor declared as `name`, if any.
            pub fn sensor_index(name: &str) -> ::core::option::Option<usize> {
                Self::SENSORS.iter().position(|s| *s == name)
            }
        }
    }

    fn sparsity(&self, ids: &[Id], rows: usize, cols: usize) -> TokenStream {
        let rows_t = (0..rows).map(|i| {
            let row = (0..cols).map(|j| !self.g.is_zero(ids[i * cols + j]));
            quote!([#(#row),*])
        });
        quote!([#(#rows_t),*])
    }

    fn tests(&self) -> TokenStream {
        super::emit_tests::tests(self.decl, self.d)
    }
}

/// A float literal that round-trips exactly in the model's scalar (`{:?}`
/// is shortest-exact): an `f32` model gets the nearest `f32` of the value,
/// with no digits beyond what `f32` holds.
fn float_literal(v: f64, scalar: Scalar) -> TokenStream {
    let mut s = match scalar {
        Scalar::F64 => format!("{v:?}"),
        // A value beyond f32's range keeps its f64 digits: rustc then
        // reports the literal as out of range for `f32`.
        Scalar::F32 if (v as f32).is_finite() => format!("{:?}", v as f32),
        Scalar::F32 => format!("{v:?}"),
    };
    if !s.contains('.') && !s.contains('e') {
        s.push_str(".0");
    }
    let lit: syn::LitFloat = syn::LitFloat::new(&s, proc_macro2::Span::call_site());
    quote!(#lit)
}

/// `Model::normalize_state` for states declared `angle` or `quaternion`, or
/// nothing (the trait's no-op default) if there are none.
fn normalize_state(states: &[Var], n: &Literal, scalar: Scalar) -> TokenStream {
    let math = scalar.math();
    let scalar = scalar.tokens();
    let mut offset = 0;
    let mut body = TokenStream::new();
    for v in states {
        match v.manifold {
            Manifold::Plain => {}
            Manifold::Angle => body.extend(quote! {
                x[#offset] = #math::wrap_angle(x[#offset]);
            }),
            Manifold::UnitQuaternion => {
                let k: Vec<usize> = (offset..offset + 4).collect();
                body.extend(quote! {
                    {
                        let norm = #math::sqrt(#(x[#k] * x[#k])+*);
                        if norm > 0.0 && norm.is_finite() {
                            let inv = 1.0 / norm;
                            #(x[#k] *= inv;)*
                        }
                    }
                });
            }
        }
        offset += v.shape.len();
    }
    if body.is_empty() {
        return body;
    }
    quote! {
        /// Wraps the `angle` states to (-pi, pi] and renormalizes the
        /// `quaternion` states (see `Model::normalize_state`).
        fn normalize_state(x: &mut ::nav_runtime::nalgebra::SVector<#scalar, #n>) {
            #body
        }
    }
}
