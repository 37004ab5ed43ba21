//! Discretization of continuous models: `Phi` and `Qd` over a step.

use nalgebra::SMatrix;

use super::covariance::mirror_upper;
use crate::real::Real;

/// How a continuous model's transition matrix `Phi` and process noise `Qd` are
/// obtained over a step `dt`. Discrete models (`Model::DISCRETE`) always use the
/// model's own `Phi` and `Qd` and ignore this setting.
///
/// With `F` the continuous Jacobian and `Qc = G Q G^T` the continuous noise
/// covariance, the exact discretization is `Phi = exp(F dt)`,
/// `Qd = int_0^dt exp(F s) Qc exp(F s)^T ds` (Brown & Hwang, eqs. 3.9.20, 3.9.21).
/// The choice trades cost against the size of `||F dt||`:
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Discretization {
    /// `Phi = I + F dt`, `Qd = Qc dt`, through the generated sparse
    /// [`Model::propagate_covariance`](crate::model::Model::propagate_covariance) (structural zeros cost nothing). The
    /// truncation error is O((||F|| dt)^2) per step; right when `||F dt|| << 1`,
    /// e.g. an INS error model at 100 Hz (the Schuler frequency 1.24e-3 rad/s and
    /// Earth rate give `||F dt||` around 1e-5). The state uses the model's Euler
    /// transition. The default.
    #[default]
    FirstOrder,
    /// Dense `Phi = I + F dt + (F dt)^2 / 2` with the trapezoidal
    /// `Qd = (Phi Qc Phi^T + Qc) dt / 2`, and the state by Heun's method
    /// (second-order Runge-Kutta built from two model transitions). Error
    /// O((||F|| dt)^3) per step; for steps of about a second or where `F` has
    /// fast modes, at O(N^3) cost per step.
    SecondOrder,
    /// Exact (to rounding) `Phi` and `Qd` by Van Loan's method (C. F. Van Loan,
    /// "Computing integrals involving the matrix exponential", IEEE TAC 23(3),
    /// 1978): `exp([[-F, Qc], [0, F^T]] dt) = [[., E12], [0, E22]]`,
    /// `Phi = E22^T`, `Qd = Phi E12`. The exponential is a degree-16 Taylor
    /// series with scaling and squaring, evaluated on the three N x N blocks of
    /// the block-triangular 2N x 2N matrix, so it needs no `2N` const generic and
    /// allocates nothing. The state is integrated with classical Runge-Kutta 4.
    /// For long steps (1 s and more) or stiff dynamics; about 20 dense N x N
    /// products per block per step, so 10-100 times the cost of `SecondOrder`.
    VanLoan,
}

/// Dense second-order discretization: `Phi = I + F dt + (F dt)^2 / 2` and the
/// trapezoidal `Qd = (Phi Qc Phi^T + Qc) dt / 2` (Brown & Hwang, sec. 7.2), with
/// `Qc = G Q G^T` the continuous noise covariance. Returns `(Phi, Qd)`.
pub fn second_order<T: Real, const N: usize>(
    f: &SMatrix<T, N, N>,
    qc: &SMatrix<T, N, N>,
    dt: T,
) -> (SMatrix<T, N, N>, SMatrix<T, N, N>) {
    let half = T::of(0.5);
    let fdt = f * dt;
    let phi = SMatrix::<T, N, N>::identity() + fdt + fdt * fdt * half;
    let mut qd = (phi * qc * phi.transpose() + qc) * (half * dt);
    mirror_upper(&mut qd);
    (phi, qd)
}

/// Van Loan's exact discretization (IEEE TAC 23(3), 1978): with
/// `A = [[-F, Qc], [0, F^T]] dt` and `exp(A) = [[E11, E12], [0, E22]]`,
/// `Phi = E22^T = exp(F dt)` and `Qd = Phi E12 = int_0^dt exp(F s) Qc exp(F s)^T ds`.
/// Returns `(Phi, Qd)`; `Qd` is symmetrized from its upper triangle.
///
/// The 2N x 2N exponential is computed on its three N x N blocks (block upper
/// triangular matrices are closed under products), by scaling `A` by `2^-s`
/// until its infinity norm is at most 1/2, a degree-16 Taylor polynomial
/// (truncation below 1e-19 relative) and `s` squarings. No allocation.
pub fn van_loan<T: Real, const N: usize>(
    f: &SMatrix<T, N, N>,
    qc: &SMatrix<T, N, N>,
    dt: T,
) -> (SMatrix<T, N, N>, SMatrix<T, N, N>) {
    let a = BlockUpper {
        a: -(f * dt),
        b: qc * dt,
        c: f.transpose() * dt,
    };
    let e = a.exp();
    let phi = e.c.transpose();
    let mut qd = phi * e.b;
    mirror_upper(&mut qd);
    (phi, qd)
}

/// A 2N x 2N block upper-triangular matrix `[[a, b], [0, c]]`.
#[derive(Clone, Copy)]
struct BlockUpper<T: Real, const N: usize> {
    a: SMatrix<T, N, N>,
    b: SMatrix<T, N, N>,
    c: SMatrix<T, N, N>,
}

impl<T: Real, const N: usize> BlockUpper<T, N> {
    fn identity() -> Self {
        Self {
            a: SMatrix::identity(),
            b: SMatrix::zeros(),
            c: SMatrix::identity(),
        }
    }

    /// `[[a1, b1], [0, c1]] [[a2, b2], [0, c2]] = [[a1 a2, a1 b2 + b1 c2], [0, c1 c2]]`.
    fn mul(&self, o: &Self) -> Self {
        Self {
            a: self.a * o.a,
            b: self.a * o.b + self.b * o.c,
            c: self.c * o.c,
        }
    }

    fn scale(&self, k: T) -> Self {
        Self {
            a: self.a * k,
            b: self.b * k,
            c: self.c * k,
        }
    }

    /// Infinity norm (maximum absolute row sum) of the full 2N x 2N matrix.
    fn norm_inf(&self) -> f64 {
        let mut n: f64 = 0.0;
        for r in 0..N {
            let top: f64 = (0..N)
                .map(|c| self.a[(r, c)].abs().to_f64() + self.b[(r, c)].abs().to_f64())
                .sum();
            let bottom: f64 = (0..N).map(|c| self.c[(r, c)].abs().to_f64()).sum();
            n = n.max(top).max(bottom);
        }
        n
    }

    /// `exp(self)` by scaling and squaring of a degree-16 Taylor polynomial
    /// (Moler & Van Loan, "Nineteen dubious ways...", SIAM Review 45(1), 2003,
    /// method 3): with `||A / 2^s|| <= 1/2` the remainder is below
    /// `0.5^17 / 17!`, about 2e-20.
    fn exp(&self) -> Self {
        const DEGREE: u32 = 16;
        const MAX_SQUARINGS: i32 = 64;
        let norm = self.norm_inf();
        let mut squarings = 0;
        if norm.is_finite() && norm > 0.5 {
            squarings = (libm::ceil(libm::log2(norm / 0.5)) as i32).clamp(0, MAX_SQUARINGS);
        }
        let scaled = self.scale(T::of(libm::pow(2.0, -f64::from(squarings))));
        // Horner: I + A (I + A/2 (I + A/3 (...))).
        let mut r = Self::identity();
        for k in (1..=DEGREE).rev() {
            let t = scaled.mul(&r).scale(T::of(1.0 / f64::from(k)));
            r = Self {
                a: t.a + SMatrix::identity(),
                b: t.b,
                c: t.c + SMatrix::identity(),
            };
        }
        for _ in 0..squarings {
            r = r.mul(&r);
        }
        r
    }
}
