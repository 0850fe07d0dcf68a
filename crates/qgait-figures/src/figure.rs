//! Drawing one figure to both PNG and SVG, and the styles shared by all figures.

use std::collections::HashSet;
use std::ops::Range;
use std::path::{Path, PathBuf};

use plotters::chart::MeshStyle;
use plotters::coord::types::RangedCoordf64;
use plotters::coord::Shift;
use plotters::prelude::*;

use super::font::{self, FAMILY};

/// What plotters said when drawing failed (its error types are generic over the backend, so
/// their description is kept).
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("plotting failed: {0}")]
pub struct PlotError(pub String);

/// Why a figure could not be saved.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum FigureError {
    /// The font shipped inside the binary could not be registered with plotters.
    #[error("the embedded DejaVu Sans font could not be loaded")]
    Font,
    /// Drawing a figure, or writing its file, failed.
    #[error("{stage} {}", path.display())]
    File {
        /// `drawing` or `writing`.
        stage: &'static str,
        /// The file.
        path: PathBuf,
        /// What plotters said.
        #[source]
        error: PlotError,
    },
}

/// A figure that can be drawn on any plotters backend.
pub trait Figure {
    /// File name without extension.
    fn stem(&self) -> String;
    /// Size in pixels.
    fn size(&self) -> (u32, u32);
    /// Draws the whole figure.
    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError>;
}

/// Writes `<dir>/<stem>.png` and `<dir>/<stem>.svg`.
pub fn save<F: Figure>(figure: &F, dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    if !font::ensure_registered() {
        return Err(FigureError::Font);
    }
    let stem = figure.stem();
    let png = dir.join(format!("{stem}.png"));
    let svg = dir.join(format!("{stem}.svg"));
    let failed = |stage, path: &Path| {
        let path = path.to_path_buf();
        move |error| FigureError::File { stage, path, error }
    };
    {
        let root = BitMapBackend::new(&png, figure.size()).into_drawing_area();
        figure.draw(&root).map_err(failed("drawing", &png))?;
        root.present()
            .map_err(draw_err)
            .map_err(failed("writing", &png))?;
    }
    {
        let root = SVGBackend::new(&svg, figure.size()).into_drawing_area();
        figure.draw(&root).map_err(failed("drawing", &svg))?;
        root.present()
            .map_err(draw_err)
            .map_err(failed("writing", &svg))?;
    }
    Ok(vec![png, svg])
}

/// Keeps a plotters error's description.
pub fn draw_err<E: std::fmt::Debug>(e: E) -> PlotError {
    PlotError(format!("{e:?}"))
}

/// A drawing area, as figures split them.
pub type Area<DB> = DrawingArea<DB, Shift>;

/// Clears `root` to white and splits off a header `height` pixels high with the figure's
/// `title` in its top left corner (bold, 24 px): every figure starts so. Returns the header
/// (for the figure's subtitle and legend) and the area below it.
pub fn titled<DB: DrawingBackend>(
    root: &DrawingArea<DB, Shift>,
    height: u32,
    title: &str,
) -> Result<(Area<DB>, Area<DB>), PlotError> {
    root.fill(&WHITE).map_err(draw_err)?;
    let (header, rest) = root.split_vertically(height);
    header
        .draw_text(title, &bold(24), (16, 10))
        .map_err(draw_err)?;
    Ok((header, rest))
}

/// A line of plain `size`-pixel text in a header at `(16, y)`.
pub fn header_line<DB: DrawingBackend>(
    header: &DrawingArea<DB, Shift>,
    line: &str,
    size: u32,
    y: i32,
) -> Result<(), PlotError> {
    header
        .draw_text(line, &text(size), (16, y))
        .map_err(draw_err)
}

/// The room around a panel's plot, in pixels: `margin` on every side, then `x_labels` below
/// the plot (the x axis's labels and title) and `y_labels` to its left (the y axis's).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Frame {
    /// On every side.
    pub margin: u32,
    /// Below the plot.
    pub x_labels: u32,
    /// Left of the plot.
    pub y_labels: u32,
}

