//! Each aiding sensor's innovations over a replay: their mean NIS, the share
//! of rows the gate refused, and the noise sigma they support
//! (docs/tuning.md), in the JSON (`innovations`) and as a warning when the
//! given sigma is off by more than a factor of two.

use nav_runtime::innovations::{InnovationTotals, MAX_VARIANCE_STEP};
use nav_runtime::log::{Warning, WarningKind};
use serde_json::{json, Map, Value};

/// A sigma is judged off when the supported one differs by more than this
/// factor (either way).
pub const SIGMA_FACTOR_LIMIT: f64 = 2.0;

/// Fewer updates than this say nothing about a sigma.
pub const MIN_UPDATES: u64 = 10;

/// The supported sigma must be known to this standard error of its
/// logarithm (about +-20 %) before the given one is called off.
pub const MAX_LOG_SIGMA_ERROR: f64 = 0.2;

/// One aiding sensor's innovations over a run.
#[derive(Clone, Debug, PartialEq)]
pub struct SensorInnovations {
    /// The sensor's name (its `meta.toml` section, `dvl`, `usbl`, ...).
    pub sensor: String,
    /// The noise sigma the filter used (units of its file), `None` when the
    /// sensor has one per output.
    pub noise_sigma: Option<f64>,
    /// Rows refused by the gate (their innovations are counted too).
    pub gated: u64,
    /// Where its sigma is set: the file (`meta.toml`, `replay.toml`) and
    /// the key (`sensors.dvl.noise_sigma`), for the warning.
    pub setting: (String, String),
    /// The sums over its updates.
    pub totals: InnovationTotals,
}

impl SensorInnovations {
    /// The factor on the noise sigma the innovations support and the
    /// standard error of its logarithm, when the run measured it.
    pub fn supported_factor(&self) -> Option<(f64, f64)> {
        let f = self.totals.sigma_factor()?;
        let e = self.totals.log_sigma_standard_error();
        (self.totals.updates >= MIN_UPDATES && e <= MAX_LOG_SIGMA_ERROR).then_some((f, e))
    }

    /// The JSON of one sensor: `updates`, `gated_share`, `nis_per_dof`,
    /// `noise_sigma`, `supported_sigma` (or `supported_factor` without one
    /// sigma) and `supported_log_sigma_error`.
    pub fn json(&self) -> Value {
        let t = &self.totals;
        let mut m = Map::new();
        m.insert("updates".into(), json!(t.updates));
        let share = if t.updates > 0 {
            self.gated as f64 / t.updates as f64
        } else {
            0.0
        };
        m.insert("gated_share".into(), json!(share));
        m.insert("nis_per_dof".into(), json!(t.nis_per_dof()));
        m.insert("noise_sigma".into(), json!(self.noise_sigma));
        let factor = t.sigma_factor();
        match (self.noise_sigma, factor) {
            (Some(s), Some(f)) => m.insert("supported_sigma".into(), json!(s * f)),
            _ => m.insert("supported_factor".into(), json!(factor)),
        };
        let e = t.log_sigma_standard_error();
        m.insert(
            "supported_log_sigma_error".into(),
            json!(e.is_finite().then_some(e)),
        );
        Value::Object(m)
    }

