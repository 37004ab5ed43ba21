//! Noise parameters identified from the log alone (`navsim tune`,
//! docs/tuning.md): the innovation likelihood of the replay (eq. T1 of
//! [`nav_runtime::innovations`]) maximised over the sigmas of `meta.toml`.
//!
//! - A sensor's noise sigma takes the covariance-matching step of eq. T3
//!   from the innovations of one replay (no extra replay per sensor);
//! - any other parameter (the IMU noise, a bias sigma) takes a Newton step
//!   in `ln sigma` on the likelihood, from two more replays with the
//!   parameter `x2` and `/2`, all replays of a step run at once on the
//!   cores; near the optimum, one the log identifies takes the Newton step
//!   even where no probe gains, with closer probes, taken together with
//!   the parameters it trades against (eq. T6, `joint.rs`);
//! - the standard error of each result is the inverse square root of the
//!   likelihood's curvature (eq. T4 for a sensor; the finite difference for
//!   the others), taken together with the cross information of the
//!   probes (eq. T5, `joint.rs`); one above [`MAX_LOG_SIGMA_ERROR`] means the log does not
//!   identify the parameter: the given value is kept and said so, never a
//!   value that wandered, unless the log rejects the given value
//!   ([`REJECTED_AT`] standard errors from the tuned one): then the tuned
//!   value stays, said to be known only roughly.
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
mod joint;
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
use joint::{sensor_gradient, JointInformation};
pub use meta_text::{tuned_mapping_text, tuned_meta_text, with_values};
pub use tunable::{
    clock_key, clock_of, file_clock_of, in_mapping, mapped_clock_key, mapped_clock_of, noise_block,
    noise_parameters, own_sensor, scaled_sigmas, tuned_mapping_values, with_noise_values,
    LogTuning, Replayed, Tunable,
};

/// A parameter whose `ln sigma` is known to worse than this standard error
/// (a factor of about 1.28 either way) is not identified by the log.
pub const MAX_LOG_SIGMA_ERROR: f64 = 0.25;

/// A given value this many standard errors of `ln sigma` from the tuned
/// one is one the log rejects (under the quadratic, `ln L` lower by 4.5):
/// a parameter whose standard error is above [`MAX_LOG_SIGMA_ERROR`]
/// keeps its tuned value then, said as known only roughly, rather than
/// going back to a value the log rules out (a heading model's gyro noise
/// started 100 times too large went back to it, `ln L` 68 below the
/// tuned one, called flat).
pub const REJECTED_AT: f64 = 3.0;

/// Whether the log rejects the `given` value of a parameter tuned to
/// `value` with standard error `error` of its logarithm ([`REJECTED_AT`]).
fn rejects_given(value: f64, given: f64, error: f64) -> bool {
    let d = (value / given).ln().abs();
    error.is_finite() && d.is_finite() && d > REJECTED_AT * error
}

/// Step of the finite differences in `ln sigma` (a factor of 2).
const STEP: f64 = core::f64::consts::LN_2;

/// Largest change of `ln sigma` in one iteration (a factor of 10).
const MAX_MOVE: f64 = core::f64::consts::LN_10;

/// Converged when no parameter moves more than this in `ln sigma` (1 %).
const CONVERGED: f64 = 0.01;

/// Halvings of a step that lowers the likelihood before it is taken as it
/// is.
const MAX_HALVINGS: usize = 3;

/// A probe must raise the log-likelihood by this much to move a parameter
/// (a likelihood ratio of e^2, about the 95 % level of one parameter).
const SIGNIFICANT: f64 = 2.0;

/// Times the tuned sigmas are made 10 x larger when the filter diverges
/// with the given ones.
const DIVERGED_RETRIES: i32 = 2;

/// Fewer updates of a sensor than this identify nothing.
const MIN_UPDATES: u64 = 10;

/// The clock offsets tried around the given one, s: a grid over +-2 s
/// every 0.5 s (the innovation likelihood of a 1 Hz DVL falls off within
/// about +-0.4 s of its best offset, so the grid lands within its bowl).
const CLOCK_GRID: [f64; 8] = [-2.0, -1.5, -1.0, -0.5, 0.5, 1.0, 1.5, 2.0];

