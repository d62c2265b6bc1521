//! The equi-angular cube map (EAC): the cube's six faces, each storing angle instead of tangent.
//!
//! # Formula
//!
//! C. Brown, "Bringing pixels front and center in VR video" (Google, 2017), as ffmpeg's `v360`
//! filter computes it (`xyz_to_eac` / `eac_to_xyz` in `libavfilter/vf_v360.c`). The face is
//! picked and its coordinates `(sc, tc)` are taken exactly as for the [`Cube`](crate::Cube)
//! (the GL / Vulkan face table and tie rule of [`select_face`]); then each axis stores the
//! angle from the face's centre, α = atan(c) ∈ [−π/4, π/4], scaled to [0, 1]:
//!
//! ```text
//! u = ½ + (2/π) · atan(sc / |ma|),   v = ½ + (2/π) · atan(tc / |ma|)      (e = 2u − 1 = (4/π) atan c)
//! inverse: (sc, tc) = (tan(π/4 · (2u − 1)), tan(π/4 · (2v − 1))), R = normalize(face table)
//! ```
//!
//! Each axis is treated apart, so angle is uniform along each axis of a face (a face's centre
//! row and column are sampled at equal angles), not over solid angle: the area element below
//! varies over a face by a factor of √2 (largest at the centre, smallest at the middle of an
//! edge), against 3√3 ≈ 5.2 for the plain cube (centre against corner).
//!
//! `u` and `v` are clamped to [0, 1] (f32's `atan(1)` times `2/π` can round past ¼).
//!
//! # Faces, axes and layouts
//!
//! The charts are the cube's faces in GL order (+x, −x, +y, −y, +z, −z) with the cube's
//! orientation (s to the right, t downwards), so every cube layout (crosses, strips, six
//! files) holds an EAC map the same way. Its default atlas is [`Atlas::EAC_V360`], the faces
//! of ffmpeg `v360`'s `eac` layout (−x, +z, +x over −y, −z, +y); `envmap-render` writes and
//! reads that layout's files with their turned bottom row and 2-pixel padding.
//!
//! # Where it is available
//!
//! This scalar mapping, [`AnyMapping::Eac`](crate::AnyMapping::Eac) and its eight-wide
//! kernels in `envmap-simd` (`envmap_simd::eac`, at the three accuracy tiers).
//!
//! # Area element
//!
//! With `c = tan α` and `α = π/4 · (2u − 1)`, `dc = (π/2)(1 + c²) du`, so
//!
//! ```text
//! dΩ = (π/2)² (1 + sc²)(1 + tc²) / (1 + sc² + tc²)^{3/2} du dv
//! ```
//!
//! A texel's solid angle is exact: a rectangle of `(u, v)` is a rectangle of the face's plane
//! ([`crate::solid_angle::eac_face`]).

use glam::Vec3;

use crate::atlas::Atlas;
use crate::cube::{face_direction, select_face, CubeFace};
use crate::mapping::{in_unit_square, ChartUv, Mapping};
use crate::math::{atan, clamp01, sqrt, tan};

/// 2/π in f32.
const TWO_OVER_PI: f32 = core::f32::consts::FRAC_2_PI;

/// The equi-angular cube map; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Eac;

impl Eac {
    /// Forward mapping: the face (as the chart) and the angles along its axes as `(u, v)`.
    ///
    /// ```
    /// use envmap_core::Eac;
    /// use glam::Vec3;
    /// // On +z, 22.5° to the right of the centre: u = ½ + (2/π)(π/8) = ¾.
    /// let d = Vec3::new((core::f32::consts::PI / 8.0).tan(), 0.0, 1.0);
    /// let c = Eac::forward(d).unwrap();
    /// assert_eq!(c.chart, 4);
    /// assert!((c.u - 0.75).abs() < 1e-6 && (c.v - 0.5).abs() < 1e-6);
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let (face, sc, tc, ma) = select_face(dir)?;
        let u = clamp01(0.5 + TWO_OVER_PI * atan(sc / ma));
        let v = clamp01(0.5 + TWO_OVER_PI * atan(tc / ma));
        Some(ChartUv::new(face as u32, u, v))
    }

    /// Inverse mapping: `None` for a face above 5, NaN or `(u, v)` outside `[0, 1]²`.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        let face = CubeFace::from_index(c.chart)?;
        if !in_unit_square(c.u, c.v) {
            return None;
        }
        let angle = |u: f32| core::f32::consts::FRAC_PI_4 * (2.0 * u - 1.0);
        let d = face_direction(face, tan(angle(c.u)), tan(angle(c.v)));
        Some(d / sqrt(d.length_squared()))
    }
}

