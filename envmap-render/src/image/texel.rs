// GPU texel formats and their packers: what a KTX2, DDS or KTX 1 file's
// texels are, bit for bit.

mod words;

#[cfg(not(feature = "instruments"))]
pub(crate) use words::unpack_b10g11r11;
#[cfg(feature = "instruments")]
pub use words::unpack_b10g11r11;
pub(crate) use words::{
    clamp_counted, f16, pack_b10g11r11, pack_rgb9e5, pack_rgbd, unpack_rgb9e5, unpack_rgbd,
};

/// A texel format a GPU samples directly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum TexelFormat {
    /// `R16G16B16A16_SFLOAT`: binary16 RGBA, 8 bytes.
    Rgba16f,
    /// `R32G32B32A32_SFLOAT`: binary32 RGBA, 16 bytes.
    Rgba32f,
    /// `B10G11R11_UFLOAT_PACK32`: R 11 bits (bits 0-10), G 11 bits
    /// (11-21), B 10 bits (22-31), unsigned floats, 4 bytes.
    B10g11r11,
    /// `E5B9G9R9_UFLOAT_PACK32`: 9-bit mantissas R (bits 0-8), G (9-17),
    /// B (18-26) with a shared 5-bit exponent (27-31), 4 bytes.
    E5b9g9r9,
    /// `R16G16B16_SFLOAT`: binary16 RGB, 6 bytes (read only).
    Rgb16f,
    /// `R32G32B32_SFLOAT`: binary32 RGB, 12 bytes (read only).
    Rgb32f,
    /// `BC6H_UFLOAT_BLOCK`: unsigned HDR RGB compressed in blocks of 4×4
    /// texels, 16 bytes each (one byte per texel), as Direct3D 11 defines
    /// it. Lossy: each block holds two or four endpoints and an index per
    /// texel; what a file loses is measured on writing (see
    /// [Texel formats](crate::image#texel-formats)).
    Bc6h,
    /// RGBD in 8-bit RGBA, Babylon.js's encoding of HDR in 8 bits (its
    /// `toRGBD`/`fromRGBD`): with m the largest channel,
    /// D = ⌊max(255/m, 1)⌋/255, rgb = (c·D)^(1/2.2) and a = D, each
    /// rounded to 8 bits; decoded as rgb^2.2 / a. Holds 0 … 255, with
    /// about 0.6 % relative precision above 1 and 8-bit gamma-2.2 steps
    /// below. Lossy; written into Babylon.js `.env` files only, as PNG
    /// ([`FileFormat::Env`](crate::image::FileFormat::Env)).
    Rgbd8,
}

/// What packing changed: components clamped, by cause.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Clamped {
    /// Components above the format's largest finite value (including +∞),
    /// written as that value.
    pub above: u64,
    /// Negative components (−∞ included) of an unsigned format, written as 0;
    /// for the signed half formats, components below −65504, written as
    /// −65504.
    pub below: u64,
    /// NaN components, written as 0.
    pub nan: u64,
}

impl std::iter::Sum for Clamped {
    fn sum<I: Iterator<Item = Clamped>>(iter: I) -> Clamped {
        iter.fold(Clamped::default(), |mut a, b| {
            a.add(b);
            a
        })
    }
}

impl Clamped {
    /// Whether nothing was clamped.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn is_empty(&self) -> bool {
        self.above == 0 && self.below == 0 && self.nan == 0
    }

    /// All components clamped.
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn total(&self) -> u64 {
        self.above + self.below + self.nan
    }

    /// Adds `other`'s counts to these.
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    pub(crate) fn add(&mut self, other: Clamped) {
        self.above += other.above;
        self.below += other.below;
        self.nan += other.nan;
    }

    /// One line for a summary: "none", or what was clamped (`max` is the
    /// format's largest value).
    #[must_use]
    pub fn describe(&self, format: TexelFormat) -> String {
        if self.is_empty() {
            return "none".to_owned();
        }
        let mut parts = Vec::new();
        if self.above > 0 {
            parts.push(format!(
                "{} components above {} clamped to it",
                self.above,
                format.max_value()
            ));
        }
        if self.below > 0 {
            parts.push(if format.is_unsigned() {
                format!("{} negative components written as 0", self.below)
            } else {
                format!("{} components below -65504 clamped to it", self.below)
            });
        }
        if self.nan > 0 {
            parts.push(format!("{} NaN components written as 0", self.nan));
        }
        parts.join(", ")
    }
}

