//! Scalar math used by the mappings: libm by default, std with the `std` feature.
//!
//! Every function here is a thin, documented wrapper so that the whole crate
//! switches between `libm` and `std` in one place.

macro_rules! route {
    ($(#[$doc:meta])* $name:ident, $libm:ident, ($($arg:ident),*)) => {
        $(#[$doc])*
        #[inline]
        #[must_use]
        pub(crate) fn $name($($arg: f32),*) -> f32 {
            #[cfg(feature = "std")]
            {
                f32::$name($($arg),*)
            }
            #[cfg(not(feature = "std"))]
            {
                libm::$libm($($arg),*)
            }
        }
    };
}

route!(/// Square root.
    sqrt, sqrtf, (x));
route!(/// Sine.
    sin, sinf, (x));
route!(/// Cosine.
    cos, cosf, (x));
route!(/// Arc sine.
    asin, asinf, (x));
route!(/// Arc tangent.
    atan, atanf, (x));
route!(/// Tangent.
    tan, tanf, (x));
route!(/// Four-quadrant arc tangent of `self / other`: `atan2(y, x)`.
    atan2, atan2f, (y, x));

/// Both sine and cosine of `x`.
#[inline]
#[must_use]
pub(crate) fn sin_cos(x: f32) -> (f32, f32) {
    (sin(x), cos(x))
}

/// `x` with the sign of `s` (signed zeros respected).
#[inline]
#[must_use]
pub(crate) fn copysign(x: f32, s: f32) -> f32 {
    f32::from_bits((x.to_bits() & 0x7fff_ffff) | (s.to_bits() & 0x8000_0000))
}

/// `x` clamped into `[0, 1]`; NaN stays NaN (as `f32::clamp` does).
#[inline]
#[must_use]
pub(crate) fn clamp01(x: f32) -> f32 {
    x.clamp(0.0, 1.0)
}
