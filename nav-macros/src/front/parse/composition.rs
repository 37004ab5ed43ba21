//! The grammar of compositions: `model Name = A + B { order { .. } allow_unused
//! { .. } scalar f32; }` and the internal steps `@nav_block { .. } @nav_compose { .. } { .. }`
//! through which the blocks' macros hand their tokens back (see
//! `front/compose.rs`).

use proc_macro2::TokenStream;
use syn::parse::{Parse, ParseStream};
use syn::{braced, Attribute, Ident, Path, Token, Visibility};

use super::{ComposeDecl, Item};

/// One step of a composition: `@nav_block { B { .. } } @nav_compose { C } { collected }`.
pub struct Step {
    pub block: TokenStream,
    pub compose: TokenStream,
    pub collected: TokenStream,
}

impl Parse for Step {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let marker = |input: ParseStream, kw: &str| -> syn::Result<()> {
            input.parse::<Token![@]>()?;
            let ident: Ident = input.parse()?;
            if ident != kw {
                return Err(syn::Error::new(
                    ident.span(),
                    format!("internal composition step: expected `@{kw}`"),
                ));
            }
            Ok(())
        };
        let group = |input: ParseStream| -> syn::Result<TokenStream> {
            let inner;
            braced!(inner in input);
            inner.parse()
        };
        marker(input, "nav_block")?;
        let block = group(input)?;
        marker(input, "nav_compose")?;
        let compose = group(input)?;
        let collected = group(input)?;
        Ok(Step {
            block,
            compose,
            collected,
        })
    }
}

impl Parse for ComposeDecl {
    /// A composition as carried through the steps: `#[..] pub model Foo = A + B ..`.
    fn parse(input: ParseStream) -> syn::Result<Self> {
        match input.parse::<Item>()? {
            Item::Compose(c) => Ok(c),
            _ => Err(input.error("expected a composition `model Name = A + B;`")),
        }
    }
}

/// `= A + path::B ;` or `= A + B { order { .. } allow_unused { .. } }`.
pub(super) fn parse_composition(
    input: ParseStream,
    attrs: Vec<Attribute>,
    vis: Visibility,
    name: Ident,
) -> syn::Result<ComposeDecl> {
    input.parse::<Token![=]>()?;
    let mut blocks = vec![input.call(Path::parse_mod_style)?];
    while input.peek(Token![+]) {
        input.parse::<Token![+]>()?;
        blocks.push(input.call(Path::parse_mod_style)?);
    }
    let mut compose = ComposeDecl {
        attrs,
        vis,
        name,
        blocks,
        order: None,
        observability: super::Observability::default(),
        scalar: None,
        tokens: TokenStream::new(),
    };
    if input.peek(syn::token::Brace) {
        let body;
        braced!(body in input);
        while !body.is_empty() {
            let kw: Ident = body.parse()?;
            if kw == "scalar" {
                if compose.scalar.is_some() {
                    return Err(syn::Error::new(kw.span(), "duplicate `scalar` section"));
                }
                compose.scalar = Some(super::Scalar::parse_after_keyword(&body)?);
                continue;
            }
            let once = |seen: bool| {
                if seen {
                    Err(syn::Error::new(
                        kw.span(),
                        format!("duplicate `{kw}` section"),
                    ))
                } else {
                    Ok(())
                }
            };
            if kw == "order" {
                once(compose.order.is_some())?;
                let inner;
                braced!(inner in body);
                let names = inner.parse_terminated(Ident::parse, Token![,])?;
                compose.order = Some((kw, names.into_iter().collect()));
            } else if kw == "allow_unused" {
                once(!compose.observability.allow_unused.is_empty())?;
                compose.observability.allow_unused = super::parse_allow_unused(&body)?;
            } else if kw == "runs_with" {
                once(compose.observability.runs_with.is_some())?;
                compose.observability.runs_with =
                    Some((kw.clone(), super::parse_runs_with(&body)?));
            } else {
                return Err(syn::Error::new(
                    kw.span(),
                    format!("unknown section `{kw}` of a composition; expected `order`, `allow_unused`, `runs_with` or `scalar`"),
                ));
            }
        }
        if input.peek(Token![;]) {
            input.parse::<Token![;]>()?;
        }
    } else {
        input.parse::<Token![;]>().map_err(|e| {
            syn::Error::new(
                e.span(),
                "expected `+ Block`, `;` or `{ order { .. } allow_unused { .. } }` after the blocks of a composition",
            )
        })?;
    }
    Ok(compose)
}