/// How hard the BC6H encoder searches for each block's mode, partition and
/// endpoints: each is one of the presets of Intel's ISPC texture
/// compressor, whose kernel `block_compression` ports. Every setting but
/// [`Bc6hQuality::VerySlow`] then encodes again at `VerySlow` the few
/// blocks that decode with more than about 3 % relative RMS error (a sun's,
/// a sharp edge's), and keeps whichever decodes closer. So the default,
/// `VeryFast`, comes close to `VerySlow` in a fraction of its time
/// (`docs/engines.md` has the errors per level, the times and the command
/// that prints them).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum Bc6hQuality {
    /// One-region modes, no refinement (ISPC's `very_fast`).
    #[default]
    VeryFast,
    /// One-region modes and the likeliest two-region partitions, one
    /// refinement pass (ISPC's `fast`).
    Fast,
    /// Both kinds of region, two refinement passes (ISPC's `basic`).
    Basic,
    /// Every mode, the ten likeliest partitions (ISPC's `slow`).
    Slow,
    /// Every mode and all 32 partitions (ISPC's `very_slow`).
    VerySlow,
}

impl Bc6hQuality {
    /// The names accepted by [`Bc6hQuality::parse`], for messages.
    pub const NAMES: &'static str = "very-fast, fast, basic, slow, very-slow";

    /// Every setting, fastest first.
    pub const ALL: [Bc6hQuality; 5] = [
        Bc6hQuality::VeryFast,
        Bc6hQuality::Fast,
        Bc6hQuality::Basic,
        Bc6hQuality::Slow,
        Bc6hQuality::VerySlow,
    ];

    /// The name (`"basic"`, ...).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Bc6hQuality::VeryFast => "very-fast",
            Bc6hQuality::Fast => "fast",
            Bc6hQuality::Basic => "basic",
            Bc6hQuality::Slow => "slow",
            Bc6hQuality::VerySlow => "very-slow",
        }
    }

    /// The setting by its name (`very-fast`, `fast`, `basic`, `slow`,
    /// `very-slow`; `_` for `-` too).
    ///
    /// # Errors
    ///
    /// An unknown name, listing the accepted ones.
    pub fn parse(name: &str) -> crate::Result<Self> {
        let n = name.to_ascii_lowercase().replace('_', "-");
        Self::ALL
            .into_iter()
            .find(|q| q.name() == n)
            .ok_or_else(|| crate::Error::UnknownName {
                what: "BC6H quality",
                name: name.to_owned(),
                expected: Self::NAMES.to_owned(),
            })
    }
}

/// Why BC6H is refused in a build without it.
#[cfg_attr(not(any(feature = "ktx2", feature = "dds")), allow(dead_code))]
pub(crate) const NO_BC6H: &str =
    "BC6H needs envmap-render's `bc6h` feature (on by default; this build has it off)";

/// Why a KTX2, DDS or KTX 1 writer refuses RGBD.
#[cfg_attr(
    not(any(feature = "ktx2", feature = "dds", feature = "ktx1")),
    allow(dead_code)
)]
pub(crate) const RGBD_IN_ENV: &str =
    "RGBD is written into Babylon.js .env files only (envmap bake --target babylon); KTX2, DDS and KTX 1 hold rgba16f, rgba32f, rg11b10f, rgb9e5 or bc6h";

/// The largest finite binary16 value.
pub const F16_MAX: f32 = 65504.0;
/// The largest RGB9E5 value: (2⁹ − 1)/2⁹ · 2^(31 − 15) (`EXT_texture_shared_exponent`).
pub const RGB9E5_MAX: f32 = 65408.0;
/// The largest unsigned 11-bit float: (2 − 2⁻⁶) · 2¹⁵.
pub const UF11_MAX: f32 = 65024.0;
/// The largest unsigned 10-bit float: (2 − 2⁻⁵) · 2¹⁵.
pub const UF10_MAX: f32 = 64512.0;
/// The largest value RGBD holds: 255 (D = 1/255, rgb = 1).
pub const RGBD_MAX: f32 = 255.0;

