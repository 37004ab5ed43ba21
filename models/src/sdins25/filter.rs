//! The SDINS-25 filter over a log: the generic INS replay of `nav_replay::ins`
//! (re-exported here) run with the paper's model [`Sdins25`].

pub use nav_replay::ins::setup::*;
use nav_runtime::log::LogDir;

use super::model::Sdins25;
use crate::harness::RunError;

/// Number of error states of SDINS-25.
pub const N: usize = 25;

/// The error-state filter of SDINS-25.
pub type Filter = InsFilter<Sdins25, N>;

/// The nominal solution of SDINS-25.
pub type Nominal = InsNominal<Sdins25, N>;

/// The result of an SDINS-25 run over a log.
pub type Sdins25Run = InsRun<Sdins25, N>;

/// Initial SDINS-25 filter: [`initial_vehicle_filter`] of [`Sdins25`].
pub fn initial_filter(log: &LogDir, options: &FilterOptions) -> Result<Filter, RunError> {
    initial_vehicle_filter::<Sdins25, N>(log, options)
}

/// Runs the SDINS-25 filter over `log`: [`run_vehicle`] of [`Sdins25`].
///
/// # Errors
/// As [`run_vehicle`].
pub fn run(
    log: &LogDir,
    options: &FilterOptions,
    record_times: &[f64],
) -> Result<Sdins25Run, RunError> {
    run_vehicle::<Sdins25, N>(log, options, record_times)
}
