//! Spellings of names: the constant and module names generated from declared
//! names, and "did you mean" suggestions for unknown ones.

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

/// `" ; did you mean `x`?"` for the closest candidate by edit distance, if close.
pub fn suggest(name: &str, candidates: impl IntoIterator<Item = String>) -> String {
    let mut best: Option<(usize, String)> = None;
    for c in candidates {
        let d = edit_distance(name, &c);
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

/// Levenshtein distance.
fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut prev: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut cur = vec![i + 1];
        for (j, cb) in b.iter().enumerate() {
            let sub = prev[j] + usize::from(ca != *cb);
            cur.push(sub.min(prev[j + 1] + 1).min(cur[j] + 1));
        }
        prev = cur;
    }
    prev[b.len()]
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
        ];
        for (name, want) in cases {
            assert_eq!(suggest(name, cands()), want, "{name}");
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
