//! "Did you mean": the one suggestion rule of every user-facing name lookup
//! (sensor and section names of `meta.toml` and `replay.toml`, mapping keys
//! and columns, model, scenario and fault names on the command line).
//!
//! A name is compared with each valid one ignoring case on both sides, by
//! the optimal-string-alignment distance: insertions, deletions,
//! substitutions, and a swapped pair of neighbouring letters counted as one
//! edit (`dlv` is one edit from `dvl`, `DVL` none). The closest valid name
//! is suggested when at most one edit away, or two for names of
//! [`TWO_EDITS_FROM`] letters or more (two edits in a short name reach other
//! short names as easily); of equally close names, the first listed.

/// Length (of the longer name, in letters) from which two edits are still
/// a likely misspelling.
pub const TWO_EDITS_FROM: usize = 6;

/// The valid name closest to `name` under the rule of the module docs, if
/// any.
pub fn closest_name<'a>(name: &str, valid: &[&'a str]) -> Option<&'a str> {
    let lower = name.to_lowercase();
    let mut best: Option<(usize, &'a str)> = None;
    for v in valid {
        let d = edit_distance(&lower, &v.to_lowercase());
        let longer = name.chars().count().max(v.chars().count());
        let limit = if longer >= TWO_EDITS_FROM { 2 } else { 1 };
        if d <= limit && best.is_none_or(|(b, _)| d < b) {
            best = Some((d, v));
        }
    }
    best.map(|(_, v)| v)
}

/// `"; did you mean `x`?"` for [`closest_name`], or an empty string.
pub fn did_you_mean(name: &str, valid: &[&str]) -> String {
    closest_name(name, valid).map_or(String::new(), |c| format!("; did you mean `{c}`?"))
}

/// Optimal-string-alignment distance of `a` and `b` (characters).
fn edit_distance(a: &str, b: &str) -> usize {
    let (a, b): (Vec<char>, Vec<char>) = (a.chars().collect(), b.chars().collect());
    // Three rows of the table: i - 2, i - 1, i.
    let mut before: Vec<usize> = vec![0; b.len() + 1];
    let mut previous: Vec<usize> = (0..=b.len()).collect();
    let mut current: Vec<usize> = vec![0; b.len() + 1];
    for i in 1..=a.len() {
        current[0] = i;
        for j in 1..=b.len() {
            let substitution = previous[j - 1] + usize::from(a[i - 1] != b[j - 1]);
            let mut d = substitution.min(previous[j] + 1).min(current[j - 1] + 1);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                d = d.min(before[j - 2] + 1);
            }
            current[j] = d;
        }
        std::mem::swap(&mut before, &mut previous);
        std::mem::swap(&mut previous, &mut current);
    }
    previous[b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    const SENSORS: &[&str] = &[
        "imu", "dvl", "depth", "heading", "usbl", "gnss", "baro", "mag",
    ];

    #[test]
    fn the_rule_as_a_table() {
        for (name, expected) in [
            ("dvl", Some("dvl")),
            ("DVL", Some("dvl")),
            ("Dvl", Some("dvl")),
            ("dlv", Some("dvl")),
            ("dvll", Some("dvl")),
            ("dv", Some("dvl")),
            ("detph", Some("depth")),
            ("DEPHT", Some("depth")),
            ("haeding", Some("heading")),
            ("headnig", Some("heading")),
            ("hdg", None),
            ("compass", None),
            ("uslb", Some("usbl")),
            ("gsns", Some("gnss")),
            ("magnetometer", None),
            ("heeadnig", Some("heading")),
            ("xyz", None),
        ] {
            assert_eq!(closest_name(name, SENSORS), expected, "{name}");
        }
        // Case on the valid side too.
        assert_eq!(closest_name("fxi", &["Fix", "Range"]), Some("Fix"));
        assert_eq!(closest_name("FIX", &["Fix", "Range"]), Some("Fix"));
        assert_eq!(
            did_you_mean("rnage", &["Fix", "Range"]),
            "; did you mean `Range`?"
        );
        assert_eq!(did_you_mean("speed", &["Fix", "Range"]), "");
    }

    #[test]
    fn distance_counts_a_swap_as_one_edit() {
        for (a, b, d) in [
            ("", "", 0),
            ("abc", "abc", 0),
            ("abc", "acb", 1),
            ("abc", "ab", 1),
            ("abc", "xbc", 1),
            ("ab", "ba", 1),
            ("abcd", "badc", 2),
            ("", "abc", 3),
        ] {
            assert_eq!(edit_distance(a, b), d, "{a} {b}");
        }
    }
}
