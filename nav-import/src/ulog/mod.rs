//! PX4 ULog import: `navsim import ulog FILE --out DIR` turns a PX4 flight log
//! into a log directory (`imu.csv`, `mag.csv`, `baro.csv`, `gnss.csv`,
//! `reference.csv`, `truth.csv` when the log has ground truth, `meta.toml`
//! and `noise.toml`). The topic table and the file formats are in
//! `docs/ulog.md`.
//!
//! The ULog format is read by the `px4-ulog` crate, behind a framing pass of
//! our own ([`guard`]) that checks every message before the crate sees it: a
//! ULog file comes from someone else and is untrusted input. A malformed file
//! is an [`ImportError`] naming the file, the byte offset and the message or
//! field; nothing is allocated from a size read in the file (tables grow with
//! the messages actually present).

pub(crate) mod assemble;
mod decode;
mod error;
pub mod fuzz;
pub mod guard;
mod instances;
mod topics;
pub mod writer;

#[cfg(test)]
mod tests;

use std::collections::HashMap;
use std::fmt::Write as _;
use std::path::Path;

use px4_ulog::stream_parser::model::DataMessage;
use px4_ulog::stream_parser::{LogParser, ParameterMessage};

pub use assemble::euler;
pub use error::ImportError;
pub use topics::{PARAMETERS, WANTED};

/// One CSV file of the log directory.
#[derive(Debug, Clone, PartialEq)]
pub struct CsvFile {
    /// File name (`imu.csv`, ...).
    pub name: &'static str,
    /// Column names.
    pub header: Vec<&'static str>,
    /// Row-major values, `header.len()` per row; NaN is an empty cell (a
    /// column the log has no source for).
    pub values: Vec<f64>,
    /// Rows dropped (time not increasing, value not finite).
    pub dropped: usize,
}

impl CsvFile {
    /// Number of rows.
    pub fn rows(&self) -> usize {
        self.values
            .len()
            .checked_div(self.header.len())
            .unwrap_or(0)
    }

    /// Row `r`.
    pub fn row(&self, r: usize) -> Vec<f64> {
        let n = self.header.len();
        self.values[r * n..(r + 1) * n].to_vec()
    }

    /// The time of the first row.
    pub fn first_t(&self) -> Option<f64> {
        self.values.first().copied()
    }

    /// The first row whose time is at or after `t`.
    pub fn row_at_or_after(&self, t: f64) -> Option<usize> {
        (0..self.rows()).find(|&r| self.values[r * self.header.len()] >= t)
    }

    /// Drops the rows before time `t`; returns how many.
    pub fn drop_before(&mut self, t: f64) -> usize {
        let keep = self.row_at_or_after(t).unwrap_or(self.rows());
        self.values.drain(..keep * self.header.len());
        keep
    }

    /// The CSV text.
    pub fn text(&self) -> String {
        let mut out = self.header.join(",");
        out.push('\n');
        for r in 0..self.rows() {
            for (i, v) in self.row(r).iter().enumerate() {
                if i > 0 {
                    out.push(',');
                }
                if i == 0 {
                    let _ = write!(out, "{v:.6}");
                } else if v.is_finite() {
                    let _ = write!(out, "{v}");
                }
            }
            out.push('\n');
        }
        out
    }
}

/// The content of an imported log directory.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedLog {
    /// The CSV files, `imu.csv` first.
    pub files: Vec<CsvFile>,
    /// `meta.toml`.
    pub meta: String,
    /// `noise.toml` (aiding-sensor noise: `[mag]`, `[baro]`, `[gnss]`).
    pub noise: String,
    /// Which topics and instances were used, what was dropped or defaulted.
    pub warnings: Vec<String>,
    /// The replay models and, for those the log cannot serve, what it lacks.
    pub models: Vec<(&'static str, Option<String>)>,
}

impl ImportedLog {
    /// The file named `name`, if written.
    pub fn file(&self, name: &str) -> Option<&CsvFile> {
        self.files.iter().find(|f| f.name == name)
    }

    /// Writes the log directory `dir` all at once (`crate::staging`): an
    /// earlier import there is replaced whole, anything else non-empty is
    /// refused, and a failure leaves `dir` as it was.
    ///
    /// # Errors
    /// [`ImportError::Io`] naming the path under `dir` that failed, or
    /// [`ImportError::Refused`].
    pub fn write(&self, dir: &Path) -> Result<(), ImportError> {
        let texts: Vec<(&str, String)> = self
            .files
            .iter()
            .map(|f| (f.name, f.text()))
            .chain([
                ("meta.toml", self.meta.clone()),
                ("noise.toml", self.noise.clone()),
            ])
            .collect();
        let files: Vec<(&str, &[u8])> = texts.iter().map(|(n, t)| (*n, t.as_bytes())).collect();
        crate::staging::write_log_dir(dir, &files).map_err(|e| match e {
            crate::staging::StageError::Io { path, source } => ImportError::Io { path, source },
            crate::staging::StageError::Refused { path, reason } => {
                ImportError::Refused { path, reason }
            }
        })
    }

