//! `qgait imu --compare`: joint angles from `qgait imu` against a reference solution of the
//! same recording (OpenSense's `.mot`/`.sto`), as a table of every coordinate's RMSE and
//! largest difference and a figure of both over time (`imu_angles.png`/`.svg`).
//!
//! Rows are matched by time (the reference's rows; a reference time without a row of ours
//! within 1 µs is an error). Compared: every coordinate in both files whose reference is not
//! zero throughout (a coordinate the reference's model locks or the sensors do not determine,
//! MTP for instance, is left out). The pelvis is compared as an orientation: when both have
//! `pelvis_tilt`, `pelvis_list` and `pelvis_rotation` (z, x, y body-fixed, gait2392's and
//! Rajagopal's sequence), the reference's three are re-expressed on the principal branch
//! (list within ±90°) with the rotation within half a turn of ours, because OpenSim's IK may
//! report an equivalent branch (tilt and list near ±180°, or whole turns added).

use std::path::{Path, PathBuf};

use plotters::coord::Shift;
use plotters::prelude::*;
use qgait_kernel::imu::math::three_axes;
use qgait_kernel::{Quat, Vec3};

use super::figure::{self, draw_err, gait_color, Figure, Frame};
use super::ReportError;
use qgait_opensim::mot::MotionTable;

fn unit(in_degrees: bool) -> &'static str {
    if in_degrees {
        "degrees"
    } else {
        "radians"
    }
}

/// One compared coordinate.
#[derive(Debug, Clone, PartialEq)]
pub struct Compared {
    /// The coordinate.
    pub name: String,
    /// Ours at the reference's times (degrees or as the files are).
    pub ours: Vec<f64>,
    /// The reference's (the pelvis on the principal branch).
    pub theirs: Vec<f64>,
    /// Root mean square of the difference.
    pub rmse: f64,
    /// Largest absolute difference.
    pub max: f64,
}

/// The comparison of two solutions of one recording.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// The reference's times.
    pub time: Vec<f64>,
    /// Every compared coordinate, in the reference's column order.
    pub coordinates: Vec<Compared>,
}

const PELVIS: [&str; 3] = ["pelvis_tilt", "pelvis_list", "pelvis_rotation"];

/// The pelvis angles (degrees) of the same orientation on the principal branch, the rotation
/// within half a turn of `near`.
fn principal_pelvis(angles: [f64; 3], near: f64) -> [f64; 3] {
    let (x, y, z) = (Vec3::unit_x(), Vec3::unit_y(), Vec3::unit_z());
    let [tilt, list, rotation] = angles.map(f64::to_radians);
    let q = Quat::from_axis_angle(z, tilt)
        * Quat::from_axis_angle(x, list)
        * Quat::from_axis_angle(y, rotation);
    let [a, b, c] = three_axes(q, [z, x, y]).map(f64::to_degrees);
    [a, b, c + 360.0 * ((near - c) / 360.0).round()]
}

/// Compares `ours` with `theirs` (see the [module](self) docs).
pub fn compare(ours: &MotionTable, theirs: &MotionTable) -> Result<Comparison, ReportError> {
    if ours.in_degrees() != theirs.in_degrees() {
        return Err(ReportError::Units {
            location: theirs.labels_location(),
            theirs: unit(theirs.in_degrees()),
            ours: unit(ours.in_degrees()),
        });
    }
    // Our row for each reference row.
    let mut index = Vec::with_capacity(theirs.rows());
    let mut j = 0;
    for &t in theirs.time() {
        while j < ours.rows() && ours.time()[j] < t - 1e-6 {
            j += 1;
        }
        if j == ours.rows() || (ours.time()[j] - t).abs() > 1e-6 {
            return Err(ReportError::NoRow {
                location: theirs.labels_location(),
                time: t,
            });
        }
        index.push(j);
    }
    let mut coordinates = Vec::new();
    let pelvis = PELVIS
        .iter()
        .all(|c| ours.column(c).is_some() && theirs.column(c).is_some());
    let pick = |table: &MotionTable, name: &str, rows: Option<&[usize]>| -> Vec<f64> {
        let c = table.column(name).expect("a column of both");
        match rows {
            Some(rows) => rows.iter().map(|&r| c[r]).collect(),
            None => c.to_vec(),
        }
    };
    let mut principal: Option<[Vec<f64>; 3]> = None;
    if pelvis {
        let ours_rot = pick(ours, "pelvis_rotation", Some(&index));
        let deg = |v: f64| {
            if theirs.in_degrees() {
                v
            } else {
                v.to_degrees()
            }
        };
        let undeg = |v: f64| {
            if theirs.in_degrees() {
                v
            } else {
                v.to_radians()
            }
        };
        let t = PELVIS.map(|c| pick(theirs, c, None));
        let mut out = [Vec::new(), Vec::new(), Vec::new()];
        for r in 0..theirs.rows() {
            let p = principal_pelvis([deg(t[0][r]), deg(t[1][r]), deg(t[2][r])], deg(ours_rot[r]));
            for k in 0..3 {
                out[k].push(undeg(p[k]));
            }
        }
        principal = Some(out);
    }
    for name in theirs.labels().iter().skip(1) {
        if ours.column(name).is_none() {
            continue;
        }
        let reference = match (PELVIS.iter().position(|p| p == name), &principal) {
            (Some(k), Some(p)) => p[k].clone(),
            _ => pick(theirs, name, None),
        };
        if reference.iter().all(|v| *v == 0.0) {
            continue;
        }
        let mine = pick(ours, name, Some(&index));
        let (mut sum, mut max) = (0.0, 0.0f64);
        for (a, b) in mine.iter().zip(&reference) {
            let e = a - b;
            sum += e * e;
            max = max.max(e.abs());
        }
        let rmse = (sum / reference.len().max(1) as f64).sqrt();
        coordinates.push(Compared {
            name: name.clone(),
            ours: mine,
            theirs: reference,
            rmse,
            max,
        });
    }
    if coordinates.is_empty() {
        return Err(ReportError::NothingInCommon {
            location: theirs.labels_location(),
        });
    }
    Ok(Comparison {
        time: theirs.time().to_vec(),
        coordinates,
    })
}

