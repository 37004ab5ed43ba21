//! The mounting calibration states of the DVL, the USBL transponder and
//! the GNSS antenna (docs/calibration.md): the `[sensors.<name>] estimate`
//! of a log's `meta.toml` sets the prior sigma of each of the calibrated
//! block's states (the listed ones from the log, the others zero: fixed at
//! the given value), and the run's final estimate is read back as
//! calibrated values with sigmas.
//!
//! One vehicle serves every subset of `estimate`: its state vector is fixed
//! when it is compiled, and a state with a zero prior sigma gets no gain, so
//! it stays at its prior (the given value) exactly.

use nav_ins::{Builder, InsFilter, InsVehicle};
use nav_runtime::log::{DvlCalibration, Meta, Warning, WarningKind, ESTIMATE_NAMES};

use super::constant_states::{z_of, ConstantState};
use crate::innovations::{SensorInnovations, SIGMA_FACTOR_LIMIT};
use crate::RunError;

/// A sensor whose mounting a vehicle may carry as states: its
/// `[sensors.<name>]`, the states of its calibrated block (the name in
/// [`nav_runtime::log::ESTIMATE_NAMES`] it answers to, the state, its
/// scalars), the block, and a vehicle that has it.
struct Calibratable {
    sensor: &'static str,
    states: &'static [(&'static str, &'static str, usize)],
    block: &'static str,
    vehicle: &'static str,
}

const CALIBRATABLE: [Calibratable; 3] = [
    Calibratable {
        sensor: "dvl",
        states: &[
            ("lever_arm", "dvl_lever_arm", 3),
            ("misalignment", "dvl_misalignment", 3),
            ("scale", "dvl_scale", 1),
            ("time_offset", "dvl_time_offset", 1),
        ],
        block: "DvlCalibrated",
        vehicle: "sdins20-dvl-cal",
    },
    Calibratable {
        sensor: "usbl",
        states: &[
            ("lever_arm", "usbl_lever_arm", 3),
            ("time_offset", "usbl_time_offset", 1),
        ],
        block: "UsblCalibrated",
        vehicle: "sdins25-usbl-cal",
    },
    Calibratable {
        sensor: "gnss",
        states: &[
            ("lever_arm", "gnss_lever_arm", 3),
            ("time_offset", "gnss_time_offset", 1),
        ],
        block: "GnssFixCalibrated",
        vehicle: "a vehicle of your own, as `ShipGnssCal` of examples/ship",
    },
];

impl Calibratable {
    /// Whether vehicle `V` carries these states.
    fn carried_by<V: InsVehicle<N>, const N: usize>(&self) -> bool {
        self.states.iter().all(|(_, name, len)| {
            let first = if *len == 1 {
                (*name).to_string()
            } else {
                format!("{name}[0]")
            };
            V::STATE_NAMES.contains(&first.as_str())
        })
    }
}

/// Whether vehicle `V` carries the DVL calibration states.
pub fn can_calibrate<V: InsVehicle<N>, const N: usize>() -> bool {
    CALIBRATABLE[0].carried_by::<V, N>()
}

/// Sets the prior sigmas of `V`'s calibration states from `meta`.
///
/// # Errors
/// [`RunError::Invalid`] naming the key when an `estimate` lists something
/// and `V` has no calibration states for that sensor; the builder's setup
/// errors.
pub(super) fn register<V: InsVehicle<N>, const N: usize>(
    builder: &mut Builder<V, N>,
    meta: &Meta,
) -> Result<(), RunError> {
    for c in &CALIBRATABLE {
        let cal = meta.sensors.calibration(c.sensor);
        if !c.carried_by::<V, N>() {
            if cal.any() {
                let (sensor, upper) = (c.sensor, c.sensor.to_uppercase());
                return Err(RunError::Invalid(format!(
                    "meta.toml: sensors.{sensor}.estimate = {:?}: vehicle {} cannot estimate the \
                     {upper}'s mounting (its {upper} block has no calibration states); replay with a \
                     vehicle whose {upper} is the `{}` block ({}), or drop the key",
                    cal.names(),
                    V::REPLAY_NAME,
                    c.block,
                    c.vehicle
                )));
            }
            continue;
        }
        for (listed, state, _) in c.states {
            builder.state_sigma(state, prior_sigma(&cal, listed).unwrap_or(0.0))?;
        }
    }
    Ok(())
}

