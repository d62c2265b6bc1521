// Named layouts, and telling an image's representation from its size.

use std::fmt;
use std::str::FromStr;

use envmap_core::{AnyMapping, Atlas, Fisheye, Frame, Mapping};

use crate::error::{Error, Result};
use crate::image::convention::FileAxes;

/// A named layout of a representation's charts, as the command line spells it.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Layout {
    /// `latlong`: one 2:1 image.
    LatLong,
    /// `cross`: cube, horizontal cross (4×3 faces).
    Cross,
    /// `vcross`: cube, vertical cross (3×4 faces, −z turned half a turn).
    VCross,
    /// `strip`: cube, six faces in a row (6×1), GL order.
    Strip,
    /// `vstrip`: cube, six faces in a column (1×6), GL order.
    VStrip,
    /// `faces`: cube, six square files `<stem>_+x.<ext>` ... `<stem>_-z.<ext>`;
    /// held in memory as a [`Strip`](Layout::Strip).
    Faces,
    /// `square`: one square image (sphere maps, angular map, octahedral maps).
    Square,
    /// `side-by-side`: dual paraboloid (and dual fisheye), front disk left, back disk right
    /// (2:1).
    SideBySide,
    /// `stacked`: tennisball, two 3:1 strips stacked (3:2).
    Stacked,
    /// `3x2`: cube or EAC, three faces by two: +x, −x, +y over −y, +z, −z,
    /// each in GL's orientation (ffmpeg `v360`'s `c3x2`).
    Grid3x2,
    /// `v360`: EAC as ffmpeg's `v360` filter and YouTube store it: −x, +z,
    /// +x over −y, −z, +y, the bottom row's faces turned (−y and +y a
    /// quarter turn counter-clockwise, −z clockwise) and every row padded by
    /// 2 pixels on each side, so an `n`-texel face makes a
    /// `(3n + 4) × (2n + 8)` file. Held in memory unturned and unpadded
    /// ([`Atlas::EAC_V360`]); see [`crate::image`], "Layouts".
    V360,
    /// `dfisheye`: a dual fisheye as ffmpeg's `v360` lays it out (its `dfisheye`): the back
    /// lens (looking along −z) left, the front lens (along +z, the latlong's centre) right
    /// (2:1; [`Atlas::DUAL_FISHEYE_V360`]). The dual fisheye's default; `side-by-side` puts
    /// the front lens left.
    DualFisheye,
}

impl Layout {
    /// Every layout, in the order of [`Layout::NAMES`].
    pub const ALL: [Layout; 12] = [
        Layout::LatLong,
        Layout::Cross,
        Layout::VCross,
        Layout::Strip,
        Layout::VStrip,
        Layout::Faces,
        Layout::Square,
        Layout::SideBySide,
        Layout::Stacked,
        Layout::Grid3x2,
        Layout::V360,
        Layout::DualFisheye,
    ];

    /// The names [`FromStr`] accepts (case-insensitive), in the order of [`Layout::ALL`].
    pub const NAMES: [&'static str; 12] = [
        "latlong",
        "cross",
        "vcross",
        "strip",
        "vstrip",
        "faces",
        "square",
        "side-by-side",
        "stacked",
        "3x2",
        "v360",
        "dfisheye",
    ];

