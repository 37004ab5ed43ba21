//! Syntax: the declaration as written, parsed with syn into this crate's small
//! AST. Nothing is validated here beyond the grammar (see `front/check.rs`).
//! The grammar of compositions and of their internal steps is in
//! [`composition`].

mod composition;

pub use crate::symbolic::ProcessKind;
pub use composition::Step;

use proc_macro2::{Delimiter, Span, TokenStream, TokenTree};
use syn::parse::{Parse, ParseStream, Parser};
use syn::{braced, bracketed, Attribute, Expr, Ident, LitInt, Path, Token, Visibility};

/// Everything inside one `model! { .. }` invocation: declarations, or one
/// internal step of a composition (see `front/compose.rs`).
pub enum Declarations {
    Items(Vec<Item>),
    Step(Box<Step>),
}

/// One declaration of an invocation.
pub enum Item {
    /// `pub model Foo { .. }`.
    Model(ModelDecl),
    /// `pub block Foo { .. }`.
    Block(BlockDecl),
    /// `pub model Foo = A + B + ..;`.
    Compose(ComposeDecl),
}

/// `pub model Foo { .. }` (also the body of a block, and the assembled
/// declaration of a composed model).
#[derive(Clone)]
pub struct ModelDecl {
    /// Doc comments (and other outer attributes) of the model.
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    pub states: Vec<Var>,
    pub inputs: Vec<Var>,
    pub params: Vec<Var>,
    pub noise: Vec<Var>,
    /// `needs { .. }`: names a block reads from other blocks (blocks only).
    pub needs: Vec<Var>,
    /// Model-level `let name = expr;`, in order: seen by the process section
    /// and by every sensor.
    pub lets: Vec<(Ident, Expr)>,
    /// `fn name(a, b) = expr;` at model level: inlined at every call.
    pub functions: Vec<FnDecl>,
    pub process: Option<Process>,
    pub sensors: Vec<SensorDecl>,
    /// `"; .."` appended to unknown-name errors (a hint about `needs` in blocks).
    pub unknown_hint: &'static str,
    /// `scalar f32;`: the scalar the code is generated for (`f64` by default).
    pub scalar: Scalar,
    /// The observability options of a model (hand-written or composed).
    pub observability: Observability,
}

/// What a model says about which states its sensors must see (see
/// `front/observability.rs`).
#[derive(Clone, Default)]
pub struct Observability {
    /// `allow_unused { a, b[1], .. }`: state scalars that are meant to be seen
    /// by no sensor (dead-reckoned) in some declared sensor set.
    pub allow_unused: Vec<(Ident, Option<LitInt>)>,
    /// `runs_with { [A, B], [A, B, C] }`: the sensor sets the model is meant
    /// to run with (the keyword, for spans); all its sensors when absent.
    pub runs_with: Option<(Ident, Vec<Vec<Ident>>)>,
}

/// `{ a, b[1], .. }` after `allow_unused`.
pub(super) fn parse_allow_unused(body: ParseStream) -> syn::Result<Vec<(Ident, Option<LitInt>)>> {
    let inner;
    braced!(inner in body);
    let mut out = Vec::new();
    while !inner.is_empty() {
        let name: Ident = inner.parse()?;
        let index = if inner.peek(syn::token::Bracket) {
            let ix;
            bracketed!(ix in inner);
            Some(ix.parse::<LitInt>()?)
        } else {
            None
        };
        out.push((name, index));
        if inner.is_empty() {
            break;
        }
        inner.parse::<Token![,]>()?;
    }
    Ok(out)
}

/// `{ [A, B], [A, B, C] }` after `runs_with`.
pub(super) fn parse_runs_with(body: ParseStream) -> syn::Result<Vec<Vec<Ident>>> {
    let inner;
    braced!(inner in body);
    let mut sets = Vec::new();
    while !inner.is_empty() {
        let set;
        bracketed!(set in inner);
        let names = set.parse_terminated(Ident::parse, Token![,])?;
        sets.push(names.into_iter().collect());
        if inner.is_empty() {
            break;
        }
        inner.parse::<Token![,]>()?;
    }
    Ok(sets)
}

/// The scalar a model's code is generated for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Scalar {
    /// Double precision, the default.
    #[default]
    F64,
    /// Single precision (`scalar f32;`).
    F32,
}

impl Scalar {
    /// The Rust type.
    pub fn tokens(self) -> TokenStream {
        match self {
            Scalar::F64 => quote::quote!(f64),
            Scalar::F32 => quote::quote!(f32),
        }
    }

