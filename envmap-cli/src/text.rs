//! The line formats of `envmap map` and `envmap unmap`: directions in,
//! chart points out as CSV, and back.
//!
//! A line holds numbers separated by commas and/or white space. Empty lines,
//! `#` comments and lines without any digit (CSV headers such as `x,y,z` or
//! `chart,u,v`) are skipped. Each data line gives one output row or an
//! [`Error::Input`] saying what is wrong with it (the caller adds the file
//! name and line number):
//!
//! | command | input line | output row |
//! | --- | --- | --- |
//! | `map` | `x y z` (any length, in the caller's frame) | `chart,u,v` (and `,x,y`, the texel, with an image size) |
//! | `unmap` | `chart,u,v` (more numbers are ignored) | `x,y,z`, a unit direction |
//!
//! `map` refuses zero, NaN and infinite directions; `unmap` refuses a chart
//! that is not a whole number below the chart count and points outside the
//! chart (u, v outside `[0, 1]`, NaN, a disk chart's corners).
//!
//! A direction a fisheye does not see (beyond its field of view) has no chart point: `map`
//! writes an empty row for it (`,,`, or `,,,,` with an image size), and `unmap` answers an
//! empty row with an empty row (`,,`), so that rows stay aligned through both.

use envmap_core::glam::Vec3;
use envmap_core::texel::texel_index;
use envmap_core::{AnyMapping, Atlas, ChartUv, Frame, Framed, Mapping};

use envmap_render::{Error, Result};

/// Whether a line is skipped: empty, a `#` comment, or a line without any
/// digit (a CSV header such as `chart,u,v`; a line like `nan 0 1` is data,
/// and is reported as a direction that has no mapping).
#[must_use]
pub fn is_skipped(line: &str) -> bool {
    let t = line.trim();
    t.is_empty() || t.starts_with('#') || !t.contains(|c: char| c.is_ascii_digit())
}

/// The numbers of a line, separated by commas and/or white space (Rust's
/// `f32` syntax: `1`, `-2.5e3`, `inf`, `NaN`).
///
/// # Errors
///
/// [`Error::Input`] naming the first token that is not a number.
pub fn numbers(line: &str) -> Result<Vec<f32>> {
    line.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|t| !t.is_empty())
        .map(|t| {
            t.parse::<f32>()
                .map_err(|_| Error::Input(format!("'{t}' is not a number")))
        })
        .collect()
}

fn plural(n: usize) -> &'static str {
    if n == 1 {
        ""
    } else {
        "s"
    }
}

/// `envmap map`: directions to chart points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MapLines {
    mapping: Framed<AnyMapping>,
    atlas: Atlas,
    size: Option<(u32, u32)>,
}

impl MapLines {
    /// Maps directions given in `frame` with `mapping`; with `size`, also
    /// prints the texel of each point in a `width × height` image laid out
    /// as `atlas`.
    #[must_use]
    pub fn new(mapping: AnyMapping, frame: Frame, atlas: Atlas, size: Option<(u32, u32)>) -> Self {
        Self {
            mapping: Framed::new(mapping, frame),
            atlas,
            size,
        }
    }

    /// The CSV header row.
    #[must_use]
    pub fn header(&self) -> &'static str {
        if self.size.is_some() {
            "chart,u,v,x,y"
        } else {
            "chart,u,v"
        }
    }

    /// The output row of one input line; `None` for a skipped line.
    ///
    /// # Errors
    ///
    /// [`Error::Input`]: not a number, not three numbers, or a direction
    /// that has no mapping (zero, NaN or infinite). A direction a fisheye does not see gives
    /// an empty row (see the [module docs](self)).
    pub fn line(&self, line: &str) -> Result<Option<String>> {
        if is_skipped(line) {
            return Ok(None);
        }
        let v = numbers(line)?;
        let [x, y, z] = v[..] else {
            return Err(Error::Input(format!(
                "expected a direction 'x y z' or 'x,y,z', got {} number{}",
                v.len(),
                plural(v.len())
            )));
        };
        let d = Vec3::new(x, y, z);
        let Some(c) = self.mapping.forward(d) else {
            if envmap_core::normalize_direction(d).is_some() {
                // A valid direction the mapping does not see.
                return Ok(Some(
                    if self.size.is_some() { ",,,," } else { ",," }.to_owned(),
                ));
            }
            return Err(Error::Input(format!(
                "({x}, {y}, {z}) has no direction (zero, NaN or infinite)"
            )));
        };
        let mut row = format!("{},{},{}", c.chart, c.u, c.v);
        if let Some((w, h)) = self.size {
            let (cw, ch) = self.atlas.cell_size(w, h).unwrap_or((w, h));
            let (i, j) = (texel_index(c.u, cw), texel_index(c.v, ch));
            if let Some((tx, ty)) = self.atlas.chart_to_texel(c.chart, i, j, w, h) {
                row.push_str(&format!(",{tx},{ty}"));
            }
        }
        Ok(Some(row))
    }
}

