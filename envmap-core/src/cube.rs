//! Cube mapping with the OpenGL / Vulkan face table.
//!
//! # Formula
//!
//! Seed `000` ("Cubic texture environment map"): the largest |component| of
//! R picks the face, and R is scaled by 1 / max(|rx|, |ry|, |rz|) onto the cube.
//! The face orientation is the OpenGL 4.6 / Vulkan table (OpenGL 4.6 core
//! specification, §8.13 "Cube Map Texture Selection", table 8.19), so cube
//! maps made here load into GL, Vulkan, Direct3D and wgpu unchanged:
//!
//! | major axis | face | sc | tc | ma |
//! | --- | --- | --- | --- | --- |
//! | +x | 0 | −z | −y | x |
//! | −x | 1 | +z | −y | x |
//! | +y | 2 | +x | +z | y |
//! | −y | 3 | +x | −z | y |
//! | +z | 4 | +x | −y | z |
//! | −z | 5 | −x | −y | z |
//!
//! ```text
//! s = ½ (sc / |ma| + 1),   t = ½ (tc / |ma| + 1)      (u = s, v = t)
//! inverse: (sc, tc) = (2s − 1, 2t − 1), R = normalize(face table solved for x, y, z with |ma| = 1)
//! ```
//!
//! s and t are computed exactly as written (one division, one addition, one
//! exact halving), without normalising R: no squaring, so no overflow or
//! underflow at any magnitude, and `sc / |ma|` never exceeds 1 in magnitude,
//! so s, t ∈ [0, 1].
//!
//! # Ties
//!
//! When two or three components share the largest magnitude (cube edges and
//! corners), z wins over y, and y over x — the rule the Vulkan specification
//! recommends (§16.5.4 "Cube Map Face Selection"):
//!
//! ```text
//! if |z| ≥ |x| and |z| ≥ |y|: z major   else if |y| ≥ |x|: y major   else x major
//! ```
//!
//! The sign of the major component picks the face by its sign bit, so signed
//! zeros count; a zero major component only occurs for the zero vector, which
//! gives `None`. `envmap-simd` applies the identical rule bit for bit.
//!
//! # Axes and image orientation
//!
//! Each face is an image with s to the right and t downwards (row 0 first, as
//! GL uploads it). Laid out as a horizontal cross the faces join up as seen
//! from inside the cube looking at +z with +y up: `−x +z +x −z` across, +y
//! above +z and −y below it (GL cube maps are left-handed in this sense).
//!
//! # Area element
//!
//! dΩ = dsc dtc / (1 + sc² + tc²)^{3/2}; a texel's solid angle is exact via
//! A(x, y) = atan2(xy, √(1 + x² + y²)) at its corners.

use glam::Vec3;

use crate::atlas::Atlas;
use crate::mapping::{in_unit_square, ChartUv, Mapping};

/// The six faces, numbered as in GL (`GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u32)]
pub enum CubeFace {
    /// Face 0, +x major.
    PosX = 0,
    /// Face 1, −x major.
    NegX = 1,
    /// Face 2, +y major.
    PosY = 2,
    /// Face 3, −y major.
    NegY = 3,
    /// Face 4, +z major.
    PosZ = 4,
    /// Face 5, −z major.
    NegZ = 5,
}

impl CubeFace {
    /// All faces in GL order.
    pub const ALL: [CubeFace; 6] = [
        CubeFace::PosX,
        CubeFace::NegX,
        CubeFace::PosY,
        CubeFace::NegY,
        CubeFace::PosZ,
        CubeFace::NegZ,
    ];

    /// The face with GL index `i`, or `None` for `i > 5`.
    #[inline]
    #[must_use]
    pub const fn from_index(i: u32) -> Option<CubeFace> {
        match i {
            0 => Some(CubeFace::PosX),
            1 => Some(CubeFace::NegX),
            2 => Some(CubeFace::PosY),
            3 => Some(CubeFace::NegY),
            4 => Some(CubeFace::PosZ),
            5 => Some(CubeFace::NegZ),
            _ => None,
        }
    }

