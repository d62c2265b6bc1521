//! Reflection directions, in the two conventions found in the literature.
//!
//! The two formulas differ in which way the non-normal vector points, so they
//! are given distinct names:
//!
//! | function | formula | `v`/`i` points | source |
//! | --- | --- | --- | --- |
//! | [`reflect_view`] | R = 2(N·V)N − V | from the surface **towards the viewer** | seed `000` (class notes) |
//! | [`reflect_incident`] | R = I − 2(N·I)N | from the eye **towards the surface** | GLSL `reflect(I, N)` |
//!
//! With I = −V both give the same R. Neither normalises its inputs: with a
//! unit normal, |R| = |V| (resp. |I|).

use glam::Vec3;

/// The seed's reflection, R = 2(N·V)N − V, with `v` the vector from the surface
/// **towards the viewer** and `n` the unit surface normal.
///
/// Source: seed `000` ("Direction from normal and view direction").
///
/// ```
/// use envmap_core::reflect_view;
/// use glam::Vec3;
/// // Looking straight at a mirror: the reflection comes back to the viewer.
/// assert_eq!(reflect_view(Vec3::Z, Vec3::Z), Vec3::Z);
/// ```
#[inline]
#[must_use]
pub fn reflect_view(n: Vec3, v: Vec3) -> Vec3 {
    2.0 * n.dot(v) * n - v
}

/// GLSL's `reflect(I, N)` = I − 2(N·I)N, with `i` the **incident** direction
/// (from the eye towards the surface) and `n` the unit surface normal.
///
/// Source: the OpenGL Shading Language specification, `reflect`.
///
/// ```
/// use envmap_core::{reflect_incident, reflect_view};
/// use glam::Vec3;
/// let n = Vec3::new(0.0, 0.6, 0.8);
/// let v = Vec3::new(0.3, -0.2, 0.9);
/// assert!((reflect_incident(-v, n) - reflect_view(n, v)).length() < 1e-6);
/// ```
#[inline]
#[must_use]
pub fn reflect_incident(i: Vec3, n: Vec3) -> Vec3 {
    i - 2.0 * n.dot(i) * n
}
