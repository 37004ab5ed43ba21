//! Syntax: the declaration as written, parsed with syn into this crate's small
//! AST. Nothing is validated here beyond the grammar (see `check.rs`).

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::{braced, bracketed, Attribute, Expr, Ident, LitInt, Token, Visibility};

/// Everything inside one `model! { .. }` invocation.
pub struct Declarations {
    pub models: Vec<ModelDecl>,
}

/// `pub model Foo { .. }`.
pub struct ModelDecl {
    /// Doc comments (and other outer attributes) of the model.
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    pub states: Vec<Var>,
    pub inputs: Vec<Var>,
    pub params: Vec<Var>,
    pub noise: Vec<Var>,
    pub process: Option<Process>,
    pub sensors: Vec<SensorDecl>,
}

/// A declared name with its shape: `x`, `x: 3`, `x: 3x3`.
pub struct Var {
    pub attrs: Vec<Attribute>,
    pub name: Ident,
    pub shape: Shape,
    /// The tokens of the shape, for error spans (the name's span if scalar).
    pub shape_span: Span,
}

/// Shapes of declared names and of expression values.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    Scalar,
    Vector(usize),
    Matrix(usize, usize),
}

impl Shape {
    /// Number of scalars.
    pub fn len(self) -> usize {
        match self {
            Shape::Scalar => 1,
            Shape::Vector(n) => n,
            Shape::Matrix(r, c) => r * c,
        }
    }
}

impl std::fmt::Display for Shape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Shape::Scalar => write!(f, "scalar"),
            Shape::Vector(n) => write!(f, "{n}-vector"),
            Shape::Matrix(r, c) => write!(f, "{r}x{c} matrix"),
        }
    }
}

/// Continuous (`d/dt x = ..`) or discrete (`x = ..` from the previous values).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ProcessKind {
    Continuous,
    Discrete,
}

/// The `continuous { .. }` or `discrete { .. }` section.
pub struct Process {
    pub kind: ProcessKind,
    pub keyword: Ident,
    pub stmts: Vec<Stmt>,
}

/// One statement of a process or sensor body.
pub enum Stmt {
    /// `let name = value;`
    Let { name: Ident, value: Expr },
    /// `d/dt target = value;` (`derivative`) or `target = value;`.
    Assign {
        target: Ident,
        derivative: Option<Span>,
        value: Expr,
    },
}

/// `sensor Name: M { .. }`.
pub struct SensorDecl {
    pub attrs: Vec<Attribute>,
    pub name: Ident,
    pub dim: usize,
    pub dim_lit: LitInt,
    pub inputs: Vec<Var>,
    /// `angles = [i, ..];` with the keyword for spans.
    pub angles: Option<(Ident, Vec<LitInt>)>,
    /// `let` statements, in order.
    pub lets: Vec<(Ident, Expr)>,
    /// `h = expr;` with the `h` token for spans.
    pub h: Option<(Ident, Expr)>,
    /// Other assignments in a sensor body (rejected by the checker).
    pub stray: Vec<Ident>,
}

impl Parse for Declarations {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let mut models = Vec::new();
        while !input.is_empty() {
            models.push(input.parse()?);
        }
        Ok(Declarations { models })
    }
}

impl Parse for ModelDecl {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        keyword(input, "model")?;
        let name: Ident = input.parse()?;
        let body;
        braced!(body in input);
        let mut decl = ModelDecl {
            attrs,
            vis,
            name,
            states: Vec::new(),
            inputs: Vec::new(),
            params: Vec::new(),
            noise: Vec::new(),
            process: None,
            sensors: Vec::new(),
        };
        let mut seen: Vec<String> = Vec::new();
        while !body.is_empty() {
            let attrs = body.call(Attribute::parse_outer)?;
            let kw: Ident = body.parse()?;
            let kw_str = kw.to_string();
            if kw_str != "sensor" {
                if seen.contains(&kw_str) {
                    return Err(syn::Error::new(
                        kw.span(),
                        format!("duplicate `{kw_str}` section"),
                    ));
                }
                seen.push(kw_str.clone());
            }
            match kw_str.as_str() {
                "states" => decl.states = parse_vars(&body)?,
                "inputs" => decl.inputs = parse_vars(&body)?,
                "parameters" => decl.params = parse_vars(&body)?,
                "noise" => decl.noise = parse_vars(&body)?,
                "continuous" | "discrete" => {
                    if let Some(prev) = &decl.process {
                        return Err(syn::Error::new(
                            kw.span(),
                            format!("a model has one process section; `{}` was already given", prev.keyword),
                        ));
                    }
                    let kind = if kw_str == "continuous" { ProcessKind::Continuous } else { ProcessKind::Discrete };
                    let inner;
                    braced!(inner in body);
                    let mut stmts = Vec::new();
                    while !inner.is_empty() {
                        stmts.push(inner.parse()?);
                    }
                    decl.process = Some(Process { kind, keyword: kw, stmts });
                }
                "sensor" => decl.sensors.push(parse_sensor(&body, attrs)?),
                _ => {
                    return Err(syn::Error::new(
                        kw.span(),
                        format!(
                            "unknown section `{kw}`; expected `states`, `inputs`, `parameters`, `noise`, \
                             `continuous`, `discrete` or `sensor`"
                        ),
                    ))
                }
            }
        }
        Ok(decl)
    }
}

