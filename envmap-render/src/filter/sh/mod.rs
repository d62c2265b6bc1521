//! Irradiance: the SH9 projection of any environment map, irradiance
//! coefficients and the forms engines load, deringing, and irradiance maps
//! from the SH or by exact cosine convolution.
//!
//! # The basis (Ramamoorthi & Hanrahan 2001)
//!
//! "An Efficient Representation for Irradiance Environment Maps"
//! (SIGGRAPH 2001, eq. 3 and 12): nine real spherical harmonics *without*
//! the Condon–Shortley phase, in envmap's canonical frame (z up,
//! right-handed), for a unit direction (x, y, z):
//!
//! | index | name | function | constant |
//! | --- | --- | --- | --- |
//! | 0 | L00 | [`Y00`] | 1/(2√π) = 0.282095 |
//! | 1, 2, 3 | L1−1, L10, L11 | [`Y1`]·y, Y1·z, Y1·x | √(3/4π) = 0.488603 |
//! | 4, 5, 7 | L2−2, L2−1, L21 | [`Y2`]·xy, Y2·yz, Y2·xz | √(15/4π) = 1.092548 |
//! | 6 | L20 | [`Y20`]·(3z² − 1) | √(5/16π) = 0.315392 |
//! | 8 | L22 | [`Y22`]·(x² − y²) | √(15/16π) = 0.546274 |
//!
//! Radiance coefficients ([`ShKind::Radiance`], [`Sh9::project`]):
//! L_lm = ∫ L(ω) Y_lm(ω) dω. The irradiance E(n) = ∫ L(ω) max(n·ω, 0) dω is
//! Σ Â_l L_lm Y_lm(n) with Â_0 = π, Â_1 = 2π/3, Â_2 = π/4 ([`A_HAT`]; R&H
//! eq. 8–9; Â_3 = 0 and Â_4 = −π/24, so SH9 leaves out band 4 and up);
//! [`Sh9::irradiance`] gives E_lm = Â_l·L_lm ([`ShKind::Irradiance`]). R&H's
//! quadratic-form constants c1…c5 (0.429043, 0.511664, 0.743125, 0.886227,
//! 0.247708) are Â_l times these basis constants (tested).
//!
//! # E or E/π
//!
//! Irradiance *coefficients* are E. Everything that stores or returns
//! irradiance values takes an [`IrradianceScale`] ([`Sh9::irradiance_at`],
//! [`irradiance_map`], `irradiance_map_exact`), whose default is **E/π**:
//! the outgoing radiance of a white Lambertian surface, which is what
//! engines expect in a diffuse irradiance map (Filament, Bevy,
//! glTF-IBL-Sampler and cmft all store E/π). Filament's shader form is E/π
//! too. A constant environment L gives E = πL, E/π = L.
//!
//! # The projection
//!
//! L_lm = Σ over texels of L·Y_lm(d)·Ω: d the direction at the texel's
//! centre, Ω the texel's exact solid angle (`TexelWeights`; texels of a
//! disk whose centre is outside it weigh 0). The sum is made in the map's own
//! axes and then taken to canonical axes through the image's frame
//! ([`Representation::frame`](crate::image::Representation::frame), exactly: see Frames). Texels go eight at a time:
//!
//! * a latlong (one chart, not turned): every basis polynomial is a function
//!   of θ times one of 1, cos φ, sin φ, cos 2φ, sin 2φ, so each row needs five
//!   sums per channel against tables of those (computed in f64 at the
//!   columns' centres); the row's θ factors and solid angle are applied in
//!   f64. It runs at the speed of reading the image.
//! * every other map: directions from the mapping's 8-wide inverse
//!   ([`envmap_simd::Exact`] tier) at the texel centres, the nine
//!   polynomials, 27 sums.
//!
//! Sums are f32 within blocks of 512 texels of a row, f64 beyond; rows go in
//! fixed tasks of 8, added in order, so the result is the same, bit for bit,
//! at any number of threads. A row whose fast sums are not finite is summed
//! again texel by texel in f64, skipping texels with a NaN or infinite
//! channel: they count as black and are counted
//! (`Sh9::project_detailed`); nothing NaN comes out. (A bake replaces
//! them by black before this step already.)
//!
//! Tests hold the sum within 10⁻⁵ × |L00| of the plain f64 sum over every
//! texel (the scalar core's direction taken to canonical axes in f64), over
//! 13 representations and frames and a smooth map with and without a sun.
//! The sum itself is a midpoint rule over texels: on the upper-hemisphere
//! step, L10 = √(3π)/2 comes out low by the rule's relative Δθ²/8. The
//! measured errors are in `docs/lighting.md`.
//!
//! # Frames
//!
//! `Sh9::in_frame` and `Sh9::transformed` re-express the function in
//! other axes, exactly, for any orthogonal matrix (rotations and
//! reflections): band 0 is kept; band 1 is the vector a = (L11, L1−1, L10)
//! of f₁ = Y1·a·d, and becomes Mᵀa; band 2 is the traceless symmetric
//! matrix Q of f₂ = dᵀQd (on the sphere 3z² − 1 = 2z² − x² − y²), and
//! becomes MᵀQM. No fitting, no sampling: a test holds it against f(M·d)
//! to rounding.
//!
//! **The y-up frame.** [`Sh9::to_y_up`] = `in_frame(Frame::Y_UP_RH)`: the
//! GL world (y up, right-handed; envmap's `World::YUp`, the axes of every
//! cube file envmap writes). Its (x, y, z) is canonical (x, −z, y), so the
//! y-up coefficients are the canonical ones renamed: L1−1 ← L10,
//! L10 ← −L1−1, L11 ← L11, L2−2 ← L21, L21 ← −L2−2, L2−1 ← −L2−1, and L20,
//! L22 mixed (3z² − 1 and x² − y² about the new axes).
//!
//! # Filament's form
//!
//! `Sh9::filament_shader_form` is what Filament's `cmgen --sh-shader`
//! prints and writes into the `sh` key of its KTX files and into `sh.txt`:
//! the irradiance, divided by π, in y-up axes, each coefficient times its
//! basis constant (Filament's basis has Condon–Shortley signs and its
//! pre-scaling multiplies them back, so the signs are R&H's), so that a
//! shader evaluates, for a unit GL direction n = (x, y, z),
//!
//! ```text
//! E(n)/π = sh0 + sh1·y + sh2·z + sh3·x + sh4·yx + sh5·yz + sh6·(3z² − 1) + sh7·zx + sh8·(x² − y²)
//! ```
//!
//! (Filament `libs/ibl/src/CubemapSH.cpp`, `preprocessSHForShader`.) The
//! axes are those of envmap's cube files, which are `cmgen --no-mirror`'s;
//! cmgen's default mirroring negates x, which flips sh3, sh4 and sh7.
//! `tests/irradiance.rs` (an ignored test CI runs) compares it with cmgen's own
//! output. The two differ slightly because cmgen projects its own cube,
//! filled from nearest input texels shifted by up to one texel, and because
//! it decodes an `.hdr` value up to half an RGBE step brighter than envmap
//! does (Radiance's (m + ½)·2^(e − 136)).
//!
//! # Deringing
//!
//! Off unless asked for (`Sh9::windowed`). The window is Filament's
//! (`CubemapSH::sincWindow`, after Sloan, "Deringing Spherical Harmonics",
//! 2017): band l is scaled by `sinc4_window`: 1 for l = 0, 0 for l ≥ w, else
//! (sin x / x)⁴ with x = πl/w, w the cutoff in bands. [`ShWindow::Auto`]
//! takes the cutoff from `Sh9::auto_cutoff`: none if the reconstructed
//! irradiance is non-negative already; otherwise bisection for the largest
//! w whose windowed irradiance has a minimum ≥ 0 in all three channels (one
//! window for all, so colours do not shift), between 1 (band 0 alone,
//! non-negative unless a channel's mean is negative) and 13 (doubled while
//! still non-negative), to 10⁻⁶ relative. The minimum over the sphere
//! (`Sh9::irradiance_minimum`) is searched over 1024 Fibonacci points
//! (≈ 0.11 rad apart), the 8 lowest refined by Newton's method on the sphere
//! (E is a quadratic there: E(n) = c + b·n + nᵀQn); tests check it against
//! a dense Fibonacci grid and a zonal closed form.
//!
//! cmgen 1.9.25 windows by default (`--sh-window=auto`) and windows every
//! map, needed or not: its bisection runs between 3 and 13, per channel,
//! keeping the smallest. On maps that need no window its windowed and plain
//! coefficients give a sinc⁴ window of cutoff [`CMGEN_SMOOTH_CUTOFF`], so
//! `ShWindow::Sinc4 { cutoff: 12.7675 }` reproduces cmgen's default there.
//!
//! # Irradiance maps
//!
//! [`irradiance_map`]: E or E/π from the SH at every texel centre of any
//! representation (the SH taken to the map's axes first, then polynomials
//! eight texels at a time); `irradiance_cube` is the default, a
//! [`DEFAULT_IRRADIANCE_SIZE`]² = 32² GL cube (horizontal cross), E/π.
//!
//! `irradiance_map_exact`: the exact cosine convolution
//! E(n) = Σ_j L_j·max(n·l_j, 0)·Ω_j over every texel j of one level of a
//! `Pyramid` (solid-angle-weighted means, so each level keeps the map's
//! integral), eight output texels at a time (two batches per source texel),
//! f32 within blocks of 256 source texels and f64 beyond, rows in parallel,
//! black and non-finite source texels skipped (the latter counted). Level 0
//! is the definition itself; a coarser level replaces each texel's
//! radiance by its mean over a larger texel, an error that shrinks as the
//! texel's angle squared. [`ExactLevel::Auto`] decides by convergence:
//! starting at the coarsest level with at least [`AUTO_START_TEXELS`]
//! texels, it convolves each next finer level until two successive ones
//! differ by at most the tolerance (relative RMS over the map,
//! `relative_rms`; default [`DEFAULT_EXACT_TOLERANCE`] = 10⁻³, under
//! half-float precision, 4.9·10⁻⁴, once the finer level's error is a
//! fraction of that difference), or reaches level 0. The finer of the two
//! is returned, with the difference. Each finer level costs four times the
//! last, so the search costs about 4/3 of its result.
//!
//! The irradiance cube from SH9 is within 0.5 % (relative RMS) of the exact
//! convolution for a smooth map, and exact for a band-limited one or the
//! hemisphere step (E = π(1 + cos θ)/2 is SH9); SH9 cannot hold a sun, for
//! which the exact mode is there (`tests/irradiance.rs`).
//!
//! # Speed
//!
//! `envmap-bench/benches/sh.rs` times the projection and both irradiance
//! maps; the figures are in `docs/lighting.md`.

