//! Structural observability at the declaration: every state scalar must reach
//! a measurement of every sensor set the model is meant to run with
//! (`runs_with { [A, B], .. }`, all its sensors when absent), through the
//! sparsity of `H` and `F` (see `Derived::observable_with`), unless
//! `allow_unused { .. }` accepts it as dead-reckoned. A warning is not
//! available to a proc macro on stable Rust; an error with an explicit,
//! checked opt-out is (see `docs/language.md`, "Structural observability").

use std::collections::HashMap;

use syn::Ident;

use super::ctxt::Ctxt;
use super::names::suggest;
use super::parse::{ModelDecl, Shape};
use crate::symbolic::derive::Derived;

/// Where a composed model's errors go: its name (the states' spans are in
/// the blocks), and the block of each state, named in the messages.
pub struct Composed<'a> {
    pub name: &'a Ident,
    pub state_block: &'a HashMap<String, String>,
}

/// The declared sensor sets as sensor indices (declaration order), or the
/// set of all sensors when `runs_with` is absent. Unknown names are skipped
/// here; [`check`] reports them.
pub fn run_sets(decl: &ModelDecl) -> Vec<Vec<usize>> {
    match &decl.observability.runs_with {
        None => vec![(0..decl.sensors.len()).collect()],
        Some((_, sets)) => sets
            .iter()
            .map(|set| {
                let mut out: Vec<usize> = Vec::new();
                for name in set {
                    if let Some(k) = decl.sensors.iter().position(|s| s.name == *name) {
                        if !out.contains(&k) {
                            out.push(k);
                        }
                    }
                }
                out
            })
            .collect(),
    }
}

