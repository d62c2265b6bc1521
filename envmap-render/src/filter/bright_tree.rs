//! The split texels summed hierarchically: a tree over their points (a
//! quadtree on the cube's faces), each node holding its points' Ω·L, their
//! centre and the angular radius that holds them, walked once per eight
//! output directions with the Barnes–Hut rule (Barnes & Hut 1986, "A
//! hierarchical O(N log N) force-calculation algorithm", Nature 324): a
//! node whose radius is small against its distance from the lobe, or
//! against the lobe's width, is added whole at its centre; a nearer one is
//! opened.
//!
//! About a centre weighted by each point's Ω·|L| (largest channel) the
//! first-order term of the weight's change cancels, so a node ρ across at
//! angle θ from the lobe is added with a relative error of order (ρ/θ)²
//! (ρ/W near the peak, W the lobe's width): the sum costs the log of the
//! points far from the lobe and every point near it, where a flat sum
//! costs every point everywhere.

use envmap_core::glam::{DVec3, Vec3};
use envmap_core::AnyMapping;
use envmap_simd::Dir8;
use wide::f32x8;

use crate::filter::specular::{peak_magnitude, weight8, Bright};

/// A node is added whole when its angular radius is at most
/// `max(W / CORE, dist / FAR)`: `W` the lobe's width, `dist` the angle
/// from the nearest of the eight directions to the node's nearest point.
/// Near the lobe a node at most an eighth of the lobe across; in the tail
/// one at most a sixteenth of its distance across ([`FAR`]).
pub(crate) const CORE: f32 = 16.0;

/// See [`CORE`]: a far node is added whole when its radius is at most
/// its distance over `FAR`. Coarser far nodes (16, 8) move a chain's
/// levels by only a small fraction of a per cent; 32 keeps that margin.
pub(crate) const FAR: f32 = 32.0;

/// Depth of the leaves: faces cut into 2¹⁵ × 2¹⁵ cells (0.003° across),
/// finer than any part [`crate::filter::specular::split_bright`] makes.
const DEPTH: u32 = 15;

/// The walk's stack size: 6 roots + 3 per level below a face, rounded up.
const STACK: usize = 6 + 3 * (DEPTH as usize + 1) + 6;

#[derive(Clone, Copy, Debug)]
struct Node {
    /// Unit centre (Ω·|L|-weighted mean of the points' directions).
    dir: Vec3,
    /// Σ Ω·L of the node's points per channel.
    ol: [f32; 3],
    /// Largest angle from `dir` to any of the node's points (radians).
    rho: f32,
    /// Children: `kids[first..first + count]`; a leaf has none.
    first: u32,
    count: u32,
    /// The leaves below (the node itself for a leaf):
    /// `leaves[leaf_first..leaf_first + leaf_count]`.
    leaf_first: u32,
    leaf_count: u32,
}

/// A node to be opened with at most this many leaves below is summed leaf
/// by leaf, without testing its children: cheaper than the walk for a few
/// points.
const FLAT: u32 = 16;

/// The split texels' points as a tree, for [`BrightTree::sums`].
#[derive(Clone, Debug, Default)]
pub(crate) struct BrightTree {
    nodes: Vec<Node>,
    kids: Vec<u32>,
    roots: Vec<u32>,
    leaves: Vec<u32>,
}

/// A node's sums while it is built: Σ Ω·L, Σ w·d (w = Ω·|L|, largest
/// channel), and its points' directions' range for the radius.
struct Acc {
    ol: [f64; 3],
    wd: DVec3,
}

/// Interleaves the bits of `i` and `j` (Morton order).
fn morton(i: u32, j: u32) -> u64 {
    let spread = |x: u32| {
        let mut v = u64::from(x);
        v = (v | (v << 16)) & 0x0000_ffff_0000_ffff;
        v = (v | (v << 8)) & 0x00ff_00ff_00ff_00ff;
        v = (v | (v << 4)) & 0x0f0f_0f0f_0f0f_0f0f;
        v = (v | (v << 2)) & 0x3333_3333_3333_3333;
        v = (v | (v << 1)) & 0x5555_5555_5555_5555;
        v
    };
    spread(i) | (spread(j) << 1)
}

impl BrightTree {
    /// The tree over `b`'s points.
    #[must_use]
    pub(crate) fn new(b: &Bright) -> BrightTree {
        let n = 1u32 << DEPTH;
        let mut keyed: Vec<(u64, usize)> = b
            .dirs
            .iter()
            .enumerate()
            .filter_map(|(k, &d)| {
                let c = AnyMapping::Cube.forward(d)?;
                let i = ((c.u * n as f32) as u32).min(n - 1);
                let j = ((c.v * n as f32) as u32).min(n - 1);
                Some(((u64::from(c.chart) << (2 * DEPTH)) | morton(i, j), k))
            })
            .collect();
        keyed.sort_unstable();
        let mut t = BrightTree::default();
        for face in keyed.chunk_by(|a, b| a.0 >> (2 * DEPTH) == b.0 >> (2 * DEPTH)) {
            let root = t.build(b, face, 0);
            t.roots.push(root);
        }
        t
    }

