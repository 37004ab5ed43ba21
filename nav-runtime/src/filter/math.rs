//! Scalar functions used by generated code, so the same code builds with `std`
//! or with `core` + libm (feature `std` off). The functions here are `f64`;
//! [`single`] has the same names for models declared `scalar f32;`.

macro_rules! unary {
    ($($name:ident),*) => {$(
        #[doc = concat!("`", stringify!($name), "` of a scalar (std or libm).")]
        #[inline(always)]
        pub fn $name(x: f64) -> f64 {
            libm::$name(x)
        }
    )*};
}
unary!(sin, cos, tan, asin, acos, atan, sqrt, exp);

/// `(sin x, cos x)` with one argument reduction; the same values as
/// [`sin`] and [`cos`] (tested).
#[inline(always)]
pub fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

/// Natural logarithm.
#[inline(always)]
pub fn ln(x: f64) -> f64 {
    libm::log(x)
}

/// Four-quadrant arctangent of `y / x`.
#[inline(always)]
pub fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

/// Absolute value.
#[inline(always)]
pub fn abs(x: f64) -> f64 {
    libm::fabs(x)
}

/// Integer power by repeated multiplication (exact for small exponents).
#[inline(always)]
pub fn powi(x: f64, n: i32) -> f64 {
    libm::pow(x, n as f64)
}

/// Wraps an angle to (-pi, pi].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = 2.0 * core::f64::consts::PI;
    let r = a - two_pi * libm::floor((a + core::f64::consts::PI) / two_pi);
    if r <= -core::f64::consts::PI {
        r + two_pi
    } else {
        r
    }
}

/// The functions of [`crate::math`] in `f32` (libm's single-precision
/// routines), for models declared `scalar f32;`.
pub mod single {
    macro_rules! unary {
        ($($name:ident => $libm:ident),*) => {$(
            #[doc = concat!("`", stringify!($name), "` in `f32` (libm).")]
            #[inline(always)]
            pub fn $name(x: f32) -> f32 {
                libm::$libm(x)
            }
        )*};
    }
    unary!(sin => sinf, cos => cosf, tan => tanf, asin => asinf, acos => acosf,
           atan => atanf, sqrt => sqrtf, exp => expf, ln => logf, abs => fabsf);

    /// `(sin x, cos x)` with one argument reduction.
    #[inline(always)]
    pub fn sin_cos(x: f32) -> (f32, f32) {
        libm::sincosf(x)
    }

    /// Four-quadrant arctangent of `y / x`.
    #[inline(always)]
    pub fn atan2(y: f32, x: f32) -> f32 {
        libm::atan2f(y, x)
    }

    /// Integer power.
    #[inline(always)]
    pub fn powi(x: f32, n: i32) -> f32 {
        libm::powf(x, n as f32)
    }

    /// Wraps an angle to (-pi, pi].
    #[inline]
    pub fn wrap_angle(a: f32) -> f32 {
        let two_pi = 2.0 * core::f32::consts::PI;
        let r = a - two_pi * libm::floorf((a + core::f32::consts::PI) / two_pi);
        if r <= -core::f32::consts::PI {
            r + two_pi
        } else {
            r
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sin_cos_equals_sin_and_cos() {
        let mut x = -40.0;
        while x < 40.0 {
            assert_eq!(sin_cos(x), (sin(x), cos(x)), "at {x}");
            x += 0.0137;
        }
        for x in [0.0, -0.0, 1e-300, 1e22, f64::MAX, f64::INFINITY, f64::NAN] {
            let (s, c) = sin_cos(x);
            assert_eq!(s.to_bits(), sin(x).to_bits(), "sin at {x}");
            assert_eq!(c.to_bits(), cos(x).to_bits(), "cos at {x}");
        }
    }

    #[test]
    fn single_precision_functions_agree_with_double() {
        for x in [-3.0f32, -0.7, 0.0, 0.4, 1.3, 2.9] {
            let d = f64::from(x);
            let close = |a: f32, b: f64| {
                (f64::from(a) - b).abs() <= 4.0 * f64::from(f32::EPSILON) * b.abs().max(1.0)
            };
            assert!(
                close(single::sin(x), sin(d)) && close(single::cos(x), cos(d)),
                "{x}"
            );
            assert!(close(single::atan2(x, 0.3), atan2(d, 0.3f32.into())), "{x}");
            assert!(
                close(single::abs(x), abs(d)) && close(single::exp(x), exp(d)),
                "{x}"
            );
            assert_eq!(single::sin_cos(x), (single::sin(x), single::cos(x)));
            assert!(
                close(single::wrap_angle(x * 3.0), wrap_angle(d * 3.0)),
                "{x}"
            );
        }
    }

    #[test]
    fn wrap_angle_cases() {
        use core::f64::consts::PI;
        let cases = [
            (0.0, 0.0),
            (PI, PI),
            (-PI, PI),
            (3.0 * PI, PI),
            (0.5, 0.5),
            (-7.0, -7.0 + 2.0 * PI),
        ];
        for (a, want) in cases {
            assert!(
                (wrap_angle(a) - want).abs() < 1e-12,
                "{a} -> {}",
                wrap_angle(a)
            );
        }
    }
}
