//! Frozen-value ("stuck sensor") detection.
//!
//! A sensor whose output freezes keeps reporting one value. Its innovation
//! grows as the vehicle moves on, but the innovation gate does not tell a
//! frozen sensor from a filter that has drifted: a gate that accepts the first
//! frozen samples pulls the estimate towards them and may later refuse every
//! correct sample (gate lock-out). The raw values themselves say more: with
//! noise of standard deviation `sigma` and an output resolution (quantization
//! step) `q`, two consecutive independent readings of a constant quantity are
//! *exactly* equal with probability
//!
//! ```text
//! p = erf(q / (2 sigma)) - (2 s / (q sqrt(2 pi))) (1 - exp(-q^2 / (2 s^2))),  s = sigma sqrt(2)
//! ```
//!
//! (the difference of two readings is `N(0, 2 sigma^2)`; the probability that
//! two values fall in one quantization cell, for a uniformly distributed cell
//! phase, is `E[max(0, 1 - |d| / q)]`; `p ~ q / (2 sqrt(pi) sigma)` for small
//! `q`, `p = 0` for `q = 0`). A run of `n` identical values has probability
//! `p^(n-1)`; [`StuckDetector::required_repeats`] picks the shortest run whose
//! probability is below a false-alarm probability, never fewer than
//! [`StuckDetector::MIN_REPEATS`] (a sensor that repeats its last value once
//! when a new one is not ready is not declared stuck).
//!
//! **Rule.** A sample whose raw values equal (bitwise-equal as `f64` values,
//! `==`) those of the previous `repeats - 1` samples of the same sensor is
//! refused, and so is every further identical sample, until the value changes;
//! the first changed sample is taken normally. The samples before the run
//! reached `repeats` have already been used (they are indistinguishable from
//! good ones when they arrive). The detector keeps a fixed-size copy of the
//! last values: no allocation.

/// Number of raw values of one sample compared by a [`StuckDetector`]; longer
/// samples are compared on their first `MAX_RAW_VALUES` values.
pub const MAX_RAW_VALUES: usize = 16;

/// What a [`StuckDetector`] concluded about one sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StuckVerdict {
    /// A value different from the previous sample's (or no values to compare).
    Fresh,
    /// The same value as the previous `run - 1` samples, still within what
    /// noise and quantization explain: use it.
    Repeat {
        /// Length of the run of identical values, this sample included.
        run: u32,
    },
    /// The sensor is stuck: refuse the sample.
    Stuck {
        /// Length of the run of identical values, this sample included.
        run: u32,
    },
}

impl StuckVerdict {
    /// `true` for [`StuckVerdict::Stuck`].
    pub fn is_stuck(self) -> bool {
        matches!(self, Self::Stuck { .. })
    }
}

/// Declares a sensor stuck after `repeats` identical consecutive samples (see
/// the module docs).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StuckDetector {
    repeats: u32,
    last: [f64; MAX_RAW_VALUES],
    len: usize,
    run: u32,
    episodes: u64,
}

impl StuckDetector {
    /// Fewest identical samples that declare a sensor stuck.
    pub const MIN_REPEATS: u32 = 3;
    /// Default probability that a healthy sensor is declared stuck at a given
    /// sample.
    pub const DEFAULT_FALSE_ALARM: f64 = 1e-6;

    /// A detector declaring the sensor stuck at the `repeats`-th identical
    /// consecutive sample (at least [`Self::MIN_REPEATS`]; `u32::MAX`
    /// disables it).
    pub fn new(repeats: u32) -> Self {
        Self {
            repeats: repeats.max(Self::MIN_REPEATS),
            last: [0.0; MAX_RAW_VALUES],
            len: 0,
            run: 0,
            episodes: 0,
        }
    }

    /// A detector for a sensor with noise `noise_sigma` and output resolution
    /// `resolution` (same units), at false-alarm probability `false_alarm`
    /// ([`Self::required_repeats`]).
    pub fn for_sensor(noise_sigma: f64, resolution: f64, false_alarm: f64) -> Self {
        Self::new(Self::required_repeats(noise_sigma, resolution, false_alarm))
    }