use std::f64::consts::PI;

use crate::par::*;
use envmap_core::glam::{DMat3, DVec3, Vec3};
use envmap_core::Frame;

use crate::image::EnvImage;

mod irradiance;
mod project;
pub use irradiance::*;
use project::*;

// ---------------------------------------------------------------------------
// The basis
// ---------------------------------------------------------------------------

/// Y00 = 1/(2√π).
pub const Y00: f64 = 0.282_094_791_773_878_14;
/// The band-1 constant √(3/(4π)): Y1−1 = Y1·y, Y10 = Y1·z, Y11 = Y1·x.
pub const Y1: f64 = 0.488_602_511_902_919_9;
/// The constant of the three band-2 products √(15/(4π)): Y2−2 = Y2·xy,
/// Y2−1 = Y2·yz, Y21 = Y2·xz.
pub const Y2: f64 = 1.092_548_430_592_079_2;
/// Y20 = Y20·(3z² − 1) with this constant, √(5/(16π)).
pub const Y20: f64 = 0.315_391_565_252_520_05;
/// Y22 = Y22·(x² − y²) with this constant, √(15/(16π)).
pub const Y22: f64 = 0.546_274_215_296_039_6;

/// The constant of each basis function, in coefficient order (see
/// [`NAMES`]).
pub const BASIS_CONSTANTS: [f64; 9] = [Y00, Y1, Y1, Y1, Y2, Y2, Y20, Y2, Y22];

/// Â_l, the clamped cosine's convolution factors for bands 0, 1, 2:
/// π, 2π/3, π/4 (Ramamoorthi & Hanrahan 2001, eq. 8–9).
pub const A_HAT: [f64; 3] = [PI, 2.0 * PI / 3.0, PI / 4.0];

/// The band l of each coefficient.
pub const BANDS: [u32; 9] = [0, 1, 1, 1, 2, 2, 2, 2, 2];

/// The coefficients' names, in order: L00, L1−1, L10, L11, L2−2, L2−1, L20,
/// L21, L22.
pub const NAMES: [&str; 9] = [
    "L00", "L1-1", "L10", "L11", "L2-2", "L2-1", "L20", "L21", "L22",
];

/// The polynomial of each basis function without its constant, for a unit
/// direction: 1, y, z, x, xy, yz, 3z² − 1, xz, x² − y².
#[inline]
fn poly(d: DVec3) -> [f64; 9] {
    let (x, y, z) = (d.x, d.y, d.z);
    [
        1.0,
        y,
        z,
        x,
        x * y,
        y * z,
        3.0 * z * z - 1.0,
        x * z,
        x * x - y * y,
    ]
}

/// `d` scaled to unit length (any finite non-zero length, denormals and
/// `f64::MAX` included); `None` for zero or non-finite input.
fn unit(d: DVec3) -> Option<DVec3> {
    if !d.is_finite() {
        return None;
    }
    let m = d.x.abs().max(d.y.abs()).max(d.z.abs());
    if m == 0.0 {
        return None;
    }
    let d = d / m;
    Some(d / d.length())
}

/// The nine basis functions at `dir` (x, y, z; normalised first), in
/// coefficient order; NaN for a zero or non-finite direction.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn basis(dir: [f64; 3]) -> [f64; 9] {
    match unit(DVec3::from_array(dir)) {
        Some(d) => {
            let p = poly(d);
            core::array::from_fn(|i| BASIS_CONSTANTS[i] * p[i])
        }
        None => [f64::NAN; 9],
    }
}

// ---------------------------------------------------------------------------
// Coefficients
// ---------------------------------------------------------------------------

/// What a set of coefficients stands for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum ShKind {
    /// Radiance L: L_lm = ∫ L(ω) Y_lm(ω) dω, what [`Sh9::project`] gives.
    #[default]
    Radiance,
    /// Irradiance E (not divided by π): E_lm = Â_l·L_lm, what
    /// [`Sh9::irradiance`] gives; [`Sh9::eval`] of them is E(n).
    Irradiance,
}

/// Nine real SH coefficients per colour channel (RGB), in the order of
/// [`NAMES`], in Ramamoorthi and Hanrahan's basis (no Condon–Shortley sign)
/// and envmap's canonical frame (z up, right-handed); see the
/// [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sh9 {
    /// `coeffs[i][c]`: coefficient `i` ([`NAMES`]) of channel `c`.
    pub coeffs: [[f64; 3]; 9],
    /// Radiance or irradiance coefficients.
    pub kind: ShKind,
}

impl Default for Sh9 {
    /// All zero, radiance.
    fn default() -> Self {
        Self::zero(ShKind::Radiance)
    }
}

/// A projection and what it left out.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Projection {
    /// The radiance coefficients.
    pub sh: Sh9,
    /// Texels skipped because a channel was NaN or ±Inf (they count as
    /// black).
    pub skipped: u64,
}

impl Sh9 {
    /// All coefficients zero.
    #[must_use]
    pub const fn zero(kind: ShKind) -> Self {
        Self {
            coeffs: [[0.0; 3]; 9],
            kind,
        }
    }

    /// The radiance coefficients of `img`: Σ L·Y(ω)·Ω over its texels (see
    /// the [module docs](self)); texels with a NaN or infinite channel are
    /// skipped (`Sh9::project_detailed` counts them).
    #[must_use]
    pub fn project(img: &EnvImage) -> Sh9 {
        Self::project_detailed(img).sh
    }

