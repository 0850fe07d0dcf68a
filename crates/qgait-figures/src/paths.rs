//! Sagittal paths of the hip, knee, ankle and toe over the cycle, right and left limb, gaits
//! overlaid (the paper's Figs 8-9).

use plotters::coord::Shift;
use plotters::prelude::*;
use qgait_kernel::metrics::Plane;
use qgait_kernel::{Joint, Side};

use super::figure::{self, draw_err, gait_color, Figure, PlotError};
use super::Analysis;

const PANEL_W: u32 = 560;
const PANEL_H: u32 = 300;
const HEADER: u32 = 110;

/// The 4 × 2 grid of sagittal joint paths.
pub struct SagittalPaths<'a> {
    /// The gaits.
    pub analysis: &'a Analysis,
}

impl Figure for SagittalPaths<'_> {
    fn stem(&self) -> String {
        "paths_sagittal".into()
    }

    fn size(&self) -> (u32, u32) {
        (2 * PANEL_W, HEADER + Joint::ALL.len() as u32 * PANEL_H)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (header, grid) = figure::titled(
            root,
            HEADER,
            "Sagittal paths of the joint centres over one gait cycle",
        )?;
        figure::header_line(
                &header,
                &format!(
                    "{}; x forward, y up; each panel has its own scale; dot = 0 % of the cycle; identical curves overlap",
                    self.analysis.model
                ),
                16,
                44,
            )?;
        figure::draw_gait_legend(&header, self.analysis, 16, 78)?;

        let panels = grid.split_evenly((Joint::ALL.len(), 2));
        for (j, joint) in Joint::ALL.into_iter().enumerate() {
            // Both limbs of a joint share ranges so they can be compared.
            let all = || {
                self.analysis.gaits.iter().flat_map(move |g| {
                    g.poses.iter().flat_map(move |p| {
                        Side::ALL
                            .into_iter()
                            .map(move |s| Plane::Sagittal.project(p.point(s, joint)))
                    })
                })
            };
            let xr = figure::padded_range(all().map(|p| p[0]), 0.05, 0.01);
            let yr = figure::padded_range(all().map(|p| p[1]), 0.08, 0.01);
            for (s, side) in Side::ALL.into_iter().enumerate() {
                let side_name = match side {
                    Side::Right => "right",
                    Side::Left => "left",
                };
                let title = format!("{} {}", side_name, joint.name());
                let mut chart = figure::METRE_PANEL.chart(
                    &panels[2 * j + s],
                    Some((&title, 17)),
                    xr.0..xr.1,
                    yr.0..yr.1,
                )?;
                figure::axes(&mut chart, "x, forward (m)", "y, up (m)", 13)
                    .x_labels(6)
                    .y_labels(5)
                    .x_label_formatter(&|v| figure::tick(*v, 2))
                    .y_label_formatter(&|v| figure::tick(*v, 3))
                    .draw()
                    .map_err(draw_err)?;
                for (g, gait) in self.analysis.gaits.iter().enumerate() {
                    let color = gait_color(g);
                    let pts: Vec<(f64, f64)> = gait
                        .poses
                        .iter()
                        .map(|p| {
                            let [a, b] = Plane::Sagittal.project(p.point(side, joint));
                            (a, b)
                        })
                        .collect();
                    figure::draw_polyline(
                        chart.plotting_area(),
                        &pts,
                        color.stroke_width(figure::gait_width(g, self.analysis.gaits.len())),
                    )?;
                    chart
                        .draw_series(pts.first().map(|&p| Circle::new(p, 5, color.filled())))
                        .map_err(draw_err)?;
                }
            }
        }
        Ok(())
    }
}
