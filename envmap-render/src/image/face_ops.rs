// Cube faces stored turned or mirrored: the per-face transforms some tools
// and engines need (cmft's `--posXrotate90` and kin).

use std::fmt;
use std::str::FromStr;

use envmap_core::CubeFace;

use crate::error::{Error, Result};
use crate::image::envimage::{EnvImage, RgbImage};

/// One of the eight ways to turn and mirror a square image: a 2 × 2 matrix
/// of 0 and ±1 acting on texel coordinates about the centre, x right and y
/// down.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct FaceTurn {
    m: [[i8; 2]; 2],
}

impl Default for FaceTurn {
    fn default() -> Self {
        FaceTurn::IDENTITY
    }
}

impl FaceTurn {
    /// Leaves the face as it is.
    pub const IDENTITY: FaceTurn = FaceTurn {
        m: [[1, 0], [0, 1]],
    };
    /// A quarter turn clockwise: (x, y) → (−y, x).
    pub const ROT90: FaceTurn = FaceTurn {
        m: [[0, -1], [1, 0]],
    };
    /// A half turn.
    pub const ROT180: FaceTurn = FaceTurn {
        m: [[-1, 0], [0, -1]],
    };
    /// A quarter turn counter-clockwise.
    pub const ROT270: FaceTurn = FaceTurn {
        m: [[0, 1], [-1, 0]],
    };
    /// Left and right mirrored.
    pub const FLIP_X: FaceTurn = FaceTurn {
        m: [[-1, 0], [0, 1]],
    };
    /// Top and bottom mirrored.
    pub const FLIP_Y: FaceTurn = FaceTurn {
        m: [[1, 0], [0, -1]],
    };
    /// Mirrored about the main diagonal.
    pub const TRANSPOSE: FaceTurn = FaceTurn {
        m: [[0, 1], [1, 0]],
    };
    /// Mirrored about the other diagonal (the transpose turned half a turn).
    pub const ANTI_TRANSPOSE: FaceTurn = FaceTurn {
        m: [[0, -1], [-1, 0]],
    };
    /// All eight: the four turns, then the four mirrors.
    pub const ALL: [FaceTurn; 8] = [
        FaceTurn::IDENTITY,
        FaceTurn::ROT90,
        FaceTurn::ROT180,
        FaceTurn::ROT270,
        FaceTurn::FLIP_X,
        FaceTurn::FLIP_Y,
        FaceTurn::TRANSPOSE,
        FaceTurn::ANTI_TRANSPOSE,
    ];

    /// `self` followed by `next`.
    #[must_use]
    pub const fn then(self, next: FaceTurn) -> FaceTurn {
        let (a, b) = (next.m, self.m);
        FaceTurn {
            m: [
                [
                    a[0][0] * b[0][0] + a[0][1] * b[1][0],
                    a[0][0] * b[0][1] + a[0][1] * b[1][1],
                ],
                [
                    a[1][0] * b[0][0] + a[1][1] * b[1][0],
                    a[1][0] * b[0][1] + a[1][1] * b[1][1],
                ],
            ],
        }
    }

    /// The turn that undoes this one (the matrix is orthogonal: its transpose).
    #[must_use]
    pub const fn inverse(self) -> FaceTurn {
        FaceTurn {
            m: [[self.m[0][0], self.m[1][0]], [self.m[0][1], self.m[1][1]]],
        }
    }

    /// Where texel `(i, j)` of an `n × n` image goes.
    #[must_use]
    pub(crate) fn apply_texel(self, i: u32, j: u32, n: u32) -> (u32, u32) {
        // Twice the coordinates about the centre, so that they are whole.
        let c = i64::from(n) - 1;
        let (x, y) = (2 * i64::from(i) - c, 2 * i64::from(j) - c);
        let m = self.m.map(|r| r.map(i64::from));
        let (x2, y2) = (m[0][0] * x + m[0][1] * y, m[1][0] * x + m[1][1] * y);
        (((x2 + c) / 2) as u32, ((y2 + c) / 2) as u32)
    }

    /// `img` (square) turned: texel `(i, j)` moves to `apply_texel(i, j)`.
    #[must_use]
    pub fn apply(self, img: &RgbImage) -> RgbImage {
        if self == FaceTurn::IDENTITY || img.width != img.height {
            return img.clone();
        }
        let n = img.width;
        let mut pixels = vec![[0.0f32; 3]; img.pixels.len()];
        for j in 0..n {
            for i in 0..n {
                let (x, y) = self.apply_texel(i, j, n);
                pixels[(y * n + x) as usize] = img.pixels[(j * n + i) as usize];
            }
        }
        RgbImage {
            width: n,
            height: n,
            pixels,
        }
    }