    /// The layout's name, as the command line spells it.
    #[must_use]
    pub const fn name(self) -> &'static str {
        Self::NAMES[self as usize]
    }

    /// The atlas that holds the image in memory. [`Layout::Faces`] is only an
    /// on-disk layout: in memory its faces form a horizontal strip.
    #[must_use]
    pub const fn atlas(self) -> Atlas {
        match self {
            Layout::LatLong => Atlas::LATLONG,
            Layout::Cross => Atlas::CUBE_HORIZONTAL_CROSS,
            Layout::VCross => Atlas::CUBE_VERTICAL_CROSS,
            Layout::Strip | Layout::Faces => Atlas::CUBE_HORIZONTAL_STRIP,
            Layout::VStrip => Atlas::CUBE_VERTICAL_STRIP,
            Layout::Square => Atlas::SINGLE_SQUARE,
            Layout::SideBySide => Atlas::PARABOLOID_SIDE_BY_SIDE,
            Layout::Stacked => Atlas::TENNISBALL_STACKED,
            Layout::Grid3x2 => Atlas::CUBE_3X2,
            Layout::V360 => Atlas::EAC_V360,
            Layout::DualFisheye => Atlas::DUAL_FISHEYE_V360,
        }
    }

    /// Whether this layout is six files rather than one image.
    #[must_use]
    pub const fn is_six_files(self) -> bool {
        matches!(self, Layout::Faces)
    }

    /// The single-image layout whose atlas is `atlas` (never [`Layout::Faces`]).
    #[must_use]
    pub(crate) fn from_atlas(atlas: &Atlas) -> Option<Layout> {
        Layout::ALL
            .into_iter()
            .filter(|l| !l.is_six_files())
            .find(|l| l.atlas() == *atlas)
    }

    /// The mappings that can be stored in this layout.
    #[must_use]
    pub const fn mappings(self) -> &'static [AnyMapping] {
        match self {
            Layout::LatLong => &[AnyMapping::LatLong],
            Layout::Cross
            | Layout::VCross
            | Layout::Strip
            | Layout::VStrip
            | Layout::Faces
            | Layout::Grid3x2 => &[AnyMapping::Cube, AnyMapping::Eac],
            Layout::V360 => &[AnyMapping::Eac],
            Layout::Square => &SQUARE_MAPPINGS,
            Layout::SideBySide => &[
                AnyMapping::DualParaboloid,
                AnyMapping::Fisheye(Fisheye::DUAL),
            ],
            Layout::Stacked => &[AnyMapping::Tennisball],
            Layout::DualFisheye => &[AnyMapping::Fisheye(Fisheye::DUAL)],
        }
    }

    /// The layouts a mapping can be stored in; the first is its default.
    #[must_use]
    pub const fn for_mapping(mapping: AnyMapping) -> &'static [Layout] {
        match mapping {
            AnyMapping::LatLong => &[Layout::LatLong],
            AnyMapping::Cube => &[
                Layout::Cross,
                Layout::VCross,
                Layout::Strip,
                Layout::VStrip,
                Layout::Grid3x2,
                Layout::Faces,
            ],
            AnyMapping::Eac => &[
                Layout::V360,
                Layout::Cross,
                Layout::VCross,
                Layout::Strip,
                Layout::VStrip,
                Layout::Grid3x2,
                Layout::Faces,
            ],
            AnyMapping::SphereMap
            | AnyMapping::SphereMapGl
            | AnyMapping::Octahedral
            | AnyMapping::EqualAreaOctahedral
            | AnyMapping::Angular => &[Layout::Square],
            AnyMapping::DualParaboloid => &[Layout::SideBySide],
            AnyMapping::Fisheye(f) if f.is_dual() => &[Layout::DualFisheye, Layout::SideBySide],
            AnyMapping::Fisheye(_) => &[Layout::Square],
            AnyMapping::Tennisball => &[Layout::Stacked],
        }
    }

    /// The aspect ratio of the whole image (`"4:3"`), or `"six square files"`.
    #[must_use]
    pub(crate) fn aspect_text(self) -> String {
        if self.is_six_files() {
            return "six square files".to_owned();
        }
        let (w, h) = self.atlas().image_aspect();
        format!("{w}:{h}")
    }
}

/// What an image's texels mean: the mapping, the layout of its charts, and
/// the axis convention.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Representation {
    /// The parameterization the charts follow.
    pub mapping: AnyMapping,
    /// Where each chart lies in the image.
    pub atlas: Atlas,
    /// The axes the map was made in: the mapping's formulas are applied to
    /// directions expressed in these axes, and `frame.to_canonical` takes
    /// them to envmap's canonical z-up, right-handed world. A z-up map (seed
    /// `000`, Blender) has [`Frame::Z_UP_RH`]; a cube map for GL, Vulkan or
    /// wgpu, whose +y face is up, has [`Frame::Y_UP_RH`].
    pub frame: Frame,
}