impl Mapping for Eac {
    fn name(&self) -> &'static str {
        "eac"
    }
    fn chart_count(&self) -> u32 {
        6
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        Self::forward(dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        Self::inverse(c)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        if chart >= 6 {
            return 0.0;
        }
        crate::solid_angle::eac_face(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::EAC_V360
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Cube;

    /// Directions spread over the sphere (a Fibonacci lattice), at several magnitudes.
    fn directions(n: u32) -> impl Iterator<Item = Vec3> {
        let golden = core::f32::consts::PI * (3.0 - sqrt(5.0));
        (0..n).map(move |i| {
            let z = 1.0 - (2.0 * i as f32 + 1.0) / n as f32;
            let r = sqrt(1.0 - z * z);
            let (s, c) = crate::math::sin_cos(golden * i as f32);
            let scale = [1.0, 1e-30, 1e30, 3.5][i as usize % 4];
            Vec3::new(r * c, r * s, z) * scale
        })
    }

    fn angle(a: Vec3, b: Vec3) -> f32 {
        let (a, b) = (a.normalize(), b.normalize());
        crate::math::atan2(a.cross(b).length(), a.dot(b))
    }

    #[test]
    fn same_face_as_the_cube_and_u_in_range() {
        for d in directions(20_000) {
            let e = Eac::forward(d).unwrap();
            let c = Cube::forward(d).unwrap();
            assert_eq!(e.chart, c.chart, "{d}");
            assert!(
                (0.0..=1.0).contains(&e.u) && (0.0..=1.0).contains(&e.v),
                "{d}"
            );
        }
    }

    #[test]
    fn round_trips() {
        let mut worst = 0.0f32;
        for d in directions(20_000) {
            let back = Eac::inverse(Eac::forward(d).unwrap()).unwrap();
            worst = worst.max(angle(d, back));
        }
        assert!(worst < 4e-7, "direction round trip {worst} rad");
        #[cfg(feature = "std")]
        std::eprintln!("eac scalar round trips: worst direction {worst:e} rad");
        // Chart points, away from the faces' edges (where a point is shared).
        let mut worst = 0.0f32;
        for chart in 0..6 {
            for i in 1..64 {
                for j in 1..64 {
                    let c = ChartUv::new(chart, i as f32 / 64.0, j as f32 / 64.0);
                    let back = Eac::forward(Eac::inverse(c).unwrap()).unwrap();
                    assert_eq!(back.chart, chart);
                    worst = worst.max((back.u - c.u).abs()).max((back.v - c.v).abs());
                }
            }
        }
        assert!(worst < 3e-7, "chart round trip {worst}");
        #[cfg(feature = "std")]
        std::eprintln!("eac scalar round trips: worst chart |Δu| or |Δv| {worst:e}");
    }

    #[test]
    fn named_directions() {
        for face in CubeFace::ALL {
            let c = Eac::forward(face.axis()).unwrap();
            assert_eq!((c.chart, c.u, c.v), (face as u32, 0.5, 0.5));
            assert_eq!(
                Eac::inverse(ChartUv::new(face as u32, 0.5, 0.5)),
                Some(face.axis())
            );
        }
        // The face's edges and corners are where the cube has them: u, v in {0, 1}.
        let c = Eac::forward(Vec3::new(1.0, 0.0, 1.0)).unwrap();
        assert_eq!(c.chart, 4);
        assert!((c.u - 1.0).abs() < 1e-7 && (c.v - 0.5).abs() < 1e-7);
        let c = Eac::forward(Vec3::new(-1.0, 1.0, 1.0)).unwrap();
        assert_eq!(c.chart, 4);
        assert!(c.u.abs() < 1e-7 && c.v.abs() < 1e-7);
        let d = Eac::inverse(ChartUv::new(4, 0.0, 0.0)).unwrap();
        assert!(angle(d, Vec3::new(-1.0, 1.0, 1.0)) < 2e-7);
        // A face spans ±45° along each axis: 22.5° below the centre is v = ¾.
        let half = Vec3::new(0.0, -tan(core::f32::consts::PI / 8.0), 1.0);
        let c = Eac::forward(half).unwrap();
        assert!((c.v - 0.75).abs() < 1e-7, "{}", c.v);
    }

    #[test]
    fn continuous_across_a_face() {
        // Along +z's centre row, u grows with the angle, evenly.
        let mut last = -1.0f32;
        for k in 0..=90 {
            let a = (k as f32 - 45.0).to_radians() * 0.999;
            let (s, c) = crate::math::sin_cos(a);
            let u = Eac::forward(Vec3::new(s, 0.0, c)).unwrap().u;
            assert!(u > last);
            assert!((u - (0.5 + a * TWO_OVER_PI)).abs() < 1e-6);
            last = u;
        }
    }

    #[test]
    fn bad_input() {
        assert_eq!(Eac::forward(Vec3::ZERO), None);
        assert_eq!(Eac::forward(Vec3::new(0.0, f32::NAN, 1.0)), None);
        assert_eq!(Eac::forward(Vec3::new(f32::INFINITY, 0.0, 1.0)), None);
        assert_eq!(Eac::inverse(ChartUv::new(6, 0.5, 0.5)), None);
        assert_eq!(Eac::inverse(ChartUv::new(0, 1.1, 0.5)), None);
        assert_eq!(Eac::inverse(ChartUv::new(0, f32::NAN, 0.5)), None);
    }

    #[test]
    fn solid_angles_are_the_area_element_integrated() {
        use crate::solid_angle::eac_face;
        let m = Eac;
        // Whole faces.
        let total: f64 = (0..6).map(|f| m.solid_angle(f, 0.0, 1.0, 0.0, 1.0)).sum();
        assert!(
            (total - 4.0 * core::f64::consts::PI).abs() < 1e-13,
            "{total}"
        );
        // Texels of a 64² face sum to the face, and each is the area element integrated by
        // a 16×16 midpoint rule.
        let n = 64;
        let mut sum = 0.0;
        let mut worst = 0.0f64;
        let density = |u: f64, v: f64| {
            let h = core::f64::consts::FRAC_PI_2;
            let (x, y) = (
                libm::tan(h / 2.0 * (2.0 * u - 1.0)),
                libm::tan(h / 2.0 * (2.0 * v - 1.0)),
            );
            h * h * (1.0 + x * x) * (1.0 + y * y) / libm::pow(1.0 + x * x + y * y, 1.5)
        };
        for i in 0..n {
            for j in 0..n {
                let w = m.texel_solid_angle(2, i, j, n, n);
                sum += w;
                if (i * 7 + j) % 97 == 0 {
                    let k = 16;
                    let mut q = 0.0;
                    for a in 0..k {
                        for b in 0..k {
                            let u =
                                (f64::from(i) + (f64::from(a) + 0.5) / f64::from(k)) / f64::from(n);
                            let v =
                                (f64::from(j) + (f64::from(b) + 0.5) / f64::from(k)) / f64::from(n);
                            q += density(u, v);
                        }
                    }
                    q /= f64::from(k * k * n * n);
                    worst = worst.max((w - q).abs() / q);
                    assert!((w - q).abs() < 1e-6 * q, "texel ({i}, {j}): {w} vs {q}");
                }
            }
        }
        assert!(
            (sum - 4.0 * core::f64::consts::PI / 6.0).abs() < 1e-12,
            "{sum}"
        );
        #[cfg(feature = "std")]
        std::eprintln!("eac texel solid angles against the area element: worst {worst:e} relative");
        // Orientation, clipping, NaN as for every chart.
        assert_eq!(
            eac_face(0.5, 0.25, 0.0, 1.0),
            -eac_face(0.25, 0.5, 0.0, 1.0)
        );
        assert_eq!(eac_face(-1.0, 2.0, 0.0, 1.0), eac_face(0.0, 1.0, 0.0, 1.0));
        assert!(eac_face(f64::NAN, 1.0, 0.0, 1.0).is_nan());
        assert_eq!(m.solid_angle(6, 0.0, 1.0, 0.0, 1.0), 0.0);
    }
}
