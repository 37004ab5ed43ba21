//! Noise parameters identified from the log alone (`navsim tune`,
//! docs/tuning.md): the innovation likelihood of the replay (eq. T1 of
//! [`nav_runtime::innovations`]) maximised over the sigmas of `meta.toml`.
//!
//! - A sensor's noise sigma takes the covariance-matching step of eq. T3
//!   from the innovations of one replay (no extra replay per sensor);
//! - any other parameter (the IMU noise, a bias sigma) takes a Newton step
//!   in `ln sigma` on the likelihood, from two more replays with the
//!   parameter `x2` and `/2`, all replays of a step run at once on the
//!   cores;
//! - the standard error of each result is the inverse square root of the
//!   likelihood's curvature (eq. T4 for a sensor; the finite difference for
//!   the others); one above [`MAX_LOG_SIGMA_ERROR`] means the log does not
//!   identify the parameter: the given value is kept and said so, never a
//!   value that wandered.
//!
//! What can be tuned is a [`Tunable`]: a replay model that reads its
//! sigmas from `meta.toml` and reports its sensors' innovations
//! ([`ReplayOutput::innovations`](crate::ReplayOutput::innovations)),
//! replayed through
//! [`ReplayModel::replay_files`](crate::ReplayModel::replay_files) with
//! another [`Meta`](nav_runtime::log::Meta) ([`LogTuning`]), or a declared
//! model replayed from its mapping
//! ([`MappingTuning`](crate::model_replay::MappingTuning)).

mod command;
mod meta_text;
mod report;
#[cfg(test)]
mod tests;
mod tunable;

use std::collections::BTreeMap;

use nav_runtime::innovations::InnovationTotals;
use rayon::prelude::*;

use crate::RunError;
pub use command::{tune_with, tune_with_progress, tuning_warnings, TuneArgs, TuneFlags};
pub use meta_text::{tuned_meta_text, with_values};
pub use tunable::{LogTuning, Replayed, Tunable};

/// A parameter whose `ln sigma` is known to worse than this standard error
/// (a factor of about 1.28 either way) is not identified by the log.
pub const MAX_LOG_SIGMA_ERROR: f64 = 0.25;

/// Step of the finite differences in `ln sigma` (a factor of 2).
const STEP: f64 = core::f64::consts::LN_2;

/// Largest change of `ln sigma` in one iteration (a factor of 10).
const MAX_MOVE: f64 = core::f64::consts::LN_10;

/// Converged when no parameter moves more than this in `ln sigma` (1 %).
const CONVERGED: f64 = 0.01;

/// A probe must raise the log-likelihood by this much to move a parameter
/// (a likelihood ratio of e^2, about the 95 % level of one parameter).
const SIGNIFICANT: f64 = 2.0;

/// Times the tuned sigmas are made 10 x larger when the filter diverges
/// with the given ones.
const DIVERGED_RETRIES: i32 = 2;

/// Fewer updates of a sensor than this identify nothing.
const MIN_UPDATES: u64 = 10;

/// What to tune and how long.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneOptions {
    /// The `meta.toml` keys to tune (`sensors.dvl.noise_sigma`, ...);
    /// empty: every aiding sensor's `noise_sigma` and the IMU's two noise
    /// sigmas.
    pub params: Vec<String>,
    /// Most forward replays of the log (the budget).
    pub max_replays: usize,
}

impl Default for TuneOptions {
    fn default() -> Self {
        Self {
            params: Vec::new(),
            max_replays: 30,
        }
    }
}

/// How a parameter is identified.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ParameterKind {
    /// A sensor's noise sigma: from its own innovations (eq. T3).
    SensorNoise,
    /// Anything else: from the likelihood of the whole run.
    Likelihood,
}

/// One tuned parameter.
#[derive(Clone, Debug, PartialEq)]
pub struct TunedParameter {
    /// Its `meta.toml` key.
    pub key: String,
    /// How it was identified.
    pub kind: ParameterKind,
    /// The value in `meta.toml`.
    pub initial: f64,
    /// The tuned value (the initial one when not identifiable).
    pub value: f64,
    /// Standard error of `ln value` (about the relative standard error).
    pub log_standard_error: f64,
    /// `None` when the log identifies it; otherwise why not.
    pub not_identifiable: Option<String>,
}

