//! Atlas layouts: where each chart of a mapping lies in one image.
//!
//! An image is divided into a grid of `cols × rows` equal cells; each chart
//! occupies one cell, possibly turned by half a turn (the −z face of a vertical
//! cross). Cells that hold no chart (the corners of a cube cross) and points
//! outside a chart's domain (a disk's corners) hold no direction.
//!
//! | atlas | grid | cell w:h | cells (chart at col,row) |
//! | --- | --- | --- | --- |
//! | [`Atlas::LATLONG`] | 1×1 | 2:1 | 0 at 0,0 |
//! | [`Atlas::SINGLE_SQUARE`] | 1×1 | 1:1 | 0 at 0,0 (sphere maps, octahedral) |
//! | [`Atlas::CUBE_HORIZONTAL_CROSS`] | 4×3 | 1:1 | +y 1,0; −x 0,1; +z 1,1; +x 2,1; −z 3,1; −y 1,2 |
//! | [`Atlas::CUBE_VERTICAL_CROSS`] | 3×4 | 1:1 | +y 1,0; −x 0,1; +z 1,1; +x 2,1; −y 1,2; −z 1,3 turned half a turn |
//! | [`Atlas::CUBE_HORIZONTAL_STRIP`] | 6×1 | 1:1 | faces 0..5 left to right |
//! | [`Atlas::CUBE_VERTICAL_STRIP`] | 1×6 | 1:1 | faces 0..5 top to bottom |
//! | [`Atlas::PARABOLOID_SIDE_BY_SIDE`] | 2×1 | 1:1 | front 0,0; back 1,0 |
//! | [`Atlas::TENNISBALL_STACKED`] | 1×2 | 3:1 | chart 0 at 0,0; chart 1 at 0,1 |
//! | [`Atlas::CUBE_3X2`] | 3×2 | 1:1 | +x 0,0; −x 1,0; +y 2,0; −y 0,1; +z 1,1; −z 2,1 (ffmpeg `v360`'s `c3x2`) |
//! | [`Atlas::EAC_V360`] | 3×2 | 1:1 | −x 0,0; +z 1,0; +x 2,0; −y 0,1; −z 1,1; +y 2,1 (ffmpeg `v360`'s `eac`, as held in memory) |
//! | [`Atlas::DUAL_FISHEYE_V360`] | 2×1 | 1:1 | back (chart 1) 0,0; front (chart 0) 1,0 (ffmpeg `v360`'s `dfisheye`) |
//!
//! Faces keep their GL orientation in every cube layout (each face image is
//! exactly what GL expects for that face), except the vertical cross's −z,
//! which the layout's convention stores turned by half a turn so that it joins
//! −y above it. ffmpeg's `v360` `eac` files turn the faces of their bottom row
//! and pad each row with 2 pixels; `envmap-render` applies both when it reads
//! and writes such a file, and holds the faces here unturned and unpadded.

use crate::mapping::ChartUv;

/// How a chart is turned within its cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Turn {
    /// Stored as is: chart (u, v) = cell (u, v).
    None,
    /// Turned half a turn: chart (u, v) = cell (1 − u, 1 − v).
    Half,
}

/// One chart's place in an atlas.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Cell {
    /// The chart stored in this cell.
    pub chart: u32,
    /// Grid column, from 0 at the left.
    pub col: u32,
    /// Grid row, from 0 at the top.
    pub row: u32,
    /// How the chart is turned within the cell.
    pub turn: Turn,
}

const fn cell(chart: u32, col: u32, row: u32) -> Cell {
    Cell {
        chart,
        col,
        row,
        turn: Turn::None,
    }
}

/// A layout of charts in one image; see the [module docs](self).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Atlas {
    /// Short name of the layout (`"cross"`, `"strip"`, ...).
    pub name: &'static str,
    /// Grid columns.
    pub cols: u32,
    /// Grid rows.
    pub rows: u32,
    /// Width of one cell in units of [`cell_aspect_h`](Atlas::cell_aspect_h).
    pub cell_aspect_w: u32,
    /// Height of one cell (the cell is `cell_aspect_w : cell_aspect_h`).
    pub cell_aspect_h: u32,
    /// The occupied cells, one per chart, in chart order.
    pub cells: &'static [Cell],
}

