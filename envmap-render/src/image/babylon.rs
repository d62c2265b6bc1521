//! Babylon.js environment files (`.env`), written and read as Babylon.js
//! itself writes and reads them (`Misc/environmentTextureTools.ts`).
//!
//! A file is the 8 bytes `86 16 87 96 F6 D6 96 36`, a JSON manifest ended
//! by a NUL byte, then one PNG per face per level, largest level first and
//! the faces in GL order (+X, −X, +Y, −Y, +Z, −Z) within each. The
//! manifest (version 2) holds:
//!
//! - `width`: level 0's face size, a power of two;
//! - `imageType`: `"image/png"` (envmap writes PNG; it reads no WebP);
//! - `specular.mipmaps`: `{length, position}` of every image, the
//!   position counted from the byte after the NUL; 6·(log2 width + 1)
//!   of them, the full chain down to 1×1, which is the only count
//!   Babylon.js loads;
//! - `specular.lodGenerationScale`: Babylon.js's rule from roughness to
//!   level, lod = scale·log2(width·α) (its PBR shader's `getLodFromAlphaG`;
//!   α = roughness²), 0.8 unless said;
//! - `irradiance`: the nine RGB terms `x, y, z, xx, yy, zz, yz, zx, xy`
//!   of Babylon.js's `SphericalPolynomial`.
//!
//! Texels are RGBD ([`TexelFormat::Rgbd8`]): 8-bit RGBA PNG holding
//! values 0 … 255; brighter texels (a sun) are clipped at 255, counted, and
//! the energy lost reported by the bake.
//!
//! **The irradiance polynomial.** Babylon.js (`cubemapToSphericalPolynomial.ts`)
//! projects the radiance on its SH basis (Condon–Shortley signs: the
//! terms of L1−1, L11, L2−1 and L21 negated against envmap's
//! Ramamoorthi–Hanrahan basis), convolves with the clamped cosine and
//! divides by π (coefficients of E/π), then folds them into the
//! polynomial with `SphericalPolynomial.FromHarmonics`. Its renderer
//! undoes that fold (`SphericalHarmonics.FromPolynomial`,
//! `preScaleForRendering`) and evaluates E/π at the normal. envmap writes
//! the terms that unfold gives E/π back from exactly (its inverse, in f64;
//! Babylon.js's own fold has a constant off by 6·10⁻⁵), from envmap's SH
//! of the source (not clamped at 4096 as Babylon.js clamps its own), in
//! the cube's axes.

use std::path::Path;

use serde_json::{json, Value};

use crate::error::{Error, Result};
use crate::filter::sh::Sh9;
use crate::image::format::{decode_error, whole, Codec, Contents, FileFormat, Source};
use crate::image::texel::{Clamped, TexelFormat};
use crate::image::texture::{Texture, TextureFile, TextureInfo, TextureKind, TextureOptions};
use crate::image::RgbImage;

/// The first 8 bytes of every `.env` file.
pub(crate) const MAGIC: [u8; 8] = [0x86, 0x16, 0x87, 0x96, 0xF6, 0xD6, 0x96, 0x36];

/// Babylon.js's `lodGenerationScale` when a file gives none, and what
/// envmap writes.
pub(crate) const DEFAULT_LOD_SCALE: f32 = 0.8;

/// The manifest version envmap writes (Babylon.js's `CurrentVersion`).
const VERSION: u64 = 2;

/// The polynomial's terms, in the order the manifest lists them.
pub(crate) const TERMS: [&str; 9] = ["x", "y", "z", "xx", "yy", "zz", "yz", "zx", "xy"];

/// The codec of Babylon.js's two files of RGBD faces: `.env`
/// ([`FileFormat::Env`]) or a glTF light ([`FileFormat::Gltf`]).
pub(crate) struct Babylon(FileFormat);

/// The `.env` codec.
pub(crate) const ENV: Babylon = Babylon(FileFormat::Env);

/// The glTF image-based-light codec.
pub(crate) const GLTF: Babylon = Babylon(FileFormat::Gltf);

impl Codec for Babylon {
    fn read(&self, path: &Path, src: Source<'_>, max_texels: u64) -> Result<Contents> {
        let bytes = whole(path, self.0, src, max_texels)?;
        if self.0 == FileFormat::Gltf {
            decode_gltf(path, &bytes, max_texels).map(Contents::Chain)
        } else {
            decode(path, &bytes, max_texels).map(Contents::Chain)
        }
    }

