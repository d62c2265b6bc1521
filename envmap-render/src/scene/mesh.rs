// Triangle meshes with smooth vertex normals: a sphere, a torus and the Utah
// teapot.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::sync::OnceLock;

use crate::error::{Error, Result};
use envmap_core::glam::{DVec3, Vec3};

/// The Utah teapot's patches in the `bpt` text format (public domain).
const TEAPOT_BPT: &str = include_str!("../../data/teapot.bpt");

/// Grid step, in model units, used to weld the teapot's vertices: points
/// that round to the same multiple of it become one vertex.
pub const WELD_TOLERANCE: f64 = 1e-5;

/// How far a normal's length may stray from 1 before [`Mesh::validate`]
/// rejects it.
const UNIT_TOLERANCE: f32 = 1e-3;

/// An indexed triangle mesh with one unit normal per vertex.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Mesh {
    /// Vertex positions.
    pub positions: Vec<Vec3>,
    /// Unit vertex normals, pointing out of the object; same length as
    /// `positions`.
    pub normals: Vec<Vec3>,
    /// Vertex indices of each triangle, counter-clockwise seen from outside.
    pub triangles: Vec<[u32; 3]>,
}

/// A bicubic Bézier patch: 4 × 4 control points, `control[i][j]` with `i`
/// along the `u` parameter and `j` along `v`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BezierPatch {
    /// The control points, row by row as they appear in the data file.
    pub control: [[Vec3; 4]; 4],
}

impl Mesh {
    /// The smallest and largest coordinate over all vertices, as
    /// `(min, max)`. An empty mesh gives `(Vec3::ZERO, Vec3::ZERO)`.
    #[must_use]
    pub fn bounds(&self) -> (Vec3, Vec3) {
        let mut it = self.positions.iter();
        let Some(&first) = it.next() else {
            return (Vec3::ZERO, Vec3::ZERO);
        };
        it.fold((first, first), |(lo, hi), &p| (lo.min(p), hi.max(p)))
    }

