//! Composition: reusable blocks (`block Name { .. }`) and models assembled from
//! them (`model Vehicle = Core + A + B;`).
//!
//! A proc macro cannot read another invocation, so a block exports its own
//! tokens: `block Dvl { .. }` is checked on its own (its `needs` as inputs) and
//! emits `macro_rules! Dvl` whose expansion is `model! { @nav_block { Dvl { .. } }
//! <rest> }`. A composition `model V = A + B + C;` expands to
//! `A! { @nav_compose { <the composition> } { } }`; each step receives one
//! block's tokens, appends them to the collected ones and calls the next
//! block's macro, and the last step assembles one declaration and runs the
//! ordinary pipeline on it. Errors of the assembly (a name declared by two
//! blocks, a `need` no block provides or of another shape, an unused state)
//! carry the spans of the block declarations and of the composition.

use std::collections::HashMap;

use proc_macro2::{Span, TokenStream};
use quote::quote;
use syn::parse::ParseStream;
use syn::visit_mut::VisitMut;
use syn::{Ident, Visibility};

use super::ctxt::Ctxt;
use super::names::suggest;
use super::parse::{
    parse_named_body, BlockDecl, ComposeDecl, ModelDecl, Process, ProcessKind, Shape, Step, Stmt,
    Var,
};

