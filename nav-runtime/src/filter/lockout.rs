//! Gate lock-out release on evidence (docs/lockout.md).
//!
//! The innovation gate trusts the predicted innovation covariance `S`. After
//! the filter has taken an outlier it could not recognise (early, while
//! `H P H^T` dwarfed `R`), its estimate is off while `S` has shrunk, and every
//! later, correct measurement of that sensor fails the gate: a *lock-out*.
//! Consecutive refusals alone do not tell a locked-out filter from a sensor
//! that is wrong: a USBL 10 km off or a DVL reading 30 m/s is refused just as
//! often. What tells them apart is what the refused innovations look like:
//!
//! - **Agreement** (eq. L1-L3 of docs/lockout.md). A locked-out filter sees
//!   the innovations `nu_i = b + e_i` of one offset `b` (its own error seen
//!   through `H`) plus noise `e_i ~ N(0, S_i)`. With `W_i = S_i^-1`, the
//!   weighted mean `b^ = (sum W_i)^-1 sum W_i nu_i` (L1) and the spread
//!   `T = sum (nu_i - b^)^T W_i (nu_i - b^) = sum nu_i^T W_i nu_i - b^T (sum
//!   W_i) b^` (L2) is chi-square with `(n - 1) M` degrees of freedom, so `n`
//!   refusals in a row agree if `T <= chi2((n - 1) M, p)` (L3). Outliers that
//!   scatter (multipath, spikes, noise) fail this: the run restarts at the
//!   newest refusal.
//! - **Plausibility**. An innovation component beyond the sensor's configured
//!   absolute bound (its units: m, m/s, rad) is physically impossible as a
//!   filter error; it is ignored (it neither counts nor breaks a run), so
//!   only runs of plausible innovations release. This is what stops a sensor
//!   that is wrong *consistently* (a fixed 10 km offset agrees with itself).
//!
//! A run that agrees and is plausible is **released by inflating `P`**, not
//! by applying a sample: with `U = P H^T` and `C = H P H^T` at the current
//! state, `d = U C^-1 b^` is the state error that explains the offset `b^`
//! with the correlations `P` already holds (`H d = b^`, and the least
//! `d^T P^-1 d` among those that do), and `P <- P + d d^T` (L4) adds the
//! covariance of that error, so that `S` grows by `b^ b^T`. The next sample of
//! the sensor then passes the gate on its own and is applied through the
//! ordinary Kalman gain, with the posterior covariance that goes with it.
//!
//! Storage is fixed ([`MAX_LOCKOUT_SENSORS`] sensors, innovations of at most
//! [`MAX_LOCKOUT_DIM`] components); nothing here allocates or panics, and the
//! chi-square thresholds are computed once, when the rule is made.

use core::any::TypeId;

use nalgebra::{Cholesky, SMatrix, SVector};

use crate::ekf::{Ekf, UpdateReport};
use crate::gate::chi_square_quantile;
use crate::model::{Model, Sensor};
use crate::real::Real;
use crate::setup_error::SetupError;

/// Largest measurement dimension whose refusals are examined; refusals of
/// larger measurements are never released. (The storage is part of the
/// filter, which the scheduler copies at every checkpoint, so it is kept
/// small: position, velocity, depth and heading sensors have 1 to 3.)
pub const MAX_LOCKOUT_DIM: usize = 3;

/// Number of sensors per filter whose runs of refusals are examined;
/// refusals of further sensors are never released.
pub const MAX_LOCKOUT_SENSORS: usize = 4;

/// Number of sensors that can have a plausibility bound.
pub const MAX_LOCKOUT_BOUNDS: usize = 6;

/// Largest run length a [`LockoutRelease`] accepts.
pub const MAX_LOCKOUT_REFUSALS: u32 = 64;

/// The release rule: how many consecutive refusals of one sensor are examined
/// and at which probability their agreement is tested (eq. L3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LockoutRelease {
    refusals: u32,
    probability: f64,
    /// `chi2((refusals - 1) m, probability)` for `m = 1 ..= MAX_LOCKOUT_DIM`.
    thresholds: [f64; MAX_LOCKOUT_DIM],
}

impl LockoutRelease {
    /// Default run length: 3 refusals in a row. A consistent filter refuses 3
    /// good samples in a row with probability `(1 - 0.9999)^3 = 1e-12` at the
    /// default gate.
    pub const DEFAULT_REFUSALS: u32 = 3;

