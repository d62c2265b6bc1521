//! Cubes as six files.
//!
//! A cube can be written as six square files `<stem>_+x.<ext>`, `<stem>_-x.<ext>`,
//! ..., `<stem>_-z.<ext>` (the names of [`CubeFace::name`]), each face exactly
//! as GL expects it for `GL_TEXTURE_CUBE_MAP_POSITIVE_X + face`, or under the
//! names of another scheme ([`FaceNames`]: `px nx ...`, `posx negx ...`,
//! `right left top bottom front back`, `0 ... 5`, `R L U D F B`). A path
//! with `{face}` in its file name is a pattern (`sky_{face}.exr`). A six-file
//! cube is loaded from the pattern, from any one of the six names in any
//! scheme (the siblings are found), or from `<stem>.<ext>` with
//! [`Layout::Faces`]; in memory it becomes a horizontal strip. Six-file
//! outputs write all six temporary files before renaming any.

use std::path::{Path, PathBuf};

use envmap_core::{AnyMapping, CubeFace};

use crate::error::{Error, Result};
use crate::image::atomic::Outputs;
use crate::image::envimage::{check_size, EnvImage};
use crate::image::format::FileFormat;
use crate::image::io::{
    apply_non_finite, encode, read_dimensions, read_rgb, LoadOptions, Loaded, SaveOptions,
    SourceFormat, View,
};
use crate::image::layout::{Layout, Representation};
use crate::image::metadata::{self, FileMetadata};

/// The placeholder for the face name in a six-file pattern.
pub const FACE_PLACEHOLDER: &str = "{face}";

/// Whether the file name holds a [`FACE_PLACEHOLDER`] pattern.
#[must_use]
pub(crate) fn is_face_pattern(path: &Path) -> bool {
    path.file_name()
        .is_some_and(|n| n.to_string_lossy().contains(FACE_PLACEHOLDER))
}

/// How the six files of a cube are named: the face names of a scheme, in
/// GL order (+x, −x, +y, −y, +z, −z), each placed after the stem and an
/// underscore (`sky_px.exr`) or where a `{face}` pattern says.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum FaceNames {
    /// `+x -x +y -y +z -z` (envmap's, [`CubeFace::name`]).
    #[default]
    Signs,
    /// `px nx py ny pz nz` (Filament's cmgen, three.js examples).
    Px,
    /// `posx negx posy negy posz negz` (Humus's cube maps, many engines).
    Pos,
    /// `right left top bottom front back` (three.js examples; Unity's
    /// 6-sided skybox names +x "Left", being left-handed: pass
    /// `--face-transform` or rename for it).
    Words,
    /// `0 1 2 3 4 5` (the GL face index).
    Index,
    /// `R L U D F B` (py360convert's faces: Right, Left, Up, Down, Front,
    /// Back are +x, −x, +y, −y, +z, −z).
    Frblud,
}

impl FaceNames {
    /// Every scheme, as [`FaceNames::NAMES`] lists them.
    pub const ALL: [FaceNames; 6] = [
        FaceNames::Signs,
        FaceNames::Px,
        FaceNames::Pos,
        FaceNames::Words,
        FaceNames::Index,
        FaceNames::Frblud,
    ];

    /// The names on the command line (`--face-names`).
    pub const NAMES: [&'static str; 6] = ["+x", "px", "posx", "words", "index", "frblud"];

    /// The scheme's name on the command line.
    #[must_use]
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The six face names, in GL order.
    #[must_use]
    pub const fn names(self) -> [&'static str; 6] {
        match self {
            FaceNames::Signs => ["+x", "-x", "+y", "-y", "+z", "-z"],
            FaceNames::Px => ["px", "nx", "py", "ny", "pz", "nz"],
            FaceNames::Pos => ["posx", "negx", "posy", "negy", "posz", "negz"],
            FaceNames::Words => ["right", "left", "top", "bottom", "front", "back"],
            FaceNames::Index => ["0", "1", "2", "3", "4", "5"],
            FaceNames::Frblud => ["R", "L", "U", "D", "F", "B"],
        }
    }

    /// Whether one file name of the scheme is taken for a cube face on its
    /// own, six files or not (`sky_+x.exr`, `m0_px.hdr`, `posx.jpg`); the
    /// others (`front.png`, `sky_0.exr`, `F.png`) are taken for one only
    /// when all six exist, square and of one size.
    #[must_use]
    pub(crate) const fn is_distinctive(self) -> bool {
        matches!(self, FaceNames::Signs | FaceNames::Px | FaceNames::Pos)
    }
}

impl std::fmt::Display for FaceNames {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl std::str::FromStr for FaceNames {
    type Err = Error;