    /// Probability that two consecutive readings of a constant quantity with
    /// noise `noise_sigma` and resolution `resolution` are identical (module
    /// docs). `1` when that cannot be bounded (zero, negative or non-finite
    /// noise, non-finite resolution).
    pub fn repeat_probability(noise_sigma: f64, resolution: f64) -> f64 {
        if !(noise_sigma.is_finite() && noise_sigma > 0.0 && resolution.is_finite()) {
            return 1.0;
        }
        let q = resolution.abs();
        if q == 0.0 {
            return 0.0;
        }
        let s = noise_sigma * core::f64::consts::SQRT_2;
        let x = q / s;
        let tail = if x < 1e-4 {
            // 1 - exp(-x^2/2) without cancellation.
            0.5 * x * x - 0.125 * x * x * x * x
        } else {
            1.0 - libm::exp(-0.5 * x * x)
        };
        let p = libm::erf(x / core::f64::consts::SQRT_2)
            - 2.0 / (x * libm::sqrt(2.0 * core::f64::consts::PI)) * tail;
        p.clamp(0.0, 1.0)
    }

    /// Shortest run of identical samples whose probability for a healthy
    /// sensor is at most `false_alarm` (at least [`Self::MIN_REPEATS`];
    /// `u32::MAX` when identical samples are expected anyway).
    pub fn required_repeats(noise_sigma: f64, resolution: f64, false_alarm: f64) -> u32 {
        let p = Self::repeat_probability(noise_sigma, resolution);
        if p <= 0.0 {
            return Self::MIN_REPEATS;
        }
        if p >= 0.999 || !(false_alarm > 0.0 && false_alarm < 1.0) {
            return u32::MAX;
        }
        // p^(n-1) <= false_alarm.
        let n = 1.0 + libm::ceil(libm::log(false_alarm) / libm::log(p));
        if n >= f64::from(u32::MAX) {
            u32::MAX
        } else {
            (n as u32).max(Self::MIN_REPEATS)
        }
    }

    /// The run length that declares the sensor stuck.
    pub fn repeats(&self) -> u32 {
        self.repeats
    }

    /// `true` while the last sample was refused as stuck.
    pub fn is_stuck(&self) -> bool {
        self.run >= self.repeats
    }

    /// Number of times the sensor was declared stuck (runs that reached
    /// `repeats`).
    pub fn episodes(&self) -> u64 {
        self.episodes
    }

