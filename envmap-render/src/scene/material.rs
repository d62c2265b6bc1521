// Materials: the glTF 2.0 metallic-roughness model (glTF 2.0 spec,
// Appendix B "BRDF Implementation"), and the named presets of the command
// line.

use crate::error::{Error, Result};

/// A glTF metallic-roughness material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    /// Base colour, linear RGB in [0, 1].
    pub base_color: [f32; 3],
    /// Metallic factor in [0, 1]: 0 dielectric, 1 metal.
    pub metallic: f32,
    /// Perceptual roughness in [0, 1] (GGX α = roughness²).
    pub roughness: f32,
    /// The reflectance at normal incidence of the dielectric part (0.04,
    /// glTF's value for IOR 1.5).
    pub dielectric_f0: f32,
}

impl Default for Material {
    /// Glossy white plastic: base 0.8, dielectric, roughness 0.5.
    fn default() -> Self {
        Self::new([0.8; 3], 0.0, 0.5)
    }
}

impl Material {
    /// A material of base colour (linear), metallic and perceptual
    /// roughness, its dielectric part at the usual F0 of 0.04.
    #[must_use]
    pub const fn new(base_color: [f32; 3], metallic: f32, roughness: f32) -> Self {
        Self {
            base_color,
            metallic,
            roughness,
            dielectric_f0: 0.04,
        }
    }

    /// The preset names [`Material::preset`] accepts.
    pub const PRESETS: &'static str = "mirror, chrome, gold, plastic, rubber, diffuse";

    /// A named preset: `mirror` (metal, white, roughness 0), `chrome`
    /// (metal, 0.55 grey, roughness 0.1), `gold` (metal, (1.0, 0.766,
    /// 0.336) — the physically based value of gold's F0 in linear sRGB —
    /// roughness 0.25), `plastic` (dielectric red 0.8/0.05/0.05, roughness
    /// 0.4), `rubber` (dielectric 0.1 grey, roughness 0.9), `diffuse`
    /// (dielectric white 0.8, roughness 1).
    ///
    /// # Errors
    ///
    /// An unknown name, listing the presets.
    pub fn preset(name: &str) -> Result<Self> {
        let m = Material::new;
        Ok(match name.to_ascii_lowercase().as_str() {
            "mirror" => m([1.0; 3], 1.0, 0.0),
            "chrome" => m([0.55; 3], 1.0, 0.1),
            "gold" => m([1.0, 0.766, 0.336], 1.0, 0.25),
            "plastic" => m([0.8, 0.05, 0.05], 0.0, 0.4),
            "rubber" => m([0.1; 3], 0.0, 0.9),
            "diffuse" => m([0.8; 3], 0.0, 1.0),
            _ => {
                return Err(Error::UnknownName {
                    what: "material",
                    name: name.to_owned(),
                    expected: Self::PRESETS.to_owned(),
                })
            }
        })
    }

    /// The reflectance at normal incidence: mix(dielectric F0, base colour,
    /// metallic).
    #[must_use]
    pub(crate) fn f0(&self) -> [f32; 3] {
        let m = self.metallic.clamp(0.0, 1.0);
        self.base_color
            .map(|b| self.dielectric_f0 * (1.0 - m) + b.clamp(0.0, 1.0) * m)
    }

    /// The Lambertian albedo: base colour · (1 − metallic).
    #[must_use]
    pub(crate) fn diffuse_color(&self) -> [f32; 3] {
        let m = self.metallic.clamp(0.0, 1.0);
        self.base_color.map(|b| b.clamp(0.0, 1.0) * (1.0 - m))
    }

    /// The roughness clamped to [0, 1] (NaN to 0).
    #[must_use]
    pub(crate) fn clamped_roughness(&self) -> f32 {
        if self.roughness.is_nan() {
            0.0
        } else {
            self.roughness.clamp(0.0, 1.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn f0_and_diffuse_follow_the_metallic_mix() {
        let plastic = Material::preset("plastic").unwrap();
        assert_eq!(plastic.f0(), [0.04; 3]);
        assert_eq!(plastic.diffuse_color(), plastic.base_color);
        let gold = Material::preset("Gold").unwrap();
        assert_eq!(gold.f0(), gold.base_color);
        assert_eq!(gold.diffuse_color(), [0.0; 3]);
        let half = Material {
            metallic: 0.5,
            base_color: [1.0, 0.0, 0.5],
            ..Material::default()
        };
        assert_eq!(half.f0(), [0.52, 0.02, 0.27]);
        assert_eq!(half.diffuse_color(), [0.5, 0.0, 0.25]);
        let e = Material::preset("velvet").unwrap_err().to_string();
        assert!(
            e.contains("mirror, chrome, gold, plastic, rubber, diffuse"),
            "{e}"
        );
        for name in Material::PRESETS.split(", ") {
            let m = Material::preset(name).unwrap();
            assert!((0.0..=1.0).contains(&m.roughness) && (0.0..=1.0).contains(&m.metallic));
        }
    }
}