    fn write_chain(&self, tex: &Texture, opts: TextureOptions) -> Result<(Vec<u8>, Clamped)> {
        if opts.zstd.is_some() {
            return Err(Error::options(format!(
                "{} has no supercompression; zstd is for KTX2",
                self.0.name()
            )));
        }
        let sh = level0_sh(tex)?;
        let e = if self.0 == FileFormat::Gltf {
            encode_gltf(tex, &sh)?
        } else {
            encode(tex, &sh, DEFAULT_LOD_SCALE)?
        };
        Ok((e.bytes, e.clamped))
    }
}

/// The radiance SH of a cube texture's level 0, in the cube's own axes
/// (the directions its faces are looked up by).
fn level0_sh(tex: &Texture) -> Result<Sh9> {
    check_chain(tex)?;
    let img = tex.level_image(0, None, |_| envmap_core::Frame::IDENTITY)?;
    Ok(Sh9::project(&img))
}

/// What [`encode`] made.
#[derive(Clone, Debug)]
pub(crate) struct Encoded {
    /// The file.
    pub bytes: Vec<u8>,
    /// Components outside RGBD's 0 … 255, over all levels.
    pub clamped: Clamped,
    /// Per level: the fraction of its radiant energy (Σ over channels and
    /// texels of value × solid angle) above the largest value the file
    /// holds, lost to RGBD's ceiling.
    pub clipped: Vec<f64>,
    /// A glTF light: its texels as Babylon.js sees them, decoded from the
    /// images written (a `.env` is read back by its own reader instead).
    pub seen: Option<Texture>,
}

/// Refuses a texture that is not a square power-of-two cube with its full
/// chain down to 1×1: the only `.env` Babylon.js loads.
fn check_chain(tex: &Texture) -> Result<()> {
    let (w, h) = tex.size();
    if tex.kind() != TextureKind::Cube {
        return Err(Error::unsupported(
            "a Babylon.js .env file holds a cube map; this texture is 2D",
        ));
    }
    if w != h || !w.is_power_of_two() {
        return Err(Error::dimensions(format!(
            "a Babylon.js .env cube's faces are square with a power-of-two size; these are {w}×{h}"
        )));
    }
    let full = w.trailing_zeros() as usize + 1;
    if tex.level_count() != full {
        return Err(Error::dimensions(format!(
            "a Babylon.js .env file holds every level down to 1×1 ({full} levels for {w}×{w}); this chain has {}",
            tex.level_count()
        )));
    }
    Ok(())
}

/// Babylon.js's polynomial of radiance coefficients `sh` (envmap's basis,
/// in the cube's axes): the terms from which its renderer's unfold
/// (`SphericalHarmonics.FromPolynomial`, then `preScaleForRendering` and
/// the shader's sum) gives back E/π exactly. That unfold is linear and is
/// inverted here exactly; Babylon.js's own fold (`FromHarmonics`) uses
/// constants rounded to six digits, one of them off by 6·10⁻⁵ (0.886277 for
/// π·Y00 = 0.886227), which its own files carry into the constant term.
#[must_use]
pub(crate) fn polynomial(sh: &Sh9) -> [[f64; 3]; 9] {
    let pi = core::f64::consts::PI;
    // E/π in Babylon.js's basis (Condon–Shortley signs), over π: what the
    // unfold's products with π give back.
    let e = sh.irradiance();
    let h: [[f64; 3]; 9] = core::array::from_fn(|i| e.coeffs[i].map(|v| v * SIGN[i] / (pi * pi)));
    let [l00, l1m1, l10, l11, l2m2, l2m1, l20, l21, l22] = h;
    let det = 0.376127 * 1.34567 + 0.376126 * 0.672834;
    let xx_yy: [f64; 3] = core::array::from_fn(|k| (1.34567 * l00[k] - 0.376126 * l20[k]) / det);
    let zz: [f64; 3] = core::array::from_fn(|k| (0.672834 * l00[k] + 0.376127 * l20[k]) / det);
    let d: [f64; 3] = core::array::from_fn(|k| l22[k] / 1.16538);
    let c = |f: &dyn Fn(usize) -> f64| -> [f64; 3] { core::array::from_fn(f) };
    [
        c(&|k| -l11[k] / 0.977204),
        c(&|k| -l1m1[k] / 0.977204),
        c(&|k| l10[k] / 0.977204),
        c(&|k| (xx_yy[k] + d[k]) / 2.0),
        c(&|k| (xx_yy[k] - d[k]) / 2.0),
        zz,
        c(&|k| -l2m1[k] / 1.16538),
        c(&|k| -l21[k] / 1.16538),
        c(&|k| l2m2[k] / 1.16538),
    ]
}