    /// Checks that every triangle's indices are in range, every position is
    /// finite and every normal is a finite unit vector (length within 10⁻³
    /// of 1).
    pub fn validate(&self) -> Result<()> {
        if self.positions.len() != self.normals.len() {
            return Err(Error::MeshCounts {
                positions: self.positions.len(),
                normals: self.normals.len(),
            });
        }
        for (vertex, &position) in self.positions.iter().enumerate() {
            if !position.is_finite() {
                return Err(Error::MeshPosition { vertex, position });
            }
        }
        for (vertex, &normal) in self.normals.iter().enumerate() {
            if !normal.is_finite() || (normal.length() - 1.0).abs() > UNIT_TOLERANCE {
                return Err(Error::MeshNormal { vertex, normal });
            }
        }
        let vertices = self.positions.len();
        for (triangle, tri) in self.triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= vertices) {
                return Err(Error::MeshIndex {
                    triangle,
                    index,
                    vertices,
                });
            }
        }
        Ok(())
    }

    /// A sphere of `radius` centred on the origin with its poles on the z
    /// axis: `segments` vertices around each of `rings − 1` circles of
    /// latitude, plus one vertex at each pole.
    ///
    /// Gives `2 + (rings − 1) · segments` vertices and
    /// `2 · segments · (rings − 1)` triangles. Normals are exact
    /// (`position / radius`). `segments` is raised to at least 3 and `rings`
    /// to at least 2.
    #[must_use]
    pub fn sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
        let segments = segments.max(3);
        let rings = rings.max(2);
        let r = f64::from(radius);
        let mut positions = Vec::with_capacity((2 + (rings - 1) * segments) as usize);
        let mut normals = Vec::with_capacity(positions.capacity());
        let mut push = |n: DVec3| {
            positions.push((n * r).as_vec3());
            normals.push(n.as_vec3());
        };
        push(DVec3::Z);
        for i in 1..rings {
            let theta = PI * f64::from(i) / f64::from(rings);
            let (st, ct) = theta.sin_cos();
            for j in 0..segments {
                let phi = 2.0 * PI * f64::from(j) / f64::from(segments);
                let (sp, cp) = phi.sin_cos();
                push(DVec3::new(st * cp, st * sp, ct));
            }
        }
        push(-DVec3::Z);

        let south = 1 + (rings - 1) * segments;
        let ring = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
        let mut triangles = Vec::with_capacity((2 * segments * (rings - 1)) as usize);
        for j in 0..segments {
            // Going down a meridian then east is counter-clockwise from outside.
            triangles.push([0, ring(1, j), ring(1, j + 1)]);
            triangles.push([ring(rings - 1, j), south, ring(rings - 1, j + 1)]);
        }
        for i in 1..rings - 1 {
            for j in 0..segments {
                let (a, b) = (ring(i, j), ring(i, j + 1));
                let (c, d) = (ring(i + 1, j), ring(i + 1, j + 1));
                triangles.push([a, c, d]);
                triangles.push([a, d, b]);
            }
        }
        Mesh {
            positions,
            normals,
            triangles,
        }
    }

    /// A torus around the z axis: the circle of radius `major` in the xy
    /// plane swept by a tube of radius `minor`.
    ///
    /// `segments` steps around the z axis, `sides` around the tube; gives
    /// `segments · sides` vertices and `2 · segments · sides` triangles, with
    /// exact normals. Both counts are raised to at least 3.
    #[must_use]
    pub fn torus(major: f32, minor: f32, segments: u32, sides: u32) -> Mesh {
        let segments = segments.max(3);
        let sides = sides.max(3);
        let (big, small) = (f64::from(major), f64::from(minor));
        let count = (segments * sides) as usize;
        let mut positions = Vec::with_capacity(count);
        let mut normals = Vec::with_capacity(count);
        for i in 0..segments {
            let (su, cu) = (2.0 * PI * f64::from(i) / f64::from(segments)).sin_cos();
            for j in 0..sides {
                let (sv, cv) = (2.0 * PI * f64::from(j) / f64::from(sides)).sin_cos();
                let n = DVec3::new(cv * cu, cv * su, sv);
                positions.push((DVec3::new(big * cu, big * su, 0.0) + small * n).as_vec3());
                normals.push(n.as_vec3());
            }
        }
        let index = |i: u32, j: u32| (i % segments) * sides + j % sides;
        let mut triangles = Vec::with_capacity(2 * count);
        for i in 0..segments {
            for j in 0..sides {
                // ∂/∂u × ∂/∂v points out of the tube.
                let (a, b) = (index(i, j), index(i + 1, j));
                let (c, d) = (index(i + 1, j + 1), index(i, j + 1));
                triangles.push([a, b, c]);
                triangles.push([a, c, d]);
            }
        }
        Mesh {
            positions,
            normals,
            triangles,
        }
    }

    /// The Utah teapot, standing on z = 0 with z up, each of its 32 patches
    /// evaluated on a `(subdivisions + 1)²` grid, welded along the seams.
    ///
    /// It spans x from −3.0 (handle) to about 3.434 (spout tip; the control
    /// points reach 3.525) and z from 0 to 3.15. `subdivisions` is raised to at least 1. Built from
    /// `teapot_patches`; see `Mesh::from_patches`.
    #[must_use]
    pub fn teapot(subdivisions: u32) -> Mesh {
        Mesh::from_patches(teapot_patches(), subdivisions)
    }

    /// Tessellates bicubic Bézier patches: each on a `(subdivisions + 1)²`
    /// grid of parameters, two triangles per grid cell, normals from the
    /// partial derivatives and each patch turned to face outward; then
    /// vertices closer than [`WELD_TOLERANCE`] are merged, their normals
    /// averaged, and triangles that collapse are dropped.
    ///
    /// `subdivisions` is raised to at least 1.
    #[must_use]
    pub(crate) fn from_patches(patches: &[BezierPatch], subdivisions: u32) -> Mesh {
        let n = subdivisions.max(1);
        let flips = outward_flips(patches);
        let mut welder = Welder::default();
        let mut triangles = Vec::new();
        let side = n + 1;
        for (patch, &flip) in patches.iter().zip(&flips) {
            let mut ids = Vec::with_capacity((side * side) as usize);
            for i in 0..side {
                for j in 0..side {
                    let (u, v) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
                    let p = eval(patch, u, v);
                    let normal = patch_normal(patch, u, v);
                    ids.push(welder.add(p, if flip { -normal } else { normal }));
                }
            }
            for i in 0..n {
                for j in 0..n {
                    let a = ids[(i * side + j) as usize];
                    let b = ids[((i + 1) * side + j) as usize];
                    let c = ids[((i + 1) * side + j + 1) as usize];
                    let d = ids[(i * side + j + 1) as usize];
                    for t in [[a, b, c], [a, c, d]] {
                        let t = if flip { [t[0], t[2], t[1]] } else { t };
                        if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                            triangles.push(t);
                        }
                    }
                }
            }
        }
        let (positions, normals) = welder.finish();
        Mesh {
            positions,
            normals,
            triangles,
        }
    }
}

