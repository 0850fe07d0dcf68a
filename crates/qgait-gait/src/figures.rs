//! The report's figures, drawn with the report room's helpers (PNG and SVG each):
//! - `kinematics`: every joint angle over the cycle, rows proximal to distal (pelvis, hip,
//!   knee, ankle and foot), columns sagittal, frontal, transverse, each panel with its axis
//!   titles (`% gait cycle`, `deg`); the reference's mean ± 1 SD as a grey band, each side's
//!   mean ± SD in its colour over its strides drawn thin, each side's measured toe off as a
//!   solid vertical line and the reference's (the normal range of the stance phase, or the
//!   reference recording's) dashed; a panel with neither a curve nor a band is left out;
//! - `map`: the Movement Analysis Profile, the nine GVS per side (those the model can
//!   move: a planar model's four sagittal ones) and the GPS as bars, with the scores of a typical member of the reference as
//!   ticks;
//! - `events`: the heel's and toe's forward position relative to the pelvis over time with the
//!   detected events, to check them.

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::angles::{Seen, Variable};
use crate::error::FigureError;
use crate::output::Report;
use qgait_figures::figure::{self, draw_err, Figure, Frame, LEFT_LEG, RIGHT_LEG};

/// Side colours, right first.
pub const SIDE_COLORS: [RGBColor; 2] = [RIGHT_LEG, LEFT_LEG];

/// The MAP's ticks at the scores of a typical member of the reference.
const NORMAL_TICK: RGBColor = RGBColor(0, 140, 70);

/// What a panel of the kinematics figure shows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Panel {
    /// A GPS variable.
    Variable(Variable),
    /// An angle the models do not give (its normative band only, if any), with its title.
    Absent(&'static str),
}

/// The 4 x 3 panels: rows pelvis, hip, knee, ankle and foot; columns sagittal, frontal,
/// transverse (the foot progression in the ankle's row, as the Plug-in Gait report has it).
/// Only the panels with something to draw are drawn ([`Kinematics::shown`]).
pub const PANELS: [[Panel; 3]; 4] = {
    use Panel::{Absent, Variable as V};
    use Variable::*;
    [
        [V(PelvicTilt), V(PelvicObliquity), V(PelvicRotation)],
        [V(HipFlexion), V(HipAbduction), V(HipRotation)],
        [
            V(KneeFlexion),
            Absent("Knee varus (var +)"),
            Absent("Knee rotation (int +)"),
        ],
        [
            V(AnkleDorsiflexion),
            Absent("Ankle inversion (inv +)"),
            V(FootProgression),
        ],
    ]
};

/// At most this many strides of a side are drawn one by one in a panel (evenly spread over
/// them): past that the lines are a blur, and the SVG grows with each.
pub const MAX_STRIDE_LINES: usize = 60;

/// The x axis title of every kinematics panel.
pub const X_TITLE: &str = "% gait cycle";
/// The y axis title of every kinematics panel.
pub const Y_TITLE: &str = "deg";

/// `n` indices spread evenly over `0..total` (all of them when `total <= n`), first and last
/// included.
pub fn spread(total: usize, n: usize) -> Vec<usize> {
    if total <= n {
        return (0..total).collect();
    }
    if n < 2 {
        return (0..n).collect();
    }
    (0..n).map(|k| k * (total - 1) / (n - 1)).collect()
}

/// Draws one figure to PNG and SVG in `dir`.
fn save<F: Figure>(f: &F, dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    figure::save(f, dir).map_err(|error| FigureError::Save {
        stem: f.stem(),
        error: error.into(),
    })
}

/// Writes every figure; returns the files.
pub fn save_all(report: &Report, dir: &Path) -> Result<Vec<PathBuf>, FigureError> {
    let mut files = Vec::new();
    if report.curves.iter().flatten().any(Option::is_some) {
        files.extend(save(&Kinematics { report }, dir)?);
    }
    if report.scores.is_some() {
        files.extend(save(&Map { report }, dir)?);
    }
    files.extend(save(&EventsFigure { report }, dir)?);
    Ok(files)
}

const PANEL_W: u32 = 420;
const PANEL_H: u32 = 280;
const HEADER: u32 = 130;

