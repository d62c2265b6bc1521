//! The accuracy-versus-speed chart: worst error (log axis) against ns per
//! element, functions on the left and mappings on the right, one point per
//! function or mapping and tier, baselines as crosses, the memory floor (a
//! copy of the same bytes) as a dashed line and the Pareto front (no other
//! point both faster and more accurate) as a line.
//!
//! Text needs a TrueType font, read at run time (plotters' `ab_glyph`
//! backend; no system font library). Without one the chart is drawn without
//! text.

use plotters::prelude::*;
use plotters::style::FontStyle;

use crate::report::Row;

/// Font files tried when none is given.
pub const FONT_CANDIDATES: [&str; 4] = [
    "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
    "/usr/share/fonts/TTF/DejaVuSans.ttf",
    "/usr/share/fonts/dejavu/DejaVuSans.ttf",
    "/System/Library/Fonts/Supplemental/Arial.ttf",
];

/// Registers the first readable font of `path` or [`FONT_CANDIDATES`] as
/// `sans-serif`; returns whether one was found.
pub fn register_font(path: Option<&str>) -> bool {
    let candidates: Vec<&str> = path.map_or_else(|| FONT_CANDIDATES.to_vec(), |p| vec![p]);
    for c in candidates {
        if let Ok(bytes) = std::fs::read(c) {
            let bytes: &'static [u8] = Box::leak(bytes.into_boxed_slice());
            if plotters::style::register_font("sans-serif", FontStyle::Normal, bytes).is_ok() {
                return true;
            }
        }
    }
    false
}

fn tier_colour(tier: &str) -> RGBColor {
    match tier {
        "exact" => RGBColor(31, 119, 180),
        "fine" => RGBColor(44, 160, 44),
        "fast" => RGBColor(255, 127, 14),
        "wide" => RGBColor(148, 103, 189),
        "std" => RGBColor(0, 0, 0),
        _ => RGBColor(127, 127, 127),
    }
}

/// Indices of the points on the Pareto front (sorted by time): no other
/// point is both at most as slow and strictly more accurate.
#[must_use]
pub fn pareto(points: &[(f64, f64)]) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..points.len()).collect();
    idx.sort_by(|&a, &b| {
        points[a]
            .0
            .total_cmp(&points[b].0)
            .then(points[a].1.total_cmp(&points[b].1))
    });
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for i in idx {
        if points[i].1 < best {
            best = points[i].1;
            front.push(i);
        }
    }
    front
}

type Err = Box<dyn std::error::Error>;

fn panel(
    area: &DrawingArea<BitMapBackend<'_>, plotters::coord::Shift>,
    title: &str,
    rows: &[&Row],
    floor: Option<f64>,
    text: bool,
) -> Result<(), Err> {
    let pts: Vec<(f64, f64)> = rows
        .iter()
        .map(|r| (r.ns, r.max_abs_err.unwrap_or(f64::NAN).max(1e-9)))
        .collect();
    let xmax = pts.iter().map(|p| p.0).fold(floor.unwrap_or(0.0), f64::max) * 1.15;
    let xmin = pts
        .iter()
        .map(|p| p.0)
        .fold(floor.unwrap_or(f64::INFINITY), f64::min)
        / 1.15;
    let (ymin, ymax) = pts.iter().fold((f64::INFINITY, 0.0_f64), |(a, b), p| {
        (a.min(p.1), b.max(p.1))
    });
    let mut builder = ChartBuilder::on(area);
    builder.margin(12);
    if text {
        builder
            .caption(title, ("sans-serif", 20))
            .x_label_area_size(36)
            .y_label_area_size(64);
    }
    let mut chart = builder.build_cartesian_2d(
        (xmin.max(1e-3)..xmax.max(1e-2)).log_scale(),
        ((ymin / 2.0)..(ymax * 2.0)).log_scale(),
    )?;
    let mut mesh = chart.configure_mesh();
    if text {
        mesh.x_desc("ns per element (log)")
            .y_desc("worst error, rad (log)")
            .label_style(("sans-serif", 13))
            .x_label_formatter(&|x| format!("{x}"))
            .y_label_formatter(&|y| format!("{y:.0e}"));
    } else {
        mesh.x_labels(0).y_labels(0);
    }
    mesh.draw()?;
    if let Some(f) = floor {
        chart.draw_series(DashedLineSeries::new(
            [(f, ymin / 2.0), (f, ymax * 2.0)],
            6,
            4,
            ShapeStyle::from(&RGBColor(127, 127, 127)).stroke_width(1),
        ))?;
    }
    let front = pareto(&pts);
    chart.draw_series(LineSeries::new(
        front.iter().map(|&i| pts[i]),
        ShapeStyle::from(&RGBColor(214, 39, 40)).stroke_width(2),
    ))?;
    for (r, &p) in rows.iter().zip(&pts) {
        let c = tier_colour(r.tier);
        let baseline = matches!(r.tier, "wide" | "std" | "scalar");
        if baseline {
            chart.draw_series(std::iter::once(Cross::new(p, 5, c.stroke_width(2))))?;
        } else if r.direction == Some("inverse") {
            chart.draw_series(std::iter::once(TriangleMarker::new(p, 5, c.filled())))?;
        } else {
            chart.draw_series(std::iter::once(Circle::new(p, 4, c.filled())))?;
        }
        if text {
            let label = match r.direction {
                Some("inverse") => format!("{} inv {}", r.name, r.tier),
                Some(_) => format!("{} {}", r.name, r.tier),
                None => format!("{} {}", r.name, r.tier),
            };
            chart.draw_series(std::iter::once(Text::new(
                label,
                p,
                ("sans-serif", 10).into_font().color(&c),
            )))?;
        }
    }
    Ok(())
}

/// Draws the chart of `rows` (functions, and mappings at the smallest size
/// measured) into the PNG `path`, 1600 × 800.
///
/// # Errors
///
/// Drawing or writing the file failed.
pub fn draw(path: &str, rows: &[Row], text: bool) -> Result<(), Err> {
    let root = BitMapBackend::new(path, (1600, 800)).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(800);
    let fns: Vec<&Row> = rows
        .iter()
        .filter(|r| r.kind == "function" && r.max_abs_err.is_some())
        .collect();
    let fn_floor = fns.iter().filter_map(|r| r.copy_ns).reduce(f64::min);
    panel(
        &left,
        "functions: exact (blue), fine (green), fast (orange), wide (purple x), std (black x)",
        &fns,
        fn_floor,
        text,
    )?;
    let n = rows
        .iter()
        .filter(|r| r.kind == "mapping")
        .map(|r| r.n)
        .min()
        .unwrap_or(0);
    let maps: Vec<&Row> = rows
        .iter()
        .filter(|r| r.kind == "mapping" && r.n == n && r.max_abs_err.is_some())
        .collect();
    let map_floor = rows
        .iter()
        .filter(|r| r.kind == "mapping" && r.n == n && r.tier == "copy")
        .map(|r| r.ns)
        .reduce(f64::max);
    panel(
        &right,
        &format!(
            "mappings, {n} per pass: forward (dots), inverse (triangles), scalar core (grey x)"
        ),
        &maps,
        map_floor,
        text,
    )?;
    root.present()?;
    Ok(())
}
