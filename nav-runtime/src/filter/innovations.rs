//! What the innovations of a sensor say about its noise: per update
//! ([`InnovationStatistics`], from an [`UpdateReport`]) and summed over a run
//! ([`InnovationTotals`]).
//!
//! The innovation `nu ~ N(0, S)`, `S = H P H^T + R`, of a consistent filter
//! gives the log-likelihood of the run (docs/tuning.md, eq. T1)
//!
//! ```text
//! ln L = -1/2 sum_k ( ln det S_k + nu_k^T S_k^-1 nu_k + M ln 2 pi )
//! ```
//!
//! For a common scale of one sensor's noise, `R_k = c R0_k`, its derivative
//! by `c` is zero where (eq. T2)
//!
//! ```text
//! sum_k tr(S_k^-1 R_k) = sum_k nu_k^T S_k^-1 R_k S_k^-1 nu_k
//! ```
//!
//! With the filter's own share `H P H^T` held, the scale that makes the
//! innovations' spread match the covariance the filter predicts
//! (covariance matching, in the sums above: `n` the mean NIS and `w` the
//! mean noise share `tr(S^-1 R) / M` per degree of freedom) is (eq. T3)
//!
//! ```text
//! c <- c * (n - 1 + w) / w
//! ```
//!
//! It is the solution of eq. T2 when the noise dominates `S` (`w = 1`: the
//! mean NIS), exact for any share when `H P H^T` is the same at every
//! update, and 1 in expectation for a consistent filter. The Fisher
//! information of `ln sigma` (`sigma` = `sqrt(c)` times the given sigma) is
//! `2 sum_k tr((S_k^-1 R_k)^2)` (eq. T4): its inverse square root is the
//! standard error of the sigma the run supports, small when `R` dominates
//! `S` over many updates and large (the log does not tell) when `H P H^T`
//! hides the noise.
//!
//! [`UpdateReport`]: crate::ekf::UpdateReport

use nalgebra::{Cholesky, SMatrix, SVector};

use crate::real::Real;

/// One update's innovation, weighed against its covariance and its noise.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InnovationStatistics {
    /// Measurement dimension `M` (0: no statistics, `S` not positive
    /// definite or not finite).
    pub dof: usize,
    /// `nu^T S^-1 nu`.
    pub nis: f64,
    /// `ln det S`.
    pub log_det_s: f64,
    /// `tr(S^-1 R)`: how much of `S` is the sensor's noise (`M` when all of
    /// it, 0 when none).
    pub noise_share: f64,
    /// `nu^T S^-1 R S^-1 nu`: the innovation seen through the noise (eq. T2).
    pub noise_nis: f64,
    /// `tr((S^-1 R)^2)`: the information the update carries on the noise
    /// scale (eq. T4).
    pub noise_information: f64,
}

impl InnovationStatistics {
    /// The statistics of innovation `nu` with covariance `s` and noise `r`.
    pub fn of<const M: usize, T: Real>(
        nu: &SVector<T, M>,
        s: &SMatrix<T, M, M>,
        r: &SMatrix<T, M, M>,
    ) -> Self {
        let to64 = |m: &SMatrix<T, M, M>| m.map(|v| v.to_f64());
        let (nu, s, r) = (nu.map(|v| v.to_f64()), to64(s), to64(r));
        let Some(chol) = Cholesky::new(s) else {
            return Self::default();
        };
        let log_det_s = 2.0
            * chol
                .l_dirty()
                .diagonal()
                .iter()
                .map(|d| libm::log(*d))
                .sum::<f64>();
        let s_inv_nu = chol.solve(&nu);
        let w = chol.solve(&r);
        let stats = Self {
            dof: M,
            nis: nu.dot(&s_inv_nu),
            log_det_s,
            noise_share: w.trace(),
            noise_nis: s_inv_nu.dot(&(r * s_inv_nu)),
            noise_information: (w * w).trace(),
        };
        let finite = [
            stats.nis,
            stats.log_det_s,
            stats.noise_share,
            stats.noise_nis,
            stats.noise_information,
        ]
        .iter()
        .all(|v| v.is_finite());
        if finite {
            stats
        } else {
            Self::default()
        }
    }
}

