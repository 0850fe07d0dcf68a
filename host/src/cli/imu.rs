//! `qgait imu`: IMU segment orientations (OpenSim orientation `.sto`) to gait2392 joint angles
//! (OpenSim `.mot`), with the kernel's OpenSense-style calibration and solver
//! ([`qgait_kernel::imu`]).

use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use qgait_kernel::imu::{
    heading_free_pelvis, Calibration, Heading, HeadingAxis, Mode, Segment, Settings, Solver, LUMBAR,
};
use qgait_kernel::models::gait2392::COORDINATES;
use qgait_kernel::Gait2392;

use crate::cli::diagnostics::Diagnostics;
use crate::cli::model_args::ModelArgs;
use crate::cli::{refuse_overwrite, write_output_with};
use crate::diagnostics::Warning;
use crate::model::error::ModelError;
use crate::opensim::imu_sto::OrientationReader;
use crate::opensim::mot::{write_mot_header, write_mot_row};
use crate::progress::Progress;

/// Arguments of `qgait imu`.
#[derive(Debug, Args)]
pub struct ImuArgs {
    /// The recording: OpenSim orientation .sto (DataType=Quaternion, `<body>_imu` columns,
    /// cells `w,x,y,z`).
    pub orientations: PathBuf,
    /// The static calibration pose (same format; its first row is used), the subject standing
    /// in the model's default pose (OpenSense's `orientation_file_for_calibration`).
    #[arg(long, value_name = "STATIC.sto")]
    pub calibration: PathBuf,
    /// The model: gait2392 (the default), a SUBJECT.toml or an OpenSim MODEL.osim of the
    /// gait2392 family (its joint axes are used; gait2392's coordinates are written).
    #[command(flatten)]
    pub model: ModelArgs,
    /// The IMU whose heading axis points forward in the calibration pose (OpenSense's
    /// `base_imu_label`, e.g. `torso_imu` or `pelvis_imu`); default none: no heading
    /// correction, as OpenSense (the subject then faces the sensors' world x at calibration).
    #[arg(long, value_name = "NAME")]
    pub base_imu: Option<String>,
    /// The base IMU's axis that points forward (OpenSense's `base_heading_axis`).
    #[arg(
        long,
        default_value = "z",
        value_name = "x|-x|y|-y|z|-z",
        allow_hyphen_values = true
    )]
    pub base_heading_axis: String,
    /// Rotation from the sensors' world frame to OpenSim's (y up): space-fixed X, Y, Z Euler
    /// angles in radians, as OpenSense's `sensor_to_opensim_rotations` (the default turns a
    /// z-up world, Xsens or APDM, to OpenSim's y up).
    #[arg(
        long,
        default_value = "-1.5707963267948966,0,0",
        value_name = "RX,RY,RZ",
        allow_hyphen_values = true
    )]
    pub sensor_to_opensim: String,
    /// The solver: per-leg least squares (OpenSense's problem) or the per-joint closed form.
    #[arg(long, value_enum, default_value_t = ModeArg::LeastSquares)]
    pub mode: ModeArg,
    /// The pelvis's convention: `opensense` (in the sensors' world frame, heading in
    /// `pelvis_rotation`, as OpenSense writes it) or `heading-free` (tilt and list relative to
    /// the direction of progression: the centred 2 s mean of `pelvis_rotation`; for analyses
    /// of turning walks).
    #[arg(long, value_enum, default_value_t = PelvisArg::Opensense)]
    pub pelvis: PelvisArg,
    /// Output .mot (joint angles in degrees).
    #[arg(short, long, value_name = "ANGLES.mot")]
    pub output: PathBuf,
}

/// `--mode`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum ModeArg {
    /// [`Mode::LeastSquares`].
    LeastSquares,
    /// [`Mode::ClosedForm`].
    ClosedForm,
}

/// `--pelvis`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum PelvisArg {
    /// As OpenSense: in the sensors' world frame.
    Opensense,
    /// Relative to the direction of progression ([`heading_free_pelvis`]).
    HeadingFree,
}

/// The window of the direction of progression for `--pelvis heading-free` (seconds, centred):
/// about two strides, so that the pelvis's rotation within a stride averages out.
pub const PROGRESSION_WINDOW: f64 = 2.0;

