//! Lowering: the declaration becomes scalar nodes of one [`Graph`]. Every value
//! has a shape (scalar, vector, matrix) and is stored as its scalars in row-major
//! order; shape errors, unknown names and unsupported constructs are reported
//! here, each at its own span, and lowering continues past them.

use std::collections::HashMap;

use quote::ToTokens;
use syn::{BinOp, Expr, ExprLit, Lit, UnOp};

use super::ctxt::Ctxt;
use super::names::suggest;
use super::parse::{FnDecl, ModelDecl, SensorDecl, Shape, Stmt, Var};
use crate::symbolic::rotation;
use crate::symbolic::{Func, Graph, Id, Lowered, ProcessKind, Sym};

/// Lowers one checked declaration; `None` if there is no process section.
pub fn lower(cx: &Ctxt, decl: &ModelDecl) -> Option<Lowered> {
    let process = decl.process.as_ref()?;
    let mut graph = Graph::new();
    let mut model_scope = Scope::default();
    model_scope.bind_record(&mut graph, &decl.states, Kind::State, Sym::State);
    model_scope.bind_record(&mut graph, &decl.inputs, Kind::Input, Sym::Input);
    model_scope.bind_record(&mut graph, &decl.params, Kind::Param, Sym::Param);
    model_scope.bind_record(&mut graph, &decl.noise, Kind::Noise, Sym::Noise);
    // Model-level `let`s, seen by the process section and every sensor.
    {
        let mut lw = Lowerer {
            cx,
            g: &mut graph,
            scope: model_scope,
            sensor: None,
            model_let: true,
            functions: &decl.functions,
            calling: Vec::new(),
            process_lets: &[],
            unknown_hint: decl.unknown_hint,
            sensors: &decl.sensors,
        };
        for (name, value) in &decl.lets {
            lw.bind_let(name, value);
        }
        model_scope = lw.scope;
    }

    // The process section.
    let n: usize = decl.states.iter().map(|s| s.shape.len()).sum();
    let mut f: Vec<Id> = (0..n)
        .map(|k| match process.kind {
            ProcessKind::Continuous => Graph::ZERO,
            ProcessKind::Discrete => graph.sym(Sym::State(k as u32)),
        })
        .collect();
    let mut scope = model_scope.clone();
    if process.kind == ProcessKind::Discrete {
        let dt = graph.sym(Sym::Dt);
        scope.insert(
            "dt",
            Binding {
                val: Val::scalar(dt),
                kind: Kind::Dt,
            },
        );
    }
    let mut process_lets = Vec::new();
    {
        let mut lw = Lowerer {
            cx,
            g: &mut graph,
            scope,
            sensor: None,
            model_let: false,
            functions: &decl.functions,
            calling: Vec::new(),
            process_lets: &[],
            unknown_hint: decl.unknown_hint,
            sensors: &decl.sensors,
        };
        for stmt in &process.stmts {
            match stmt {
                Stmt::Let { name, value } => {
                    if let Some(val) = lw.expr(value) {
                        lw.scope.insert_new(
                            &name.to_string(),
                            Binding {
                                val,
                                kind: Kind::Let,
                            },
                        );
                    } else {
                        lw.scope.failed.push(name.to_string());
                    }
                    process_lets.push(name.to_string());
                }
                Stmt::Assign {
                    target,
                    derivative,
                    value,
                } => {
                    let Some(val) = lw.expr(value) else { continue };
                    let Some((offset, state)) = state_offset(&decl.states, target) else {
                        continue;
                    };
                    if val.shape != state.shape {
                        let what = if derivative.is_some() {
                            format!("d/dt {target}")
                        } else {
                            target.to_string()
                        };
                        cx.error_spanned_by(
                            value,
                            format!(
                                "`{what}` must be a {}, but the expression is a {}",
                                state.shape, val.shape
                            ),
                        );
                        continue;
                    }
                    f[offset..offset + val.e.len()].copy_from_slice(&val.e);
                }
            }
        }
    }

    // The sensors.
    let mut sensors = Vec::new();
    for (si, sensor) in decl.sensors.iter().enumerate() {
        let mut scope = model_scope.clone();
        let si = si as u32;
        scope.bind_record(&mut graph, &sensor.inputs, Kind::Aux, |k| Sym::Aux(si, k));
        let mut lw = Lowerer {
            cx,
            g: &mut graph,
            scope,
            sensor: Some(sensor),
            model_let: false,
            functions: &decl.functions,
            calling: Vec::new(),
            process_lets: &process_lets,
            unknown_hint: decl.unknown_hint,
            sensors: &decl.sensors,
        };
        for (name, value) in &sensor.lets {
            if let Some(val) = lw.expr(value) {
                lw.scope.insert_new(
                    &name.to_string(),
                    Binding {
                        val,
                        kind: Kind::Let,
                    },
                );
            } else {
                lw.scope.failed.push(name.to_string());
            }
        }
        let mut h = vec![Graph::ZERO; sensor.dim];
        if let Some((_, value)) = &sensor.h {
            if let Some(val) = lw.expr(value) {
                let ok = match val.shape {
                    Shape::Scalar => sensor.dim == 1,
                    Shape::Vector(m) => m == sensor.dim,
                    Shape::Matrix(..) => false,
                };
                if ok {
                    h = val.e;
                } else {
                    cx.error_spanned_by(
                        value,
                        format!(
                            "sensor `{}` declares {} output{} but `h` is a {}",
                            sensor.name,
                            sensor.dim,
                            if sensor.dim == 1 { "" } else { "s" },
                            val.shape
                        ),
                    );
                }
            }
        }
        sensors.push(h);
    }
    Some(Lowered {
        graph,
        kind: process.kind,
        f,
        sensors,
    })
}

