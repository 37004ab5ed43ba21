//! What a replay writes: the JSON and human report, the time series
//! (streamed to CSV with a bounded copy for plots), the SVG plots, and the
//! staging of `--out` directories that an interruption removes.

pub mod interrupt;
pub mod plot;
pub mod report;
pub mod series;
