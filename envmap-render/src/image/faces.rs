//! Cubes as six files.
//!
//! A cube can be written as six square files `<stem>_+x.<ext>`, `<stem>_-x.<ext>`,
//! ..., `<stem>_-z.<ext>` (the names of [`CubeFace::name`]), each face exactly
//! as GL expects it for `GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`. A path with
//! `{face}` in its file name is a pattern (`sky_{face}.exr`). A six-file cube
//! is loaded from the pattern, from any one of the six names (the siblings
//! are found), or from `<stem>.<ext>` with [`Layout::Faces`]; in memory it
//! becomes a horizontal strip. Six-file outputs write all six temporary files
//! before renaming any.

use std::path::{Path, PathBuf};

use envmap_core::{AnyMapping, CubeFace};

use crate::error::{Error, Result};
use crate::image::atomic::Outputs;
use crate::image::envimage::{check_size, EnvImage};
use crate::image::io::{
    apply_non_finite, encode, read_dimensions, read_rgb, FileFormat, LoadOptions, Loaded,
    SaveOptions, SourceFormat, View,
};
use crate::image::layout::{Layout, Representation};

/// The placeholder for the face name in a six-file pattern.
pub const FACE_PLACEHOLDER: &str = "{face}";

/// Whether the file name holds a [`FACE_PLACEHOLDER`] pattern.
#[must_use]
pub fn is_face_pattern(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| n.to_string_lossy().contains(FACE_PLACEHOLDER))
}

/// The face a file name names by its `_+x` ... `_-z` suffix, if any.
#[must_use]
pub fn face_of_name(path: &Path) -> Option<CubeFace> {
    let stem = path.file_stem()?.to_str()?;
    CubeFace::ALL.into_iter().find(|f| {
        stem.strip_suffix(f.name())
            .is_some_and(|s| s.ends_with('_'))
    })
}

/// The six face files of a cube, in GL order (+x, −x, +y, −y, +z, −z).
///
/// `path` may be a pattern (`sky_{face}.exr` → `sky_+x.exr`, ...), one of the
/// six names (`sky_-y.exr` → its siblings), or a plain name (`sky.exr` →
/// `sky_+x.exr`, ...).
pub fn face_paths(path: &Path) -> Result<[PathBuf; 6]> {
    let bad = || Error::layout("cannot name six cube faces after this path").in_file(path);
    let name = path.file_name().and_then(|n| n.to_str()).ok_or_else(bad)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let names: Vec<String> = if name.contains(FACE_PLACEHOLDER) {
        CubeFace::ALL
            .iter()
            .map(|f| name.replace(FACE_PLACEHOLDER, f.name()))
            .collect()
    } else {
        let stem = path.file_stem().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let ext = path.extension().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let base = match face_of_name(path) {
            Some(f) => &stem[..stem.len() - f.name().len() - 1],
            None => stem,
        };
        CubeFace::ALL
            .iter()
            .map(|f| format!("{base}_{}.{ext}", f.name()))
            .collect()
    };
    Ok(std::array::from_fn(|i| dir.join(&names[i])))
}