/// The frame of a panel whose y axis is in metres (tick labels to the centimetre, a title
/// beside them): the paper's joint paths and distances.
pub const METRE_PANEL: Frame = Frame::new(10, 44, 70);

/// A panel's chart: x and y in `f64`, as every figure has them.
pub type Chart<'a, DB> = ChartContext<'a, DB, Cartesian2d<RangedCoordf64, RangedCoordf64>>;

impl Frame {
    /// `margin` on every side, `x_labels` below the plot, `y_labels` left of it.
    pub const fn new(margin: u32, x_labels: u32, y_labels: u32) -> Frame {
        Frame {
            margin,
            x_labels,
            y_labels,
        }
    }

    /// A chart on `area` in this frame, `x` across and `y` up, under `caption` (its text and
    /// its bold size) if one is given.
    pub fn chart<'a, DB: DrawingBackend>(
        self,
        area: &'a Area<DB>,
        caption: Option<(&str, u32)>,
        x: Range<f64>,
        y: Range<f64>,
    ) -> Result<Chart<'a, DB>, PlotError> {
        let mut builder = ChartBuilder::on(area);
        if let Some((text, size)) = caption {
            builder.caption(text, bold(size));
        }
        builder
            .margin(self.margin)
            .x_label_area_size(self.x_labels)
            .y_label_area_size(self.y_labels)
            .build_cartesian_2d(x, y)
            .map_err(draw_err)
    }

    /// The plot's width and height inside an area of `width` × `height` pixels.
    pub fn plot_size(self, width: u32, height: u32) -> (f64, f64) {
        (
            f64::from(width - 2 * self.margin - self.y_labels),
            f64::from(height - 2 * self.margin - self.x_labels),
        )
    }
}

