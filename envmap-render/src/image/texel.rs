// GPU texel formats and their packers: what a KTX2, DDS or KTX 1 file's
// texels are, bit for bit.

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

/// `v` clamped to `[lo, hi]`, NaN to 0, counting each.
/// RGBD, as Babylon.js's `toRGBD` (`helperFunctions.fx`) computes it in
/// f32 and the GPU rounds it to 8-bit unorm: with m the largest channel
/// (clamped to [0, 255] and counted first), D = ⌊max(255/m, 1)⌋/255
/// (1 for black), rgb = (c·D)^(1/2.2), a = D, each round(255·v).
#[must_use]
pub(crate) fn pack_rgbd(rgb: [f32; 3], c: &mut Clamped) -> [u8; 4] {
    let rgb = rgb.map(|v| clamp_counted(v, 0.0, RGBD_MAX, c));
    let m = rgb[0].max(rgb[1]).max(rgb[2]);
    let d = if m > 0.0 {
        ((255.0 / m).max(1.0).floor() / 255.0).clamp(0.0, 1.0)
    } else {
        1.0
    };
    let unorm = |v: f32| (v.clamp(0.0, 1.0) * 255.0).round() as u8;
    let [r, g, b] = rgb.map(|v| unorm((v * d).powf(1.0 / 2.2)));
    [r, g, b, unorm(d)]
}

/// RGBD decoded as Babylon.js's `fromRGBD`: rgb^2.2 / a (0 where a is 0,
/// which no writer makes).
#[must_use]
pub(crate) fn unpack_rgbd(b: [u8; 4]) -> [f32; 3] {
    let a = f32::from(b[3]) / 255.0;
    if a == 0.0 {
        return [0.0; 3];
    }
    [b[0], b[1], b[2]].map(|v| (f32::from(v) / 255.0).powf(2.2) / a)
}

fn clamp_counted(v: f32, lo: f32, hi: f32, c: &mut Clamped) -> f32 {
    if v.is_nan() {
        c.nan += 1;
        0.0
    } else if v > hi {
        c.above += 1;
        hi
    } else if v < lo {
        c.below += 1;
        lo
    } else {
        v
    }
}

/// binary16 conversions (IEEE 754-2008 §3.6; rounding to nearest, ties to
/// even): the `half` crate's, which use the CPU's F16C where it has it,
/// in builds with a format that stores half floats (`exr`, `ktx2`, `dds`,
/// `ktx1`); otherwise envmap's own, which agree with `half`'s bit for bit
/// (`own_f16_conversion_is_halfs` below; NaN payloads aside).
pub(crate) mod f16 {
    #[cfg(any(feature = "exr", feature = "ktx2", feature = "dds", feature = "ktx1"))]
    mod imp {
        use half::slice::{HalfBitsSliceExt, HalfFloatSliceExt};

        #[cfg(test)]
        pub(crate) fn from_f32(v: f32) -> u16 {
            half::f16::from_f32(v).to_bits()
        }

        pub(crate) fn from_f32_slice(f: &[f32], out: &mut [u16]) {
            let out: &mut [half::f16] = out.reinterpret_cast_mut();
            out.convert_from_f32_slice(f);
        }

        pub(crate) fn to_f32_slice(h: &[u16], out: &mut [f32]) {
            let h: &[half::f16] = h.reinterpret_cast();
            h.convert_to_f32_slice(out);
        }
    }

    #[cfg(not(any(feature = "exr", feature = "ktx2", feature = "dds", feature = "ktx1")))]
    mod imp {
        #[cfg(test)]
        pub(crate) fn from_f32(v: f32) -> u16 {
            super::own_from_f32(v)
        }

        pub(crate) fn from_f32_slice(f: &[f32], out: &mut [u16]) {
            for (o, &v) in out.iter_mut().zip(f) {
                *o = super::own_from_f32(v);
            }
        }

        pub(crate) fn to_f32_slice(h: &[u16], out: &mut [f32]) {
            for (o, &v) in out.iter_mut().zip(h) {
                *o = super::own_to_f32(v);
            }
        }
    }

    #[cfg(test)]
    pub(crate) use imp::from_f32;
    pub(crate) use imp::{from_f32_slice, to_f32_slice};