    /// Short name, `"+x"`, `"-x"`, ... (also used for six-file cube names).
    #[inline]
    #[must_use]
    pub const fn name(self) -> &'static str {
        ["+x", "-x", "+y", "-y", "+z", "-z"][self as usize]
    }

    /// The unit vector of the face's major axis.
    #[inline]
    #[must_use]
    pub const fn axis(self) -> Vec3 {
        match self {
            CubeFace::PosX => Vec3::X,
            CubeFace::NegX => Vec3::NEG_X,
            CubeFace::PosY => Vec3::Y,
            CubeFace::NegY => Vec3::NEG_Y,
            CubeFace::PosZ => Vec3::Z,
            CubeFace::NegZ => Vec3::NEG_Z,
        }
    }
}

/// The face a direction selects, by the GL table and the z-over-y-over-x tie
/// rule; `None` for NaN, ±Inf or the zero vector.
///
/// Also returns `(sc, tc, |ma|)` for the face.
#[inline]
#[must_use]
pub fn select_face(d: Vec3) -> Option<(CubeFace, f32, f32, f32)> {
    if !d.is_finite() {
        return None;
    }
    let (ax, ay, az) = (d.x.abs(), d.y.abs(), d.z.abs());
    let r = if az >= ax && az >= ay {
        if d.z.is_sign_negative() {
            (CubeFace::NegZ, -d.x, -d.y, az)
        } else {
            (CubeFace::PosZ, d.x, -d.y, az)
        }
    } else if ay >= ax {
        if d.y.is_sign_negative() {
            (CubeFace::NegY, d.x, -d.z, ay)
        } else {
            (CubeFace::PosY, d.x, d.z, ay)
        }
    } else if d.x.is_sign_negative() {
        (CubeFace::NegX, d.z, -d.y, ax)
    } else {
        (CubeFace::PosX, -d.z, -d.y, ax)
    };
    if r.3 == 0.0 {
        return None;
    }
    Some(r)
}

/// The (unnormalised) direction through face coordinates `(sc, tc)` of
/// `face`, with `|ma| = 1`: the face table solved for x, y, z. Coordinates
/// outside `[−1, 1]` give points on the face's plane beyond its edges, which
/// is how a seamless cube filter finds the texels across an edge.
///
/// ```
/// use envmap_core::cube::{face_direction, CubeFace};
/// use glam::Vec3;
/// assert_eq!(face_direction(CubeFace::PosZ, 0.5, -0.25), Vec3::new(0.5, 0.25, 1.0));
/// ```
#[inline]
#[must_use]
pub const fn face_direction(face: CubeFace, sc: f32, tc: f32) -> Vec3 {
    match face {
        CubeFace::PosX => Vec3::new(1.0, -tc, -sc),
        CubeFace::NegX => Vec3::new(-1.0, -tc, sc),
        CubeFace::PosY => Vec3::new(sc, 1.0, tc),
        CubeFace::NegY => Vec3::new(sc, -1.0, -tc),
        CubeFace::PosZ => Vec3::new(sc, -tc, 1.0),
        CubeFace::NegZ => Vec3::new(-sc, -tc, -1.0),
    }
}

/// The cube mapping; see the [module docs](self).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct Cube;

impl Cube {
    /// Forward mapping: face (as the chart) and `(s, t)` as `(u, v)`.
    ///
    /// ```
    /// use envmap_core::Cube;
    /// use glam::Vec3;
    /// let c = Cube::forward(Vec3::new(2.0, -1.0, 1.0)).unwrap();
    /// // +x face: sc = −z, tc = −y.
    /// assert_eq!((c.chart, c.u, c.v), (0, 0.25, 0.75));
    /// ```
    #[inline]
    #[must_use]
    pub fn forward(dir: Vec3) -> Option<ChartUv> {
        let (face, sc, tc, ma) = select_face(dir)?;
        let s = 0.5 * (sc / ma + 1.0);
        let t = 0.5 * (tc / ma + 1.0);
        Some(ChartUv::new(face as u32, s, t))
    }