    /// The module of `nav_runtime` with the scalar functions of this precision.
    pub fn math(self) -> TokenStream {
        match self {
            Scalar::F64 => quote::quote!(::nav_runtime::math),
            Scalar::F32 => quote::quote!(::nav_runtime::math::single),
        }
    }

    /// `scalar f32;` or `scalar f64;` after the keyword.
    pub fn parse_after_keyword(input: ParseStream) -> syn::Result<Scalar> {
        let ty: Ident = input.parse()?;
        let scalar = match ty.to_string().as_str() {
            "f64" => Scalar::F64,
            "f32" => Scalar::F32,
            other => {
                return Err(syn::Error::new(
                    ty.span(),
                    format!("unknown scalar `{other}`; expected `f32` or `f64`"),
                ))
            }
        };
        input.parse::<Token![;]>()?;
        Ok(scalar)
    }
}

/// `fn name(a, b) = expr;`: a small function of the model, inlined where it
/// is called; its body sees only its parameters.
#[derive(Clone)]
pub struct FnDecl {
    pub name: Ident,
    pub params: Vec<Ident>,
    pub body: Expr,
}

/// `pub block Foo { .. }`: a reusable part of a model (see `compose.rs`).
pub struct BlockDecl {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    /// The block's sections, parsed as a model named after the block.
    pub decl: ModelDecl,
    /// `Foo { .. }` as written, re-emitted by the block's macro.
    pub tokens: TokenStream,
}

/// `pub model Foo = A + path::B { order { .. } allow_unused { .. } }`.
pub struct ComposeDecl {
    pub attrs: Vec<Attribute>,
    pub vis: Visibility,
    pub name: Ident,
    /// The blocks, in the order their states are assembled.
    pub blocks: Vec<Path>,
    /// `order { a, b, .. }`: an explicit order of all states.
    pub order: Option<(Ident, Vec<Ident>)>,
    /// `allow_unused { .. }` and `runs_with { .. }`.
    pub observability: Observability,
    /// `scalar f32;`: the composed model's scalar.
    pub scalar: Option<Scalar>,
    /// The whole declaration as written, carried through the composition steps.
    pub tokens: TokenStream,
}

/// A declared name with its shape: `x`, `x: 3`, `x: 3x3`.
#[derive(Clone)]
pub struct Var {
    pub attrs: Vec<Attribute>,
    pub name: Ident,
    pub shape: Shape,
    /// The tokens of the shape, for error spans (the name's span if scalar).
    pub shape_span: Span,
    /// `x: angle` or `q: quaternion` (states only): what the filter keeps
    /// the state on after every step (see `Model::normalize_state`).
    pub manifold: Manifold,
}

/// The set a state lives on, restored after every predict and update.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Manifold {
    /// Any real values.
    Plain,
    /// A scalar angle (rad), wrapped to (-pi, pi].
    Angle,
    /// A unit quaternion `[w, x, y, z]`, renormalized.
    UnitQuaternion,
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

/// The `continuous { .. }` or `discrete { .. }` section.
#[derive(Clone)]
pub struct Process {
    pub kind: ProcessKind,
    pub keyword: Ident,
    pub stmts: Vec<Stmt>,
}

/// One statement of a process or sensor body.
#[derive(Clone)]
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
#[derive(Clone)]
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
        if input.peek(Token![@]) {
            return Ok(Declarations::Step(Box::new(input.parse()?)));
        }
        let mut items = Vec::new();
        while !input.is_empty() {
            items.push(input.parse()?);
        }
        Ok(Declarations::Items(items))
    }
}

impl Parse for Item {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let start = input.fork();
        let attrs = input.call(Attribute::parse_outer)?;
        let vis: Visibility = input.parse()?;
        if input.peek(Token![let]) {
            return Err(syn::Error::new(input.span(), MISPLACED_LET));
        }
        let kw: Ident = input.parse()?;
        if kw == "block" {
            let (decl, tokens) = parse_named_body(input, Vec::new(), vis.clone(), true)?;
            return Ok(Item::Block(BlockDecl {
                attrs,
                vis,
                decl,
                tokens,
            }));
        }
        if kw != "model" {
            return Err(syn::Error::new(
                kw.span(),
                "expected `model` (a declaration `model Name { .. }` or a composition `model Name = A + B;`) or \
                 `block`",
            ));
        }
        if input.peek(Ident) && input.peek2(Token![=]) {
            let name: Ident = input.parse()?;
            let compose = composition::parse_composition(input, attrs, vis, name)?;
            // The tokens consumed since `start`, re-parsed at every composition step.
            let end = input.cursor();
            let tokens = start.step(|cursor| {
                let mut c = *cursor;
                let mut out = TokenStream::new();
                while c != end {
                    let Some((tt, next)) = c.token_tree() else {
                        break;
                    };
                    out.extend([tt]);
                    c = next;
                }
                Ok((out, c))
            })?;
            return Ok(Item::Compose(ComposeDecl { tokens, ..compose }));
        }
        let (mut decl, _) = parse_named_body(input, attrs, vis, false)?;
        decl.unknown_hint = "";
        Ok(Item::Model(decl))
    }
}

