//! Recovery from a lock-out into divergence (docs/lockout.md, "Recovery").
//!
//! The release of [`crate::lockout`] judges refused *innovations*, and
//! ignores those beyond a plausibility bound. Once the filter itself has
//! diverged (a transient of wrong IMU samples, say), its error seen through
//! the sensor exceeds that bound and grows: every later reading of a correct
//! sensor is refused, and nothing releases it. This rule judges the
//! *readings* instead:
//!
//! - **Plausible**: the Euclidean norm of the reading is within the sensor's
//!   reading bound (a DVL reading faster than any vehicle is a sensor fault,
//!   whatever the filter believes).
//! - **Agreeing with one another**: each refused reading follows on from the
//!   previous reading of the chain (the last accepted one, then each refused
//!   one that joined) by no more than the sensor's rate bound times the time
//!   between them, plus [`NOISE_SIGMAS`] sigmas of the difference of two
//!   readings' noise, per component (angles wrapped). A step (a depth meter
//!   jumping 100 m, a compass flipping by 180 deg, a USBL fix 10 km off) is
//!   not a reading that agrees.
//!
//! A reading that fails either is a *miss*: it neither joins the chain nor
//! ends the run; more than [`MAX_MISSES`] misses in a row mark the run as a
//! sensor fault, which never recovers until a reading is accepted again. A
//! run of refused readings that are all plausible and agree, lasting at least
//! the sensor's horizon (`horizon_s`, and at least `min_refusals` readings),
//! is evidence that the filter, not the sensor, is wrong: the covariance of
//! the states the sensor observes is inflated
//! ([`crate::ekf::Ekf::recover_after_refusal`]).
//!
//! The allowance grows with the time since the chain's newest reading, so a
//! step is caught only if it exceeds the rate bound times the span of
//! [`MAX_MISSES`] + 1 readings (plus the noise allowance): the rule is meant
//! for gross faults, far beyond what the vehicle can do in a few samples.
//!
//! Time is the filter's own clock: the sum of its prediction steps (s).
//! Storage is fixed ([`MAX_RECOVERY_SENSORS`] sensors, readings of at most
//! [`MAX_RECOVERY_DIM`] components); nothing here allocates or panics.

use core::any::TypeId;

use crate::ekf::Ekf;
use crate::model::{Model, Sensor};
use crate::real::Real;
use crate::setup_error::SetupError;

/// The recovery inflates `P` so that the innovation covariance grows by
/// `(k nu)(k nu)^T` with this `k`: the refused innovation is then half a
/// sigma, and the next reading passes the gate even if the filter's error
/// seen through the sensor has doubled meanwhile.
pub const INFLATION_FACTOR: f64 = 2.0;

/// Largest reading dimension the rule follows.
pub const MAX_RECOVERY_DIM: usize = 3;

/// Number of sensors per filter whose readings are followed.
pub const MAX_RECOVERY_SENSORS: usize = 4;

/// Number of sensors that can have a recovery rule.
pub const MAX_RECOVERY_RULES: usize = 6;

/// Refused readings in a row that may fail plausibility or agreement (a
/// glitch) before the run is taken as a sensor fault.
pub const MAX_MISSES: u32 = 2;

/// Allowance for reading noise in the agreement test, in sigmas of the
/// difference of two readings (`sqrt(2) sigma`).
pub const NOISE_SIGMAS: f64 = 5.0;

/// One sensor's recovery rule (units of the reading the caller passes).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RecoveryRule {
    /// Shortest run of refusals that recovers, from its first refusal (s).
    pub horizon_s: f64,
    /// Fewest refused readings in the run.
    pub min_refusals: u32,
    /// Largest Euclidean norm of a plausible reading (reading units).
    pub reading_bound: f64,
    /// Largest change of each reading component per second that the vehicle
    /// can produce (reading units per s).
    pub rate_bound: f64,
    /// States whose covariance a recovery scales (bit `j` = state `j`;
    /// states beyond 63 cannot be named): eq. R1 of docs/lockout.md scales
    /// those the sensor observes by `sqrt(NIS / M)`. 0: only eq. R2.
    pub scaled_states: u64,
}

