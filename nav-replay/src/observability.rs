//! The `observability` object of a replay's JSON (docs/observability.md),
//! for any model whose run was recorded: per state its `learned` fraction
//! (and `by_sensor`), the weakest directions with their coefficients by
//! state name, and a warning per estimated state the log did not teach.

use nav_runtime::log::{Warning, WarningKind};
use nav_runtime::smoother::Observability;
use serde_json::{json, Map, Value};

/// A state asked to be estimated (a sensor bias, a state of the user's own
/// block) that the log taught less than this is a warning.
pub const NOT_LEARNED: f64 = 0.1;

/// Coefficients smaller than this are left out of a direction.
const SMALL_COEFFICIENT: f64 = 0.05;

/// The JSON of `o` for the states `names`, and the warnings:
/// `estimated(i, name)` says whether state `i` is one the user asked to
/// estimate (`Some(words added after its name in the warning)`) or part of
/// the navigation solution (`None`: never a warning).
pub fn json<const N: usize>(
    o: &Observability<N>,
    names: &[&str; N],
    estimated: impl Fn(usize, &str) -> Option<&'static str>,
) -> (Value, Vec<Warning>) {
    let mut states = Map::new();
    let mut warnings = Vec::new();
    for (i, name) in names.iter().enumerate() {
        let learned = o.learned[i];
        if learned.is_nan() {
            states.insert((*name).to_string(), json!({"learned": null, "fixed": true}));
            continue;
        }
        let mut entry = json!({"learned": learned});
        if !o.by_sensor.is_empty() {
            let by_sensor: Map<String, Value> = o
                .by_sensor
                .iter()
                .map(|(sensor, l)| ((*sensor).to_string(), Value::from(l[i])))
                .collect();
            entry["by_sensor"] = Value::Object(by_sensor);
        }
        states.insert((*name).to_string(), entry);
        if let (true, Some(whose)) = (learned < NOT_LEARNED, estimated(i, name)) {
            warnings.push(Warning::about(
                WarningKind::Suspicious,
                "observability",
                format!(
                    "state {name}{whose} was not learned on this log ({:.0} % of its prior sigma): its estimate is its prior",
                    learned * 100.0
                ),
            ));
        }
    }
    let weakest: Vec<Value> = o
        .weakest
        .iter()
        .map(|d| {
            let combination: Map<String, Value> = names
                .iter()
                .zip(d.coefficients)
                .filter(|(_, c)| c.abs() >= SMALL_COEFFICIENT)
                .map(|(n, c)| ((*n).to_string(), Value::from(c)))
                .collect();
            json!({"learned": d.learned, "combination": combination})
        })
        .collect();
    (
        json!({"states": states, "weakest": weakest, "skipped_epochs": o.skipped_epochs}),
        warnings,
    )
}