fn state_offset<'a>(states: &'a [Var], target: &syn::Ident) -> Option<(usize, &'a Var)> {
    let mut offset = 0;
    for s in states {
        if s.name == *target {
            return Some((offset, s));
        }
        offset += s.shape.len();
    }
    None
}

/// A value: its shape and its scalars, row-major.
#[derive(Clone, Debug)]
pub struct Val {
    pub shape: Shape,
    pub e: Vec<Id>,
}

impl Val {
    fn scalar(id: Id) -> Val {
        Val {
            shape: Shape::Scalar,
            e: vec![id],
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    State,
    Input,
    Param,
    Noise,
    Aux,
    Let,
    Dt,
}

#[derive(Clone)]
struct Binding {
    val: Val,
    kind: Kind,
}

#[derive(Clone, Default)]
struct Scope {
    names: HashMap<String, Binding>,
    /// `let`s whose value had errors: their uses report nothing more.
    failed: Vec<String>,
}

impl Scope {
    fn bind_record(&mut self, g: &mut Graph, vars: &[Var], kind: Kind, sym: impl Fn(u32) -> Sym) {
        let mut k = 0u32;
        for v in vars {
            let e = (0..v.shape.len())
                .map(|_| {
                    k += 1;
                    g.sym(sym(k - 1))
                })
                .collect();
            self.insert_new(
                &v.name.to_string(),
                Binding {
                    val: Val { shape: v.shape, e },
                    kind,
                },
            );
        }
    }

    fn insert(&mut self, name: &str, b: Binding) {
        self.names.insert(name.to_string(), b);
    }

    /// Binds `name` unless taken (duplicates were reported by the checker).
    fn insert_new(&mut self, name: &str, b: Binding) {
        self.names.entry(name.to_string()).or_insert(b);
    }
}

/// The built-in functions of the expression language.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Builtin {
    Scalar(Func),
    Atan2,
    Powi,
    Dot,
    Cross,
    Skew,
    NormSquared,
    Norm,
    Transpose,
    EulerDcm,
    Min,
    Max,
    Clamp,
    QuatMul,
    QuatToDcm,
    DcmToEuler,
    RotvecToQuat,
    Normalize,
    /// WGS-84 meridian radius of curvature at a latitude.
    MeridianRadius,
    /// WGS-84 transverse (prime vertical) radius of curvature.
    TransverseRadius,
}

/// WGS-84 semi-major axis, m.
const WGS84_A: f64 = 6378137.0;
/// WGS-84 first eccentricity squared.
const WGS84_E2: f64 = 0.0066943799901413165;

const BUILTINS: &[(&str, Builtin, usize)] = &[
    ("sin", Builtin::Scalar(Func::Sin), 1),
    ("cos", Builtin::Scalar(Func::Cos), 1),
    ("tan", Builtin::Scalar(Func::Tan), 1),
    ("asin", Builtin::Scalar(Func::Asin), 1),
    ("acos", Builtin::Scalar(Func::Acos), 1),
    ("atan", Builtin::Scalar(Func::Atan), 1),
    ("sqrt", Builtin::Scalar(Func::Sqrt), 1),
    ("exp", Builtin::Scalar(Func::Exp), 1),
    ("ln", Builtin::Scalar(Func::Ln), 1),
    ("abs", Builtin::Scalar(Func::Abs), 1),
    ("sign", Builtin::Scalar(Func::Sign), 1),
    ("min", Builtin::Min, 2),
    ("max", Builtin::Max, 2),
    ("clamp", Builtin::Clamp, 3),
    ("quat_mul", Builtin::QuatMul, 2),
    ("quat_to_dcm", Builtin::QuatToDcm, 1),
    ("dcm_to_euler", Builtin::DcmToEuler, 1),
    ("rotvec_to_quat", Builtin::RotvecToQuat, 1),
    ("normalize", Builtin::Normalize, 1),
    ("atan2", Builtin::Atan2, 2),
    ("powi", Builtin::Powi, 2),
    ("dot", Builtin::Dot, 2),
    ("cross", Builtin::Cross, 2),
    ("skew", Builtin::Skew, 1),
    ("norm_squared", Builtin::NormSquared, 1),
    ("norm", Builtin::Norm, 1),
    ("transpose", Builtin::Transpose, 1),
    ("euler_dcm", Builtin::EulerDcm, 3),
    ("meridian_radius", Builtin::MeridianRadius, 1),
    ("transverse_radius", Builtin::TransverseRadius, 1),
];

/// Whether `name` is a builtin function.
pub fn is_builtin(name: &str) -> bool {
    BUILTINS.iter().any(|(n, ..)| *n == name)
}

struct Lowerer<'a> {
    cx: &'a Ctxt,
    g: &'a mut Graph,
    scope: Scope,
    /// The sensor being lowered, or `None` in the process section.
    sensor: Option<&'a SensorDecl>,
    /// Lowering a model-level `let` (which may not read process noise).
    model_let: bool,
    /// The model's functions, and those being inlined (to refuse recursion).
    functions: &'a [FnDecl],
    calling: Vec<String>,
    /// Names of the process section's `let`s (for hints in sensors).
    process_lets: &'a [String],
    /// The model's sensors (for hints about another sensor's `let`s).
    sensors: &'a [SensorDecl],
    /// Appended to unknown-name errors without a suggestion (blocks: about `needs`).
    unknown_hint: &'static str,
}

