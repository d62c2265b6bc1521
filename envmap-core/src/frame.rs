//! Axis conventions: how the caller's axes relate to a mapping's canonical frame.
//!
//! Every mapping is defined in one right-handed canonical frame (z up for
//! latlong and the octahedral maps, z the view axis for the sphere map and
//! paraboloid; the cube's face table applies to the vector as given). A
//! [`Frame`] is an orthogonal matrix taking the caller's coordinates to the
//! canonical ones, and [`Framed`] applies it around any mapping:
//! `forward(d) = mapping.forward(M d)`, `inverse(c) = Mᵀ mapping.inverse(c)`.
//!
//! | preset | caller's axes | caller (x, y, z) → canonical |
//! | --- | --- | --- |
//! | [`Frame::Z_UP_RH`] | z up, right-handed (seed `000`, Blender, pbrt) | (x, y, z) |
//! | [`Frame::Y_UP_RH`] | y up, right-handed (OpenGL, glTF, Vulkan clip aside) | (x, −z, y) |
//! | [`Frame::Y_UP_LH`] | y up, left-handed (Direct3D, Unity) | (x, z, y) |
//!
//! Y_UP_RH is the usual glTF-to-z-up rotation (+90° about x); Y_UP_LH first
//! flips z (left- to right-handed), then applies it. A user rotation composes
//! with a preset by [`Frame::then`].
//!
//! Cube maps meant for GL, Vulkan, D3D or wgpu are indexed with the vector in
//! the API's own coordinates (their face table is applied as given), so a GL
//! program's y-up directions use [`Frame::IDENTITY`] with [`crate::Cube`].

use glam::{Mat3, Quat, Vec3};

use crate::atlas::Atlas;
use crate::mapping::{ChartUv, Mapping};

/// An orthogonal change of axes, caller → canonical; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Frame {
    to_canonical: Mat3,
}

impl Default for Frame {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Frame {
    /// No change: the caller's axes are the canonical ones.
    pub const IDENTITY: Frame = Frame {
        to_canonical: Mat3::IDENTITY,
    };
    /// Z up, right-handed (seed `000`): the canonical frame itself.
    pub const Z_UP_RH: Frame = Frame::IDENTITY;
    /// Y up, right-handed (OpenGL, glTF): canonical = (x, −z, y).
    pub const Y_UP_RH: Frame = Frame {
        to_canonical: Mat3::from_cols(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, -1.0, 0.0),
        ),
    };
    /// Y up, left-handed (Direct3D, Unity): canonical = (x, z, y).
    pub const Y_UP_LH: Frame = Frame {
        to_canonical: Mat3::from_cols(
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 0.0),
        ),
    };

    /// A frame from a caller → canonical matrix; `None` unless it is
    /// orthogonal (columns of unit length, mutually perpendicular, within 1e-4).
    /// Reflections (determinant −1) are allowed: they change handedness.
    #[must_use]
    pub fn from_mat3(m: Mat3) -> Option<Frame> {
        let p = m.transpose() * m;
        let ok = (p - Mat3::IDENTITY)
            .to_cols_array()
            .iter()
            .all(|e| e.abs() <= 1e-4);
        ok.then_some(Frame { to_canonical: m })
    }

    /// A rotation frame from a quaternion (normalised first); `None` for a
    /// zero or non-finite quaternion.
    #[must_use]
    pub fn from_quat(q: Quat) -> Option<Frame> {
        if !q.is_finite() || q.length_squared() == 0.0 {
            return None;
        }
        Some(Frame {
            to_canonical: Mat3::from_quat(q.normalize()),
        })
    }

    /// Yaw, pitch and roll in radians, applied in that order about the
    /// canonical z (up), y and x axes, as `Rz(yaw) · Ry(pitch) · Rx(roll)`.
    #[must_use]
    pub fn from_yaw_pitch_roll(yaw: f32, pitch: f32, roll: f32) -> Frame {
        Frame {
            to_canonical: Mat3::from_rotation_z(yaw)
                * Mat3::from_rotation_y(pitch)
                * Mat3::from_rotation_x(roll),
        }
    }

    /// This frame followed by `next` (caller → self's canonical → next).
    #[must_use]
    pub fn then(self, next: Frame) -> Frame {
        Frame {
            to_canonical: next.to_canonical * self.to_canonical,
        }
    }

    /// The inverse change of axes.
    #[must_use]
    pub fn inverse(self) -> Frame {
        Frame {
            to_canonical: self.to_canonical.transpose(),
        }
    }

    /// The caller → canonical matrix.
    #[must_use]
    pub fn matrix(self) -> Mat3 {
        self.to_canonical
    }

    /// Whether the frame changes handedness (determinant −1).
    #[must_use]
    pub fn is_reflection(self) -> bool {
        self.to_canonical.determinant() < 0.0
    }

    /// Caller's coordinates → canonical coordinates.
    #[inline]
    #[must_use]
    pub fn to_canonical(self, d: Vec3) -> Vec3 {
        self.to_canonical * d
    }

    /// Canonical coordinates → caller's coordinates.
    #[inline]
    #[must_use]
    pub fn from_canonical(self, d: Vec3) -> Vec3 {
        self.to_canonical.transpose() * d
    }
}

/// A mapping seen through a [`Frame`]: directions are given in the caller's axes.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Framed<M> {
    /// The mapping, in its canonical frame.
    pub mapping: M,
    /// Caller → canonical.
    pub frame: Frame,
}

impl<M> Framed<M> {
    /// `mapping` seen through `frame`.
    #[must_use]
    pub const fn new(mapping: M, frame: Frame) -> Self {
        Self { mapping, frame }
    }
}

impl<M: Mapping> Mapping for Framed<M> {
    fn name(&self) -> &'static str {
        self.mapping.name()
    }
    fn chart_count(&self) -> u32 {
        self.mapping.chart_count()
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        // Check before rotating: a NaN would otherwise spread, and Inf·0 make NaN.
        if !dir.is_finite() {
            return None;
        }
        // Pre-scale so the matrix product cannot overflow.
        let m = dir.abs().max_element();
        if m == 0.0 {
            return None;
        }
        self.mapping.forward(self.frame.to_canonical(dir / m))
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        self.mapping
            .inverse(c)
            .map(|d| self.frame.from_canonical(d))
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        self.mapping.in_chart(chart, u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        self.mapping.solid_angle(chart, u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        self.mapping.atlas()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn presets_send_up_to_z() {
        assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::Y), Vec3::Z);
        assert_eq!(Frame::Y_UP_LH.to_canonical(Vec3::Y), Vec3::Z);
        assert!(!Frame::Y_UP_RH.is_reflection());
        assert!(Frame::Y_UP_LH.is_reflection());
        // glTF's forward (+z, towards the viewer) becomes −y.
        assert_eq!(Frame::Y_UP_RH.to_canonical(Vec3::Z), Vec3::NEG_Y);
        // D3D's forward (+z, into the screen) becomes +y.
        assert_eq!(Frame::Y_UP_LH.to_canonical(Vec3::Z), Vec3::Y);
    }

    #[test]
    fn round_trip_and_validation() {
        let f = Frame::Y_UP_RH.then(Frame::from_yaw_pitch_roll(0.3, -0.2, 1.1));
        let d = Vec3::new(0.2, -0.5, 0.7);
        assert!((f.from_canonical(f.to_canonical(d)) - d).length() < 1e-6);
        assert!(Frame::from_mat3(Mat3::from_diagonal(Vec3::splat(2.0))).is_none());
        assert!(Frame::from_quat(Quat::from_xyzw(0.0, 0.0, 0.0, 0.0)).is_none());
    }
}