    /// The warning when the innovations say the sigma is off by more than
    /// [`SIGMA_FACTOR_LIMIT`].
    pub fn warning(&self) -> Option<Warning> {
        let (f, e) = self.supported_factor()?;
        if (1.0 / SIGMA_FACTOR_LIMIT..=SIGMA_FACTOR_LIMIT).contains(&f) {
            return None;
        }
        let nis = self.totals.nis_per_dof().unwrap_or(f64::NAN);
        // The factor is held to one step of eq. T3 either way: at that
        // bound the log supports at least (or at most) that much.
        let step = MAX_VARIANCE_STEP.sqrt();
        let bound = if f >= step * (1.0 - 1e-12) {
            "at least "
        } else if f <= (1.0 + 1e-12) / step {
            "at most "
        } else {
            ""
        };
        let given = match self.noise_sigma {
            Some(s) => format!(
                "noise_sigma {s:.4} supports {bound}{:.4} (+-{:.0} %)",
                s * f,
                100.0 * e
            ),
            None => format!("its sigmas support {bound}{f:.3} times the given ones"),
        };
        let direction = if f > 1.0 {
            "too small (or the filter's process noise is, or the file's clock is off)"
        } else {
            "too large"
        };
        // A sensor of meta.toml reads a file whose clock tuning can search.
        let clock = if self.setting.0 == "meta.toml" {
            format!(
                " (and its file's clock: `--params files.{}.time.offset_s`)",
                self.sensor
            )
        } else {
            String::new()
        };
        Some(
            Warning::about(
                WarningKind::NoiseSigma,
                &self.setting.0,
                format!(
                    "{}: mean NIS {nis:.2} per component over {} updates ({} gated): its \
                     sigma looks {direction}: {given}; `tune` identifies the noise from the \
                     log{clock}",
                    self.sensor, self.totals.updates, self.gated
                ),
            )
            .with_key(&self.setting.1),
        )
    }
}

/// The JSON `innovations` object: one entry per sensor with updates.
pub fn innovations_json(sensors: &[SensorInnovations]) -> Value {
    Value::Object(
        sensors
            .iter()
            .filter(|s| s.totals.updates > 0)
            .map(|s| (s.sensor.clone(), s.json()))
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use nav_runtime::innovations::InnovationStatistics;
    use nav_runtime::nalgebra::{SMatrix, SVector};

    /// `n` scalar updates whose innovation is `ratio` times the noise
    /// sigma, with `H P H^T` negligible.
    fn sensor(n: u64, ratio: f64) -> SensorInnovations {
        let mut totals = InnovationTotals::default();
        for k in 0..n {
            let sign = if k % 2 == 0 { 1.0 } else { -1.0 };
            totals.add(&InnovationStatistics::of(
                &SVector::<f64, 1>::new(sign * ratio * 0.1),
                &SMatrix::<f64, 1, 1>::new(0.01),
                &SMatrix::<f64, 1, 1>::new(0.01),
            ));
        }
        SensorInnovations {
            sensor: "dvl".into(),
            noise_sigma: Some(0.1),
            gated: 0,
            setting: ("meta.toml".into(), "sensors.dvl.noise_sigma".into()),
            totals,
        }
    }

    #[test]
    fn a_sigma_off_by_more_than_two_is_a_warning_with_the_supported_sigma() {
        // (updates, innovation / sigma, warned)
        let cases = [
            (100, 1.0, false),
            (100, 1.9, false),
            (100, 0.6, false),
            (100, 3.0, true),
            (100, 0.3, true),
            // Too few updates to tell.
            (5, 10.0, false),
        ];
        for (n, ratio, warned) in cases {
            let s = sensor(n, ratio);
            let w = s.warning();
            assert_eq!(w.is_some(), warned, "{n} {ratio}: {w:?}");
            if let Some(w) = w {
                assert_eq!(w.kind, WarningKind::NoiseSigma);
                assert_eq!(w.key.as_deref(), Some("sensors.dvl.noise_sigma"));
                let supported = format!("supports {:.4}", 0.1 * ratio);
                assert!(w.message.contains(&supported), "{}", w.message);
            }
            let j = s.json();
            approx::assert_relative_eq!(
                j["supported_sigma"].as_f64().unwrap(),
                0.1 * ratio,
                max_relative = 1e-9
            );
        }
    }

    #[test]
    fn a_factor_held_at_one_step_is_said_to_be_a_bound() {
        // (innovation / sigma, the message's words): one step of eq. T3 is
        // a factor of 10 on the sigma; "supports 1.0000" for a sigma 30
        // times too small claimed a value the log did not give.
        let cases = [
            (30.0, "supports at least 1.0000"),
            (1.0 / 30.0, "supports at most 0.0100"),
            (5.0, "supports 0.5000"),
            (0.2, "supports 0.0200"),
        ];
        for (ratio, words) in cases {
            let w = sensor(100, ratio).warning().expect("off by more than 2");
            assert!(w.message.contains(words), "{ratio}: {}", w.message);
        }
    }
}
