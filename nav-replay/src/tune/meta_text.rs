//! The log's `meta.toml` with tuned values: the file as the user wrote it
//! (comments, order, mapping sections) with only the tuned keys' values
//! changed, checked by reading it back.

use nav_runtime::log::Meta;

use super::tunable::{file_clock_of, in_mapping, mapped_clock_of};
use crate::RunError;

/// `text` (a `meta.toml`) with each `(key, value)` of `values` set, keys as
/// `sensors.<sensor>.<name>`. Only the value of each key's line changes
/// (the rest of the line, a comment, is kept).
///
/// # Errors
/// A key whose line is not found under its `[sensors.<sensor>]` header (a
/// file that writes its sections as inline tables), or a result that does
/// not read back to the values asked for.
pub fn tuned_meta_text(text: &str, values: &[(String, f64)]) -> Result<String, RunError> {
    // The sigmas of sensors fed by name and the own noise are `replay.toml`'s.
    let values: Vec<(String, f64)> = values
        .iter()
        .filter(|(k, _)| !in_mapping(k))
        .cloned()
        .collect();
    let texts: Vec<(String, String)> = values
        .iter()
        .filter(|(k, _)| file_clock_of(k).is_none())
        .map(|(k, v)| (k.clone(), format!("{v:?}")))
        .collect();
    let mut out = with_values(text, "meta.toml", &texts)?;
    for (key, value) in &values {
        if let Some(sensor) = file_clock_of(key) {
            out = with_clock_offset(&out, "meta.toml", &format!("files.{sensor}"), *value)?;
        }
    }
    let (meta, mapping, _) = Meta::parse_log(&out).map_err(RunError::from)?;
    for (key, value) in &values {
        let read = match file_clock_of(key) {
            Some(sensor) => mapping.time_offset(sensor),
            None => meta.noise_parameter(key),
        };
        if read != Some(*value) {
            return Err(RunError::Invalid(format!(
                "meta.toml: `{key}` does not read back as {value} after writing"
            )));
        }
    }
    Ok(out)
}

/// `text` (the TOML file `file`: a `meta.toml`, `section` being
/// `files.<sensor>`, or a `replay.toml`, `sensors.<Name>`) with `offset_s`
/// of the section's `time` set to `value`: in the section's one-line `time
/// = { ... }` table (the key replaced or added), a `time = "column"` made
/// `time = { column = "column", offset_s = ... }`, or in its
/// `[<section>.time]` table, or as a new `time = { offset_s = ... }` line
/// under the section's header, or in a new section at the end.
///
/// # Errors
/// A `time` table of the section that spans several lines.
fn with_clock_offset(
    text: &str,
    file: &str,
    section: &str,
    value: f64,
) -> Result<String, RunError> {
    let subtable = format!("{section}.time");
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let header_of = |line: &str| {
        let code = line.split('#').next().unwrap_or("").trim();
        code.starts_with('[').then(|| {
            code.trim_matches(|c| c == '[' || c == ']')
                .trim()
                .to_string()
        })
    };
    let mut current = String::new();
    let mut header_at = None;
    for (n, line) in lines.iter().enumerate() {
        if let Some(h) = header_of(line) {
            current = h;
            if current == section {
                header_at = Some(n);
            }
            if current == subtable {
                let key = format!("{subtable}.offset_s");
                let done = with_values(text, file, &[(key, format!("{value:?}"))]);
                return done.or_else(|_| {
                    lines.insert(n + 1, format!("offset_s = {value:?}"));
                    Ok(lines.join("\n") + "\n")
                });
            }
            continue;
        }
        if current != section {
            continue;
        }
        let Some((k, rest)) = line.split_once('=') else {
            continue;
        };
        if k.trim() != "time" {
            continue;
        }
        let prefix = &line[..line.len() - rest.len()];
        let code = rest.split('#').next().unwrap_or("");
        let given = format!("v = {}", code.trim()).parse::<toml::Table>();
        if let Some(toml::Value::String(column)) = given.ok().and_then(|mut t| t.remove("v")) {
            // A column name alone: the table of the column and the offset.
            let comment = &rest[code.len()..];
            let space = if comment.is_empty() { "" } else { " " };
            lines[n] =
                format!("{prefix} {{ column = {column:?}, offset_s = {value:?} }}{space}{comment}");
            return Ok(lines.join("\n") + "\n");
        }
        let (Some(open), Some(close)) = (rest.find('{'), rest.rfind('}')) else {
            return Err(RunError::Invalid(format!(
                "{file}: `{section}.time` is not a one-line table: the tuned clock offset cannot be written into it"
            )));
        };
        let inner = &rest[open + 1..close];
        let mut entries: Vec<String> = inner
            .split(',')
            .map(str::trim)
            .filter(|e| !e.is_empty() && e.split('=').next().map(str::trim) != Some("offset_s"))
            .map(str::to_string)
            .collect();
        entries.push(format!("offset_s = {value:?}"));
        let new = format!(
            "{prefix}{}{{ {} }}{}",
            &rest[..open],
            entries.join(", "),
            &rest[close + 1..]
        );
        lines[n] = new;
        return Ok(lines.join("\n") + "\n");
    }
    match header_at {
        Some(n) => lines.insert(n + 1, format!("time = {{ offset_s = {value:?} }}")),
        None => {
            lines.push(String::new());
            lines.push(format!("[{section}]"));
            lines.push(format!("time = {{ offset_s = {value:?} }}"));
        }
    }
    Ok(lines.join("\n") + "\n")
}