/// Babylon.js's SH basis against envmap's: the Condon–Shortley sign of
/// L1−1, L11, L2−1 and L21.
const SIGN: [f64; 9] = [1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0, -1.0, 1.0];

/// E/π at the unit direction `n` (the cube's axes) as Babylon.js's renderer
/// evaluates the polynomial `p`: `SphericalHarmonics.FromPolynomial`, then
/// `preScaleForRendering` and the shader's sum over its basis.
#[cfg(test)]
#[must_use]
pub(crate) fn babylon_irradiance(p: &[[f64; 3]; 9], n: [f64; 3]) -> [f64; 3] {
    let [x, y, z, xx, yy, zz, yz, zx, xy] = *p;
    let pi = core::f64::consts::PI;
    let h: [[f64; 3]; 9] = [
        core::array::from_fn(|k| (0.376127 * xx[k] + 0.376127 * yy[k] + 0.376126 * zz[k]) * pi),
        core::array::from_fn(|k| -0.977204 * y[k] * pi),
        core::array::from_fn(|k| 0.977204 * z[k] * pi),
        core::array::from_fn(|k| -0.977204 * x[k] * pi),
        core::array::from_fn(|k| 1.16538 * xy[k] * pi),
        core::array::from_fn(|k| -1.16538 * yz[k] * pi),
        core::array::from_fn(|k| (1.34567 * zz[k] - 0.672834 * xx[k] - 0.672834 * yy[k]) * pi),
        core::array::from_fn(|k| -1.16538 * zx[k] * pi),
        core::array::from_fn(|k| (1.16538 * xx[k] - 1.16538 * yy[k]) * pi),
    ];
    let [nx, ny, nz] = n;
    let t = [
        1.0,
        ny,
        nz,
        nx,
        nx * ny,
        ny * nz,
        3.0 * nz * nz - 1.0,
        nx * nz,
        nx * nx - ny * ny,
    ];
    core::array::from_fn(|k| {
        (0..9)
            .map(|i| h[i][k] * SIGN[i] * crate::filter::sh::BASIS_CONSTANTS[i] * t[i])
            .sum()
    })
}

/// The `.env` file of the cube chain `tex` (square, power of two, every
/// level down to 1×1), with the irradiance polynomial of the radiance
/// coefficients `sh` (in the cube's axes) and `lod_scale` as its
/// `lodGenerationScale`.
///
/// # Errors
///
/// Another texture; a PNG the encoder cannot write.
pub(crate) fn encode(tex: &Texture, sh: &Sh9, lod_scale: f32) -> Result<Encoded> {
    let faces = faces(tex, false)?;
    let mut mipmaps = Vec::with_capacity(faces.pngs.len());
    let mut position = 0usize;
    for b in &faces.pngs {
        mipmaps.push(json!({"length": b.len(), "position": position}));
        position += b.len();
    }
    let p = polynomial(sh);
    let irradiance: serde_json::Map<String, Value> = TERMS
        .iter()
        .zip(p)
        .map(|(name, v)| ((*name).to_owned(), json!(v)))
        .collect();
    let manifest = json!({
        "version": VERSION,
        "width": tex.size().0,
        "imageType": "image/png",
        "irradiance": irradiance,
        "specular": {
            "mipmaps": mipmaps,
            "lodGenerationScale": lod_scale,
        },
    });
    let text = serde_json::to_string(&manifest)
        .map_err(|e| Error::unsupported(format!("the .env manifest: {e}")))?;
    let mut bytes = Vec::with_capacity(MAGIC.len() + text.len() + 1 + position);
    bytes.extend_from_slice(&MAGIC);
    bytes.extend_from_slice(text.as_bytes());
    bytes.push(0);
    for b in faces.pngs {
        bytes.extend_from_slice(&b);
    }
    Ok(Encoded {
        bytes,
        clamped: faces.clamped,
        clipped: faces.clipped,
        seen: None,
    })
}

/// Every face of a chain as an RGBD PNG, level 0 first.
struct Faces {
    pngs: Vec<Vec<u8>>,
    clamped: Clamped,
    clipped: Vec<f64>,
}