    /// Summary for `--json`: `files` (rows per file), `models` (which replay
    /// models the log serves, and what it lacks for the others) and `warnings`.
    pub fn summary(&self) -> serde_json::Value {
        let files: serde_json::Map<String, serde_json::Value> = self
            .files
            .iter()
            .map(|f| (f.name.to_string(), serde_json::json!(f.rows())))
            .collect();
        let models: serde_json::Map<String, serde_json::Value> = self
            .models
            .iter()
            .map(|(m, missing)| {
                let v = match missing {
                    None => serde_json::json!({ "servable": true }),
                    Some(why) => serde_json::json!({ "servable": false, "missing": why }),
                };
                (m.to_string(), v)
            })
            .collect();
        serde_json::json!({ "files": files, "models": models, "warnings": self.warnings })
    }
}

/// Reads the ULog file at `path` and writes the log directory `out`.
///
/// # Errors
/// Any [`ImportError`]; nothing is written unless the whole file was read.
pub fn import(path: &Path, out: &Path) -> Result<ImportedLog, ImportError> {
    let bytes = std::fs::read(path).map_err(|source| ImportError::Io {
        path: path.to_path_buf(),
        source,
    })?;
    let log = read(&path.display().to_string(), &bytes)?;
    log.write(out)?;
    Ok(log)
}

/// Imports the ULog bytes `bytes`; `file` names them in messages.
///
/// A panic inside the ULog crate (a case the framing pass does not yet
/// cover) becomes an [`ImportError::Malformed`] too.
///
/// # Errors
/// Any [`ImportError`] but `Io`.
pub fn read(file: &str, bytes: &[u8]) -> Result<ImportedLog, ImportError> {
    match std::panic::catch_unwind(|| read_unguarded(file, bytes)) {
        Ok(result) => result,
        Err(_) => Err(ImportError::Malformed {
            file: file.to_string(),
            offset: 0,
            reason: "the ULog reader failed on this file (an unchecked malformed message)".into(),
        }),
    }
}

/// [`read`] without the panic guard (for the fuzz target, which must see panics).
///
/// # Errors
/// Any [`ImportError`] but `Io`.
pub fn read_unguarded(file: &str, bytes: &[u8]) -> Result<ImportedLog, ImportError> {
    let malformed = |offset: usize, reason: String| ImportError::Malformed {
        file: file.to_string(),
        offset,
        reason,
    };
    let framing = guard::frames(bytes).map_err(|(offset, reason)| malformed(offset, reason))?;
    let mut collector = decode::Collector::default();
    let mut parameters: HashMap<String, f64> = HashMap::new();
    let mut data_seen = false;
    {
        let mut on_data = |m: &DataMessage| {
            data_seen = true;
            collector.take(m);
        };
        let mut on_parameter = |p: &ParameterMessage| {
            let (name, value, stage) = match p {
                // The f32's shortest decimal (0.015, not 0.014999999664723873).
                ParameterMessage::Float(n, v, s) => {
                    (*n, v.to_string().parse().unwrap_or(f64::NAN), s)
                }
                ParameterMessage::Int32(n, v, s) => (*n, f64::from(*v), s),
            };
            // The initial parameters; changes in flight are not used.
            if *stage == px4_ulog::stream_parser::LogStage::Definitions {
                parameters.insert(name.to_string(), value);
            }
        };
        let mut parser = LogParser::default();
        parser.set_data_message_callback(&mut on_data);
        parser.set_parameter_message_callback(&mut on_parameter);
        parser
            .consume_bytes(&bytes[..guard::HEADER_LEN])
            .map_err(|e| malformed(0, format!("file header: {}", e.description)))?;
        for f in &framing.frames {
            parser
                .consume_bytes(&bytes[f.offset..f.offset + f.len])
                .map_err(|e| {
                    malformed(
                        f.offset,
                        format!("{}: {}", guard::describe(f.kind), clip(&e.description)),
                    )
                })?;
        }
    }
    let mut warnings = Vec::new();
    for (at, next) in &framing.cut {
        warnings.push(format!(
            "{file}: the message at byte {at} is cut by data appended at byte {next} (a log continued after a cut); read on from there"
        ));
    }
    if let Some(at) = framing.truncated_at {
        warnings.push(format!(
            "{file}: the file ends inside the message at byte {at} (truncated log); read up to there"
        ));
    }
    if !data_seen {
        return Err(ImportError::Unusable {
            file: file.to_string(),
            reason: "no data messages (only the definitions section)".into(),
        });
    }
    let origin_us = u64::from_le_bytes(bytes[8..16].try_into().unwrap_or([0; 8])) as f64;
    warnings.push(format!(
        "times are seconds after the log's start (header timestamp {origin_us} us)"
    ));
    assemble::assemble(file, origin_us, collector.tables, &parameters, warnings)
}

/// The crate's message without the format it may quote, at most 200 characters.
fn clip(s: &str) -> String {
    let s = s.split(", format:").next().unwrap_or(s);
    let mut out: String = s.chars().take(200).collect();
    if s.chars().count() > 200 {
        out.push_str("...");
    }
    out
}