impl Parse for Stmt {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        if input.peek(Token![let]) {
            input.parse::<Token![let]>()?;
            let name: Ident = input.parse()?;
            input.parse::<Token![=]>()?;
            let value: Expr = input.parse()?;
            input.parse::<Token![;]>()?;
            return Ok(Stmt::Let { name, value });
        }
        let derivative = if input.peek(Ident) && input.peek2(Token![/]) {
            let d: Ident = input.parse()?;
            if d != "d" {
                return Err(syn::Error::new(
                    d.span(),
                    "expected `d/dt state = ..`, `state = ..` or `let name = ..`",
                ));
            }
            input.parse::<Token![/]>()?;
            let dt: Ident = input.parse()?;
            if dt != "dt" {
                return Err(syn::Error::new(
                    dt.span(),
                    "expected `dt` in `d/dt state = ..`",
                ));
            }
            Some(d.span().join(dt.span()).unwrap_or(d.span()))
        } else {
            None
        };
        let target: Ident = input.parse()?;
        input.parse::<Token![=]>()?;
        let value: Expr = input.parse()?;
        input.parse::<Token![;]>()?;
        Ok(Stmt::Assign {
            target,
            derivative,
            value,
        })
    }
}

fn keyword(input: ParseStream, kw: &str) -> syn::Result<Ident> {
    let ident: Ident = input.parse()?;
    if ident != kw {
        return Err(syn::Error::new(ident.span(), format!("expected `{kw}`")));
    }
    Ok(ident)
}

/// `{ a, b: 3, c: 3x3, }` with doc comments on each entry.
fn parse_vars(input: ParseStream) -> syn::Result<Vec<Var>> {
    let inner;
    braced!(inner in input);
    let mut vars = Vec::new();
    while !inner.is_empty() {
        let attrs = inner.call(Attribute::parse_outer)?;
        let name: Ident = inner.parse()?;
        let (shape, shape_span) = if inner.peek(Token![:]) {
            inner.parse::<Token![:]>()?;
            parse_shape(&inner)?
        } else {
            (Shape::Scalar, name.span())
        };
        vars.push(Var {
            attrs,
            name,
            shape,
            shape_span,
        });
        if inner.is_empty() {
            break;
        }
        inner.parse::<Token![,]>()?;
    }
    Ok(vars)
}

/// `3`, `3x3` (one literal with suffix `x3`) or `3 x 3`.
fn parse_shape(input: ParseStream) -> syn::Result<(Shape, Span)> {
    let lit: LitInt = input.parse()?;
    let first: usize = lit
        .base10_parse()
        .map_err(|_| syn::Error::new(lit.span(), "expected a dimension"))?;
    let suffix = lit.suffix();
    if let Some(cols) = suffix.strip_prefix('x') {
        let cols: usize = cols
            .parse()
            .map_err(|_| syn::Error::new(lit.span(), "expected a dimension like `3` or `3x3`"))?;
        return Ok((Shape::Matrix(first, cols), lit.span()));
    }
    if !suffix.is_empty() {
        return Err(syn::Error::new(
            lit.span(),
            "expected a dimension like `3` or `3x3`",
        ));
    }
    if input.peek(Ident) && !input.peek2(Token![:]) {
        let x: Ident = input.fork().parse()?;
        if x == "x" {
            input.parse::<Ident>()?;
            let cols: LitInt = input.parse()?;
            let span = lit.span().join(cols.span()).unwrap_or(lit.span());
            return Ok((Shape::Matrix(first, cols.base10_parse()?), span));
        }
    }
    Ok((Shape::Vector(first), lit.span()))
}

/// `sensor Name: M { inputs { .. } angles = [..]; let a = ..; h = ..; }`.
fn parse_sensor(input: ParseStream, attrs: Vec<Attribute>) -> syn::Result<SensorDecl> {
    let name: Ident = input.parse()?;
    input.parse::<Token![:]>()?;
    let dim_lit: LitInt = input.parse()?;
    let dim = dim_lit.base10_parse()?;
    let body;
    braced!(body in input);
    let mut sensor = SensorDecl {
        attrs,
        name,
        dim,
        dim_lit,
        inputs: Vec::new(),
        angles: None,
        lets: Vec::new(),
        h: None,
        stray: Vec::new(),
    };
    while !body.is_empty() {
        if body.peek(Token![let]) {
            match body.parse::<Stmt>()? {
                Stmt::Let { name, value } => sensor.lets.push((name, value)),
                Stmt::Assign { .. } => unreachable!("`let` parses as a let statement"),
            }
            continue;
        }
        let kw: Ident = body.fork().parse()?;
        if kw == "inputs" && body.peek2(syn::token::Brace) {
            body.parse::<Ident>()?;
            sensor.inputs.extend(parse_vars(&body)?);
        } else if kw == "angles" {
            body.parse::<Ident>()?;
            body.parse::<Token![=]>()?;
            let list;
            bracketed!(list in body);
            let items = list.parse_terminated(LitInt::parse, Token![,])?;
            body.parse::<Token![;]>()?;
            sensor.angles = Some((kw, items.into_iter().collect()));
        } else {
            body.parse::<Ident>()?;
            body.parse::<Token![=]>()?;
            let value: Expr = body.parse()?;
            body.parse::<Token![;]>()?;
            if kw == "h" && sensor.h.is_none() {
                sensor.h = Some((kw, value));
            } else {
                sensor.stray.push(kw);
            }
        }
    }
    Ok(sensor)
}