/// The normative-band figure.
pub struct Kinematics<'a> {
    /// The report.
    pub report: &'a Report,
}

impl Figure for Kinematics<'_> {
    fn stem(&self) -> String {
        "kinematics".into()
    }

    fn size(&self) -> (u32, u32) {
        (
            3 * PANEL_W,
            HEADER + self.rows().len().max(1) as u32 * PANEL_H,
        )
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), figure::PlotError> {
        let r = self.report;
        let (header, grid) = figure::titled(root, HEADER, "Joint angles over the gait cycle")?;
        // The legend: what the grey is, the sides, the thin lines, the toe-off lines.
        header
            .draw(&Rectangle::new(
                [(16, 46), (52, 60)],
                BLACK.mix(0.12).filled(),
            ))
            .map_err(draw_err)?;
        header
            .draw(&PathElement::new(
                vec![(16, 53), (52, 53)],
                BLACK.mix(0.45).stroke_width(1),
            ))
            .map_err(draw_err)?;
        header
            .draw_text(
                &format!("{}: mean ± 1 SD", r.reference.legend()),
                &figure::text(18),
                (60, 44),
            )
            .map_err(draw_err)?;
        side_legend(&header, 16, 72)?;
        header
            .draw_text(
                "mean ± 1 SD of each side; thin lines: single strides",
                &figure::text(18),
                (300, 70),
            )
            .map_err(draw_err)?;
        figure::header_line(
            &header,
            &if r.reference.toe_off_from.is_empty() {
                "vertical lines: measured toe off (solid)".to_string()
            } else {
                format!(
                    "vertical lines: measured toe off (solid); reference toe off (dashed): {}",
                    r.reference.toe_off_from
                )
            },
            18,
            100,
        )?;
        let rows = self.rows();
        let cells = grid.split_evenly((rows.len().max(1), 3));
        for (i, cell) in cells.iter().enumerate() {
            let (k, col) = (i / 3, i % 3);
            if let Some(&row) = rows.get(k) {
                if self.shown(row, col) {
                    self.panel(cell, row, col)?;
                }
            }
        }
        Ok(())
    }
}