    /// Builds the node over `pts` (sorted keys sharing their top `depth`
    /// levels below the face) and returns its index.
    fn build(&mut self, b: &Bright, pts: &[(u64, usize)], depth: u32) -> u32 {
        let leaf_first = self.leaves.len() as u32;
        // Descend while the points share the next level's cell.
        let mut depth = depth;
        while depth < DEPTH {
            let shift = 2 * (DEPTH - depth - 1);
            if pts[0].0 >> shift == pts[pts.len() - 1].0 >> shift {
                depth += 1;
            } else {
                break;
            }
        }
        let mut acc = Acc {
            ol: [0.0; 3],
            wd: DVec3::ZERO,
        };
        if depth == DEPTH || pts.len() == 1 {
            for &(_, k) in pts {
                add_point(&mut acc, b.dirs[k], b.omega_l[k]);
            }
            let dir = centre(&acc, b.dirs[pts[0].1]);
            let rho = pts
                .iter()
                .map(|&(_, k)| b.dirs[k].angle_between(dir))
                .fold(0.0f32, f32::max);
            let k = self.push(dir, &acc, rho, Vec::new(), leaf_first);
            self.leaves.push(k);
            return k;
        }
        let shift = 2 * (DEPTH - depth - 1);
        let children: Vec<u32> = pts
            .chunk_by(|x, y| x.0 >> shift == y.0 >> shift)
            .map(|group| self.build(b, group, depth + 1))
            .collect();
        for &c in &children {
            let node = self.nodes[c as usize];
            add_point(&mut acc, node.dir, node.ol);
        }
        let dir = centre(&acc, self.nodes[children[0] as usize].dir);
        let rho = children
            .iter()
            .map(|&c| {
                let node = self.nodes[c as usize];
                node.dir.angle_between(dir) + node.rho
            })
            .fold(0.0f32, f32::max);
        self.push(dir, &acc, rho, children, leaf_first)
    }

    fn push(&mut self, dir: Vec3, acc: &Acc, rho: f32, children: Vec<u32>, leaf_first: u32) -> u32 {
        let first = self.kids.len() as u32;
        let count = children.len() as u32;
        self.kids.extend(children);
        self.nodes.push(Node {
            dir,
            ol: acc.ol.map(|v| v as f32),
            rho: if rho.is_finite() {
                rho
            } else {
                core::f32::consts::PI
            },
            first,
            count,
            leaf_first,
            // A leaf's own entry is pushed by the caller, after this.
            leaf_count: (self.leaves.len() as u32 - leaf_first).max(1),
        });
        (self.nodes.len() - 1) as u32
    }

    /// Σ w·Ω·L over the points for eight directions `r` (lanes), w the GGX
    /// weight at α² = `a2`, `width` the lobe's width (radians): nodes added
    /// whole by the rule of [`CORE`] and [`FAR`], accumulated in f32 per
    /// run of 256 nodes and in f64 across runs.
    #[must_use]
    #[inline]
    pub(crate) fn sums(&self, r: &Dir8, a2: f32, width: f32) -> [[f64; 3]; 8] {
        if self.nodes.is_empty() {
            return [[0.0f64; 3]; 8];
        }
        self.walk(r, a2, width)
    }

    /// [`Self::sums`] of a tree with nodes: kept out of line, so that the
    /// callers' loops (the sampled levels' per-texel work) are compiled
    /// without the walk's code and registers.
    #[inline(never)]
    fn walk(&self, r: &Dir8, a2: f32, width: f32) -> [[f64; 3]; 8] {
        let mut out = [[0.0f64; 3]; 8];
        let core = width / CORE;
        // The walk's stack, on the stack: at most the 6 roots plus 3 more
        // per level opened below them (a node has at most 4 children).
        let mut stack = [0u32; STACK];
        let mut top = 0usize;
        for &root in &self.roots {
            stack[top] = root;
            top += 1;
        }
        let mut run = 0u32;
        let flush = |out: &mut [[f64; 3]; 8], s: [f32x8; 3]| {
            let a = s.map(f32x8::to_array);
            for (l, o) in out.iter_mut().enumerate() {
                for (c, v) in o.iter_mut().enumerate() {
                    *v += f64::from(a[c][l]);
                }
            }
        };
        let add = |node: &Node, s: &mut [f32x8; 3], run: &mut u32| {
            let w = weight8(r, node.dir, a2);
            s[0] += w * f32x8::splat(node.ol[0]);
            s[1] += w * f32x8::splat(node.ol[1]);
            s[2] += w * f32x8::splat(node.ol[2]);
            *run += 1;
        };
        let mut s = [f32x8::ZERO; 3];
        while top > 0 {
            top -= 1;
            let k = stack[top];
            let node = &self.nodes[k as usize];
            if node.count > 0 {
                let c = r.x * f32x8::splat(node.dir.x)
                    + r.y * f32x8::splat(node.dir.y)
                    + r.z * f32x8::splat(node.dir.z);
                let cmax = c.to_array().into_iter().fold(-1.0f32, f32::max);
                let dist = cmax.clamp(-1.0, 1.0).acos() - node.rho;
                if node.rho <= core.max(dist / FAR) {
                    add(node, &mut s, &mut run);
                } else if node.leaf_count <= FLAT {
                    let (a, b) = (
                        node.leaf_first as usize,
                        (node.leaf_first + node.leaf_count) as usize,
                    );
                    for &leaf in &self.leaves[a..b] {
                        add(&self.nodes[leaf as usize], &mut s, &mut run);
                    }
                } else {
                    let (a, b) = (node.first as usize, (node.first + node.count) as usize);
                    for &kid in &self.kids[a..b] {
                        stack[top] = kid;
                        top += 1;
                    }
                    continue;
                }
            } else {
                add(node, &mut s, &mut run);
            }
            if run >= 256 {
                flush(&mut out, s);
                s = [f32x8::ZERO; 3];
                run = 0;
            }
        }
        flush(&mut out, s);
        out
    }
}