/// A texel of an atlas image resolved to its chart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct ChartTexel {
    /// The chart.
    pub chart: u32,
    /// Column within the chart (as the chart is oriented, not as stored).
    pub i: u32,
    /// Row within the chart.
    pub j: u32,
    /// Chart width in texels.
    pub w: u32,
    /// Chart height in texels.
    pub h: u32,
}

impl Atlas {
    /// Latitude-longitude: one 2:1 cell.
    pub const LATLONG: Atlas = Atlas {
        name: "latlong",
        cols: 1,
        rows: 1,
        cell_aspect_w: 2,
        cell_aspect_h: 1,
        cells: &[cell(0, 0, 0)],
    };
    /// One square chart (sphere maps, octahedral maps, one cube face).
    pub const SINGLE_SQUARE: Atlas = Atlas {
        name: "square",
        cols: 1,
        rows: 1,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[cell(0, 0, 0)],
    };
    /// Cube, horizontal cross (4×3).
    pub const CUBE_HORIZONTAL_CROSS: Atlas = Atlas {
        name: "cross",
        cols: 4,
        rows: 3,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 2, 1),
            cell(1, 0, 1),
            cell(2, 1, 0),
            cell(3, 1, 2),
            cell(4, 1, 1),
            cell(5, 3, 1),
        ],
    };
    /// Cube, vertical cross (3×4), −z turned half a turn.
    pub const CUBE_VERTICAL_CROSS: Atlas = Atlas {
        name: "vcross",
        cols: 3,
        rows: 4,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 2, 1),
            cell(1, 0, 1),
            cell(2, 1, 0),
            cell(3, 1, 2),
            cell(4, 1, 1),
            Cell {
                chart: 5,
                col: 1,
                row: 3,
                turn: Turn::Half,
            },
        ],
    };
    /// Cube, horizontal strip (6×1), faces in GL order.
    pub const CUBE_HORIZONTAL_STRIP: Atlas = Atlas {
        name: "strip",
        cols: 6,
        rows: 1,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 0, 0),
            cell(1, 1, 0),
            cell(2, 2, 0),
            cell(3, 3, 0),
            cell(4, 4, 0),
            cell(5, 5, 0),
        ],
    };
    /// Cube, vertical strip (1×6), faces in GL order.
    pub const CUBE_VERTICAL_STRIP: Atlas = Atlas {
        name: "vstrip",
        cols: 1,
        rows: 6,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 0, 0),
            cell(1, 0, 1),
            cell(2, 0, 2),
            cell(3, 0, 3),
            cell(4, 0, 4),
            cell(5, 0, 5),
        ],
    };
    /// Dual paraboloid: front disk left, back disk right.
    pub const PARABOLOID_SIDE_BY_SIDE: Atlas = Atlas {
        name: "side-by-side",
        cols: 2,
        rows: 1,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[cell(0, 0, 0), cell(1, 1, 0)],
    };
    /// Dual fisheye as ffmpeg's `v360` lays out its `dfisheye`: the back lens (chart 1,
    /// looking along −z) left, the front lens (chart 0, looking along +z) right.
    pub const DUAL_FISHEYE_V360: Atlas = Atlas {
        name: "dfisheye",
        cols: 2,
        rows: 1,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[cell(0, 1, 0), cell(1, 0, 0)],
    };
    /// Cube, three faces by two: +x, −x, +y on top, −y, +z, −z below (ffmpeg
    /// `v360`'s `c3x2` with its default face order `rludfb`).
    pub const CUBE_3X2: Atlas = Atlas {
        name: "3x2",
        cols: 3,
        rows: 2,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 0, 0),
            cell(1, 1, 0),
            cell(2, 2, 0),
            cell(3, 0, 1),
            cell(4, 1, 1),
            cell(5, 2, 1),
        ],
    };
    /// The faces of ffmpeg `v360`'s `eac` layout: −x, +z, +x on top, −y, −z,
    /// +y below, each in GL's orientation. The file turns the bottom row's
    /// faces and pads the rows (`envmap-render`'s `v360` layout).
    pub const EAC_V360: Atlas = Atlas {
        name: "v360",
        cols: 3,
        rows: 2,
        cell_aspect_w: 1,
        cell_aspect_h: 1,
        cells: &[
            cell(0, 2, 0),
            cell(1, 0, 0),
            cell(2, 2, 1),
            cell(3, 0, 1),
            cell(4, 1, 0),
            cell(5, 1, 1),
        ],
    };
    /// Tennisball: two 3:1 strips stacked, chart 0 on top (a 3:2 image).
    pub const TENNISBALL_STACKED: Atlas = Atlas {
        name: "stacked",
        cols: 1,
        rows: 2,
        cell_aspect_w: 3,
        cell_aspect_h: 1,
        cells: &[cell(0, 0, 0), cell(1, 0, 1)],
    };

    /// Aspect ratio (width : height) of the whole image, as a reduced fraction.
    #[must_use]
    pub const fn image_aspect(&self) -> (u32, u32) {
        let w = self.cols * self.cell_aspect_w;
        let h = self.rows * self.cell_aspect_h;
        let g = gcd(w, h);
        (w / g, h / g)
    }

    /// Image size for cells `cell_w` texels wide; `None` if the cell height
    /// would not be a whole number (e.g. a tennisball strip 100 wide) or the
    /// size overflows.
    #[must_use]
    pub fn image_size_for_cell_width(&self, cell_w: u32) -> Option<(u32, u32)> {
        let scaled = u64::from(cell_w) * u64::from(self.cell_aspect_h);
        if cell_w == 0 || scaled % u64::from(self.cell_aspect_w) != 0 {
            return None;
        }
        let cell_h = u32::try_from(scaled / u64::from(self.cell_aspect_w)).ok()?;
        Some((
            self.cols.checked_mul(cell_w)?,
            self.rows.checked_mul(cell_h)?,
        ))
    }

    /// Cell size of an image `w × h` in this layout; `None` if the image does
    /// not divide into the grid with the cells' aspect ratio.
    #[must_use]
    pub fn cell_size(&self, w: u32, h: u32) -> Option<(u32, u32)> {
        if w == 0 || h == 0 || !w.is_multiple_of(self.cols) || !h.is_multiple_of(self.rows) {
            return None;
        }
        let (cw, ch) = (w / self.cols, h / self.rows);
        if u64::from(cw) * u64::from(self.cell_aspect_h)
            != u64::from(ch) * u64::from(self.cell_aspect_w)
        {
            return None;
        }
        Some((cw, ch))
    }

    /// The cell that holds `chart`, if any.
    #[must_use]
    pub fn cell_of(&self, chart: u32) -> Option<Cell> {
        self.cells.iter().copied().find(|c| c.chart == chart)
    }

    /// The cell at grid position `(col, row)`, if a chart occupies it.
    #[must_use]
    pub fn cell_at(&self, col: u32, row: u32) -> Option<Cell> {
        self.cells
            .iter()
            .copied()
            .find(|c| c.col == col && c.row == row)
    }

    /// Resolves texel `(x, y)` of a `w × h` atlas image to its chart texel;
    /// `None` for texels in empty cells, outside the image, or when the image
    /// size does not fit the layout.
    #[must_use]
    pub fn texel_to_chart(&self, x: u32, y: u32, w: u32, h: u32) -> Option<ChartTexel> {
        let (cw, ch) = self.cell_size(w, h)?;
        if x >= w || y >= h {
            return None;
        }
        let c = self.cell_at(x / cw, y / ch)?;
        let (lx, ly) = (x % cw, y % ch);
        let (i, j) = match c.turn {
            Turn::None => (lx, ly),
            Turn::Half => (cw - 1 - lx, ch - 1 - ly),
        };
        Some(ChartTexel {
            chart: c.chart,
            i,
            j,
            w: cw,
            h: ch,
        })
    }

    /// Image texel of chart texel `(i, j)` of `chart` in a `w × h` atlas image.
    #[must_use]
    pub fn chart_to_texel(&self, chart: u32, i: u32, j: u32, w: u32, h: u32) -> Option<(u32, u32)> {
        let (cw, ch) = self.cell_size(w, h)?;
        if i >= cw || j >= ch {
            return None;
        }
        let c = self.cell_of(chart)?;
        let (lx, ly) = match c.turn {
            Turn::None => (i, j),
            Turn::Half => (cw - 1 - i, ch - 1 - j),
        };
        Some((c.col * cw + lx, c.row * ch + ly))
    }

    /// Chart point of image coordinates `(x, y)` ∈ [0, 1]² (x right, y down);
    /// `None` in empty cells, outside the image, or for NaN.
    #[must_use]
    pub fn image_to_chart(&self, x: f32, y: f32) -> Option<ChartUv> {
        if !(0.0..=1.0).contains(&x) || !(0.0..=1.0).contains(&y) {
            return None;
        }
        let gx = x * self.cols as f32;
        let gy = y * self.rows as f32;
        let col = (gx as u32).min(self.cols - 1);
        let row = (gy as u32).min(self.rows - 1);
        let c = self.cell_at(col, row)?;
        let (u, v) = (gx - col as f32, gy - row as f32);
        let (u, v) = match c.turn {
            Turn::None => (u, v),
            Turn::Half => (1.0 - u, 1.0 - v),
        };
        Some(ChartUv::new(c.chart, u.clamp(0.0, 1.0), v.clamp(0.0, 1.0)))
    }

    /// Image coordinates `(x, y)` ∈ [0, 1]² of a chart point; `None` if the
    /// chart has no cell here.
    #[must_use]
    pub fn chart_to_image(&self, p: ChartUv) -> Option<(f32, f32)> {
        let c = self.cell_of(p.chart)?;
        let (u, v) = match c.turn {
            Turn::None => (p.u, p.v),
            Turn::Half => (1.0 - p.u, 1.0 - p.v),
        };
        Some((
            (c.col as f32 + u) / self.cols as f32,
            (c.row as f32 + v) / self.rows as f32,
        ))
    }
}

