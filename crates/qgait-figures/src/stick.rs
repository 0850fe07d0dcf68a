//! Stick figures of both legs at 0-100 % of the cycle in one plane (the paper's Figs 5-7):
//! one row of panels per gait, one column per percentage, the same scale on both axes.

use plotters::coord::Shift;
use plotters::prelude::*;
use qgait_kernel::metrics::Plane;
use qgait_kernel::{BilateralPose, Joint, Side, Vec3};

use super::figure::{self, draw_err, Figure, Frame, PlotError, LEFT_LEG, PELVIS, RIGHT_LEG};
use super::{Analysis, STICK_PERCENTS};

const PANEL: u32 = 300;
const HEADER: u32 = 110;
const PANEL_TITLE: u32 = 26;
const FRAME: Frame = Frame::new(8, 42, 62);

/// The stick-figure grid of one plane.
pub struct StickFigure<'a> {
    analysis: &'a Analysis,
    plane: Plane,
    /// Poses per gait per percentage.
    poses: Vec<Vec<BilateralPose<f64>>>,
}

impl<'a> StickFigure<'a> {
    /// Computes the poses to draw.
    pub fn new(analysis: &'a Analysis, plane: Plane) -> Self {
        let poses = analysis
            .gaits
            .iter()
            .map(|g| {
                STICK_PERCENTS
                    .iter()
                    .map(|&p| analysis.pose_at(g, p))
                    .collect()
            })
            .collect();
        Self {
            analysis,
            plane,
            poses,
        }
    }
}

/// Plane coordinates as drawn: (horizontal, vertical). The transverse plane is seen from above
/// with x forward to the right, so +z (right) points down the page: it is drawn as -z.
pub fn screen(plane: Plane, p: Vec3<f64>) -> (f64, f64) {
    let [a, b] = plane.project(p);
    match plane {
        Plane::Transverse => (a, -b),
        _ => (a, b),
    }
}

/// Title and axis descriptions of a plane.
pub fn plane_text(plane: Plane) -> (&'static str, &'static str, &'static str) {
    match plane {
        Plane::Sagittal => (
            "sagittal plane (x-y), seen from the right",
            "x, forward (m)",
            "y, up (m)",
        ),
        Plane::Frontal => (
            "frontal plane (z-y), seen from behind",
            "z, to the right (m)",
            "y, up (m)",
        ),
        Plane::Transverse => (
            "transverse plane (x-z), seen from above",
            "x, forward (m)",
            "z, to the right (m), +z down",
        ),
    }
}

impl Figure for StickFigure<'_> {
    fn stem(&self) -> String {
        format!("stick_{}", self.plane.name().to_lowercase())
    }

    fn size(&self) -> (u32, u32) {
        (
            STICK_PERCENTS.len() as u32 * PANEL,
            HEADER + self.analysis.gaits.len() as u32 * PANEL,
        )
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (title, x_desc, y_desc) = plane_text(self.plane);
        let (header, grid) = figure::titled(
            root,
            HEADER,
            &format!("Stick figures of both legs, {title}"),
        )?;
        figure::header_line(
            &header,
            &format!(
                "{}; same scale on both axes; one row per gait",
                self.analysis.model
            ),
            16,
            44,
        )?;
        draw_legend(&header, 16, 78)?;

        // One range for every panel, equal scale on both axes.
        let points = self.poses.iter().flatten().flat_map(|pose| {
            Side::ALL.into_iter().flat_map(move |s| {
                Joint::ALL
                    .into_iter()
                    .map(move |j| screen(self.plane, pose.point(s, j)))
            })
        });
        let (xs, ys): (Vec<f64>, Vec<f64>) = points.unzip();
        let (x0, x1) = figure::padded_range(xs, 0.06, 0.1);
        let (y0, y1) = figure::padded_range(ys, 0.06, 0.1);
        let (plot_w, plot_h) = FRAME.plot_size(PANEL, PANEL - PANEL_TITLE);
        let scale = ((x1 - x0) / plot_w).max((y1 - y0) / plot_h); // metres per pixel
        let (xc, yc) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
        let (xr, yr) = (
            xc - scale * plot_w / 2.0..xc + scale * plot_w / 2.0,
            yc - scale * plot_h / 2.0..yc + scale * plot_h / 2.0,
        );

        let panels = grid.split_evenly((self.analysis.gaits.len(), STICK_PERCENTS.len()));
        for (g, gait) in self.analysis.gaits.iter().enumerate() {
            for (k, &percent) in STICK_PERCENTS.iter().enumerate() {
                let panel = &panels[g * STICK_PERCENTS.len() + k];
                let area = panel
                    .titled(
                        &format!("{}, {percent} % of cycle", gait.label),
                        figure::bold(15),
                    )
                    .map_err(draw_err)?;
                let mut chart = FRAME.chart(&area, None, xr.clone(), yr.clone())?;
                let transverse = self.plane == Plane::Transverse;
                figure::axes(&mut chart, x_desc, y_desc, 12)
                    .x_labels(5)
                    .y_labels(5)
                    .x_label_formatter(&|v| figure::tick(*v, 1))
                    .y_label_formatter(&|v| figure::tick(if transverse { -v } else { *v }, 1))
                    .draw()
                    .map_err(draw_err)?;
                let pose = &self.poses[g][k];
                let pelvis = [
                    screen(self.plane, pose.right.hip),
                    screen(self.plane, pose.left.hip),
                ];
                figure::draw_polyline(chart.plotting_area(), &pelvis, PELVIS.stroke_width(3))?;
                for (side, color) in [(Side::Left, LEFT_LEG), (Side::Right, RIGHT_LEG)] {
                    let pts: Vec<(f64, f64)> = Joint::ALL
                        .iter()
                        .map(|&j| screen(self.plane, pose.point(side, j)))
                        .collect();
                    figure::draw_polyline(chart.plotting_area(), &pts, color.stroke_width(3))?;
                    chart
                        .draw_series(pts.iter().map(|&p| Circle::new(p, 4, color.filled())))
                        .map_err(draw_err)?;
                }
            }
        }
        Ok(())
    }
}

/// The colour key shared by the stick figures.
fn draw_legend<DB: DrawingBackend>(
    area: &DrawingArea<DB, Shift>,
    x: i32,
    y: i32,
) -> Result<(), PlotError> {
    let mut x = x;
    for (color, text) in [
        (RIGHT_LEG, "right leg"),
        (LEFT_LEG, "left leg"),
        (PELVIS, "pelvis (hip to hip)"),
    ] {
        area.draw(&PathElement::new(
            vec![(x, y + 9), (x + 36, y + 9)],
            color.stroke_width(3),
        ))
        .map_err(draw_err)?;
        area.draw(&Text::new(text, (x + 44, y), figure::text(16)))
            .map_err(draw_err)?;
        x += 60 + 10 * text.len() as i32;
    }
    area.draw(&Circle::new((x + 6, y + 9), 4, BLACK.filled()))
        .map_err(draw_err)?;
    area.draw(&Text::new(
        "joint centres: hip, knee, ankle, toe along each leg",
        (x + 18, y),
        figure::text(16),
    ))
    .map_err(draw_err)?;
    Ok(())
}
