// What envmap writes into a file about its conventions, and reads back.

use envmap_core::glam::{Mat3, Vec3};
use envmap_core::{AnyMapping, Frame};

use crate::image::convention::{Convention, FileAxes, World};
use crate::image::layout::{Layout, Representation};

/// The key of the mapping's name.
pub(crate) const MAPPING: &str = "envmap.mapping";
/// The key of a fisheye's lens and field of view (`"equidistant 190"`: the law, and degrees
/// per lens).
pub(crate) const LENS: &str = "envmap.lens";
/// The key of the layout's name.
pub(crate) const LAYOUT: &str = "envmap.layout";
/// The key of a six-file cube face's name.
pub(crate) const FACE: &str = "envmap.face";
/// The key of the axes (`format_axes`).
pub(crate) const AXES: &str = "envmap.axes";
/// The key of what the values are, when the writer said
/// ([`crate::image::io::SaveOptions::content`]): "irradiance E/pi", a
/// specular level's roughness, a DFG table's axes.
pub(crate) const CONTENT: &str = "envmap.content";

/// `tags` and `description` with `content` (what the values are) added,
/// when there is one.
pub(crate) fn with_content(
    mut tags: Vec<(String, String)>,
    description: String,
    content: Option<&str>,
) -> (Vec<(String, String)>, String) {
    let Some(c) = content else {
        return (tags, description);
    };
    tags.push((CONTENT.to_owned(), c.to_owned()));
    let description = if description.is_empty() {
        c.to_owned()
    } else {
        format!("{description}; {c}")
    };
    (tags, description)
}

/// What a file says about itself (any part may be missing).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct FileMetadata {
    /// The mapping it names.
    pub mapping: Option<AnyMapping>,
    /// The layout it names.
    pub layout: Option<Layout>,
    /// Its axes.
    pub axes: Option<FileAxes>,
}

impl FileMetadata {
    /// The key of the free text a file's writer gave about its content
    /// (`envmap.content`: `convert --content`), among a file's tags.
    pub const CONTENT_KEY: &'static str = CONTENT;
}

impl FileMetadata {
    /// Reads the `envmap.*` keys of `tags`; unknown values are ignored.
    #[must_use]
    pub(crate) fn from_tags(tags: &[(String, String)]) -> Self {
        let get = |k: &str| tags.iter().find(|(key, _)| key == k).map(|(_, v)| v.trim());
        // A fisheye's lens and field of view, when it says them.
        let lens = |m: AnyMapping| match (m, get(LENS)) {
            (AnyMapping::Fisheye(f), Some(t)) => f.from_lens_text(t).map(AnyMapping::Fisheye),
            _ => Some(m),
        };
        FileMetadata {
            mapping: get(MAPPING).and_then(|v| v.parse().ok()).and_then(lens),
            layout: get(LAYOUT).and_then(|v| v.parse().ok()),
            axes: get(AXES).and_then(parse_axes),
        }
    }

    /// Whether the file said anything about itself.
    #[must_use]
    pub fn is_empty(&self) -> bool {
        *self == FileMetadata::default()
    }
}

/// `axes` as [`AXES`] stores it.
#[must_use]
pub(crate) fn format_axes(axes: FileAxes) -> String {
    match axes {
        FileAxes::Convention(c, w) => format!("convention {c} world {w}"),
        FileAxes::Frame(f) => {
            let m = f.matrix().to_cols_array();
            let n: Vec<String> = m.iter().map(|x| format!("{x}")).collect();
            format!("frame {}", n.join(" "))
        }
    }
}

/// The inverse of [`format_axes`]; `None` for anything else (or a frame
/// that is not orthogonal).
#[must_use]
pub(crate) fn parse_axes(s: &str) -> Option<FileAxes> {
    let words: Vec<&str> = s.split_whitespace().collect();
    match words.as_slice() {
        ["convention", c, "world", w] => {
            Some(FileAxes::Convention(c.parse().ok()?, w.parse().ok()?))
        }
        ["frame", rest @ ..] if rest.len() == 9 => {
            let v: Vec<f32> = rest.iter().map(|x| x.parse().ok()).collect::<Option<_>>()?;
            let m = Mat3::from_cols(
                Vec3::new(v[0], v[1], v[2]),
                Vec3::new(v[3], v[4], v[5]),
                Vec3::new(v[6], v[7], v[8]),
            );
            Frame::from_mat3(m).map(FileAxes::Frame)
        }
        _ => None,
    }
}