    /// Default agreement probability: 3 samples of a locked-out filter fail
    /// the test one time in 1000 (the run then restarts, so a lock-out is
    /// released a few samples later).
    pub const DEFAULT_PROBABILITY: f64 = 0.999;

    /// A rule examining `refusals` consecutive refusals (2 ..=
    /// [`MAX_LOCKOUT_REFUSALS`]) with agreement probability `probability`.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] for a run length out of range,
    /// [`SetupError::InvalidProbability`] for a probability outside (0, 1).
    pub fn new(refusals: u32, probability: f64) -> Result<Self, SetupError> {
        if !(2..=MAX_LOCKOUT_REFUSALS).contains(&refusals) {
            return Err(SetupError::Invalid {
                reason: "lock-out release needs 2 to 64 consecutive refusals",
            });
        }
        let invalid = SetupError::InvalidProbability { probability };
        let mut thresholds = [0.0; MAX_LOCKOUT_DIM];
        for (m, t) in thresholds.iter_mut().enumerate() {
            let dof = (refusals as usize - 1) * (m + 1);
            *t = chi_square_quantile(probability, dof).ok_or(invalid)?;
        }
        Ok(Self {
            refusals,
            probability,
            thresholds,
        })
    }

    /// Consecutive refusals examined.
    pub fn refusals(&self) -> u32 {
        self.refusals
    }

    /// Agreement probability of eq. L3.
    pub fn probability(&self) -> f64 {
        self.probability
    }

    /// Eq. L3's threshold for an `m`-dimensional sensor (`None` beyond
    /// [`MAX_LOCKOUT_DIM`]).
    pub fn threshold(&self, m: usize) -> Option<f64> {
        self.thresholds.get(m.wrapping_sub(1)).copied()
    }
}

impl Default for LockoutRelease {
    fn default() -> Self {
        // Both constants are in range, so this cannot fail; the fallback keeps
        // the function total.
        Self::new(Self::DEFAULT_REFUSALS, Self::DEFAULT_PROBABILITY).unwrap_or(Self {
            refusals: Self::DEFAULT_REFUSALS,
            probability: Self::DEFAULT_PROBABILITY,
            thresholds: [f64::INFINITY; MAX_LOCKOUT_DIM],
        })
    }
}

/// What the rule made of one refused innovation.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Verdict {
    /// Beyond the sensor's plausibility bound: ignored.
    Implausible,
    /// Added to the run, which is still shorter than the rule's length.
    Collecting,
    /// The run does not agree within its noise (eq. L3): it restarts at
    /// this refusal.
    Inconsistent,
    /// The run agrees: `P` is inflated (eq. L4).
    Release,
    /// Not examined: no rule, a measurement larger than [`MAX_LOCKOUT_DIM`],
    /// a full sensor table, or an `S` or `H P H^T` without Cholesky factor.
    NotExamined,
}

/// The sufficient statistics of one sensor's run of refusals (eqs. L1, L2):
/// `sum W_i`, `sum W_i nu_i`, `sum nu_i^T W_i nu_i` and the count.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Evidence {
    count: u32,
    information: [[f64; MAX_LOCKOUT_DIM]; MAX_LOCKOUT_DIM],
    weighted: [f64; MAX_LOCKOUT_DIM],
    square: f64,
}

impl Evidence {
    const EMPTY: Self = Self {
        count: 0,
        information: [[0.0; MAX_LOCKOUT_DIM]; MAX_LOCKOUT_DIM],
        weighted: [0.0; MAX_LOCKOUT_DIM],
        square: 0.0,
    };

    /// Adds innovation `nu` with weight `w = S^-1`.
    fn add<const M: usize>(&mut self, nu: &SVector<f64, M>, w: &SMatrix<f64, M, M>) {
        let wn = w * nu;
        for (i, row) in self.information.iter_mut().enumerate().take(M) {
            for (j, a) in row.iter_mut().enumerate().take(M) {
                *a += w[(i, j)];
            }
        }
        for (i, g) in self.weighted.iter_mut().enumerate().take(M) {
            *g += wn[i];
        }
        self.square += nu.dot(&wn);
        self.count = self.count.saturating_add(1);
    }

