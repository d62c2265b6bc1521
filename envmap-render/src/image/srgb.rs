//! The sRGB transfer functions (IEC 61966-2-1), exact, and the lookup
//! tables that decode 8- and 16-bit files with them.

use std::sync::OnceLock;

/// The exact sRGB EOTF (IEC 61966-2-1): encoded value in `[0, 1]` → linear.
///
/// `c / 12.92` up to 0.04045, `((c + 0.055) / 1.055)^2.4` above; computed
/// in f64 and rounded once. `srgb_to_linear(128.0 / 255.0)` is 0.2158605 (to 7 digits).
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    let c = f64::from(c);
    let l = if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    };
    l as f32
}

/// The sRGB OETF: linear → encoded value in `[0, 1]` (clamped; NaN → 0).
#[must_use]
pub fn linear_to_srgb(l: f32) -> f32 {
    if l.is_nan() {
        return 0.0;
    }
    let l = f64::from(l.clamp(0.0, 1.0));
    let c = if l <= 0.003_130_8 {
        12.92 * l
    } else {
        1.055 * l.powf(1.0 / 2.4) - 0.055
    };
    c as f32
}

/// Linear → 8-bit sRGB code: the code whose exact EOTF value is nearest in
/// the encoded domain (the decision points are the EOTF of the half codes).
/// Clamps; NaN and negative values give 0, `+∞` gives 255. Every code `k`
/// maps back to itself: `linear_to_srgb8(srgb_to_linear(k / 255)) == k`.
#[must_use]
pub fn linear_to_srgb8(l: f32) -> u8 {
    // Count of thresholds ≤ l: 0 for NaN (every comparison is false).
    srgb8_thresholds().partition_point(|&t| t <= l) as u8
}

fn srgb8_thresholds() -> &'static [f32; 255] {
    static T: OnceLock<[f32; 255]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [0.0f32; 255];
        for (k, v) in t.iter_mut().enumerate() {
            *v = srgb_to_linear((k as f32 + 0.5) / 255.0);
        }
        t
    })
}

#[cfg(feature = "image")]
pub(super) fn srgb8_lut() -> &'static [f32; 256] {
    static T: OnceLock<[f32; 256]> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = [0.0f32; 256];
        for (k, v) in t.iter_mut().enumerate() {
            *v = srgb_to_linear(k as f32 / 255.0);
        }
        t
    })
}

#[cfg(feature = "image")]
pub(super) fn srgb16_lut() -> &'static [f32] {
    static T: OnceLock<Vec<f32>> = OnceLock::new();
    T.get_or_init(|| {
        (0..=u16::MAX)
            .map(|k| srgb_to_linear(f32::from(k) / 65535.0))
            .collect()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_codes_round_trip() {
        assert!((srgb_to_linear(128.0 / 255.0) - 0.215_860_5).abs() < 1e-7);
        assert_eq!(srgb_to_linear(0.0), 0.0);
        assert_eq!(srgb_to_linear(1.0), 1.0);
        for k in 0..=255u8 {
            let l = srgb_to_linear(f32::from(k) / 255.0);
            assert_eq!(linear_to_srgb8(l), k);
            assert_eq!((linear_to_srgb(l) * 255.0).round() as u8, k);
        }
        assert_eq!(linear_to_srgb8(f32::NAN), 0);
        assert_eq!(linear_to_srgb8(-1.0), 0);
        assert_eq!(linear_to_srgb8(f32::INFINITY), 255);
        assert_eq!(linear_to_srgb8(5000.0), 255);
    }
}
