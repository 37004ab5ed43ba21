//! JSON results, human-readable text and output directories.

use std::path::{Path, PathBuf};

use nav_runtime::stats::Summary;
use serde_json::{Map, Value};

use crate::{metric_values, ReplayOutput, RunError, RunResult};

/// The `{"median","p95","max"}` object of metric `key` over runs.
pub fn summary_of(runs: &[RunResult], key: &str) -> Value {
    summary_value(&metric_values(runs, key))
}

/// The `{"median","p95","max"}` object of values (`null` fields for no values).
pub fn summary_value(values: &[f64]) -> Value {
    let s = Summary::of(values);
    let mut m = Map::new();
    m.insert("median".into(), Value::from(s.median));
    m.insert("p95".into(), Value::from(s.p95));
    m.insert("max".into(), Value::from(s.max));
    Value::Object(m)
}

/// The JSON object of a replay: `model`, `samples`, `runtime_s`, `skipped_rows` (and
/// `skipped_rows_by_file`, `unknown_files`) when `lenient`, then the model's keys.
pub fn replay_json(
    model: &str,
    output: &ReplayOutput,
    lenient: bool,
    skipped: &std::collections::BTreeMap<String, usize>,
    unknown_files: &[String],
) -> Value {
    let mut m = output.metrics.clone();
    m.insert("model".into(), Value::from(model));
    m.insert("samples".into(), Value::from(output.samples));
    m.insert("runtime_s".into(), Value::from(output.runtime_s));
    if lenient {
        m.insert(
            "skipped_rows".into(),
            Value::from(skipped.values().sum::<usize>()),
        );
        let by_file: Map<String, Value> = skipped
            .iter()
            .map(|(k, v)| (k.clone(), Value::from(*v)))
            .collect();
        m.insert("skipped_rows_by_file".into(), Value::Object(by_file));
        let unknown: Vec<Value> = unknown_files
            .iter()
            .map(|f| Value::from(f.as_str()))
            .collect();
        m.insert("unknown_files".into(), Value::Array(unknown));
    }
    Value::Object(m)
}

/// The one-line JSON text of a value.
pub fn json_line(value: &Value) -> String {
    serde_json::to_string(value).unwrap_or_else(|_| "{}".to_string())
}

fn fmt_number(v: &Value) -> String {
    match v.as_f64() {
        Some(x) if v.is_f64() => {
            if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e6) {
                format!("{x:.4e}")
            } else {
                format!("{x:.4}")
            }
        }
        _ => v.to_string(),
    }
}

/// Text of one value for people: whole numbers (counts, even when the JSON
/// spells them `2000.0`) without decimals, other numbers with four, arrays as
/// `[a, b]`, strings without quotes, `null` as `n/a`.
pub fn format_value(v: &Value) -> String {
    match v {
        Value::Number(_) => match v.as_f64() {
            Some(x) if x.fract() == 0.0 && x.abs() < 1e15 => format!("{x:.0}"),
            _ => fmt_number(v),
        },
        Value::Array(items) => {
            let parts: Vec<String> = items.iter().map(format_value).collect();
            format!("[{}]", parts.join(", "))
        }
        Value::String(s) => s.clone(),
        Value::Null => "n/a".to_string(),
        other => other.to_string(),
    }
}

/// Human-readable rendering of a result object: `scenario`/`model` first, then one
/// `key: value` line per key; `{"median","p95","max"}` objects on one line.
pub fn human(value: &Value) -> String {
    let mut out = String::new();
    let Some(map) = value.as_object() else {
        return value.to_string();
    };
    let first = ["scenario", "model", "runs", "seed"];
    let mut keys: Vec<&String> = map.keys().filter(|k| first.contains(&k.as_str())).collect();
    keys.sort_by_key(|k| first.iter().position(|f| f == k));
    keys.extend(map.keys().filter(|k| !first.contains(&k.as_str())));
    let width = keys.iter().map(|k| k.len()).max().unwrap_or(0);
    for k in keys {
        render(&mut out, k, &map[k.as_str()], width, 0);
    }
    out
}