    /// Inverse mapping: `None` for a face above 5, NaN or `(s, t)` outside `[0, 1]²`.
    #[inline]
    #[must_use]
    pub fn inverse(c: ChartUv) -> Option<Vec3> {
        let face = CubeFace::from_index(c.chart)?;
        if !in_unit_square(c.u, c.v) {
            return None;
        }
        let sc = 2.0 * c.u - 1.0;
        let tc = 2.0 * c.v - 1.0;
        let d = face_direction(face, sc, tc);
        Some(d / crate::math::sqrt(d.length_squared()))
    }
}

impl Mapping for Cube {
    fn name(&self) -> &'static str {
        "cube"
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
        crate::solid_angle::cube_face(u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        Atlas::CUBE_HORIZONTAL_CROSS
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn table_rows() {
        // A direction with distinct components per row: (ma, sc, tc) checked.
        let d = |x, y, z| Cube::forward(Vec3::new(x, y, z)).unwrap();
        let c = d(4.0, 1.0, 2.0); // +x: sc=−z, tc=−y
        assert_eq!((c.chart, c.u, c.v), (0, 0.25, 0.375));
        let c = d(-4.0, 1.0, 2.0); // −x: sc=+z, tc=−y
        assert_eq!((c.chart, c.u, c.v), (1, 0.75, 0.375));
        let c = d(1.0, 4.0, 2.0); // +y: sc=+x, tc=+z
        assert_eq!((c.chart, c.u, c.v), (2, 0.625, 0.75));
        let c = d(1.0, -4.0, 2.0); // −y: sc=+x, tc=−z
        assert_eq!((c.chart, c.u, c.v), (3, 0.625, 0.25));
        let c = d(1.0, 2.0, 4.0); // +z: sc=+x, tc=−y
        assert_eq!((c.chart, c.u, c.v), (4, 0.625, 0.25));
        let c = d(1.0, 2.0, -4.0); // −z: sc=−x, tc=−y
        assert_eq!((c.chart, c.u, c.v), (5, 0.375, 0.25));
    }

    #[test]
    fn ties_z_over_y_over_x() {
        let f = |x, y, z| Cube::forward(Vec3::new(x, y, z)).unwrap().chart;
        assert_eq!(f(1.0, 1.0, 1.0), 4);
        assert_eq!(f(-1.0, -1.0, -1.0), 5);
        assert_eq!(f(1.0, 1.0, 0.5), 2);
        assert_eq!(f(1.0, -1.0, 0.5), 3);
        assert_eq!(f(1.0, 0.5, 1.0), 4);
        assert_eq!(f(0.5, 1.0, -1.0), 5);
    }

    #[test]
    fn signed_zero_axes() {
        let f = |x, y, z| Cube::forward(Vec3::new(x, y, z)).unwrap();
        let c = f(1.0, -0.0, 0.0);
        assert_eq!((c.chart, c.u, c.v), (0, 0.5, 0.5));
        let c = f(-0.0, 0.0, -1.0);
        assert_eq!((c.chart, c.u, c.v), (5, 0.5, 0.5));
        assert_eq!(Cube::forward(Vec3::new(-0.0, -0.0, -0.0)), None);
    }

    #[test]
    fn centre_and_corner_inverses() {
        for face in CubeFace::ALL {
            let d = Cube::inverse(ChartUv::new(face as u32, 0.5, 0.5)).unwrap();
            assert_eq!(d, face.axis());
        }
        // Corner (s, t) = (0, 0) of +z is (−1, +1, +1)/√3.
        let d = Cube::inverse(ChartUv::new(4, 0.0, 0.0)).unwrap();
        assert!((d - Vec3::new(-1.0, 1.0, 1.0).normalize()).length() < 1e-6);
    }

    #[test]
    fn bad_input() {
        assert_eq!(Cube::forward(Vec3::ZERO), None);
        assert_eq!(Cube::forward(Vec3::new(0.0, f32::NAN, 1.0)), None);
        assert_eq!(Cube::forward(Vec3::new(0.0, f32::NEG_INFINITY, 1.0)), None);
        assert_eq!(Cube::inverse(ChartUv::new(6, 0.5, 0.5)), None);
        assert_eq!(Cube::inverse(ChartUv::new(0, -0.1, 0.5)), None);
    }
}