    /// [`Sh9::project`], with the number of texels skipped.
    #[must_use]
    pub(crate) fn project_detailed(img: &EnvImage) -> Projection {
        let (raw, skipped) = native_sums(img, Path::Fast);
        let sh = from_native(raw, img.representation().frame);
        Projection { sh, skipped }
    }

    /// The irradiance coefficients E_lm = Â_l·L_lm (E, not E/π); the same
    /// coefficients if they already are irradiance.
    #[must_use]
    pub fn irradiance(&self) -> Sh9 {
        match self.kind {
            ShKind::Irradiance => *self,
            ShKind::Radiance => Sh9 {
                coeffs: core::array::from_fn(|i| {
                    self.coeffs[i].map(|c| c * A_HAT[BANDS[i] as usize])
                }),
                kind: ShKind::Irradiance,
            },
        }
    }

    /// The function the coefficients stand for at `dir` (canonical axes,
    /// normalised first): radiance for [`ShKind::Radiance`], E for
    /// [`ShKind::Irradiance`]. NaN for a zero or non-finite direction.
    #[must_use]
    pub fn eval(&self, dir: Vec3) -> [f32; 3] {
        self.eval_f64(dir.as_dvec3().to_array()).map(|v| v as f32)
    }

    /// [`Sh9::eval`] in f64.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn eval_f64(&self, dir: [f64; 3]) -> [f64; 3] {
        let b = basis(dir);
        let mut out = [0.0; 3];
        for (c, o) in out.iter_mut().enumerate() {
            *o = (0..9).map(|i| self.coeffs[i][c] * b[i]).sum();
        }
        out
    }

    /// The irradiance at `dir` (canonical axes), E or E/π as `scale` says,
    /// whatever the kind of the coefficients.
    #[must_use]
    pub fn irradiance_at(&self, dir: Vec3, scale: IrradianceScale) -> [f32; 3] {
        let e = self.irradiance().eval_f64(dir.as_dvec3().to_array());
        e.map(|v| (v * scale.factor()) as f32)
    }

    /// The coefficients of g(d) = f(m·d) (`m` by rows: `m[i][j]` is row i,
    /// column j), where f is the function these
    /// coefficients stand for: the same function seen in axes that `m`
    /// takes to the current ones. `m` must be orthogonal (rotations and
    /// reflections alike) within 10⁻⁴, as [`Frame::from_mat3`] asks; it is
    /// made exactly orthogonal first (polar decomposition). `None`
    /// otherwise, or for non-finite input.
    ///
    /// Exact, with no fitting: band 0 is a constant; band 1 is the vector
    /// a = (L11, L1−1, L10) (x, y, z) in f = Y1·a·d, which becomes mᵀa; band
    /// 2 is the traceless symmetric matrix Q with f = dᵀQd on the sphere,
    /// which becomes mᵀQm.
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn transformed(&self, m: [[f64; 3]; 3]) -> Option<Sh9> {
        let m = DMat3::from_cols_array_2d(&m).transpose();
        if !m.is_finite() {
            return None;
        }
        if max_abs_diff(m.transpose() * m, DMat3::IDENTITY) > 1e-4 + 1e-9 {
            return None;
        }
        Some(self.apply(orthonormalize(m)?))
    }

    /// The same function with directions in `frame`'s axes (the caller's
    /// axes of [`Frame`], which [`Frame::to_canonical`] takes to envmap's
    /// canonical ones): g(d) = f(frame.to_canonical(d)).
    #[must_use]
    pub(crate) fn in_frame(&self, frame: Frame) -> Sh9 {
        if frame == Frame::IDENTITY {
            return *self;
        }
        match orthonormalize(frame.matrix().as_dmat3()) {
            Some(m) => self.apply(m),
            // A frame is orthogonal within 10⁻⁴: never reached.
            None => Sh9 {
                coeffs: [[f64::NAN; 3]; 9],
                kind: self.kind,
            },
        }
    }

    /// The coefficients in the GL world's axes (y up, right-handed:
    /// [`Frame::Y_UP_RH`], envmap's `World::YUp`, the axes of every cube
    /// file envmap writes): `in_frame(Frame::Y_UP_RH)`. For y-up
    /// (x, y, z) the canonical direction is (x, −z, y), so, for example,
    /// the y-up L1−1 (the y term) is the canonical L10.
    #[must_use]
    pub fn to_y_up(&self) -> Sh9 {
        self.in_frame(Frame::Y_UP_RH)
    }

    /// Filament's pre-scaled shader form (what `cmgen --sh-shader` prints
    /// and writes into its KTX `sh` key and `sh.txt`): nine RGB values
    /// `sh[i]` such that, for a unit direction n = (x, y, z) in the GL
    /// world (y up; the axes of envmap's cube files, which are `cmgen
    /// --no-mirror`'s),
    ///
    /// ```text
    /// E(n)/π = sh0 + sh1·y + sh2·z + sh3·x + sh4·yx + sh5·yz + sh6·(3z² − 1) + sh7·zx + sh8·(x² − y²)
    /// ```
    ///
    /// That is the irradiance coefficients in y-up axes times each basis
    /// constant, divided by π (Filament's own basis carries Condon–Shortley
    /// signs and its pre-scaling multiplies them back in, so nothing is
    /// negated here). Radiance coefficients are convolved first.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn filament_shader_form(&self) -> [[f64; 3]; 9] {
        let e = self.irradiance().to_y_up();
        core::array::from_fn(|i| e.coeffs[i].map(|v| v * BASIS_CONSTANTS[i] / PI))
    }

    /// The coefficients with band l scaled by the window's factor (see
    /// [`sinc4_window`]); [`ShWindow::Auto`] finds its cutoff with
    /// `Sh9::auto_cutoff` and changes nothing when none is needed.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn windowed(&self, window: ShWindow) -> Sh9 {
        let Some(w) = window.cutoff(self) else {
            return *self;
        };
        let f = [0, 1, 2].map(|l| sinc4_window(l, w));
        Sh9 {
            coeffs: core::array::from_fn(|i| self.coeffs[i].map(|c| c * f[BANDS[i] as usize])),
            kind: self.kind,
        }
    }

    /// The cutoff of the sinc⁴ window that keeps the reconstructed
    /// irradiance non-negative over the whole sphere, in every channel; see
    /// the [module docs](self). `None` when the irradiance is non-negative
    /// already (nothing to window), or for non-finite coefficients.
    #[must_use]
    pub(crate) fn auto_cutoff(&self) -> Option<f64> {
        let e = self.irradiance();
        if e.coeffs.iter().flatten().any(|c| !c.is_finite()) {
            return None;
        }
        let lowest = |w: Option<f64>| -> f64 {
            let s = match w {
                Some(cutoff) => e.windowed(ShWindow::Sinc4 { cutoff }),
                None => e,
            };
            (0..3)
                .map(|c| Quadric::of(&s, c).minimum().0)
                .fold(f64::INFINITY, f64::min)
        };
        if lowest(None) >= 0.0 {
            return None;
        }
        // A cutoff of 1 keeps band 0 alone: non-negative unless a channel's
        // mean is negative, which no window can mend.
        if e.coeffs[0].iter().any(|&c| c < 0.0) {
            return Some(1.0);
        }
        let (mut lo, mut hi) = (1.0f64, AUTO_CUTOFF_START);
        while lowest(Some(hi)) >= 0.0 {
            lo = hi;
            hi *= 2.0;
            if hi > 1e9 {
                return Some(lo);
            }
        }
        while hi - lo > 1e-6 * hi {
            let m = 0.5 * (lo + hi);
            if lowest(Some(m)) >= 0.0 {
                lo = m;
            } else {
                hi = m;
            }
        }
        Some(lo)
    }

    #[cfg(test)]
    /// The minimum over the sphere of the irradiance E these coefficients
    /// give (convolved first if they are radiance), per channel, with
    /// where it is (canonical axes); see the [module docs](self) for how it
    /// is found.
    #[must_use]
    pub(crate) fn irradiance_minimum(&self) -> [(f64, [f64; 3]); 3] {
        let e = self.irradiance();
        [0, 1, 2].map(|c| {
            let (v, d) = Quadric::of(&e, c).minimum();
            (v, d.to_array())
        })
    }

    /// g(d) = f(m·d) for an exactly orthogonal `m`.
    fn apply(&self, m: DMat3) -> Sh9 {
        let mt = m.transpose();
        let c = &self.coeffs;
        let mut out = [[0.0; 3]; 9];
        for ch in 0..3 {
            out[0][ch] = c[0][ch];
            let a = mt * DVec3::new(c[3][ch], c[1][ch], c[2][ch]);
            out[3][ch] = a.x;
            out[1][ch] = a.y;
            out[2][ch] = a.z;
            // By rows: q[r][s] is row r, column s.
            let q = (mt * quadratic(c, ch) * m).transpose().to_cols_array_2d();
            let sym = |r: usize, s: usize| 0.5 * (q[r][s] + q[s][r]);
            let (xx, yy, zz) = (q[0][0], q[1][1], q[2][2]);
            out[4][ch] = 2.0 * sym(0, 1) / Y2;
            out[5][ch] = 2.0 * sym(1, 2) / Y2;
            out[6][ch] = (2.0 * zz - xx - yy) / (6.0 * Y20);
            out[7][ch] = 2.0 * sym(0, 2) / Y2;
            out[8][ch] = (xx - yy) / (2.0 * Y22);
        }
        Sh9 {
            coeffs: out,
            kind: self.kind,
        }
    }
}