impl Kinematics<'_> {
    /// The [`Variable::ALL`] index of a panel's variable, if it is one.
    fn variable(row: usize, col: usize) -> Option<usize> {
        match PANELS[row][col] {
            Panel::Variable(v) => Variable::ALL.iter().position(|x| *x == v),
            Panel::Absent(_) => None,
        }
    }

    /// Whether panel (row, col) has something to draw: a curve of the subject or a band of the
    /// reference.
    pub fn shown(&self, row: usize, col: usize) -> bool {
        let r = self.report;
        match Self::variable(row, col) {
            Some(v) => {
                (0..2).any(|s| r.curves[s][v].is_some() || r.reference.bands[s][v].is_some())
            }
            None => r
                .reference
                .extra
                .iter()
                .any(|(cell, _, _)| *cell == (row, col)),
        }
    }

    /// The rows of [`PANELS`] with a panel to draw.
    pub fn rows(&self) -> Vec<usize> {
        (0..PANELS.len())
            .filter(|&row| (0..3).any(|col| self.shown(row, col)))
            .collect()
    }

    fn panel<DB: DrawingBackend>(
        &self,
        area: &DrawingArea<DB, Shift>,
        row: usize,
        col: usize,
    ) -> Result<(), figure::PlotError> {
        let r = self.report;
        let panel = PANELS[row][col];
        let v = Self::variable(row, col);
        let title = match panel {
            Panel::Variable(var) => var.title(),
            Panel::Absent(t) => t,
        };
        let band: Vec<(&[f64], &[f64])> = match v {
            Some(v) => (0..2)
                .filter_map(|s| r.reference.bands[s][v].as_ref())
                .map(|b| (b.mean.as_slice(), b.sd.as_slice()))
                .collect(),
            None => r
                .reference
                .extra
                .iter()
                .filter(|(cell, _, _)| *cell == (row, col))
                .map(|(_, _, b)| (b.mean.as_slice(), b.sd.as_slice()))
                .collect(),
        };
        let curves: Vec<(usize, &crate::cycles::Curve)> = match v {
            Some(v) => (0..2)
                .filter_map(|s| r.curves[s][v].as_ref().map(|c| (s, c)))
                .collect(),
            None => Vec::new(),
        };
        // Each side's strides, at most MAX_STRIDE_LINES of them.
        let strides: Vec<(usize, Vec<Vec<f64>>)> = match v {
            Some(v) => (0..2)
                .map(|s| {
                    let all: Vec<Vec<f64>> =
                        r.stride_sample[s].iter().map(|c| c[v].clone()).collect();
                    let pick = spread(all.len(), MAX_STRIDE_LINES);
                    (s, pick.into_iter().map(|k| all[k].clone()).collect())
                })
                .collect(),
            None => Vec::new(),
        };
        let title = if band.is_empty() || !curves.is_empty() {
            title.to_string()
        } else {
            format!("{title}: reference only")
        };
        let values = band
            .iter()
            .flat_map(|(m, s)| m.iter().zip(*s).flat_map(|(m, s)| [m - s, m + s]))
            .chain(
                curves
                    .iter()
                    .flat_map(|(_, c)| c.mean.iter().zip(&c.sd).flat_map(|(m, s)| [m - s, m + s])),
            )
            .chain(
                strides
                    .iter()
                    .flat_map(|(_, c)| c.iter().flatten().copied()),
            );
        let (y0, y1) = figure::padded_range(values, 0.05, 10.0);
        let mut chart =
            Frame::new(8, 44, 56).chart(area, Some((&title, 17)), 0.0..100.0, y0..y1)?;
        figure::axes(&mut chart, X_TITLE, Y_TITLE, 13)
            .axis_desc_style(figure::text(14))
            .x_labels(6)
            .y_labels(5)
            .x_label_formatter(&|v| format!("{v:.0}"))
            .y_label_formatter(&|v| figure::tick(*v, 0))
            .draw()
            .map_err(draw_err)?;
        let step = |n: usize| 100.0 / (n - 1) as f64;
        // The normal toe off's range, behind everything.
        if let Some(rg) = r.reference.toe_off_range {
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(rg.min, y0), (rg.max, y1)],
                    BLACK.mix(0.05).filled(),
                )))
                .map_err(draw_err)?;
        }
        for (mean, sd) in &band {
            let dx = step(mean.len());
            let mut poly: Vec<(f64, f64)> = mean
                .iter()
                .zip(*sd)
                .enumerate()
                .map(|(i, (m, s))| (i as f64 * dx, m + s))
                .collect();
            poly.extend(
                mean.iter()
                    .zip(*sd)
                    .enumerate()
                    .rev()
                    .map(|(i, (m, s))| (i as f64 * dx, m - s)),
            );
            chart
                .draw_series(std::iter::once(Polygon::new(
                    poly,
                    BLACK.mix(0.12).filled(),
                )))
                .map_err(draw_err)?;
        }
        // The reference's mean (a recording's may have no spread to show): grey when one for
        // both sides (the normative data), else each side's in its colour.
        let same = band.windows(2).all(|w| w[0].0 == w[1].0);
        for (s, (mean, _)) in band.iter().enumerate() {
            let style = match (same, v) {
                (false, Some(_)) => SIDE_COLORS[s].mix(0.6).stroke_width(1),
                _ => BLACK.mix(0.45).stroke_width(1),
            };
            let dx = step(mean.len());
            let pts: Vec<(f64, f64)> = mean
                .iter()
                .enumerate()
                .map(|(i, m)| (i as f64 * dx, *m))
                .collect();
            figure::draw_polyline(chart.plotting_area(), &pts, style)?;
        }
        if let Some(zero) = (y0 < 0.0 && y1 > 0.0).then_some(0.0) {
            chart
                .draw_series(LineSeries::new(
                    [(0.0, zero), (100.0, zero)],
                    BLACK.mix(0.3),
                ))
                .map_err(draw_err)?;
        }
        for (s, all) in &strides {
            let color = SIDE_COLORS[*s].mix(0.3).stroke_width(1);
            for c in all {
                let dx = step(c.len());
                let pts: Vec<(f64, f64)> = c
                    .iter()
                    .enumerate()
                    .map(|(i, m)| (i as f64 * dx, *m))
                    .collect();
                figure::draw_polyline(chart.plotting_area(), &pts, color)?;
            }
        }
        for (s, c) in &curves {
            let color = SIDE_COLORS[*s];
            let dx = step(c.mean.len());
            if c.n > 1 {
                let mut poly: Vec<(f64, f64)> = c
                    .mean
                    .iter()
                    .zip(&c.sd)
                    .enumerate()
                    .map(|(i, (m, sd))| (i as f64 * dx, m + sd))
                    .collect();
                poly.extend(
                    c.mean
                        .iter()
                        .zip(&c.sd)
                        .enumerate()
                        .rev()
                        .map(|(i, (m, sd))| (i as f64 * dx, m - sd)),
                );
                chart
                    .draw_series(std::iter::once(Polygon::new(
                        poly,
                        color.mix(0.15).filled(),
                    )))
                    .map_err(draw_err)?;
            }
            let pts: Vec<(f64, f64)> = c
                .mean
                .iter()
                .enumerate()
                .map(|(i, m)| (i as f64 * dx, *m))
                .collect();
            figure::draw_polyline(chart.plotting_area(), &pts, color.stroke_width(2))?;
        }
        // The reference's toe off, dashed: grey when one for both sides (the normative one),
        // else each side's in its colour; then the measured one of each side, solid.
        let same_toe_off = r.reference.toe_off[0] == r.reference.toe_off[1];
        for (s, to) in r.reference.toe_off.iter().enumerate() {
            if let Some(p) = to {
                let color = if same_toe_off {
                    BLACK.mix(0.6)
                } else {
                    SIDE_COLORS[s].mix(0.6)
                };
                chart
                    .draw_series(DashedLineSeries::new(
                        [(*p, y0), (*p, y1)],
                        6,
                        4,
                        color.stroke_width(2),
                    ))
                    .map_err(draw_err)?;
            }
        }
        for (s, to) in r.toe_off.iter().enumerate() {
            if let Some(p) = to {
                chart
                    .draw_series(LineSeries::new(
                        [(*p, y0), (*p, y1)],
                        SIDE_COLORS[s].stroke_width(2),
                    ))
                    .map_err(draw_err)?;
            }
        }
        Ok(())
    }
}