/// The prior sigma of the value `name` of `ESTIMATE_NAMES` when the log
/// lists it.
fn prior_sigma(cal: &DvlCalibration, name: &str) -> Option<f64> {
    let i = ESTIMATE_NAMES.iter().position(|n| *n == name)?;
    cal.sigmas()[i]
}

/// The calibrated value of `filter`'s state `state` (`K` scalars, named
/// `state[0]`.. or `state` for one): the given value `base` plus the
/// state, with its sigma when `prior` (the prior sigma of a listed value)
/// is given; a value not listed has sigma 0.
fn read<V: InsVehicle<N>, const N: usize, const K: usize>(
    filter: &InsFilter<V, N>,
    state: &str,
    base: [f64; K],
    prior: Option<f64>,
) -> Calibrated<K> {
    let first = if K == 1 {
        state.to_string()
    } else {
        format!("{state}[0]")
    };
    let i = V::STATE_NAMES.iter().position(|n| *n == first).unwrap_or(0);
    let (x, p) = (filter.ekf().state(), filter.covariance());
    let sigma = core::array::from_fn(|k| prior.map_or(0.0, |_| p[(i + k, i + k)].max(0.0).sqrt()));
    Calibrated {
        estimated: prior.is_some(),
        given: base,
        value: core::array::from_fn(|k| base[k] + x[i + k]),
        sigma,
        prior_sigma: prior.unwrap_or(0.0),
        z: core::array::from_fn(|k| prior.and_then(|s0| z_of(x[i + k], sigma[k], s0))),
    }
}

/// The given lever arm of `sensor` in `meta` (zero when none is given).
fn given_arm(meta: &Meta, sensor: &str) -> [f64; 3] {
    meta.sensors
        .mounting(sensor)
        .map_or([0.0; 3], |m| m.lever_arm)
}

/// The JSON of one calibrated value (docs/cli-and-json.md), `unit` times
/// the values and sigmas.
fn entry<const K: usize>(c: &Calibrated<K>, unit: f64) -> serde_json::Value {
    let v: Vec<f64> = c.value.iter().map(|v| v * unit).collect();
    let s: Vec<f64> = c.sigma.iter().map(|v| v * unit).collect();
    let one_or_all = |v: &[Option<f64>]| {
        if K == 1 {
            serde_json::json!(v[0])
        } else {
            serde_json::json!(v)
        }
    };
    let as_some = |v: Vec<f64>| v.into_iter().map(Some).collect::<Vec<_>>();
    serde_json::json!({
        "estimated": c.estimated,
        "value": one_or_all(&as_some(v)),
        "sigma": one_or_all(&as_some(s)),
        "prior_sigma": c.prior_sigma * unit,
        "z": one_or_all(&c.z),
    })
}

/// One calibrated value: the estimate and its sigma, per component.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Calibrated<const K: usize> {
    /// Whether `estimate` lists it (else it is the given value, sigma 0).
    pub estimated: bool,
    /// The log's given value (the prior mean).
    pub given: [f64; K],
    /// Estimate: the given value plus the state.
    pub value: [f64; K],
    /// Its sigma (the state's).
    pub sigma: [f64; K],
    /// Prior sigma.
    pub prior_sigma: f64,
    /// The estimate's distance from the given value in sigmas of the
    /// spread a consistent filter's estimate has (eq. B1 of
    /// docs/trust.md); `None` when not estimated or not learned.
    pub z: [Option<f64>; K],
}