/// The Utah teapot's 32 patches, parsed once from the embedded data.
///
/// The embedded file is checked by this module's tests; were it unreadable,
/// this would give no patches (and [`Mesh::teapot`] an empty mesh) rather
/// than panic.
#[must_use]
pub(crate) fn teapot_patches() -> &'static [BezierPatch] {
    static PATCHES: OnceLock<Vec<BezierPatch>> = OnceLock::new();
    PATCHES.get_or_init(|| parse_bpt(TEAPOT_BPT).unwrap_or_default())
}

/// Parses patches in the `bpt` text format: the patch count on the first
/// line, then per patch a line with its degrees in u and v (only `3 3`,
/// bicubic, is accepted) followed by 16 control points, one `x y z` per
/// line, row by row. Blank lines are skipped.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
pub(crate) fn parse_bpt(text: &str) -> Result<Vec<BezierPatch>> {
    let mut lines = text
        .lines()
        .enumerate()
        .map(|(i, l)| (i + 1, l.trim()))
        .filter(|(_, l)| !l.is_empty());
    let mut last_line = 0;
    let mut next = |what: &str| {
        let found = lines.next();
        if let Some((line, _)) = found {
            last_line = line;
        }
        found.ok_or_else(|| Error::PatchData {
            line: last_line + 1,
            message: format!("unexpected end of data, expected {what}"),
        })
    };
    let (line, first) = next("the patch count")?;
    let count: usize = first.parse().map_err(|_| Error::PatchData {
        line,
        message: format!("expected the patch count, found {first:?}"),
    })?;
    let mut patches = Vec::with_capacity(count.min(1024));
    for _ in 0..count {
        let (line, degrees) = next("the degrees `3 3`")?;
        if degrees.split_whitespace().collect::<Vec<_>>() != ["3", "3"] {
            return Err(Error::PatchData {
                line,
                message: format!("expected degrees `3 3`, found {degrees:?}"),
            });
        }
        let mut control = [[Vec3::ZERO; 4]; 4];
        for row in &mut control {
            for point in row {
                let (line, text) = next("a control point `x y z`")?;
                let xyz: Vec<f32> = text
                    .split_whitespace()
                    .map(str::parse::<f32>)
                    .collect::<Result<_, _>>()
                    .ok()
                    .filter(|v: &Vec<f32>| v.len() == 3 && v.iter().all(|c| c.is_finite()))
                    .ok_or_else(|| Error::PatchData {
                        line,
                        message: format!("expected a control point `x y z`, found {text:?}"),
                    })?;
                *point = Vec3::new(xyz[0], xyz[1], xyz[2]);
            }
        }
        patches.push(BezierPatch { control });
    }
    if let Ok((line, extra)) = next("") {
        return Err(Error::PatchData {
            line,
            message: format!("data after the last of {count} patches: {extra:?}"),
        });
    }
    Ok(patches)
}