impl Comparison {
    /// The table (Markdown): every compared coordinate's RMSE and largest difference.
    pub fn markdown(&self, unit: &str) -> String {
        let mut s = format!("| coordinate | RMSE ({unit}) | max ({unit}) |\n|---|---:|---:|\n");
        for c in &self.coordinates {
            s.push_str(&format!(
                "| `{}` | {:.2} | {:.2} |\n",
                c.name, c.rmse, c.max
            ));
        }
        s
    }
}

const COLUMNS: usize = 3;
const PANEL_W: u32 = 520;
const PANEL_H: u32 = 250;
const HEADER: u32 = 96;
const FRAME: Frame = Frame::new(8, 34, 56);

/// Both solutions of every compared coordinate over time.
struct AnglesFigure<'a> {
    comparison: &'a Comparison,
    labels: [&'a str; 2],
    unit: &'a str,
}

impl Figure for AnglesFigure<'_> {
    fn stem(&self) -> String {
        "imu_angles".into()
    }

    fn size(&self) -> (u32, u32) {
        let rows = self.comparison.coordinates.len().div_ceil(COLUMNS) as u32;
        (COLUMNS as u32 * PANEL_W, HEADER + rows * PANEL_H)
    }

    fn draw<DB: DrawingBackend>(
        &self,
        root: &DrawingArea<DB, Shift>,
    ) -> Result<(), figure::PlotError> {
        let (header, grid) = figure::titled(root, HEADER, "Joint angles from IMU orientations")?;
        for (k, label) in self.labels.iter().enumerate() {
            let x = 16 + 420 * k as i32;
            let color = gait_color(k);
            header
                .draw(&PathElement::new(
                    vec![(x, 62), (x + 30, 62)],
                    color.stroke_width(3),
                ))
                .map_err(draw_err)?;
            header
                .draw_text(label, &figure::text(16), (x + 38, 53))
                .map_err(draw_err)?;
        }
        let rows = self.comparison.coordinates.len().div_ceil(COLUMNS);
        let panels = grid.split_evenly((rows, COLUMNS));
        let t0 = self.comparison.time.first().copied().unwrap_or(0.0);
        let t1 = self
            .comparison
            .time
            .last()
            .copied()
            .unwrap_or(1.0)
            .max(t0 + 1e-9);
        for (panel, c) in panels.iter().zip(&self.comparison.coordinates) {
            let (y0, y1) = figure::padded_range(c.ours.iter().chain(&c.theirs).copied(), 0.08, 1.0);
            let title = format!("{}  (RMSE {:.2}, max {:.2})", c.name, c.rmse, c.max);
            let mut chart = FRAME.chart(panel, Some((&title, 15)), t0..t1, y0..y1)?;
            figure::axes(&mut chart, "time (s)", self.unit, 12)
                .x_labels(7)
                .y_labels(5)
                .x_label_formatter(&|v| format!("{v:.0}"))
                .y_label_formatter(&|v| figure::tick(*v, 0))
                .draw()
                .map_err(draw_err)?;
            // The reference first and wider, so that ours drawn on it leaves a rim of it.
            for (series, color, width) in [(&c.theirs, 1, 4), (&c.ours, 0, 2)] {
                let pts = figure::decimate_series(
                    chart.plotting_area(),
                    self.comparison
                        .time
                        .iter()
                        .copied()
                        .zip(series.iter().copied()),
                );
                figure::draw_polyline(
                    chart.plotting_area(),
                    &pts,
                    gait_color(color).stroke_width(width),
                )?;
            }
        }
        Ok(())
    }
}

/// Writes `imu_angles.png` and `.svg` into `dir`: ours (`labels[0]`) and the reference's
/// (`labels[1]`) over time, one panel per coordinate.
pub fn draw(
    comparison: &Comparison,
    labels: [&str; 2],
    unit: &str,
    dir: &Path,
) -> Result<Vec<PathBuf>, ReportError> {
    std::fs::create_dir_all(dir).map_err(|error| ReportError::CreateDir {
        path: dir.to_path_buf(),
        error,
    })?;
    Ok(figure::save(
        &AnglesFigure {
            comparison,
            labels,
            unit,
        },
        dir,
    )?)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The other Euler branch of z-x-y (tilt + 180, 180 - list, rotation + 180) and whole
    /// turns come back to the principal angles, the rotation next to the one asked for.
    #[test]
    fn principal_pelvis_undoes_branch_jumps_and_turns() {
        for k in 0..200 {
            let f = k as f64;
            let angles = [
                40.0 * (0.7 * f).sin(),
                30.0 * (1.3 * f).cos(),
                170.0 * (0.9 * f).sin(),
            ];
            let turns = 360.0 * ((k % 7) as f64 - 3.0);
            let other = [
                angles[0] + 180.0 + turns,
                180.0 - angles[1] - turns,
                angles[2] + 180.0 + 2.0 * turns,
            ];
            let near = angles[2] + 720.0 + 10.0 * (f * 0.1).sin();
            let got = principal_pelvis(other, near);
            let want = [angles[0], angles[1], angles[2] + 720.0];
            for i in 0..3 {
                assert!((got[i] - want[i]).abs() < 1e-9, "{k}: {got:?} {want:?}");
            }
        }
    }
}
