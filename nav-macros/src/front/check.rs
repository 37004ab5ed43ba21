//! Declaration-level checks: names, duplicates, sections, assignment targets and
//! sensor headers. Expression-level problems (unknown names, shapes, unsupported
//! constructs) are found while lowering (`lower.rs`) into the same context.

use std::collections::HashMap;

use syn::Ident;

use super::ctxt::Ctxt;
use super::names::screaming_case;
use super::names::suggest;
use super::parse::{ModelDecl, ProcessKind, Shape, Stmt, Var};

/// Inherent constants of the model type; a state must not produce one of them.
pub const RESERVED_CONSTS: &[&str] = &[
    "N",
    "NW",
    "UNUSED_STATES",
    "OPS_TRANSITION",
    "OPS_DERIVATIVE",
    "OPS_JACOBIAN",
    "OPS_NOISE_JACOBIAN",
    "OPS_PROCESS_NOISE",
    "OPS_PROPAGATE_COVARIANCE",
];

/// Sensor names that would collide with the generated record types.
const RESERVED_SENSORS: &[&str] = &["State", "Input", "Params", "Noise"];

/// Runs every declaration-level check of one model.
pub fn check(cx: &Ctxt, decl: &ModelDecl) {
    let mut model_names = Names::default();
    let kinds: [(&str, &[Var]); 4] = [
        ("a state", &decl.states),
        ("an input", &decl.inputs),
        ("a parameter", &decl.params),
        ("a noise input", &decl.noise),
    ];
    for (kind, vars) in kinds {
        for v in vars {
            model_names.declare(cx, &v.name, kind);
            check_shape(cx, v);
        }
    }
    for (name, _) in &decl.lets {
        model_names.declare(cx, name, "a model-level `let` binding");
    }
    let mut functions: Vec<String> = Vec::new();
    for f in &decl.functions {
        let name = f.name.to_string();
        if super::lower::is_builtin(&name) {
            cx.error_spanned_by(
                &f.name,
                format!("`{name}` is a builtin function; name the model function otherwise"),
            );
        } else if functions.contains(&name) {
            cx.error_spanned_by(&f.name, format!("function `{name}` is declared twice"));
        }
        functions.push(name);
        let mut params: Vec<String> = Vec::new();
        for p in &f.params {
            if params.contains(&p.to_string()) {
                cx.error_spanned_by(
                    p,
                    format!("parameter `{p}` of `{}` is listed twice", f.name),
                );
            }
            params.push(p.to_string());
        }
    }
    for v in &decl.states {
        let konst = screaming_case(&v.name.to_string());
        if RESERVED_CONSTS.contains(&konst.as_str()) {
            cx.error_spanned_by(
                &v.name,
                format!(
                    "state `{}` would generate the index constant `{konst}`, which is reserved",
                    v.name
                ),
            );
        }
    }
    if decl.states.is_empty() {
        cx.error_spanned_by(
            &decl.name,
            format!(
                "model `{}` declares no states: add `states {{ .. }}`",
                decl.name
            ),
        );
    }
    match &decl.process {
        None => cx.error_spanned_by(
            &decl.name,
            format!("model `{}` has no process section: add `continuous {{ .. }}` or `discrete {{ .. }}`", decl.name),
        ),
        Some(process) => {
            let mut names = model_names.clone();
            let mut assigned: HashMap<String, &Ident> = HashMap::new();
            for stmt in &process.stmts {
                match stmt {
                    Stmt::Let { name, .. } => names.declare(cx, name, "a `let` binding"),
                    Stmt::Assign { target, derivative, .. } => {
                        let wrong_form = match (process.kind, derivative) {
                            (ProcessKind::Discrete, Some(span)) => {
                                cx.error_at(
                                    *span,
                                    "`d/dt` is only allowed in a `continuous` section; in `discrete` write `state = ..` \
                                     (the next value from the previous ones)",
                                );
                                true
                            }
                            (ProcessKind::Continuous, None) => {
                                cx.error_spanned_by(
                                    target,
                                    format!(
                                        "in a `continuous` section write `d/dt {target} = ..` (or `let {target} = ..` \
                                         for a local value)"
                                    ),
                                );
                                true
                            }
                            _ => false,
                        };
                        let what = if derivative.is_some() { "`d/dt` of" } else { "assignment to" };
                        if !decl.states.iter().any(|s| s.name == *target) {
                            let target_name = target.to_string();
                            // A declared name of another kind: say what it is
                            // rather than suggest a state spelled alike.
                            let hint = match names.kinds.get(&target_name) {
                                Some(kind) => format!(
                                    ", but {kind}: only states are assigned in the process section{}",
                                    match *kind {
                                        "a parameter" | "an input" => {
                                            " (declare it under `states { .. }` to estimate it)"
                                        }
                                        _ => "",
                                    }
                                ),
                                None => {
                                    let states: Vec<String> =
                                        decl.states.iter().map(|s| s.name.to_string()).collect();
                                    let hint = suggest(&target_name, states.clone());
                                    if hint.is_empty() {
                                        format!("; the states are `{}`", states.join("`, `"))
                                    } else {
                                        hint
                                    }
                                }
                            };
                            cx.error_spanned_by(target, format!("{what} `{target}`, which is not a state{hint}"));
                        } else if !wrong_form && assigned.insert(target.to_string(), target).is_some() {
                            // A statement of the wrong form was reported
                            // above; counting it too would add a second,
                            // misleading error at the same place.
                            cx.error_spanned_by(target, format!("state `{target}` is assigned more than once"));
                        }
                    }
                }
            }
        }
    }

    let mut sensor_names: HashMap<String, &Ident> = HashMap::new();
    for sensor in &decl.sensors {
        let name = sensor.name.to_string();
        if sensor_names.insert(name.clone(), &sensor.name).is_some() {
            cx.error_spanned_by(&sensor.name, format!("duplicate sensor `{name}`"));
        }
        if RESERVED_SENSORS.contains(&name.as_str()) {
            cx.error_spanned_by(
                &sensor.name,
                format!(
                    "a sensor named `{name}` would collide with the generated type `{}{name}`",
                    decl.name
                ),
            );
        }
        if sensor.dim == 0 {
            cx.error_spanned_by(&sensor.dim_lit, "a sensor needs at least one output");
        }
        let mut names = model_names.clone();
        for v in &sensor.inputs {
            names.declare(cx, &v.name, "a sensor input");
            check_shape(cx, v);
        }
        for (name, _) in &sensor.lets {
            names.declare(cx, name, "a `let` binding");
        }
        if sensor.h.is_none() {
            cx.error_spanned_by(
                &sensor.name,
                format!(
                    "sensor `{name}` has no measurement: add `h = [..];` with {} component{}",
                    sensor.dim,
                    if sensor.dim == 1 { "" } else { "s" }
                ),
            );
        }
        for stray in &sensor.stray {
            if stray == "h" {
                cx.error_spanned_by(stray, "`h` is given more than once");
            } else {
                cx.error_spanned_by(
                    stray,
                    format!("unexpected `{stray} = ..` in a sensor; expected `h = ..`, `angles = [..]` or `let`"),
                );
            }
        }
        if let Some((_, angles)) = &sensor.angles {
            let mut seen = Vec::new();
            for lit in angles {
                match lit.base10_parse::<usize>() {
                    Ok(i) if i < sensor.dim && !seen.contains(&i) => seen.push(i),
                    Ok(i) if i < sensor.dim => {
                        cx.error_spanned_by(lit, format!("angle component {i} is listed twice"))
                    }
                    _ => cx.error_spanned_by(
                        lit,
                        format!(
                            "angle component out of range: sensor `{name}` has {}, numbered from 0",
                            match sensor.dim {
                                1 => "1 output".to_string(),
                                m => format!("{m} outputs"),
                            }
                        ),
                    ),
                }
            }
        }
    }
}

fn check_shape(cx: &Ctxt, v: &Var) {
    let zero = match v.shape {
        Shape::Scalar => false,
        Shape::Vector(n) => n == 0,
        Shape::Matrix(r, c) => r == 0 || c == 0,
    };
    if zero {
        cx.error_at(v.shape_span, format!("`{}` has a zero dimension", v.name));
    }
}

/// Names declared in one scope, with what declared them.
#[derive(Clone, Default)]
struct Names {
    kinds: HashMap<String, &'static str>,
}

impl Names {
    fn declare(&mut self, cx: &Ctxt, name: &Ident, kind: &'static str) {
        let s = name.to_string();
        if s == "dt" {
            cx.error_spanned_by(
                name,
                "`dt` is reserved: it is the time step of the generated functions",
            );
            return;
        }
        match self.kinds.get(&s) {
            Some(prev) => cx.error_spanned_by(
                name,
                format!("duplicate name `{s}`: already declared as {prev}"),
            ),
            None => {
                self.kinds.insert(s, kind);
            }
        }
    }
}