/// Half-width of the first parabola fitted around the best grid offset, s.
const CLOCK_STEP: f64 = 0.25;

/// A clock offset known to worse than this standard error (s) is not
/// identified by the log.
pub const MAX_CLOCK_ERROR: f64 = 0.1;

/// A clock offset moves only when the sensor's innovations fit clearly
/// better: the geometric mean of their variances (at the best scale of
/// `S`) must fall by this share. The likelihood-ratio test alone is met by
/// shifts that change a 1000-row sensor's fit by a tenth of a percent,
/// which a model's small mismatches produce at any offset.
const MIN_CLOCK_GAIN: f64 = 0.2;

/// Parabola refinements after the grid (two replays each; the step shrinks
/// by 2.5 each time: 0.25, 0.1, 0.04 s).
const CLOCK_REFINEMENTS: usize = 3;

/// Covariance-matching steps of the sensors' sigmas before a clock search.
const CLOCK_PRE_STEPS: usize = 3;

/// Replays a clock search takes: the grid, two per refinement, and the
/// replay with the offsets found.
const CLOCK_REPLAYS: usize = CLOCK_GRID.len() + 2 * CLOCK_REFINEMENTS + 1;

/// What to tune and how long.
#[derive(Clone, Debug, PartialEq)]
pub struct TuneOptions {
    /// The `meta.toml` keys to tune (`sensors.dvl.noise_sigma`,
    /// `files.dvl.time.offset_s`, ...); empty: every aiding sensor's
    /// `noise_sigma` and clock offset and the IMU's two noise sigmas.
    pub params: Vec<String>,
    /// Most forward replays of the log (the budget).
    pub max_replays: usize,
}

/// The default budget of forward replays: the sigma steps of the
/// simulated Monte Carlo (docs/tuning.md) take up to 28, a clock search up
/// to 18 more, and a clock that moves by a second makes the
/// sigmas move again after it; a tuning that converges stops earlier.
pub const DEFAULT_MAX_REPLAYS: usize = 100;