/// The faces of the chain `tex` (checked first) as RGBD PNGs, with what
/// packing clamped and each level's energy clipped; with `gamma`, each
/// texel is raised to 1/2.2 first (see [`encode_gltf`]).
fn faces(tex: &Texture, gamma: bool) -> Result<Faces> {
    use crate::par::*;
    check_chain(tex)?;
    let images: Vec<(usize, &RgbImage)> = tex
        .levels()
        .iter()
        .enumerate()
        .flat_map(|(p, faces)| faces.iter().map(move |f| (p, f)))
        .collect();
    let encoded: Vec<Result<FacePng>> = images
        .par_iter()
        .enumerate()
        .map(|(k, &(_, img))| face_png(img, (k % 6) as u32, gamma))
        .collect();
    let mut clamped = Clamped::default();
    let mut energy = vec![[0.0f64; 2]; tex.level_count()];
    let mut pngs = Vec::with_capacity(images.len());
    for ((p, _), e) in images.iter().zip(encoded) {
        let (png, c, [all, above]) = e?;
        clamped.add(c);
        energy[*p][0] += all;
        energy[*p][1] += above;
        pngs.push(png);
    }
    let clipped = energy
        .iter()
        .map(|&[all, above]| if all > 0.0 { above / all } else { 0.0 })
        .collect();
    Ok(Faces {
        pngs,
        clamped,
        clipped,
    })
}

/// The glTF 2.0 file (JSON, its images inside as `data:` URIs) of one
/// image-based light (`EXT_lights_image_based`, the vendor extension
/// Babylon.js's glTF loader reads) made from the cube chain `tex` (square,
/// power of two, down to 1×1) and the radiance coefficients `sh` (in the
/// cube's axes), selected by the file's one scene, which has no nodes.
///
/// The light holds the chain's faces as RGBD PNGs (`specularImages`, per
/// level +X … −Z, rows as a `.env` holds them), `specularImageSize`, and
/// the irradiance coefficients E in Babylon.js's basis (Condon–Shortley
/// signs), `intensity` 1 and no rotation. Babylon.js's loader reads the
/// chain at lodGenerationScale = (levels − 1)/log2(size), 1 here: lod =
/// log2(size·α), [`crate::filter::specular::RoughnessRule::Log2`].
///
/// Babylon.js's loader puts the images in a `RawCubeTexture`, which keeps
/// its texture's gamma-space default: its PBR shader raises the RGBD-decoded
/// texels to 2.2 once more (`GAMMAREFLECTION`). So each texel is written as
/// RGBD of c^(1/2.2), which Babylon.js shows as c (measured in Chromium by
/// `tests/tests/babylon_browser.rs`): the light holds up to 255^2.2 ≈
/// 1.96·10⁵, at about twice RGBD's relative step.
///
/// # Errors
///
/// As [`encode`].
pub(crate) fn encode_gltf(tex: &Texture, sh: &Sh9) -> Result<Encoded> {
    use base64::Engine as _;
    let faces = faces(tex, true)?;
    let n = tex.level_count();
    let images: Vec<Value> = faces
        .pngs
        .iter()
        .map(|png| {
            json!({
                "uri": format!(
                    "data:image/png;base64,{}",
                    base64::engine::general_purpose::STANDARD.encode(png)
                ),
                "mimeType": "image/png",
            })
        })
        .collect();
    let specular: Vec<Vec<usize>> = (0..n).map(|p| (6 * p..6 * p + 6).collect()).collect();
    let e = sh.irradiance();
    let coefficients: Vec<[f64; 3]> = (0..9).map(|i| e.coeffs[i].map(|v| v * SIGN[i])).collect();
    let gltf = json!({
        "asset": {"version": "2.0", "generator": crate::image::metadata::software()},
        "extensionsUsed": ["EXT_lights_image_based"],
        "extensions": {
            "EXT_lights_image_based": {
                "lights": [{
                    "name": "environment",
                    "intensity": 1.0,
                    "irradianceCoefficients": coefficients,
                    "specularImageSize": tex.size().0,
                    "specularImages": specular,
                }],
            },
        },
        "images": images,
        "scene": 0,
        "scenes": [{"nodes": [], "extensions": {"EXT_lights_image_based": {"light": 0}}}],
    });
    let bytes =
        serde_json::to_vec(&gltf).map_err(|e| Error::unsupported(format!("the glTF JSON: {e}")))?;
    // What Babylon.js sees: each image decoded, raised to 2.2.
    let pngs: Vec<&[u8]> = faces.pngs.iter().map(Vec::as_slice).collect();
    let levels = chain_from_pngs(Path::new(""), FileFormat::Gltf, &pngs, tex.size().0, true)?;
    Ok(Encoded {
        bytes,
        clamped: faces.clamped,
        clipped: faces.clipped,
        seen: Some(Texture::new(TextureKind::Cube, levels)?),
    })
}

/// The largest value a `.env` (255) or a glTF light (255^2.2, see
/// [`encode_gltf`]) holds.
#[must_use]
pub(crate) fn ceiling(gltf: bool) -> f32 {
    if gltf {
        crate::image::texel::RGBD_MAX.powf(2.2)
    } else {
        crate::image::texel::RGBD_MAX
    }
}

