//! LANGUAGE REFERENCE PLACEHOLDER

mod check;
mod cse;
mod ctxt;
mod derive;
mod diff;
mod emit;
mod emit_tests;
mod expr;
mod lower;
mod ops;
mod parse;

use proc_macro::TokenStream;

/// Declares estimator models; see the crate documentation for the language.
#[proc_macro]
pub fn model(input: TokenStream) -> TokenStream {
    expand(input.into()).into()
}

/// Parse -> check -> lower -> derive -> emit, for every declaration of the input.
fn expand(input: proc_macro2::TokenStream) -> proc_macro2::TokenStream {
    let decls = match syn::parse2::<parse::Declarations>(input) {
        Ok(d) => d,
        Err(e) => return e.to_compile_error(),
    };
    let mut out = proc_macro2::TokenStream::new();
    for decl in &decls.models {
        match expand_model(decl) {
            Ok(tokens) => out.extend(tokens),
            Err(e) => out.extend(e.to_compile_error()),
        }
    }
    out
}

fn expand_model(decl: &parse::ModelDecl) -> syn::Result<proc_macro2::TokenStream> {
    let cx = ctxt::Ctxt::new();
    check::check(&cx, decl);
    let lowered = lower::lower(&cx, decl);
    cx.check()?;
    let lowered = lowered.expect("a checked model has a process section");
    let nw = decl.noise.iter().map(|v| v.shape.len()).sum();
    let derived = derive::derive(lowered, nw);
    Ok(emit::model(decl, &derived))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The body of the first `nav_runtime::model! { .. }` in `source`.
    fn macro_body(source: &str) -> proc_macro2::TokenStream {
        let start = source.find("nav_runtime::model! {").expect("a model! invocation");
        let file: syn::File = syn::parse_str(&source[start..]).expect("parses");
        match &file.items[0] {
            syn::Item::Macro(m) => m.mac.tokens.clone(),
            _ => panic!("expected a macro invocation"),
        }
    }

    #[test]
    fn ins25_expansion_is_fast() {
        let body = macro_body(include_str!("../tests/ins25.rs"));
        let start = std::time::Instant::now();
        let out = expand(body);
        let elapsed = start.elapsed();
        let text = out.to_string();
        assert!(!text.contains("compile_error"), "{text}");
        if std::env::var_os("NAV_MACROS_DUMP").is_some() {
            std::fs::write(std::env::temp_dir().join("ins25_expanded.rs"), &text).unwrap();
        }
        eprintln!("INS-25 expansion: {elapsed:?}, {} bytes", text.len());
        assert!(elapsed.as_secs_f64() < 5.0, "expansion took {elapsed:?}");
    }
}