fn render(out: &mut String, key: &str, v: &Value, width: usize, indent: usize) {
    let pad = " ".repeat(indent);
    match v {
        Value::Object(o)
            if o.contains_key("median") && o.contains_key("p95") && o.contains_key("max") =>
        {
            out.push_str(&format!(
                "{pad}{key:width$}  median {}  p95 {}  max {}\n",
                fmt_number(&o["median"]),
                fmt_number(&o["p95"]),
                fmt_number(&o["max"])
            ));
        }
        Value::Object(o) => {
            out.push_str(&format!("{pad}{key}:\n"));
            let w = o.keys().map(|k| k.len()).max().unwrap_or(0);
            for (k, v) in o {
                render(out, k, v, w, indent + 2);
            }
        }
        Value::Array(items) if !items.is_empty() && items.iter().all(is_warning) => {
            out.push_str(&format!("{pad}{key}:\n"));
            render_warnings(out, items, indent + 2);
        }
        other => out.push_str(&format!("{pad}{key:width$}  {}\n", format_value(other))),
    }
}

/// Whether `v` is a warning of the JSON (an object with a `kind` and a
/// `message`).
fn is_warning(v: &Value) -> bool {
    v.get("kind").is_some_and(Value::is_string) && v.get("message").is_some_and(Value::is_string)
}

/// A run of more than this many warnings of one kind and file is shown by
/// its first and a count (the JSON keeps each).
const REPEATS_SHOWN: usize = 3;

/// Warnings one per line, `kind (file:line, key): message`; a run of more
/// than [`REPEATS_SHOWN`] of the same kind and file as its first and a
/// count.
fn render_warnings(out: &mut String, items: &[Value], indent: usize) {
    let pad = " ".repeat(indent);
    let same =
        |a: &Value, b: &Value| a.get("kind") == b.get("kind") && a.get("file") == b.get("file");
    let mut k = 0;
    while k < items.len() {
        let run = items[k..].iter().take_while(|w| same(w, &items[k])).count();
        let shown = if run > REPEATS_SHOWN { 1 } else { run };
        for w in &items[k..k + shown] {
            let text = |f: &str| w.get(f).and_then(Value::as_str);
            let mut place: Vec<String> = Vec::new();
            if let Some(file) = text("file") {
                let line = w.get("line").and_then(Value::as_u64);
                place.push(line.map_or_else(|| file.to_string(), |l| format!("{file}:{l}")));
            }
            if let Some(key) = text("key") {
                place.push(key.to_string());
            }
            let place = if place.is_empty() {
                String::new()
            } else {
                format!(" ({})", place.join(", "))
            };
            out.push_str(&format!(
                "{pad}{}{place}: {}\n",
                text("kind").unwrap_or_default(),
                text("message").unwrap_or_default()
            ));
        }
        if run > shown {
            out.push_str(&format!(
                "{pad}  ... and {} more {} warnings of the same file (all in the JSON)\n",
                run - shown,
                items[k]
                    .get("kind")
                    .and_then(Value::as_str)
                    .unwrap_or_default()
            ));
        }
        k += run;
    }
}

/// An output directory written atomically: files go to a temporary sibling directory
/// and are moved into the target by [`StagedDir::commit`]; dropping an uncommitted
/// `StagedDir` deletes the temporary directory, so an error leaves no partial output.
/// Existing files in the target with other names are kept.
#[derive(Debug)]
pub struct StagedDir {
    target: PathBuf,
    staging: PathBuf,
    committed: bool,
}