/// `block Name { .. }`: checks the block on its own and emits its macro.
pub fn block(b: &BlockDecl) -> TokenStream {
    let name = &b.decl.name;
    let errors = match check_block(&b.decl) {
        Ok(()) => TokenStream::new(),
        Err(e) => e.to_compile_error(),
    };
    let tokens = &b.tokens;
    let attrs = &b.attrs;
    // `pub` blocks are visible in the whole crate (the most a `macro_rules!`
    // defined by a macro can be); other visibilities are kept. A
    // `#[macro_export]` block is used from other crates by path
    // (`use lib::Block;`); in its own crate a macro-expanded exported macro
    // cannot be named by path, so it gets no `use`.
    let exported = attrs.iter().any(|a| a.path().is_ident("macro_export"));
    let use_vis = match &b.vis {
        Visibility::Public(_) => quote!(pub(crate)),
        Visibility::Inherited => quote!(pub(self)),
        v => quote!(#v),
    };
    // A block that is not exported is defined under a hidden name and
    // imported under its own: `use Block;` of a macro named like a type of
    // the same module (the sensor type `ShipGps` of `model Ship = .. +
    // ShipGps` with `sensor Gps`) would import the type as well and clash
    // with it, while `use hidden as Block;` of a name that is only a macro
    // imports the macro alone.
    let (macro_name, import) = if exported {
        (name.clone(), TokenStream::new())
    } else {
        let hidden = Ident::new(&format!("__nav_block_{name}"), name.span());
        let import = quote! {
            #[allow(unused_imports)]
            #use_vis use #hidden as #name;
        };
        (hidden, import)
    };
    let doc = format!(
        "Model block `{name}`: use it in a composition `model Vehicle = .. + {name} + ..;` \
         (its macro re-emits the block's declaration)."
    );
    quote! {
        #errors
        #(#attrs)*
        #[doc = ""]
        #[doc = #doc]
        #[allow(unused_macros, non_snake_case)]
        macro_rules! #macro_name {
            ($($rest:tt)*) => {
                ::nav_runtime::model! { @nav_block { #tokens } $($rest)* }
            };
        }
        #import
    }
}

/// The checks a block passes on its own: the model checks with its `needs` as
/// inputs, so every mistake inside a block is reported once, at the block.
fn check_block(decl: &ModelDecl) -> syn::Result<()> {
    let mut model = decl.clone();
    model.inputs.append(&mut model.needs);
    if model.states.is_empty() {
        model.states.push(Var {
            attrs: Vec::new(),
            name: Ident::new("__nav_block_without_states", Span::call_site()),
            shape: Shape::Scalar,
            shape_span: Span::call_site(),
            manifold: super::parse::Manifold::Plain,
        });
    }
    if model.process.is_none() {
        model.process = Some(Process {
            kind: ProcessKind::Continuous,
            keyword: Ident::new("continuous", Span::call_site()),
            stmts: Vec::new(),
        });
    }
    let cx = Ctxt::new();
    super::check::check(&cx, &model);
    let _ = super::lower::lower(&cx, &model);
    cx.check()
}

/// `model V = A + B ..;`: the first step, a call of the first block's macro.
pub fn start(c: &ComposeDecl) -> TokenStream {
    let first = &c.blocks[0];
    let tokens = &c.tokens;
    quote!(#first! { @nav_compose { #tokens } { } })
}

/// One step: collects the block and calls the next one, or assembles the model.
pub fn step(step: Step) -> syn::Result<TokenStream> {
    let compose: ComposeDecl = syn::parse2(step.compose.clone())?;
    let mut collected = step.collected.clone();
    collected.extend(step.block);
    let parse_all = |input: ParseStream| -> syn::Result<Vec<ModelDecl>> {
        let mut blocks = Vec::new();
        while !input.is_empty() {
            let (decl, _) = parse_named_body(input, Vec::new(), Visibility::Inherited, true)?;
            blocks.push(decl);
        }
        Ok(blocks)
    };
    let blocks = syn::parse::Parser::parse2(parse_all, collected.clone())?;
    if blocks.len() < compose.blocks.len() {
        let next = &compose.blocks[blocks.len()];
        let tokens = &step.compose;
        return Ok(quote!(#next! { @nav_compose { #tokens } { #collected } }));
    }
    let (decl, owners) = assemble(&compose, blocks)?;
    let derived = crate::derive_model(&decl)?;
    super::observability::check(
        &decl,
        &derived,
        Some(super::observability::Composed {
            name: &compose.name,
            state_block: &owners,
        }),
    )?;
    Ok(crate::back::emit::model(&decl, &derived))
}

/// What declared a name: the block (index) and the kind of declaration.
#[derive(Clone)]
struct Owner {
    block: usize,
    kind: &'static str,
    /// `None` for a block-level `let` or function, which no `needs` reads.
    shape: Option<Shape>,
}

/// One declaration from the blocks, or the errors of the assembly. Also
/// returns the block of each state, for messages.
fn assemble(
    c: &ComposeDecl,
    blocks: Vec<ModelDecl>,
) -> syn::Result<(ModelDecl, HashMap<String, String>)> {
    let cx = Ctxt::new();
    let block_names: Vec<String> = blocks.iter().map(|b| b.name.to_string()).collect();
    let listed = || format!("`{}`", block_names.join("`, `"));

    // A block listed twice, or two blocks declaring one name.
    let mut skip = vec![false; blocks.len()];
    for (b, block) in blocks.iter().enumerate() {
        if let Some(first) = block_names[..b].iter().position(|n| *n == block_names[b]) {
            cx.error_spanned_by(
                &c.blocks[b],
                format!(
                    "block `{}` is listed twice (also as block {} of `{}`)",
                    block.name,
                    first + 1,
                    c.name
                ),
            );
            skip[b] = true;
        }
    }
    let mut owners: HashMap<String, Owner> = HashMap::new();
    let mut sensors: HashMap<String, usize> = HashMap::new();
    for (b, block) in blocks.iter().enumerate() {
        if skip[b] {
            continue;
        }
        // Every declared name, block-level `let`s and functions included
        // (those have no shape: no `needs` reads them).
        let kinds: [(&'static str, &[Var]); 4] = [
            ("state", &block.states),
            ("input", &block.inputs),
            ("parameter", &block.params),
            ("noise input", &block.noise),
        ];
        let declared = kinds
            .into_iter()
            .flat_map(|(kind, vars)| vars.iter().map(move |v| (kind, &v.name, Some(v.shape))))
            .chain(block.lets.iter().map(|(n, _)| ("`let`", n, None)))
            .chain(block.functions.iter().map(|f| ("function", &f.name, None)));
        for (kind, ident, shape) in declared {
            let name = ident.to_string();
            match owners.get(&name) {
                Some(prev) => {
                    let what = if prev.kind == kind {
                        format!(
                            "blocks `{}` and `{}` both declare the {kind} `{name}`",
                            block_names[prev.block], block.name
                        )
                    } else {
                        format!(
                            "block `{}` declares the {kind} `{name}`, which block `{}` declares as a {}",
                            block.name, block_names[prev.block], prev.kind
                        )
                    };
                    let remedy = match shape {
                        Some(_) => {
                            "a block that reads another block's name lists it in its `needs { .. }`"
                        }
                        None => "rename one of them",
                    };
                    cx.error_spanned_by(
                        &c.blocks[b],
                        format!("{what}: every name of a model belongs to one block ({remedy})"),
                    )
                }
                None => {
                    owners.insert(
                        name,
                        Owner {
                            block: b,
                            kind,
                            shape,
                        },
                    );
                }
            }
        }
        for s in &block.sensors {
            let name = s.name.to_string();
            if let Some(&prev) = sensors.get(&name) {
                cx.error_spanned_by(
                    &c.blocks[b],
                    format!(
                        "blocks `{}` and `{}` both declare sensor `{name}`: sensor names of a model are unique",
                        block_names[prev], block.name
                    ),
                );
            } else {
                sensors.insert(name, b);
            }
        }
    }

    // Every need is declared by another block, with the same shape.
    for (b, block) in blocks.iter().enumerate() {
        if skip[b] {
            continue;
        }
        for need in &block.needs {
            let name = need.name.to_string();
            match owners.get(&name) {
                None => {
                    let mut cands: Vec<String> = owners.keys().cloned().collect();
                    cands.sort();
                    cx.error_spanned_by(
                        &need.name,
                        format!(
                            "block `{}` needs `{name}`, which no block of `{}` declares (its blocks: {}){}",
                            block.name,
                            c.name,
                            listed(),
                            match suggest(&name, cands) {
                                s if s.is_empty() => "; add the block that declares it".to_string(),
                                s => s,
                            }
                        ),
                    );
                }
                Some(Owner {
                    block: owner,
                    kind,
                    shape: None,
                }) => cx.error_spanned_by(
                    &need.name,
                    format!(
                        "block `{}` needs `{name}`, which block `{}` declares as a {kind}: `needs` reads states, \
                         inputs and parameters of other blocks, not their `let`s or functions",
                        block.name, block_names[*owner]
                    ),
                ),
                Some(Owner {
                    block: owner,
                    shape: Some(shape),
                    ..
                }) if *shape != need.shape => cx.error_at(
                    need.shape_span,
                    format!(
                        "block `{}` needs `{name}` as a {}, but block `{}` declares it as a {shape}",
                        block.name, need.shape, block_names[*owner]
                    ),
                ),
                Some(_) => {}
            }
        }
    }

    // One kind of process.
    let mut process: Option<(usize, ProcessKind, Ident)> = None;
    for (b, block) in blocks.iter().enumerate() {
        let Some(p) = &block.process else { continue };
        match &process {
            None => process = Some((b, p.kind, p.keyword.clone())),
            Some((first, kind, kw)) if *kind != p.kind => cx.error_spanned_by(
                &p.keyword,
                format!(
                    "block `{}` has a `{}` process section but block `{}` has `{kw}`: the blocks of a model share \
                     one kind of process",
                    block.name, p.keyword, block_names[*first]
                ),
            ),
            Some(_) => {}
        }
    }

    // The state order.
    let all_states: Vec<&Var> = blocks.iter().flat_map(|b| &b.states).collect();
    let mut order: Vec<usize> = (0..all_states.len()).collect();
    if let Some((kw, names)) = &c.order {
        order.clear();
        for name in names {
            match all_states.iter().position(|s| s.name == *name) {
                Some(k) if order.contains(&k) => {
                    cx.error_spanned_by(name, format!("state `{name}` is listed twice in `order`"))
                }
                Some(k) => order.push(k),
                None => {
                    let hint = suggest(
                        &name.to_string(),
                        all_states.iter().map(|s| s.name.to_string()),
                    );
                    cx.error_spanned_by(
                        name,
                        format!("`{name}` is not a state of `{}`{hint}", c.name),
                    );
                }
            }
        }
        let missing: Vec<String> = (0..all_states.len())
            .filter(|k| !order.contains(k))
            .map(|k| all_states[k].name.to_string())
            .collect();
        if !missing.is_empty() && names.len() >= order.len() {
            cx.error_spanned_by(
                kw,
                format!(
                    "`order` must list every state once; missing `{}`",
                    missing.join("`, `")
                ),
            );
        }
    }
    cx.check()?;

    // Local `let`s that would collide across blocks are renamed.
    let cx = Ctxt::new();
    let mut blocks = blocks;
    let mut process_lets: HashMap<String, usize> = HashMap::new();
    for (b, block) in blocks.iter_mut().enumerate() {
        let block_name = block.name.to_string();
        let taken = |name: &str, lets: &HashMap<String, usize>| {
            owners.get(name).is_some_and(|o| o.block != b)
                || lets.get(name).is_some_and(|&o| o != b)
        };
        if let Some(p) = &mut block.process {
            let mut renames = Vec::new();
            for stmt in &p.stmts {
                if let Stmt::Let { name, .. } = stmt {
                    if taken(&name.to_string(), &process_lets) {
                        renames.push(name.clone());
                    }
                }
            }
            for old in renames {
                let mut r = Rename::new(&old, &block_name);
                for stmt in &mut p.stmts {
                    match stmt {
                        Stmt::Let { name, value } => {
                            r.ident(name);
                            r.visit_expr_mut(value);
                        }
                        Stmt::Assign { value, .. } => r.visit_expr_mut(value),
                    }
                }
            }
            for stmt in &p.stmts {
                if let Stmt::Let { name, .. } = stmt {
                    process_lets.insert(name.to_string(), b);
                }
            }
        }
        for s in &mut block.sensors {
            let renames: Vec<Ident> = s
                .lets
                .iter()
                .map(|(n, _)| n.clone())
                .filter(|n| taken(&n.to_string(), &HashMap::new()))
                .collect();
            for old in renames {
                let mut r = Rename::new(&old, &block_name);
                for (name, value) in &mut s.lets {
                    r.ident(name);
                    r.visit_expr_mut(value);
                }
                if let Some((_, h)) = &mut s.h {
                    r.visit_expr_mut(h);
                }
            }
            for v in &s.inputs {
                if let Some(o) = owners.get(&v.name.to_string()).filter(|o| o.block != b) {
                    cx.error_spanned_by(
                        &v.name,
                        format!(
                            "sensor input `{}` of sensor `{}` (block `{block_name}`) has the name of a {} of block \
                             `{}`: rename one of them",
                            v.name,
                            s.name,
                            o.kind,
                            block_names[o.block]
                        ),
                    );
                }
            }
        }
    }
    cx.check()?;

    let state_block: HashMap<String, String> = owners
        .iter()
        .filter(|(_, o)| o.kind == "state")
        .map(|(n, o)| (n.clone(), block_names[o.block].clone()))
        .collect();
    let all_states: Vec<Var> = blocks
        .iter()
        .flat_map(|b| b.states.iter().cloned())
        .collect();
    let mut decl = ModelDecl {
        attrs: c.attrs.clone(),
        vis: c.vis.clone(),
        name: c.name.clone(),
        states: order.iter().map(|&k| all_states[k].clone()).collect(),
        inputs: Vec::new(),
        params: Vec::new(),
        noise: Vec::new(),
        needs: Vec::new(),
        lets: Vec::new(),
        functions: Vec::new(),
        process: process.map(|(_, kind, keyword)| Process {
            kind,
            keyword,
            stmts: Vec::new(),
        }),
        sensors: Vec::new(),
        unknown_hint: "",
        scalar: c.scalar.unwrap_or_default(),
        observability: c.observability.clone(),
    };
    for block in blocks {
        decl.inputs.extend(block.inputs);
        decl.params.extend(block.params);
        decl.noise.extend(block.noise);
        decl.lets.extend(block.lets);
        decl.functions.extend(block.functions);
        if let (Some(p), Some(bp)) = (&mut decl.process, block.process) {
            p.stmts.extend(bp.stmts);
        }
        decl.sensors.extend(block.sensors);
    }
    Ok((decl, state_block))
}

/// Renames one local name in expressions (never a called function's name).
struct Rename {
    old: String,
    new: String,
}

impl Rename {
    fn new(old: &Ident, block: &str) -> Self {
        Rename {
            old: old.to_string(),
            new: format!("{old}__{block}"),
        }
    }

    fn ident(&self, ident: &mut Ident) {
        if *ident == self.old {
            *ident = Ident::new(&self.new, ident.span());
        }
    }
}

impl VisitMut for Rename {
    fn visit_expr_path_mut(&mut self, p: &mut syn::ExprPath) {
        if p.qself.is_none() && p.path.segments.len() == 1 && p.path.leading_colon.is_none() {
            self.ident(&mut p.path.segments[0].ident);
        }
    }

    fn visit_expr_call_mut(&mut self, call: &mut syn::ExprCall) {
        for arg in &mut call.args {
            self.visit_expr_mut(arg);
        }
    }
}