/// A face's PNG, what packing clamped, its energy: all, above 255.
type FacePng = (Vec<u8>, Clamped, [f64; 2]);

/// One face as an RGBD PNG, what packing clamped, and its radiant energy:
/// [all, above 255], each Σ channel × solid angle. The PNG's rows run
/// bottom-up against the face's (its top row is the face's last, GL's
/// t = 1): Babylon.js uploads a face's image flipped
/// (`_UploadLevelsAsync`: `invertY`), and writes its own files so.
fn face_png(img: &RgbImage, face: u32, gamma: bool) -> Result<FacePng> {
    let (w, h) = (img.width, img.height);
    let mut packed = vec![0u8; img.pixels.len() * 4];
    let (clamped, ceiling) = if gamma {
        let raised: Vec<[f32; 3]> = img
            .pixels
            .iter()
            .map(|t| t.map(|v| if v > 0.0 { v.powf(1.0 / 2.2) } else { v }))
            .collect();
        let c = TexelFormat::Rgbd8.pack_into(&raised, &mut packed);
        (c, f64::from(ceiling(true)))
    } else {
        let c = TexelFormat::Rgbd8.pack_into(&img.pixels, &mut packed);
        (c, f64::from(ceiling(false)))
    };
    let row = w as usize * 4;
    let rgba: Vec<u8> = packed.chunks_exact(row).rev().flatten().copied().collect();
    let mut energy = [0.0f64; 2];
    for (k, px) in img.pixels.iter().enumerate() {
        let (i, j) = ((k as u32) % w, (k as u32) / w);
        let dw = envmap_core::Mapping::texel_solid_angle(
            &envmap_core::AnyMapping::Cube,
            face,
            i,
            j,
            w,
            h,
        );
        for &v in px {
            if v.is_finite() && v > 0.0 {
                energy[0] += f64::from(v) * dw;
                energy[1] += (f64::from(v) - ceiling).max(0.0) * dw;
            }
        }
    }
    let mut out = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut out, w, h);
        enc.set_color(png::ColorType::Rgba);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_compression(png::Compression::Balanced);
        enc.set_filter(png::Filter::Adaptive);
        let err = |e: png::EncodingError| Error::unsupported(format!("PNG encoder: {e}"));
        let mut writer = enc.write_header().map_err(err)?;
        writer.write_image_data(&rgba).map_err(err)?;
        writer.finish().map_err(err)?;
    }
    Ok((out, clamped, energy))
}

/// What a `.env` manifest says, for `envmap info` and the reader.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Manifest {
    /// The manifest's version (1 or 2).
    pub version: u64,
    /// Level 0's face size.
    pub width: u32,
    /// `specular.lodGenerationScale` (0.8 when absent).
    pub lod_scale: f64,
    /// The irradiance polynomial, if the file has one.
    pub irradiance: Option<[[f64; 3]; 9]>,
    /// Where each image is: (position from the end of the manifest, length).
    pub images: Vec<(usize, usize)>,
    /// Whether an irradiance cube follows the specular images (read past).
    pub irradiance_texture: bool,
}