    /// f32 → binary16 bits, rounded to nearest, ties to even; beyond
    /// 65504 (after rounding) infinite; NaN stays NaN.
    #[cfg_attr(
        any(feature = "exr", feature = "ktx2", feature = "dds", feature = "ktx1"),
        allow(dead_code)
    )]
    pub(crate) fn own_from_f32(v: f32) -> u16 {
        let x = v.to_bits();
        let sign = ((x >> 16) & 0x8000) as u16;
        let exp = ((x >> 23) & 0xff) as i32;
        let man = x & 0x7f_ffff;
        if exp == 0xff {
            let nan = if man != 0 {
                0x200 | (man >> 13) as u16
            } else {
                0
            };
            return sign | 0x7c00 | nan;
        }
        let e = exp - 127 + 15;
        if e >= 0x1f {
            return sign | 0x7c00;
        }
        if e <= 0 {
            // Subnormal (or zero) in binary16: the 24-bit significand
            // shifted right by 14 − e, rounded to nearest even.
            if e < -10 {
                return sign;
            }
            let m = man | 0x80_0000;
            let shift = (14 - e) as u32;
            let rest = m & ((1 << shift) - 1);
            let halfway = 1 << (shift - 1);
            let mut h = m >> shift;
            if rest > halfway || (rest == halfway && h & 1 == 1) {
                h += 1;
            }
            return sign | h as u16;
        }
        let rest = man & 0x1fff;
        let mut h = ((e as u32) << 10) | (man >> 13);
        // A carry out of the mantissa raises the exponent (to infinity past
        // the largest finite value), as it should.
        if rest > 0x1000 || (rest == 0x1000 && h & 1 == 1) {
            h += 1;
        }
        sign | h as u16
    }

    /// binary16 bits → f32, exactly.
    #[cfg_attr(
        any(feature = "exr", feature = "ktx2", feature = "dds", feature = "ktx1"),
        allow(dead_code)
    )]
    pub(crate) fn own_to_f32(h: u16) -> f32 {
        let sign = u32::from(h & 0x8000) << 16;
        let exp = u32::from((h >> 10) & 0x1f);
        let man = u32::from(h & 0x3ff);
        let bits = match (exp, man) {
            (0, 0) => sign,
            (0, m) => {
                // m × 2⁻²⁴, normalised: its top bit p (0–9) is the
                // implicit one.
                let p = 31 - m.leading_zeros();
                sign | ((p + 103) << 23) | ((m << (23 - p)) & 0x7f_ffff)
            }
            (0x1f, m) => sign | 0x7f80_0000 | (m << 13),
            (e, m) => sign | ((e + 112) << 23) | (m << 13),
        };
        f32::from_bits(bits)
    }
}

/// ⌊log₂ v⌋ for a positive finite f32, exactly (from its bits).
fn floor_log2(v: f32) -> i32 {
    let bits = v.to_bits();
    let e = ((bits >> 23) & 0xff) as i32;
    if e == 0 {
        // Subnormal: the position of the highest set mantissa bit.
        -127 + (32 - (bits & 0x7f_ffff).leading_zeros() as i32) - 23
    } else {
        e - 127
    }
}

/// One texel as `E5B9G9R9_UFLOAT_PACK32`, by the extension's algorithm
/// (`EXT_texture_shared_exponent`, "Appendix: RGB9E5 shared exponent
/// conversion"): each channel clamped to [0, 65408], the shared exponent
/// from the largest, raised by one when that channel's mantissa rounds to
/// 512, mantissas ⌊c/2^(e−24) + ½⌋. Exact: each mantissa is rounded from
/// the channel's own significand and exponent in integers (a test checks
/// it against the same arithmetic in f64, where every step is exact too).
#[must_use]
pub(crate) fn pack_rgb9e5(rgb: [f32; 3], c: &mut Clamped) -> u32 {
    let ch = rgb.map(|v| clamp_counted(v, 0.0, RGB9E5_MAX, c));
    let max = ch[0].max(ch[1]).max(ch[2]);
    let mut e = if max > 0.0 {
        floor_log2(max).max(-16) + 16
    } else {
        0
    };
    if scaled_round(max, e) >= 512 {
        e += 1;
    }
    let m = ch.map(|v| scaled_round(v, e));
    m[0] | (m[1] << 9) | (m[2] << 18) | ((e as u32) << 27)
}

