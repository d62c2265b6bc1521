//! [`AnyMapping`]: every mapping behind one enum, for code that picks at run time.

use core::fmt;
use core::str::FromStr;

use glam::Vec3;

use crate::atlas::Atlas;
use crate::fisheye::Fisheye;
use crate::mapping::{ChartUv, Mapping};
use crate::{
    Angular, Cube, DualParaboloid, Eac, EqualAreaOctahedral, LatLong, Octahedral, SphereMap,
    Tennisball,
};

/// Every mapping of the crate, chosen at run time (a command-line flag, a file
/// header). Implements [`Mapping`] by dispatching to the concrete type.
///
/// Every mapping but a [`Fisheye`] that does not cover the sphere (one lens under 360°, two
/// under 180°) gives every finite non-zero direction a chart point; such a fisheye gives
/// `None` for the directions it does not see ([`AnyMapping::covers_sphere`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum AnyMapping {
    /// [`LatLong`].
    LatLong,
    /// [`Cube`].
    Cube,
    /// [`SphereMap::CLASS`] (eye along +z).
    SphereMap,
    /// [`SphereMap::OPENGL`] (eye along −z, `GL_SPHERE_MAP`).
    SphereMapGl,
    /// [`DualParaboloid`].
    DualParaboloid,
    /// [`Tennisball`].
    Tennisball,
    /// [`Octahedral`].
    Octahedral,
    /// [`EqualAreaOctahedral`].
    EqualAreaOctahedral,
    /// [`Angular`] (Debevec's light probe).
    Angular,
    /// [`Eac`] (the equi-angular cube map).
    Eac,
    /// A [`Fisheye`]: one lens or two back to back, of a given law and field of view.
    Fisheye(Fisheye),
}

impl AnyMapping {
    /// Every mapping, in a fixed order.
    ///
    /// The fisheyes appear with their defaults ([`Fisheye::SINGLE`], [`Fisheye::DUAL`]): one
    /// equidistant lens of 180°, which sees half the sphere, and two back to back.
    pub const ALL: [AnyMapping; 12] = [
        AnyMapping::LatLong,
        AnyMapping::Cube,
        AnyMapping::SphereMap,
        AnyMapping::SphereMapGl,
        AnyMapping::DualParaboloid,
        AnyMapping::Tennisball,
        AnyMapping::Octahedral,
        AnyMapping::EqualAreaOctahedral,
        AnyMapping::Angular,
        AnyMapping::Eac,
        AnyMapping::Fisheye(Fisheye::SINGLE),
        AnyMapping::Fisheye(Fisheye::DUAL),
    ];

    /// The names [`FromStr`] accepts, in the order of [`AnyMapping::ALL`].
    /// The names are those of the kinds of mapping: a fisheye's parameters other than whether
    /// it is dual are not part of its name.
    pub const NAMES: [&'static str; 12] = [
        "latlong",
        "cube",
        "sphere",
        "sphere-gl",
        "paraboloid",
        "tennisball",
        "octahedral",
        "octahedral-equal-area",
        "angular",
        "eac",
        "fisheye",
        "dual-fisheye",
    ];

    /// Whether the charts are disks inscribed in their squares (sphere maps,
    /// dual paraboloid, angular map, fisheyes): texels outside the disk hold no
    /// direction, and a filter must stay inside the rim.
    #[inline]
    #[must_use]
    pub const fn has_disk_charts(self) -> bool {
        matches!(
            self,
            AnyMapping::SphereMap
                | AnyMapping::SphereMapGl
                | AnyMapping::DualParaboloid
                | AnyMapping::Angular
                | AnyMapping::Fisheye(_)
        )
    }

    /// Whether every finite non-zero direction has a chart point: true but for a
    /// [`Fisheye`] that does not cover the sphere, whose
    /// [`forward`](AnyMapping::forward) gives `None` for the directions it does not see.
    #[inline]
    #[must_use]
    pub const fn covers_sphere(self) -> bool {
        match self {
            AnyMapping::Fisheye(f) => f.covers_sphere(),
            _ => true,
        }
    }

    /// Whether the charts are the cube's six faces, in the GL face order and
    /// orientation ([`Cube`] and [`Eac`]): every cube layout, face file and
    /// face convention applies.
    #[inline]
    #[must_use]
    pub const fn has_cube_faces(self) -> bool {
        matches!(self, AnyMapping::Cube | AnyMapping::Eac)
    }

    /// The solid angle of the directions that have a chart point, in steradians: 4π but for
    /// a fisheye that does not cover the sphere ([`Fisheye::seen_solid_angle`]).
    #[must_use]
    pub fn seen_solid_angle(self) -> f64 {
        match self {
            AnyMapping::Fisheye(f) => f.seen_solid_angle(),
            _ => 4.0 * core::f64::consts::PI,
        }
    }