/// Splits a `.env` file into its manifest and the bytes after it.
fn manifest<'a>(path: &Path, bytes: &'a [u8]) -> Result<(Manifest, &'a [u8])> {
    let bad = |m: String| decode_error(path, FileFormat::Env, m);
    if !bytes.starts_with(&MAGIC) {
        return Err(bad(
            "not a Babylon.js environment file (its first 8 bytes differ)".into(),
        ));
    }
    let rest = &bytes[MAGIC.len()..];
    let nul = rest
        .iter()
        .position(|&b| b == 0)
        .ok_or_else(|| bad("the manifest has no terminating NUL byte".into()))?;
    let value: Value = serde_json::from_slice(&rest[..nul])
        .map_err(|e| bad(format!("the manifest is not JSON: {e}")))?;
    let data = &rest[nul + 1..];
    let version = value.get("version").and_then(Value::as_u64).unwrap_or(1);
    if version > VERSION {
        return Err(bad(format!(
            "manifest version {version}; envmap reads versions 1 and 2"
        )));
    }
    let image_type = value
        .get("imageType")
        .and_then(Value::as_str)
        .unwrap_or("image/png");
    if image_type != "image/png" {
        return Err(bad(format!(
            "its images are {image_type}; envmap reads .env files of PNG images"
        )));
    }
    let width = value
        .get("width")
        .and_then(Value::as_u64)
        .and_then(|w| u32::try_from(w).ok())
        .filter(|w| w.is_power_of_two())
        .ok_or_else(|| bad("`width` is missing or not a power of two".into()))?;
    let specular = value
        .get("specular")
        .ok_or_else(|| bad("the manifest has no `specular`".into()))?;
    let lod_scale = match specular.get("lodGenerationScale").and_then(Value::as_f64) {
        Some(s) if s > 0.0 && s.is_finite() => s,
        _ => f64::from(DEFAULT_LOD_SCALE),
    };
    let mips = specular
        .get("mipmaps")
        .and_then(Value::as_array)
        .ok_or_else(|| bad("`specular.mipmaps` is missing".into()))?;
    let full = width.trailing_zeros() as usize + 1;
    if mips.len() != 6 * full {
        return Err(bad(format!(
            "`specular.mipmaps` lists {} images; a {width}² chain down to 1×1 has {}",
            mips.len(),
            6 * full
        )));
    }
    let mut images = Vec::with_capacity(mips.len());
    for (k, m) in mips.iter().enumerate() {
        let get = |key: &str| {
            m.get(key)
                .and_then(Value::as_u64)
                .and_then(|v| usize::try_from(v).ok())
        };
        let (Some(pos), Some(len)) = (get("position"), get("length")) else {
            return Err(bad(format!(
                "image {k} (level {}, face {}) has no position or length",
                k / 6,
                k % 6
            )));
        };
        if pos.checked_add(len).is_none_or(|end| end > data.len()) {
            return Err(bad(format!(
                "image {k} (level {}, face {}) runs past the end of the file ({pos} + {len} > {})",
                k / 6,
                k % 6,
                data.len()
            )));
        }
        images.push((pos, len));
    }
    let irr = value.get("irradiance");
    let irradiance = irr.and_then(|irr| {
        let mut p = [[0.0; 3]; 9];
        for (t, name) in p.iter_mut().zip(TERMS) {
            let a = irr.get(name)?.as_array()?;
            if a.len() != 3 {
                return None;
            }
            for (o, v) in t.iter_mut().zip(a) {
                *o = v.as_f64()?;
            }
        }
        Some(p)
    });
    let irradiance_texture = irr.is_some_and(|i| i.get("irradianceTexture").is_some());
    Ok((
        Manifest {
            version,
            width,
            lod_scale,
            irradiance,
            images,
            irradiance_texture,
        },
        data,
    ))
}

/// Decodes a `.env` file's `bytes` (named `path` in errors): every level's
/// faces, RGBD decoded, with what the manifest says as the texture's
/// description.
pub(crate) fn decode(path: &Path, bytes: &[u8], max_texels: u64) -> Result<TextureFile> {
    let (m, data) = manifest(path, bytes)?;
    let w = m.width;
    let full = m.images.len() / 6;
    crate::image::texture::check_texels(TextureKind::Cube, w, w, full, max_texels)
        .map_err(|e| e.in_file(path))?;
    let pngs: Vec<&[u8]> = m
        .images
        .iter()
        .map(|&(pos, len)| &data[pos..pos + len])
        .collect();
    let levels = chain_from_pngs(path, FileFormat::Env, &pngs, w, false)?;
    let level_bytes = (0..full)
        .map(|p| m.images[6 * p..6 * p + 6].iter().map(|i| i.1 as u64).sum())
        .collect();
    let mut key_values = vec![
        ("babylon.version".to_owned(), m.version.to_string()),
        (
            "babylon.lodGenerationScale".to_owned(),
            format!("{}", m.lod_scale),
        ),
    ];
    if let Some(p) = m.irradiance {
        let text = TERMS
            .iter()
            .zip(p)
            .map(|(n, v)| format!("{n} {} {} {}", v[0], v[1], v[2]))
            .collect::<Vec<_>>()
            .join("\n");
        key_values.push(("babylon.irradiance".to_owned(), text));
    }
    if m.irradiance_texture {
        key_values.push((
            "babylon.irradianceTexture".to_owned(),
            "present (not read)".to_owned(),
        ));
    }
    babylon_file(FileFormat::Env, levels, level_bytes, key_values, None)
}