/// The result of a tuning.
#[derive(Clone, Debug, PartialEq)]
pub struct Tuning {
    /// The model tuned.
    pub model: String,
    /// Every parameter asked for.
    pub parameters: Vec<TunedParameter>,
    /// Forward replays of the log used.
    pub replays: usize,
    /// Whether the parameters stopped moving within the budget.
    pub converged: bool,
    /// Innovation log-likelihood with the given (`None`: the filter
    /// diverged with them) and with the tuned values.
    pub log_likelihood: (Option<f64>, f64),
    /// What the user should know about how the tuning went.
    pub notes: Vec<String>,
    /// Per sensor, the mean NIS per degree of freedom with the given and
    /// with the tuned values.
    pub nis: BTreeMap<String, (Option<f64>, Option<f64>)>,
    /// The replay with the tuned values.
    pub after: Replayed,
}

/// The parameters asked for, checked against the model's.
fn chosen(t: &dyn Tunable, asked: &[String]) -> Result<Vec<(String, f64)>, RunError> {
    let all = t.parameters();
    let asked = if asked.is_empty() {
        let default = t.default_parameters();
        if default.is_empty() {
            return Err(RunError::Invalid(format!(
                "model {} has no noise sigma to tune on this log",
                t.model()
            )));
        }
        default
    } else {
        asked.to_vec()
    };
    let mut out: Vec<(String, f64)> = Vec::new();
    for key in &asked {
        let Some((_, v)) = all.iter().find(|(k, _)| k == key) else {
            return Err(t.unknown(key));
        };
        if out.iter().any(|(k, _)| k == key) {
            return Err(RunError::Invalid(format!("--params: {key} given twice")));
        }
        out.push((key.clone(), *v));
    }
    Ok(out)
}

/// One replay's answer and its total log-likelihood.
struct Run {
    output: Replayed,
    log_likelihood: f64,
}

fn replay(t: &dyn Tunable, values: &[(String, f64)]) -> Result<Run, RunError> {
    let output = t.replay(values)?;
    let mut total = InnovationTotals::default();
    for s in &output.innovations {
        total.merge(&s.totals);
    }
    Ok(Run {
        output,
        log_likelihood: total.log_likelihood(),
    })
}

fn totals_of<'a>(run: &'a Run, sensor: &str) -> Option<&'a InnovationTotals> {
    run.output
        .innovations
        .iter()
        .find(|s| s.sensor == sensor)
        .map(|s| &s.totals)
}

/// The step of `ln sigma` of each sensor noise among `params` from the
/// innovations of `run` (eq. T3); 0 for the other parameters. Every step
/// moves a sensor with enough updates, also one whose noise the filter's
/// uncertainty still hides: a sigma far too small is such a sensor until
/// it has moved.
fn sensor_moves(t: &dyn Tunable, params: &[(String, f64)], run: &Run) -> Vec<f64> {
    params
        .iter()
        .map(|(key, _)| {
            t.sensor_of(key)
                .and_then(|sensor| totals_of(run, sensor))
                .filter(|t| t.updates >= MIN_UPDATES)
                .and_then(InnovationTotals::sigma_factor)
                .map_or(0.0, |f| f.ln().clamp(-MAX_MOVE, MAX_MOVE))
        })
        .collect()
}

/// Why a sensor's sigma cannot be identified from `totals`, if it cannot.
fn sensor_verdict(sensor: &str, totals: Option<&InnovationTotals>) -> Option<String> {
    match totals {
        None => Some(format!(
            "the model reports no innovations of {sensor}: it does not use {sensor}.csv, or the log has none"
        )),
        Some(t) if t.updates == 0 => Some(format!(
            "{sensor} never reported (no row of {sensor}.csv was applied or gated)"
        )),
        Some(t) if t.updates < MIN_UPDATES => Some(format!(
            "only {} updates of {sensor}: the log is too short to tell its noise",
            t.updates
        )),
        Some(t) if t.log_sigma_standard_error() > MAX_LOG_SIGMA_ERROR => Some(format!(
            "{sensor}'s noise is hidden by the filter's own uncertainty (standard error of ln sigma {:.2})",
            t.log_sigma_standard_error()
        )),
        _ => None,
    }
}