/// The cubic Bernstein basis at `t` and its derivative.
fn bernstein(t: f64) -> ([f64; 4], [f64; 4]) {
    let s = 1.0 - t;
    (
        [s * s * s, 3.0 * t * s * s, 3.0 * t * t * s, t * t * t],
        [
            -3.0 * s * s,
            3.0 * s * s - 6.0 * t * s,
            6.0 * t * s - 3.0 * t * t,
            3.0 * t * t,
        ],
    )
}

/// Sums `Σᵢ Σⱼ a[i] b[j] P[i][j]` in f64.
fn combine(patch: &BezierPatch, a: &[f64; 4], b: &[f64; 4]) -> DVec3 {
    let mut sum = DVec3::ZERO;
    for (row, &ai) in patch.control.iter().zip(a) {
        for (p, &bj) in row.iter().zip(b) {
            sum += (ai * bj) * DVec3::from(*p);
        }
    }
    sum
}

/// The patch's point at `(u, v)`.
fn eval(patch: &BezierPatch, u: f64, v: f64) -> DVec3 {
    combine(patch, &bernstein(u).0, &bernstein(v).0)
}

/// The unnormalised `∂S/∂u × ∂S/∂v` at `(u, v)`.
fn raw_normal(patch: &BezierPatch, u: f64, v: f64) -> DVec3 {
    let (bu, du) = bernstein(u);
    let (bv, dv) = bernstein(v);
    combine(patch, &du, &bv).cross(combine(patch, &bu, &dv))
}

/// The unit normal `∂S/∂u × ∂S/∂v` at `(u, v)`; where it vanishes (a
/// collapsed patch edge), the normal at a parameter moved a little toward
/// the patch's centre, which tends to the limit normal there.
fn patch_normal(patch: &BezierPatch, u: f64, v: f64) -> DVec3 {
    let scale = patch
        .control
        .iter()
        .flatten()
        .map(|p| (DVec3::from(*p) - DVec3::from(patch.control[0][0])).length_squared())
        .fold(0.0, f64::max);
    let tiny = 1e-12 * scale.max(f64::MIN_POSITIVE);
    for step in [0.0, 1e-4, 1e-3, 1e-2, 1e-1] {
        let n = raw_normal(patch, u + (0.5 - u) * step, v + (0.5 - v) * step);
        if n.length_squared() > tiny * tiny && n.is_finite() {
            // Divided by the length, as in `try_normalize`.
            return n / n.length();
        }
    }
    DVec3::Z
}