/// Checks `runs_with` and `allow_unused` against the derived sparsity.
pub fn check(decl: &ModelDecl, derived: &Derived, composed: Option<Composed>) -> syn::Result<()> {
    let cx = Ctxt::new();
    let obs = &decl.observability;
    let model = &decl.name;
    let sensor_names: Vec<String> = decl.sensors.iter().map(|s| s.name.to_string()).collect();

    // The sensor sets name declared sensors, once each.
    let mut misnamed = false;
    if let Some((kw, sets)) = &obs.runs_with {
        if sets.is_empty() {
            cx.error_spanned_by(
                kw,
                "`runs_with` lists no sensor set: give at least one, e.g. `[A, B]`",
            );
        }
        for set in sets {
            if set.is_empty() {
                cx.error_spanned_by(
                    kw,
                    "an empty sensor set in `runs_with` observes nothing: list the sensors it runs with",
                );
            }
            for (i, name) in set.iter().enumerate() {
                if set[..i].contains(name) {
                    cx.error_spanned_by(
                        name,
                        format!("sensor `{name}` is listed twice in this set"),
                    );
                } else if !sensor_names.contains(&name.to_string()) {
                    misnamed = true;
                    let hint = suggest(&name.to_string(), sensor_names.iter().cloned());
                    let hint = if hint.is_empty() {
                        match sensor_names.len() {
                            0 => "; it declares none".to_string(),
                            _ => format!("; its sensors are `{}`", sensor_names.join("`, `")),
                        }
                    } else {
                        hint
                    };
                    cx.error_spanned_by(
                        name,
                        format!("`{name}` is not a sensor of `{model}`{hint}"),
                    );
                }
            }
        }
    }
    // A model without sensors measures nothing: it makes no claim to check.
    // A set with a misspelled sensor would report the consequences of the
    // typo: the typo alone is reported.
    let sets = run_sets(decl);
    if misnamed
        || decl.sensors.is_empty()
        || obs.runs_with.as_ref().is_some_and(|(_, s)| s.is_empty())
    {
        return cx.check();
    }
    let observable: Vec<Vec<bool>> = sets
        .iter()
        .map(|set| {
            let mut on = vec![false; decl.sensors.len()];
            for &k in set {
                on[k] = true;
            }
            derived.observable_with(&on)
        })
        .collect();
    let set_name = |k: usize| {
        let names: Vec<&str> = sets[k].iter().map(|&s| sensor_names[s].as_str()).collect();
        format!("[{}]", names.join(", "))
    };

    // Scalar ranges of the states.
    let mut ranges = Vec::new();
    let mut offset = 0;
    for v in &decl.states {
        ranges.push((v, offset..offset + v.shape.len()));
        offset += v.shape.len();
    }
    let everywhere = |k: usize| observable.iter().all(|o| o[k]);
    let mut allowed = vec![false; offset];
    for (name, index) in &obs.allow_unused {
        let Some((v, range)) = ranges.iter().find(|(v, _)| v.name == *name) else {
            let hint = suggest(
                &name.to_string(),
                decl.states.iter().map(|s| s.name.to_string()),
            );
            cx.error_spanned_by(name, format!("`{name}` is not a state of `{model}`{hint}"));
            continue;
        };
        let scalars: Vec<usize> = match index {
            None => range.clone().collect(),
            Some(lit) => match lit.base10_parse::<usize>() {
                Ok(i) if i < range.len() && v.shape != Shape::Scalar => vec![range.start + i],
                _ => {
                    cx.error_spanned_by(
                        lit,
                        format!("`{name}` is a {}: no component {lit}", v.shape),
                    );
                    continue;
                }
            },
        };
        if scalars.iter().all(|&k| everywhere(k)) {
            let what = match index {
                Some(i) => format!("{name}[{i}]"),
                None => name.to_string(),
            };
            let by = if obs.runs_with.is_some() {
                "a sensor of every set of `runs_with`".to_string()
            } else {
                format!("a sensor of `{model}`")
            };
            cx.error_spanned_by(
                name,
                format!("`{what}` is used by {by}: remove it from `allow_unused`"),
            );
        }
        for k in scalars {
            allowed[k] = true;
        }
    }

    for (v, range) in &ranges {
        let bad: Vec<usize> = range
            .clone()
            .filter(|&k| !everywhere(k) && !allowed[k])
            .collect();
        if bad.is_empty() {
            continue;
        }
        let what = if bad.len() == range.len() {
            format!("state `{}`", v.name)
        } else {
            let parts: Vec<String> = bad
                .iter()
                .map(|k| format!("{}[{}]", v.name, k - range.start))
                .collect();
            format!("`{}`", parts.join("`, `"))
        };
        let accept = if bad.len() == range.len() || bad.len() > 1 {
            v.name.to_string()
        } else {
            format!("{}[{}]", v.name, bad[0] - range.start)
        };
        let by = match &obs.runs_with {
            None => format!("no sensor of `{model}`"),
            Some(_) => {
                let missing: Vec<String> = (0..sets.len())
                    .filter(|&s| bad.iter().any(|&k| !observable[s][k]))
                    .map(set_name)
                    .collect();
                format!(
                    "no sensor of the set{} {} of `runs_with`",
                    if missing.len() > 1 { "s" } else { "" },
                    missing.join(" and ")
                )
            }
        };
        match &composed {
            Some(c) => {
                let block = c
                    .state_block
                    .get(&v.name.to_string())
                    .map(String::as_str)
                    .unwrap_or("?");
                cx.error_spanned_by(
                    c.name,
                    format!(
                        "{what} (block `{block}`) is used by {by}, directly or through the dynamics, so no \
                         measurement can ever correct it: add a block whose sensor observes it, or accept it with \
                         `allow_unused {{ {accept} }}`"
                    ),
                );
            }
            None => cx.error_at(
                v.name.span(),
                format!(
                    "{what} is used by {by}, directly or through the dynamics, so no measurement can ever \
                     correct it: add a sensor that observes it, or accept it as dead-reckoned with \
                     `allow_unused {{ {accept} }}`"
                ),
            ),
        }
    }
    cx.check()
}