/// `text` (the TOML file `file`, a `replay.toml`) with each key of
/// `values` (`sensors.<name>.sigma`, `noise.<name>`) set to its values: a
/// number for one value, an array for several. Only the values change, as
/// in [`with_values`]; the result is read back.
///
/// # Errors
/// As [`with_values`]; a result whose values do not read back.
pub fn tuned_mapping_text(
    text: &str,
    file: &str,
    values: &[(String, Vec<f64>)],
) -> Result<String, RunError> {
    let texts: Vec<(String, String)> = values
        .iter()
        .filter(|(key, _)| mapped_clock_of(key).is_none())
        .map(|(key, v)| {
            let cells: Vec<String> = v.iter().map(|s| format!("{s:?}")).collect();
            let value = match cells.as_slice() {
                [one] => one.clone(),
                _ => format!("[{}]", cells.join(", ")),
            };
            (key.clone(), value)
        })
        .collect();
    let mut out = with_values(text, file, &texts)?;
    for (key, v) in values {
        if let (Some(name), [value]) = (mapped_clock_of(key), v.as_slice()) {
            out = with_clock_offset(&out, file, &format!("sensors.{name}"), *value)?;
        }
    }
    let table: toml::Table = out
        .parse()
        .map_err(|e| RunError::Invalid(format!("{file}: not TOML after writing: {e}")))?;
    for (key, want) in values {
        let mut node = Some(&table);
        let mut value = None;
        let parts: Vec<&str> = key.split('.').collect();
        for (i, part) in parts.iter().enumerate() {
            let v = node.and_then(|t| t.get(*part));
            if i + 1 == parts.len() {
                value = v;
            } else {
                node = v.and_then(toml::Value::as_table);
            }
        }
        let read: Option<Vec<f64>> = match value {
            Some(toml::Value::Float(f)) => Some(vec![*f]),
            Some(toml::Value::Integer(i)) => Some(vec![*i as f64]),
            Some(toml::Value::Array(a)) => a.iter().map(toml::Value::as_float).collect(),
            _ => None,
        };
        if read.as_ref() != Some(want) {
            return Err(RunError::Invalid(format!(
                "{file}: `{key}` does not read back as {want:?} after writing"
            )));
        }
    }
    Ok(out)
}