    /// The weighted mean `b^` (eq. L1) and the spread `T` (eq. L2); `None`
    /// if `sum W_i` has no Cholesky factor.
    fn mean_and_spread<const M: usize>(&self) -> Option<(SVector<f64, M>, f64)> {
        let read = |r: &[f64; MAX_LOCKOUT_DIM], j: usize| r.get(j).copied().unwrap_or(0.0);
        let zero = [0.0; MAX_LOCKOUT_DIM];
        let a =
            SMatrix::<f64, M, M>::from_fn(|i, j| read(self.information.get(i).unwrap_or(&zero), j));
        let g = SVector::<f64, M>::from_fn(|i, _| read(&self.weighted, i));
        let mean = Cholesky::new(a)?.solve(&g);
        let spread = self.square - g.dot(&mean);
        (spread.is_finite() && all_finite(mean.as_slice())).then_some((mean, spread))
    }
}

/// The lock-out state of one filter: the rule, the plausibility bounds by
/// sensor name and the current run of refusals of each sensor.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Lockout {
    rule: Option<LockoutRelease>,
    bounds: [Option<(&'static str, f64)>; MAX_LOCKOUT_BOUNDS],
    runs: [Option<(TypeId, Evidence)>; MAX_LOCKOUT_SENSORS],
    /// The recovery from a lock-out into divergence ([`crate::recovery`]).
    pub(crate) recovery: crate::recovery::Recovery,
}

impl Lockout {
    /// No rule (never released), no bounds.
    pub(crate) const fn new() -> Self {
        Self {
            rule: None,
            bounds: [None; MAX_LOCKOUT_BOUNDS],
            runs: [None; MAX_LOCKOUT_SENSORS],
            recovery: crate::recovery::Recovery::new(),
        }
    }

    /// The plausibility bound of sensor `name` (infinite if none is set).
    fn bound(&self, name: &str) -> f64 {
        self.bounds
            .iter()
            .flatten()
            .find(|(n, _)| *n == name)
            .map_or(f64::INFINITY, |(_, b)| *b)
    }

    fn set_bound(&mut self, name: &'static str, bound: f64) -> Result<(), SetupError> {
        if bound.is_nan() || bound <= 0.0 {
            return Err(SetupError::Invalid {
                reason: "lock-out plausibility bound must be positive",
            });
        }
        if let Some(slot) = self.bounds.iter_mut().flatten().find(|(n, _)| *n == name) {
            slot.1 = bound;
            return Ok(());
        }
        match self.bounds.iter_mut().find(|b| b.is_none()) {
            Some(slot) => {
                *slot = Some((name, bound));
                Ok(())
            }
            None => Err(SetupError::Invalid {
                reason: "too many lock-out plausibility bounds (capacity 6)",
            }),
        }
    }

    /// Forgets the run of `sensor` (after an accepted sample or a recovery).
    pub(crate) fn clear(&mut self, sensor: TypeId) {
        if let Some(slot) = self
            .runs
            .iter_mut()
            .find(|r| r.is_some_and(|(id, _)| id == sensor))
        {
            *slot = None;
        }
    }

    /// The run of `sensor`, a new empty one if it has none (`None` if the
    /// table is full).
    fn run_of(&mut self, sensor: TypeId) -> Option<&mut Evidence> {
        let index = match self
            .runs
            .iter()
            .position(|r| r.is_some_and(|(id, _)| id == sensor))
        {
            Some(i) => i,
            None => {
                let i = self.runs.iter().position(Option::is_none)?;
                *self.runs.get_mut(i)? = Some((sensor, Evidence::EMPTY));
                i
            }
        };
        self.runs.get_mut(index)?.as_mut().map(|(_, e)| e)
    }

    /// The rule applied to one refused innovation `nu` with covariance `s`
    /// of the sensor `sensor` named `name`: updates the run and returns the
    /// verdict with, for [`Verdict::Release`], the run's mean `b^`.
    pub(crate) fn judge<const M: usize>(
        &mut self,
        sensor: TypeId,
        name: &str,
        nu: &SVector<f64, M>,
        s: &SMatrix<f64, M, M>,
    ) -> (Verdict, SVector<f64, M>) {
        let zero = SVector::<f64, M>::zeros();
        let Some(rule) = self.rule else {
            return (Verdict::NotExamined, zero);
        };
        let Some(threshold) = rule.threshold(M) else {
            return (Verdict::NotExamined, zero);
        };
        let bound = self.bound(name);
        // NaN is never plausible (the filter refuses it before this anyway).
        if nu.iter().any(|v| v.is_nan() || v.abs() > bound) {
            return (Verdict::Implausible, zero);
        }
        let Some(w) = Cholesky::new(*s).map(|c| c.inverse()) else {
            return (Verdict::NotExamined, zero);
        };
        let Some(run) = self.run_of(sensor) else {
            return (Verdict::NotExamined, zero);
        };
        run.add(nu, &w);
        if run.count < rule.refusals {
            return (Verdict::Collecting, zero);
        }
        let agreed = run
            .mean_and_spread::<M>()
            .filter(|(_, spread)| *spread <= threshold);
        match agreed {
            Some((mean, _)) => {
                *run = Evidence::EMPTY;
                (Verdict::Release, mean)
            }
            None => {
                *run = Evidence::EMPTY;
                run.add(nu, &w);
                (Verdict::Inconsistent, zero)
            }
        }
    }

    /// The lock-out step after the gate decided on a measurement of sensor
    /// `S` (the filter's one call): an accepted sample ends the run; a
    /// refused one is judged and, on [`Verdict::Release`], `p` is inflated
    /// by eq. L4 at the state `x`. Returns `true` if `p` was inflated.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn after_gate<S, T: Real, const N: usize, const M: usize>(
        &mut self,
        report: &UpdateReport<M, T>,
        p: &mut SMatrix<T, N, N>,
        x: &SVector<T, N>,
        input: &<S::Model as Model<N, T>>::Input,
        params: &<S::Model as Model<N, T>>::Params,
        aux: &S::Aux,
    ) -> bool
    where
        S: Sensor<N, M, T>,
    {
        let sensor = TypeId::of::<S>();
        if self.rule.is_none() {
            return false;
        }
        if report.accepted {
            self.clear(sensor);
            return false;
        }
        let (verdict, mean) = self.judge(
            sensor,
            S::NAME,
            &report.innovation.map(Real::to_f64),
            &report.innovation_covariance.map(Real::to_f64),
        );
        if verdict != Verdict::Release {
            return false;
        }
        let (_, u, hph) = S::innovation_terms(p, x, input, params, aux);
        match inflation(p, &u, &hph, &mean.map(T::of)) {
            Some(inflated) => {
                *p = inflated;
                true
            }
            None => false,
        }
    }
}