/// ⌊v·2^(24 − e) + ½⌋ for a finite `v` in [0, 2^(e − 15)), exactly: `v` is
/// M·2^E (M its integer significand), so the product is M shifted by
/// E + 24 − e, rounded half up where the shift is to the right.
fn scaled_round(v: f32, e: i32) -> u32 {
    let bits = v.to_bits();
    let exp = ((bits >> 23) & 0xff) as i32;
    let (m, ex) = if exp == 0 {
        (bits & 0x7f_ffff, -149)
    } else {
        ((bits & 0x7f_ffff) | 0x80_0000, exp - 150)
    };
    let shift = ex + 24 - e;
    if shift >= 0 {
        // Below 512 by `v`'s range: no bit is lost.
        m << shift
    } else if shift > -25 {
        let r = shift.unsigned_abs();
        (m + (1 << (r - 1))) >> r
    } else {
        // Under a quarter: M < 2^24.
        0
    }
}

/// One `E5B9G9R9_UFLOAT_PACK32` texel: each mantissa · 2^(e − 24).
#[must_use]
pub(crate) fn unpack_rgb9e5(w: u32) -> [f32; 3] {
    // 2^(e − 24) exactly, from its bits (a normal f32 for every e in 0..=31).
    let scale = f32::from_bits(((127 + (w >> 27) as i32 - 24) as u32) << 23);
    [w & 0x1ff, (w >> 9) & 0x1ff, (w >> 18) & 0x1ff].map(|m| m as f32 * scale)
}

/// One unsigned small float with `m` mantissa bits and a 5-bit exponent
/// (bias 15, exponent 31 reserved for infinity and NaN), rounded to nearest
/// even; `v` already clamped to [0, max].
fn pack_ufloat(v: f32, m: u32) -> u32 {
    if v == 0.0 {
        return 0;
    }
    let e = floor_log2(v);
    if e < -14 {
        // Subnormal: v / 2^(−14 − m), rounded to nearest even; 2^m rounds
        // up into the smallest normal, whose bits are the same number.
        let x = f64::from(v) * 2f64.powi(14 + m as i32);
        return round_half_even(x) as u32;
    }
    // Normal: round the f32 mantissa from 23 bits to m, carrying into the
    // exponent when it overflows.
    let bits = v.to_bits();
    let shift = 23 - m;
    let mant = bits & 0x7f_ffff;
    let mut q = ((e + 15) as u32) << m | (mant >> shift);
    let rest = mant & ((1 << shift) - 1);
    let half = 1 << (shift - 1);
    if rest > half || (rest == half && q & 1 == 1) {
        q += 1;
    }
    q
}

/// x rounded to the nearest integer, ties to even.
fn round_half_even(x: f64) -> f64 {
    let r = x.round();
    if (r - x).abs() == 0.5 && r % 2.0 != 0.0 {
        r - x.signum()
    } else {
        r
    }
}

/// An unsigned small float with `m` mantissa bits → f32.
fn unpack_ufloat(q: u32, m: u32) -> f32 {
    let e = q >> m;
    let f = q & ((1 << m) - 1);
    let unit = 2f32.powi(-(m as i32));
    match e {
        0 => f as f32 * unit * 2f32.powi(-14),
        31 if f == 0 => f32::INFINITY,
        31 => f32::NAN,
        _ => (1.0 + f as f32 * unit) * 2f32.powi(e as i32 - 15),
    }
}

/// One texel as `B10G11R11_UFLOAT_PACK32`: R and G unsigned 11-bit floats
/// (6-bit mantissa), B unsigned 10-bit (5-bit mantissa), each clamped to
/// its largest finite value and at zero (counted), rounded to nearest even.
#[must_use]
pub(crate) fn pack_b10g11r11(rgb: [f32; 3], c: &mut Clamped) -> u32 {
    let r = pack_ufloat(clamp_counted(rgb[0], 0.0, UF11_MAX, c), 6);
    let g = pack_ufloat(clamp_counted(rgb[1], 0.0, UF11_MAX, c), 6);
    let b = pack_ufloat(clamp_counted(rgb[2], 0.0, UF10_MAX, c), 5);
    r | (g << 11) | (b << 22)
}

