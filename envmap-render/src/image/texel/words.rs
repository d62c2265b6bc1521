//! The texel words of the packed formats, one texel at a time: RGBD
//! (Babylon.js), binary16, RGB9E5 and B10G11R11 (EXT_texture_shared_exponent,
//! EXT_packed_float), with the clamp that counts what does not fit.

use super::{Clamped, RGB9E5_MAX, RGBD_MAX, UF10_MAX, UF11_MAX};

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

/// `v` clamped to `[lo, hi]`, NaN to 0, each counted in `c`.
pub(crate) fn clamp_counted(v: f32, lo: f32, hi: f32, c: &mut Clamped) -> f32 {
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
    use crate::image::texel::*;

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
