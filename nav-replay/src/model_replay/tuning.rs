//! A declared model replayed from `replay.toml`, as something noise tuning
//! can tune ([`crate::tune::Tunable`]): each mapped sensor's `sigma` (all
//! its outputs scaled together, the value reported is the first output's)
//! and, when asked for, each `[noise]` entry (a vector's scalars scaled
//! together) and each mapped sensor's clock offset
//! (`sensors.<Name>.time.offset_s`, found by the clock search).

use std::path::Path;

use nav_runtime::ekf::Ekf;
use nav_runtime::model::Model;

use super::run::{run, RunOptions, SensorSummary};
use super::{Mapping, ModelReplay, ModelReplayError};
use crate::innovations::SensorInnovations;
use crate::tune::{
    mapped_clock_key, mapped_clock_of, noise_block, noise_parameters, own_sensor,
    with_noise_values, Replayed, Tunable,
};
use crate::RunError;

/// `replay` of a log directory with the mapping `mapping` (read from
/// `mapping_file`).
pub struct MappingTuning<'a, M: Model<N>, const N: usize> {
    replay: &'a ModelReplay<M, N>,
    dir: &'a Path,
    mapping_file: String,
    mapping: Mapping,
    options: RunOptions,
}

impl<'a, M: Model<N>, const N: usize> MappingTuning<'a, M, N> {
    /// The model of `replay` on the log in `dir` with its mapping.
    pub fn new(
        replay: &'a ModelReplay<M, N>,
        dir: &'a Path,
        mapping_file: String,
        mapping: Mapping,
        options: RunOptions,
    ) -> Self {
        Self {
            replay,
            dir,
            mapping_file,
            mapping,
            options,
        }
    }

    /// The mapping with `values` in place of the given ones.
    pub fn mapping_with(&self, values: &[(String, f64)]) -> Mapping {
        let mut m = self.mapping.clone();
        let declared = self.replay.declared();
        for (key, value) in values {
            if let Some(name) = own_sensor(key) {
                let k = declared.sensors.iter().position(|s| s.name == name);
                if let Some(Some(s)) = k.and_then(|k| m.sensors.get_mut(k)) {
                    s.sigma = crate::tune::scaled_sigmas(&s.sigma, *value);
                }
            }
            if let Some(name) = mapped_clock_of(key) {
                let k = declared.sensors.iter().position(|s| s.name == name);
                if let Some(Some(s)) = k.and_then(|k| m.sensors.get_mut(k)) {
                    s.source.time_offset_s = *value;
                }
            }
        }
        with_noise_values(&declared.noise, &mut m.noise, |key| {
            values.iter().find(|(k, _)| k == key).map(|(_, v)| *v)
        });
        m
    }

    fn summary_innovations(&self, s: &SensorSummary) -> SensorInnovations {
        let k = self
            .replay
            .declared()
            .sensors
            .iter()
            .position(|d| d.name == s.name);
        let sigma = k
            .and_then(|k| self.mapping.sensors.get(k))
            .and_then(Option::as_ref)
            .and_then(|m| (m.sigma.len() == 1).then(|| m.sigma[0]));
        SensorInnovations {
            sensor: s.name.to_string(),
            noise_sigma: sigma,
            gated: s.gated,
            setting: (
                self.mapping_file.clone(),
                format!("sensors.{}.sigma", s.name),
            ),
            totals: s.innovations,
        }
    }
}

impl<M: Model<N>, const N: usize> Tunable for MappingTuning<'_, M, N>
where
    Ekf<M, N>: Clone,
{
    fn model(&self) -> &str {
        self.replay.name()
    }
    fn parameters(&self) -> Vec<(String, f64)> {
        let declared = self.replay.declared();
        let mut out = Vec::new();
        for (d, m) in declared.sensors.iter().zip(&self.mapping.sensors) {
            // A sensor fed by the log whose sigmas are all positive (a
            // zero sigma has no scale to find).
            if let Some(m) = m.as_ref().filter(|m| m.sigma.iter().all(|s| *s > 0.0)) {
                out.push((format!("sensors.{}.sigma", d.name), m.sigma[0]));
            }
        }
        out.extend(noise_parameters(&declared.noise, &self.mapping.noise));
        // Each mapped file's clock: its times come from its own column, so
        // it is trusted (not in the default set) unless `--params` names it.
        for (d, m) in declared.sensors.iter().zip(&self.mapping.sensors) {
            if let Some(m) = m {
                out.push((mapped_clock_key(d.name), m.source.time_offset_s));
            }
        }
        out
    }
    fn default_parameters(&self) -> Vec<String> {
        self.parameters()
            .into_iter()
            .map(|(k, _)| k)
            .filter(|k| own_sensor(k).is_some())
            .collect()
    }
    fn sensor_of<'k>(&self, key: &'k str) -> Option<&'k str> {
        own_sensor(key)
    }
    fn mapping_values(&self, key: &str) -> Option<Vec<f64>> {
        let declared = self.replay.declared();
        let mapped = |name: &str| {
            let k = declared.sensors.iter().position(|d| d.name == name)?;
            self.mapping.sensors.get(k)?.as_ref()
        };
        if let Some(name) = own_sensor(key) {
            return Some(mapped(name)?.sigma.clone());
        }
        if let Some(name) = mapped_clock_of(key) {
            return Some(vec![mapped(name)?.source.time_offset_s]);
        }
        noise_block(&declared.noise, &self.mapping.noise, key)
    }
    fn replay(&self, values: &[(String, f64)]) -> Result<Replayed, RunError> {
        let mapping = self.mapping_with(values);
        let r = run::<M, N>(
            self.dir,
            &self.mapping_file,
            &mapping,
            &self.replay.feeds,
            &self.options,
            None,
        )
        .map_err(|e| match e {
            ModelReplayError::Log(e) => RunError::Log(e),
            e => RunError::Invalid(e.to_string()),
        })?;
        Ok(Replayed {
            innovations: r
                .sensors
                .iter()
                .map(|s| self.summary_innovations(s))
                .collect(),
            warnings: r.warnings,
        })
    }
}