/// Band 2 of channel `ch` as the traceless symmetric Q with
/// f₂(d) = dᵀQd on the unit sphere (3z² − 1 = 2z² − x² − y² there).
fn quadratic(c: &[[f64; 3]; 9], ch: usize) -> DMat3 {
    let (c4, c5, c6, c7, c8) = (c[4][ch], c[5][ch], c[6][ch], c[7][ch], c[8][ch]);
    let xx = -Y20 * c6 + Y22 * c8;
    let yy = -Y20 * c6 - Y22 * c8;
    let zz = 2.0 * Y20 * c6;
    let (xy, yz, xz) = (0.5 * Y2 * c4, 0.5 * Y2 * c5, 0.5 * Y2 * c7);
    // Symmetric: these rows are its columns too.
    DMat3::from_cols_array_2d(&[[xx, xy, xz], [xy, yy, yz], [xz, yz, zz]])
}

/// The orthogonal matrix nearest `m` (its polar factor), by Newton's
/// iteration X ← (X + X⁻ᵀ)/2; `None` if it does not converge to a finite
/// matrix (a singular `m`).
fn orthonormalize(m: DMat3) -> Option<DMat3> {
    let mut x = m;
    for _ in 0..40 {
        let next = (x + inverse_by_cofactors(x).transpose()) * 0.5;
        let step = max_abs_diff(next, x);
        x = next;
        if !x.is_finite() {
            return None;
        }
        if step <= 1e-16 {
            break;
        }
    }
    Some(x)
}

/// Coefficients summed in a map's own axes (Σ L·Ω·poly) → radiance
/// coefficients in canonical axes.
fn from_native(raw: Raw, frame: Frame) -> Sh9 {
    let native = Sh9 {
        coeffs: core::array::from_fn(|i| raw[i].map(|s| s * BASIS_CONSTANTS[i])),
        kind: ShKind::Radiance,
    };
    // The map's formulas see d_file = Fᵀ·d: f_canonical(d) = f_file(Fᵀ d).
    native.in_frame(frame.inverse())
}

// ---------------------------------------------------------------------------
// Deringing
// ---------------------------------------------------------------------------

/// A window over the SH bands (deringing); off unless asked for.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ShWindow {
    /// The sinc⁴ window with this cutoff, in bands (`sinc4_window`).
    Sinc4 {
        /// The band at which the window reaches 0.
        cutoff: f64,
    },
    /// The sinc⁴ window whose cutoff `Sh9::auto_cutoff` finds (none if
    /// the irradiance is non-negative already).
    Auto,
    /// cmgen's default (`--sh-window=auto`), which windows every map: the
    /// cutoff `Sh9::auto_cutoff` finds, at most [`CMGEN_SMOOTH_CUTOFF`]
    /// (the cutoff cmgen applies to maps that need none; see the
    /// [module docs](self)).
    Cmgen,
}

/// The sinc⁴ cutoff cmgen 1.9.25 applies by default to maps whose
/// irradiance needs no window: measured from its band ratios (band 1 ×
/// 0.96036, band 2 × 0.84978).
pub const CMGEN_SMOOTH_CUTOFF: f64 = 12.7675;

impl ShWindow {
    /// The cutoff this window applies to `sh`, or `None` for none.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn cutoff(self, sh: &Sh9) -> Option<f64> {
        match self {
            ShWindow::Sinc4 { cutoff } => Some(cutoff),
            ShWindow::Auto => sh.auto_cutoff(),
            ShWindow::Cmgen => Some(
                sh.auto_cutoff()
                    .map_or(CMGEN_SMOOTH_CUTOFF, |c| c.min(CMGEN_SMOOTH_CUTOFF)),
            ),
        }
    }
}

/// Where `Sh9::auto_cutoff`'s bisection starts its upper end: 13, cmgen's
/// `4·bands + 1` for three bands.
pub const AUTO_CUTOFF_START: f64 = 13.0;

/// The factor of band `l` in the sinc⁴ window of cutoff `w` (Filament's
/// `CubemapSH::sincWindow`, after Sloan's "Deringing Spherical
/// Harmonics"): 1 for l = 0, 0 for l ≥ w, else (sin x / x)⁴ with
/// x = π·l/w. An infinite `w` gives 1; a NaN one 0 (for l > 0).
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn sinc4_window(l: u32, w: f64) -> f64 {
    if l == 0 {
        return 1.0;
    }
    let l = f64::from(l);
    if w.is_infinite() && w > 0.0 {
        return 1.0;
    }
    if w.is_nan() || w <= l {
        return 0.0;
    }
    let x = PI * l / w;
    (x.sin() / x).powi(4)
}

/// One channel's irradiance as a quadratic on the unit sphere:
/// E(n) = c + b·n + nᵀQn.
struct Quadric {
    c: f64,
    b: DVec3,
    q: DMat3,
}

/// The Fibonacci points [`Quadric::minimum`] starts from.
const MIN_POINTS: u32 = 1024;
/// How many of the lowest of them it refines.
const MIN_STARTS: usize = 8;

impl Quadric {
    fn of(sh: &Sh9, ch: usize) -> Quadric {
        let e = &sh.coeffs;
        Quadric {
            c: Y00 * e[0][ch],
            b: DVec3::new(e[3][ch], e[1][ch], e[2][ch]) * Y1,
            q: quadratic(e, ch),
        }
    }

    fn value(&self, n: DVec3) -> f64 {
        self.c + self.b.dot(n) + n.dot(self.q * n)
    }

    /// The minimum over the sphere and where it is: the lowest of
    /// [`MIN_POINTS`] Fibonacci points, the [`MIN_STARTS`] lowest refined
    /// by Newton's method on the sphere.
    fn minimum(&self) -> (f64, DVec3) {
        let golden = PI * (3.0 - 5f64.sqrt());
        let n = MIN_POINTS;
        let mut pts: Vec<(f64, DVec3)> = (0..n)
            .map(|k| {
                let z = 1.0 - (2.0 * f64::from(k) + 1.0) / f64::from(n);
                let r = (1.0 - z * z).max(0.0).sqrt();
                let (s, c) = (golden * f64::from(k)).sin_cos();
                let d = DVec3::new(r * c, r * s, z);
                (self.value(d), d)
            })
            .collect();
        pts.sort_by(|a, b| a.0.total_cmp(&b.0));
        pts.iter()
            .take(MIN_STARTS)
            .map(|&(_, d)| self.refine(d))
            .fold(
                (f64::INFINITY, DVec3::Z),
                |a, b| if b.0 < a.0 { b } else { a },
            )
    }