/// The settings from the command line (also `qgait packets --orientations` and `verify
/// --orientations`, which take the same options).
pub(crate) fn settings(a: &ImuArgs) -> anyhow::Result<Settings<f64>> {
    let parts: Vec<&str> = a.sensor_to_opensim.split(',').collect();
    let mut r = [0.0; 3];
    if parts.len() != 3 {
        bail!(
            "--sensor-to-opensim `{}`: expected three angles in radians, RX,RY,RZ",
            a.sensor_to_opensim
        );
    }
    for (p, slot) in parts.iter().zip(&mut r) {
        *slot = p
            .trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| {
                format!(
                    "--sensor-to-opensim `{}`: `{p}` is not a number (radians)",
                    a.sensor_to_opensim
                )
            })?;
    }
    let axis: HeadingAxis = a.base_heading_axis.parse().map_err(|()| {
        anyhow::anyhow!(
            "--base-heading-axis `{}`: expected x, -x, y, -y, z or -z",
            a.base_heading_axis
        )
    })?;
    let heading = match &a.base_imu {
        None => None,
        Some(name) => Some(Heading {
            base: Segment::from_name(name).with_context(|| {
                format!(
                    "--base-imu `{name}`: not an IMU of the set ({})",
                    Segment::ALL.map(Segment::imu_label).join(", ")
                )
            })?,
            axis,
        }),
    };
    Ok(Settings {
        sensor_to_opensim: r,
        heading,
    })
}

/// Runs `qgait imu`.
pub fn run_imu(a: ImuArgs, diagnostics: &Diagnostics) -> anyhow::Result<()> {
    let mut inputs: Vec<String> = [&a.orientations, &a.calibration]
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    inputs.extend(a.model.inputs());
    refuse_overwrite([a.output.as_path()], &inputs)?;
    let chosen = a.model.load_or("gait2392", diagnostics)?;
    let Some(geometry) = chosen.geometry() else {
        bail!(
            "--model {}: `qgait imu` solves a gait2392-family model (gait2392, a SUBJECT.toml or an .osim)",
            chosen.name()
        );
    };
    let settings = settings(&a)?;
    let mut warnings: Vec<Warning> = Vec::new();
    let model = Gait2392::<f64>::new(geometry).map_err(|error| ModelError::Rejected {
        name: chosen.name().to_string(),
        error,
    })?;

    let calibration = calibrate(&a.calibration, &model, &settings, &mut warnings)?;
    let mut reader = OrientationReader::open(&a.orientations)?;
    for s in calibration.1.iter().copied() {
        if !reader.sensors().any(|r| r == s) {
            bail!(
                "{}: no column `{s}`, but the calibration pose ({}) has it",
                reader.labels_location(),
                a.calibration.display()
            );
        }
    }
    for s in reader.sensors().collect::<Vec<_>>() {
        if !calibration.1.contains(&s) {
            warnings.push(Warning(format!(
                "{}: `{s}` has no reading in the calibration pose ({}); its column is ignored",
                reader.labels_location(),
                a.calibration.display()
            )));
        }
    }
    let calibration = calibration.0;

    let mode = match a.mode {
        ModeArg::LeastSquares => Mode::LeastSquares,
        ModeArg::ClosedForm => Mode::ClosedForm,
    };
    let name = a
        .orientations
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let labels: Vec<String> = std::iter::once("time")
        .chain(COORDINATES)
        .chain(LUMBAR)
        .map(String::from)
        .collect();
    let mut solver = Solver::new();
    let progress = Progress::new(0, "imu", diagnostics.quiet());
    let heading_free = a.pelvis == PelvisArg::HeadingFree;
    let mut window = ProgressionWindow::new(PROGRESSION_WINDOW);
    write_output_with(Some(&a.output), |out| {
        write_mot_header(&mut *out, &name, &labels, true, None)?;
        let mut emit = |row: &Row, heading: Option<f64>| -> std::io::Result<()> {
            let mut row = *row;
            if let Some(h) = heading {
                let pelvis = [1, 2, 3].map(|c| row[c].to_radians());
                let p = heading_free_pelvis(&model, pelvis, h.to_radians());
                for (k, v) in p.into_iter().enumerate() {
                    row[k + 1] = v.to_degrees();
                }
            }
            write_mot_row(&mut *out, &row)
        };
        while let Some(r) = reader.next_row()? {
            let segments = calibration
                .segments(&r.readings)
                .map_err(|e| anyhow::anyhow!("{}:{}: {e}", reader.source(), r.line))?;
            let solved = solver.solve(&model, &segments, mode);
            let mut row: Row = [0.0; COLUMNS];
            row[0] = r.time;
            for (v, q) in row[1..]
                .iter_mut()
                .zip(solved.coordinates.iter().chain(&solved.lumbar))
            {
                *v = q.to_degrees();
            }
            if heading_free {
                window.push(row, false, &mut emit)?;
            } else {
                emit(&row, None)?;
            }
            progress.inc(1);
        }
        if heading_free {
            window.push([f64::INFINITY; COLUMNS], true, &mut emit)?;
        }
        Ok(())
    })?;
    progress.finish();
    warnings.extend(reader.take_warnings());
    diagnostics.warn(warnings);
    Ok(())
}

