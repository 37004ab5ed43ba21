//! Workspace scenarios: the papers' systems, the smoother, the lock-out recovery,
//! reliability under faults and the build checks, one file each. One test
//! binary, each file a module of it, so that the suite compiles and links
//! the models and their dependencies once instead of once per file.

mod cli_plumbing;
mod filter_only;
mod leveling;
mod lockout_recovery;
mod marker_path;
mod no_std;
mod reliability_faults;
mod reliability_soak;
mod sdins25_scenarios;
mod smoother;
mod vkf_scenario;