/// Tunes the noise parameters of `t` (a model on a log: [`LogTuning`] for a
/// replay model reading `meta.toml`). `progress` is told the replays done
/// so far and the budget.
///
/// # Errors
/// A parameter the model does not have, a model that reports no
/// innovations, and any error of the replay with the given values (a log
/// that cannot be replayed cannot be tuned).
pub fn tune(
    t: &dyn Tunable,
    options: &TuneOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Tuning, RunError> {
    let params = chosen(t, &options.params)?;
    if options.max_replays < 2 {
        return Err(RunError::Invalid(format!(
            "--max-replays {}: at least 2 (the given and the tuned values)",
            options.max_replays
        )));
    }
    let mut values = params.clone();
    let mut replays = 0usize;
    let mut notes = Vec::new();
    let given = replay(t, &values);
    replays += 1;
    progress(replays, options.max_replays);
    let (before, before_log_likelihood) = match given {
        Ok(run) => {
            let l = run.log_likelihood;
            (run, Some(l))
        }
        // The given sigmas make the filter diverge (too small a noise
        // lets it trust a reading or its own solution too much): start
        // from larger ones, which the likelihood then brings down.
        Err(RunError::Diverged(why)) => {
            let mut started = None;
            for power in 1..=DIVERGED_RETRIES {
                let scale = 10f64.powi(power);
                let larger: Vec<(String, f64)> =
                    params.iter().map(|(k, v)| (k.clone(), v * scale)).collect();
                replays += 1;
                progress(replays, options.max_replays);
                match replay(t, &larger) {
                    Ok(run) => {
                        values = larger;
                        notes.push(format!(
                            "with the given sigmas the filter diverged ({}); the tuning started from every tuned sigma x {scale}",
                            crate::program::one_line(&why)
                        ));
                        started = Some(run);
                        break;
                    }
                    Err(RunError::Diverged(_)) => continue,
                    Err(e) => return Err(e),
                }
            }
            match started {
                Some(run) => (run, None),
                None => {
                    return Err(RunError::Diverged(format!(
                    "{why}; with every tuned sigma up to {} times larger too: nothing to tune from",
                    10f64.powi(DIVERGED_RETRIES)
                )))
                }
            }
        }
        Err(e) => return Err(e),
    };
    if before
        .output
        .innovations
        .iter()
        .all(|s| s.totals.updates == 0)
    {
        return Err(RunError::Invalid(format!(
            "model {} reported no sensor innovations on this log: nothing to tune from",
            t.model()
        )));
    }
    let kinds: Vec<ParameterKind> = params
        .iter()
        .map(|(k, _)| match t.sensor_of(k) {
            Some(_) => ParameterKind::SensorNoise,
            None => ParameterKind::Likelihood,
        })
        .collect();
    let likelihood_params: Vec<usize> = (0..params.len())
        .filter(|&i| kinds[i] == ParameterKind::Likelihood)
        .collect();
    let per_step = 1 + 2 * likelihood_params.len();
    // Curvature (per unit ln sigma squared) of each likelihood parameter at
    // the last step.
    let mut curvature = vec![f64::NAN; params.len()];
    let before_nis = if before_log_likelihood.is_some() {
        nis_of(&before.output)
    } else {
        Vec::new()
    };
    let mut center = before;
    let mut converged = false;
    // A step needs its replays, and one is kept for the replay with the
    // given values of parameters the log does not identify.
    while replays + per_step < options.max_replays {
        let mut moves = sensor_moves(t, &params, &center);
        if !likelihood_params.is_empty() {
            let probes: Vec<(usize, f64)> = likelihood_params
                .iter()
                .flat_map(|&i| [(i, STEP), (i, -STEP)])
                .collect();
            let runs: Vec<Result<Run, RunError>> = probes
                .par_iter()
                .map(|&(i, d)| {
                    let mut v = values.clone();
                    v[i].1 *= d.exp();
                    replay(t, &v)
                })
                .collect();
            replays += runs.len();
            progress(replays.min(options.max_replays), options.max_replays);
            for (k, &i) in likelihood_params.iter().enumerate() {
                // A probe that fails (a sigma so small that the run diverges)
                // is a likelihood of minus infinity.
                let l = |r: &Result<Run, RunError>| {
                    r.as_ref().map_or(f64::NEG_INFINITY, |r| r.log_likelihood)
                };
                let (up, down, mid) = (l(&runs[2 * k]), l(&runs[2 * k + 1]), center.log_likelihood);
                let c = (up - 2.0 * mid + down) / (STEP * STEP);
                let g = (up - down) / (2.0 * STEP);
                curvature[i] = c;
                // Only a clearly better likelihood moves a parameter (one
                // where it is flat stays where the user put it).
                moves[i] = if up.max(down) - mid < SIGNIFICANT {
                    0.0
                } else if c < 0.0 && c.is_finite() {
                    (-g / c).clamp(-MAX_MOVE, MAX_MOVE)
                } else if up > down {
                    STEP
                } else {
                    -STEP
                };
            }
        }
        let previous = values.clone();
        for (v, m) in values.iter_mut().zip(&moves) {
            v.1 *= m.exp();
        }
        replays += 1;
        match replay(t, &values) {
            Ok(run) => center = run,
            Err(_) => {
                // The step went where the filter cannot run: stay before it.
                values = previous;
                progress(replays.min(options.max_replays), options.max_replays);
                break;
            }
        }
        progress(replays.min(options.max_replays), options.max_replays);
        if moves.iter().all(|m| m.abs() < CONVERGED) {
            converged = true;
            break;
        }
    }
    // The likelihood parameters the log does not identify go back to their
    // given values, and the sensors' sigmas are stepped again with them.
    let mut center_values = values.clone();
    let mut why_not: Vec<Option<String>> = vec![None; params.len()];
    let mut errors = vec![f64::INFINITY; params.len()];
    let mut reset = false;
    for &i in &likelihood_params {
        let c = curvature[i];
        let e = if c < 0.0 {
            (-c).sqrt().recip()
        } else {
            f64::INFINITY
        };
        errors[i] = e;
        if e > MAX_LOG_SIGMA_ERROR {
            why_not[i] = Some(if c.is_nan() {
                "the budget of replays allowed no step".to_string()
            } else {
                format!(
                    "the likelihood is flat in it (standard error of ln sigma {}): the log has too little excitation or too few updates to tell it",
                    if e.is_finite() { format!("{e:.2}") } else { "infinite".into() }
                )
            });
            reset |= values[i].1 != params[i].1;
            values[i].1 = params[i].1;
        }
    }
    // So does a sensor whose sigma the log does not tell.
    for (i, (key, initial)) in params.iter().enumerate() {
        if let Some(sensor) = t.sensor_of(key) {
            let t = totals_of(&center, sensor);
            errors[i] = t.map_or(f64::INFINITY, InnovationTotals::log_sigma_standard_error);
            why_not[i] = sensor_verdict(sensor, t);
            if why_not[i].is_some() {
                reset |= values[i].1 != *initial;
                values[i].1 = *initial;
            }
        }
    }
    if reset {
        loop {
            replays += 1;
            progress(replays.min(options.max_replays), options.max_replays);
            match replay(t, &values) {
                Ok(run) => {
                    center = run;
                    center_values.clone_from(&values);
                }
                // The given value of such a parameter makes the filter
                // diverge: the last step's value stays, said so.
                Err(RunError::Diverged(_)) => {
                    for i in 0..params.len() {
                        if let Some(why) = why_not[i].as_mut() {
                            if center_values[i].1 != params[i].1 {
                                why.push_str("; kept at the last step's value: the given one makes the filter diverge");
                            }
                        }
                    }
                    values.clone_from(&center_values);
                    break;
                }
                Err(e) => return Err(e),
            }
            let mut moves = sensor_moves(t, &params, &center);
            for (m, why) in moves.iter_mut().zip(&why_not) {
                if why.is_some() {
                    *m = 0.0;
                }
            }
            if replays >= options.max_replays || moves.iter().all(|m| m.abs() < CONVERGED) {
                break;
            }
            for (v, m) in values.iter_mut().zip(&moves) {
                v.1 *= m.exp();
            }
        }
    }
    let parameters: Vec<TunedParameter> = params
        .iter()
        .enumerate()
        .map(|(i, (key, initial))| {
            let (log_standard_error, not_identifiable) = match t.sensor_of(key) {
                // A sensor's verdict at the final replay, unless the log
                // already failed to tell it.
                Some(sensor) if why_not[i].is_none() => {
                    let t = totals_of(&center, sensor);
                    let e = t.map_or(f64::INFINITY, InnovationTotals::log_sigma_standard_error);
                    (e, sensor_verdict(sensor, t))
                }
                _ => (errors[i], why_not[i].clone()),
            };
            TunedParameter {
                key: key.clone(),
                kind: kinds[i],
                initial: *initial,
                value: values[i].1,
                log_standard_error,
                not_identifiable,
            }
        })
        .collect();
    let after_nis = nis_of(&center.output);
    let mut nis: BTreeMap<String, (Option<f64>, Option<f64>)> = BTreeMap::new();
    for (sensor, n) in &before_nis {
        nis.entry(sensor.clone()).or_default().0 = *n;
    }
    for (sensor, n) in after_nis {
        nis.entry(sensor).or_default().1 = n;
    }
    Ok(Tuning {
        model: t.model().to_string(),
        parameters,
        replays,
        converged,
        log_likelihood: (before_log_likelihood, center.log_likelihood),
        nis,
        notes,
        after: center.output,
    })
}

/// Mean NIS per degree of freedom of each sensor with updates.
fn nis_of(output: &Replayed) -> Vec<(String, Option<f64>)> {
    output
        .innovations
        .iter()
        .filter(|s| s.totals.updates > 0)
        .map(|s| (s.sensor.clone(), s.totals.nis_per_dof()))
        .collect()
}
