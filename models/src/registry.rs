//! Every built-in scenario and replay model of this crate, by name: the
//! registry `navsim` runs them from. Add new scenarios and models here.

use nav_replay::ins::InsReplay;
use nav_runtime::log::did_you_mean;

use crate::demo;
use crate::harness::{ReplayModel, RunError, Scenario};
use crate::vehicles::sdins::{Sdins20, Sdins25Composed};

/// Scenario run by `navsim` without a command (when it is registered).
pub const DEFAULT_SCENARIO: &str = "lawnmower-dvl";
/// Scenario run without a command while [`DEFAULT_SCENARIO`] is not registered.
pub const FALLBACK_SCENARIO: &str = demo::NAME;
/// First seed when `--seed` is not given.
pub const DEFAULT_SEED: u64 = 1;

/// Every built-in scenario. Add new scenarios here.
pub fn scenarios() -> Vec<Box<dyn Scenario>> {
    let mut all: Vec<Box<dyn Scenario>> = vec![Box::new(demo::ConstantVelocity)];
    all.extend(
        crate::leveling::scenarios()
            .into_iter()
            .map(|s| Box::new(s) as Box<dyn Scenario>),
    );
    all.extend(
        crate::sdins25::scenarios()
            .into_iter()
            .map(|s| Box::new(s) as Box<dyn Scenario>),
    );
    all.push(Box::new(crate::marker::MarkerPath));
    all.push(Box::new(crate::vkf::VkfScenario));
    all
}

/// Every replay model. Add new models here.
pub fn replay_models() -> Vec<Box<dyn ReplayModel>> {
    vec![
        Box::new(demo::DepthKf),
        Box::new(crate::leveling::Leveling6Replay),
        Box::new(crate::sdins25::Sdins25Replay::new()),
        Box::new(InsReplay::<Sdins25Composed, 25>::new()),
        Box::new(InsReplay::<Sdins20, 20>::new()),
        Box::new(InsReplay::<crate::vehicles::sdins::Sdins20DvlCal, 28>::new()),
        Box::new(InsReplay::<crate::vehicles::sdins::Sdins25UsblCal, 29>::new()),
        Box::new(InsReplay::<crate::vehicles::pressure_auv::PressureAuv, 20>::new()),
        Box::new(crate::ahrs::AhrsReplay),
        Box::new(crate::gnss_ins::GnssInsReplay),
        Box::new(nav_replay::dead_reckoning::DeadReckoning),
    ]
}

/// The scenario named `name`, or an error listing the valid names.
pub fn find_scenario(name: &str) -> Result<Box<dyn Scenario>, RunError> {
    let all = scenarios();
    let names: Vec<&str> = all.iter().map(|s| s.name()).collect();
    let valid = names.join(", ");
    all.into_iter().find(|s| s.name() == name).ok_or_else(|| {
        RunError::Invalid(format!(
            "unknown scenario `{name}`; valid scenarios: {valid}{}",
            did_you_mean(name, &names)
        ))
    })
}

/// What `--draw-biases` would change: the Monte Carlo runs (`navsim
/// scenario`) or the written log (`navsim simulate`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum BiasesDrawnFor {
    /// `navsim scenario`.
    Runs,
    /// `navsim simulate`.
    Log,
}

/// `--draw-biases` for `scenario`: an error naming the scenarios where it
/// changes something when it would change nothing here (it used to be
/// ignored in silence).
///
/// # Errors
/// [`RunError::Invalid`] as above.
pub fn check_draw_biases(scenario: &dyn Scenario, drawn: BiasesDrawnFor) -> Result<(), RunError> {
    let (takes, command): (fn(&dyn Scenario) -> bool, _) = match drawn {
        BiasesDrawnFor::Runs => (|s| s.draws_biases(), "scenario"),
        BiasesDrawnFor::Log => (|s| s.draws_biases_in_log(), "simulate"),
    };
    if takes(scenario) {
        return Ok(());
    }
    let all = scenarios();
    let names: Vec<&str> = all
        .iter()
        .filter(|s| takes(s.as_ref()))
        .map(|s| s.name())
        .collect();
    Err(RunError::Invalid(format!(
        "--draw-biases: `navsim {command} {}` has no bias to draw on request (the flag would change \
         nothing); it changes `navsim {command}` of: {}",
        scenario.name(),
        names.join(", ")
    )))
}

/// The replay model named `name`, or an error listing the valid names.
pub fn find_replay_model(name: &str) -> Result<Box<dyn ReplayModel>, RunError> {
    let all = replay_models();
    let names: Vec<&str> = all.iter().map(|s| s.name()).collect();
    let valid = names.join(", ");
    all.into_iter().find(|s| s.name() == name).ok_or_else(|| {
        RunError::Invalid(format!(
            "unknown model `{name}`; valid models: {valid}{}",
            did_you_mean(name, &names)
        ))
    })
}

/// The scenario run without a command.
pub fn default_scenario() -> &'static str {
    if scenarios().iter().any(|s| s.name() == DEFAULT_SCENARIO) {
        DEFAULT_SCENARIO
    } else {
        FALLBACK_SCENARIO
    }
}