impl Lowerer<'_> {
    /// `let name = value;`: binds the value, or records the name as failed so
    /// its uses report nothing more.
    fn bind_let(&mut self, name: &syn::Ident, value: &Expr) {
        if let Some(val) = self.expr(value) {
            self.scope.insert_new(
                &name.to_string(),
                Binding {
                    val,
                    kind: Kind::Let,
                },
            );
        } else {
            self.scope.failed.push(name.to_string());
        }
    }

    fn expr(&mut self, e: &Expr) -> Option<Val> {
        match e {
            Expr::Lit(ExprLit { lit, .. }) => {
                let v = match lit {
                    Lit::Int(i) => i.base10_parse::<u64>().ok().map(|v| v as f64),
                    Lit::Float(f) => f.base10_parse::<f64>().ok(),
                    _ => None,
                };
                match v {
                    Some(v) => Some(Val::scalar(self.g.constant(v))),
                    None => self.fail(e, "only numeric literals are supported"),
                }
            }
            Expr::Path(p) => match p.path.get_ident() {
                Some(ident) if p.qself.is_none() => self.ident(ident),
                _ => self.fail(e, "paths are not supported: use a declared name"),
            },
            Expr::Paren(p) => self.expr(&p.expr),
            Expr::Group(g) => self.expr(&g.expr),
            Expr::Unary(u) => match u.op {
                UnOp::Neg(_) => {
                    let v = self.expr(&u.expr)?;
                    Some(self.map(&v, |g, a| g.neg(a)))
                }
                _ => self.fail(
                    e,
                    format!(
                        "the unary operator `{}` is not supported",
                        u.op.to_token_stream()
                    ),
                ),
            },
            Expr::Binary(b) => self.binary(e, &b.op, &b.left, &b.right),
            Expr::Call(call) => {
                let name = match &*call.func {
                    Expr::Path(p) if p.qself.is_none() => p.path.get_ident(),
                    _ => None,
                };
                let Some(name) = name else {
                    return self.fail(
                        &call.func,
                        "only calls of the built-in functions are supported",
                    );
                };
                let args: Vec<&Expr> = call.args.iter().collect();
                self.call(e, name, &args)
            }
            Expr::MethodCall(m) => {
                if m.turbofish.is_some() {
                    return self.fail(e, "generic arguments are not supported");
                }
                let args: Vec<&Expr> = std::iter::once(&*m.receiver).chain(m.args.iter()).collect();
                self.call(e, &m.method, &args)
            }
            Expr::Array(arr) => {
                let elems: Vec<Option<Val>> = arr.elems.iter().map(|x| self.expr(x)).collect();
                let elems: Vec<Val> = elems.into_iter().collect::<Option<_>>()?;
                self.array(e, elems)
            }
            Expr::Index(ix) => {
                let base = self.expr(&ix.expr)?;
                self.index(e, base, &ix.index)
            }
            _ => self.fail(e, unsupported(e)),
        }
    }

    fn fail<T: ToTokens, M: std::fmt::Display>(&self, at: T, msg: M) -> Option<Val> {
        self.cx.error_spanned_by(at, msg);
        None
    }

    fn ident(&mut self, ident: &syn::Ident) -> Option<Val> {
        let name = ident.to_string();
        let Some(b) = self.scope.names.get(&name) else {
            if self.scope.failed.contains(&name) {
                return None;
            }
            let hint = if name == "dt" {
                if self.sensor.is_some() {
                    "; `dt` is not available in sensors".to_string()
                } else {
                    "; `dt` is only available in `discrete` sections (a continuous model gives `d/dt`)".to_string()
                }
            } else if let Some(f) = self.calling.last() {
                format!("; the body of model function `{f}` sees only its parameters (pass `{name}` as an argument)")
            } else if self.sensor.is_some() && self.process_lets.contains(&name) {
                format!("; `{name}` is a `let` of the process section, which sensors do not see (move it to the model level, beside the sections, to share it)")
            } else if let Some(owner) = self.sensors.iter().find(|s| {
                !matches!(self.sensor, Some(current) if current.name == s.name)
                    && s.lets.iter().any(|(n, _)| *n == name)
            }) {
                let here = if self.sensor.is_some() {
                    "other sensors do not see it"
                } else {
                    "the process section does not see it"
                };
                format!(
                    "; `{name}` is a `let` of sensor `{}`: {here} (move it to the model level, beside the sections, to share it)",
                    owner.name
                )
            } else {
                let mut cands: Vec<String> = self.scope.names.keys().cloned().collect();
                cands.sort();
                let hint = suggest(&name, cands);
                if hint.is_empty() {
                    self.unknown_hint.to_string()
                } else {
                    hint
                }
            };
            return self.fail(ident, format!("unknown name `{name}`{hint}"));
        };
        if b.kind == Kind::Noise && self.model_let {
            return self.fail(
                ident,
                format!(
                    "process noise `{name}` cannot be used in a model-level `let`, which the sensors see too: \
                     use it in the process section"
                ),
            );
        }
        if b.kind == Kind::Noise {
            if let Some(sensor) = self.sensor {
                return self.fail(
                    ident,
                    format!(
                        "process noise `{name}` cannot be used in sensor `{}`: noise inputs may appear only in the \
                         process equations",
                        sensor.name
                    ),
                );
            }
        }
        Some(b.val.clone())
    }

    fn map(&mut self, v: &Val, f: impl Fn(&mut Graph, Id) -> Id) -> Val {
        Val {
            shape: v.shape,
            e: v.e.iter().map(|&a| f(self.g, a)).collect(),
        }
    }

    fn binary(&mut self, e: &Expr, op: &BinOp, l: &Expr, r: &Expr) -> Option<Val> {
        let (verb, prep) = match op {
            BinOp::Add(_) => ("add", "and"),
            BinOp::Sub(_) => ("subtract", "and"),
            BinOp::Mul(_) => ("multiply", "by"),
            BinOp::Div(_) => ("divide", "by"),
            BinOp::BitXor(_) => {
                return self.fail(
                    op,
                    "`^` is exclusive or in Rust, not a power: write `powi(x, 2)` (or `x.powi(2)`) for a square",
                );
            }
            _ => {
                return self.fail(
                    op,
                    format!("the operator `{}` is not supported", op.to_token_stream()),
                );
            }
        };
        let (lv, rv) = (self.expr(l), self.expr(r));
        let (lv, rv) = (lv?, rv?);
        let g = &mut *self.g;
        let elementwise = |g: &mut Graph, f: fn(&mut Graph, Id, Id) -> Id| Val {
            shape: lv.shape,
            e: lv.e.iter().zip(&rv.e).map(|(&a, &b)| f(g, a, b)).collect(),
        };
        let result = match (op, lv.shape, rv.shape) {
            (BinOp::Add(_), a, b) if a == b => Some(elementwise(g, Graph::add)),
            (BinOp::Sub(_), a, b) if a == b => Some(elementwise(g, Graph::sub)),
            (BinOp::Mul(_), Shape::Scalar, _) => {
                let s = lv.e[0];
                Some(Val {
                    shape: rv.shape,
                    e: rv.e.iter().map(|&b| g.mul(s, b)).collect(),
                })
            }
            (BinOp::Mul(_), _, Shape::Scalar) => {
                let s = rv.e[0];
                Some(Val {
                    shape: lv.shape,
                    e: lv.e.iter().map(|&a| g.mul(a, s)).collect(),
                })
            }
            (BinOp::Div(_), _, Shape::Scalar) => {
                let s = rv.e[0];
                Some(Val {
                    shape: lv.shape,
                    e: lv.e.iter().map(|&a| g.div(a, s)).collect(),
                })
            }
            (BinOp::Mul(_), Shape::Matrix(r, c), Shape::Vector(n)) if c == n => Some(Val {
                shape: Shape::Vector(r),
                e: matmul(g, &lv.e, &rv.e, r, c, 1),
            }),
            (BinOp::Mul(_), Shape::Matrix(r, c), Shape::Matrix(c2, k)) if c == c2 => Some(Val {
                shape: Shape::Matrix(r, k),
                e: matmul(g, &lv.e, &rv.e, r, c, k),
            }),
            _ => None,
        };
        if result.is_none() {
            let hint = match (op, lv.shape, rv.shape) {
                (BinOp::Mul(_), Shape::Vector(_), Shape::Vector(_)) => {
                    "; use `dot(a, b)` for the inner product or `cross(a, b)` for the cross product"
                }
                (BinOp::Mul(_), Shape::Vector(_), Shape::Matrix(..)) => {
                    "; write `transpose(m) * v` instead"
                }
                (BinOp::Div(_), _, _) => "; only division by a scalar is supported",
                (BinOp::Add(_) | BinOp::Sub(_), _, _) => "; both operands must have the same shape",
                _ => "",
            };
            self.cx.error_spanned_by(
                e,
                format!("cannot {verb} {} {prep} {}{hint}", lv.shape, rv.shape),
            );
        }
        result
    }

    fn call(&mut self, e: &Expr, name: &syn::Ident, args: &[&Expr]) -> Option<Val> {
        let fname = name.to_string();
        if let Some(f) = self.functions.iter().find(|f| f.name == fname) {
            return self.inline(e, f, args);
        }
        let Some(&(_, builtin, arity)) = BUILTINS.iter().find(|(n, ..)| *n == fname) else {
            let hint = suggest(&fname, BUILTINS.iter().map(|(n, ..)| n.to_string()));
            return self.fail(name, format!("unknown function `{fname}`{hint}"));
        };
        if args.len() != arity {
            return self.fail(
                e,
                format!(
                    "`{fname}` takes {arity} argument{}, found {}",
                    if arity == 1 { "" } else { "s" },
                    args.len()
                ),
            );
        }
        if builtin == Builtin::Powi {
            let base = self.expr(args[0]);
            let Some(n) = int_literal(args[1]) else {
                return self.fail(args[1], "the exponent of `powi` must be an integer literal");
            };
            let base = self.scalar_arg(&fname, args[0], base?)?;
            return Some(Val::scalar(self.g.powi(base, n)));
        }
        let vals: Vec<Option<Val>> = args.iter().map(|a| self.expr(a)).collect();
        let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
        let g = &mut *self.g;
        match builtin {
            Builtin::Scalar(f) => {
                let a = self.scalar_arg(&fname, args[0], vals[0].clone())?;
                Some(Val::scalar(self.g.call(f, a)))
            }
            Builtin::Atan2 => {
                let y = self.scalar_arg(&fname, args[0], vals[0].clone());
                let x = self.scalar_arg(&fname, args[1], vals[1].clone());
                Some(Val::scalar(self.g.atan2(y?, x?)))
            }
            Builtin::Powi => unreachable!("handled above"),
            Builtin::Min | Builtin::Max | Builtin::Clamp => {
                let xs: Vec<Option<Id>> = args
                    .iter()
                    .zip(&vals)
                    .map(|(a, v)| self.scalar_arg(&fname, a, v.clone()))
                    .collect();
                let xs: Vec<Id> = xs.into_iter().collect::<Option<_>>()?;
                let g = &mut *self.g;
                Some(Val::scalar(match builtin {
                    Builtin::Min => g.min(xs[0], xs[1]),
                    Builtin::Max => g.max(xs[0], xs[1]),
                    _ => {
                        let low = g.max(xs[0], xs[1]);
                        g.min(low, xs[2])
                    }
                }))
            }
            Builtin::Dot => match (vals[0].shape, vals[1].shape) {
                (Shape::Vector(a), Shape::Vector(b)) if a == b => {
                    let terms: Vec<Id> = vals[0]
                        .e
                        .iter()
                        .zip(&vals[1].e)
                        .map(|(&x, &y)| g.mul(x, y))
                        .collect();
                    Some(Val::scalar(g.sum(terms)))
                }
                (a, b) => self.fail(
                    e,
                    format!("`dot` needs two vectors of the same length, found {a} and {b}"),
                ),
            },
            Builtin::Cross => match (vals[0].shape, vals[1].shape) {
                (Shape::Vector(3), Shape::Vector(3)) => {
                    let (a, b) = (&vals[0].e, &vals[1].e);
                    let e = (0..3)
                        .map(|i| {
                            let (j, k) = ((i + 1) % 3, (i + 2) % 3);
                            let l = g.mul(a[j], b[k]);
                            let r = g.mul(a[k], b[j]);
                            g.sub(l, r)
                        })
                        .collect();
                    Some(Val {
                        shape: Shape::Vector(3),
                        e,
                    })
                }
                (a, b) => self.fail(e, format!("`cross` needs two 3-vectors, found {a} and {b}")),
            },
            Builtin::Skew => match vals[0].shape {
                Shape::Vector(3) => {
                    let v = &vals[0].e;
                    let z = Graph::ZERO;
                    let n: Vec<Id> = v.iter().map(|&a| g.neg(a)).collect();
                    let e = vec![z, n[2], v[1], v[2], z, n[0], n[1], v[0], z];
                    Some(Val {
                        shape: Shape::Matrix(3, 3),
                        e,
                    })
                }
                a => self.fail(args[0], format!("`skew` needs a 3-vector, found {a}")),
            },
            Builtin::NormSquared | Builtin::Norm => match vals[0].shape {
                Shape::Vector(_) => {
                    let terms: Vec<Id> = vals[0].e.iter().map(|&x| g.mul(x, x)).collect();
                    let s = g.sum(terms);
                    let s = if builtin == Builtin::Norm {
                        g.call(Func::Sqrt, s)
                    } else {
                        s
                    };
                    Some(Val::scalar(s))
                }
                a => self.fail(args[0], format!("`{fname}` needs a vector, found {a}")),
            },
            Builtin::Transpose => match vals[0].shape {
                Shape::Matrix(r, c) => {
                    let m = &vals[0].e;
                    let e = (0..c)
                        .flat_map(|j| (0..r).map(move |i| m[i * c + j]))
                        .collect();
                    Some(Val {
                        shape: Shape::Matrix(c, r),
                        e,
                    })
                }
                a => self.fail(args[0], format!("`transpose` needs a matrix, found {a}")),
            },
            Builtin::QuatMul => match (vals[0].shape, vals[1].shape) {
                (Shape::Vector(4), Shape::Vector(4)) => Some(Val {
                    shape: Shape::Vector(4),
                    e: rotation::quat_mul(g, &vals[0].e, &vals[1].e),
                }),
                (a, b) => self.fail(
                    e,
                    format!("`quat_mul` needs two quaternions (4-vectors [w, x, y, z]), found {a} and {b}"),
                ),
            },
            Builtin::QuatToDcm => match vals[0].shape {
                Shape::Vector(4) => Some(Val {
                    shape: Shape::Matrix(3, 3),
                    e: rotation::quat_to_dcm(g, &vals[0].e),
                }),
                a => self.fail(
                    args[0],
                    format!("`quat_to_dcm` needs a quaternion (4-vector [w, x, y, z]), found {a}"),
                ),
            },
            Builtin::DcmToEuler => match vals[0].shape {
                Shape::Matrix(3, 3) => Some(Val {
                    shape: Shape::Vector(3),
                    e: rotation::dcm_to_euler(g, &vals[0].e),
                }),
                a => self.fail(
                    args[0],
                    format!("`dcm_to_euler` needs a 3x3 matrix `C_b^n`, found {a}"),
                ),
            },
            Builtin::RotvecToQuat => match vals[0].shape {
                Shape::Vector(3) => Some(Val {
                    shape: Shape::Vector(4),
                    e: rotation::rotvec_to_quat(g, &vals[0].e),
                }),
                a => self.fail(
                    args[0],
                    format!("`rotvec_to_quat` needs a rotation vector (3-vector, rad), found {a}"),
                ),
            },
            Builtin::Normalize => match vals[0].shape {
                Shape::Vector(_) => {
                    let terms: Vec<Id> = vals[0].e.iter().map(|&x| g.mul(x, x)).collect();
                    let s = g.sum(terms);
                    let norm = g.call(Func::Sqrt, s);
                    Some(self.map(&vals[0].clone(), |g, x| g.div(x, norm)))
                }
                a => self.fail(args[0], format!("`normalize` needs a vector, found {a}")),
            },
            Builtin::MeridianRadius | Builtin::TransverseRadius => {
                let lat = self.scalar_arg(&fname, args[0], vals[0].clone())?;
                let g = &mut *self.g;
                // k = 1 - e2 sin^2(lat); R_M = a (1 - e2) / k^1.5, R_N = a / sqrt(k),
                // built as the blocks wrote them, so the graph is the same.
                let (a, e2, one) = (g.constant(WGS84_A), g.constant(WGS84_E2), g.constant(1.0));
                let s = g.call(Func::Sin, lat);
                let es = g.mul(e2, s);
                let ess = g.mul(es, s);
                let k = g.sub(one, ess);
                let root = g.call(Func::Sqrt, k);
                Some(Val::scalar(if builtin == Builtin::MeridianRadius {
                    let one_minus_e2 = g.sub(one, e2);
                    let numerator = g.mul(a, one_minus_e2);
                    let k_root = g.mul(k, root);
                    g.div(numerator, k_root)
                } else {
                    g.div(a, root)
                }))
            }
            Builtin::EulerDcm => {
                let r = self.scalar_arg(&fname, args[0], vals[0].clone());
                let p = self.scalar_arg(&fname, args[1], vals[1].clone());
                let y = self.scalar_arg(&fname, args[2], vals[2].clone());
                Some(Val {
                    shape: Shape::Matrix(3, 3),
                    e: euler_dcm(self.g, r?, p?, y?),
                })
            }
        }
    }

    /// A call of a model function: its body lowered in a scope of its
    /// parameters bound to the arguments.
    fn inline(&mut self, e: &Expr, f: &FnDecl, args: &[&Expr]) -> Option<Val> {
        let fname = f.name.to_string();
        if args.len() != f.params.len() {
            let n = f.params.len();
            return self.fail(
                e,
                format!(
                    "`{fname}` takes {n} argument{}, found {}",
                    if n == 1 { "" } else { "s" },
                    args.len()
                ),
            );
        }
        if self.calling.contains(&fname) {
            return self.fail(
                e,
                format!("`{fname}` calls itself: model functions cannot be recursive"),
            );
        }
        let vals: Vec<Option<Val>> = args.iter().map(|a| self.expr(a)).collect();
        let vals: Vec<Val> = vals.into_iter().collect::<Option<_>>()?;
        let mut scope = Scope::default();
        for (p, val) in f.params.iter().zip(vals) {
            scope.insert(
                &p.to_string(),
                Binding {
                    val,
                    kind: Kind::Let,
                },
            );
        }
        let outer = std::mem::replace(&mut self.scope, scope);
        self.calling.push(fname);
        let out = self.expr(&f.body);
        self.calling.pop();
        self.scope = outer;
        out
    }

    fn scalar_arg(&self, fname: &str, at: &Expr, v: Val) -> Option<Id> {
        if v.shape == Shape::Scalar {
            Some(v.e[0])
        } else {
            self.cx.error_spanned_by(
                at,
                format!("`{fname}` expects a scalar argument, found a {}", v.shape),
            );
            None
        }
    }

    fn array(&mut self, e: &Expr, elems: Vec<Val>) -> Option<Val> {
        let Some(first) = elems.first() else {
            return self.fail(e, "empty vector literal");
        };
        match first.shape {
            Shape::Scalar if elems.iter().all(|v| v.shape == Shape::Scalar) => Some(Val {
                shape: Shape::Vector(elems.len()),
                e: elems.iter().map(|v| v.e[0]).collect(),
            }),
            Shape::Vector(n) if elems.iter().all(|v| v.shape == Shape::Vector(n)) => Some(Val {
                shape: Shape::Matrix(elems.len(), n),
                e: elems.into_iter().flat_map(|v| v.e).collect(),
            }),
            _ => {
                let shapes: Vec<String> = elems.iter().map(|v| v.shape.to_string()).collect();
                self.fail(
                    e,
                    format!(
                        "a vector literal needs scalars and a matrix literal rows of equal length, found [{}]",
                        shapes.join(", ")
                    ),
                )
            }
        }
    }

    fn index(&mut self, e: &Expr, base: Val, index: &Expr) -> Option<Val> {
        let index = strip_parens(index);
        match (base.shape, index) {
            (Shape::Vector(n), Expr::Lit(_)) => {
                let Some(i) = usize_literal(index) else {
                    return self.fail(index, "indices must be integer literals");
                };
                if i >= n {
                    return self.fail(
                        index,
                        format!("index {i} is out of range for a {}", base.shape),
                    );
                }
                Some(Val::scalar(base.e[i]))
            }
            (Shape::Matrix(r, c), Expr::Tuple(t)) if t.elems.len() == 2 => {
                let (Some(i), Some(j)) = (usize_literal(&t.elems[0]), usize_literal(&t.elems[1]))
                else {
                    return self.fail(index, "indices must be integer literals");
                };
                if i >= r || j >= c {
                    return self.fail(
                        index,
                        format!("index ({i}, {j}) is out of range for a {}", base.shape),
                    );
                }
                Some(Val::scalar(base.e[i * c + j]))
            }
            (Shape::Matrix(..), _) => self.fail(
                index,
                "index a matrix with `m[(row, column)]` (integer literals)",
            ),
            (Shape::Vector(_), _) => {
                self.fail(index, "index a vector with `v[i]` (an integer literal)")
            }
            (Shape::Scalar, _) => self.fail(e, "cannot index a scalar"),
        }
    }
}