/// "right" and "left" in their colours, from (x, y).
fn side_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    y: i32,
) -> Result<(), figure::PlotError> {
    for (s, name) in ["right", "left"].iter().enumerate() {
        let x = x + 140 * s as i32;
        area.draw(&PathElement::new(
            vec![(x, y + 9), (x + 36, y + 9)],
            SIDE_COLORS[s].stroke_width(4),
        ))
        .map_err(draw_err)?;
        area.draw(&Text::new(name.to_string(), (x + 44, y), figure::text(16)))
            .map_err(draw_err)?;
    }
    Ok(())
}

/// The Movement Analysis Profile.
pub struct Map<'a> {
    /// The report.
    pub report: &'a Report,
}

impl Figure for Map<'_> {
    fn stem(&self) -> String {
        "map".into()
    }

    fn size(&self) -> (u32, u32) {
        (1100, 520)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), figure::PlotError> {
        let Some(s) = &self.report.scores else {
            return Ok(());
        };
        let (header, area) = figure::titled(root, 90, "Movement Analysis Profile")?;
        figure::header_line(
            &header,
            &format!(
                "Gait Variable Scores and Gait Profile Score (degrees) against {}{}",
                self.report.reference.legend(),
                if self.report.seen == Seen::SAGITTAL {
                    "; sagittal angles only (planar model)".to_string()
                } else if self.report.seen.is_all() {
                    String::new()
                } else {
                    format!(
                        "; the {} angles the model can move",
                        self.report.seen.variables().len()
                    )
                }
            ),
            15,
            42,
        )?;
        side_legend(&header, 16, 64)?;
        header
            .draw(&PathElement::new(
                vec![(296, 73), (332, 73)],
                RGBColor(60, 60, 60).stroke_width(4),
            ))
            .map_err(draw_err)?;
        header
            .draw(&Text::new("overall GPS", (340, 64), figure::text(16)))
            .map_err(draw_err)?;
        let normal = self.report.normal_scores.as_ref();
        if normal.is_some() {
            header
                .draw(&PathElement::new(
                    vec![(480, 73), (516, 73)],
                    NORMAL_TICK.stroke_width(3),
                ))
                .map_err(draw_err)?;
            header
                .draw(&Text::new(
                    "typical of the reference (RMS of its SD)",
                    (524, 64),
                    figure::text(16),
                ))
                .map_err(draw_err)?;
        }
        // Groups: the variables scored (those the model can move), then GPS (right,
        // left, overall).
        let scored: Vec<usize> = Variable::ALL
            .iter()
            .enumerate()
            .filter(|(_, v)| s.variables.contains(v))
            .map(|(i, _)| i)
            .collect();
        let gps_group = scored.len();
        let labels: Vec<String> = scored
            .iter()
            .map(|&v| {
                Variable::ALL[v]
                    .title()
                    .split(" (")
                    .next()
                    .unwrap_or("")
                    .to_string()
            })
            .chain(["GPS".to_string()])
            .collect();
        // Bars: (group, slot, value, colour, the reference member's value).
        let mut bars: Vec<(usize, usize, f64, RGBColor, Option<f64>)> = Vec::new();
        for (group, &v) in scored.iter().enumerate() {
            for (side, color) in SIDE_COLORS.iter().enumerate() {
                if let Some(g) = s.gvs[side][v] {
                    bars.push((group, side, g, *color, normal.and_then(|n| n.gvs[side][v])));
                }
            }
        }
        for (side, color) in SIDE_COLORS.iter().enumerate() {
            if let Some(g) = s.gps[side] {
                bars.push((gps_group, side, g, *color, normal.and_then(|n| n.gps[side])));
            }
        }
        if let Some(g) = s.overall {
            bars.push((
                gps_group,
                2,
                g,
                RGBColor(60, 60, 60),
                normal.and_then(|n| n.overall),
            ));
        }
        let top = bars
            .iter()
            .flat_map(|b| [b.2, b.4.unwrap_or(0.0)])
            .fold(5.0f64, f64::max)
            * 1.15;
        let mut chart =
            Frame::new(12, 60, 50).chart(&area, None, 0.0..labels.len() as f64, 0.0..top)?;
        chart
            .configure_mesh()
            .disable_x_mesh()
            .x_labels(0)
            .y_labels(6)
            .y_desc("degrees")
            .label_style(figure::text(13))
            .axis_desc_style(figure::text(13))
            .y_label_formatter(&|v| figure::tick(*v, 0))
            .light_line_style(WHITE.mix(0.0))
            .bold_line_style(BLACK.mix(0.08))
            .draw()
            .map_err(draw_err)?;
        for (g, side, value, color, typical) in &bars {
            let width = if *g == gps_group { 0.27 } else { 0.38 };
            let x0 = *g as f64 + 0.1 + *side as f64 * width;
            chart
                .draw_series(std::iter::once(Rectangle::new(
                    [(x0, 0.0), (x0 + width * 0.9, *value)],
                    color.filled(),
                )))
                .map_err(draw_err)?;
            if let Some(n) = typical {
                chart
                    .draw_series(LineSeries::new(
                        [(x0 - 0.02, *n), (x0 + width * 0.9 + 0.02, *n)],
                        NORMAL_TICK.stroke_width(3),
                    ))
                    .map_err(draw_err)?;
            }
            chart
                .draw_series(std::iter::once(Text::new(
                    format!("{value:.1}"),
                    (x0, *value + top * 0.03),
                    figure::text(11),
                )))
                .map_err(draw_err)?;
        }
        // Group labels under the axis, a word per line (on the whole figure: the chart clips).
        for (g, label) in labels.iter().enumerate() {
            let (px, py) = chart.plotting_area().map_coordinate(&(g as f64 + 0.1, 0.0));
            for (k, w) in label.split(' ').enumerate() {
                root.draw(&Text::new(
                    w.to_string(),
                    (px, py + 8 + 16 * k as i32),
                    figure::text(13),
                ))
                .map_err(draw_err)?;
            }
        }
        Ok(())
    }
}