impl Default for TuneOptions {
    fn default() -> Self {
        Self {
            params: Vec::new(),
            max_replays: DEFAULT_MAX_REPLAYS,
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
    /// A sensor file's clock offset (s, added to its times): the best of a
    /// grid of its own innovation likelihood, refined by a parabola.
    ClockOffset,
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
    /// Standard error of `ln value` (about the relative standard error);
    /// for a [`ParameterKind::ClockOffset`], of the value itself (s).
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
        Err(RunError::Diverged { message: why, .. }) => {
            let mut started = None;
            for power in 1..=DIVERGED_RETRIES {
                let scale = 10f64.powi(power);
                // Sigmas only: a clock offset is not a scale.
                let larger: Vec<(String, f64)> = params
                    .iter()
                    .map(|(k, v)| match clock_of(k) {
                        Some(_) => (k.clone(), *v),
                        None => (k.clone(), v * scale),
                    })
                    .collect();
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
                    Err(RunError::Diverged { .. }) => continue,
                    Err(e) => return Err(e),
                }
            }
            match started {
                Some(run) => (run, None),
                None => {
                    return Err(RunError::diverged(format!(
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
        .map(|(k, _)| match (t.sensor_of(k), clock_of(k)) {
            (Some(_), _) => ParameterKind::SensorNoise,
            (None, Some(_)) => ParameterKind::ClockOffset,
            (None, None) => ParameterKind::Likelihood,
        })
        .collect();
    let likelihood_params: Vec<usize> = (0..params.len())
        .filter(|&i| kinds[i] == ParameterKind::Likelihood)
        .collect();
    let per_step = 1 + 2 * likelihood_params.len();
    // Curvature (per unit ln sigma squared) of each likelihood parameter at
    // the last step.
    let mut curvature = vec![f64::NAN; params.len()];
    // The cross information of each likelihood parameter with each
    // sensor's sigma at the last step (eq. T5).
    let mut cross = Vec::new();
    let before_nis = if before_log_likelihood.is_some() {
        nis_of(&before.output)
    } else {
        Vec::new()
    };
    let mut center = before;
    // The clocks first: a reading taken at the wrong time makes every
    // sigma look too small. But not with sigmas ten times off, whose
    // gating and recoveries make the fit at any offset a matter of chance:
    // the sensors' sigmas take a few covariance-matching steps before.
    if kinds.contains(&ParameterKind::ClockOffset) {
        for _ in 0..CLOCK_PRE_STEPS {
            let moves = sensor_moves(t, &params, &center);
            if moves.iter().all(|m| m.abs() < CONVERGED)
                || replays + CLOCK_REPLAYS + 2 >= options.max_replays
            {
                break;
            }
            let previous = values.clone();
            for (v, m) in values.iter_mut().zip(&moves) {
                v.1 *= m.exp();
            }
            replays += 1;
            progress(replays.min(options.max_replays), options.max_replays);
            match replay(t, &values) {
                Ok(run) => center = run,
                Err(_) => {
                    values = previous;
                    break;
                }
            }
        }
    }
    let clocks = search_clocks(
        t,
        &params,
        &kinds,
        &mut values,
        center,
        &mut replays,
        options,
        progress,
    );
    let mut center = clocks.center;
    let mut converged = false;
    // The probes' step in `ln sigma`: a factor of 2, a quarter of that
    // near the optimum.
    let mut probe = STEP;
    // Whether the last probes were the refining ones.
    let mut refined_since_wide = false;
    // The replays with each likelihood parameter multiplied by `e^h`
    // and by `e^-h` (in the order of `likelihood_params`), in parallel.
    let probe_runs = |values: &[(String, f64)], h: f64| -> Vec<Result<Run, RunError>> {
        likelihood_params
            .iter()
            .flat_map(|&i| [(i, h), (i, -h)])
            .collect::<Vec<_>>()
            .par_iter()
            .map(|&(i, d)| {
                let mut v = values.to_vec();
                v[i].1 *= d.exp();
                replay(t, &v)
            })
            .collect()
    };
    // A step needs its replays, and one is kept for the replay with the
    // given values of parameters the log does not identify.
    while replays + per_step < options.max_replays {
        let mut moves = sensor_moves(t, &params, &center);
        // Whether a parameter moves by a Newton step that no probe showed
        // to gain: such a step must not lower the likelihood at all, or
        // the steps would drift downhill by up to `SIGNIFICANT` each.
        let mut refining = false;
        if !likelihood_params.is_empty() {
            let runs = probe_runs(&values, probe);
            refined_since_wide = probe != STEP;
            replays += runs.len();
            progress(replays.min(options.max_replays), options.max_replays);
            // The curvatures and cross terms of these probes; those over a
            // factor of 2 are also the ones kept for the standard errors.
            let here_cross = cross_information(t, &params, &likelihood_params, &runs, probe);
            let mut here_curvature = curvature.clone();
            // Whether every parameter the curvature identifies is near
            // enough its optimum for a Newton step (no probe-sized move).
            let mut local = true;
            // Refining steps wait for the sensors' sigmas to be near their
            // own optimum: a curvature measured with them ten times off can
            // be thousands of times what it is there.
            let sensors_near = moves.iter().all(|m| m.abs() <= STEP / 2.0);
            for (k, &i) in likelihood_params.iter().enumerate() {
                let (up, down, mid) = (
                    probe_likelihood(&runs[2 * k]),
                    probe_likelihood(&runs[2 * k + 1]),
                    center.log_likelihood,
                );
                let c = (up - 2.0 * mid + down) / (probe * probe);
                let g = (up - down) / (2.0 * probe);
                here_curvature[i] = c;
                if probe == STEP {
                    curvature[i] = c;
                }
                // Identified by the probes over a factor of 2, and still by
                // the refining ones.
                let known = identifies(curvature[i]) && (probe == STEP || identifies(c));
                // Only a clearly better likelihood moves a parameter (one
                // where it is flat stays where the user put it), unless the
                // curvature over a factor of 2 identifies it: then the
                // Newton step finds the top of the bowl, where neither
                // probe is better by `SIGNIFICANT`. Without it a parameter
                // known to a standard error `s` stopped anywhere within
                // about `(2 s^2 + STEP^2 / 2) / STEP` of its optimum (2.3
                // `s` for `s` = 0.2), which the standard error does not
                // report.
                let newton = (-g / c).clamp(-MAX_MOVE, MAX_MOVE);
                moves[i] = if up.max(down) - mid < SIGNIFICANT {
                    if sensors_near && known && c < 0.0 && c.is_finite() && newton.abs() <= STEP {
                        refining = true;
                        newton
                    } else {
                        0.0
                    }
                } else if c < 0.0 && c.is_finite() {
                    // Far from the optimum the quadratic under-steps (a
                    // process noise started ten times too large took twelve
                    // steps to halve): the better probe is known to raise
                    // the likelihood, so the step goes at least that far.
                    let better = if up > down { probe } else { -probe };
                    if newton.abs() < probe && newton * better > 0.0 {
                        better
                    } else {
                        newton
                    }
                } else if up > down {
                    probe
                } else {
                    -probe
                };
                local &= !known || (c.is_finite() && moves[i] == newton);
            }
            if probe == STEP {
                cross.clone_from(&here_cross);
            }
            // Near the optimum the steps of parameters that trade against
            // each other are taken together (eq. T6); not with the sensors'
            // sigmas far from theirs, where a curvature measured there
            // steers the sensors' large steps astray (survey seed 5137,
            // every sigma ten times off: no step raised the likelihood).
            let coupled = here_cross
                .iter()
                .any(|&(i, _, v)| v != 0.0 && identifies(curvature[i]));
            if local && coupled && sensors_near {
                let info = joint_information(t, &params, &here_curvature, &here_cross, &center);
                if let Some(joint) = info.joint_step(&moves) {
                    moves = joint;
                }
            }
            // Near the optimum the probes close in. The secant over a
            // factor of 2 either way aims the Newton step at the point
            // whose two probes are equally likely, which the skew of a
            // variance's likelihood sets off its top (3.9 standard errors
            // in the unit test); over a quarter of it, a sixteenth as far.
            // Only when every parameter, the sensors' sigmas too, is near
            // its optimum.
            let near = moves.iter().all(|m| m.abs() <= STEP / 2.0);
            probe = if local && refining && near {
                STEP / 4.0
            } else {
                STEP
            };
        }
        // The step, halved while it lowers the likelihood (a sensor's
        // sigma matched to its innovations and a process noise that feeds
        // the same innovations, stepped together, overshoot each other and
        // oscillate) or the filter cannot run with it.
        let previous = values.clone();
        let mut step = moves;
        let mut moved = None;
        let mut at_optimum = false;
        for halving in 0..=MAX_HALVINGS {
            values = previous.clone();
            for (v, m) in values.iter_mut().zip(&step) {
                v.1 *= m.exp();
            }
            replays += 1;
            progress(replays.min(options.max_replays), options.max_replays);
            match replay(t, &values) {
                Ok(run)
                    if !center.log_likelihood.is_finite()
                        || run.log_likelihood
                            >= center.log_likelihood - if refining { 0.0 } else { SIGNIFICANT } =>
                {
                    moved = Some(run);
                    break;
                }
                result => {
                    if halving == MAX_HALVINGS {
                        // An eighth of the step still lowers it: the
                        // parameters are at the optimum the steps can see.
                        at_optimum = result.is_ok();
                        break;
                    }
                    if replays + 1 >= options.max_replays {
                        break;
                    }
                    step.iter_mut().for_each(|m| *m *= 0.5);
                }
            }
        }
        let Some(run) = moved else {
            // No step the filter can run with raises the likelihood: stay
            // before it.
            values = previous;
            converged = at_optimum;
            break;
        };
        center = run;
        // A parameter the curvature identifies has converged when its step
        // is a quarter of its standard error: the Newton steps of two
        // parameters that trade against each other close in on the
        // optimum slowly, and the last percent is below what the log tells.
        let converged_at = |i: usize| match curvature[i] {
            c if kinds[i] == ParameterKind::Likelihood && identifies(c) => {
                CONVERGED.max(0.25 / (-c).sqrt())
            }
            _ => CONVERGED,
        };
        if step
            .iter()
            .enumerate()
            .all(|(i, m)| m.abs() < converged_at(i))
        {
            converged = true;
            break;
        }
    }
    // The standard errors are those of probes over a factor of 2 (the
    // scale of a 95 % interval); after steps with the refining probes
    // they are measured again where the steps ended.
    if refined_since_wide && replays + 2 * likelihood_params.len() < options.max_replays {
        let runs = probe_runs(&values, STEP);
        replays += runs.len();
        progress(replays.min(options.max_replays), options.max_replays);
        cross = cross_information(t, &params, &likelihood_params, &runs, STEP);
        for (k, &i) in likelihood_params.iter().enumerate() {
            let (up, down) = (
                probe_likelihood(&runs[2 * k]),
                probe_likelihood(&runs[2 * k + 1]),
            );
            curvature[i] = (up - 2.0 * center.log_likelihood + down) / (STEP * STEP);
        }
    }
    // The likelihood parameters the log does not identify go back to their
    // given values, and the sensors' sigmas are stepped again with them.
    let mut center_values = values.clone();
    let mut why_not: Vec<Option<String>> = vec![None; params.len()];
    let mut errors = vec![f64::INFINITY; params.len()];
    let mut reset = false;
    let marginal = joint_information(t, &params, &curvature, &cross, &center).marginal_errors();
    for &i in &likelihood_params {
        let c = curvature[i];
        let e = match marginal.as_ref().and_then(|m| m[i]) {
            Some(e) => e,
            None if c < 0.0 => (-c).sqrt().recip(),
            None => f64::INFINITY,
        };
        errors[i] = e;
        if e > MAX_LOG_SIGMA_ERROR && rejects_given(values[i].1, params[i].1, e) {
            notes.push(roughly_known(&params[i].0, values[i].1, params[i].1, e));
        } else if e > MAX_LOG_SIGMA_ERROR {
            let own = if c < 0.0 {
                (-c).sqrt().recip()
            } else {
                f64::INFINITY
            };
            why_not[i] = Some(if c.is_nan() {
                "the budget of replays allowed no step".to_string()
            } else if own <= MAX_LOG_SIGMA_ERROR {
                // Known on its own, not beside the others.
                format!(
                    "it and a tuned sensor sigma act on the same innovations: alone its standard error of ln sigma would be {own:.2}, taken together it is {e:.2}"
                )
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
    // So does a sensor whose sigma the log does not tell, on its own or
    // beside the parameters that act on the same innovations.
    for (i, (key, initial)) in params.iter().enumerate() {
        if let Some(sensor) = t.sensor_of(key) {
            let t = totals_of(&center, sensor);
            let joint = marginal.as_ref().and_then(|m| m[i]);
            errors[i] = joint.unwrap_or_else(|| {
                t.map_or(f64::INFINITY, InnovationTotals::log_sigma_standard_error)
            });
            why_not[i] = sensor_verdict(sensor, t).or_else(|| {
                let e = joint?;
                if e > MAX_LOG_SIGMA_ERROR && rejects_given(values[i].1, *initial, e) {
                    notes.push(roughly_known(key, values[i].1, *initial, e));
                    return None;
                }
                (e > MAX_LOG_SIGMA_ERROR).then(|| confounded(sensor, e))
            });
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
                Err(RunError::Diverged { .. }) => {
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
    let marginal = joint_information(t, &params, &curvature, &cross, &center).marginal_errors();
    if marginal.is_none() && !cross.is_empty() {
        notes.push(
            "the parameters' joint information (eq. T5) is not positive definite (its finite differences are too noisy to combine): each standard error is the parameter's own, with the others held".to_string(),
        );
    }
    let parameters: Vec<TunedParameter> = params
        .iter()
        .enumerate()
        .map(|(i, (key, initial))| {
            let (log_standard_error, not_identifiable) = match t.sensor_of(key) {
                // A sensor's verdict at the final replay, unless the log
                // already failed to tell it; its error taken with the
                // others'.
                Some(sensor) if why_not[i].is_none() => {
                    let totals = totals_of(&center, sensor);
                    let own =
                        totals.map_or(f64::INFINITY, InnovationTotals::log_sigma_standard_error);
                    let e = marginal.as_ref().and_then(|m| m[i]).unwrap_or(own);
                    (e, sensor_verdict(sensor, totals))
                }
                _ if kinds[i] == ParameterKind::ClockOffset => {
                    (clocks.errors[i], clocks.why_not[i].clone())
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

/// The cross information of each likelihood parameter `i` with each
/// sensor sigma `s` (eq. T5): minus the change of the sensor's gradient
/// (`sensor_gradient`) between the replays with `i` doubled and halved
/// (`runs`, in the order of the probes, each `step` in `ln sigma` from the
/// center), per unit `ln sigma`.
fn cross_information(
    t: &dyn Tunable,
    params: &[(String, f64)],
    likelihood_params: &[usize],
    runs: &[Result<Run, RunError>],
    step: f64,
) -> Vec<(usize, usize, f64)> {
    let mut cross = Vec::new();
    for (k, &i) in likelihood_params.iter().enumerate() {
        let (Ok(up), Ok(down)) = (&runs[2 * k], &runs[2 * k + 1]) else {
            continue;
        };
        for (s, (key, _)) in params.iter().enumerate() {
            let Some(sensor) = t.sensor_of(key) else {
                continue;
            };
            if let (Some(a), Some(b)) = (totals_of(up, sensor), totals_of(down, sensor)) {
                let change = (sensor_gradient(a) - sensor_gradient(b)) / (2.0 * step);
                cross.push((i, s, -change));
            }
        }
    }
    cross
}

/// The joint information of the parameters the log identifies on their
/// own (sensors from `center`'s innovations, eq. T4; likelihood parameters
/// from their curvature) with the cross information (eq. T5), whose
/// inverse gives their marginal standard errors.
fn joint_information(
    t: &dyn Tunable,
    params: &[(String, f64)],
    curvature: &[f64],
    cross: &[(usize, usize, f64)],
    center: &Run,
) -> JointInformation {
    let diagonal = params
        .iter()
        .enumerate()
        .map(|(i, (key, _))| match t.sensor_of(key) {
            Some(sensor) => totals_of(center, sensor)
                .filter(|totals| sensor_verdict(sensor, Some(totals)).is_none())
                .map(|totals| 2.0 * totals.noise_information),
            // One the log does not identify on its own is reset, not
            // combined.
            None => identifies(curvature[i]).then(|| -curvature[i]),
        })
        .collect();
    JointInformation {
        diagonal,
        cross: cross.to_vec(),
    }
}

/// The log-likelihood of a probe's replay; one that fails (a sigma so
/// small that the run diverges) is minus infinity.
fn probe_likelihood(r: &Result<Run, RunError>) -> f64 {
    r.as_ref().map_or(f64::NEG_INFINITY, |r| r.log_likelihood)
}

/// Whether a likelihood parameter's curvature `c` (per unit `ln sigma`
/// squared) identifies it on its own: a standard error of `ln sigma` of at
/// most [`MAX_LOG_SIGMA_ERROR`].
fn identifies(c: f64) -> bool {
    c < 0.0 && -c >= MAX_LOG_SIGMA_ERROR.powi(-2)
}

/// The note of a parameter known only roughly whose given value the log
/// rejects ([`REJECTED_AT`]).
fn roughly_known(key: &str, value: f64, given: f64, error: f64) -> String {
    format!(
        "{key}: known only to a factor of {:.1} (standard error of ln sigma {error:.2}), but the log rejects the given {given}, {:.0} standard errors from the tuned {value:.4e}: the tuned value is kept",
        error.exp(),
        (value / given).ln().abs() / error
    )
}

/// Why a sensor's sigma is not identified beside the other parameters.
fn confounded(sensor: &str, error: f64) -> String {
    format!(
        "its noise and a tuned process noise act on the same innovations of {sensor}: taken together, the standard error of ln sigma is {error:.2}"
    )
}

/// What a clock search leaves: the replay to go on from, and per
/// parameter the standard error of a clock offset (s) and why it was not
/// identified (unused for the other parameters).
struct Clocks {
    center: Run,
    errors: Vec<f64>,
    why_not: Vec<Option<String>>,
}

/// The profile innovation log-likelihood of `sensor` in `run`
/// ([`InnovationTotals::profile_log_likelihood`]: at the best scale of its
/// innovation covariance, so that a sigma still far off does not decide
/// the clock), minus infinity for a run that failed or a sensor with too
/// few updates.
fn own_likelihood(run: Option<&Run>, sensor: &str) -> f64 {
    run.and_then(|r| totals_of(r, sensor))
        .filter(|t| t.updates >= MIN_UPDATES)
        .map_or(f64::NEG_INFINITY, InnovationTotals::profile_log_likelihood)
}

/// The rise of `sensor`'s profile likelihood that moves its clock: at
/// least [`SIGNIFICANT`], and the rise that a fall of [`MIN_CLOCK_GAIN`]
/// in the geometric mean of its innovation variances gives.
fn clock_gain_needed(run: &Run, sensor: &str) -> f64 {
    let dof = totals_of(run, sensor).map_or(0.0, |t| t.dof as f64);
    SIGNIFICANT.max(-0.5 * dof * (1.0 - MIN_CLOCK_GAIN).ln())
}

/// The fall of the geometric mean of `sensor`'s innovation variances that
/// a rise `gain` of its profile likelihood means.
fn variance_fall(run: &Run, sensor: &str, gain: f64) -> f64 {
    let dof = totals_of(run, sensor).map_or(0.0, |t| t.dof as f64);
    if dof > 0.0 {
        1.0 - (-2.0 * gain.max(0.0) / dof).exp()
    } else {
        0.0
    }
}

/// Finds the clock offset of every [`ParameterKind::ClockOffset`] among
/// `params`: the grid [`CLOCK_GRID`] around the given offsets (all sensors
/// moved together, each judged by its own profile likelihood, since a
/// sensor's clock moves its own innovations far more than the others'),
/// then [`CLOCK_REFINEMENTS`] parabolas through the best point and a step either
/// side. An offset moves only when its likelihood rises by
/// [`SIGNIFICANT`] and by [`MIN_CLOCK_GAIN`] of its innovation variance,
/// and its standard error (the parabola's curvature) is at most
/// [`MAX_CLOCK_ERROR`]; `values` gets the offsets found and the replay
/// with them becomes the center. Without clock parameters, or without the
/// budget for the search, nothing is replayed.
#[allow(clippy::too_many_arguments)]
fn search_clocks(
    t: &dyn Tunable,
    params: &[(String, f64)],
    kinds: &[ParameterKind],
    values: &mut [(String, f64)],
    center: Run,
    replays: &mut usize,
    options: &TuneOptions,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Clocks {
    let clocks: Vec<(usize, &str)> = params
        .iter()
        .enumerate()
        .filter(|(i, _)| kinds[*i] == ParameterKind::ClockOffset)
        .filter_map(|(i, (k, _))| Some((i, clock_of(k)?)))
        .collect();
    let mut out = Clocks {
        center,
        errors: vec![f64::INFINITY; params.len()],
        why_not: vec![None; params.len()],
    };
    if clocks.is_empty() {
        return out;
    }
    if *replays + CLOCK_REPLAYS + 2 > options.max_replays {
        for &(i, _) in &clocks {
            out.why_not[i] = Some(format!(
                "the budget of replays allowed no clock search ({CLOCK_REPLAYS} replays)"
            ));
        }
        return out;
    }
    let shifted = |shift: &dyn Fn(usize) -> f64| -> Vec<(String, f64)> {
        let mut v = values.to_vec();
        for &(i, _) in &clocks {
            v[i].1 = params[i].1 + shift(i);
        }
        v
    };
    let grid: Vec<Result<Run, RunError>> = CLOCK_GRID
        .par_iter()
        .map(|&g| replay(t, &shifted(&|_| g)))
        .collect();
    *replays += grid.len();
    progress((*replays).min(options.max_replays), options.max_replays);
    // Per clock: the best grid shift and its likelihood, and the given one's.
    let best: Vec<(f64, f64, f64)> = clocks
        .iter()
        .map(|&(_, sensor)| {
            let at_given = own_likelihood(Some(&out.center), sensor);
            let (shift, l) = CLOCK_GRID
                .iter()
                .zip(&grid)
                .map(|(g, r)| (*g, own_likelihood(r.as_ref().ok(), sensor)))
                .fold((0.0, at_given), |b, c| if c.1 > b.1 { c } else { b });
            (shift, l, at_given)
        })
        .collect();
    // Refined: a parabola through the best point and `h` either side, its
    // vertex (or the best of the three) the next center, `h` shrinking.
    let previous = values.to_vec();
    let mut center_shift: Vec<f64> = best.iter().map(|b| b.0).collect();
    let mut center_l: Vec<f64> = best.iter().map(|b| b.1).collect();
    let mut curvature = vec![f64::NAN; clocks.len()];
    let mut h = CLOCK_STEP;
    for _ in 0..CLOCK_REFINEMENTS {
        let around: Vec<Result<Run, RunError>> = [-h, h]
            .par_iter()
            .map(|&d| {
                replay(
                    t,
                    &shifted(&|i| {
                        let k = clocks.iter().position(|c| c.0 == i).unwrap_or(0);
                        center_shift[k] + d
                    }),
                )
            })
            .collect();
        *replays += around.len();
        progress((*replays).min(options.max_replays), options.max_replays);
        for (k, &(_, sensor)) in clocks.iter().enumerate() {
            let (down, mid, up) = (
                own_likelihood(around[0].as_ref().ok(), sensor),
                center_l[k],
                own_likelihood(around[1].as_ref().ok(), sensor),
            );
            let c = (up - 2.0 * mid + down) / (h * h);
            if c < 0.0 && c.is_finite() {
                // The finest step with a bowl gives the standard error (at
                // a step of hundredths of a second, the rows that cross
                // the gate make the likelihood ragged).
                curvature[k] = c;
                center_shift[k] += (-(up - down) / (2.0 * h * c)).clamp(-h, h);
                // The vertex's value, as the parabola has it.
                center_l[k] = mid - (up - down).powi(2) / (8.0 * h * h * c);
            } else if up.max(down) > mid {
                center_shift[k] += if up > down { h } else { -h };
                center_l[k] = up.max(down);
            }
        }
        h /= 2.5;
    }
    for (k, &(i, sensor)) in clocks.iter().enumerate() {
        let (mid, at_given, c) = (center_l[k], best[k].2, curvature[k]);
        let error = if c < 0.0 && c.is_finite() {
            (-c).sqrt().recip()
        } else {
            f64::INFINITY
        };
        out.errors[i] = error;
        out.why_not[i] = if !best[k].1.is_finite() {
            Some(format!(
                "{sensor} has fewer than {MIN_UPDATES} updates: nothing to time it by"
            ))
        } else if mid - at_given < clock_gain_needed(&out.center, sensor) {
            Some(format!(
                "no offset within {} s of the given one fits {sensor}'s readings clearly better (their variance falls by {:.0} %, {:.0} % needed)",
                CLOCK_GRID[CLOCK_GRID.len() - 1],
                100.0 * variance_fall(&out.center, sensor, mid - at_given),
                100.0 * MIN_CLOCK_GAIN
            ))
        } else if error > MAX_CLOCK_ERROR {
            Some(format!(
                "{sensor}'s likelihood is too flat in its clock offset (standard error {}): the log has too little motion to time it",
                if error.is_finite() { format!("{error:.2} s") } else { "infinite".into() }
            ))
        } else {
            None
        };
        values[i].1 = match out.why_not[i] {
            None => params[i].1 + center_shift[k],
            Some(_) => params[i].1,
        };
    }
    if values.iter().zip(&previous).all(|(a, b)| a.1 == b.1) {
        return out;
    }
    *replays += 1;
    progress((*replays).min(options.max_replays), options.max_replays);
    match replay(t, values) {
        Ok(run) => out.center = run,
        Err(e) => {
            // The offsets found make the filter fail: keep the given ones.
            for &(i, _) in &clocks {
                if out.why_not[i].is_none() {
                    out.why_not[i] = Some(format!(
                        "the replay with the offsets found failed ({}): the given one is kept",
                        crate::program::one_line(&e.to_string())
                    ));
                }
            }
            values.clone_from_slice(&previous);
        }
    }
    out
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
