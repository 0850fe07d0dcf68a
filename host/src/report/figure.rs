//! Drawing one figure to both PNG and SVG, and the styles shared by all figures.

use std::path::{Path, PathBuf};

use anyhow::Context;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::{self, FAMILY};

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// File name without extension.
    fn stem(&self) -> String;
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> anyhow::Result<()>;
}

/// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`.
pub fn save<F: Figure>(figure: &F, dir: &Path) -> anyhow::Result<Vec<PathBuf>> {
    font::ensure_registered()?;
    let stem = figure.stem();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    {
        let root = BitMapBackend::new(&png, figure.size()).into_drawing_area();
        figure
            .draw(&root)
            .with_context(|| format!("drawing {}", png.display()))?;
        root.present()
            .map_err(draw_err)
            .with_context(|| format!("writing {}", png.display()))?;
    }
    {
        let root = SVGBackend::new(&svg, figure.size()).into_drawing_area();
        figure
            .draw(&root)
            .with_context(|| format!("drawing {}", svg.display()))?;
        root.present()
            .map_err(draw_err)
            .with_context(|| format!("writing {}", svg.display()))?;
    }
    Ok(vec![png, svg])
}

/// Converts a plotters error into an `anyhow` error.
pub fn draw_err<E: std::fmt::Debug>(e: E) -> anyhow::Error {
    anyhow::anyhow!("plotting failed: {e:?}")
}

/// Text style of a given size.
pub fn text(size: u32) -> TextStyle<'static> {
    (FAMILY, size).into_font().color(&BLACK)
}

/// Bold text style of a given size.
pub fn bold(size: u32) -> TextStyle<'static> {
    (FAMILY, size, FontStyle::Bold).into_font().color(&BLACK)
}

/// Colour of the n-th gait (colour-blind-friendly Okabe-Ito order).
pub fn gait_color(n: usize) -> RGBColor {
    const COLORS: [RGBColor; 7] = [
        RGBColor(0, 114, 178),   // blue
        RGBColor(213, 94, 0),    // vermillion
        RGBColor(0, 158, 115),   // bluish green
        RGBColor(204, 121, 167), // reddish purple
        RGBColor(230, 159, 0),   // orange
        RGBColor(86, 180, 233),  // sky blue
        RGBColor(0, 0, 0),       // black
    ];
    COLORS[n % COLORS.len()]
}

/// Colour of the right leg in stick figures.
pub const RIGHT_LEG: RGBColor = RGBColor(204, 37, 41);
/// Colour of the left leg in stick figures.
pub const LEFT_LEG: RGBColor = RGBColor(57, 106, 177);
/// Colour of the pelvis line in stick figures.
pub const PELVIS: RGBColor = RGBColor(110, 110, 110);

/// A range that contains `values` with a relative margin (and a minimum width, so a constant
/// curve still gets a readable axis).
pub fn padded_range(
    values: impl IntoIterator<Item = f64>,
    margin: f64,
    min_width: f64,
) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in values {
        lo = lo.min(v);
        hi = hi.max(v);
    }
    if !lo.is_finite() {
        return (-min_width / 2.0, min_width / 2.0);
    }
    let width = (hi - lo).max(min_width);
    let mid = (lo + hi) / 2.0;
    (mid - width * (0.5 + margin), mid + width * (0.5 + margin))
}

/// A tick label with `decimals` decimals and no "-0.0".
pub fn tick(v: f64, decimals: usize) -> String {
    let s = format!("{v:.decimals$}");
    match s.strip_prefix('-') {
        Some(rest) if rest.chars().all(|c| c == '0' || c == '.') => rest.to_string(),
        _ => s,
    }
}

/// Draws a polyline as separate segments with round joins (plotters' thick polylines draw
/// spikes where a path turns back on itself, and plain segments leave notches at the joints).
pub fn draw_polyline<DB: DrawingBackend, CT: plotters::coord::CoordTranslate<From = (f64, f64)>>(
    area: &DrawingArea<DB, CT>,
    points: &[(f64, f64)],
    style: ShapeStyle,
) -> anyhow::Result<()> {
    for w in points.windows(2) {
        area.draw(&PathElement::new(vec![w[0], w[1]], style))
            .map_err(draw_err)?;
    }
    if style.stroke_width >= 3 {
        let joint = ShapeStyle {
            color: style.color,
            filled: true,
            stroke_width: 0,
        };
        let radius = style.stroke_width as i32 / 2;
        for &p in points.iter().skip(1).take(points.len().saturating_sub(2)) {
            area.draw(&Circle::new(p, radius, joint))
                .map_err(draw_err)?;
        }
    }
    Ok(())
}

/// Line width of the n-th of `count` overlaid gaits: earlier gaits are drawn wider, so a curve
/// hidden under an identical later one still shows as a coloured rim.
pub fn gait_width(n: usize, count: usize) -> u32 {
    2 + (count.saturating_sub(n + 1)).min(3) as u32
}

/// One legend entry per gait (a line in its colour and its label), in a row from (x, y).
pub fn draw_gait_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    analysis: &super::Analysis,
    x: i32,
    y: i32,
) -> anyhow::Result<()> {
    let mut x = x;
    for (g, gait) in analysis.gaits.iter().enumerate() {
        let color = gait_color(g);
        area.draw(&PathElement::new(
            vec![(x, y + 9), (x + 36, y + 9)],
            color.stroke_width(4),
        ))
        .map_err(draw_err)?;
        area.draw(&Text::new(gait.label.clone(), (x + 44, y), text(16)))
            .map_err(draw_err)?;
        x += 70 + 10 * gait.label.chars().count() as i32;
    }
    Ok(())
}
