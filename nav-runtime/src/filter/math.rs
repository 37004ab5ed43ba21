//! Scalar functions used by generated code, so the same code builds with `std`
//! or with `core` + libm (feature `std` off).

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