fn add_point(acc: &mut Acc, d: Vec3, ol: [f32; 3]) {
    let w = f64::from(peak_magnitude(ol));
    acc.wd += w * d.as_dvec3();
    for (a, v) in acc.ol.iter_mut().zip(ol) {
        *a += f64::from(v);
    }
}

fn centre(acc: &Acc, fallback: Vec3) -> Vec3 {
    if acc.wd.length() > 0.0 {
        acc.wd.normalize().as_vec3()
    } else {
        fallback
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::brdf::lobe_width;

    /// Points scattered over the sphere (a spiral), some negative.
    fn scattered(n: usize) -> Bright {
        let mut b = Bright::default();
        let golden = core::f64::consts::PI * (3.0 - 5f64.sqrt());
        for k in 0..n {
            let z = 1.0 - 2.0 * (k as f64 + 0.5) / n as f64;
            let s = (1.0 - z * z).sqrt();
            let phi = golden * k as f64;
            b.dirs.push(Vec3::new(
                (s * phi.cos()) as f32,
                (s * phi.sin()) as f32,
                z as f32,
            ));
            let v = 1.0 + (k % 7) as f32;
            b.omega_l.push([v, -0.25 * v, 0.5 * v]);
        }
        b
    }

    fn flat(b: &Bright, r: &Dir8, a2: f32) -> [[f64; 3]; 8] {
        let mut out = [[0.0f64; 3]; 8];
        for (d, ol) in b.dirs.iter().zip(&b.omega_l) {
            let w = weight8(r, *d, a2).to_array();
            for l in 0..8 {
                for c in 0..3 {
                    out[l][c] += f64::from(w[l]) * f64::from(ol[c]);
                }
            }
        }
        out
    }

    #[test]
    fn the_tree_sums_as_the_flat_sum_does() {
        let b = scattered(20_000);
        let t = BrightTree::new(&b);
        assert!(t.nodes.len() >= b.dirs.len());
        for roughness in [0.1f32, 0.25, 0.5, 1.0] {
            let alpha = roughness * roughness;
            let a2 = alpha * alpha;
            let width = lobe_width(f64::from(alpha)) as f32;
            for seed in 0..4 {
                let dirs: [Vec3; 8] = core::array::from_fn(|l| {
                    let a = 0.7 * seed as f32 + 0.01 * l as f32;
                    Vec3::new(a.cos(), a.sin(), 0.3 * (seed as f32 - 1.5)).normalize()
                });
                let r = Dir8::new(
                    f32x8::new(dirs.map(|d| d.x)),
                    f32x8::new(dirs.map(|d| d.y)),
                    f32x8::new(dirs.map(|d| d.z)),
                );
                let (got, want) = (t.sums(&r, a2, width), flat(&b, &r, a2));
                for l in 0..8 {
                    for c in 0..3 {
                        let scale = want[l].iter().map(|v| v.abs()).fold(0.0, f64::max);
                        let err = (got[l][c] - want[l][c]).abs() / scale;
                        assert!(
                            err < 2e-3,
                            "roughness {roughness}, lane {l}, channel {c}: {} vs {} ({err:.2e})",
                            got[l][c],
                            want[l][c]
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn an_empty_tree_sums_to_zero() {
        let t = BrightTree::new(&Bright::default());
        assert!(t.nodes.is_empty());
        let r = Dir8::new(f32x8::ZERO, f32x8::ZERO, f32x8::ONE);
        assert_eq!(t.sums(&r, 0.1, 0.3), [[0.0; 3]; 8]);
    }
}