impl RecoveryRule {
    /// A rule; see the fields.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] for a horizon or rate bound that is not finite
    /// and positive, a reading bound that is not positive (infinity allowed),
    /// or fewer than 2 refusals.
    pub fn new(
        horizon_s: f64,
        min_refusals: u32,
        reading_bound: f64,
        rate_bound: f64,
    ) -> Result<Self, SetupError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        if !positive(horizon_s) || !positive(rate_bound) {
            return Err(SetupError::Invalid {
                reason: "recovery horizon and rate bound must be finite and positive",
            });
        }
        if reading_bound.is_nan() || reading_bound <= 0.0 {
            return Err(SetupError::Invalid {
                reason: "recovery reading bound must be positive",
            });
        }
        if min_refusals < 2 {
            return Err(SetupError::Invalid {
                reason: "recovery needs at least 2 refused readings",
            });
        }
        Ok(Self {
            horizon_s,
            min_refusals,
            reading_bound,
            rate_bound,
            scaled_states: 0,
        })
    }

    /// The same rule scaling the states of mask `states` on a recovery
    /// (see [`RecoveryRule::scaled_states`]).
    #[must_use]
    pub fn with_scaled_states(mut self, states: u64) -> Self {
        self.scaled_states = states;
        self
    }
}

/// What the rule made of one reading.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Judgement {
    /// No rule for the sensor, a reading too large or not finite, or a full
    /// sensor table.
    NotFollowed,
    /// Accepted by the filter: the chain is anchored at it, the run ends.
    Anchored,
    /// Refused, implausible or not agreeing with the chain: a miss.
    Miss,
    /// Refused after the run was taken as a sensor fault.
    Fault,
    /// Refused, joined the run, which is still too short.
    Following,
    /// Refused, and the run has lasted its horizon: recover. The run's
    /// duration from its first refusal (s).
    Recover(f64),
}

/// The chain of one sensor's readings.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Chain {
    /// The newest reading of the chain and its time (s), if any.
    last: Option<([f64; MAX_RECOVERY_DIM], f64)>,
    /// Time of the first refusal of the current run (s).
    run_start: f64,
    refused: u32,
    misses: u32,
    fault: bool,
    /// Set when the filter is taken back to the first refusal of a run
    /// that proved it wrong (a rollback): the run's second refusal
    /// recovers at once, reporting this duration of the proving run (s).
    forced: Option<f64>,
}

impl Chain {
    const EMPTY: Self = Self {
        last: None,
        run_start: 0.0,
        refused: 0,
        misses: 0,
        fault: false,
        forced: None,
    };
}

