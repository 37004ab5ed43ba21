//! What can be tuned: a model on a log whose noise parameters can be set
//! and whose replay reports its sensors' innovations. Two kinds: a replay
//! model reading `meta.toml` ([`LogTuning`]) and a declared model replayed
//! from `replay.toml` (`model_replay::MappingTuning`).

use nav_runtime::log::{LogFiles, Warning};

use crate::innovations::SensorInnovations;
use nav_runtime::model::{block_of, blocks};

use crate::{OwnMapping, ReplayModel, ReplayOptions, RunError};

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
    /// The given values of parameter `key` when it is a value of a
    /// `replay.toml` (`sensors.<name>.sigma`: per output; `noise.<name>`:
    /// per scalar), what `--write` of that file scales; `None` for the
    /// others.
    fn mapping_values(&self, key: &str) -> Option<Vec<f64>> {
        let _ = key;
        None
    }
    /// The error for a key that is not a parameter (naming it and the
    /// closest one).
    fn unknown(&self, key: &str) -> RunError {
        unknown_parameter(self, key)
    }
    /// One forward replay with `values` in place of the given ones.
    ///
    /// # Errors
    /// As the model's replay; [`RunError::Diverged`] when the filter
    /// diverges with these values.
    fn replay(&self, values: &[(String, f64)]) -> Result<Replayed, RunError>;
}

/// The aiding sensor whose noise sigma `key` of a `meta.toml` is
/// (`sensors.<sensor>.noise_sigma`, not the IMU's).
fn aiding_sensor(key: &str) -> Option<&str> {
    let sensor = key.strip_prefix("sensors.")?.strip_suffix(".noise_sigma")?;
    (sensor != "imu" && !sensor.contains('.')).then_some(sensor)
}

/// The sensor whose clock offset `key` is (the offset in seconds added to
/// the times of its file, found by searching the sensor's innovation
/// likelihood): `files.<sensor>.time.offset_s` of a `meta.toml`
/// ([`file_clock_of`]) or `sensors.<Name>.time.offset_s` of a
/// `replay.toml` ([`mapped_clock_of`]); `None` for the others.
pub fn clock_of(key: &str) -> Option<&str> {
    file_clock_of(key).or_else(|| mapped_clock_of(key))
}

/// The sensor of a `meta.toml` clock key, `files.<sensor>.time.offset_s`.
pub fn file_clock_of(key: &str) -> Option<&str> {
    let sensor = key.strip_prefix("files.")?.strip_suffix(".time.offset_s")?;
    (!sensor.is_empty() && !sensor.contains('.')).then_some(sensor)
}

/// The sensor of a `replay.toml` clock key, `sensors.<Name>.time.offset_s`.
pub fn mapped_clock_of(key: &str) -> Option<&str> {
    let name = key
        .strip_prefix("sensors.")?
        .strip_suffix(".time.offset_s")?;
    (!name.is_empty() && !name.contains('.')).then_some(name)
}

/// The key of the clock offset of `name`, a sensor fed from `replay.toml`.
pub fn mapped_clock_key(name: &str) -> String {
    format!("sensors.{name}.time.offset_s")
}

/// The key of `sensor`'s clock offset.
pub fn clock_key(sensor: &str) -> String {
    format!("files.{sensor}.time.offset_s")
}

/// `--params KEY` that `t` does not have: an error naming it and the
/// closest key.
fn unknown_parameter<T: Tunable + ?Sized>(t: &T, key: &str) -> RunError {
    let known: Vec<String> = t.parameters().into_iter().map(|(k, _)| k).collect();
    let known: Vec<&str> = known.iter().map(String::as_str).collect();
    RunError::Invalid(format!(
        "--params {key}: not a noise parameter of model {}{}",
        t.model(),
        nav_runtime::suggestion::did_you_mean(key, &known)
    ))
}

/// A replay model on a log directory whose sigmas are in `meta.toml`, and
/// for a vehicle's own sensors and noise in `replay.toml`.
pub struct LogTuning<'a> {
    model: &'a dyn ReplayModel,
    files: &'a LogFiles,
    options: ReplayOptions,
    /// What `replay.toml` gives the sensors fed by name and the own noise.
    own: OwnMapping,
    /// The GNSS fixes carry the receiver's `eph`/`epv`: the section's
    /// sigma is then only a floor under them.
    receiver_sigmas: bool,
}

impl<'a> LogTuning<'a> {
    /// `model` on the log of `files`, each replay with `options`.
    ///
    /// # Errors
    /// The errors of the log's `replay.toml`, for a model that reads one.
    pub fn new(
        model: &'a dyn ReplayModel,
        files: &'a LogFiles,
        options: ReplayOptions,
    ) -> Result<Self, RunError> {
        Ok(Self {
            model,
            files,
            options,
            own: model.own_mapping(files)?,
            receiver_sigmas: receiver_sigmas(files),
        })
    }
}

