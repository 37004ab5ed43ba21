//! What can be tuned: a model on a log whose noise parameters can be set
//! and whose replay reports its sensors' innovations. Two kinds: a replay
//! model reading `meta.toml` ([`LogTuning`]) and a declared model replayed
//! from `replay.toml` (`model_replay::MappingTuning`).

use nav_runtime::log::{LogFiles, Warning};

use crate::innovations::SensorInnovations;
use crate::{ReplayModel, ReplayOptions, RunError};

/// What one replay of a tuning returns.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Replayed {
    /// Each sensor's innovations.
    pub innovations: Vec<SensorInnovations>,
    /// The replay's warnings.
    pub warnings: Vec<Warning>,
}

/// A model on a log, with noise parameters by key.
pub trait Tunable: Sync {
    /// The model's name.
    fn model(&self) -> &str;
    /// Every parameter that can be tuned, with its given value, in a fixed
    /// order.
    fn parameters(&self) -> Vec<(String, f64)>;
    /// The keys tuned when none are asked for.
    fn default_parameters(&self) -> Vec<String>;
    /// The sensor whose noise sigma parameter `key` is (tuned from its own
    /// innovations, eq. T3), `None` for the others.
    fn sensor_of<'k>(&self, key: &'k str) -> Option<&'k str>;
    /// The error for a key that is not a parameter (naming it and the
    /// closest one).
    fn unknown(&self, key: &str) -> RunError {
        let known: Vec<String> = self.parameters().into_iter().map(|(k, _)| k).collect();
        let known: Vec<&str> = known.iter().map(String::as_str).collect();
        RunError::Invalid(format!(
            "--params {key}: not a noise parameter of model {}{}",
            self.model(),
            nav_runtime::suggestion::did_you_mean(key, &known)
        ))
    }
    /// One forward replay with `values` in place of the given ones.
    ///
    /// # Errors
    /// As the model's replay; [`RunError::Diverged`] when the filter
    /// diverges with these values.
    fn replay(&self, values: &[(String, f64)]) -> Result<Replayed, RunError>;
}

/// A replay model on a log directory whose sigmas are in `meta.toml`.
pub struct LogTuning<'a> {
    model: &'a dyn ReplayModel,
    files: &'a LogFiles,
    options: ReplayOptions,
}

impl<'a> LogTuning<'a> {
    /// `model` on the log of `files`, each replay with `options`.
    pub fn new(model: &'a dyn ReplayModel, files: &'a LogFiles, options: ReplayOptions) -> Self {
        Self {
            model,
            files,
            options,
        }
    }
}

impl Tunable for LogTuning<'_> {
    fn model(&self) -> &str {
        self.model.name()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        self.files.meta().noise_parameters()
    }
    fn default_parameters(&self) -> Vec<String> {
        self.parameters()
            .into_iter()
            .map(|(k, _)| k)
            .filter(|k| {
                k == "sensors.imu.gyro_noise_sigma"
                    || k == "sensors.imu.accel_noise_sigma"
                    || self.sensor_of(k).is_some()
            })
            .collect()
    }
    fn sensor_of<'k>(&self, key: &'k str) -> Option<&'k str> {
        let sensor = key.strip_prefix("sensors.")?.strip_suffix(".noise_sigma")?;
        (sensor != "imu" && !sensor.contains('.')).then_some(sensor)
    }
    fn unknown(&self, key: &str) -> RunError {
        // The meta's own error names the key and the closest one.
        let mut meta = *self.files.meta();
        meta.set_noise_parameter(key, 1.0).err().map_or_else(
            || RunError::Invalid(format!("--params {key}")),
            RunError::from,
        )
    }
    fn replay(&self, values: &[(String, f64)]) -> Result<Replayed, RunError> {
        let mut meta = *self.files.meta();
        for (k, v) in values {
            meta.set_noise_parameter(k, *v).map_err(RunError::from)?;
        }
        let output = self
            .model
            .replay_files(&self.files.with_meta(meta), &self.options, None)?;
        Ok(Replayed {
            innovations: output.innovations,
            warnings: output.warnings,
        })
    }
}
