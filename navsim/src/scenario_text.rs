//! The human-readable text of a scenario result: what `navsim scenario` (and
//! `navsim merge`) print without `--json`.
//!
//! Order: the scenario, the number of runs and the seeds; the headline figures
//! next to the paper's (a note when percentiles come from fewer than
//! [`FEW_RUNS`] runs); the filter health as integer totals over the runs, sensors
//! without data omitted; every other key of the JSON; and where plots go. The
//! text is rendered from the JSON object, so both always agree and the JSON
//! itself is unchanged.

use std::path::Path;

use serde_json::{Map, Value};

use nav_replay::output::report;

/// Below this many runs a p95 or a maximum is flagged as a rough figure.
pub const FEW_RUNS: u64 = 20;

/// One headline figure: a key of the JSON (`a.b` for a nested key), how to call
/// it, its unit and the paper's figure, if the paper gives one.
struct Headline {
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    paper: Option<&'static str>,
}

const fn line(
    key: &'static str,
    label: &'static str,
    unit: &'static str,
    paper: Option<&'static str>,
) -> Headline {
    Headline {
        key,
        label,
        unit,
        paper,
    }
}

const LAWNMOWER_IMU_ONLY: &[Headline] = &[
    line(
        "horizontal_error_final_m",
        "horizontal error at the end",
        "m",
        Some("diverges"),
    ),
    line("horizontal_error_rms_m", "horizontal error RMS", "m", None),
    line("depth_error_rms_m", "depth error RMS", "m", None),
];

const LAWNMOWER_DVL: &[Headline] = &[
    line(
        "horizontal_error_final_m",
        "horizontal error at the end",
        "m",
        Some("about 3.5 m"),
    ),
    line("horizontal_error_rms_m", "horizontal error RMS", "m", None),
    line(
        "depth_error_rms_m",
        "depth error RMS",
        "m",
        Some("within the 0.5 m sensor error"),
    ),
];

const LAWNMOWER_USBL_DEEP: &[Headline] = &[
    line(
        "horizontal_error_rms_m",
        "horizontal error RMS",
        "m",
        Some("bounded, max about 30 m, std about 18 m"),
    ),
    line(
        "horizontal_error_final_m",
        "horizontal error at the end",
        "m",
        None,
    ),
    line("depth_error_rms_m", "depth error RMS", "m", None),
];

const LEVELING_MOVING: &[Headline] = &[
    line(
        "roll_error_mean_deg",
        "roll error, mean",
        "deg",
        Some("0.083 deg"),
    ),
    line(
        "pitch_error_mean_deg",
        "pitch error, mean",
        "deg",
        Some("0.058 deg"),
    ),
    line(
        "roll_error_std_deg",
        "roll error, std",
        "deg",
        Some("0.046 deg"),
    ),
    line(
        "pitch_error_std_deg",
        "pitch error, std",
        "deg",
        Some("0.019 deg"),
    ),
];

const LEVELING_STATIONARY: &[Headline] = &[
    line(
        "roll_error_mean_deg",
        "roll error, mean",
        "deg",
        Some("-0.051 deg"),
    ),
    line(
        "pitch_error_mean_deg",
        "pitch error, mean",
        "deg",
        Some("0.054 deg"),
    ),
    line(
        "roll_error_std_deg",
        "roll error, std",
        "deg",
        Some("0.003 deg"),
    ),
    line(
        "pitch_error_std_deg",
        "pitch error, std",
        "deg",
        Some("0.004 deg"),
    ),
];

const LEVELING_STRAIGHT: &[Headline] = &[
    line("roll_error_mean_deg", "roll error, mean", "deg", None),
    line("pitch_error_mean_deg", "pitch error, mean", "deg", None),
    line(
        "roll_error_std_deg",
        "roll error, std",
        "deg",
        Some("weaker observability than S-type"),
    ),
    line("pitch_error_std_deg", "pitch error, std", "deg", None),
];

const VKF: &[Headline] = &[
    line(
        "vkf.horizontal_error_final_m",
        "VKF-aided, error at the end",
        "m",
        Some("best of the three (plots only)"),
    ),
    line(
        "ins_dvl.horizontal_error_final_m",
        "INS-DVL, error at the end",
        "m",
        None,
    ),
    line(
        "pure_ins.horizontal_error_final_m",
        "pure INS, error at the end",
        "m",
        Some("diverges"),
    ),
    line("vkf.distance_travelled_m", "distance travelled", "m", None),
];