/// `C_b^n` from roll, pitch, yaw (Z-Y-X), the transpose of
/// `C_n^b = C_x(roll) C_y(pitch) C_z(yaw)` (see `docs/language.md`).
fn euler_dcm(g: &mut Graph, roll: Id, pitch: Id, yaw: Id) -> Vec<Id> {
    let (sf, cf) = (g.call(Func::Sin, roll), g.call(Func::Cos, roll));
    let (st, ct) = (g.call(Func::Sin, pitch), g.call(Func::Cos, pitch));
    let (sp, cp) = (g.call(Func::Sin, yaw), g.call(Func::Cos, yaw));
    let mut m = |a: Id, b: Id| g.mul(a, b);
    let ctcp = m(ct, cp);
    let ctsp = m(ct, sp);
    let sfst = m(sf, st);
    let cfst = m(cf, st);
    let sfstcp = m(sfst, cp);
    let cfsp = m(cf, sp);
    let sfstsp = m(sfst, sp);
    let cfcp = m(cf, cp);
    let sfct = m(sf, ct);
    let cfstcp = m(cfst, cp);
    let sfsp = m(sf, sp);
    let cfstsp = m(cfst, sp);
    let sfcp = m(sf, cp);
    let cfct = m(cf, ct);
    let r1c0 = g.sub(sfstcp, cfsp);
    let r1c1 = g.add(sfstsp, cfcp);
    let r2c0 = g.add(cfstcp, sfsp);
    let r2c1 = g.sub(cfstsp, sfcp);
    let nst = g.neg(st);
    // C_n^b rows: [ctcp, ctsp, -st], [r1c0, r1c1, sfct], [r2c0, r2c1, cfct]; transposed:
    vec![ctcp, r1c0, r2c0, ctsp, r1c1, r2c1, nst, sfct, cfct]
}

