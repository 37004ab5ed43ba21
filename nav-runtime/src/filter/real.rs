//! The scalar a model is generated for: `f64` (the default) or `f32`
//! (`scalar f32;` in the declaration, for flight and vehicle computers that
//! run single precision). The generated code is concrete in its scalar; the
//! filter core ([`crate::ekf::Ekf`], its updates, gates and covariance
//! kernels) is generic over it. Times, thresholds and reports stay `f64`
//! where they leave the filter (a NIS is compared with a chi-square quantile
//! in `f64`), so an `f32` filter differs from its `f64` twin only by the
//! rounding of its own arithmetic (see `docs/language.md`, "Scalar type").

/// `f32` or `f64`: what a filter's state, covariance and generated functions
/// are computed in. Sealed: the generator emits code for these two only.
pub trait Real: nalgebra::RealField + Copy + Default + sealed::Sealed {
    /// `"f32"` or `"f64"`.
    const NAME: &'static str;
    /// The largest finite value.
    const MAX: Self;
    /// The machine epsilon (the relative rounding unit times two), as `f64`.
    const EPSILON: f64;
    /// The nearest value of this type to `v` (exact for `f64`).
    fn of(v: f64) -> Self;
    /// The value as `f64` (exact).
    fn to_f64(self) -> f64;
    /// The angle wrapped to (-pi, pi] ([`crate::math::wrap_angle`] in this
    /// precision).
    fn wrap_angle(self) -> Self;

    /// `self + a b`, the step of the covariance kernels' sums: one rounding
    /// (a fused multiply-add) if `FUSED`, two otherwise. The kernels take
    /// `FUSED` as a parameter: the `fma` feature's choice in the filter,
    /// both in their tests.
    #[inline(always)]
    fn plus_product<const FUSED: bool>(self, a: Self, b: Self) -> Self {
        if FUSED {
            a.mul_add(b, self)
        } else {
            self + a * b
        }
    }
}

impl Real for f64 {
    const NAME: &'static str = "f64";
    const MAX: f64 = f64::MAX;
    const EPSILON: f64 = f64::EPSILON;
    #[inline(always)]
    fn of(v: f64) -> f64 {
        v
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn wrap_angle(self) -> f64 {
        crate::math::wrap_angle(self)
    }
}

impl Real for f32 {
    const NAME: &'static str = "f32";
    const MAX: f32 = f32::MAX;
    const EPSILON: f64 = f32::EPSILON as f64;
    #[inline(always)]
    fn of(v: f64) -> f32 {
        v as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        f64::from(self)
    }
    #[inline(always)]
    fn wrap_angle(self) -> f32 {
        crate::math::single::wrap_angle(self)
    }
}

mod sealed {
    pub trait Sealed {}
    impl Sealed for f64 {}
    impl Sealed for f32 {}
}

#[cfg(test)]
mod tests {
    use super::Real;

    #[test]
    fn conversions_round_to_nearest_and_back_exactly() {
        assert_eq!(<f64 as Real>::of(0.1), 0.1);
        assert_eq!(<f32 as Real>::of(0.1), 0.1f32);
        assert_eq!(<f32 as Real>::of(1e300), f32::INFINITY);
        assert_eq!(0.1f32.to_f64(), f64::from(0.1f32));
        assert_eq!((<f32 as Real>::NAME, <f64 as Real>::NAME), ("f32", "f64"));
    }
}
