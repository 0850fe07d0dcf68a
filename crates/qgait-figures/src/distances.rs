//! Knee-knee, ankle-ankle and toe-toe distance over the cycle (the paper's Fig 10, Eqs 18-20).

use plotters::coord::Shift;
use plotters::prelude::*;
use qgait_kernel::metrics::Distances;

use super::figure::{self, draw_err, gait_color, Figure, PlotError};
use super::Analysis;

const PANEL_W: u32 = 1000;
const PANEL_H: u32 = 300;
const HEADER: u32 = 110;

/// Percent of the cycle where stance ends in normal gait (marked on the plots).
pub const STANCE_END_PERCENT: f64 = 60.0;

/// The three distance panels.
pub struct DistanceFigure<'a> {
    /// The gaits.
    pub analysis: &'a Analysis,
}

/// Picks one distance out of the three.
pub type Measure = fn(&Distances<f64>) -> f64;

/// The distances shown, with their titles.
pub const MEASURES: [(&str, Measure); 3] = [
    ("knee-knee distance", |d| d.knee),
    ("ankle-ankle distance", |d| d.ankle),
    ("toe-toe distance", |d| d.toe),
];

impl Figure for DistanceFigure<'_> {
    fn stem(&self) -> String {
        "distances".into()
    }

    fn size(&self) -> (u32, u32) {
        (PANEL_W, HEADER + MEASURES.len() as u32 * PANEL_H)
    }

    fn draw<DB: DrawingBackend>(&self, root: &DrawingArea<DB, Shift>) -> Result<(), PlotError> {
        let (header, grid) = figure::titled(
            root,
            HEADER,
            "Distance between the two legs' joint centres over the gait cycle",
        )?;
        figure::header_line(
                &header,
                &format!(
                    "{}; 3-D Euclidean distance (paper Eqs 18-20); dashed line: end of stance in normal gait (60 %)",
                    self.analysis.model
                ),
                16,
                46,
            )?;
        figure::draw_gait_legend(&header, self.analysis, 16, 78)?;
        let panels = grid.split_evenly((MEASURES.len(), 1));
        for (panel, (title, measure)) in panels.iter().zip(MEASURES) {
            let values = self
                .analysis
                .gaits
                .iter()
                .flat_map(|g| g.distances.iter().map(measure));
            let (y0, y1) = figure::padded_range(values, 0.08, 0.02);
            let (y0, y1) = (y0.max(0.0), y1);
            let mut chart =
                figure::METRE_PANEL.chart(panel, Some((title, 17)), 0.0..100.0, y0..y1)?;
            figure::axes(&mut chart, "gait cycle (%)", "distance (m)", 13)
                .x_labels(11)
                .y_labels(6)
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| figure::tick(*v, 2))
                .draw()
                .map_err(draw_err)?;
            chart
                .draw_series(DashedLineSeries::new(
                    [(STANCE_END_PERCENT, y0), (STANCE_END_PERCENT, y1)],
                    8,
                    6,
                    BLACK.mix(0.5).stroke_width(1),
                ))
                .map_err(draw_err)?;
            for (g, gait) in self.analysis.gaits.iter().enumerate() {
                let color = gait_color(g);
                let pts = figure::decimate_series(
                    chart.plotting_area(),
                    gait.percent
                        .iter()
                        .copied()
                        .zip(gait.distances.iter().map(measure)),
                );
                let style = color.stroke_width(figure::gait_width(g, self.analysis.gaits.len()));
                figure::draw_polyline(chart.plotting_area(), &pts, style)?;
                chart
                    .draw_series(std::iter::empty::<PathElement<(f64, f64)>>())
                    .map_err(draw_err)?
                    .label(gait.label.clone())
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 24, y)], color.stroke_width(3))
                    });
            }
        }
        Ok(())
    }
}