/// A panel's axes in the figures' one style: axis titles `x` and `y`, labels and titles in
/// `size`-pixel text, no light grid, a faint bold grid. The caller sets the label counts and
/// formatters, then draws.
pub fn axes<'a, 'b, DB: DrawingBackend>(
    chart: &'b mut Chart<'a, DB>,
    x: &str,
    y: &str,
    size: u32,
) -> MeshStyle<'a, 'b, RangedCoordf64, RangedCoordf64, DB> {
    let mut mesh = chart.configure_mesh();
    mesh.x_desc(x)
        .y_desc(y)
        .label_style(text(size))
        .axis_desc_style(text(size))
        .light_line_style(WHITE.mix(0.0))
        .bold_line_style(BLACK.mix(0.08));
    mesh
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
///
/// Drawn once per pixel: both backends draw at whole pixels, so a point on the same pixel as
/// the previous one, a segment between two pixels already joined, and a joint on a pixel that
/// already has one change nothing and are skipped. A long recording (a million rows, its cycles
/// retracing each other) then draws what a short one does: its SVG stays the size of the
/// picture, not of the data.
pub fn draw_polyline<DB: DrawingBackend, CT: plotters::coord::CoordTranslate<From = (f64, f64)>>(
    area: &DrawingArea<DB, CT>,
    points: &[(f64, f64)],
    style: ShapeStyle,
) -> Result<(), PlotError> {
    // Consecutive points on distinct pixels, each with the first point that landed there, and
    // the pixels of the inner points (where the round joins go).
    let mut path: Vec<((i32, i32), (f64, f64))> = Vec::new();
    let mut joints: Vec<((i32, i32), (f64, f64))> = Vec::new();
    let mut joint_pixels = HashSet::new();
    let thick = style.stroke_width >= 3;
    for (i, &p) in points.iter().enumerate() {
        let px = area.map_coordinate(&p);
        if path.last().is_none_or(|&(last, _)| last != px) {
            path.push((px, p));
        }
        if thick && i > 0 && i + 1 < points.len() && joint_pixels.insert(px) {
            joints.push((px, p));
        }
    }
    let mut segments = HashSet::new();
    for w in path.windows(2) {
        let ((a, pa), (b, pb)) = (w[0], w[1]);
        if segments.insert(if a <= b { (a, b) } else { (b, a) }) {
            area.draw(&PathElement::new(vec![pa, pb], style))
                .map_err(draw_err)?;
        }
    }
    let joint = ShapeStyle {
        color: style.color,
        filled: true,
        stroke_width: 0,
    };
    for (_, p) in joints {
        area.draw(&Circle::new(p, style.stroke_width as i32 / 2, joint))
            .map_err(draw_err)?;
    }
    Ok(())
}

/// The points of a curve over `x` that draw the same line at whole pixels: per pixel column, the
/// first, lowest, highest and last point in their order (a line through every point of a column
/// covers the pixels from its lowest to its highest one). A series of any length gives at most
/// four points per column.
pub fn decimate_series<
    DB: DrawingBackend,
    CT: plotters::coord::CoordTranslate<From = (f64, f64)>,
>(
    area: &DrawingArea<DB, CT>,
    points: impl IntoIterator<Item = (f64, f64)>,
) -> Vec<(f64, f64)> {
    let mut out = Vec::new();
    // The column being collected: each point with its pixel.
    type Column = Vec<((i32, i32), (f64, f64))>;
    let mut column: Column = Vec::new();
    let flush = |column: &mut Column, out: &mut Vec<(f64, f64)>| {
        if column.is_empty() {
            return;
        }
        let last = column.len() - 1;
        let lo = (0..=last).min_by_key(|&i| column[i].0 .1).unwrap_or(0);
        let hi = (0..=last).max_by_key(|&i| column[i].0 .1).unwrap_or(0);
        let mut keep = vec![0, lo, hi, last];
        keep.sort_unstable();
        keep.dedup();
        out.extend(keep.into_iter().map(|i| column[i].1));
        column.clear();
    };
    for p in points {
        let px = area.map_coordinate(&p);
        if column.last().is_some_and(|(c, _)| c.0 != px.0) {
            flush(&mut column, &mut out);
        }
        column.push((px, p));
    }
    flush(&mut column, &mut out);
    out
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
) -> Result<(), PlotError> {
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

#[cfg(test)]
mod tests {
    use super::*;

    const W: u32 = 400;
    const H: u32 = 300;

    /// A figure-eight traced `cycles` times with `per_cycle` points each, wobbling slightly
    /// from cycle to cycle like a real recording.
    fn recording(cycles: usize, per_cycle: usize) -> Vec<(f64, f64)> {
        (0..cycles * per_cycle)
            .map(|i| {
                let t = i as f64 / per_cycle as f64 * std::f64::consts::TAU;
                let wobble = 1.0 + 0.004 * ((i / per_cycle) % 3) as f64;
                (t.sin() * wobble, (2.0 * t).sin() * 0.5)
            })
            .collect()
    }

    /// Draws with `draw` on a fresh chart and returns the pixels.
    fn pixels(
        draw: impl FnOnce(
            &DrawingArea<
                BitMapBackend<'_>,
                plotters::coord::cartesian::Cartesian2d<
                    plotters::coord::types::RangedCoordf64,
                    plotters::coord::types::RangedCoordf64,
                >,
            >,
        ),
    ) -> Vec<u8> {
        let mut buf = vec![0u8; (W * H * 3) as usize];
        {
            let root = BitMapBackend::with_buffer(&mut buf, (W, H)).into_drawing_area();
            root.fill(&WHITE).unwrap();
            let chart = ChartBuilder::on(&root)
                .margin(10)
                .build_cartesian_2d(-1.2..1.2, -0.7..0.7)
                .unwrap();
            draw(chart.plotting_area());
            root.present().unwrap();
        }
        buf
    }

    /// Pixels inked in the first picture, pixels inked in one picture only, pixels that differ.
    fn compare(a: &[u8], b: &[u8]) -> (usize, usize, usize) {
        let white = |p: &[u8]| p == [255, 255, 255];
        let pairs = || a.chunks(3).zip(b.chunks(3));
        (
            a.chunks(3).filter(|p| !white(p)).count(),
            pairs().filter(|(p, q)| white(p) != white(q)).count(),
            pairs().filter(|(p, q)| p != q).count(),
        )
    }

    /// A figure whose drawing fails, or draws nothing.
    struct Blank(bool);

    impl Figure for Blank {
        fn stem(&self) -> String {
            "blank".into()
        }

        fn size(&self) -> (u32, u32) {
            (20, 10)
        }

        fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
            if self.0 {
                return Err(PlotError("no ink".into()));
            }
            root.fill(&WHITE).map_err(draw_err)
        }
    }

    #[test]
    fn a_figure_that_fails_names_its_file_and_the_stage() {
        let dir = tempfile::tempdir().unwrap();
        let e = save(&Blank(true), dir.path()).unwrap_err();
        assert!(
            matches!(&e, FigureError::File { stage: "drawing", path, error }
                if path.ends_with("blank.png") && error.0 == "no ink"),
            "{e:?}"
        );
        assert_eq!(
            format!("{:#}", anyhow::Error::from(e)),
            format!(
                "drawing {}: plotting failed: no ink",
                dir.path().join("blank.png").display()
            )
        );
        let missing = dir.path().join("missing");
        let e = save(&Blank(false), &missing).unwrap_err();
        assert!(
            matches!(&e, FigureError::File { stage: "writing", path, .. }
                if path.ends_with("blank.png")),
            "{e:?}"
        );
        assert_eq!(save(&Blank(false), dir.path()).unwrap().len(), 2);
    }

    #[test]
    fn a_path_drawn_once_per_pixel_looks_the_same_as_every_segment_drawn() {
        let pts = recording(20, 5000);
        for width in [2, 4] {
            let style = RED.stroke_width(width);
            let every = pixels(|area| {
                for w in pts.windows(2) {
                    area.draw(&PathElement::new(vec![w[0], w[1]], style))
                        .unwrap();
                }
                if width >= 3 {
                    let joint = ShapeStyle {
                        color: style.color,
                        filled: true,
                        stroke_width: 0,
                    };
                    for &p in &pts[1..pts.len() - 1] {
                        area.draw(&Circle::new(p, width as i32 / 2, joint)).unwrap();
                    }
                }
            });
            let once = pixels(|area| draw_polyline(area, &pts, style).unwrap());
            let (inked, coverage, value) = compare(&every, &once);
            // The same pixels inked; thick lines differ only in the shade of some edge pixels,
            // which anti-aliasing darkens each time a segment is drawn over them again.
            assert!(
                coverage == 0 && value * 20 < inked,
                "width {width}: {coverage} pixels inked in one only, {value} of {inked} differ"
            );
        }
    }

    #[test]
    fn a_series_decimated_per_pixel_column_looks_the_same_and_stays_small() {
        // 200,000 points over 100 % of a cycle, jagged like 2,000 cycles packed side by side.
        let pts: Vec<(f64, f64)> = (0..200_000)
            .map(|i| {
                let x = -1.0 + 2.0 * i as f64 / 200_000.0;
                (x, 0.5 * (i as f64 * 0.0628).sin() * (1.0 - x * x))
            })
            .collect();
        for width in [2, 4] {
            let style = BLUE.stroke_width(width);
            let every = pixels(|area| draw_polyline(area, &pts, style).unwrap());
            let mut kept = 0;
            let few = pixels(|area| {
                let d = decimate_series(area, pts.iter().copied());
                kept = d.len();
                draw_polyline(area, &d, style).unwrap();
            });
            assert!(kept <= 4 * W as usize, "{kept} points kept");
            let (inked, coverage, _) = compare(&every, &few);
            assert!(
                coverage * 100 < inked,
                "width {width}: {coverage} of {inked} pixels differ"
            );
        }
    }
}