/// For each patch, whether `∂S/∂u × ∂S/∂v` points inward and must be
/// reversed. Decided by casting rays from points of the patch, along its
/// normal tilted a few ways, through a coarse tessellation of all patches:
/// an even number of crossings means the normal faces outside. The majority
/// of the rays decides.
fn outward_flips(patches: &[BezierPatch]) -> Vec<bool> {
    const N: u32 = 8;
    let grid = |patch: &BezierPatch| {
        let mut pts = Vec::with_capacity(((N + 1) * (N + 1)) as usize);
        for i in 0..=N {
            for j in 0..=N {
                pts.push(eval(
                    patch,
                    f64::from(i) / f64::from(N),
                    f64::from(j) / f64::from(N),
                ));
            }
        }
        pts
    };
    let grids: Vec<Vec<DVec3>> = patches.iter().map(grid).collect();
    let mut soup: Vec<[DVec3; 3]> = Vec::new();
    for pts in &grids {
        let at = |i: u32, j: u32| pts[(i * (N + 1) + j) as usize];
        for i in 0..N {
            for j in 0..N {
                soup.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
                soup.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
            }
        }
    }
    // Tilts chosen off any symmetry of the model so rays miss edges.
    let tilts = [
        DVec3::new(0.013, 0.007, 0.011),
        DVec3::new(0.45, 0.21, 0.05),
        DVec3::new(-0.43, 0.17, -0.09),
        DVec3::new(0.11, -0.47, 0.13),
        DVec3::new(-0.07, 0.39, -0.31),
    ];
    grids
        .iter()
        .map(|pts| {
            let at = |i: u32, j: u32| pts[(i * (N + 1) + j) as usize];
            let mut inward = 0i32;
            for (i, j) in [(2, 3), (4, 4), (5, 2), (3, 6), (6, 5)] {
                let tri = [at(i, j), at(i + 1, j), at(i + 1, j + 1)];
                let face = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
                let Some(normal) = try_normalize(face) else {
                    continue;
                };
                let origin = (tri[0] + tri[1] + tri[2]) / 3.0;
                for tilt in tilts {
                    let dir = normal + tilt;
                    let dir = dir / dir.length();
                    let hits = soup
                        .iter()
                        .filter(|t| **t != tri && ray_hits(origin, dir, t))
                        .count();
                    inward += if hits % 2 == 1 { 1 } else { -1 };
                }
            }
            inward > 0
        })
        .collect()
}

/// Whether the ray `origin + t·dir`, `t > 0`, crosses the triangle
/// (Möller–Trumbore).
fn ray_hits(origin: DVec3, dir: DVec3, tri: &[DVec3; 3]) -> bool {
    let e1 = tri[1] - tri[0];
    let e2 = tri[2] - tri[0];
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-14 {
        return false;
    }
    let inv = 1.0 / det;
    let s = origin - tri[0];
    let u = s.dot(p) * inv;
    if !(0.0..=1.0).contains(&u) {
        return false;
    }
    let q = s.cross(e1);
    let v = dir.dot(q) * inv;
    if v < 0.0 || u + v > 1.0 {
        return false;
    }
    e2.dot(q) * inv > 1e-9
}

/// `v / |v|`, or `None` when `v` is zero or that is not finite. Each
/// component is divided by the length (glam's `try_normalize` multiplies by
/// its reciprocal, which can differ in the last bit and move the teapot's
/// normals).
fn try_normalize(v: DVec3) -> Option<DVec3> {
    let n = v / v.length();
    (v.length_squared() > 0.0 && n.is_finite()).then_some(n)
}

/// Merges points that quantise to the same [`WELD_TOLERANCE`] cell, summing
/// their unit normals.
#[derive(Default)]
struct Welder {
    index: HashMap<[i64; 3], u32>,
    positions: Vec<DVec3>,
    normal_sums: Vec<DVec3>,
    first_normals: Vec<DVec3>,
}

impl Welder {
    fn add(&mut self, p: DVec3, normal: DVec3) -> u32 {
        let key = (p / WELD_TOLERANCE).to_array().map(|c| c.round() as i64);
        let next = self.positions.len() as u32;
        let id = *self.index.entry(key).or_insert(next);
        if id == next {
            self.positions.push(p);
            self.normal_sums.push(DVec3::ZERO);
            self.first_normals.push(normal);
        }
        self.normal_sums[id as usize] += normal;
        id
    }