/// Whether a GNSS fix of the log carries the receiver's `eph` or `epv`
/// (read on a reader of its own; a file that cannot be read says no, and
/// the replays then say why).
fn receiver_sigmas(files: &LogFiles) -> bool {
    use nav_runtime::log::GnssRow;
    let Ok(own) = LogFiles::open(files.dir(), files.strictness()) else {
        return false;
    };
    let Ok(Some(mut rows)) = own.rows::<GnssRow>() else {
        return false;
    };
    while let Ok(Some((_, r))) = rows.next_row() {
        if r.eph.is_some() || r.epv.is_some() {
            return true;
        }
    }
    false
}

/// The sensor of key `sensors.<name>.sigma` (a sensor fed by name from
/// `replay.toml`; `meta.toml`'s keys end in `noise_sigma` and the like).
pub fn own_sensor(key: &str) -> Option<&str> {
    let name = key.strip_prefix("sensors.")?.strip_suffix(".sigma")?;
    (!name.is_empty() && !name.contains('.')).then_some(name)
}

/// The keys `noise.<block>` of a declared process noise (scalar `names`
/// with their `values`): one per block (a scalar, or a whole vector tuned
/// as one), with its first scalar's value; a block with a value that is
/// not positive has no scale to find and is left out.
pub fn noise_parameters(names: &[&str], values: &[f64]) -> Vec<(String, f64)> {
    blocks(names)
        .into_iter()
        .filter_map(|block| {
            let key = format!("noise.{block}");
            let v = noise_block(names, values, &key)?;
            v.iter().all(|q| *q > 0.0).then(|| (key, v[0]))
        })
        .collect()
}

/// The values of the scalars of noise key `noise.<block>` (of the scalar
/// noise `names` with their `values`), `None` for another key.
pub fn noise_block(names: &[&str], values: &[f64], key: &str) -> Option<Vec<f64>> {
    let block = key.strip_prefix("noise.")?;
    let v: Vec<f64> = names
        .iter()
        .zip(values)
        .filter(|(n, _)| block_of(n) == block)
        .map(|(_, q)| *q)
        .collect();
    (!v.is_empty()).then_some(v)
}

/// The identified `values` that are values of a `replay.toml`, each with
/// every scalar of its sensor or noise vector ([`Tunable::mapping_values`]
/// scaled by [`scaled_sigmas`]): what `--write` of that file writes.
pub fn tuned_mapping_values(t: &dyn Tunable, values: &[(String, f64)]) -> Vec<(String, Vec<f64>)> {
    values
        .iter()
        .filter_map(|(key, v)| Some((key.clone(), scaled_sigmas(&t.mapping_values(key)?, *v))))
        .collect()
}

/// `values` (of the scalar noise `names`) with each block whose key
/// `noise.<block>` `value_of` gives set to it: its first scalar to that
/// value, the others scaled by the same ratio.
pub fn with_noise_values(
    names: &[&str],
    values: &mut [f64],
    value_of: impl Fn(&str) -> Option<f64>,
) {
    for block in blocks(names) {
        let Some(first) = value_of(&format!("noise.{block}")) else {
            continue;
        };
        let at: Vec<usize> = (0..names.len())
            .filter(|&i| block_of(names[i]) == block)
            .collect();
        let given: Vec<f64> = at.iter().map(|&i| values[i]).collect();
        if given[0] > 0.0 {
            for (&i, v) in at.iter().zip(scaled_sigmas(&given, first)) {
                values[i] = v;
            }
        }
    }
}

/// Whether `key` is a value of `replay.toml` (`sensors.<name>.sigma`,
/// `sensors.<name>.time.offset_s`, `noise.<name>`) rather than of
/// `meta.toml`.
pub fn in_mapping(key: &str) -> bool {
    own_sensor(key).is_some() || mapped_clock_of(key).is_some() || key.starts_with("noise.")
}

/// A sensor's sigmas (per output) with the first set to `first` and the
/// others scaled by the same ratio (a sensor's outputs are tuned together).
pub fn scaled_sigmas(given: &[f64], first: f64) -> Vec<f64> {
    let ratio = first / given[0];
    let mut out: Vec<f64> = given.iter().map(|s| s * ratio).collect();
    out[0] = first;
    out
}