    /// Newton's method on the sphere from `n` (gradient steps where the
    /// Hessian is not positive definite), with backtracking.
    fn refine(&self, mut n: DVec3) -> (f64, DVec3) {
        let mut f = self.value(n);
        // |q| summed by rows.
        let q_abs = self
            .q
            .transpose()
            .to_cols_array()
            .iter()
            .map(|v| v.abs())
            .sum::<f64>();
        let scale = self.b.length() + 2.0 * q_abs;
        if scale.is_nan() || scale <= 0.0 || !f.is_finite() {
            return (f, n);
        }
        let q2 = self.q * 2.0;
        for _ in 0..100 {
            let g = self.b + q2 * n;
            let gn = g.dot(n);
            let (t1, t2) = orthonormal_pair(n);
            let (g1, g2) = (t1.dot(g), t2.dot(g));
            let h11 = t1.dot(q2 * t1) - gn;
            let h22 = t2.dot(q2 * t2) - gn;
            let h12 = t1.dot(q2 * t2);
            let det = h11 * h22 - h12 * h12;
            let (mut s1, mut s2) = if h11 > 0.0 && det > 0.0 {
                (-(h22 * g1 - h12 * g2) / det, -(h11 * g2 - h12 * g1) / det)
            } else {
                (-g1 / scale, -g2 / scale)
            };
            let len = s1.hypot(s2);
            if len.is_nan() || len <= 1e-15 {
                break;
            }
            if len > 0.5 {
                s1 *= 0.5 / len;
                s2 *= 0.5 / len;
            }
            let mut moved = false;
            for _ in 0..50 {
                let m = n + t1 * s1 + t2 * s2;
                let m = m / m.length();
                let fm = self.value(m);
                if fm < f {
                    (n, f) = (m, fm);
                    moved = true;
                    break;
                }
                s1 *= 0.5;
                s2 *= 0.5;
            }
            if !moved {
                break;
            }
        }
        (f, n)
    }
}

/// Two unit vectors perpendicular to the unit `n` and to each other (not
/// glam's `any_orthonormal_pair`, which builds another pair).
fn orthonormal_pair(n: DVec3) -> (DVec3, DVec3) {
    let a = if n.x.abs() < 0.6 { DVec3::X } else { DVec3::Y };
    let t1 = n.cross(a);
    let t1 = t1 / t1.length();
    (t1, n.cross(t1))
}

// ---------------------------------------------------------------------------
// f64 matrix steps glam computes otherwise
// ---------------------------------------------------------------------------

/// The largest |a − b| over the entries, by rows; NaN differences are
/// passed over (glam's `abs_diff_eq` only compares with a bound, and fails
/// on NaN).
fn max_abs_diff(a: DMat3, b: DMat3) -> f64 {
    (a - b)
        .transpose()
        .to_cols_array()
        .iter()
        .fold(0.0, |m, d| m.max(d.abs()))
}

