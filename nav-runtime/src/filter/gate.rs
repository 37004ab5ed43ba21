//! Innovation gates: chi-square thresholds on the normalized innovation squared.
//!
//! For a consistent filter the innovation `nu = z - h(x)` of an `M`-dimensional
//! measurement is zero-mean Gaussian with covariance `S = H P H^T + R`, so the
//! normalized innovation squared `NIS = nu^T S^-1 nu` is chi-square distributed
//! with `M` degrees of freedom (Bar-Shalom, Li & Kirubarajan, *Estimation with
//! Applications to Tracking and Navigation*, 2001, sec. 5.4). A gate with
//! probability `p` accepts a measurement when `NIS <= chi2_quantile(p, M)`, so a
//! consistent filter rejects a fraction `1 - p` of good measurements and an
//! outlier of `k` sigma along one axis is rejected once `k^2` exceeds the
//! threshold (10 sigma: NIS = 100 against 3.84 .. 26.2 for `M` = 1 .. 12 at 0.95).
//!
//! Everything here is `core` + libm: the regularized incomplete gamma function is
//! evaluated by its power series or its continued fraction (Numerical Recipes,
//! 3rd ed., sec. 6.2, eqs. 6.2.5 and 6.2.7) and the quantile is found by bisection,
//! so there is no dependency on a statistics crate.

use crate::setup_error::SetupError;

/// Degrees of freedom for which a [`Gate`] caches its threshold; larger
/// measurement vectors are evaluated on demand (no allocation either way).
pub const CACHED_DOF: usize = 12;

/// A chi-square innovation gate: accepts when `NIS <= chi2_quantile(probability, M)`.
///
/// Thresholds for `M = 1 ..= 12` are computed once, at construction, so gating
/// costs one comparison per update. `Option<Gate>` is the per-sensor setting used
/// by [`crate::ekf::Ekf`]; `None` disables gating.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Gate {
    probability: f64,
    thresholds: [f64; CACHED_DOF],
}

impl Gate {
    /// The default gate probability: one consistent measurement in 10,000 is
    /// rejected (about 3.9 sigma for one degree of freedom). Tight enough to
    /// stop gross outliers, loose enough not to starve a filter whose covariance
    /// is slightly optimistic.
    pub const DEFAULT_PROBABILITY: f64 = 0.9999;

    /// A gate accepting a consistent measurement with probability `probability`.
    ///
    /// # Errors
    /// [`SetupError::InvalidProbability`] unless `0 < probability < 1`.
    pub fn new(probability: f64) -> Result<Self, SetupError> {
        if !(probability > 0.0 && probability < 1.0) {
            return Err(SetupError::InvalidProbability { probability });
        }
        if probability == Self::DEFAULT_PROBABILITY {
            return Ok(Self::default());
        }
        let mut thresholds = [0.0; CACHED_DOF];
        for (i, t) in thresholds.iter_mut().enumerate() {
            *t = chi_square_quantile(probability, i + 1)
                .ok_or(SetupError::InvalidProbability { probability })?;
        }
        Ok(Self {
            probability,
            thresholds,
        })
    }

    /// The probability that a consistent measurement passes the gate.
    pub fn probability(&self) -> f64 {
        self.probability
    }

    /// The NIS threshold for an `m`-dimensional measurement (`m >= 1`).
    /// Returns `+inf` for `m == 0` (nothing to test).
    pub fn threshold(&self, m: usize) -> f64 {
        match m {
            0 => f64::INFINITY,
            _ => match self.thresholds.get(m - 1) {
                Some(t) => *t,
                None => chi_square_quantile(self.probability, m).unwrap_or(f64::INFINITY),
            },
        }
    }

    /// `true` if `nis` passes the gate for an `m`-dimensional measurement.
    /// A NaN `nis` never passes.
    pub fn accepts(&self, nis: f64, m: usize) -> bool {
        nis <= self.threshold(m)
    }
}

/// The thresholds of the gate at [`Gate::DEFAULT_PROBABILITY`] for `M = 1
/// ..= 12`, bit for bit those [`chi_square_quantile`] gives (checked by a
/// test): every filter starts with this gate, so it costs no quantile
/// searches to build.
const DEFAULT_THRESHOLD_BITS: [u64; CACHED_DOF] = [
    0x402e45fe3a3b14d0, // 15.136705226623604
    0x40326bb1bbb55554, // 18.420680743952587
    0x40351b8600a509e8, // 21.10751346616044
    0x4037834316c081fc, // 23.512742444991076
    0x4039bead4ea92962, // 25.74483195905612
    0x403bdb392de2e5a6, // 27.856341236014167
    0x403de0a418a03bf8, // 29.87750390922517
    0x403fd3df6dbead3a, // 31.82762800126259
    0x4040dc27453c148c, // 33.719948438964906
    0x4041c8319bdd9638, // 35.564013941952396
    0x4042aef9695ea30e, // 37.366986437997284
    0x40439134257ab706, // 39.13440388194981
];