/// The faces of a chain of `pngs` (six per level, level 0 `w`² first),
/// decoded (and raised to 2.2 when `gamma`, see [`encode_gltf`]) into
/// levels; errors name the level and face.
fn chain_from_pngs(
    path: &Path,
    format: FileFormat,
    pngs: &[&[u8]],
    w: u32,
    gamma: bool,
) -> Result<Vec<Vec<RgbImage>>> {
    use crate::par::*;
    let faces: Vec<Result<RgbImage>> = pngs
        .par_iter()
        .enumerate()
        .map(|(k, png)| {
            let size = (w >> (k / 6)).max(1);
            let mut img = face_from_png(png, size).map_err(|e| {
                decode_error(path, format, format!("level {} face {}: {e}", k / 6, k % 6))
            })?;
            if gamma {
                for t in &mut img.pixels {
                    *t = t.map(|v| v.powf(2.2));
                }
            }
            Ok(img)
        })
        .collect();
    let mut levels: Vec<Vec<RgbImage>> = Vec::with_capacity(pngs.len() / 6);
    for (k, f) in faces.into_iter().enumerate() {
        if k % 6 == 0 {
            levels.push(Vec::with_capacity(6));
        }
        levels[k / 6].push(f?);
    }
    Ok(levels)
}

/// Decodes a glTF file's `bytes` (named `path` in errors) holding an
/// `EXT_lights_image_based` light as [`encode_gltf`] writes one: the first
/// light's `specularImages` (a full chain, each image a `data:` URI of an
/// RGBD PNG), decoded as Babylon.js shows them (raised to 2.2), with the
/// light's other fields as the description. Images in buffers or outside
/// files are refused by name.
pub(crate) fn decode_gltf(path: &Path, bytes: &[u8], max_texels: u64) -> Result<TextureFile> {
    use base64::Engine as _;
    let bad = |m: String| decode_error(path, FileFormat::Gltf, m);
    let doc: Value = serde_json::from_slice(bytes).map_err(|e| bad(format!("JSON: {e}")))?;
    let light = &doc["extensions"]["EXT_lights_image_based"]["lights"][0];
    if light.is_null() {
        return Err(bad(
            "no EXT_lights_image_based light in the file's extensions".into(),
        ));
    }
    let w = light["specularImageSize"]
        .as_u64()
        .and_then(|w| u32::try_from(w).ok())
        .filter(|w| w.is_power_of_two())
        .ok_or_else(|| bad("specularImageSize is not a power of two".into()))?;
    let full = w.trailing_zeros() as usize + 1;
    let levels = light["specularImages"]
        .as_array()
        .ok_or_else(|| bad("the light has no specularImages".into()))?;
    if levels.len() != full {
        return Err(bad(format!(
            "{} specular levels; a {w}² chain down to 1×1 has {full}",
            levels.len()
        )));
    }
    crate::image::texture::check_texels(TextureKind::Cube, w, w, full, max_texels)
        .map_err(|e| e.in_file(path))?;
    let mut pngs = Vec::with_capacity(6 * full);
    for (p, level) in levels.iter().enumerate() {
        let faces = level
            .as_array()
            .filter(|f| f.len() == 6)
            .ok_or_else(|| bad(format!("specular level {p} does not list six images")))?;
        for (f, i) in faces.iter().enumerate() {
            let image = i
                .as_u64()
                .and_then(|i| doc["images"].get(i as usize))
                .ok_or_else(|| bad(format!("level {p} face {f}: no such image")))?;
            let uri = image["uri"].as_str().unwrap_or_default();
            let data =
                uri.strip_prefix("data:image/png;base64,").ok_or_else(|| {
                    bad(format!(
                    "level {p} face {f}: envmap reads images held as data:image/png URIs, not {}",
                    if uri.is_empty() { "buffer views" } else { "outside files" }
                ))
                })?;
            let png = base64::engine::general_purpose::STANDARD
                .decode(data)
                .map_err(|e| bad(format!("level {p} face {f}: base64: {e}")))?;
            pngs.push(png);
        }
    }
    let pngs: Vec<&[u8]> = pngs.iter().map(Vec::as_slice).collect();
    let chain = chain_from_pngs(path, FileFormat::Gltf, &pngs, w, true)?;
    let mut key_values = vec![
        (
            "gltf.intensity".to_owned(),
            light["intensity"].as_f64().unwrap_or(1.0).to_string(),
        ),
        (
            "gltf.texels".to_owned(),
            format!(
                "RGBD of c^(1/2.2), read as Babylon.js shows them (decoded, raised to 2.2): up to {:.0}",
                ceiling(true)
            ),
        ),
    ];
    if let Some(c) = light["irradianceCoefficients"].as_array() {
        let text = c
            .iter()
            .map(|v| {
                v.as_array()
                    .map(|v| {
                        v.iter()
                            .map(|x| x.to_string())
                            .collect::<Vec<_>>()
                            .join(" ")
                    })
                    .unwrap_or_default()
            })
            .collect::<Vec<_>>()
            .join("\n");
        key_values.push(("gltf.irradianceCoefficients".to_owned(), text));
    }
    let level_bytes = (0..full)
        .map(|p| pngs[6 * p..6 * p + 6].iter().map(|i| i.len() as u64).sum())
        .collect();
    let writer = doc["asset"]["generator"].as_str().map(str::to_owned);
    babylon_file(FileFormat::Gltf, chain, level_bytes, key_values, writer)
}

