//! ROS 2 bag import: `navsim import mcap FILE --out DIR` reads a bag in MCAP
//! with CDR messages and writes a log directory (docs/mcap.md).
//!
//! The bag is streamed through the `mcap` crate's sans-io reader, a block at
//! a time; only the rows of the output files are kept. The standard message
//! types of [`messages::TYPES`] are understood without a mapping, each
//! feeding one sensor file; a mapping file ([`Mapping`]) says which topic
//! feeds which sensor where a type appears on several topics, and declares
//! frames, the clock, the water density and an origin for positions given
//! in a local frame. A bag is untrusted input: every message is decoded by
//! a bounded reader ([`cdr`]), and an error names the topic and the
//! message's index on it.

pub mod cdr;
mod convert;
pub mod fuzz;
mod mapping;
pub mod messages;
mod mounting;

#[cfg(test)]
mod tests;
#[cfg(any(test, feature = "bag-writer"))]
pub mod writer;

use std::collections::HashMap;
use std::io::Read;
use std::path::{Path, PathBuf};

use crate::ulog::CsvFile;
pub use convert::Converter;
pub use mapping::{Clock, Mapping, Sensor};

/// What can go wrong importing a bag.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ImportError {
    /// The bag, the mapping or the output could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The path.
        path: PathBuf,
        /// The cause.
        #[source]
        source: std::io::Error,
    },
    /// `--out` is something the import must not replace.
    #[error("{}: {reason}", path.display())]
    Refused {
        /// `--out`.
        path: PathBuf,
        /// Why.
        reason: String,
    },
    /// The MCAP container is malformed (truncated, bad record, bad chunk).
    #[error("{file}: {reason}")]
    Container {
        /// The bag as given.
        file: String,
        /// What the MCAP reader found.
        reason: String,
    },
    /// One message is malformed or absurd.
    #[error("{file}: topic `{topic}`, message {index}: {reason}")]
    Message {
        /// The bag as given.
        file: String,
        /// The topic.
        topic: String,
        /// 0-based index of the message on its topic.
        index: u64,
        /// What is wrong, naming the field.
        reason: String,
    },
    /// The mapping file is wrong, or the bag needs one.
    #[error("{file}: {reason}")]
    Mapping {
        /// The mapping file (or the bag, when it needs a mapping).
        file: String,
        /// What is wrong.
        reason: String,
    },
    /// The bag is well formed but lacks what a log directory needs.
    #[error("{file}: {reason}")]
    Unusable {
        /// The bag as given.
        file: String,
        /// What is missing.
        reason: String,
    },
}

/// What an import wrote.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportSummary {
    /// The files and their rows.
    pub files: Vec<(String, usize)>,
    /// Topics read: (topic, type, sensor or "ignored", messages).
    pub topics: Vec<(String, String, String, u64)>,
    /// What was converted, defaulted, dropped or not understood.
    pub warnings: Vec<String>,
}

impl ImportSummary {
    /// Summary for `--json`: `files`, `topics`, `warnings`.
    pub fn json(&self) -> serde_json::Value {
        let files: serde_json::Map<String, serde_json::Value> = self
            .files
            .iter()
            .map(|(n, r)| (n.clone(), serde_json::json!(r)))
            .collect();
        let topics: Vec<serde_json::Value> = self
            .topics
            .iter()
            .map(|(t, ty, s, n)| {
                serde_json::json!({ "topic": t, "type": ty, "sensor": s, "messages": n })
            })
            .collect();
        serde_json::json!({ "files": files, "topics": topics, "warnings": self.warnings })
    }
}

/// The content of a log directory, before it is written.
#[derive(Debug, Clone, PartialEq)]
pub struct ImportedBag {
    /// The CSV files, `imu.csv` first.
    pub files: Vec<CsvFile>,
    /// `meta.toml`.
    pub meta: String,
    /// The summary.
    pub summary: ImportSummary,
}

impl ImportedBag {
    /// The file named `name`, if written.
    pub fn file(&self, name: &str) -> Option<&CsvFile> {
        self.files.iter().find(|f| f.name == name)
    }