/// The events over time.
pub struct EventsFigure<'a> {
    /// The report.
    pub report: &'a Report,
}

impl Figure for EventsFigure<'_> {
    fn stem(&self) -> String {
        "events".into()
    }

    fn size(&self) -> (u32, u32) {
        (1200, 110 + 300 * self.report.recordings.len() as u32)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), figure::PlotError> {
        let method = if self.report.recordings.iter().all(|w| w.gait.is_some()) {
            "Gait events (foot-velocity rules R of docs/gait-analysis.md)"
        } else {
            "Gait events (Zeni et al. 2008 where a recording has too few strides for the rules)"
        };
        let (header, area) = figure::titled(root, 110, method)?;
        let key = "heel (solid) and toe tip (thin) forward of the pelvis along the direction of \
                   progression; triangles: heel strikes, dots: toe offs";
        figure::header_line(&header, key, 15, 44)?;
        side_legend(&header, 16, 74)?;
        let rows = area.split_evenly((self.report.recordings.len().max(1), 1));
        for (w, row) in self.report.recordings.iter().zip(&rows) {
            // A long recording: a minute of it (crate::stream::EXCERPT), its bouts in words.
            let x = &w.excerpt;
            let t = &x.time;
            let (heel, toe) = (&x.heel, &x.toe);
            let (y0, y1) =
                figure::padded_range(heel.iter().chain(toe).flatten().copied(), 0.05, 0.2);
            let (t0, t1) = (t[0], *t.last().unwrap_or(&t[0]));
            let caption = if t1 - t0 < w.duration() - 1e-6 {
                let walking: f64 = w.bouts.iter().map(|b| b.end - b.start).sum();
                format!(
                    "{}: {} to {} s of {} h; {} walking bouts, {} min of walking (bouts.csv)",
                    w.label,
                    crate::number::round(t0, 1),
                    crate::number::round(t1, 1),
                    crate::number::round(w.duration() / 3600.0, 2),
                    w.bouts.len(),
                    crate::number::round(walking / 60.0, 1)
                )
            } else {
                w.label.clone()
            };
            let mut chart = Frame::new(10, 36, 56).chart(
                row,
                Some((&caption, 15)),
                t0..t1.max(t0 + 1e-6),
                y0..y1,
            )?;
            figure::axes(&mut chart, "time (s)", "forward (m)", 12)
                .y_label_formatter(&|v| figure::tick(*v, 2))
                .draw()
                .map_err(draw_err)?;
            for s in 0..2 {
                let color = SIDE_COLORS[s];
                for (signal, width) in [(&heel[s], 2), (&toe[s], 1)] {
                    let pts = figure::decimate_series(
                        chart.plotting_area(),
                        t.iter().copied().zip(signal.iter().copied()),
                    );
                    figure::draw_polyline(chart.plotting_area(), &pts, color.stroke_width(width))?;
                }
                for &e in &x.heel_strikes[s] {
                    chart
                        .draw_series(std::iter::once(TriangleMarker::new(
                            (t[e], heel[s][e]),
                            6,
                            color.filled(),
                        )))
                        .map_err(draw_err)?;
                }
                for &e in &x.toe_offs[s] {
                    chart
                        .draw_series(std::iter::once(Circle::new(
                            (t[e], toe[s][e]),
                            4,
                            color.filled(),
                        )))
                        .map_err(draw_err)?;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strides_drawn_are_spread_over_all() {
        assert_eq!(spread(3, 60), vec![0, 1, 2]);
        assert_eq!(spread(0, 60), Vec::<usize>::new());
        assert_eq!(spread(101, 5), vec![0, 25, 50, 75, 100]);
        let s = spread(1000, MAX_STRIDE_LINES);
        assert_eq!(s.len(), MAX_STRIDE_LINES);
        assert_eq!((s[0], s[s.len() - 1]), (0, 999));
        assert!(s.windows(2).all(|w| w[0] < w[1]));
        assert_eq!(spread(10, 1), vec![0]);
    }
}