/// The axes that give `frame` for a `mapping` file, by name where a
/// convention and world give it (the first in [`Convention::ALL`] order, in
/// [`World::YUp`], [`World::YUpLh`], [`World::ZUp`] order), else the frame.
#[must_use]
pub fn identify(mapping: AnyMapping, frame: Frame) -> FileAxes {
    for w in World::ALL {
        for c in Convention::ALL {
            let f = c.frame(mapping, w);
            if (f.matrix() - frame.matrix()).abs_diff_eq(Mat3::ZERO, 1e-6) {
                return FileAxes::Convention(c, w);
            }
        }
    }
    FileAxes::Frame(frame)
}

/// The tags envmap writes for an image of `repr` (`layout` as stored;
/// `face` for one file of a six-file cube).
#[must_use]
pub(crate) fn tags(
    repr: &Representation,
    layout: Option<Layout>,
    face: Option<&str>,
) -> Vec<(String, String)> {
    let axes = identify(repr.mapping, repr.frame);
    let mut t = vec![(MAPPING.to_owned(), repr.mapping.to_string())];
    if let AnyMapping::Fisheye(f) = repr.mapping {
        t.push((LENS.to_owned(), f.lens_text().to_string()));
    }
    if let Some(l) = layout.or_else(|| repr.layout()) {
        t.push((LAYOUT.to_owned(), l.name().to_owned()));
    }
    if let Some(f) = face {
        t.push((FACE.to_owned(), f.to_owned()));
    }
    t.push((AXES.to_owned(), format_axes(axes)));
    t
}

/// The words envmap writes beside the tags.
#[must_use]
pub(crate) fn description(
    repr: &Representation,
    layout: Option<Layout>,
    face: Option<&str>,
) -> String {
    let axes = identify(repr.mapping, repr.frame);
    let mapping = match repr.mapping {
        AnyMapping::Fisheye(f) => format!(
            "{} ({} lens, {} degrees each{})",
            repr.mapping,
            f.lens(),
            f.fov_degrees(),
            if f.covers_sphere() {
                ""
            } else {
                "; black where unseen"
            }
        ),
        m => m.to_string(),
    };
    let what = match (layout.or_else(|| repr.layout()), face) {
        (_, Some(f)) => format!("face {f} of a cube written as six files"),
        (Some(l), None) => format!("{mapping} map, {} layout", l.name()),
        (None, None) => format!("{mapping} map"),
    };
    format!("{what}; axes: {}", axes.describe(repr.mapping))
}

/// `s` with the few non-ASCII characters envmap's descriptions use spelled
/// in ASCII (any other replaced by `?`): OpenEXR text attributes and PNG
/// `tEXt` chunks hold Latin-1.
#[must_use]
#[cfg(any(feature = "exr", feature = "image"))]
pub(crate) fn ascii(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '−' => out.push('-'),
            '→' => out.push_str("->"),
            '×' => out.push('x'),
            'π' => out.push_str("pi"),
            c if c.is_ascii() => out.push(c),
            _ => out.push('?'),
        }
    }
    out
}

/// `envmap` and its version, for the software tag.
#[must_use]
pub(crate) fn software() -> String {
    format!("envmap {}", env!("CARGO_PKG_VERSION"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axes_round_trip_through_text() {
        for w in World::ALL {
            for c in Convention::ALL {
                let a = FileAxes::Convention(c, w);
                assert_eq!(parse_axes(&format_axes(a)), Some(a));
            }
        }
        let f = FileAxes::Frame(Frame::from_yaw_pitch_roll(0.3, -0.2, 1.0));
        let back = parse_axes(&format_axes(f)).unwrap();
        let (FileAxes::Frame(a), FileAxes::Frame(b)) = (f, back) else {
            panic!("{back:?}")
        };
        assert!(a.matrix().abs_diff_eq(b.matrix(), 1e-6));
        assert_eq!(parse_axes("frame 1 2 3"), None);
        assert_eq!(parse_axes("convention maya world y-up"), None);
    }

    #[test]
    fn identify_names_the_default_and_the_seed() {
        let f = Convention::Envmap.frame(AnyMapping::LatLong, World::YUp);
        assert_eq!(
            identify(AnyMapping::LatLong, f),
            FileAxes::Convention(Convention::Envmap, World::YUp)
        );
        assert_eq!(
            identify(AnyMapping::Cube, Frame::IDENTITY),
            FileAxes::Convention(Convention::Envmap, World::ZUp)
        );
        let odd = Frame::from_yaw_pitch_roll(0.1, 0.0, 0.0);
        assert_eq!(identify(AnyMapping::Cube, odd), FileAxes::Frame(odd));
        let t = tags(
            &Representation::for_file(AnyMapping::Cube, FileAxes::default()),
            None,
            None,
        );
        let m = FileMetadata::from_tags(&t);
        assert_eq!(m.mapping, Some(AnyMapping::Cube));
        assert_eq!(m.layout, Some(Layout::Cross));
        assert_eq!(m.axes, Some(FileAxes::default()));
    }
}