    /// The names in [`FaceNames::NAMES`] (case-insensitive), any face name
    /// of a scheme (`px`, `right`, `0`, `F`), and `signs`, `envmap`
    /// (+x); `cmgen` (px); `pos` (posx); `three` (words); `py360convert`
    /// (frblud).
    fn from_str(s: &str) -> Result<Self> {
        let l = s.to_ascii_lowercase();
        if let Some(n) = FaceNames::ALL.into_iter().find(|n| n.name() == l) {
            return Ok(n);
        }
        match l.as_str() {
            "signs" | "envmap" => return Ok(FaceNames::Signs),
            "cmgen" => return Ok(FaceNames::Px),
            "pos" => return Ok(FaceNames::Pos),
            "three" => return Ok(FaceNames::Words),
            "py360convert" => return Ok(FaceNames::Frblud),
            _ => {}
        }
        if let Some((n, _)) = scheme_of_face_name(&l) {
            return Ok(n);
        }
        Err(Error::UnknownName {
            what: "face naming scheme",
            name: s.to_owned(),
            expected: "+x (+x -x +y -y +z -z), px (px nx ...), posx (posx negx ...), \
                       words (right left top bottom front back), index (0 ... 5), \
                       frblud (R L U D F B)"
                .to_owned(),
        })
    }
}

/// The scheme and face of one face name (case-insensitive).
fn scheme_of_face_name(name: &str) -> Option<(FaceNames, CubeFace)> {
    FaceNames::ALL.into_iter().find_map(|n| {
        n.names()
            .iter()
            .position(|f| f.eq_ignore_ascii_case(name))
            .and_then(|i| CubeFace::from_index(i as u32))
            .map(|f| (n, f))
    })
}

/// A face name found at the end of a file's stem.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FaceName {
    /// The naming scheme.
    pub scheme: FaceNames,
    /// The face.
    pub face: CubeFace,
    /// The stem before the name, separator included (`"sky_"`, or empty).
    pub prefix: String,
    /// Whether the name was in capitals (`PX.png`): its siblings are too.
    pub upper: bool,
}

/// The face a file name names: a face name of any [`FaceNames`] scheme
/// (case-insensitive) ending its stem, after `_`, `-`, `.`, a space or
/// nothing (`sky_+x.exr`, `m0_px.hdr`, `posx.jpg`, `front.png`, `F.png`).
/// The sign names need their separator: `sky+x.png` names no face.
#[must_use]
pub(crate) fn face_name(path: &Path) -> Option<FaceName> {
    let stem = path.file_stem()?.to_str()?;
    for scheme in FaceNames::ALL {
        for (i, n) in scheme.names().iter().enumerate() {
            let Some(cut) = stem.len().checked_sub(n.len()) else {
                continue;
            };
            let Some((prefix, tail)) = stem.split_at_checked(cut) else {
                continue;
            };
            let separated = prefix.is_empty() || prefix.ends_with(['_', '-', '.', ' ']);
            if !separated || !tail.eq_ignore_ascii_case(n) {
                continue;
            }
            let face = CubeFace::from_index(i as u32)?;
            let upper = tail.chars().any(|c| c.is_ascii_uppercase())
                && !tail.chars().any(|c| c.is_ascii_lowercase())
                && scheme != FaceNames::Frblud;
            return Some(FaceName {
                scheme,
                face,
                prefix: prefix.to_owned(),
                upper,
            });
        }
    }
    None
}

#[cfg(test)]
/// The face a file name names by a face name of any scheme; see
/// [`face_name`].
#[must_use]
pub(crate) fn face_of_name(path: &Path) -> Option<CubeFace> {
    face_name(path).map(|f| f.face)
}

/// The six face files of a cube, in GL order (+x, −x, +y, −y, +z, −z).
///
/// `path` may be a pattern (`sky_{face}.exr` → `sky_+x.exr`, ...: the first
/// scheme whose six files all exist, else the sign names), one of the six
/// names in any scheme (`sky_-y.exr`, `m0_ny.hdr` → its siblings in its
/// scheme), or a plain name (`sky.exr` → `sky_+x.exr`, ...).
pub fn face_paths(path: &Path) -> Result<[PathBuf; 6]> {
    if is_face_pattern(path) {
        for scheme in FaceNames::ALL {
            let p = face_paths_named(path, scheme)?;
            if p.iter().all(|p| p.is_file()) {
                return Ok(p);
            }
        }
    }
    let scheme = face_name(path).map_or(FaceNames::Signs, |f| f.scheme);
    face_paths_named(path, scheme)
}

/// The six face files of a cube named in `scheme`: a `{face}` pattern
/// filled with its names; the siblings of a face's file name (its prefix
/// kept, in the same case); or `<stem>_<name>.<ext>` after a plain name.
pub fn face_paths_named(path: &Path, scheme: FaceNames) -> Result<[PathBuf; 6]> {
    let bad = || Error::layout("cannot name six cube faces after this path").in_file(path);
    let name = path.file_name().and_then(|n| n.to_str()).ok_or_else(bad)?;
    let dir = path.parent().unwrap_or(Path::new(""));
    let faces = scheme.names();
    let names: Vec<String> = if name.contains(FACE_PLACEHOLDER) {
        faces
            .iter()
            .map(|f| name.replace(FACE_PLACEHOLDER, f))
            .collect()
    } else {
        let stem = path.file_stem().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let ext = path.extension().and_then(|s| s.to_str()).ok_or_else(bad)?;
        let (prefix, upper) = match face_name(path) {
            Some(f) => (f.prefix, f.upper),
            None => (format!("{stem}_"), false),
        };
        faces
            .iter()
            .map(|f| {
                let f = if upper {
                    f.to_ascii_uppercase()
                } else {
                    (*f).to_owned()
                };
                format!("{prefix}{f}.{ext}")
            })
            .collect()
    };
    Ok(std::array::from_fn(|i| dir.join(&names[i])))
}

/// Whether `path` is one face of a six-file cube by its name alone: a
/// pattern, or a face name of a distinctive scheme; or of another scheme
/// when its six files exist, square and of one size.
pub(super) fn names_a_face_file(path: &Path) -> bool {
    if is_face_pattern(path) {
        return true;
    }
    let Some(f) = face_name(path) else {
        return false;
    };
    if f.scheme.is_distinctive() {
        return true;
    }
    let Ok(paths) = face_paths_named(path, f.scheme) else {
        return false;
    };
    let sizes: Option<Vec<(u32, u32)>> = paths.iter().map(|p| read_dimensions(p).ok()).collect();
    sizes.is_some_and(|s| s.iter().all(|&(w, h)| w == h && (w, h) == s[0]))
}

pub(super) fn load_six(path: &Path, opts: &LoadOptions) -> Result<Loaded> {
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
        frame: opts.axes.unwrap_or_default().frame(AnyMapping::Cube),
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
    let mut image = opts
        .face_transforms
        .apply(image, false)
        .map_err(|e| e.in_file(path))?;
    let source = source.unwrap_or(SourceFormat {
        format: FileFormat::from_path(&paths[0])?,
        pixel_format: String::new(),
        tags: Vec::new(),
    });
    // The +x face's own word on the axes, unless the caller gave them.
    let metadata = FileMetadata::from_tags(&source.tags);
    if let (None, Some(axes)) = (opts.axes, metadata.axes) {
        image.set_frame(axes.frame(AnyMapping::Cube));
    }
    Ok(Loaded {
        image,
        source,
        files: paths.to_vec(),
        replaced,
        metadata,
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
    let scheme = opts
        .face_names
        .or_else(|| face_name(path).map(|f| f.scheme))
        .unwrap_or_default();
    let paths = face_paths_named(path, scheme)?;
    for ((chart, p), f) in (0u32..).zip(&paths).zip(CubeFace::ALL) {
        let face = image
            .chart_image(chart)
            .ok_or_else(|| Error::layout(format!("the image has no face {chart}")))?;
        let repr = image.representation();
        let (tags, description) = metadata::with_content(
            metadata::tags(repr, Some(Layout::Faces), Some(f.name())),
            metadata::description(repr, Some(Layout::Faces), Some(f.name())),
            opts.content.as_deref(),
        );
        let view = View {
            width: face.width,
            height: face.height,
            pixels: &face.pixels,
            stream: None,
            atlas: None,
            tags: &tags,
            description: &description,
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