    fn finish(self) -> (Vec<Vec3>, Vec<Vec3>) {
        let normals = self
            .normal_sums
            .iter()
            .zip(&self.first_normals)
            .map(|(sum, first)| try_normalize(*sum).unwrap_or(*first).as_vec3())
            .collect();
        let positions = self.positions.iter().map(|p| p.as_vec3()).collect();
        (positions, normals)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn face(mesh: &Mesh, t: [u32; 3]) -> Vec3 {
        let [a, b, c] = t.map(|i| mesh.positions[i as usize]);
        (b - a).cross(c - a)
    }

    fn area(mesh: &Mesh) -> f64 {
        mesh.triangles
            .iter()
            .map(|&t| 0.5 * f64::from(face(mesh, t).length()))
            .sum()
    }

    /// Every triangle has area, and its winding agrees with its vertices'
    /// normals.
    fn check_winding_and_area(mesh: &Mesh, min_area: f32) {
        for &t in &mesh.triangles {
            let f = face(mesh, t);
            assert!(0.5 * f.length() > min_area, "degenerate triangle {t:?}");
            let n: Vec3 = t.iter().map(|&i| mesh.normals[i as usize]).sum();
            assert!(f.dot(n) > 0.0, "triangle {t:?} winds inward");
        }
    }

    #[test]
    fn sphere_counts_normals_and_area() {
        let (segments, rings) = (64, 32);
        let mesh = Mesh::sphere(2.0, segments, rings);
        mesh.validate().unwrap();
        assert_eq!(mesh.positions.len(), (2 + (rings - 1) * segments) as usize);
        assert_eq!(mesh.triangles.len(), (2 * segments * (rings - 1)) as usize);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            assert!((*n - *p / 2.0).length() < 1e-5, "{p} {n}");
            assert!((n.length() - 1.0).abs() < 1e-5);
        }
        check_winding_and_area(&mesh, 1e-6);
        let exact = 4.0 * std::f64::consts::PI * 4.0;
        let rel = (area(&mesh) - exact).abs() / exact;
        assert!(rel < 0.01, "area off by {rel}");
        let (lo, hi) = mesh.bounds();
        assert!((lo + Vec3::splat(2.0)).abs().max_element() < 1e-2, "{lo}");
        assert!((hi - Vec3::splat(2.0)).abs().max_element() < 1e-2, "{hi}");
    }

    #[test]
    fn sphere_minimum_counts() {
        let mesh = Mesh::sphere(1.0, 0, 0);
        mesh.validate().unwrap();
        assert_eq!(mesh.positions.len(), 5);
        assert_eq!(mesh.triangles.len(), 6);
        check_winding_and_area(&mesh, 1e-3);
    }

