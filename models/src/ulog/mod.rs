//! PX4 logs on the replay side: reading `reference.csv` back, scoring a
//! replay against PX4's estimate or the truth. The import itself (`navsim
//! import ulog`) is `nav_import::ulog` (docs/ulog.md), which this crate
//! does not depend on: it reads log directories only.

pub mod reference;
pub mod replay;
pub mod running_score;