/// One `B10G11R11_UFLOAT_PACK32` texel → linear RGB.
#[cfg_attr(feature = "instruments", visibility::make(pub))]
#[must_use]
pub(crate) fn unpack_b10g11r11(w: u32) -> [f32; 3] {
    [
        unpack_ufloat(w & 0x7ff, 6),
        unpack_ufloat((w >> 11) & 0x7ff, 6),
        unpack_ufloat(w >> 22, 5),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The shared-exponent packing in f64 (every step exact there): the
    /// reference the integer packing is held to.
    fn pack_rgb9e5_f64(rgb: [f32; 3]) -> u32 {
        let ch = rgb.map(|v| clamp_counted(v, 0.0, RGB9E5_MAX, &mut Clamped::default()));
        let max = ch[0].max(ch[1]).max(ch[2]);
        let mut e = if max > 0.0 {
            floor_log2(max).max(-16) + 16
        } else {
            0
        };
        // 2^(24 − e) exactly, from its bits (e in 0..=32).
        let scale = |e: i32| f64::from_bits(((1023 + 24 - e) as u64) << 52);
        if (f64::from(max) * scale(e) + 0.5).floor() >= 512.0 {
            e += 1;
        }
        let s = scale(e);
        let m = ch.map(|v| (f64::from(v) * s + 0.5).floor() as u32);
        m[0] | (m[1] << 9) | (m[2] << 18) | ((e as u32) << 27)
    }

    /// The integer packing equals the f64 one on every kind of value:
    /// each exponent's mantissa ties and their neighbours, subnormals,
    /// zero, the largest value and beyond, NaN, and a million random
    /// texels over 2^-30 .. 2^17.
    #[test]
    fn rgb9e5_in_integers_is_the_f64_packing() {
        let mut values = vec![
            0.0,
            f32::MIN_POSITIVE,
            f32::from_bits(1),
            f32::from_bits(0x7f_ffff),
            RGB9E5_MAX,
            RGB9E5_MAX * 1.001,
            f32::INFINITY,
            f32::NAN,
            -1.0,
        ];
        for e in -40..18 {
            for k in [
                0.5, 1.0, 255.5, 256.0, 256.5, 383.5, 510.5, 511.0, 511.5, 511.75,
            ] {
                let v = (k / 256.0) * 2f32.powi(e);
                let b = v.to_bits();
                values.extend([
                    v,
                    f32::from_bits(b + 1),
                    f32::from_bits(b.saturating_sub(1)),
                ]);
            }
        }
        let check = |rgb: [f32; 3]| {
            let mut c = Clamped::default();
            assert_eq!(
                pack_rgb9e5(rgb, &mut c),
                pack_rgb9e5_f64(rgb),
                "{rgb:?} ({:?})",
                rgb.map(f32::to_bits)
            );
        };
        for &a in &values {
            for &b in &values {
                check([a, b, 1.0]);
                check([a, b, a * 0.37]);
            }
        }
        let mut rng = crate::instruments::Pcg32::new(0x9e37_79b9);
        let mut r = || rng.next_u32();
        for _ in 0..1_000_000 {
            let mut v = || f32::from_bits(r() % (0x4800_0000 - 0x3080_0000) + 0x3080_0000);
            check([v(), v(), v()]);
        }
    }

    fn rt9(v: [f32; 3]) -> [f32; 3] {
        unpack_rgb9e5(pack_rgb9e5(v, &mut Clamped::default()))
    }

    fn rt11(v: [f32; 3]) -> [f32; 3] {
        unpack_b10g11r11(pack_b10g11r11(v, &mut Clamped::default()))
    }

    #[test]
    fn rgb9e5_named_values() {
        assert_eq!(pack_rgb9e5([0.0; 3], &mut Clamped::default()), 0);
        assert_eq!(rt9([0.0; 3]), [0.0; 3]);
        // 1.0 is mantissa 256 at exponent 16 (the DFD's 8448 = 0x2100 sample upper).
        let one = pack_rgb9e5([1.0, 0.0, 0.0], &mut Clamped::default());
        assert_eq!((one & 0x1ff, one >> 27), (256, 16));
        assert_eq!(rt9([1.0, 0.5, 0.25]), [1.0, 0.5, 0.25]);
        assert_eq!(rt9([RGB9E5_MAX; 3]), [RGB9E5_MAX; 3]);
        // The smallest non-zero value, 2^-24 (mantissa 1 at exponent 0).
        let tiny = 2f32.powi(-24);
        assert_eq!(pack_rgb9e5([tiny, 0.0, 0.0], &mut Clamped::default()), 1);
        assert_eq!(rt9([tiny, 0.0, 0.0])[0], tiny);
        // 511.5 · 2^-8 rounds to 512 · 2^-8 = 2: the exponent goes up by one.
        let v = 511.5 / 256.0;
        let w = pack_rgb9e5([v, 0.0, 0.0], &mut Clamped::default());
        assert_eq!((w & 0x1ff, w >> 27), (256, 17));
        assert_eq!(rt9([v, 0.0, 0.0])[0], 2.0);
        // Just below the tie stays at the lower exponent.
        let v = 511.49 / 256.0;
        assert_eq!(
            pack_rgb9e5([v, 0.0, 0.0], &mut Clamped::default()) >> 27,
            16
        );
    }

    #[test]
    fn rgb9e5_clamps_and_counts() {
        let mut c = Clamped::default();
        let w = pack_rgb9e5([1e6, -1.0, f32::NAN], &mut c);
        assert_eq!(
            c,
            Clamped {
                above: 1,
                below: 1,
                nan: 1
            }
        );
        assert_eq!(unpack_rgb9e5(w), [RGB9E5_MAX, 0.0, 0.0]);
        let mut c = Clamped::default();
        let _ = pack_rgb9e5([f32::INFINITY, f32::NEG_INFINITY, 3.0], &mut c);
        assert_eq!(
            c,
            Clamped {
                above: 1,
                below: 1,
                nan: 0
            }
        );
    }

    #[test]
    fn b10g11r11_named_values() {
        assert_eq!(pack_b10g11r11([0.0; 3], &mut Clamped::default()), 0);
        assert_eq!(rt11([1.0, 1.0, 1.0]), [1.0; 3]);
        // 1.0 is exponent 15, mantissa 0, in each field.
        assert_eq!(
            pack_b10g11r11([1.0, 1.0, 1.0], &mut Clamped::default()),
            (15 << 6) | (15 << 17) | (15 << 27)
        );
        assert_eq!(
            rt11([UF11_MAX, UF11_MAX, UF10_MAX]),
            [UF11_MAX, UF11_MAX, UF10_MAX]
        );
        // The smallest normal, 2^-14, and the smallest subnormals.
        let n = 2f32.powi(-14);
        assert_eq!(rt11([n, n, n]), [n, n, n]);
        assert_eq!(
            pack_b10g11r11([n, 0.0, 0.0], &mut Clamped::default()),
            1 << 6
        );
        let s11 = 2f32.powi(-20);
        let s10 = 2f32.powi(-19);
        assert_eq!(rt11([s11, s11, s10]), [s11, s11, s10]);
        // Rounds up an exponent: (2 − 2^-7)·1 rounds (tie, odd mantissa 63) to 2.
        let v = 2.0 - 2f32.powi(-7);
        assert_eq!(rt11([v, 0.0, 0.0])[0], 2.0);
        // A tie with an even mantissa stays: 1 + 2^-7 → 1.
        assert_eq!(rt11([1.0 + 2f32.powi(-7), 0.0, 0.0])[0], 1.0);
        // The largest subnormal rounding into the smallest normal.
        let v = 2f32.powi(-14) - 2f32.powi(-22);
        assert_eq!(rt11([v, 0.0, 0.0])[0], n);
    }

    #[test]
    fn b10g11r11_clamps_and_counts() {
        let mut c = Clamped::default();
        let w = pack_b10g11r11([70000.0, -2.0, 65000.0], &mut c);
        assert_eq!(
            c,
            Clamped {
                above: 2,
                below: 1,
                nan: 0
            }
        );
        assert_eq!(unpack_b10g11r11(w), [UF11_MAX, 0.0, UF10_MAX]);
    }

    #[test]
    fn f16_clamps_instead_of_overflowing() {
        let mut c = Clamped::default();
        let mut out = Vec::new();
        let got = TexelFormat::Rgba16f.pack(&[[1e5, -1e5, 65504.0]], &mut out);
        c.add(got);
        assert_eq!(
            c,
            Clamped {
                above: 1,
                below: 1,
                nan: 0
            }
        );
        assert_eq!(
            TexelFormat::Rgba16f.unpack(&out),
            vec![[65504.0, -65504.0, 65504.0]]
        );
        assert_eq!(&out[6..8], &0x3c00u16.to_le_bytes());
    }

    /// envmap's own binary16 conversions (for builds without `half`) give
    /// `half`'s bits: every binary16 value back to f32, and f32 values
    /// spread over every exponent (a stride through all 2³² bit patterns)
    /// and every rounding case near the binary16 grid to binary16.
    #[test]
    #[cfg(any(feature = "exr", feature = "ktx2", feature = "dds", feature = "ktx1"))]
    fn own_f16_conversion_is_halfs() {
        use super::f16::{own_from_f32, own_to_f32};
        for h in 0..=u16::MAX {
            let want = half::f16::from_bits(h).to_f32();
            let got = own_to_f32(h);
            if want.is_nan() {
                assert!(got.is_nan(), "{h:#06x}");
            } else {
                assert_eq!(got.to_bits(), want.to_bits(), "{h:#06x}");
            }
        }
        let check = |v: f32| {
            let want = half::f16::from_f32(v).to_bits();
            let got = own_from_f32(v);
            if v.is_nan() {
                assert!(got & 0x7c00 == 0x7c00 && got & 0x3ff != 0, "{v:e}");
            } else {
                assert_eq!(got, want, "{v:e} ({:#010x})", v.to_bits());
            }
        };
        for b in (0..=u32::MAX).step_by(4099) {
            check(f32::from_bits(b));
        }
        // Each binary16 value, the midpoints beside it and one f32 ulp
        // either side of those: the ties and their neighbours.
        for h in 0..0x7c00u16 {
            let v = half::f16::from_bits(h).to_f32();
            let next = half::f16::from_bits(h + 1).to_f32();
            let mid = f32::midpoint(v, next);
            for x in [
                v,
                mid,
                f32::from_bits(mid.to_bits() - 1),
                f32::from_bits(mid.to_bits() + 1),
            ] {
                check(x);
                check(-x);
            }
        }
    }

    /// A deterministic stream of values spread over many octaves.
    fn values(n: usize) -> impl Iterator<Item = f32> {
        let mut rng = crate::instruments::Pcg32::new(0x9e37_79b9_7f4a_7c15);
        (0..n).map(move |_| {
            let u = f64::from(rng.next_f32());
            (2f64.powf(u * 36.0 - 20.0)) as f32
        })
    }

    #[test]
    fn relative_error_bounds_over_random_values() {
        let v: Vec<f32> = values(30_000).collect();
        let mut worst = [0f64; 3];
        for t in v.chunks_exact(3) {
            let t = [t[0].min(6e4), t[1].min(6e4), t[2].min(6e4)];
            let a = rt11(t);
            let b = rt9(t);
            let mut out = Vec::new();
            TexelFormat::Rgba16f.pack(&[t], &mut out);
            let h = TexelFormat::Rgba16f.unpack(&out)[0];
            let max = f64::from(t[0].max(t[1]).max(t[2]));
            for k in 0..3 {
                let x = f64::from(t[k]);
                // Normal range of each format only (subnormals have absolute steps).
                if x >= 2f64.powi(-14) {
                    let m = if k == 2 { 5 } else { 6 };
                    let e = (f64::from(a[k]) - x).abs() / x;
                    assert!(e <= 2f64.powi(-m - 1) * (1.0 + 1e-12), "{x} {}", a[k]);
                    worst[0] = worst[0].max(e);
                    let e = (f64::from(h[k]) - x).abs() / x;
                    assert!(e <= 2f64.powi(-11) * (1.0 + 1e-12), "{x} {}", h[k]);
                    worst[1] = worst[1].max(e);
                }
                // RGB9E5: within half a step of the shared exponent. The step
                // is 2^(⌊log2 max⌋ − 8), doubled where the largest channel
                // rounds up to 512 steps (EXT_texture_shared_exponent's
                // exponent bump), and 2^-24 at the bottom.
                let e = (f64::from(b[k]) - x).abs();
                let mut step = 2f64.powi(max.max(2f64.powi(-16)).log2().floor() as i32 - 8);
                if (max / step + 0.5).floor() >= 512.0 {
                    step *= 2.0;
                }
                assert!(
                    e <= (step / 2.0).max(2f64.powi(-25)) * (1.0 + 1e-12),
                    "{t:?} {b:?}"
                );
                if max > 2f64.powi(-15) {
                    worst[2] = worst[2].max(e / max);
                }
            }
        }
        // The bounds are reached, not just respected.
        assert!(worst[0] > 2f64.powi(-6) * 0.9, "{worst:?}");
        assert!(worst[1] > 2f64.powi(-11) * 0.9, "{worst:?}");
        assert!(worst[2] > 2f64.powi(-9) * 0.9, "{worst:?}");
    }

    #[test]
    fn packed_words_round_trip_exactly() {
        // Every finite 11/10-bit code decodes and re-encodes to itself.
        for q in 0..(31u32 << 6) {
            let w = q | (q << 11) | ((q >> 1) << 22);
            let v = unpack_b10g11r11(w);
            assert_eq!(pack_b10g11r11(v, &mut Clamped::default()), w, "{q}");
        }
        // Every RGB9E5 word whose largest mantissa is normalised (≥ 256, or
        // exponent 0) is canonical and round-trips.
        for e in 0..32u32 {
            for m in [0u32, 1, 255, 256, 300, 511] {
                if e > 0 && m < 256 {
                    continue;
                }
                let w = m | ((m / 2) << 9) | (1 << 18) | (e << 27);
                let w = if e == 0 && m == 0 { 0 } else { w };
                let v = unpack_rgb9e5(w);
                assert_eq!(pack_rgb9e5(v, &mut Clamped::default()), w, "{e} {m}");
            }
        }
    }

    /// The parallel block paths give the bytes and counts of packing texel
    /// by texel, and unpack back to the texel-by-texel values.
    #[test]
    fn blocks_in_parallel_equal_texel_by_texel() {
        let v: Vec<f32> = values(3 * 40_001).collect();
        let mut texels: Vec<[f32; 3]> = v.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        texels[7] = [-1.0, f32::NAN, 1e9];
        // The formats that store each texel apart (BC6H's blocks: tests/bc6h.rs).
        for f in TexelFormat::WRITABLE.into_iter().filter(|f| f.block() == 1) {
            let mut whole = Vec::new();
            let c = f.pack(&texels, &mut whole);
            let mut one = Vec::new();
            let mut c1 = Clamped::default();
            for t in &texels {
                c1.add(f.pack(std::slice::from_ref(t), &mut one));
            }
            assert_eq!(whole, one, "{f:?}");
            assert_eq!(c, c1, "{f:?}");
            // RGBA32F stores every f32 as is; the others clamp 3 components.
            assert_eq!(c.total() >= 2, f != TexelFormat::Rgba32f, "{f:?} {c:?}");
            let back = f.unpack(&whole);
            let back1: Vec<[f32; 3]> = one
                .chunks_exact(f.bytes())
                .flat_map(|b| f.unpack(b))
                .collect();
            assert_eq!(back.len(), texels.len());
            for (a, b) in back.iter().zip(&back1) {
                assert!(
                    a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits()),
                    "{f:?}"
                );
            }
        }
    }

    #[test]
    fn names_and_numbers() {
        // BC6H is read and written only with its feature.
        for f in TexelFormat::WRITABLE
            .into_iter()
            .filter(|f| f.is_writable())
        {
            assert_eq!(TexelFormat::parse(f.name()).unwrap(), f);
            assert_eq!(TexelFormat::from_vk_format(f.vk_format()), Some(f));
            assert_eq!(
                TexelFormat::from_dxgi_format(f.dxgi_format().unwrap()),
                Some(f)
            );
        }
        assert!(TexelFormat::parse("astc").is_err());
        assert_eq!(TexelFormat::parse("BC6H").unwrap(), TexelFormat::Bc6h);
    }
}