impl<const K: usize> Calibrated<K> {
    /// The value as a random-constant state against its prior (the
    /// correction to the given value), for the warning of one beyond it;
    /// `None` when not estimated.
    fn check(
        &self,
        state: &'static str,
        key: &'static str,
        file: &'static str,
    ) -> Option<ConstantState> {
        self.estimated.then(|| ConstantState {
            state,
            key,
            file,
            value: (0..K).map(|k| self.value[k] - self.given[k]).collect(),
            sigma: self.sigma.to_vec(),
            prior_sigma: vec![self.prior_sigma; K],
            z: self.z.to_vec(),
        })
    }

    /// Per component, how many of its sigmas the estimate is off `truth`
    /// (a known value, as in a simulation): about 1 for an honest sigma,
    /// beyond 4 rarely.
    pub fn errors_in_sigmas(&self, truth: [f64; K]) -> [f64; K] {
        core::array::from_fn(|k| (self.value[k] - truth[k]).abs() / self.sigma[k])
    }
}

/// The DVL mounting at the end of a run of a vehicle with calibration
/// states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct DvlMounting {
    /// Lever arm, body axes (FRD) relative to the IMU, m.
    pub lever_arm: Calibrated<3>,
    /// Misalignment: small rotation of the DVL axes from the body axes
    /// beyond the log's given `misalignment`, rad.
    pub misalignment: Calibrated<3>,
    /// Scale factor (the DVL reads this many times the speed).
    pub scale: Calibrated<1>,
    /// Lag of the DVL's clock behind the log's times, s: a row the log
    /// puts at `t` was measured at `t - lag` (the file's `offset_s` less
    /// this aligns it).
    pub time_offset: Calibrated<1>,
}

impl DvlMounting {
    /// The mounting in `filter` (of a vehicle that has the states; `None`
    /// otherwise), with the given values of `meta`.
    pub fn of<V: InsVehicle<N>, const N: usize>(
        filter: &InsFilter<V, N>,
        meta: &Meta,
    ) -> Option<Self> {
        if !can_calibrate::<V, N>() {
            return None;
        }
        let cal = &meta.sensors.dvl_calibration;
        Some(Self {
            lever_arm: read(
                filter,
                "dvl_lever_arm",
                given_arm(meta, "dvl"),
                cal.lever_arm,
            ),
            misalignment: read(filter, "dvl_misalignment", [0.0; 3], cal.misalignment),
            scale: read(filter, "dvl_scale", [1.0], cal.scale),
            time_offset: read(filter, "dvl_time_offset", [0.0], cal.time_offset),
        })
    }

    /// The estimated values as random-constant states against their
    /// priors ([`super::constant_states`]).
    pub fn checks(&self) -> Vec<ConstantState> {
        [
            self.lever_arm
                .check("dvl_lever_arm", "sensors.dvl.lever_arm_sigma", "dvl.csv"),
            self.misalignment.check(
                "dvl_misalignment",
                "sensors.dvl.misalignment_sigma",
                "dvl.csv",
            ),
            self.scale
                .check("dvl_scale", "sensors.dvl.scale_sigma", "dvl.csv"),
            self.time_offset.check(
                "dvl_time_offset",
                "sensors.dvl.time_offset_sigma",
                "dvl.csv",
            ),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    /// The warning of a mounting estimated with a noise sigma the DVL's
    /// `innovations` say is more than [`SIGMA_FACTOR_LIMIT`] times too
    /// small: the gate then refuses the rows the mounting states learn
    /// from, and on a simulated survey the estimate made the run worse on
    /// 61 of 100 seeds (docs/calibration.md, "A sigma too small").
    pub fn sigma_warning(&self, innovations: &[SensorInnovations]) -> Option<Warning> {
        if self.checks().is_empty() {
            return None;
        }
        let dvl = innovations.iter().find(|s| s.sensor == "dvl")?;
        let (factor, _) = dvl.supported_factor()?;
        (factor > SIGMA_FACTOR_LIMIT).then(|| {
            Warning::about(
                WarningKind::Suspicious,
                "meta.toml",
                format!(
                    "the DVL's mounting was estimated with a noise_sigma its innovations say is \
                     {factor:.1} times too small ({} of {} rows gated): with such a sigma the gate \
                     refuses the rows the mounting states learn from, and they can make the run \
                     worse than without them (docs/calibration.md); tune the DVL's sigma first \
                     (`navsim tune`) and estimate the mounting with it",
                    dvl.gated, dvl.totals.updates
                ),
            )
            .with_key("sensors.dvl.estimate")
        })
    }

    /// The replay JSON's `dvl_calibration` (docs/cli-and-json.md): per
    /// value whether it was estimated, the estimate, its sigma and the
    /// prior sigma; angles in degrees.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "lever_arm_m": entry(&self.lever_arm, 1.0),
            "misalignment_deg": entry(&self.misalignment, 180.0 / core::f64::consts::PI),
            "scale": entry(&self.scale, 1.0),
            "time_offset_s": entry(&self.time_offset, 1.0),
        })
    }
}

