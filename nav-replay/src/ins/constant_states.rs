//! The random-constant states at the end of a run, against their priors:
//! a test of the filter's honesty that needs no truth (docs/trust.md, "A
//! bias beyond its prior"). The sensor and IMU biases are here; the
//! mounting calibration states make the same [`ConstantState`] in
//! [`super::calibration`] (prior mean: the given value).
//!
//! A bias the navigator carries as a random constant (no process noise:
//! the IMU's, the DVL's, the depth sensor's, the compass's, the USBL's) has
//! prior mean zero and variance `P0`. In a linear Gaussian filter the
//! estimate and its error are uncorrelated, so the estimate `b` of a
//! consistent filter spreads as `N(0, P0 - P)`, with `P` the final variance:
//! `z = b / sqrt(P0 - P)` is a standard normal (eq. B1 of
//! docs/trust.md). A `|z|` beyond [`PRIOR_Z_LIMIT`] (one chance in 16,000
//! per component) says the state has taken up an error the model does not
//! carry (a lever arm, a clock lag, a scale, a prior too small), and that
//! the covariance, the NEES and the sigmas of the run are then not to be
//! trusted as they stand.

use nav_ins::{InsFilter, InsVehicle};
use nav_runtime::log::{Warning, WarningKind};
use serde_json::{json, Map, Value};

/// `|z|` beyond which a state is said to be beyond its prior.
pub const PRIOR_Z_LIMIT: f64 = 4.0;

/// Share of its prior variance a component must have lost (that the log
/// taught) before its `z` is formed: below it `P0 - P` is a difference of
/// two nearly equal numbers.
pub const MIN_TAUGHT: f64 = 0.01;

/// One group of a random-constant state (a bias, a mounting calibration)
/// at the end of a run.
#[derive(Clone, Debug, PartialEq)]
pub struct ConstantState {
    /// The state's declared name (`dvl_bias`).
    pub state: &'static str,
    /// The `meta.toml` key of its prior sigma (`sensors.dvl.bias_sigma`).
    pub key: &'static str,
    /// The file of the sensor, for the warning (`dvl.csv`, `imu.csv`).
    pub file: &'static str,
    /// Final estimate per component (the sensor's units; for a calibration
    /// the correction to the given value).
    pub value: Vec<f64>,
    /// Final sigma per component.
    pub sigma: Vec<f64>,
    /// Prior sigma per component.
    pub prior_sigma: Vec<f64>,
    /// `value / sqrt(prior_sigma^2 - sigma^2)` per component (eq. B1);
    /// `None` where the log taught less than [`MIN_TAUGHT`] of the prior.
    pub z: Vec<Option<f64>>,
}

impl ConstantState {
    /// The largest `|z|` of the group (`None`: nothing learned).
    pub fn largest_z(&self) -> Option<f64> {
        self.z.iter().flatten().map(|z| z.abs()).reduce(f64::max)
    }

    /// The group's JSON: `value`, `sigma`, `prior_sigma` and `z` (null
    /// where not formed).
    pub fn json(&self) -> Value {
        json!({
            "value": self.value,
            "sigma": self.sigma,
            "prior_sigma": self.prior_sigma,
            "z": self.z,
        })
    }