impl StagedDir {
    /// Creates the temporary directory next to `target`.
    pub fn new(target: &Path) -> Result<StagedDir, RunError> {
        if target.exists() && !target.is_dir() {
            return Err(RunError::Invalid(format!(
                "{}: exists and is not a directory",
                target.display()
            )));
        }
        let name = target
            .file_name()
            .map(|n| n.to_string_lossy().into_owned())
            .unwrap_or_else(|| "out".into());
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        // A file on the way is said as such (creating under it fails with
        // "File exists", which names neither the file nor the cause).
        if let Some(file) = parent.ancestors().find(|a| a.exists()) {
            if !file.is_dir() {
                return Err(RunError::Invalid(format!(
                    "{}: {} exists and is not a directory",
                    target.display(),
                    file.display()
                )));
            }
        }
        std::fs::create_dir_all(&parent).map_err(|e| RunError::io(&parent, e))?;
        let nanos = std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.subsec_nanos())
            .unwrap_or(0);
        let staging = parent.join(format!(".{name}.partial-{}-{nanos}", std::process::id()));
        std::fs::create_dir(&staging).map_err(|e| RunError::io(&staging, e))?;
        Ok(StagedDir {
            target: target.to_path_buf(),
            staging,
            committed: false,
        })
    }

    /// Where to write files now.
    pub fn path(&self) -> &Path {
        &self.staging
    }

    /// Moves the written files into the target directory.
    pub fn commit(mut self) -> Result<PathBuf, RunError> {
        if !self.target.exists() {
            std::fs::rename(&self.staging, &self.target)
                .map_err(|e| RunError::io(&self.target, e))?;
        } else {
            let entries =
                std::fs::read_dir(&self.staging).map_err(|e| RunError::io(&self.staging, e))?;
            for entry in entries {
                let entry = entry.map_err(|e| RunError::io(&self.staging, e))?;
                let to = self.target.join(entry.file_name());
                std::fs::rename(entry.path(), &to).map_err(|e| RunError::io(&to, e))?;
            }
            std::fs::remove_dir(&self.staging).map_err(|e| RunError::io(&self.staging, e))?;
        }
        self.committed = true;
        Ok(self.target.clone())
    }
}

impl Drop for StagedDir {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.staging);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn human_rendering() {
        let v: Value = serde_json::json!({
            "seed": 1, "scenario": "x", "runs": 3,
            "err_m": {"median": 1.0, "p95": 2.5, "max": 3.0},
            "nested": {"a": 1.5}
        });
        let h = human(&v);
        let lines: Vec<&str> = h.lines().collect();
        assert!(lines[0].starts_with("scenario"));
        assert!(h.contains("median 1.0000  p95 2.5000  max 3.0000"));
        assert!(h.contains("nested:\n  a  1.5000"));
    }

    #[test]
    fn counts_are_integers_and_arrays_are_readable() {
        let v: Value = serde_json::json!({
            "accepted": 99990.0, "band": [4.115373097378335, 15.763189220193315],
            "name": "x", "missing": null, "flag": true
        });
        let h = human(&v);
        assert!(h.contains("accepted  99990\n"), "{h}");
        assert!(h.contains("band      [4.1154, 15.7632]\n"), "{h}");
        assert!(h.contains("name      x\n"), "{h}");
        assert!(h.contains("missing   n/a\n"), "{h}");
        assert!(h.contains("flag      true\n"), "{h}");
    }

    /// Warnings read one per line with their place, and a run of one kind
    /// in one file as its first and a count, not as a line of JSON.
    #[test]
    fn warnings_are_lines_and_repeats_are_counted() {
        let w = |kind: &str, file: &str, message: &str| serde_json::json!({"kind": kind, "file": file, "line": 7, "key": null, "message": message});
        let mut warnings = vec![w("imu_gap", "imu.csv", "a gap")];
        for k in 0..5 {
            warnings.push(w("lockout_recovery", "dvl.csv", &format!("recovery {k}")));
        }
        warnings.push(w("noise_sigma", "meta.toml", "too small"));
        let h = human(&serde_json::json!({"model": "m", "warnings": warnings}));
        let expected = "model     m\nwarnings:\n  imu_gap (imu.csv:7): a gap\n  \
                        lockout_recovery (dvl.csv:7): recovery 0\n    ... and 4 more \
                        lockout_recovery warnings of the same file (all in the JSON)\n  \
                        noise_sigma (meta.toml:7): too small\n";
        assert_eq!(h, expected);
        // No warnings: an empty list.
        let h = human(&serde_json::json!({"warnings": []}));
        assert_eq!(h, "warnings  []\n");
    }

    #[test]
    fn summary_nan_is_null() {
        let v = summary_value(&[]);
        assert_eq!(
            v,
            serde_json::json!({"median": null, "p95": null, "max": null})
        );
    }
}