pub(super) fn load(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
    if let Some(m) = opts.mapping.filter(|m| *m != AnyMapping::Cube) {
        return Err(Error::layout(format!("six files hold a cube, not a {m} map")).in_file(path));
    }
    let paths = face_paths(path)?;
    FileFormat::from_path(&paths[0])?;
    for (p, f) in paths.iter().zip(CubeFace::ALL) {
        if !p.is_file() {
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!(
                    "face {} of the six-file cube is missing (expected {})",
                    f.name(),
                    name_list(&paths)
                ),
            });
        }
    }
    let mut size = None;
    for (p, f) in paths.iter().zip(CubeFace::ALL) {
        let (w, h) = read_dimensions(p)?;
        if w != h {
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!("face {} is {w}×{h}; cube faces must be square", f.name()),
            });
        }
        match size {
            None => size = Some(w),
            Some(s) if s != w => {
                return Err(Error::CubeFaces {
                    path: p.clone(),
                    message: format!(
                        "face {} is {w}×{h}, but face +x ({}) is {s}×{s}; all six faces must be the same size",
                        f.name(),
                        paths[0].display()
                    ),
                })
            }
            Some(_) => {}
        }
    }
    let s = size.unwrap_or(0);
    check_size(s, s, 6, opts.max_texels).map_err(|e| e.in_file(&paths[0]))?;
    let repr = Representation {
        mapping: AnyMapping::Cube,
        atlas: Layout::Faces.atlas(),
        frame: opts.frame,
    };
    let mut image = EnvImage::new_with_limit(6 * s, s, repr, opts.max_texels)
        .map_err(|e| e.in_file(&paths[0]))?;
    let mut source = None;
    let mut replaced = 0;
    for (chart, p) in (0u32..).zip(&paths) {
        let (mut face, src) = read_rgb(p, opts.max_texels, opts.cancel)?;
        replaced += apply_non_finite(&mut face.pixels, opts.non_finite);
        if (face.width, face.height) != (s, s) {
            // The header said otherwise a moment ago: the file changed.
            return Err(Error::CubeFaces {
                path: p.clone(),
                message: format!(
                    "face changed size while loading ({}×{})",
                    face.width, face.height
                ),
            });
        }
        image
            .set_chart_image(chart, &face)
            .map_err(|e| e.in_file(p))?;
        source.get_or_insert(src);
    }
    Ok(Loaded {
        image,
        source: source.unwrap_or(SourceFormat {
            format: FileFormat::from_path(&paths[0])?,
            pixel_format: String::new(),
        }),
        files: paths.to_vec(),
        replaced,
    })
}

fn name_list(paths: &[PathBuf]) -> String {
    let names: Vec<String> = paths
        .iter()
        .map(|p| {
            p.file_name()
                .unwrap_or_default()
                .to_string_lossy()
                .into_owned()
        })
        .collect();
    names.join(", ")
}

/// Stages a cube as six files named after `path` (see [`face_paths`]), in
/// `format`, into `run`.
pub(super) fn stage(
    run: &mut Outputs<'_>,
    image: &EnvImage,
    path: &Path,
    format: FileFormat,
    opts: &SaveOptions,
) -> Result<()> {
    if image.mapping() != AnyMapping::Cube {
        return Err(Error::layout(format!(
            "only a cube can be saved as six files; this image is a {} map",
            image.mapping()
        ))
        .in_file(path));
    }
    let paths = face_paths(path)?;
    for (chart, p) in (0u32..).zip(&paths) {
        let face = image
            .chart_image(chart)
            .ok_or_else(|| Error::layout(format!("the image has no face {chart}")))?;
        let view = View {
            width: face.width,
            height: face.height,
            pixels: &face.pixels,
        };
        run.stage_with(p, |out| encode(p, format, view, opts, out))?;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn face_names() {
        let names = |p: &str| -> Vec<String> {
            face_paths(Path::new(p))
                .unwrap()
                .iter()
                .map(|p| p.to_string_lossy().into_owned())
                .collect()
        };
        let expected = [
            "d/sky_+x.exr",
            "d/sky_-x.exr",
            "d/sky_+y.exr",
            "d/sky_-y.exr",
            "d/sky_+z.exr",
            "d/sky_-z.exr",
        ];
        assert_eq!(names("d/sky.exr"), expected);
        assert_eq!(names("d/sky_-y.exr"), expected);
        assert_eq!(names("d/sky_{face}.exr"), expected);
        assert_eq!(names("d/{face}.png")[5], "d/-z.png");
        assert_eq!(face_of_name(Path::new("sky_+z.png")), Some(CubeFace::PosZ));
        assert_eq!(face_of_name(Path::new("sky+z.png")), None);
        assert!(is_face_pattern(Path::new("a/b_{face}.hdr")));
    }
}
