//! `qgait packets`: the byte stream the IMU nodes send for a motion, or the segment nodes' stream
//! of an IMU recording (`--orientations`).

use std::io::Write;
use std::path::PathBuf;

use anyhow::bail;
use clap::{Args, ValueEnum};
use qgait_proto::ModelId;

use crate::cli::device_args::OrientationArgs;
use crate::cli::diagnostics::Diagnostics;
use qgait_device::orientations::OrientationStream;
use qgait_device::packets::{PacketsError, Timing};

/// `qgait packets` arguments.
#[derive(Debug, Args)]
pub struct PacketsArgs {
    /// Motion file (.mot/.sto) or `builtin:...`.
    #[arg(
        required_unless_present = "orientations",
        conflicts_with = "orientations"
    )]
    pub motion: Option<String>,
    /// Samples per second of MOTION (default: its time column; an orientation recording has
    /// its own times).
    #[arg(long, value_name = "HZ", conflicts_with = "orientations")]
    pub rate: Option<f64>,
    /// Model whose joints are sent (one packet per joint per row).
    #[arg(long, value_enum, default_value = "phak")]
    pub model: WireModel,
    /// Output file (the byte stream, as the nodes send it).
    #[arg(short, long, value_name = "STREAM.bin")]
    pub output: PathBuf,
    /// The IMU orientation input instead of a motion.
    #[command(flatten)]
    pub imu: OrientationArgs,
}

/// A model id on the command line.
#[derive(Debug, Clone, Copy, PartialEq, Eq, ValueEnum)]
pub enum WireModel {
    /// 6 joints: hip flexion, knee, ankle of both legs.
    Hak,
    /// 8 joints: HAK plus pelvis rotation and list.
    Phak,
    /// All 17 gait2392 coordinates.
    Gait2392,
}

impl From<WireModel> for ModelId {
    fn from(m: WireModel) -> ModelId {
        match m {
            WireModel::Hak => ModelId::Hak,
            WireModel::Phak => ModelId::Phak,
            WireModel::Gait2392 => ModelId::Gait2392,
        }
    }
}

/// Runs `qgait packets`: each row's packets are written before the next row is read.
pub fn run_packets(args: PacketsArgs, quiet: bool) -> anyhow::Result<()> {
    if let Some(stream) = args.imu.stream(quiet)? {
        return write_orientation_stream(&args, &stream, quiet);
    }
    let Some(motion) = &args.motion else {
        bail!("give either MOTION or --orientations ORIENTATIONS.sto --calibration STATIC.sto");
    };
    crate::cli::output::refuse_overwrite([args.output.as_path()], &[motion])?;
    let diagnostics = Diagnostics::new(quiet);
    let warn = |w| diagnostics.warn(w);
    let (rows, w) = qgait_model::motion::source::MotionRows::open(motion)?;
    warn(w);
    let timing = args.rate.map_or(Timing::TimeColumn, Timing::Rate);
    let mut file = crate::cli::output::OutputFile::create(&args.output)?;
    let (counts, w) =
        qgait_device::packets::write_stream(rows, args.model.into(), timing, &warn, file.writer())
            .map_err(|e| match e {
                PacketsError::Write(io) => crate::cli::output::with_path(io.into(), &args.output),
                other => other.into(),
            })?;
    file.commit()?;
    warn(w);
    if !quiet {
        eprintln!(
            "wrote {} packets ({} samples × {} joints), {} bytes, to {}",
            counts.packets,
            counts.samples,
            ModelId::from(args.model).required_joints().len(),
            counts.bytes,
            args.output.display()
        );
    }
    Ok(())
}

/// `qgait packets --orientations`: the nodes' stream of an IMU recording.
fn write_orientation_stream(
    args: &PacketsArgs,
    stream: &OrientationStream,
    quiet: bool,
) -> anyhow::Result<()> {
    let inputs: Vec<String> = [&args.imu.orientations, &args.imu.calibration]
        .into_iter()
        .flatten()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    crate::cli::output::refuse_overwrite([args.output.as_path()], &inputs)?;
    let bytes = stream.bytes(4);
    let mut file = crate::cli::output::OutputFile::create(&args.output)?;
    file.writer()
        .write_all(&bytes)
        .map_err(|e| crate::cli::output::with_path(e.into(), &args.output))?;
    file.commit()?;
    if !quiet {
        eprintln!(
            "wrote the configuration (gait2392, {:?}), the calibration pose and {} samples of {} segments, {} bytes, to {}",
            stream.imu.mode,
            stream.rows.len(),
            stream.imu.segments.count_ones(),
            bytes.len(),
            args.output.display()
        );
    }
    Ok(())
}