impl TexelFormat {
    /// The formats envmap writes into KTX2 and DDS files (RGBD,
    /// [`TexelFormat::Rgbd8`], goes into Babylon.js `.env` files only).
    pub const WRITABLE: [TexelFormat; 5] = [
        TexelFormat::Rgba16f,
        TexelFormat::Rgba32f,
        TexelFormat::B10g11r11,
        TexelFormat::E5b9g9r9,
        TexelFormat::Bc6h,
    ];

    /// The names accepted by [`TexelFormat::parse`], for messages.
    pub const NAMES: &'static str = "rgba16f, rgba32f, rg11b10f, rgb9e5, bc6h, rgbd";

    /// The format by its name: `rgba16f`, `rgba32f`, `rg11b10f` (also
    /// `r11g11b10f`, `b10g11r11`), `rgb9e5` (also `e5b9g9r9`), `bc6h`
    /// (also `bc6h-ufloat`), `rgbd` (also `rgbd8`).
    ///
    /// # Errors
    ///
    /// An unknown name, listing the accepted ones.
    pub fn parse(name: &str) -> crate::Result<Self> {
        Ok(match name.to_ascii_lowercase().as_str() {
            "rgba16f" | "rgba16" | "f16" => TexelFormat::Rgba16f,
            "rgba32f" | "rgba32" | "f32" => TexelFormat::Rgba32f,
            "rg11b10f" | "r11g11b10f" | "b10g11r11" | "rg11b10" => TexelFormat::B10g11r11,
            "rgb9e5" | "e5b9g9r9" => TexelFormat::E5b9g9r9,
            "bc6h" | "bc6h-ufloat" | "bc6h_ufloat" | "bc6hu" => TexelFormat::Bc6h,
            "rgbd" | "rgbd8" => TexelFormat::Rgbd8,
            _ => {
                return Err(crate::Error::UnknownName {
                    what: "texel format",
                    name: name.to_owned(),
                    expected: Self::NAMES.to_owned(),
                })
            }
        })
    }

