//! Aiding-sensor error models: a constant bias (and optional scale-factor error)
//! drawn once per run, plus white noise drawn per sample, from a seeded ChaCha
//! generator. Used for the DVL, depth meter, compass, USBL and speed log of
//! docs/models/ (sdins25.md Table 1, leveling6.md Table 1, the DVL model of vkf.md).
//!
//! The measurement is `z = (1 + s) x + b + v`, per axis, with `s`, `b` drawn once
//! and `v ~ N(0, sigma)` drawn each call. Noise figures are 1-sigma per sample at
//! the sensor's rate (docs/models/conventions.md, item 8). Units are those of the measured
//! quantity (m, m/s, rad).
//!
//! Seeds: every model takes a seed; [`derive_seed`] turns one run seed into
//! independent, reproducible seeds per sensor.

use nalgebra::SVector;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// `N(0, sigma)` from `rng`. One standard-normal draw is always consumed, even
/// when `sigma == 0`, so the random stream of a run does not depend on which
/// sigmas are zero.
pub fn normal<R: Rng + ?Sized>(rng: &mut R, sigma: f64) -> f64 {
    let z: f64 = StandardNormal.sample(rng);
    sigma * z
}

/// A seed for sub-stream `label` of run `seed` (FNV-1a of the label mixed with
/// the seed by SplitMix64), so each sensor of a run gets its own reproducible
/// generator.
pub fn derive_seed(seed: u64, label: &str) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in label.bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    let mut z = seed ^ h;
    z = z.wrapping_add(0x9e37_79b9_7f4a_7c15);
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// How a run constant (bias or scale factor) is drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Draw {
    /// Always zero.
    #[default]
    Zero,
    /// `N(0, sigma)`.
    Gaussian(f64),
    /// Uniform in `[-half_width, half_width]`.
    Uniform(f64),
    /// A given value (not random).
    Fixed(f64),
}

impl Draw {
    /// One draw. Random variants always consume one draw from `rng`.
    pub fn sample<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match *self {
            Draw::Zero => 0.0,
            Draw::Gaussian(s) => normal(rng, s),
            Draw::Uniform(w) => w * (2.0 * rng.random::<f64>() - 1.0),
            Draw::Fixed(v) => v,
        }
    }
}

/// Error specification of one sensor axis.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ErrorSpec {
    /// Bias, drawn once per run (measurement units).
    pub bias: Draw,
    /// Scale-factor error, drawn once per run (fraction).
    pub scale: Draw,
    /// White noise 1-sigma per sample (measurement units).
    pub noise: f64,
}

impl ErrorSpec {
    /// Gaussian bias `N(0, bias_sigma)` and white noise `noise_sigma`, no scale error.
    pub fn gaussian(bias_sigma: f64, noise_sigma: f64) -> Self {
        Self {
            bias: Draw::Gaussian(bias_sigma),
            scale: Draw::Zero,
            noise: noise_sigma,
        }
    }
    /// With a scale-factor error.
    pub fn with_scale(mut self, scale: Draw) -> Self {
        self.scale = scale;
        self
    }

    /// SDINS-25 Table 1 DVL (RDI Workhorse Navigator): 0.01 m/s bias, 0.1 m/s noise, per body axis.
    pub fn sdins25_dvl() -> Self {
        Self::gaussian(0.01, 0.1)
    }
    /// SDINS-25 Table 1 depth meter: 0.5 m bias, 0.5 m noise.
    pub fn sdins25_depth() -> Self {
        Self::gaussian(0.5, 0.5)
    }
    /// SDINS-25 Table 1 magnetic compass (TCM2): 10 deg bias, 1 deg noise (in rad).
    pub fn sdins25_compass() -> Self {
        Self::gaussian(10f64.to_radians(), 1f64.to_radians())
    }
    /// SDINS-25 Table 1 USBL (ORE Trackpoint II): 18 m bias, 18 m noise, per horizontal axis.
    pub fn sdins25_usbl() -> Self {
        Self::gaussian(18.0, 18.0)
    }
    /// LEVELING-6 Table 1 speed log: 0.1 m/s bias, 0.1 m/s noise.
    pub fn leveling6_speed_log() -> Self {
        Self::gaussian(0.1, 0.1)
    }
    /// VKF DVL: scale error uniform within +-0.2 %, bias uniform within
    /// +-0.5 m/s, white noise `noise` m/s (the paper gives no figure).
    pub fn vkf_dvl(noise: f64) -> Self {
        Self {
            bias: Draw::Uniform(0.5),
            scale: Draw::Uniform(0.002),
            noise,
        }
    }
}

/// A seeded error source for an `N`-axis sensor.
#[derive(Clone, Debug)]
pub struct SensorErrorModel<const N: usize> {
    /// This run's biases (measurement units).
    pub bias: SVector<f64, N>,
    /// This run's scale-factor errors (fractions).
    pub scale: SVector<f64, N>,
    /// White-noise 1-sigma per sample (measurement units).
    pub noise: SVector<f64, N>,
    rng: ChaCha8Rng,
}

