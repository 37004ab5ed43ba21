//! PX4 logs on the replay side: reading `reference.csv` back, scoring a
//! replay against PX4's estimate or the truth. The import itself (`navsim
//! import ulog`) is `nav_import::ulog` (docs/ulog.md); its items are
//! re-exported here for the rest of this crate.

pub mod reference;
pub mod replay;
pub mod running_score;

pub use nav_import::ulog::{euler, import, read, CsvFile, ImportError, ImportedLog};