const MARKER_PATH: &[Headline] = &[
    line("path_rms_true_m", "path RMS, true position", "m", None),
    line(
        "path_rms_estimated_m",
        "path RMS, estimated position",
        "m",
        Some("0.528 m average (0.469-0.625)"),
    ),
    line("collisions", "collisions", "", None),
    line(
        "planning_time_s",
        "planning time",
        "s",
        Some("4.5 s average"),
    ),
    line("qp_solve_time_ms", "QP solve time", "ms", None),
];

const DEMO: &[Headline] = &[
    line("depth_error_final_m", "depth error at the end", "m", None),
    line("depth_error_rms_m", "depth error RMS", "m", None),
];

fn headlines(scenario: &str) -> &'static [Headline] {
    match scenario {
        "lawnmower-imu-only" => LAWNMOWER_IMU_ONLY,
        "lawnmower-dvl" | "lawnmower-usbl" => LAWNMOWER_DVL,
        "lawnmower-usbl-deep" => LAWNMOWER_USBL_DEEP,
        "leveling-moving" => LEVELING_MOVING,
        "leveling-stationary" => LEVELING_STATIONARY,
        "leveling-straight" => LEVELING_STRAIGHT,
        "vkf" => VKF,
        "marker-path" => MARKER_PATH,
        _ => DEMO,
    }
}

/// Keys consumed by the header, so they are not repeated under "details".
const HEADER_KEYS: &[&str] = &["scenario", "runs", "seed", "faults", "draw_biases"];
/// Keys of the NEES line.
const NEES_KEYS: &[&str] = &["nees_mean", "nees_dof", "nees_band_95", "nees_consistent"];

fn lookup<'a>(map: &'a Map<String, Value>, key: &str) -> Option<&'a Value> {
    let mut parts = key.split('.');
    let mut v = map.get(parts.next()?)?;
    for p in parts {
        v = v.get(p)?;
    }
    Some(v)
}

fn is_summary(v: &Value) -> bool {
    ["median", "p95", "max"]
        .iter()
        .all(|k| v.get(k).is_some_and(|x| x.is_number() || x.is_null()))
}

fn with_unit(number: String, unit: &str) -> String {
    if unit.is_empty() {
        number
    } else {
        format!("{number} {unit}")
    }
}

/// The value column of a headline: `median X u (p95 Y, max Z)` or `X u`.
fn figure(v: &Value, unit: &str) -> String {
    if is_summary(v) {
        format!(
            "median {} (p95 {}, max {})",
            with_unit(report::format_value(&v["median"]), unit),
            report::format_value(&v["p95"]),
            report::format_value(&v["max"])
        )
    } else {
        with_unit(report::format_value(v), unit)
    }
}

fn seeds_text(seed: u64, runs: u64) -> String {
    match runs {
        0 => "no seeds".to_string(),
        1 => format!("seed {seed}"),
        n => format!("seeds {seed}-{}", seed + n - 1),
    }
}

/// Whether a health entry (one sensor's counts) has any non-zero count.
fn has_data(counts: &Map<String, Value>) -> bool {
    counts
        .values()
        .any(|v| v.as_f64().is_some_and(|x| x != 0.0))
}

/// Order of the per-sensor counts; any other count follows in key order.
const COUNT_ORDER: &[&str] = &["rows", "accepted", "gated", "rejected", "skipped", "stuck"];

fn health_lines(out: &mut String, health: &Map<String, Value>, runs: u64) {
    out.push_str(&format!(
        "\nfilter health (totals over {runs} run{})\n",
        if runs == 1 { "" } else { "s" }
    ));
    let sensors: Vec<(&String, &Map<String, Value>)> = health
        .iter()
        .filter_map(|(k, v)| v.as_object().map(|o| (k, o)))
        .filter(|(_, o)| has_data(o))
        .collect();
    let width = sensors.iter().map(|(k, _)| k.len()).max().unwrap_or(0);
    for (name, counts) in &sensors {
        let mut keys: Vec<&String> = counts
            .keys()
            .filter(|k| COUNT_ORDER.contains(&k.as_str()))
            .collect();
        keys.sort_by_key(|k| COUNT_ORDER.iter().position(|c| c == k));
        keys.extend(counts.keys().filter(|k| !COUNT_ORDER.contains(&k.as_str())));
        let items: Vec<String> = keys
            .iter()
            .filter(|k| {
                matches!(k.as_str(), "rows" | "accepted")
                    || counts[k.as_str()].as_f64().is_some_and(|x| x != 0.0)
            })
            .map(|k| format!("{} {}", report::format_value(&counts[k.as_str()]), k))
            .collect();
        out.push_str(&format!("  {name:width$}  {}\n", items.join(", ")));
    }
    let scalars: Vec<String> = health
        .iter()
        .filter(|(_, v)| !v.is_object())
        .map(|(k, v)| format!("{} {}", report::format_value(v), k.replace('_', " ")))
        .collect();
    if !scalars.is_empty() {
        out.push_str(&format!("  {}\n", scalars.join(", ")));
    }
}

