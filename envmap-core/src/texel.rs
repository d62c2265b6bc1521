//! Texel addressing: from chart coordinates to texel indices and back.
//!
//! A chart (or image) `n` texels wide covers `u ∈ [0, 1]`; texel `i` spans
//! `[i / n, (i + 1) / n]` and has its centre at `(i + 0.5) / n`. Indices are
//! clamped, so `u = 1.0` (the right edge) is texel `n − 1`, never `n`.

/// Index of the texel containing coordinate `u` in a row of `n` texels.
///
/// `floor(u · n)` clamped to `[0, n − 1]`: `u = 1.0` gives `n − 1`, negative
/// `u` gives 0, NaN gives 0. `n = 0` gives 0 (there is no valid index; callers
/// must not index an empty image).
///
/// ```
/// use envmap_core::texel::texel_index;
/// assert_eq!(texel_index(0.0, 4), 0);
/// assert_eq!(texel_index(0.2499, 4), 0);
/// assert_eq!(texel_index(0.25, 4), 1);
/// assert_eq!(texel_index(1.0, 4), 3);
/// assert_eq!(texel_index(f32::NAN, 4), 0);
/// ```
#[inline]
#[must_use]
pub fn texel_index(u: f32, n: u32) -> u32 {
    let x = u * n as f32;
    // `as` saturates (NaN → 0), then clamp the top.
    let i = x as u32;
    i.min(n.saturating_sub(1))
}

/// Centre of texel `i` in a row of `n` texels: `(i + 0.5) / n`.
///
/// Computed in f64 and rounded once, so it is the f32 nearest the exact centre.
///
/// ```
/// use envmap_core::texel::texel_center;
/// assert_eq!(texel_center(0, 4), 0.125);
/// assert_eq!(texel_center(3, 4), 0.875);
/// ```
#[inline]
#[must_use]
pub fn texel_center(i: u32, n: u32) -> f32 {
    ((f64::from(i) + 0.5) / f64::from(n)) as f32
}

/// Bounds `[i / n, (i + 1) / n]` of texel `i` in a row of `n`, in f64.
#[inline]
#[must_use]
pub fn texel_bounds(i: u32, n: u32) -> (f64, f64) {
    let n = f64::from(n);
    (f64::from(i) / n, (f64::from(i) + 1.0) / n)
}

/// Bilinear footprint of coordinate `u` in a row of `n` texels: the two texel
/// indices whose centres bracket `u` and the weight of the second.
///
/// Indices are *not* wrapped or clamped here: the first may be −1 and the
/// second `n` at the edges, so each representation applies its own edge rule
/// (latlong wraps, the cube steps onto the neighbouring face, disks clamp).
/// Coordinates outside `[0, 1]` are first clamped to it (so the indices
/// always lie in `[−1, n]`); NaN and ±Inf give `(0, 1, 0.0)`.
///
/// ```
/// use envmap_core::texel::bilinear_footprint;
/// assert_eq!(bilinear_footprint(0.5, 4), (1, 2, 0.5));
/// assert_eq!(bilinear_footprint(0.0, 4), (-1, 0, 0.5));
/// assert_eq!(bilinear_footprint(1e30, 4), bilinear_footprint(1.0, 4));
/// assert_eq!(bilinear_footprint(f32::NAN, 4), (0, 1, 0.0));
/// ```
#[inline]
#[must_use]
pub fn bilinear_footprint(u: f32, n: u32) -> (i64, i64, f32) {
    let x = u * n as f32 - 0.5;
    if !x.is_finite() {
        return (0, 1, 0.0);
    }
    // The range u ∈ [0, 1] covers; beyond it `x as i64` would saturate and
    // `i0 + 1` overflow.
    let x = x.clamp(-0.5, n as f32 - 0.5);
    // floor without a libm call: truncate, then step down for negatives.
    let t = x as i64;
    let i0 = if (t as f32) > x { t - 1 } else { t };
    (i0, i0 + 1, x - i0 as f32)
}
