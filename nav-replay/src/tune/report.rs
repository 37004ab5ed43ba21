//! The JSON of a tuning (`navsim tune --json`; the human output renders
//! the same object).

use serde_json::{json, Map, Value};

use super::{ParameterKind, Tuning};

impl Tuning {
    /// `model`, `replays`, `converged`, `parameters` (per key: `initial`,
    /// `value`, `log_standard_error` (a clock offset: `standard_error_s`),
    /// `identifiable`, `reason`, `method`),
    /// `nis` (per sensor: `before`, `after`) and `log_likelihood`
    /// (`before`, `after`).
    pub fn json(&self) -> Value {
        let parameters: Map<String, Value> = self
            .parameters
            .iter()
            .map(|p| {
                let e = p.log_standard_error;
                let mut entry = json!({
                    "initial": p.initial,
                    "value": p.value,
                    "identifiable": p.not_identifiable.is_none(),
                    "reason": p.not_identifiable,
                    "method": match p.kind {
                        ParameterKind::SensorNoise => "sensor innovations",
                        ParameterKind::Likelihood => "likelihood",
                        ParameterKind::ClockOffset => "clock search",
                    },
                });
                let error_key = match p.kind {
                    ParameterKind::ClockOffset => "standard_error_s",
                    _ => "log_standard_error",
                };
                entry[error_key] = json!(e.is_finite().then_some(e));
                (p.key.clone(), entry)
            })
            .collect();
        let nis: Map<String, Value> = self
            .nis
            .iter()
            .map(|(s, (b, a))| (s.clone(), json!({"before": b, "after": a})))
            .collect();
        json!({
            "model": self.model,
            "replays": self.replays,
            "converged": self.converged,
            "parameters": parameters,
            "nis": nis,
            "log_likelihood": {
                "before": self.log_likelihood.0,
                "after": self.log_likelihood.1,
            },
        })
    }

    /// The tuned values of the parameters the log identifies (what
    /// `--write` changes in `meta.toml`).
    pub fn identified_values(&self) -> Vec<(String, f64)> {
        self.parameters
            .iter()
            .filter(|p| p.not_identifiable.is_none())
            .map(|p| (p.key.clone(), p.value))
            .collect()
    }
}