/// `Name { sections }`: the sections of a model or a block, with the tokens as written.
pub fn parse_named_body(
    input: ParseStream,
    attrs: Vec<Attribute>,
    vis: Visibility,
    is_block: bool,
) -> syn::Result<(ModelDecl, TokenStream)> {
    let name: Ident = input.parse()?;
    let group = match input.parse::<TokenTree>()? {
        TokenTree::Group(g) if g.delimiter() == Delimiter::Brace => g,
        other => {
            return Err(syn::Error::new(
                other.span(),
                if is_block {
                    "expected `{ .. }` with the sections of the block"
                } else {
                    "expected `{ .. }` with the sections of the model, or `= A + B;` for a composition"
                },
            ))
        }
    };
    let tokens = quote::quote!(#name #group);
    let parser = |body: ParseStream| parse_sections(body, attrs, vis, name.clone(), is_block);
    let decl = parser.parse2(group.stream())?;
    Ok((decl, tokens))
}

fn parse_sections(
    body: ParseStream,
    attrs: Vec<Attribute>,
    vis: Visibility,
    name: Ident,
    is_block: bool,
) -> syn::Result<ModelDecl> {
    {
        let mut decl = ModelDecl {
            attrs,
            vis,
            name,
            states: Vec::new(),
            inputs: Vec::new(),
            params: Vec::new(),
            noise: Vec::new(),
            needs: Vec::new(),
            lets: Vec::new(),
            functions: Vec::new(),
            process: None,
            sensors: Vec::new(),
            unknown_hint: if is_block {
                "; a name another block declares must be listed in the block's `needs { .. }`"
            } else {
                ""
            },
            scalar: Scalar::F64,
            observability: Observability::default(),
        };
        let mut seen: Vec<String> = Vec::new();
        while !body.is_empty() {
            let attrs = body.call(Attribute::parse_outer)?;
            if body.peek(Token![fn]) {
                decl.functions.push(parse_function(body)?);
                continue;
            }
            if body.peek(Token![let]) {
                match body.parse::<Stmt>()? {
                    Stmt::Let { name, value } => decl.lets.push((name, value)),
                    Stmt::Assign { .. } => unreachable!("`let` parses as a let statement"),
                }
                continue;
            }
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
                "states" => decl.states = parse_declarations(body, true)?,
                "inputs" => decl.inputs = parse_vars(body)?,
                "parameters" => decl.params = parse_vars(body)?,
                "noise" => decl.noise = parse_vars(body)?,
                "needs" if is_block => decl.needs = parse_vars(body)?,
                "continuous" | "discrete" => {
                    if let Some(prev) = &decl.process {
                        return Err(syn::Error::new(
                            kw.span(),
                            format!(
                                "a model has one process section; `{}` was already given",
                                prev.keyword
                            ),
                        ));
                    }
                    let kind = if kw_str == "continuous" {
                        ProcessKind::Continuous
                    } else {
                        ProcessKind::Discrete
                    };
                    let inner;
                    braced!(inner in body);
                    let mut stmts = Vec::new();
                    while !inner.is_empty() {
                        stmts.push(inner.parse()?);
                    }
                    decl.process = Some(Process {
                        kind,
                        keyword: kw,
                        stmts,
                    });
                }
                "sensor" => decl.sensors.push(parse_sensor(body, attrs)?),
                "scalar" if is_block => {
                    return Err(syn::Error::new(
                        kw.span(),
                        "a block has no scalar of its own: the composed model chooses it \
                         (`model Name = A + B { scalar f32; }`)",
                    ))
                }
                "scalar" => decl.scalar = Scalar::parse_after_keyword(body)?,
                "allow_unused" | "runs_with" if is_block => {
                    return Err(syn::Error::new(
                        kw.span(),
                        format!(
                        "`{kw}` is a section of models, not of blocks: the composed model says it \
                             (`model Name = A + B {{ {kw} {{ .. }} }}`)"
                    ),
                    ))
                }
                "allow_unused" => decl.observability.allow_unused = parse_allow_unused(body)?,
                "runs_with" => {
                    decl.observability.runs_with = Some((kw.clone(), parse_runs_with(body)?))
                }
                "needs" => return Err(syn::Error::new(
                    kw.span(),
                    "`needs { .. }` is a section of blocks (`block Name { .. }`), not of models",
                )),
                _ => {
                    let mut sections = vec![
                        "states",
                        "inputs",
                        "parameters",
                        "noise",
                        "continuous",
                        "discrete",
                    ];
                    if is_block {
                        sections.push("needs");
                    } else {
                        sections.extend(["scalar", "allow_unused", "runs_with"]);
                    }
                    let hint = crate::front::names::suggest(
                        &kw_str,
                        sections
                            .iter()
                            .chain(["sensor"].iter())
                            .map(|s| s.to_string()),
                    );
                    let hint = match hint.strip_prefix("; ") {
                        Some(h) => format!(" ({h})"),
                        None => String::new(),
                    };
                    return Err(syn::Error::new(
                        kw.span(),
                        format!(
                            "unknown section `{kw}`{hint}; expected `{}` or `sensor`",
                            sections.join("`, `")
                        ),
                    ));
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

/// `fn name(a, b) = expr;`.
fn parse_function(input: ParseStream) -> syn::Result<FnDecl> {
    input.parse::<Token![fn]>()?;
    let name: Ident = input.parse()?;
    let args;
    syn::parenthesized!(args in input);
    let params = args.parse_terminated(Ident::parse, Token![,])?;
    input.parse::<Token![=]>().map_err(|e| {
        syn::Error::new(
            e.span(),
            "expected `= expression;`: a model function is `fn name(a, b) = expression;`",
        )
    })?;
    let body: Expr = input.parse()?;
    input.parse::<Token![;]>()?;
    Ok(FnDecl {
        name,
        params: params.into_iter().collect(),
        body,
    })
}

/// Where a `let` may stand, for errors at a `let` anywhere else.
const MISPLACED_LET: &str = "a `let` may stand at the top level of a model (seen by the process section and every \
                             sensor), in `continuous { .. }` / `discrete { .. }`, or in a `sensor`; not in a list of \
                             declarations";

/// `{ a, b: 3, c: 3x3, }` with doc comments on each entry.
fn parse_vars(input: ParseStream) -> syn::Result<Vec<Var>> {
    parse_declarations(input, false)
}

/// [`parse_vars`], also with `x: angle` and `q: quaternion` if `states`.
fn parse_declarations(input: ParseStream, states: bool) -> syn::Result<Vec<Var>> {
    let inner;
    braced!(inner in input);
    let mut vars = Vec::new();
    while !inner.is_empty() {
        let attrs = inner.call(Attribute::parse_outer)?;
        if inner.peek(Token![let]) {
            return Err(syn::Error::new(inner.span(), MISPLACED_LET));
        }
        let name: Ident = inner.parse()?;
        let mut manifold = Manifold::Plain;
        let (shape, shape_span) = if inner.peek(Token![:]) {
            inner.parse::<Token![:]>()?;
            if inner.peek(Ident) {
                let kind: Ident = inner.parse()?;
                let (m, shape) = match kind.to_string().as_str() {
                    "angle" => (Manifold::Angle, Shape::Scalar),
                    "quaternion" => (Manifold::UnitQuaternion, Shape::Vector(4)),
                    _ => {
                        return Err(syn::Error::new(
                            kind.span(),
                            format!("expected a dimension like `3` or `3x3`, `angle` or `quaternion`, found `{kind}`"),
                        ))
                    }
                };
                if !states {
                    return Err(syn::Error::new(
                        kind.span(),
                        format!("`{kind}` marks a state (kept on its manifold by the filter); other declarations take a dimension like `3` or `3x3`"),
                    ));
                }
                if inner.peek(Token![:]) || inner.peek(LitInt) {
                    return Err(syn::Error::new(
                        inner.span(),
                        format!(
                            "`{kind}` takes no dimension: an `angle` state is one scalar and a `quaternion` \
                             state a 4-vector (declare several angles one by one: `roll: angle, pitch: angle`)"
                        ),
                    ));
                }
                manifold = m;
                (shape, kind.span())
            } else {
                parse_shape(&inner)?
            }
        } else {
            (Shape::Scalar, name.span())
        };
        vars.push(Var {
            attrs,
            name,
            shape,
            shape_span,
            manifold,
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
    if !input.peek(Token![:]) || !input.peek2(LitInt) {
        return Err(syn::Error::new(
            input.span(),
            format!(
                "expected `: M` after `sensor {name}`: a sensor declares its number of outputs, \
                 `sensor {name}: M {{ .. }}`"
            ),
        ));
    }
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