impl Representation {
    /// A representation; an error unless `atlas` can hold `mapping` (one cell
    /// per chart, cells of the mapping's shape).
    pub fn new(mapping: AnyMapping, atlas: Atlas, frame: Frame) -> Result<Self> {
        check_compatible(mapping, &atlas)?;
        Ok(Self {
            mapping,
            atlas,
            frame,
        })
    }

    /// `mapping` in its default atlas and the frame its files have with
    /// `axes` (for example [`FileAxes::default`]: envmap's conventions in
    /// the GL world; see [`crate::image`]).
    #[must_use]
    pub fn for_file(mapping: AnyMapping, axes: FileAxes) -> Self {
        Self {
            frame: axes.frame(mapping),
            ..Self::default_for(mapping)
        }
    }

    /// `mapping` in its default atlas ([`Mapping::atlas`]) and the identity
    /// frame (envmap's canonical axes; the seed's).
    #[must_use]
    pub fn default_for(mapping: AnyMapping) -> Self {
        Self {
            mapping,
            atlas: mapping.atlas(),
            frame: Frame::IDENTITY,
        }
    }

    /// The named layout of this atlas, if it is one of the built-in ones.
    #[must_use]
    pub fn layout(&self) -> Option<Layout> {
        Layout::from_atlas(&self.atlas)
    }

    /// Image size for cells `cell_width` texels wide (a cube's face edge, a
    /// latlong's width); `None` if the cell height would not be whole.
    #[cfg_attr(not(feature = "instruments"), allow(dead_code))]
    #[cfg_attr(feature = "instruments", visibility::make(pub))]
    #[must_use]
    pub(crate) fn size_for_cell_width(&self, cell_width: u32) -> Option<(u32, u32)> {
        self.atlas.image_size_for_cell_width(cell_width)
    }

    /// The size of the file that holds a `width × height` image of this
    /// representation: the image's own, but for a layout whose files are
    /// padded ([`Layout::V360`]: 4 more pixels across, 8 more down).
    #[must_use]
    pub fn file_size(&self, width: u32, height: u32) -> (u32, u32) {
        match crate::image::framing::Framing::of(&self.atlas) {
            Some(f) => f.file_size(&self.atlas, width, height),
            None => (width, height),
        }
    }

    /// Checks that a `width × height` image fits this representation.
    pub(crate) fn check_size(&self, width: u32, height: u32) -> Result<()> {
        check_fits(self.mapping, &self.atlas, width, height)
    }
}

/// The square single-chart mappings, which a 1:1 image cannot tell apart.
const SQUARE_MAPPINGS: [AnyMapping; 6] = [
    AnyMapping::SphereMap,
    AnyMapping::SphereMapGl,
    AnyMapping::Angular,
    AnyMapping::Octahedral,
    AnyMapping::EqualAreaOctahedral,
    AnyMapping::Fisheye(Fisheye::SINGLE),
];

impl fmt::Display for Layout {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for Layout {
    type Err = Error;