    /// The short name (`"rgba16f"`, `"rgb9e5"`, ...).
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            TexelFormat::Rgba16f => "rgba16f",
            TexelFormat::Rgba32f => "rgba32f",
            TexelFormat::B10g11r11 => "rg11b10f",
            TexelFormat::E5b9g9r9 => "rgb9e5",
            TexelFormat::Rgb16f => "rgb16f",
            TexelFormat::Rgb32f => "rgb32f",
            TexelFormat::Bc6h => "bc6h",
            TexelFormat::Rgbd8 => "rgbd",
        }
    }

    /// The Vulkan name (`"R16G16B16A16_SFLOAT"`, ...).
    #[must_use]
    pub const fn vk_name(self) -> &'static str {
        match self {
            TexelFormat::Rgba16f => "R16G16B16A16_SFLOAT",
            TexelFormat::Rgba32f => "R32G32B32A32_SFLOAT",
            TexelFormat::B10g11r11 => "B10G11R11_UFLOAT_PACK32",
            TexelFormat::E5b9g9r9 => "E5B9G9R9_UFLOAT_PACK32",
            TexelFormat::Rgb16f => "R16G16B16_SFLOAT",
            TexelFormat::Rgb32f => "R32G32B32_SFLOAT",
            TexelFormat::Bc6h => "BC6H_UFLOAT_BLOCK",
            TexelFormat::Rgbd8 => "R8G8B8A8_UNORM",
        }
    }

    /// wgpu's name (`wgpu::TextureFormat`'s variant, as in wgpu 24–27:
    /// `"Rgba16Float"`, `"Rgba32Float"`, `"Rg11b10Ufloat"`,
    /// `"Rgb9e5Ufloat"`, `"Bc6hRgbUfloat"`, the last with
    /// `Features::TEXTURE_COMPRESSION_BC`), if wgpu has the format (it has
    /// no three-channel float formats).
    #[must_use]
    pub const fn wgpu_name(self) -> Option<&'static str> {
        match self {
            TexelFormat::Rgba16f => Some("Rgba16Float"),
            TexelFormat::Rgba32f => Some("Rgba32Float"),
            TexelFormat::B10g11r11 => Some("Rg11b10Ufloat"),
            TexelFormat::E5b9g9r9 => Some("Rgb9e5Ufloat"),
            TexelFormat::Bc6h => Some("Bc6hRgbUfloat"),
            TexelFormat::Rgbd8 => Some("Rgba8Unorm"),
            TexelFormat::Rgb16f | TexelFormat::Rgb32f => None,
        }
    }

    /// The `DXGI_FORMAT` name (`"DXGI_FORMAT_R16G16B16A16_FLOAT"`, ...), if
    /// Direct3D has the format (see [`TexelFormat::dxgi_format`]).
    #[must_use]
    pub const fn dxgi_name(self) -> Option<&'static str> {
        match self {
            TexelFormat::Rgba16f => Some("DXGI_FORMAT_R16G16B16A16_FLOAT"),
            TexelFormat::Rgba32f => Some("DXGI_FORMAT_R32G32B32A32_FLOAT"),
            TexelFormat::B10g11r11 => Some("DXGI_FORMAT_R11G11B10_FLOAT"),
            TexelFormat::E5b9g9r9 => Some("DXGI_FORMAT_R9G9B9E5_SHAREDEXP"),
            TexelFormat::Rgb32f => Some("DXGI_FORMAT_R32G32B32_FLOAT"),
            TexelFormat::Bc6h => Some("DXGI_FORMAT_BC6H_UF16"),
            TexelFormat::Rgb16f | TexelFormat::Rgbd8 => None,
        }
    }

    /// The `VkFormat` number (KTX2's `vkFormat`): for RGBD, the format its
    /// bytes are uploaded as (`R8G8B8A8_UNORM`, 37), which no KTX2 file of
    /// envmap's holds.
    #[must_use]
    pub const fn vk_format(self) -> u32 {
        match self {
            TexelFormat::Rgba16f => 97,
            TexelFormat::Rgba32f => 109,
            TexelFormat::B10g11r11 => 122,
            TexelFormat::E5b9g9r9 => 123,
            TexelFormat::Rgb16f => 90,
            TexelFormat::Rgb32f => 106,
            TexelFormat::Bc6h => 143,
            TexelFormat::Rgbd8 => 37,
        }
    }

    /// The format of a `VkFormat` number, if envmap reads it.
    #[must_use]
    #[cfg_attr(not(feature = "ktx2"), allow(dead_code))]
    pub(crate) const fn from_vk_format(vk: u32) -> Option<Self> {
        Some(match vk {
            97 => TexelFormat::Rgba16f,
            109 => TexelFormat::Rgba32f,
            122 => TexelFormat::B10g11r11,
            123 => TexelFormat::E5b9g9r9,
            90 => TexelFormat::Rgb16f,
            106 => TexelFormat::Rgb32f,
            #[cfg(feature = "bc6h")]
            143 => TexelFormat::Bc6h,
            _ => return None,
        })
    }

    /// The `DXGI_FORMAT` number (DDS), if the format has one.
    #[must_use]
    pub const fn dxgi_format(self) -> Option<u32> {
        match self {
            TexelFormat::Rgba16f => Some(10),
            TexelFormat::Rgba32f => Some(2),
            TexelFormat::B10g11r11 => Some(26),
            TexelFormat::E5b9g9r9 => Some(67),
            TexelFormat::Rgb32f => Some(6),
            TexelFormat::Bc6h => Some(95),
            TexelFormat::Rgb16f | TexelFormat::Rgbd8 => None,
        }
    }

    /// The format of a `DXGI_FORMAT` number, if envmap reads it.
    #[must_use]
    #[cfg_attr(not(feature = "dds"), allow(dead_code))]
    pub(crate) const fn from_dxgi_format(dxgi: u32) -> Option<Self> {
        Some(match dxgi {
            10 => TexelFormat::Rgba16f,
            2 => TexelFormat::Rgba32f,
            26 => TexelFormat::B10g11r11,
            67 => TexelFormat::E5b9g9r9,
            6 => TexelFormat::Rgb32f,
            #[cfg(feature = "bc6h")]
            95 => TexelFormat::Bc6h,
            _ => return None,
        })
    }

    /// Bytes per texel, or per block of a block-compressed format (16 for
    /// BC6H's 4×4 texels; [`TexelFormat::block`]).
    #[must_use]
    pub const fn bytes(self) -> usize {
        match self {
            TexelFormat::Bc6h => 16,
            TexelFormat::Rgba16f => 8,
            TexelFormat::Rgba32f => 16,
            TexelFormat::B10g11r11 | TexelFormat::E5b9g9r9 | TexelFormat::Rgbd8 => 4,
            TexelFormat::Rgb16f => 6,
            TexelFormat::Rgb32f => 12,
        }
    }

    /// The side of the square blocks the format stores texels in: 4 for
    /// BC6H, 1 for the formats that store each texel apart.
    #[must_use]
    pub const fn block(self) -> u32 {
        match self {
            TexelFormat::Bc6h => 4,
            _ => 1,
        }
    }

    /// The bytes of a `w`×`h` image in this format: a whole number of
    /// blocks for a block-compressed format (a 1×1 or 2×2 BC6H level takes
    /// one block).
    #[must_use]
    pub const fn image_bytes(self, w: u32, h: u32) -> usize {
        let b = self.block();
        w.div_ceil(b) as usize * h.div_ceil(b) as usize * self.bytes()
    }

    /// KTX2's `typeSize`: the size of one component, or of the packed word
    /// for the `_PACK32` formats, 1 for a block-compressed format.
    #[must_use]
    #[cfg_attr(not(feature = "ktx2"), allow(dead_code))]
    pub(crate) const fn type_size(self) -> u32 {
        match self {
            TexelFormat::Bc6h => 1,
            TexelFormat::Rgba16f | TexelFormat::Rgb16f => 2,
            _ => 4,
        }
    }

    /// Whether the format has no sign (negative values clamp to 0).
    #[must_use]
    pub(crate) const fn is_unsigned(self) -> bool {
        matches!(
            self,
            TexelFormat::B10g11r11 | TexelFormat::E5b9g9r9 | TexelFormat::Bc6h | TexelFormat::Rgbd8
        )
    }

    /// Whether envmap writes this format (BC6H with the `bc6h` feature).
    #[must_use]
    pub const fn is_writable(self) -> bool {
        let read_only = matches!(self, TexelFormat::Rgb16f | TexelFormat::Rgb32f);
        let unbuilt = matches!(self, TexelFormat::Bc6h) && !cfg!(feature = "bc6h");
        !read_only && !unbuilt
    }

    /// The largest finite value the format holds (of its smallest channel
    /// for B10G11R11: R and G reach 65024, B 64512).
    #[must_use]
    pub const fn max_value(self) -> f32 {
        match self {
            TexelFormat::Rgba16f | TexelFormat::Rgb16f | TexelFormat::Bc6h => F16_MAX,
            TexelFormat::Rgba32f | TexelFormat::Rgb32f => f32::MAX,
            TexelFormat::B10g11r11 => UF10_MAX,
            TexelFormat::E5b9g9r9 => RGB9E5_MAX,
            TexelFormat::Rgbd8 => RGBD_MAX,
        }
    }

    /// The worst relative rounding error of one component within the
    /// format's normal range (half a unit in the last place of its mantissa):
    /// 2⁻¹¹ binary16, 2⁻²⁴ binary32, 2⁻⁷ (B 2⁻⁶) the small floats, and for
    /// RGB9E5 2⁻⁹ of the texel's largest channel. BC6H's error depends on
    /// each block's content, not on a rounding step: its binary16 endpoints'
    /// 2⁻¹¹ is only the floor (the writers measure the rest).
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn relative_precision(self) -> f32 {
        match self {
            TexelFormat::Rgba16f | TexelFormat::Rgb16f | TexelFormat::Bc6h => 2f32.powi(-11),
            TexelFormat::Rgba32f | TexelFormat::Rgb32f => 2f32.powi(-24),
            TexelFormat::B10g11r11 => 2f32.powi(-7),
            TexelFormat::E5b9g9r9 => 2f32.powi(-9),
            // Above 1, m·D ≥ 1/2: half an 8-bit step at 0.5^(1/2.2), times 2.2.
            TexelFormat::Rgbd8 => 0.0059,
        }
    }

    /// Packs `texels` (alpha 1 where the format has it), appending to `out`;
    /// returns what was clamped. A block-compressed format packs them as an
    /// image one texel high ([`TexelFormat::unpack`] gives them back, with
    /// its last block's padding), at the default quality; a texture's
    /// levels are packed as images by the file writers and
    /// [`Texture::upload`](crate::image::texture::Texture::upload).
    ///
    /// # Panics
    ///
    /// Never for the writable formats; the read-only ones pack as their
    /// RGBA counterparts' RGB would (used in tests only).
    pub fn pack(self, texels: &[[f32; 3]], out: &mut Vec<u8>) -> Clamped {
        let at = out.len();
        let w = u32::try_from(texels.len()).unwrap_or(u32::MAX);
        out.resize(at + self.image_bytes(w, 1), 0);
        self.pack_image_into(texels, (w, 1), Bc6hQuality::default(), &mut out[at..])
    }

    /// Packs the `w`×`h` image `pixels` (rows top-down) into `out`, which
    /// holds exactly [`TexelFormat::image_bytes`] bytes; BC6H is encoded at
    /// `quality` (and without the `bc6h` feature, which the writers check
    /// first, left black). Returns what was clamped.
    ///
    /// # Panics
    ///
    /// If `out` has another length, or `pixels` is not `w × h` long.
    pub(crate) fn pack_image_into(
        self,
        pixels: &[[f32; 3]],
        (w, h): (u32, u32),
        quality: Bc6hQuality,
        out: &mut [u8],
    ) -> Clamped {
        if self != TexelFormat::Bc6h {
            return self.pack_into(pixels, out);
        }
        #[cfg(feature = "bc6h")]
        return crate::image::bc6h::encode(pixels, (w, h), quality, out);
        #[cfg(not(feature = "bc6h"))]
        {
            let _ = (pixels, w, h, quality, out);
            Clamped::default()
        }
    }

    /// The texels of the `w`×`h` image `bytes` holds in this format (the
    /// inverse of `TexelFormat::pack_image_into`, its BC6H decoded by
    /// `bcdec_rs`; black without the `bc6h` feature).
    #[cfg_attr(not(any(feature = "ktx2", feature = "dds")), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    pub(crate) fn unpack_image(self, bytes: &[u8], (w, h): (u32, u32)) -> Vec<[f32; 3]> {
        if self != TexelFormat::Bc6h {
            return self.unpack(bytes);
        }
        #[cfg(feature = "bc6h")]
        return crate::image::bc6h::decode(bytes, (w, h));
        #[cfg(not(feature = "bc6h"))]
        {
            let _ = bytes;
            vec![[0.0; 3]; w as usize * h as usize]
        }
    }

    /// Packs `texels` into `out`, which holds exactly `texels.len() ×`
    /// [`TexelFormat::bytes`] bytes, in parallel over blocks of texels;
    /// returns what was clamped.
    ///
    /// # Panics
    ///
    /// If `out` has another length.
    pub(crate) fn pack_into(self, texels: &[[f32; 3]], out: &mut [u8]) -> Clamped {
        use crate::par::*;
        const BLOCK: usize = 16 * 1024;
        assert_eq!(out.len(), texels.len() * self.bytes(), "packed length");
        if texels.len() <= BLOCK {
            return self.pack_block(texels, out);
        }
        texels
            .par_chunks(BLOCK)
            .zip(out.par_chunks_mut(BLOCK * self.bytes()))
            .map(|(t, o)| self.pack_block(t, o))
            .sum()
    }

    /// [`TexelFormat::pack_into`] on one thread.
    fn pack_block(self, texels: &[[f32; 3]], out: &mut [u8]) -> Clamped {
        let mut c = Clamped::default();
        let n = self.bytes();
        match self {
            // Images, by `pack_image_into`.
            TexelFormat::Bc6h => {}
            TexelFormat::Rgba16f | TexelFormat::Rgb16f => {
                // Clamp a run of components, then convert the run at once
                // (`half`'s slice conversion uses the CPU's F16C where it has it).
                const RUN: usize = 256;
                let ch = n / 2;
                let mut f = [0f32; 4 * RUN];
                let mut h = [0u16; 4 * RUN];
                for (t, o) in texels.chunks(RUN).zip(out.chunks_mut(RUN * n)) {
                    let k = t.len() * ch;
                    for (i, px) in t.iter().enumerate() {
                        for (j, &v) in px.iter().enumerate() {
                            f[i * ch + j] = clamp_counted(v, -F16_MAX, F16_MAX, &mut c);
                        }
                        if ch == 4 {
                            f[i * 4 + 3] = 1.0;
                        }
                    }
                    f16::from_f32_slice(&f[..k], &mut h[..k]);
                    for (b, v) in o.chunks_exact_mut(2).zip(&h[..k]) {
                        b.copy_from_slice(&v.to_le_bytes());
                    }
                }
            }
            TexelFormat::Rgba32f | TexelFormat::Rgb32f => {
                for (t, o) in texels.iter().zip(out.chunks_exact_mut(n)) {
                    for (j, &v) in t.iter().enumerate() {
                        o[4 * j..4 * j + 4].copy_from_slice(&v.to_le_bytes());
                    }
                    if n == 16 {
                        o[12..16].copy_from_slice(&1f32.to_le_bytes());
                    }
                }
            }
            TexelFormat::B10g11r11 => {
                for (t, o) in texels.iter().zip(out.chunks_exact_mut(4)) {
                    o.copy_from_slice(&pack_b10g11r11(*t, &mut c).to_le_bytes());
                }
            }
            TexelFormat::E5b9g9r9 => {
                for (t, o) in texels.iter().zip(out.chunks_exact_mut(4)) {
                    o.copy_from_slice(&pack_rgb9e5(*t, &mut c).to_le_bytes());
                }
            }
            TexelFormat::Rgbd8 => {
                for (t, o) in texels.iter().zip(out.chunks_exact_mut(4)) {
                    o.copy_from_slice(&pack_rgbd(*t, &mut c));
                }
            }
        }
        c
    }

    /// Unpacks `bytes` (a whole number of texels) into linear RGB, dropping
    /// alpha. A block-compressed format's bytes are unpacked as an image one
    /// texel high, the top row of each block (what [`TexelFormat::pack`]
    /// wrote).
    #[must_use]
    pub fn unpack(self, bytes: &[u8]) -> Vec<[f32; 3]> {
        use crate::par::*;
        if self == TexelFormat::Bc6h {
            let w = u32::try_from(bytes.len() / self.bytes() * 4).unwrap_or(u32::MAX);
            return self.unpack_image(bytes, (w, 1));
        }
        const BLOCK: usize = 16 * 1024;
        let n = self.bytes();
        let mut out = vec![[0f32; 3]; bytes.len() / n];
        if out.len() <= BLOCK {
            self.unpack_block(bytes, &mut out);
        } else {
            out.par_chunks_mut(BLOCK)
                .zip(bytes.par_chunks(BLOCK * n))
                .for_each(|(o, b)| self.unpack_block(b, o));
        }
        out
    }

    /// [`TexelFormat::unpack`] of one block, on one thread.
    fn unpack_block(self, bytes: &[u8], out: &mut [[f32; 3]]) {
        let n = self.bytes();
        let word = |b: &[u8], i: usize| u32::from_le_bytes([b[i], b[i + 1], b[i + 2], b[i + 3]]);
        match self {
            // Images, by `unpack_image`.
            TexelFormat::Bc6h => {}
            TexelFormat::Rgba16f | TexelFormat::Rgb16f => {
                const RUN: usize = 256;
                let ch = n / 2;
                let mut h = [0u16; 4 * RUN];
                let mut f = [0f32; 4 * RUN];
                for (b, o) in bytes.chunks(RUN * n).zip(out.chunks_mut(RUN)) {
                    let k = o.len() * ch;
                    for (v, c) in h[..k].iter_mut().zip(b.chunks_exact(2)) {
                        *v = u16::from_le_bytes([c[0], c[1]]);
                    }
                    f16::to_f32_slice(&h[..k], &mut f[..k]);
                    for (i, px) in o.iter_mut().enumerate() {
                        *px = [f[i * ch], f[i * ch + 1], f[i * ch + 2]];
                    }
                }
            }
            TexelFormat::Rgba32f | TexelFormat::Rgb32f => {
                for (b, o) in bytes.chunks_exact(n).zip(out) {
                    *o = [0, 4, 8].map(|i| f32::from_bits(word(b, i)));
                }
            }
            TexelFormat::B10g11r11 => {
                for (b, o) in bytes.chunks_exact(4).zip(out) {
                    *o = unpack_b10g11r11(word(b, 0));
                }
            }
            TexelFormat::E5b9g9r9 => {
                for (b, o) in bytes.chunks_exact(4).zip(out) {
                    *o = unpack_rgb9e5(word(b, 0));
                }
            }
            TexelFormat::Rgbd8 => {
                for (b, o) in bytes.chunks_exact(4).zip(out) {
                    *o = unpack_rgbd([b[0], b[1], b[2], b[3]]);
                }
            }
        }
    }
}
