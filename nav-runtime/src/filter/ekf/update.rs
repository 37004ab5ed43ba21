//! Measurement updates (eqs. U1-U6), batch and sequential, and the
//! [`Estimator`] interface.

use nalgebra::{Cholesky, SMatrix, SVector};

use super::covariance::mirror_upper;
use super::gating::passes;
use super::joseph::joseph_in_place;
use super::validation::{all_finite, check_measurement, checked_noise};
use super::{Ekf, FilterError, UpdateReport};
use crate::model::{Model, Sensor};
use crate::real::Real;

/// A filter that can fuse measurements of the sensors of its model.
pub trait Estimator<const N: usize> {
    /// The process model.
    type Model: Model<N>;
    /// Batch update, as [`Ekf::update`].
    ///
    /// # Errors
    /// As [`Ekf::update`]; the filter is unchanged on error.
    fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Self::Model>;
    /// Sequential scalar update for diagonal `R`, as [`Ekf::update_sequential`].
    ///
    /// # Errors
    /// As [`Ekf::update_sequential`]; the filter is unchanged on error.
    fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Self::Model>;
}

impl<Mo: Model<N, T>, const N: usize, T: Real> Ekf<Mo, N, T> {
    /// Fuses measurement `z` of sensor `S` with noise covariance `r`.
    ///
    /// Computes the innovation (eq. U1, angle components wrapped per
    /// `S::ANGLES`), `(h, U = P H^T, H P H^T)` from the generated sparse
    /// [`Sensor::innovation_terms`], `S = H P H^T + R` and its Cholesky factor
    /// (never an explicit inverse), the NIS (eq. U3) and gates it against the
    /// chi-square threshold of the sensor's gate. If accepted, `K = U S^-1` by
    /// two triangular solves, `x += K nu` and the Joseph update (eq. U6) on the
    /// upper triangle, mirrored; then any covariance diagonal that is not
    /// positive and finite is repaired (see [`FilterCounters::covariance_repairs`](crate::ekf::FilterCounters::covariance_repairs)):
    /// reset to its value before the update (a valid upper bound, since an
    /// update can only reduce variance) or to the variance floor, with its row
    /// and column decorrelated so `P` stays positive semidefinite.
    ///
    /// A gated measurement is not an error: the report says `accepted: false`
    /// and the state is unchanged.
    ///
    /// # Errors
    /// Non-finite `z` or aux, invalid `r` (non-finite, asymmetric beyond 1e-9
    /// relative, negative variance), `S` not positive definite, or non-finite
    /// model output. The filter state is unchanged in every case.
    pub fn update<S, const M: usize>(
        &mut self,
        z: &SVector<T, M>,
        r: &SMatrix<T, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M, T>, FilterError>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        let result = self.batch_update::<S, M>(z, r, aux);
        self.stored::<S, M>(result, aux)
    }