    /// The name [`FromStr`] reads (every one of the eight has one).
    fn name(self) -> &'static str {
        [
            (FaceTurn::ROT90, "rot90"),
            (FaceTurn::ROT180, "rot180"),
            (FaceTurn::ROT270, "rot270"),
            (FaceTurn::FLIP_X, "flipx"),
            (FaceTurn::FLIP_Y, "flipy"),
            (FaceTurn::TRANSPOSE, "transpose"),
            (FaceTurn::ANTI_TRANSPOSE, "antitranspose"),
            (FaceTurn::IDENTITY, "none"),
        ]
        .into_iter()
        .find(|(t, _)| *t == self)
        .map_or("none", |(_, n)| n)
    }
}

impl FromStr for FaceTurn {
    type Err = Error;

    /// `rot90`, `rot180`, `rot270`, `flipx`, `flipy`, `transpose`,
    /// `antitranspose` (and
    /// `rotate90` ..., `fliph`/`flipv` as cmft spells them, `none`).
    fn from_str(s: &str) -> Result<Self> {
        Ok(match s.to_ascii_lowercase().as_str() {
            "rot90" | "rotate90" | "cw" => FaceTurn::ROT90,
            "rot180" | "rotate180" => FaceTurn::ROT180,
            "rot270" | "rotate270" | "ccw" => FaceTurn::ROT270,
            "flipx" | "fliph" | "mirror" => FaceTurn::FLIP_X,
            "flipy" | "flipv" => FaceTurn::FLIP_Y,
            "transpose" => FaceTurn::TRANSPOSE,
            "antitranspose" | "anti-transpose" => FaceTurn::ANTI_TRANSPOSE,
            "none" | "identity" => FaceTurn::IDENTITY,
            _ => {
                return Err(Error::UnknownName {
                    what: "face transform",
                    name: s.to_owned(),
                    expected: "rot90, rot180, rot270, flipx, flipy, transpose, antitranspose"
                        .to_owned(),
                })
            }
        })
    }
}

/// How each of a cube file's six faces is stored against GL's orientation;
/// see the [module docs](super).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub struct FaceTransforms {
    /// Per face in GL order: the file's face is the GL face turned so.
    pub faces: [FaceTurn; 6],
}

impl FaceTransforms {
    /// Every face as GL has it.
    #[must_use]
    pub(crate) fn is_identity(&self) -> bool {
        self.faces.iter().all(|t| *t == FaceTurn::IDENTITY)
    }

    /// `face` additionally turned by `turn`.
    #[must_use]
    pub fn with(mut self, face: CubeFace, turn: FaceTurn) -> Self {
        let k = face as usize;
        self.faces[k] = self.faces[k].then(turn);
        self
    }

    /// A cube as the file stores it (`to_file`), or back in GL's
    /// orientation from how the file stored it (`!to_file`). Other mappings
    /// and the identity are returned as they are.
    pub fn apply(&self, mut img: EnvImage, to_file: bool) -> Result<EnvImage> {
        if self.is_identity() || !img.mapping().has_cube_faces() {
            return Ok(img);
        }
        for (chart, t) in (0u32..).zip(self.faces) {
            let t = if to_file { t } else { t.inverse() };
            if t == FaceTurn::IDENTITY {
                continue;
            }
            if let Some(face) = img.chart_image(chart) {
                img.set_chart_image(chart, &t.apply(&face))?;
            }
        }
        Ok(img)
    }
}

impl fmt::Display for FaceTransforms {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let mut first = true;
        for (face, t) in CubeFace::ALL.into_iter().zip(self.faces) {
            if t == FaceTurn::IDENTITY {
                continue;
            }
            if !first {
                f.write_str(",")?;
            }
            first = false;
            // Every composition is one of the eight, each named.
            write!(f, "{}:{}", face.name(), t.name())?;
        }
        if first {
            f.write_str("none")?;
        }
        Ok(())
    }
}

impl FromStr for FaceTransforms {
    type Err = Error;

