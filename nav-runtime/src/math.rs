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