    /// The warning of a group beyond its prior, keyed by its prior sigma.
    pub fn warning(&self) -> Option<Warning> {
        let z = self.largest_z().filter(|z| *z > PRIOR_Z_LIMIT)?;
        let list = |v: &[f64]| {
            v.iter()
                .map(|x| format!("{x:.3e}"))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let spread: Vec<f64> = self
            .prior_sigma
            .iter()
            .zip(&self.sigma)
            .map(|(p, s)| (p * p - s * s).max(0.0).sqrt())
            .collect();
        Some(
            Warning::about(
                WarningKind::StateBeyondPrior,
                self.file,
                format!(
                    "{} ends at [{}] against a prior sigma of [{}] and a final sigma of [{}]: \
                     {z:.1} times the spread a consistent filter's estimate has, [{}] \
                     (sqrt(prior^2 - sigma^2): what the log taught; |z| above {PRIOR_Z_LIMIT}). \
                     The state has taken up an error the model does not carry (a mounting, a \
                     clock lag, a scale, or a `{}` too small), and the run's sigmas and NEES are \
                     not to be trusted as they stand",
                    self.state,
                    list(&self.value),
                    list(&self.prior_sigma),
                    list(&self.sigma),
                    list(&spread),
                    self.key,
                ),
            )
            .with_key(self.key),
        )
    }
}

/// A bias group's name, the `meta.toml` key of its prior and its file.
#[derive(Clone, Copy)]
struct BiasGroup {
    state: &'static str,
    key: &'static str,
    file: &'static str,
}

const fn group(state: &'static str, key: &'static str, file: &'static str) -> BiasGroup {
    BiasGroup { state, key, file }
}

const ACCEL: BiasGroup = group("accel_bias", "sensors.imu.accel_bias_sigma", "imu.csv");
const GYRO: BiasGroup = group("gyro_bias", "sensors.imu.gyro_bias_sigma", "imu.csv");
const DVL: BiasGroup = group("dvl_bias", "sensors.dvl.bias_sigma", "dvl.csv");
const DEPTH: BiasGroup = group("depth_bias", "sensors.depth.bias_sigma", "depth.csv");
const COMPASS: BiasGroup = group("compass_bias", "sensors.heading.bias_sigma", "heading.csv");
const USBL: BiasGroup = group("usbl_bias", "sensors.usbl.bias_sigma", "usbl.csv");

/// The random-constant biases of `f` that the vehicle carries, with their
/// priors `prior_sigma` (the filter's initial sigmas, by state index).
pub fn constant_states<V: InsVehicle<N>, const N: usize>(
    f: &InsFilter<V, N>,
    prior_sigma: &[f64; N],
) -> Vec<ConstantState> {
    let nominal = f.nominal();
    let layout = nominal.layout();
    let p = f.covariance();
    // Each bias the navigator keeps as a random constant: where it sits in
    // the state (absent: the vehicle lacks it) and its estimate.
    let at = |group: BiasGroup, index: Option<usize>, value: &[f64]| {
        index.map(|i| (group, i, value.to_vec()))
    };
    let groups = [
        at(
            ACCEL,
            Some(layout.accel_bias),
            nominal.accel_bias.as_slice(),
        ),
        at(GYRO, Some(layout.gyro_bias), nominal.gyro_bias.as_slice()),
        at(DVL, layout.dvl_bias, nominal.dvl_bias.as_slice()),
        at(DEPTH, layout.depth_bias, &[nominal.depth_bias]),
        at(COMPASS, layout.compass_bias, &[nominal.compass_bias]),
        at(USBL, layout.usbl_bias, nominal.usbl_bias.as_slice()),
    ];
    groups
        .into_iter()
        .flatten()
        .filter_map(|(BiasGroup { state, key, file }, at, value)| {
            let indices = at..at + value.len();
            let prior: Vec<f64> = indices.clone().map(|i| prior_sigma[i]).collect();
            // A bias switched off (`bias_sigma` zero: its prior at the
            // navigator's floor) is not a state of the run.
            if prior.iter().all(|s| *s <= nav_ins::SIGMA_FLOOR) {
                return None;
            }
            let sigma: Vec<f64> = indices.clone().map(|i| p[(i, i)].max(0.0).sqrt()).collect();
            let z = (0..value.len())
                .map(|k| z_of(value[k], sigma[k], prior[k]))
                .collect();
            Some(ConstantState {
                state,
                key,
                file,
                value,
                sigma,
                prior_sigma: prior,
                z,
            })
        })
        .collect()
}

/// Eq. B1: `value / sqrt(prior^2 - sigma^2)`, or `None` where the log
/// taught less than [`MIN_TAUGHT`] of the prior variance (or a figure is
/// not finite).
pub fn z_of(value: f64, sigma: f64, prior: f64) -> Option<f64> {
    let p0 = prior * prior;
    let taught = p0 - sigma * sigma;
    (p0 > 0.0 && taught > MIN_TAUGHT * p0 && value.is_finite()).then(|| value / taught.sqrt())
}

/// Puts `states` into `metrics` as `bias_states` (by name) and the
/// warnings of those beyond their priors into `warnings`: what every INS
/// replay's output says of them.
pub fn report(
    states: &[ConstantState],
    metrics: &mut Map<String, Value>,
    warnings: &mut Vec<Warning>,
) {
    let json: Map<String, Value> = states
        .iter()
        .map(|s| (s.state.to_string(), s.json()))
        .collect();
    metrics.insert("bias_states".into(), Value::Object(json));
    warnings.extend(states.iter().filter_map(ConstantState::warning));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn z_is_the_estimate_over_what_the_log_taught() {
        // (value, sigma, prior sigma, z)
        let cases: [(f64, f64, f64, Option<f64>); 7] = [
            (0.3, 0.8, 1.0, Some(0.5)),
            (-1.2, 0.6, 1.0, Some(-1.5)),
            (0.0, 0.0, 2.0, Some(0.0)),
            // Taught less than 1 % of the prior variance: not formed.
            (0.01, 0.999, 1.0, None),
            // Inflated past the prior (a recovery): not formed.
            (0.5, 1.5, 1.0, None),
            // A bias switched off, a value that is not a number.
            (0.0, 0.0, 0.0, None),
            (f64::NAN, 0.5, 1.0, None),
        ];
        for (value, sigma, prior, z) in cases {
            let got = z_of(value, sigma, prior);
            match (got, z) {
                (Some(a), Some(b)) => {
                    assert!((a - b).abs() < 1e-12, "{value} {sigma} {prior}: {a}")
                }
                _ => assert_eq!(got, z, "{value} {sigma} {prior}"),
            }
        }
    }

    fn dvl(z: [Option<f64>; 3]) -> ConstantState {
        ConstantState {
            state: "dvl_bias",
            key: "sensors.dvl.bias_sigma",
            file: "dvl.csv",
            value: vec![0.02, 0.0, 0.0],
            sigma: vec![0.001; 3],
            prior_sigma: vec![0.005; 3],
            z: z.to_vec(),
        }
    }

    #[test]
    fn only_a_z_beyond_the_limit_is_a_warning_keyed_by_the_prior() {
        assert_eq!(dvl([Some(3.9), Some(-3.9), None]).warning(), None);
        assert_eq!(dvl([None; 3]).largest_z(), None);
        let w = dvl([Some(1.0), Some(-4.2), None])
            .warning()
            .expect("beyond the limit");
        assert_eq!(w.kind, WarningKind::StateBeyondPrior);
        assert_eq!(w.key.as_deref(), Some("sensors.dvl.bias_sigma"));
        assert_eq!(w.file.as_deref(), Some("dvl.csv"));
        assert!(w.message.contains("4.2 times"), "{}", w.message);
    }

    #[test]
    fn the_report_lists_every_group_and_warns_of_those_beyond() {
        let (mut metrics, mut warnings) = (Map::new(), Vec::new());
        report(
            &[
                dvl([Some(0.5); 3]),
                ConstantState {
                    state: "gyro_bias",
                    ..dvl([Some(5.0); 3])
                },
            ],
            &mut metrics,
            &mut warnings,
        );
        let json = &metrics["bias_states"];
        assert_eq!(json["dvl_bias"]["z"][0], 0.5);
        assert_eq!(json["gyro_bias"]["prior_sigma"][2], 0.005);
        assert_eq!(warnings.len(), 1);
    }
}