impl<const N: usize> SensorErrorModel<N> {
    /// Every axis with the same spec; draws bias then scale per axis in order.
    pub fn new(spec: ErrorSpec, seed: u64) -> Self {
        Self::per_axis([spec; N], seed)
    }

    /// One spec per axis.
    pub fn per_axis(specs: [ErrorSpec; N], seed: u64) -> Self {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let mut bias = SVector::<f64, N>::zeros();
        let mut scale = SVector::<f64, N>::zeros();
        let mut noise = SVector::<f64, N>::zeros();
        for (i, s) in specs.iter().enumerate() {
            bias[i] = s.bias.sample(&mut rng);
            scale[i] = s.scale.sample(&mut rng);
            noise[i] = s.noise;
        }
        Self {
            bias,
            scale,
            noise,
            rng,
        }
    }

    /// One white-noise draw with this model's sigmas.
    pub fn noise_sample(&mut self) -> SVector<f64, N> {
        let sig = self.noise;
        self.noise_sample_with(&sig)
    }

    /// One white-noise draw with given sigmas (e.g. a USBL noise proportional to slant range).
    pub fn noise_sample_with(&mut self, sigma: &SVector<f64, N>) -> SVector<f64, N> {
        SVector::<f64, N>::from_fn(|i, _| normal(&mut self.rng, sigma[i]))
    }

    /// `z = (1 + s) x + b + v`.
    pub fn measure(&mut self, truth: &SVector<f64, N>) -> SVector<f64, N> {
        let v = self.noise_sample();
        truth + truth.component_mul(&self.scale) + self.bias + v
    }

    /// As [`Self::measure`] with per-sample noise sigmas given by the caller.
    pub fn measure_with_noise(
        &mut self,
        truth: &SVector<f64, N>,
        sigma: &SVector<f64, N>,
    ) -> SVector<f64, N> {
        let v = self.noise_sample_with(sigma);
        truth + truth.component_mul(&self.scale) + self.bias + v
    }
}

/// A single-axis sensor (depth meter, compass, speed log).
pub type ScalarSensor = SensorErrorModel<1>;

impl SensorErrorModel<1> {
    /// `z = (1 + s) x + b + v` for a scalar.
    pub fn measure_scalar(&mut self, truth: f64) -> f64 {
        self.measure(&SVector::<f64, 1>::new(truth))[0]
    }
    /// As [`Self::measure_scalar`] for an angle (rad), wrapped to (-pi, pi].
    pub fn measure_angle(&mut self, truth: f64) -> f64 {
        crate::math::wrap_angle(self.measure_scalar(truth))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    #[test]
    fn reproducible_and_distinct_streams() {
        let s = ErrorSpec::sdins25_dvl();
        let mut a = SensorErrorModel::<3>::new(s, 5);
        let mut b = SensorErrorModel::<3>::new(s, 5);
        let x = Vector3::new(1.5, 0.0, 0.0);
        assert_eq!(a.bias, b.bias);
        assert_eq!(a.measure(&x), b.measure(&x));
        assert_ne!(derive_seed(1, "dvl"), derive_seed(1, "depth"));
        assert_ne!(derive_seed(1, "dvl"), derive_seed(2, "dvl"));
        assert_eq!(derive_seed(9, "usbl"), derive_seed(9, "usbl"));
    }

    #[test]
    fn statistics_match_spec() {
        // Bias: one draw per run; noise: per sample.
        let spec = ErrorSpec::sdins25_depth();
        let n = 4000;
        let mut sb = 0.0;
        for seed in 0..n {
            sb += ScalarSensor::new(spec, derive_seed(seed, "depth")).bias[0].powi(2);
        }
        assert!(((sb / n as f64).sqrt() / 0.5 - 1.0).abs() < 0.03);
        let mut m = ScalarSensor::new(spec, 1);
        let b = m.bias[0];
        let (mut s1, mut s2) = (0.0, 0.0);
        for _ in 0..n {
            let z = m.measure_scalar(-20.0) - (-20.0) - b;
            s1 += z;
            s2 += z * z;
        }
        let mean = s1 / n as f64;
        let sd = (s2 / n as f64 - mean * mean).sqrt();
        assert!(
            mean.abs() < 0.03 && (sd / 0.5 - 1.0).abs() < 0.03,
            "{mean} {sd}"
        );
    }

    #[test]
    fn uniform_bias_and_scale_bounds() {
        for seed in 0..200 {
            let m = SensorErrorModel::<3>::new(ErrorSpec::vkf_dvl(0.01), seed);
            assert!(m.bias.amax() <= 0.5 && m.scale.amax() <= 0.002);
        }
        let mut m = SensorErrorModel::<1>::new(
            ErrorSpec {
                bias: Draw::Fixed(0.2),
                scale: Draw::Fixed(0.01),
                noise: 0.0,
            },
            0,
        );
        assert!((m.measure_scalar(10.0) - 10.3).abs() < 1e-12);
        let mut c = ScalarSensor::new(
            ErrorSpec {
                bias: Draw::Fixed(0.5),
                scale: Draw::Zero,
                noise: 0.0,
            },
            0,
        );
        assert!((c.measure_angle(3.0) - (3.5 - 2.0 * core::f64::consts::PI)).abs() < 1e-12);
    }
}