/// The innovation statistics of one sensor summed over a run.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct InnovationTotals {
    /// Updates counted (applied or refused by the gate).
    pub updates: u64,
    /// Sum of their dimensions.
    pub dof: u64,
    /// Sums of the fields of [`InnovationStatistics`].
    pub nis: f64,
    /// Sum of `ln det S`.
    pub log_det_s: f64,
    /// Sum of `tr(S^-1 R)`.
    pub noise_share: f64,
    /// Sum of `nu^T S^-1 R S^-1 nu`.
    pub noise_nis: f64,
    /// Sum of `tr((S^-1 R)^2)`.
    pub noise_information: f64,
}

/// Largest change of a noise variance that one application of eq. T3
/// proposes (a factor of 10 on the sigma).
pub const MAX_VARIANCE_STEP: f64 = 100.0;

/// `ln(2 pi)`.
const LN_2PI: f64 = 1.837_877_066_409_345_5;

impl InnovationTotals {
    /// Adds one update (one without statistics is not counted).
    pub fn add(&mut self, s: &InnovationStatistics) {
        if s.dof == 0 {
            return;
        }
        self.updates += 1;
        self.dof += s.dof as u64;
        self.nis += s.nis;
        self.log_det_s += s.log_det_s;
        self.noise_share += s.noise_share;
        self.noise_nis += s.noise_nis;
        self.noise_information += s.noise_information;
    }

    /// Adds the totals of another run or sensor.
    pub fn merge(&mut self, o: &InnovationTotals) {
        self.updates += o.updates;
        self.dof += o.dof;
        self.nis += o.nis;
        self.log_det_s += o.log_det_s;
        self.noise_share += o.noise_share;
        self.noise_nis += o.noise_nis;
        self.noise_information += o.noise_information;
    }

    /// Mean NIS per degree of freedom (1 for a consistent filter), `None`
    /// without updates.
    pub fn nis_per_dof(&self) -> Option<f64> {
        (self.dof > 0).then(|| self.nis / self.dof as f64)
    }

    /// The innovation log-likelihood of the run (eq. T1).
    pub fn log_likelihood(&self) -> f64 {
        -0.5 * (self.log_det_s + self.nis + self.dof as f64 * LN_2PI)
    }

