//! Log importers: other tools' logs into a log directory of the project's
//! format (`docs/log-format.md`).
//!
//! - [`ulog`]: PX4 flight logs (`docs/ulog.md`);
//! - [`mcap`]: ROS 2 bags in MCAP with CDR messages (`docs/mcap.md`).
//!
//! Every importer treats its input as untrusted: a malformed file is an
//! error naming the file and where in it, never a panic, and nothing is
//! allocated from a size read in the file without a bound.

pub mod mcap;
pub mod staging;
pub mod ulog;
