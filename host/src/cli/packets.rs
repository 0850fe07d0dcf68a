//! `qgait packets`: the byte stream the IMU nodes send for a motion, the segment nodes' stream
//! of an IMU recording (`--orientations`), or the raw nodes' stream of raw IMU recordings
//! (`--raw`).

use std::io::Write;
use std::path::{Path, PathBuf};

use anyhow::{bail, Context};
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
        required_unless_present_any = ["orientations", "raw"],
        conflicts_with_all = ["orientations", "raw"]
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
    /// Raw nodes instead: their samples (protocol.md 4.10) from raw IMU recordings.
    #[command(flatten)]
    pub raw: RawArgs,
}

/// `qgait packets --raw`: what raw nodes send.
#[derive(Debug, Args)]
pub struct RawArgs {
    /// Raw IMU recordings, one per sensor, as `qgait fuse` reads them (the shared CSV layout or
    /// an Xsens MT Manager .txt), sampling in step: a `RawImuConfig`, then every sensor's
    /// `RawImuSample`s, the counts of an ICM-20948 (±2000 °/s at 16.4 counts per °/s, ±16 g at
    /// 2048 counts per g, 0.15 µT per count).
    #[arg(long, value_name = "RAW", num_args = 1.., conflicts_with = "orientations")]
    pub raw: Vec<PathBuf>,
    /// Each recording's segment, in the order of the files (`pelvis`, `femur_r`, `tibia_r`,
    /// `calcn_r`, `femur_l`, `tibia_l`, `calcn_l`, `torso`; default: in that order).
    #[arg(long, value_name = "SEGMENT", requires = "raw")]
    pub segment: Vec<String>,
    /// 9d: with the magnetometer (default when every file has one); 6d: without.
    #[arg(long = "fusion", value_enum, requires = "raw")]
    pub fusion: Option<crate::cli::fuse::ModeArg>,
    /// One orientation per this many samples (`RawImuConfig.output_every`).
    #[arg(long, default_value_t = 1, value_name = "N", requires = "raw", value_parser = clap::value_parser!(u8).range(1..))]
    pub output_every: u8,
    /// Only the first N samples of each recording.
    #[arg(long = "raw-rows", value_name = "N", requires = "raw")]
    pub raw_rows: Option<usize>,
    /// The sampling rate (Hz) of Xsens files without a `// Update Rate` comment.
    #[arg(long = "raw-rate", value_name = "HZ", requires = "raw")]
    pub raw_rate: Option<f64>,
    /// For a hub with raw input (firmware features `imu` and `raw`) instead of a node: the
    /// stream starts with gait2392 and the IMU configuration (`--base-imu`,
    /// `--base-heading-axis`, `--sensor-to-opensim`, `--mode`: the readings are the fusion's,
    /// in its z-up world), so the first sample with every sensor fused is the calibration pose
    /// (the subject standing in the model's default pose) and each later one a pose frame.
    #[arg(long, requires = "raw")]
    pub hub: bool,
    /// With --hub: the time (s from the first sample) of the calibration pose, the IMU
    /// configuration sent just before the first sample at or after it. The subject must stand
    /// still in the model's default pose then, and the fusion must have settled: VQF starts
    /// from the first samples' inclination and heading and corrects them over about a second
    /// (its accelerometer low-pass averages the first samples; its magnetometer gain starts at
    /// 1 and falls as 1/k), so a calibration on the very first sample is taken from an
    /// unsettled fusion.
    #[arg(long, default_value_t = 2.0, value_name = "S", requires = "hub")]
    pub calibrate_at: f64,
}