const fn gcd(mut a: u32, mut b: u32) -> u32 {
    while b != 0 {
        let t = a % b;
        a = b;
        b = t;
    }
    a
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn aspects() {
        assert_eq!(Atlas::LATLONG.image_aspect(), (2, 1));
        assert_eq!(Atlas::CUBE_HORIZONTAL_CROSS.image_aspect(), (4, 3));
        assert_eq!(Atlas::CUBE_VERTICAL_CROSS.image_aspect(), (3, 4));
        assert_eq!(Atlas::CUBE_HORIZONTAL_STRIP.image_aspect(), (6, 1));
        assert_eq!(Atlas::PARABOLOID_SIDE_BY_SIDE.image_aspect(), (2, 1));
        assert_eq!(Atlas::TENNISBALL_STACKED.image_aspect(), (3, 2));
    }

    #[test]
    fn sizes() {
        assert_eq!(
            Atlas::TENNISBALL_STACKED.image_size_for_cell_width(300),
            Some((300, 200))
        );
        assert_eq!(
            Atlas::TENNISBALL_STACKED.image_size_for_cell_width(100),
            None
        );
        assert_eq!(
            Atlas::CUBE_HORIZONTAL_CROSS.cell_size(4096, 3072),
            Some((1024, 1024))
        );
        assert_eq!(Atlas::CUBE_HORIZONTAL_CROSS.cell_size(4096, 3000), None);
        assert_eq!(Atlas::LATLONG.cell_size(4096, 2048), Some((4096, 2048)));
        assert_eq!(Atlas::LATLONG.cell_size(4096, 2047), None);
    }

    #[test]
    fn texels_round_trip_every_layout() {
        for a in [
            Atlas::CUBE_HORIZONTAL_CROSS,
            Atlas::CUBE_VERTICAL_CROSS,
            Atlas::CUBE_HORIZONTAL_STRIP,
            Atlas::CUBE_VERTICAL_STRIP,
            Atlas::PARABOLOID_SIDE_BY_SIDE,
            Atlas::TENNISBALL_STACKED,
            Atlas::CUBE_3X2,
            Atlas::EAC_V360,
        ] {
            let (w, h) = a.image_size_for_cell_width(6).unwrap();
            let mut seen = 0;
            for y in 0..h {
                for x in 0..w {
                    if let Some(t) = a.texel_to_chart(x, y, w, h) {
                        seen += 1;
                        assert_eq!(a.chart_to_texel(t.chart, t.i, t.j, w, h), Some((x, y)));
                    }
                }
            }
            let (cw, ch) = a.cell_size(w, h).unwrap();
            assert_eq!(seen, a.cells.len() as u32 * cw * ch, "{}", a.name);
        }
    }

    #[test]
    fn vertical_cross_turns_neg_z() {
        let a = Atlas::CUBE_VERTICAL_CROSS;
        let t = a.texel_to_chart(3, 9, 9, 12).unwrap();
        assert_eq!((t.chart, t.i, t.j), (5, 2, 2));
        let p = a.image_to_chart(0.5, 0.99).unwrap();
        assert_eq!(p.chart, 5);
        assert!(p.v < 0.1);
        assert_eq!(a.texel_to_chart(0, 0, 9, 12), None);
    }
}