    /// Forward mapping of the chosen variant; `None` also for a direction a fisheye does not
    /// see ([`AnyMapping::covers_sphere`]).
    #[inline]
    #[must_use]
    pub fn forward(self, d: Vec3) -> Option<ChartUv> {
        match self {
            AnyMapping::LatLong => LatLong::forward(d),
            AnyMapping::Cube => Cube::forward(d),
            AnyMapping::SphereMap => SphereMap::CLASS.forward(d),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.forward(d),
            AnyMapping::DualParaboloid => DualParaboloid::forward(d),
            AnyMapping::Tennisball => Tennisball::forward(d),
            AnyMapping::Octahedral => Octahedral::forward(d),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral::forward(d),
            AnyMapping::Angular => Angular::forward(d),
            AnyMapping::Eac => Eac::forward(d),
            AnyMapping::Fisheye(f) => f.forward(d),
        }
    }

    /// Inverse mapping of the chosen variant.
    #[inline]
    #[must_use]
    pub fn inverse(self, c: ChartUv) -> Option<Vec3> {
        match self {
            AnyMapping::LatLong => LatLong::inverse(c),
            AnyMapping::Cube => Cube::inverse(c),
            AnyMapping::SphereMap => SphereMap::CLASS.inverse(c),
            AnyMapping::SphereMapGl => SphereMap::OPENGL.inverse(c),
            AnyMapping::DualParaboloid => DualParaboloid::inverse(c),
            AnyMapping::Tennisball => Tennisball::inverse(c),
            AnyMapping::Octahedral => Octahedral::inverse(c),
            AnyMapping::EqualAreaOctahedral => EqualAreaOctahedral::inverse(c),
            AnyMapping::Angular => Angular::inverse(c),
            AnyMapping::Eac => Eac::inverse(c),
            AnyMapping::Fisheye(f) => f.inverse(c),
        }
    }

    fn as_dyn(&self) -> &dyn Mapping {
        match self {
            AnyMapping::LatLong => &LatLong,
            AnyMapping::Cube => &Cube,
            AnyMapping::SphereMap => &SphereMap::CLASS,
            AnyMapping::SphereMapGl => &SphereMap::OPENGL,
            AnyMapping::DualParaboloid => &DualParaboloid,
            AnyMapping::Tennisball => &Tennisball,
            AnyMapping::Octahedral => &Octahedral,
            AnyMapping::EqualAreaOctahedral => &EqualAreaOctahedral,
            AnyMapping::Angular => &Angular,
            AnyMapping::Eac => &Eac,
            AnyMapping::Fisheye(f) => f,
        }
    }
}

impl Mapping for AnyMapping {
    fn name(&self) -> &'static str {
        self.as_dyn().name()
    }
    fn chart_count(&self) -> u32 {
        self.as_dyn().chart_count()
    }
    fn forward(&self, dir: Vec3) -> Option<ChartUv> {
        AnyMapping::forward(*self, dir)
    }
    fn inverse(&self, c: ChartUv) -> Option<Vec3> {
        AnyMapping::inverse(*self, c)
    }
    fn in_chart(&self, chart: u32, u: f32, v: f32) -> bool {
        self.as_dyn().in_chart(chart, u, v)
    }
    fn solid_angle(&self, chart: u32, u0: f64, u1: f64, v0: f64, v1: f64) -> f64 {
        self.as_dyn().solid_angle(chart, u0, u1, v0, v1)
    }
    fn atlas(&self) -> Atlas {
        self.as_dyn().atlas()
    }
}

impl fmt::Display for AnyMapping {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// The error of parsing an unknown mapping name.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct UnknownMapping;

impl fmt::Display for UnknownMapping {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str("unknown mapping; expected one of: ")?;
        for (i, n) in AnyMapping::NAMES.iter().enumerate() {
            if i > 0 {
                f.write_str(", ")?;
            }
            f.write_str(n)?;
        }
        Ok(())
    }
}

impl FromStr for AnyMapping {
    type Err = UnknownMapping;

    /// Parses the names in [`AnyMapping::NAMES`] (case-insensitive), plus the
    /// aliases `equirect`, `equirectangular`, `cubemap`, `dual-paraboloid`,
    /// `octahedral-ea`, `sphere-class`, `light-probe` and `lightprobe` (the
    /// angular map), `mirror-ball` and `mirrorball` (`sphere-gl`: a
    /// photograph of a chrome ball is a GL sphere map seen from the camera), and
    /// `dfisheye` and `dual_fisheye` (`dual-fisheye`, as ffmpeg's v360 spells it). A fisheye
    /// parses to its default lens and field of view ([`Fisheye::SINGLE`], [`Fisheye::DUAL`]).
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let eq = |a: &str| s.eq_ignore_ascii_case(a);
        for (m, n) in AnyMapping::ALL.iter().zip(AnyMapping::NAMES) {
            if eq(n) {
                return Ok(*m);
            }
        }
        Ok(match () {
            () if eq("equirect") || eq("equirectangular") => AnyMapping::LatLong,
            () if eq("cubemap") => AnyMapping::Cube,
            () if eq("dual-paraboloid") => AnyMapping::DualParaboloid,
            () if eq("octahedral-ea") => AnyMapping::EqualAreaOctahedral,
            () if eq("sphere-class") => AnyMapping::SphereMap,
            () if eq("light-probe") || eq("lightprobe") => AnyMapping::Angular,
            () if eq("mirror-ball") || eq("mirrorball") => AnyMapping::SphereMapGl,
            () if eq("dfisheye") || eq("dual_fisheye") => AnyMapping::Fisheye(Fisheye::DUAL),
            () => return Err(UnknownMapping),
        })
    }
}