/// A `format` file's cube chain of RGBD `levels` as read: tagged with the
/// axes Babylon.js looks it up in, and described.
fn babylon_file(
    format: FileFormat,
    levels: Vec<Vec<RgbImage>>,
    level_bytes: Vec<u64>,
    key_values: Vec<(String, String)>,
    writer: Option<String>,
) -> Result<TextureFile> {
    // Babylon.js looks its cube up at the direction in its world
    // (left-handed, y up) on GL's face table.
    use crate::image::metadata::{format_axes, AXES, MAPPING};
    let axes = crate::image::FileAxes::Convention(
        crate::image::Convention::Envmap,
        crate::image::World::YUpLh,
    );
    let texture = Texture::new(TextureKind::Cube, levels)?.with_tags(&[
        (
            MAPPING.to_owned(),
            envmap_core::AnyMapping::Cube.to_string(),
        ),
        (AXES.to_owned(), format_axes(axes)),
    ]);
    Ok(TextureFile {
        info: TextureInfo {
            container: format.name(),
            format: TexelFormat::Rgbd8,
            kind: TextureKind::Cube,
            size: texture.size(),
            levels: texture.level_count(),
            supercompression: None,
            orientation: None,
            writer,
            key_values,
            level_bytes,
        },
        texture,
    })
}

/// One face's RGBD PNG, decoded to linear RGB with its rows turned back
/// top-down (see `face_png`); it must be `size`² RGBA (or RGB, read as
/// D = 1) in 8 bits.
fn face_from_png(bytes: &[u8], size: u32) -> std::result::Result<RgbImage, String> {
    let mut dec = png::Decoder::new(std::io::Cursor::new(bytes));
    dec.set_transformations(png::Transformations::EXPAND);
    let mut reader = dec.read_info().map_err(|e| format!("PNG: {e}"))?;
    let (w, h) = (reader.info().width, reader.info().height);
    if (w, h) != (size, size) {
        return Err(format!(
            "the image is {w}×{h}; this level's faces are {size}×{size}"
        ));
    }
    let Some(len) = reader.output_buffer_size() else {
        return Err("PNG: image too large".into());
    };
    let mut buf = vec![0u8; len];
    let frame = reader
        .next_frame(&mut buf)
        .map_err(|e| format!("PNG: {e}"))?;
    if frame.bit_depth != png::BitDepth::Eight {
        return Err(format!(
            "{:?}-bit samples; RGBD images are 8-bit",
            frame.bit_depth
        ));
    }
    let channels = match frame.color_type {
        png::ColorType::Rgba => 4,
        png::ColorType::Rgb => 3,
        other => return Err(format!("{other:?} pixels; RGBD images are RGBA")),
    };
    let row = w as usize * channels;
    let pixels = buf[..frame.buffer_size()]
        .chunks_exact(row)
        .rev()
        .flat_map(|r| r.chunks_exact(channels))
        .map(|c| {
            let a = if channels == 4 { c[3] } else { 255 };
            crate::image::texel::unpack_rgbd([c[0], c[1], c[2], a])
        })
        .collect();
    Ok(RgbImage {
        width: w,
        height: h,
        pixels,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::filter::sh::ShKind;

    /// Babylon.js's renderer gives back E/π from the polynomial envmap
    /// writes, for every basis function alone and in both signs, to
    /// rounding.
    #[test]
    fn babylons_chain_gives_back_e_over_pi() {
        let dirs = [
            [1.0, 0.0, 0.0],
            [0.0, -1.0, 0.0],
            [0.6, 0.0, 0.8],
            [-0.48, 0.6, 0.64],
            [0.0, 0.6, -0.8],
        ];
        for i in 0..9 {
            for sign in [1.0, -1.0] {
                let mut sh = Sh9::zero(ShKind::Radiance);
                sh.coeffs[i] = [sign, 2.0 * sign, 0.5];
                let p = polynomial(&sh);
                for d in dirs {
                    let want = sh.irradiance().eval_f64(d);
                    let got = babylon_irradiance(&p, d);
                    for c in 0..3 {
                        let w = want[c] / core::f64::consts::PI;
                        assert!(
                            (got[c] - w).abs() <= 1e-12 * (1.0 + w.abs()),
                            "term {i} dir {d:?}: {} against {w}",
                            got[c]
                        );
                    }
                }
            }
        }
    }
}