    /// `face:op[,face:op...]`, faces by any scheme's names (`+x`, `px`,
    /// `posx`, `right`, `0`, `R`), ops as [`FaceTurn`] parses them; `none`
    /// for no transform.
    fn from_str(s: &str) -> Result<Self> {
        let mut t = FaceTransforms::default();
        if s.trim().eq_ignore_ascii_case("none") {
            return Ok(t);
        }
        for part in s.split(',').map(str::trim).filter(|p| !p.is_empty()) {
            let bad = |what: &str| {
                Error::options(format!(
                    "'{part}': {what}; expected face:op, e.g. +x:rot90 or -z:flipx"
                ))
            };
            let (face, op) = part.rsplit_once(':').ok_or_else(|| bad("no ':'"))?;
            let face = face_by_name(face).ok_or_else(|| bad("unknown face"))?;
            t = t.with(face, op.parse()?);
        }
        Ok(t)
    }
}

/// A face by a name of any scheme.
fn face_by_name(name: &str) -> Option<CubeFace> {
    use crate::image::faces::FaceNames;
    FaceNames::ALL.into_iter().find_map(|n| {
        n.names()
            .iter()
            .position(|f| f.eq_ignore_ascii_case(name.trim()))
            .and_then(|i| CubeFace::from_index(i as u32))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn numbered(n: u32) -> RgbImage {
        RgbImage {
            width: n,
            height: n,
            pixels: (0..n * n).map(|k| [k as f32, 0.0, 0.0]).collect(),
        }
    }

    #[test]
    fn turns_do_what_their_names_say() {
        let img = numbered(3);
        // 0 1 2 / 3 4 5 / 6 7 8 turned clockwise: 6 3 0 / 7 4 1 / 8 5 2.
        let r: Vec<f32> = FaceTurn::ROT90
            .apply(&img)
            .pixels
            .iter()
            .map(|p| p[0])
            .collect();
        assert_eq!(r, [6.0, 3.0, 0.0, 7.0, 4.0, 1.0, 8.0, 5.0, 2.0]);
        let f: Vec<f32> = FaceTurn::FLIP_X
            .apply(&img)
            .pixels
            .iter()
            .map(|p| p[0])
            .collect();
        assert_eq!(f, [2.0, 1.0, 0.0, 5.0, 4.0, 3.0, 8.0, 7.0, 6.0]);
        let t: Vec<f32> = FaceTurn::TRANSPOSE
            .apply(&img)
            .pixels
            .iter()
            .map(|p| p[0])
            .collect();
        assert_eq!(t, [0.0, 3.0, 6.0, 1.0, 4.0, 7.0, 2.0, 5.0, 8.0]);
        assert_eq!(FaceTurn::ROT90.then(FaceTurn::ROT90), FaceTurn::ROT180);
        assert_eq!(FaceTurn::ROT90.then(FaceTurn::ROT270), FaceTurn::IDENTITY);
        assert_eq!(FaceTurn::ROT90.inverse(), FaceTurn::ROT270);
        // Every one of the eight undoes, on even and odd sizes.
        assert_eq!(
            FaceTurn::TRANSPOSE.then(FaceTurn::ROT180),
            FaceTurn::ANTI_TRANSPOSE
        );
        let all = FaceTurn::ALL;
        for n in [1, 2, 4, 5] {
            let img = numbered(n);
            for t in all {
                assert_eq!(t.inverse().apply(&t.apply(&img)), img, "{t:?} at {n}");
            }
        }
    }

    #[test]
    fn transforms_parse_and_print() {
        let t: FaceTransforms = "+x:rot90, pz:flipx,+x:rot90".parse().unwrap();
        assert_eq!(t.faces[0], FaceTurn::ROT180);
        assert_eq!(t.faces[4], FaceTurn::FLIP_X);
        assert_eq!(t.to_string(), "+x:rot180,+z:flipx");
        assert_eq!(t.to_string().parse::<FaceTransforms>().unwrap(), t);
        assert!("none".parse::<FaceTransforms>().unwrap().is_identity());
        // Every one of the eight prints as a name that parses back to it.
        for turn in FaceTurn::ALL {
            assert_eq!(turn.name().parse::<FaceTurn>().unwrap(), turn);
            let t = FaceTransforms::default().with(CubeFace::NegZ, turn);
            assert_eq!(t.to_string().parse::<FaceTransforms>().unwrap(), t);
        }
        let e = "+w:rot90"
            .parse::<FaceTransforms>()
            .unwrap_err()
            .to_string();
        assert!(e.contains("unknown face"), "{e}");
        let e = "+x:spin".parse::<FaceTransforms>().unwrap_err().to_string();
        assert!(e.contains("rot90"), "{e}");
    }
}
