//! Direction arguments: validation and overflow-free normalisation.

use glam::Vec3;

/// Normalises `d` without overflow or underflow trouble.
///
/// Returns `None` when any component is NaN or ±Inf, or when `d` is the zero
/// vector (either sign of zero). Otherwise the result has unit length within
/// an ulp or two, whatever the magnitude of `d`: components from denormals up
/// to `f32::MAX` are first divided by the largest magnitude (so nothing is
/// squared at its original scale), then normalised.
///
/// ```
/// use envmap_core::normalize_direction;
/// use glam::Vec3;
/// let d = normalize_direction(Vec3::new(1.8e38, 2.4e38, 0.0)).unwrap();
/// assert!((d - Vec3::new(0.6, 0.8, 0.0)).length() < 1e-6);
/// assert!(normalize_direction(Vec3::ZERO).is_none());
/// assert!(normalize_direction(Vec3::new(f32::NAN, 0.0, 1.0)).is_none());
/// ```
#[inline]
#[must_use]
pub fn normalize_direction(d: Vec3) -> Option<Vec3> {
    if !d.is_finite() {
        return None;
    }
    let m = d.abs().max_element();
    if m == 0.0 {
        return None;
    }
    // Division (not multiplication by 1/m, which overflows for denormal m).
    let s = d / m;
    // 1 <= |s| <= sqrt(3): no overflow, no harmful underflow.
    Some(s / crate::math::sqrt(s.length_squared()))
}