    /// Fuses measurement `z` of sensor `S` as `M` scalar updates, one per row of
    /// `H` (from the dense [`Sensor::jacobian`] at the prior state, with
    /// `P H^T` from the generated sparse [`Sensor::innovation_terms`]), with no
    /// matrix inverse or factorization: each step divides by the scalar
    /// `s_i = h_i P h_i^T + r_i` (the scalar fusion of PX4's EKF2), and the
    /// steps are stored as one Joseph pass over `P`.
    ///
    /// **Valid only for diagonal `R`**, which is why the noise is given as its
    /// diagonal `r_diag`: with correlated noise the scalar updates would ignore
    /// the correlation. Each scalar innovation is corrected for the state change
    /// of the earlier rows, `e_i = nu_i - h_i (x_i - x_0)`, with `h` and `H`
    /// evaluated once at the prior as in the batch update, so the result equals
    /// [`Ekf::update`] to rounding (tested to 1e-12, linear and nonlinear `h`), and
    /// `sum_i e_i^2 / s_i` equals the batch NIS (the scalar innovations are the
    /// decorrelated batch innovation), which is what the gate tests. The
    /// gate decision is made on the whole vector before anything is stored.
    ///
    /// # Errors
    /// As [`Ekf::update`]; a non-positive `s_i` gives
    /// [`FilterError::InnovationCovarianceNotPositiveDefinite`].
    pub fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<T, M>,
        r_diag: &SVector<T, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M, T>, FilterError>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        let result = self.sequential_update::<S, M>(z, r_diag, aux);
        self.stored::<S, M>(result, aux)
    }

    /// The totals of an update's outcome, the state normalized after an
    /// accepted one, and the gate's decision handed to the lock-out.
    fn stored<S, const M: usize>(
        &mut self,
        result: Result<UpdateReport<M, T>, FilterError>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M, T>, FilterError>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        match result {
            Ok(report) => {
                self.count_gate_outcome(&report);
                if report.accepted {
                    // An accepted update's Joseph pass checked (or repaired) `P`.
                    self.clean = true;
                    Mo::normalize_state(&mut self.x);
                    self.counters.covariance_repairs += u64::from(report.repairs);
                }
                self.after_gate::<S, M>(&report, aux);
                Ok(report)
            }
            Err(e) => {
                self.counters.updates_rejected += 1;
                Err(e)
            }
        }
    }

    /// Eqs. U1-U6 with the generated sparse innovation terms.
    ///
    /// Stores the posterior in place if the update is accepted and succeeds;
    /// on error `x` and `P` are unchanged.
    pub(super) fn batch_update<S, const M: usize>(
        &mut self,
        z: &SVector<T, M>,
        r: &SMatrix<T, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M, T>, FilterError>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        check_measurement::<S, T, N, M>(z, aux)?;
        let r = checked_noise(r)?;
        let (h, u, hph) = S::innovation_terms(&self.p, &self.x, &self.input, &self.params, aux);
        if !(all_finite(h.as_slice()) && all_finite(u.as_slice()) && all_finite(hph.as_slice())) {
            return Err(FilterError::NonFiniteResult {
                stage: "measurement model",
            });
        }
        let nu = innovation::<S, T, N, M>(z, &h);
        let mut s = hph + r;
        mirror_upper(&mut s);
        let not_pd = FilterError::InnovationCovarianceNotPositiveDefinite { sensor: S::NAME };
        // S^-1 once (M x M, from the Cholesky factor): the NIS and the gain
        // are then products, cheaper than M + N triangular solve pairs.
        let s_inverse = Cholesky::new(s).ok_or(not_pd)?.inverse();
        let nis = nu.dot(&(s_inverse * nu)).to_f64();
        if !nis.is_finite() {
            return Err(not_pd);
        }
        let threshold = self.sensor_gate::<S, M>().map(|g| g.threshold(M));
        let mut report = UpdateReport {
            sensor: S::NAME,
            accepted: passes(nis, threshold),
            nis,
            threshold,
            innovation: nu,
            innovation_covariance: s,
            noise: r,
            repairs: 0,
            recovered: None,
        };
        if !report.accepted {
            return Ok(report);
        }
        // K = U S^-1, eq. U4.
        let k = u * s_inverse;
        let x_new = self.x + k * nu;
        if !all_finite(x_new.as_slice()) {
            return Err(FilterError::NonFiniteResult { stage: "update" });
        }
        report.repairs = joseph_in_place(&mut self.p, &k, &u, &s, T::of(self.variance_floor))?;
        self.x = x_new;
        Ok(report)
    }

    /// Scalar sequential fusion for diagonal `R` (see [`Ekf::update_sequential`]).
    ///
    /// The scalar steps are formed without touching `P`: with `k_j = u_j /
    /// s_j`, step `j` takes `P` to `P - u_j k_j^T`, so the vector of step
    /// `i` is `u_i = P_{i-1} h_i = U[:, i] - sum_{j<i} u_j (k_j . h_i)`
    /// from the generated sparse `U = P H^T` (O(N M^2) instead of a dense
    /// `P h_i` per step). Once the gate has accepted the whole vector, the
    /// `M` steps are stored as one Joseph pass, `P - K U'^T - U' K^T + K D
    /// K^T` with `K = [k_i]`, `U' = [u_i]` and `D = diag(s_i)` (each step's
    /// `-k u^T - u k^T + s k k^T` is its scalar Joseph form), in place with
    /// the checks and repairs of [`Ekf::update`].
    pub(super) fn sequential_update<S, const M: usize>(
        &mut self,
        z: &SVector<T, M>,
        r_diag: &SVector<T, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M, T>, FilterError>
    where
        S: Sensor<N, M, T, Model = Mo>,
    {
        check_measurement::<S, T, N, M>(z, aux)?;
        if !all_finite(r_diag.as_slice()) {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "not finite",
            });
        }
        if r_diag.iter().any(|v| *v < T::zero()) {
            return Err(FilterError::InvalidMeasurementNoise {
                reason: "negative variance",
            });
        }
        let (h, u_prior, hph) =
            S::innovation_terms(&self.p, &self.x, &self.input, &self.params, aux);
        let hm = S::jacobian(&self.x, &self.input, &self.params, aux);
        if !(all_finite(h.as_slice())
            && all_finite(hm.as_slice())
            && all_finite(u_prior.as_slice())
            && all_finite(hph.as_slice()))
        {
            return Err(FilterError::NonFiniteResult {
                stage: "measurement model",
            });
        }
        let nu = innovation::<S, T, N, M>(z, &h);
        let not_pd = FilterError::InnovationCovarianceNotPositiveDefinite { sensor: S::NAME };

        // The batch S = H P H^T + R, for the report only.
        let mut s_full = hph;
        for i in 0..M {
            s_full[(i, i)] += r_diag[i];
        }
        mirror_upper(&mut s_full);

        let mut u = u_prior;
        let mut k = SMatrix::<T, N, M>::zeros();
        let mut s = SMatrix::<T, M, M>::zeros();
        let mut dx = SVector::<T, N>::zeros();
        let mut nis = T::zero();
        for i in 0..M {
            let hi = hm.row(i).transpose();
            for j in 0..i {
                let c = k.column(j).dot(&hi);
                let uj = u.column(j).into_owned();
                u.column_mut(i).axpy(-c, &uj, T::one());
            }
            let ui = u.column(i).into_owned();
            let si = hi.dot(&ui) + r_diag[i];
            if !(si.is_finite() && si > T::zero()) {
                return Err(not_pd);
            }
            let mut ei = nu[i] - hi.dot(&dx);
            if S::ANGLES[i] {
                ei = ei.wrap_angle();
            }
            nis += ei * ei / si;
            let ki = ui / si;
            dx += ki * ei;
            k.set_column(i, &ki);
            s[(i, i)] = si;
        }
        let nis = nis.to_f64();
        if !nis.is_finite() {
            return Err(not_pd);
        }
        let threshold = self.sensor_gate::<S, M>().map(|g| g.threshold(M));
        let mut report = UpdateReport {
            sensor: S::NAME,
            accepted: passes(nis, threshold),
            nis,
            threshold,
            innovation: nu,
            innovation_covariance: s_full,
            noise: SMatrix::from_diagonal(r_diag),
            repairs: 0,
            recovered: None,
        };
        if !report.accepted {
            return Ok(report);
        }
        let x_new = self.x + dx;
        if !all_finite(x_new.as_slice()) {
            return Err(FilterError::NonFiniteResult { stage: "update" });
        }
        report.repairs = joseph_in_place(&mut self.p, &k, &u, &s, T::of(self.variance_floor))?;
        self.x = x_new;
        Ok(report)
    }
}

impl<Mo: Model<N>, const N: usize> Estimator<N> for Ekf<Mo, N> {
    type Model = Mo;

    fn update<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r: &SMatrix<f64, M, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        Ekf::update::<S, M>(self, z, r, aux)
    }

    fn update_sequential<S, const M: usize>(
        &mut self,
        z: &SVector<f64, M>,
        r_diag: &SVector<f64, M>,
        aux: &S::Aux,
    ) -> Result<UpdateReport<M>, FilterError>
    where
        S: Sensor<N, M, Model = Mo>,
    {
        Ekf::update_sequential::<S, M>(self, z, r_diag, aux)
    }
}

/// `nu = z - h`, angle components wrapped to (-pi, pi] (eq. U1).
pub(super) fn innovation<S, T: Real, const N: usize, const M: usize>(
    z: &SVector<T, M>,
    h: &SVector<T, M>,
) -> SVector<T, M>
where
    S: Sensor<N, M, T>,
{
    let mut nu = z - h;
    for (v, angle) in nu.iter_mut().zip(S::ANGLES.iter()) {
        if *angle {
            *v = v.wrap_angle();
        }
    }
    nu
}