/// Row-major product of an r x c and a c x k matrix.
fn matmul(g: &mut Graph, a: &[Id], b: &[Id], r: usize, c: usize, k: usize) -> Vec<Id> {
    let mut out = Vec::with_capacity(r * k);
    for i in 0..r {
        for j in 0..k {
            let terms: Vec<Id> = (0..c).map(|l| g.mul(a[i * c + l], b[l * k + j])).collect();
            out.push(g.sum(terms));
        }
    }
    out
}

fn strip_parens(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip_parens(&p.expr),
        Expr::Group(g) => strip_parens(&g.expr),
        _ => e,
    }
}

fn usize_literal(e: &Expr) -> Option<usize> {
    match strip_parens(e) {
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse().ok(),
        _ => None,
    }
}

fn int_literal(e: &Expr) -> Option<i32> {
    match strip_parens(e) {
        Expr::Lit(ExprLit {
            lit: Lit::Int(i), ..
        }) => i.base10_parse().ok(),
        Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => int_literal(&u.expr).map(|n| -n),
        _ => None,
    }
}

/// The message for an expression form the language does not have.
fn unsupported(e: &Expr) -> String {
    let what = match e {
        Expr::If(_) => "`if` expressions are not supported: a model is straight-line arithmetic",
        Expr::ForLoop(_) | Expr::While(_) | Expr::Loop(_) => {
            "loops are not supported: a model is straight-line arithmetic (write the components out)"
        }
        Expr::Closure(_) => "closures are not supported",
        Expr::Match(_) => "`match` expressions are not supported",
        Expr::Block(_) | Expr::Unsafe(_) => "blocks are not supported",
        Expr::Macro(_) => "macro calls are not supported",
        Expr::Assign(_) => "assignments inside expressions are not supported",
        Expr::Field(_) => "field access is not supported: index vectors with `v[i]`",
        Expr::Cast(_) => "`as` casts are not supported",
        Expr::Tuple(_) => "tuples are not supported: use a vector literal `[a, b]`",
        Expr::Range(_) => "ranges are not supported",
        Expr::Reference(_) => "references are not supported",
        Expr::Return(_) | Expr::Break(_) | Expr::Continue(_) => "control flow is not supported",
        Expr::Struct(_) => "struct literals are not supported",
        Expr::Repeat(_) => "repeat arrays `[x; n]` are not supported",
        Expr::Try(_) => "the `?` operator is not supported",
        _ => "this expression is not supported",
    };
    what.to_string()
}