/// The recovery state of one filter: its clock, the rules by sensor name and
/// the chain of each followed sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Recovery {
    clock_s: f64,
    rules: [Option<(&'static str, RecoveryRule)>; MAX_RECOVERY_RULES],
    chains: [Option<(TypeId, Chain)>; MAX_RECOVERY_SENSORS],
}

impl Recovery {
    /// No rules (never recovers).
    pub(crate) const fn new() -> Self {
        Self {
            clock_s: 0.0,
            rules: [None; MAX_RECOVERY_RULES],
            chains: [None; MAX_RECOVERY_SENSORS],
        }
    }

    /// Advances the clock by one prediction step `dt` (s).
    pub(crate) fn advance(&mut self, dt: f64) {
        self.clock_s += dt;
    }

    pub(crate) fn rule(&self, name: &str) -> Option<RecoveryRule> {
        self.rules
            .iter()
            .flatten()
            .find(|(n, _)| *n == name)
            .map(|(_, r)| *r)
    }

    pub(crate) fn set_rule(
        &mut self,
        name: &'static str,
        rule: Option<RecoveryRule>,
    ) -> Result<(), SetupError> {
        let existing = self
            .rules
            .iter_mut()
            .find(|r| r.is_some_and(|(n, _)| n == name));
        match (existing, rule) {
            (Some(slot), Some(rule)) => *slot = Some((name, rule)),
            (Some(slot), None) => *slot = None,
            (None, None) => {}
            (None, Some(rule)) => match self.rules.iter_mut().find(|r| r.is_none()) {
                Some(slot) => *slot = Some((name, rule)),
                None => {
                    return Err(SetupError::Invalid {
                        reason: "too many recovery rules (capacity 6)",
                    })
                }
            },
        }
        Ok(())
    }

    /// Restarts the run of `sensor` (the lock-out release has just inflated
    /// `P` for it: the horizon counts again from this refusal).
    pub(crate) fn restart_run(&mut self, sensor: TypeId) {
        if let Some((_, chain)) = self
            .chains
            .iter_mut()
            .flatten()
            .find(|(id, _)| *id == sensor)
        {
            chain.refused = 0;
        }
    }

    /// Makes the second refusal of `sensor` that joins its run recover at
    /// once, reported as a run of `lasted` s (the run that proved the
    /// filter wrong, before the filter was taken back to its start); an
    /// accepted reading first cancels it.
    pub(crate) fn force(&mut self, sensor: TypeId, lasted: f64) {
        if let Some(chain) = self.chain_of(sensor) {
            chain.forced = Some(lasted);
        }
    }

    fn chain_of(&mut self, sensor: TypeId) -> Option<&mut Chain> {
        let index = match self
            .chains
            .iter()
            .position(|c| c.is_some_and(|(id, _)| id == sensor))
        {
            Some(i) => i,
            None => {
                let i = self.chains.iter().position(Option::is_none)?;
                *self.chains.get_mut(i)? = Some((sensor, Chain::EMPTY));
                i
            }
        };
        self.chains.get_mut(index)?.as_mut().map(|(_, c)| c)
    }

    /// The rule applied to one reading of sensor `sensor` named `name`:
    /// `reading` (at most [`MAX_RECOVERY_DIM`] components), the 1-sigma noise
    /// of each component `sigma`, which components are angles (rad,
    /// compared wrapped), and whether the filter accepted it.
    pub(crate) fn judge(
        &mut self,
        sensor: TypeId,
        name: &str,
        accepted: bool,
        reading: &[f64],
        sigma: &[f64],
        angles: &[bool],
    ) -> Judgement {
        let Some(rule) = self.rule(name) else {
            return Judgement::NotFollowed;
        };
        let now = self.clock_s;
        if reading.is_empty()
            || reading.len() > MAX_RECOVERY_DIM
            || reading.iter().any(|v| !v.is_finite())
        {
            return Judgement::NotFollowed;
        }
        let mut values = [0.0; MAX_RECOVERY_DIM];
        for (v, r) in values.iter_mut().zip(reading) {
            *v = *r;
        }
        let Some(chain) = self.chain_of(sensor) else {
            return Judgement::NotFollowed;
        };
        if accepted {
            *chain = Chain {
                last: Some((values, now)),
                ..Chain::EMPTY
            };
            return Judgement::Anchored;
        }
        let norm = libm::sqrt(reading.iter().map(|v| v * v).sum::<f64>());
        let agrees = match chain.last {
            None => true,
            Some((last, at)) => {
                let elapsed = (now - at).max(0.0);
                values.iter().zip(last).enumerate().all(|(i, (v, l))| {
                    let mut d = v - l;
                    if angles.get(i).copied().unwrap_or(false) {
                        d = crate::math::wrap_angle(d);
                    }
                    let s = sigma.get(i).copied().unwrap_or(0.0).abs();
                    let allowed =
                        rule.rate_bound * elapsed + NOISE_SIGMAS * core::f64::consts::SQRT_2 * s;
                    d.abs() <= allowed
                })
            }
        };
        if !(norm <= rule.reading_bound && agrees) {
            chain.misses = chain.misses.saturating_add(1);
            if chain.misses > MAX_MISSES {
                chain.fault = true;
            }
            return Judgement::Miss;
        }
        chain.misses = 0;
        chain.last = Some((values, now));
        if chain.fault {
            return Judgement::Fault;
        }
        if chain.refused == 0 {
            chain.run_start = now;
        }
        chain.refused = chain.refused.saturating_add(1);
        // A rollback's recovery comes at the second refusal of the run: the
        // first shows how far the filter is off, the second how fast that
        // grows (eq. R3 needs both).
        if let (Some(lasted), true) = (chain.forced, chain.refused >= 2) {
            chain.forced = None;
            chain.refused = 0;
            return Judgement::Recover(lasted);
        }
        let lasted = now - chain.run_start;
        if chain.refused >= rule.min_refusals && lasted >= rule.horizon_s {
            // The next refusal starts a new run.
            chain.refused = 0;
            return Judgement::Recover(lasted);
        }
        Judgement::Following
    }
}

/// The recovery settings and step of a filter (the state lives in the
/// filter, see [`crate::recovery`]).
impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// Sets (or with `None` removes) the recovery rule of the sensor named
    /// `sensor` (its `Sensor::NAME`). Without a rule a sensor never recovers.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] if [`MAX_RECOVERY_RULES`] other sensors have
    /// a rule.
    pub fn set_recovery_rule(
        &mut self,
        sensor: &'static str,
        rule: Option<RecoveryRule>,
    ) -> Result<(), SetupError> {
        self.lockout.recovery.set_rule(sensor, rule)
    }

    /// The recovery rule of the sensor named `sensor`.
    pub fn recovery_rule(&self, sensor: &str) -> Option<RecoveryRule> {
        self.lockout.recovery.rule(sensor)
    }

    /// Makes the second refused reading of sensor `S` (counted from now)
    /// that agrees with its chain recover at once (eqs. R1, R2 of
    /// docs/lockout.md, reported as a run of `lasted` s). For a filter
    /// taken back to the first refusal of a run that proved it wrong
    /// ("Rollback" in docs/lockout.md): the recovery then happens where the
    /// error began, with the growth between the two readings for the
    /// caller's eq. R3, and the readings of the run correct it instead of
    /// being lost. An accepted reading cancels it.
    pub fn force_recovery<S, const M: usize>(&mut self, lasted: f64)
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        self.lockout.recovery.force(TypeId::of::<S>(), lasted);
    }

    /// The filter's clock: the sum of its prediction steps (s).
    pub fn clock_s(&self) -> f64 {
        self.lockout.recovery.clock_s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    use Judgement::{Anchored as A, Fault as F, Following as W, Miss as X};

    /// One reading: time (s), value, accepted by the filter.
    type Step = (f64, f64, bool);

    /// A 1-D sensor with rule: horizon 3 s, 3 refusals, reading bound 5,
    /// rate bound 1 per s, noise sigma 0.1 (allowance 0.71 + 1 per s).
    struct Case {
        what: &'static str,
        steps: &'static [Step],
        expected: &'static [Judgement],
    }

    const R3: Judgement = Judgement::Recover(3.0);

    const CASES: &[Case] = &[
        Case {
            what: "smooth readings refused for the horizon recover",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 1.2, false),
                (2.0, 1.4, false),
                (3.0, 1.6, false),
                (4.0, 1.8, false),
            ],
            expected: &[A, W, W, W, R3],
        },
        Case {
            what: "an accepted reading ends the run",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 1.2, false),
                (2.0, 1.4, false),
                (3.0, 1.6, true),
                (4.0, 1.8, false),
                (5.0, 2.0, false),
            ],
            expected: &[A, W, W, A, W, W],
        },
        Case {
            what: "a step beyond the rate bound is a sensor fault: never recovers",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 4.8, false),
                (2.0, 4.8, false),
                (3.0, 4.8, false),
                (4.0, 4.8, false),
                (5.0, 4.8, false),
                (6.0, 4.8, false),
                (7.0, 4.8, false),
                (8.0, 4.8, false),
                (9.0, 4.8, false),
                (10.0, 4.8, false),
            ],
            // Latched after the third miss; once the allowance has grown to
            // the step (t = 4 s) its readings join the chain, but never recover.
            expected: &[A, X, X, X, F, F, F, F, F, F, F],
        },
        Case {
            what: "an implausible reading (beyond the bound) is a miss",
            steps: &[
                (0.0, 4.5, true),
                (1.0, 5.2, false),
                (2.0, 5.3, false),
                (3.0, 5.4, false),
                (4.0, 5.5, false),
            ],
            expected: &[A, X, X, X, X],
        },
        Case {
            what: "one glitch neither joins nor ends a run",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 1.1, false),
                (2.0, -3.0, false),
                (3.0, 1.2, false),
                (4.0, 1.3, false),
            ],
            expected: &[A, W, X, W, R3],
        },
        Case {
            what: "a fault run is cleared by an accepted reading",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 4.8, false),
                (2.0, 4.8, false),
                (3.0, 4.8, false),
                (4.0, 4.8, false),
                (5.0, 1.0, true),
                (6.0, 1.1, false),
                (7.0, 1.2, false),
                (8.0, 1.3, false),
                (9.0, 1.4, false),
            ],
            expected: &[A, X, X, X, F, A, W, W, W, R3],
        },
        Case {
            what: "a run restarts after a recovery",
            steps: &[
                (0.0, 1.0, true),
                (1.0, 1.0, false),
                (2.0, 1.0, false),
                (3.0, 1.0, false),
                (4.0, 1.0, false),
                (5.0, 1.0, false),
                (6.0, 1.0, false),
                (7.0, 1.0, false),
                (8.0, 1.0, false),
            ],
            expected: &[A, W, W, W, R3, W, W, W, R3],
        },
        Case {
            what: "three refusals within the horizon do not recover",
            steps: &[
                (0.0, 1.0, true),
                (0.5, 1.0, false),
                (1.0, 1.0, false),
                (1.5, 1.0, false),
                (2.0, 1.0, false),
                (3.5, 1.0, false),
            ],
            expected: &[A, W, W, W, W, R3],
        },
    ];

    /// The judgements of the rule of [`Case`] on `steps`; with `force`
    /// `(k, lasted)`, a recovery forced before step `k`.
    fn judged(steps: &[Step], force: Option<(usize, f64)>) -> Vec<Judgement> {
        let id = TypeId::of::<Case>();
        let mut r = Recovery::new();
        r.set_rule("s", Some(RecoveryRule::new(3.0, 3, 5.0, 1.0).unwrap()))
            .unwrap();
        let mut clock = 0.0;
        let mut got = Vec::new();
        for (k, &(t, v, accepted)) in steps.iter().enumerate() {
            if t > clock {
                r.advance(t - clock);
                clock = t;
            }
            if let Some((_, lasted)) = force.filter(|(at, _)| *at == k) {
                r.force(id, lasted);
            }
            got.push(r.judge(id, "s", accepted, &[v], &[0.1], &[false]));
        }
        got
    }

    #[test]
    fn recovery_rule_cases() {
        for case in CASES {
            assert_eq!(judged(case.steps, None), case.expected, "{}", case.what);
        }
    }

    /// A forced recovery (a rollback to the start of a run that proved the
    /// filter wrong): the second refusal that joins recovers at once with
    /// the given duration; an accepted reading cancels it; a miss does not
    /// count.
    #[test]
    fn a_forced_recovery_comes_at_the_second_joining_refusal() {
        const R7: Judgement = Judgement::Recover(7.0);
        // Force before step `at`; the steps as in `CASES`.
        let cases: &[(&str, usize, &[Step], &[Judgement])] = &[
            (
                "the second refusal recovers, the run starts again",
                1,
                &[
                    (0.0, 1.0, true),
                    (1.0, 1.2, false),
                    (2.0, 1.4, false),
                    (3.0, 1.6, false),
                ],
                &[A, W, R7, W],
            ),
            (
                "an accepted reading cancels it",
                1,
                &[
                    (0.0, 1.0, true),
                    (1.0, 1.2, false),
                    (2.0, 1.4, true),
                    (3.0, 1.6, false),
                    (4.0, 1.8, false),
                ],
                &[A, W, A, W, W],
            ),
            (
                "a miss does not count",
                1,
                &[
                    (0.0, 1.0, true),
                    (1.0, 4.8, false),
                    (2.0, 1.6, false),
                    (3.0, 1.8, false),
                ],
                &[A, X, W, R7],
            ),
        ];
        for &(what, at, steps, expected) in cases {
            assert_eq!(judged(steps, Some((at, 7.0))), expected, "{what}");
        }
    }

    #[test]
    fn angles_are_compared_wrapped() {
        let id = TypeId::of::<Case>();
        let mut r = Recovery::new();
        r.set_rule(
            "c",
            Some(RecoveryRule::new(1.0, 2, f64::INFINITY, 0.5).unwrap()),
        )
        .unwrap();
        let pi = core::f64::consts::PI;
        assert_eq!(r.judge(id, "c", true, &[pi - 0.01], &[0.01], &[true]), A);
        r.advance(1.0);
        // Across +-pi: a change of 0.02 rad, not 2 pi.
        assert_eq!(r.judge(id, "c", false, &[-pi + 0.01], &[0.01], &[true]), W);
        r.advance(1.0);
        assert_eq!(
            r.judge(id, "c", false, &[-pi + 0.02], &[0.01], &[true]),
            Judgement::Recover(1.0)
        );
        // Without wrapping the same step is a miss.
        let mut r2 = Recovery::new();
        r2.set_rule(
            "c",
            Some(RecoveryRule::new(1.0, 2, f64::INFINITY, 0.5).unwrap()),
        )
        .unwrap();
        r2.judge(id, "c", true, &[pi - 0.01], &[0.01], &[false]);
        r2.advance(1.0);
        assert_eq!(
            r2.judge(id, "c", false, &[-pi + 0.01], &[0.01], &[false]),
            X
        );
    }

    #[test]
    fn no_rule_no_finite_reading_and_invalid_rules() {
        let id = TypeId::of::<Case>();
        let mut r = Recovery::new();
        assert_eq!(
            r.judge(id, "s", false, &[1.0], &[0.1], &[false]),
            Judgement::NotFollowed
        );
        r.set_rule("s", Some(RecoveryRule::new(3.0, 3, 5.0, 1.0).unwrap()))
            .unwrap();
        assert_eq!(
            r.judge(id, "s", false, &[f64::NAN], &[0.1], &[false]),
            Judgement::NotFollowed
        );
        assert_eq!(
            r.judge(id, "s", false, &[1.0; 4], &[0.1; 4], &[false; 4]),
            Judgement::NotFollowed
        );
        r.set_rule("s", None).unwrap();
        assert_eq!(r.rule("s"), None);
        for (h, n, b, rate) in [
            (0.0, 3, 5.0, 1.0),
            (f64::INFINITY, 3, 5.0, 1.0),
            (3.0, 1, 5.0, 1.0),
            (3.0, 3, 0.0, 1.0),
            (3.0, 3, f64::NAN, 1.0),
            (3.0, 3, 5.0, -1.0),
        ] {
            assert!(
                RecoveryRule::new(h, n, b, rate).is_err(),
                "{h} {n} {b} {rate}"
            );
        }
        assert!(RecoveryRule::new(3.0, 2, f64::INFINITY, 1.0).is_ok());
    }
}