/// The mounting of a USBL transponder or a GNSS antenna at the end of a
/// run of a vehicle that carries its calibration states.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FixMounting {
    /// The log sensor: `usbl` or `gnss`.
    pub sensor: &'static str,
    /// Body axes (FRD) relative to the IMU, m.
    pub lever_arm: Calibrated<3>,
    /// Lag of the fixes' clock behind the log's times, s: a fix the log
    /// puts at `t` is where the vehicle was at `t - lag`.
    pub time_offset: Calibrated<1>,
}

impl FixMounting {
    /// The calibrated mountings in `filter` (of the USBL and the GNSS
    /// antenna, those whose states vehicle `V` carries), with the given
    /// values of `meta`.
    pub fn all_of<V: InsVehicle<N>, const N: usize>(
        filter: &InsFilter<V, N>,
        meta: &Meta,
    ) -> Vec<Self> {
        CALIBRATABLE[1..]
            .iter()
            .filter(|c| c.carried_by::<V, N>())
            .map(|c| {
                let cal = meta.sensors.calibration(c.sensor);
                FixMounting {
                    sensor: c.sensor,
                    lever_arm: read(
                        filter,
                        c.states[0].1,
                        given_arm(meta, c.sensor),
                        cal.lever_arm,
                    ),
                    time_offset: read(filter, c.states[1].1, [0.0], cal.time_offset),
                }
            })
            .collect()
    }

    /// The estimated values as random-constant states against their
    /// priors ([`super::constant_states`]).
    pub fn checks(&self) -> Vec<ConstantState> {
        let (arm, lag, arm_key, lag_key, file) = match self.sensor {
            "usbl" => (
                "usbl_lever_arm",
                "usbl_time_offset",
                "sensors.usbl.lever_arm_sigma",
                "sensors.usbl.time_offset_sigma",
                "usbl.csv",
            ),
            _ => (
                "gnss_lever_arm",
                "gnss_time_offset",
                "sensors.gnss.lever_arm_sigma",
                "sensors.gnss.time_offset_sigma",
                "gnss.csv",
            ),
        };
        [
            self.lever_arm.check(arm, arm_key, file),
            self.time_offset.check(lag, lag_key, file),
        ]
        .into_iter()
        .flatten()
        .collect()
    }

    /// The replay JSON's `<sensor>_calibration` (docs/cli-and-json.md):
    /// `lever_arm_m` and `time_offset_s` as the DVL's.
    pub fn json(&self) -> serde_json::Value {
        serde_json::json!({
            "lever_arm_m": entry(&self.lever_arm, 1.0),
            "time_offset_s": entry(&self.time_offset, 1.0),
        })
    }
}