    /// The innovation log-likelihood (eq. T1) with every `S` scaled by the
    /// factor that maximises it (`NIS / dof`): a measure of how well the
    /// readings fit that does not depend on how well the sigmas are set
    /// (tuning compares clock offsets by it before the sigmas are tuned).
    /// Minus infinity without updates.
    pub fn profile_log_likelihood(&self) -> f64 {
        if self.dof == 0 || self.nis.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater) {
            return f64::NEG_INFINITY;
        }
        let dof = self.dof as f64;
        -0.5 * (self.log_det_s + dof * libm::log(self.nis / dof) + dof + dof * LN_2PI)
    }

    /// The factor on the sensor's noise sigma that the innovations support
    /// (the square root of eq. T3, its variance factor held within
    /// [`MAX_VARIANCE_STEP`] either way); `None` when the noise is no
    /// measurable part of the innovations.
    pub fn sigma_factor(&self) -> Option<f64> {
        // A NaN share fails `> 0` too.
        if self.dof == 0 || self.noise_share.partial_cmp(&0.0) != Some(core::cmp::Ordering::Greater)
        {
            return None;
        }
        let n = self.nis / self.dof as f64;
        let w = self.noise_share / self.dof as f64;
        let f = ((n - 1.0 + w) / w).clamp(1.0 / MAX_VARIANCE_STEP, MAX_VARIANCE_STEP);
        f.is_finite().then(|| libm::sqrt(f))
    }

    /// The standard error of `ln sigma` from the Fisher information of
    /// eq. T4 (infinite without information): a relative standard error of
    /// the supported sigma.
    pub fn log_sigma_standard_error(&self) -> f64 {
        if self.noise_information > 0.0 {
            libm::sqrt(2.0 * self.noise_information).recip()
        } else {
            f64::INFINITY
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn statistics_of_a_two_component_innovation_match_their_definitions() {
        let nu = Vector2::new(0.3, -0.2);
        let hph = Matrix2::new(0.05, 0.01, 0.01, 0.02);
        let r = Matrix2::new(0.04, 0.0, 0.0, 0.09);
        let s = hph + r;
        let st = InnovationStatistics::of(&nu, &s, &r);
        let s_inv = s.try_inverse().unwrap();
        let w = s_inv * r;
        assert_eq!(st.dof, 2);
        approx::assert_relative_eq!(st.nis, (nu.transpose() * s_inv * nu)[0], epsilon = 1e-12);
        approx::assert_relative_eq!(st.log_det_s, s.determinant().ln(), epsilon = 1e-12);
        approx::assert_relative_eq!(st.noise_share, w.trace(), epsilon = 1e-12);
        approx::assert_relative_eq!(
            st.noise_nis,
            (nu.transpose() * s_inv * r * s_inv * nu)[0],
            epsilon = 1e-12
        );
        approx::assert_relative_eq!(st.noise_information, (w * w).trace(), epsilon = 1e-12);
    }

    /// The profile likelihood is the likelihood at the best scale of `S`,
    /// and the same whatever scale `S` was given with.
    #[test]
    fn the_profile_likelihood_is_the_best_over_a_scale_of_s() {
        let nu = [Vector2::new(0.3, -0.2), Vector2::new(-0.1, 0.4)];
        let s = Matrix2::new(0.05, 0.01, 0.01, 0.02);
        let totals = |scale: f64| {
            let mut t = InnovationTotals::default();
            for n in &nu {
                t.add(&InnovationStatistics::of(n, &(s * scale), &(s * scale)));
            }
            t
        };
        let best = totals(1.0).profile_log_likelihood();
        for scale in [0.1, 0.5, 2.0, 30.0] {
            approx::assert_relative_eq!(
                totals(scale).profile_log_likelihood(),
                best,
                epsilon = 1e-9
            );
            assert!(totals(scale).log_likelihood() <= best + 1e-12);
        }
        let k = totals(1.0).nis / 4.0;
        approx::assert_relative_eq!(totals(k).log_likelihood(), best, epsilon = 1e-9);
        assert_eq!(
            InnovationTotals::default().profile_log_likelihood(),
            f64::NEG_INFINITY
        );
    }

    #[test]
    fn a_covariance_that_is_not_positive_definite_gives_no_statistics() {
        let nu = Vector2::new(1.0, 1.0);
        for s in [
            Matrix2::new(1.0, 2.0, 2.0, 1.0),
            Matrix2::from_element(f64::NAN),
        ] {
            let st = InnovationStatistics::of(&nu, &s, &Matrix2::identity());
            assert_eq!(st, InnovationStatistics::default());
            let mut t = InnovationTotals::default();
            t.add(&st);
            assert_eq!(t.updates, 0);
        }
    }

    /// Innovations drawn from `N(0, H P H^T + c_true R)` with a filter that
    /// assumes `R`: the supported factor is `sqrt(c_true)` whatever the
    /// filter's own share, and known to a few per cent over 20 000 updates.
    #[cfg(feature = "simulation")]
    #[test]
    fn the_supported_sigma_factor_recovers_a_wrong_noise_scale() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        for (sigma_ratio, hph) in [(10.0, 0.0), (0.1, 0.0), (1.0, 0.5), (3.0, 0.01)] {
            let r = 1.0f64;
            let mut t = InnovationTotals::default();
            for _ in 0..20_000 {
                let n: f64 = rng.sample(rand_distr::StandardNormal);
                let true_var = hph + sigma_ratio * sigma_ratio * r;
                let nu = SVector::<f64, 1>::new(n * true_var.sqrt());
                let s = SMatrix::<f64, 1, 1>::new(hph + r);
                t.add(&InnovationStatistics::of(
                    &nu,
                    &s,
                    &SMatrix::<f64, 1, 1>::new(r),
                ));
            }
            let f = t.sigma_factor().unwrap();
            approx::assert_relative_eq!(f, sigma_ratio, max_relative = 0.03);
            assert!(t.log_sigma_standard_error() < 0.02);
        }
    }

    #[test]
    fn the_log_likelihood_is_the_gaussian_density_of_the_innovations() {
        let mut t = InnovationTotals::default();
        let mut expected = 0.0;
        for (nu, s) in [(0.5, 2.0), (-1.0, 0.5), (0.1, 1.0)] {
            t.add(&InnovationStatistics::of(
                &SVector::<f64, 1>::new(nu),
                &SMatrix::<f64, 1, 1>::new(s),
                &SMatrix::<f64, 1, 1>::new(s / 2.0),
            ));
            expected += -0.5 * (nu * nu / s + s.ln() + LN_2PI);
        }
        approx::assert_relative_eq!(t.log_likelihood(), expected, epsilon = 1e-12);
        approx::assert_relative_eq!(t.nis_per_dof().unwrap(), (0.125 + 2.0 + 0.01) / 3.0);
        assert_eq!(InnovationTotals::default().sigma_factor(), None);
        assert!(InnovationTotals::default()
            .log_sigma_standard_error()
            .is_infinite());
    }
}