/// Output columns: time, gait2392's 17 coordinates, the lumbar joint's 3.
const COLUMNS: usize = 21;

/// One output row (time, then degrees).
type Row = [f64; COLUMNS];

/// The rows within half a window of the next row to write, for the direction of progression:
/// the mean `pelvis_rotation` over the rows within `window / 2` seconds of a row's time (a
/// centred moving average). Memory is bounded by the window, not by the recording.
struct ProgressionWindow {
    half: f64,
    rows: std::collections::VecDeque<Row>,
    /// Index in `rows` of the next row to write.
    next: usize,
}

impl ProgressionWindow {
    fn new(window: f64) -> Self {
        Self {
            half: window / 2.0,
            rows: std::collections::VecDeque::new(),
            next: 0,
        }
    }

    /// Adds `row` (or, with `last`, ends the recording: `row` is not kept) and hands every row
    /// whose window is now complete to `emit` with its direction of progression (degrees).
    fn push(
        &mut self,
        row: Row,
        last: bool,
        emit: &mut impl FnMut(&Row, Option<f64>) -> std::io::Result<()>,
    ) -> std::io::Result<()> {
        let t_new = row[0];
        if !last {
            self.rows.push_back(row);
        }
        while self.next < self.rows.len() {
            let t = self.rows[self.next][0];
            if !last && t + self.half >= t_new {
                break;
            }
            let (sum, n) = self
                .rows
                .iter()
                .filter(|r| (r[0] - t).abs() <= self.half)
                .fold((0.0, 0), |(s, n), r| (s + r[3], n + 1));
            emit(&self.rows[self.next], Some(sum / n as f64))?;
            self.next += 1;
            while self.next < self.rows.len()
                && self.rows[0][0] < self.rows[self.next][0] - self.half
            {
                self.rows.pop_front();
                self.next -= 1;
            }
        }
        Ok(())
    }
}

/// The calibration from the first row of `path`, and the sensors it has.
fn calibrate(
    path: &Path,
    model: &Gait2392<f64>,
    settings: &Settings<f64>,
    warnings: &mut Vec<Warning>,
) -> anyhow::Result<(Calibration<f64>, Vec<Segment>)> {
    let mut reader = OrientationReader::open(path)?;
    let row = reader
        .next_row()?
        .expect("the reader refuses a file without rows");
    if reader.next_row()?.is_some() {
        warnings.push(Warning(format!(
            "{}: the calibration pose has more than one row; the first (line {}) is used",
            reader.source(),
            row.line
        )));
    }
    warnings.extend(reader.take_warnings());
    let present: Vec<Segment> = Segment::ALL
        .into_iter()
        .filter(|&s| row.readings.get(s).is_some())
        .collect();
    let calibration = Calibration::new(model, &row.readings, settings)
        .map_err(|e| anyhow::anyhow!("{}:{}: {e}", reader.source(), row.line))?;
    Ok((calibration, present))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The window's means are the centred means over the whole recording, every row is written
    /// once in order, and it holds no more than a window of rows.
    #[test]
    fn progression_window_is_the_centred_mean_in_bounded_memory() {
        let n = 1000;
        let time: Vec<f64> = (0..n)
            .map(|i| i as f64 * 0.01 + (i % 7) as f64 * 1e-4)
            .collect();
        let rot: Vec<f64> = time
            .iter()
            .map(|t| 90.0 * t + 5.0 * (7.0 * t).sin())
            .collect();
        let mut window = ProgressionWindow::new(0.5);
        let mut got = Vec::new();
        let mut most = 0;
        let mut emit = |r: &Row, h: Option<f64>| {
            got.push((r[0], h.unwrap()));
            Ok(())
        };
        for (t, v) in time.iter().zip(&rot) {
            let mut row = [0.0; COLUMNS];
            row[0] = *t;
            row[3] = *v;
            window.push(row, false, &mut emit).unwrap();
            most = most.max(window.rows.len());
        }
        window.push([0.0; COLUMNS], true, &mut emit).unwrap();
        assert_eq!(got.len(), n);
        for (i, (t, h)) in got.iter().enumerate() {
            assert_eq!(*t, time[i]);
            let near: Vec<f64> = (0..n)
                .filter(|&j| (time[j] - t).abs() <= 0.25)
                .map(|j| rot[j])
                .collect();
            let mean = near.iter().sum::<f64>() / near.len() as f64;
            assert!((h - mean).abs() < 1e-9, "row {i}: {h} vs {mean}");
        }
        assert!(most <= 60, "held {most} rows for a 0.5 s window at 100 Hz");
    }
}
