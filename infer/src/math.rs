//! Scalar maths shared by every module.
//!
//! `infer` uses the `libm` crate for transcendental functions in every build,
//! with or without `std`, so results are bit-identical across targets and a
//! dataset or plan does not depend on the platform's C maths library.

pub(crate) use core::f64::consts::PI;

#[inline]
pub(crate) fn sin_cos(x: f64) -> (f64, f64) {
    libm::sincos(x)
}

#[inline]
pub(crate) fn atan2(y: f64, x: f64) -> f64 {
    libm::atan2(y, x)
}

#[inline]
pub(crate) fn sqrt(x: f64) -> f64 {
    libm::sqrt(x)
}

#[inline]
pub(crate) fn tan(x: f64) -> f64 {
    libm::tan(x)
}

#[inline]
pub(crate) fn acos(x: f64) -> f64 {
    libm::acos(x)
}

#[inline]
pub(crate) fn tanh(x: f64) -> f64 {
    libm::tanh(x)
}

#[inline]
pub(crate) fn floor(x: f64) -> f64 {
    libm::floor(x)
}

#[inline]
pub(crate) fn ceil(x: f64) -> f64 {
    libm::ceil(x)
}

/// Degrees to radians.
#[inline]
pub fn deg(x: f64) -> f64 {
    x * (PI / 180.0)
}

/// Radians to degrees.
#[inline]
pub fn to_deg(x: f64) -> f64 {
    x * (180.0 / PI)
}

/// Wraps an angle into (−π, π].
#[inline]
pub fn wrap_angle(a: f64) -> f64 {
    let two_pi = 2.0 * PI;
    let mut w = a - two_pi * floor(a / two_pi);
    if w > PI {
        w -= two_pi;
    }
    w
}

/// 2-D cross product (z component).
#[inline]
pub(crate) fn cross(a: [f64; 2], b: [f64; 2]) -> f64 {
    a[0] * b[1] - a[1] * b[0]
}