    #[test]
    fn torus_counts_and_normals() {
        let (major, minor) = (1.5f32, 0.5f32);
        let mesh = Mesh::torus(major, minor, 48, 24);
        mesh.validate().unwrap();
        assert_eq!(mesh.positions.len(), 48 * 24);
        assert_eq!(mesh.triangles.len(), 2 * 48 * 24);
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            // Analytic normal: from the nearest point of the tube's centre circle.
            let centre = Vec3::new(p.x, p.y, 0.0).normalize() * major;
            let expected = (*p - centre) / minor;
            assert!((*n - expected).length() < 1e-5, "{p} {n}");
        }
        check_winding_and_area(&mesh, 1e-6);
        let (lo, hi) = mesh.bounds();
        assert!((hi.z - minor).abs() < 1e-5 && (lo.z + minor).abs() < 1e-5);
        assert!((hi.x - (major + minor)).abs() < 1e-5);
        // Area 4π²Rr within 1 %.
        let exact = 4.0 * std::f64::consts::PI.powi(2) * f64::from(major * minor);
        assert!((area(&mesh) - exact).abs() / exact < 0.01);
    }

    #[test]
    fn embedded_teapot_parses() {
        let patches = parse_bpt(TEAPOT_BPT).expect("embedded teapot data must parse");
        assert_eq!(patches.len(), 32);
        assert_eq!(teapot_patches(), &patches[..]);
        assert_eq!(patches[0].control[0][0], Vec3::new(1.4, 0.0, 2.4));
    }

    #[test]
    fn parse_errors_name_the_line() {
        assert!(matches!(
            parse_bpt("x"),
            Err(Error::PatchData { line: 1, .. })
        ));
        assert!(matches!(
            parse_bpt("1\n3 2\n"),
            Err(Error::PatchData { line: 2, .. })
        ));
        let mut text = String::from("1\n3 3\n");
        for _ in 0..15 {
            text.push_str("0 0 0\n");
        }
        assert!(matches!(
            parse_bpt(&text),
            Err(Error::PatchData { line: 18, .. })
        ));
        text.push_str("1 2 nan\n");
        assert!(matches!(
            parse_bpt(&text),
            Err(Error::PatchData { line: 18, .. })
        ));
        let good = text.replace("1 2 nan", "1 2 3");
        assert_eq!(parse_bpt(&good).unwrap().len(), 1);
        assert!(matches!(
            parse_bpt(&(good + "4\n")),
            Err(Error::PatchData { line: 19, .. })
        ));
    }

    #[test]
    fn validate_rejects_bad_meshes() {
        let mut mesh = Mesh::sphere(1.0, 3, 2);
        mesh.triangles.push([0, 1, 99]);
        assert!(matches!(
            mesh.validate(),
            Err(Error::MeshIndex { index: 99, .. })
        ));
        let mut mesh = Mesh::sphere(1.0, 3, 2);
        mesh.normals[2] *= 2.0;
        assert!(matches!(
            mesh.validate(),
            Err(Error::MeshNormal { vertex: 2, .. })
        ));
        mesh.normals[2] = Vec3::NAN;
        assert!(matches!(
            mesh.validate(),
            Err(Error::MeshNormal { vertex: 2, .. })
        ));
        let mut mesh = Mesh::sphere(1.0, 3, 2);
        mesh.normals.pop();
        assert!(matches!(mesh.validate(), Err(Error::MeshCounts { .. })));
        assert_eq!(Mesh::default().bounds(), (Vec3::ZERO, Vec3::ZERO));
    }

    #[test]
    fn teapot_bounds_and_welding() {
        let s = 12;
        let mesh = Mesh::teapot(s);
        mesh.validate().unwrap();
        let raw = 32 * (s as usize + 1).pow(2);
        assert!(
            mesh.positions.len() < raw * 9 / 10,
            "welding left {} of {raw} vertices",
            mesh.positions.len()
        );
        let (lo, hi) = mesh.bounds();
        assert!((lo.x + 3.0).abs() < 0.02, "min x {}", lo.x);
        // The data's 3.525 is a control point of the spout's tip; the
        // surface itself reaches 3.434075 (exactly, at u = 1/2 on the lip).
        assert!((hi.x - 3.434).abs() < 0.01, "max x {}", hi.x);
        let points = || {
            teapot_patches()
                .iter()
                .flat_map(|p| p.control.iter().flatten())
        };
        let cmax = points().fold(Vec3::splat(f32::MIN), |m, &p| m.max(p));
        let cmin = points().fold(Vec3::splat(f32::MAX), |m, &p| m.min(p));
        assert_eq!((cmin.x, cmax.x, cmin.z, cmax.z), (-3.0, 3.525, 0.0, 3.15));
        assert!(lo.z.abs() < 1e-6, "min z {}", lo.z);
        assert!((hi.z - 3.15).abs() < 1e-4, "max z {}", hi.z);
        // Every vertex is used, no triangle is degenerate.
        let mut used = vec![false; mesh.positions.len()];
        for &t in &mesh.triangles {
            assert!(face(&mesh, t).length() > 0.0, "degenerate triangle {t:?}");
            for i in t {
                used[i as usize] = true;
            }
        }
        assert!(used.iter().all(|&u| u));
    }

    #[test]
    fn teapot_normals_point_outward() {
        let mesh = Mesh::teapot(16);
        // A discrete estimate of the surface normal at each vertex: the
        // area-weighted sum of the faces around it.
        let mut estimate = vec![Vec3::ZERO; mesh.positions.len()];
        for &t in &mesh.triangles {
            let f = face(&mesh, t);
            for i in t {
                estimate[i as usize] += f;
            }
        }
        let mut close = 0;
        for (i, (&n, e)) in mesh.normals.iter().zip(&estimate).enumerate() {
            let e = e.normalize();
            let cos = n.dot(e);
            assert!(
                cos > 0.0,
                "vertex {i} at {}: normal {n} vs surface {e}",
                mesh.positions[i]
            );
            if cos > 0.95 {
                close += 1;
            }
        }
        assert!(
            close * 100 > 97 * mesh.normals.len(),
            "only {close} of {} normals agree with the surface",
            mesh.normals.len()
        );
        // On the body, away from handle and spout, normals point away from
        // the axis; the lid's knob faces up and the bottom down.
        let mut body = 0;
        for (p, n) in mesh.positions.iter().zip(&mesh.normals) {
            let radial = Vec3::new(p.x, p.y, 0.0);
            if p.y.abs() > 0.8 && p.z > 0.3 && p.z < 2.3 {
                assert!(n.dot(radial) > 0.0, "body normal {n} at {p}");
                body += 1;
            }
            if radial.length() < 1e-4 {
                let expected = if p.z > 1.0 { Vec3::Z } else { -Vec3::Z };
                assert!(n.dot(expected) > 0.999, "pole normal {n} at {p}");
            }
        }
        assert!(body > 100);
    }

    #[test]
    fn teapot_welds_seams_smoothly() {
        // Where patches meet along a seam, the welded vertex's normal
        // matches each patch's own normal there (the patches are G1 across
        // the body's seams), so averaging does not bend it.
        let patches = teapot_patches();
        let flips = outward_flips(patches);
        // Body patches 4 and 5 share the edge at angle −90° (the y axis).
        for k in 0..=8 {
            let v = f64::from(k) / 8.0;
            let a = patch_normal(&patches[4], v, 1.0) * if flips[4] { -1.0 } else { 1.0 };
            let b = patch_normal(&patches[5], v, 0.0) * if flips[5] { -1.0 } else { 1.0 };
            assert!(
                (eval(&patches[4], v, 1.0) - eval(&patches[5], v, 0.0)).length() < 1e-9,
                "seam points differ"
            );
            assert!(
                a.dot(b) > 0.999,
                "normals differ across the seam: {a:?} {b:?}"
            );
        }
    }

    #[test]
    fn every_teapot_patch_faces_out() {
        // Every patch runs around its body, lid, bottom, handle or spout in
        // v: at mid-v it bulges away from the chord between its v = 0 and
        // v = 1 edges, which is the outward direction of a convex cross
        // section. The chosen orientation must agree, patch by patch. (The
        // rim's lip, patches 0 to 3, is concave on its inner side, u < 1/2,
        // where the outside is the pot's opening; so is the spout's lip,
        // patches 18 and 19, for u > 1/2.)
        let patches = teapot_patches();
        let flips = outward_flips(patches);
        for (k, (patch, &flip)) in patches.iter().zip(&flips).enumerate() {
            let us: &[f64] = match k {
                0..=3 => &[0.6, 0.8],
                18 | 19 => &[0.2, 0.4],
                _ => &[0.25, 0.5, 0.75],
            };
            for &u in us {
                let n = patch_normal(patch, u, 0.5) * if flip { -1.0 } else { 1.0 };
                let mid = (eval(patch, u, 0.0) + eval(patch, u, 1.0)) / 2.0;
                let bulge = eval(patch, u, 0.5) - mid;
                assert!(n.dot(bulge) > 0.0, "patch {k} faces in at u = {u}");
            }
        }
    }

    #[test]
    fn teapot_minimum_subdivision() {
        let mesh = Mesh::teapot(0);
        mesh.validate().unwrap();
        assert!(!mesh.triangles.is_empty());
    }
}