    /// Checks one sample's raw values (the first [`MAX_RAW_VALUES`]) against
    /// the previous sample's. Empty `values` are not compared and leave the
    /// detector unchanged. A non-finite value never equals anything.
    pub fn observe(&mut self, values: &[f64]) -> StuckVerdict {
        let values = values.get(..MAX_RAW_VALUES).unwrap_or(values);
        if values.is_empty() {
            return StuckVerdict::Fresh;
        }
        let previous = self.last.get(..self.len).unwrap_or(&[]);
        let same =
            previous.len() == values.len() && previous.iter().zip(values).all(|(a, b)| a == b);
        if !same {
            self.len = values.len();
            if let Some(dst) = self.last.get_mut(..values.len()) {
                dst.copy_from_slice(values);
            }
            self.run = 1;
            return StuckVerdict::Fresh;
        }
        self.run = self.run.saturating_add(1);
        if self.run == self.repeats {
            self.episodes += 1;
        }
        if self.run >= self.repeats {
            StuckVerdict::Stuck { run: self.run }
        } else {
            StuckVerdict::Repeat { run: self.run }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_run_of_identical_values_is_refused_until_the_value_changes() {
        let mut d = StuckDetector::new(3);
        assert_eq!(d.observe(&[1.0, 2.0]), StuckVerdict::Fresh);
        assert_eq!(d.observe(&[1.0, 2.0]), StuckVerdict::Repeat { run: 2 });
        assert_eq!(d.observe(&[1.0, 2.0]), StuckVerdict::Stuck { run: 3 });
        assert!(d.is_stuck());
        assert_eq!(d.observe(&[1.0, 2.0]), StuckVerdict::Stuck { run: 4 });
        // One changed component is a new value.
        assert_eq!(d.observe(&[1.0, 2.5]), StuckVerdict::Fresh);
        assert!(!d.is_stuck());
        assert_eq!(d.observe(&[1.0, 2.5]), StuckVerdict::Repeat { run: 2 });
        assert_eq!(d.episodes(), 1);
        assert_eq!(d.observe(&[1.0, 2.5]), StuckVerdict::Stuck { run: 3 });
        assert_eq!(d.episodes(), 2);
    }

    #[test]
    fn empty_and_non_finite_values_are_never_stuck() {
        let mut d = StuckDetector::new(3);
        for _ in 0..10 {
            assert_eq!(d.observe(&[]), StuckVerdict::Fresh);
            assert_eq!(d.observe(&[f64::NAN]), StuckVerdict::Fresh);
        }
        assert_eq!(d.episodes(), 0);
        // A different length is a different value.
        d.observe(&[1.0]);
        assert_eq!(d.observe(&[1.0, 1.0]), StuckVerdict::Fresh);
    }

    #[test]
    fn fewer_than_min_repeats_is_not_allowed() {
        assert_eq!(StuckDetector::new(0).repeats(), StuckDetector::MIN_REPEATS);
        let mut d = StuckDetector::new(1);
        d.observe(&[3.0]);
        assert!(!d.observe(&[3.0]).is_stuck());
    }

    #[test]
    fn long_samples_are_compared_on_their_first_values() {
        let mut d = StuckDetector::new(3);
        let mut a = [0.0; MAX_RAW_VALUES + 2];
        d.observe(&a);
        a[MAX_RAW_VALUES] = 9.0;
        d.observe(&a);
        assert!(d.observe(&a).is_stuck());
    }

    /// The closed form against a direct simulation of quantized noise.
    #[test]
    fn repeat_probability_matches_quantized_noise() {
        // splitmix64 + Box-Muller, reproducible.
        let mut state = 7u64;
        let mut uniform = || {
            state = state.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
        };
        let sigma = 0.2;
        for q in [0.02, 0.1, 0.2, 0.5] {
            let n = 200_000;
            let mut equal = 0;
            for _ in 0..n {
                let phase = uniform() * q;
                let mut gauss = || {
                    let (u1, u2) = (uniform().max(1e-300), uniform());
                    (-2.0 * u1.ln()).sqrt() * (core::f64::consts::TAU * u2).cos()
                };
                let (a, b) = (sigma * gauss() + phase, sigma * gauss() + phase);
                if (a / q).floor() == (b / q).floor() {
                    equal += 1;
                }
            }
            let measured = f64::from(equal) / f64::from(n);
            let p = StuckDetector::repeat_probability(sigma, q);
            let se = (p * (1.0 - p) / f64::from(n)).sqrt();
            assert!(
                (measured - p).abs() < 5.0 * se,
                "q {q}: measured {measured}, formula {p}"
            );
        }
    }

    #[test]
    fn required_repeats_grows_with_the_resolution() {
        let sigma = 0.1;
        assert_eq!(
            StuckDetector::required_repeats(sigma, 0.0, 1e-6),
            StuckDetector::MIN_REPEATS
        );
        let fine = StuckDetector::required_repeats(sigma, 1e-3, 1e-6);
        let coarse = StuckDetector::required_repeats(sigma, 0.1, 1e-6);
        assert!(
            fine >= StuckDetector::MIN_REPEATS && coarse > fine,
            "{fine} {coarse}"
        );
        // The chosen run is rare enough, one fewer is not.
        let p = StuckDetector::repeat_probability(sigma, 0.1);
        assert!(p.powi(coarse as i32 - 1) <= 1e-6);
        assert!(p.powi(coarse as i32 - 2) > 1e-6);
        // Resolution far coarser than the noise: repeats are normal.
        assert_eq!(
            StuckDetector::required_repeats(sigma, 1000.0, 1e-6),
            u32::MAX
        );
        assert_eq!(StuckDetector::required_repeats(0.0, 0.1, 1e-6), u32::MAX);
    }
}