/// The inverse by cofactors, each divided by the determinant (non-finite
/// for a singular matrix). glam's `inverse` multiplies by the determinant's
/// reciprocal instead, which rounds differently.
fn inverse_by_cofactors(m: DMat3) -> DMat3 {
    // By rows: m[i][j] is row i, column j.
    let m = m.transpose().to_cols_array_2d();
    let cof = |i: usize, j: usize| {
        let (i1, i2) = ((i + 1) % 3, (i + 2) % 3);
        let (j1, j2) = ((j + 1) % 3, (j + 2) % 3);
        m[i1][j1] * m[i2][j2] - m[i1][j2] * m[i2][j1]
    };
    let det = m[0][0] * cof(0, 0) + m[0][1] * cof(0, 1) + m[0][2] * cof(0, 2);
    // Column j of the inverse: row j's cofactors.
    DMat3::from_cols_array_2d(&core::array::from_fn(|j| {
        core::array::from_fn(|i| cof(j, i) / det)
    }))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::weights::TexelWeights;
    use crate::image::{FileAxes, Representation};
    use crate::scene::procedural::{fill, smooth, sunny};
    use envmap_core::glam::Quat;
    use envmap_core::texel::texel_center;
    use envmap_core::Atlas;
    use envmap_core::{AnyMapping, ChartUv, Mapping};

    /// The f64 reference: every texel's direction (the scalar core's
    /// inverse at its centre) taken to canonical axes, the basis there, the
    /// texel's exact solid angle, all summed in f64.
    fn reference(img: &EnvImage) -> Sh9 {
        let m = img.mapping();
        let (cw, ch) = img.cell_size();
        let w = TexelWeights::new(m, cw, ch);
        let f = img.representation().frame.matrix().as_dmat3();
        let mut raw = [[0.0f64; 3]; 9];
        for chart in 0..m.chart_count() {
            for j in 0..ch {
                for i in 0..cw {
                    let Some(l) = img.chart_texel(chart, i, j) else {
                        continue;
                    };
                    let wt = w.get(chart, i, j);
                    let c = ChartUv::new(chart, texel_center(i, cw), texel_center(j, ch));
                    let Some(d) = m.inverse(c) else {
                        continue;
                    };
                    if wt == 0.0 || !l.iter().all(|v| v.is_finite()) {
                        continue;
                    }
                    let b = basis((f * d.as_dvec3()).to_array());
                    for k in 0..9 {
                        for c in 0..3 {
                            raw[k][c] += f64::from(l[c]) * wt * b[k];
                        }
                    }
                }
            }
        }
        Sh9 {
            coeffs: raw,
            kind: ShKind::Radiance,
        }
    }

    /// The largest coefficient difference over the largest |L00|, and
    /// where (coefficient, channel).
    fn worst(a: &Sh9, b: &Sh9) -> (f64, usize, usize) {
        let l00 = b.coeffs[0].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let mut w = (0.0, 0, 0);
        for i in 0..9 {
            for c in 0..3 {
                let e = (a.coeffs[i][c] - b.coeffs[i][c]).abs() / l00;
                if e > w.0 {
                    w = (e, i, c);
                }
            }
        }
        w
    }

    fn repr(mapping: AnyMapping, atlas: Atlas, frame: Frame) -> Representation {
        Representation::new(mapping, atlas, frame).unwrap()
    }

    fn gl_cube() -> Representation {
        default_irradiance_representation()
    }

    #[test]
    fn constants_are_the_formulas() {
        assert!((Y00 - 0.5 / PI.sqrt()).abs() < 1e-16);
        assert!((Y1 - (3.0 / (4.0 * PI)).sqrt()).abs() < 1e-16);
        assert!((Y2 - (15.0 / (4.0 * PI)).sqrt()).abs() < 1e-15);
        assert!((Y20 - (5.0 / (16.0 * PI)).sqrt()).abs() < 1e-16);
        assert!((Y22 - (15.0 / (16.0 * PI)).sqrt()).abs() < 1e-16);
        // R&H's quadratic-form constants c1…c5 are Â_l times the basis,
        // to the six digits printed (c3 = 0.743125 is 0.7431239 rounded up
        // by one in its last digit: 1.2e-6).
        let c = [0.429043, 0.511664, 0.743125, 0.886227, 0.247708];
        let ours = [
            A_HAT[2] * Y22,
            A_HAT[1] * Y1 / 2.0,
            3.0 * A_HAT[2] * Y20,
            A_HAT[0] * Y00,
            A_HAT[2] * Y20,
        ];
        for (a, b) in c.iter().zip(ours) {
            assert!((a - b).abs() < 1.5e-6, "{a} {b}");
        }
    }

    #[test]
    fn the_basis_is_orthonormal_under_the_projection() {
        // Each basis function as an environment projects onto itself.
        let r = repr(
            AnyMapping::Cube,
            Atlas::CUBE_HORIZONTAL_CROSS,
            Frame::IDENTITY,
        );
        let mut worst_off = 0.0f64;
        for i in 0..9 {
            let img = fill(r, 4 * 96, 3 * 96, |d| {
                let b = basis(d.as_dvec3().to_array())[i] as f32;
                [b, 0.0, 0.0]
            })
            .unwrap();
            let sh = Sh9::project(&img);
            for k in 0..9 {
                let want = if k == i { 1.0 } else { 0.0 };
                worst_off = worst_off.max((sh.coeffs[k][0] - want).abs());
            }
        }
        println!("basis orthonormality, cube 96²: worst |<Y_i, Y_k> − δ| = {worst_off:.2e}");
        assert!(worst_off < 2e-4, "{worst_off}");
    }

    #[test]
    fn a_constant_environment_gives_two_root_pi_l_and_e_equal_pi_l() {
        let l = [0.25f32, 1.0, 3.5];
        // The cube's symmetry makes every non-constant coefficient vanish
        // exactly (Σ Ω x² = Σ Ω y² = Σ Ω z² = 4π/3); the latlong and the
        // octahedral map sum Y20 (and the octahedral map Y22) by their texel
        // centres, which is the midpoint rule: an error of the order of the
        // texel's angle squared, here (π/256)² and (2/256)².
        for (r, cw, bound) in [
            (gl_cube(), 64, 1e-7),
            (
                Representation::for_file(AnyMapping::LatLong, FileAxes::default()),
                512,
                (PI / 256.0).powi(2),
            ),
            (
                repr(
                    AnyMapping::Octahedral,
                    Atlas::SINGLE_SQUARE,
                    Frame::IDENTITY,
                ),
                256,
                (2.0f64 / 256.0).powi(2),
            ),
        ] {
            let (w, h) = r.size_for_cell_width(cw).unwrap();
            let img = fill(r, w, h, |_| l).unwrap();
            let sh = Sh9::project(&img);
            let mut rest = 0.0f64;
            for (c, &lc) in l.iter().enumerate() {
                let want = 2.0 * PI.sqrt() * f64::from(lc);
                assert!(
                    (sh.coeffs[0][c] - want).abs() < 1e-7 * want,
                    "{:?}",
                    sh.coeffs[0]
                );
                for k in 1..9 {
                    rest = rest.max(sh.coeffs[k][c].abs() / want);
                }
            }
            println!(
                "constant, {} {w}×{h}: L00 = 2√π·L, others ≤ {rest:.1e} × L00 (bound {bound:.1e})",
                r.mapping
            );
            assert!(rest < bound, "{rest}");
            for d in [Vec3::X, Vec3::NEG_Z, Vec3::new(1.0, 2.0, -3.0)] {
                let e = sh.irradiance_at(d, IrradianceScale::E);
                let ep = sh.irradiance_at(d, IrradianceScale::EOverPi);
                for c in 0..3 {
                    let want = PI as f32 * l[c];
                    assert!((e[c] - want).abs() < 1e-5 * want, "{e:?}");
                    assert!((ep[c] - l[c]).abs() < 1e-5 * l[c], "{ep:?}");
                }
            }
        }
    }

    #[test]
    fn the_upper_hemisphere_step_gives_its_closed_forms() {
        // Canonical z up, identity frame: the step lies on a row boundary.
        let h = 128u32;
        let r = Representation::default_for(AnyMapping::LatLong);
        let img = fill(r, 2 * h, h, |d| if d.z > 0.0 { [1.0; 3] } else { [0.0; 3] }).unwrap();
        let sh = Sh9::project(&img);
        let dt = PI / f64::from(h);
        // The midpoint rule's leading error for L10 is a relative Δθ²/8
        // (derived in the module docs); allow twice that.
        let bound = dt * dt / 4.0;
        let l00 = PI.sqrt();
        let l10 = (3.0 * PI).sqrt() / 2.0;
        let e00 = (sh.coeffs[0][0] - l00).abs() / l00;
        let e10 = (sh.coeffs[2][0] - l10).abs() / l10;
        let rest = (1..9)
            .filter(|&k| k != 2)
            .map(|k| sh.coeffs[k][0].abs())
            .fold(0.0, f64::max);
        println!("step: L00 rel. error {e00:.1e}, L10 {e10:.1e} (bound {bound:.1e}), others ≤ {rest:.1e}");
        assert!(e00 < 1e-6);
        assert!(e10 < bound);
        assert!(rest < bound * l00, "{rest}");
        let mut worst = 0.0f64;
        for k in 0..=180 {
            let t = (k as f64).to_radians();
            let d = Vec3::new(t.sin() as f32, 0.0, t.cos() as f32);
            let e = f64::from(sh.irradiance_at(d, IrradianceScale::E)[0]);
            worst = worst.max((e - PI * (1.0 + t.cos()) / 2.0).abs());
        }
        println!("step: E(θ) − π(1 + cos θ)/2 ≤ {worst:.1e}");
        assert!(worst < PI * bound, "{worst}");
    }

    #[test]
    fn the_projection_equals_the_f64_texel_sum_in_every_representation() {
        let yup = FileAxes::default();
        let turned = Frame::from_yaw_pitch_roll(0.3, -1.1, 2.0);
        let cases: Vec<(&str, Representation, u32)> = vec![
            (
                "latlong z-up",
                Representation::default_for(AnyMapping::LatLong),
                256,
            ),
            (
                "latlong y-up",
                Representation::for_file(AnyMapping::LatLong, yup),
                256,
            ),
            (
                "latlong 9-wide tail",
                Representation::for_file(AnyMapping::LatLong, yup),
                18,
            ),
            ("cube cross GL", gl_cube(), 48),
            (
                "cube vcross",
                repr(AnyMapping::Cube, Atlas::CUBE_VERTICAL_CROSS, turned),
                48,
            ),
            (
                "cube strip 17",
                repr(
                    AnyMapping::Cube,
                    Atlas::CUBE_HORIZONTAL_STRIP,
                    Frame::IDENTITY,
                ),
                17,
            ),
            (
                "octahedral",
                Representation::for_file(AnyMapping::Octahedral, yup),
                100,
            ),
            (
                "equal-area oct.",
                repr(
                    AnyMapping::EqualAreaOctahedral,
                    Atlas::SINGLE_SQUARE,
                    turned,
                ),
                100,
            ),
            (
                "sphere map",
                Representation::for_file(AnyMapping::SphereMap, yup),
                100,
            ),
            (
                "sphere map GL",
                Representation::for_file(AnyMapping::SphereMapGl, yup),
                100,
            ),
            (
                "paraboloid",
                Representation::for_file(AnyMapping::DualParaboloid, yup),
                100,
            ),
            (
                "angular",
                Representation::for_file(AnyMapping::Angular, yup),
                100,
            ),
            (
                "tennisball",
                Representation::for_file(AnyMapping::Tennisball, yup),
                99,
            ),
        ];
        let mut overall = (0.0, String::new());
        for (name, r, cw) in cases {
            let (w, h) = r.size_for_cell_width(cw).unwrap();
            for (env, f) in [("smooth", smooth as fn(Vec3) -> [f32; 3]), ("sun", sunny)] {
                let img = fill(r, w, h, f).unwrap();
                let ours = Sh9::project(&img);
                let refr = reference(&img);
                let (e, i, c) = worst(&ours, &refr);
                if e > overall.0 {
                    overall = (e, format!("{name} {w}×{h} {env}, {} channel {c}", NAMES[i]));
                }
                assert!(
                    e < 1e-5,
                    "{name} {env}: {e:.2e} at {} channel {c}",
                    NAMES[i]
                );
            }
        }
        println!(
            "SH9 vs the f64 texel sum: worst {:.2e} × |L00| ({})",
            overall.0, overall.1
        );
    }

    #[test]
    fn the_separable_latlong_sums_equal_the_generic_loop() {
        let r = Representation::for_file(AnyMapping::LatLong, FileAxes::default());
        for w in [16u32, 18, 34, 512] {
            let img = fill(r, w, w / 2, sunny).unwrap();
            let (a, _) = native_sums(&img, Path::Fast);
            let (b, _) = native_sums(&img, Path::Generic);
            let (a, b) = (from_native(a, r.frame), from_native(b, r.frame));
            let (e, i, c) = worst(&a, &b);
            assert!(e < 1e-6, "{w}: {e:.2e} at {} {c}", NAMES[i]);
        }
    }

    #[test]
    fn non_finite_texels_are_skipped_and_counted() {
        for r in [
            Representation::for_file(AnyMapping::LatLong, FileAxes::default()),
            gl_cube(),
        ] {
            let (w, h) = r.size_for_cell_width(64).unwrap();
            let clean = fill(r, w, h, smooth).unwrap();
            let mut bad = clean.clone();
            let mut zeroed = clean.clone();
            let mut n = 0;
            for (k, (p, z)) in bad
                .pixels_mut()
                .iter_mut()
                .zip(zeroed.pixels_mut())
                .enumerate()
            {
                if k % 97 == 3 && *p != [0.0; 3] {
                    p[k % 3] = [f32::NAN, f32::INFINITY, f32::NEG_INFINITY][k % 3];
                    *z = [0.0; 3];
                    n += 1;
                }
            }
            let got = Sh9::project_detailed(&bad);
            assert_eq!(got.skipped, n);
            assert!(got.sh.coeffs.iter().flatten().all(|v| v.is_finite()));
            let (e, _, _) = worst(&got.sh, &Sh9::project(&zeroed));
            assert!(e < 1e-6, "{e}");
            assert_eq!(Sh9::project_detailed(&clean).skipped, 0);
        }
    }

    fn random_sh(seed: u64) -> Sh9 {
        let mut rng = crate::instruments::Pcg32::new(seed);
        let mut next = || f64::from(rng.next_f32()) * 2.0 - 1.0;
        Sh9 {
            coeffs: core::array::from_fn(|_| [next(), next(), next()]),
            kind: ShKind::Radiance,
        }
    }

    fn dirs(n: u32) -> Vec<[f64; 3]> {
        let golden = PI * (3.0 - 5f64.sqrt());
        (0..n)
            .map(|k| {
                let z = 1.0 - (2.0 * f64::from(k) + 1.0) / f64::from(n);
                let r = (1.0 - z * z).sqrt();
                let (s, c) = (golden * f64::from(k)).sin_cos();
                [r * c, r * s, z]
            })
            .collect()
    }

    #[test]
    fn rotations_and_reflections_are_exact() {
        let q = Quat::from_axis_angle(Vec3::new(0.3, -0.7, 0.2).normalize(), 2.1);
        let rot = envmap_core::glam::Mat3::from_quat(q).as_dmat3();
        let rot = orthonormalize(rot).unwrap();
        let mirror = DMat3::from_diagonal(DVec3::new(-1.0, 1.0, 1.0));
        let mut worst_err = 0.0f64;
        for (k, m) in [rot, mirror * rot, Frame::Y_UP_LH.matrix().as_dmat3()]
            .into_iter()
            .enumerate()
        {
            let sh = random_sh(k as u64 + 1);
            let g = sh.transformed(m.transpose().to_cols_array_2d()).unwrap();
            for d in dirs(500) {
                let md = (m * DVec3::from_array(d)).to_array();
                let (a, b) = (g.eval_f64(d), sh.eval_f64(md));
                for c in 0..3 {
                    worst_err = worst_err.max((a[c] - b[c]).abs());
                }
            }
        }
        println!("g(d) = f(m·d) through the rotated coefficients: worst {worst_err:.1e}");
        assert!(worst_err < 1e-13);
        // Not orthogonal, not finite: refused.
        let skew = [[1.0, 0.01, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        assert!(random_sh(9).transformed(skew).is_none());
        assert!(random_sh(9).transformed([[f64::NAN; 3]; 3]).is_none());
    }

    #[test]
    fn the_y_up_coefficients_are_the_canonical_ones_with_the_axes_renamed() {
        // y-up (x, y, z) is canonical (x, −z, y): the y-up y term is the
        // canonical z term, the y-up z term minus the canonical y term.
        let sh = random_sh(3);
        let y = sh.to_y_up();
        for c in 0..3 {
            let k = &sh.coeffs;
            assert!((y.coeffs[0][c] - k[0][c]).abs() < 1e-15);
            assert!((y.coeffs[1][c] - k[2][c]).abs() < 1e-15); // y ← z
            assert!((y.coeffs[2][c] + k[1][c]).abs() < 1e-15); // z ← −y
            assert!((y.coeffs[3][c] - k[3][c]).abs() < 1e-15); // x ← x
            assert!((y.coeffs[4][c] - k[7][c]).abs() < 1e-15); // xy ← xz
            assert!((y.coeffs[7][c] + k[4][c]).abs() < 1e-15); // xz ← −xy
            assert!((y.coeffs[5][c] + k[5][c]).abs() < 1e-15); // yz ← −zy
        }
        for d in dirs(200) {
            let n = Vec3::new(d[0] as f32, d[1] as f32, d[2] as f32);
            let a = y.eval(n);
            let b = sh.eval(Frame::Y_UP_RH.to_canonical(n));
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn the_filament_form_evaluates_e_over_pi_in_y_up_axes() {
        let sh = random_sh(5);
        let f = sh.filament_shader_form();
        let mut worst_err = 0.0f64;
        for d in dirs(300) {
            let [x, y, z] = d;
            let terms = [
                1.0,
                y,
                z,
                x,
                y * x,
                y * z,
                3.0 * z * z - 1.0,
                z * x,
                x * x - y * y,
            ];
            let n = Vec3::new(x as f32, y as f32, z as f32);
            let canon = Frame::Y_UP_RH.to_canonical(n);
            let want = sh.irradiance().eval_f64(canon.as_dvec3().to_array());
            for c in 0..3 {
                let got: f64 = (0..9).map(|i| f[i][c] * terms[i]).sum();
                worst_err = worst_err.max((got - want[c] / PI).abs());
            }
        }
        assert!(worst_err < 1e-6, "{worst_err}");
        // A y-up file's upper hemisphere: E/π = ½ + ½·y, in the form's terms.
        let r = gl_cube();
        let img = fill(r, 4 * 32, 3 * 32, |d| {
            let y_up = Frame::Y_UP_RH.from_canonical(d);
            if y_up.y > 0.0 {
                [1.0; 3]
            } else {
                [0.0; 3]
            }
        })
        .unwrap();
        let f = Sh9::project(&img).filament_shader_form();
        let want = [0.5, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0];
        for i in 0..9 {
            assert!((f[i][0] - want[i]).abs() < 2e-4, "sh{i} = {}", f[i][0]);
        }
    }

    #[test]
    fn a_bright_top_half_lights_plus_y_brightest() {
        // A y-up latlong file (envmap's default conventions) whose top half
        // is bright: the irradiance cube's +y face (chart 2) is brightest.
        let r = Representation::for_file(AnyMapping::LatLong, FileAxes::default());
        let (w, h) = (128u32, 64u32);
        let mut img = EnvImage::new(w, h, r).unwrap();
        for (y, row) in img.rows_mut().enumerate() {
            row.fill(if (y as u32) < h / 2 {
                [4.0; 3]
            } else {
                [0.5; 3]
            });
        }
        let sh = Sh9::project(&img);
        let cube = irradiance_cube(&sh, IrradianceScale::default()).unwrap();
        let means: Vec<f64> = (0..6)
            .map(|k| {
                let f = cube.chart_image(k).unwrap();
                f.pixels.iter().map(|p| f64::from(p[1])).sum::<f64>() / f.pixels.len() as f64
            })
            .collect();
        let best = (0..6)
            .max_by(|&a, &b| means[a].total_cmp(&means[b]))
            .unwrap();
        assert_eq!(best, 2, "{means:?}");
        // And the brightest texel of the whole cube is on +y, and in the
        // y-up coefficients E(+y) is the largest of the six axes.
        let y = sh.to_y_up();
        let axes = [
            [1.0, 0.0, 0.0],
            [-1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.0, 0.0, -1.0],
        ];
        let e: Vec<f64> = axes
            .iter()
            .map(|&a| y.irradiance().eval_f64(a)[0])
            .collect();
        assert_eq!(
            (0..6).max_by(|&a, &b| e[a].total_cmp(&e[b])).unwrap(),
            2,
            "{e:?}"
        );
        // E/π on +y: ∫ over the hemisphere facing +y = 4·(1 − 1/8)... the
        // step's closed form, scaled: 0.5 + (4 − 0.5)·(1 + 1)/2... simply
        // between the two radiances, and nearer the bright one.
        let top = cube.chart_image(2).unwrap().pixels[32 * 16 + 16][0];
        assert!(top > 3.0 && top < 4.0, "{top}");
    }

    #[test]
    fn the_sinc4_window_is_cmgens() {
        assert_eq!(sinc4_window(0, 3.0), 1.0);
        assert_eq!(sinc4_window(3, 3.0), 0.0);
        assert_eq!(sinc4_window(1, f64::INFINITY), 1.0);
        assert_eq!(sinc4_window(1, f64::NAN), 0.0);
        assert_eq!(sinc4_window(1, -2.0), 0.0);
        // cmgen 1.9.25's default window on two maps that need none:
        // band 1 × 0.96036 (upper hemisphere 0.480082/0.499898), band 2 ×
        // 0.84977 (1 + xy: 0.212650/0.250242). The first gives the cutoff,
        // 12.7673; the window's shape must then give the second.
        assert!((sinc4_window(1, 12.7673) - 0.480082 / 0.499898).abs() < 2e-6);
        assert!((sinc4_window(2, 12.7673) - 0.212650 / 0.250242).abs() < 2e-5);
        let x = PI / 5.0;
        assert!((sinc4_window(1, 5.0) - (x.sin() / x).powi(4)).abs() < 1e-16);
    }

    #[test]
    fn the_minimum_search_finds_the_minimum() {
        let dense = dirs(200_000);
        let mut worst_gap = 0.0f64;
        for seed in 0..40 {
            let sh = random_sh(100 + seed).irradiance();
            for c in 0..3 {
                let q = Quadric::of(&sh, c);
                let (found, at) = q.minimum();
                let brute = dense
                    .iter()
                    .map(|&d| sh.eval_f64(d)[c])
                    .fold(f64::INFINITY, f64::min);
                // The value reported is the function's at the point reported.
                assert!((sh.eval_f64(at.to_array())[c] - found).abs() < 1e-12);
                // Never above the dense search, and not far below it: the
                // dense points are ≤ 0.006 rad apart.
                assert!(found <= brute + 1e-12, "{found} {brute}");
                worst_gap = worst_gap.max(brute - found);
                assert!(brute - found < 1e-3, "{found} {brute}");
            }
        }
        println!("minimum search: dense 2·10⁵-point minimum − ours ≤ {worst_gap:.1e}");
        // A zonal quadratic's closed form: E(z) = 1 + 0.5z + 0.8(3z² − 1)
        // has its minimum at z = −0.5/4.8.
        let mut sh = Sh9::zero(ShKind::Irradiance);
        for c in 0..3 {
            sh.coeffs[0][c] = 1.0 / Y00;
            sh.coeffs[2][c] = 0.5 / Y1;
            sh.coeffs[6][c] = 0.8 / Y20;
        }
        let z = -0.5 / 4.8;
        let want = 1.0 + 0.5 * z + 0.8 * (3.0 * z * z - 1.0);
        let (got, at) = sh.irradiance_minimum()[0];
        assert!((got - want).abs() < 1e-12, "{got} {want}");
        assert!((at[2] - z).abs() < 1e-6, "{at:?}");
    }

    #[test]
    fn the_auto_window_removes_negative_irradiance_and_only_then() {
        let r = gl_cube();
        let (w, h) = r.size_for_cell_width(64).unwrap();
        // A sun 50 000 times the sky: its SH9 irradiance rings below zero.
        let sh = Sh9::project(&fill(r, w, h, sunny).unwrap());
        let before = sh
            .irradiance_minimum()
            .iter()
            .map(|m| m.0)
            .fold(f64::INFINITY, f64::min);
        assert!(before < 0.0, "{before}");
        let cutoff = sh.auto_cutoff().unwrap();
        let win = sh.windowed(ShWindow::Auto);
        assert_eq!(win, sh.windowed(ShWindow::Sinc4 { cutoff }));
        let e = win.irradiance();
        let lowest = dirs(100_000)
            .iter()
            .flat_map(|&d| e.eval_f64(d))
            .fold(f64::INFINITY, f64::min);
        let scale = e.coeffs[0][0] * Y00;
        println!("sun: SH9 min E {before:.3}, window cutoff {cutoff:.4}, windowed min {lowest:.2e} (E mean {scale:.1})");
        assert!(lowest >= -1e-9 * scale, "{lowest}");
        // The cutoff is the boundary: a little wider rings again.
        let wider = sh.windowed(ShWindow::Sinc4 {
            cutoff: cutoff * 1.001,
        });
        assert!(wider.irradiance_minimum().iter().any(|m| m.0 < 0.0));
        // A smooth map needs no window: Auto changes nothing.
        let smooth_sh = Sh9::project(&fill(r, w, h, smooth).unwrap());
        assert_eq!(smooth_sh.auto_cutoff(), None);
        assert_eq!(smooth_sh.windowed(ShWindow::Auto), smooth_sh);
        // cmgen's default windows both: the smooth map at its measured
        // cutoff, the sun at the auto cutoff (below that one).
        assert_eq!(
            ShWindow::Cmgen.cutoff(&smooth_sh),
            Some(CMGEN_SMOOTH_CUTOFF)
        );
        assert!(cutoff < CMGEN_SMOOTH_CUTOFF);
        assert_eq!(ShWindow::Cmgen.cutoff(&sh), Some(cutoff));
        let f = smooth_sh.windowed(ShWindow::Cmgen);
        for (i, want) in [(1, 0.96036), (6, 0.84978)] {
            let ratio = f.coeffs[i][0] / smooth_sh.coeffs[i][0];
            assert!((ratio - want).abs() < 2e-5, "band of {i}: {ratio}");
        }
        // Windowing commutes with the convolution.
        let a = sh.windowed(ShWindow::Auto).irradiance();
        let b = sh.irradiance().windowed(ShWindow::Sinc4 { cutoff });
        assert!(worst(&a, &b).0 < 1e-15);
    }

    #[test]
    fn bad_input_gives_documented_results() {
        let sh = random_sh(7);
        assert!(sh.eval(Vec3::ZERO).iter().all(|v| v.is_nan()));
        assert!(sh.eval(Vec3::NAN).iter().all(|v| v.is_nan()));
        assert!(basis([1e-310, 0.0, 0.0]).iter().all(|v| v.is_finite()));
        assert!(basis([f64::MAX, f64::MAX, 0.0])
            .iter()
            .all(|v| v.is_finite()));
        let mut nan = sh;
        nan.coeffs[4][1] = f64::NAN;
        assert_eq!(nan.auto_cutoff(), None);
        // Tiny images.
        for r in [
            Representation::default_for(AnyMapping::LatLong),
            gl_cube(),
            Representation::default_for(AnyMapping::DualParaboloid),
        ] {
            let (w, h) = r.size_for_cell_width(r.atlas.cell_aspect_w.max(1)).unwrap();
            let img = fill(r, w, h, |_| [1.0; 3]).unwrap();
            let p = Sh9::project(&img);
            assert!(p.coeffs.iter().flatten().all(|v| v.is_finite()));
            let m = irradiance_map(&p, r, w, h, IrradianceScale::E).unwrap();
            assert!(m.pixels().iter().flatten().all(|v| v.is_finite()));
        }
        // A size that does not fit: an error, not a panic.
        assert!(irradiance_map(&sh, gl_cube(), 10, 10, IrradianceScale::E).is_err());
    }
}