/// Where the plots and per-run CSV files of a result are, for the last line.
#[derive(Debug, Clone, Copy)]
pub enum Plots<'a> {
    /// No `--out` was given.
    NotWritten,
    /// Written to this directory (`--out`).
    WrittenTo(&'a Path),
    /// A merged result: in each shard's output directory.
    InShards,
}

/// The text `navsim scenario` (and `navsim merge`) prints for a result object.
/// A value that is not a scenario object falls back to [`report::human`].
pub fn scenario_text(value: &Value, where_plots_go: Plots<'_>) -> String {
    let Some(map) = value.as_object() else {
        return report::human(value);
    };
    let Some(name) = map.get("scenario").and_then(Value::as_str) else {
        return report::human(value);
    };
    let runs = map.get("runs").and_then(Value::as_u64).unwrap_or(0);
    let seed = map.get("seed").and_then(Value::as_u64).unwrap_or(0);
    let mut out = format!(
        "scenario {name}: {runs} run{}, {}\n",
        if runs == 1 { "" } else { "s" },
        seeds_text(seed, runs)
    );
    if let Some(faults) = map.get("faults").and_then(Value::as_array) {
        let names: Vec<&str> = faults.iter().filter_map(Value::as_str).collect();
        out.push_str(&format!("faults injected: {}\n", names.join(", ")));
    }
    if map.get("draw_biases").and_then(Value::as_bool) == Some(true) {
        out.push_str("sensor biases drawn per run\n");
    }

    // Headline figures against the paper's.
    let rows: Vec<(&Headline, &Value)> = headlines(name)
        .iter()
        .filter_map(|h| lookup(map, h.key).map(|v| (h, v)))
        .collect();
    let mut consumed: Vec<&str> = HEADER_KEYS.to_vec();
    if !rows.is_empty() || map.contains_key("nees_mean") {
        out.push_str("\nresult");
        if rows.iter().any(|(_, v)| is_summary(v)) {
            out.push_str(&format!(" (statistics over the {runs} runs)"));
        }
        out.push('\n');
        let cells: Vec<(String, String, &Headline)> = rows
            .iter()
            .map(|(h, v)| (h.label.to_string(), figure(v, h.unit), *h))
            .collect();
        let label_w = cells.iter().map(|c| c.0.len()).max().unwrap_or(0);
        let fig_w = cells.iter().map(|c| c.1.len()).max().unwrap_or(0);
        for (label, fig, h) in &cells {
            match h.paper {
                Some(p) => out.push_str(&format!("  {label:label_w$}  {fig:fig_w$}  paper: {p}\n")),
                None => out.push_str(&format!("  {label:label_w$}  {fig}\n")),
            }
            if !h.key.contains('.') {
                consumed.push(h.key);
            }
        }
        if let Some(nees) = map.get("nees_mean") {
            let states = map
                .get("nees_dof")
                .and_then(Value::as_u64)
                .map(|n| format!(" of the {n} states"))
                .unwrap_or_default();
            let mut text = format!("  NEES{states}, mean  {}", report::format_value(nees));
            if let Some([lo, hi]) = map
                .get("nees_band_95")
                .and_then(Value::as_array)
                .map(Vec::as_slice)
            {
                text.push_str(&format!(
                    " (95 % band for {runs} runs: [{}, {}]",
                    report::format_value(lo),
                    report::format_value(hi)
                ));
                match map.get("nees_consistent").and_then(Value::as_bool) {
                    Some(true) => text.push_str(", consistent)"),
                    Some(false) => text.push_str(", outside: not consistent)"),
                    None => text.push(')'),
                }
            }
            out.push_str(&text);
            out.push('\n');
            consumed.extend_from_slice(NEES_KEYS);
        }
        if runs < FEW_RUNS && rows.iter().any(|(_, v)| is_summary(v)) {
            out.push_str(&format!(
                "  note: p95 and max of fewer than {FEW_RUNS} runs are rough; use --runs {FEW_RUNS} or more\n"
            ));
        }
    }

    if let Some(health) = map.get("health").and_then(Value::as_object) {
        health_lines(&mut out, health, runs);
        consumed.push("health");
    }
    if let Some(injected) = map.get("faults_injected").and_then(Value::as_object) {
        let items: Vec<String> = injected
            .iter()
            .map(|(k, v)| format!("{k} {}", report::format_value(v)))
            .collect();
        out.push_str(&format!(
            "  samples changed by faults (totals): {}\n",
            items.join(", ")
        ));
        consumed.push("faults_injected");
    }

    // Everything else, as `key  value` lines.
    let rest: Map<String, Value> = map
        .iter()
        .filter(|(k, _)| !consumed.contains(&k.as_str()))
        .map(|(k, v)| (k.clone(), v.clone()))
        .collect();
    if !rest.is_empty() {
        out.push_str("\ndetails (JSON keys; counts are totals over the runs)\n");
        for line in report::human(&Value::Object(rest)).lines() {
            out.push_str("  ");
            out.push_str(line);
            out.push('\n');
        }
    }

    out.push('\n');
    out.push_str(&match where_plots_go {
        Plots::WrittenTo(dir) => format!(
            "plots, per-run CSV and summary.json written to {}\n",
            dir.display()
        ),
        Plots::NotWritten => {
            "plots and per-run CSV: add --out DIR; one JSON object on stdout: add --json\n"
                .to_string()
        }
        Plots::InShards => "plots and per-run CSV: in each shard's --out directory\n".to_string(),
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    /// The JSON of `navsim scenario lawnmower-dvl --runs 2` (numbers shortened).
    fn lawnmower_dvl() -> Value {
        json!({
            "compass_bias_error_final_deg": {"max": 0.1103, "median": 0.0978, "p95": 0.1091},
            "compass_bias_sigma_final_deg": 0.0616,
            "depth_error_rms_m": {"max": 0.3000, "median": 0.1971, "p95": 0.2897},
            "health": {
                "covariance_repairs": 0.0,
                "depth": {"accepted": 2000.0, "gated": 0.0, "rejected": 0.0, "rows": 2000.0, "skipped": 0.0, "stuck": 0.0},
                "dvl": {"accepted": 99990.0, "gated": 10.0, "rejected": 0.0, "rows": 100000.0, "skipped": 0.0, "stuck": 0.0},
                "heading": {"accepted": 1999.0, "gated": 1.0, "rejected": 0.0, "rows": 2000.0, "skipped": 0.0, "stuck": 0.0},
                "replays": 0.0,
                "usbl": {"accepted": 0.0, "gated": 0.0, "rejected": 0.0, "rows": 0.0, "skipped": 0.0, "stuck": 0.0}
            },
            "horizontal_error_final_m": {"max": 4.9140, "median": 2.8738, "p95": 4.7100},
            "horizontal_error_rms_m": {"max": 3.6387, "median": 3.0515, "p95": 3.5800},
            "nees_band_95": [4.115373097378335, 15.763189220193315],
            "nees_consistent": true,
            "nees_dof": 9,
            "nees_mean": 15.6663,
            "runs": 2,
            "runtime_s": {"max": 0.1790, "median": 0.1299, "p95": 0.1741},
            "scenario": "lawnmower-dvl",
            "seed": 1
        })
    }

    fn position(text: &str, needle: &str) -> usize {
        text.find(needle)
            .unwrap_or_else(|| panic!("`{needle}` not in:\n{text}"))
    }

    #[test]
    fn leads_with_scenario_runs_and_headline_against_the_paper() {
        let text = scenario_text(&lawnmower_dvl(), Plots::NotWritten);
        let first = text.lines().next().unwrap();
        assert_eq!(first, "scenario lawnmower-dvl: 2 runs, seeds 1-2");
        let headline = position(&text, "horizontal error at the end");
        let line = text
            .lines()
            .find(|l| l.contains("horizontal error at the end"))
            .unwrap();
        assert!(
            line.contains("median 2.8738 m (p95 4.7100, max 4.9140)"),
            "{line}"
        );
        assert!(line.contains("paper: about 3.5 m"), "{line}");
        let nees = position(&text, "NEES of the 9 states, mean  15.6663");
        assert!(text.contains("[4.1154, 15.7632], consistent)"), "{text}");
        let health = position(&text, "filter health (totals over 2 runs)");
        assert!(headline < nees && nees < health, "{text}");
    }

    #[test]
    fn health_counts_are_integers_and_absent_sensors_are_omitted() {
        let text = scenario_text(&lawnmower_dvl(), Plots::NotWritten);
        assert!(
            text.contains("  dvl      100000 rows, 99990 accepted, 10 gated\n"),
            "{text}"
        );
        assert!(
            text.contains("  depth    2000 rows, 2000 accepted\n"),
            "{text}"
        );
        assert!(text.contains("0 covariance repairs, 0 replays"), "{text}");
        assert!(!text.contains("usbl"), "{text}");
        assert!(!text.contains(".0000"), "counts printed as floats:\n{text}");
        assert!(!text.contains("health:"), "raw health block:\n{text}");
    }

    #[test]
    fn few_runs_are_flagged_and_many_are_not() {
        let text = scenario_text(&lawnmower_dvl(), Plots::NotWritten);
        assert!(
            text.contains("p95 and max of fewer than 20 runs are rough"),
            "{text}"
        );
        let mut many = lawnmower_dvl();
        many["runs"] = json!(100);
        let text = scenario_text(&many, Plots::NotWritten);
        assert!(text.starts_with("scenario lawnmower-dvl: 100 runs, seeds 1-100\n"));
        assert!(!text.contains("rough"), "{text}");
        assert!(text.contains("totals over 100 runs"), "{text}");
    }

    #[test]
    fn says_where_plots_go() {
        let text = scenario_text(&lawnmower_dvl(), Plots::NotWritten);
        assert!(text
            .trim_end()
            .ends_with("add --out DIR; one JSON object on stdout: add --json"));
        let text = scenario_text(&lawnmower_dvl(), Plots::WrittenTo(Path::new("/tmp/x")));
        assert!(text
            .trim_end()
            .ends_with("plots, per-run CSV and summary.json written to /tmp/x"));
        let text = scenario_text(&lawnmower_dvl(), Plots::InShards);
        assert!(text.trim_end().ends_with("in each shard's --out directory"));
    }

    #[test]
    fn other_keys_follow_as_details_without_repeating_the_headline() {
        let text = scenario_text(&lawnmower_dvl(), Plots::NotWritten);
        let details = position(&text, "details (JSON keys");
        assert!(position(&text, "compass_bias_error_final_deg") > details);
        assert!(position(&text, "runtime_s") > details);
        assert_eq!(
            text.matches("horizontal_error_final_m").count(),
            0,
            "{text}"
        );
        assert_eq!(
            text.matches("horizontal error at the end").count(),
            1,
            "{text}"
        );
    }

    #[test]
    fn nested_headlines_and_number_headlines() {
        let v = json!({
            "scenario": "vkf", "runs": 1, "seed": 3,
            "vkf": {"horizontal_error_final_m": 9.2, "distance_travelled_m": 8343.0},
            "ins_dvl": {"horizontal_error_final_m": 10.17},
            "pure_ins": {"horizontal_error_final_m": 3813.0}
        });
        let text = scenario_text(&v, Plots::NotWritten);
        assert!(text.starts_with("scenario vkf: 1 run, seed 3\n"), "{text}");
        assert!(
            text.contains("VKF-aided, error at the end  9.2000 m"),
            "{text}"
        );
        assert!(
            text.contains("pure INS, error at the end   3813 m"),
            "{text}"
        );
        assert!(!text.contains("rough"), "numbers, not percentiles:\n{text}");
    }

    #[test]
    fn faults_and_injected_counts_are_shown() {
        let mut v = lawnmower_dvl();
        v["faults"] = json!(["spikes"]);
        v["faults_injected"] = json!({"spikes": 7474.0});
        let text = scenario_text(&v, Plots::NotWritten);
        assert!(text.contains("faults injected: spikes\n"), "{text}");
        assert!(
            text.contains("samples changed by faults (totals): spikes 7474\n"),
            "{text}"
        );
    }
}