impl RawArgs {
    /// The raw stream the arguments describe, if `--raw` is given.
    pub fn stream(&self) -> anyhow::Result<Option<qgait_device::raw::RawStream>> {
        use qgait_device::raw::{segment_of_name, RawStream, Sensitivities};
        use qgait_kernel::imu::SENSORS;
        use qgait_proto::{FusionMode, SegmentId};
        if self.raw.is_empty() {
            return Ok(None);
        }
        if !self.segment.is_empty() && self.segment.len() != self.raw.len() {
            bail!(
                "{} --segment for {} --raw files: give one per file, or none",
                self.segment.len(),
                self.raw.len()
            );
        }
        if self.raw.len() > SENSORS {
            bail!("at most {} raw recordings (one per segment)", SENSORS);
        }
        let mut recordings = Vec::new();
        for (i, path) in self.raw.iter().enumerate() {
            let segment = match self.segment.get(i) {
                Some(name) => segment_of_name(name).with_context(|| {
                    format!("--segment {name}: not one of pelvis, femur_r, tibia_r, calcn_r, femur_l, tibia_l, calcn_l, torso")
                })?,
                None => SegmentId::ALL[i],
            };
            let mut r = crate::cli::fuse::read(path, self.raw_rate)?;
            if let Some(n) = self.raw_rows {
                truncate(&mut r, n);
            }
            recordings.push((segment, r));
        }
        let fusion = match self.fusion {
            Some(crate::cli::fuse::ModeArg::NineD) => FusionMode::NineD,
            Some(crate::cli::fuse::ModeArg::SixD) => FusionMode::SixD,
            None if recordings.iter().all(|(_, r)| r.mag.is_some()) => FusionMode::NineD,
            None => FusionMode::SixD,
        };
        let sensors: Vec<_> = recordings.iter().map(|(s, r)| (*s, r)).collect();
        Ok(Some(RawStream::new(
            &sensors,
            fusion,
            self.output_every,
            Sensitivities::default(),
        )?))
    }
}

/// Keeps the first `n` samples of `r`.
fn truncate(r: &mut qgait_fusion::RawRecording, n: usize) {
    r.times.truncate(n);
    r.lines.truncate(n);
    r.gyr.truncate(n);
    r.acc.truncate(n);
    if let Some(m) = &mut r.mag {
        m.truncate(n);
    }
    if let Some(t) = &mut r.truth {
        t.truncate(n);
    }
    if let Some(m) = &mut r.movement {
        m.truncate(n);
    }
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
    if let Some(stream) = args.raw.stream()? {
        return write_raw_stream(&args, &stream, quiet);
    }
    if let Some(stream) = args.imu.stream(quiet)? {
        return write_orientation_stream(&args, &stream, quiet);
    }
    let Some(motion) = &args.motion else {
        bail!("give MOTION, --orientations ORIENTATIONS.sto --calibration STATIC.sto, or --raw RAW...");
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
    let bytes = stream.bytes(4);
    write_stream(&args.output, &inputs, &bytes)?;
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

/// Writes a stream's `bytes` to `output`, which must not be one of the `inputs`.
fn write_stream(output: &Path, inputs: &[String], bytes: &[u8]) -> anyhow::Result<()> {
    crate::cli::output::refuse_overwrite([output], inputs)?;
    let mut file = crate::cli::output::OutputFile::create(output)?;
    file.writer()
        .write_all(bytes)
        .map_err(|e| crate::cli::output::with_path(e.into(), output))?;
    file.commit()?;
    Ok(())
}

/// `qgait packets --raw`: the raw nodes' stream of raw IMU recordings.
fn write_raw_stream(
    args: &PacketsArgs,
    stream: &qgait_device::raw::RawStream,
    quiet: bool,
) -> anyhow::Result<()> {
    let inputs: Vec<String> = args
        .raw
        .raw
        .iter()
        .map(|p| p.to_string_lossy().into_owned())
        .collect();
    let bytes = if args.raw.hub {
        let settings = args.imu.settings.settings()?;
        let period = 1.0 / f64::from(stream.config.rate_hz);
        let at = (args.raw.calibrate_at / period).ceil();
        if !(0.0..stream.rows as f64).contains(&at) {
            bail!(
                "--calibrate-at {} s: the recordings have samples from 0 to {:.3} s",
                args.raw.calibrate_at,
                (stream.rows.max(1) - 1) as f64 * period
            );
        }
        qgait_device::raw_hub::RawHubStream::new(
            stream.clone(),
            &settings,
            args.imu.settings.mode(),
            at as u32,
        )?
        .bytes(4)
    } else {
        stream.bytes()
    };
    write_stream(&args.output, &inputs, &bytes)?;
    if !quiet {
        let hub = if args.raw.hub {
            "gait2392 and the IMU configuration (for a hub with raw input), "
        } else {
            ""
        };
        let c = &stream.config;
        eprintln!(
            "wrote {hub}the raw input's configuration ({:?}, {} Hz, an orientation every {} samples) and {} samples of {} sensors, {} bytes, to {}",
            c.fusion,
            c.rate_hz,
            c.output_every,
            stream.rows,
            c.segments.count_ones(),
            bytes.len(),
            args.output.display()
        );
    }
    Ok(())
}