    /// Writes the log directory `out` (staged: [`crate::staging`]).
    ///
    /// # Errors
    /// [`ImportError::Io`] naming the path under `out`, or [`ImportError::Refused`].
    pub fn write(&self, out: &Path) -> Result<(), ImportError> {
        let texts: Vec<(&str, String)> = self
            .files
            .iter()
            .map(|f| (f.name, f.text()))
            .chain([("meta.toml", self.meta.clone())])
            .collect();
        let files: Vec<(&str, &[u8])> = texts.iter().map(|(n, t)| (*n, t.as_bytes())).collect();
        crate::staging::write_log_dir(out, &files).map_err(|e| match e {
            crate::staging::StageError::Io { path, source } => ImportError::Io { path, source },
            crate::staging::StageError::Refused { path, reason } => {
                ImportError::Refused { path, reason }
            }
        })
    }
}

/// Reads the bag at `bag` with the mapping file `mapping` (or the defaults)
/// and writes the log directory `out`.
///
/// # Errors
/// Any [`ImportError`]; `out` is left as it was on error.
pub fn import(
    bag: &Path,
    mapping: Option<&Path>,
    out: &Path,
) -> Result<ImportSummary, ImportError> {
    let mapping = match mapping {
        Some(p) => {
            let text = std::fs::read_to_string(p).map_err(|source| ImportError::Io {
                path: p.to_path_buf(),
                source,
            })?;
            Mapping::parse(&p.display().to_string(), &text)?
        }
        None => Mapping::default(),
    };
    let file = std::fs::File::open(bag).map_err(|source| ImportError::Io {
        path: bag.to_path_buf(),
        source,
    })?;
    let imported = read(&bag.display().to_string(), file, &mapping)?;
    imported.write(out)?;
    Ok(imported.summary)
}

/// Largest record (other than a chunk) and largest chunk accepted, bytes:
/// no ROS 2 message of the understood types comes near it.
pub const RECORD_LIMIT: usize = 64 << 20;

/// Reads a bag from `input` (`file` names it in messages), streaming.
///
/// # Errors
/// Any [`ImportError`] but `Io` of the output.
pub fn read(
    file: &str,
    mut input: impl Read,
    mapping: &Mapping,
) -> Result<ImportedBag, ImportError> {
    let container = |reason: String| ImportError::Container {
        file: file.to_string(),
        reason,
    };
    let options = mcap::sans_io::linear_reader::LinearReaderOptions::default()
        .with_record_length_limit(RECORD_LIMIT)
        .with_prevalidate_chunk_crcs(true);
    let mut reader = mcap::sans_io::linear_reader::LinearReader::new_with_options(options);
    let mut cx = Converter::new(file, mapping);
    let mut schemas: HashMap<u16, String> = HashMap::new();
    while let Some(event) = reader.next_event() {
        let event = event.map_err(|e| match e {
            mcap::McapError::UnexpectedEof => container(
                "MCAP: the file ends inside a record or before its footer (truncated bag)".into(),
            ),
            e => container(format!("MCAP: {e}")),
        })?;
        match event {
            mcap::sans_io::linear_reader::LinearReadEvent::ReadRequest(need) => {
                let buf = reader.insert(need.min(1 << 20));
                let n = input.read(buf).map_err(|source| ImportError::Io {
                    path: PathBuf::from(file),
                    source,
                })?;
                // 0 is the end of the file: the reader then says whether it
                // ended inside a record (a truncated bag).
                reader.notify_read(n);
            }
            mcap::sans_io::linear_reader::LinearReadEvent::Record { opcode, data } => {
                let record = mcap::parse_record(opcode, data)
                    .map_err(|e| container(format!("MCAP record 0x{opcode:02x}: {e}")))?;
                match record {
                    mcap::records::Record::Schema { header, .. } => {
                        schemas.insert(header.id, messages::canonical(&header.name));
                    }
                    mcap::records::Record::Channel(ch) => {
                        let ty = schemas.get(&ch.schema_id).cloned().unwrap_or_default();
                        cx.channel(ch.id, &ch.topic, &ty, &ch.message_encoding)?;
                    }
                    mcap::records::Record::Message { header, data } => {
                        cx.message(header.channel_id, header.log_time, &data)?;
                    }
                    _ => {}
                }
            }
        }
    }
    cx.finish()
}