impl Default for Gate {
    /// The gate at [`Gate::DEFAULT_PROBABILITY`].
    fn default() -> Self {
        Self {
            probability: Self::DEFAULT_PROBABILITY,
            thresholds: DEFAULT_THRESHOLD_BITS.map(f64::from_bits),
        }
    }
}

/// The chi-square quantile: the `x` with `P(chi2_dof <= x) = probability`.
///
/// `None` if `probability` is not in (0, 1) or `dof == 0`. Accurate to about
/// 1e-12 relative (bisection to the last representable bracket); the upper tail
/// is used for `probability > 0.5`, so thresholds near 1 keep their precision.
pub fn chi_square_quantile(probability: f64, dof: usize) -> Option<f64> {
    if !(probability > 0.0 && probability < 1.0) || dof == 0 {
        return None;
    }
    let a = 0.5 * dof as f64;
    let upper = probability > 0.5;
    let target = if upper {
        1.0 - probability
    } else {
        probability
    };
    // f(x) < 0 while x is below the quantile.
    let below = |x: f64| {
        if upper {
            regularized_upper_gamma(a, 0.5 * x) > target
        } else {
            regularized_lower_gamma(a, 0.5 * x) < target
        }
    };
    let mut lo = 0.0;
    let mut hi = dof as f64 + 10.0;
    let mut guard = 0;
    while below(hi) {
        lo = hi;
        hi *= 2.0;
        guard += 1;
        if guard > 64 {
            return None;
        }
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if below(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    Some(0.5 * (lo + hi))
}

/// The chi-square cumulative distribution `P(chi2_dof <= x) = P(dof/2, x/2)`.
pub fn chi_square_cdf(x: f64, dof: usize) -> f64 {
    if dof == 0 {
        return if x >= 0.0 { 1.0 } else { 0.0 };
    }
    regularized_lower_gamma(0.5 * dof as f64, 0.5 * x)
}

/// The regularized lower incomplete gamma function
/// `P(a, x) = gamma(a, x) / Gamma(a)` for `a > 0`, `x >= 0` (NaN otherwise).
pub fn regularized_lower_gamma(a: f64, x: f64) -> f64 {
    if a.is_nan() || a <= 0.0 || x.is_nan() || x < 0.0 {
        return f64::NAN;
    }
    if x == 0.0 {
        return 0.0;
    }
    if x.is_infinite() {
        return 1.0;
    }
    if x < a + 1.0 {
        gamma_series(a, x)
    } else {
        1.0 - gamma_continued_fraction(a, x)
    }
}

/// The regularized upper incomplete gamma function `Q(a, x) = 1 - P(a, x)`,
/// computed directly in the tail so that small values keep their precision.
pub fn regularized_upper_gamma(a: f64, x: f64) -> f64 {
    if a.is_nan() || a <= 0.0 || x.is_nan() || x < 0.0 {
        return f64::NAN;
    }
    if x == 0.0 {
        return 1.0;
    }
    if x.is_infinite() {
        return 0.0;
    }
    if x < a + 1.0 {
        1.0 - gamma_series(a, x)
    } else {
        gamma_continued_fraction(a, x)
    }
}

/// `exp(-x + a ln x - ln Gamma(a))`, the prefactor shared by both expansions.
fn gamma_prefactor(a: f64, x: f64) -> f64 {
    libm::exp(-x + a * libm::log(x) - libm::lgamma(a))
}

/// `P(a, x)` by the series `e^-x x^a / Gamma(a) * sum_n x^n / (a (a+1) .. (a+n))`
/// (Numerical Recipes eq. 6.2.5); converges fast for `x < a + 1`.
fn gamma_series(a: f64, x: f64) -> f64 {
    let mut ap = a;
    let mut term = 1.0 / a;
    let mut sum = term;
    for _ in 0..1000 {
        ap += 1.0;
        term *= x / ap;
        sum += term;
        if libm::fabs(term) < libm::fabs(sum) * f64::EPSILON {
            break;
        }
    }
    sum * gamma_prefactor(a, x)
}

/// `Q(a, x)` by the continued fraction (Numerical Recipes eq. 6.2.7), evaluated
/// with the modified Lentz method; converges fast for `x >= a + 1`.
fn gamma_continued_fraction(a: f64, x: f64) -> f64 {
    const TINY: f64 = 1e-300;
    let mut b = x + 1.0 - a;
    let mut c = 1.0 / TINY;
    let mut d = 1.0 / b;
    let mut h = d;
    for i in 1..1000 {
        let an = -(i as f64) * (i as f64 - a);
        b += 2.0;
        d = an * d + b;
        if libm::fabs(d) < TINY {
            d = TINY;
        }
        c = b + an / c;
        if libm::fabs(c) < TINY {
            c = TINY;
        }
        d = 1.0 / d;
        let delta = d * c;
        h *= delta;
        if libm::fabs(delta - 1.0) < f64::EPSILON {
            break;
        }
    }
    gamma_prefactor(a, x) * h
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Published table values (NIST/SEMATECH e-Handbook, table 1.3.6.7.4, and
    /// Abramowitz & Stegun table 26.8), quoted to 6 decimals.
    const TABLE: &[(f64, usize, f64)] = &[
        (0.95, 1, 3.841459),
        (0.95, 2, 5.991465),
        (0.95, 3, 7.814728),
        (0.95, 4, 9.487729),
        (0.95, 5, 11.070498),
        (0.95, 6, 12.591587),
        (0.95, 7, 14.067140),
        (0.95, 8, 15.507313),
        (0.95, 9, 16.918978),
        (0.95, 10, 18.307038),
        (0.95, 11, 19.675138),
        (0.95, 12, 21.026070),
        (0.99, 1, 6.634897),
        (0.99, 2, 9.210340),
        (0.99, 3, 11.344867),
        (0.99, 4, 13.276704),
        (0.99, 6, 16.811894),
        (0.99, 12, 26.216967),
        (0.999, 1, 10.827566),
        (0.999, 3, 16.266236),
        (0.999, 12, 32.909490),
        (0.90, 1, 2.705543),
        (0.90, 2, 4.605170),
        (0.90, 12, 18.549348),
        (0.05, 1, 0.003932),
        (0.05, 2, 0.102587),
        (0.05, 12, 5.226029),
        (0.5, 1, 0.454936),
        (0.5, 3, 2.365974),
    ];

    #[test]
    fn quantiles_match_published_tables() {
        for &(p, k, want) in TABLE {
            let got = chi_square_quantile(p, k).unwrap();
            assert!(
                (got - want).abs() < 1.5e-6,
                "chi2({p}, {k}) = {got}, table {want}"
            );
        }
    }

    #[test]
    fn three_sigma_gate_is_nine_for_one_dof() {
        // P(|N(0,1)| <= 3) = 0.99730020393674; the 1-dof quantile is 3^2.
        let got = chi_square_quantile(0.997_300_203_936_74, 1).unwrap();
        assert!((got - 9.0).abs() < 1e-9, "{got}");
        let approx = chi_square_quantile(0.9973, 1).unwrap();
        assert!((approx - 9.0).abs() < 2e-3, "{approx}");
    }

    #[test]
    fn closed_forms_for_one_and_two_dof() {
        // dof 2: P = 1 - exp(-x/2); dof 1: P = erf(sqrt(x/2)).
        for x in [0.01, 0.5, 1.0, 3.0, 10.0, 40.0] {
            let p2 = chi_square_cdf(x, 2);
            assert!(
                (p2 - (1.0 - libm::exp(-0.5 * x))).abs() < 1e-14,
                "dof 2 at {x}"
            );
            let p1 = chi_square_cdf(x, 1);
            assert!(
                (p1 - libm::erf(libm::sqrt(0.5 * x))).abs() < 1e-14,
                "dof 1 at {x}"
            );
        }
    }

    #[test]
    fn quantile_inverts_cdf_including_far_tails() {
        for k in 1..=CACHED_DOF + 3 {
            for p in [1e-6, 0.01, 0.3, 0.5, 0.9, 0.9999, 1.0 - 1e-9] {
                let x = chi_square_quantile(p, k).unwrap();
                let back = if p > 0.5 {
                    1.0 - regularized_upper_gamma(0.5 * k as f64, 0.5 * x)
                } else {
                    chi_square_cdf(x, k)
                };
                let err = if p > 0.5 {
                    ((1.0 - back) - (1.0 - p)).abs() / (1.0 - p)
                } else {
                    (back - p).abs() / p
                };
                assert!(err < 1e-9, "k {k}, p {p}: x {x}, back {back}");
            }
        }
    }

    #[test]
    fn invalid_arguments() {
        for p in [0.0, 1.0, -0.1, 1.5, f64::NAN, f64::INFINITY] {
            assert!(chi_square_quantile(p, 3).is_none());
            assert!(Gate::new(p).is_err());
        }
        assert!(chi_square_quantile(0.9, 0).is_none());
        assert!(regularized_lower_gamma(-1.0, 1.0).is_nan());
        assert!(regularized_lower_gamma(1.0, f64::NAN).is_nan());
    }

    /// The default gate's stored thresholds are the computed ones, bit for bit.
    #[test]
    fn default_thresholds_are_the_computed_quantiles() {
        let g = Gate::default();
        for m in 1..=CACHED_DOF {
            let computed = chi_square_quantile(Gate::DEFAULT_PROBABILITY, m).unwrap();
            assert_eq!(g.threshold(m).to_bits(), computed.to_bits(), "M = {m}");
        }
        assert_eq!(Gate::new(Gate::DEFAULT_PROBABILITY).unwrap(), g);
    }

    #[test]
    fn gate_caches_and_extends_beyond_twelve() {
        let g = Gate::new(0.95).unwrap();
        assert_eq!(g.threshold(0), f64::INFINITY);
        assert!((g.threshold(3) - 7.814728).abs() < 1e-6);
        // 0.95 quantile with 15 dof: 24.995790.
        assert!((g.threshold(15) - 24.995790).abs() < 1e-5);
        assert!(g.accepts(3.0, 1) && !g.accepts(100.0, 1) && !g.accepts(f64::NAN, 1));
        assert_eq!(Gate::default().probability(), Gate::DEFAULT_PROBABILITY);
        assert!(Gate::default().threshold(1).is_finite());
    }
}