/// `text` (the TOML file `file`) with the value of each dotted key of
/// `values` replaced by the given TOML text, on the key's own line under
/// its section's header; the rest of each line (a comment) is kept.
///
/// # Errors
/// A key that is not on a line of its own under its section's header.
pub fn with_values(
    text: &str,
    file: &str,
    values: &[(String, String)],
) -> Result<String, RunError> {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    for (key, value) in values {
        let Some((section, name)) = key.rsplit_once('.') else {
            return Err(RunError::Invalid(format!(
                "{file}: `{key}`: not a key of a section"
            )));
        };
        let mut current = String::new();
        let mut done = false;
        for line in lines.iter_mut() {
            let code = line.split('#').next().unwrap_or("").trim();
            if code.starts_with('[') {
                current = code
                    .trim_matches(|c| c == '[' || c == ']')
                    .trim()
                    .to_string();
                continue;
            }
            if current != section {
                continue;
            }
            let Some((k, rest)) = line.split_once('=') else {
                continue;
            };
            if k.trim() != name {
                continue;
            }
            let comment = rest.find('#').map(|i| &rest[i..]).unwrap_or("");
            let indent = &line[..line.len() - line.trim_start().len()];
            let new = if comment.is_empty() {
                format!("{indent}{name} = {value}")
            } else {
                format!("{indent}{name} = {value}  {comment}")
            };
            *line = new;
            done = true;
            break;
        }
        if !done {
            return Err(RunError::Invalid(format!(
                "{file}: `{key}` is not on a line of its own under [{section}]: the tuned file cannot be written by changing its value"
            )));
        }
    }
    let mut out = lines.join("\n");
    out.push('\n');
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const META: &str = "# survey 12\n[initial]\nlat = 0.6\nlon = 2.2\ndepth = 10.0\n\n[sensors.imu]\ngyro_noise_sigma = 1e-6   # data sheet\naccel_noise_sigma = 1e-3\n\n[sensors.dvl]\nnoise_sigma = 0.02\nbias_sigma = 0.01\n\n[sensors.depth]\nnoise_sigma = 0.1\n";

    #[test]
    fn only_the_tuned_values_change_and_the_file_reads_back() {
        let values = vec![
            ("sensors.dvl.noise_sigma".to_string(), 0.0312),
            ("sensors.imu.gyro_noise_sigma".to_string(), 2.5e-6),
        ];
        let out = tuned_meta_text(META, &values).unwrap();
        assert!(out.contains("noise_sigma = 0.0312\n"), "{out}");
        assert!(
            out.contains("gyro_noise_sigma = 2.5e-6  # data sheet"),
            "{out}"
        );
        assert!(out.contains("# survey 12"));
        // The depth sensor's noise_sigma is another section's: unchanged.
        assert!(out.contains("[sensors.depth]\nnoise_sigma = 0.1"), "{out}");
        let meta = Meta::parse(&out).unwrap();
        assert_eq!(
            meta.noise_parameter("sensors.dvl.noise_sigma"),
            Some(0.0312)
        );
        assert_eq!(meta.noise_parameter("sensors.dvl.bias_sigma"), Some(0.01));
    }

    /// A clock offset goes into the file's one-line `time` table (replaced
    /// or added), its `[files.<sensor>.time]` table, a new `time` line, or
    /// a new section; each reads back.
    #[test]
    fn a_clock_offset_is_written_where_the_file_keeps_its_time() {
        let key = "files.dvl.time.offset_s".to_string();
        let cases: [(&str, &str); 5] = [
            (
                "[files.dvl]\nfile = \"raw.csv\"\ntime = { from_index = true, period_s = 1.0, offset_s = -0.45 }  # fitted\n",
                "time = { from_index = true, period_s = 1.0, offset_s = 1.0 }  # fitted",
            ),
            (
                "[files.dvl]\ntime = { from_index = true, period_s = 1.0 }\n",
                "time = { from_index = true, period_s = 1.0, offset_s = 1.0 }",
            ),
            (
                "[files.dvl.time]\noffset_s = 0.2\n",
                "offset_s = 1.0",
            ),
            ("[files.dvl]\nfile = \"raw.csv\"\n", "time = { offset_s = 1.0 }"),
            ("", "[files.dvl]\ntime = { offset_s = 1.0 }"),
        ];
        for (section, expected) in cases {
            let text = format!("{META}{section}");
            let out = tuned_meta_text(&text, &[(key.clone(), 1.0)])
                .unwrap_or_else(|e| panic!("{section}: {e}"));
            assert!(out.contains(expected), "{section}\n---\n{out}");
            assert!(out.contains("# survey 12"));
        }
        let several = format!("{META}[files.dvl]\ntime = {{\n  offset_s = 0.1 }}\n");
        assert!(tuned_meta_text(&several, &[(key, 1.0)]).is_err());
    }

    /// The clock of a sensor fed from `replay.toml`: a time column named
    /// alone becomes the table of the column and the offset.
    #[test]
    fn a_mapped_clock_offset_is_written_into_the_sensors_time() {
        let key = "sensors.Fix.time.offset_s".to_string();
        let cases: [(&str, &str); 5] = [
            (
                "file = \"gnss.csv\"\ntime = \"stamp\"  # receiver time\n",
                "time = { column = \"stamp\", offset_s = -0.25 } # receiver time",
            ),
            (
                "time = { column = \"ms\", unit = \"ms\" }\n",
                "time = { column = \"ms\", unit = \"ms\", offset_s = -0.25 }",
            ),
            ("time = { offset_s = 0.5 }\n", "time = { offset_s = -0.25 }"),
            ("file = \"gnss.csv\"\n", "time = { offset_s = -0.25 }"),
            (
                "file = \"gnss.csv\"\ntime=\"t\"\n",
                "time= { column = \"t\", offset_s = -0.25 }",
            ),
        ];
        for (section, expected) in cases {
            let text = format!("[inputs]\nfile = \"in.csv\"\n\n[sensors.Fix]\n{section}");
            let out = tuned_mapping_text(&text, "replay.toml", &[(key.clone(), vec![-0.25])])
                .unwrap_or_else(|e| panic!("{section}: {e}"));
            assert!(out.contains(expected), "{section}\n---\n{out}");
            assert!(out.contains("[inputs]\nfile = \"in.csv\""), "{out}");
        }
    }

    #[test]
    fn a_key_that_is_not_on_its_own_line_is_an_error_naming_it() {
        let inline = "[initial]\nlat = 0.6\nlon = 2.2\ndepth = 10.0\n[sensors]\ndvl = { noise_sigma = 0.02 }\n";
        let e = tuned_meta_text(inline, &[("sensors.dvl.noise_sigma".into(), 0.03)]).unwrap_err();
        assert!(e.to_string().contains("sensors.dvl.noise_sigma"), "{e}");
    }
}
