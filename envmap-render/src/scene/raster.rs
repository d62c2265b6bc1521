// Rasterizing: the camera's view, triangles into the pixels they cover
// (perspective-correct weights, nearest hit), the surface at a hit, and
// supersampled images box-filtered down.
use envmap_core::glam::Vec3;

use super::renderer::*;
use crate::image::RgbImage;
use crate::scene::mesh::Mesh;

/// The camera's orthonormal basis and projection scale.
#[derive(Clone, Copy, Debug)]
pub(super) struct View {
    pub(super) eye: Vec3,
    pub(super) forward: Vec3,
    pub(super) right: Vec3,
    pub(super) up: Vec3,
    pub(super) tan_y: f32,
    pub(super) tan_x: f32,
    pub(super) width: f32,
    pub(super) height: f32,
}

impl View {
    pub(super) fn new(cam: &Camera, width: u32, height: u32) -> Self {
        let forward = (cam.target - cam.eye).normalize_or(Vec3::Y);
        let right = forward.cross(cam.up).normalize_or(Vec3::X);
        let up = right.cross(forward);
        let tan_y = (cam.fov_y_deg.clamp(1.0, 170.0).to_radians() * 0.5).tan();
        Self {
            eye: cam.eye,
            forward,
            right,
            up,
            tan_y,
            tan_x: tan_y * width as f32 / height as f32,
            width: width as f32,
            height: height as f32,
        }
    }

    /// The view ray through pixel position `(x, y)` (pixel units, y down).
    pub(super) fn ray(&self, x: f32, y: f32) -> Vec3 {
        let sx = (2.0 * x / self.width - 1.0) * self.tan_x;
        let sy = (1.0 - 2.0 * y / self.height) * self.tan_y;
        (self.forward + sx * self.right + sy * self.up).normalize()
    }

    /// Screen position (pixel units) and view depth of a world point.
    pub(super) fn project(&self, p: Vec3) -> (f32, f32, f32) {
        let d = p - self.eye;
        let z = d.dot(self.forward);
        let x = d.dot(self.right) / (z * self.tan_x);
        let y = d.dot(self.up) / (z * self.tan_y);
        (
            (x + 1.0) * 0.5 * self.width,
            (1.0 - y) * 0.5 * self.height,
            z,
        )
    }
}

/// The nearest surface found at one pixel: triangle and perspective-correct
/// barycentric weights.
#[derive(Clone, Copy, Debug)]
pub(super) struct Hit {
    pub(super) tri: u32,
    pub(super) w: [f32; 3],
    pub(super) inv_z: f32,
}

pub(super) const NEAR: f32 = 1e-3;

/// The interpolated unit normal at a hit and the unit vector from it to
/// the eye.
#[inline(always)]
pub(super) fn surface(mesh: &Mesh, hit: &Hit, view: &View) -> (Vec3, Vec3) {
    let [a, b, c] = mesh.triangles[hit.tri as usize].map(|i| i as usize);
    let n = (mesh.normals[a] * hit.w[0] + mesh.normals[b] * hit.w[1] + mesh.normals[c] * hit.w[2])
        .normalize_or(Vec3::Z);
    let p =
        mesh.positions[a] * hit.w[0] + mesh.positions[b] * hit.w[1] + mesh.positions[c] * hit.w[2];
    (n, (view.eye - p).normalize_or(-view.forward))
}

/// Rasterizes one projected triangle into the band starting at row `y0`,
/// keeping the nearest hit per pixel (largest 1/z).
pub(super) fn raster(
    v: &[(f32, f32, f32); 3],
    t: u32,
    y0: u32,
    rows: u32,
    w: u32,
    hits: &mut [Option<Hit>],
) {
    let area = (v[1].0 - v[0].0) * (v[2].1 - v[0].1) - (v[2].0 - v[0].0) * (v[1].1 - v[0].1);
    if area.abs() < 1e-12 || !area.is_finite() {
        return;
    }
    let xmin = v
        .iter()
        .map(|p| p.0)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(0.0) as u32;
    let xmax = v
        .iter()
        .map(|p| p.0)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil()
        .min(w as f32 - 1.0);
    if xmax < 0.0 {
        return;
    }
    let xmax = xmax as u32;
    let ymin = v
        .iter()
        .map(|p| p.1)
        .fold(f32::INFINITY, f32::min)
        .floor()
        .max(y0 as f32) as u32;
    let ymax = v
        .iter()
        .map(|p| p.1)
        .fold(f32::NEG_INFINITY, f32::max)
        .ceil()
        .min((y0 + rows) as f32 - 1.0);
    if ymax < y0 as f32 {
        return;
    }
    let ymax = ymax as u32;
    let inv_area = 1.0 / area;
    let inv_z = [1.0 / v[0].2, 1.0 / v[1].2, 1.0 / v[2].2];
    for y in ymin..=ymax {
        let py = y as f32 + 0.5;
        for x in xmin..=xmax {
            let px = x as f32 + 0.5;
            // Screen-space barycentrics from edge functions.
            let b0 = ((v[1].0 - px) * (v[2].1 - py) - (v[2].0 - px) * (v[1].1 - py)) * inv_area;
            let b1 = ((v[2].0 - px) * (v[0].1 - py) - (v[0].0 - px) * (v[2].1 - py)) * inv_area;
            let b2 = 1.0 - b0 - b1;
            if b0 < 0.0 || b1 < 0.0 || b2 < 0.0 {
                continue;
            }
            let iz = b0 * inv_z[0] + b1 * inv_z[1] + b2 * inv_z[2];
            let k = ((y - y0) * w + x) as usize;
            if hits[k].is_some_and(|h| h.inv_z >= iz) {
                continue;
            }
            // Perspective-correct weights.
            let wts = [b0 * inv_z[0] / iz, b1 * inv_z[1] / iz, b2 * inv_z[2] / iz];
            hits[k] = Some(Hit {
                tri: t,
                w: wts,
                inv_z: iz,
            });
        }
    }
}

/// Box-filters an image `s` times larger in each direction.
pub(super) fn downsample(hi: Vec<[f32; 3]>, w: u32, h: u32, s: u32) -> RgbImage {
    if s == 1 {
        return RgbImage {
            width: w,
            height: h,
            pixels: hi,
        };
    }
    let (ow, oh) = (w / s, h / s);
    let mut pixels = vec![[0.0f32; 3]; (ow * oh) as usize];
    let inv = 1.0 / (s * s) as f32;
    for (k, out) in pixels.iter_mut().enumerate() {
        let (x, y) = (k as u32 % ow, k as u32 / ow);
        let mut acc = [0.0f32; 3];
        for dy in 0..s {
            for dx in 0..s {
                let p = hi[((y * s + dy) * w + x * s + dx) as usize];
                for c in 0..3 {
                    acc[c] += p[c];
                }
            }
        }
        *out = acc.map(|a| a * inv);
    }
    RgbImage {
        width: ow,
        height: oh,
        pixels,
    }
}
