//! Spellings of names: the constant and module names generated from declared
//! names, "did you mean" suggestions for unknown ones, and collisions of
//! generated type names.

use super::parse::Item;

/// `velocity_error` -> `VELOCITY_ERROR`.
pub fn screaming_case(name: &str) -> String {
    let mut out = String::new();
    let mut prev_lower = false;
    for ch in name.trim_start_matches("r#").chars() {
        if ch.is_uppercase() && prev_lower {
            out.push('_');
        }
        prev_lower = ch.is_lowercase() || ch.is_ascii_digit();
        out.extend(ch.to_uppercase());
    }
    out
}

/// `" ; did you mean `x`?"` for the closest candidate, if close: at most a
/// third of the longer name's letters apart (at least one), counting a
/// swapped pair of neighbours as one edit and ignoring case, so `Fxi` finds
/// `Fix` and `dvl` finds `Dvl`.
pub fn suggest(name: &str, candidates: impl IntoIterator<Item = String>) -> String {
    let mut best: Option<(usize, String)> = None;
    for c in candidates {
        let d = edit_distance(&name.to_lowercase(), &c.to_lowercase());
        let limit = 1.max(name.chars().count().max(c.chars().count()) / 3);
        let better = match &best {
            None => true,
            Some((bd, bc)) => (d, &c) < (*bd, bc),
        };
        if d <= limit && better {
            best = Some((d, c));
        }
    }
    match best {
        Some((_, c)) => format!("; did you mean `{c}`?"),
        None => String::new(),
    }
}

/// Edit distance with insertions, deletions, substitutions and swaps of two
/// neighbouring letters (optimal string alignment).
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    // d[i][j]: distance of a[..i] and b[..j].
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let sub = d[i - 1][j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut best = sub.min(d[i - 1][j] + 1).min(d[i][j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

/// `Leveling6` -> `leveling6`, `MarkerFix` -> `marker_fix`.
pub fn snake_case(name: &str) -> String {
    let mut out = String::new();
    let mut prev_lower = false;
    for ch in name.chars() {
        if ch.is_uppercase() && prev_lower {
            out.push('_');
        }
        prev_lower = ch.is_lowercase() || ch.is_ascii_digit();
        out.extend(ch.to_lowercase());
    }
    out
}

/// Sensors whose generated type names (`ModelSensor`, `ModelSensorAux`)
/// collide with a type generated for another declaration of the same
/// invocation (`model Cart { sensor Fix .. }` beside `model CartFix`): one
/// error per model, at the first colliding sensor's name, keyed by model
/// name. (Declarations in other invocations are out of a macro's sight: there
/// rustc reports the duplicate types.)
pub fn collisions(items: &[Item]) -> std::collections::HashMap<String, syn::Error> {
    use std::collections::HashMap;
    let records = ["", "State", "Input", "Params", "Noise"];
    // Generated type name -> what generates it.
    let mut owners: HashMap<String, Vec<String>> = HashMap::new();
    let mut add = |ty: String, what: String| owners.entry(ty).or_default().push(what);
    for item in items {
        let name = match item {
            Item::Model(d) => d.name.to_string(),
            Item::Compose(c) => c.name.to_string(),
            Item::Block(_) => continue,
        };
        for r in records {
            add(format!("{name}{r}"), format!("model `{name}`"));
        }
        if let Item::Model(d) = item {
            for s in &d.sensors {
                let what = format!("sensor `{}` of model `{name}`", s.name);
                add(format!("{name}{}", s.name), what.clone());
                if !s.inputs.is_empty() {
                    add(format!("{name}{}Aux", s.name), what);
                }
            }
        }
    }
    let mut errors = HashMap::new();
    for item in items {
        let Item::Model(d) = item else { continue };
        let name = d.name.to_string();
        for s in &d.sensors {
            let ty = format!("{name}{}", s.name);
            let mut tys = vec![ty.clone()];
            if !s.inputs.is_empty() {
                tys.push(format!("{ty}Aux"));
            }
            let me = format!("sensor `{}` of model `{name}`", s.name);
            let clash = tys.iter().find_map(|t| {
                let other = owners[t].iter().find(|w| **w != me)?;
                Some((t.clone(), other.clone()))
            });
            if let Some((t, other)) = clash {
                errors.entry(name.clone()).or_insert_with(|| {
                    syn::Error::new(
                        s.name.span(),
                        format!(
                            "{me} generates the type `{t}`, which {other} also generates; rename the sensor or the model"
                        ),
                    )
                });
            }
        }
    }
    errors
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn suggestions() {
        let cands = || ["velocity", "a", "gyro", "specific_force"].map(String::from);
        let cases = [
            ("velocty", "; did you mean `velocity`?"),
            ("gyr", "; did you mean `gyro`?"),
            ("specific_forc", "; did you mean `specific_force`?"),
            ("zzz", ""),
            ("b", "; did you mean `a`?"),
            // A swapped pair is one edit.
            ("veloctiy", "; did you mean `velocity`?"),
            ("gyor", "; did you mean `gyro`?"),
        ];
        for (name, want) in cases {
            assert_eq!(suggest(name, cands()), want, "{name}");
        }
        // Sensor names: short, capitalized; a swap or a case slip still finds them.
        let sensors = || ["Fix", "Dvl", "Depth", "Usbl"].map(String::from);
        let cases = [
            ("Fxi", "; did you mean `Fix`?"),
            ("dvl", "; did you mean `Dvl`?"),
            ("DVL", "; did you mean `Dvl`?"),
            ("Detph", "; did you mean `Depth`?"),
            ("Usb", "; did you mean `Usbl`?"),
            ("Gps", ""),
        ];
        for (name, want) in cases {
            assert_eq!(suggest(name, sensors()), want, "{name}");
        }
    }

    #[test]
    fn screaming() {
        let cases = [
            ("velocity", "VELOCITY"),
            ("c_bn", "C_BN"),
            ("Vx", "VX"),
            ("gyroBias", "GYRO_BIAS"),
        ];
        for (name, want) in cases {
            assert_eq!(screaming_case(name), want);
        }
    }
}