/// `envmap unmap`: chart points to unit directions.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct UnmapLines {
    mapping: Framed<AnyMapping>,
}

impl UnmapLines {
    /// Inverts chart points of `mapping`, giving directions in `frame`.
    #[must_use]
    pub fn new(mapping: AnyMapping, frame: Frame) -> Self {
        Self {
            mapping: Framed::new(mapping, frame),
        }
    }

    /// The CSV header row.
    #[must_use]
    pub fn header(&self) -> &'static str {
        "x,y,z"
    }

    /// The output row of one input line; `None` for a skipped line.
    ///
    /// # Errors
    ///
    /// [`Error::Input`]: not a number, fewer than three numbers, a chart
    /// that does not exist, or a point outside its chart. An empty row (commas only: `map`'s
    /// row for a direction a fisheye does not see) gives an empty row.
    pub fn line(&self, line: &str) -> Result<Option<String>> {
        let t = line.trim();
        if t.contains(',') && t.chars().all(|c| c == ',' || c.is_whitespace()) {
            return Ok(Some(",,".to_owned()));
        }
        if is_skipped(line) {
            return Ok(None);
        }
        let v = numbers(line)?;
        let [chart, u, w, ..] = v[..] else {
            return Err(Error::Input(format!(
                "expected 'chart,u,v', got {} number{}",
                v.len(),
                plural(v.len())
            )));
        };
        let m = self.mapping.mapping;
        let count = m.chart_count();
        if !(chart >= 0.0 && chart.fract() == 0.0 && chart < count as f32) {
            return Err(Error::Input(format!(
                "chart {chart} does not exist; {m} has charts 0 to {}",
                count - 1
            )));
        }
        let c = ChartUv::new(chart as u32, u, w);
        let Some(d) = self.mapping.inverse(c) else {
            return Err(Error::Input(format!(
                "({u}, {w}) lies outside chart {} of {m} (u and v must be in [0, 1]{})",
                c.chart,
                if m.has_disk_charts() {
                    ", inside the disk"
                } else {
                    ""
                }
            )));
        };
        Ok(Some(format!("{},{},{}", d.x, d.y, d.z)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn msg(r: Result<Option<String>>) -> String {
        r.unwrap_err().to_string()
    }

    #[test]
    fn map_and_unmap_lines() {
        let m = MapLines::new(
            AnyMapping::Cube,
            Frame::IDENTITY,
            Atlas::CUBE_HORIZONTAL_CROSS,
            None,
        );
        assert_eq!(m.line("# comment").unwrap(), None);
        assert_eq!(m.line("x,y,z").unwrap(), None);
        assert_eq!(m.line(" 0, 0 ,1").unwrap().unwrap(), "4,0.5,0.5");
        assert!(msg(m.line("1 2")).contains("got 2 numbers"));
        assert!(msg(m.line("1 2 z3")).contains("'z3' is not a number"));
        assert!(msg(m.line("0 0 0")).contains("has no direction"));
        // A fisheye's unseen direction: an empty row, and back.
        let f = MapLines::new(
            AnyMapping::Fisheye(envmap_core::Fisheye::SINGLE),
            Frame::IDENTITY,
            Atlas::SINGLE_SQUARE,
            None,
        );
        assert_eq!(f.line("0 0 -1").unwrap().as_deref(), Some(",,"));
        assert_eq!(f.line("0 0 1").unwrap().as_deref(), Some("0,0.5,0.5"));
        let back = UnmapLines::new(
            AnyMapping::Fisheye(envmap_core::Fisheye::SINGLE),
            Frame::IDENTITY,
        );
        assert_eq!(back.line(",,").unwrap().as_deref(), Some(",,"));
        assert!(msg(m.line("nan 0 1")).contains("has no direction"));

        let u = UnmapLines::new(AnyMapping::Cube, Frame::IDENTITY);
        assert_eq!(u.line("4,0.5,0.5").unwrap().unwrap(), "0,0,1");
        assert!(msg(u.line("6,0.5,0.5")).contains("chart 6 does not exist"));
        assert!(msg(u.line("0.5,0.5,0.5")).contains("chart 0.5 does not exist"));
        assert!(msg(u.line("-0,0.5,nan")).contains("lies outside chart 0"));
        assert!(msg(u.line("1e30,0.5,0.5")).contains("does not exist"));
        assert!(msg(u.line("1,0.5")).contains("got 2 numbers"));
    }
}