    /// Parses the names in [`Layout::NAMES`] (case-insensitive), plus the
    /// aliases `equirect`, `hcross`, `horizontal-cross`, `vertical-cross`,
    /// `hstrip`, `horizontal-strip`, `vertical-strip`, `six-files`, `sphere`,
    /// `octahedral`, `sidebyside`, `paraboloid` and `tennisball`.
    fn from_str(s: &str) -> Result<Self> {
        let eq = |a: &str| s.eq_ignore_ascii_case(a);
        if let Some(l) = Layout::ALL.into_iter().find(|l| eq(l.name())) {
            return Ok(l);
        }
        Ok(match () {
            () if eq("equirect") => Layout::LatLong,
            () if eq("hcross") || eq("horizontal-cross") => Layout::Cross,
            () if eq("vertical-cross") => Layout::VCross,
            () if eq("hstrip") || eq("horizontal-strip") => Layout::Strip,
            () if eq("vertical-strip") => Layout::VStrip,
            () if eq("six-files") => Layout::Faces,
            () if eq("sphere") || eq("octahedral") => Layout::Square,
            () if eq("sidebyside") || eq("paraboloid") => Layout::SideBySide,
            () if eq("tennisball") => Layout::Stacked,
            () => {
                return Err(Error::UnknownName {
                    what: "layout",
                    name: s.to_owned(),
                    expected: Layout::NAMES.join(", "),
                })
            }
        })
    }
}

/// The aspect ratios [`detect`] accepts, with what each is taken for.
const DETECTED: [((u32, u32), AnyMapping, Layout, &str); 5] = [
    ((2, 1), AnyMapping::LatLong, Layout::LatLong, "latlong"),
    ((4, 3), AnyMapping::Cube, Layout::Cross, "cube cross"),
    (
        (3, 4),
        AnyMapping::Cube,
        Layout::VCross,
        "cube vertical cross",
    ),
    ((6, 1), AnyMapping::Cube, Layout::Strip, "cube strip"),
    (
        (1, 6),
        AnyMapping::Cube,
        Layout::VStrip,
        "cube vertical strip",
    ),
];

/// `w : h` reduced to lowest terms (`(0, 0)` for an empty image).
#[must_use]
pub(crate) fn aspect_ratio(width: u32, height: u32) -> (u32, u32) {
    let (mut a, mut b) = (width, height);
    while b != 0 {
        (a, b) = (b, a % b);
    }
    match (width.checked_div(a), height.checked_div(a)) {
        (Some(w), Some(h)) => (w, h),
        _ => (0, 0),
    }
}

fn accepted_ratios() -> String {
    let mut s = String::new();
    for ((w, h), _, _, what) in DETECTED {
        s.push_str(&format!("{w}:{h} {what}, "));
    }
    s.push_str(
        "1:1 sphere or octahedral (name the mapping), 3:2 tennisball or a cube in 3×2 (name \
         it); a dual paraboloid is 2:1 and needs its mapping named (--from paraboloid); \
         ffmpeg v360's EAC, (3n + 4) × (2n + 8), needs --from eac",
    );
    s
}

fn size_text(width: u32, height: u32) -> String {
    let (a, b) = aspect_ratio(width, height);
    format!("{width}×{height} ({a}:{b})")
}

/// Picks a representation from the aspect ratio of a `width × height` image.
///
/// 2:1 is latlong (a dual paraboloid, also 2:1, must be named explicitly,
/// see [`resolve`]), 4:3 a cube cross, 3:4 a vertical cross, 6:1 a strip,
/// 1:6 a vertical strip, 3:2 a tennisball. A square image is an error that
/// lists the five square mappings and says how to choose; any other size is
/// an error naming its ratio and the accepted ones.
///
/// ```
/// use envmap_core::{AnyMapping, Atlas};
/// use envmap_render::image::detect;
/// assert_eq!(detect(4096, 3072).unwrap(), (AnyMapping::Cube, Atlas::CUBE_HORIZONTAL_CROSS));
/// assert!(detect(512, 512).unwrap_err().to_string().contains("octahedral"));
/// ```
pub fn detect(width: u32, height: u32) -> Result<(AnyMapping, Atlas)> {
    if width == 0 || height == 0 {
        return Err(Error::layout(format!(
            "image is {width}×{height}: an environment map cannot be empty"
        )));
    }
    let ratio = aspect_ratio(width, height);
    if let Some((_, m, l, _)) = DETECTED.iter().find(|(r, ..)| *r == ratio) {
        return Ok((*m, l.atlas()));
    }
    if ratio == (1, 1) {
        return Err(Error::layout(format!(
            "image is {}: a square image can be a sphere map (sphere, or sphere-gl for \
             GL_SPHERE_MAP and mirror-ball photographs), an angular map (angular, the \
             light-probe format) or an octahedral map (octahedral, octahedral-equal-area); \
             name the mapping (e.g. --from octahedral)",
            size_text(width, height)
        )));
    }
    if ratio == (3, 2) {
        return Err(Error::layout(format!(
            "image is {}: a 3:2 image can be a tennisball map (two 3:1 strips stacked: \
             --from tennisball) or a cube of three faces by two (ffmpeg v360's c3x2: \
             --from-layout 3x2; an equi-angular one: --from eac --from-layout 3x2); name it",
            size_text(width, height)
        )));
    }
    let v360 = Layout::V360.atlas();
    let eac = crate::image::framing::Framing::of(&v360)
        .and_then(|f| f.inner_size(&v360, width, height).ok());
    let hint = if let Some((w, _)) = eac {
        format!(
            " ({width}×{height} is (3n + 4) × (2n + 8) for n = {}: ffmpeg v360's equi-angular \
             cube map, read with --from eac)",
            w / 3
        )
    } else if ratio == (3, 1) {
        " (3:1 is one tennisball strip; a tennisball map stacks both strips, 3:2)".to_owned()
    } else {
        near_hint(width, height)
    };
    Err(Error::layout(format!(
        "image is {}: no layout has this aspect ratio{hint}. Accepted: {}",
        size_text(width, height),
        accepted_ratios()
    )))
}

/// A hint when a size is within 1 % of an accepted ratio but not exact.
fn near_hint(width: u32, height: u32) -> String {
    let r = f64::from(width) / f64::from(height);
    let mut ratios: Vec<((u32, u32), &str)> =
        DETECTED.iter().map(|(r, _, _, what)| (*r, *what)).collect();
    ratios.push(((1, 1), "square"));
    ratios.push(((3, 2), "tennisball or a 3×2 cube"));
    for ((a, b), what) in ratios {
        let q = f64::from(a) / f64::from(b);
        if (r / q - 1.0).abs() < 0.01 {
            return format!(" (close to {a}:{b}, {what}, but charts must be whole texels)");
        }
    }
    String::new()
}

/// Checks that `atlas` can hold `mapping` (one cell per chart, cells of the
/// mapping's shape) and that a `width × height` image fits it.
pub(crate) fn check_fits(
    mapping: AnyMapping,
    atlas: &Atlas,
    width: u32,
    height: u32,
) -> Result<()> {
    check_compatible(mapping, atlas)?;
    if atlas.cell_size(width, height).is_none() {
        let (a, b) = atlas.image_aspect();
        let mut msg = format!(
            "{} needs {a}:{b}, this image is {}",
            atlas.name,
            size_text(width, height)
        );
        if aspect_ratio(width, height) == (a, b) {
            // Right ratio, but the cells are not whole texels (e.g. 3:2 at 150×100).
            msg.push_str(&format!(
                " and its {}×{} cells are not whole texels",
                atlas.cols, atlas.rows
            ));
        }
        return Err(Error::layout(msg));
    }
    Ok(())
}

/// Checks that `atlas` can hold `mapping`: one cell per chart, each chart
/// present once, and cells of the shape of the mapping's default atlas.
pub(crate) fn check_compatible(mapping: AnyMapping, atlas: &Atlas) -> Result<()> {
    let n = mapping.chart_count();
    let default = mapping.atlas();
    let shape = |a: &Atlas| aspect_ratio(a.cell_aspect_w, a.cell_aspect_h);
    let charts_ok = atlas.cells.len() == n as usize
        && (0..n).all(|c| atlas.cells.iter().filter(|cell| cell.chart == c).count() == 1)
        && atlas
            .cells
            .iter()
            .all(|c| c.col < atlas.cols && c.row < atlas.rows);
    if !charts_ok || shape(atlas) != shape(&default) {
        let names: Vec<&str> = Layout::for_mapping(mapping)
            .iter()
            .map(|l| l.name())
            .collect();
        return Err(Error::layout(format!(
            "{mapping} cannot be laid out as {}; its layouts: {}",
            atlas.name,
            names.join(", ")
        )));
    }
    Ok(())
}

/// The representation of a `width × height` image, from an explicit mapping
/// and/or layout, or detected from the aspect ratio when neither is given.
///
/// * neither: [`detect`];
/// * a mapping only: the mapping's layout that fits the size (a cube tries
///   cross, vcross, strip, vstrip), or an error saying what it needs;
/// * a layout only: the layout's mapping (a cube layout's: the cube, not
///   EAC); `square` fits five mappings and is an error asking for the
///   mapping;
/// * both: the layout must be one of the mapping's and fit the size
///   ("cross needs 4:3, this image is 2048×1024 (2:1)").
///
/// [`Layout::Faces`] describes six files, not one image, and is refused here
/// (the loader assembles the faces into a strip first).
pub fn resolve(
    width: u32,
    height: u32,
    mapping: Option<AnyMapping>,
    layout: Option<Layout>,
) -> Result<(AnyMapping, Atlas)> {
    if layout.is_some_and(Layout::is_six_files) {
        return Err(Error::layout(
            "faces is a layout of six files, not of one image; \
             load a six-file cube by one face's name or a {face} pattern",
        ));
    }
    match (mapping, layout) {
        (None, None) => detect(width, height),
        (Some(m), None) => {
            let layouts: Vec<Layout> = Layout::for_mapping(m)
                .iter()
                .copied()
                .filter(|l| !l.is_six_files())
                .collect();
            if let Some(l) = layouts
                .iter()
                .find(|l| l.atlas().cell_size(width, height).is_some())
            {
                return Ok((m, l.atlas()));
            }
            let needs: Vec<String> = layouts
                .iter()
                .map(|l| format!("{} ({l})", l.aspect_text()))
                .collect();
            Err(Error::layout(format!(
                "{m} needs {}, this image is {}",
                join_or(&needs),
                size_text(width, height)
            )))
        }
        // A cube layout alone is the cube's, side by side the paraboloid's: an EAC map or a
        // dual fisheye in one is named.
        (None, Some(l)) => match l.mappings() {
            [m] | [m @ (AnyMapping::Cube | AnyMapping::DualParaboloid), ..] => {
                check_fits(*m, &l.atlas(), width, height)?;
                Ok((*m, l.atlas()))
            }
            many => {
                let names: Vec<String> = many.iter().map(ToString::to_string).collect();
                Err(Error::layout(format!(
                    "the {l} layout holds {}; name the mapping (e.g. --from {})",
                    join_or(&names),
                    names[0]
                )))
            }
        },
        (Some(m), Some(l)) => {
            if !Layout::for_mapping(m).contains(&l) {
                let names: Vec<&str> = Layout::for_mapping(m).iter().map(|l| l.name()).collect();
                return Err(Error::layout(format!(
                    "{m} has no {l} layout; its layouts: {}",
                    names.join(", ")
                )));
            }
            check_fits(m, &l.atlas(), width, height)?;
            Ok((m, l.atlas()))
        }
    }
}

/// [`resolve`], packaged with a frame as a [`Representation`].
pub fn representation(
    width: u32,
    height: u32,
    mapping: Option<AnyMapping>,
    layout: Option<Layout>,
    frame: Frame,
) -> Result<Representation> {
    let (mapping, atlas) = resolve(width, height, mapping, layout)?;
    Ok(Representation {
        mapping,
        atlas,
        frame,
    })
}

fn join_or(items: &[String]) -> String {
    match items {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} or {last}", init.join(", ")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for l in Layout::ALL {
            assert_eq!(l.name().parse::<Layout>().unwrap(), l);
            assert_eq!(l.name().to_uppercase().parse::<Layout>().unwrap(), l);
            if !l.is_six_files() {
                assert_eq!(Layout::from_atlas(&l.atlas()), Some(l));
            }
            for m in l.mappings() {
                assert!(Layout::for_mapping(*m).contains(&l));
                check_compatible(*m, &l.atlas()).unwrap();
            }
        }
        let e = "diagonal".parse::<Layout>().unwrap_err().to_string();
        assert!(e.contains("vcross") && e.contains("diagonal"), "{e}");
    }

    #[test]
    fn join() {
        let v = |s: &[&str]| s.iter().map(|s| (*s).to_owned()).collect::<Vec<_>>();
        assert_eq!(join_or(&v(&["a"])), "a");
        assert_eq!(join_or(&v(&["a", "b", "c"])), "a, b or c");
    }

    #[test]
    fn aspect() {
        assert_eq!(aspect_ratio(4096, 3072), (4, 3));
        assert_eq!(aspect_ratio(1000, 333), (1000, 333));
        assert_eq!(aspect_ratio(0, 0), (0, 0));
    }
}