/// Eq. L4: `P + d d^T` with `d = U C^-1 b` (`U = P H^T`, `C = H P H^T`);
/// `None` if `C` has no Cholesky factor or the result is not finite.
pub(crate) fn inflation<T: Real, const N: usize, const M: usize>(
    p: &SMatrix<T, N, N>,
    u: &SMatrix<T, N, M>,
    hph: &SMatrix<T, M, M>,
    mean: &SVector<T, M>,
) -> Option<SMatrix<T, N, N>> {
    let mut c = *hph;
    for i in 0..M {
        for j in 0..i {
            c[(i, j)] = c[(j, i)];
        }
    }
    let d = u * Cholesky::new(c)?.solve(mean);
    // `d_i d_j == d_j d_i` exactly, so a symmetric `P` stays symmetric.
    let inflated = p + d * d.transpose();
    all_finite(inflated.as_slice()).then_some(inflated)
}

fn all_finite<T: Real>(v: &[T]) -> bool {
    v.iter().all(|x| x.is_finite())
}

/// The lock-out release settings of a filter (the state lives in the filter,
/// see [`crate::lockout`]).
impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// Gate lock-out release by `rule` (`None`, the default: a sensor the
    /// gate refuses stays refused). See [`crate::lockout`].
    #[must_use]
    pub fn with_lockout_release(mut self, rule: Option<LockoutRelease>) -> Self {
        self.set_lockout_release(rule);
        self
    }

    /// Changes the lock-out release rule; the runs of refusals collected so
    /// far are forgotten.
    pub fn set_lockout_release(&mut self, rule: Option<LockoutRelease>) {
        self.lockout.rule = rule;
        self.lockout.runs = [None; MAX_LOCKOUT_SENSORS];
    }

    /// The lock-out release rule in use.
    pub fn lockout_release(&self) -> Option<LockoutRelease> {
        self.lockout.rule
    }

    /// Sets the plausibility bound of the sensor named `sensor` (its
    /// `Sensor::NAME`): refused innovations with a component larger than
    /// `bound` in absolute value (the sensor's units) never lead to a
    /// release. Without a bound every size is plausible.
    ///
    /// # Errors
    /// [`SetupError::Invalid`] if `bound` is not positive (NaN
    /// included) or [`MAX_LOCKOUT_BOUNDS`] other sensors have a bound.
    pub fn set_lockout_bound(
        &mut self,
        sensor: &'static str,
        bound: f64,
    ) -> Result<(), SetupError> {
        self.lockout.set_bound(sensor, bound)
    }

    /// The plausibility bound of the sensor named `sensor` (infinite if none).
    pub fn lockout_bound(&self, sensor: &str) -> f64 {
        self.lockout.bound(sensor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A run of 1-D refusals with unit `S`: the innovations, the bound and
    /// the verdict after each.
    struct Case {
        what: &'static str,
        innovations: &'static [f64],
        bound: f64,
        verdicts: &'static [Verdict],
    }

    use Verdict::{Collecting as C, Implausible as I, Inconsistent as X, Release as R};

    /// chi2(2 dof, 0.999) = 13.8: three unit-variance innovations agree when
    /// their spread about the mean is below it (e.g. +-2.6 about it).
    const CASES: &[Case] = &[
        Case {
            what: "a constant offset (lock-out) releases at the third",
            innovations: &[10.0, 10.0, 10.0],
            bound: f64::INFINITY,
            verdicts: &[C, C, R],
        },
        Case {
            what: "an offset with unit noise releases",
            innovations: &[9.0, 11.0, 10.5],
            bound: f64::INFINITY,
            verdicts: &[C, C, R],
        },
        Case {
            what: "a spread just inside chi2(2, 0.999) releases",
            innovations: &[7.4, 10.0, 12.6],
            bound: f64::INFINITY,
            verdicts: &[C, C, R],
        },
        Case {
            what: "a spread just outside it restarts at the newest",
            innovations: &[7.3, 10.0, 12.7, 12.7, 12.7],
            bound: f64::INFINITY,
            verdicts: &[C, C, X, C, R],
        },
        Case {
            what: "alternating outliers never release",
            innovations: &[10.0, -10.0, 10.0, -10.0, 10.0, -10.0],
            bound: f64::INFINITY,
            verdicts: &[C, C, X, C, X, C],
        },
        Case {
            what: "a consistent offset beyond the bound is ignored",
            innovations: &[1e4, 1e4, 1e4, 1e4],
            bound: 100.0,
            verdicts: &[I, I, I, I],
        },
        Case {
            what: "implausible samples neither count nor break a run",
            innovations: &[10.0, 1e4, 10.0, -1e4, 10.0],
            bound: 100.0,
            verdicts: &[C, I, C, I, R],
        },
        Case {
            what: "a component exactly at the bound is plausible",
            innovations: &[100.0, 100.0, 100.0],
            bound: 100.0,
            verdicts: &[C, C, R],
        },
    ];

    #[test]
    fn release_rule_cases() {
        let s = SMatrix::<f64, 1, 1>::new(1.0);
        let id = TypeId::of::<Case>();
        for case in CASES {
            let mut l = Lockout::new();
            l.rule = Some(LockoutRelease::default());
            l.set_bound("s", case.bound).unwrap_or(());
            let got: Vec<Verdict> = case
                .innovations
                .iter()
                .map(|nu| l.judge(id, "s", &SVector::<f64, 1>::new(*nu), &s).0)
                .collect();
            assert_eq!(got, case.verdicts, "{}", case.what);
        }
    }

    /// The mean of a release is the `S^-1`-weighted mean (eq. L1) and the
    /// spread is chi-square (eq. L2): checked on 2-D innovations with
    /// different covariances against the direct sums.
    #[test]
    fn mean_and_spread_match_the_direct_sums() {
        let s = [
            SMatrix::<f64, 2, 2>::new(2.0, 0.5, 0.5, 1.0),
            SMatrix::<f64, 2, 2>::new(1.0, -0.2, -0.2, 3.0),
            SMatrix::<f64, 2, 2>::new(4.0, 0.0, 0.0, 0.5),
        ];
        let nu = [
            SVector::<f64, 2>::new(5.0, -3.0),
            SVector::<f64, 2>::new(6.0, -2.0),
            SVector::<f64, 2>::new(4.5, -2.5),
        ];
        let mut e = Evidence::EMPTY;
        let (mut a, mut g) = (SMatrix::<f64, 2, 2>::zeros(), SVector::<f64, 2>::zeros());
        for (si, ni) in s.iter().zip(&nu) {
            let w = si.try_inverse().unwrap();
            e.add(ni, &w);
            a += w;
            g += w * ni;
        }
        let mean = a.try_inverse().unwrap() * g;
        let spread: f64 = s
            .iter()
            .zip(&nu)
            .map(|(si, ni)| {
                let d = ni - mean;
                d.dot(&(si.try_inverse().unwrap() * d))
            })
            .sum();
        let (m, t) = e.mean_and_spread::<2>().unwrap();
        assert!((m - mean).norm() < 1e-12, "{m} vs {mean}");
        assert!((t - spread).abs() < 1e-12, "{t} vs {spread}");
    }

    /// Under the lock-out hypothesis (common offset, independent `N(0, S_i)`
    /// noise) the rule releases at its probability: 3-sample runs of 2-D
    /// innovations fail the agreement test at about 1 - 0.999.
    #[test]
    fn agreement_test_fails_at_its_probability_under_the_lock_out_hypothesis() {
        // splitmix64 and Box-Muller, for reproducible normal draws.
        let mut state = 7u64;
        let mut uniform = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut normal = move || {
            let (u1, u2) = (uniform().max(1e-300), uniform());
            (-2.0 * u1.ln()).sqrt() * (core::f64::consts::TAU * u2).cos()
        };
        let s = SMatrix::<f64, 2, 2>::new(4.0, 1.0, 1.0, 2.0);
        let l_s = Cholesky::new(s).unwrap().l();
        let offset = SVector::<f64, 2>::new(40.0, -25.0);
        let trials = 40_000;
        let mut failures = 0;
        for _ in 0..trials {
            let mut l = Lockout::new();
            l.rule = Some(LockoutRelease::default());
            let mut last = Verdict::NotExamined;
            for _ in 0..3 {
                let nu = offset + l_s * SVector::<f64, 2>::new(normal(), normal());
                last = l.judge(TypeId::of::<Case>(), "s", &nu, &s).0;
            }
            failures += usize::from(last == Verdict::Inconsistent);
        }
        // Binomial(40000, 1e-3): mean 40, sd 6.3; 4 sd either side.
        assert!((15..=65).contains(&failures), "{failures} of {trials}");
    }

    #[test]
    fn inflation_makes_the_offset_one_sigma_and_keeps_p_symmetric() {
        let p = SMatrix::<f64, 3, 3>::new(1.0, 0.3, 0.1, 0.3, 2.0, -0.2, 0.1, -0.2, 0.5);
        let h = SMatrix::<f64, 2, 3>::new(1.0, 0.0, 0.0, 0.0, 1.0, 1.0);
        let u = p * h.transpose();
        let c = h * u;
        let b = SVector::<f64, 2>::new(30.0, -12.0);
        let inflated = inflation(&p, &u, &c, &b).unwrap();
        assert_eq!(inflated, inflated.transpose());
        // H (P + d d^T) H^T = C + b b^T.
        let grown = h * inflated * h.transpose() - c;
        assert!((grown - b * b.transpose()).norm() < 1e-9, "{grown}");
        // A singular H P H^T is refused rather than inverted.
        assert!(inflation(&p, &u, &SMatrix::<f64, 2, 2>::zeros(), &b).is_none());
    }

    #[test]
    fn invalid_rules_and_bounds_are_refused() {
        assert!(LockoutRelease::new(1, 0.999).is_err());
        assert!(LockoutRelease::new(65, 0.999).is_err());
        assert!(LockoutRelease::new(3, 1.0).is_err());
        assert!(LockoutRelease::new(3, f64::NAN).is_err());
        let rule = LockoutRelease::default();
        assert_eq!(rule.refusals(), 3);
        // chi2(2, 0.999) = 13.8155.
        assert!((rule.threshold(1).unwrap() - 13.8155).abs() < 1e-3);
        assert_eq!(rule.threshold(0), None);
        assert_eq!(rule.threshold(MAX_LOCKOUT_DIM + 1), None);
        let mut l = Lockout::new();
        for bad in [0.0, -1.0, f64::NAN] {
            assert!(l.set_bound("s", bad).is_err());
        }
        let names = ["a", "b", "c", "d", "e", "f", "g"];
        for name in &names[..MAX_LOCKOUT_BOUNDS] {
            l.set_bound(name, 1.0).unwrap();
        }
        assert!(l.set_bound(names[MAX_LOCKOUT_BOUNDS], 1.0).is_err());
        l.set_bound("a", 2.0).unwrap();
        assert_eq!(l.bound("a"), 2.0);
        assert_eq!(l.bound("z"), f64::INFINITY);
    }
}
