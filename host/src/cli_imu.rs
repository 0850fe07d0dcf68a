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
use qgait_kernel::{Gait2392, Gait2392Geometry};

use crate::cli::{refuse_overwrite, write_output_with};
use crate::imu_sto::OrientationReader;
use crate::mot::{MotionTable, Warning};
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
    /// Kinematic model (gait2392's coordinates are written; the calibration and the solution
    /// depend only on its joint axes, which scaling does not change).
    #[arg(long, default_value = "gait2392", value_name = "gait2392")]
    pub model: String,
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

/// The settings from the command line.
fn settings(a: &ImuArgs) -> anyhow::Result<Settings<f64>> {
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
pub fn run_imu(a: ImuArgs, quiet: bool) -> anyhow::Result<()> {
    if !a.model.eq_ignore_ascii_case("gait2392") {
        bail!(
            "--model `{}`: `qgait imu` writes gait2392's coordinates only (--model gait2392)",
            a.model
        );
    }
    let inputs: Vec<&str> = [&a.orientations, &a.calibration]
        .iter()
        .filter_map(|p| p.to_str())
        .collect();
    refuse_overwrite([a.output.as_path()], &inputs)?;
    let settings = settings(&a)?;
    let mut warnings: Vec<Warning> = Vec::new();
    let model = Gait2392::<f64>::new(&Gait2392Geometry::generic())
        .map_err(|e| anyhow::anyhow!("gait2392: {e:?}"))?;

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
    let names: Vec<&str> = COORDINATES.iter().copied().chain(LUMBAR).collect();
    let mut columns: Vec<Vec<f64>> = vec![Vec::new(); names.len() + 1];
    let mut solver = Solver::new();
    let progress = Progress::new(0, "imu", quiet);
    while let Some(row) = reader.next_row()? {
        let segments = calibration
            .segments(&row.readings)
            .map_err(|e| anyhow::anyhow!("{}:{}: {e}", reader.source(), row.line))?;
        let out = solver.solve(&model, &segments, mode);
        columns[0].push(row.time);
        for (col, v) in columns[1..]
            .iter_mut()
            .zip(out.coordinates.iter().chain(&out.lumbar))
        {
            col.push(v.to_degrees());
        }
        progress.inc(1);
    }
    progress.finish();
    warnings.extend(reader.take_warnings());

    if a.pelvis == PelvisArg::HeadingFree {
        let progression = centred_mean(&columns[0], &columns[3], PROGRESSION_WINDOW);
        for (r, heading) in progression.into_iter().enumerate() {
            let pelvis = [1, 2, 3].map(|c| columns[c][r].to_radians());
            let p = heading_free_pelvis(&model, pelvis, heading.to_radians());
            for (k, v) in p.into_iter().enumerate() {
                columns[k + 1][r] = v.to_degrees();
            }
        }
    }

    let name = a
        .orientations
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let labels = std::iter::once("time")
        .chain(names.iter().copied())
        .map(String::from)
        .collect();
    let table = MotionTable::new(name, a.output.display().to_string(), true, labels, columns)
        .map_err(anyhow::Error::msg)?;
    write_output_with(Some(&a.output), |out| Ok(table.write_mot(out)?))?;
    if !quiet {
        for w in warnings {
            eprintln!("warning: {w}");
        }
    }
    Ok(())
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

/// The mean of `values` over the rows within `window / 2` seconds of each row's time (a
/// centred moving average, by a sliding sum).
fn centred_mean(time: &[f64], values: &[f64], window: f64) -> Vec<f64> {
    let half = window / 2.0;
    let (mut lo, mut hi, mut sum) = (0, 0, 0.0);
    time.iter()
        .map(|&t| {
            while hi < time.len() && time[hi] <= t + half {
                sum += values[hi];
                hi += 1;
            }
            while time[lo] < t - half {
                sum -= values[lo];
                lo += 1;
            }
            sum / (hi - lo) as f64
        })
        .collect()
}