impl Tunable for LogTuning<'_> {
    fn model(&self) -> &str {
        self.model.name()
    }
    /// The sigmas of `meta.toml` the model uses
    /// ([`ReplayModel::uses_noise_parameter`]), then the clock offset of each aiding
    /// sensor that has a noise sigma (its file's `time.offset_s`), then the
    /// sigma of each sensor `replay.toml` feeds by name whose sigmas are
    /// all positive (the first output's; all are scaled together) and each
    /// block of its `[noise]` ([`noise_parameters`]).
    fn parameters(&self) -> Vec<(String, f64)> {
        let mut out = self.files.meta().noise_parameters();
        out.retain(|(k, _)| self.model.uses_noise_parameter(k));
        let clocks: Vec<(String, f64)> = out
            .iter()
            .filter_map(|(k, _)| aiding_sensor(k))
            .filter_map(|s| Some((clock_key(s), self.files.mapping().time_offset(s)?)))
            .collect();
        out.extend(clocks);
        for (name, sigma) in &self.own.sigmas {
            if !sigma.is_empty() && sigma.iter().all(|s| *s > 0.0) {
                out.push((format!("sensors.{name}.sigma"), sigma[0]));
            }
        }
        let names: Vec<&str> = self.own.noise.iter().map(|(n, _)| n.as_str()).collect();
        let values: Vec<f64> = self.own.noise.iter().map(|(_, q)| *q).collect();
        out.extend(noise_parameters(&names, &values));
        // The clock of each sensor fed by name: its file has a time column
        // of its own, so it is searched only when `--params` names it.
        out.extend(
            self.own
                .clocks
                .iter()
                .map(|(name, offset)| (mapped_clock_key(name), *offset)),
        );
        out
    }
    /// The IMU's two noise sigmas, every aiding sensor's noise sigma, and
    /// the clock offset of every aiding file whose times the mapping makes
    /// (a `time` table in its `[files.<sensor>]` section: times from the
    /// row index, an offset or a stamp, a clock already in doubt). A file
    /// with its own time column is trusted unless `--params` names its
    /// clock.
    fn default_parameters(&self) -> Vec<String> {
        let mapped_time = |sensor: &str| {
            self.files
                .mapping()
                .get(sensor)
                .is_some_and(|m| !m.time.is_identity())
        };
        self.parameters()
            .into_iter()
            .map(|(k, _)| k)
            .filter(|k| {
                k == "sensors.imu.gyro_noise_sigma"
                    || k == "sensors.imu.accel_noise_sigma"
                    || aiding_sensor(k).is_some()
                    || self.sensor_of(k).is_some()
                    || file_clock_of(k).is_some_and(mapped_time)
            })
            .collect()
    }
    fn sensor_of<'k>(&self, key: &'k str) -> Option<&'k str> {
        if let Some(name) = own_sensor(key) {
            return self.mapping_values(key).is_some().then_some(name);
        }
        // A GNSS fix with the receiver's `eph`/`epv` has their square as
        // its variance, the section's sigma as a floor: it does not scale
        // with the setting (eq. T3 would drive the floor to zero where
        // `eph` dominates), so that key is tuned by its likelihood.
        aiding_sensor(key).filter(|s| *s != "gnss" || !self.receiver_sigmas)
    }
    fn mapping_values(&self, key: &str) -> Option<Vec<f64>> {
        if let Some(name) = own_sensor(key) {
            let (_, sigma) = self.own.sigmas.iter().find(|(n, _)| n == name)?;
            return Some(sigma.clone());
        }
        if let Some(name) = mapped_clock_of(key) {
            let (_, offset) = self.own.clocks.iter().find(|(n, _)| n == name)?;
            return Some(vec![*offset]);
        }
        let names: Vec<&str> = self.own.noise.iter().map(|(n, _)| n.as_str()).collect();
        let values: Vec<f64> = self.own.noise.iter().map(|(_, q)| *q).collect();
        noise_block(&names, &values, key)
    }
    fn unknown(&self, key: &str) -> RunError {
        if key.starts_with("files.") || in_mapping(key) {
            return unknown_parameter(self, key);
        }
        // The meta's own error names the key and the closest one.
        let mut meta = *self.files.meta();
        meta.set_noise_parameter(key, 1.0).err().map_or_else(
            || {
                // A key of the file that the model's filter does not use.
                let used: Vec<String> = self.parameters().into_iter().map(|(k, _)| k).collect();
                RunError::Invalid(format!(
                    "--params {key}: model {} does not use it (its parameters: {})",
                    self.model(),
                    used.join(", ")
                ))
            },
            RunError::from,
        )
    }
    fn replay(&self, values: &[(String, f64)]) -> Result<Replayed, RunError> {
        let in_meta = |k: &str| file_clock_of(k).is_none() && !in_mapping(k);
        let mut meta = *self.files.meta();
        for (k, v) in values.iter().filter(|(k, _)| in_meta(k)) {
            meta.set_noise_parameter(k, *v).map_err(RunError::from)?;
        }
        let mut files = self.files.with_meta(meta);
        for (k, v) in values {
            if let Some(sensor) = file_clock_of(k) {
                files = files
                    .with_time_offset(sensor, *v)
                    .ok_or_else(|| unknown_parameter(self, k))?;
            } else if in_mapping(k) {
                if self.mapping_values(k).is_none() {
                    return Err(unknown_parameter(self, k));
                }
                files = files.with_mapping_value(k, *v);
            }
        }
        let output = self.model.replay_files(&files, &self.options, None)?;
        Ok(Replayed {
            innovations: output.innovations,
            warnings: output.warnings,
        })
    }
}
